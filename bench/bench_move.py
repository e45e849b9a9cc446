"""One time-optimal rest-to-rest move from Python: drivetrain against ruckig's Python call.

The same move, limits and answer (duration): 0.3 m under 1 m/s, 5 m/s^2, 50 m/s^3, rest to rest.
drivetrain: ``time_optimal_duration`` called with floats (the scalar path) and, per move, the
vectorised path on 10^5 moves. ruckig: ``Ruckig(1).calculate(input, trajectory)`` with the input
and trajectory objects made once (the cheapest way to call it), then ``trajectory.duration``.
Time: min over 7 repeats of the mean of a loop of calls (``time.perf_counter``; in-process).
Run: ``.venv/bin/python bench/bench_move.py``.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from ruckig import InputParameter, Ruckig, Trajectory

from drivetrain.motion.moves import time_optimal_duration

D, V, A, J = 0.3, 1.0, 5.0, 50.0


def per_call(fn: Callable[[], object], n: int = 20_000) -> float:
    runs = []
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        runs.append((time.perf_counter() - t0) / n)
    return min(runs)


def main() -> None:
    inp, otg, traj = InputParameter(1), Ruckig(1), Trajectory(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [0.0], [0.0], [0.0]
    inp.target_position, inp.target_velocity, inp.target_acceleration = [D], [0.0], [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [V], [A], [J]

    def theirs() -> float:
        otg.calculate(inp, traj)
        return float(traj.duration)

    def ours() -> float:
        return float(time_optimal_duration(D, V, A, J))

    assert abs(ours() - theirs()) < 1e-9, (ours(), theirs())
    t_ours, t_theirs = per_call(ours), per_call(theirs)
    n = 100_000
    d = np.full(n, D)
    t_vec = per_call(lambda: time_optimal_duration(d, V, A, J), 20) / n
    print("### one time-optimal move (0.3 m; 1 m/s, 5 m/s^2, 50 m/s^3; rest to rest), in-process, min of 7\n")
    print("| call | time per move | ratio to ruckig |")
    print("|---|---:|---:|")
    print(f"| drivetrain `time_optimal_duration(0.3, 1.0, 5.0, 50.0)` (scalar path) | {t_ours * 1e6:.2f} us | "
          f"{t_ours / t_theirs:.2f}x |")
    print(f"| ruckig `Ruckig(1).calculate(inp, traj)` + `traj.duration` | {t_theirs * 1e6:.2f} us | 1x |")
    print(f"| drivetrain, vectorised over {n:,} moves | {t_vec * 1e6:.3f} us | {t_vec / t_theirs:.3f}x |")
    print(f"\n| target (issue 16) | measured | required | met |\n|---|---:|---:|---|\n"
          f"| scalar move / ruckig | {t_ours / t_theirs:.2f} | <= 2 | {'yes' if t_ours <= 2 * t_theirs else 'NO'} |")


if __name__ == "__main__":
    main()
