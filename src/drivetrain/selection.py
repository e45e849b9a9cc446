"""Motor and gearbox selection from the catalog: every motor against every ratio, with reasons.

Candidates are catalog motors, each direct or behind each catalog gearbox (one row per model
and ratio). The duty cycle of the axis is computed once; a gearbox of ratio i and efficiency
eta changes it only through T_in = Q(T_out / i) + J_g i alpha (four-quadrant rule, stage.py),
so the per-sample work runs once per distinct (i, eta) and the per-candidate work is closed
forms over arrays (motor_fit.py).

Checks per candidate (each with required, available, margin, ok): peak torque against the
intermittent envelope at the speed where it occurs, RMS torque against the continuous torque
at the mean speed, max speed against the motor and the gearbox's input speed, inertia ratio,
and for a gearbox: its rated output torque against the cycle's speed-weighted cubic-mean
output torque (Harmonic Drive / strain-wave selection practice), and the torque that passes it
when the motor gives its peak torque, (1 - k)(T_M - T_L) + T_L with k = J_M / (J_M + J_LR)
(lecture, Dynamic Loading and Gearbox Sizing), against its emergency-stop or max torque.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.duty import cubic_mean
from drivetrain.errors import InputError
from drivetrain.motor_fit import Demand, MotorArrays, demand, fit_motors, scaled
from drivetrain.stage import Stage, torque_in
from drivetrain.units import to_rpm

if TYPE_CHECKING:
    from drivetrain.axis import Axis, Margins, SelectSpec
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.duty import DutyCycle

Array = NDArray[np.float64]

CHECK_UNITS = {"peak_torque": "N*m", "rms_torque": "N*m", "max_speed": "rpm", "inertia_ratio": "-",
               "gearbox_rated_torque": "N*m", "gearbox_peak_torque": "N*m"}


@dataclass(frozen=True)
class Candidates:
    """Every evaluated candidate as arrays (index k over candidates)."""

    motor: NDArray[np.intp]  # index into the motor table
    gearbox: NDArray[np.intp]  # index into the gearbox table, -1 for direct drive
    ratio: Array
    inertia_ratio: Array
    required: dict[str, Array]
    available: dict[str, Array]
    margin: dict[str, Array]
    approximate: dict[str, NDArray[np.bool_]]
    rms_torque: Array
    peak_torque: Array

    @property
    def ok(self) -> NDArray[np.bool_]:
        """True where every check passes."""
        out = np.ones(len(self.motor), dtype=bool)
        for m in self.margin.values():
            out &= m >= 0.0
        return out

    @property
    def worst_margin(self) -> Array:
        """The smallest margin of each candidate."""
        return np.min(np.vstack(list(self.margin.values())), axis=0)


def _gearbox_options(gb: GearboxTable | None, allow_direct: bool) -> list[tuple[float, float, list[int]]]:
    """Distinct (ratio, efficiency) groups with the gearbox rows in each; (1, 1, [-1]) is direct drive."""
    groups: dict[tuple[float, float], list[int]] = {}
    if allow_direct:
        groups[(1.0, 1.0)] = [-1]
    if gb is not None:
        eff = np.where(np.isnan(gb.efficiency), 1.0, gb.efficiency)
        for k in range(len(gb)):
            groups.setdefault((float(gb.ratio[k]), float(eff[k])), []).append(k)
    return [(i, e, rows) for (i, e), rows in groups.items()]


def evaluate(axis: Axis, duty: DutyCycle, motors: MotorTable, gb: GearboxTable | None, margins: Margins,
             allow_direct: bool = True, max_inertia_ratio: float | None = None) -> Candidates:
    """Check every motor against every gearbox row (and direct drive), vectorised over candidates."""
    limit = margins.inertia_ratio if max_inertia_ratio is None else min(max_inertia_ratio, margins.inertia_ratio)
    motor_arrays = MotorArrays(
        inertia=motors.rotor_inertia, rated_torque=motors.rated_torque, peak_torque=motors.peak_torque,
        rated_speed=motors.rated_speed, max_speed=motors.max_speed, stall_torque=motors.stall_torque,
        approximate=~motors.has_curve, curves=tuple(motors.curves),
    )
    n_m = len(motors)
    t0, e0, w0, a0 = duty.torque, duty.external, duty.omega, duty.alpha
    direction = np.asarray(duty.samples.direction, dtype=float)
    out_cubic = cubic_mean(t0, w0, duty.weights)
    run_t = float(np.median(np.abs(duty.external))) if duty.external.size else 0.0
    parts: list[dict[str, Any]] = []
    base: dict[float, Demand] = {}
    for ratio, eff, rows in _gearbox_options(gb, allow_direct):
        if eff not in base:
            # Losses applied at ratio 1; every ratio of the same efficiency is a scaling of it.
            stage = Stage("gearbox", "gearbox", ratio=1.0, efficiency=eff, back_efficiency=eff)
            t_in, _ = torque_in(stage, t0, e0, w0, a0, direction, axis.efficiency_model)
            base[eff] = demand(w0, a0, t_in, duty.weights, duty.period, duty.load_inertia)
        d = scaled(base[eff], ratio)
        rows_arr = np.asarray(rows)
        m_idx = np.repeat(np.arange(n_m), len(rows_arr))
        g_idx = np.tile(rows_arr, n_m)
        direct = g_idx < 0
        safe_g = np.where(direct, 0, g_idx)

        def pick(values: Array | None, fallback: float, safe: NDArray[np.intp] = safe_g,
                 is_direct: NDArray[np.bool_] = direct) -> Array:
            if values is None:
                return np.full(len(safe), fallback)
            v = np.asarray(values, dtype=float)[safe]
            return np.where(is_direct | np.isnan(v), fallback, v)

        j_g = pick(gb.inertia_input if gb is not None else None, 0.0)
        speed_in = pick(gb.max_input_speed if gb is not None else None, math.inf)
        speed_in = np.where(np.isinf(speed_in), pick(gb.rated_input_speed if gb is not None else None, math.inf),
                            speed_in)
        fit = fit_motors(d, motor_arrays, torque_margin=margins.torque, rms_margin=margins.rms_torque or margins.torque,
                         speed_margin=margins.speed, inertia_ratio_limit=limit, speed_limit=speed_in,
                         extra_inertia=j_g, index=m_idx)
        req, avail, mar, approx = dict(fit.required), dict(fit.available), dict(fit.margin), dict(fit.approximate)
        # Gearbox output torque: rated vs the cycle's cubic mean; and what passes at the motor's peak torque.
        rated = pick(gb.rated_output_torque if gb is not None else None, math.inf)
        req["gearbox_rated_torque"] = np.full(len(m_idx), out_cubic * margins.torque)
        avail["gearbox_rated_torque"] = rated
        j_lr = d.load_inertia
        j_rotor = motor_arrays.inertia[m_idx]
        k_split = (j_rotor + j_g) / (j_rotor + j_g + j_lr)
        t_pass = ((1.0 - k_split) * (motor_arrays.peak_torque[m_idx] - run_t / ratio) + run_t / ratio) * ratio * eff
        t_max = pick(gb.max_output_torque if gb is not None else None, math.nan)
        t_estop = pick(gb.emergency_stop_torque if gb is not None else None, math.inf)
        cap = np.where(np.isnan(t_max), t_estop, t_max)
        req["gearbox_peak_torque"] = np.where(direct, 0.0, t_pass)
        avail["gearbox_peak_torque"] = np.where(direct, math.inf, cap)
        for name in ("gearbox_rated_torque", "gearbox_peak_torque"):
            with np.errstate(divide="ignore", invalid="ignore"):
                mar[name] = np.where(direct, math.inf, avail[name] / np.maximum(req[name], 1e-300) - 1.0)
            approx[name] = np.zeros(len(m_idx), dtype=bool)
        parts.append({"motor": m_idx, "gearbox": g_idx, "ratio": np.full(len(m_idx), ratio),
                      "inertia_ratio": fit.inertia_ratio, "required": req, "available": avail, "margin": mar,
                      "approximate": approx, "rms": fit.rms_torque, "peak": fit.peak_torque})
    names = list(parts[0]["margin"])

    def cat(key: str, sub: str | None = None) -> Any:
        if sub is None:
            return np.concatenate([p[key] for p in parts])
        return {n: np.concatenate([p[key][n] for p in parts]) for n in names}

    return Candidates(motor=cat("motor"), gearbox=cat("gearbox"), ratio=cat("ratio"),
                      inertia_ratio=cat("inertia_ratio"), required=cat("required", "x"),
                      available=cat("available", "x"), margin=cat("margin", "x"),
                      approximate=cat("approximate", "x"), rms_torque=cat("rms"), peak_torque=cat("peak"))


def _size_key(motors: MotorTable) -> Array:
    """Motor size for 'smallest': rated power, else rated torque x rated speed [W]."""
    p = np.asarray(motors.rated_power, dtype=float)
    return np.where(np.isnan(p), motors.rated_torque * motors.rated_speed, p)


def _objective(c: Candidates, motors: MotorTable, gb: GearboxTable | None, objective: str,
               duty: DutyCycle) -> Array:
    """Score to minimise for each candidate."""
    gb_size = np.zeros(len(c.motor))
    if gb is not None:
        has = c.gearbox >= 0
        gb_size[has] = np.nan_to_num(gb.rated_output_torque[c.gearbox[has]], nan=0.0)
    if objective == "rms_utilisation":
        return c.required["rms_torque"] / np.maximum(c.available["rms_torque"], 1e-300)
    if objective == "inertia_match":
        return np.abs(np.log(np.maximum(c.inertia_ratio, 1e-12)))
    if objective == "energy":
        return _energy(c, motors, gb, duty)
    return _size_key(motors)[c.motor] * 1e6 + gb_size


def _energy(c: Candidates, motors: MotorTable, gb: GearboxTable | None, duty: DutyCycle) -> Array:
    """Motoring energy per cycle [J]: integral of max(T omega, 0) at the motor, per candidate (chunked)."""
    out = np.full(len(c.motor), math.inf)
    ok = np.flatnonzero(c.ok)[:5000]
    direction = np.asarray(duty.samples.direction, dtype=float)
    for ratio in np.unique(c.ratio[ok]):
        sel = ok[c.ratio[ok] == ratio]
        effs = np.ones(len(sel)) if gb is None else np.where(c.gearbox[sel] >= 0,
                                                             np.nan_to_num(gb.efficiency[c.gearbox[sel]], nan=1.0), 1.0)
        for eff in np.unique(effs):
            s2 = sel[effs == eff]
            stage = Stage("g", "gearbox", ratio=float(ratio), efficiency=float(eff), back_efficiency=float(eff))
            w_in, a_in = duty.omega * ratio, duty.alpha * ratio
            t_in, _ = torque_in(stage, duty.torque, duty.external, w_in, a_in, direction, "four_quadrant")
            j = motors.rotor_inertia[c.motor[s2]]
            if gb is not None:
                j = j + np.where(c.gearbox[s2] >= 0, np.nan_to_num(gb.inertia_input[c.gearbox[s2]]), 0.0)
            p = (t_in[None, :] + j[:, None] * a_in[None, :]) * w_in[None, :]
            out[s2] = np.sum(duty.weights[None, :] * np.maximum(p, 0.0), axis=1)
    return out


def pareto_front(size: Array, margin: Array, ratio: Array) -> NDArray[np.intp]:
    """Indices not dominated on (smaller size, larger margin, smaller inertia ratio)."""
    n = len(size)
    keep = np.ones(n, dtype=bool)
    for k in range(n):
        dom = (size <= size[k]) & (margin >= margin[k]) & (ratio <= ratio[k])
        strict = (size < size[k]) | (margin > margin[k]) | (ratio < ratio[k])
        if np.any(dom & strict):
            keep[k] = False
    return np.flatnonzero(keep)


def select(axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins) -> dict[str, Any]:
    """Evaluate the catalog against the duty cycle; rank, explain and summarise."""
    from drivetrain import catalog

    kind = None if spec.kind == "any" else spec.kind
    try:
        motors = catalog.motors(vendor=spec.vendor, kind=kind, voltage=spec.voltage, flange=spec.flange)
    except InputError as exc:
        raise exc.at("motor.select") from None
    if len(motors) == 0:
        raise InputError("motor.select", "no motor matches these filters: relax voltage or flange "
                         f"(voltage={spec.voltage}, flange={spec.flange}, vendor={spec.vendor})", has_value=False)
    gb = None
    own_gearbox = any(st.kind == "gearbox" for st in axis.transmission)
    if spec.gearbox == "only" or (spec.gearbox == "auto" and not own_gearbox):
        gb_kind = "small_gearhead" if spec.kind == "small_dc" else "servo_gearbox"
        try:
            gb = catalog.gearboxes(series=spec.gearbox_series, kind=gb_kind)
        except InputError as exc:
            raise exc.at("motor.select.gearbox_series") from None
    c = evaluate(axis, duty, motors, gb, margins, allow_direct=spec.gearbox != "only" or gb is None,
                 max_inertia_ratio=spec.max_inertia_ratio)
    score = _objective(c, motors, gb, spec.objective, duty)
    ok = c.ok
    passing = np.flatnonzero(ok)
    passing = passing[np.argsort(score[passing], kind="stable")]
    failing = np.flatnonzero(~ok)
    failing = failing[np.argsort(-c.worst_margin[failing], kind="stable")]

    def row(k: int, rank: int | None) -> dict[str, Any]:
        return candidate_dict(c, k, motors, gb, rank)

    shown = [row(int(k), r + 1) for r, k in enumerate(passing[: spec.top])]
    shown += [row(int(k), None) for k in failing[: max(spec.top - len(shown), 3)]]
    summary: dict[str, Any] = {
        "objective": spec.objective, "evaluated": len(c.motor), "motors": len(motors),
        "gearbox_rows": 0 if gb is None else len(gb), "passing": len(passing),
        "failures_by_check": {n: int(np.sum(c.margin[n] < 0.0)) for n in c.margin},
    }
    if len(passing):
        best = int(passing[0])
        summary["selected"] = row(best, 1)
        summary["next_smaller"] = _next_smaller(c, motors, gb, best)
        summary["optimal_ratio"] = optimal_ratio(axis, duty, motors, int(c.motor[best]), gb)
        top = passing[:2000]
        front = pareto_front(_size_key(motors)[c.motor[top]], c.worst_margin[top], c.inertia_ratio[top])
        summary["pareto_front"] = [_label(c, int(top[k]), motors, gb) for k in front[:50]]
    else:
        summary["advice"] = advice(c, margins, spec)
    summary["_candidates"] = c
    summary["_tables"] = (motors, gb)
    return {"candidates": shown, "selection": summary}


def _label(c: Candidates, k: int, motors: MotorTable, gb: GearboxTable | None) -> str:
    g = int(c.gearbox[k])
    return str(motors.ids[c.motor[k]]) + ("" if g < 0 or gb is None else f" + {gb.ids[g]}")


def candidate_dict(c: Candidates, k: int, motors: MotorTable, gb: GearboxTable | None,
                   rank: int | None) -> dict[str, Any]:
    """One candidate as in design.md: motor, gearbox, ratio, inertia ratio, ok, checks, why it failed."""
    m, g = int(c.motor[k]), int(c.gearbox[k])
    checks = []
    for n in c.margin:
        req, avail = float(c.required[n][k]), float(c.available[n][k])
        if n.startswith("gearbox") and g < 0:
            continue
        checks.append({"name": n, "required": req, "available": avail if math.isfinite(avail) else None,
                       "unit": CHECK_UNITS[n], "margin": float(c.margin[n][k]) if math.isfinite(c.margin[n][k])
                       else None, "ok": bool(c.margin[n][k] >= 0.0), "approximate": bool(c.approximate[n][k])})
    bad = [(float(c.margin[n][k]), n) for n in c.margin if c.margin[n][k] < 0.0]
    failed = ""
    if bad:
        mar, n = min(bad)
        failed = (f"{n}: required {c.required[n][k]:.4g} {CHECK_UNITS[n]} > available "
                  f"{c.available[n][k]:.4g} {CHECK_UNITS[n]} ({mar * 100:.1f} %)")
    return {
        "rank": rank, "motor": str(motors.ids[m]), "vendor": str(motors.vendor[m]),
        "gearbox": None if g < 0 or gb is None else str(gb.ids[g]), "ratio": float(c.ratio[k]),
        "inertia_ratio": float(c.inertia_ratio[k]), "rms_torque_Nm": float(c.rms_torque[k]),
        "peak_torque_Nm": float(c.peak_torque[k]), "rated_power_W": float(motors.rated_power[m]),
        "ok": not bad, "failed": failed, "approximate_envelope": bool(~motors.has_curve[m]),
        "rated_torque_derived": bool(motors.approx_rated[m]), "checks": checks,
    }


def _next_smaller(c: Candidates, motors: MotorTable, gb: GearboxTable | None, best: int) -> dict[str, Any] | None:
    """The next smaller motor than the selected one, in its best configuration, and why it fails."""
    size = _size_key(motors)
    chosen = size[c.motor[best]]
    smaller = size[c.motor] < chosen
    if not np.any(smaller):
        return None
    top_small = np.max(size[c.motor][smaller])
    pool = np.flatnonzero(size[c.motor] == top_small)
    k = int(pool[np.argmax(c.worst_margin[pool])])
    return candidate_dict(c, k, motors, gb, None)


def optimal_ratio(axis: Axis, duty: DutyCycle, motors: MotorTable, m: int,
                  gb: GearboxTable | None) -> dict[str, Any]:
    """Best ratio for one motor: sqrt(J_L / J_M) for pure inertia, and the ratio minimising RMS torque.

    The numerical optimum runs the four-quadrant reflection through an ideal gearbox of ratio i
    and minimises the RMS motor torque (rotor included) with a bounded scalar search.
    """
    from scipy.optimize import minimize_scalar

    j_m = float(motors.rotor_inertia[m])
    direction = np.asarray(duty.samples.direction, dtype=float)

    def rms_at(i: float) -> float:
        st = Stage("g", "gearbox", ratio=i)
        t_in, _ = torque_in(st, duty.torque, duty.external, duty.omega * i, duty.alpha * i, direction,
                            axis.efficiency_model)
        t_m = t_in + j_m * duty.alpha * i
        return float(np.sqrt(np.sum(duty.weights * t_m**2) / duty.period))

    top = float(motors.max_speed[m]) / max(float(np.max(np.abs(duty.omega))), 1e-12)
    hi = max(min(top, 1000.0), 1.0)
    res = minimize_scalar(rms_at, bounds=(0.01, hi), method="bounded", options={"xatol": 1e-6})
    best = float(res.x)
    nearest = None
    if gb is not None and len(gb):
        ratios = np.unique(gb.ratio)
        nearest = float(ratios[np.argmin(np.abs(np.log(ratios / best)))])
    return {"motor": str(motors.ids[m]), "inertia_match_ratio": math.sqrt(duty.load_inertia / j_m),
            "min_rms_ratio": best, "min_rms_torque_Nm": float(res.fun), "max_ratio_for_speed": top,
            "nearest_catalog_ratio": nearest}


def advice(c: Candidates, margins: Margins, spec: SelectSpec) -> str:
    """What to relax when nothing passes: the check that blocks most and the best candidate's shortfall."""
    best = int(np.argmax(c.worst_margin))
    blocking = [(float(c.margin[n][best]), n) for n in c.margin if c.margin[n][best] < 0]
    parts = [f"no candidate passes all checks ({len(c.motor)} evaluated)."]
    for mar, n in sorted(blocking):
        need = c.required[n][best]
        have = c.available[n][best]
        if n == "inertia_ratio":
            parts.append(f"the closest candidate needs an inertia ratio of {need:.3g} (limit {have:.3g}): raise "
                         "motor.margins.inertia_ratio or allow a gearbox (motor.select.gearbox: auto)")
        elif n == "max_speed":
            parts.append(f"it needs {need:.0f} rpm but reaches {have:.0f} rpm: a smaller ratio or a faster motor")
        else:
            parts.append(f"{n} short by {-mar * 100:.0f} % ({need:.4g} vs {have:.4g} {CHECK_UNITS[n]}): lengthen "
                         "the acceleration times, lower margins, or widen the vendor/voltage filters")
    if spec.vendor or spec.voltage or spec.flange:
        parts.append("filters in use: " + ", ".join(f"{k}={getattr(spec, k)}" for k in ("vendor", "voltage", "flange")
                                                    if getattr(spec, k)))
    return " ".join(parts)


def explain(result_selection: dict[str, Any], model: str) -> str:
    """Why a catalog motor was accepted or rejected, in its best configuration."""
    c: Candidates = result_selection["_candidates"]
    motors, gb = result_selection["_tables"]
    ids = np.asarray(motors.ids)
    hits = np.flatnonzero(ids == model)
    if not len(hits):
        lowered = {str(i).lower(): i for i in ids}
        if model.lower() in lowered:
            hits = np.flatnonzero(ids == lowered[model.lower()])
        else:
            raise InputError("--explain", "is not among the evaluated motors (check the filters)", model)
    rows = np.flatnonzero(np.isin(c.motor, hits))
    k = int(rows[np.argmax(c.worst_margin[rows])])
    d = candidate_dict(c, k, motors, gb, None)
    n_ok = int(np.sum(c.ok[rows]))
    lines = [f"{model}: {n_ok} of {len(rows)} configurations pass; best configuration: "
             f"{d['gearbox'] or 'direct drive'} (ratio {d['ratio']:.4g}, inertia ratio {d['inertia_ratio']:.3g})"]
    for ch in d["checks"]:
        mar = "n/a" if ch["margin"] is None else f"{ch['margin'] * 100:+.1f} %"
        avail = "n/a" if ch["available"] is None else f"{ch['available']:.4g}"
        lines.append(f"  {'ok  ' if ch['ok'] else 'FAIL'} {ch['name']}: required {ch['required']:.4g}, available "
                     f"{avail} {ch['unit']} ({mar})")
    if d["failed"]:
        lines.append(f"  rejected because {d['failed']}")
    return "\n".join(lines)


__all__ = ["Candidates", "evaluate", "explain", "optimal_ratio", "select", "to_rpm"]
