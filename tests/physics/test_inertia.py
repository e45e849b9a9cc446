"""Inertia formulas of the lecture, and published inertia values (examples/published.json)."""

import math

import pytest

from drivetrain.physics import inertia as inr
from drivetrain.physics.materials import DENSITY, FRICTION, shear_modulus


def test_point_mass_and_parallel_axis() -> None:
    assert inr.point_mass(2.0, 0.5) == 0.5
    assert inr.parallel_axis(inr.solid_cylinder(4.0, 0.2), 4.0, 0.3) == pytest.approx(0.02 + 0.36)


def test_hollow_cylinder_reads_plus_errata() -> None:
    # ERRATA: J = M (D_o^2 + D_i^2) / 8; the density form must agree with it.
    rho, length, do, di = 7870.0, 0.3, 0.1, 0.06
    mass = inr.cylinder_mass(rho, length, do, di)
    assert inr.hollow_cylinder(mass, do, di) == pytest.approx(inr.cylinder_from_density(rho, length, do, di))


def test_block_and_composite() -> None:
    assert inr.rectangular_block(12.0, 0.1, 0.2) == pytest.approx(0.05)
    assert inr.composite([1.0, 2.0, 0.5]) == 3.5


def test_lecture_densities() -> None:
    assert DENSITY["iron"] == 7.87e3 and DENSITY["aluminium"] == 2.70e3
    assert FRICTION["steel_steel"].static == 0.78 and FRICTION["steel_steel"].sliding == 0.42


def test_stainless_shear_modulus_from_lecture() -> None:
    assert shear_modulus("stainless_steel") == pytest.approx(11e6 * 6894.757, rel=1e-6)


def test_fanuc_alpha_screw_and_table_inertia() -> None:
    """FANUC alpha series B-65142E/04, 4.1, p.31: Jb = 0.0008 (0.000803), Jw = 0.00162 kg m^2."""
    jb = inr.cylinder_from_density(7800.0, 1.0, 0.032)
    jw = inr.linear_mass_reflected(1000.0, 0.008 / (2 * math.pi))
    assert jb == pytest.approx(0.0008, rel=0.01)  # published to 1 significant figure
    assert jw == pytest.approx(0.00162, rel=0.01)
    # FANUC's kgf*cm*s^2 figures: 1 kg m^2 = 100 / 9.8 kgf cm s^2.
    assert jb * 100 / 9.8 == pytest.approx(0.0082, rel=0.01)
    assert jw * 100 / 9.8 == pytest.approx(0.0165, rel=0.01)


def test_fanuc_alpha_i_screw_inertia() -> None:
    """FANUC B-65262EN/03, 3.2.3: D = 40 mm, L = 1 m steel: Jb = 0.00196 kg m^2 (0.02 kgf cm s^2)."""
    jb = inr.cylinder_from_density(7800.0, 1.0, 0.04)
    assert jb == pytest.approx(0.00196, rel=0.005)
    assert jb * 100 / 9.8 == pytest.approx(0.02, rel=0.005)


def test_steel_screw_imperial_rule() -> None:
    # ERRATA: 0.0012 L D^4 oz-in-s^2 is pi rho / (32 g) x 16 with rho = 0.28 lb/in^3, g = 386 in/s^2.
    exact = math.pi * 0.28 * 16 / (32 * 386)
    assert inr.steel_screw_imperial(1.0, 1.0) == pytest.approx(exact, rel=0.06)
