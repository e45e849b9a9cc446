"""The cascaded loop: tuning rule, margins, notch, and clear errors for unstable gains."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drivetrain.dynamics import (
    Chain,
    Notch,
    ServoLoop,
    analyse_loop,
    check_stable,
    notch_effect,
    propose_notch,
    tune,
    two_mass_chain,
)
from drivetrain.dynamics.control import margins
from drivetrain.errors import InputError

BENCH = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002)


def test_tuning_rule_respects_the_anti_resonance() -> None:
    f_ar = math.sqrt(500.0 / 5e-4) / (2 * math.pi)  # 159.2 Hz
    loop = tune(BENCH)  # highest the rule allows
    f_v = 0.5 * f_ar
    assert loop.velocity_kp == pytest.approx(2 * math.pi * f_v * 6e-4)
    assert loop.velocity_ti == pytest.approx(4 / (2 * math.pi * f_v))
    assert loop.position_kv == pytest.approx(2 * math.pi * f_v / 4)
    assert loop.acceleration_ff == pytest.approx(6e-4)
    assert "anti-resonance" in loop.notes[0]
    asked = tune(BENCH, 500.0)
    assert asked.velocity_kp == pytest.approx(loop.velocity_kp)
    assert "lowered" in asked.notes[0]
    low = tune(BENCH, 20.0)
    assert low.velocity_kp == pytest.approx(2 * math.pi * 20.0 * 6e-4)


def test_rigid_loop_margins_and_bandwidth() -> None:
    # A rigid inertia under the tuned loop: crossover near f_v, healthy phase margin, stable.
    rigid = Chain(inertia=np.array([6e-4]), stiffness=np.zeros(0))
    loop = tune(rigid, 50.0)
    a = analyse_loop(rigid, loop)
    assert a.stable
    assert a.velocity_margins.gain_crossover_hz == pytest.approx(50.0 * 1.03, rel=0.05)
    assert 45.0 < a.velocity_margins.phase_margin_deg < 80.0
    assert a.velocity_margins.gain_margin > 2.0
    assert 40.0 < a.velocity_bandwidth_hz < 120.0
    assert a.position_bandwidth_hz < a.velocity_bandwidth_hz
    bode = a.bode()
    assert bode["velocity_open_dB"].shape == a.freq_hz.shape


def test_margins_of_a_known_loop() -> None:
    # L(s) = K / (s (s + 1)^2): phase crossover at w = 1 rad/s where |L| = K/2 -> GM = 2/K.
    f = np.geomspace(1e-3, 10, 20000)
    s = 2j * math.pi * f
    k = 0.5
    m = margins(f, k / (s * (s + 1) ** 2))
    assert m.gain_margin == pytest.approx(2 / k, rel=1e-3)
    assert m.phase_crossover_hz == pytest.approx(1 / (2 * math.pi), rel=1e-3)


def test_unstable_gain_set_is_a_clear_input_error() -> None:
    loop = tune(BENCH)
    bad = loop.with_(velocity_kp=30 * loop.velocity_kp)
    with pytest.raises(InputError) as err:
        check_stable(BENCH, bad)
    assert err.value.field == "dynamics.loop"
    assert "unstable" in str(err.value) and "Hz" in str(err.value)
    assert not analyse_loop(BENCH, bad).stable
    check_stable(BENCH, loop)  # the tuned set passes


def test_bad_loop_settings_name_the_field() -> None:
    with pytest.raises(InputError) as err:
        ServoLoop(velocity_kp=-1.0, velocity_ti=0.01, position_kv=10.0)
    assert err.value.field == "dynamics.loop.velocity_kp"
    with pytest.raises(InputError) as err:
        ServoLoop(velocity_kp=1.0, velocity_ti=float("nan"), position_kv=10.0)
    assert err.value.field == "dynamics.loop.velocity_ti"


def test_notch_proposal_and_effect() -> None:
    f_r = math.sqrt(500.0 * 6e-4 / (1e-4 * 5e-4)) / (2 * math.pi)
    f_ar = math.sqrt(500.0 / 5e-4) / (2 * math.pi)
    n = propose_notch(f_r, f_ar, 80.0)
    assert n.center_hz == pytest.approx(f_r)
    assert n.depth == pytest.approx(min(0.1, (f_ar / f_r) ** 2))
    assert abs(n.response(f_r)) == pytest.approx(n.depth, rel=1e-9)
    # no more than 10 deg of lag at the loop bandwidth
    assert -math.degrees(np.angle(n.response(80.0))) <= 10.0 + 1e-6
    # the discrete biquad has the same depth at the centre (prewarped Tustin)
    b0, b1, b2, a1, a2 = n.discrete(125e-6)
    z = np.exp(2j * math.pi * f_r * 125e-6)
    h = (b0 + b1 / z + b2 / z**2) / (1 + a1 / z + a2 / z**2)
    assert abs(h) == pytest.approx(n.depth, rel=1e-9)
    eff = notch_effect(BENCH, tune(BENCH))
    assert eff["with"]["velocity_margins"]["phase_margin_deg"] > eff["without"]["velocity_margins"][
        "phase_margin_deg"]
    with pytest.raises(InputError):
        Notch(100.0, 10.0, depth=1.5)
