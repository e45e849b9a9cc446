// Tables of a sizing result: the verdict, the checks, the duty cycle, ranked candidates and the
// side-by-side comparison. Text only through textContent (never HTML from data).

import { el } from "./dom.js";
import { dynamicsPanel, passedOverForMotion } from "./dynamics.js";

// A number for reading: up to ``sig`` significant digits, plain between 0.001 and 1e6
// (1.27, 0.54, 3000), else in engineering notation, the exponent a multiple of 3 (12.5e-6, 2.4e6).
export function fmt(value, sig = 4) {
  if (value === null || value === undefined || Number.isNaN(value)) return "–";
  if (typeof value !== "number") return String(value);
  if (value === 0) return "0";
  if (!Number.isFinite(value)) return value > 0 ? "∞" : "-∞";
  const a = Math.abs(Number(value.toPrecision(sig)));
  if (a >= 1e6 || a < 1e-3) {
    let exp = Math.floor(Math.log10(a) / 3) * 3;
    let mantissa = Number((value / 10 ** exp).toPrecision(sig));
    if (Math.abs(mantissa) >= 1000) {
      exp += 3;
      mantissa = Number((mantissa / 1000).toPrecision(sig));
    }
    return `${mantissa}e${exp}`;
  }
  return String(Number(value.toPrecision(sig)));
}

export function pct(margin) {
  if (margin === null || margin === undefined) return "–";
  return `${margin >= 0 ? "+" : ""}${(margin * 100).toFixed(1)} %`;
}


export function table(caption, headers, rows, cls = "data") {
  const t = el("table", { class: cls });
  if (caption) t.append(el("caption", { class: "sr-only", text: caption }));
  t.append(el("thead", {}, el("tr", {}, ...headers.map((h) => el("th", { scope: "col", text: h })))));
  const body = el("tbody");
  for (const r of rows) {
    const tr = el("tr", r.cls ? { class: r.cls } : {});
    r.cells.forEach((c, k) => {
      const cell = k === 0 ? el("th", { scope: "row" }) : el("td");
      if (c instanceof Node) cell.append(c);
      else cell.textContent = c;
      tr.append(cell);
    });
    body.append(tr);
  }
  t.append(body);
  return t;
}

const CHECK_NAMES = {
  peak_torque: "peak torque",
  rms_torque: "RMS torque",
  max_speed: "max speed",
  inertia_ratio: "inertia ratio J_L/J_M",
  gearbox_rated_torque: "gearbox rated torque",
  gearbox_peak_torque: "gearbox peak torque",
};

export function checkName(name) {
  return CHECK_NAMES[name] || name.replace(/_/g, " ");
}

// The answer's verdict in three outcomes (result.verdict: status "pass", "pass with unknowns" or "fail", and
// the checks that could not be judged, docs/axis-file.md); a result without the block: pass or fail by ``ok``.
export function outcome(result, ok) {
  const v = result.verdict;
  if (v && v.status) return { status: v.status, unknowns: v.unknowns || [] };
  return { status: ok ? "pass" : "fail", unknowns: [] };
}

// The checks a result is judged by: the given motor's, else the selected candidate's; with the answer's
// verdict (``status``, ``unknowns``: outcome above), which decides ``ok``.
export function verdict(result) {
  if (result.motor) {
    const o = outcome(result, result.motor.ok);
    return { who: result.motor.name, ok: o.status !== "fail", ...o, failed: result.motor.failed, checks: result.motor.checks, kind: "motor" };
  }
  const sel = result.selection;
  if (sel && sel.selected) {
    const c = sel.selected;
    // a selection whose passing motors have no orderable drive fails (drive_select.orderable)
    // the verdict is the advice's first clause; the motor it names and the motors passed over fold away
    const failed = sel.drive_advice ? `not orderable: ${sel.drive_advice.split("; ")[0]}` : "";
    const o = outcome(result, !sel.drive_advice);
    return { who: c.motor + (c.gearbox ? ` + ${c.gearbox}` : ""), ok: o.status !== "fail", ...o, failed, checks: c.checks, kind: "selection", candidate: c };
  }
  if (sel) return { who: null, ok: false, status: "fail", unknowns: outcome(result, false).unknowns, failed: sel.advice || "no candidate passes every check", checks: [], kind: "none-pass" };
  return null;
}

// The verdict's line under the banner: PASS, PASS WITH UNKNOWNS with each check not judged (its part and
// what would decide it), or FAIL.
export function verdictLine(v) {
  const head = { pass: "PASS", "pass with unknowns": "PASS WITH UNKNOWNS", fail: "FAIL" }[v.status] || "FAIL";
  const line = el("div", { class: "verdict-line" }, el("strong", { text: head }));
  if (v.unknowns && v.unknowns.length) {
    line.append(v.status === "fail" ? ": not judged (motor.select.unknown: fail):" : ": not judged:");
    line.append(el("ul", { class: "unknown-list" }, ...v.unknowns.map((u) => el("li", { text: `${u.check} (${u.part}): ${u.decide}` }))));
  }
  return line;
}

export function renderBanner(node, result) {
  const v = verdict(result);
  node.className = "banner";
  if (!v) {
    node.textContent = "Duty cycle only: give a motor, or a catalog selection (motor: select), to check one.";
    return;
  }
  if (v.kind === "none-pass") {
    node.classList.add("bad");
    node.textContent = `No catalog candidate passes. ${v.failed}`;
    return;
  }
  node.classList.add(v.status === "pass with unknowns" ? "warn" : v.ok ? "good" : "bad");
  if (v.kind === "selection") {
    const s = result.selection;
    const c = v.candidate;
    node.replaceChildren(
      el("strong", { text: `Selected motor: ${c.motor}` }),
      ` (${c.vendor})${c.gearbox ? ` with gearbox ${c.gearbox}, ratio ${fmt(c.ratio)}`
        : s.transmission_gearbox ? `, on the axis's ${s.transmission_gearbox}` : ", direct drive"}: ` +
        `${s.passing} of ${s.evaluated} combinations pass.` + (v.failed ? ` ${v.failed[0].toUpperCase()}${v.failed.slice(1)}.` : ""),
    );
    const folded = passedOver(s);
    if (folded) node.append(folded);
    const moved = passedOverForMotion(s);
    if (moved) node.append(moved);
  } else {
    const said = v.status === "pass" ? ": every check passes." : v.status === "pass with unknowns" ? ": no judged check fails." : `: ${v.failed}`;
    node.replaceChildren(el("strong", { text: `Motor ${v.who}: ${v.ok ? "OK" : "FAILS"}` }), said);
  }
  node.append(verdictLine(v));
}

// The motors a selection passed over for their drive, folded: a count in the summary, each motor with
// its reason inside (selection.drive_passed_over lists the first 20 of drive_passed_over_count).
export function passedOver(sel) {
  // the ones passed over for how they move are folded apart (dynamics.js)
  const over = (sel.drive_passed_over || []).filter((p) => p.drive_status !== "dynamics");
  if (!over.length) return null;
  const moved = (sel.drive_passed_over || []).length - over.length;
  const n = Math.max((sel.drive_passed_over_count || 0) - moved, over.length);
  const list = el("ul", { class: "passed-over-list" }, ...over.map((p) => el("li", { text: `${p.motor}: ${p.reason}` })));
  if (n > over.length) list.append(el("li", { class: "muted", text: `… and ${n - over.length} more` }));
  const rest = sel.drive_advice ? sel.drive_advice.split("; ").slice(1).join("; ") : "";
  return el("details", { class: "passed-over" },
    el("summary", { text: `${n} passing motor${n === 1 ? "" : "s"} passed over for ${n === 1 ? "its" : "their"} drive` }),
    ...(rest ? [el("p", { text: rest })] : []), list);
}

// The drive, the motor's electrical figures and the regen block (payload.electrical, web/payload.py).
export function electricalParts(e) {
  if (!e) return [];
  const parts = [];
  const rows = [];
  const d = e.drive;
  if (d) {
    const status = d.status || (d.ok ? "ok" : "fails");
    rows.push({ cls: status === "fails" ? "fail" : "", cells: ["drive", `${d.id || "none"}${d.basis ? ` (${d.basis})` : ""}`, status] });
    if (d.reason) rows.push({ cells: ["", d.reason, ""] });
    for (const c of d.checks || []) rows.push({ cls: c.ok ? "" : "fail", cells: [checkName(c.name), `${fmt(c.required)} / ${fmt(c.available)} ${c.unit}`, pct(c.margin)] });
  }
  const m = e.electrical;
  if (m) {
    if (m.envelope_source) rows.push({ cells: ["envelope source", m.envelope_source, ""] });
    if (m.rms_current_A != null) rows.push({ cells: ["motor current RMS / peak", `${fmt(m.rms_current_A)} / ${fmt(m.peak_current_A)} A`, ""] });
    for (const c of m.checks || []) rows.push({ cls: c.ok ? "" : "fail", cells: [checkName(c.name), `${fmt(c.required)} / ${fmt(c.available)} ${c.unit}`, pct(c.margin)] });
    rows.push({ cells: ["winding temperature rise", m.winding_temperature_rise_K != null ? `${fmt(m.winding_temperature_rise_K)} K` : "not known", ""] });
    if (m.note) rows.push({ cells: ["", m.note, ""] });
  }
  const g = e.regen;
  if (g) {
    rows.push({ cells: ["regen into the DC bus", `${fmt(g.energy_per_cycle_J)} J per cycle (capacitors ${fmt(g.capacitor_absorbed_J)} J)`, ""] });
    rows.push({ cells: ["braking resistor", `${fmt(g.resistor_energy_per_cycle_J)} J per cycle, peak ${fmt(g.resistor_peak_power_W)} W, average ${fmt(g.resistor_average_power_W)} W`, ""] });
    if (g.resistor_min_ohm != null || g.resistor_max_ohm != null) rows.push({ cells: ["resistance window", `${fmt(g.resistor_min_ohm)} to ${fmt(g.resistor_max_ohm)} Ω`, ""] });
    const b = g.builtin_resistor_sufficient;
    rows.push({ cls: b === false ? "fail" : "", cells: ["built-in resistor sufficient", b == null ? "not known" : b ? "yes" : "no", ""] });
  }
  if (rows.length) parts.push(table("Drive, electrical and regeneration", ["item", "value (required / available)", "margin"], rows, "data electrical-table"));
  return parts;
}

export function renderChecks(node, result, electrical = null) {
  const v = verdict(result);
  if (!v || !v.checks.length) {
    node.replaceChildren(el("p", { class: "muted", text: "No motor to check." }), ...electricalParts(electrical));
    return;
  }
  const rows = v.checks.map((c) => ({
    cls: c.ok ? "" : "fail",
    cells: [
      checkName(c.name) + (c.approximate ? " *" : ""),
      `${fmt(c.required)} ${c.unit === "-" ? "" : c.unit}`.trim(),
      `${fmt(c.available)} ${c.unit === "-" ? "" : c.unit}`.trim(),
      pct(c.margin),
      c.ok ? "ok" : "FAILS",
    ],
  }));
  const parts = [el("p", { class: "muted", text: `${v.who}` }), table(`Checks of ${v.who}`, ["check", "required", "available", "margin", "result"], rows, "data checks-table")];
  if (v.checks.some((c) => c.approximate)) parts.push(el("p", { class: "muted small", text: "* against an envelope derived from the ratings (no vendor curve)." }));
  parts.push(...electricalParts(electrical));
  node.replaceChildren(...parts);
}

// A demand figure within ZERO_TOLERANCE of its scale is the round-off of a sum that is zero: it shows as 0
// (drivetrain.report.display.snap_zero and METRIC_SCALES, docs/architecture.md "Terminal output").
export const ZERO_TOLERANCE = 1e-9;
const METRIC_SCALES = {
  average_power_W: "peak_power_W", rms_torque_Nm: "peak_torque_Nm", accel_torque_Nm: "peak_torque_Nm",
  run_torque_Nm: "peak_torque_Nm", decel_torque_Nm: "peak_torque_Nm", holding_torque_Nm: "peak_torque_Nm",
  mean_speed_rpm: "max_speed_rpm", peak_torque_speed_rpm: "max_speed_rpm",
};

export function snappedMetrics(result) {
  const out = { ...result };
  for (const [key, scale] of Object.entries(METRIC_SCALES)) {
    const v = result[key];
    const s = result[scale];
    if (typeof v === "number" && typeof s === "number" && Number.isFinite(v) && Number.isFinite(s) && s !== 0
        && Math.abs(v) <= ZERO_TOLERANCE * Math.abs(s)) out[key] = 0;
  }
  return out;
}

export function renderMetrics(node, result, motion) {
  const m = snappedMetrics(result);
  const speedUnit = "rpm";
  const rows = [
    ["cycle time", `${fmt(m.cycle_time_s)} s`],
    ["load inertia at the motor shaft", `${fmt(m.load_inertia_kgm2 * 1e4)} kg·cm²`],
    ["peak torque", `${fmt(m.peak_torque_Nm)} N·m at ${fmt(m.peak_torque_speed_rpm, 4)} ${speedUnit}`],
    ["RMS torque", `${fmt(m.rms_torque_Nm)} N·m`],
    ["accel / run / decel torque (move 1)", `${fmt(m.accel_torque_Nm)} / ${fmt(m.run_torque_Nm)} / ${fmt(m.decel_torque_Nm)} N·m`],
    ["holding torque", `${fmt(m.holding_torque_Nm)} N·m`],
    ["max / mean speed", `${fmt(m.max_speed_rpm)} / ${fmt(m.mean_speed_rpm)} ${speedUnit}`],
    ["peak / average power", `${fmt(m.peak_power_W)} / ${fmt(m.average_power_W)} W`],
    ["regenerated energy per cycle", `${fmt(m.regen_energy_J)} J`],
  ].map((r) => ({ cells: r }));
  const caption = `Demand at the motor shaft, rotor excluded (${motion} axis)`;
  node.replaceChildren(table(caption, ["quantity", "value"], rows, "data metrics-table"));
}

export function candidateKey(c) {
  return `${c.motor}|${c.gearbox || ""}`;
}

export function renderCandidates(node, result, picked, onToggle) {
  const list = result.candidates || [];
  if (!list.length) {
    node.replaceChildren(el("p", { class: "muted", text: "No catalog selection: set motor → select to rank catalog motors and gearboxes." }));
    return;
  }
  const full = picked.size >= 3;
  const rows = list.map((c) => {
    const checks = Object.fromEntries(c.checks.map((x) => [x.name, x]));
    const key = candidateKey(c);
    const id = `cmp-${key.replace(/[^A-Za-z0-9]+/g, "-")}`;
    const box = el("input", { type: "checkbox", id, "aria-label": `Compare ${c.motor}${c.gearbox ? " with " + c.gearbox : ""}` });
    box.checked = picked.has(key);
    box.disabled = full && !box.checked;
    box.addEventListener("change", () => onToggle(c, box.checked));
    return {
      cls: c.ok ? "" : "fail",
      cells: [
        c.motor,
        c.rank ? String(c.rank) : "–",
        box,
        c.gearbox ? `${c.gearbox} (i = ${fmt(c.ratio)})` : "direct",
        fmt(c.inertia_ratio, 3),
        pct(checks.peak_torque ? checks.peak_torque.margin : null),
        pct(checks.rms_torque ? checks.rms_torque.margin : null),
        c.ok ? "ok" : c.failed,
        c.drive ? `${c.drive.id || "–"}${c.drive.status && c.drive.status !== "ok" ? ` (${c.drive.status})` : ""}` : "–",
      ],
    };
  });
  const s = result.selection || {};
  const intro = el("p", { class: "muted", text: `Best first by "${s.objective || "smallest"}"; rejected ones last, each with the check it fails. Tick 2–3 to compare.` });
  // The motor stays in view (a sticky first column) while the table scrolls sideways.
  node.replaceChildren(intro, el("div", { class: "table-wrap candidates-wrap" },
    table("Ranked candidates", ["motor", "rank", "compare", "gearbox", "J_L/J_M", "peak margin", "RMS margin", "result", "drive"], rows, "data candidates-table")));
}

export function renderCompare(node, picks, onClear) {
  if (picks.length < 2) {
    node.hidden = picks.length === 0;
    node.replaceChildren(picks.length ? el("p", { class: "muted", text: "Tick one or two more candidates to compare." }) : "");
    return;
  }
  node.hidden = false;
  const names = new Set();
  for (const c of picks) for (const x of c.checks) names.add(x.name);
  const head = ["", ...picks.map((c) => c.motor + (c.gearbox ? ` + ${c.gearbox}` : ""))];
  const rows = [
    ["vendor", ...picks.map((c) => c.vendor || "–")],
    ["rank", ...picks.map((c) => (c.rank ? String(c.rank) : "rejected"))],
    ["gear ratio", ...picks.map((c) => fmt(c.ratio))],
    ["inertia ratio J_L/J_M", ...picks.map((c) => fmt(c.inertia_ratio, 3))],
    ["rated power", ...picks.map((c) => (c.rated_power_W ? `${fmt(c.rated_power_W)} W` : "–"))],
    ["RMS / peak torque", ...picks.map((c) => `${fmt(c.rms_torque_Nm)} / ${fmt(c.peak_torque_Nm)} N·m`)],
  ];
  for (const n of names) {
    rows.push([`${checkName(n)} margin`, ...picks.map((c) => {
      const x = c.checks.find((y) => y.name === n);
      return x ? `${pct(x.margin)} (${fmt(x.required)} / ${fmt(x.available)} ${x.unit === "-" ? "" : x.unit})`.trim() : "–";
    })]);
  }
  rows.push(["result", ...picks.map((c) => (c.ok ? "ok" : c.failed))]);
  const clear = el("button", { type: "button", class: "small", text: "Clear comparison" });
  clear.addEventListener("click", onClear);
  node.replaceChildren(el("h3", { text: "Side by side" }), el("div", { class: "table-wrap" },
    table("Compared candidates", head, rows.map((r) => ({ cells: r })), "data compare-table")), clear);
}

const MECHANISM_NAMES = {
  screw_buckling: "screw buckling",
  screw_tensile_compressive: "screw tensile/compressive",
  screw_critical_speed: "screw critical speed",
  screw_dn_speed: "screw DN value",
  nut_life: "nut life L10",
  nut_static_safety: "nut static safety",
  guide_life: "guide life L10",
  guide_static_safety: "guide static safety",
  belt_slack_side: "belt pretension",
  belt_tension: "belt tension",
  rack_feed_force: "rack feed force",
  servo_bandwidth: "servo bandwidth (f1 ≥ 2 × f_v)",
};

// The mechanism's own checks (screw, nut, guide, belt, rack) and the first mode across the stroke
// with the servo-bandwidth check. Returns false when there is nothing to show.
export function renderMechanism(node, result, modes) {
  const checks = [...(result.mechanism_checks || []), ...((modes && modes.checks) || [])];
  const dynamics = dynamicsPanel(result);
  if (!checks.length) {
    if (dynamics) node.replaceChildren(dynamics);
    else node.replaceChildren();
    return Boolean(dynamics);
  }
  const unit = (u) => (u === "-" ? "" : u);
  const rows = checks.map((c) => {
    const unknown = c.status === "unknown";
    return {
      cls: unknown ? "unknown" : c.ok ? "" : "fail",
      cells: [
        MECHANISM_NAMES[c.name] || c.name.replace(/_/g, " "),
        c.required === null ? "not stated" : `${fmt(c.required)} ${unit(c.unit)}`.trim(),
        c.available === null ? "no limit" : `${fmt(c.available)} ${unit(c.unit)}`.trim(),
        pct(c.margin),
        unknown ? "unknown" : c.ok ? "ok" : "FAILS",
        c.source + (c.note ? ` (${c.note})` : ""),
      ],
    };
  });
  const parts = [el("div", { class: "table-wrap" }, table("Checks of the mechanism", ["check", "required", "available", "margin", "result", "source"], rows, "data mechanism-table"))];
  if (modes) {
    parts.push(el("p", {
      class: "muted modes-summary",
      text: `Lowest first mode ${fmt(modes.f1_min_Hz)} Hz at load position ${fmt(modes.worst_position_m * 1000)} mm ` +
        `(motor ${modes.motor}); weakest link: ${modes.weakest_link}. ` +
        (modes.velocity_bandwidth_Hz === null
          ? "Velocity bandwidth not stated (dynamics.loop.velocity_bandwidth); "
          : `Velocity bandwidth ${fmt(modes.velocity_bandwidth_Hz)} Hz from ${modes.bandwidth_source}; `) +
        `f1 allows up to ${fmt(modes.max_velocity_bandwidth_Hz)} Hz.`,
    }));
  }
  if (dynamics) parts.push(dynamics);
  node.replaceChildren(...parts);
  return true;
}

// The result's warnings (an answer out of all scale with the load, e.g. a unit slip): one line each,
// above the checks; hidden when there are none.
export function renderWarnings(node, result) {
  const list = Array.isArray(result.warnings) ? result.warnings : [];
  node.hidden = !list.length;
  if (!list.length) {
    node.replaceChildren();
    return;
  }
  const title = list.length === 1 ? "Warning: " : `${list.length} warnings: `;
  node.replaceChildren(
    el("strong", { text: title }),
    el("ul", { class: "warning-list" }, ...list.map((w) => el("li", { text: String(w) }))),
  );
}
