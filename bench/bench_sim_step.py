"""Convergence study: ``drivetrain simulate``'s figures against the step.

Run: ``.venv/bin/python bench/bench_sim_step.py [--refine 1 2 4 8] [examples/*.yaml]``. Prints a markdown table.

For every example that ``simulate`` accepts, the axis is simulated on its own profile (``simulate_axis``)
at the step h of ``default_step`` (step x omega_max <= 0.2) and at h/2, h/4, h/8 (the same tuned loop,
window and reference; only the step changes), and the settling time per stop (load into its window),
the largest following error (motor, as the drive sees it) and the largest load position error are printed
with their deviation
from the finest run. A stop that never settles prints "-". Also printed: h x omega_max and the
wall time of each run (one process, warm kernel; the machine is shared, so times are indicative).
The last row per example ("auto") is what ``simulate`` reports with its automatic step (refined
until two runs agree, ``simulation.simulate``), with its step and whether the test passed.
"""

from __future__ import annotations

import argparse
import glob
import math
import time

import numpy as np

from drivetrain.axis.model import load_axis
from drivetrain.dynamics.axis_model import simulate_axis
from drivetrain.dynamics.kernel_io import _omega_max, default_step
from drivetrain.errors import InputError


def _fmt_ms(v: float) -> str:
    return "-" if math.isnan(v) else f"{v * 1e3:.2f}"


def _dev(v: float, ref: float, h: float) -> str:
    if math.isnan(v) or math.isnan(ref):
        return "same" if math.isnan(v) and math.isnan(ref) else "differs"
    d = v - ref
    rel = f"{100 * d / ref:+.1f} %" if ref > 0 else "abs"
    return f"{d * 1e3:+.2f} ms ({rel}, {abs(d) / h:.1f} h)"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="*")
    ap.add_argument("--refine", type=int, nargs="+", default=[1, 2, 4, 8])
    args = ap.parse_args()
    files = args.files or sorted(glob.glob("examples/*.yaml"))
    print("| example | step | h [us] | h w_max | settling per stop [ms] | vs finest | max following error [mrad] "
          "| vs finest | max load error [mrad] | run [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in files:
        axis = load_axis(f)
        try:
            base = simulate_axis(axis)
        except InputError as exc:
            print(f"| {f} | not accepted: {exc} |||||||||")
            continue
        h0 = default_step(base.chain, base.loop) if base.loop is not None else float(base.step)
        w = _omega_max(base.chain)
        runs: list[tuple[str, float, object, float]] = []
        for k in args.refine:
            t0 = time.perf_counter()
            r = simulate_axis(axis, step=h0 / k)
            runs.append((f"h/{k}", h0 / k, r, time.perf_counter() - t0))
        t0 = time.perf_counter()
        auto = simulate_axis(axis)
        runs.append((f"auto{'' if auto.step_converged else ' (not converged)'}", auto.step, auto,
                     time.perf_counter() - t0))
        fine = runs[-2][2]
        for label, h, r, dt in runs:
            assert hasattr(r, "settling_time")
            st = np.asarray(r.settling_time, dtype=float)
            dev = ", ".join(_dev(float(a), float(b), h0) for a, b in zip(st, fine.settling_time, strict=True))
            fe_dev = 100 * (r.max_following_error / fine.max_following_error - 1)
            print(f"| {f.split('/')[-1]} | {label} | {h * 1e6:.3g} | {h * w:.3f} | "
                  f"{', '.join(_fmt_ms(float(v)) for v in st) or 'no stop'} | {dev} | "
                  f"{r.max_following_error * 1e3:.4g} | {fe_dev:+.2f} % | {r.max_load_error * 1e3:.4g} | "
                  f"{dt:.3f} |")


if __name__ == "__main__":
    main()
