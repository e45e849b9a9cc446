// A small YAML writer for the axis: block mappings for sections, one-line flow mappings for
// short mappings of scalars (a profile step, a transmission element, a load), like the shipped
// examples. Strings that YAML would read as something else (numbers, booleans, dates, null) or
// that hold special characters are double-quoted (JSON string syntax is valid YAML).

const RESERVED = /^(true|false|yes|no|on|off|y|n|null|~)$/i;
const NUMBER_LIKE = /^[-+]?(\.[0-9]+|[0-9][0-9_]*(\.[0-9_]*)?)([eE][-+]?[0-9]+)?$|^[-+]?\.(inf|nan)$|^0[xob]/i;
const DATE_LIKE = /^\d{4}-\d\d?-\d\d?/;
const SEXAGESIMAL = /^[-+]?[0-9][0-9_]*(:[0-5]?[0-9])+(\.[0-9_]*)?$/;
const PLAIN = /^[-+]?[A-Za-z0-9_.][A-Za-z0-9_ .*\/^+\-()°µ·²³%]*$/;

function scalar(value) {
  if (value === null || value === undefined) return "null";
  if (typeof value === "boolean") return value ? "true" : "false";
  if (typeof value === "number") return Number.isFinite(value) ? String(value) : JSON.stringify(String(value));
  const text = String(value);
  const plain =
    text.length > 0 &&
    text === text.trim() &&
    PLAIN.test(text) &&
    !RESERVED.test(text) &&
    !NUMBER_LIKE.test(text) &&
    !DATE_LIKE.test(text) &&
    !SEXAGESIMAL.test(text);
  return plain ? text : JSON.stringify(text);
}

function key(name) {
  return /^[A-Za-z_][A-Za-z0-9_]*$/.test(name) && !RESERVED.test(name) ? name : JSON.stringify(name);
}

function isScalar(v) {
  return v === null || ["string", "number", "boolean"].includes(typeof v);
}

function flow(obj) {
  const entries = Object.entries(obj);
  if (entries.length === 0 || entries.length > 8 || !entries.every(([, v]) => isScalar(v))) return null;
  const text = "{" + entries.map(([k, v]) => `${key(k)}: ${scalar(v)}`).join(", ") + "}";
  return text.length <= 100 ? text : null;
}

function lines(value, indent, out) {
  const pad = "  ".repeat(indent);
  if (Array.isArray(value)) {
    for (const item of value) {
      if (isScalar(item)) {
        out.push(`${pad}- ${scalar(item)}`);
      } else if (Array.isArray(item)) {
        out.push(`${pad}-`);
        lines(item, indent + 1, out);
      } else {
        const f = flow(item);
        if (f) {
          out.push(`${pad}- ${f}`);
        } else if (Object.keys(item).length === 0) {
          out.push(`${pad}- {}`);
        } else {
          const sub = [];
          lines(item, indent + 1, sub);
          sub[0] = `${pad}- ${sub[0].trimStart()}`;
          out.push(...sub);
        }
      }
    }
    return out;
  }
  for (const [k, v] of Object.entries(value)) {
    if (isScalar(v)) {
      out.push(`${pad}${key(k)}: ${scalar(v)}`);
    } else if (Array.isArray(v)) {
      if (v.length === 0) {
        out.push(`${pad}${key(k)}: []`);
      } else {
        out.push(`${pad}${key(k)}:`);
        lines(v, indent + 1, out);
      }
    } else {
      const f = indent > 0 || k === "load" || k === "margins" || k === "select" ? flow(v) : null;
      if (f) {
        out.push(`${pad}${key(k)}: ${f}`);
      } else if (Object.keys(v).length === 0) {
        out.push(`${pad}${key(k)}: {}`);
      } else {
        out.push(`${pad}${key(k)}:`);
        lines(v, indent + 1, out);
      }
    }
  }
  return out;
}

export function toYaml(axis) {
  return lines(axis, 0, []).join("\n") + "\n";
}
