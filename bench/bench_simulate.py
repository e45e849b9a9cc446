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

Everything is measured in the same run; the last table compares with the issue's targets: the
first-run compile (fresh processes with an empty numba cache, then with it written), the kernel
time per 100,000 steps with full recording, the speed-up over python-control, and 1,000 simulations
of 10 s (``sweep``: metrics only, the runs spread over the cores). Timings are best-of-N wall
times; the machine's load average is printed because other processes share the cores.
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
from drivetrain.dynamics.reference import Reference

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


COLD_CODE = """
import time
t0 = time.perf_counter()
import numpy as np
from drivetrain.dynamics import move_reference, simulate, tune, two_mass_chain
c = two_mass_chain(1e-4, 5e-4, 500.0)
l = tune(c)
r = move_reference(1.0, 10.0, 100.0)
t1 = time.perf_counter()
simulate(c, l, r)
t2 = time.perf_counter()
print(t1 - t0, t2 - t1, t2 - t0, time.process_time())
"""


def cold_compile_seconds(repeat: int = 2) -> dict[str, float]:
    """A small simulation in a fresh process, first with an empty numba cache (compile), then with the
    cache just written (load); each field the best of ``repeat`` such pairs. Each run is split into (a)
    start, imports and ``tune`` (its stability check and modes use numpy only) and (b) the first
    ``simulate()`` call (numba import, compile or cache load, run). The compilation costs the first run
    the difference of the two (b)."""
    keys = ("setup", "simulate", "total", "cpu")
    out: dict[str, float] = {}
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache)
            for label in ("cold", "warm"):
                res = subprocess.run([sys.executable, "-c", COLD_CODE], env=env, capture_output=True, text=True,
                                     check=True)
                values = [float(v) for v in res.stdout.strip().splitlines()[-1].split()]
                for k, v in zip(keys, values, strict=True):
                    out[f"{label}_{k}"] = min(v, out.get(f"{label}_{k}", math.inf))
    out["compile"] = out["cold_simulate"] - out["warm_simulate"]
    return out


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

    load_start = os.getloadavg()[0]
    cold = cold_compile_seconds()
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
    from drivetrain.dynamics.kernel_io import kernel_module

    kern = kernel_module()
    orig = kern.run_two  # the kernel simulate() uses for a two-mass chain
    kt: list[float] = []

    def timed(*a: Any) -> Any:
        t0 = time.perf_counter()
        r = orig(*a)
        kt.append(time.perf_counter() - t0)
        return r

    kern.run_two = timed
    rows: list[tuple[str, float]] = []
    for label, chain, loop, rec in (("kernel, stick friction, full recording", stick, loop_drive, 1),
                                    ("kernel, stick friction, metrics only", stick, loop_drive, steps),
                                    ("kernel, tanh friction, full recording", smooth, loop_cmp, 1)):
        kt.clear()
        for _ in range(20):
            simulate(chain, loop, ref, step=H, duration=T_END, record_every=rec, check_stability=False)
        rows.append((label, min(kt) * per))
    kern.run_two = orig
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
    sweep(stick, loop_drive, ref, velocity_kp=kp[:2], stiffness=kk[:2], step=H, duration=0.01)  # warm up
    results = {}
    for dur, repeat in ((T_END, 5), (1.0, 3)):
        walls, cpus = [], []
        for _ in range(repeat):
            t0, c0 = time.perf_counter(), time.process_time()
            out = sweep(stick, loop_drive, ref, velocity_kp=kp, stiffness=kk, step=H, duration=dur)
            walls.append(time.perf_counter() - t0)
            cpus.append(time.process_time() - c0)
        best = int(np.argmin(walls))
        results[dur] = (walls[best], max(walls), cpus[best], int(np.sum(out["diverged"])))
    load_end = os.getloadavg()[0]

    threads = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
    print(f"## Closed-loop simulation benchmark ({threads} threads, {os.cpu_count()} CPUs, "
          f"numba {numba.__version__})\n")
    print("Two-mass axis 1e-4 / 5e-4 kg m^2, 500 N m/rad, 1 mrad backlash, Stribeck friction, cascaded loop, "
          f"10 kHz step, {T_END:g} s ({steps:,} steps). Load average (1 min) of the machine: {load_start:.2f} at "
          f"the start, {load_end:.2f} at the end (other processes share the cores).\n")
    print("| what | time per 100,000 steps [ms] | speed-up vs python-control |")
    print("|---|---:|---:|")
    for label, t in rows:
        print(f"| {label} | {t * 1e3:.2f} | {ct_per / t:,.0f}x |")
    print(f"| python-control `input_output_response` (NonlinearIOSystem, RK45, {span:g} s run, scaled) | "
          f"{ct_per * 1e3:,.0f} | 1x |")
    print(f"| scipy `solve_ivp` (RK45, same rhs, {span:g} s run, scaled) | {ivp_per * 1e3:,.0f} | "
          f"{ct_per / ivp_per:.1f}x |")
    print()
    print("| first run in a fresh process [s] | start, imports, `tune` | first `simulate()` | total | CPU |")
    print("|---|---:|---:|---:|---:|")
    for label, key in (("empty numba cache (compile)", "cold"), ("cache written (load)", "warm")):
        print(f"| {label} | {cold[key + '_setup']:.2f} | {cold[key + '_simulate']:.2f} | {cold[key + '_total']:.2f} | "
              f"{cold[key + '_cpu']:.2f} |")
    print()
    print(f"Agreement over the first {span:g} s (load position, rad at the motor shaft; the reference moves "
          f"up to {float(np.max(np.abs(ref.resample(t_span)[0]))):.2f} rad, the load error reaches "
          f"{peak_err:.2e} rad):\n")
    print("| pair | max difference [rad] | tolerance [rad] | ok |")
    print("|---|---:|---:|---|")
    tol = 1e-3
    agree = []
    for label, d, tl in (("kernel (0.1 ms step) vs python-control", diff_ct, tol),
                         ("kernel (0.1 ms step) vs solve_ivp", diff_ivp, tol),
                         ("python-control vs solve_ivp", diff_ref, 1e-6),
                         ("kernel (0.01 ms step) vs solve_ivp (rtol 1e-9)", diff_fine, tol / 10)):
        agree.append(d <= tl)
        print(f"| {label} | {d:.2e} | {tl:.0e} | {'yes' if d <= tl else 'NO'} |")
    print()
    print("Tolerance: 1e-3 rad at the 0.1-ms step (1e-4 of the 10-rad move): the kernel updates the loops "
          "once per step (zero-order hold, one step of delay) and integrates by semi-implicit Euler, so it "
          "is O(h) away from the continuous controller the adaptive solvers integrate; the largest "
          "difference sits where the acceleration feed-forward steps. A 10x smaller step must cut the "
          "difference about 10x (last row, tolerance 1e-4 rad).\n")
    print(f"| {n} simulations, kp x U(0.5, 1.2), K x U(0.7, 1.5), metrics only, {threads} threads | "
          f"wall time, best run [s] | slowest run [s] | CPU time of the best run [s] | CPU time / {threads} [s] | "
          "diverged |")
    print("|---|---:|---:|---:|---:|---:|")
    for dur, (wall, worst, cpu, div) in results.items():
        print(f"| each {dur:g} s ({round(dur / H):,} steps) | {wall:.2f} | {worst:.2f} | {cpu:.2f} | "
              f"{cpu / threads:.2f} | {div} |")
    print(f"\n(10-s runs: best of 5, 1-s runs: best of 3. With every core free the wall time approaches the CPU "
          f"time / {threads}; when other processes hold a core it approaches the CPU time.)\n")
    full = rows[0][1]
    sweep_wall = results[T_END][0]
    targets = (
        ("compile cost of the first run: first `simulate()`, empty cache minus cache written [s]",
         cold["compile"], "<= 2", cold["compile"] <= 2.0),
        ("whole first run in a fresh process, empty cache (start, imports, `tune`, compile, run) [s]",
         cold["cold_total"], "<= 2", cold["cold_total"] <= 2.0),
        ("kernel, stick friction, full recording [ms per 100,000 steps]", full * 1e3, "<= 3", full <= 3e-3),
        ("speed-up of that kernel over python-control", ct_per / full, ">= 1000", ct_per / full >= 1000),
        (f"{n} simulations of {T_END:g} s on all cores [s]", sweep_wall, "< 1", sweep_wall < 1.0),
        ("agreement with python-control and solve_ivp (rows above)", float(sum(agree)), f"{len(agree)} of "
         f"{len(agree)}", all(agree)),
    )
    print("| target (issue 6) | measured | required | met |")
    print("|---|---:|---:|---|")
    for label, value, need, ok in targets:
        print(f"| {label} | {value:,.2f} | {need} | {'yes' if ok else 'NO'} |")
    if cold["cold_total"] > 2.0:
        print(f"\nThe whole first run exceeds 2 s by {cold['cold_total'] - 2.0:.2f} s: it includes "
              f"{cold['cold_setup']:.2f} s before `simulate()` (Python start, imports and `tune`) "
              "and numba's one-time start-up inside the first compile; with the "
              f"cache written the same run takes {cold['warm_total']:.2f} s.")
    if sweep_wall >= 1.0:
        cpu = results[T_END][2]
        print(f"\nThe {n} simulations took {sweep_wall:.2f} s of wall time for {cpu:.2f} s of CPU time: the "
              f"{threads} threads did not get {threads} cores to themselves (load average {load_end:.2f}); "
              f"with the cores free the run takes about {cpu / threads:.2f} s.")


if __name__ == "__main__":
    main()
