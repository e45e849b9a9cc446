// The order sheet of a sizing result (the JSON ``order`` block, drivetrain.sizing.order): one table row per
// part (status, vendor, the order code as written, or the positions still to choose, or "specification"),
// then each part's specification and open points. Text only through textContent (never HTML from data).

import { el } from "./dom.js";
import { fmt, table } from "./results.js";

const UNIT_SUFFIXES = [["_Nm_per_arcmin", "N*m/arcmin"], ["_Nm_per_rad", "N*m/rad"], ["_NmA", "N*m/A"],
  ["_kgm2", "kg*m^2"], ["_Nm", "N*m"], ["_rpm", "rpm"], ["_ohm", "ohm"], ["_arcmin", "arcmin"], ["_mm", "mm"],
  ["_A", "A"], ["_V", "V"], ["_s", "s"], ["_J", "J"], ["_W", "W"], ["_N", "N"], ["_h", "h"]];

// The order code cell, as the CLI and the report print it (drivetrain.report.order.code_cell).
export function codeCell(r) {
  let code = "specification";
  if (r.order_code) code = r.order_code;
  else if (r.catalog_id && r.choose.length) code = `${r.catalog_id} (choose position ${r.choose.map((c) => c.position).join(", ")})`;
  else if (r.catalog_id) code = `${r.catalog_id} (not as written)`;
  return code + (r.unverified ? " †" : "");
}

function value(v) {
  if (typeof v === "boolean") return v ? "yes" : "no";
  if (typeof v === "number") return fmt(v);
  if (Array.isArray(v)) return v.map(value).join(", ");
  return String(v);
}

// A row's specification in one line: name value unit (the unit from the key's suffix).
export function specText(spec) {
  const out = [];
  for (const [key, v] of Object.entries(spec || {})) {
    if (v === null || v === undefined) continue;
    const hit = UNIT_SUFFIXES.find(([s]) => key.endsWith(s));
    const name = (hit ? key.slice(0, -hit[0].length) : key).replace(/_/g, " ");
    out.push(`${name} ${value(v)}${hit ? ` ${hit[1]}` : ""}`);
  }
  return out.join("; ");
}

export function stateText(order) {
  if (order.complete) return "Complete: every part can be ordered as written.";
  return `${order.complete_rows} complete, ${order.incomplete_rows} incomplete, ${order.specification_rows} specification(s): not every part can be ordered as written.`;
}

export function renderOrder(node, result) {
  if (!node) return;
  const order = result && result.order;
  if (!order) {
    node.replaceChildren(el("p", { class: "muted", text: "No order sheet." }));
    return;
  }
  const rows = order.rows.map((r) => ({
    cls: r.status === "complete" ? "" : "unknown",
    cells: [r.part.replace(/_/g, " "), r.status, String(r.quantity), r.vendor || "–", codeCell(r)],
  }));
  const details = el("dl", { class: "detail order-detail" });
  for (const r of order.rows) {
    details.append(el("dt", { text: `${r.part.replace(/_/g, " ")}: ${r.name}` }));
    const spec = specText(r.spec);
    if (spec) details.append(el("dd", { text: spec }));
    for (const p of r.open_points) details.append(el("dd", { class: "muted", text: `open: ${p}` }));
  }
  const parts = [el("p", { class: "muted", text: stateText(order) }),
    table("Order sheet", ["part", "status", "qty", "vendor", "order code"], rows, "data order-table"), details];
  if (order.rows.some((r) => r.unverified)) parts.push(el("p", { class: "muted small", text: "† unverified catalog data (not traced to a vendor document)." }));
  node.replaceChildren(...parts);
}
