"""Four physics fixes and the thrust sign (issue 12), each checked against a hand calculation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle, load_metrics
from drivetrain.errors import InputError
from drivetrain.sizing.pipeline import size

G = 9.80665


# --------------------------------------------------------------------------- (1) gearbox split


def belt_then_gearbox(profile: list | None = None) -> dict:
    """Rotary load 2 kg m^2 behind a belt 20/40 then a 10:1 gearbox; every element lossless."""
    return {
        "mechanism": {"type": "rotary", "load": {"inertia": 2.0}},
        "transmission": [
            {"type": "belt", "drive_teeth": 20, "driven_teeth": 40, "efficiency": 1.0,
             "drive_pulley": {"inertia": 1e-4}, "driven_pulley": {"inertia": 8e-4}},
            {"type": "gearbox", "ratio": 10, "efficiency": 1.0, "inertia": 1e-4},
        ],
        "extra_inertia": 2e-4,
        "motor": {"inertia": 5e-4, "rated_torque": 3.0, "peak_torque": 10.0, "max_speed": "6000 rpm"},
        "profile": profile or [{"move": "90 deg", "time": 0.5, "accel": 0.1}, {"dwell": 0.5}],
    }


def test_gearbox_split_reflects_what_turns_before_the_gearbox() -> None:
    """Lecture, Dynamic Loading and Gearbox Sizing: T_GR = (1 - k) T_M for a purely inertial load,
    k = J_motor side / J_total at the motor shaft. Motor side: rotor 5e-4, extra_inertia 2e-4, drive pulley
    1e-4, driven pulley 8e-4 / 2^2, gearbox input 1e-4 / 2^2 = 1.025e-3 kg m^2 with the rotor; load side
    2 / 20^2 = 5e-3 kg m^2. Gearbox output at motor peak = (1 - k) 10 N m x 2 x 10 = 165.975 N m, which is
    also J_L alpha_L with alpha_L = 10 / 6.025e-3 / 20 (the whole chain accelerated by the motor's peak)."""
    res = size(belt_then_gearbox())
    k = 1.025e-3 / 6.025e-3
    assert res.duty.load_inertia == pytest.approx(5.525e-3, rel=1e-12)
    assert res.motor is not None
    assert res.motor.gearbox_torque_split_k == pytest.approx(k, rel=1e-12)
    assert res.motor.gearbox_output_torque_at_motor_peak_Nm == pytest.approx((1 - k) * 10.0 * 20.0, rel=1e-12)
    assert res.motor.gearbox_output_torque_at_motor_peak_Nm == pytest.approx(2.0 * 10.0 / 6.025e-3 / 20.0,
                                                                                rel=1e-12)


def test_gearbox_torque_at_motor_peak_bounds_the_cycles_own_output_peak() -> None:
    """The cycle needs less than the motor's peak, so its own gearbox output peak is below the one at motor peak."""
    res = size(belt_then_gearbox())
    assert res.motor is not None and res.motor.peak_torque_Nm < 10.0
    assert res.motor.gearbox_output_peak_torque_Nm < res.motor.gearbox_output_torque_at_motor_peak_Nm


# --------------------------------------------------------------------------- (2) breakaway


def slideway(points: int = 64, static: float = 0.3) -> dict:
    """A 50 kg slide on a belt (r = 20 mm), mu 0.1, mu0 0.3, 0.2 m in 1 s with 0.25 s ramps, then a dwell."""
    return {
        "mechanism": {"type": "belt", "diameter": "40 mm", "efficiency": 1.0,
                      "load": {"mass": 50, "friction": 0.1, "static_friction": static}},
        "profile": [{"move": 0.2, "time": 1.0, "accel": 0.25}, {"dwell": 0.5}],
    }


def test_breakaway_only_where_motion_starts() -> None:
    """Decel torque = (-m a + mu m g) r; breakaway mu0 m g r + m a r only at the start of the move.

    v_peak = 0.2 / 0.75, a = v_peak / 0.25 = 1.0667 m/s^2: decel -50 a 0.02 + 0.1 50 g 0.02 = -0.0860 N m.
    """
    m = load_metrics(duty_cycle(parse_axis(slideway())))
    a = 0.2 / 0.75 / 0.25
    r = 0.02
    assert m["decel_torque_Nm"] == pytest.approx((-50 * a + 0.1 * 50 * G) * r, rel=1e-12)
    assert m["accel_torque_Nm"] == pytest.approx((50 * a + 0.3 * 50 * G) * r, rel=1e-12)
    assert m["peak_torque_Nm"] == pytest.approx((50 * a + 0.3 * 50 * G) * r, rel=1e-12)


def test_rms_does_not_depend_on_the_number_of_points_with_breakaway() -> None:
    """RMS by hand: accel (m a + mu m g) r for 0.25 s, run mu m g r for 0.5 s, decel for 0.25 s, dwell 0."""
    a = 0.2 / 0.75 / 0.25
    r = 0.02
    acc, run, dec = (50 * a + 5 * G) * r, 5 * G * r, (-50 * a + 5 * G) * r
    hand = math.sqrt((acc**2 * 0.25 + run**2 * 0.5 + dec**2 * 0.25) / 1.5)
    axis = parse_axis(slideway())
    for points in (3, 16, 17, 64, 301):
        assert load_metrics(duty_cycle(axis, points))["rms_torque_Nm"] == pytest.approx(hand, rel=1e-12)


def test_breakaway_samples_carry_no_weight_and_sit_at_the_start_of_each_move() -> None:
    s = parse_axis(slideway()).cycle().sample(9)
    starts = np.flatnonzero(s.breakaway)
    assert len(starts) == 1
    assert s.t[starts[0]] == 0.0 and s.v[starts[0]] == 0.0 and s.weights[starts[0]] == 0.0
    assert float(np.sum(s.weights)) == pytest.approx(1.5, rel=1e-15)


def test_rotary_breakaway_torque_at_the_start_only() -> None:
    axis = {"mechanism": {"type": "rotary", "load": {"inertia": 0.1, "friction_torque": 1.0,
                                                    "static_friction_torque": 3.0}},
            "profile": [{"move": "1 rev", "time": 1.0, "accel": 0.25}, {"dwell": 0.5}]}
    m = load_metrics(duty_cycle(parse_axis(axis)))
    alpha = 2 * math.pi / 0.75 / 0.25
    assert m["accel_torque_Nm"] == pytest.approx(0.1 * alpha + 3.0, rel=1e-12)
    assert m["decel_torque_Nm"] == pytest.approx(-0.1 * alpha + 1.0, rel=1e-12)
    acc, run, dec = 0.1 * alpha + 1.0, 1.0, -0.1 * alpha + 1.0
    hand = math.sqrt((acc**2 * 0.25 + run**2 * 0.5 + dec**2 * 0.25) / 1.5)
    for points in (3, 16, 65):
        assert load_metrics(duty_cycle(parse_axis(axis), points))["rms_torque_Nm"] == pytest.approx(hand, rel=1e-12)


# --------------------------------------------------------------------------- (3) guide RMS force


def test_guide_actuator_rms_force_has_the_friction_term() -> None:
    """Lecture, linear actuator pages: F_actuator = (W_L / g) a + F_applied + mu W_L, and
    F_T,RMS = sqrt((F_acc^2 t_a + F_vel^2 t_v + F_dec^2 t_d + F_off^2 t_off) / t_total).

    A belt actuator, mu 0.12, 20 kg, 0.3 m in 1 s with 0.2 s ramps, 0.5 s off: the off force is 0.
    """
    axis = {"mechanism": {"type": "belt", "diameter": "30 mm",
                          "load": {"mass": 20, "friction": 0.12}},
            "guide": {"l_z": "50 mm"},
            "profile": [{"move": 0.3, "time": 1.0, "accel": 0.2}, {"dwell": 0.5}]}
    res = size(axis)
    a = 0.3 / 0.8 / 0.2
    w = 20 * G
    f_acc, f_vel, f_dec = 20 * a + 0.12 * w, 0.12 * w, -20 * a + 0.12 * w
    hand = math.sqrt((f_acc**2 * 0.2 + f_vel**2 * 0.6 + f_dec**2 * 0.2) / 1.5)
    assert res.guide.actuator_rms_force_N == pytest.approx(hand, rel=1e-12)


# --------------------------------------------------------------------------- (4) negative Coulomb torque


@pytest.mark.parametrize("mech", ["rotary", "custom"])
@pytest.mark.parametrize("key", ["friction_torque", "static_friction_torque"])
def test_negative_coulomb_torque_is_refused(mech: str, key: str) -> None:
    axis = {"mechanism": {"type": mech, "load": {"inertia": 0.1, key: -0.5}},
            "profile": [{"move": "1 rev", "time": 1.0}]}
    with pytest.raises(InputError) as err:
        parse_axis(axis)
    assert err.value.field == f"mechanism.load.{key}"
    assert ">= 0" in str(err.value)


# --------------------------------------------------------------------------- thrust sign


def thrust_axis(mode: str | None = None, thrust: float = 100.0) -> dict:
    load: dict = {"mass": 10, "thrust": thrust}
    if mode is not None:
        load["thrust_mode"] = mode
    return {"mechanism": {"type": "belt", "diameter": "40 mm", "efficiency": 1.0, "load": load},
            "profile": [{"move": 0.2, "time": 1.0, "accel": 0.25}, {"move": -0.2, "time": 1.0, "accel": 0.25}]}


def run_torques(axis: dict) -> tuple[float, float]:
    duty = duty_cycle(parse_axis(axis))
    rows = [r for r in load_metrics(duty)["segments"] if r["kind"] == "run"]
    return rows[0]["torque_Nm"], rows[1]["torque_Nm"]


def test_thrust_acts_against_the_motion_by_default() -> None:
    """ServoSoft quadrant pages: +T_Thrust in quadrants 1-2, -T_Thrust in quadrants 3-4 (against the motion)."""
    fwd, back = run_torques(thrust_axis())
    assert fwd == pytest.approx(100 * 0.02, rel=1e-12)
    assert back == pytest.approx(-100 * 0.02, rel=1e-12)
    assert run_torques(thrust_axis("against_motion")) == (fwd, back)


def test_signed_thrust_keeps_its_sign_on_the_return_move() -> None:
    """``thrust_mode: signed``: an external force of fixed direction (a spring-less constant push)."""
    fwd, back = run_torques(thrust_axis("signed"))
    assert fwd == pytest.approx(2.0, rel=1e-12)
    assert back == pytest.approx(2.0, rel=1e-12)


def test_rotary_process_torque_against_the_motion() -> None:
    axis = {"mechanism": {"type": "rotary", "load": {"inertia": 0.1, "torque": 5.0}},
            "profile": [{"move": "1 rev", "time": 1.0, "accel": 0.25}, {"move": "-1 rev", "time": 1.0, "accel": 0.25}]}
    fwd, back = run_torques(axis)
    assert (fwd, back) == (pytest.approx(5.0), pytest.approx(-5.0))
    axis["mechanism"]["load"]["thrust_mode"] = "signed"
    assert run_torques(axis) == (pytest.approx(5.0), pytest.approx(5.0))


def test_per_move_thrust_follows_the_same_rule() -> None:
    axis = thrust_axis(thrust=0.0)
    axis["profile"][1]["thrust"] = 50.0
    assert run_torques(axis)[1] == pytest.approx(-50 * 0.02, rel=1e-12)


# --------------------------------------------------------------------------- properties


@given(st.lists(st.tuples(st.floats(-0.5, 0.5).filter(lambda d: abs(d) > 1e-3), st.floats(0.2, 2.0),
                          st.floats(0.05, 0.45)), min_size=1, max_size=4),
       st.floats(0.0, 0.3), st.floats(0.0, 0.5), st.sampled_from(["0 deg", "30 deg", "90 deg"]))
@settings(max_examples=40, deadline=None)
def test_rms_is_the_same_at_any_number_of_points(moves: list, mu: float, extra: float, incline: str) -> None:
    """Piecewise-linear torque (no speed-dependent load): Simpson is exact, and breakaway weighs nothing."""
    prof: list = []
    for d, t, f in moves:
        prof += [{"move": d, "time": t, "accel": t * f}, {"dwell": 0.1}]
    axis = parse_axis({"mechanism": {"type": "ball_screw", "lead": "10 mm", "efficiency": 0.9, "incline": incline,
                                     "load": {"mass": 20, "friction": mu, "static_friction": mu + extra,
                                              "thrust": 30}},
                       "transmission": [{"type": "gearbox", "ratio": 3, "efficiency": 0.95}],
                       "profile": prof})
    coarse, fine = load_metrics(duty_cycle(axis, 5)), load_metrics(duty_cycle(axis, 65))
    assert coarse["rms_torque_Nm"] == pytest.approx(fine["rms_torque_Nm"], rel=1e-9)
    assert coarse["peak_torque_Nm"] == pytest.approx(fine["peak_torque_Nm"], rel=1e-9)


@given(st.lists(st.tuples(st.floats(0.01, 0.5), st.floats(0.2, 2.0), st.floats(0.05, 0.45)), min_size=1, max_size=4),
       st.floats(-200.0, 200.0), st.floats(0.0, 0.3))
@settings(max_examples=30, deadline=None)
def test_mirrored_moves_negate_the_torque_with_a_thrust_against_the_motion(moves: list, thrust: float,
                                                                           mu: float) -> None:
    """Level axis, thrust against the motion: every quadrant mirrors (lecture: -T_Thrust in quadrants 3 and 4)."""
    def axis(sign: float) -> dict:
        return {"mechanism": {"type": "ball_screw", "lead": "10 mm", "efficiency": 0.9,
                              "load": {"mass": 20, "friction": mu, "static_friction": mu * 1.5, "thrust": thrust}},
                "transmission": [{"type": "gearbox", "ratio": 3, "efficiency": 0.95, "inertia": 2e-5}],
                "profile": [{"move": sign * d, "time": t, "accel": t * f} for d, t, f in moves]}
    a = duty_cycle(parse_axis(axis(1.0)))
    b = duty_cycle(parse_axis(axis(-1.0)))
    np.testing.assert_allclose(b.torque, -a.torque, rtol=1e-12, atol=1e-12)
