"""The checks in words: their names and rules, a value in display units, the failure sentence, the verdict
at the top of the report and the table of checks.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from drivetrain.report.blocks import Cell, Table, Verdict
from drivetrain.report.display import DisplayUnits, fmt_number, fmt_percent, pretty_unit
from drivetrain.report.focus import Focus, candidate_label
from drivetrain.sizing.axis_blocks import own_checks

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

CHECK_NAMES: dict[str, str] = {
    "peak_torque": "Peak torque",
    "rms_torque": "RMS torque",
    "max_speed": "Maximum speed",
    "inertia_ratio": "Inertia ratio J_L/J_M",
    "mechanical_fit": "Motor onto gearbox (shaft, bore, flange)",
    "gearbox_peak_torque": "Gearbox T2B (cyclic peak)",
    "gearbox_rated_torque": "Gearbox T2N (rated torque)",
    "gearbox_emergency_stop_torque": "Gearbox T2NOT (emergency stop)",
    "gearbox_max_input_speed": "Gearbox n1max (max input speed)",
    "gearbox_mean_input_speed": "Gearbox n1N (mean input speed)",
    "motor_brake": "Motor brake",
    "gearbox_radial_load": "Gearbox F2r (radial output load)",
    "gearbox_axial_load": "Gearbox F2a (axial output load)",
    "slip_limit": "Load slip on its carrier",
    "brake_holding_torque": "Brake holding torque",
    "guide_normal": "Guide normal force",
    "guide_pitch": "Guide pitch moment",
    "guide_roll": "Guide roll moment",
    "guide_yaw": "Guide yaw moment",
}
"""Readable names of the motor checks."""

CHECK_QUANTITY: dict[str, str] = {"N*m": "torque", "Nm": "torque", "rpm": "angular_speed", "kg*m^2": "inertia",
                                   "W": "power", "N": "force", "s": "time", "J": "energy", "m/s^2": "acceleration"}
EXTRA_CHECKS = ("slip_check", "brake_check", "guide", "gearbox_checks")
"""The blocks of ``SizingResult`` that hold the axis's own checks (a ``RatingCheck``, or a block with ``checks``)."""


def _check_quantity(unit: str) -> str | None:
    return CHECK_QUANTITY.get(unit)


def check_value(value: float, unit: str, du: DisplayUnits) -> str:
    """A check's required or available value in display units ("1.373 N·m", "3429 rpm", "4.905")."""
    from drivetrain.units import from_rpm

    q = _check_quantity(unit)
    if q == "angular_speed":
        return du.fmt(from_rpm(value), q)
    if q is not None:
        return du.fmt(value, q)
    return fmt_number(value) + ("" if unit in ("-", "") else f" {pretty_unit(unit)}")


def failure_sentence(check: dict[str, Any], du: DisplayUnits) -> str:
    """'Peak torque: required 5.4 N·m > available 4.5 N·m (−16.7 %)'; an unjudged check says why."""
    name = CHECK_NAMES.get(check["name"], check["name"].replace("_", " "))
    unit = check.get("unit", "")
    if check.get("available") is None or check.get("margin") is None:
        return f"{name}: {check.get('note') or 'cannot be judged'}"
    if check["name"] == "mechanical_fit":
        return (f"{name}: motor shaft {fmt_number(check['required'])} mm > gearbox input bore "
                f"{fmt_number(check['available'])} mm, or flange/pilot differ ({fmt_percent(check['margin'])})")
    return (f"{name}: required {check_value(check['required'], unit, du)} > available "
            f"{check_value(check['available'], unit, du)} ({fmt_percent(check['margin'])})")


def _margin_factors(result: SizingResult) -> dict[str, float]:
    m = result.axis.spec.motor.margins if result.axis.spec.motor is not None else None
    if m is None:
        return {}
    return {"peak_torque": m.torque, "rms_torque": m.rms_torque or m.torque, "max_speed": m.speed,
            "gearbox_rated_torque": m.torque, "gearbox_peak_torque": m.torque}


def _rule(check: dict[str, Any], factors: dict[str, float]) -> str:
    f = factors.get(check["name"], 1.0)
    times = f" × {fmt_number(f, 3)}" if f != 1.0 else ""
    fs = factors.get("max_speed", 1.0)
    times_s = f" × {fmt_number(fs, 3)}" if fs != 1.0 else ""
    rules = {
        "peak_torque": f"|T_M|{times} ≤ intermittent envelope at that speed",
        "rms_torque": f"T_rms{times} ≤ continuous torque at mean speed",
        "max_speed": f"n_max{times} ≤ motor max speed",
        "inertia_ratio": "J_L / J_M ≤ limit",
        "mechanical_fit": "motor shaft ≤ gearbox input bore (≥ smallest bushing); flange, pilot = adapter's",
        "gearbox_peak_torque": f"cycle's peak output torque{times} (× shock factor above 1000 cycles/h) ≤ T2B",
        "gearbox_rated_torque": f"cubic-mean output torque{times} ≤ T2N",
        "gearbox_emergency_stop_torque": "torque through the gearbox at the motor's peak (k-split) ≤ T2NOT",
        "gearbox_max_input_speed": f"peak input speed{times_s} ≤ n1max",
        "gearbox_mean_input_speed": "mean input speed ≤ n1N",
        "slip_limit": "peak acceleration ≤ μ_0 g cos α ∓ g sin α (up / down the slope)",
        "brake_holding_torque": "torque held in braked dwells ≤ brake holding torque",
        "guide_normal": "peak normal force ≤ guide rating",
        "guide_pitch": "peak pitch moment ≤ guide rating",
        "guide_roll": "peak roll moment ≤ guide rating",
        "guide_yaw": "peak yaw moment ≤ guide rating",
    }
    text = rules.get(check["name"], check.get("note") or "")
    if check.get("approximate"):
        text += " (approximate envelope)"
    if check.get("status") in ("unknown", "not_judged") and check.get("note"):
        # a check without a rule of its own already reads its note
        text = f"not judged: {check['note']}" if text == check["note"] else text + f" — not judged: {check['note']}"
    return text


def axis_checks(result: SizingResult) -> list[dict[str, Any]]:
    """The axis's own checks (load slip, brake, guide ratings, gearbox ratings) of the result,
    as the JSON states them (read with the motor's checks)."""
    return [c.to_dict() for _, c in own_checks(result, EXTRA_CHECKS)]


def _tightest(checks: list[dict[str, Any]], du: DisplayUnits) -> str:
    finite = [c for c in checks if c.get("margin") is not None and math.isfinite(c["margin"])
              and c.get("available") is not None]
    if not finite:
        return ""
    t = min(finite, key=lambda c: c["margin"])
    return (f"Tightest check: {CHECK_NAMES.get(t['name'], t['name'])}, margin {fmt_percent(t['margin'])} "
            f"(required {check_value(t['required'], t['unit'], du)} of {check_value(t['available'], t['unit'], du)}"
            " available).")


_APPROX_NOTE = ("Torque checks use the speed-torque envelope derived from the motor's ratings (approximate, no "
                "vendor curve): confirm thin margins on the datasheet curve.")


def verdict(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Verdict:
    """The banner: the three outcomes of ``SizingResult.status`` (pass, pass with unknowns, fail) with what
    fails and every check that could not be judged (or info where no motor is given)."""
    verdict = _checks_verdict(result, du, focus)
    if result.status == "fail" and verdict.status != "fail":  # motor.select.unknown: fail
        names = ", ".join(u.check for u in result.unknowns)
        return Verdict("fail", f"Fails: checks that cannot be judged count as failures (motor.select.unknown: fail): "
                       f"{names}", verdict.details)
    return verdict


def unknown_lines(result: SizingResult) -> list[str]:
    """One sentence per check of the answer that could not be judged (``SizingResult.unknowns``)."""
    return [f"Not judged: {u.part}: {u.decide}." if u.check == u.part else
            f"Not judged ({u.part}): {CHECK_NAMES.get(u.check, u.check)}: {u.decide}." for u in result.unknowns]


def _checks_verdict(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Verdict:
    verdict = _motor_verdict(result, du, focus)
    failed = [c for c in axis_checks(result) if not c.get("ok", True)]
    if not failed:
        return verdict
    lines = [failure_sentence(c, du) for c in sorted(failed, key=lambda c: c.get("margin") or 0.0)]
    if verdict.status == "fail":
        return Verdict("fail", verdict.headline, lines + verdict.details)
    names = ", ".join(CHECK_NAMES.get(c["name"], c["name"]).lower() for c in failed)
    head = f"Axis check{'s' if len(failed) > 1 else ''} failing: {names}"
    motor = [f"Motor: {verdict.headline}."] if verdict.status in ("pass", "unknowns") else []
    return Verdict("fail", head, lines + motor + verdict.details)


def _motor_verdict(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Verdict:
    m = result.metrics
    sel = result.selection
    if focus is not None and focus.origin == "axis":
        checks = focus.checks
        failed = [c for c in checks if not c["ok"]]
        approx = any(c.get("approximate") for c in checks)
        if not failed:
            details = [d for d in (_tightest(checks, du), _APPROX_NOTE if approx else "") if d]
            unknown = unknown_lines(result)
            if unknown:
                return Verdict("unknowns", f"Motor {focus.label}: pass with unknowns "
                               f"({len(unknown)} not judged)", details + unknown)
            return Verdict("pass", f"Motor {focus.label} is adequate: all {len(checks)} checks pass", details)
        details = [failure_sentence(c, du) for c in sorted(failed, key=lambda c: c["margin"])]
        return Verdict("fail", f"Motor {focus.label} is not adequate: {len(failed)} of {len(checks)} checks fail",
                       details)
    if sel is not None or result.candidates:
        scope = ""
        if sel is not None and sel.evaluated is not None and sel.passing is not None:
            how = (f"direct and behind {sel.gearbox_rows} catalog gearbox rows" if sel.gearbox_rows
                   else (f"on the axis's {sel.transmission_gearbox}" if sel.transmission_gearbox
                         else "direct drive"))
            scope = (f"{sel.passing} of {sel.evaluated} configurations pass, no check failing "
                     f"({sel.motors} motors, "
                     f"{how}); objective: {sel.objective.replace('_', ' ')}.")
        if focus is not None and focus.passed:
            details = [d for d in (scope, _tightest(focus.checks, du)) if d]
            nxt = sel.next_smaller if sel is not None else None
            if nxt is not None and nxt.motor:
                short = [c for c in nxt.checks if c.status == "fail"]
                first = min(short, key=lambda c: (c.name != "max_speed", c.margin or 0.0)) if short else None
                why = failure_sentence(first.to_dict(), du) if first is not None else (nxt.failed or "fails a check")
                details.append(f"Next smaller motor {candidate_label(nxt)} is rejected: {why}.")
            if any(c.get("approximate") for c in focus.checks):
                details.append(_APPROX_NOTE)
            unknown = unknown_lines(result)
            if unknown:
                return Verdict("unknowns", f"Selected: {focus.label}, pass with unknowns "
                               f"({len(unknown)} not judged)", details + unknown)
            return Verdict("pass", f"Selected: {focus.label}, passes every check", details)
        details = [d for d in (scope,) if d]
        if focus is not None:
            bad = [c for c in focus.checks if not c.get("ok", True)]
            bad = [c for c in bad if c.get("status", "fail") == "fail"]
            details += [f"Closest: {focus.label}: " + failure_sentence(c, du) for c in
                        sorted(bad, key=lambda c: (c["name"] != "max_speed", c.get("margin") or 0.0))[:2]]
        if sel is not None and sel.advice:
            details += sel.advice.splitlines()
        if sel is not None and sel.drive_advice:  # the motors pass, but none can be ordered with a drive
            return Verdict("fail", "No passing motor has a drive that can be ordered",
                           [*details, f"Not orderable: {sel.drive_advice}."])
        return Verdict("fail", "No catalog motor passes every check", details)
    return Verdict("info", "Demand at the motor shaft (no motor given)", [
        f"Peak {du.fmt(m.peak_torque_Nm, 'torque')}, RMS {du.fmt(m.rms_torque_Nm, 'torque')}, "
        f"up to {du.fmt(speed_si(m.max_speed_rpm), 'angular_speed')}, load inertia "
        f"{du.fmt(m.load_inertia_kgm2, 'inertia')} at the motor shaft (rotor excluded).",
        "Add a motor (its ratings, or a catalog id) or motor: {select: ...} to the axis file to check one.",
        *unknown_lines(result),
    ])


def speed_si(rpm: float) -> float:
    """A speed the result gives in rpm, in rad/s (the SI the display units convert from)."""
    from drivetrain.units import from_rpm

    return from_rpm(rpm)


def checks_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table | None:
    own = axis_checks(result)
    if focus is None and not own:
        return None
    factors = _margin_factors(result)
    rows = []
    for c in [*(focus.checks if focus is not None else []), *own]:
        ok = bool(c["ok"])
        avail = c.get("available")
        status = c.get("status")
        unjudged = status in ("unknown", "not_judged")
        verdict = {"unknown": "UNKNOWN", "not_judged": "NOT JUDGED"}.get(str(status), "PASS" if ok else "FAIL")
        rows.append([
            Cell(CHECK_NAMES.get(c["name"], c["name"].replace("_", " "))),
            Cell(_rule(c, factors), "muted"),
            Cell(check_value(c["required"], c["unit"], du)),
            Cell(check_value(avail, c["unit"], du) if avail is not None else ("not given" if unjudged else "no limit")),
            Cell(fmt_percent(c.get("margin")), "muted" if unjudged else ("pass" if ok else "fail")),
            Cell(verdict, "muted" if unjudged else ("pass" if ok else "fail")),
        ])
    note = "Required values include the margin factors of the axis file; margin = available / required − 1. "
    if focus is not None and any(c.get("approximate") for c in focus.checks):
        note += "Envelope values are approximate, derived from the motor's ratings (no vendor curve)."
    if focus is None:
        title = "Checks of the axis"
    else:
        what = "motor" if focus.gearbox is None else "motor and gearbox"
        title = f"Checks of {what} {focus.label}" + (" and of the axis" if own else "")
    return Table("checks", title,
                 ["check", "rule", "required", "available", "margin", "result"], rows, "llrrrl", note,
                 [0.16, 0.36, 0.13, 0.13, 0.11, 0.11])
