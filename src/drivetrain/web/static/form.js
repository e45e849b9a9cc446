// The axis editor form, built from the server's form description (GET /api/form), which comes
// from the same model the CLI validates axis files with. Every input carries data-path, the
// dotted field path of the axis file ("mechanism.load.mass", "transmission[0].ratio",
// "profile[2].time"), so an error from the server is shown at the input that caused it.

import { el, getAt, idFor, joinPath, label, parsePath, readText, setAt, show, unitHint, unitOf } from "./formkit.js";
import { profileMethods } from "./profile.js";

export { joinPath, parsePath } from "./formkit.js";

const STEP_ORDER = ["move", "speed", "dwell", "time", "max_speed", "max_accel", "max_jerk", "accel", "decel", "shape", "law",
  "jerk_fraction", "jerk", "thrust", "holding"];

// Keys of motor: that a catalog selection takes beside select (docs/axis-file.md, "Electrical data").
const SELECTION_SUPPLY = ["supply_voltage", "dc_bus_voltage"];

export class AxisForm {
  constructor(root, desc, onChange) {
    this.root = root;
    this.desc = desc;
    this.onChange = onChange;
    this.axis = {};
    this.rendering = false;
    // Paths of sections the form just created empty (a given motor): their "is required" errors
    // wait until the user edits something inside.
    this.pristine = new Set();
    this.waitingFor = [];
    // The last type change's notice: {path, text}, shown in that section until the next edit.
    this.notice = null;
    root.addEventListener("input", (e) => this.onInput(e));
    root.addEventListener("change", (e) => this.onInput(e));
    root.addEventListener("submit", (e) => e.preventDefault());
  }

  // The axis with its keys in the axis file's order (type first, then the model's fields), so the
  // YAML reads the same however the form was filled in.
  value() {
    return this.ordered(JSON.parse(JSON.stringify(this.axis)), { kind: "object", fields: this.desc.axis.fields });
  }

  ordered(value, f) {
    if (value === null || typeof value !== "object" || !f) return value;
    if (Array.isArray(value)) {
      if (f.kind === "profile") return value.map((step) => this.orderKeys(step, STEP_ORDER.map((name) => ({ name }))));
      return f.kind === "list" ? value.map((v) => this.ordered(v, f.item)) : value;
    }
    if (f.kind === "union") {
      const variant = f.variants[value[f.tag]];
      return this.orderKeys(value, [{ name: f.tag }, ...(variant ? variant.fields : [])]);
    }
    if (f.kind === "object") return this.orderKeys(value, f.fields);
    return value;
  }

  orderKeys(obj, fields) {
    if (obj === null || typeof obj !== "object" || Array.isArray(obj)) return obj;
    const out = {};
    for (const f of fields) if (obj[f.name] !== undefined) out[f.name] = this.ordered(obj[f.name], f.kind ? f : null);
    for (const [k, v] of Object.entries(obj)) if (!(k in out)) out[k] = v;
    return out;
  }

  // A new axis (a project, an example, a file): nothing is pristine, no notice.
  load(axis) {
    this.pristine.clear();
    this.notice = null;
    this.render(axis);
  }

  render(axis) {
    this.axis = JSON.parse(JSON.stringify(axis || {}));
    const focused = document.activeElement && this.root.contains(document.activeElement) ? document.activeElement.id : null;
    const open = new Set([...this.root.querySelectorAll("details[open]")].map((d) => d.dataset.key));
    // Removing a focused input fires its change event: an old value must not come back from it.
    this.rendering = true;
    try {
      this.root.replaceChildren(this.objectFields(this.desc.axis.fields, this.axis, ""));
    } finally {
      this.rendering = false;
    }
    for (const d of this.root.querySelectorAll("details")) if (open.has(d.dataset.key)) d.open = true;
    if (focused) {
      const again = document.getElementById(focused);
      if (again) again.focus();
    }
  }

  changed(structural) {
    if (structural) this.render(this.axis);
    this.onChange(this.value());
  }

  onInput(event) {
    if (this.rendering) return;
    const input = event.target;
    if (!input.dataset || input.dataset.path === undefined) return;
    if (["toggle", "type", "step-kind", "motor-mode"].includes(input.dataset.role)) {
      if (event.type !== "change") return;
    }
    const path = input.dataset.path;
    const parts = parsePath(path);
    const role = input.dataset.role;
    if (role !== "motor-mode") this.touch(path);
    if (role === "toggle") {
      // A new motor starts as a catalog selection: nothing to fill in before it sizes.
      setAt(this.axis, parts, input.checked ? (path === "motor" ? { select: {} } : {}) : undefined);
      this.changed(true);
      return;
    }
    if (role === "motor-mode") {
      this.setMotorMode(input.value);
      return;
    }
    if (role === "type") {
      this.changeType(parts.slice(0, -1), input.value, input.dataset.union);
      return;
    }
    if (role === "step-kind") {
      this.changeStepKind(parts, input.value);
      return;
    }
    if (role === "other") {
      this.setOtherKeys(parts, input.value);
      this.onChange(this.value());
      return;
    }
    if (input.dataset.kind === "quantity") this.showUnit(input);
    let value;
    if (input.type === "checkbox") value = input.checked;
    else if (input.tagName === "SELECT") value = input.value === "" ? undefined : input.value;
    else value = readText(input.value, input.dataset.numeric === "1");
    setAt(this.axis, parts, value);
    if (input.dataset.structural === "1" && event.type === "change") this.changed(true);
    else this.onChange(this.value());
  }

  // An edit at ``path``: the sections holding it are no longer pristine; a type notice goes.
  touch(path) {
    for (const p of [...this.pristine]) if (path === p || path.startsWith(p + ".") || path.startsWith(p + "[")) this.pristine.delete(p);
    if (this.notice && (path === this.notice.path || path.startsWith(this.notice.path + ".") || path.startsWith(this.notice.path + "["))) {
      this.notice = null;
      for (const n of this.root.querySelectorAll(".type-notice")) n.remove();
    }
  }

  // The motor: "catalog" (motor.select, the default) or "given" (its data or a catalog id).
  setMotorMode(mode) {
    const motor = getAt(this.axis, ["motor"]) || {};
    const next = {};
    for (const [k, v] of Object.entries(motor)) if (k !== "select") next[k] = v;
    if (mode === "catalog") next.select = motor.select || {};
    else if (!Object.keys(next).some((k) => k !== "margins")) this.pristine.add("motor");
    setAt(this.axis, ["motor"], next);
    this.changed(true);
  }

  // The unit beside a quantity input: the one the user writes (see unitOf).
  showUnit(input) {
    const span = input.closest(".field") && input.closest(".field").querySelector(".unit");
    if (!span) return;
    const f = { quantity: input.dataset.quantity, unit: input.dataset.unitSi, example_unit: input.dataset.exampleUnit,
      default: input.dataset.default === undefined ? undefined : Number(input.dataset.default) };
    span.textContent = `[${unitOf(f, input.value)}]`;
  }

  // ---------------------------------------------------------------- objects and fields

  objectFields(fields, obj, prefix) {
    const box = el("div", { class: "fields" });
    const basic = fields.filter((f) => !f.advanced);
    const advanced = fields.filter((f) => f.advanced);
    for (const f of basic) box.append(this.field(f, obj ? obj[f.name] : undefined, joinPath(prefix, f.name)));
    if (advanced.length) {
      const hasValue = advanced.some((f) => obj && obj[f.name] !== undefined);
      const details = el("details", { class: "more", dataset: { key: `more:${prefix}` } });
      details.open = hasValue;
      const last = prefix ? prefix.split(".").pop() : "axis";
      const what = /\[\d+\]$/.test(last) || !last ? "" : `${last.replace(/_/g, " ")} `;
      details.append(el("summary", { text: `More ${what}options (${advanced.length})` }));
      for (const f of advanced) details.append(this.field(f, obj ? obj[f.name] : undefined, joinPath(prefix, f.name)));
      box.append(details);
    }
    return box;
  }

  field(f, value, path) {
    switch (f.kind) {
      case "object":
        return this.objectField(f, value, path);
      case "union":
        return this.unionField(f, value, path);
      case "list":
        return this.listField(f, value, path);
      case "profile":
        return this.profileField(f, value, path);
      case "mapping":
        return this.mappingField(f, value, path);
      case "enum":
        return this.enumField(f, value, path);
      case "bool":
        return this.boolField(f, value, path);
      default:
        return this.inputField(f, value, path);
    }
  }

  inputField(f, value, path) {
    const id = idFor(path);
    const numeric = f.kind === "quantity" || f.kind === "number" || f.kind === "integer";
    let placeholder = "";
    if (f.kind === "quantity") {
      placeholder = f.default !== undefined && f.default !== null ? `default ${f.default}`
        : f.quantity === "dimensionless" ? "number" : `e.g. 1 ${f.example_unit || f.unit}`;
    } else if (f.default !== undefined && f.default !== null) {
      placeholder = `default ${show(f.default)}`;
    }
    const quantity = f.kind === "quantity";
    const input = el("input", {
      id, type: "text", value: show(value), placeholder, "data-path": path, "data-kind": f.kind,
      "data-numeric": numeric ? "1" : "0", inputmode: f.kind === "integer" ? "numeric" : undefined,
      "aria-required": f.required ? "true" : undefined, spellcheck: "false",
      "data-quantity": quantity ? f.quantity : undefined, "data-unit-si": quantity ? f.unit || "" : undefined,
      "data-example-unit": quantity ? f.example_unit || "" : undefined,
      "data-default": quantity && typeof f.default === "number" ? String(f.default) : undefined,
    });
    const unitText = quantity ? `[${unitOf(f, value)}]` : "";
    const hint = quantity ? unitHint(f) : f.help || "";
    const wrap = el("div", { class: "field", "data-field": path },
      el("label", { for: id, text: label(f.label) + (f.required ? " *" : "") }),
      input,
      el("span", { class: "unit", text: unitText, title: hint }),
    );
    if (hint) input.title = hint;
    return wrap;
  }

  enumField(f, value, path) {
    const id = idFor(path);
    const select = el("select", { id, "data-path": path, "data-kind": "enum" });
    const blank = f.default !== undefined && f.default !== null ? `(default: ${f.default})` : "—";
    if (!f.required || f.default !== undefined) select.append(el("option", { value: "", text: blank }));
    for (const o of f.options) select.append(el("option", { value: String(o), text: String(o) }));
    select.value = value === undefined || value === null ? "" : String(value);
    return el("div", { class: "field", "data-field": path }, el("label", { for: id, text: label(f.label) }), select, el("span", { class: "unit" }));
  }

  boolField(f, value, path) {
    const id = idFor(path);
    const box = el("input", { id, type: "checkbox", "data-path": path, "data-kind": "bool" });
    box.checked = Boolean(value);
    return el("div", { class: "field check", "data-field": path }, box, el("label", { for: id, text: label(f.label) }));
  }

  objectField(f, value, path) {
    const fs = el("fieldset", { class: "group", "data-path": path, "data-field": path });
    if (f.nullable) {
      const id = idFor(path) + "-on";
      const toggle = el("input", { id, type: "checkbox", "data-path": path, "data-role": "toggle" });
      toggle.checked = value !== undefined && value !== null;
      fs.append(el("legend", {}, toggle, el("label", { for: id, text: ` ${label(f.label)}` })));
      if (!toggle.checked) {
        fs.classList.add("off");
        return fs;
      }
    } else {
      fs.append(el("legend", { text: label(f.label) }));
    }
    if (path === "motor") {
      fs.append(this.motorFields(f, value || {}, path));
      return fs;
    }
    fs.append(this.objectFields(f.fields, value || {}, path));
    return fs;
  }

  // The motor: first the choice (select from the catalog, the default; or a given motor), then
  // the fields of that choice and the margins.
  motorFields(f, value, path) {
    const box = el("div", { class: "fields" });
    const catalog = value.select !== undefined && value.select !== null;
    const radio = (mode, id, text, checked) => {
      const r = el("input", { type: "radio", id, name: "motor-mode", value: mode, "data-path": path, "data-role": "motor-mode" });
      r.checked = checked;
      return el("label", { class: "choice", for: id }, r, ` ${text}`);
    };
    box.append(el("div", { class: "motor-mode", role: "radiogroup", "aria-label": "Motor" },
      radio("catalog", "f-motor-select-on", "Select from the catalog (ranks motors and gearboxes)", catalog),
      radio("given", "f-motor-given-on", "A given motor (its data, or a catalog id)", !catalog)));
    const select = f.fields.find((x) => x.name === "select");
    const margins = f.fields.filter((x) => x.name === "margins");
    const given = f.fields.filter((x) => x.name !== "select" && x.name !== "margins");
    if (catalog) {
      box.append(this.objectField({ ...select, nullable: false, label: "Selection" }, value.select, joinPath(path, "select")));
      // the machine's supply, used for every candidate (the only given keys a selection takes)
      box.append(this.objectFields(given.filter((x) => SELECTION_SUPPLY.includes(x.name)), value, path));
    } else box.append(this.objectFields(given, value, path));
    box.append(this.objectFields(margins, value, path));
    return box;
  }

  unionField(f, value, path, extra = null) {
    const fs = el("fieldset", { class: "group union", "data-path": path, "data-field": path });
    fs.append(el("legend", { text: label(f.label) }));
    if (extra) fs.append(extra);
    const types = this.typeOrder(f);
    const current = value && value[f.tag] !== undefined ? String(value[f.tag]) : "";
    const id = idFor(joinPath(path, f.tag));
    const select = el("select", { id, "data-path": joinPath(path, f.tag), "data-role": "type", "data-union": f.name });
    if (!current) select.append(el("option", { value: "", text: "choose…" }));
    for (const t of types) select.append(el("option", { value: t, text: t }));
    select.value = current;
    fs.append(el("div", { class: "field", "data-field": joinPath(path, f.tag) }, el("label", { for: id, text: "Type" }), select, el("span", { class: "unit" })));
    if (this.notice && this.notice.path === path) fs.append(el("p", { class: "type-notice", role: "status", text: this.notice.text }));
    const variant = f.variants[current];
    if (variant) fs.append(this.objectFields(variant.fields, value, path));
    return fs;
  }

  typeOrder(f) {
    const known = f.name === "mechanism" ? this.desc.mechanism_types : f.name === "item" || f.name === "transmission" ? this.desc.transmission_types : null;
    const variants = Object.keys(f.variants);
    if (!known) return variants;
    return [...known.filter((t) => variants.includes(t)), ...variants.filter((t) => !known.includes(t))];
  }

  // A new type keeps what applies to it and clears the rest, saying which: every field when both
  // types share one model (ball_screw and lead_screw); otherwise only the fields that mean the same
  // for every type (efficiency, incline, the load when its model is the same). A screw's diameter
  // is not a pinion's pitch diameter.
  changeType(parts, type, unionName) {
    const old = getAt(this.axis, parts) || {};
    const spec = this.findUnion(parts, unionName);
    const variant = spec ? spec.variants[type] : null;
    const before = spec && old.type !== undefined ? spec.variants[old.type] : null;
    const shared = new Set(this.desc.type_independent || []);
    const next = { type };
    const cleared = [];
    for (const [k, v] of Object.entries(old)) {
      if (k === "type" || v === undefined) continue;
      const now = variant ? variant.fields.find((x) => x.name === k) : null;
      const was = before ? before.fields.find((x) => x.name === k) : null;
      const sameModel = variant && before && variant.title && variant.title === before.title;
      const sameMeaning = now && shared.has(k) && (!was || now.kind !== "object" || now.title === was.title);
      if (now && (sameModel || sameMeaning)) next[k] = v;
      else cleared.push(k);
    }
    const path = parts.map((p, i) => (typeof p === "number" ? `[${p}]` : (i ? "." : "") + p)).join("");
    this.notice = cleared.length
      ? { path, text: `Changed to ${type}: cleared ${cleared.join(", ")} (${old.type ? `they belong to the ${old.type}` : "they do not apply"}); kept ${Object.keys(next).filter((k) => k !== "type").join(", ") || "nothing else"}.` }
      : null;
    setAt(this.axis, parts, next);
    this.changed(true);
  }

  findUnion(parts, unionName) {
    const top = this.desc.axis.fields;
    if (parts[0] === "mechanism") return top.find((f) => f.name === "mechanism");
    if (parts[0] === "transmission") return top.find((f) => f.name === "transmission").item;
    return null;
  }

  listField(f, value, path) {
    const list = Array.isArray(value) ? value : [];
    const fs = el("fieldset", { class: "group list", "data-path": path, "data-field": path });
    fs.append(el("legend", { text: label(f.label) }));
    const item = f.item;
    list.forEach((entry, k) => {
      const itemPath = joinPath(path, k);
      const controls = el("div", { class: "item-controls" },
        this.button("↑", `Move ${f.label} element ${k + 1} up`, () => this.moveItem(path, k, -1), k === 0),
        this.button("↓", `Move ${f.label} element ${k + 1} down`, () => this.moveItem(path, k, 1), k === list.length - 1),
        this.button("Remove", `Remove ${f.label} element ${k + 1}`, () => this.removeItem(path, k)),
      );
      if (item.kind === "union") {
        const sub = this.unionField({ ...item, name: f.name, label: `${f.label} ${k + 1} (from the motor outward)` }, entry, itemPath, controls);
        fs.append(sub);
      } else if (item.kind === "object") {
        const sub = el("fieldset", { class: "group", "data-path": itemPath, "data-field": itemPath },
          el("legend", { text: `${label(f.label)} ${k + 1}` }), controls, this.objectFields(item.fields, entry || {}, itemPath));
        fs.append(sub);
      } else {
        fs.append(el("div", { class: "item" }, this.inputField({ ...item, label: `${f.label} ${k + 1}` }, entry, itemPath), controls));
      }
    });
    const add = el("div", { class: "row add" });
    if (item.kind === "union") {
      const id = idFor(path) + "-add-type";
      const select = el("select", { id });
      for (const t of this.typeOrder({ ...item, name: f.name })) select.append(el("option", { value: t, text: t }));
      add.append(el("label", { for: id, text: "Add" }), select,
        this.button("Add element", `Add a ${f.label} element of the chosen type`, () => this.addItem(path, { type: select.value })));
    } else {
      add.append(this.button(`Add ${f.label.replace(/s$/, "")}`, null, () => this.addItem(path, item.kind === "object" ? {} : "")));
    }
    fs.append(add);
    return fs;
  }

  button(text, aria, onClick, disabled = false) {
    const b = el("button", { type: "button", text, "aria-label": aria || undefined, class: "small" });
    b.disabled = disabled;
    b.addEventListener("click", onClick);
    return b;
  }

  addItem(path, entry) {
    const parts = parsePath(path);
    const list = getAt(this.axis, parts);
    if (Array.isArray(list)) list.push(entry);
    else setAt(this.axis, parts, [entry]);
    this.changed(true);
  }

  removeItem(path, k) {
    const list = getAt(this.axis, parsePath(path));
    if (Array.isArray(list)) list.splice(k, 1);
    this.changed(true);
  }

  moveItem(path, k, delta) {
    const list = getAt(this.axis, parsePath(path));
    const j = k + delta;
    if (!Array.isArray(list) || j < 0 || j >= list.length) return;
    [list[k], list[j]] = [list[j], list[k]];
    this.changed(true);
  }

  mappingField(f, value, path) {
    const fs = el("fieldset", { class: "group", "data-path": path, "data-field": path });
    fs.append(el("legend", { text: label(f.label) }));
    const note = value === undefined || value === null
      ? "Not set. Edit this section in the YAML pane."
      : `Set in the YAML pane (${Object.keys(value).length} keys).`;
    fs.append(el("p", { class: "muted", text: note }));
    return fs;
  }

  // ---------------------------------------------------------------- errors

  // The section (a path) holding an error the user has not edited yet (it waits for the first
  // edit there), else null.
  waiting(field) {
    if (field === undefined || field === null) return null;
    for (const p of this.pristine) if (field === p || field.startsWith(p + ".") || field.startsWith(p + "[")) return p;
    return null;
  }

  clearErrors() {
    for (const node of this.root.querySelectorAll(".field-error")) node.remove();
    for (const node of this.root.querySelectorAll("[aria-invalid]")) {
      node.removeAttribute("aria-invalid");
      node.removeAttribute("aria-describedby");
    }
    for (const node of this.root.querySelectorAll(".invalid")) node.classList.remove("invalid");
  }

  // The element showing the field at ``path`` (or its closest shown parent).
  target(path) {
    if (!path) return null;
    const esc = (p) => (window.CSS && CSS.escape ? CSS.escape(p) : p.replace(/"/g, '\\"'));
    let p = path;
    const profileKey = /^(profile\[\d+\])\.(\w+)$/.exec(path);
    if (profileKey && !this.root.querySelector(`[data-path="${esc(path)}"]`)) {
      const other = this.root.querySelector(`[data-role="other"][data-path="${esc(profileKey[1])}"]`);
      if (other) return other;
    }
    while (p) {
      const found = this.root.querySelector(`[data-path="${esc(p)}"]:not([data-role="toggle"]):not([data-role="other"])`)
        || this.root.querySelector(`[data-field="${esc(p)}"]`);
      if (found) return found;
      const cut = Math.max(p.lastIndexOf("."), p.lastIndexOf("["));
      if (cut <= 0) break;
      p = p.slice(0, cut);
    }
    return null;
  }

  // Mark each error at its field; returns [{field, message, element}] in order.
  showErrors(errors) {
    this.clearErrors();
    const shown = [];
    this.waitingFor = [];
    errors.forEach((err, k) => {
      const section = this.waiting(err.field);
      if (section) {
        if (!this.waitingFor.includes(section)) this.waitingFor.push(section);
        return;
      }
      const node = this.target(err.field);
      if (!node) {
        shown.push({ ...err, element: null });
        return;
      }
      const msgId = `err-${k}`;
      const text = err.field && err.message.startsWith(err.field + ": ") ? err.message.slice(err.field.length + 2) : err.message;
      const p = el("p", { class: "field-error", id: msgId, text: err.field && !err.message.startsWith(err.field) ? `${err.field}: ${text}` : text });
      let input = node;
      if (node.tagName === "TBODY") {
        const cell = el("td", { colspan: "8" }, p);
        node.append(el("tr", { class: "row-error" }, cell));
        input = node.querySelector("select") || node;
      } else if (node.tagName === "FIELDSET" || node.tagName === "TR" || node.classList.contains("field")) {
        input = node.querySelector("input:not([type=checkbox]):not(:disabled), select:not(:disabled)") || node;
        if (node.tagName === "FIELDSET") {
          const legend = node.querySelector(":scope > legend");
          (legend || node.firstChild) ? (legend ? legend.after(p) : node.prepend(p)) : node.append(p);
          input = node;
        } else if (node.tagName === "TR") {
          const cell = el("td", { colspan: String(node.children.length) }, p);
          const row = el("tr", { class: "row-error" }, cell);
          node.after(row);
          input = node.querySelector("select") || node;
        } else {
          node.append(p);
        }
      } else if (node.closest(".field")) {
        node.closest(".field").append(p);
      } else if (node.closest("tbody.step")) {
        node.closest("tbody.step").append(el("tr", { class: "row-error" }, el("td", { colspan: "8" }, p)));
      } else {
        node.after(p);
      }
      input.classList.add("invalid");
      if (input.matches && input.matches("input, select, textarea")) {
        input.setAttribute("aria-invalid", "true");
        input.setAttribute("aria-describedby", msgId);
      }
      for (let d = input.closest("details"); d; d = d.parentElement.closest("details")) d.open = true;
      shown.push({ ...err, element: input });
    });
    return shown;
  }
}

Object.assign(AxisForm.prototype, profileMethods);
