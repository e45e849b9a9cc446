"""Benchmark of catalog selection: candidates evaluated per second.

Every catalog motor, direct and behind every catalog gearbox row (the selection's own candidate
set, about 10^5), on a 10,000-sample cycle, through ``selection.evaluate`` (the compiled pass).
Peer, in the same run: the straightforward implementation that re-runs the duty cycle for each
candidate (its gearbox prepended to the axis, rotor added) and checks peak torque against the
envelope at every sample and RMS against the continuous torque, timed on 200 random candidates.
Also: a whole ``size`` of the shipped example with its selection, end to end.
Run: ``.venv/bin/python bench/bench_select.py``.
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
from drivetrain.axis.model import Margins, load_axis, parse_axis
from drivetrain.duty.cycle import duty_from_samples
from drivetrain.physics.stage import Stage
from drivetrain.sizing.envelope import continuous_torque, intermittent_torque
from drivetrain.sizing.pipeline import size
from drivetrain.sizing.selection import evaluate

AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "profile": [{"move": f"{(k % 5 + 1) * 20 * (-1) ** k} mm", "time": "0.4 s", "shape": "s_curve",
                 "jerk_fraction": 0.5} for k in range(10)],
}
POINTS = 143  # 10 moves x 7 pieces: about 10,000 samples


def naive(axis: Any, cycle: Any, samples: Any, m: Any, k: int, gb: Any, g: int) -> bool:
    """Re-run the duty cycle with the gearbox (row g, -1 direct) in the chain, then check at every sample."""
    ax = axis
    if g >= 0:
        eff = float(np.nan_to_num(gb.efficiency[g], nan=1.0))
        stage = Stage("gearbox", "gearbox", ratio=float(gb.ratio[g]),
                      inertia_in=float(np.nan_to_num(gb.inertia_input[g])), efficiency=eff, back_efficiency=eff)
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
    m = catalog.motors()
    gb = catalog.gearboxes(kind="servo_gearbox")
    evaluate(axis, duty, m, gb, Margins())  # compile or load the compiled pass
    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        c = evaluate(axis, duty, m, gb, Margins())
        runs.append(time.perf_counter() - t0)
    t_ours = statistics.median(runs)
    n_cand = len(c.motor)
    n_naive = 200
    rng = np.random.default_rng(1)
    picks = [(int(rng.integers(len(m))), int(rng.integers(-1, len(gb)))) for _ in range(n_naive)]
    t0 = time.perf_counter()
    for k, g in picks:
        naive(axis, cycle, samples, m, k, gb, g)
    t_naive = (time.perf_counter() - t0) / n_naive
    full_axis = load_axis(os.path.join(os.path.dirname(__file__), "..", "examples", "ball_screw.yaml"))
    size(full_axis)
    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        res = size(full_axis)
        runs.append(time.perf_counter() - t0)
    t_full = statistics.median(runs)
    print(f"### selection: {n_cand:,} candidates ({len(m)} motors x ({len(gb)} gearbox rows + direct)), "
          f"{len(duty.t)}-sample cycle\n")
    print("| measure | drivetrain | re-run duty per candidate | ratio |")
    print("|---|---|---|---|")
    print(f"| candidates per second | {n_cand / t_ours:,.0f} | {1 / t_naive:,.0f} | "
          f"{(n_cand / t_ours) * t_naive:,.0f}x |")
    print(f"| time for {n_cand:,} candidates | {t_ours * 1e3:.0f} ms | {t_naive * n_cand:.0f} s (extrapolated from "
          f"{n_naive}) | |")
    print(f"| whole `size` of examples/ball_screw.yaml with selection ({res.selection.evaluated:,} candidates) "
          f"| {t_full * 1e3:.0f} ms | | target < 500 ms |")


if __name__ == "__main__":
    main()
