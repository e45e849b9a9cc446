// The page: projects, the axis editor (form and YAML kept in sync), live sizing and results,
// and the catalog browser. Every change re-sizes after a short pause; a newer request cancels
// an older one still in flight.

import { confirmedTwice, el } from "./dom.js";
import { api, ApiError, filenameOf, saveBlob } from "./api.js";
import { CatalogView } from "./catalog.js";
import { AxisForm } from "./form.js";
import { MachineView } from "./machine.js";
import * as plots from "./plots.js";
import * as R from "./results.js";
import { renderOrder } from "./order.js";
import { renderVersions } from "./versions.js";
import { toYaml } from "./yaml.js";

const $ = (id) => document.getElementById(id);
const SIZE_DELAY_MS = 250;
const YAML_DELAY_MS = 300;
const BLANK = { axis: "new axis", mechanism: { type: "ball_screw" }, transmission: [], profile: [] };

const state = {
  axis: null,
  project: null, // {id, name, version}
  savedText: null,
  lastSized: "",
  payload: null,
  sizeTimer: null,
  sizeAbort: null,
  sizeSeq: 0,
  yamlTimer: null,
  yamlSeq: 0,
  picks: new Map(),
  pickCache: new Map(),
  deleteArmed: null,
};
let form = null;


function setStatus(text, bad = false) {
  const s = $("status");
  s.textContent = text;
  s.classList.toggle("bad", bad);
}

function axisName() {
  return (state.axis && typeof state.axis.axis === "string" && state.axis.axis) || "axis";
}

function safeName(name) {
  return (name.replace(/[^A-Za-z0-9._-]+/g, "_").replace(/^[._]+|[._]+$/g, "") || "axis").slice(0, 80);
}

// ---------------------------------------------------------------- editor <-> YAML

function setYaml(text) {
  $("yaml-text").value = text;
  showYamlError(null);
  updateSaveState();
}

function showYamlError(message) {
  const p = $("yaml-error");
  p.hidden = !message;
  p.textContent = message || "";
  $("yaml-text").setAttribute("aria-invalid", message ? "true" : "false");
}

function onFormChange(axis) {
  state.axis = axis;
  setYaml(toYaml(axis));
  scheduleSize();
}

async function onYamlInput() {
  clearTimeout(state.yamlTimer);
  updateSaveState();
  document.body.dataset.sizing = "pending";
  state.yamlTimer = setTimeout(async () => {
    const seq = ++state.yamlSeq;
    try {
      const res = await api.post("/api/yaml/parse", { yaml: $("yaml-text").value });
      if (seq !== state.yamlSeq) return;
      showYamlError(null);
      state.axis = res.axis;
      form.pristine.clear(); // an edit in the YAML: every error shows
      form.render(res.axis);
      scheduleSize();
    } catch (err) {
      if (seq !== state.yamlSeq) return;
      showYamlError(err.message);
      // the text does not parse: nothing to size, the result shown stays that of the last axis
      document.body.dataset.sizing = state.sizeAbort ? "busy" : "idle";
    }
  }, YAML_DELAY_MS);
}

function loadAxis(axis, text) {
  state.axis = axis;
  form.load(axis);
  setYaml(text !== undefined ? text : toYaml(axis));
  state.lastSized = "";
  state.picks.clear();
  scheduleSize(0);
}

// ---------------------------------------------------------------- sizing

// body[data-sizing]: "pending" from an edit until its sizing is asked for, "busy" while asked, "idle" when
// the result shown is the answer to the axis as it stands (the browser tests wait for "idle").
function scheduleSize(delay = SIZE_DELAY_MS) {
  clearTimeout(state.sizeTimer);
  document.body.dataset.sizing = "pending";
  state.sizeTimer = setTimeout(runSize, delay);
}

// An axis with nothing entered yet (a new project: a mechanism type, no dimensions, no profile) is not
// sent: the server could only refuse it, and the page makes no failing request on its own.
function nothingToSize(axis) {
  const mechanism = axis && axis.mechanism;
  const profile = axis && axis.profile;
  return (!mechanism || Object.keys(mechanism).every((k) => k === "type")) && (!Array.isArray(profile) || !profile.length);
}

function settle(results) {
  results.setAttribute("aria-busy", "false");
  document.body.dataset.sizing = "idle";
}

async function runSize() {
  const key = JSON.stringify(state.axis);
  const results = document.querySelector(".results");
  if (key === state.lastSized || nothingToSize(state.axis)) {
    // an answer still on its way was asked for another axis: drop it (a newer sequence number)
    if (state.sizeAbort) state.sizeAbort.abort();
    state.sizeAbort = null;
    state.sizeSeq += 1;
    if (key !== state.lastSized) {
      state.lastSized = key;
      state.payload = null;
      renderWaiting();
    }
    settle(results);
    return;
  }
  if (state.sizeAbort) state.sizeAbort.abort();
  const abort = new AbortController();
  state.sizeAbort = abort;
  const seq = ++state.sizeSeq;
  results.setAttribute("aria-busy", "true");
  document.body.dataset.sizing = "busy";
  try {
    const payload = await api.post("/api/size", state.axis, { signal: abort.signal });
    if (seq !== state.sizeSeq) return;
    state.lastSized = key;
    state.payload = payload;
    renderResult(payload);
  } catch (err) {
    if (err.name === "AbortError" || seq !== state.sizeSeq) return;
    state.lastSized = key;
    renderError(err);
  } finally {
    if (seq === state.sizeSeq) {
      state.sizeAbort = null;
      // an edit made while this answer was on its way keeps the page "pending"
      if (document.body.dataset.sizing === "busy") settle(results);
      else results.setAttribute("aria-busy", "false");
      document.body.dataset.sized = String(seq);
    }
  }
}

function renderWaiting() {
  const banner = $("result-banner");
  banner.className = "banner";
  banner.textContent = "Fill in the mechanism (its type, dimensions and load) and the profile to size the axis.";
  $("result-warnings").hidden = true;
  $("error-summary").hidden = true;
  $("result-body").classList.add("stale");
  form.clearErrors();
}

function renderResult(payload) {
  const r = payload.result;
  form.clearErrors();
  $("error-summary").hidden = true;
  $("result-body").classList.remove("stale");
  R.renderBanner($("result-banner"), r);
  if (payload.notes && payload.notes.length) $("result-banner").append(el("span", { class: "muted small", text: ` (${payload.notes.join("; ")})` }));
  R.renderWarnings($("result-warnings"), r);
  R.renderChecks($("checks"), r, payload.electrical);
  R.renderMetrics($("metrics"), r, payload.motion);
  renderOrder($("order-sheet"), r);
  const hasMechanism = R.renderMechanism($("mechanism"), r, payload.modes);
  $("mechanism-title").hidden = !hasMechanism;
  $("mechanism").hidden = !hasMechanism;
  $("plot-modes").hidden = !payload.modes;
  if (payload.modes) plots.drawModes($("plot-modes"), payload.modes);
  else plots.clear($("plot-modes"));
  const keys = new Set((r.candidates || []).map(R.candidateKey));
  for (const k of [...state.picks.keys()]) if (!keys.has(k)) state.picks.delete(k);
  for (const c of r.candidates || []) if (state.picks.has(R.candidateKey(c))) state.picks.set(R.candidateKey(c), c);
  state.pickCache.clear();
  renderCandidatesAndCompare();
  plots.drawProfile($("plot-profile"), payload);
  plots.drawShaft($("plot-shaft"), payload);
  setStatus(`sized in ${Math.round(payload.elapsed_ms)} ms`);
}

function renderError(err) {
  const banner = $("result-banner");
  banner.className = "banner bad";
  $("result-body").classList.add("stale");
  $("result-warnings").hidden = true;
  if (err instanceof ApiError && err.status === 422) {
    const shown = form.showErrors(err.errors);
    banner.textContent = shown.length
      ? `${shown.length} problem${shown.length === 1 ? "" : "s"} in the axis: fix the marked field${shown.length === 1 ? "" : "s"}.`
      : waitingText(form.waitingFor);
    if (!shown.length) banner.className = "banner";
    const box = $("error-summary");
    const list = el("ul");
    for (const e of shown) {
      const item = el("li");
      if (e.element) {
        const b = el("button", { type: "button", class: "link", text: e.message });
        b.addEventListener("click", () => e.element.focus());
        item.append(b);
      } else {
        item.textContent = e.message;
      }
      list.append(item);
    }
    box.replaceChildren(list);
    box.hidden = !shown.length;
    if (!shown.length) {
      setStatus(`waiting for the ${form.waitingFor.join(" and ")}`);
      return;
    }
  } else {
    form.clearErrors();
    $("error-summary").hidden = true;
    banner.textContent = err.message;
  }
  setStatus(err.message.split("\n")[0], true);
}

// What the axis waits for when every error lies in a section the user has not edited yet.
function waitingText(sections) {
  const parts = sections.map((p) => (p === "motor"
    ? "the motor's data (inertia, rated and peak torque, max speed) or its catalog id"
    : p === "mechanism" ? "the mechanism (its type, dimensions and load)" : `the ${p.replace(/[._]/g, " ")}`));
  return `Fill in ${parts.join(" and ")} to size the axis.`;
}

function renderCandidatesAndCompare() {
  const r = state.payload ? state.payload.result : null;
  if (!r) return;
  R.renderCandidates($("candidates"), r, state.picks, togglePick);
  const picks = [...state.picks.values()];
  R.renderCompare($("compare"), picks, () => {
    state.picks.clear();
    renderCandidatesAndCompare();
  });
  drawPlaneWithPicks(picks);
}

function togglePick(candidate, on) {
  const key = R.candidateKey(candidate);
  if (on && state.picks.size < 3) state.picks.set(key, candidate);
  else state.picks.delete(key);
  renderCandidatesAndCompare();
}

async function drawPlaneWithPicks(picks) {
  const payload = state.payload;
  if (picks.length < 2) {
    plots.drawPlane($("plot-plane"), payload);
    return;
  }
  const sizedFor = state.lastSized;
  try {
    const details = await Promise.all(picks.map(async (c) => {
      const key = R.candidateKey(c);
      if (!state.pickCache.has(key)) {
        const q = new URLSearchParams({ motor: c.motor });
        if (c.gearbox) q.set("gearbox", c.gearbox);
        state.pickCache.set(key, api.post(`/api/size/candidate?${q}`, state.axis));
      }
      return state.pickCache.get(key);
    }));
    if (sizedFor !== state.lastSized) return;
    plots.drawPlane($("plot-plane"), payload, details);
  } catch (err) {
    setStatus(err.message, true);
    plots.drawPlane($("plot-plane"), payload);
  }
}

// ---------------------------------------------------------------- projects

function updateSaveState() {
  const text = $("yaml-text").value;
  const s = $("save-state");
  if (!state.project) s.textContent = "not saved yet";
  else if (text === state.savedText) s.textContent = `saved, version ${state.project.version}`;
  else s.textContent = "unsaved changes";
  $("project-actions").hidden = !state.project;
}

async function refreshProjects() {
  let list = [];
  try {
    list = await api.get("/api/projects?kind=axis");
  } catch (err) {
    setStatus(err.message, true);
  }
  const ul = $("project-list");
  ul.replaceChildren();
  for (const p of list) {
    const current = state.project && state.project.id === p.id;
    const b = el("button", { type: "button", class: "project", "aria-current": current ? "true" : undefined, "data-id": String(p.id) },
      el("span", { class: "name", text: p.name }),
      el("span", { class: "meta", text: `v${p.version} · ${new Date(p.updated * 1000).toLocaleString()}` }));
    b.addEventListener("click", () => openProject(p.id));
    ul.append(el("li", {}, b));
  }
  $("no-projects").hidden = list.length > 0;
}

function adopt(detail) {
  state.project = { id: detail.id, name: detail.name, version: detail.version };
  state.savedText = detail.yaml;
  $("project-name").value = detail.name;
  history.replaceState(null, "", `#project=${detail.id}`);
}

async function openProject(id) {
  document.body.dataset.sizing = "pending"; // an axis is on its way (see scheduleSize)
  let loaded = false;
  try {
    const detail = await api.get(`/api/projects/${id}`);
    adopt(detail);
    if (detail.axis) {
      loadAxis(detail.axis, detail.yaml);
      loaded = true;
    } else {
      setYaml(detail.yaml);
      showYamlError(detail.yaml_error ? detail.yaml_error.detail : "the saved text does not parse");
    }
    updateSaveState();
    await Promise.all([refreshProjects(), refreshHistory()]);
    setStatus(`opened ${detail.name}`);
  } catch (err) {
    setStatus(err.message, true);
  } finally {
    if (!loaded) scheduleSize(0); // settles: the axis sized is still the one shown
  }
}

async function saveProject() {
  const text = $("yaml-text").value;
  const name = $("project-name").value.trim() || axisName();
  try {
    let detail;
    if (!state.project) {
      detail = await api.post("/api/projects", { name, yaml: text });
    } else {
      detail = await api.put(`/api/projects/${state.project.id}`, { yaml: text, base_version: state.project.version });
      if (name !== state.project.name) {
        const renamed = await api.patch(`/api/projects/${state.project.id}`, { name });
        detail = { ...detail, name: renamed.name };
      }
    }
    adopt(detail);
    updateSaveState();
    await Promise.all([refreshProjects(), refreshHistory()]);
    setStatus(`saved ${detail.name}, version ${detail.version}`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

async function renameProject() {
  if (!state.project) return;
  const name = $("project-name").value.trim();
  try {
    const p = await api.patch(`/api/projects/${state.project.id}`, { name });
    state.project.name = p.name;
    await refreshProjects();
    setStatus(`renamed to ${p.name}`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

async function duplicateProject() {
  if (!state.project) return;
  try {
    const p = await api.post(`/api/projects/${state.project.id}/duplicate`, {});
    await openProject(p.id);
    setStatus(`duplicated as ${p.name}`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

async function deleteProject() {
  if (!state.project) return;
  const b = $("delete-project");
  if (!confirmedTwice(b, state)) return;
  try {
    const name = state.project.name;
    await api.del(`/api/projects/${state.project.id}`);
    newProject();
    await refreshProjects();
    setStatus(`deleted ${name}`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

async function restoreWith(promise, what) {
  try {
    const detail = await promise;
    adopt(detail);
    if (detail.axis) loadAxis(detail.axis, detail.yaml);
    else setYaml(detail.yaml);
    updateSaveState();
    await Promise.all([refreshProjects(), refreshHistory()]);
    setStatus(`${what}: now version ${detail.version}`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

async function refreshHistory() {
  await renderVersions($("version-list"), state.project, restoreWith);
}

function newProject() {
  state.project = null;
  state.savedText = null;
  $("project-name").value = "";
  history.replaceState(null, "", location.pathname);
  loadAxis(JSON.parse(JSON.stringify(BLANK)));
  form.pristine.add("mechanism"); // a new axis: no error before the user has entered anything
  refreshProjects();
}

// ---------------------------------------------------------------- files

async function uploadYaml(file) {
  const data = new FormData();
  data.append("file", file);
  try {
    const res = await api.post("/api/yaml/upload", data);
    loadAxis(res.axis, res.yaml);
    setStatus(`read ${file.name}`);
  } catch (err) {
    setStatus(err.message, true);
    showYamlError(err.message);
  }
}

function downloadYaml() {
  const blob = new Blob([$("yaml-text").value], { type: "application/yaml" });
  saveBlob(blob, `${safeName(axisName())}.yaml`);
}

async function downloadReport(format) {
  setStatus(`writing the ${format.toUpperCase()} report…`);
  try {
    const response = await api.post(`/api/report?format=${format}`, state.axis, { raw: true });
    const blob = await response.blob();
    saveBlob(blob, filenameOf(response, `${safeName(axisName())}-report.${format}`));
    setStatus(`${format.toUpperCase()} report downloaded`);
  } catch (err) {
    setStatus(err.message, true);
  }
}

// ---------------------------------------------------------------- views

function showView(name) {
  const editor = name === "editor";
  for (const v of ["editor", "machine", "catalog"]) {
    $(`view-${v}`).hidden = v !== name;
    $(`tab-${v}`).setAttribute("aria-pressed", String(v === name));
  }
  setStatus("");
  if (name === "catalog") catalogView.open();
  else if (name === "machine") {
    history.replaceState(null, "", machineView.project ? `#machine=${machineView.project.id}` : location.pathname);
    machineView.open();
  } else history.replaceState(null, "", state.project ? `#project=${state.project.id}` : location.pathname);
  if (editor && state.payload) {
    plots.drawProfile($("plot-profile"), state.payload);
    plots.drawShaft($("plot-shaft"), state.payload);
    drawPlaneWithPicks([...state.picks.values()]);
  }
}

let catalogView = null;
let machineView = null;

async function init() {
  const desc = await api.get("/api/form");
  form = new AxisForm($("axis-form"), desc, onFormChange);
  catalogView = new CatalogView({
    motors: $("cat-motors"), gearboxes: $("cat-gearboxes"), drives: $("cat-drives"), filters: $("catalog-filters"), table: $("catalog-table"),
    prev: $("cat-prev"), next: $("cat-next"), page: $("cat-page"), envelope: $("plot-envelope"), detail: $("catalog-detail"),
    importForm: $("import-form"), importResult: $("import-result"),
  }, setStatus);
  machineView = new MachineView({
    setStatus,
    openAxisProject: async (id) => {
      showView("editor");
      await openProject(id);
    },
    openAxis: (axis) => {
      showView("editor");
      state.project = null;
      state.savedText = null;
      $("project-name").value = "";
      history.replaceState(null, "", location.pathname);
      loadAxis(axis);
      updateSaveState();
      refreshProjects();
      setStatus(`opened the machine's axis ${axis.axis || ""} (not saved)`);
    },
  });

  $("yaml-text").addEventListener("input", onYamlInput);
  $("new-project").addEventListener("click", newProject);
  $("save-project").addEventListener("click", saveProject);
  $("rename-project").addEventListener("click", renameProject);
  $("duplicate-project").addEventListener("click", duplicateProject);
  $("delete-project").addEventListener("click", deleteProject);
  $("undo-project").addEventListener("click", () => state.project && restoreWith(api.post(`/api/projects/${state.project.id}/undo`), "undone"));
  $("history").addEventListener("toggle", refreshHistory);
  $("upload-yaml").addEventListener("click", () => $("upload-input").click());
  $("upload-input").addEventListener("change", (e) => {
    const file = e.target.files && e.target.files[0];
    if (file) uploadYaml(file);
    e.target.value = "";
  });
  $("download-yaml").addEventListener("click", downloadYaml);
  $("report-html").addEventListener("click", () => downloadReport("html"));
  $("report-pdf").addEventListener("click", () => downloadReport("pdf"));
  $("tab-editor").addEventListener("click", () => showView("editor"));
  $("tab-catalog").addEventListener("click", () => showView("catalog"));
  $("tab-machine").addEventListener("click", () => showView("machine"));
  $("project-name").addEventListener("keydown", (e) => {
    if (e.key === "Enter") saveProject();
  });
  document.addEventListener("keydown", (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === "s") {
      e.preventDefault();
      saveProject();
    }
  });
  $("example-select").addEventListener("change", async (e) => {
    const name = e.target.value;
    if (!name) return;
    document.body.dataset.sizing = "pending"; // an axis is on its way (see scheduleSize)
    try {
      const ex = await api.get(`/api/examples/${encodeURIComponent(name)}`);
      loadAxis(ex.axis, ex.yaml);
      setStatus(`loaded the ${name} example (not saved)`);
    } catch (err) {
      setStatus(err.message, true);
      scheduleSize(0); // settles: the axis shown is still the one sized
    }
    e.target.value = "";
  });
  try {
    const names = await api.get("/api/examples");
    for (const n of names) $("example-select").append(el("option", { value: n, text: n.replace(/_/g, " ") }));
  } catch (err) {
    /* examples are optional */
  }
  const m = /^#project=(\d+)$/.exec(location.hash);
  const mm = /^#machine=(\d+)$/.exec(location.hash);
  await refreshProjects();
  if (m) await openProject(Number(m[1]));
  else newProject();
  if (mm) {
    showView("machine");
    await machineView.openProject(Number(mm[1]));
  }
  document.body.dataset.ready = "1";
}

init().catch((err) => setStatus(`the page could not start: ${err.message}`, true));
