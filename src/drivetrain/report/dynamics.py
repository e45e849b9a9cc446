"""The report's section on how the axis will move (``selection.dynamics``, docs/checks.md "Dynamic
selection"): every candidate the selection judged dynamically with its settling time, following error,
velocity bandwidth, margins, first resonance and anti-resonance; the static picks passed over for how
they move and why; the inertia ratio the answer ends up with; the settling-optimal ratio where computed.

Plain strings (``blocks.Table``); each renderer escapes them for its medium.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from drivetrain.report.blocks import Cell, Table
from drivetrain.report.display import fmt_number

if TYPE_CHECKING:
    from drivetrain.report.display import DisplayUnits
    from drivetrain.sizing.result import SizingResult

PASSED_OVER = "passed over for how it moves"
"""The label of a static pick the dynamic checks passed over (report, CLI and web app alike)."""


def _ms(x: float | None) -> str:
    if x is None:
        return "never settles"
    return f"{x * 1e3:.1f} ms"


def position(x: float | None, motion: str, du: DisplayUnits) -> str:
    """A load position tolerance or error [m or rad] in the report's units ("-" when absent)."""
    if x is None or not math.isfinite(x):
        return "-" if x is None else "unbounded"
    if motion == "linear":
        return du.fmt(x, "length") if du.system != "si" else (f"{x * 1e6:.3g} um" if x < 1e-3 else
                                                               f"{x * 1e3:.4g} mm")
    return f"{math.degrees(x) * 60.0:.3g} arcmin"


def _settling(c: dict[str, Any]) -> str:
    if not c.get("simulated", True):
        return "not simulated"
    stops = c.get("settling_time_per_stop_s") or []
    if any(v is None for v in stops):
        return "never settles"
    return _ms(max(stops)) if stops else "-"


def _follow(c: dict[str, Any], motion: str, du: DisplayUnits) -> str:
    if not c.get("simulated", True):
        return "not simulated"
    errs = c.get("following_error_per_move") or []
    return position(max(errs), motion, du) if errs else "-"


def _hz(x: float | None) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:.1f} Hz"


def candidates_table(dyn: dict[str, Any], du: DisplayUnits) -> Table:
    """Every candidate judged, in the order judged: its dynamic figures and result."""
    motion = dyn["requirements"]["motion"]
    chosen = (dyn.get("chosen") or {}).get("motor"), (dyn.get("chosen") or {}).get("gearbox")
    over = {(p["motor"], p.get("gearbox")) for p in dyn.get("passed_over", [])}
    rows = []
    for c in dyn["candidates"]:
        key = (c["motor"], c.get("gearbox"))
        result = ("answer" if key == chosen else PASSED_OVER if key in over else c["status"])
        cls = "pass" if key == chosen else "fail" if c["status"] == "fail" else "warn" if key in over else ""
        gm = f"{c['gain_margin_dB']:.1f} dB" if math.isfinite(c["gain_margin_dB"]) else "inf"
        modes = f"{_hz(c.get('resonance_Hz'))} / {_hz(c.get('anti_resonance_Hz'))}"
        rows.append([Cell(c["motor"]), Cell(c.get("gearbox") or "-"), Cell(_settling(c)), Cell(_follow(c, motion, du)),
                     Cell(_hz(c["velocity_bandwidth_Hz"])), Cell(f"{c['phase_margin_deg']:.1f} deg / {gm}"),
                     Cell(modes), Cell("yes" if c.get("notch") else "no"), Cell(result, cls)])
    req = dyn["requirements"]
    asked = [f"settling into {position(req['settling_window'], motion, du)}"
             + (f" within {_ms(req['settling_time'])}" if req.get("settling_time") is not None else "")]
    if req.get("following_error") is not None:
        asked.append(f"following error <= {position(req['following_error'], motion, du)}")
    if req.get("velocity_bandwidth") is not None:
        asked.append(f"velocity bandwidth >= {fmt_number(req['velocity_bandwidth'])} Hz")
    asked.append(f"phase margin >= {fmt_number(req['phase_margin_deg'])} deg, gain margin >= "
                 f"{fmt_number(req['gain_margin_db'])} dB")
    notch = "allowed" if req["notch"] else "not allowed"
    loop = (f"loop: current {fmt_number(req['current_bandwidth'])} Hz, delay {req['loop_delay'] * 1e6:.4g} us, "
            f"{'with' if req['feedforward'] else 'no'} feed-forward, notch {notch}")
    objective = ("the one that settles fastest among them" if dyn.get("objective") == "fastest_settling"
                 else "the first that passes")
    note = ("Settling: the worst stop; following error: the worst move (at the load); bandwidth: the tuned velocity "
            "loop's -3 dB bandwidth; resonance and anti-resonance: the chain's first, at the mechanism's weakest "
            f"position. Asked: {'; '.join(asked)} ({loop}). {dyn['judged']} candidate(s) judged, best-ranked "
            f"first, up to {req['candidates']}; the answer is {objective}. A candidate that fails a linear check "
            "(margins, bandwidth) is not simulated.")
    columns = ["motor", "gearbox", "settling", "following error", "bandwidth", "phase / gain margin",
               "resonance / anti-resonance", "notch", "result"]
    # relative column widths for the PDF: the names and the result wrap least
    widths = [1.15, 1.0, 0.95, 1.1, 1.0, 1.55, 1.5, 0.6, 1.2]
    return Table("dynamics", "Candidates judged on how they move", columns, rows, "llrrrrrll", note, widths)


def passed_over_table(dyn: dict[str, Any]) -> Table | None:
    """The static picks passed over for how they move, each with the check that decided it."""
    over = dyn.get("passed_over") or []
    if not over:
        return None
    rows = [[Cell(p["motor"]), Cell(p.get("gearbox") or "-"), Cell(p["status"], "fail" if p["status"] == "fail"
                                                                     else "warn"), Cell(p["reason"])]
            for p in over]
    return Table("dynamics-passed-over", "Static picks " + PASSED_OVER, ["motor", "gearbox", "dynamic result", "why"],
                 rows, "llll", widths=[1.0, 1.0, 0.8, 3.2])


def inertia_sentence(result: SizingResult) -> str | None:
    """The inertia ratio the dynamic pick ends up with, and that the dynamic checks decided it."""
    sel = result.selection
    dyn, pick = (None, None) if sel is None else (sel.dynamics, sel.selected)
    if not dyn or pick is None or not dyn.get("chosen") or dyn["chosen"]["motor"] != pick.motor:
        return None
    ratio = pick.inertia_ratio
    limit = result.axis.spec.motor.margins.inertia_ratio if result.axis.spec.motor is not None else None
    rule = f" (the inertia_ratio check, at most {fmt_number(limit)}, still applies)" if limit else ""
    return (f"{pick.motor} ends up with an inertia ratio J_L/J_M of {fmt_number(ratio)}: the dynamic checks "
            f"(settling, following error, bandwidth, margins) decided the pick, not the ratio{rule}.")


def settling_ratio_sentence(dyn: dict[str, Any]) -> str | None:
    """The settling-optimal ratio line (``selection.dynamics.settling_optimal_ratio``), where computed."""
    opt = dyn.get("settling_optimal_ratio")
    if not opt:
        return None
    if opt.get("ratio") is None:
        return f"settling-optimal ratio for {opt['motor']}: {opt['reason']}"
    return (f"settling-optimal {opt['stage']} for {opt['motor']}: {opt['label']} (settles in "
            f"{_ms(opt['settling_time_s'])}; at its own ratio, {_ms(opt['current_settling_time_s'])}); "
            f"{opt['scanned']} ratios scanned, {fmt_number(opt['range'][0])} to {fmt_number(opt['range'][1])} times "
            "its own (within its torque and speed)")


def dynamics_tables(result: SizingResult, du: DisplayUnits) -> list[Table]:
    """The report's dynamics section: the candidates judged, the picks passed over, and notes on the
    answer's inertia ratio and the settling-optimal ratio ([] when the axis states no requirements)."""
    dyn = result.selection.dynamics if result.selection is not None else None
    if not dyn:
        return []
    table = candidates_table(dyn, du)
    extra = [s for s in (inertia_sentence(result), settling_ratio_sentence(dyn)) if s]
    if extra:
        table.note = " ".join([table.note, *extra])
    over = passed_over_table(dyn)
    return [table] + ([over] if over is not None else [])
