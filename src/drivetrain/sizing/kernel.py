"""The candidate checks of the catalog selection, in numpy. Imported lazily by ``selection.evaluate``.

Every candidate (gearbox-ratio group x motor x gearbox row) gets all its checks from whole-array
operations over blocks of candidates (``BLOCK`` at a time, so the temporaries stay bounded): no
compiled code, so nothing to build at install and nothing to
compile on a first run. The physics is that of ``motor_fit.fit_motors``, ``checks.mechanical_fit``
and ``checks.gearbox_checks`` (their docstrings give the sources); ``tests/sizing/test_selection.py``
asserts that these arrays and those reference functions give the same required/available/margin
for every candidate of the shipped catalog, and ``tests/sizing/test_kernel.py`` that they equal, to the
bit, the per-candidate loop the checks were first written as (run by the interpreter).

Per candidate k (motor m, group g of ratio i and efficiency eta, gearbox row r or -1 direct):

* J = J_M + J_g (rotor plus the gearbox's input inertia) [kg m^2];
* peak: max over the convex-hull vertices v of the demand of |T_v + J alpha_v| [N m], per
  speed bin against the intermittent envelope there (worst bin); a motor slower than the
  cycle's top speed is not judged on torque (margin NaN: its max_speed check fails instead);
* RMS: sqrt((S_TT + 2 J S_Ta + J^2 S_aa) / t_cycle) against the continuous torque at the mean
  speed (lecture, Torque Effective Value);
* speed: max |omega| x margin against the motor's max speed;
* inertia ratio: (J_L / i^2 + J_g) / J_M against the limit;
* mechanical fit: the motor shaft into the gearbox's input bore range, flange and pilot equal
  to the input adapter's where the catalog gives them (``checks.mechanical_fit``);
* gearbox (``checks.gearbox_checks``): T2B against the cycle's peak output torque (x shock
  factor above 1000 cycles/h), T2N against the cubic-mean output torque, T2NOT against the
  torque that passes at the motor's peak, ((1 - k)(T_M - T_L/i) + T_L/i) i eta with
  k = J / (J + J_L/i^2) (lecture, Dynamic Loading and Gearbox Sizing), n1max against the peak
  input speed x speed margin, n1N against the mean input speed;
* motor brake (only where the axis needs a holding brake, ``motor_brake.holding_need``): the brake
  variant's holding torque against the static load torque at the axis's motor shaft / i x eta
  (the load drives back through the gearbox: ``physics.brake.held_torque``) x the brake factor;
  unknown where the catalog lacks the holding torque. The rotor inertia is then the brake
  variant's (``motor_brake.braked_motors``, before the model is built);
* output loads: the radial and axial load the axis puts on the gearbox output
  (``mechanism_checks.output_loads``: a belt pulley's shaft load, a pinion's forces) against F2r and
  F2a as the catalog gives them; unknown where either is not known.

A margin is NaN where a rating or dimension it needs is unknown; the candidate's ``unknown``
bits say which. Envelopes are not computed here: the caller passes them, computed by
``envelope.py`` at the speeds these checks need (the mean speed of every group for every motor;
every bin for the motors fast enough to reach the top bin).

Each quantity is computed with the same floating-point operations in the same order as the
per-candidate loop (no fused multiply-add), so the results do not depend on the processor or the
numpy build beyond IEEE 754 arithmetic.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.sizing.checks import mechanical_fit

# rows of the check arrays, in the order of selection.CHECK_UNITS
(PEAK, RMS, SPEED, INERTIA, FIT, GB_PEAK, GB_RATED, GB_ESTOP, GB_SPEED, GB_MEAN_SPEED, BRAKE, GB_RADIAL,
 GB_AXIAL) = range(13)
N_CHECKS = 13

_RPM = 60.0 / (2.0 * np.pi)
_MM = 1e3

FIT_TOLERANCE = 0.5e-3
"""[m] a motor flange or pilot within this of the gearbox adapter's counts as equal (whole millimetres)."""

# a candidate's detail vector: required, available, margin of each check, then these
N_DETAIL = 3 * N_CHECKS + 3
D_RMS, D_PEAK, D_INERTIA = 3 * N_CHECKS, 3 * N_CHECKS + 1, 3 * N_CHECKS + 2

BLOCK = 65536
"""Candidates checked together (whole motors of the grid): numpy's per-call cost sets the lower end
(the selection of examples/ball_screw.yaml, 295,204 candidates: 42 ms CPU at 65,536, 59 ms at 16,384,
85 ms at 8,192, no faster at 131,072), the temporaries (a few tens of megabytes) the upper."""

FULL_SCAN = 1 << 18
"""Candidates x bins up to which the worst bin is found by a scan of every bin (beyond, by the search)."""

Array = NDArray[np.float64]
_INF, _NAN = np.inf, np.nan


def check(model: tuple[Any, ...], row_start: NDArray[np.int64], rows: NDArray[np.int64],
          pick: NDArray[np.int64], motor: NDArray[np.int32], slot: NDArray[np.int32],
          worst: NDArray[np.float64], failed: NDArray[np.uint16], unknown: NDArray[np.uint16],
          detail: NDArray[np.float64]) -> None:
    """Check candidates: every one of the grid, or the listed ones in detail.

    Grid (``pick`` empty): every candidate in group, motor, row order gets its motor, slot (index
    into ``rows``), worst known margin (NaN if every margin is unknown), a bit mask of the checks
    that fail (bit c: check c, margin < 0) and one of the checks that cannot be judged (margin
    NaN: a rating or dimension is unknown). List: ``pick`` (3, n) holds motor, group and slot of
    n candidates, and column k of ``detail`` (N_DETAIL, n) gets candidate k's required, available
    and margin of every check, its RMS and peak torque and inertia ratio.

    ``model`` (see ``selection.evaluate``). Motors (M): rotor inertia [kg m^2], peak torque [N m],
    max speed [rad/s], shaft, flange and pilot diameter [m], brake holding torque [N m]. Envelopes
    [N m]: ``cont_mean`` (M, G) continuous at each group's mean speed, ``env_full[full_row[g, m]]``
    (B,) intermittent at every bin of group g where the motor reaches the top bin (row -1 where it does not).
    Groups (G): ratio, efficiency, the demand behind the ratio: ``hull_speed`` (G, B) bin upper edges [rad/s],
    ``hull_t``/``hull_a`` (G, B, V) hull vertices per bin [N m, rad/s^2], ``all_t``/``all_a`` (G,
    V2) hull of the whole cycle, ``sums`` (G, 3) S_TT, S_Ta, S_aa, ``g_speed`` (G, 2) max and mean
    |omega| [rad/s], reflected load inertia [kg m^2]. ``rows[row_start[g]:row_start[g + 1]]`` are
    the gearbox rows (-1 direct) of group g. Gearbox rows (NaN where unknown): input inertia [kg
    m^2] (0 where unknown), n1max and n1N [rad/s], T2N, T2B and T2NOT [N m], input bore max and min,
    flange and pilot [m]. ``par``: period [s], torque, RMS and speed margins, inertia-ratio limit,
    cubic-mean output torque [N m], running load torque [N m], peak output torque [N m], shock
    factor (NaN where the cycle rate needs one that is not given), static torque the brake must hold
    at the axis's motor shaft x the brake factor [N m] (NaN: the axis needs no brake), radial and
    axial load on the gearbox output [N] (NaN: not modelled). Gearbox rows also: drawn adapters
    (R, 3 A) [m], F2r and F2a [N].
    """
    listed = pick.shape[1] > 0
    with np.errstate(all="ignore"):  # inf and NaN are values here (an unknown rating, a zero demand)
        if listed:
            for lo in range(0, pick.shape[1], BLOCK):
                hi = min(lo + BLOCK, pick.shape[1])
                _, detail[:, lo:hi] = _block(model, rows, pick[0, lo:hi], pick[1, lo:hi], pick[2, lo:hi], True)
            return
        # the grid as motors x slots (a slot is one gearbox row, or direct, of one group): whole rows of
        # motors at a time, each candidate written to its place in group, motor, row order
        n_motors, n_slots = model[0].shape[0], len(rows)
        width = np.diff(row_start)
        group = np.repeat(np.arange(len(width)), width)  # each slot's group
        first = np.concatenate([[0], np.cumsum(width * n_motors)])[:-1]  # each group's first candidate
        q = np.arange(n_slots)[None, :]
        g = group[None, :]
        at_slot = (first[group] + q[0] - row_start[group])[None, :]
        step = max(1, BLOCK // max(n_slots, 1))
        fits = _fit_table(model, rows, np.arange(n_motors)[:, None], q)  # the same for every block of motors
        for lo in range(0, n_motors, step):
            m = np.arange(lo, min(lo + step, n_motors))[:, None]
            mar, slow = _block(model, rows, m, g, q, False, fits)
            k = at_slot + m * width[group][None, :]
            _summarise(mar, slow, k, m, q, motor, slot, worst, failed, unknown)


def _summarise(mar: list[Array], slow: NDArray[np.bool_], k: NDArray[np.int64], m: NDArray[np.int64],
               q: NDArray[np.int64], motor: NDArray[np.int32], slot: NDArray[np.int32], worst: Array,
               failed: NDArray[np.uint16], unknown: NDArray[np.uint16]) -> None:
    """Write candidates ``k``: the worst known margin (the first of equal ones; NaN if none is known),
    the bits of the checks that fail and of those that cannot be judged. A margin of the gearbox row
    alone comes as one row over the slots (broadcast over the motors)."""
    w = np.full(k.shape, _NAN)
    bits = np.zeros(k.shape, dtype=np.uint16)
    gaps = np.zeros(k.shape, dtype=np.uint16)
    for c, x in enumerate(mar):
        gap = np.isnan(x)
        if c == PEAK:
            gap &= ~slow  # a motor too slow for the top bin is not judged on peak torque: max_speed fails
        bit = np.uint16(1 << c)
        bits |= np.less(x, 0.0) * bit
        gaps |= gap * bit
        np.fmin(w, x, out=w)  # the smallest known margin, NaN if none is known
    zero = np.flatnonzero(w.ravel() == 0.0)
    if len(zero):  # the first of the checks at zero gives the sign (0.0 or -0.0), as a loop over them would
        flat = np.stack([np.broadcast_to(x, k.shape).ravel()[zero] for x in mar])
        w.ravel()[zero] = flat[np.argmax(flat == 0.0, axis=0), np.arange(len(zero))]
    motor[k] = m
    slot[k] = q
    worst[k] = w
    failed[k] = bits
    unknown[k] = gaps


def _support(t: Array, a: Array, j: Array) -> Array:
    """max over the vertices (last axis) of |T_v + J alpha_v| [N m]."""
    s = np.abs(t[..., 0] + j * a[..., 0])
    for v in range(1, t.shape[-1]):
        s = np.maximum(s, np.abs(t[..., v] + j * a[..., v]))
    return s


def _worst_bin(env_full: Array, hull_t: Array, hull_a: Array, pair: NDArray[np.int64], g: NDArray[np.int64],
               j: Array, peak_all: Array, tm: float) -> tuple[Array, Array, Array]:
    """Required torque, available torque and margin at the worst speed bin of candidates that reach the
    top bin (pair: their row of ``env_full``): the lowest margin, the first bin on ties, the first NaN
    margin before any number (numpy's argmin over every bin).

    The bins of each pair are visited from its lowest envelope up, all candidates in step; a candidate
    stops at the first bin whose envelope is above (margin + 1) x its whole cycle's peak torque: no bin
    there can lower its margin (a bin's peak torque is at most the cycle's; 1e-12 covers rounding), so
    the result is the full scan's. Groups with a NaN vertex and candidates without a finite, positive
    cycle peak are scanned in full, and so are all when they are few (``FULL_SCAN``: one pass over every
    bin costs less than the search's steps then).
    """
    n_bins = env_full.shape[1]
    used = np.flatnonzero(np.bincount(pair, minlength=len(env_full)))  # the rows these candidates need
    at = np.searchsorted(used, pair)
    env = env_full[used]
    bound = peak_all * tm * (1.0 + 1e-12)
    req, av, mar = np.empty(len(pair)), np.empty(len(pair)), np.empty(len(pair))
    nan_vertex = np.asarray(np.isnan(hull_t).any(axis=(1, 2)) | np.isnan(hull_a).any(axis=(1, 2)))
    whole = nan_vertex[g] | ~(np.isfinite(bound) & (bound > 0.0)) | (len(pair) * n_bins <= FULL_SCAN)
    # An unknown envelope (NaN) at a bin where torque is needed is an unknown margin, which wins: the
    # first such bin (a motor without a max speed is judged at every bin, its envelope NaN above its
    # rated speed, typically).
    gap = np.isnan(env)
    has_gap = np.asarray(gap.any(axis=1))[at] & ~whole
    k = np.flatnonzero(has_gap)
    if len(k):
        b = np.argmax(gap, axis=1)[at[k]]
        rb = _support(hull_t[g[k], b], hull_a[g[k], b], j[k]) * tm
        req[k], av[k], mar[k] = rb, _NAN, _NAN
        whole[k[~(rb > 0.0)]] = True  # no torque needed there (an infinite margin): every bin
    k = np.flatnonzero(whole)
    if len(k):
        rb = _support(hull_t[g[k]], hull_a[g[k]], j[k][:, None]) * tm
        eb = env[at[k]]
        mb = np.where(rb > 0.0, eb / rb - 1.0, _INF)
        b = np.argmin(mb, axis=1)[:, None]
        req[k] = np.take_along_axis(rb, b, axis=1)[:, 0]
        av[k] = np.take_along_axis(eb, b, axis=1)[:, 0]
        mar[k] = np.take_along_axis(mb, b, axis=1)[:, 0]
    order = np.argsort(env, axis=1, kind="stable")
    best = np.empty(len(pair), dtype=np.int64)
    k = np.flatnonzero(~whole & ~has_gap)
    for step in range(n_bins):
        if not len(k):
            break
        b = order[at[k], step]
        eb = env[at[k], b]
        if step:
            go = ~(eb > (mar[k] + 1.0) * bound[k])
            k, b, eb = k[go], b[go], eb[go]
        gk = g[k]
        rb = _support(hull_t[gk, b], hull_a[gk, b], j[k]) * tm
        mb = np.where(rb > 0.0, eb / rb - 1.0, _INF)
        if step:
            take = (mb < mar[k]) | ((mb == mar[k]) & (b < best[k]))
            k_new, b, eb, rb, mb = k[take], b[take], eb[take], rb[take], mb[take]
        else:
            k_new = k
        req[k_new], av[k_new], mar[k_new], best[k_new] = rb, eb, mb, b
    return req, av, mar


def _over(num: Array, den: Array) -> Array:
    """num / den - 1, infinite where den is not positive (nothing required)."""
    return np.where(den > 0.0, num / den - 1.0, _INF)


def _block(model: tuple[Any, ...], rows: NDArray[np.int64], m: NDArray[np.int64], g: NDArray[np.int64],
           q: NDArray[np.int64], listed: bool,
           fits: tuple[Array, NDArray[np.intp], NDArray[np.intp]] | None = None) -> tuple[Any, Any]:
    """Candidates (motor m, group g, slot q; listed: 1-D, grid: motors as a column, slots as a row):
    listed, their margins (N_CHECKS, n) and detail vectors (N_DETAIL, n); grid, each check's margins
    (broadcast over motors and slots) and whether each motor is too slow for the cycle's top bin.
    ``fits`` (grid): the mechanical fit of every motor and slot (:func:`_fit_table`), computed once for
    all blocks."""
    (j_rotor, t_peak, w_max, m_shaft, m_flange, m_pilot, m_bolt, m_brake, cont_mean, full_row, env_full, g_ratio,
     g_eff, hull_speed, hull_t, hull_a, all_t, all_a, sums, g_speed, g_j_load, gb_j, gb_nmax, gb_nmean, gb_t2n, gb_t2b,
     gb_t2not, gb_bore_max, gb_bore_min, gb_flange, gb_pilot, gb_adapters, gb_f2r, gb_f2a, par) = model
    period, tm, rm, sm, limit, out_cubic, run_t = par[0], par[1], par[2], par[3], par[4], par[5], par[6]
    out_peak, fs, hold, load_r, load_a = par[7], par[8], par[9], par[10], par[11]
    top = hull_speed.shape[1] - 1
    shape = np.broadcast_shapes(m.shape, q.shape)
    req_t2b = out_peak * tm * (1.0 if np.isnan(fs) else fs)
    req_t2n = out_cubic * tm
    # the gearbox row's ratings, the direct drive's (index 0) first: what direct drive never limits
    r = rows[q] + 1
    direct = r == 0

    def row(col: Array, none: float) -> Array:
        return np.concatenate([[none], col])[r]

    r_j, r_speed, r_mean = row(gb_j, 0.0), row(gb_nmax, _INF), row(gb_nmean, _INF)
    r_t2n, r_t2b, r_t2not = row(gb_t2n, _INF), row(gb_t2b, _INF), row(gb_t2not, _INF)
    r_bmax, r_bmin, r_fl, r_pi = row(gb_bore_max, _INF), row(gb_bore_min, _NAN), row(gb_flange, _NAN), \
        row(gb_pilot, _NAN)
    r_ad = np.concatenate([np.full((1, gb_adapters.shape[1]), _NAN), gb_adapters])[r]  # drawn adapters, flat
    r_f2r, r_f2a = row(gb_f2r, _INF), row(gb_f2a, _INF)
    # the output loads against F2r / F2a: nothing needed passes; an unknown load or rating is unknown
    r_mar_f2r = np.where(direct | (load_r == 0.0), _INF, np.where(np.isnan(r_f2r), _NAN, r_f2r / load_r - 1.0))
    r_mar_f2a = np.where(direct | (load_a == 0.0), _INF, np.where(np.isnan(r_f2a), _NAN, r_f2a / load_a - 1.0))
    req_s = g_speed[g, 0] * sm
    req_mean = g_speed[g, 1]
    # margins of the row alone; an unknown rating leaves its check unknown, whatever is required
    r_mar_speed = np.where(np.isnan(r_speed), _NAN, _over(r_speed, req_s))
    r_mar_mean = np.where(np.isnan(r_mean), _NAN, _over(r_mean, req_mean))
    r_mar_t2n = np.where(np.isnan(r_t2n), _NAN, r_t2n / req_t2n - 1.0 if req_t2n > 0.0 else _INF)
    r_mar_t2b = np.where(np.isnan(r_t2b) | (~direct & bool(np.isnan(fs))), _NAN,
                         r_t2b / req_t2b - 1.0 if req_t2b > 0.0 else _INF)  # or a shock factor is missing
    i = g_ratio[g]
    j_m = j_rotor[m]
    j = j_m + r_j
    # peak torque against the intermittent envelope, worst bin; a motor slower than the top bin is not
    # judged on torque (its required torque, shown in detail, is that of the top bin)
    slow = w_max[m] < hull_speed[g, top]
    av_p = np.full(shape, _NAN)
    mar_p = np.full(shape, _NAN)
    if listed:
        peak_all = _support(all_t[g], all_a[g], j)  # peak motor torque over the cycle: the cycle hull's support
        req_p = _support(hull_t[g, top], hull_a[g, top], j) * tm
    fast = np.nonzero(~slow)
    if len(fast[0]):
        gf = np.broadcast_to(g, shape)[fast]
        pair = full_row[gf, np.broadcast_to(m, shape)[fast]]
        peak_fast = peak_all[fast] if listed else _support(all_t[gf], all_a[gf], j[fast])
        req_fast, av_p[fast], mar_p[fast] = _worst_bin(env_full, hull_t, hull_a, pair, gf, j[fast], peak_fast, tm)
        if listed:
            req_p[fast] = req_fast
    # the other checks, each a closed form in J
    s_tt, s_ta, s_aa = sums[g, 0], sums[g, 1], sums[g, 2]
    cont = cont_mean[m, g] if listed else cont_mean[m[:, 0]][:, g[0]]  # (rows, then columns: the faster way)
    w_m, j_l, t_pk = w_max[m], g_j_load[g], t_peak[m]
    sh, fl_m, pi_m, bc_m = m_shaft[m], m_flange[m], m_pilot[m], m_bolt[m]
    mar_motor_speed = _over(w_m, req_s)
    t_l = run_t / i
    # RMS torque against the continuous torque at the mean speed
    rms = np.sqrt(np.maximum(s_tt + 2.0 * j * s_ta + j * j * s_aa, 0.0) / period)
    req_r = rms * rm
    mar_r = _over(cont, req_r)
    # inertia ratio, the gearbox's input inertia on the load side
    ir = (j_l + r_j) / j_m
    mar_i = np.where(ir > 0.0, limit / ir - 1.0, _INF)
    # mechanical fit: it depends on the motor's and the gearbox input's dimensions alone. Listed candidates
    # (few) each get theirs; the grid looks it up in the table of every motor and slot (``fits``)
    if listed:
        mar_f = _fit(sh, fl_m, pi_m, bc_m, r_bmax, r_bmin, r_fl, r_pi, direct, r_ad.reshape(*shape, -1, 3))
    else:
        assert fits is not None
        table, at_motor, at_row = fits
        mar_f = table.take(at_motor[m[:, 0]], axis=0).take(at_row[q[0]], axis=1)  # rows, then columns: faster
    # gearbox: what passes at the motor's peak against the emergency-stop torque
    req_ge = np.where(direct, 0.0, ((1.0 - j / (j + j_l)) * (t_pk - t_l) + t_l) * i * g_eff[g])
    mar_ge = np.where(np.isnan(r_t2not), _NAN, np.where(direct, _INF, _over(r_t2not, req_ge)))
    # motor brake: holding torque against the static torque through the gearbox (holding direction)
    if np.isnan(hold):
        req_b, av_b, mar_b = np.zeros(1), np.full(1, _INF), np.full(1, _INF)  # no brake needed: never limits
    else:
        req_b = hold / i * g_eff[g]
        av_b = m_brake[m]
        mar_b = np.where(np.isnan(av_b), _NAN, _over(av_b, req_b))
    margins = [mar_p, mar_r, mar_motor_speed, mar_i, mar_f, r_mar_t2b, r_mar_t2n, mar_ge, r_mar_speed, r_mar_mean,
               mar_b, r_mar_f2r, r_mar_f2a]
    if not listed:
        return margins, slow
    mar = np.empty((N_CHECKS, *shape))
    for c, x in enumerate(margins):
        mar[c] = x
    out = np.empty((N_DETAIL, *shape))
    for c, x in enumerate((req_p, req_r, req_s * _RPM, ir, np.where(direct, 0.0, sh * _MM), req_t2b, req_t2n,
                           req_ge, req_s * _RPM, req_mean * _RPM, req_b, np.where(direct, 0.0, load_r),
                           np.where(direct, 0.0, load_a),
                           av_p, cont, w_m * _RPM, limit, r_bmax * _MM, r_t2b, r_t2n, r_t2not, r_speed * _RPM,
                           r_mean * _RPM, av_b, r_f2r, r_f2a)):
        out[c] = x
    out[2 * N_CHECKS:3 * N_CHECKS] = mar
    out[D_RMS], out[D_PEAK], out[D_INERTIA] = rms, peak_all, ir
    return mar, out


def _fit_table(model: tuple[Any, ...], rows: NDArray[np.int64], m: NDArray[np.int64],
               q: NDArray[np.int64]) -> tuple[Array, NDArray[np.intp], NDArray[np.intp]]:
    """The mechanical fit of motors ``m`` (a column) onto slots ``q`` (a row) as a table: its values once per
    distinct motor (shaft, flange, pilot, bolt circle) and distinct gearbox input (bores, flange, pilot,
    drawn adapters), and each motor's and slot's index into it."""
    m_shaft, m_flange, m_pilot, m_bolt = model[3], model[4], model[5], model[6]
    gb_bore_max, gb_bore_min, gb_flange, gb_pilot, gb_adapters = model[27], model[28], model[29], model[30], model[31]
    r = rows[q[0]] + 1  # the gearbox row of each slot, the direct drive's (index 0) first, as in _block

    def row(col: Array, none: float) -> Array:
        return np.concatenate([[none], col])[r]

    flat = [row(gb_bore_max, _INF), row(gb_bore_min, _NAN), row(gb_flange, _NAN), row(gb_pilot, _NAN), r == 0]
    r_ad = np.concatenate([np.full((1, gb_adapters.shape[1]), _NAN), gb_adapters])[r]
    mm = m[:, 0]
    motor_dims, at_motor = _distinct(np.stack([m_shaft[mm], m_flange[mm], m_pilot[mm], m_bolt[mm]], axis=1))
    row_dims, at_row = _distinct(np.concatenate([np.stack(flat, axis=1), r_ad.reshape(len(r), -1)], axis=1))
    md, rd = motor_dims.T[:, :, None], row_dims.T[:5, None, :]
    table = _fit(md[0], md[1], md[2], md[3], rd[0], rd[1], rd[2], rd[3], rd[4],
                 row_dims[None, :, 5:].reshape(1, len(row_dims), -1, 3))
    return table, at_motor, at_row


_SENTINEL = -1.0
"""Stands for NaN in ``_distinct`` (the rows it compares are never negative)."""


def _distinct(a: Array) -> tuple[Array, NDArray[np.intp]]:
    """The distinct rows of ``a`` and, for each row of ``a``, its index among them. NaN (unknown) equals
    NaN here: ``np.unique`` along an axis keeps every NaN row apart, which for the candidates of a long
    listing made one "distinct" row per candidate and an outer product of many GB. The rows are
    dimensions and flags, never negative, so NaN is mapped to -1 for the comparison and back."""
    key = np.where(np.isnan(a), _SENTINEL, a)
    found, at = np.unique(key, axis=0, return_inverse=True)
    return np.where(found == _SENTINEL, _NAN, found), np.asarray(at).ravel()


def _fit(sh: Array, fl_m: Array, pi_m: Array, bc_m: Array, r_bmax: Array, r_bmin: Array, r_fl: Array, r_pi: Array,
         direct: Array, r_ad: Array) -> Array:
    """Margin of the mechanical fit (``checks.mechanical_fit``, whose arithmetic this is): the motor shaft
    [m] into the gearbox's input bore range, and its flange onto the input adapter: one of the drawn
    adapters ``r_ad`` (..., A, 3: bore, pilot, bolt circle [m]) where the catalog draws them, else the
    adapter's square flange and pilot where named (unknown where not); a known shortfall first, NaN where
    one is unknown and none falls short, infinite for direct drive."""
    return np.where(direct > 0.0, _INF, mechanical_fit(sh, fl_m, pi_m, r_bmax, r_bmin, r_fl, r_pi, FIT_TOLERANCE,
                                                       bc_m, r_ad))


def closest_failing(worst: NDArray[np.float64], failed: NDArray[Any], n: int) -> NDArray[np.int64]:
    """Indices of the ``n`` failing candidates with the largest worst margin, best first: ties in index
    order, NaN margins after every number (a stable sort of the failures, without sorting them all)."""
    if n <= 0:
        return np.empty(0, dtype=np.int64)
    failing = np.flatnonzero(failed != 0)
    key = np.where(np.isnan(worst[failing]), -np.inf, worst[failing])
    if len(failing) > n:
        # first a lower bound of the n-th largest key: the n-th largest of the maxima of blocks of keys (at least
        # n blocks, so n distinct keys reach it); only the keys at or above it can be among the n largest, and
        # numpy's partition of all of them is slow where many are equal (3-12 ms for ball_screw's 180,000)
        step = max(1, min(256, len(key) // n))
        tops = np.maximum.reduceat(key, np.arange(0, len(key), step))
        keep = key >= np.partition(tops, len(tops) - n)[len(tops) - n]
        failing, key = failing[keep], key[keep]
    if len(failing) > n:
        nth = np.partition(key, len(key) - n)[len(key) - n]  # the n-th largest key: no later one can be better
        # every key above it, and of those equal to it the first ones in index order (a stable sort puts them
        # so): n in all, however many candidates share the n-th key (thousands may, e.g. -inf)
        keep = key > nth
        keep[np.flatnonzero(key == nth)[:n - int(np.count_nonzero(keep))]] = True
        failing, key = failing[keep], key[keep]
    return failing[np.argsort(-key, kind="stable")[:n]].astype(np.int64)


__all__ = ["BLOCK", "BRAKE", "D_INERTIA", "D_PEAK", "D_RMS", "FIT", "FIT_TOLERANCE", "GB_AXIAL", "GB_ESTOP",
           "GB_MEAN_SPEED", "GB_PEAK", "GB_RADIAL", "GB_RATED", "GB_SPEED", "INERTIA", "N_CHECKS", "N_DETAIL", "PEAK",
           "RMS", "SPEED", "check", "closest_failing"]
