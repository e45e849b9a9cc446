"""Benchmark of catalog selection: candidates evaluated per second.

10,000 motor x ratio candidates (catalog motors x ideal gearbox ratios) on a 10,000-sample
cycle. Peer, in the same run: the straightforward implementation that re-runs the duty cycle
for each candidate (gearbox prepended to the axis, rotor added) and checks peak torque against
the envelope at every sample and RMS against the continuous torque. Also: a whole selection
of the shipped example against the shipped catalog (every motor, direct and behind every
gearbox row), end to end. Run: ``.venv/bin/python bench/bench_select.py``.
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from dataclasses import replace
from typing import Any

import numpy as np

os.environ.setdefault("DRIVETRAIN_DATA_DIR", tempfile.mkdtemp(prefix="drivetrain-bench-"))

from drivetrain import catalog
from drivetrain.axis import load_axis, parse_axis
from drivetrain.duty import duty_from_samples
from drivetrain.envelope import continuous_torque, intermittent_torque
from drivetrain.motor_fit import MotorArrays, demand, fit_motors, scaled
from drivetrain.sizing import size
from drivetrain.stage import Stage

AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "profile": [{"move": f"{(k % 5 + 1) * 20 * (-1) ** k} mm", "time": "0.4 s", "shape": "s_curve",
                 "jerk_fraction": 0.5} for k in range(10)],
}
POINTS = 143  # 10 moves x 7 pieces: about 10,000 samples


def naive(axis: Any, cycle: Any, samples: Any, m: Any, k: int, ratio: float) -> bool:
    """Re-run the duty cycle with the gearbox in the chain, then check at every sample."""
    stage = Stage("gearbox", "gearbox", ratio=ratio, efficiency=0.97, back_efficiency=0.97)
    ax = replace(axis, transmission=(stage, *axis.transmission))
    duty = duty_from_samples(ax, cycle, samples)
    t_m = duty.motor_torque(float(m.rotor_inertia[k]))
    peak_env = intermittent_torque(m.peak_torque[k], m.rated_torque[k], m.rated_speed[k], m.max_speed[k],
                                   duty.omega).torque[0]
    ok_peak = bool(np.all(np.abs(t_m) <= peak_env))
    rms = float(np.sqrt(np.sum(duty.weights * t_m**2) / duty.period))
    mean = float(np.sum(duty.weights * np.abs(duty.omega)) / duty.period)
    cont = continuous_torque(m.rated_torque[k], m.rated_speed[k], m.max_speed[k], np.array([mean])).torque[0, 0]
    return ok_peak and rms <= cont


def main() -> None:
    axis = parse_axis(AXIS)
    cycle = axis.cycle()
    samples = cycle.sample(POINTS)
    duty = duty_from_samples(axis, cycle, samples)
    m = catalog.motors(kind="ac_servo")
    ratios = np.geomspace(1.0, 100.0, int(np.ceil(10_000 / len(m))))
    n_cand = len(m) * len(ratios)
    arrays = MotorArrays(inertia=m.rotor_inertia, rated_torque=m.rated_torque, peak_torque=m.peak_torque,
                         rated_speed=m.rated_speed, max_speed=m.max_speed, stall_torque=m.stall_torque,
                         approximate=~m.has_curve)

    def ours() -> int:
        base = demand(duty.omega, duty.alpha, duty.torque / 0.97, duty.weights, duty.period, duty.load_inertia)
        passing = 0
        for r in ratios:
            fit = fit_motors(scaled(base, float(r)), arrays, inertia_ratio_limit=1e9)
            passing += int(np.sum(fit.ok))
        return passing

    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        ours()
        runs.append(time.perf_counter() - t0)
    t_ours = statistics.median(runs)
    n_naive = 200
    rng = np.random.default_rng(1)
    picks = [(int(rng.integers(len(m))), float(rng.choice(ratios))) for _ in range(n_naive)]
    t0 = time.perf_counter()
    for k, r in picks:
        naive(axis, cycle, samples, m, k, r)
    t_naive = (time.perf_counter() - t0) / n_naive
    full_axis = load_axis(os.path.join(os.path.dirname(__file__), "..", "examples", "ball_screw.yaml"))
    size(full_axis)
    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        res = size(full_axis)
        runs.append(time.perf_counter() - t0)
    t_full = statistics.median(runs)
    print(f"### selection: {n_cand} motor x ratio candidates, {len(duty.t)}-sample cycle\n")
    print("| measure | drivetrain | re-run duty per candidate | ratio |")
    print("|---|---|---|---|")
    print(f"| candidates per second | {n_cand / t_ours:,.0f} | {1 / t_naive:,.0f} | "
          f"{(n_cand / t_ours) * t_naive:,.0f}x |")
    print(f"| time for {n_cand} candidates | {t_ours * 1e3:.0f} ms | {t_naive * n_cand:.1f} s (extrapolated from "
          f"{n_naive}) | |")
    print(f"| whole `size` of examples/ball_screw.yaml with selection ({res.selection['evaluated']:,} candidates) "
          f"| {t_full * 1e3:.0f} ms | | target < 500 ms |")


if __name__ == "__main__":
    main()
