// The axis editor form, built from the server's form description (GET /api/form), which comes
// from the same model the CLI validates axis files with. Every input carries data-path, the
// dotted field path of the axis file ("mechanism.load.mass", "transmission[0].ratio",
// "profile[2].time"), so an error from the server is shown at the input that caused it.

const NUMBER = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;
const PROFILE_FIXED = ["move", "time", "dwell", "accel", "decel", "shape", "jerk_fraction", "thrust", "holding"];
const STEP_ORDER = ["move", "speed", "dwell", "time", "max_speed", "max_accel", "max_jerk", "accel", "decel", "shape", "law",
  "jerk_fraction", "jerk", "thrust", "holding"];

export function parsePath(path) {
  const parts = [];
  const re = /([^.[\]]+)|\[(\d+)\]/g;
  let m;
  while ((m = re.exec(path)) !== null) parts.push(m[2] !== undefined ? Number(m[2]) : m[1]);
  return parts;
}

export function joinPath(prefix, name) {
  if (typeof name === "number") return `${prefix}[${name}]`;
  return prefix ? `${prefix}.${name}` : name;
}

function getAt(obj, parts) {
  let node = obj;
  for (const p of parts) {
    if (node === null || typeof node !== "object") return undefined;
    node = node[p];
  }
  return node;
}

function setAt(obj, parts, value) {
  let node = obj;
  for (let k = 0; k < parts.length - 1; k++) {
    const p = parts[k];
    if (node[p] === null || typeof node[p] !== "object") node[p] = typeof parts[k + 1] === "number" ? [] : {};
    node = node[p];
  }
  const last = parts[parts.length - 1];
  if (value === undefined) {
    if (Array.isArray(node)) node[last] = null;
    else delete node[last];
  } else {
    node[last] = value;
  }
}

function idFor(path) {
  return "f-" + path.replace(/[^A-Za-z0-9]+/g, "-");
}

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === "text") node.textContent = v;
    else if (k === "dataset") Object.assign(node.dataset, v);
    else if (k in node && typeof v !== "string") node[k] = v;
    else node.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children) if (c !== null && c !== undefined) node.append(c);
  return node;
}

function show(value) {
  if (value === undefined || value === null) return "";
  if (typeof value === "object") return JSON.stringify(value);
  return String(value);
}

function readText(text, numeric) {
  const t = text.trim();
  if (t === "") return undefined;
  if (numeric && NUMBER.test(t)) return Number(t);
  return t;
}

function label(text) {
  const s = text.replace(/_/g, " ");
  return s.charAt(0).toUpperCase() + s.slice(1);
}

export class AxisForm {
  constructor(root, desc, onChange) {
    this.root = root;
    this.desc = desc;
    this.onChange = onChange;
    this.axis = {};
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

  render(axis) {
    this.axis = JSON.parse(JSON.stringify(axis || {}));
    const focused = document.activeElement && this.root.contains(document.activeElement) ? document.activeElement.id : null;
    const open = new Set([...this.root.querySelectorAll("details[open]")].map((d) => d.dataset.key));
    this.root.replaceChildren(this.objectFields(this.desc.axis.fields, this.axis, ""));
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
    const input = event.target;
    if (!input.dataset || input.dataset.path === undefined) return;
    if (input.dataset.role === "toggle" || input.dataset.role === "type" || input.dataset.role === "step-kind") {
      if (event.type !== "change") return;
    }
    const path = input.dataset.path;
    const parts = parsePath(path);
    const role = input.dataset.role;
    if (role === "toggle") {
      setAt(this.axis, parts, input.checked ? {} : undefined);
      this.changed(true);
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
    let value;
    if (input.type === "checkbox") value = input.checked;
    else if (input.tagName === "SELECT") value = input.value === "" ? undefined : input.value;
    else value = readText(input.value, input.dataset.numeric === "1");
    setAt(this.axis, parts, value);
    if (input.dataset.structural === "1" && event.type === "change") this.changed(true);
    else this.onChange(this.value());
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
    const input = el("input", {
      id, type: "text", value: show(value), placeholder, "data-path": path, "data-kind": f.kind,
      "data-numeric": numeric ? "1" : "0", inputmode: f.kind === "integer" ? "numeric" : undefined,
      "aria-required": f.required ? "true" : undefined, spellcheck: "false",
    });
    const unitText = f.kind === "quantity" ? (f.unit ? `[${f.unit}]` : "[-]") : "";
    const unitHint = f.kind === "quantity"
      ? `${f.quantity.replace(/_/g, " ")}: a bare number is in ${f.unit || "SI"}; or type a unit, e.g. 2 ${f.example_unit || f.unit}`
      : f.help || "";
    const wrap = el("div", { class: "field", "data-field": path },
      el("label", { for: id, text: label(f.label) + (f.required ? " *" : "") }),
      input,
      el("span", { class: "unit", text: unitText, title: unitHint }),
    );
    if (unitHint) input.title = unitHint;
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
    if (path === "motor" && value && value.select) {
      // A catalog selection: the given-motor fields do not apply; keep them out of the way.
      const main = f.fields.filter((x) => x.name === "select" || x.name === "margins");
      const given = f.fields.filter((x) => !main.includes(x));
      fs.append(this.objectFields(main, value, path));
      const details = el("details", { class: "more", dataset: { key: "motor:given" } },
        el("summary", { text: "A given motor instead (untick Select to use it)" }));
      details.append(this.objectFields(given, value, path));
      fs.append(details);
      return fs;
    }
    fs.append(this.objectFields(f.fields, value || {}, path));
    return fs;
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

  changeType(parts, type, unionName) {
    const old = getAt(this.axis, parts) || {};
    const spec = this.findUnion(parts, unionName);
    const variant = spec ? spec.variants[type] : null;
    const next = { type };
    if (variant) {
      const names = new Set(variant.fields.map((v) => v.name));
      for (const [k, v] of Object.entries(old)) if (k !== "type" && names.has(k)) next[k] = v;
    }
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

  // ---------------------------------------------------------------- profile table

  profileField(f, value, path) {
    const steps = Array.isArray(value) ? value : [];
    const columns = this.desc.profile.columns;
    const main = columns.filter((c) => ["move", "time", "accel", "decel", "shape"].includes(c.key));
    const extra = columns.filter((c) => !main.includes(c));
    const fs = el("fieldset", { class: "group profile", "data-path": path, "data-field": path });
    fs.append(el("legend", { text: "Profile: moves and dwells (the cycle repeats)" }));
    if (!steps.length) fs.append(el("p", { class: "muted", text: "No steps yet: add a move (distance and time) and a dwell." }));
    const table = el("table", { class: "profile-table", hidden: steps.length === 0 });
    const head = el("tr", {}, el("th", { scope: "col", text: "#" }), el("th", { scope: "col", text: "Step" }));
    for (const c of main) head.append(el("th", { scope: "col", text: c.label, title: c.hint || "" }));
    head.append(el("th", { scope: "col" }, el("span", { class: "sr-only", text: "Actions" })));
    table.append(el("thead", {}, head));
    steps.forEach((step, k) => table.append(this.profileRows(step || {}, k, steps.length, path, main, extra)));
    fs.append(el("div", { class: "table-wrap" }, table));
    fs.append(el("div", { class: "row add" },
      this.button("Add move", "Add a move step", () => this.addItem(path, { move: "", time: "" })),
      this.button("Add dwell", "Add a dwell step", () => this.addItem(path, { dwell: "" }))));
    return fs;
  }

  stepInput(c, step, k, rowPath, isDwell) {
    const key = c.key === "time" && isDwell ? "dwell" : c.key;
    const cellPath = joinPath(rowPath, key);
    let input;
    if (c.options) {
      input = el("select", {
        id: idFor(cellPath), "data-path": cellPath, "aria-label": `Step ${k + 1} ${c.label}`,
        "data-structural": c.key === "shape" ? "1" : undefined,
      });
      for (const o of c.options) input.append(el("option", { value: o, text: o || "—" }));
      input.value = step[key] === undefined ? "" : String(step[key]);
    } else {
      input = el("input", {
        id: idFor(cellPath), type: "text", value: show(step[key]), "data-path": cellPath, "data-numeric": "1",
        "aria-label": `Step ${k + 1} ${c.label}`, placeholder: c.hint.split(" (")[0], spellcheck: "false",
      });
    }
    return input;
  }

  profileRows(step, k, n, path, main, extra) {
    const rowPath = joinPath(path, k);
    const isDwell = step.dwell !== undefined;
    const group = el("tbody", { class: "step", "data-path": rowPath, "data-field": rowPath });
    const tr = el("tr");
    tr.append(el("th", { scope: "row", rowspan: "2", text: String(k + 1) }));
    const kind = el("select", { id: idFor(rowPath) + "-kind", "data-path": rowPath, "data-role": "step-kind", "aria-label": `Step ${k + 1} kind` },
      el("option", { value: "move", text: "move" }), el("option", { value: "dwell", text: "dwell" }));
    kind.value = isDwell ? "dwell" : "move";
    tr.append(el("td", {}, kind));
    for (const c of main) {
      const applies = !isDwell || c.key === "time";
      tr.append(el("td", {}, applies ? this.stepInput(c, step, k, rowPath, isDwell) : ""));
    }
    tr.append(el("td", { class: "row-buttons" },
      this.button("↑", `Move step ${k + 1} up`, () => this.moveItem(path, k, -1), k === 0),
      this.button("↓", `Move step ${k + 1} down`, () => this.moveItem(path, k, 1), k === n - 1),
      this.button("✕", `Remove step ${k + 1}`, () => this.removeItem(path, k))));
    group.append(tr);
    const more = el("div", { class: "step-more" });
    for (const c of extra) {
      const applies = isDwell ? c.key === "holding" : c.key !== "holding";
      if (!applies) continue;
      if (c.key === "jerk_fraction" && step.shape !== "s_curve" && step.jerk_fraction === undefined) continue;
      const input = this.stepInput(c, step, k, rowPath, isDwell);
      more.append(el("label", { for: input.id, text: c.label }), input);
    }
    const known = new Set(PROFILE_FIXED);
    const other = Object.entries(step).filter(([key]) => !known.has(key));
    const otherId = idFor(joinPath(rowPath, "_other"));
    more.append(el("label", { for: otherId, text: "Other keys" }), el("input", {
      id: otherId, type: "text", value: other.map(([a, b]) => `${a}: ${show(b)}`).join("; "),
      "data-path": rowPath, "data-role": "other", placeholder: "e.g. speed: 1 m/s", spellcheck: "false", class: "other",
      title: "any other step keys as key: value; … (speed, max_speed, max_accel, max_jerk, law, jerk)",
    }));
    group.append(el("tr", { class: "step-extra" }, el("td", { colspan: String(main.length + 2) }, more)));
    return group;
  }

  changeStepKind(parts, kind) {
    const step = getAt(this.axis, parts) || {};
    let next;
    if (kind === "dwell") next = { dwell: step.time !== undefined ? step.time : "" };
    else next = { move: "", time: step.dwell !== undefined ? step.dwell : "" };
    setAt(this.axis, parts, next);
    this.changed(true);
  }

  setOtherKeys(parts, text) {
    const step = getAt(this.axis, parts) || {};
    for (const key of Object.keys(step)) if (!PROFILE_FIXED.includes(key)) delete step[key];
    for (const piece of text.split(";")) {
      const m = /^\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(.*?)\s*$/.exec(piece);
      if (m && m[2] !== "") step[m[1]] = readText(m[2], true);
    }
    setAt(this.axis, parts, step);
  }

  // ---------------------------------------------------------------- errors

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
    if (profileKey && !PROFILE_FIXED.includes(profileKey[2])) {
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
    errors.forEach((err, k) => {
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
