// The profile table of the axis editor: one row per step, a field for every key a step of the
// axis file takes (move, time, accel, decel, shape, jerk_fraction, jerk, speed, max_speed,
// max_accel, max_jerk, law, thrust, dwell, holding), chosen by the step's kind (a move, a move
// by speed, a time-optimal move, a cam law move, a dwell). Mixed into AxisForm (this = the form).

import { el, getAt, idFor, joinPath, readText, setAt, show } from "./formkit.js";

const MAIN = ["move", "time", "accel", "decel", "shape"];
// The main column a key is shown in when the step's kind puts it there.
const IN_COLUMN = { speed: "move", dwell: "time" };
const SHAPED = ["jerk_fraction", "jerk"];

export function stepKind(step) {
  if (!step || typeof step !== "object") return "move";
  if (step.dwell !== undefined) return "dwell";
  if (step.law !== undefined) return "cam";
  if (step.max_speed !== undefined || step.max_accel !== undefined || step.max_jerk !== undefined) return "optimal";
  if (step.speed !== undefined && step.move === undefined) return "speed";
  return "move";
}

export const profileMethods = {
  kindKeys(kind) {
    const k = this.desc.profile.kinds.find((x) => x.kind === kind);
    return k ? k.keys : [];
  },

  profileField(f, value, path) {
    const steps = Array.isArray(value) ? value : [];
    const columns = this.desc.profile.columns;
    const main = columns.filter((c) => MAIN.includes(c.key));
    const fs = el("fieldset", { class: "group profile", "data-path": path, "data-field": path });
    fs.append(el("legend", { text: "Profile: moves and dwells (the cycle repeats)" }));
    if (!steps.length) fs.append(el("p", { class: "muted", text: "No steps yet: add a move (distance and time) and a dwell." }));
    const table = el("table", { class: "profile-table", hidden: steps.length === 0 });
    const head = el("tr", {}, el("th", { scope: "col", text: "#" }), el("th", { scope: "col", text: "Step" }));
    for (const c of main) head.append(el("th", { scope: "col", text: c.label, title: c.hint || "" }));
    head.append(el("th", { scope: "col" }, el("span", { class: "sr-only", text: "Actions" })));
    table.append(el("thead", {}, head));
    steps.forEach((step, k) => table.append(this.profileRows(step || {}, k, steps.length, path, main)));
    fs.append(el("div", { class: "table-wrap" }, table));
    fs.append(el("div", { class: "row add" },
      this.button("Add move", "Add a move step", () => this.addItem(path, { move: "", time: "" })),
      this.button("Add dwell", "Add a dwell step", () => this.addItem(path, { dwell: "" }))));
    return fs;
  },

  stepInput(c, step, k, rowPath, key = c.key) {
    const cellPath = joinPath(rowPath, key);
    const shown = this.desc.profile.columns.find((x) => x.key === key) || c;
    let input;
    if (shown.options) {
      input = el("select", {
        id: idFor(cellPath), "data-path": cellPath, "aria-label": `Step ${k + 1} ${shown.label}`,
        "data-structural": key === "shape" ? "1" : undefined,
      });
      for (const o of shown.options) input.append(el("option", { value: o, text: o || "—" }));
      input.value = step[key] === undefined ? "" : String(step[key]);
    } else {
      input = el("input", {
        id: idFor(cellPath), type: "text", value: show(step[key]), "data-path": cellPath, "data-numeric": "1",
        "aria-label": `Step ${k + 1} ${shown.label}`, placeholder: shown.hint.split(" (")[0], spellcheck: "false",
        title: shown.hint,
      });
    }
    return input;
  },

  profileRows(step, k, n, path, main) {
    const rowPath = joinPath(path, k);
    const kind = stepKind(step);
    const keys = this.kindKeys(kind);
    const group = el("tbody", { class: "step", "data-path": rowPath, "data-field": rowPath, "data-kind": kind });
    const tr = el("tr");
    tr.append(el("th", { scope: "row", rowspan: "2", text: String(k + 1) }));
    const select = el("select", { id: idFor(rowPath) + "-kind", "data-path": rowPath, "data-role": "step-kind", "aria-label": `Step ${k + 1} kind` });
    for (const x of this.desc.profile.kinds) select.append(el("option", { value: x.kind, text: x.label, title: x.hint }));
    select.value = kind;
    const current = this.desc.profile.kinds.find((x) => x.kind === kind);
    if (current) select.title = current.hint;
    tr.append(el("td", {}, select));
    const inMain = new Set();
    for (const c of main) {
      const key = keys.find((x) => x === c.key || IN_COLUMN[x] === c.key);
      if (key) inMain.add(key);
      tr.append(el("td", {}, key ? this.stepInput(c, step, k, rowPath, key) : ""));
    }
    tr.append(el("td", { class: "row-buttons" },
      this.button("↑", `Move step ${k + 1} up`, () => this.moveItem(path, k, -1), k === 0),
      this.button("↓", `Move step ${k + 1} down`, () => this.moveItem(path, k, 1), k === n - 1),
      this.button("✕", `Remove step ${k + 1}`, () => this.removeItem(path, k))));
    group.append(tr);
    const more = el("div", { class: "step-more" });
    for (const key of keys) {
      if (inMain.has(key)) continue;
      if (SHAPED.includes(key) && step.shape !== "s_curve" && step[key] === undefined) continue;
      const c = this.desc.profile.columns.find((x) => x.key === key);
      if (!c) continue;
      const input = this.stepInput(c, step, k, rowPath);
      more.append(el("label", { for: input.id, text: c.label }), input);
    }
    // Keys the step's kind does not take (or no step takes): shown, so nothing is hidden.
    const other = Object.entries(step).filter(([key]) => !keys.includes(key));
    if (other.length) {
      const otherId = idFor(joinPath(rowPath, "_other"));
      more.append(el("label", { for: otherId, text: "Other keys" }), el("input", {
        id: otherId, type: "text", value: other.map(([a, b]) => `${a}: ${show(b)}`).join("; "),
        "data-path": rowPath, "data-role": "other", spellcheck: "false", class: "other",
        title: `keys a ${kind} step does not take, as key: value; …`,
      }));
    }
    group.append(el("tr", { class: "step-extra" }, el("td", { colspan: String(main.length + 2) }, more)));
    return group;
  },

  changeStepKind(parts, kind) {
    const step = getAt(this.axis, parts) || {};
    const distance = step.move !== undefined ? step.move : "";
    const time = step.time !== undefined ? step.time : step.dwell !== undefined ? step.dwell : "";
    let next;
    if (kind === "dwell") next = { dwell: time };
    else if (kind === "speed") next = { speed: step.speed !== undefined ? step.speed : "", time };
    else if (kind === "optimal") {
      next = { move: distance, max_speed: step.max_speed !== undefined ? step.max_speed : "", max_accel: step.max_accel !== undefined ? step.max_accel : "" };
    } else if (kind === "cam") next = { move: distance, time, law: step.law || "cycloidal" };
    else next = { move: distance, time };
    if (kind !== "dwell" && step.thrust !== undefined) next.thrust = step.thrust;
    setAt(this.axis, parts, next);
    this.changed(true);
  },

  setOtherKeys(parts, text) {
    const step = getAt(this.axis, parts) || {};
    const keys = this.kindKeys(stepKind(step));
    for (const key of Object.keys(step)) if (!keys.includes(key)) delete step[key];
    for (const piece of text.split(";")) {
      const m = /^\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(.*?)\s*$/.exec(piece);
      if (m && m[2] !== "") step[m[1]] = readText(m[2], true);
    }
    setAt(this.axis, parts, step);
  },
};
