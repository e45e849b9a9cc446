"""The compiled candidate loop of the catalog selection (numba). Imported lazily by
``selection.evaluate``: importing this module imports numba, which ``import drivetrain`` and a
sizing with a given motor never pay for.

One pass over every candidate (gearbox-ratio group x motor x gearbox row) writes all its checks
into preallocated arrays: no temporaries the size of the candidate set, no per-group Python.
The physics is that of ``motor_fit.fit_motors``, ``checks.mechanical_fit`` and
``checks.gearbox_checks`` (their docstrings give the sources); ``tests/test_selection.py``
asserts that this loop and those reference functions give the same required/available/margin
for every candidate of the shipped catalog.

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
  input speed x speed margin, n1N against the mean input speed.

A margin is NaN where a rating or dimension it needs is unknown; the candidate's ``unknown``
bits say which. Envelopes are not computed here: the caller passes them, computed by
``envelope.py`` at the speeds this loop needs (the mean speed of every group for every motor;
every bin for the motors fast enough to reach the top bin).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.jit import njit

# rows of the check arrays, in the order of selection.CHECK_UNITS
(PEAK, RMS, SPEED, INERTIA, FIT, GB_PEAK, GB_RATED, GB_ESTOP, GB_SPEED, GB_MEAN_SPEED) = range(10)
N_CHECKS = 10

_OPTIONS: dict[str, Any] = {"cache": True, "error_model": "numpy", "nogil": True, "no_cfunc_wrapper": True,
                            "fastmath": {"contract", "afn", "nsz"}}

_RPM = 60.0 / (2.0 * np.pi)
_MM = 1e3

FIT_TOLERANCE = 0.5e-3
"""[m] a motor flange or pilot within this of the gearbox adapter's counts as equal (whole millimetres)."""

# a candidate's detail vector: required, available, margin of each check, then these
N_DETAIL = 3 * N_CHECKS + 3
D_RMS, D_PEAK, D_INERTIA = 3 * N_CHECKS, 3 * N_CHECKS + 1, 3 * N_CHECKS + 2


@njit(**_OPTIONS)
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
    max speed [rad/s], shaft, flange and pilot diameter [m]. Envelopes [N m]: ``cont_mean`` (M, G)
    continuous at each group's mean speed, ``env_full[full_row[g, m]]`` (B,) intermittent at every
    bin of group g where the motor reaches the top bin (row -1 where it does not). Groups (G):
    ratio, efficiency, the demand behind the ratio: ``hull_speed`` (G, B) bin upper edges [rad/s],
    ``hull_t``/``hull_a`` (G, B, V) hull vertices per bin [N m, rad/s^2], ``all_t``/``all_a`` (G,
    V2) hull of the whole cycle, ``sums`` (G, 3) S_TT, S_Ta, S_aa, ``g_speed`` (G, 2) max and mean
    |omega| [rad/s], reflected load inertia [kg m^2]. ``rows[row_start[g]:row_start[g + 1]]`` are
    the gearbox rows (-1 direct) of group g. Gearbox rows (NaN where unknown): input inertia [kg
    m^2] (0 where unknown), n1max and n1N [rad/s], T2N, T2B and T2NOT [N m], input bore max and min,
    flange and pilot [m]. ``par``: period [s], torque, RMS and speed margins, inertia-ratio limit,
    cubic-mean output torque [N m], running load torque [N m], peak output torque [N m], shock
    factor (NaN where the cycle rate needs one that is not given).

    Work runs per (group, motor) pair over the pair's gearbox rows, each quantity in its own short
    loop over the rows (which the compiler turns into vector instructions); a listed candidate is a
    pair of one row. One code path serves both modes, and no helper is called (a call would count
    references to every array it is passed).
    """
    (j_rotor, t_peak, w_max, m_shaft, m_flange, m_pilot, cont_mean, full_row, env_full, g_ratio, g_eff,
     hull_speed, hull_t, hull_a, all_t, all_a, sums, g_speed, g_j_load, gb_j, gb_nmax, gb_nmean, gb_t2n, gb_t2b,
     gb_t2not, gb_bore_max, gb_bore_min, gb_flange, gb_pilot, par) = model
    period, tm, rm, sm, limit, out_cubic, run_t = par[0], par[1], par[2], par[3], par[4], par[5], par[6]
    out_peak, fs = par[7], par[8]
    n_motors, n_bins, n_v, n_all = j_rotor.shape[0], hull_speed.shape[1], hull_t.shape[2], all_t.shape[1]
    top = n_bins - 1
    listed = pick.shape[1] > 0
    n_pairs = pick.shape[1] if listed else (row_start.shape[0] - 1) * n_motors
    width = 1 if listed else int(np.max(np.diff(row_start)))
    # per row of the current group, and per row of the current pair
    r_direct = np.empty(width, dtype=np.bool_)
    r_j, r_speed, r_mean, r_t2n, r_t2b, r_t2not = (np.empty(width), np.empty(width), np.empty(width),
                                                   np.empty(width), np.empty(width), np.empty(width))
    r_bmax, r_bmin, r_fl, r_pi = np.empty(width), np.empty(width), np.empty(width), np.empty(width)
    # the margins that depend on the row alone
    r_mar_speed, r_mar_mean, r_mar_t2n, r_mar_t2b = np.empty(width), np.empty(width), np.empty(width), np.empty(width)
    j, peak_all, s = np.empty(width), np.empty(width), np.empty(width)
    req_p, av_p, mar_p = np.empty(width), np.empty(width), np.empty(width)
    mar = np.empty(N_CHECKS)
    req_t2b = out_peak * tm * (1.0 if math.isnan(fs) else fs)
    req_t2n = out_cubic * tm
    k = 0
    g_loaded = -1
    for pair in range(n_pairs):
        if listed:
            m, g, q0, q1 = pick[0, pair], pick[1, pair], pick[2, pair], pick[2, pair] + 1
        else:
            g, m = pair // n_motors, pair % n_motors
            q0, q1 = row_start[g], row_start[g + 1]
        n = q1 - q0
        req_s = g_speed[g, 0] * sm
        req_mean = g_speed[g, 1]
        if listed or g != g_loaded:
            for q in range(n):
                r = rows[q0 + q]
                d = r < 0
                r_direct[q] = d
                r_j[q] = 0.0 if d else gb_j[r]
                r_speed[q] = math.inf if d else gb_nmax[r]
                r_mean[q] = math.inf if d else gb_nmean[r]
                r_t2n[q] = math.inf if d else gb_t2n[r]
                r_t2b[q] = math.inf if d else gb_t2b[r]
                r_t2not[q] = math.inf if d else gb_t2not[r]
                r_bmax[q] = math.inf if d else gb_bore_max[r]
                r_bmin[q] = math.nan if d else gb_bore_min[r]
                r_fl[q] = math.nan if d else gb_flange[r]
                r_pi[q] = math.nan if d else gb_pilot[r]
                r_mar_speed[q] = r_speed[q] / req_s - 1.0 if req_s > 0.0 else math.inf
                r_mar_mean[q] = r_mean[q] / req_mean - 1.0 if req_mean > 0.0 else math.inf
                r_mar_t2n[q] = r_t2n[q] / req_t2n - 1.0 if req_t2n > 0.0 else math.inf
                r_mar_t2b[q] = r_t2b[q] / req_t2b - 1.0 if req_t2b > 0.0 else math.inf
                # an unknown rating leaves its check unknown, whatever is required
                r_mar_speed[q] = math.nan if math.isnan(r_speed[q]) else r_mar_speed[q]
                r_mar_mean[q] = math.nan if math.isnan(r_mean[q]) else r_mar_mean[q]
                r_mar_t2n[q] = math.nan if math.isnan(r_t2n[q]) else r_mar_t2n[q]
                if math.isnan(r_t2b[q]) or (not d and math.isnan(fs)):
                    r_mar_t2b[q] = math.nan  # or the cycle rate needs a shock factor that is not given
            g_loaded = g
        i = g_ratio[g]
        j_m = j_rotor[m]
        for q in range(n):
            j[q] = j_m + r_j[q]
        # peak motor torque over the cycle: the support function of the cycle's hull
        for q in range(n):
            peak_all[q] = abs(all_t[g, 0] + j[q] * all_a[g, 0])
        for v in range(1, n_all):
            for q in range(n):
                peak_all[q] = max(peak_all[q], abs(all_t[g, v] + j[q] * all_a[g, v]))
        # peak torque against the intermittent envelope
        slow = w_max[m] < hull_speed[g, top]
        if slow:
            # slower than the cycle's top speed: not judged on torque (max_speed fails instead)
            for q in range(n):
                s[q] = abs(hull_t[g, top, 0] + j[q] * hull_a[g, top, 0])
            for v in range(1, n_v):
                for q in range(n):
                    s[q] = max(s[q], abs(hull_t[g, top, v] + j[q] * hull_a[g, top, v]))
            for q in range(n):
                req_p[q], av_p[q], mar_p[q] = s[q] * tm, math.nan, math.nan
        else:
            # Worst bin, the first on ties and a NaN margin the worst (numpy's argmin over the
            # bins). From the top speed down (where the envelope is usually lowest) with "<=", so
            # the lowest index wins a tie; a bin is skipped when even the whole cycle's peak
            # torque there could not lower the margin (a bound: env_b / (peak tm) - 1 > margin).
            row = full_row[g, m]
            for q in range(n):
                bound = peak_all[q] * tm * (1.0 + 1e-12)
                rq, aq, mq = 0.0, 0.0, math.inf
                for b in range(top, -1, -1):
                    eb = env_full[row, b]
                    if math.isnan(mq):
                        if not math.isnan(eb):
                            continue  # only a NaN margin at a lower bin can replace a NaN one
                    elif b != top and eb > (mq + 1.0) * bound:
                        continue
                    sb = abs(hull_t[g, b, 0] + j[q] * hull_a[g, b, 0])
                    for v in range(1, n_v):
                        sb = max(sb, abs(hull_t[g, b, v] + j[q] * hull_a[g, b, v]))
                    rb = sb * tm
                    mb = eb / rb - 1.0 if rb > 0.0 else math.inf
                    if b == top or mb <= mq or math.isnan(mb):
                        rq, aq, mq = rb, eb, mb
                req_p[q], av_p[q], mar_p[q] = rq, aq, mq
        # the other checks, each a closed form in J
        s_tt, s_ta, s_aa = sums[g, 0], sums[g, 1], sums[g, 2]
        cont, w_m, j_l, t_pk = cont_mean[m, g], w_max[m], g_j_load[g], t_peak[m]
        sh, fl_m, pi_m = m_shaft[m], m_flange[m], m_pilot[m]
        mar_motor_speed = w_m / req_s - 1.0 if req_s > 0.0 else math.inf
        t_l = run_t / i
        for q in range(n):
            jq = j[q]
            direct = r_direct[q]
            # RMS torque against the continuous torque at the mean speed
            rms = math.sqrt(max(s_tt + 2.0 * jq * s_ta + jq * jq * s_aa, 0.0) / period)
            req_r = rms * rm
            mar_r = cont / req_r - 1.0 if req_r > 0.0 else math.inf
            # inertia ratio, the gearbox's input inertia on the load side
            ir = (j_l + r_j[q]) / j_m
            mar_i = limit / ir - 1.0 if ir > 0.0 else math.inf
            # mechanical fit (checks.mechanical_fit): known shortfalls first, then unknowns
            mar_f = math.inf
            if not direct:
                m1 = r_bmax[q] / sh - 1.0
                m2 = sh / r_bmin[q] - 1.0 if not math.isnan(r_bmin[q]) else math.inf
                if math.isnan(sh):
                    m2 = math.nan
                m3 = math.inf
                if not math.isnan(r_fl[q]):
                    m3 = math.nan if math.isnan(fl_m) else (
                        math.inf if abs(fl_m - r_fl[q]) <= FIT_TOLERANCE else -abs(fl_m / r_fl[q] - 1.0))
                m4 = math.inf
                if not math.isnan(r_pi[q]):
                    m4 = math.nan if math.isnan(pi_m) else (
                        math.inf if abs(pi_m - r_pi[q]) <= FIT_TOLERANCE else -abs(pi_m / r_pi[q] - 1.0))
                lo, gap = math.inf, False
                for x in (m1, m2, m3, m4):
                    if math.isnan(x):
                        gap = True
                    elif x < lo:
                        lo = x
                mar_f = lo if (lo < 0.0 or not gap) else math.nan
            # gearbox: what passes at the motor's peak against the emergency-stop torque
            req_ge = 0.0 if direct else ((1.0 - jq / (jq + j_l)) * (t_pk - t_l) + t_l) * i * g_eff[g]
            mar_ge = math.inf if direct else (r_t2not[q] / req_ge - 1.0 if req_ge > 0.0 else math.inf)
            if math.isnan(r_t2not[q]):
                mar_ge = math.nan
            mar[PEAK], mar[RMS], mar[SPEED], mar[INERTIA], mar[FIT] = mar_p[q], mar_r, mar_motor_speed, mar_i, mar_f
            mar[GB_PEAK], mar[GB_RATED], mar[GB_ESTOP] = r_mar_t2b[q], r_mar_t2n[q], mar_ge
            mar[GB_SPEED], mar[GB_MEAN_SPEED] = r_mar_speed[q], r_mar_mean[q]
            if listed:
                detail[PEAK, k], detail[RMS, k], detail[SPEED, k] = req_p[q], req_r, req_s * _RPM
                detail[INERTIA, k], detail[FIT, k] = ir, (0.0 if direct else sh * _MM)
                detail[GB_PEAK, k], detail[GB_RATED, k], detail[GB_ESTOP, k] = req_t2b, req_t2n, req_ge
                detail[GB_SPEED, k], detail[GB_MEAN_SPEED, k] = req_s * _RPM, req_mean * _RPM
                a = N_CHECKS
                detail[a + PEAK, k], detail[a + RMS, k], detail[a + SPEED, k] = av_p[q], cont, w_m * _RPM
                detail[a + INERTIA, k], detail[a + FIT, k] = limit, r_bmax[q] * _MM
                detail[a + GB_PEAK, k], detail[a + GB_RATED, k] = r_t2b[q], r_t2n[q]
                detail[a + GB_ESTOP, k] = r_t2not[q]
                detail[a + GB_SPEED, k], detail[a + GB_MEAN_SPEED, k] = r_speed[q] * _RPM, r_mean[q] * _RPM
                for c in range(N_CHECKS):
                    detail[2 * N_CHECKS + c, k] = mar[c]
                detail[D_RMS, k], detail[D_PEAK, k], detail[D_INERTIA, k] = rms, peak_all[q], ir
            else:
                # worst known margin (NaN if none is known), the bits of the checks that fail and
                # of those that cannot be judged
                w = math.nan
                bits, gaps = 0, 0
                for c in range(N_CHECKS):
                    x = mar[c]
                    if math.isnan(x):
                        if not (c == PEAK and slow):  # not judged, not unknown: max_speed fails instead
                            gaps |= 1 << c
                    else:
                        if x < 0.0:
                            bits |= 1 << c
                        if not x >= w:
                            w = x
                motor[k], slot[k], worst[k], failed[k], unknown[k] = m, q0 + q, w, bits, gaps
            k += 1


@njit(**_OPTIONS)
def closest_failing(worst: NDArray[np.float64], failed: NDArray[Any], n: int) -> NDArray[np.int64]:
    """Indices of the ``n`` failing candidates with the largest worst margin, best first: ties in index
    order, NaN margins after every number (a stable sort of the failures, in one pass)."""
    best = np.empty(max(n, 0), dtype=np.int64)
    key = np.empty(max(n, 0))
    count = 0
    if n <= 0:
        return best
    for k in range(worst.shape[0]):
        if failed[k] == 0:
            continue
        x = -math.inf if math.isnan(worst[k]) else worst[k]
        if count == n and not x > key[n - 1]:
            continue  # not better than the last kept (a tie keeps the earlier index)
        # insert before the first kept key that is smaller
        pos = count if count < n else n - 1
        while pos > 0 and key[pos - 1] < x:
            pos -= 1
        last = count if count < n else n - 1
        for t in range(last, pos, -1):
            key[t], best[t] = key[t - 1], best[t - 1]
        key[pos], best[pos] = x, k
        count = min(count + 1, n)
    return best[:count]


__all__ = ["D_INERTIA", "D_PEAK", "D_RMS", "FIT", "FIT_TOLERANCE", "GB_ESTOP", "GB_MEAN_SPEED", "GB_PEAK",
           "GB_RATED", "GB_SPEED", "INERTIA", "N_CHECKS", "N_DETAIL", "PEAK", "RMS", "SPEED", "check",
           "closest_failing"]
