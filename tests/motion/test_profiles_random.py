"""The profile guarantees of ``drivetrain.motion.profiles``, checked ruckig-style on seeded random moves.

Target reached within 1e-9 relative; speed, acceleration and jerk never above the step's peaks
(or a time-optimal move's limits) by more than 1e-12 relative; rest at both ends; no NaN; and
the closed-form time-optimal durations equal ruckig's within 1e-9 s.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from ruckig import InputParameter, Result, Ruckig, Trajectory

from drivetrain.motion.cams import CAM_LAWS
from drivetrain.motion.cycle import Cycle
from drivetrain.motion.moves import time_optimal_parameters
from drivetrain.motion.profiles import parse_profile, ruckig_move

N_PER_FAMILY = 1000
N_RUCKIG = 100_000
LIMIT = 1.0 + 1e-12

Rng = np.random.Generator


def _log_uniform(rng: Rng, lo: float, hi: float) -> float:
    return float(10.0 ** rng.uniform(math.log10(lo), math.log10(hi)))


def _move(rng: Rng) -> float:
    return _log_uniform(rng, 1e-4, 10.0) * float(rng.choice([-1.0, 1.0]))


def _ramps(rng: Rng, t: float) -> tuple[float, float]:
    t_a = rng.uniform(0.01, 0.99) * t
    return t_a, rng.uniform(0.01, 1.0) * (t - t_a)


def _trapezoid(rng: Rng) -> dict[str, Any]:
    t = _log_uniform(rng, 1e-2, 10.0)
    t_a, t_d = _ramps(rng, t)
    return {"move": _move(rng), "time": t, "accel": t_a, "decel": t_d}


def _speed_given(rng: Rng) -> dict[str, Any]:
    step = _trapezoid(rng)
    step["speed"] = step.pop("move") * 3.0
    return step


def _shape(rng: Rng) -> dict[str, Any]:
    shape = str(rng.choice(["trapezoid", "triangle", "s_curve"]))
    return {"move": _move(rng), "time": _log_uniform(rng, 1e-2, 10.0), "shape": shape}


def _s_curve_fraction(rng: Rng) -> dict[str, Any]:
    step = _trapezoid(rng)
    return {**step, "shape": "s_curve", "jerk_fraction": float(rng.choice([0.0, 1.0, rng.uniform()]))}


def _s_curve_jerk(rng: Rng) -> dict[str, Any]:
    step = _trapezoid(rng)
    v = 2.0 * abs(step["move"]) / (2.0 * step["time"] - step["accel"] - step["decel"])
    need = 4.0 * v / min(step["accel"], step["decel"]) ** 2
    return {**step, "shape": "s_curve", "jerk": need * _log_uniform(rng, 1.0, 100.0)}


def _cam(rng: Rng) -> dict[str, Any]:
    return {"move": _move(rng), "time": _log_uniform(rng, 1e-2, 10.0), "law": str(rng.choice(CAM_LAWS))}


def _limits(rng: Rng) -> dict[str, Any]:
    return {"move": _move(rng), "max_speed": _log_uniform(rng, 1e-2, 10.0), "max_accel": _log_uniform(rng, 1e-1, 1e2)}


def _limits_jerk(rng: Rng) -> dict[str, Any]:
    return {**_limits(rng), "max_jerk": _log_uniform(rng, 1.0, 1e4)}


FAMILIES: dict[str, Callable[[Rng], dict[str, Any]]] = {
    "trapezoid": _trapezoid, "speed": _speed_given, "shape": _shape, "s_curve_fraction": _s_curve_fraction,
    "s_curve_jerk": _s_curve_jerk, "cam": _cam, "time_optimal": _limits, "time_optimal_jerk": _limits_jerk,
}


def _check_guarantees(cycle: Cycle, raw: dict[str, Any], rng: Rng) -> None:
    step = cycle.steps[0]
    s = cycle.sample(17)
    t = np.r_[s.t, rng.uniform(0.0, cycle.period, 64)]
    k = cycle.evaluate(t)
    both = [np.r_[s.x, k.x], np.r_[s.v, k.v], np.r_[s.a, k.a], np.r_[s.j, k.j]]
    assert all(np.isfinite(q).all() for q in both), raw
    _, v, a, j = both
    # target reached, from rest to rest
    end = cycle.evaluate([cycle.period])
    assert abs(end.x[0] - step.distance) <= 1e-9 * abs(step.distance), raw
    assert abs(s.x[-1] - step.distance) <= 1e-9 * abs(step.distance), raw
    assert abs(s.v[0]) <= 1e-12 * step.peak_speed and abs(s.v[-1]) <= 1e-12 * step.peak_speed, raw
    if step.peak_jerk > 0.0:  # jerk-limited shapes also start and end without acceleration
        peak = max(step.peak_accel, step.peak_decel)
        assert abs(s.a[0]) <= 1e-12 * peak and abs(s.a[-1]) <= 1e-12 * peak, raw
    # limits: the step's own peaks, and a time-optimal move's requested limits
    assert np.abs(v).max() <= step.peak_speed * LIMIT, raw
    assert np.abs(s.a[s.t <= step.t_accel]).max() <= step.peak_accel * LIMIT, raw
    assert np.abs(s.a[s.t >= step.duration - step.t_decel]).max() <= step.peak_decel * LIMIT, raw
    assert np.abs(a).max() <= max(step.peak_accel, step.peak_decel) * LIMIT, raw
    assert np.abs(j).max() <= step.peak_jerk * LIMIT, raw
    if "max_speed" in raw:
        assert step.peak_speed <= raw["max_speed"] * LIMIT and step.peak_accel <= raw["max_accel"] * LIMIT, raw
        assert step.peak_jerk <= raw.get("max_jerk", 0.0) * LIMIT, raw
    # the speed-given move covers the movement amount
    if "speed" in raw:
        assert step.peak_speed == pytest.approx(abs(raw["speed"]), rel=1e-12), raw


@pytest.mark.parametrize("family", list(FAMILIES))
def test_guarantees_on_seeded_random_moves(family: str) -> None:
    rng = np.random.default_rng(20240601 + list(FAMILIES).index(family))
    for _ in range(N_PER_FAMILY):
        raw = FAMILIES[family](rng)
        _check_guarantees(parse_profile([raw], "linear"), raw, rng)


def _random_limits(rng: Rng, n: int) -> tuple[np.ndarray, ...]:
    """Log-uniform over decades: distance 1e-3..10, vmax 1e-2..10, amax 1e-1..1e2, jmax 1..1e4."""
    d = 10.0 ** rng.uniform(-3, 1, n) * rng.choice([-1.0, 1.0], n)
    return d, 10.0 ** rng.uniform(-2, 1, n), 10.0 ** rng.uniform(-1, 2, n), 10.0 ** rng.uniform(0, 4, n)


def test_time_optimal_closed_form_guarantees_vectorised() -> None:
    d, vmax, amax, jmax = _random_limits(np.random.default_rng(7), N_RUCKIG)
    opt = time_optimal_parameters(d, vmax, amax, jmax)
    assert all(np.isfinite(q).all() for q in opt)
    assert np.all(opt.peak_speed <= vmax * LIMIT) and np.all(opt.peak_accel <= amax * LIMIT)
    assert np.all(opt.peak_accel <= opt.t_jerk * jmax * LIMIT)  # jerk a_p / t_j within the limit
    assert np.all(np.minimum.reduce([opt.t_jerk, opt.t_const, opt.t_cruise]) >= 0.0)
    ramp = 2.0 * opt.t_jerk + opt.t_const
    np.testing.assert_allclose(opt.peak_speed * (ramp + opt.t_cruise), np.abs(d), rtol=1e-9)
    np.testing.assert_allclose(opt.duration, 2.0 * ramp + opt.t_cruise, rtol=1e-15)


def _ruckig_durations(d: np.ndarray, vmax: np.ndarray, amax: np.ndarray, jmax: np.ndarray) -> np.ndarray:
    inp, otg, traj = InputParameter(1), Ruckig(1), Trajectory(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [0.0], [0.0], [0.0]
    inp.target_velocity, inp.target_acceleration = [0.0], [0.0]
    out = np.empty(len(d))
    for i in range(len(d)):
        inp.target_position = [float(d[i])]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [float(vmax[i])], [float(amax[i])], [float(jmax[i])]
        assert otg.calculate(inp, traj) == Result.Working
        out[i] = traj.duration
    return out


def test_time_optimal_durations_equal_ruckig() -> None:
    """10^5 seeded rest-to-rest cases, jerk-limited; ruckig is called once per case."""
    d, vmax, amax, jmax = _random_limits(np.random.default_rng(2024), N_RUCKIG)
    ours = time_optimal_parameters(d, vmax, amax, jmax).duration
    start = time.perf_counter()
    theirs = _ruckig_durations(d, vmax, amax, jmax)
    assert time.perf_counter() - start < 30.0
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-9)


def test_time_optimal_durations_equal_ruckig_without_jerk_limit() -> None:
    d, vmax, amax, _ = _random_limits(np.random.default_rng(2025), 10_000)
    jmax = np.full_like(d, np.inf)
    ours = time_optimal_parameters(d, vmax, amax, jmax).duration
    np.testing.assert_allclose(ours, _ruckig_durations(d, vmax, amax, jmax), rtol=0, atol=1e-9)


def test_ruckig_move_matches_ruckig_and_reaches_the_target() -> None:
    rng = np.random.default_rng(11)
    for _ in range(300):
        vmax, amax, jmax = _log_uniform(rng, 0.1, 10), _log_uniform(rng, 0.5, 50), _log_uniform(rng, 5, 500)
        x0, x1 = rng.uniform(-2, 2, 2)
        v0, a0 = rng.uniform(-1.5, 1.5) * vmax, rng.uniform(-1.5, 1.5) * amax  # may start beyond the limits
        v1 = rng.uniform(-0.9, 0.9) * vmax
        move = ruckig_move(x0, v0, a0, x1, v1, 0.0, vmax, amax, jmax)
        inp, otg, traj = InputParameter(1), Ruckig(1), Trajectory(1)
        inp.current_position, inp.current_velocity, inp.current_acceleration = [x0], [v0], [a0]
        inp.target_position, inp.target_velocity, inp.target_acceleration = [x1], [v1], [0.0]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [vmax], [amax], [jmax]
        otg.calculate(inp, traj)
        t = np.linspace(0.0, move.duration, 41)
        ours = move.evaluate(t)
        ref = np.array([[q[0] for q in traj.at_time(float(ti))] for ti in t])
        assert np.isfinite(np.c_[ours.x, ours.v, ours.a, ours.j]).all()
        np.testing.assert_allclose(ours.x, ref[:, 0], rtol=0, atol=1e-9 * max(1.0, abs(x1)))
        np.testing.assert_allclose(ours.v, ref[:, 1], rtol=0, atol=1e-9 * vmax)
        np.testing.assert_allclose(ours.a, ref[:, 2], rtol=0, atol=1e-9 * amax)
        assert abs(ours.x[-1] - x1) <= 1e-9 * max(1.0, abs(x1)) and abs(ours.v[-1] - v1) <= 1e-9 * vmax
        assert np.abs(ours.j).max() <= jmax * LIMIT
