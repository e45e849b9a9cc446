// The machine view: a machine project (the machine file with its axes inline or naming saved axis
// projects), its axes table and the YAML kept in sync, sizing on demand, and the result: the
// machine table, the DC bus over the cycle, resistor and supply, the bill of materials, each
// axis's checks, and the report, AAS and YAML downloads. Projects are saved with history through
// /api/projects (kind "machine"); sizing is /api/machine/size (docs/machine.md).

import { confirmedTwice, el } from "./dom.js";
import { api, ApiError, filenameOf, saveBlob } from "./api.js";
import { fmt } from "./results.js";
import * as MR from "./machine_results.js";
import { renderVersions } from "./versions.js";
import { toYaml } from "./yaml.js";

const $ = (id) => document.getElementById(id);
const YAML_DELAY_MS = 300;
const BLANK = { version: 1, machine: "new machine", cycle_time: "1 s", supply: { voltage: "400 V", phases: 3 }, axes: [] };
function safeName(name) {
  return (String(name).replace(/[^A-Za-z0-9._-]+/g, "_").replace(/^[._]+|[._]+$/g, "") || "machine").slice(0, 80);
}

function copy(x) {
  return JSON.parse(JSON.stringify(x));
}

export class MachineView {
  constructor({ setStatus, openAxisProject, openAxis }) {
    this.setStatus = setStatus;
    this.openAxisProject = openAxisProject;
    this.openAxis = openAxis;
    this.machine = copy(BLANK);
    this.project = null; // {id, name, version}
    this.savedText = null;
    this.payload = null;
    this.yamlTimer = null;
    this.yamlSeq = 0;
    this.sizeSeq = 0;
    this.deleteArmed = null;
    this.axisProjects = [];
    this.started = false;
  }

  // ---------------------------------------------------------------- start

  async start() {
    if (this.started) return;
    this.started = true;
    $("m-yaml").addEventListener("input", () => this.onYamlInput());
    $("m-new").addEventListener("click", () => this.newMachine());
    $("m-save").addEventListener("click", () => this.save());
    $("m-size").addEventListener("click", () => this.size());
    $("m-duplicate").addEventListener("click", () => this.duplicate());
    $("m-delete").addEventListener("click", () => this.remove());
    $("m-undo").addEventListener("click", () => this.project && this.restoreWith(api.post(`/api/projects/${this.project.id}/undo`), "undone"));
    $("m-history").addEventListener("toggle", () => this.refreshHistory());
    $("m-add").addEventListener("click", () => this.addProjectAxis());
    $("m-download-yaml").addEventListener("click", () => saveBlob(new Blob([$("m-yaml").value], { type: "application/yaml" }), `${safeName(this.machine.machine || "machine")}.yaml`));
    $("m-report-html").addEventListener("click", () => this.download("/api/report/machine?format=html", "report HTML", "-report.html"));
    $("m-report-pdf").addEventListener("click", () => this.download("/api/report/machine?format=pdf", "report PDF", "-report.pdf"));
    $("m-aas").addEventListener("click", () => this.download("/api/machine/aas", "AAS submodel", ".aas.json"));
    $("m-name").addEventListener("keydown", (e) => {
      if (e.key === "Enter") this.save();
    });
    $("m-example-select").addEventListener("change", async (e) => {
      const name = e.target.value;
      e.target.value = "";
      if (!name) return;
      try {
        const ex = await api.get(`/api/machine/examples/${encodeURIComponent(name)}`);
        this.load(ex.machine, ex.yaml);
        this.setStatus(`loaded the ${name} machine example (not saved)`);
      } catch (err) {
        this.setStatus(err.message, true);
      }
    });
    try {
      for (const n of await api.get("/api/machine/examples")) $("m-example-select").append(el("option", { value: n, text: n.replace(/_/g, " ") }));
    } catch (err) {
      /* examples are optional */
    }
    this.load(this.machine);
    await this.refreshProjects();
  }

  async open() {
    await this.start();
    await Promise.all([this.refreshProjects(), this.refreshAxisProjects()]);
    if (this.payload) MR.drawBus(this, this.payload);
  }

  // ---------------------------------------------------------------- machine <-> YAML <-> form

  load(machine, text) {
    this.machine = machine;
    $("m-yaml").value = text !== undefined ? text : toYaml(machine);
    this.showYamlError(null);
    this.renderForm();
    this.clearResult("Size the machine to see its axes, bus and bill of materials.");
    this.updateSaveState();
  }

  changed() {
    $("m-yaml").value = toYaml(this.machine);
    this.showYamlError(null);
    this.renderForm();
    this.markStale();
    this.updateSaveState();
  }

  showYamlError(message) {
    const p = $("m-yaml-error");
    p.hidden = !message;
    p.textContent = message || "";
    $("m-yaml").setAttribute("aria-invalid", message ? "true" : "false");
  }

  onYamlInput() {
    clearTimeout(this.yamlTimer);
    this.updateSaveState();
    this.markStale();
    this.yamlTimer = setTimeout(async () => {
      const seq = ++this.yamlSeq;
      try {
        const res = await api.post("/api/machine/parse", { yaml: $("m-yaml").value });
        if (seq !== this.yamlSeq) return;
        this.showYamlError(null);
        this.machine = res.machine;
        this.renderForm();
      } catch (err) {
        if (seq !== this.yamlSeq) return;
        this.showYamlError(err.message);
      }
    }, YAML_DELAY_MS);
  }

  axisLabel(a, k) {
    if (a && typeof a.name === "string" && a.name) return a.name;
    if (a && a.axis && typeof a.axis.axis === "string") return a.axis.axis;
    return `axis ${k + 1}`;
  }

  input(field, value, onChange, attrs = {}) {
    const i = el("input", { type: "text", "data-field": field, value: value === undefined || value === null ? "" : String(value), autocomplete: "off", ...attrs });
    i.addEventListener("change", () => onChange(i.value.trim()));
    return i;
  }

  renderForm() {
    const m = this.machine && typeof this.machine === "object" ? this.machine : {};
    const supply = m.supply && typeof m.supply === "object" ? m.supply : {};
    const set = (fn) => (v) => {
      fn(v);
      this.changed();
    };
    const field = (id, label, control) => {
      control.id = id;
      return el("div", { class: "field", "data-owner": control.dataset.field }, el("label", { for: id, text: label }), control, el("span", { class: "unit" }));
    };
    const phases = el("select", { "data-field": "supply.phases" }, el("option", { value: "3", text: "3" }), el("option", { value: "1", text: "1" }));
    phases.value = String(supply.phases || 3);
    phases.addEventListener("change", set(() => {
      this.machine.supply = { ...(this.machine.supply || {}), phases: Number(phases.value) };
    }));
    $("m-form").replaceChildren(el("div", { class: "fields" },
      field("m-f-name", "machine name", this.input("machine", m.machine, set((v) => { this.machine.machine = v; }))),
      field("m-f-cycle", "cycle time", this.input("cycle_time", m.cycle_time, set((v) => { this.machine.cycle_time = v; }))),
      field("m-f-voltage", "supply voltage", this.input("supply.voltage", supply.voltage, set((v) => {
        this.machine.supply = { ...(this.machine.supply || {}), voltage: v };
      }))),
      field("m-f-phases", "supply phases", phases)));
    this.renderAxes();
  }

  renderAxes() {
    const axes = Array.isArray(this.machine.axes) ? this.machine.axes : [];
    const names = axes.map((a, k) => this.axisLabel(a, k));
    const rows = axes.map((a, k) => {
      const where = `axes[${k}]`;
      const entry = a && typeof a === "object" ? a : {};
      const update = (fn) => {
        fn(entry);
        this.machine.axes[k] = entry;
        this.changed();
      };
      const name = this.input(`${where}.name`, names[k], (v) => this.renameAxis(k, names[k], v), { "aria-label": `name of axis ${k + 1}`, size: "8" });
      let source = "inline";
      if (entry.project !== undefined) {
        const p = this.axisProjects.find((q) => q.id === entry.project);
        source = `project ${p ? p.name : "#" + entry.project}${entry.project_version ? ` v${entry.project_version}` : ""}`;
      } else if (entry.include !== undefined) source = `include ${entry.include}`;
      const mode = entry.after !== undefined ? "after" : entry.offset === "free" ? "free" : "offset";
      const modeSel = el("select", { "data-field": `${where}.start`, "aria-label": `start of axis ${names[k]}` },
        el("option", { value: "offset", text: "at offset" }), el("option", { value: "after", text: "after axis" }), el("option", { value: "free", text: "free phase" }));
      modeSel.value = mode;
      modeSel.addEventListener("change", () => update((e) => {
        delete e.after;
        delete e.delay;
        delete e.offset;
        if (modeSel.value === "offset") e.offset = "0 s";
        else if (modeSel.value === "free") e.offset = "free";
        else e.after = names.find((n, j) => j !== k) || "";
      }));
      const start = el("div", { class: "start" }, modeSel);
      if (mode === "offset") {
        start.append(this.input(`${where}.offset`, entry.offset === undefined ? "0 s" : entry.offset, (v) => update((e) => { e.offset = v; }), { "aria-label": `offset of axis ${names[k]}`, size: "6" }));
      } else if (mode === "after") {
        const sel = el("select", { "data-field": `${where}.after`, "aria-label": `axis ${names[k]} starts after` });
        for (const n of names) if (n !== names[k]) sel.append(el("option", { value: n, text: n }));
        if (![...sel.options].some((o) => o.value === entry.after)) sel.append(el("option", { value: String(entry.after), text: String(entry.after) }));
        sel.value = String(entry.after);
        sel.addEventListener("change", () => update((e) => { e.after = sel.value; }));
        start.append(sel, this.input(`${where}.delay`, entry.delay || "", (v) => update((e) => {
          if (v) e.delay = v;
          else delete e.delay;
        }), { "aria-label": `delay of axis ${names[k]}`, placeholder: "delay", size: "5" }));
      }
      const motors = this.input(`${where}.motors`, entry.motors || 1, (v) => update((e) => {
        const n = Number(v);
        e.motors = Number.isInteger(n) && String(n) === v ? n : v;
        if (e.motors === 1) {
          delete e.motors;
          delete e.split;
        }
      }), { "aria-label": `motors of axis ${names[k]}`, size: "2" });
      const motorCell = el("div", { class: "start" }, motors);
      if ((entry.motors || 1) !== 1) {
        const text = Array.isArray(entry.split) ? entry.split.join(", ") : entry.split || "";
        motorCell.append(this.input(`${where}.split`, text, (v) => update((e) => {
          if (!v) delete e.split;
          else e.split = v === "stiffness" ? v : v.split(",").map((s) => s.trim()).filter(Boolean);
        }), { "aria-label": `load split of axis ${names[k]}`, placeholder: "50 %, 50 %", size: "10" }));
      }
      const remove = el("button", { type: "button", class: "small danger", text: "Remove", "aria-label": `Remove axis ${names[k]}` });
      remove.addEventListener("click", () => this.removeAxis(k, names[k]));
      const tr = el("tr", { "data-owner": where },
        el("th", { scope: "row" }, name), el("td", { text: source }), el("td", {}, start), el("td", {}, motorCell), el("td", {}, remove));
      const err = el("tr", { class: "row-error", hidden: true }, el("td", { colspan: "5" }, el("p", { class: "field-error", "data-error-for": where })));
      return [tr, err];
    });
    const t = el("table", { class: "data machine-axes-table" },
      el("caption", { class: "sr-only", text: "Axes of the machine" }),
      el("thead", {}, el("tr", {}, ...["axis", "source", "start in the cycle", "motors, split", ""].map((h) => el("th", { scope: "col", text: h })))),
      el("tbody", {}, ...rows.flat()));
    $("m-axes").replaceChildren(axes.length ? t : el("p", { class: "muted", text: "No axes yet: add a saved axis project, load an example or write them in the YAML." }));
  }

  renameAxis(k, old, name) {
    if (!name) return;
    this.machine.axes[k].name = name;
    for (const a of this.machine.axes) if (a && a.after === old) a.after = name;
    for (const b of this.machine.buses || []) if (b && Array.isArray(b.axes)) b.axes = b.axes.map((n) => (n === old ? name : n));
    this.changed();
  }

  removeAxis(k, name) {
    this.machine.axes.splice(k, 1);
    for (const a of this.machine.axes) {
      if (a && a.after === name) {
        delete a.after;
        delete a.delay;
        a.offset = "0 s";
      }
    }
    if (Array.isArray(this.machine.buses)) {
      for (const b of this.machine.buses) if (b && Array.isArray(b.axes)) b.axes = b.axes.filter((n) => n !== name);
      this.machine.buses = this.machine.buses.filter((b) => !b || !Array.isArray(b.axes) || b.axes.length);
      if (!this.machine.buses.length) delete this.machine.buses;
    }
    this.changed();
    this.setStatus(`removed axis ${name}`);
  }

  addProjectAxis() {
    const id = Number($("m-add-select").value);
    const p = this.axisProjects.find((q) => q.id === id);
    if (!p) {
      this.setStatus("choose a saved axis project to add", true);
      return;
    }
    if (!Array.isArray(this.machine.axes)) this.machine.axes = [];
    const taken = new Set(this.machine.axes.map((a, k) => this.axisLabel(a, k)));
    let name = p.name;
    for (let n = 2; taken.has(name); n++) name = `${p.name} ${n}`;
    this.machine.axes.push({ name, project: p.id, offset: "0 s" });
    const bus = Array.isArray(this.machine.buses) && this.machine.buses.length === 1 ? this.machine.buses[0] : null;
    if (bus && Array.isArray(bus.axes)) bus.axes.push(name);
    this.changed();
    this.setStatus(`added axis ${name} from project ${p.name}`);
  }

  async refreshAxisProjects() {
    try {
      this.axisProjects = await api.get("/api/projects?kind=axis");
    } catch (err) {
      this.axisProjects = [];
    }
    const sel = $("m-add-select");
    sel.replaceChildren(el("option", { value: "", text: "saved axis project…" }),
      ...this.axisProjects.map((p) => el("option", { value: String(p.id), text: `${p.name} (v${p.version})` })));
    this.renderAxes();
  }

  // ---------------------------------------------------------------- errors at their field

  clearErrors() {
    MR.clearFieldErrors();
  }

  showErrors(errors) {
    MR.showFieldErrors(errors);
  }

  // ---------------------------------------------------------------- sizing and result

  markStale() {
    $("m-result-body").classList.add("stale");
  }

  clearResult(text) {
    this.payload = null;
    const b = $("m-banner");
    b.className = "banner";
    b.textContent = text;
    $("m-result-body").hidden = true;
    this.clearErrors();
  }

  async size() {
    clearTimeout(this.yamlTimer);
    const seq = ++this.sizeSeq;
    document.body.dataset.machine = "busy";
    const b = $("m-banner");
    b.className = "banner";
    b.textContent = "Sizing every axis and the DC bus…";
    try {
      const res = await api.post("/api/machine/parse", { yaml: $("m-yaml").value });
      this.machine = res.machine;
      this.showYamlError(null);
      this.renderForm();
      const payload = await api.post("/api/machine/size", this.machine);
      if (seq !== this.sizeSeq) return;
      this.payload = payload;
      this.clearErrors();
      this.renderResult(payload);
      this.setStatus(`sized ${payload.machine.name}`);
    } catch (err) {
      if (seq !== this.sizeSeq) return;
      b.className = "banner bad";
      $("m-result-body").hidden = true;
      if (err instanceof ApiError && err.status === 422) {
        if (err.field === "yaml") this.showYamlError(err.message);
        else this.showErrors(err.errors);
        b.textContent = `The machine cannot be sized: ${err.message}`;
      } else {
        b.textContent = err.message;
      }
      this.setStatus(err.message.split("\n")[0], true);
    } finally {
      if (seq === this.sizeSeq) document.body.dataset.machine = "idle";
    }
  }

  renderResult(p) {
    const m = p.machine;
    const body = $("m-result-body");
    body.hidden = false;
    body.classList.remove("stale");
    const b = $("m-banner");
    const mv = MR.machineVerdict(p);
    b.className = `banner ${mv.cls}`;
    const failing = p.axes.filter((a) => !a.ok).map((a) => a.name);
    const busBad = p.buses.filter((x) => x.ok === false).map((x) => x.name);
    b.replaceChildren(el("strong", { text: m.ok ? `${m.name}: every axis passes` : `${m.name} does not pass` }),
      failing.length ? `: axis ${failing.join(", ")} fails` : "",
      busBad.length ? `; bus ${busBad.join(", ")}: its supply module or braking resistors do not suffice` : "",
      `. Bus peak ${fmt(m.bus_peak_power_W)} W, braking resistor ${fmt(m.resistor_energy_per_cycle_J)} J per cycle.`, mv.line);
    MR.renderTable(this, p);
    MR.drawBus(this, p);
    MR.renderBuses(this, p);
    MR.renderBom(this, p);
    MR.renderAxisResults(this, p);
  }

  async download(url, what, suffix) {
    this.setStatus(`writing the ${what}…`);
    try {
      const res = await api.post("/api/machine/parse", { yaml: $("m-yaml").value });
      this.machine = res.machine;
      const response = await api.post(url, this.machine, { raw: true });
      saveBlob(await response.blob(), filenameOf(response, `${safeName(this.machine.machine || "machine")}${suffix}`));
      this.setStatus(`${what} downloaded`);
    } catch (err) {
      if (err instanceof ApiError && err.status === 422) this.showErrors(err.errors);
      this.setStatus(err.message, true);
    }
  }

  // ---------------------------------------------------------------- projects

  updateSaveState() {
    const text = $("m-yaml").value;
    const s = $("m-save-state");
    if (!this.project) s.textContent = "not saved yet";
    else if (text === this.savedText) s.textContent = `saved, version ${this.project.version}`;
    else s.textContent = "unsaved changes";
    $("m-project-actions").hidden = !this.project;
  }

  async refreshProjects() {
    let list = [];
    try {
      list = await api.get("/api/projects?kind=machine");
    } catch (err) {
      this.setStatus(err.message, true);
    }
    const ul = $("m-project-list");
    ul.replaceChildren();
    for (const p of list) {
      const current = this.project && this.project.id === p.id;
      const b = el("button", { type: "button", class: "project", "aria-current": current ? "true" : undefined, "data-id": String(p.id) },
        el("span", { class: "name", text: p.name }),
        el("span", { class: "meta", text: `v${p.version} · ${new Date(p.updated * 1000).toLocaleString()}` }));
      b.addEventListener("click", () => this.openProject(p.id));
      ul.append(el("li", {}, b));
    }
    $("m-no-projects").hidden = list.length > 0;
  }

  adopt(detail) {
    this.project = { id: detail.id, name: detail.name, version: detail.version };
    this.savedText = detail.yaml;
    $("m-name").value = detail.name;
    history.replaceState(null, "", `#machine=${detail.id}`);
  }

  async openProject(id) {
    await this.start();
    try {
      const detail = await api.get(`/api/projects/${id}`);
      if (detail.kind !== "machine") throw new Error(`project ${detail.name} is an axis project: open it in the axis editor`);
      this.adopt(detail);
      if (detail.machine) this.load(detail.machine, detail.yaml);
      else {
        $("m-yaml").value = detail.yaml;
        this.showYamlError(detail.yaml_error ? detail.yaml_error.detail : "the saved text does not parse");
      }
      this.updateSaveState();
      await Promise.all([this.refreshProjects(), this.refreshHistory(), this.refreshAxisProjects()]);
      this.setStatus(`opened ${detail.name}`);
    } catch (err) {
      this.setStatus(err.message, true);
    }
  }

  async save() {
    const text = $("m-yaml").value;
    const name = $("m-name").value.trim() || String(this.machine.machine || "machine");
    try {
      let detail;
      if (!this.project) {
        detail = await api.post("/api/projects", { name, yaml: text, kind: "machine" });
      } else {
        detail = await api.put(`/api/projects/${this.project.id}`, { yaml: text, base_version: this.project.version });
        if (name !== this.project.name) {
          const renamed = await api.patch(`/api/projects/${this.project.id}`, { name });
          detail = { ...detail, name: renamed.name };
        }
      }
      this.adopt(detail);
      this.updateSaveState();
      await Promise.all([this.refreshProjects(), this.refreshHistory()]);
      this.setStatus(`saved ${detail.name}, version ${detail.version}`);
    } catch (err) {
      if (err instanceof ApiError && err.field === "yaml") this.showYamlError(err.message);
      this.setStatus(err.message, true);
    }
  }

  async duplicate() {
    if (!this.project) return;
    try {
      const p = await api.post(`/api/projects/${this.project.id}/duplicate`, {});
      await this.openProject(p.id);
      this.setStatus(`duplicated as ${p.name}`);
    } catch (err) {
      this.setStatus(err.message, true);
    }
  }

  async remove() {
    if (!this.project) return;
    const b = $("m-delete");
    if (!confirmedTwice(b, this)) return;
    try {
      const name = this.project.name;
      await api.del(`/api/projects/${this.project.id}`);
      this.newMachine();
      this.setStatus(`deleted ${name}`);
    } catch (err) {
      this.setStatus(err.message, true);
    }
  }

  async restoreWith(promise, what) {
    try {
      const detail = await promise;
      this.adopt(detail);
      if (detail.machine) this.load(detail.machine, detail.yaml);
      else $("m-yaml").value = detail.yaml;
      this.updateSaveState();
      await Promise.all([this.refreshProjects(), this.refreshHistory()]);
      this.setStatus(`${what}: now version ${detail.version}`);
    } catch (err) {
      this.setStatus(err.message, true);
    }
  }

  async refreshHistory() {
    await renderVersions($("m-version-list"), this.project, (req, what) => this.restoreWith(req, what));
  }

  newMachine() {
    this.project = null;
    this.savedText = null;
    $("m-name").value = "";
    history.replaceState(null, "", location.pathname);
    this.load(copy(BLANK));
    this.refreshProjects();
  }
}
