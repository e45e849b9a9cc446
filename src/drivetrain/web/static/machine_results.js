// The machine view's result: the machine table, the DC bus over the cycle, the bus, resistor and
// supply figures with the phasing of free axes, the bill of materials and each axis's checks; and
// the API's errors shown at the field they name. Text only through textContent (never HTML from data).

import { el } from "./dom.js";
import { checkName, fmt, pct, renderChecks, table, verdictLine } from "./results.js";

const $ = (id) => document.getElementById(id);
const copy = (x) => JSON.parse(JSON.stringify(x));
const COLORS = ["#1f5fae", "#c2410c", "#15803d", "#7c3aed", "#b91c1c", "#0e7490", "#a16207", "#be185d"];
const BUS_ROWS = [
  ["bus_peak_power_W", "bus peak power", "W"], ["bus_peak_regen_power_W", "bus peak regenerative power", "W"],
  ["bus_rms_power_W", "bus RMS power", "W"], ["regen_into_bus_J", "braking energy of the axes", "J"],
  ["regen_shared_J", "shared with motoring axes", "J"], ["capacitor_energy_per_event_J", "capacitors per event", "J"],
  ["capacitor_absorbed_J", "capacitors absorb per cycle", "J"], ["resistor_energy_per_cycle_J", "braking resistor energy per cycle", "J"],
  ["resistor_peak_power_W", "braking resistor peak power", "W"], ["resistor_average_power_W", "braking resistor average power", "W"],
  ["resistor_min_ohm", "resistance at least", "Ω"], ["resistor_max_ohm", "resistance at most", "Ω"],
  ["supply_peak_power_W", "supply peak power", "W"], ["supply_continuous_power_W", "supply continuous power", "W"],
  ["supply_peak_current_A", "supply peak line current", "A"], ["supply_rms_current_A", "supply RMS line current", "A"],
];

export function renderTable(view, p) {
  const rows = p.table.map((r) => {
    const go = el("button", { type: "button", class: "link id", text: r.motors > 1 ? `${r.axis} (motor ${r.motor_index})` : r.axis, "aria-label": `result of axis ${r.axis}${r.motors > 1 ? ` motor ${r.motor_index}` : ""}` });
    go.addEventListener("click", () => {
      const d = $(`m-axis-${r.axis}-${r.motor_index}`.replace(/[^A-Za-z0-9_-]/g, "_"));
      if (d) {
        d.open = true;
        d.scrollIntoView({ block: "start" });
      }
    });
    const cell = el("span", {}, go);
    const link = p.links[r.axis];
    if (link && r.motor_index === 1) {
      const open = el("button", { type: "button", class: "small", text: "open project", "aria-label": `open axis project ${link.name}` });
      open.addEventListener("click", () => view.openAxisProject(link.project));
      cell.append(" ", open);
    }
    return {
      cls: r.ok ? "" : "fail",
      cells: [cell, r.motors > 1 ? `${Math.round(r.share * 100)} %` : "1", r.motor || "–", r.drive || "–", r.gearbox || "–",
        r.min_margin === null ? "–" : `${pct(r.min_margin)} (${checkName(r.limit)})`, r.ok ? (r.status || "pass") : `FAIL${r.failed ? ": " + r.failed : ""}`],
    };
  });
  $("m-table").replaceChildren(table("Axes of the machine: motor, drive, gearbox, margins", ["axis", "load", "motor", "drive", "gearbox", "smallest margin", "result"], rows, "data machine-table"));
}

export function drawBus(view, p) {
  const node = $("plot-bus");
  if (typeof window.Plotly === "undefined" || !p) return;
  const s = p.series;
  const traces = [];
  let k = 0;
  for (const [name, values] of Object.entries(s)) {
    if (name === "t_s") continue;
    const bus = name.endsWith(":bus");
    traces.push({ x: s.t_s, y: values, name: bus ? `bus ${name.slice(0, -4)}` : name, yaxis: bus ? "y2" : "y", line: { color: COLORS[k++ % COLORS.length], width: bus ? 2.4 : 1.3 } });
  }
  window.Plotly.react(node, traces, {
    title: { text: "DC-bus power over the machine cycle (+ drawn, − fed back)", font: { size: 13 }, x: 0.01, xanchor: "left" },
    height: 360, margin: { l: 56, r: 20, t: 30, b: 36 }, font: { size: 11, family: "system-ui, sans-serif" },
    legend: { orientation: "h", y: -0.18 }, paper_bgcolor: "rgba(0,0,0,0)", plot_bgcolor: "#fff",
    grid: { rows: 2, columns: 1, subplots: [["xy"], ["xy2"]], roworder: "top to bottom" },
    xaxis: { title: { text: "time [s]" } }, yaxis: { title: { text: "axes [W]" } }, yaxis2: { title: { text: "bus [W]" } },
  }, { displaylogo: false, responsive: true });
}

export function renderBuses(view, p) {
  const rows = BUS_ROWS.map(([key, label, unit]) => ({
    cells: [label, ...p.buses.map((b) => (b[key] === null || b[key] === undefined ? "–" : `${fmt(b[key])} ${unit}`))],
  }));
  rows.push({ cells: ["braking resistor needed", ...p.buses.map((b) => (b.resistor_needed ? "yes" : "no"))] });
  if (p.buses.some((b) => b.resistors)) {
    rows.push({ cells: ["braking resistors", ...p.buses.map((b) => (b.resistors ? b.resistors.map((r) => `${r.id}: ${fmt(r.average_power_W)} W avg, ${fmt(r.peak_power_W)} W peak ${r.ok ? "ok" : "FAILS"}`).join("; ") : "none named"))] });
  }
  if (p.buses.some((b) => b.supply_module)) {
    rows.push({ cells: ["supply module", ...p.buses.map((b) => (b.supply_module ? `${b.supply_module.id}: ${b.supply_module.ok ? "ok" : "FAILS"}` : "none named"))] });
  }
  $("m-buses").replaceChildren(table("DC buses", ["quantity", ...p.buses.map((b) => b.name)], rows, "data bus-table"));
  const ph = p.phasing;
  if (!ph) {
    $("m-phasing").replaceChildren();
    return;
  }
  const keys = [["bus_peak_power_W", "bus peak power", "W"], ["resistor_peak_power_W", "resistor peak power", "W"], ["resistor_energy_per_cycle_J", "resistor energy per cycle", "J"], ["supply_peak_power_W", "supply peak power", "W"]];
  $("m-phasing").replaceChildren(el("h4", { text: `Phasing of the free axes (${ph.free_axes.join(", ")})` }),
    table("Phasing", ["quantity", "all in phase", "random p50", "random p95", "random max"],
      keys.map(([k, label, u]) => ({ cells: [label, `${fmt(ph.in_phase[k])} ${u}`, `${fmt(ph.random[k].p50)} ${u}`, `${fmt(ph.random[k].p95)} ${u}`, `${fmt(ph.random[k].p100)} ${u}`] })), "data phasing-table"),
    el("p", { class: "muted small", text: `${ph.samples} random phasings, seed ${ph.seed}.` }));
}

export function renderBom(view, p) {
  const rows = p.bill_of_materials.map((r) => ({
    cells: [r.kind.replace(/_/g, " "), r.order_code || r.note || "–", r.vendor || "–", String(r.quantity), r.used_by.join(", ")],
  }));
  $("m-bom").replaceChildren(table("Bill of materials", ["item", "order code", "vendor", "qty", "used by"], rows, "data bom-table"));
}

// An axis's outcome in the machine's list: pass, pass with unknowns or FAIL (its result's verdict block).
export function axisOutcome(r, row) {
  const status = r && r.verdict ? r.verdict.status : row && row.ok ? "pass" : "fail";
  return status === "fail" ? "FAIL" : status;
}

// The machine's verdict (machine.verdict: the worst of its axes'): the banner's class and its last line,
// PASS, PASS WITH UNKNOWNS with every check not judged (axis, part, what would decide it), or FAIL.
export function machineVerdict(p) {
  const v = p.verdict || { status: p.machine.ok ? "pass" : "fail", unknowns: [] };
  const cls = v.status === "pass with unknowns" ? "warn" : v.status === "pass" ? "good" : "bad";
  const unknowns = (v.unknowns || []).map((u) => ({ ...u, check: `${u.axis}: ${u.check}` }));
  return { cls, line: verdictLine({ status: v.status, unknowns }) };
}

export function renderAxisResults(view, p) {
  const out = [];
  for (const a of p.axes) {
    const results = a.results || [a.result];
    results.forEach((r, k) => {
      const row = p.table.find((t) => t.axis === a.name && t.motor_index === k + 1);
      const id = `m-axis-${a.name}-${k + 1}`.replace(/[^A-Za-z0-9_-]/g, "_");
      const d = el("details", { id, class: "axis-result" }, el("summary", {
        text: `${a.name}${results.length > 1 ? `, motor ${k + 1} (${Math.round(a.load_shares[k] * 100)} % of the load)` : ""}: ${axisOutcome(r, row)}`,
      }));
      const checks = el("div");
      renderChecks(checks, r, row ? row.electrical : null);
      d.append(el("p", { class: "muted small", text: `start ${fmt(a.offset_s)} s (${a.phasing}), peak power ${fmt(a.peak_power_W)} W, regen ${fmt(a.regen_energy_J)} J, power basis: ${a.power_basis}` }), checks);
      const entry = (view.machine.axes || []).find((e, j) => view.axisLabel(e, j) === a.name);
      if (entry && entry.axis && k === 0) {
        const b = el("button", { type: "button", class: "small", text: "Open in the axis editor" });
        b.addEventListener("click", () => view.openAxis(copy(entry.axis)));
        d.append(b);
      }
      out.push(d);
    });
  }
  $("m-axis-results").replaceChildren(...out);
}

// "axes[2].offset" -> the keys a field error may belong to, most specific first.
function owners(field) {
  const out = [];
  let f = field || "";
  while (f) {
    out.push(f);
    const cut = Math.max(f.lastIndexOf("."), f.lastIndexOf("["));
    f = cut > 0 ? f.slice(0, cut) : "";
  }
  return out;
}

export function clearFieldErrors() {
  for (const n of document.querySelectorAll("#view-machine [aria-invalid=true]")) if (n.id !== "m-yaml") n.setAttribute("aria-invalid", "false");
  for (const n of document.querySelectorAll("#view-machine .inline-error")) n.remove();
  for (const n of document.querySelectorAll("#m-axes .row-error")) n.hidden = true;
  $("m-other-errors").hidden = true;
}

export function showFieldErrors(errors) {
  clearFieldErrors();
  const other = [];
  let first = null;
  for (const e of errors) {
    const keys = owners(e.field);
    const control = keys.map((k) => document.querySelector(`#view-machine [data-field="${CSS.escape(k)}"]`)).find(Boolean);
    if (control) {
      control.setAttribute("aria-invalid", "true");
      const msg = el("p", { class: "field-error inline-error", role: "alert", text: e.message });
      const id = `m-err-${Math.random().toString(36).slice(2)}`;
      msg.id = id;
      control.setAttribute("aria-describedby", id);
      control.insertAdjacentElement("afterend", msg);
      first = first || control;
      continue;
    }
    const row = keys.map((k) => document.querySelector(`#m-axes [data-error-for="${CSS.escape(k)}"]`)).find(Boolean);
    if (row) {
      row.textContent = row.textContent ? `${row.textContent}\n${e.message}` : e.message;
      row.closest("tr").hidden = false;
      continue;
    }
    other.push(e.message);
  }
  const box = $("m-other-errors");
  box.textContent = other.join("\n");
  box.hidden = !other.length;
  if (first) first.focus();
}
