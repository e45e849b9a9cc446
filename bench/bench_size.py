"""Benchmark of ``size`` on a 10-move cycle sampled at about 10,000 points.

Peer, in the same run: a straightforward implementation of the same duty cycle that loops over
samples in Python and reflects each sample through the chain one at a time (the way a
spreadsheet or a first script does it). Reports wall time per sizing, the ratio, peak memory
(tracemalloc) and the import time of ``drivetrain`` and of ``drivetrain size --help``.
Run: ``.venv/bin/python bench/bench_size.py``.
"""

from __future__ import annotations

import math
import statistics
import subprocess
import sys
import time
import tracemalloc
from typing import Any

import numpy as np

from drivetrain.axis.model import parse_axis
from drivetrain.sizing.pipeline import size

AXIS: dict[str, Any] = {
    "axis": "bench 10 moves",
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "transmission": [{"type": "coupling", "inertia": 2e-5}, {"type": "gearbox", "ratio": 3, "inertia": 3e-5}],
    "profile": [{"move": f"{(k % 5 + 1) * 20 * (-1) ** k} mm", "time": "0.4 s", "shape": "s_curve",
                 "jerk_fraction": 0.5} for k in range(10)],
    "motor": {"name": "m", "inertia": 1e-4, "rated_torque": 2.0, "peak_torque": 6.0, "rated_speed": "3000 rpm",
              "max_speed": "6000 rpm"},
}
# s-curve moves: 7 pieces each, 143 points per piece: about 10,000 samples.
POINTS = 143  # 10 moves x 7 pieces: about 10,000 samples


def naive_duty(axis: Any, t: np.ndarray, x: np.ndarray, v: np.ndarray, a: np.ndarray, d: np.ndarray) -> float:
    """Per-sample Python loop over the same physics; returns the RMS torque."""
    mech = axis.mechanism
    total = 0.0
    for k in range(len(t)):
        f = float(mech.external_torque(np.array([x[k]]), np.array([v[k]]), np.array([d[k]]),
                                       np.array([mech.load.thrust]), axis.gravity)[0])
        t_out = f * mech.stage.ratio
        omega, alpha = v[k] * mech.stage.ratio, a[k] * mech.stage.ratio
        for st in reversed(axis.stages):
            if st is not mech.stage:
                omega, alpha = omega * st.ratio, alpha * st.ratio
            bracket = st.inertia_inside * alpha + t_out / st.ratio
            sgn = math.copysign(1.0, omega) if omega != 0 else math.copysign(1.0, d[k])
            lossy = bracket / st.efficiency if bracket * sgn > 0 else bracket * st.back_efficiency
            t_out = st.inertia_in * alpha + lossy
        total += t_out**2
    return math.sqrt(total / len(t))


def timed(fn: Any, repeat: int) -> float:
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        runs.append(time.perf_counter() - t0)
    return statistics.median(runs)


def main() -> None:
    axis = parse_axis(AXIS)
    result = size(axis, POINTS)
    n = len(result.duty.t)
    ours = timed(lambda: size(axis, POINTS), 20)
    s = result.duty.samples
    peer = timed(lambda: naive_duty(axis, s.t, s.x, s.v, s.a, s.direction), 3)
    tracemalloc.start()
    size(axis, POINTS)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    imp = timed(lambda: subprocess.run([sys.executable, "-c", "import drivetrain"], check=True), 5)
    helptime = timed(lambda: subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", "--help"],
                                            check=True, capture_output=True), 5)
    base = timed(lambda: subprocess.run([sys.executable, "-c", "pass"], check=True), 5)
    print(f"### size: 10-move cycle, {n} samples\n")
    print("| measure | drivetrain | per-sample Python loop | ratio |")
    print("|---|---|---|---|")
    print(f"| wall time per sizing | {ours * 1e3:.1f} ms | {peer * 1e3:.0f} ms | {peer / ours:.0f}x |")
    print(f"| peak memory per sizing | {peak / 1e6:.1f} MB | | |")
    print(f"| `import drivetrain` (process start {base * 1e3:.0f} ms incl.) | {imp * 1e3:.0f} ms | | |")
    print(f"| `drivetrain size --help` | {helptime * 1e3:.0f} ms | | target < 300 ms |")


if __name__ == "__main__":
    main()
