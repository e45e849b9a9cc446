"""Winding temperature over a repeating cycle, and vendor derating rules."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.errors import InputError
from drivetrain.physics.motor_thermal import (
    INSULATION_RISE_K,
    copper_resistance,
    derating,
    periodic_rise,
    steady_rise,
    thermal_resistance,
    time_to_fraction,
)
from drivetrain.physics.regen import copper_loss

# Siemens 1FT7044-5AK7 (Configuration Manual 01/2009, Table 4-8, p. 90): I_0 = 5.7 A at 100 K,
# R_ph = 0.61 ohm at 20 degC, T_th = 35 min.
I0, RISE, R20, TAU = 5.7, 100.0, 0.61, 35 * 60.0


def march(t: np.ndarray, loss: np.ndarray, r_th: float, tau: float, cycles: int) -> np.ndarray:
    """Reference: the exact one-step recursion marched over many cycles in plain Python."""
    theta = 0.0
    out = np.zeros(t.size)
    for _ in range(cycles):
        out[0] = theta
        for k in range(t.size - 1):
            h = t[k + 1] - t[k]
            a = math.exp(-h / tau)
            slope = (1 - a) * tau / h if h > 0 else 1.0
            theta = a * theta + r_th * (loss[k + 1] - a * loss[k] - (loss[k + 1] - loss[k]) * slope)
            out[k + 1] = theta
    return out


def test_periodic_solution_equals_the_limit_of_marching() -> None:
    t = np.concatenate([np.linspace(0, 2, 21), np.linspace(2, 5, 31), np.linspace(5, 6, 11)])
    loss = np.concatenate([np.linspace(0, 300, 21), np.full(31, 40.0), np.linspace(40, 0, 11)])
    per = periodic_rise(t, loss, 0.3, 4.0)
    ref = march(t, loss, 0.3, 4.0, cycles=60)  # 60 cycles = 90 time constants
    np.testing.assert_allclose(per.rise, ref, rtol=1e-9, atol=1e-9)
    assert per.rise[0] == pytest.approx(per.rise[-1], rel=1e-12)
    w = np.diff(t)
    mean_loss = float(np.sum(w * (loss[1:] + loss[:-1]) / 2) / 6.0)
    assert float(per.mean) == pytest.approx(0.3 * mean_loss, rel=1e-12)
    assert float(per.peak) == pytest.approx(float(ref.max()), rel=1e-9)
    assert float(per.ripple) == pytest.approx(float(per.peak - per.mean))


def test_constant_loss_gives_the_steady_rise_without_ripple() -> None:
    t = np.linspace(0, 10, 101)
    per = periodic_rise(t, np.full(101, 50.0), 2.0, 30.0)
    np.testing.assert_allclose(per.rise, 100.0, rtol=1e-12)
    assert float(per.ripple) == pytest.approx(0.0, abs=1e-9)


def test_long_cycles_do_not_overflow() -> None:
    """A cycle of 1e5 time constants: the block-wise sums stay finite and the rise follows the loss."""
    t = np.linspace(0, 1e5, 2001)
    loss = np.where(t < 5e4, 10.0, 0.0)
    per = periodic_rise(t, loss, 1.0, 1.0)
    assert np.all(np.isfinite(per.rise))
    assert float(per.peak) == pytest.approx(10.0, rel=1e-9)


def test_rated_current_gives_the_rated_rise() -> None:
    """Siemens 1FT7044-5AK7: at I_0 = 5.7 A the winding reaches its 100 K rating."""
    r_hot = float(copper_resistance(R20, 20.0 + RISE))
    r_th = float(thermal_resistance(RISE, I0, r_hot))
    t = np.linspace(0, 60, 61)
    per = periodic_rise(t, copper_loss(np.full(61, I0), r_hot), r_th, TAU)
    assert float(per.mean) == pytest.approx(RISE, rel=1e-12)
    assert float(steady_rise(I0, I0, RISE)) == RISE
    assert float(per.time_to_95) == pytest.approx(3.0 * TAU, rel=0.002)  # ln 20 = 2.996
    assert float(time_to_fraction(TAU, 0.95)) == pytest.approx(TAU * math.log(20.0))
    with pytest.raises(ValueError):
        time_to_fraction(TAU, 1.0)


@given(st.lists(st.floats(0.0, 30.0), min_size=2, max_size=40), st.floats(0.1, 10.0), st.floats(0.05, 5.0),
       st.floats(1.0, 5000.0))
@settings(max_examples=150, deadline=None)
def test_temperature_rise_scales_with_i2r(currents: list[float], k: float, r: float, tau: float) -> None:
    i = np.array(currents)
    t = np.linspace(0.0, 3.0, i.size)
    r_th = 0.05
    base = periodic_rise(t, copper_loss(i, r), r_th, tau)
    scaled_i = periodic_rise(t, copper_loss(k * i, r), r_th, tau)
    scaled_r = periodic_rise(t, copper_loss(i, k * r), r_th, tau)
    np.testing.assert_allclose(scaled_i.rise, k**2 * base.rise, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(scaled_r.rise, k * base.rise, rtol=1e-9, atol=1e-12)
    assert float(base.peak) >= float(base.mean) - 1e-9
    assert float(base.peak) <= r_th * float(copper_loss(i, r).max()) + 1e-9


def test_rms_rule_matches_the_mean_of_the_time_resolved_model() -> None:
    """Mean rise over the cycle = rated rise x (I_rms / I_0)^2 with R_th from the rating."""
    t = np.linspace(0, 2, 201)
    i = 3.0 + 4.0 * np.sin(np.pi * t) ** 2
    r_th = float(thermal_resistance(RISE, I0, R20))
    per = periodic_rise(t, copper_loss(i, R20), r_th, TAU)
    w = np.diff(t)
    i2 = i**2
    i_rms = math.sqrt(float(np.sum(w * (i2[1:] + i2[:-1]) / 2)) / 2.0)
    assert float(per.mean) == pytest.approx(float(steady_rise(i_rms, I0, RISE)), rel=1e-12)


def test_vectorised_over_candidates() -> None:
    t = np.linspace(0, 1, 11)
    loss = np.vstack([np.full(11, 10.0), np.full(11, 20.0)])
    per = periodic_rise(t, loss, np.array([1.0, 2.0]), np.array([5.0, 50.0]))
    np.testing.assert_allclose(per.mean, [10.0, 40.0])
    assert per.rise.shape == (2, 11)
    with pytest.raises(InputError):
        periodic_rise(t, loss, 1.0, 0.0)


def test_copper_resistance_and_insulation_classes() -> None:
    assert float(copper_resistance(R20, 20.0)) == R20
    assert float(copper_resistance(1.0, 255.0 - 20.0 - 20.0 + 20.0 + 235.0 - 235.0)) == pytest.approx(
        (235.0 + 235.0) / 255.0)
    assert INSULATION_RISE_K["F"] == 105.0


KOLLMORGEN = [  # (ambient degC, altitude m, factor): KDN "Derating", AKM rows: 1 %/K 40-50 degC; 6/17/30/55 %
    (40.0, 1000.0, 1.0),
    (25.0, 500.0, 1.0),
    (50.0, 1000.0, 0.90),
    (45.0, 0.0, 0.95),
    (40.0, 1500.0, 0.94),
    (40.0, 2000.0, 0.94),
    (40.0, 2500.0, 0.83),
    (40.0, 3500.0, 0.70),
    (40.0, 4500.0, 0.45),
    (45.0, 1500.0, 0.95 * 0.94),
]


@pytest.mark.parametrize(("ambient", "altitude", "factor"), KOLLMORGEN)
def test_kollmorgen_akm_derating(ambient: float, altitude: float, factor: float) -> None:
    """Kollmorgen Developer Network, "Derating", servo motors table (https://kdn.kollmorgen.com/content/derating)."""
    assert float(derating(ambient, altitude, "kollmorgen_akm")) == pytest.approx(factor, rel=1e-12)


SIEMENS = [(20.0, 1.07), (30.0, 1.00), (40.0, 1.00), (41.0, 0.96), (45.0, 0.96), (50.0, 0.92), (55.0, 0.87)]


@pytest.mark.parametrize(("ambient", "factor"), SIEMENS)
def test_siemens_1ft7_derating_at_1000_m(ambient: float, factor: float) -> None:
    """Siemens S-1FT7 Configuration Manual 09/2018, Table 2-3, p. 32, row 1000 m (ambients rounded up to 5 degC)."""
    assert float(derating(ambient, 1000.0, "siemens_1ft7")) == pytest.approx(factor, rel=1e-12)


def test_derating_outside_the_vendor_range_names_the_field() -> None:
    with pytest.raises(InputError, match=r"environment\.altitude"):
        derating(40.0, 1500.0, "siemens_1ft7")
    with pytest.raises(InputError, match=r"environment\.ambient"):
        derating(60.0, 0.0, "kollmorgen_akm")
    with pytest.raises(InputError, match=r"environment\.altitude"):
        derating(20.0, 6000.0, "kollmorgen_akm")
    with pytest.raises(ValueError, match="method"):
        derating(20.0, 0.0, "yaskawa")
    np.testing.assert_allclose(derating(np.array([40.0, 50.0]), np.array([0.0, 2500.0])), [1.0, 0.9 * 0.83])


def test_peak_between_samples_is_found() -> None:
    """A ramp loss sampled at its ends only has the same peak as the same loss sampled finely."""
    coarse = periodic_rise(np.array([0.0, 3.0]), np.array([30.0, 0.0]), 0.05, 2.0)
    t = np.linspace(0.0, 3.0, 3001)
    fine = periodic_rise(t, 30.0 - 10.0 * t, 0.05, 2.0)
    assert float(coarse.peak) == pytest.approx(float(fine.peak), rel=1e-6)
    assert float(coarse.peak) > float(coarse.rise.max())
