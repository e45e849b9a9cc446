"""Stiffness formulas: published values and closed forms."""

from __future__ import annotations

import math

import pytest

from drivetrain.dynamics import stiffness as st
from drivetrain.errors import InputError


def test_mathworks_servomechanism_shaft_stiffness() -> None:
    # MathWorks, "Design MPC Controller for Position Servomechanism" (mpcmotormodel.m):
    # d = 20 mm, L = 1 m, G = 81.5 GPa -> kT = 1280.2 N m/rad (published.json:
    # mathworks_servomech_shaft_stiffness, tolerance 1e-3 relative).
    k = st.torsional_stiffness_shaft(0.02, 1.0, 81.5e9)
    assert k == pytest.approx(1280.2, rel=1e-3)


def test_lecture_k_shaft_formula_imperial() -> None:
    # Lecture, "Mechanical Vibration in Drive Trains": K = pi D^4 G / (32 L); stainless G = 11e6 psi.
    # A 1 in x 10 in shaft: pi * 1 * 11e6 / 320 = 107,992 lb-in/rad (the formula is unit-consistent).
    assert st.torsional_stiffness_shaft(1.0, 10.0, 11e6) == pytest.approx(math.pi * 11e6 / 320.0)


def test_hollow_shaft_reduces_to_solid_and_loses_little_stiffness() -> None:
    solid = st.torsional_stiffness_shaft(0.04, 0.5, 80e9)
    assert st.torsional_stiffness_hollow_shaft(0.04, 0.0, 0.5, 80e9) == pytest.approx(solid)
    tube = st.torsional_stiffness_hollow_shaft(0.04, 0.02, 0.5, 80e9)
    assert tube == pytest.approx(solid * (1 - 0.5**4))


def test_series_and_parallel() -> None:
    assert st.stiffness_series([1000.0, 1000.0]) == pytest.approx(500.0)
    assert st.stiffness_series([1000.0, math.inf]) == pytest.approx(1000.0)
    assert st.stiffness_series([100.0, 1e9]) < 100.0
    assert st.stiffness_parallel([100.0, 300.0]) == pytest.approx(400.0)


def test_catalog_arcmin_and_reflection() -> None:
    # 1 arcmin = pi / 10800 rad: 10 N m/arcmin = 34,377.5 N m/rad.
    assert st.torsional_stiffness_from_arcmin(10.0) == pytest.approx(34377.467, rel=1e-6)
    # a gearbox of ratio 10 with that output stiffness is seen at the motor as K / 100
    assert st.reflect_stiffness(34377.467, 10.0) == pytest.approx(343.77467)
    assert st.reflect_damping(4.0, 2.0) == pytest.approx(1.0)
    assert st.arcmin_to_rad(60.0) == pytest.approx(math.radians(1.0))


def test_belt_stiffness_torsional() -> None:
    # c_sp = 1e6 N, span 0.5 m -> k = 2e6 N/m; pulley radius 20 mm -> K = k r^2 = 800 N m/rad
    assert st.belt_torsional_stiffness(1e6, 0.5, 0.02) == pytest.approx(800.0)
    # carriage between two 0.5 m spans: both act, twice as stiff
    assert st.belt_linear_drive_axial_stiffness(1e6, 0.5, 0.5) == pytest.approx(4e6)


def test_ball_screw_axial_to_torsional() -> None:
    # THK: fixed-fixed screw is 4x stiffer at mid-stroke than fixed-free over the same length.
    ff = st.screw_shaft_axial_stiffness(0.0166, 0.8, mounting="fixed_free")
    fx = st.screw_shaft_axial_stiffness(0.0166, 0.8, mounting="fixed_fixed")
    assert fx == pytest.approx(4 * ff)
    area = math.pi * 0.0166**2 / 4
    assert ff == pytest.approx(area * 206e9 / 0.8)
    k_ax = st.ball_screw_axial_stiffness(ff, nut_stiffness=1e9, bearing_stiffness=1e9)
    assert k_ax == pytest.approx(1.0 / (1 / ff + 2e-9))
    # lead 10 mm: K = k (h / 2 pi)^2
    assert st.torsional_from_axial_lead(k_ax, 0.01) == pytest.approx(k_ax * (0.01 / (2 * math.pi)) ** 2)


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: st.torsional_stiffness_shaft(-0.02, 1.0, 81.5e9), "diameter"),
        (lambda: st.torsional_stiffness_shaft(0.02, 0.0, 81.5e9), "length"),
        (lambda: st.torsional_stiffness_hollow_shaft(0.02, 0.03, 1.0, 81.5e9), "inner_diameter"),
        (lambda: st.stiffness_series([100.0, -5.0]), "stiffness[1]"),
        (lambda: st.screw_shaft_axial_stiffness(0.02, 1.0, mounting="floating"), "mounting"),
        (lambda: st.torsional_from_axial_lead(1e8, float("nan")), "lead"),
    ],
)
def test_bad_input_names_the_field(call: object, field: str) -> None:
    with pytest.raises(InputError) as err:
        call()  # type: ignore[operator]
    assert err.value.field == field
