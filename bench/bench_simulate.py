"""Benchmark: the compiled closed-loop simulation against python-control and scipy.

Run: ``.venv/bin/python bench/bench_simulate.py [--span SECONDS] [--sims N]``. Prints markdown tables.

Model (issue 6): two-mass axis, motor 1e-4 kg m^2, load 5e-4 kg m^2, spring 500 N m/rad (damping
0.002 N m s/rad), 1 mrad backlash (ElastoBacklash), Stribeck friction on both inertias
(Coulomb 0.02 N m, breakaway 0.03 N m, viscous 1e-5 N m s/rad, Stribeck speed 1 rad/s), under the
cascaded loop tuned by ``tune`` at a 10 kHz step, following back-and-forth 10 rad moves for 10 s.

Comparison: python-control's ``input_output_response`` (a ``NonlinearIOSystem``) and scipy's
``solve_ivp`` integrate the same equations with the controller in continuous time; our kernel runs
the same model with every loop updated at each 0.1 ms step and the smooth (tanh) Stribeck form, so
the three agree up to the fixed step's O(h) error. The stick (exponential) form is timed too. The
slow integrators run a shorter span (``--span``) and their time is scaled to 10 s.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from typing import Any

import numpy as np

from drivetrain.dynamics import Friction, move_reference, simulate, sweep, tune, two_mass_chain
from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import ServoLoop
from drivetrain.dynamics.simulation import Reference

H = 1e-4
T_END = 10.0
JM, JL, K, D, GAP = 1e-4, 5e-4, 500.0, 0.002, 1e-3
TC, TS, BV, WS = 0.02, 0.03, 1e-5, 1.0


def model(method: str) -> Chain:
    fr = Friction(coulomb=TC, static=TS, viscous=BV, stribeck_speed=WS, method=method)
    return two_mass_chain(JM, JL, K, damping=D, backlash=GAP).with_(friction=(fr, fr))


def comparison_loop(chain: Chain) -> ServoLoop:
    return tune(chain, current_sample_time=H, velocity_sample_time=H, position_sample_time=H)


def reference() -> Reference:
    return move_reference(10.0, 100.0, 2000.0, dwell=0.2, repeat=14, step=H)


def rhs_factory(loop: ServoLoop, ref: Reference, h: float = H) -> Any:
    """The same model as the kernel, continuous controller: x = [th_m, th_l, w_m, w_l, I, T]."""
    kp = loop.velocity_kp
    ki = kp / loop.velocity_ti
    kv = loop.position_kv
    kffv, kffa = loop.velocity_ff, loop.acceleration_ff
    wc = 2 * math.pi * loop.current_bandwidth_hz
    sq2e = math.sqrt(2 * math.e)
    wst = math.sqrt(2) * WS
    tr, xr, vr, ar = ref.time, ref.position, ref.speed, ref.acceleration

    def fric(w: float) -> float:
        x = w / wst
        return sq2e * (TS - TC) * math.exp(-x * x) * x + TC * math.tanh(10.0 * w / WS) + BV * w

    def rhs(t: float, x: Any) -> list[float]:
        th_m, th_l, w_m, w_l, integ, tq = x
        r_pos = float(np.interp(t, tr, xr))
        r_vel = float(np.interp(t, tr, vr))
        r_acc = float(np.interp(t, tr, ar))
        w_cmd = kv * (r_pos - th_m) + kffv * r_vel
        ev = w_cmd - w_m
        u = kp * ev + integ + kffa * r_acc
        rel = th_m - th_l
        wrel = w_m - w_l
        b2 = GAP / 2
        if rel > b2:
            tc, td = K * (rel - b2), D * wrel
            tau = 0.0 if tc + td <= 0 else tc + min(tc, td)
        elif rel < -b2:
            tc, td = K * (rel + b2), D * wrel
            tau = 0.0 if tc + td >= 0 else tc + max(tc, td)
        else:
            tau = 0.0
        return [w_m, w_l, (tq - tau - fric(w_m)) / JM, (tau - fric(w_l)) / JL, ki * ev, wc * (u - tq)]

    return rhs


def cold_compile_seconds() -> tuple[float, float]:
    """First-run time of a small simulation in a fresh process: with an empty numba cache (compile)
    and again with the cache just written (load)."""
    code = ("import time; t=time.perf_counter(); import numpy as np; from drivetrain.dynamics import *; "
            "c=two_mass_chain(1e-4,5e-4,500.0); l=tune(c); r=move_reference(1.0,10.0,100.0); "
            "simulate(c,l,r); print(time.perf_counter()-t)")
    out = []
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for _ in range(2):
            res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            out.append(float(res.stdout.strip().splitlines()[-1]))
    return out[0], out[1]


def best_of(fn: Any, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--span", type=float, default=0.5, help="span [s] for python-control and solve_ivp")
    ap.add_argument("--sims", type=int, default=1000)
    args = ap.parse_args()

    import numba

    cold, warm = cold_compile_seconds()
    ref = reference()
    steps = round(T_END / H)
    per = 1e5 / steps

    # --- our kernel -------------------------------------------------------------------------
    stick = model("exponential")
    smooth = model("tanh")
    loop_drive = tune(stick, current_sample_time=H, velocity_sample_time=H, position_sample_time=2 * H)
    loop_cmp = comparison_loop(smooth)
    simulate(stick, loop_drive, ref, step=H, duration=T_END)  # compile / load
    simulate(smooth, loop_cmp, ref, step=H, duration=T_END)
    import drivetrain.dynamics.simulation as simmod

    kern = simmod._kernel_module()
    orig = kern.run_kernel
    kt: list[float] = []

    def timed(*a: Any) -> Any:
        t0 = time.perf_counter()
        r = orig(*a)
        kt.append(time.perf_counter() - t0)
        return r

    kern.run_kernel = timed
    rows: list[tuple[str, float]] = []
    for label, chain, loop, rec in (("kernel, stick friction, full recording", stick, loop_drive, 1),
                                    ("kernel, stick friction, metrics only", stick, loop_drive, steps),
                                    ("kernel, tanh friction, full recording", smooth, loop_cmp, 1)):
        kt.clear()
        for _ in range(20):
            simulate(chain, loop, ref, step=H, duration=T_END, record_every=rec, check_stability=False)
        rows.append((label, min(kt) * per))
    kern.run_kernel = orig
    full_call = best_of(lambda: simulate(stick, loop_drive, ref, step=H, duration=T_END), 10) * per
    rows.append(("whole `simulate()` call (stability check, resampling, result object)", full_call))
    ours = simulate(smooth, loop_cmp, ref, step=H, duration=T_END)

    # --- python-control and solve_ivp on a shorter span ----------------------------------------
    import control
    from scipy.integrate import solve_ivp

    span = args.span
    n_span = round(span / H)
    t_span = np.arange(n_span + 1) * H
    rhs = rhs_factory(loop_cmp, ref)
    x0 = np.zeros(6)

    def updfcn(t: float, x: Any, u: Any, params: Any) -> Any:
        return np.array(rhs(t, x))

    sys_io = control.nlsys(updfcn, None, inputs=0, outputs=6, states=6, name="axis")
    t0 = time.perf_counter()
    resp = control.input_output_response(sys_io, t_span, 0, x0, solve_ivp_kwargs={"rtol": 1e-7, "atol": 1e-10})
    t_ct = time.perf_counter() - t0
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, span), x0, t_eval=t_span, rtol=1e-7, atol=1e-10)
    t_ivp = time.perf_counter() - t0
    # first-order convergence: the kernel at a 10x smaller step against a tight solve_ivp
    h_fine = H / 10
    loop_fine = tune(smooth, current_sample_time=h_fine, velocity_sample_time=h_fine, position_sample_time=h_fine)
    t_fine = np.arange(round(span / h_fine) + 1) * h_fine
    sol_fine = solve_ivp(rhs_factory(loop_fine, ref, h_fine), (0.0, span), x0, t_eval=t_fine, rtol=1e-9, atol=1e-12)
    fine = simulate(smooth, loop_fine, ref, step=h_fine, duration=span)
    diff_fine = float(np.max(np.abs(fine.states["theta_load"] - sol_fine.y[1])))
    ct_load = np.asarray(resp.states)[1]
    ivp_load = sol.y[1]
    our_load = ours.states["theta_load"][: n_span + 1]
    ct_per = t_ct / n_span * 1e5
    ivp_per = t_ivp / n_span * 1e5
    diff_ct = float(np.max(np.abs(our_load - ct_load)))
    diff_ivp = float(np.max(np.abs(our_load - ivp_load)))
    diff_ref = float(np.max(np.abs(ct_load - ivp_load)))
    peak_err = float(np.max(np.abs(ref.resample(t_span)[0] - ct_load)))

    # --- many simulations on all cores --------------------------------------------------------
    rng = np.random.default_rng(6)
    n = args.sims
    kp = loop_drive.velocity_kp * rng.uniform(0.5, 1.2, n)
    kk = K * rng.uniform(0.7, 1.5, n)
    sweep(stick, loop_drive, ref, velocity_kp=kp[:2], stiffness=kk[:2], step=H, duration=0.01)  # compile
    results = {}
    for dur in (T_END, 1.0):
        t0 = time.perf_counter()
        out = sweep(stick, loop_drive, ref, velocity_kp=kp, stiffness=kk, step=H, duration=dur)
        results[dur] = (time.perf_counter() - t0, int(np.sum(out["diverged"])))

    threads = numba.config.NUMBA_NUM_THREADS
    print(f"## Closed-loop simulation benchmark ({threads} threads, numba {numba.__version__})\n")
    print("Two-mass axis 1e-4 / 5e-4 kg m^2, 500 N m/rad, 1 mrad backlash, Stribeck friction, cascaded loop, "
          f"10 kHz step, {T_END:g} s ({steps:,} steps).\n")
    print("| what | time per 100,000 steps [ms] | speed-up vs python-control |")
    print("|---|---:|---:|")
    for label, t in rows:
        print(f"| {label} | {t * 1e3:.2f} | {ct_per / t:,.0f}x |")
    print(f"| python-control `input_output_response` (NonlinearIOSystem, RK45, {span:g} s run, scaled) | "
          f"{ct_per * 1e3:,.0f} | 1x |")
    print(f"| scipy `solve_ivp` (RK45, same rhs, {span:g} s run, scaled) | {ivp_per * 1e3:,.0f} | "
          f"{ct_per / ivp_per:.1f}x |")
    print()
    print("| compile | seconds |")
    print("|---|---:|")
    print(f"| first run in a fresh process, empty numba cache (import + compile + run) | {cold:.2f} |")
    print(f"| first run in a fresh process, cache written (import + load + run) | {warm:.2f} |")
    print()
    print(f"Agreement over the first {span:g} s (load position, rad at the motor shaft; the reference moves "
          f"up to {float(np.max(np.abs(ref.resample(t_span)[0]))):.2f} rad, the load error reaches "
          f"{peak_err:.2e} rad):\n")
    print("| pair | max difference [rad] | tolerance [rad] | ok |")
    print("|---|---:|---:|---|")
    tol = 1e-3
    for label, d, tl in (("kernel (0.1 ms step) vs python-control", diff_ct, tol),
                         ("kernel (0.1 ms step) vs solve_ivp", diff_ivp, tol),
                         ("python-control vs solve_ivp", diff_ref, 1e-6),
                         ("kernel (0.01 ms step) vs solve_ivp (rtol 1e-9)", diff_fine, tol / 10)):
        print(f"| {label} | {d:.2e} | {tl:.0e} | {'yes' if d <= tl else 'NO'} |")
    print()
    print("Tolerance: 1e-3 rad at the 0.1-ms step (1e-4 of the 10-rad move): the kernel updates the loops "
          "once per step (zero-order hold, one step of delay) and integrates by semi-implicit Euler, so it "
          "is O(h) away from the continuous controller the adaptive solvers integrate; the largest "
          "difference sits where the acceleration feed-forward steps. A 10x smaller step must cut the "
          "difference about 10x (last row, tolerance 1e-4 rad).\n")
    print(f"| {n} simulations, kp x U(0.5, 1.2), K x U(0.7, 1.5), numba prange | wall time [s] | diverged |")
    print("|---|---:|---:|")
    for dur, (wall, div) in results.items():
        print(f"| each {dur:g} s ({round(dur / H):,} steps) | {wall:.2f} | {div} |")


if __name__ == "__main__":
    main()
