"""A selection's answer in words: each candidate's checks with status, why it fails (one line per
check, a motor too slow for the cycle first), what cannot be judged and why, what to relax when
nothing passes, and why a given catalog motor was accepted or rejected (``--explain``)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from drivetrain.errors import InputError
from drivetrain.sizing.answer import Candidate, CheckRow
from drivetrain.sizing.candidates import CHECK_UNITS, MOTOR_CHECKS, Candidates, Details, closest, column
from drivetrain.sizing.checks import adapter_arrays, adapter_margin
from drivetrain.sizing.motor_brake import brake_variant

if TYPE_CHECKING:
    from drivetrain.axis.model import Margins, SelectSpec
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.sizing.answer import SelectionSummary
    from drivetrain.sizing.candidates import Ranking


_RATING_NAMES = {"gearbox_peak_torque": "T2B (max acceleration torque)", "gearbox_rated_torque": "T2N (rated torque)",
                 "gearbox_emergency_stop_torque": "T2NOT (emergency-stop torque)",
                 "gearbox_max_input_speed": "n1max (max input speed)",
                 "gearbox_mean_input_speed": "n1N (nominal input speed)",
                 "gearbox_radial_load": "F2r (max radial output load)",
                 "gearbox_axial_load": "F2a (max axial output load)"}


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g} mm"


def _plain_mm(x: float) -> float | None:
    return None if math.isnan(float(x)) else round(float(x) * 1e3, 6)


def _fit_reason(motors: MotorTable, m: int, gb: GearboxTable, g: int) -> tuple[str, str]:
    """Why motor m and gearbox row g cannot be assembled (first), and what is unknown (second)."""
    from drivetrain.sizing.kernel import FIT_TOLERANCE

    shaft, flange, pilot = (float(column(motors, c)[m]) for c in ("shaft_diameter", "flange", "pilot_diameter"))
    bmax, bmin, gfl, gpi = (float(column(gb, c)[g]) for c in ("input_bore_max", "input_bore_min", "input_flange",
                                                                 "input_pilot"))
    bad, gaps = [], []
    if math.isnan(shaft):
        gaps.append("the motor's shaft diameter")
    if math.isnan(bmax):
        gaps.append("the gearbox's input bore")
    if not math.isnan(shaft) and not math.isnan(bmax) and shaft > bmax:
        bad.append(f"motor shaft {_mm(shaft)} > gearbox input bore {_mm(bmax)}")
    if not math.isnan(shaft) and not math.isnan(bmin) and shaft < bmin:
        bad.append(f"motor shaft {_mm(shaft)} < smallest bore with bushing {_mm(bmin)}")
    adapters = adapter_arrays([str(gb.input_adapters[g])])[0]
    drawn = adapters[~np.isnan(adapters[:, 1])]
    if len(drawn):
        bolt = float(column(motors, "bolt_circle")[m])
        names = ", ".join(f"{_mm(a[0])} bore / {_mm(a[1])} pilot / {_mm(a[2])} bolt circle" for a in drawn)
        fits = float(adapter_margin(shaft, pilot, bolt, drawn))
        if math.isnan(fits):
            lacking = [w for w, v in (("shaft diameter", shaft), ("pilot", pilot), ("bolt circle", bolt))
                       if math.isnan(v)]
            gaps.append(f"the motor's {' and '.join(lacking)} to match a drawn adapter ({names})")
        elif fits < 0.0:
            bad.append(f"no drawn adapter takes the motor (shaft {_mm(shaft)}, pilot {_mm(pilot)}, bolt circle "
                       f"{_mm(bolt)}); drawn: {names}")
    else:
        for what, mine, theirs in (("flange", flange, gfl), ("pilot", pilot, gpi)):
            if math.isnan(theirs):
                continue
            if math.isnan(mine):
                gaps.append(f"the motor's {what} (the adapter takes {_mm(theirs)})")
            elif abs(mine - theirs) > FIT_TOLERANCE:
                bad.append(f"motor {what} {_mm(mine)} ≠ gearbox adapter {what} {_mm(theirs)}")
        if math.isnan(gfl) and not bad:
            gaps.append("the gearbox's motor adapter (catalog input_adapters: bore/pilot/bolt circle, or input_flange "
                        "with input_pilot): ask the vendor for the adapter of this motor's flange"
                        + (f" ({_mm(flange)} flange, {_mm(pilot)} pilot)" if not math.isnan(flange) else ""))
    return "; ".join(bad), ("the catalog lacks " + " and ".join(gaps) if gaps else "")


def _unknown_note(name: str, c: Candidates, fit_gap: str) -> str:
    """Why a check cannot be judged."""
    par = c.model[-1]
    if name == "peak_torque":
        return "not judged: the cycle's speed is beyond the motor's max speed (see max_speed)"
    if name == "rms_torque":
        return "not judged: the cycle's mean speed is beyond the motor's max speed (see max_speed)"
    if name == "mechanical_fit":
        return fit_gap or "the catalog lacks a dimension it needs"
    if name == "gearbox_peak_torque" and math.isnan(float(par[8])):
        return (f"{3600.0 / float(par[0]):.0f} cycles/h exceed the 1000/h that T2B holds for: set "
                "motor.margins.gearbox_shock_factor from the vendor's chart")
    if name in ("gearbox_radial_load", "gearbox_axial_load") and math.isnan(float(par[10 if "radial" in name else 11])):
        return ("the load this axis puts on the gearbox output is not modelled for its mechanism or first stage: "
                "compare it with the gearbox's " + _RATING_NAMES[name].split(" (")[0] + " by hand")
    if name in _RATING_NAMES:
        return f"the catalog lacks the gearbox's {_RATING_NAMES[name]}"
    if name == "motor_brake":
        return ("the catalog lacks the holding torque of this motor's brake variant (motor_brakes.csv "
                "brake_holding_torque_Nm): the vendor's brake table decides it")
    return "the catalog lacks a rating it needs"


def fewest_failures(c: Candidates, pool: NDArray[np.intp]) -> int:
    """The candidate of ``pool`` that fails the fewest checks, of those the one with the smallest shortfall
    (the largest worst margin; an unknown, NaN, worst margin counts as the lowest); ties in pool order."""
    failed = c.failed[pool].astype(np.int64)
    bits = np.zeros(len(pool), dtype=np.int64)
    for b in range(len(CHECK_UNITS)):  # a handful of bits
        bits += (failed >> b) & 1
    w = c.worst_margin[pool]
    order = np.lexsort((-np.where(np.isnan(w), -np.inf, w), bits))
    return int(pool[order[0]])


def percent(margin: float | None) -> str:
    """A margin as a signed percentage that never shows a failing margin as "-0.0 %"."""
    if margin is None:
        return "n/a"
    p = margin * 100.0
    return f"{p:+.2g} %" if p != 0.0 and abs(p) < 0.1 else f"{p:+.1f} %"


def _reason(ch: CheckRow, fit_bad: str) -> str:
    """One failing check as a sentence."""
    n, unit = ch.name, ch.unit
    pct = percent(ch.margin)
    if n == "mechanical_fit":
        return f"mechanical_fit: {fit_bad} ({pct})"
    if n == "max_speed":
        return (f"max_speed: the cycle needs {ch.required:.0f} rpm at the motor (margin included), the motor "
                f"reaches {ch.available:.0f} rpm ({pct})")
    u = "" if unit == "-" else f" {unit}"
    avail = "n/a" if ch.available is None else f"{ch.available:.4g}{u}"
    return f"{n}: required {ch.required:.4g}{u} > available {avail} ({pct})"


def candidate_answer(c: Candidates, k: int, motors: MotorTable, gb: GearboxTable | None,
                     rank: int | None, details: Details | None = None) -> Candidate:
    """One candidate as in docs/axis-file.md: motor, gearbox, ratio, inertia ratio, status, checks, why it failed.

    ``status`` is ``ok`` (every check passes), ``unknown`` (none fails, some cannot be judged:
    ``unknown`` names them) or ``fails``; ``failures`` holds one sentence per failing check, a
    motor too slow for the cycle first; ``failed`` is the first of them. ``details``: candidate k's
    (``Details.column`` of a batch that holds it), else computed here.
    """
    m, g = int(c.motor[k]), int(c.gearbox(k))
    d = c.details([k]) if details is None else details
    geared = g >= 0 and gb is not None
    fit_bad, fit_gap = _fit_reason(motors, m, gb, g) if geared and gb is not None else ("", "")
    checks: dict[str, CheckRow] = {}
    for n in c.check_names():
        if n not in MOTOR_CHECKS and not geared:
            continue
        req, avail, mar = float(d.required[n][0]), float(d.available[n][0]), float(d.margin[n][0])
        status = "unknown" if math.isnan(mar) else ("pass" if mar >= 0.0 else "fail")
        # a motor slower than the cycle is not judged on torque where it cannot go: the peak check (margin NaN
        # from the kernel) and the RMS check when the cycle's mean speed is beyond it too (no continuous torque
        # there, e.g. a low-speed direct drive motor): max_speed fails instead
        too_slow = float(d.margin["max_speed"][0]) < 0.0
        slow = too_slow and ((n == "peak_torque" and status == "unknown")
                             or (n == "rms_torque" and status == "fail" and not avail > 0.0))
        if slow:
            status, avail, mar = "not_judged", math.nan, math.nan
        checks[n] = CheckRow(name=n, required=req, available=avail if math.isfinite(avail) else None,
                             unit=CHECK_UNITS[n], margin=mar if math.isfinite(mar) else None,
                             ok=status == "pass" or (status == "unknown" and not c.strict), status=status,
                             approximate=bool(d.approximate[n][0]),
                             note=_unknown_note(n, c, fit_gap) if status in ("unknown", "not_judged") else None)
    failing = sorted((ch for ch in checks.values() if ch.status == "fail"),
                     key=lambda ch: (ch.name != "max_speed", ch.margin, ch.name))
    failures = [_reason(ch, fit_bad) for ch in failing]
    unknown = [n for n, ch in checks.items() if ch.status == "unknown"]
    if c.strict:
        failures += [f"{n}: cannot be judged, {checks[n].note}" for n in unknown]
    ok = not failures
    unverified, unverified_reason = _trace(motors, m, gb if geared else None, g)
    return Candidate(
        rank=rank, motor=str(motors.ids[m]), vendor=str(motors.vendor[m]), series=str(motors.series[m]),
        rated_power_W=float(motors.rated_power[m]), flange_mm=_plain_mm(motors.flange[m]),
        shaft_diameter_mm=_plain_mm(column(motors, "shaft_diameter")[m]),
        gearbox=str(gb.ids[g]) if geared and gb is not None else None,
        gearbox_vendor=str(gb.vendor[g]) if geared and gb is not None else None, ratio=float(c.ratio(k)),
        inertia_ratio=float(d.inertia_ratio[0]), rms_torque_Nm=float(d.rms_torque[0]),
        peak_torque_Nm=float(d.peak_torque[0]),
        ok=ok, status="fails" if not ok else ("unknown" if unknown else "ok"), unknown=unknown,
        failed=failures[0] if failures else "", failures=failures,
        approximate_envelope=bool(~motors.has_curve[m]), rated_torque_derived=bool(motors.approx_rated[m]),
        derived=_derived(motors, m), unverified=unverified, unverified_reason=unverified_reason,
        checks=list(checks.values()), brake=brake_variant(motors, m) if c.brake_needed else None)


def _derived(motors: MotorTable, m: int) -> dict[str, str] | None:
    """``derived``: the motor's catalog values computed rather than read, each with its formula
    (catalog.derive.formulas); None for a motor whose every value was read."""
    if not motors.derived[m]:
        return None
    from drivetrain.catalog.derive import formulas

    return formulas({"derived": str(motors.derived[m]), "derivation": str(motors.derivation[m]),
                     "rated_torque_basis": str(motors.rated_torque_basis[m])})


def _trace(motors: MotorTable, m: int, gb: GearboxTable | None, g: int) -> tuple[bool, str | None]:
    """``unverified`` and its reason: the motor's or the gearbox's catalog row is not traced to a vendor
    document, or a rating the sizing uses was derived (catalog.schema.trace)."""
    reasons = [f"motor: {motors.unverified_reason[m]}"] if motors.unverified[m] else []
    if gb is not None and g >= 0 and gb.unverified[g]:
        reasons.append(f"gearbox: {gb.unverified_reason[g]}")
    return bool(reasons), "; ".join(reasons) or None


def advice(c: Candidates, margins: Margins, spec: SelectSpec, motors: MotorTable | None = None,
           gb: GearboxTable | None = None) -> str:
    """What to relax when nothing passes, one line per blocking check of the closest candidate.

    A suggestion is made only where it would change something: no "allow a gearbox" when
    gearboxes are already allowed, no "lower the margins" at a margin of 1, no "widen the filters"
    without filters.
    """
    k = closest(c, np.arange(len(c.motor)))
    d = c.details([k])
    blocking = [(float(d.margin[n][0]), n) for n in CHECK_UNITS if d.margin[n][0] < 0]
    blocking.sort(key=lambda b: (b[1] != "max_speed", b[0], b[1]))
    lines = [f"no candidate passes all checks ({len(c.motor)} evaluated)"]
    filters = [f"{f}={getattr(spec, f)}" for f in ("vendor", "voltage", "flange", "gearbox_series")
               if getattr(spec, f)]
    no_gearbox = spec.gearbox == "none"
    too_slow = float(d.margin["max_speed"][0]) < 0.0
    for mar, n in blocking:
        need, have = d.required[n][0], d.available[n][0]
        fixes: list[str] = []
        if too_slow and n in ("peak_torque", "rms_torque") and not have > 0.0:
            # not judged (as candidate_answer says): the motor offers no torque at a speed it cannot reach, so a
            # shortfall against it is no measure of anything; say what would judge it instead of a percentage
            lines.append(f"{n} not judged: {_unknown_note(n, c, '').removeprefix('not judged: ')}; a motor that "
                         "reaches the cycle's speed is judged on it")
            continue
        if n == "inertia_ratio":
            head = f"the closest candidate needs an inertia ratio of {need:.3g} (limit {have:.3g})"
            if margins.inertia_ratio < 1000:
                fixes.append("raise motor.margins.inertia_ratio if the drive's tuning allows")
            if no_gearbox:
                fixes.append("allow a gearbox (motor.select.gearbox: auto)")
            else:
                fixes.append("a motor with more rotor inertia")
        elif n == "max_speed":
            head = f"it needs {need:.0f} rpm but reaches {have:.0f} rpm"
            fixes.append("a faster motor" + ("" if no_gearbox else " or a smaller ratio"))
            if margins.speed > 1.0:
                fixes.append(f"motor.margins.speed is {margins.speed:g}")
        elif n == "mechanical_fit":
            head = f"the closest gearbox cannot take the motor (shaft {need:.4g} mm, input bore {have:.4g} mm)"
            fixes.append("a gearbox series with a larger input bore (motor.select.gearbox_series) or a motor with a "
                         "smaller shaft")
        elif n.startswith("gearbox_"):
            head = f"{n} short by {-mar * 100:.0f} % ({need:.4g} vs {have:.4g} {CHECK_UNITS[n]})"
            fixes.append("a larger gearbox frame" + (" (widen motor.select.gearbox_series)" if spec.gearbox_series
                                                      else ""))
        else:
            head = f"{n} short by {-mar * 100:.0f} % ({need:.4g} vs {have:.4g} {CHECK_UNITS[n]})"
            fixes.append("lengthen the acceleration times")
            if (margins.torque > 1.0 if n == "peak_torque" else (margins.rms_torque or margins.torque) > 1.0):
                fixes.append(f"lower motor.margins.{'torque' if n == 'peak_torque' else 'rms_torque'} if the "
                             "application allows")
            if no_gearbox:
                fixes.append("allow a gearbox (motor.select.gearbox: auto)")
            if filters:
                fixes.append("widen the filters")
        lines.append(f"{head}: {', or '.join(fixes)}" if fixes else head)
    if c.strict and not blocking:
        lines.append("the closest candidates fail only on checks the catalog cannot judge: motor.select.unknown: "
                     "flag accepts them, flagged")
    if filters:
        lines.append("filters in use: " + ", ".join(filters))
    return "\n".join(lines)


def explain(result_selection: SelectionSummary, ranking: Ranking, model: str) -> str:
    """Why a catalog motor was accepted or rejected, in its best configuration (``result_selection``: the
    selection's summary, ``ranking``: the candidates it was read from)."""
    c: Candidates = ranking.candidates
    motors, gb = ranking.motors, ranking.gearboxes
    ids = np.asarray(motors.ids)
    hits = np.flatnonzero(ids == model)
    if not len(hits):
        lowered = {str(i).lower(): i for i in ids}
        if model.lower() in lowered:
            hits = np.flatnonzero(ids == lowered[model.lower()])
        else:
            raise InputError("--explain", "is not among the evaluated motors (check the filters)", model)
    rows = c.of_motors(hits)
    ok_rows = rows[c.ok[rows]]
    ranked = ranking.ranked
    mine = ranked[np.isin(c.motor[ranked], hits)] if len(ok_rows) else ranked[:0]
    if len(mine):  # a passing motor: its configuration the ranking put first
        best = int(mine[0])
    elif len(ok_rows):  # passing, but not among the candidates ranked: its passing one with the largest margin
        best = closest(c, ok_rows)
    else:
        best = fewest_failures(c, rows)
    d = candidate_answer(c, best, motors, gb, None)
    n_ok = len(ok_rows)
    mounting = d.gearbox or (f"on the axis's {result_selection.transmission_gearbox}"
                             if result_selection.transmission_gearbox else "direct drive")
    lines = [f"{model}: {n_ok} of {len(rows)} configurations pass; best configuration: "
             f"{mounting} (catalog ratio {d.ratio:.4g}, inertia ratio {d.inertia_ratio:.3g})"]
    mark = {"pass": "ok  ", "fail": "FAIL", "unknown": "??  ", "not_judged": "--  "}
    for ch in d.checks:
        mar = percent(ch.margin)
        avail = "n/a" if ch.available is None else f"{ch.available:.4g}"
        note = f": {ch.note}" if ch.note else ""
        lines.append(f"  {mark[ch.status]} {ch.name}: required {ch.required:.4g}, available "
                     f"{avail} {ch.unit} ({mar}){note}")
    if d.failures:
        lines.append("  rejected because:")
        lines += [f"    {f}" for f in d.failures]
    elif d.unknown:
        lines.append(f"  passes with checks the catalog cannot judge: {', '.join(d.unknown)}")
    per_check = {n: int(np.count_nonzero(c.failed[rows] & (1 << b))) for b, n in enumerate(CHECK_UNITS)}
    counts = ", ".join(f"{n} {v}" for n, v in per_check.items() if v)
    if counts:
        lines.append(f"  its {len(rows)} configurations fail: {counts} (one may fail several)")
    return "\n".join(lines)


__all__ = ["advice", "candidate_answer", "explain", "fewest_failures", "percent"]
