"""The compiled candidate loop of the catalog selection (numba). Imported lazily by
``selection.evaluate``: importing this module imports numba, which ``import drivetrain`` and a
sizing with a given motor never pay for.

One pass over every candidate (gearbox-ratio group x motor x gearbox row) writes all its checks
into preallocated arrays: no temporaries the size of the candidate set, no per-group Python.
The physics is that of ``motor_fit.fit_motors`` and ``selection.evaluate`` (their docstrings
give the sources); ``tests/test_selection.py`` asserts that this loop and ``fit_motors`` give
the same required/available/margin for every candidate of the shipped catalog.

Per candidate k (motor m, group g of ratio i and efficiency eta, gearbox row r or -1 direct):

* J = J_M + J_g (rotor plus the gearbox's input inertia) [kg m^2];
* peak: max over the convex-hull vertices v of the demand of |T_v + J alpha_v| [N m], per
  speed bin against the intermittent envelope there (worst bin); a motor slower than the
  cycle's top speed is judged at the top bin (it has no torque there: margin -100 %);
* RMS: sqrt((S_TT + 2 J S_Ta + J^2 S_aa) / t_cycle) against the continuous torque at the mean
  speed (lecture, Torque Effective Value);
* speed: max |omega| x margin against min(motor max speed, gearbox input speed);
* inertia ratio: (J_L / i^2 + J_g) / J_M against the limit;
* gearbox rated torque: the cycle's cubic-mean output torque x margin against the rated
  output torque; gearbox peak: ((1 - k)(T_M - T_L/i) + T_L/i) i eta with k = J / (J + J_L/i^2)
  (lecture, Dynamic Loading and Gearbox Sizing) against its max (or emergency-stop) torque.

Envelopes are not computed here: the caller passes them, computed by ``envelope.py`` at the
speeds this loop needs (the top bin and mean speed of every group for every motor; every bin
for the motors fast enough to reach the top bin).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.jit import njit

# rows of the check arrays, in the order of selection.CHECK_UNITS
PEAK, RMS, SPEED, INERTIA, GB_RATED, GB_PEAK = range(6)
N_CHECKS = 6

_OPTIONS: dict[str, Any] = {"cache": True, "error_model": "numpy", "nogil": True, "no_cfunc_wrapper": True,
                            "fastmath": {"contract", "afn", "nsz"}}

_RPM = 60.0 / (2.0 * np.pi)


# a candidate's detail vector: required, available, margin of each check, then these
N_DETAIL = 3 * N_CHECKS + 3
D_RMS, D_PEAK, D_INERTIA = 3 * N_CHECKS, 3 * N_CHECKS + 1, 3 * N_CHECKS + 2


@njit(**_OPTIONS)
def check(model: tuple[Any, ...], row_start: NDArray[np.int64], rows: NDArray[np.int64],
          pick: NDArray[np.int64], motor: NDArray[np.int32], slot: NDArray[np.int32],
          worst: NDArray[np.float64], failed: NDArray[np.uint8], detail: NDArray[np.float64]) -> None:
    """Check candidates: every one of the grid, or the listed ones in detail.

    Grid (``pick`` empty): every candidate in group, motor, row order gets its motor, slot (index
    into ``rows``), worst margin (NaN if any margin is NaN) and a bit mask of the checks that do
    not pass (bit c: check c). List: ``pick`` (3, n) holds motor, group and slot of n candidates,
    and column k of ``detail`` (N_DETAIL, n) gets candidate k's required, available and margin of
    every check, its RMS and peak torque and inertia ratio.

    ``model`` (see ``selection.evaluate``). Motors (M): rotor inertia [kg m^2], peak torque [N m],
    max speed [rad/s]. Envelopes [N m]: ``env_top`` (M, G) intermittent at each group's top bin
    speed, ``cont_mean`` (M, G) continuous at its mean speed, ``env_full[full_row[g, m]]`` (B,)
    intermittent at every bin of group g where the motor reaches the top bin (row -1 where it
    does not). Groups (G): ratio, efficiency, the demand behind the ratio: ``hull_speed`` (G, B)
    bin upper edges [rad/s], ``hull_t``/``hull_a`` (G, B, V) hull vertices per bin [N m,
    rad/s^2], ``all_t``/``all_a`` (G, V2) hull of the whole cycle, ``sums`` (G, 3) S_TT, S_Ta,
    S_aa, ``g_speed`` (G, 2) max and mean |omega| [rad/s], reflected load inertia [kg m^2].
    ``rows[row_start[g]:row_start[g + 1]]`` are the gearbox rows (-1 direct) of group g. Gearbox
    rows: input inertia [kg m^2], input speed limit [rad/s], rated and max output torque [N m]
    (gaps already filled). ``par``: period [s], torque, RMS and speed margins, inertia-ratio
    limit, cubic-mean output torque [N m], running load torque [N m].

    Work runs per (group, motor) pair over the pair's gearbox rows, each quantity in its own short
    loop over the rows (which the compiler turns into vector instructions); a listed candidate is a
    pair of one row. One code path serves both modes, and no helper is called (a call would count
    references to every array it is passed).
    """
    (j_rotor, t_peak, w_max, env_top, cont_mean, full_row, env_full, g_ratio, g_eff, hull_speed, hull_t, hull_a,
     all_t, all_a, sums, g_speed, g_j_load, gb_j, gb_speed, gb_rated, gb_cap, par) = model
    period, tm, rm, sm, limit, out_cubic, run_t = par[0], par[1], par[2], par[3], par[4], par[5], par[6]
    n_motors, n_bins, n_v, n_all = j_rotor.shape[0], hull_speed.shape[1], hull_t.shape[2], all_t.shape[1]
    top = n_bins - 1
    listed = pick.shape[1] > 0
    n_pairs = pick.shape[1] if listed else (row_start.shape[0] - 1) * n_motors
    width = 1 if listed else int(np.max(np.diff(row_start)))
    # per row of the current group (gaps of direct drive filled), and per row of the current pair
    r_direct = np.empty(width, dtype=np.bool_)
    r_j, r_speed, r_rated, r_cap = np.empty(width), np.empty(width), np.empty(width), np.empty(width)
    r_mar_speed, r_mar_rated = np.empty(width), np.empty(width)  # the margins that depend on the row alone
    j, peak_all, s = np.empty(width), np.empty(width), np.empty(width)
    req_p, av_p, mar_p = np.empty(width), np.empty(width), np.empty(width)
    k = 0
    g_loaded = -1
    for pair in range(n_pairs):
        if listed:
            m, g, q0, q1 = pick[0, pair], pick[1, pair], pick[2, pair], pick[2, pair] + 1
        else:
            g, m = pair // n_motors, pair % n_motors
            q0, q1 = row_start[g], row_start[g + 1]
        n = q1 - q0
        if listed or g != g_loaded:
            for q in range(n):
                r = rows[q0 + q]
                r_direct[q] = r < 0
                r_j[q] = 0.0 if r < 0 else gb_j[r]
                r_speed[q] = math.inf if r < 0 else gb_speed[r]
                r_rated[q] = math.inf if r < 0 else gb_rated[r]
                r_cap[q] = math.inf if r < 0 else gb_cap[r]
                req_s = g_speed[g, 0] * sm
                r_mar_speed[q] = r_speed[q] / req_s - 1.0 if req_s > 0.0 else math.inf
                r_mar_rated[q] = math.inf if r < 0 else r_rated[q] / max(out_cubic * tm, 1e-300) - 1.0
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
        if w_max[m] < hull_speed[g, top]:
            # slower than the cycle's top speed: judged at the top bin (no torque there)
            for q in range(n):
                s[q] = abs(hull_t[g, top, 0] + j[q] * hull_a[g, top, 0])
            for v in range(1, n_v):
                for q in range(n):
                    s[q] = max(s[q], abs(hull_t[g, top, v] + j[q] * hull_a[g, top, v]))
            e_top = env_top[m, g]
            for q in range(n):
                req_p[q], av_p[q] = s[q] * tm, e_top
                mar_p[q] = e_top / req_p[q] - 1.0 if req_p[q] > 0.0 else math.inf
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
        req_s = g_speed[g, 0] * sm
        mar_motor_speed = w_m / req_s - 1.0 if req_s > 0.0 else math.inf
        req_gr = out_cubic * tm
        t_l = run_t / i
        for q in range(n):
            jq = j[q]
            # RMS torque against the continuous torque at the mean speed
            rms = math.sqrt(max(s_tt + 2.0 * jq * s_ta + jq * jq * s_aa, 0.0) / period)
            req_r = rms * rm
            mar_r = cont / req_r - 1.0 if req_r > 0.0 else math.inf
            # max speed against the motor's and the gearbox's (a NaN limit propagates, as numpy.minimum)
            lim = r_speed[q]
            by_row = lim < w_m or math.isnan(lim)
            av_s = lim if by_row else w_m
            mar_s = r_mar_speed[q] if by_row else mar_motor_speed
            # inertia ratio, the gearbox's input inertia on the load side
            ir = (j_l + r_j[q]) / j_m
            mar_i = limit / ir - 1.0 if ir > 0.0 else math.inf
            # gearbox: rated output torque against the cubic mean; what passes at the motor's peak
            direct = r_direct[q]
            mar_gr = r_mar_rated[q]
            req_gp = 0.0 if direct else ((1.0 - jq / (jq + j_l)) * (t_pk - t_l) + t_l) * i * g_eff[g]
            mar_gp = math.inf if direct else r_cap[q] / max(req_gp, 1e-300) - 1.0
            if listed:
                detail[PEAK, k], detail[RMS, k], detail[SPEED, k] = req_p[q], req_r, req_s * _RPM
                detail[INERTIA, k], detail[GB_RATED, k], detail[GB_PEAK, k] = ir, req_gr, req_gp
                a = N_CHECKS
                detail[a + PEAK, k], detail[a + RMS, k], detail[a + SPEED, k] = av_p[q], cont, av_s * _RPM
                detail[a + INERTIA, k], detail[a + GB_RATED, k], detail[a + GB_PEAK, k] = limit, r_rated[q], r_cap[q]
                a = 2 * N_CHECKS
                detail[a + PEAK, k], detail[a + RMS, k], detail[a + SPEED, k] = mar_p[q], mar_r, mar_s
                detail[a + INERTIA, k], detail[a + GB_RATED, k], detail[a + GB_PEAK, k] = mar_i, mar_gr, mar_gp
                detail[D_RMS, k], detail[D_PEAK, k], detail[D_INERTIA, k] = rms, peak_all[q], ir
            else:
                # worst margin (NaN if any is NaN) and the bits of the checks that do not pass
                mp = mar_p[q]
                w = mp
                w = mar_r if (mar_r < w or math.isnan(mar_r)) else w
                w = mar_s if (mar_s < w or math.isnan(mar_s)) else w
                w = mar_i if (mar_i < w or math.isnan(mar_i)) else w
                w = mar_gr if (mar_gr < w or math.isnan(mar_gr)) else w
                w = mar_gp if (mar_gp < w or math.isnan(mar_gp)) else w
                bits = ((not mp >= 0.0) * 1 | (not mar_r >= 0.0) * 2 | (not mar_s >= 0.0) * 4
                        | (not mar_i >= 0.0) * 8 | (not mar_gr >= 0.0) * 16 | (not mar_gp >= 0.0) * 32)
                motor[k], slot[k], worst[k], failed[k] = m, q0 + q, w, bits
            k += 1


@njit(**_OPTIONS)
def closest_failing(worst: NDArray[np.float64], failed: NDArray[np.uint8], n: int) -> NDArray[np.int64]:
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


__all__ = ["D_INERTIA", "D_PEAK", "D_RMS", "GB_PEAK", "GB_RATED", "INERTIA", "N_CHECKS", "N_DETAIL", "PEAK", "RMS",
           "SPEED", "check", "closest_failing"]
