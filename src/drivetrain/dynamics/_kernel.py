"""The compiled fixed-step kernel (numba). Imported lazily by ``simulate``: importing this module
imports numba, which ``import drivetrain`` must never pay for.

Plant: N inertias joined by elasto-backlash springs (Modelica ``ElastoBacklash``), each inertia
with viscous damping to ground and friction (exponential Stribeck with exact stick, Modelica
``BearingFriction``; or the smooth tanh form), a lossy gear at the load end of any spring
(Modelica ``LossyGear``: efficiency by power direction, stuck at zero speed, self-locking),
constant load torque on the last inertia. Integrator: semi-implicit (symplectic) Euler,
speeds first, then angles from the new speeds; viscous terms and the positive slope of smooth
friction are taken linearly implicit. Controller: cascaded P position / PI velocity / first-order
current loop, each updated every ``n_pos``/``n_vel``/``n_cur`` steps (zero-order hold between).

Everything here is plain float64 arithmetic on preallocated arrays: no Python objects and no
allocation inside the time loop.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from numpy.typing import NDArray

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]

N_METRICS_BASE = 7
# metrics: 0 max|motor following error|, 1 max|load error|, 2 motor work [J], 3 peak |torque|,
# 4 integral of torque^2 dt, 5 final |load error|, 6 friction+gear+damping dissipation is not
# tracked (reserved, 0); then the peak |shaft torque| of each spring.


_FAST = {"contract", "arcp", "afn", "reassoc", "nsz"}  # no nnan/ninf: the divergence test needs NaN


@njit(cache=True, fastmath=_FAST, error_model="numpy")
def _gear_out(ts: float, d: float, eta: float, eta_b: float) -> tuple[float, bool]:
    """Torque a lossy gear delivers to its output inertia moving (or about to move) in direction d."""
    if ts * d > 0.0:
        return eta * ts, False  # forward: the spring drives the load, output = eta * input
    if eta_b > 0.0:
        return ts / eta_b, False  # backward: the load drives back, input = eta_b * output
    return 0.0, True  # self-locking: the load cannot drive the input


@njit(cache=True, fastmath=_FAST, error_model="numpy")
def run_kernel(
    h: float, n_steps: int, rec_every: int,
    jm: F64, bg: F64, kk: F64, dd: F64, gap: F64, eta: F64, eta_b: F64,
    fc: F64, fs: F64, fv: F64, ws: F64, fexp: F64, fmeth: I64,
    t_load: float,
    mode: int, kp: float, ki: float, kv: float, kffv: float, kffa: float, alpha_c: float,
    nb: F64, notch_on: bool, lp_alpha: float, lp_on: bool, tlim: float,
    n_cur: int, n_vel: int, n_pos: int, q: float,
    r_pos: F64, r_vel: F64, r_acc: F64, u_ext: F64,
    theta: F64, omega: F64, t_m0: float, integ0: float,
    speed_limit: float,
    out_theta: F64, out_omega: F64, out_torque: F64, out_cmd: F64, out_shaft: F64, out_ferr: F64,
    metrics: F64,
) -> tuple[int, int, int]:
    n = jm.size
    m = n - 1
    shaft = np.zeros(max(m, 1))
    peak = np.zeros(max(m, 1))
    stick = np.zeros(n, dtype=np.bool_)
    gear = np.zeros(n, dtype=np.bool_)
    for j in range(n):
        if j > 0 and (eta[j - 1] < 1.0 or eta_b[j - 1] < 1.0):
            gear[j] = True
        stick[j] = fmeth[j] == 0 or gear[j]
    t_m = t_m0
    t_cmd = t_m0
    w_cmd = 0.0
    integ = integ0
    x1 = integ0
    x2 = integ0
    y1 = integ0
    y2 = integ0
    lp = integ0
    th_meas = theta[0] if q <= 0.0 else q * math.floor(theta[0] / q + 0.5)
    th_prev = th_meas
    t_vel = n_vel * h
    sq2e = math.sqrt(2.0 * math.e)
    inv_den = np.empty(n)
    for j in range(n):
        inv_den[j] = 1.0 / (jm[j] + h * (bg[j] + fv[j]))
    inv_ws = 1.0 / ws
    inv_wst = inv_ws / 1.4142135623730951
    inv_q = 1.0 / q if q > 0.0 else 0.0
    inv_tvel = 1.0 / t_vel
    m0 = metrics[0]
    m1 = metrics[1]
    m3 = metrics[3]
    work = metrics[2]
    t2 = metrics[4]
    c_pos = 0
    c_vel = 0
    c_cur = 0
    c_rec = 0
    r = 0
    ferr_s = 0.0
    for k in range(n_steps + 1):
        # ---- controller (sampled; counters instead of k % n) ----
        if mode == 0:
            do_pos = c_pos == 0
            do_vel = c_vel == 0
            do_cur = c_cur == 0
            c_pos = c_pos + 1 if c_pos + 1 < n_pos else 0
            c_vel = c_vel + 1 if c_vel + 1 < n_vel else 0
            c_cur = c_cur + 1 if c_cur + 1 < n_cur else 0
            if do_pos or do_vel:
                th_meas = theta[0] if q <= 0.0 else q * math.floor(theta[0] * inv_q + 0.5)
            if do_pos:
                # The drive's following error: reference and measurement at the same sample instant.
                ferr_s = r_pos[k] - th_meas
                w_cmd = kv * ferr_s + kffv * r_vel[k]
            if do_vel:
                w_meas = omega[0] if k == 0 else (th_meas - th_prev) * inv_tvel
                th_prev = th_meas
                ev = w_cmd - w_meas
                integ_try = integ + ki * ev * t_vel
                u = kp * ev + integ_try
                if notch_on:
                    y = nb[0] * u + nb[1] * x1 + nb[2] * x2 - nb[3] * y1 - nb[4] * y2
                    x2 = x1
                    x1 = u
                    y2 = y1
                    y1 = y
                    u = y
                if lp_on:
                    lp += lp_alpha * (u - lp)
                    u = lp
                u += kffa * r_acc[k]
                if u > tlim:
                    u = tlim
                    if ev < 0.0:
                        integ = integ_try
                elif u < -tlim:
                    u = -tlim
                    if ev > 0.0:
                        integ = integ_try
                else:
                    integ = integ_try
                t_cmd = u
            if do_cur:
                t_m += alpha_c * (t_cmd - t_m)
        else:
            t_m = u_ext[k]
            t_cmd = t_m
            th_meas = theta[0] if q <= 0.0 else q * math.floor(theta[0] / q + 0.5)
            ferr_s = r_pos[k] - th_meas
        # ---- spring torques (ElastoBacklash) ----
        for e in range(m):
            rel = theta[e] - theta[e + 1]
            wrel = omega[e] - omega[e + 1]
            b2 = 0.5 * gap[e]
            if b2 <= 0.0:
                tau = kk[e] * rel + dd[e] * wrel
            elif rel > b2:
                tc = kk[e] * (rel - b2)
                td = dd[e] * wrel
                tau = 0.0 if tc + td <= 0.0 else tc + min(tc, td)
            elif rel < -b2:
                tc = kk[e] * (rel + b2)
                td = dd[e] * wrel
                tau = 0.0 if tc + td >= 0.0 else tc + max(tc, td)
            else:
                tau = 0.0
            shaft[e] = tau
        # ---- record the state at t_k ----
        ferr = ferr_s
        lerr = r_pos[k] - theta[n - 1]
        if c_rec == 0:
            for j in range(n):
                out_theta[r, j] = theta[j]
                out_omega[r, j] = omega[j]
            for e in range(m):
                out_shaft[r, e] = shaft[e]
            out_torque[r] = t_m
            out_cmd[r] = t_cmd
            out_ferr[r] = ferr
            r += 1
        c_rec = c_rec + 1 if c_rec + 1 < rec_every else 0
        m0 = max(m0, abs(ferr))
        m1 = max(m1, abs(lerr))
        m3 = max(m3, abs(t_m))
        for e in range(m):
            peak[e] = max(peak[e], abs(shaft[e]))
        if k == n_steps:
            metrics[5] = abs(lerr)
            break
        t2 += t_m * t_m * h
        # ---- speeds: semi-implicit Euler ----
        for j in range(n):
            w = omega[j]
            rest = -bg[j] * w - fv[j] * w
            if j == 0:
                rest += t_m
            if j == n - 1:
                rest -= t_load
            if j < m:
                rest -= shaft[j]
            ts = shaft[j - 1] if j > 0 else 0.0
            lin = h * (bg[j] + fv[j])  # viscous terms taken linearly implicit
            if stick[j]:
                brk = fs[j] if fmeth[j] == 0 else 0.0
                if w != 0.0:
                    d = 1.0 if w > 0.0 else -1.0
                    if gear[j]:
                        tg, locked = _gear_out(ts, d, eta[j - 1], eta_b[j - 1])
                    else:
                        tg, locked = ts, False
                    if locked:
                        wn = 0.0
                    else:
                        aw = abs(w)
                        if fmeth[j] == 0:
                            x = aw / ws[j]
                            x = x * x if fexp[j] == 2.0 else x ** fexp[j]
                            # beyond x = 40 the Stribeck term is below 4e-18 of (T_S - T_C): skip exp
                            fr = fc[j] + (fs[j] - fc[j]) * math.exp(-x) if x < 40.0 else fc[j]
                        elif fmeth[j] == 1:
                            x = aw / (1.4142135623730951 * ws[j])
                            hump = sq2e * (fs[j] - fc[j]) * math.exp(-x * x) * x if x < 7.0 else 0.0
                            fr = hump + fc[j] * (math.tanh(10.0 * aw / ws[j]) if aw < 2.0 * ws[j] else 1.0)
                        else:
                            fr = 0.0
                        wn = w + h * (rest + tg - d * fr) * inv_den[j]
                        if wn * d < 0.0:
                            wn = 0.0  # friction cannot reverse the motion: stick
                else:
                    wn = 0.0
                    for s in range(2):
                        d = 1.0 if s == 0 else -1.0
                        if gear[j]:
                            tg, locked = _gear_out(ts, d, eta[j - 1], eta_b[j - 1])
                        else:
                            tg, locked = ts, False
                        if locked:
                            continue
                        net = rest + tg
                        if d * net > brk:
                            wn = h * (net - d * brk) * inv_den[j]
                            break
            else:
                tot = rest + ts
                slope = 0.0
                if fmeth[j] == 1:
                    x = w * inv_wst[j]
                    if abs(x) < 7.0:
                        ex = math.exp(-x * x)
                        th = math.tanh(10.0 * w * inv_ws[j]) if abs(w) < 2.0 * ws[j] else (1.0 if w > 0.0 else -1.0)
                        tot -= sq2e * (fs[j] - fc[j]) * ex * x + fc[j] * th
                        slope = sq2e * (fs[j] - fc[j]) * ex * (1.0 - 2.0 * x * x) * inv_wst[j] + fc[j] * (
                            1.0 - th * th) * 10.0 * inv_ws[j]
                        if slope < 0.0:
                            slope = 0.0
                    else:
                        tot -= fc[j] if w > 0.0 else -fc[j]
                wn = w + h * tot * (inv_den[j] if slope == 0.0 else 1.0 / (jm[j] + lin + h * slope))
            if not (abs(wn) < speed_limit):
                metrics[0], metrics[1], metrics[2], metrics[3], metrics[4] = m0, m1, work, m3, t2
                return 1, k, j
            if j == 0:
                work += t_m * wn * h
            omega[j] = wn
        for j in range(n):
            theta[j] += h * omega[j]
    metrics[0], metrics[1], metrics[2], metrics[3], metrics[4] = m0, m1, work, m3, t2
    for e in range(m):
        metrics[N_METRICS_BASE + e] = max(metrics[N_METRICS_BASE + e], peak[e])
    return 0, n_steps, -1


@njit(cache=True, parallel=True, error_model="numpy")
def run_batch(
    h: float, n_steps: int,
    jm: F64, bg: F64, kk_sets: F64, dd: F64, gap: F64, eta: F64, eta_b: F64,
    fc: F64, fs: F64, fv: F64, ws: F64, fexp: F64, fmeth: I64,
    t_load: float,
    gains: F64, kffv: float, kffa: float, alpha_c: float,
    nb: F64, notch_on: bool, lp_alpha: float, lp_on: bool, tlim: float,
    n_cur: int, n_vel: int, n_pos: int, q: float,
    r_pos: F64, r_vel: F64, r_acc: F64,
    theta0: F64, omega0: F64, t_m0: float, integ0: float,
    speed_limit: float,
    metrics: F64, status: I64,
) -> None:
    """Many closed-loop runs in parallel (prange); row s uses stiffness ``kk_sets[s]`` and gains
    ``gains[s] = (kp, ki, kv)``; only the metrics are kept."""
    n_sims = kk_sets.shape[0]
    n = jm.size
    m = n - 1
    dummy_u = np.zeros(1)
    for s in prange(n_sims):
        theta = theta0.copy()
        omega = omega0.copy()
        out_theta = np.empty((1, n))
        out_omega = np.empty((1, n))
        out_torque = np.empty(1)
        out_cmd = np.empty(1)
        out_shaft = np.empty((1, max(m, 1)))
        out_ferr = np.empty(1)
        met = np.zeros(metrics.shape[1])
        st, _, _ = run_kernel(
            h, n_steps, n_steps + 1,
            jm, bg, kk_sets[s], dd, gap, eta, eta_b, fc, fs, fv, ws, fexp, fmeth, t_load,
            0, gains[s, 0], gains[s, 1], gains[s, 2], kffv, kffa, alpha_c, nb, notch_on, lp_alpha, lp_on, tlim,
            n_cur, n_vel, n_pos, q, r_pos, r_vel, r_acc, dummy_u,
            theta, omega, t_m0, integ0, speed_limit,
            out_theta, out_omega, out_torque, out_cmd, out_shaft, out_ferr, met,
        )
        for i in range(met.size):
            metrics[s, i] = met[i]
        status[s] = st
