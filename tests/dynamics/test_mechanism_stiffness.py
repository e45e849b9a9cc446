"""Mechanism stiffness across the stroke: catalog formulas, published belt data, two-mass checks, invariants.

Sources:
- THK General Catalog, Ball Screw, "Axial Rigidity of the Feed Screw System": K_S = A E / (1000 L)
  [N/um] for one fixed end, A E L / (1000 a b) for both ends fixed (A [mm^2], E = 2.06e5
  N/mm^2, lengths [mm]); the minimum of the latter is 4 A E / L at mid-span (University of Utah,
  ME EN 7960 Precision Machine Design, "Ball Screw Calculations", slide 4-26, source THK).
- ELATECH polyurethane timing belts (Goodyear Elatech catalog; copies
  https://goodyearrubberproducts.com/2012pdfs/Goodyear_Elatech_Polyurethane_PT_Belt_Division/files/
  assets/seo/page15.html (AT5, p. 14), page19.html (AT20, p. 18), page21.html (ATL5, p. 20)):
  allowable tensile load F_Tzul and specific spring rate C_spez per belt width.
- Parker Compax3 manual, "Toothed belt drive as two mass system" (C3I12T11, 4.4.9): belt spring
  D = D_1 + D_2 with D_i = D_spez / l_i, changing with the position of the moved mass, and the
  two-mass resonance of the motor inertia against the moved mass through that spring.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.dynamics import mechanism_stiffness as ms
from drivetrain.dynamics.chain import two_mass_chain
from drivetrain.dynamics.linear import natural_frequencies
from drivetrain.errors import InputError
from drivetrain.physics.belt_rack import linear_belt_spans

E_THK_N_MM2 = 2.06e5


# --- Screw drive ----------------------------------------------------------------------------------

def test_thk_shaft_rigidity_fixed_supported_by_hand() -> None:
    # THK: K_S = A E / (1000 L) [N/um]; d1 = 20 mm, nut 500 mm from the fixed bearing:
    # A = 314.16 mm^2 -> 314.16 x 2.06e5 / (1000 x 500) = 129.43 N/um.
    a_mm2 = math.pi * 20.0**2 / 4.0
    published = a_mm2 * E_THK_N_MM2 / (1000.0 * 500.0) * 1e6  # N/m
    k = ms.screw_shaft_stiffness(0.020, 0.500, 1.000, "fixed_supported")
    assert float(k) == pytest.approx(published, rel=1e-12)
    assert float(k) / 1e6 == pytest.approx(129.43, rel=1e-4)


def test_thk_shaft_rigidity_fixed_fixed_by_hand() -> None:
    # THK: K_S = A E L / (1000 a b); L = 500 mm, a = 200 mm, b = 300 mm -> 539.3 N/um;
    # at mid-span 4 A E / (1000 L) = 517.7 N/um, the minimum over the stroke.
    a_mm2 = math.pi * 20.0**2 / 4.0
    k = ms.screw_shaft_stiffness(0.020, np.array([0.200, 0.250]), 0.500, "fixed_fixed")
    assert k[0] / 1e6 == pytest.approx(a_mm2 * E_THK_N_MM2 * 500.0 / (1000.0 * 200.0 * 300.0))
    assert k[1] / 1e6 == pytest.approx(4.0 * a_mm2 * E_THK_N_MM2 / (1000.0 * 500.0))
    x = np.linspace(0.01, 0.49, 97)
    stroke = ms.screw_shaft_stiffness(0.020, x, 0.500, "fixed_fixed")
    assert float(stroke.min()) == pytest.approx(k[1], rel=1e-9)
    assert x[int(np.argmin(stroke))] == pytest.approx(0.25)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.006, 0.08), st.floats(0.2, 5.0), st.floats(0.01, 0.99))
def test_fixed_fixed_is_never_softer_than_fixed_supported(d: float, span: float, frac: float) -> None:
    x = frac * span
    ff = float(ms.screw_shaft_stiffness(d, x, span, "fixed_fixed"))
    fs = float(ms.screw_shaft_stiffness(d, x, span, "fixed_supported"))
    assert ff >= fs
    assert ff == pytest.approx(fs * span / (span - x))  # the far shaft length adds in parallel


@settings(max_examples=80, deadline=None)
@given(st.lists(st.floats(1e3, 1e10), min_size=1, max_size=6))
def test_series_is_at_most_the_weakest_element(ks: list[float]) -> None:
    total = float(ms.series(*ks))
    assert total <= min(ks) * (1 + 1e-12)
    assert total >= min(ks) / len(ks) * (1 - 1e-12)
    assert float(ms.series(*ks, math.inf)) == pytest.approx(total)


def test_screw_drive_parts_and_weakest_link() -> None:
    x = np.linspace(0.05, 0.95, 19)
    parts = ms.screw_drive_stiffness(0.0125, x, 1.0, "fixed_supported", nut_stiffness=200e6,
                                     bearing_stiffness=400e6)
    for name in ("shaft", "nut", "support bearing", "housing"):
        assert np.all(parts["total"] <= parts[name])
    stiff = ms.MechanismStiffness(position=x, parts={k: v for k, v in parts.items() if k != "total"},
                                  lever=0.01 / (2 * math.pi))
    assert stiff.worst_index == x.size - 1  # farthest from the fixed bearing
    assert stiff.weakest_link() == "shaft"
    assert stiff.weakest_link(0) == "nut"  # next to the bearing the short shaft is stiff
    assert np.allclose(stiff.torsional, stiff.axial * (0.01 / (2 * math.pi)) ** 2)


def test_screw_stiffness_inputs_rejected_by_name() -> None:
    with pytest.raises(InputError, match="nut_position"):
        ms.screw_shaft_stiffness(0.02, 1.0, 1.0, "fixed_fixed")
    with pytest.raises(InputError, match="mounting"):
        ms.screw_shaft_stiffness(0.02, 0.5, 1.0, "glued")
    with pytest.raises(InputError, match="nut_stiffness"):
        ms.screw_drive_stiffness(0.02, 0.5, 1.0, nut_stiffness=-1.0)


# --- Timing belt --------------------------------------------------------------------------------

@pytest.mark.parametrize(("profile", "f_tzul", "c_spez"), [
    # ELATECH tables: allowable tensile load F_Tzul [N] and specific spring rate C_spez [N], type M.
    ("AT5 10 mm", 560.0, 140_000.0), ("AT5 50 mm", 3500.0, 875_000.0), ("AT5 100 mm", 7000.0, 1_750_000.0),
    ("ATL5 25 mm", 2530.0, 632_500.0), ("ATL5 50 mm", 5060.0, 1_265_000.0),
    ("AT20 50 mm", 12000.0, 3_000_000.0), ("AT20 150 mm", 37000.0, 9_250_000.0)])
def test_elatech_specific_spring_rate_is_allowable_load_over_0p4_percent(profile: str, f_tzul: float,
                                                                          c_spez: float) -> None:
    assert ms.belt_specific_stiffness_from_tension(f_tzul) == pytest.approx(c_spez, rel=1e-12), profile


def test_belt_minimum_stiffness_positions() -> None:
    c, length = 1.0e6, 2.0
    x = np.linspace(0.01, length - 0.01, 199)
    omega = ms.linear_belt_stiffness(c, x, length, "omega")
    assert float(omega.min()) == pytest.approx(4.0 * c / length, rel=1e-3)  # BRECO: minimum at L1 = L2
    assert x[int(np.argmin(omega))] == pytest.approx(length / 2, abs=0.011)
    loop = ms.linear_belt_stiffness(c, x, length, "loop")
    assert np.all(np.diff(loop) < 0.0)  # softer the farther the carriage travels from the drive
    assert float(ms.linear_belt_stiffness(c, length, length, "loop")) == pytest.approx(2.0 * c / length)
    assert np.array_equal(ms.conveyor_stiffness(c, x, length), loop)


@settings(max_examples=80, deadline=None)
@given(st.floats(1e4, 1e7), st.floats(0.1, 6.0), st.floats(0.0, 1.0))
def test_belt_stiffness_never_below_equal_span_value(c: float, length: float, frac: float) -> None:
    # For a fixed total L1 + L2, c (1/L1 + 1/L2) >= 4 c / (L1 + L2).
    l1, l2 = linear_belt_spans(frac * length, length, "loop")
    k = float(ms.belt_drive_stiffness(c, l1, l2))
    assert k >= 4.0 * c / float(l1 + l2) * (1 - 1e-12)


def test_three_metre_belt_gantry_first_mode_in_tens_of_hz() -> None:
    # A 3 m belt axis, ELATECH ATL5 50 mm (C_spez = 1 265 000 N, p. 20), carriage 30 kg, drive pulley
    # pitch radius 30 mm, motor 1.2e-3 kg m^2 behind a 10:1 gearbox (0.12 kg m^2 at the pulley),
    # everything else rigid. Two-mass: omega^2 = k r^2 (1/J + 1/(m r^2))
    # (Parker Compax3: f = 1/2pi sqrt(D (1/m + r^2/J)), J seen at the pulley).
    c, length, m, r, j = 1_265_000.0, 3.0, 30.0, 0.030, 1.2e-3 * 10.0**2
    x = np.linspace(0.05, length, 60)
    k_x = ms.linear_belt_stiffness(c, x, length, "loop")
    stiff = ms.MechanismStiffness(position=x, parts={"belt": k_x, "carriage clamp": np.full_like(x, 5e8)},
                                  lever=r)
    f1 = np.array([natural_frequencies(two_mass_chain(j, m * r * r, float(kt)))[0] for kt in stiff.torsional])
    by_hand = np.sqrt(stiff.axial * (1.0 / m + r * r / j)) / (2.0 * math.pi)
    assert np.allclose(f1, by_hand, rtol=1e-9)
    assert 10.0 <= float(f1.min()) < 100.0
    assert int(np.argmin(f1)) == x.size - 1  # softest with the carriage at the idler
    assert stiff.weakest_link() == "belt"


def test_belt_inputs_rejected_by_name() -> None:
    with pytest.raises(InputError, match=r"belt\.specific_stiffness"):
        ms.belt_drive_stiffness(0.0, 1.0, 1.0)
    with pytest.raises(InputError, match="position"):
        ms.linear_belt_stiffness(1e6, 4.0, 3.0)


# --- Rack and pinion, and the input shaft --------------------------------------------------------

def test_rack_mesh_stiffness_by_hand() -> None:
    # c_gamma b cos^2(alpha): 20 N/(mm um) x 30 mm x cos^2 20 deg = 529.8 N/um.
    k = ms.rack_mesh_stiffness(0.030)
    assert k == pytest.approx(20e9 * 0.030 * math.cos(math.radians(20)) ** 2)
    assert k / 1e6 == pytest.approx(529.8, rel=1e-3)


def test_torsional_at_input_for_screw_lever() -> None:
    # k_theta = k_x (h / 2 pi)^2: 1e9 N/m through a 10 mm lead is 2533.0 N m/rad (as dynamics.stiffness).
    assert float(ms.torsional_at_input(1e9, 0.01 / (2 * math.pi))) == pytest.approx(2533.03, rel=1e-5)
