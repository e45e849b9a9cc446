"""Motor and gearbox selection from the catalog: every motor against every ratio, with reasons.

Candidates are catalog motors, each direct or behind each catalog gearbox (one row per model
and ratio). The duty cycle of the axis is computed once; a gearbox of ratio i and efficiency
eta changes it only through T_in = Q(T_out / i) + J_g i alpha (four-quadrant rule, stage.py),
so the per-sample work runs once per distinct (i, eta) and the per-candidate work is closed
forms over arrays (motor_fit.py).

Checks per candidate (each with required, available, margin, ok): peak torque against the
intermittent envelope at the speed where it occurs, RMS torque against the continuous torque
at the mean speed, max speed against the motor's, inertia ratio, and for a gearbox: whether
the motor can be assembled onto it (``checks.mechanical_fit``) and every rating as vendors
rate it (``checks.gearbox_ratings``: T2B, T2N, T2NOT, n1max, n1N).

A check whose rating or dimension the catalog lacks is *unknown* (margin NaN). Unknown checks
do not reject a candidate by default (``motor.select.unknown: flag``): it passes with status
``unknown`` and the names of those checks, and the answer says so, as it does for an envelope
derived from ratings; ``unknown: fail`` rejects it instead (docs/checks.md).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.errors import InputError
from drivetrain.physics.averages import cubic_mean
from drivetrain.physics.stage import Stage
from drivetrain.sizing.answer import Candidate, OptimalRatio, SelectionSummary
from drivetrain.sizing.candidates import (
    BRAKE_BIT,
    CHECK_UNITS,
    FIT_BIT,
    MOTOR_CHECKS,
    Candidates,
    Details,
    Ranking,
    Selection,
    closest,
    column,
)
from drivetrain.sizing.checks import MAX_ADAPTERS, adapter_arrays, running_torque, shock_factor
from drivetrain.sizing.demand import Demand
from drivetrain.sizing.envelope import continuous_torque, intermittent_torque, motor_envelopes
from drivetrain.sizing.mechanism_checks import output_loads
from drivetrain.sizing.motor_brake import braked_motors, holding_need
from drivetrain.sizing.motor_fit import demand
from drivetrain.sizing.reasons import advice, candidate_answer, explain
from drivetrain.units import to_rpm

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis, Margins, SelectSpec
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.duty.cycle import DutyCycle

Array = NDArray[np.float64]


def gearbox_options(gb: GearboxTable | None, allow_direct: bool) -> tuple[Array, Array, NDArray[np.int64],
                                                                          NDArray[np.int64]]:
    """Distinct (ratio, efficiency) groups, in order of first appearance, direct drive (1, 1) first:
    their ratios, efficiencies, and the gearbox rows of group g, ``rows[row_start[g]:row_start[g + 1]]``
    in table order (-1 is direct drive; a catalog row of ratio 1 and efficiency 1 joins it)."""
    if gb is None or not len(gb):  # direct drive alone (or nothing): the result of the general path below
        n = 1 if allow_direct else 0
        return np.ones(n), np.ones(n), np.full(n, -1, dtype=np.int64), np.arange(n + 1, dtype=np.int64)
    ratio = np.array([1.0] if allow_direct else [])
    eff = np.array([1.0] if allow_direct else [])
    rows = np.array([-1] if allow_direct else [], dtype=np.int64)
    if gb is not None and len(gb):
        ratio = np.concatenate([ratio, np.asarray(gb.ratio, dtype=float)])
        eff = np.concatenate([eff, np.where(np.isnan(gb.efficiency), 1.0, gb.efficiency)])
        rows = np.concatenate([rows, np.arange(len(gb), dtype=np.int64)])
    # (ratio, efficiency) pairs as complex numbers: numpy sorts them by real, then imaginary part
    _, first, inverse = np.unique(ratio + 1j * eff, return_index=True, return_inverse=True)
    by_appearance = np.argsort(first)
    group = np.argsort(by_appearance)[inverse.ravel()]  # group number of each row, by first appearance
    order = np.argsort(group, kind="stable")
    row_start = np.concatenate([[0], np.cumsum(np.bincount(group))]).astype(np.int64)
    return ratio[first[by_appearance]], eff[first[by_appearance]], rows[order], row_start


def _padded(arrays: list[Array], shape: tuple[int, ...]) -> Array:
    """Stack arrays to ``(len(arrays), *shape)``, padding each axis by repeating its last entry.

    A repeated hull vertex or speed bin changes no maximum and no first-worst bin.
    """
    if len(arrays) == 1 and arrays[0].shape == shape:  # nothing to pad
        return np.asarray(arrays[0], dtype=float)[None]
    out = np.empty((len(arrays), *shape))
    for k, a in enumerate(arrays):
        out[k][tuple(slice(0, n) for n in a.shape)] = a
        for d, n in enumerate(a.shape):  # fill the rest of each axis with its last entry
            lead = (slice(None),) * d
            out[k][(*lead, slice(n, None))] = out[k][(*lead, slice(n - 1, n))]
    return out


def lossy_torque(axis: Axis, duty: DutyCycle, efficiency: float) -> Array:
    """The load torque at the input of a gearbox of ratio 1 and this efficiency [N m], per sample:
    what every ratio of that efficiency scales (four-quadrant rule, stage.py)."""
    stage = Stage("gearbox", "gearbox", efficiency=efficiency, back_efficiency=efficiency)
    return duty.behind(stage, axis.efficiency_model).torque


def evaluate(axis: Axis, duty: DutyCycle, motors: MotorTable, gb: GearboxTable | None, margins: Margins,
             allow_direct: bool = True, max_inertia_ratio: float | None = None, strict: bool = False,
             given_demands: Mapping[float, Demand] | None = None) -> Candidates:
    """Check every motor against every gearbox row (and direct drive) in one compiled pass.

    The per-sample work runs once per distinct gearbox efficiency (its losses at ratio 1, then
    scaled to each ratio, motor_fit.scaled); envelopes are computed by envelope.py at the speeds
    the checks need; _select_kernel.check does the per-candidate arithmetic.

    ``given_demands``: ``motor_fit.demand`` of ``lossy_torque`` for some efficiencies, where the caller
    has it already (a study evaluates one cycle against several motor tables); the others are
    computed here.
    """
    from drivetrain.sizing.kernel import check

    limit = margins.inertia_ratio if max_inertia_ratio is None else min(max_inertia_ratio, margins.inertia_ratio)
    t0, w0, a0 = duty.torque, duty.omega, duty.alpha
    out_cubic = cubic_mean(t0, w0, duty.weights)
    run_t = running_torque(duty.external)
    ratio, eff_g, rows, row_start = gearbox_options(gb, allow_direct)
    base: dict[float, Demand] = {}
    for eff in eff_g.tolist():
        if eff not in base and given_demands is not None and eff in given_demands:
            base[eff] = given_demands[eff]
        elif eff not in base:
            # Losses applied at ratio 1; every ratio of the same efficiency is a scaling of it.
            base[eff] = demand(w0, a0, lossy_torque(axis, duty, eff), duty.weights, duty.period, duty.load_inertia)
    effs = list(base)
    demands = list(base.values())
    e_of = np.array([effs.index(e) for e in eff_g.tolist()])  # each group's efficiency
    n_bins = max(d.hull_torque.shape[0] for d in demands)
    n_v = max(d.hull_torque.shape[1] for d in demands)
    n_all = max(d.all_torque.shape[0] for d in demands)
    # The demand behind each ratio (motor_fit.scaled, here as arrays over the groups).
    col = ratio[:, None]
    hull_speed = _padded([d.hull_speed for d in demands], (n_bins,))[e_of] * col
    hull_t = _padded([d.hull_torque for d in demands], (n_bins, n_v))[e_of] / col[:, :, None]
    hull_a = _padded([d.hull_alpha for d in demands], (n_bins, n_v))[e_of] * col[:, :, None]
    all_t = _padded([d.all_torque for d in demands], (n_all,))[e_of] / col
    all_a = _padded([d.all_alpha for d in demands], (n_all,))[e_of] * col
    # Cycle sums once per efficiency, then behind each ratio i (T / i, alpha x i, motor_fit.scaled):
    # S_TT / i^2, S_Ta, S_aa i^2; no (groups x samples) arrays. Speeds once per distinct ratio, with
    # fit_motors' own operations on the scaled demand, so a speed exactly at a motor's limit is judged
    # the same way (max and mean of |omega i|).
    w = duty.weights
    e_sums = np.array([[np.sum(w * d.torque**2), np.sum(w * d.torque * d.alpha), np.sum(w * d.alpha**2)]
                       for d in demands]).reshape(len(demands), 3)
    sums = e_sums[e_of] * np.stack([1.0 / ratio**2, np.ones_like(ratio), ratio**2], axis=1)
    g_speed = np.empty((len(ratio), 2))
    for r in _distinct(ratio).tolist():
        speed_r = np.abs(w0 * r)
        g_speed[ratio == r] = (np.max(speed_r) if speed_r.size else 0.0, np.sum(w * speed_r) / duty.period)
    g_j_load = duty.load_inertia / ratio**2
    # Envelopes: continuous at each group's mean speed (every motor), intermittent at every bin for
    # the motors that reach the top bin (a slower motor is not judged on torque). With curves, the
    # intermittent one at the top bin too, for the approximate flag as fit_motors sets it.
    n_m, n_g = len(motors), len(ratio)
    rated, peak, w_n, w_max, stall = (motors.rated_torque, motors.peak_torque, motors.rated_speed, motors.max_speed,
                                      motors.stall_torque)
    curves = tuple(motors.curves) if any(c is not None for c in motors.curves) else None
    if curves is None:
        cont_mean = continuous_torque(rated, w_n, w_max, g_speed[:, 1], stall).torque
        approx_motor = ~motors.has_curve
    else:
        cont_env, peak_env = motor_envelopes(rated, peak, w_n, w_max, np.concatenate([hull_speed[:, -1],
                                                                                      g_speed[:, 1]]), stall, curves)
        cont_mean = cont_env.torque[:, n_g:]
        approx_motor = np.asarray(peak_env.approximate, dtype=bool) | np.asarray(cont_env.approximate, dtype=bool)
    cont_mean = np.ascontiguousarray(cont_mean)
    reaches = ~(w_max[None, :] < hull_speed[:, -1:])  # (G, M); an unknown max speed is judged at every bin
    g_of, m_of = np.nonzero(reaches)
    full_row = np.full((n_g, n_m), -1, dtype=np.int64)
    full_row[g_of, m_of] = np.arange(len(g_of))
    env_full = np.zeros((1, n_bins))
    if len(g_of) and curves is None:
        env_full = intermittent_torque(peak[m_of], rated[m_of], w_n[m_of], w_max[m_of], hull_speed[g_of],
                                       stall[m_of]).torque
    elif len(g_of) and curves is not None:
        env_full = motor_envelopes(rated[m_of], peak[m_of], w_n[m_of], w_max[m_of], hull_speed[g_of], stall[m_of],
                                   [curves[m] for m in m_of])[1].torque
    # Gearbox rows as the checks read them: NaN where a rating or dimension is unknown.
    if gb is not None and len(gb):
        gb_j = np.nan_to_num(gb.inertia_input, nan=0.0)
        gb_cols = [gb.max_input_speed, gb.rated_input_speed, gb.rated_output_torque, gb.max_output_torque,
                   gb.emergency_stop_torque] + [column(gb, c) for c in ("input_bore_max", "input_bore_min",
                                                                          "input_flange", "input_pilot")]
        gb_adapters = adapter_arrays(gb.input_adapters).reshape(len(gb), -1)
        gb_loads = [gb.max_radial_load, gb.max_axial_load]
    else:
        gb_j = np.zeros(1)
        gb_cols = [np.zeros(1)] * 9
        gb_adapters = np.full((1, 3 * MAX_ADAPTERS), np.nan)
        gb_loads = [np.zeros(1)] * 2
    out_peak = float(np.max(np.abs(duty.torque))) if duty.torque.size else 0.0
    shock = shock_factor(duty.period, margins.gearbox_shock_factor)
    need = holding_need(axis, duty)
    hold = need.torque * margins.brake if need.needed else math.nan
    load_r, load_a = output_loads(axis, duty) if gb is not None and len(gb) else (0.0, 0.0)
    par = np.array([duty.period, margins.torque, margins.rms_torque or margins.torque, margins.speed, limit,
                    out_cubic, run_t, out_peak, shock, hold, load_r, load_a])
    f64 = np.ascontiguousarray
    model = (f64(motors.rotor_inertia, dtype=float), f64(peak, dtype=float), f64(w_max, dtype=float),
             *(f64(column(motors, c), dtype=float) for c in ("shaft_diameter", "flange", "pilot_diameter",
                                                              "bolt_circle", "brake_holding_torque")),
             cont_mean, full_row, f64(env_full, dtype=float), ratio, eff_g, hull_speed, hull_t, hull_a, all_t,
             all_a, sums, g_speed, g_j_load, f64(gb_j, dtype=float), *(f64(c, dtype=float) for c in gb_cols),
             f64(gb_adapters, dtype=float), *(f64(c, dtype=float) for c in gb_loads), par)
    n = n_m * len(rows)
    motor_idx, slot = np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int32)
    worst, failed, unknown = np.empty(n), np.empty(n, dtype=np.uint16), np.empty(n, dtype=np.uint16)
    check(model, row_start, rows, np.empty((3, 0), dtype=np.int64), motor_idx, slot, worst, failed, unknown,
          np.empty((0, 0)))
    slot_group = np.repeat(np.arange(n_g), np.diff(row_start))
    return Candidates(motor=motor_idx, slot=slot, worst_margin=worst, failed=failed, unknown=unknown, slot_row=rows,
                      slot_group=slot_group, group_ratio=ratio, approx_motor=np.asarray(approx_motor, dtype=bool),
                      model=model, strict=strict)


def size_key(motors: MotorTable) -> Array:
    """Motor size for 'smallest': rated power, else rated torque x rated speed [W]."""
    p = np.asarray(motors.rated_power, dtype=float)
    return np.where(np.isnan(p), motors.rated_torque * motors.rated_speed, p)


def objective_scores(c: Candidates, ks: NDArray[np.intp], motors: MotorTable, gb: GearboxTable | None, objective: str,
               duty: DutyCycle) -> Array:
    """Score to minimise for the candidates ``ks``."""
    if objective in ("rms_utilisation", "inertia_match"):
        d = c.details(ks)
        if objective == "rms_utilisation":
            return d.required["rms_torque"] / np.maximum(d.available["rms_torque"], 1e-300)
        return np.abs(np.log(np.maximum(d.inertia_ratio, 1e-12)))
    if objective == "energy":
        return _energy(c, ks, motors, gb, duty)
    gb_size = np.zeros(len(ks))
    if gb is not None:
        rows = c.gearbox(ks)
        has = rows >= 0
        gb_size[has] = np.nan_to_num(gb.rated_output_torque[rows[has]], nan=0.0)
    return size_key(motors)[c.motor[ks]] * 1e6 + gb_size


def _energy(c: Candidates, ks: NDArray[np.intp], motors: MotorTable, gb: GearboxTable | None,
            duty: DutyCycle) -> Array:
    """Motoring energy per cycle [J]: integral of max(T omega, 0) at the motor, for the first 5000 of ``ks``."""
    out = np.full(len(ks), math.inf)
    ok = np.arange(min(len(ks), 5000))
    ratios, rows, motor = c.ratio(ks), c.gearbox(ks), c.motor[ks]
    for ratio in _distinct(ratios[ok]):
        sel = ok[ratios[ok] == ratio]
        effs = np.ones(len(sel)) if gb is None else np.where(rows[sel] >= 0,
                                                             np.nan_to_num(gb.efficiency[rows[sel]], nan=1.0), 1.0)
        for eff in _distinct(effs):
            s2 = sel[effs == eff]
            stage = Stage("g", "gearbox", ratio=float(ratio), efficiency=float(eff), back_efficiency=float(eff))
            cycle = duty.behind(stage, "four_quadrant")
            j = motors.rotor_inertia[motor[s2]]
            if gb is not None:
                j = j + np.where(rows[s2] >= 0, np.nan_to_num(gb.inertia_input[rows[s2]]), 0.0)
            p = cycle.motor_torque(j) * cycle.omega[None, :]
            out[s2] = np.sum(cycle.weights[None, :] * np.maximum(p, 0.0), axis=1)
    return out


def closest_failing(c: Candidates, n: int, skip_motors: NDArray[np.bool_] | None = None) -> NDArray[np.intp]:
    """The ``n`` failing candidates with the largest worst margins, best first: ties in index order, NaN
    margins last (as a stable sort of every failing candidate, without sorting them all). ``skip_motors``
    (one flag per motor): leave out every candidate of the motors flagged (those with a passing configuration,
    which are never listed as rejected)."""
    from drivetrain.sizing.kernel import closest_failing as kernel_closest_failing

    rejected = c.rejected
    if skip_motors is not None:
        rejected = rejected & ~skip_motors[c.motor]
    return np.asarray(kernel_closest_failing(np.asarray(c.worst_margin, dtype=float), rejected, n), dtype=np.intp)


def pareto_front(size: Array, margin: Array, ratio: Array) -> NDArray[np.intp]:
    """Indices not dominated on (smaller size, larger margin, smaller inertia ratio)."""
    n = len(size)
    keep = np.ones(n, dtype=bool)
    for start in range(0, n, 256):  # blocks of rows keep the comparison matrices small
        k = slice(start, min(start + 256, n))
        s, m, r = size[k, None], margin[k, None], ratio[k, None]
        dom = (size[None, :] <= s) & (margin[None, :] >= m) & (ratio[None, :] <= r)
        strict = (size[None, :] < s) | (margin[None, :] > m) | (ratio[None, :] < r)
        keep[k] = ~np.any(dom & strict, axis=1)
    return np.flatnonzero(keep)


def _distinct(values: NDArray[Any]) -> NDArray[Any]:
    """``np.unique(values)``: its sorted distinct values, by its sorting path (the one that also gives the
    indices), which skips the masked-array check of the plain call: that imports numpy.ma (10 ms at start-up)."""
    return np.unique(values, return_index=True)[0]


def best_per_motor(c: Candidates, ranked: NDArray[np.intp]) -> NDArray[np.intp]:
    """The first candidate of each motor in ``ranked`` (its best configuration), in ranked order."""
    _, first = np.unique(c.motor[ranked], return_index=True)
    return ranked[np.sort(first)]


def catalog_tables(axis: Axis, spec: SelectSpec, brake: bool = False) -> tuple[MotorTable, GearboxTable | None, bool]:
    """The catalog motors and gearboxes a selection searches, and whether direct drive is a candidate.
    ``brake``: the axis needs a holding brake, so every motor is its brake variant (``braked_motors``)."""
    from drivetrain import catalog

    kind = None if spec.kind == "any" else spec.kind
    try:
        motors = catalog.motors(vendor=spec.vendor, kind=kind, voltage=spec.voltage, flange=spec.flange)
    except InputError as exc:
        raise exc.at("motor.select") from None
    if len(motors) == 0:
        raise InputError("motor.select", "no motor matches these filters: relax voltage or flange "
                         f"(voltage={spec.voltage}, flange={spec.flange}, vendor={spec.vendor})", has_value=False)
    if brake:
        motors = braked_motors(motors)
    gb = None
    own_gearbox = any(st.kind == "gearbox" for st in axis.transmission)
    if spec.gearbox == "only" or (spec.gearbox == "auto" and not own_gearbox):
        gb_kind = "small_gearhead" if spec.kind == "small_dc" else "servo_gearbox"
        try:
            gb = catalog.gearboxes(series=spec.gearbox_series, kind=gb_kind)
        except InputError as exc:
            raise exc.at("motor.select.gearbox_series") from None
    return motors, gb, spec.gearbox != "only" or gb is None


def ranked(c: Candidates, motors: MotorTable, gb: GearboxTable | None, objective: str,
           duty: DutyCycle) -> NDArray[np.intp]:
    """The passing candidates, best first: by the objective (ties in candidate order), a pair not
    known to assemble (a dimension missing), or whose brake's holding torque the catalog lacks, after
    every one known to (``candidates.KNOWN_FIRST``; an unknown fit after an unknown brake)."""
    passing = np.flatnonzero(c.ok)
    passing = passing[np.argsort(objective_scores(c, passing, motors, gb, objective, duty), kind="stable")]
    gaps = c.unknown[passing]
    # a pair not known to assemble last, then, before it, one whose brake is not known
    key = ((gaps & FIT_BIT) != 0).astype(np.int8) * 2 + ((gaps & BRAKE_BIT) != 0)
    return passing[np.argsort(key, kind="stable")]


def select(axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins,
           all_pairs: bool = False) -> Selection:
    """Evaluate the catalog against the duty cycle; rank, explain and summarise.

    The ranked list holds the best configuration of each motor (its best gearbox), so the top
    ``spec.top`` are that many different motors; ``all_pairs`` lists every passing pair instead.
    """
    motors, gb, allow_direct = catalog_tables(axis, spec, holding_need(axis, duty).needed)
    c = evaluate(axis, duty, motors, gb, margins, allow_direct=allow_direct, max_inertia_ratio=spec.max_inertia_ratio,
                 strict=spec.unknown == "fail")
    passing = ranked(c, motors, gb, spec.objective, duty)
    listed = passing if all_pairs else best_per_motor(c, passing)
    shown_ok = listed if all_pairs else listed[: spec.top]
    n_fail = max(spec.top - min(len(shown_ok), spec.top), 3)
    # a motor with any passing configuration is a passing motor: none of its configurations is listed as rejected
    passes = np.zeros(len(motors), dtype=bool)
    passes[c.motor[passing]] = True
    failing = closest_failing(c, n_fail * 8, passes)
    failing = failing if all_pairs else best_per_motor(c, failing)

    shown_ks = [int(k) for k in shown_ok]
    shown_ks += [int(k) for k in failing[: max(spec.top - len(shown_ks), 3)]]
    # the details of every listed candidate and the selected one in one kernel call (not one call each)
    asked = [*shown_ks, int(passing[0])] if len(passing) else shown_ks
    batch = c.details(asked) if asked else None
    at = {k: j for j, k in enumerate(asked)}

    def row(k: int, rank: int | None) -> Candidate:
        return candidate_answer(c, k, motors, gb, rank, None if batch is None else batch.column(at[k]))

    shown = [row(k, r + 1 if r < len(shown_ok) else None) for r, k in enumerate(shown_ks)]
    summary = SelectionSummary(
        objective=spec.objective, evaluated=len(c.motor), motors=len(motors),
        gearbox_rows=0 if gb is None else len(gb), passing=len(passing),
        passing_motors=len(_distinct(c.motor[passing])),
        listing="all_pairs" if all_pairs else "best_per_motor",
        unknown_policy=spec.unknown, failures_by_check=c.failures(), unknown_by_check=c.unknowns(),
        cycles_per_hour=3600.0 / duty.period,
    )
    best: int | None = None
    if len(passing):
        best = int(passing[0])
        summary.selected = row(best, 1)
        summary.next_smaller = next_smaller(c, motors, gb, best)
        summary.optimal_ratio = optimal_ratio(axis, duty, motors, int(c.motor[best]), gb)
        top = passing[:2000]
        front = pareto_front(size_key(motors)[c.motor[top]], c.worst_margin[top], c.details(top).inertia_ratio)
        summary.pareto_front = [_label(c, int(top[k]), motors, gb) for k in front[:50]]
        flagged = int(np.count_nonzero(c.unknown[passing]))
        if flagged:
            summary.unverified = (f"{flagged} of {len(passing)} passing configurations have checks the catalog "
                                  "cannot judge (status unknown): confirm them with the vendor")
    else:
        summary.advice = advice(c, margins, spec, motors, gb)
    ranking = Ranking(candidates=c, ranked=passing, motors=motors, gearboxes=gb, best=best, shown=shown_ks)
    return Selection(listed=shown, summary=summary, ranking=ranking)


def _label(c: Candidates, k: int, motors: MotorTable, gb: GearboxTable | None) -> str:
    g = int(c.gearbox(k))
    return str(motors.ids[c.motor[k]]) + ("" if g < 0 or gb is None else f" + {gb.ids[g]}")


_MAX_SPEED_BIT = list(CHECK_UNITS).index("max_speed")


def next_smaller(c: Candidates, motors: MotorTable, gb: GearboxTable | None, best: int) -> Candidate | None:
    """The next smaller motor than the selected one, in its best configuration, and why it fails."""
    size = size_key(motors)
    smaller = np.flatnonzero(size < size[c.motor[best]])  # every motor has candidates
    if not len(smaller):
        return None
    # a motor that cannot reach the cycle's speed in any configuration (e.g. a low-speed direct-drive motor) says
    # nothing about how tight the selection is: the next smaller motor is one that can, where there is one
    fast = np.zeros(len(size), dtype=bool)
    fast[c.motor[(c.failed & (1 << _MAX_SPEED_BIT)) == 0]] = True
    if fast[smaller].any():
        smaller = smaller[fast[smaller]]
    k = closest(c, c.of_motors(smaller[size[smaller] == np.max(size[smaller])]))
    out = candidate_answer(c, k, motors, gb, None)
    if out.ok:  # it passes, and ranks after the selected one: a fit or brake the catalog cannot judge
        gaps = [n for n in ("motor_brake", "mechanical_fit") if n in out.unknown]
        why = f"ranked after the selected motor: {' and '.join(gaps) or 'its checks'} cannot be judged"
        out.failed, out.failures = why, [why]
    return out


def candidate_cycle(axis: Axis, duty: DutyCycle, ranking: Ranking,
                    k: int | None = None) -> tuple[DutyCycle, float]:
    """A candidate's own cycle (default: the selected one): the axis's cycle behind the candidate's
    gearbox (DutyCycle.behind, as the checks put it there), and the motor's rotor inertia [kg m^2].

    The motor torque over the cycle is ``cycle.motor_torque(rotor_inertia)``.
    """
    c, motors, gb = ranking.candidates, ranking.motors, ranking.gearboxes
    if k is None:
        if ranking.best is None:
            raise ValueError("the selection has no selected candidate")
        k = ranking.best
    row = int(c.gearbox(k))
    cycle = duty
    if row >= 0 and gb is not None:
        eff = float(np.nan_to_num(gb.efficiency[row], nan=1.0))
        stage = Stage("gearbox", "gearbox", ratio=float(gb.ratio[row]),
                      inertia_in=float(np.nan_to_num(gb.inertia_input[row], nan=0.0)), efficiency=eff,
                      back_efficiency=eff)
        cycle = duty.behind(stage, axis.efficiency_model)
    return cycle, float(motors.rotor_inertia[c.motor[k]])


def optimal_ratio(axis: Axis, duty: DutyCycle, motors: MotorTable, m: int,
                  gb: GearboxTable | None) -> OptimalRatio:
    """Best ratio for one motor: sqrt(J_L / J_M) for pure inertia, and the ratio minimising RMS torque.

    Behind an ideal gearbox of ratio i the motor torque is T / i + J_M alpha i (T, alpha the load
    torque and acceleration at the gearbox output), so the mean square torque is
    (S_TT / i^2 + 2 J_M S_Ta + J_M^2 S_aa i^2) / t_cycle with S_xy the cycle sums of x y dt. It is
    convex in i^2 and least at i^4 = S_TT / (J_M^2 S_aa) (the inertia match sqrt(J_L / J_M) when T
    is the load's inertial torque alone), clamped to [0.01, the ratio where the motor reaches its
    max speed, at most 1000]. Source: lecture, Torque Effective Value (the RMS torque) and System
    Inertia Matching (IMR 1:1 ideal); the minimum is found by setting d(T_rms^2)/d(i^2) = 0.
    """
    j_m = float(motors.rotor_inertia[m])
    w = duty.weights
    s_tt = float(np.sum(w * duty.torque**2))
    s_ta = float(np.sum(w * duty.torque * duty.alpha))
    s_aa = float(np.sum(w * duty.alpha**2))
    top = float(motors.max_speed[m]) / max(float(np.max(np.abs(duty.omega))), 1e-12)
    lo, hi = 0.01, (max(min(top, 1000.0), 1.0) if math.isfinite(top) else 1000.0)  # no max speed given: 1000
    # no acceleration: the longest ratio; no torque: the shortest
    best = (s_tt / (j_m**2 * s_aa)) ** 0.25 if s_aa > 0.0 and s_tt > 0.0 else (hi if s_tt > 0.0 else lo)
    best = min(max(best, lo), hi)
    mean_square = (s_tt / best**2 + 2.0 * j_m * s_ta + j_m**2 * s_aa * best**2) / duty.period
    nearest = None
    if gb is not None and len(gb):
        ratios = _distinct(gb.ratio)
        nearest = float(ratios[np.argmin(np.abs(np.log(ratios / best)))])
    return OptimalRatio(motor=str(motors.ids[m]), inertia_match_ratio=math.sqrt(duty.load_inertia / j_m),
                        min_rms_ratio=best, min_rms_torque_Nm=math.sqrt(max(mean_square, 0.0)),
                        max_ratio_for_speed=top, nearest_catalog_ratio=nearest)


__all__ = ["CHECK_UNITS", "MOTOR_CHECKS", "Candidates", "Details", "Ranking", "Selection", "best_per_motor",
           "candidate_cycle", "catalog_tables", "closest_failing", "evaluate", "explain", "gearbox_options",
           "lossy_torque", "next_smaller", "objective_scores", "optimal_ratio", "ranked", "select", "size_key",
           "to_rpm"]
