"""Regeneration and the braking resistor: Delta's published examples and energy invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle, load_metrics
from drivetrain.physics.regen import (
    DELTA_ROTOR_ENERGY_DIVISOR,
    builtin_resistor_sufficient,
    capacitor_energy,
    copper_loss,
    kinetic_energy,
    regen_cycle,
    resistance_window,
    resistor_max_resistance,
    resistor_rating,
    rotor_energy_delta,
)

RPM = 2 * math.pi / 60

# Delta ASDA-B2 user manual, Revision May 2018, chapter 2, p. 2-13 (manualshive.com/en/manual/delta/
# asd-b2-1521-f/2474519?page=34): "Regenerative power from empty load 3000 r/min to stop E_o (joule)"
# for each motor's rotor inertia J (x 1e-4 kg m^2), and E_o = J n^2 / 182.
DELTA_ROTOR_TABLE = [  # (motor, J [1e-4 kg m^2], E_o [J] as printed)
    ("ECMA-C0401", 0.037, "0.18"),
    ("ECMA-C0602", 0.177, "0.87"),
    ("ECMA-C0604", 0.277, "1.37"),
    ("ECMA-C0804", 0.68, "3.36"),
    ("ECMA-C0807", 1.13, "5.59"),
    ("ECMA-C1010", 2.65, "13.1"),
    ("ECMC-C0910", 2.62, "12.96"),
    ("ECMC-C1020", 4.45, "22.0"),
    ("ECMA-C1330", 12.7, "62.80"),
    ("ECMA-E1305", 8.17, "40.40"),
    ("ECMA-E1310", 8.41, "41.59"),
    ("ECMA-E1315", 11.18, "55.28"),
    ("ECMA-E1320", 14.59, "72.15"),
    ("ECMA-E1820", 34.68, "171.50"),
]


@pytest.mark.parametrize(("motor", "j", "printed"), DELTA_ROTOR_TABLE)
def test_delta_rotor_energy_table(motor: str, j: float, printed: str) -> None:
    """E_o = J n^2 / 182 at 3000 r/min; tolerance one unit of the printed last digit (Delta truncates some rows)."""
    decimals = len(printed.split(".")[1])
    assert float(rotor_energy_delta(j * 1e-4, 3000.0)) == pytest.approx(float(printed), abs=10.0**-decimals)


def test_delta_divisor_is_the_rounded_kinetic_energy() -> None:
    exact = 1.0 / (0.5 * RPM**2)
    assert exact == pytest.approx(DELTA_ROTOR_ENERGY_DIVISOR, abs=0.5)
    assert float(kinetic_energy(1e-4, 3000 * RPM)) == pytest.approx(float(rotor_energy_delta(1e-4, 3000.0)),
                                                                    rel=0.003)


def test_delta_external_load_example() -> None:
    """Delta ASDA-A&A+ user manual (Revision April 2009), §6-6-3, p. 6-42; same example in ASDA-B2 (May 2018) p. 2-15.

    "When external load torque is a +70 % rated torque and rotation speed reaches 3000 r/min,
    if using 400 W servo drive (rated torque: 1.27 N m), the users need to connect an external
    regenerative resistor which power is 2 x (0.7 x 1.27) x (3000 x 2 pi / 60) = 560 W, 40 ohm."
    The factor 2 is Delta's rule that a resistor dissipates on average 50 % of its rating
    (ASDA-A §6-6-3, built-in resistor table, footnote *1). Delta ignores the capacitors here
    (a continuous overhauling load fills them once). 560 W is rounded to 10 W.

    The 400 W drive's built-in resistor (same table): 40 ohm, 60 W, 30 W average, minimum 20 ohm.
    40 ohm must lie in the resistance window [20 ohm, U_on^2 / P_peak]; U_on is not printed,
    but it is at least the 220 V class bus, sqrt(2) x 220 V.
    """
    t = np.linspace(0.0, 10.0, 1001)
    speed = 3000 * RPM
    shaft = np.full(t.size, -0.7 * 1.27 * speed)
    regen = regen_cycle(t, shaft)
    assert regen.resistor_average_power == pytest.approx(0.7 * 1.27 * speed, rel=1e-12)
    rating = float(resistor_rating(regen.resistor_average_power, 0.5))
    assert rating == pytest.approx(560.0, abs=5.0)
    r_min, r_max = resistance_window(regen.resistor_peak_power, math.sqrt(2) * 220.0, 20.0)
    assert float(r_min) <= 40.0 <= float(r_max)
    # the built-in resistor (30 W average) cannot take 279 W: an external resistor is needed, as Delta says
    assert not bool(builtin_resistor_sufficient(regen.resistor_average_power, regen.resistor_peak_power,
                                                30.0, 40.0, math.sqrt(2) * 220.0))
    assert float(resistor_rating(30.0, 0.5)) == 60.0  # Delta: 30 W processed by the 60 W built-in resistor


def test_capacitor_energy_formula() -> None:
    assert float(capacitor_energy(2e-3, 400.0, 300.0)) == pytest.approx(0.5 * 2e-3 * (400**2 - 300**2))
    assert float(resistor_max_resistance(390.0, 0.0)) == math.inf


def test_capacitors_take_each_event_before_the_resistor() -> None:
    """Two identical braking events of 50 J each; capacitors absorb 20 J of each, the resistor the rest."""
    t = np.linspace(0.0, 4.0, 401)
    shaft = np.where((t > 0.5) & (t < 1.5), -50.0, 0.0) + np.where((t > 2.5) & (t < 3.5), -50.0, 0.0)
    regen = regen_cycle(t, shaft, capacitor_energy=20.0)
    assert regen.events.start.size == 2
    np.testing.assert_allclose(regen.events.capacitor_energy, 20.0)
    np.testing.assert_allclose(regen.events.resistor_energy, regen.events.bus_energy - 20.0, rtol=1e-12)
    assert regen.resistor_peak_power == pytest.approx(50.0)
    assert regen.resistor_average_power == pytest.approx(regen.resistor_energy / 4.0)
    big = regen_cycle(t, shaft, capacitor_energy=1e3)
    assert big.resistor_energy == 0.0
    assert big.resistor_peak_power == 0.0


def test_copper_loss_lowers_the_bus_energy() -> None:
    t = np.linspace(0.0, 1.0, 101)
    shaft = np.full(t.size, -100.0)
    current = np.full(t.size, 2.0)
    cu = copper_loss(current, 1.5)
    assert float(cu[0]) == pytest.approx(3 * 4.0 * 1.5)
    regen = regen_cycle(t, shaft, cu)
    assert regen.energy == pytest.approx((100.0 - 18.0) * 1.0)
    assert regen.shaft_energy == pytest.approx(100.0)
    assert float(regen.events.copper_energy.sum()) == pytest.approx(18.0)
    # copper loss above the braking power: nothing reaches the bus
    none = regen_cycle(t, shaft, copper_loss(current, 20.0))
    assert none.energy == 0.0
    assert none.events.start.size == 0
    assert none.shaft_energy == pytest.approx(100.0)


@given(st.lists(st.floats(-500.0, 500.0), min_size=2, max_size=80), st.floats(0.0, 50.0), st.floats(0.0, 100.0))
@settings(max_examples=200, deadline=None)
def test_regen_never_exceeds_the_mechanical_energy_returned(power: list[float], loss_scale: float,
                                                            e_c: float) -> None:
    p = np.array(power)
    t = np.linspace(0.0, 2.0, p.size)
    cu = loss_scale * np.abs(np.sin(np.arange(p.size)))
    regen = regen_cycle(t, p, cu, capacitor_energy=e_c)
    ev = regen.events
    assert regen.energy <= regen.shaft_energy + 1e-9
    assert np.all(ev.bus_energy <= ev.shaft_energy + 1e-9)
    np.testing.assert_allclose(ev.capacitor_energy + ev.resistor_energy, ev.bus_energy, rtol=1e-12, atol=1e-12)
    assert np.all(ev.capacitor_energy <= e_c + 1e-12)
    assert regen.resistor_peak_power <= regen.peak_power + 1e-12
    assert np.all(ev.stop > ev.start)


def lossless_axis(profile: list) -> dict:
    return {
        "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "16 mm", "length": "0.5 m",
                      "efficiency": 1.0, "incline": "0 deg", "load": {"mass": 30.0, "friction": 0.0}},
        "transmission": [{"type": "gearbox", "ratio": 3, "efficiency": 1.0, "inertia": 2e-5}],
        "profile": profile,
    }


@given(st.lists(st.tuples(st.floats(0.02, 0.5), st.floats(0.2, 2.0), st.floats(0.05, 0.45),
                          st.booleans()), min_size=1, max_size=4),
       st.floats(1e-6, 1e-3))
@settings(max_examples=30, deadline=None)
def test_a_lossless_horizontal_cycle_returns_all_its_kinetic_energy(moves: list, rotor: float) -> None:
    """No friction, no gravity, efficiency 1, no winding resistance: each decel gives back 1/2 J omega^2.

    Trapezoidal moves; J = load inertia at the motor shaft + rotor. The duty cycle's
    regen_energy_J (the same quadrature) agrees.
    """
    prof = []
    for dist, time, frac, back in moves:
        prof.append({"move": -dist if back else dist, "time": time, "accel": time * frac})
        prof.append({"dwell": 0.1})
    duty = duty_cycle(parse_axis(lossless_axis(prof)))
    torque = duty.motor_torque(rotor)
    regen = regen_cycle(duty.t, torque * duty.omega, weights=duty.weights, period=duty.period)
    j = duty.load_inertia + rotor
    phase = np.asarray(duty.samples.phase)
    tops = [float(np.max(np.abs(duty.omega[phase == k]))) for k, ph in enumerate(duty.cycle.phases)
            if ph.kind == "decel"]
    expected = float(np.sum(kinetic_energy(j, np.array(tops))))
    assert regen.energy == pytest.approx(expected, rel=1e-9)
    assert regen.events.start.size == len(tops)
    np.testing.assert_allclose(np.sort(regen.events.bus_energy), np.sort(kinetic_energy(j, np.array(tops))),
                               rtol=1e-9)
    assert regen.shaft_energy == pytest.approx(load_metrics(duty, torque)["regen_energy_J"], rel=1e-12)


@pytest.mark.parametrize("samples", [5, 12, 65, 1001])
def test_resistor_peak_is_the_power_when_the_capacitors_are_full(samples: int) -> None:
    """A braking ramp p_bus(t) = P0 (1 - t / T): the capacitors (E_C) are full at t* where
    P0 t* - P0 t*^2 / (2 T) = E_C, so the resistor's peak is p(t*) = P0 sqrt(1 - 2 E_C / (P0 T)),
    whatever the sampling (the power is linear between samples); Simpson-like weights too."""
    p0, period, e_c = 600.0, 0.1, 5.0
    t = np.linspace(0.0, period, samples)
    shaft = -p0 * (1.0 - t / period) - 1e-9  # negative at t = T too: one event
    exact = p0 * math.sqrt(1.0 - 2.0 * e_c / (p0 * period))
    assert regen_cycle(t, shaft, capacitor_energy=e_c).resistor_peak_power == pytest.approx(exact, rel=1e-9)
    if samples % 2:
        h = t[1] - t[0]
        w = np.full(samples, 2.0 * h / 3.0)
        w[1::2] = 4.0 * h / 3.0
        w[[0, -1]] = h / 3.0
        simpson = regen_cycle(t, shaft, capacitor_energy=e_c, weights=w)
        assert simpson.resistor_peak_power == pytest.approx(exact, rel=1e-9)
