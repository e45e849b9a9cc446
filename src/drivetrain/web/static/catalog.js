// The catalog browser: filter and sort motors, gearboxes and drives, a motor's envelope, CSV import, and your
// own rows edited, removed and their history shown.

import { el } from "./dom.js";
import { api, ApiError } from "./api.js";
import { drawEnvelope } from "./plots.js";
import { fmt } from "./results.js";

const RPM = 60 / (2 * Math.PI);
const UNVERIFIED = " †";

// Fields of your rows the detail panel edits, with the unit the value is typed in (import headers).
const EDIT_FIELDS = {
  motor: [
    ["rated_torque [N*m]", "rated_torque_Nm", 1], ["peak_torque [N*m]", "peak_torque_Nm", 1],
    ["rated_speed [rpm]", "rated_speed_rad_s", RPM], ["max_speed [rpm]", "max_speed_rad_s", RPM],
    ["rotor_inertia [kg*cm^2]", "rotor_inertia_kgm2", 1e4], ["voltage [V]", "voltage_V", 1],
    ["source", "source"], ["notes", "notes"],
  ],
  gearbox: [
    ["ratio", "ratio", 1], ["efficiency", "efficiency", 1], ["rated_output_torque [N*m]", "rated_output_torque_Nm", 1],
    ["max_output_torque [N*m]", "max_output_torque_Nm", 1], ["max_input_speed [rpm]", "max_input_speed_rad_s", RPM],
    ["inertia_input [kg*cm^2]", "inertia_input_kgm2", 1e4], ["source", "source"], ["notes", "notes"],
  ],
  drive: [
    ["continuous_current [A]", "continuous_current_A", 1], ["peak_current [A]", "peak_current_A", 1],
    ["voltage [V]", "voltage_V", 1], ["source", "source"], ["notes", "notes"],
  ],
};
const ARCMIN = (180 / Math.PI) * 60;

const MOTOR_COLUMNS = [
  { key: "id", sort: "id", label: "id" },
  { key: "vendor", sort: "vendor", label: "vendor" },
  { key: "series", sort: "series", label: "series" },
  { key: "rated_power_W", sort: "rated_power", label: "P [W]" },
  { key: "rated_torque_Nm", sort: "rated_torque", label: "T rated [N·m]" },
  { key: "peak_torque_Nm", sort: "peak_torque", label: "T peak [N·m]" },
  { key: "rated_speed_rad_s", sort: "rated_speed", label: "n rated [rpm]", k: RPM },
  { key: "max_speed_rad_s", sort: "max_speed", label: "n max [rpm]", k: RPM },
  { key: "rotor_inertia_kgm2", sort: "rotor_inertia", label: "J [kg·cm²]", k: 1e4 },
  { key: "flange_m", sort: "flange", label: "flange [mm]", k: 1e3 },
  { key: "voltage_V", sort: "voltage", label: "U [V]" },
  { key: "origin", label: "origin" },
];

const GEARBOX_COLUMNS = [
  { key: "id", sort: "id", label: "id" },
  { key: "vendor", sort: "vendor", label: "vendor" },
  { key: "series", sort: "series", label: "series" },
  { key: "ratio", sort: "ratio", label: "ratio" },
  { key: "stages", sort: "stages", label: "stages" },
  { key: "rated_output_torque_Nm", sort: "rated_output_torque", label: "rated T₂ [N·m]" },
  { key: "max_output_torque_Nm", sort: "max_output_torque", label: "max T₂ [N·m]" },
  { key: "efficiency", sort: "efficiency", label: "η" },
  { key: "max_input_speed_rad_s", sort: "max_input_speed", label: "max n₁ [rpm]", k: RPM },
  { key: "inertia_input_kgm2", sort: "inertia_input", label: "J₁ [kg·cm²]", k: 1e4 },
  { key: "backlash_rad", sort: "backlash", label: "backlash [arcmin]", k: ARCMIN },
  { key: "mass_kg", sort: "mass", label: "mass [kg]" },
  { key: "origin", label: "origin" },
];

const DRIVE_COLUMNS = [
  { key: "id", sort: "id", label: "id" },
  { key: "vendor", sort: "vendor", label: "vendor" },
  { key: "series", sort: "series", label: "series" },
  { key: "continuous_current_A", sort: "continuous_current", label: "I cont. [A]" },
  { key: "peak_current_A", sort: "peak_current", label: "I peak [A]" },
  { key: "voltage_V", sort: "voltage", label: "U [V]" },
  { key: "rated_power_W", sort: "rated_power", label: "P [W]" },
  { key: "motor_series", sort: "motor_series", label: "motor series" },
  { key: "origin", label: "origin" },
  { key: "source", label: "source", wide: true },
];
const COLUMNS = { motors: MOTOR_COLUMNS, gearboxes: GEARBOX_COLUMNS, drives: DRIVE_COLUMNS };

// The motors the browser opens on: industrial AC servos (not the small DC motors).
const DEFAULT_KIND = "ac_servo";
const KIND_LABELS = { ac_servo: "AC servo (industrial)", small_dc: "small DC" };

function selectOf(id, labelText, name, options, blank, value = "") {
  const select = el("select", { id, name });
  select.append(el("option", { value: "", text: blank }));
  for (const o of options) {
    const [v, text] = Array.isArray(o) ? o : [o, o];
    select.append(el("option", { value: String(v), text: String(text) }));
  }
  select.value = value;
  return el("div", { class: "filter" }, el("label", { for: id, text: labelText }), select);
}

function inputOf(id, labelText, name, placeholder) {
  return el("div", { class: "filter" }, el("label", { for: id, text: labelText }),
    el("input", { id, name, type: "text", placeholder, spellcheck: "false", autocomplete: "off" }));
}

export class CatalogView {
  constructor(nodes, setStatus) {
    this.n = nodes;
    this.setStatus = setStatus;
    this.table = "motors";
    this.sort = { motors: { by: "rated_torque", order: "asc" }, gearboxes: { by: "ratio", order: "asc" },
      drives: { by: "continuous_current", order: "asc" } };
    this.offset = 0;
    this.limit = 50;
    this.facets = null;
    this.timer = null;
    this.loaded = false;
    this.n.motors.addEventListener("click", () => this.switchTo("motors"));
    this.n.gearboxes.addEventListener("click", () => this.switchTo("gearboxes"));
    this.n.drives.addEventListener("click", () => this.switchTo("drives"));
    this.n.prev.addEventListener("click", () => { this.offset = Math.max(0, this.offset - this.limit); this.load(); });
    this.n.next.addEventListener("click", () => { this.offset += this.limit; this.load(); });
    this.n.filters.addEventListener("input", () => this.refilter());
    this.n.filters.addEventListener("change", () => this.refilter());
    this.n.filters.addEventListener("submit", (e) => { e.preventDefault(); this.refilter(0); });
    this.n.importForm.addEventListener("submit", (e) => { e.preventDefault(); this.importFile(); });
  }

  async open() {
    if (this.loaded) return;
    this.loaded = true;
    try {
      this.facets = await api.get("/api/catalog/facets");
    } catch (err) {
      this.n.table.replaceChildren(el("p", { class: "field-error", text: err.message }));
      return;
    }
    this.buildFilters();
    await this.load();
  }

  switchTo(table) {
    this.table = table;
    this.offset = 0;
    this.n.motors.setAttribute("aria-pressed", String(table === "motors"));
    this.n.gearboxes.setAttribute("aria-pressed", String(table === "gearboxes"));
    this.n.drives.setAttribute("aria-pressed", String(table === "drives"));
    this.buildFilters();
    this.load();
  }

  buildFilters() {
    const f = this.facets;
    const box = this.n.filters;
    if (this.table === "motors") {
      box.replaceChildren(
        inputOf("flt-q", "Search", "q", "id, model or series"),
        selectOf("flt-vendor", "Vendor", "vendor", f.motor_vendors, "all vendors"),
        selectOf("flt-kind", "Kind", "kind", f.motor_kinds.map((k) => [k, KIND_LABELS[k] || k]), "all kinds",
          f.motor_kinds.includes(DEFAULT_KIND) ? DEFAULT_KIND : ""),
        selectOf("flt-voltage", "Voltage class", "voltage", f.motor_voltages.map((v) => `${v} V`), "any voltage"),
        inputOf("flt-flange", "Flange", "flange", "e.g. 80 mm"),
        selectOf("flt-origin", "Rows", "origin", ["builtin", "user"], "shipped and yours"),
      );
    } else if (this.table === "drives") {
      box.replaceChildren(
        inputOf("flt-q", "Search", "q", "id, series or motor series"),
        selectOf("flt-vendor", "Vendor", "vendor", f.drive_vendors || [], "all vendors"),
        selectOf("flt-voltage", "Voltage class", "voltage", (f.drive_voltages || []).map((v) => `${v} V`), "any voltage"),
        selectOf("flt-origin", "Rows", "origin", ["builtin", "user"], "shipped and yours"),
      );
    } else {
      box.replaceChildren(
        inputOf("flt-q", "Search", "q", "id, model or series"),
        selectOf("flt-vendor", "Vendor", "vendor", f.gearbox_vendors, "all vendors"),
        selectOf("flt-series", "Series", "series", f.gearbox_series, "all series"),
        selectOf("flt-kind", "Kind", "kind", f.gearbox_kinds, "all kinds"),
        inputOf("flt-rmin", "Ratio from", "ratio_min", "e.g. 3"),
        inputOf("flt-rmax", "to", "ratio_max", "e.g. 10"),
        selectOf("flt-origin", "Rows", "origin", ["builtin", "user"], "shipped and yours"),
      );
    }
  }

  refilter() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => { this.offset = 0; this.load(); }, 250);
  }

  params() {
    const p = new URLSearchParams();
    for (const [k, v] of new FormData(this.n.filters).entries()) {
      const value = String(v).trim();
      if (value) p.set(k, value);
    }
    const s = this.sort[this.table];
    p.set("sort", s.by);
    p.set("order", s.order);
    p.set("offset", String(this.offset));
    p.set("limit", String(this.limit));
    return p;
  }

  async load() {
    const columns = COLUMNS[this.table];
    let page;
    try {
      page = await api.get(`/api/catalog/${this.table}?${this.params()}`);
    } catch (err) {
      this.n.table.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
      this.n.page.textContent = "";
      return;
    }
    const s = this.sort[this.table];
    const head = el("tr");
    for (const c of columns) {
      const th = el("th", { scope: "col" });
      if (c.sort) {
        const active = s.by === c.sort;
        th.setAttribute("aria-sort", active ? (s.order === "asc" ? "ascending" : "descending") : "none");
        const b = el("button", { type: "button", class: "sort", text: c.label + (active ? (s.order === "asc" ? " ▲" : " ▼") : "") });
        b.addEventListener("click", () => {
          this.sort[this.table] = { by: c.sort, order: active && s.order === "asc" ? "desc" : "asc" };
          this.offset = 0;
          this.load();
        });
        th.append(b);
      } else {
        th.textContent = c.label;
      }
      head.append(th);
    }
    const body = el("tbody");
    for (const item of page.items) {
      const tr = el("tr");
      columns.forEach((c, k) => {
        let v = item[c.key];
        if (typeof v === "number" && c.k) v = v * c.k;
        const text = typeof v === "number" ? fmt(v) : v === null || v === undefined || v === "" ? "–" : String(v);
        if (k === 0) {
          const motor = this.table === "motors";
          const b = el("button", { type: "button", class: "link id", text,
            title: motor ? `Show the envelope and data of ${text}` : `Show the data of ${text}` });
          b.addEventListener("click", () => (motor ? this.showMotor(item.id) : this.showItem(item.id)));
          // the dagger is drawn by CSS (th.unverified::after), so the cell's text stays the id
          tr.append(el("th", { scope: "row", class: item.unverified ? "unverified" : undefined,
            title: item.unverified ? `unverified: ${item.unverified_reason}` : undefined }, b));
        } else {
          tr.append(el("td", { class: c.wide ? "wide" : undefined, text, title: text.length > 14 ? text : undefined }));
        }
      });
      body.append(tr);
    }
    const t = el("table", { class: "data catalog-table" }, el("caption", { class: "sr-only", text: `${this.table} of the catalog` }), el("thead", {}, head), body);
    this.n.table.replaceChildren(t);
    const last = Math.min(page.offset + page.items.length, page.total);
    this.n.page.textContent = page.total ? `${page.offset + 1}–${last} of ${page.total}` : "nothing matches";
    this.n.prev.disabled = page.offset === 0;
    this.n.next.disabled = last >= page.total;
  }

  async showMotor(id) {
    try {
      const [env, item] = await Promise.all([
        api.get(`/api/catalog/motors/${encodeURIComponent(id)}/envelope`),
        api.get(`/api/catalog/items/${encodeURIComponent(id)}`),
      ]);
      drawEnvelope(this.n.envelope, env);
      const scaled = (v, k) => (typeof v === "number" ? fmt(v * k) : "–");
      this.renderItem(item, [
        ["rated / peak torque", `${scaled(item.rated_torque_Nm, 1)} / ${scaled(item.peak_torque_Nm, 1)} N·m`],
        ["rated / max speed", `${scaled(item.rated_speed_rad_s, RPM)} / ${scaled(item.max_speed_rad_s, RPM)} rpm`],
        ["rotor inertia", `${scaled(item.rotor_inertia_kgm2, 1e4)} kg·cm²`],
      ]);
    } catch (err) {
      this.n.detail.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
    }
  }

  async showItem(id) {
    try {
      const item = await api.get(`/api/catalog/items/${encodeURIComponent(id)}`);
      const scaled = (v, k) => (typeof v === "number" ? fmt(v * k) : "–");
      this.renderItem(item, item.table === "gearbox" ? [
        ["ratio, efficiency", `${scaled(item.ratio, 1)}, ${scaled(item.efficiency, 1)}`],
        ["rated / max output torque", `${scaled(item.rated_output_torque_Nm, 1)} / ${scaled(item.max_output_torque_Nm, 1)} N·m`],
        ["input inertia", `${scaled(item.inertia_input_kgm2, 1e4)} kg·cm²`],
      ] : item.table === "drive" ? [
        ["continuous / peak current", `${scaled(item.continuous_current_A, 1)} / ${scaled(item.peak_current_A, 1)} A`],
        ["voltage class", `${scaled(item.voltage_V, 1)} V`],
        ["motor series", item.motor_series || "–"],
      ] : []);
    } catch (err) {
      this.n.detail.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
    }
  }

  // The detail of one row: its values, sources per field group, the unverified flag, and for your own
  // rows an edit form, a remove button and the history of the row.
  renderItem(item, values) {
    const keys = [["vendor", item.vendor], ["series", item.series],
      ["origin", item.origin === "user" ? "your catalog" : "shipped catalog"], ...values,
      ["source", item.source], ["notes", item.notes]];
    for (const [group, where] of Object.entries(item.sources || {})) keys.push([`source: ${group}`, where]);
    keys.push(["verified", item.unverified ? `no: ${item.unverified_reason}` : "yes"]);
    const dl = el("dl", { class: "detail" });
    for (const [k, v] of keys) dl.append(el("dt", { text: k }), el("dd", { text: v === null || v === undefined || v === "" ? "–" : String(v) }));
    const parts = [el("h3", { text: item.id })];
    if (item.unverified) {
      parts.push(el("p", { class: "unverified-note", text: `${UNVERIFIED.trim()} unverified: ${item.unverified_reason}` }));
    }
    parts.push(dl);
    if (item.origin === "user") parts.push(this.editor(item));
    this.n.detail.replaceChildren(...parts);
  }

  editor(item) {
    const form = el("form", { class: "edit-form", "aria-label": `Edit ${item.id}` });
    const fields = EDIT_FIELDS[item.table] || [];
    fields.forEach(([name, key, k], i) => {
      const v = item[key];
      const shown = typeof v === "number" ? String(Number((v * k).toPrecision(12))) : v === null || v === undefined ? "" : String(v);
      const input = el("input", { id: `edit-${i}`, name, type: "text", value: shown, "data-old": shown, spellcheck: "false", autocomplete: "off" });
      form.append(el("label", { for: `edit-${i}`, text: name }), input);
    });
    const save = el("button", { type: "submit", text: "Save changes" });
    const remove = el("button", { type: "button", class: "danger", text: "Remove from your catalog" });
    const hist = el("button", { type: "button", class: "link", text: "History" });
    const out = el("div", { role: "status", "aria-live": "polite" });
    form.append(save, remove, hist, out);
    form.addEventListener("submit", async (e) => {
      e.preventDefault();
      const changes = {};
      for (const input of form.querySelectorAll("input")) {
        if (input.value !== input.dataset.old) changes[input.name] = input.value.trim() === "" ? null : input.value;
      }
      if (!Object.keys(changes).length) { out.replaceChildren(el("p", { class: "muted", text: "Nothing changed." })); return; }
      try {
        const updated = await api.patch(`/api/catalog/items/${encodeURIComponent(item.id)}`, changes);
        this.setStatus(`saved ${item.id}`);
        this.renderItem(updated, []);
        this.load();
      } catch (err) {
        out.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
      }
    });
    remove.addEventListener("click", async () => {
      if (!window.confirm(`Remove ${item.id} from your catalog?`)) return;
      try {
        const rep = await api.del(`/api/catalog/items/${encodeURIComponent(item.id)}`);
        this.setStatus(rep.message);
        this.n.detail.replaceChildren(el("p", { class: "ok-text", text: rep.message }));
        this.load();
      } catch (err) {
        out.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
      }
    });
    hist.addEventListener("click", async () => {
      try {
        const h = await api.get(`/api/catalog/history?id=${encodeURIComponent(item.id)}`);
        const list = el("ol", { class: "history" });
        for (const e of h.entries) list.append(el("li", { text: `${e.at} ${e.action} (${e.source || "–"})` }));
        out.replaceChildren(h.entries.length ? list : el("p", { class: "muted", text: "No changes recorded." }));
      } catch (err) {
        out.replaceChildren(el("p", { class: "field-error", role: "alert", text: err.message }));
      }
    });
    return form;
  }

  async importFile() {
    const out = this.n.importResult;
    const data = new FormData(this.n.importForm);
    if (!data.get("kind")) data.delete("kind");
    if (!data.get("replace")) data.delete("replace");
    const file = data.get("file");
    if (!file || !file.name) {
      out.replaceChildren(el("p", { class: "field-error", text: "Choose a CSV or JSON file first." }));
      return;
    }
    out.replaceChildren(el("p", { class: "muted", text: `Importing ${file.name}…` }));
    try {
      const rep = await api.post("/api/catalog/import", data);
      out.replaceChildren(el("p", { class: "ok-text", text: rep.message }));
      this.setStatus(rep.message);
      if (this.facets) {
        this.facets = await api.get("/api/catalog/facets");
        this.buildFilters();
      }
      this.load();
    } catch (err) {
      if (!(err instanceof ApiError)) throw err;
      const rows = err.errors.map((e) => {
        const m = /^(.*):(\d+):([^:]*)$/.exec(e.field || "");
        const message = e.field && e.message.startsWith(e.field + ": ") ? e.message.slice(e.field.length + 2) : e.message;
        return m ? [m[2], m[3], message] : ["–", e.field || "–", message];
      });
      const t = el("table", { class: "data import-errors" }, el("caption", { text: `${rows.length} problem(s); nothing was imported` }),
        el("thead", {}, el("tr", {}, el("th", { scope: "col", text: "line" }), el("th", { scope: "col", text: "column" }), el("th", { scope: "col", text: "problem" }))));
      const body = el("tbody");
      for (const r of rows) body.append(el("tr", { class: "fail" }, el("th", { scope: "row", text: r[0] }), el("td", { text: r[1] }), el("td", { text: r[2] })));
      t.append(body);
      out.replaceChildren(el("p", { class: "field-error", role: "alert", text: "The file was not imported." }), t);
    }
  }
}
