"""The compiled fixed-step kernels (numba). Imported lazily by ``simulate``: importing this module
imports numba, which ``import drivetrain`` must never pay for.

Plant: N inertias joined by elasto-backlash springs (Modelica ``ElastoBacklash``), each inertia
with viscous damping to ground and friction (exponential Stribeck with exact stick, Modelica
``BearingFriction``; or the smooth tanh form), a lossy gear at the load end of any spring
(Modelica ``LossyGear``: efficiency by power direction, stuck at zero speed, self-locking),
constant load torque on the last inertia. Integrator: semi-implicit (symplectic) Euler,
speeds first, then angles from the new speeds; viscous terms and the positive slope of smooth
friction are taken linearly implicit. Controller: cascaded P position / PI velocity / first-order
current loop, each updated every ``n_pos``/``n_vel``/``n_cur`` steps (zero-order hold between).
The same kernel runs the plant open loop (``mode`` 1) from a given motor torque.

Two kernels with the same equations, each compiled on first use only (``cache=True``, one
specialisation each: the callers pass float64/int64 C-contiguous arrays only, and a test checks
that no second specialisation appears). No explicit signatures: with them numba would compile both
kernels as soon as this module is imported.

``run_two``   the two-mass chain (motor and load), the common servo case: the state lives in local
              scalars, which LLVM keeps in registers across the steps.
``run_chain`` any number of inertias, the state in arrays.

``tests/dynamics/test_dynamics_simulate.py`` runs both on the same two-mass axis and asserts they agree.

Size: the two kernels and the layout of their packed arguments (the ``N_*``, ``P_*``, ``I_*`` indices they
read as compile-time constants) stay in this one file. numba's cache is checked against the file that
holds each kernel only, and a global is frozen into the cached code: with the layout in another file, a
change to it would leave the cached kernels reading the old layout (numba docs, "Cache invalidation",
https://numba.readthedocs.io/en/stable/user/jit.html#cache). And the kernels call no helpers (below).

Compilation: the per-inertia friction/gear update is written once inside a loop over the inertias
(numba compiles it once; LLVM unrolls the two-inertia loop), and no helper functions are called, so
nothing is left as a call in the time loop and the first compile stays short. ``no_rewrites`` skips
numba's rewrite and dead-branch-pruning passes (array-expression fusion, constant folding of literal
arguments), which find nothing in this scalar code but cost 0.3-0.4 s of the first compile; the
compiled code is the same (bitwise-equal results, same speed). ``no_cfunc_wrapper``: the kernels are
only called from Python, so no C-callable wrapper is built.

``fastmath`` allows FMA contraction, reciprocal instead of division, approximate library functions,
reassociation and ignoring the sign of zero (``contract, arcp, afn, reassoc, nsz``): these change
results only at the rounding level. Measured on the benchmark's 10-s closed-loop run against the
same kernel compiled without fastmath: angles agree to 1e-15, speeds to 2e-13, torques to 5e-12 of
each series' largest value, far under the integrator's O(h) error; the kernel is about 15 % faster.
``nnan``/``ninf`` are not allowed, so a diverging run still shows as NaN/inf and is caught.

Arguments (packed so that one signature serves every model):
    plant   (N_PLANT, n): rows JM inertia [kg m^2], BG viscous damping to ground [N m s/rad], FC
            Coulomb [N m], FS breakaway [N m], FV friction viscous [N m s/rad], WS Stribeck speed
            [rad/s], FEXP Stribeck exponent
    fmeth   (n,): friction form, -1 none, 0 exponential with stick, 1 tanh
    spring  (N_SPRING, max(n - 1, 1)): rows KK stiffness [N m/rad], DD damping [N m s/rad], GAP
            backlash [rad], ETA, ETAB forward/backward gear efficiency at its load end
    tab_x, tab_k (t,): the last spring's stiffness tab_k [N m/rad] against the last inertia's angle
            tab_x [rad], strictly increasing (``Chain.spring_table``): with t >= 2 the spring's
            stiffness follows the load, interpolated linearly each step (held beyond the ends; the
            interval is tracked from the previous step, so the lookup costs O(1) per step); t < 2:
            the constant KK row, the code path of a chain without a table
    par     (N_PAR,): float parameters, see the P_* indices
    ipar    (N_IPAR,): integer parameters, see the I_* indices
    r_pos, r_vel, r_acc (n_steps + 1,): reference [rad, rad/s, rad/s^2] at each step
    u_ext   (n_steps + 1,) motor torque [N m] in open loop (mode 1); unused in closed loop
    theta, omega (n,): initial angles/speeds, overwritten with the final ones
    rec     (3 n + 2, n_steps // rec_every + 1): recorded samples, rows: n angles, n speeds, n - 1
            spring torques, motor torque, torque command, following error
    metrics (N_METRICS_BASE + max(n - 1, 1),): see below; accumulated into (start from zeros)
Returns (status, step, inertia): status 0 done, 1 diverged at that step and inertia.

Everything here is plain float64 arithmetic on preallocated arrays: no Python objects and no
allocation inside the time loop.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.jit import njit

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]

N_METRICS_BASE = 7
# metrics: 0 max|motor following error|, 1 max|load error|, 2 motor work [J], 3 peak |torque|,
# 4 integral of torque^2 dt, 5 final |load error|, 6 reserved (0); then the peak |shaft torque| of
# each spring.

JM, BG, FC, FS, FV, WS, FEXP = range(7)
N_PLANT = 7
KK, DD, GAP, ETA, ETAB = range(5)
N_SPRING = 5
# float parameters: step [s], load torque [N m], velocity kp [N m s/rad], ki = kp/Ti [N m/rad],
# position kv [1/s], speed and acceleration feed-forward, current-loop smoothing factor per current
# sample, notch biquad (b0, b1, b2, a1, a2), low-pass factor, torque limit [N m], encoder
# resolution [rad] (0: none), initial torque [N m], initial integrator [N m], divergence speed [rad/s]
(P_H, P_TLOAD, P_KP, P_KI, P_KV, P_KFFV, P_KFFA, P_ALPHA, P_NB0, P_NB1, P_NB2, P_NB3, P_NB4, P_LP, P_TLIM,
 P_Q, P_TM0, P_INTEG0, P_VLIM) = range(19)
N_PAR = 19
# integer parameters: steps, record every, mode (0 closed loop, 1 open loop), notch on, low-pass on,
# current/velocity/position loop periods in steps
I_STEPS, I_REC, I_MODE, I_NOTCH, I_LP, I_CUR, I_VEL, I_POS = range(8)
N_IPAR = 8

_SQ2 = 1.4142135623730951
_FAST = {"contract", "arcp", "afn", "reassoc", "nsz"}  # no nnan/ninf: the divergence test needs NaN
# numba options of both kernels (see the module docstring); no_rewrites and no_cfunc_wrapper are numba
# target options that its type stubs do not list
_OPTIONS: dict[str, Any] = {"cache": True, "fastmath": _FAST, "error_model": "numpy", "nogil": True,
                            "no_rewrites": True, "no_cfunc_wrapper": True}


@njit(**_OPTIONS)
def run_two(plant: F64, fmeth: I64, spring: F64, tab_x: F64, tab_k: F64, par: F64, ipar: I64, r_pos: F64,
            r_vel: F64, r_acc: F64, u_ext: F64, theta: F64, omega: F64, rec: F64, metrics: F64) -> tuple[int, int, int]:
    """Two inertias (motor ``a``, load ``b``) joined by one spring; state in scalars."""
    h = par[P_H]
    t_load = par[P_TLOAD]
    kp = par[P_KP]
    ki = par[P_KI]
    kv = par[P_KV]
    kffv = par[P_KFFV]
    kffa = par[P_KFFA]
    alpha_c = par[P_ALPHA]
    nb0 = par[P_NB0]
    nb1 = par[P_NB1]
    nb2 = par[P_NB2]
    nb3 = par[P_NB3]
    nb4 = par[P_NB4]
    lp_alpha = par[P_LP]
    tlim = par[P_TLIM]
    q = par[P_Q]
    speed_limit = par[P_VLIM]
    n_steps = ipar[I_STEPS]
    rec_every = ipar[I_REC]
    closed = ipar[I_MODE] == 0
    notch_on = ipar[I_NOTCH] != 0
    lp_on = ipar[I_LP] != 0
    n_cur = ipar[I_CUR]
    n_vel = ipar[I_VEL]
    n_pos = ipar[I_POS]
    ks = spring[KK, 0]
    ds = spring[DD, 0]
    n_tab = tab_x.size
    it = 0
    b2 = 0.5 * spring[GAP, 0]
    eta = spring[ETA, 0]
    eta_b = spring[ETAB, 0]
    gear_b = eta < 1.0 or eta_b < 1.0
    visc = np.empty(2)
    jlin = np.empty(2)
    inv_den = np.empty(2)
    inv_ws = np.empty(2)
    inv_wst = np.empty(2)
    for j in range(2):
        visc[j] = plant[BG, j] + plant[FV, j]
        jlin[j] = plant[JM, j] + h * visc[j]  # viscous terms taken linearly implicit
        inv_den[j] = 1.0 / jlin[j]
        inv_ws[j] = 1.0 / plant[WS, j]
        inv_wst[j] = inv_ws[j] / _SQ2
    sq2e = math.sqrt(2.0 * math.e)
    tha = theta[0]
    thb = theta[1]
    wa = omega[0]
    wb = omega[1]
    t_m = par[P_TM0]
    t_cmd = t_m
    w_cmd = 0.0
    integ = par[P_INTEG0]
    x1 = integ
    x2 = integ
    y1 = integ
    y2 = integ
    lp = integ
    inv_q = 1.0 / q if q > 0.0 else 0.0
    th_meas = tha if q <= 0.0 else q * math.floor(tha * inv_q + 0.5)
    th_prev = th_meas
    t_vel = n_vel * h
    inv_tvel = 1.0 / t_vel
    m0 = metrics[0]
    m1 = metrics[1]
    work = metrics[2]
    m3 = metrics[3]
    t2 = metrics[4]
    peak = metrics[N_METRICS_BASE]
    c_pos = 0
    c_vel = 0
    c_cur = 0
    c_rec = 0
    r = 0
    ferr = 0.0
    for k in range(n_steps + 1):
        # ---- controller (sampled; counters instead of k % n) ----
        if closed:
            do_pos = c_pos == 0
            do_vel = c_vel == 0
            c_pos = c_pos + 1 if c_pos + 1 < n_pos else 0
            c_vel = c_vel + 1 if c_vel + 1 < n_vel else 0
            if do_pos or do_vel:
                th_meas = tha if q <= 0.0 else q * math.floor(tha * inv_q + 0.5)
            if do_pos:
                # the drive's following error: reference and measurement at the same sample instant
                ferr = r_pos[k] - th_meas
                w_cmd = kv * ferr + kffv * r_vel[k]
            if do_vel:
                w_meas = wa if k == 0 else (th_meas - th_prev) * inv_tvel
                th_prev = th_meas
                ev = w_cmd - w_meas
                integ_try = integ + ki * ev * t_vel
                u = kp * ev + integ_try
                if notch_on:
                    y = nb0 * u + nb1 * x1 + nb2 * x2 - nb3 * y1 - nb4 * y2
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
                        integ = integ_try  # anti-windup: integrate only away from the limit
                elif u < -tlim:
                    u = -tlim
                    if ev > 0.0:
                        integ = integ_try
                else:
                    integ = integ_try
                t_cmd = u
            if c_cur == 0:
                t_m += alpha_c * (t_cmd - t_m)
            c_cur = c_cur + 1 if c_cur + 1 < n_cur else 0
        else:
            t_m = u_ext[k]
            t_cmd = t_m
            th_meas = tha if q <= 0.0 else q * math.floor(tha * inv_q + 0.5)
            ferr = r_pos[k] - th_meas
        # ---- spring torque (ElastoBacklash: none in the gap, never pulling, continuous) ----
        if n_tab >= 2:  # stiffness at the load's position (Chain.spring_table)
            while it < n_tab - 2 and thb > tab_x[it + 1]:
                it += 1
            while it > 0 and thb < tab_x[it]:
                it -= 1
            if thb <= tab_x[0]:
                ks = tab_k[0]
            elif thb >= tab_x[n_tab - 1]:
                ks = tab_k[n_tab - 1]
            else:
                ks = tab_k[it] + (tab_k[it + 1] - tab_k[it]) * (thb - tab_x[it]) / (tab_x[it + 1] - tab_x[it])
        rel = tha - thb
        shaft = 0.0
        if b2 <= 0.0:
            shaft = ks * rel + ds * (wa - wb)
        elif rel > b2 or rel < -b2:
            tc = ks * (rel - b2) if rel > 0.0 else ks * (rel + b2)
            td = ds * (wa - wb)
            if tc > 0.0:
                shaft = 0.0 if tc + td <= 0.0 else tc + min(tc, td)
            else:
                shaft = 0.0 if tc + td >= 0.0 else tc + max(tc, td)
        # ---- record the state at t_k ----
        lerr = r_pos[k] - thb
        if c_rec == 0:
            rec[0, r] = tha
            rec[1, r] = thb
            rec[2, r] = wa
            rec[3, r] = wb
            rec[4, r] = shaft
            rec[5, r] = t_m
            rec[6, r] = t_cmd
            rec[7, r] = ferr
            r += 1
        c_rec = c_rec + 1 if c_rec + 1 < rec_every else 0
        m0 = max(m0, abs(ferr))
        m1 = max(m1, abs(lerr))
        m3 = max(m3, abs(t_m))
        peak = max(peak, abs(shaft))
        if k == n_steps:
            metrics[5] = abs(lerr)
            break
        t2 += t_m * t_m * h
        # ---- speeds: semi-implicit Euler, from the state at t_k ----
        wn_a = 0.0
        for j in range(2):
            w = wa if j == 0 else wb
            ts = 0.0 if j == 0 else shaft  # spring torque arriving from the motor side
            rest = -visc[j] * w + (t_m - shaft if j == 0 else -t_load)
            gear = j == 1 and gear_b
            fm = fmeth[j]
            fc = plant[FC, j]
            fs = plant[FS, j]
            ws = plant[WS, j]
            if fm == 0 or gear:  # exact stick state (BearingFriction; LossyGear stuck at zero speed)
                if w != 0.0:
                    d = 1.0 if w > 0.0 else -1.0
                    tg = ts
                    locked = False
                    if gear:
                        if ts * d > 0.0:
                            tg = eta * ts  # forward: the spring drives the load, output = eta * input
                        elif eta_b > 0.0:
                            tg = ts / eta_b  # backward: the load drives back, input = eta_b * output
                        else:
                            locked = True  # self-locking: the load cannot drive the input
                    wn = 0.0
                    if not locked:
                        aw = abs(w)
                        fr = 0.0
                        if fm == 0:
                            x = aw / ws
                            x = x * x if plant[FEXP, j] == 2.0 else x ** plant[FEXP, j]
                            # beyond x = 40 the Stribeck term is below 4e-18 of (T_S - T_C): skip exp
                            fr = fc + (fs - fc) * math.exp(-x) if x < 40.0 else fc
                        elif fm == 1:
                            x = aw / (_SQ2 * ws)
                            fr = sq2e * (fs - fc) * math.exp(-x * x) * x if x < 7.0 else 0.0
                            fr += fc * (math.tanh(10.0 * aw / ws) if aw < 2.0 * ws else 1.0)
                        wn = w + h * (rest + tg - d * fr) * inv_den[j]
                        if wn * d < 0.0:
                            wn = 0.0  # friction cannot reverse the motion: stick
                else:
                    wn = 0.0
                    brk = fs if fm == 0 else 0.0
                    for s in range(2):
                        d = 1.0 if s == 0 else -1.0
                        tg = ts
                        if gear:
                            if ts * d > 0.0:
                                tg = eta * ts
                            elif eta_b > 0.0:
                                tg = ts / eta_b
                            else:
                                continue
                        if d * (rest + tg) > brk:  # breakaway
                            wn = h * (rest + tg - d * brk) * inv_den[j]
                            break
            else:  # smooth (tanh) friction or none; its positive slope taken linearly implicit
                tot = rest + ts
                den_inv = inv_den[j]
                if fm == 1:
                    x = w * inv_wst[j]
                    if abs(x) < 7.0:
                        ex = sq2e * (fs - fc) * math.exp(-x * x)
                        th = math.tanh(10.0 * w * inv_ws[j]) if abs(w) < 2.0 * ws else (1.0 if w > 0.0 else -1.0)
                        tot -= ex * x + fc * th
                        slope = ex * (1.0 - 2.0 * x * x) * inv_wst[j] + fc * (1.0 - th * th) * 10.0 * inv_ws[j]
                        if slope > 0.0:
                            den_inv = 1.0 / (jlin[j] + h * slope)
                    else:
                        tot -= fc if w > 0.0 else -fc
                wn = w + h * tot * den_inv
            if not (abs(wn) < speed_limit):
                metrics[0] = m0
                metrics[1] = m1
                metrics[2] = work
                metrics[3] = m3
                metrics[4] = t2
                metrics[N_METRICS_BASE] = peak
                return 1, k, j
            if j == 0:
                wn_a = wn
                work += t_m * wn * h
            else:
                wb = wn
        wa = wn_a
        tha += h * wa
        thb += h * wb
    theta[0] = tha
    theta[1] = thb
    omega[0] = wa
    omega[1] = wb
    metrics[0] = m0
    metrics[1] = m1
    metrics[2] = work
    metrics[3] = m3
    metrics[4] = t2
    metrics[N_METRICS_BASE] = peak
    return 0, n_steps, -1


@njit(**_OPTIONS)
def run_chain(plant: F64, fmeth: I64, spring: F64, tab_x: F64, tab_k: F64, par: F64, ipar: I64,
              r_pos: F64, r_vel: F64, r_acc: F64, u_ext: F64, theta: F64, omega: F64, rec: F64,
              metrics: F64) -> tuple[int, int, int]:
    """Any number of inertias; the same equations as ``run_two`` with the state in arrays."""
    h = par[P_H]
    t_load = par[P_TLOAD]
    kp = par[P_KP]
    ki = par[P_KI]
    kv = par[P_KV]
    kffv = par[P_KFFV]
    kffa = par[P_KFFA]
    alpha_c = par[P_ALPHA]
    nb0 = par[P_NB0]
    nb1 = par[P_NB1]
    nb2 = par[P_NB2]
    nb3 = par[P_NB3]
    nb4 = par[P_NB4]
    lp_alpha = par[P_LP]
    tlim = par[P_TLIM]
    q = par[P_Q]
    speed_limit = par[P_VLIM]
    n_steps = ipar[I_STEPS]
    rec_every = ipar[I_REC]
    closed = ipar[I_MODE] == 0
    notch_on = ipar[I_NOTCH] != 0
    lp_on = ipar[I_LP] != 0
    n_cur = ipar[I_CUR]
    n_vel = ipar[I_VEL]
    n_pos = ipar[I_POS]
    n = theta.size
    m = n - 1
    row_w = n
    row_s = 2 * n
    row_t = 2 * n + m
    shaft = np.zeros(max(m, 1))
    peak = np.zeros(max(m, 1))
    n_tab = tab_x.size if m >= 1 else 0
    it = 0
    k_last = spring[KK, max(m - 1, 0)]
    for e in range(m):
        peak[e] = metrics[N_METRICS_BASE + e]
    visc = np.empty(n)
    jlin = np.empty(n)
    inv_den = np.empty(n)
    inv_ws = np.empty(n)
    inv_wst = np.empty(n)
    for j in range(n):
        visc[j] = plant[BG, j] + plant[FV, j]
        jlin[j] = plant[JM, j] + h * visc[j]
        inv_den[j] = 1.0 / jlin[j]
        inv_ws[j] = 1.0 / plant[WS, j]
        inv_wst[j] = inv_ws[j] / _SQ2
    sq2e = math.sqrt(2.0 * math.e)
    t_m = par[P_TM0]
    t_cmd = t_m
    w_cmd = 0.0
    integ = par[P_INTEG0]
    x1 = integ
    x2 = integ
    y1 = integ
    y2 = integ
    lp = integ
    inv_q = 1.0 / q if q > 0.0 else 0.0
    th_meas = theta[0] if q <= 0.0 else q * math.floor(theta[0] * inv_q + 0.5)
    th_prev = th_meas
    t_vel = n_vel * h
    inv_tvel = 1.0 / t_vel
    m0 = metrics[0]
    m1 = metrics[1]
    work = metrics[2]
    m3 = metrics[3]
    t2 = metrics[4]
    c_pos = 0
    c_vel = 0
    c_cur = 0
    c_rec = 0
    r = 0
    ferr = 0.0
    for k in range(n_steps + 1):
        tha = theta[0]
        if closed:
            do_pos = c_pos == 0
            do_vel = c_vel == 0
            c_pos = c_pos + 1 if c_pos + 1 < n_pos else 0
            c_vel = c_vel + 1 if c_vel + 1 < n_vel else 0
            if do_pos or do_vel:
                th_meas = tha if q <= 0.0 else q * math.floor(tha * inv_q + 0.5)
            if do_pos:
                ferr = r_pos[k] - th_meas
                w_cmd = kv * ferr + kffv * r_vel[k]
            if do_vel:
                w_meas = omega[0] if k == 0 else (th_meas - th_prev) * inv_tvel
                th_prev = th_meas
                ev = w_cmd - w_meas
                integ_try = integ + ki * ev * t_vel
                u = kp * ev + integ_try
                if notch_on:
                    y = nb0 * u + nb1 * x1 + nb2 * x2 - nb3 * y1 - nb4 * y2
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
            if c_cur == 0:
                t_m += alpha_c * (t_cmd - t_m)
            c_cur = c_cur + 1 if c_cur + 1 < n_cur else 0
        else:
            t_m = u_ext[k]
            t_cmd = t_m
            th_meas = tha if q <= 0.0 else q * math.floor(tha * inv_q + 0.5)
            ferr = r_pos[k] - th_meas
        if n_tab >= 2:  # the last spring's stiffness at the load's position (Chain.spring_table)
            thl = theta[m]
            while it < n_tab - 2 and thl > tab_x[it + 1]:
                it += 1
            while it > 0 and thl < tab_x[it]:
                it -= 1
            if thl <= tab_x[0]:
                k_last = tab_k[0]
            elif thl >= tab_x[n_tab - 1]:
                k_last = tab_k[n_tab - 1]
            else:
                k_last = tab_k[it] + (tab_k[it + 1] - tab_k[it]) * (thl - tab_x[it]) / (tab_x[it + 1] - tab_x[it])
        for e in range(m):
            rel = theta[e] - theta[e + 1]
            b2 = 0.5 * spring[GAP, e]
            ks = k_last if e == m - 1 and n_tab >= 2 else spring[KK, e]
            ds = spring[DD, e]
            tau = 0.0
            if b2 <= 0.0:
                tau = ks * rel + ds * (omega[e] - omega[e + 1])
            elif rel > b2 or rel < -b2:
                tc = ks * (rel - b2) if rel > 0.0 else ks * (rel + b2)
                td = ds * (omega[e] - omega[e + 1])
                if tc > 0.0:
                    tau = 0.0 if tc + td <= 0.0 else tc + min(tc, td)
                else:
                    tau = 0.0 if tc + td >= 0.0 else tc + max(tc, td)
            shaft[e] = tau
        lerr = r_pos[k] - theta[m]
        if c_rec == 0:
            for j in range(n):
                rec[j, r] = theta[j]
                rec[row_w + j, r] = omega[j]
            for e in range(m):
                rec[row_s + e, r] = shaft[e]
            rec[row_t, r] = t_m
            rec[row_t + 1, r] = t_cmd
            rec[row_t + 2, r] = ferr
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
        for j in range(n):
            w = omega[j]
            ts = shaft[j - 1] if j > 0 else 0.0
            drive = t_m if j == 0 else 0.0
            if j < m:
                drive -= shaft[j]
            if j == m:
                drive -= t_load
            rest = -visc[j] * w + drive
            gear = j > 0 and (spring[ETA, j - 1] < 1.0 or spring[ETAB, j - 1] < 1.0)
            eta = spring[ETA, j - 1] if j > 0 else 1.0
            eta_b = spring[ETAB, j - 1] if j > 0 else 1.0
            fm = fmeth[j]
            fc = plant[FC, j]
            fs = plant[FS, j]
            ws = plant[WS, j]
            if fm == 0 or gear:
                if w != 0.0:
                    d = 1.0 if w > 0.0 else -1.0
                    tg = ts
                    locked = False
                    if gear:
                        if ts * d > 0.0:
                            tg = eta * ts
                        elif eta_b > 0.0:
                            tg = ts / eta_b
                        else:
                            locked = True
                    wn = 0.0
                    if not locked:
                        aw = abs(w)
                        fr = 0.0
                        if fm == 0:
                            x = aw / ws
                            x = x * x if plant[FEXP, j] == 2.0 else x ** plant[FEXP, j]
                            fr = fc + (fs - fc) * math.exp(-x) if x < 40.0 else fc
                        elif fm == 1:
                            x = aw / (_SQ2 * ws)
                            fr = sq2e * (fs - fc) * math.exp(-x * x) * x if x < 7.0 else 0.0
                            fr += fc * (math.tanh(10.0 * aw / ws) if aw < 2.0 * ws else 1.0)
                        wn = w + h * (rest + tg - d * fr) * inv_den[j]
                        if wn * d < 0.0:
                            wn = 0.0
                else:
                    wn = 0.0
                    brk = fs if fm == 0 else 0.0
                    for s in range(2):
                        d = 1.0 if s == 0 else -1.0
                        tg = ts
                        if gear:
                            if ts * d > 0.0:
                                tg = eta * ts
                            elif eta_b > 0.0:
                                tg = ts / eta_b
                            else:
                                continue
                        if d * (rest + tg) > brk:
                            wn = h * (rest + tg - d * brk) * inv_den[j]
                            break
            else:
                tot = rest + ts
                den_inv = inv_den[j]
                if fm == 1:
                    x = w * inv_wst[j]
                    if abs(x) < 7.0:
                        ex = sq2e * (fs - fc) * math.exp(-x * x)
                        th = math.tanh(10.0 * w * inv_ws[j]) if abs(w) < 2.0 * ws else (1.0 if w > 0.0 else -1.0)
                        tot -= ex * x + fc * th
                        slope = ex * (1.0 - 2.0 * x * x) * inv_wst[j] + fc * (1.0 - th * th) * 10.0 * inv_ws[j]
                        if slope > 0.0:
                            den_inv = 1.0 / (jlin[j] + h * slope)
                    else:
                        tot -= fc if w > 0.0 else -fc
                wn = w + h * tot * den_inv
            if not (abs(wn) < speed_limit):
                metrics[0] = m0
                metrics[1] = m1
                metrics[2] = work
                metrics[3] = m3
                metrics[4] = t2
                for e in range(m):
                    metrics[N_METRICS_BASE + e] = peak[e]
                return 1, k, j
            if j == 0:
                work += t_m * wn * h
            omega[j] = wn  # shaft[] already holds the torques at t_k: in-place is safe
        for j in range(n):
            theta[j] += h * omega[j]
    metrics[0] = m0
    metrics[1] = m1
    metrics[2] = work
    metrics[3] = m3
    metrics[4] = t2
    for e in range(m):
        metrics[N_METRICS_BASE + e] = peak[e]
    return 0, n_steps, -1
