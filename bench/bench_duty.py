"""The duty cycle against a minimal numpy version of the same cycle, side by side.

Cycle: a horizontal ball screw (lead 10 mm, diameter 20 mm, length 0.8 m, efficiency 0.9), 25 kg
with friction coefficient 0.05; a trapezoid move of 200 mm in 0.5 s (0.1 s ramps), 0.3 s dwell,
the move back, 0.3 s dwell; the motor drives the screw directly. drivetrain: ``duty_cycle`` (the
profile sampled, the demand propagated through the screw, four-quadrant losses) then the RMS motor
torque. Peer: the same physics written out in numpy for this one cycle (a closed-form trapezoid on
a uniform grid, F = m a + mu m g sign(v), T = J_screw alpha + T_F / eta driving or T_F eta
back-driven). Both give the RMS torque; their agreement is printed. Time: CPU time
(``time.process_time``), min of the runs, in this process. Run: ``.venv/bin/python bench/bench_duty.py``.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.motion import cycle as cycle_module
from drivetrain.physics.averages import rms

LEAD, MASS, MU, ETA, G = 0.010, 25.0, 0.05, 0.9, 9.80665
AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m", "efficiency": ETA,
                  "incline": "0 deg", "load": {"mass": MASS, "friction": MU}},
    "profile": [{"move": "200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"},
                {"move": "-200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}],
}
SIZES = (1_000, 10_000, 100_000, 1_000_000)
SEGMENTS = 8  # 2 moves x 3 phases + 2 dwells


def peer(j_screw: float, n: int) -> float:
    """RMS motor torque of the cycle on n uniform samples, in plain numpy [N m]."""
    t = np.linspace(0.0, 1.6, n)
    tm = np.where(t < 0.8, t, t - 0.8)  # time within the half cycle
    sign = np.where(t < 0.8, 1.0, -1.0)
    a_max = 0.2 / (0.1 * 0.4)  # distance / (t_a (t_move - t_a))
    a = sign * np.select([tm < 0.1, tm < 0.4, tm < 0.5], [a_max, 0.0, -a_max], 0.0)
    v = sign * np.select([tm < 0.1, tm < 0.4, tm < 0.5], [a_max * tm, a_max * 0.1, a_max * (0.5 - tm)], 0.0)
    k = 2.0 * math.pi / LEAD  # rad per m
    force = MASS * a + MU * MASS * G * np.sign(v)
    t_screw = force / k
    torque = j_screw * a * k + np.where(t_screw * v > 0.0, t_screw / ETA, t_screw * ETA)
    return float(np.sqrt(np.mean(torque**2)))


def ours(axis: Any, n: int) -> float:
    duty = duty_cycle(axis, max(3, n // SEGMENTS))
    return rms(duty.torque, duty.weights, duty.period)


def best(fn: Any, *args: Any) -> tuple[float, Any]:
    out, runs = None, []
    repeat = 7 if args[-1] < 100_000 else 3
    for _ in range(repeat):
        t0 = time.process_time()
        for _ in range(max(1, 10_000 // args[-1])):
            out = fn(*args)
        runs.append((time.process_time() - t0) / max(1, 10_000 // args[-1]))
    return min(runs), out


def main() -> None:
    cycle_module.MAX_SAMPLES = 2_000_000  # the axis file's guard (500,000) lifted to measure 10^6
    axis = parse_axis(AXIS)
    j_screw = axis.mechanism.stage.inertia_in  # the screw; the load mass is in the force
    ours(axis, 1000)
    print("### duty cycle: trapezoid ball-screw cycle, drivetrain `duty_cycle` + RMS vs minimal numpy (CPU time, "
          "in-process, min of runs)\n")
    print("| samples | drivetrain | numpy peer | ratio | RMS torque drivetrain / peer [N m] |")
    print("|---:|---:|---:|---:|---|")
    for n in SIZES:
        t_ours, r_ours = best(ours, axis, n)
        t_peer, r_peer = best(peer, j_screw, n)
        print(f"| {n:,} | {t_ours * 1e3:.3f} ms | {t_peer * 1e3:.3f} ms | {t_ours / t_peer:.1f}x | "
              f"{r_ours:.4f} / {r_peer:.4f} |")


if __name__ == "__main__":
    main()
