"""Motion profiles: lecture formulas, published timing, parsing, errors, sampling and properties."""

from __future__ import annotations

import doctest
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.errors import InputError
from drivetrain.motion import profiles
from drivetrain.motion.cycle import Cycle, Samples
from drivetrain.motion.moves import (
    movement_amount,
    s_curve_jerk_time,
    s_curve_peak_accel,
    symmetric_accel_time,
    symmetric_trapezoid_peak_accel,
    symmetric_trapezoid_peak_speed,
    time_optimal_duration,
    trapezoid_peak_speed,
)
from drivetrain.motion.profiles import parse_profile, ruckig_move


def test_doctests() -> None:
    assert doctest.testmod(profiles).failed == 0


# ----------------------------------------------------------------------------- lecture formulas


def test_lecture_symmetric_trapezoid() -> None:
    """Lecture, trapezoidal profile: v_max = x_f / t_2, a_max = x_f / (t_1 t_2), t_f = t_1 + t_2."""
    x_f, t_1, t_f = 0.3, 0.1, 0.5
    t_2 = t_f - t_1
    assert symmetric_trapezoid_peak_speed(x_f, t_2) == pytest.approx(0.75, rel=1e-15)
    assert symmetric_trapezoid_peak_accel(x_f, t_1, t_2) == pytest.approx(7.5, rel=1e-15)
    cycle = parse_profile([{"move": x_f, "time": t_f, "accel": t_1}], "linear")
    step = cycle.steps[0]
    assert step.peak_speed == pytest.approx(x_f / t_2, rel=1e-14)
    assert step.peak_accel == pytest.approx(x_f / (t_1 * t_2), rel=1e-14)
    # The lecture's piecewise x(t), v(t), a(t), one time in each phase.
    a_max, v_max = x_f / (t_1 * t_2), x_f / t_2
    t = np.array([0.05, 0.3, 0.45])
    k = cycle.evaluate(t)
    x_hand = [0.5 * a_max * t[0] ** 2, 0.5 * v_max * (2 * t[1] - t_1), x_f - 0.5 * a_max * (t_f - t[2]) ** 2]
    np.testing.assert_allclose(k.x, x_hand, rtol=1e-13)
    np.testing.assert_allclose(k.v, [a_max * t[0], v_max, a_max * (t_f - t[2])], rtol=1e-13)
    np.testing.assert_allclose(k.a, [a_max, 0.0, -a_max], rtol=1e-13, atol=1e-12)


def test_movement_amount_and_peak_speed_are_inverse() -> None:
    """Lecture, Movement Amount: L_s = V (2 t_s - t_a - t_d) / 2; with t_a = t_d, V (t_s - t_a)."""
    assert movement_amount(2.0, 1.0, 0.2, 0.4) == pytest.approx(2.0 * (2.0 - 0.6) / 2.0, rel=1e-15)
    assert movement_amount(2.0, 1.0, 0.2, 0.2) == pytest.approx(2.0 * (1.0 - 0.2), rel=1e-15)
    assert movement_amount(-2.0, 1.0, 0.2, 0.2) == pytest.approx(-1.6, rel=1e-15)
    assert trapezoid_peak_speed(1.4, 1.0, 0.2, 0.4) == pytest.approx(2.0, rel=1e-15)
    np.testing.assert_allclose(movement_amount([1.0, 3.0], 1.0, 0.5, 0.5), [0.5, 1.5])


def test_s_curve_formulas() -> None:
    assert s_curve_peak_accel(1.0, 0.2, 0.0) == pytest.approx(5.0)  # trapezoid: v / t_r
    assert s_curve_peak_accel(1.0, 0.2, 1.0) == pytest.approx(10.0)  # pure s-curve: 2 v / t_r
    t_j = float(s_curve_jerk_time(1.0, 0.2, 200.0))
    assert 200.0 * t_j * (0.2 - t_j) == pytest.approx(1.0, rel=1e-14)
    assert math.isnan(float(s_curve_jerk_time(1.0, 0.2, 99.0)))  # below 4 v / t_r^2 = 100


def test_time_optimal_closed_form_cases() -> None:
    # trapezoid reaching vmax: 1 m at 1 m/s, 2 m/s^2: 0.5 + 1 / 1 = 1.5 s
    assert time_optimal_duration(1.0, 1.0, 2.0) == pytest.approx(1.5, rel=1e-15)
    # triangle: 0.1 m at 2 m/s^2: 2 sqrt(d / a)
    assert time_optimal_duration(0.1, 10.0, 2.0) == pytest.approx(2 * math.sqrt(0.05), rel=1e-15)
    # pure jerk (no limit reached): 4 (d / (2 J))^(1/3)
    assert time_optimal_duration(1e-3, 10.0, 100.0, 10.0) == pytest.approx(4 * (1e-3 / 20.0) ** (1 / 3), rel=1e-14)
    np.testing.assert_array_equal(time_optimal_duration([0.0, -0.0], 1.0, 1.0, 1.0), [0.0, 0.0])
    assert time_optimal_duration(-1.0, 1.0, 2.0) == time_optimal_duration(1.0, 1.0, 2.0)


# ----------------------------------------------------------------------------- published examples


def test_yaskawa_feed_timing() -> None:
    """Yaskawa Sigma-II SGMVH manual 11.1.1 p.11-2 and Sigma-V 2.2.2 p.2-5 (published examples
    yaskawa_sigma2_speed_500kg and yaskawa_sigma5_geared_250kg share this timing).

    Inputs: V = 15 m/min, 0.275 m fed in t_m = 1.2 s, 40 feeds per minute. Published: t_cycle =
    1.5 s, t_a = 0.1 s, t_c = 1.0 s. The source finds t_a from the movement amount with t_a = t_d
    (L = V (t_m - t_a)); the profile is that trapezoid plus a dwell to fill the cycle.
    """
    v, feed, t_m, per_min = 15.0 / 60.0, 0.275, 1.2, 40
    t_cycle = 60.0 / per_min
    t_a = float(symmetric_accel_time(feed, v, t_m))
    assert t_cycle == pytest.approx(1.5, rel=0.01)
    assert t_a == pytest.approx(0.1, rel=0.01)
    by_distance = parse_profile(
        [{"move": "275 mm", "time": "1.2 s", "accel": f"{t_a} s"}, {"dwell": f"{t_cycle - t_m} s"}], "linear"
    )
    by_speed = parse_profile([{"speed": "15 m/min", "time": "1.2 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}], "linear")
    for cycle in (by_distance, by_speed):
        assert cycle.period == pytest.approx(1.5, rel=0.01)
        kinds = {p.kind: p.t1 - p.t0 for p in cycle.phases}
        assert kinds["accel"] == pytest.approx(0.1, rel=0.01)
        assert kinds["run"] == pytest.approx(1.0, rel=0.01)  # published t_c
        assert cycle.steps[0].peak_speed * 60.0 == pytest.approx(15.0, rel=1e-9)
        assert cycle.steps[0].distance == pytest.approx(0.275, rel=1e-12)
        # Motor speed N = V / P_B with the 10 mm lead, direct coupled: published 1500 min^-1.
        assert cycle.steps[0].peak_speed / 0.01 * 60.0 == pytest.approx(1500, rel=0.01)


# ----------------------------------------------------------------------------- parsing


def test_design_example_profile() -> None:
    """Two moves (trapezoid, s-curve) and two dwells (motor and brake holding), as in docs/axis-file.md."""
    cycle = parse_profile(
        [
            {"move": "200 mm", "time": "0.5 s", "accel": "0.1 s"},
            {"dwell": "0.3 s"},
            {"move": "-200 mm", "time": "0.5 s", "shape": "s_curve", "accel": "0.15 s", "jerk_fraction": 0.5},
            {"dwell": "0.3 s", "holding": "brake"},
        ],
        "linear",
    )
    assert cycle.period == pytest.approx(1.6)
    assert [s.kind for s in cycle.steps] == ["move", "dwell", "move", "dwell"]
    assert [s.holding for s in cycle.steps] == [None, "motor", None, "brake"]
    assert [s.move_index for s in cycle.steps] == [0, None, 1, None]
    s_curve = cycle.steps[2]
    assert s_curve.direction == -1 and s_curve.t_accel == pytest.approx(0.15)
    assert s_curve.t_jerk_accel == pytest.approx(0.0375)  # half of 0.5 * 0.15 s in each jerk piece
    assert [p.kind for p in cycle.phases] == ["accel", "run", "decel", "dwell"] * 2
    # The s-curve's accel phase spans its three pieces.
    assert sum(1 for s in cycle.segments if s.phase == 4) == 3
    k = cycle.evaluate([cycle.period])
    assert k.x[0] == pytest.approx(0.0, abs=1e-15)


def test_defaults_shapes_and_speed_sign() -> None:
    trap = parse_profile([{"move": 0.3, "time": 0.3}], "linear").steps[0]
    assert trap.t_accel == pytest.approx(0.1) and trap.peak_speed == pytest.approx(1.5)  # 1/3-1/3-1/3
    tri = parse_profile([{"move": 0.3, "time": 0.3, "shape": "triangle"}], "linear")
    assert tri.steps[0].peak_speed == pytest.approx(2.0) and [p.kind for p in tri.phases] == ["accel", "decel"]
    pure = parse_profile([{"move": 0.3, "time": 0.3, "shape": "s_curve"}], "linear").steps[0]
    assert pure.t_jerk_accel == pytest.approx(0.05)  # pure s-curve by default
    assert pure.peak_accel == pytest.approx(2 * 1.5 / 0.1)
    back = parse_profile([{"speed": "-30 m/min", "time": 1.0, "accel": 0.2, "decel": 0.3}], "linear").steps[0]
    assert back.distance == pytest.approx(-0.5 * (2.0 - 0.5) / 2.0) and back.direction == -1
    assert back.peak_decel == pytest.approx(0.5 / 0.3)


def test_s_curve_with_jerk_limit() -> None:
    cycle = parse_profile([{"move": 0.3, "time": 0.3, "shape": "s_curve", "accel": 0.1, "jerk": 1000}], "linear")
    step = cycle.steps[0]
    assert step.peak_jerk == pytest.approx(1000.0, rel=1e-12)
    s = cycle.sample(33)
    assert np.abs(s.j).max() <= 1000.0 * (1 + 1e-12)
    assert np.abs(s.v).max() == pytest.approx(1.5, rel=1e-12)


def test_rotary_units_thrust_and_time_optimal() -> None:
    cycle = parse_profile(
        [
            {"move": "90 deg", "time": "0.5 s", "law": "cycloidal", "thrust": "3 N*m"},
            {"move": "-0.25 turn", "max_speed": "300 rpm", "max_accel": "100 rad/s^2", "max_jerk": "5000 rad/s^3"},
            {"dwell": 0.2},
        ],
        "rotary",
    )
    cam, opt, _ = cycle.steps
    assert cam.distance == pytest.approx(math.pi / 2) and cam.thrust == pytest.approx(3.0)
    assert cam.peak_speed == pytest.approx(2.0 * (math.pi / 2) / 0.5)
    assert opt.thrust is None and opt.shape == "time_optimal"
    assert opt.duration == pytest.approx(float(time_optimal_duration(math.pi / 2, 10 * math.pi, 100.0, 5000.0)))
    s = cycle.sample(17)
    assert np.all(s.thrust[s.step == 0] == 3.0) and np.all(np.isnan(s.thrust[s.step != 0]))
    assert s.x[-1] == pytest.approx(0.0, abs=1e-14)


def test_samples_fields() -> None:
    cycle = parse_profile(
        [{"move": 1.0, "time": 1.0, "accel": 0.25}, {"dwell": 0.5}, {"move": -1.0, "time": 1.0},
         {"dwell": 0.5, "holding": "brake"}],
        "linear",
    )
    s = cycle.sample(8)  # rounded up to 9 per segment, and one breakaway sample where each move starts
    assert isinstance(s, Samples) and len(s.t) == 9 * len(cycle.segments) + 2
    assert s.breakaway is not None and list(s.step[s.breakaway]) == [0, 2] and not s.weights[s.breakaway].any()
    assert s.weights.sum() == pytest.approx(cycle.period, rel=1e-14)
    assert set(s.direction[s.step == 0]) == {1} and set(s.direction[s.step == 2]) == {-1}
    assert set(s.direction[s.step == 1]) == {0}
    assert s.holding[s.step == 1].all() and not s.holding[s.step != 1].any()
    assert s.braked[s.step == 3].all() and not s.braked[s.step != 3].any()
    for i, phase in enumerate(cycle.phases):
        ts = s.t[s.phase == i]
        assert ts.min() == phase.t0 and ts.max() == phase.t1
    # boundaries appear twice: left and right limits of acceleration at the end of the first ramp
    at = np.flatnonzero(s.t == 0.25)
    assert sorted(s.a[at]) == pytest.approx([0.0, (4.0 / 3.0) / 0.25])


def test_rms_of_trapezoid_acceleration_is_exact() -> None:
    """sum(w a^2) over the cycle equals the hand value a^2 (t_a + t_d) / T to 1e-12 relative."""
    cycle = parse_profile([{"move": 0.7, "time": 0.9, "accel": 0.13, "decel": 0.29}, {"dwell": 0.37}], "linear")
    step = cycle.steps[0]
    hand = math.sqrt((step.peak_accel**2 * 0.13 + step.peak_decel**2 * 0.29) / cycle.period)
    for n in (3, 5, 64):
        s = cycle.sample(n)
        assert s.rms(s.a) == pytest.approx(hand, rel=1e-12)
    # piecewise-linear torque squared (s-curve acceleration) is integrated exactly as well
    sc = parse_profile([{"move": 1.0, "time": 1.0, "shape": "s_curve", "jerk_fraction": 1.0, "accel": 0.4}], "linear")
    a_p = sc.steps[0].peak_accel
    assert sc.sample(3).integral(sc.sample(3).a ** 2) == pytest.approx(2 * a_p**2 * 0.4 / 3, rel=1e-12)


def test_evaluate_agrees_with_sample_and_segment() -> None:
    cycle = parse_profile([{"move": 0.2, "time": 0.4, "law": "modified_trapezoid"}, {"move": 0.1, "time": 0.3}],
                          "linear")
    s = cycle.sample(11)
    k = cycle.evaluate(s.t)
    inner = np.r_[np.diff(s.segment) == 0, False] & np.r_[False, np.diff(s.segment) == 0]
    np.testing.assert_allclose(k.x[inner], s.x[inner], rtol=0, atol=1e-15)
    np.testing.assert_allclose(k.a[inner], s.a[inner], rtol=0, atol=1e-10)
    seg = cycle.segments[2]
    np.testing.assert_allclose(seg.evaluate([seg.t0]).x, cycle.evaluate([seg.t0]).x)


# ----------------------------------------------------------------------------- errors

BAD: list[tuple[str, Any, str]] = [
    ("accel + decel too long", [{"move": 1, "time": 0.5, "accel": 0.3}], "profile[0].accel"),
    ("accel + decel too long, 3rd", [{"dwell": 1}, {"dwell": 1}, {"move": 1, "time": 0.5, "accel": 0.2, "decel": 0.4}],
     "profile[2].accel"),
    ("negative movement amount", [{"speed": 1, "time": 0.5, "accel": 0.6}], "profile[0].time"),
    ("jerk fraction > 1", [{"move": 1, "time": 1, "shape": "s_curve", "jerk_fraction": 1.5}],
     "profile[0].jerk_fraction"),
    ("jerk fraction < 0", [{"move": 1, "time": 1, "shape": "s_curve", "jerk_fraction": -0.1}],
     "profile[0].jerk_fraction"),
    ("jerk fraction on trapezoid", [{"move": 1, "time": 1, "jerk_fraction": 0.5}], "profile[0].jerk_fraction"),
    ("jerk too low", [{"move": 1, "time": 1, "shape": "s_curve", "accel": 0.25, "jerk": 1}], "profile[0].jerk"),
    ("jerk and fraction", [{"move": 1, "time": 1, "shape": "s_curve", "jerk": 1e3, "jerk_fraction": 0.2}],
     "profile[0].jerk"),
    ("zero time", [{"move": 1, "time": 0}], "profile[0].time"),
    ("negative time", [{"move": 1, "time": "-1 s"}], "profile[0].time"),
    ("zero accel", [{"move": 1, "time": 1, "accel": 0}], "profile[0].accel"),
    ("zero dwell", [{"dwell": "0 s"}], "profile[0].dwell"),
    ("empty cycle", [], "profile"),
    ("not a list", {"move": 1}, "profile"),
    ("unknown key", [{"move": 1, "time": 1, "acel": 0.1}], "profile[0].acel"),
    ("move and dwell", [{"move": 1, "time": 1, "dwell": 1}], "profile[0]"),
    ("neither", [{"time": 1}], "profile[0]"),
    ("not a mapping", ["move 1"], "profile[0]"),
    ("unknown shape", [{"move": 1, "time": 1, "shape": "sine"}], "profile[0].shape"),
    ("unknown law", [{"move": 1, "time": 1, "law": "harmonic"}], "profile[0].law"),
    ("unknown holding", [{"dwell": 1, "holding": "clutch"}], "profile[0].holding"),
    ("angle on linear axis", [{"move": "90 deg", "time": 1}], "profile[0].move"),
    ("speed in rpm on linear axis", [{"speed": "100 rpm", "time": 1, "accel": 0.1}], "profile[0].speed"),
    ("accel as acceleration", [{"move": 1, "time": 1, "accel": "2 m/s^2"}], "profile[0].accel"),
    ("thrust as torque on linear axis", [{"move": 1, "time": 1, "thrust": "2 N*m"}], "profile[0].thrust"),
    ("missing time", [{"move": 1, "accel": 0.1}], "profile[0].time"),
    ("move and speed", [{"move": 1, "speed": 1, "time": 1}], "profile[0].speed"),
    ("zero move", [{"move": "0 mm", "time": 1}], "profile[0].move"),
    ("triangle with accel", [{"move": 1, "time": 1, "shape": "triangle", "accel": 0.2}], "profile[0].accel"),
    ("decel without accel", [{"move": 1, "time": 1, "decel": 0.2}], "profile[0].decel"),
    ("law with accel", [{"move": 1, "time": 1, "law": "cycloidal", "accel": 0.2}], "profile[0].accel"),
    ("optimal without accel", [{"move": 1, "max_speed": 1}], "profile[0].max_accel"),
    ("optimal with time", [{"move": 1, "max_speed": 1, "max_accel": 1, "time": 1}], "profile[0].time"),
    ("optimal negative limit", [{"move": 1, "max_speed": -1, "max_accel": 1}], "profile[0].max_speed"),
    ("dwell with accel", [{"dwell": 1, "accel": 0.1}], "profile[0].accel"),
]


@pytest.mark.parametrize(("raw", "field"), [(b[1], b[2]) for b in BAD], ids=[b[0] for b in BAD])
def test_bad_input_names_the_field(raw: Any, field: str) -> None:
    with pytest.raises(InputError) as info:
        parse_profile(raw, "linear")
    assert info.value.field == field


def test_error_messages_are_helpful() -> None:
    with pytest.raises(InputError) as info:
        parse_profile([{"move": 1, "time": "0.5 s", "accel": "0.3 s"}], "linear")
    err = info.value
    assert (err.field, err.rule, err.value) == ("profile[0].accel", "accel + decel must not exceed the move time 0.5 s",
                                                "0.6 s")
    assert str(err).startswith("profile[0].accel: accel + decel must not exceed the move time 0.5 s, got ")
    with pytest.raises(InputError, match="valid keys: move, speed, time, accel"):
        parse_profile([{"move": 1, "time": 1, "acel": 0.1}], "linear")
    with pytest.raises(InputError, match="valid: trapezoid, triangle, s_curve"):
        parse_profile([{"move": 1, "time": 1, "shape": "sine"}], "linear")
    with pytest.raises(InputError, match="valid: cycloidal, modified_sine, modified_trapezoid, poly345"):
        parse_profile([{"move": 1, "time": 1, "law": "x"}], "linear")
    with pytest.raises(InputError) as info:
        parse_profile([{"move": "200 mm", "time": 1}], "rotary", field="axes[1].profile")
    assert info.value.field == "axes[1].profile[0].move"


# ----------------------------------------------------------------------------- ruckig_move


def test_ruckig_move_between_states() -> None:
    move = ruckig_move(0.0, 0.5, 0.0, 1.0, 0.2, 0.0, 1.0, 2.0, 10.0)
    t = np.linspace(0.0, move.duration, 201)
    k = move.evaluate(t)
    assert k.x[0] == 0.0 and k.v[0] == pytest.approx(0.5)
    assert k.x[-1] == pytest.approx(1.0, rel=1e-9) and k.v[-1] == pytest.approx(0.2, abs=1e-9)
    assert np.abs(k.v).max() <= 1.0 * (1 + 1e-12) and np.abs(k.j).max() <= 10.0 * (1 + 1e-12)
    rest = ruckig_move(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 2.0, 10.0)
    assert rest.duration == pytest.approx(float(time_optimal_duration(1.0, 1.0, 2.0, 10.0)), abs=1e-9)
    with pytest.raises(InputError):
        ruckig_move(0.0, 0.0, 0.0, 1.0, 2.0, 0.0, 1.0, 2.0, 10.0)  # target faster than vmax
    with pytest.raises(InputError):
        ruckig_move(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 10.0)


# ----------------------------------------------------------------------------- properties


@st.composite
def steps(draw: st.DrawFn) -> dict[str, Any]:
    """A random time-given move or dwell in bare SI numbers."""
    kind = draw(st.sampled_from(["accel", "shape", "s_curve", "law", "dwell"]))
    time = draw(st.floats(0.01, 10.0))
    if kind == "dwell":
        return {"dwell": time, "holding": draw(st.sampled_from(["motor", "brake"]))}
    move = draw(st.floats(1e-4, 10.0)) * draw(st.sampled_from([-1.0, 1.0]))
    if kind == "law":
        return {"move": move, "time": time, "law": draw(st.sampled_from(["cycloidal", "modified_sine",
                                                                         "modified_trapezoid", "poly345"]))}
    if kind == "shape":
        return {"move": move, "time": time, "shape": draw(st.sampled_from(["trapezoid", "triangle", "s_curve"]))}
    accel = draw(st.floats(0.01, 0.99)) * time
    decel = draw(st.floats(0.01, 1.0)) * (time - accel)
    step: dict[str, Any] = {"move": move, "time": time, "accel": accel, "decel": decel}
    if kind == "s_curve":
        step.update(shape="s_curve", jerk_fraction=draw(st.floats(0.0, 1.0)))
    return step


cycles = st.lists(steps(), min_size=1, max_size=5)
TIME_KEYS = ("time", "accel", "decel", "dwell")


def _scales(cycle: Cycle) -> tuple[float, float, float, float]:
    moves = [s for s in cycle.steps if s.kind == "move"]
    x = max([abs(s.x0) + abs(s.distance) for s in cycle.steps] + [1e-300])
    v = max([s.peak_speed for s in moves] + [1e-300])
    a = max([max(s.peak_accel, s.peak_decel) for s in moves] + [1e-300])
    j = max([s.peak_jerk for s in moves] + [1e-300])
    return x, v, a, j


@settings(max_examples=60, deadline=None)
@given(cycles)
def test_doubling_time_halves_speed_quarters_accel(raw: list[dict[str, Any]]) -> None:
    slow = [{k: 2.0 * v if k in TIME_KEYS else v for k, v in step.items()} for step in raw]
    a, b = parse_profile(raw, "linear").sample(9), parse_profile(slow, "linear").sample(9)
    xs, vs, as_, js = _scales(parse_profile(raw, "linear"))
    assert np.isfinite(np.c_[a.x, a.v, a.a, a.j, b.x, b.v, b.a, b.j]).all()
    np.testing.assert_allclose(b.t, 2.0 * a.t, rtol=1e-12, atol=0)
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9 * xs)
    np.testing.assert_allclose(b.v, a.v / 2.0, rtol=0, atol=1e-9 * vs)
    np.testing.assert_allclose(b.a, a.a / 4.0, rtol=0, atol=1e-9 * as_)
    np.testing.assert_allclose(b.j, a.j / 8.0, rtol=0, atol=1e-9 * js)


@settings(max_examples=60, deadline=None)
@given(cycles)
def test_reversing_moves_mirrors_motion(raw: list[dict[str, Any]]) -> None:
    back = [{k: -v if k == "move" else v for k, v in step.items()} for step in raw]
    a, b = parse_profile(raw, "linear").sample(9), parse_profile(back, "linear").sample(9)
    np.testing.assert_array_equal(a.t, b.t)
    for name in ("x", "v", "a", "j"):
        np.testing.assert_allclose(getattr(b, name), -getattr(a, name), rtol=1e-12, atol=1e-300, equal_nan=False)
    np.testing.assert_array_equal(b.direction, -a.direction)


@settings(max_examples=60, deadline=None)
@given(cycles)
def test_weights_and_continuity(raw: list[dict[str, Any]]) -> None:
    cycle = parse_profile(raw, "linear")
    s = cycle.sample(7)
    assert s.weights.sum() == pytest.approx(cycle.period, rel=1e-12)
    assert s.breakaway is not None
    assert np.all(s.weights[~s.breakaway] > 0) and np.all(s.weights[s.breakaway] == 0.0)
    assert np.isfinite(np.c_[s.x, s.v, s.a, s.j]).all()
    xs, vs, _, _ = _scales(cycle)
    left = np.flatnonzero(np.diff(s.segment))  # last sample of a segment, then first of the next
    np.testing.assert_allclose(s.t[left], s.t[left + 1], rtol=0, atol=1e-12 * cycle.period)
    assert np.abs(s.x[left] - s.x[left + 1]).max(initial=0.0) <= 1e-12 * xs
    assert np.abs(s.v[left] - s.v[left + 1]).max(initial=0.0) <= 1e-9 * vs
    trapezoids = [st.index for st in cycle.steps if st.shape in ("trapezoid", "triangle")]
    for seg in np.unique(s.segment[np.isin(s.step, trapezoids)]):
        a = s.a[s.segment == seg]
        assert np.ptp(a) <= 1e-12 * max(np.abs(a).max(), 1e-300)
