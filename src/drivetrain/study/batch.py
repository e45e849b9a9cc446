"""The batched sizing path of a study: many variants of one axis against one loaded catalog.

Every use of the sizing internals by the study package is in this module (the engine's other
modules use the public API and ``SizingResult.to_dict``), so a change of the internals is met here.
Size: just over 600 lines, kept whole for that reason: one module to adapt when the engine changes.

What it saves per variant against ``drivetrain.size``, without changing any answer:

* the catalog tables, their gearbox groups and the motor order by size are built once per
  engine (once per worker process), not once per variant;
* the convex hull of each speed bin (``motor_fit.demand``) runs compiled (the same monotone
  chain, the same collinearity rule, so the same vertices);
* for the objective ``smallest`` the motors are tried in chunks from the smallest up, and the
  search stops at the first chunk with a passing candidate once no larger motor can beat it
  (objective = size x 1e6 + gearbox size, so a motor whose size key exceeds the best objective /
  1e6 cannot win); ties are broken by the catalog order of the full selection; motors that fail
  the max-speed or the inertia-ratio check behind every ratio (no gearbox row can rescue them) are
  not tried; when nothing passes, the whole catalog is evaluated, as ``select`` does;
* profiles equal (same profile entries, same kind of motion, same points per phase) share
  their sampled kinematics (``Cycle`` and ``Samples`` are functions of those alone);
* no Pareto front, next-smaller motor, optimal ratio or candidate list unless asked.

``tests/test_study_batch.py`` asserts, on a sample of variants, that the selected motor and
gearbox and every margin equal those of ``drivetrain.size``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

from drivetrain.axis.model import Axis
from drivetrain.duty.cycle import cubic_mean, duty_from_samples, load_metrics
from drivetrain.errors import InputError
from drivetrain.physics.stage import Stage
from drivetrain.sizing.envelope import continuous_torque, intermittent_torque, motor_envelopes
from drivetrain.sizing.motor_fit import _COLLINEAR, Demand
from drivetrain.sizing.selection import (
    Candidates,
    _gearbox_options,
    _objective,
    _padded,
    _size_key,
    candidate_dict,
)

if TYPE_CHECKING:
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.motion.profiles import Cycle, Samples

Array = NDArray[np.float64]

CHUNK = 12
"""Motors per chunk of the smallest-first search (extended to include motors of equal size)."""
OWN_CHECKS = ("slip_check", "guide", "brake_check")


# ---------------------------------------------------------------------------------------------
# compiled convex hull (motor_fit._chain, the same arithmetic)


@njit(cache=True, nogil=True)
def _half(x: Array, y: Array, idx: NDArray[np.int64], out: NDArray[np.int64]) -> int:  # pragma: no cover
    """One half of Andrew's monotone chain over the points ``idx`` (in order); writes indices to ``out``."""
    n = 0
    for p in idx:
        while n >= 2:
            x0, y0, x1, y1 = x[out[n - 2]], y[out[n - 2]], x[out[n - 1]], y[out[n - 1]]
            turn_a, turn_b = (x1 - x0) * (y[p] - y0), (y1 - y0) * (x[p] - x0)
            if turn_a - turn_b > _COLLINEAR * (abs(turn_a) + abs(turn_b)):
                break
            n -= 1
        out[n] = p
        n += 1
    return n


@njit(cache=True, nogil=True)
def _hulls(x: Array, y: Array, starts: NDArray[np.int64], stops: NDArray[np.int64]) -> tuple[
        NDArray[np.int64], NDArray[np.int64]]:  # pragma: no cover
    """Hull vertices (as point indices) of each run ``[starts[b], stops[b])`` of points sorted by (x, y).

    Returns the vertex indices of all runs one after the other and the count of each run,
    in the order of ``motor_fit._chain``: lower chain without its last point, then upper chain
    without its last point; fewer than 3 points are returned as they are; an empty result is
    the first point.
    """
    nb = starts.shape[0]
    total = 0
    for b in range(nb):
        total += 2 * (stops[b] - starts[b]) + 2
    verts = np.empty(total, dtype=np.int64)
    count = np.empty(nb, dtype=np.int64)
    buf = np.empty(2 * (np.max(stops - starts) if nb else 0) + 2, dtype=np.int64)
    k = 0
    for b in range(nb):
        s, e = starts[b], stops[b]
        n = e - s
        if n < 3:
            for q in range(n):
                verts[k + q] = s + q
            count[b] = n
            k += n
            continue
        fwd = np.arange(s, e)
        n_lo = _half(x, y, fwd, buf)
        c = 0
        for q in range(n_lo - 1):
            verts[k + c] = buf[q]
            c += 1
        n_up = _half(x, y, fwd[::-1], buf)
        for q in range(n_up - 1):
            verts[k + c] = buf[q]
            c += 1
        if c == 0:
            verts[k] = s
            c = 1
        count[b] = c
        k += c
    return verts[:k], count


def fast_demand(omega: Array, alpha: Array, torque: Array, weights: Array, period: float, load_inertia: float,
                bins: int = 64) -> Demand:
    """``motor_fit.demand`` with the hulls compiled: the same bins, points, vertices and padding."""
    w = np.abs(omega)
    top = float(w.max()) if w.size else 0.0
    edges = np.linspace(0.0, top if top > 0 else 1.0, bins + 1)
    idx = np.clip(np.searchsorted(edges, w, side="left") - 1, 0, bins - 1)
    order = np.lexsort((torque, alpha, idx))
    b_s, a_s, t_s = idx[order], alpha[order], torque[order]
    keep = np.ones(len(b_s), dtype=bool)
    keep[1:] = (np.diff(b_s) != 0) | (np.diff(a_s) != 0) | (np.diff(t_s) != 0)
    b_s, a_s, t_s = b_s[keep], a_s[keep], t_s[keep]
    bins_used, starts = np.unique(b_s, return_index=True)
    stops = np.append(starts[1:], len(b_s))
    speeds = edges[bins_used + 1]
    verts, count = _hulls(a_s, t_s, starts.astype(np.int64), stops.astype(np.int64))
    width = int(count.max())
    first = np.concatenate([[0], np.cumsum(count)[:-1]])
    pos = np.minimum(np.arange(width)[None, :], count[:, None] - 1)  # padding repeats the last vertex
    sel = verts[first[:, None] + pos]
    ha, ht = a_s[sel], t_s[sel]
    # hull of every vertex: the distinct vertices sorted by (alpha, T)
    va, vt = a_s[verts], t_s[verts]
    o = np.lexsort((vt, va))
    va, vt = va[o], vt[o]
    k = np.ones(len(va), dtype=bool)
    k[1:] = (np.diff(va) != 0) | (np.diff(vt) != 0)
    va, vt = va[k], vt[k]
    all_v, _ = _hulls(va, vt, np.zeros(1, dtype=np.int64), np.array([len(va)], dtype=np.int64))
    return Demand(omega=omega, alpha=alpha, torque=torque, weights=weights, period=period,
                  load_inertia=load_inertia, hull_speed=np.asarray(speeds, dtype=float), hull_torque=ht, hull_alpha=ha,
                  all_torque=vt[all_v], all_alpha=va[all_v])


def fast_demands(omega: Array, alpha: Array, torques: list[Array], weights: Array, period: float,
                 load_inertia: float, bins: int = 64) -> list[Demand]:
    """``fast_demand`` of several torque arrays over the same motion (one per gearbox efficiency),
    with one sort and one compiled pass for all of them (numpy's per-call cost dominates at this size).

    Each result equals ``motor_fit.demand`` of that torque: the points are sorted by (torque
    array, bin, alpha, T), so each array's points come in demand's own order.
    """
    n_e, n = len(torques), len(omega)
    w = np.abs(omega)
    top = float(w.max()) if w.size else 0.0
    edges = np.linspace(0.0, top if top > 0 else 1.0, bins + 1)
    idx = np.clip(np.searchsorted(edges, w, side="left") - 1, 0, bins - 1)
    t_all = np.concatenate(torques)
    a_all = np.tile(alpha, n_e)
    b_all = np.tile(idx, n_e)
    e_all = np.repeat(np.arange(n_e), n)
    order = np.lexsort((t_all, a_all, b_all, e_all))
    e_s, b_s, a_s, t_s = e_all[order], b_all[order], a_all[order], t_all[order]
    keep = np.ones(len(b_s), dtype=bool)
    keep[1:] = (np.diff(e_s) != 0) | (np.diff(b_s) != 0) | (np.diff(a_s) != 0) | (np.diff(t_s) != 0)
    e_s, b_s, a_s, t_s = e_s[keep], b_s[keep], a_s[keep], t_s[keep]
    run_key = e_s * bins + b_s
    new_run = np.ones(len(run_key), dtype=bool)
    new_run[1:] = np.diff(run_key) != 0
    starts = np.flatnonzero(new_run)
    stops = np.append(starts[1:], len(run_key))
    verts, count = _hulls(a_s, t_s, starts.astype(np.int64), stops.astype(np.int64))
    first = np.concatenate([[0], np.cumsum(count)[:-1]])
    run_e = e_s[starts]
    # hull of every vertex, per torque array: its distinct vertices sorted by (alpha, T)
    ve, va, vt = e_s[verts], a_s[verts], t_s[verts]
    o = np.lexsort((vt, va, ve))
    ve, va, vt = ve[o], va[o], vt[o]
    k = np.ones(len(va), dtype=bool)
    k[1:] = (np.diff(ve) != 0) | (np.diff(va) != 0) | (np.diff(vt) != 0)
    ve, va, vt = ve[k], va[k], vt[k]
    v_start = np.searchsorted(ve, np.arange(n_e), side="left")
    v_stop = np.searchsorted(ve, np.arange(n_e), side="right")
    all_v, all_count = _hulls(va, vt, v_start.astype(np.int64), v_stop.astype(np.int64))
    all_first = np.concatenate([[0], np.cumsum(all_count)[:-1]])
    out = []
    for e in range(n_e):
        runs = np.flatnonzero(run_e == e)
        c_e = count[runs]
        width = int(c_e.max())
        pos = np.minimum(np.arange(width)[None, :], c_e[:, None] - 1)  # padding repeats the last vertex
        sel = verts[first[runs][:, None] + pos]
        av = all_v[all_first[e]:all_first[e] + all_count[e]]
        out.append(Demand(omega=omega, alpha=alpha, torque=torques[e], weights=weights, period=period,
                          load_inertia=load_inertia, hull_speed=np.asarray(edges[b_s[starts[runs]] + 1], dtype=float),
                          hull_torque=t_s[sel], hull_alpha=a_s[sel], all_torque=vt[av], all_alpha=va[av]))
    return out


# ---------------------------------------------------------------------------------------------
# the catalog, loaded once


@dataclass
class Tables:
    """One selection's catalog tables and what the engine derives from them once."""

    motors: MotorTable
    gb: GearboxTable | None
    allow_direct: bool
    max_inertia_ratio: float | None
    ratio: Array
    eff_g: Array
    rows: NDArray[np.int64]
    row_start: NDArray[np.int64]
    size_key: Array
    order: NDArray[np.intp]  # motors by size key, ascending (stable; NaN last)
    gb_arrays: tuple[Array, Array, Array, Array]
    gb_size: Array  # rated output torque per gearbox row, 0 where unknown [N m]
    curves: bool  # the full table has datasheet curves: every chunk takes motor_envelopes' path
    _subs: dict[bytes, MotorTable] = field(default_factory=dict)

    def sub_table(self, members: NDArray[np.intp]) -> MotorTable:
        """The motors ``members`` (ascending) as a table, kept for the next variant that needs them."""
        key = members.tobytes()
        hit = self._subs.get(key)
        if hit is None:
            if len(self._subs) > 2048:
                self._subs.clear()
            hit = self._subs[key] = self.motors.take(members)
        return hit


def load_tables(spec: Any, own_gearbox: bool) -> Tables:
    """The tables of a ``motor.select`` spec, as ``selection.select`` reads them."""
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
    if spec.gearbox == "only" or (spec.gearbox == "auto" and not own_gearbox):
        gb_kind = "small_gearhead" if spec.kind == "small_dc" else "servo_gearbox"
        try:
            gb = catalog.gearboxes(series=spec.gearbox_series, kind=gb_kind)
        except InputError as exc:
            raise exc.at("motor.select.gearbox_series") from None
    allow_direct = spec.gearbox != "only" or gb is None
    ratio, eff_g, rows, row_start = _gearbox_options(gb, allow_direct)
    size_key = _size_key(motors)
    order = np.argsort(size_key, kind="stable")  # NaN sizes last
    if gb is not None and len(gb):
        gb_j = np.nan_to_num(gb.inertia_input, nan=0.0)
        gb_speed = np.where(np.isnan(gb.max_input_speed), math.inf, gb.max_input_speed)
        gb_speed = np.where(np.isinf(gb_speed), np.where(np.isnan(gb.rated_input_speed), math.inf,
                                                         gb.rated_input_speed), gb_speed)
        gb_rated = np.where(np.isnan(gb.rated_output_torque), math.inf, gb.rated_output_torque)
        estop = np.where(np.isnan(gb.emergency_stop_torque), math.inf, gb.emergency_stop_torque)
        gb_cap = np.where(np.isnan(gb.max_output_torque), estop, gb.max_output_torque)
        gb_size = np.nan_to_num(np.asarray(gb.rated_output_torque, dtype=float), nan=0.0)
    else:
        gb_j = gb_speed = gb_rated = gb_cap = np.zeros(1)
        gb_size = np.zeros(1)
    f64 = np.ascontiguousarray
    return Tables(motors=motors, gb=gb, allow_direct=allow_direct, max_inertia_ratio=spec.max_inertia_ratio,
                  ratio=ratio, eff_g=eff_g, rows=rows, row_start=row_start, size_key=size_key, order=order,
                  gb_arrays=(f64(gb_j, dtype=float), f64(gb_speed, dtype=float),
                                          f64(gb_rated, dtype=float), f64(gb_cap, dtype=float)),
                  gb_size=gb_size, curves=any(c is not None for c in motors.curves))


# ---------------------------------------------------------------------------------------------
# one variant


@dataclass
class _Groups:
    """The demand behind every gearbox group of one variant (selection.evaluate's group arrays)."""

    hull_speed: Array
    hull_t: Array
    hull_a: Array
    all_t: Array
    all_a: Array
    sums: Array
    g_speed: Array
    g_j_load: Array
    par: Array
    n_bins: int


def _groups(axis: Axis, duty: DutyCycle, tb: Tables, margins: Any) -> _Groups:
    """selection.evaluate up to the envelopes, with the compiled hull."""
    limit = margins.inertia_ratio if tb.max_inertia_ratio is None else min(tb.max_inertia_ratio,
                                                                           margins.inertia_ratio)
    t0, w0, a0 = duty.torque, duty.omega, duty.alpha
    out_cubic = cubic_mean(t0, w0, duty.weights)
    run_t = float(np.median(np.abs(duty.external))) if duty.external.size else 0.0
    ratio, eff_g = tb.ratio, tb.eff_g
    effs = list(dict.fromkeys(eff_g.tolist()))
    lossy = [duty.behind(Stage("gearbox", "gearbox", efficiency=eff, back_efficiency=eff), axis.efficiency_model).torque
             for eff in effs]
    demands = fast_demands(w0, a0, lossy, duty.weights, duty.period, duty.load_inertia)
    e_of = np.array([effs.index(e) for e in eff_g.tolist()])
    n_bins = max(d.hull_torque.shape[0] for d in demands)
    n_v = max(d.hull_torque.shape[1] for d in demands)
    n_all = max(d.all_torque.shape[0] for d in demands)
    col = ratio[:, None]
    hull_speed = _padded([d.hull_speed for d in demands], (n_bins,))[e_of] * col
    hull_t = _padded([d.hull_torque for d in demands], (n_bins, n_v))[e_of] / col[:, :, None]
    hull_a = _padded([d.hull_alpha for d in demands], (n_bins, n_v))[e_of] * col[:, :, None]
    all_t = _padded([d.all_torque for d in demands], (n_all,))[e_of] / col
    all_a = _padded([d.all_alpha for d in demands], (n_all,))[e_of] * col
    w_g = duty.weights[None, :]
    t_g = np.stack([d.torque for d in demands])[e_of] / col
    a_g = np.stack([d.alpha for d in demands])[e_of] * col
    speed_g = np.abs(w0[None, :] * col)
    sums = np.stack([np.sum(w_g * t_g**2, axis=1), np.sum(w_g * t_g * a_g, axis=1), np.sum(w_g * a_g**2, axis=1)],
                    axis=1)
    g_speed = np.stack([np.max(speed_g, axis=1), np.sum(w_g * speed_g, axis=1) / duty.period], axis=1)
    g_j_load = duty.load_inertia / ratio**2
    par = np.array([duty.period, margins.torque, margins.rms_torque or margins.torque, margins.speed, limit,
                    out_cubic, run_t])
    return _Groups(hull_speed, hull_t, hull_a, all_t, all_a, sums, g_speed, g_j_load, par, n_bins)


def _evaluate_chunk(gr: _Groups, tb: Tables, motors: MotorTable) -> Candidates:
    """selection.evaluate from the envelopes on, for the motors of ``motors`` (a sub-table)."""
    from drivetrain.sizing.kernel import check

    ratio, hull_speed, g_speed = tb.ratio, gr.hull_speed, gr.g_speed
    n_m, n_g = len(motors), len(ratio)
    rated, peak, w_n, w_max, stall = (motors.rated_torque, motors.peak_torque, motors.rated_speed, motors.max_speed,
                                      motors.stall_torque)
    curves = tuple(motors.curves) if tb.curves else None
    if curves is None:
        env_top = intermittent_torque(peak, rated, w_n, w_max, hull_speed[:, -1], stall).torque
        cont_mean = continuous_torque(rated, w_n, w_max, g_speed[:, 1], stall).torque
        approx_motor = ~motors.has_curve
    else:
        cont_env, peak_env = motor_envelopes(rated, peak, w_n, w_max, np.concatenate([hull_speed[:, -1],
                                                                                      g_speed[:, 1]]), stall, curves)
        env_top, cont_mean = peak_env.torque[:, :n_g], cont_env.torque[:, n_g:]
        approx_motor = np.asarray(peak_env.approximate, dtype=bool) | np.asarray(cont_env.approximate, dtype=bool)
    env_top, cont_mean = np.ascontiguousarray(env_top), np.ascontiguousarray(cont_mean)
    reaches = ~(w_max[None, :] < hull_speed[:, -1:])
    g_of, m_of = np.nonzero(reaches)
    full_row = np.full((n_g, n_m), -1, dtype=np.int64)
    full_row[g_of, m_of] = np.arange(len(g_of))
    env_full = np.zeros((1, gr.n_bins))
    if len(g_of) and curves is None:
        env_full = intermittent_torque(peak[m_of], rated[m_of], w_n[m_of], w_max[m_of], hull_speed[g_of],
                                       stall[m_of]).torque
    elif len(g_of) and curves is not None:
        env_full = motor_envelopes(rated[m_of], peak[m_of], w_n[m_of], w_max[m_of], hull_speed[g_of], stall[m_of],
                                   [curves[m] for m in m_of])[1].torque
    f64 = np.ascontiguousarray
    model = (f64(motors.rotor_inertia, dtype=float), f64(peak, dtype=float), f64(w_max, dtype=float), env_top,
             cont_mean, full_row, f64(env_full, dtype=float), ratio, tb.eff_g, hull_speed, gr.hull_t, gr.hull_a,
             gr.all_t, gr.all_a, gr.sums, g_speed, gr.g_j_load, *tb.gb_arrays, gr.par)
    n = n_m * len(tb.rows)
    motor_idx, slot = np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int32)
    worst, failed = np.empty(n), np.empty(n, dtype=np.uint8)
    check(model, tb.row_start, tb.rows, np.empty((3, 0), dtype=np.int64), motor_idx, slot, worst, failed,
          np.empty((0, 0)))
    slot_group = np.repeat(np.arange(n_g), np.diff(tb.row_start))
    return Candidates(motor=motor_idx, slot=slot, worst_margin=worst, failed=failed, slot_row=tb.rows,
                      slot_group=slot_group, group_ratio=ratio, approx_motor=np.asarray(approx_motor, dtype=bool),
                      model=model)


@dataclass
class Pick:
    """The selected candidate (or, when none passes, the closest failing one) of one variant."""

    candidate: dict[str, Any]
    passing: bool
    cycle_stage: Stage | None  # the candidate's gearbox as a stage (None: direct drive)
    rotor_inertia: float
    evaluated_all: bool
    failures_by_check: dict[str, int] | None


def _order_key(c: Candidates, k: int, members: NDArray[np.intp]) -> tuple[int, int, int]:
    """Position of candidate ``k`` of a chunk in the full selection's order: (group, motor, slot)."""
    return int(c.slot_group[c.slot[k]]), int(members[c.motor[k]]), int(c.slot[k])


def select_fast(axis: Axis, duty: DutyCycle, tb: Tables) -> Pick:
    """The candidate ``selection.select`` ranks first, by chunks of motors where the objective allows."""
    motor = axis.spec.motor
    assert motor is not None and motor.select is not None
    spec, margins = motor.select, motor.margins
    gr = _groups(axis, duty, tb, margins)
    if spec.objective != "smallest":
        # every candidate, ranked exactly as selection.select does
        c = _evaluate_chunk(gr, tb, tb.motors)
        passing = np.flatnonzero(c.ok)
        if len(passing):
            score = _objective(c, passing, tb.motors, tb.gb, spec.objective, duty)
            first = int(passing[np.argsort(score, kind="stable")[0]])
            return _pick(c, first, tb.motors, tb, True, True, c.failures())
        from drivetrain.sizing.selection import _closest_failing

        return _pick(c, int(_closest_failing(c, 1)[0]), tb.motors, tb, False, True, c.failures())
    # Motors that fail every candidate for a reason no gearbox row can change are left out: the
    # motor's max speed below the cycle's (x margin) behind every ratio (a gearbox's input-speed
    # limit only lowers the available speed), or the load inertia behind every ratio above the
    # limit x rotor inertia (a gearbox's input inertia only adds to the load side). Both with a
    # relative slack of 1e-9, so a motor at a limit to rounding is evaluated.
    feasible = _feasible_motors(gr, tb)
    order = tb.order[feasible[tb.order]]
    best: tuple[float, tuple[int, int, int], Candidates, int, MotorTable] | None = None
    start = 0
    while start < len(order):
        stop = min(start + CHUNK, len(order))
        while stop < len(order) and tb.size_key[order[stop]] == tb.size_key[order[stop - 1]]:
            stop += 1  # motors of equal size go in the same chunk
        members = np.sort(order[start:stop])
        sub = tb.sub_table(members)
        c = _evaluate_chunk(gr, tb, sub)
        ok = np.flatnonzero(c.failed == 0)
        if ok.size:
            rows = c.gearbox(ok)
            gb_size = np.where(rows >= 0, tb.gb_size[np.maximum(rows, 0)], 0.0) if tb.gb is not None else 0.0
            obj = tb.size_key[members[c.motor[ok]]] * 1e6 + gb_size
            obj = np.where(np.isnan(obj), math.inf, obj)
            j = int(np.argmin(obj))  # the first of equal scores: the lowest index, as the stable sort
            cand = (float(obj[j]), _order_key(c, int(ok[j]), members), c, int(ok[j]), sub)
            if best is None or (cand[0], cand[1]) < (best[0], best[1]):
                best = cand
        start = stop
        nxt = float(tb.size_key[order[stop]]) if stop < len(order) else math.inf
        if best is not None and not math.isnan(nxt) and best[0] < nxt * 1e6:
            return _pick(best[2], best[3], best[4], tb, True, False, None)
    if best is not None:
        return _pick(best[2], best[3], best[4], tb, True, False, None)
    # nothing passes: the closest candidate of the whole catalog, as selection.select reports it
    from drivetrain.sizing.selection import _closest_failing

    c = _evaluate_chunk(gr, tb, tb.motors)
    return _pick(c, int(_closest_failing(c, 1)[0]), tb.motors, tb, False, True, c.failures())


def _feasible_motors(gr: _Groups, tb: Tables) -> NDArray[np.bool_]:
    """Motors that pass the max-speed and inertia-ratio checks behind at least one ratio (necessary
    conditions of any passing candidate; see select_fast)."""
    m = tb.motors
    sm, limit = gr.par[3], gr.par[4]
    need_speed = gr.g_speed[:, 0] * sm  # (G,)
    speed_ok = ~(m.max_speed[None, :] < need_speed[:, None] * (1.0 - 1e-9))  # NaN max speed: kept
    inertia_ok = ~(gr.g_j_load[:, None] > limit * m.rotor_inertia[None, :] * (1.0 + 1e-9))
    return np.asarray(np.any(speed_ok & inertia_ok, axis=0), dtype=bool)


def _pick(c: Candidates, k: int, motors: MotorTable, tb: Tables, passing: bool, evaluated_all: bool,
          failures: dict[str, int] | None) -> Pick:
    cand = candidate_dict(c, k, motors, tb.gb, 1 if passing else None)
    row = int(c.gearbox(k))
    stage = None
    if row >= 0 and tb.gb is not None:
        eff = float(np.nan_to_num(tb.gb.efficiency[row], nan=1.0))
        stage = Stage("gearbox", "gearbox", ratio=float(tb.gb.ratio[row]),
                      inertia_in=float(np.nan_to_num(tb.gb.inertia_input[row], nan=0.0)), efficiency=eff,
                      back_efficiency=eff)
    return Pick(candidate=cand, passing=passing, cycle_stage=stage,
                rotor_inertia=float(motors.rotor_inertia[c.motor[k]]), evaluated_all=evaluated_all,
                failures_by_check=failures)


def motoring_energy(duty: DutyCycle, rotor_inertia: float) -> float:
    """Energy the motor delivers per cycle [J]: the integral of max(T omega, 0) dt, rotor included
    (``selection._energy``'s measure, regenerated energy not credited)."""
    p = duty.motor_torque(rotor_inertia) * duty.omega
    return float(np.sum(duty.weights * np.maximum(p, 0.0)))


# ---------------------------------------------------------------------------------------------
# the engine


class Engine:
    """Sizes many axes against the catalog loaded once; a worker process keeps one engine."""

    def __init__(self, points_per_phase: int = 64) -> None:
        self.points = points_per_phase
        self._tables: dict[str, Tables] = {}
        self._kinematics: dict[str, tuple[Cycle, Samples]] = {}

    def tables(self, axis: Axis) -> Tables:
        """The catalog tables of this axis's selection (loaded on first use, then kept)."""
        motor = axis.spec.motor
        assert motor is not None and motor.select is not None
        spec = motor.select
        own = any(st.kind == "gearbox" for st in axis.transmission)
        key = json.dumps([spec.model_dump(mode="json"), own], sort_keys=True, default=str)
        if key not in self._tables:
            self._tables[key] = load_tables(spec, own)
        return self._tables[key]

    def duty(self, axis: Axis) -> DutyCycle:
        """The duty cycle, the profile's kinematics shared between axes with equal profiles."""
        key = json.dumps([axis.spec.profile, axis.mechanism.motion, self.points], sort_keys=True, default=str)
        hit = self._kinematics.get(key)
        if hit is None:
            cycle = axis.cycle()
            hit = (cycle, cycle.sample(self.points))
            if len(self._kinematics) > 4096:
                self._kinematics.clear()
            self._kinematics[key] = hit
        return duty_from_samples(axis, hit[0], hit[1])

    def size(self, axis: Axis) -> dict[str, Any]:
        """A variant's result, keyed as ``SizingResult.to_dict`` where the key exists there.

        Top level: the load metrics (``rms_torque_Nm``, ``peak_torque_Nm``, ...), the axis's own
        checks, ``motor`` (a given motor's block) or ``selection`` with ``selected`` (or
        ``closest`` when nothing passes), plus ``ok`` and ``energy_per_cycle_J``.
        """
        from drivetrain.sizing.result import _brake_check, motor_result

        duty = self.duty(axis)
        metrics = load_metrics(duty)
        out: dict[str, Any] = {"axis": axis.name, "efficiency_model": axis.efficiency_model, **metrics}
        if axis.spec.guide is not None and axis.mechanism.motion == "linear":
            from drivetrain.physics.guides import guide_report

            out["guide"] = guide_report(axis, duty)
        if axis.mechanism.slip_limit is not None:
            from drivetrain.physics.guides import slip_check

            incline = getattr(axis.mechanism.load, "incline", 0.0)
            out["slip_check"] = slip_check(np.asarray(duty.samples.a), axis.mechanism.slip_limit, incline,
                                           axis.gravity)
        brake = _brake_check(axis, duty)
        if brake is not None:
            out["brake_check"] = brake
        own_ok = all(bool(out[k]["ok"]) for k in OWN_CHECKS if k in out)
        if axis.motor is not None:
            out["motor"] = motor_result(axis, duty, axis.motor)
            out["ok"] = own_ok and bool(out["motor"]["ok"])
            out["energy_per_cycle_J"] = motoring_energy(duty, axis.motor.inertia)
        elif axis.spec.motor is not None and axis.spec.motor.select is not None:
            tb = self.tables(axis)
            pick = select_fast(axis, duty, tb)
            sel: dict[str, Any] = {"objective": axis.spec.motor.select.objective}
            sel["selected" if pick.passing else "closest"] = pick.candidate
            if pick.failures_by_check is not None:
                sel["failures_by_check"] = pick.failures_by_check
            out["selection"] = sel
            out["ok"] = own_ok and pick.passing
            cycle = duty if pick.cycle_stage is None else duty.behind(pick.cycle_stage, axis.efficiency_model)
            # energy of the selected candidate; none when nothing passes (as full_result)
            out["energy_per_cycle_J"] = motoring_energy(cycle, pick.rotor_inertia) if pick.passing else math.nan
        else:
            out["ok"] = own_ok
            out["energy_per_cycle_J"] = motoring_energy(duty, 0.0)
        return out


def full_result(axis: Axis, points_per_phase: int = 64) -> dict[str, Any]:
    """``drivetrain.size(axis).to_dict()`` with ``ok`` and ``energy_per_cycle_J`` (the unbatched path,
    for results that record keys the batched path does not compute)."""
    from drivetrain.sizing.result import size
    from drivetrain.sizing.selection import candidate_cycle

    r = size(axis, points_per_phase)
    out = r.to_dict()
    out["ok"] = r.ok
    if axis.motor is not None:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, axis.motor.inertia)
    elif r.selection is not None and "_best" in r.selection:
        cycle, j = candidate_cycle(axis, r.duty, r.selection)
        out["energy_per_cycle_J"] = motoring_energy(cycle, j)
    elif r.selection is not None:
        out["energy_per_cycle_J"] = math.nan
    else:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, 0.0)
    return out


__all__ = ["Engine", "Pick", "Tables", "fast_demand", "fast_demands", "full_result", "load_tables", "motoring_energy",
           "select_fast"]
