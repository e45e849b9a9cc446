// Helpers of the axis editor's modules (form.js, profile.js): field paths, reading and showing
// values, units as the user writes them, and building elements.

export const NUMBER = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;
const WITH_UNIT = /^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*([^\s\d.+-].*?)\s*$/;

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

export function getAt(obj, parts) {
  let node = obj;
  for (const p of parts) {
    if (node === null || typeof node !== "object") return undefined;
    node = node[p];
  }
  return node;
}

export function setAt(obj, parts, value) {
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

export function idFor(path) {
  return "f-" + path.replace(/[^A-Za-z0-9]+/g, "-");
}

export function el(tag, attrs = {}, ...children) {
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

export function show(value) {
  if (value === undefined || value === null) return "";
  if (typeof value === "object") return JSON.stringify(value);
  return String(value);
}

export function readText(text, numeric) {
  const t = text.trim();
  if (t === "") return undefined;
  if (numeric && NUMBER.test(t)) return Number(t);
  return t;
}

export function label(text) {
  const s = text.replace(/_/g, " ");
  return s.charAt(0).toUpperCase() + s.slice(1);
}

// The unit a quantity input is read in: the unit the user typed ("90 deg" -> deg), the SI unit
// for a bare number (read as SI) or a nonzero default, else the unit the user is likely to type.
export function unitOf(f, value) {
  const text = value === undefined || value === null ? "" : String(value).trim();
  if (text !== "" && NUMBER.test(text)) return f.quantity === "dimensionless" ? "-" : f.unit || "-";
  const m = WITH_UNIT.exec(text);
  if (m) return m[3];
  if (f.quantity === "dimensionless") return "-";
  // Empty: a nonzero default is shown (placeholder) in SI; else the unit the user is likely to type.
  if (typeof f.default === "number" && f.default !== 0) return f.unit || "-";
  return f.example_unit || f.unit || "-";
}

export function unitHint(f) {
  if (f.quantity === "dimensionless") return "a number";
  return `${f.quantity.replace(/_/g, " ")}: any unit of it, e.g. 2 ${f.example_unit || f.unit}; a bare number is in ${f.unit || "SI"}`;
}
