// How the axis will move (selection.dynamics, docs/checks.md "Dynamic selection"): every candidate the
// selection judged on its own tuned loop and simulation, and the static picks passed over for how they
// move, each with why. Text only through textContent (never HTML from data).

import { el } from "./dom.js";
import { fmt, table } from "./results.js";

export const PASSED_OVER = "passed over for how it moves";

const ms = (s) => (s === null || s === undefined ? "never settles" : `${fmt(s * 1000, 3)} ms`);
const hz = (f) => (f === null || f === undefined || !Number.isFinite(f) ? "–" : `${fmt(f, 4)} Hz`);

// A load position tolerance or error: um / mm for a linear load, arcmin for a rotary one.
export function position(x, motion) {
  if (x === null || x === undefined) return "–";
  if (!Number.isFinite(x)) return "unbounded";
  if (motion === "linear") return x < 1e-3 ? `${fmt(x * 1e6, 3)} µm` : `${fmt(x * 1e3, 4)} mm`;
  return `${fmt((x * 180 / Math.PI) * 60, 3)} arcmin`;
}

function settling(c) {
  if (c.simulated === false) return "not simulated";
  const stops = c.settling_time_per_stop_s || [];
  if (stops.some((v) => v === null)) return "never settles";
  return stops.length ? ms(Math.max(...stops)) : "–";
}

function following(c, motion) {
  if (c.simulated === false) return "not simulated";
  const errs = c.following_error_per_move || [];
  return errs.length ? position(Math.max(...errs), motion) : "–";
}

const key = (c) => `${c.motor}|${c.gearbox || ""}`;

// The static picks passed over for how they move (selection.dynamics.passed_over), folded like the
// motors passed over for their drive: a count in the summary, each with its reason. null when none.
export function passedOverForMotion(sel) {
  const over = (sel && sel.dynamics && sel.dynamics.passed_over) || [];
  if (!over.length) return null;
  const n = over.length;
  return el("details", { class: "passed-over passed-over-motion" },
    el("summary", { text: `${n} static pick${n === 1 ? "" : "s"} ${PASSED_OVER}` }),
    el("ul", { class: "passed-over-list" },
      ...over.map((p) => el("li", { text: `${p.motor}${p.gearbox ? ` + ${p.gearbox}` : ""}: ${p.reason}` }))));
}

// The dynamics panel: the candidates judged with their settling, following error, bandwidth, margins,
// first resonance and anti-resonance and result; the answer's inertia ratio. null without requirements.
export function dynamicsPanel(result) {
  const sel = result.selection;
  const dyn = sel && sel.dynamics;
  if (!dyn) return null;
  const motion = dyn.requirements.motion;
  const chosen = dyn.chosen ? key(dyn.chosen) : null;
  const over = new Set((dyn.passed_over || []).map(key));
  const rows = dyn.candidates.map((c) => {
    const k = key(c);
    const res = k === chosen ? "answer" : over.has(k) ? PASSED_OVER : c.status;
    return {
      cls: k === chosen ? "" : c.status === "fail" ? "fail" : over.has(k) ? "unknown" : "",
      cells: [c.motor, c.gearbox || "–", settling(c), following(c, motion), hz(c.velocity_bandwidth_Hz),
        `${fmt(c.phase_margin_deg, 3)}°`, c.gain_margin_dB === null ? "∞" : `${fmt(c.gain_margin_dB, 3)} dB`,
        hz(c.resonance_Hz), hz(c.anti_resonance_Hz), c.notch ? "yes" : "no", res],
    };
  });
  const req = dyn.requirements;
  const asked = [`settling into ${position(req.settling_window, motion)}` +
    (req.settling_time === null ? "" : ` within ${ms(req.settling_time)}`)];
  if (req.following_error !== null) asked.push(`following error ≤ ${position(req.following_error, motion)}`);
  if (req.velocity_bandwidth !== null) asked.push(`velocity bandwidth ≥ ${fmt(req.velocity_bandwidth)} Hz`);
  asked.push(`phase margin ≥ ${fmt(req.phase_margin_deg)}°, gain margin ≥ ${fmt(req.gain_margin_db)} dB`);
  const parts = [
    el("h4", { text: "How it moves: the dynamic checks" }),
    el("p", { class: "muted dynamics-summary", text: `Asked: ${asked.join("; ")}. ${dyn.judged} candidate(s) judged, ` +
      `best-ranked first; the answer is ${dyn.objective === "fastest_settling" ? "the one that settles fastest" : "the first that passes"}.` }),
    el("div", { class: "table-wrap" }, table("Candidates judged on how they move",
      ["motor", "gearbox", "settling", "following error", "bandwidth", "phase margin", "gain margin", "resonance",
        "anti-res.", "notch", "result"], rows, "data dynamics-table")),
  ];
  const pick = sel.selected;
  if (dyn.chosen && pick && pick.motor === dyn.chosen.motor && pick.inertia_ratio !== undefined) {
    parts.push(el("p", { class: "muted dynamics-inertia", text: `${pick.motor} ends up with an inertia ratio ` +
      `J_L/J_M of ${fmt(pick.inertia_ratio)}: the dynamic checks decided the pick, not the ratio.` }));
  }
  const opt = dyn.settling_optimal_ratio;
  if (opt) {
    parts.push(el("p", { class: "muted dynamics-ratio", text: opt.ratio === null
      ? `Settling-optimal ratio for ${opt.motor}: ${opt.reason}`
      : `Settling-optimal ${opt.stage} for ${opt.motor}: ${opt.label} (settles in ${ms(opt.settling_time_s)}; ` +
        `at its own ratio, ${ms(opt.current_settling_time_s)}).` }));
  }
  const folded = passedOverForMotion(sel);
  if (folded) parts.push(folded);
  return el("div", { class: "dynamics" }, ...parts);
}
