"""Invariants of the duty cycle (issue: motion profiles and the duty cycle)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle, load_metrics
from drivetrain.physics.averages import rms


def screw_axis(profile: list, *, incline: str = "0 deg", mass: float = 20.0, friction: float = 0.0,
               thrust: float = 0.0, eta: float = 0.9, model: str = "four_quadrant") -> dict:
    return {
        "efficiency_model": model,
        "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "16 mm", "length": "0.5 m",
                      "efficiency": eta, "incline": incline,
                      "load": {"mass": mass, "friction": friction, "thrust": thrust}},
        "transmission": [{"type": "gearbox", "ratio": 3, "efficiency": 0.95, "inertia": 2e-5}],
        "profile": profile,
    }


moves = st.lists(
    st.tuples(st.floats(0.01, 0.5), st.floats(0.2, 2.0), st.floats(0.05, 0.45)), min_size=1, max_size=4)


@given(moves, st.floats(0.0, 0.3))
@settings(max_examples=40, deadline=None)
def test_reversing_every_move_mirrors_torques(spec: list, mu: float) -> None:
    """No gravity, no thrust: the mirrored profile gives exactly the negated torque."""
    prof = [{"move": d, "time": t, "accel": t * f} for d, t, f in spec]
    mirrored = [{"move": -d, "time": t, "accel": t * f} for d, t, f in spec]
    a = duty_cycle(parse_axis(screw_axis(prof, friction=mu)))
    b = duty_cycle(parse_axis(screw_axis(mirrored, friction=mu)))
    np.testing.assert_allclose(b.torque, -a.torque, rtol=1e-12, atol=1e-12)


@given(moves)
@settings(max_examples=40, deadline=None)
def test_doubling_every_time_quarters_inertial_torques(spec: list) -> None:
    prof = [{"move": d, "time": t, "accel": t * f} for d, t, f in spec]
    slow = [{"move": d, "time": 2 * t, "accel": 2 * t * f} for d, t, f in spec]
    a = duty_cycle(parse_axis(screw_axis(prof)))
    b = duty_cycle(parse_axis(screw_axis(slow)))
    np.testing.assert_allclose(b.torque, a.torque / 4, rtol=1e-9, atol=1e-12)


def test_rms_with_dwell_equals_the_lecture_formula() -> None:
    """T_rms = sqrt((T_P^2 t_a + T_L^2 (t_s - t_a - t_d) + T_S^2 t_d) / t_c), dwell at zero torque (brake)."""
    prof = [{"move": 0.3, "time": 1.0, "accel": 0.2, "decel": 0.1}, {"dwell": 0.7, "holding": "brake"}]
    duty = duty_cycle(parse_axis(screw_axis(prof, friction=0.1)))
    m = load_metrics(duty)
    tp, tl, ts = m["accel_torque_Nm"], m["run_torque_Nm"], m["decel_torque_Nm"]
    hand = math.sqrt((tp**2 * 0.2 + tl**2 * (1.0 - 0.2 - 0.1) + ts**2 * 0.1) / 1.7)
    assert m["rms_torque_Nm"] == pytest.approx(hand, rel=1e-9)


def test_rms_counts_the_holding_torque_when_the_motor_holds() -> None:
    """ERRATA: a vertical axis needs holding torque in the dwell unless a brake is set."""
    base = [{"move": 0.1, "time": 0.5, "accel": 0.1}]
    held = duty_cycle(parse_axis(screw_axis([*base, {"dwell": 1.0}], incline="90 deg")))
    braked = duty_cycle(parse_axis(screw_axis([*base, {"dwell": 1.0, "holding": "brake"}], incline="90 deg")))
    m_h, m_b = load_metrics(held), load_metrics(braked)
    hold = m_h["holding_torque_Nm"]
    assert hold == pytest.approx(20 * 9.80665 * 0.01 / (2 * math.pi) / 0.9 / 0.95 / 3, rel=1e-9)
    assert m_h["rms_torque_Nm"] ** 2 * 1.5 == pytest.approx(m_b["rms_torque_Nm"] ** 2 * 1.5 + hold**2 * 1.0, rel=1e-9)


def test_piecewise_constant_rms_is_exact() -> None:
    prof = [{"move": 0.2, "time": 0.6, "accel": 0.2}, {"dwell": 0.4}]
    duty = duty_cycle(parse_axis(screw_axis(prof, friction=0.05)), points_per_phase=5)
    fine = duty_cycle(parse_axis(screw_axis(prof, friction=0.05)), points_per_phase=401)
    assert rms(duty.torque, duty.weights, duty.period) == pytest.approx(
        rms(fine.torque, fine.weights, fine.period), rel=1e-12)


@given(st.floats(1.0, 100.0), st.floats(0.0, 0.4), st.floats(-0.5, 0.5), st.floats(0.3, 2.0), st.floats(0, 90))
@settings(max_examples=40, deadline=None)
def test_energy_balance_over_a_cycle(mass: float, mu: float, dist: float, t: float, incline_deg: float) -> None:
    """Lossless transmission: motor energy = potential energy change + friction work (+ 0 kinetic)."""
    if abs(dist) < 1e-3:
        return
    ax = screw_axis([{"move": dist, "time": t, "accel": t / 4}, {"dwell": 0.2}], incline=f"{incline_deg} deg",
                    mass=mass, friction=mu, eta=1.0)
    ax["transmission"][0]["efficiency"] = 1.0
    duty = duty_cycle(parse_axis(ax))
    energy = float(np.sum(duty.weights * duty.torque * duty.omega))
    g, th = 9.80665, math.radians(incline_deg)
    expected = mass * g * math.sin(th) * dist + mu * mass * g * math.cos(th) * abs(dist)
    assert energy == pytest.approx(expected, rel=1e-6, abs=1e-9)


def test_losses_only_consume_energy() -> None:
    """With efficiency < 1 the motor supplies at least the lossless energy, never less."""
    prof = [{"move": 0.3, "time": 0.8, "accel": 0.2}, {"move": -0.3, "time": 0.8, "accel": 0.2}]
    lossy = duty_cycle(parse_axis(screw_axis(prof, incline="30 deg", eta=0.8)))
    ideal_spec = screw_axis(prof, incline="30 deg", eta=1.0)
    ideal_spec["transmission"][0]["efficiency"] = 1.0
    ideal = duty_cycle(parse_axis(ideal_spec))
    e_lossy = float(np.sum(lossy.weights * lossy.torque * lossy.omega))
    e_ideal = float(np.sum(ideal.weights * ideal.torque * ideal.omega))
    assert e_ideal == pytest.approx(0.0, abs=1e-9)
    assert e_lossy > e_ideal


def test_conveyor_slip_limit_check() -> None:
    """Lecture: a_max < mu_0 g cos(alpha) (about 1 m/s^2 for mu_0 = 0.1); up the slope the weight's
    component g sin(alpha) must also be held, so the limit there is mu_0 g cos(alpha) - g sin(alpha)."""
    from drivetrain.sizing.pipeline import size

    base = {"mechanism": {"type": "conveyor", "diameter": "100 mm", "carrier_friction": 0.1, "incline": "2 deg",
                          "load": {"mass": 10}}}
    slow = size({**base, "profile": [{"move": 1.0, "time": 4.0, "accel": 1.0}]}).to_dict()["slip_check"]
    fast = size({**base, "profile": [{"move": 1.0, "time": 1.0, "accel": 0.1}]}).to_dict()["slip_check"]
    g, a = 9.80665, math.radians(2)
    assert slow["available"] == pytest.approx(0.1 * g * math.cos(a) - g * math.sin(a), rel=1e-12)
    assert slow["ok"] and not fast["ok"]


def test_guide_moments_and_rms_force() -> None:
    """Horizontal carriage: M_p = F_z l_x + F_x (l_z + d_p); F_T,RMS from the lecture's formula."""
    from drivetrain.sizing.pipeline import size

    out = size({
        "mechanism": {"type": "belt", "diameter": "50 mm", "load": {"mass": 10, "thrust": 20}},
        "profile": [{"move": 0.5, "time": 1.0, "accel": 0.25}, {"dwell": 1.0}],
        "guide": {"l_x": "0.1 m", "l_y": "0.05 m", "l_z": "0.2 m", "d_p": "0.03 m", "rated_pitch_moment": "40 N*m"},
    }).to_dict()["guide"]
    a = 0.5 / 0.75 / 0.25
    f_acc, f_vel, f_dec = 10 * a + 20, 20.0, -10 * a + 20
    hand = math.sqrt((f_acc**2 * 0.25 + f_vel**2 * 0.5 + f_dec**2 * 0.25 + 0.0) / 2.0)
    assert out["actuator_rms_force_N"] == pytest.approx(hand, rel=1e-9)
    assert out["peak_pitch_Nm"] == pytest.approx(10 * 9.80665 * 0.1 + f_acc * 0.23, rel=1e-9)
    assert out["checks"][0]["ok"]


def test_brake_holds_the_gravity_torque_at_its_shaft() -> None:
    from drivetrain.sizing.pipeline import size

    prof = [{"move": 0.1, "time": 0.5, "accel": 0.1}, {"dwell": 1.0, "holding": "brake"}]
    ax = screw_axis(prof, incline="90 deg", mass=20.0, eta=0.9)
    ax["transmission"] = [{"type": "brake", "holding_torque": "0.3 N*m"}, *ax["transmission"]]
    out = size(ax).to_dict()["brake_check"]
    # Holding is computed on the safe side (as motoring through the losses).
    need = 20 * 9.80665 * 0.01 / (2 * math.pi) / 0.9 / 0.95 / 3
    assert out["required"] == pytest.approx(need, rel=1e-9)
    assert out["ok"] == (need <= 0.3)
