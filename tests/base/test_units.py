"""Units at the boundary: parsing, SI conversion and the pint traps (style.md)."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.errors import InputError
from drivetrain.units import convert, parse, to_rpm

CASES = [
    ("10 mm", "length", 0.010),
    ("0.5 kg*cm^2", "inertia", 0.5e-4),
    ("3000 rpm", "angular_speed", 3000 * 2 * math.pi / 60),
    ("3000 r/min", "angular_speed", 3000 * 2 * math.pi / 60),
    ("30 m/min", "speed", 0.5),
    ("15 ft/s", "speed", 15 * 0.3048),
    ("5 lb", "mass", 5 * 0.45359237),
    ("4.5 lb*in^2", "inertia", 4.5 * 0.45359237 * 0.0254**2),
    ("1 oz*in*s^2", "inertia", 0.45359237 / 16 * 9.80665 * 0.0254),
    ("2 lbf", "force", 2 * 4.4482216152605),
    ("10 lbf*in", "torque", 10 * 4.4482216152605 * 0.0254),
    ("90 deg", "angle", math.pi / 2),
    ("2 Nm", "torque", 2.0),
    ("3 N·m", "torque", 3.0),
    ("60 N*m/arcmin", "torsional_stiffness", 60 * 180 * 60 / math.pi),
]


@pytest.mark.parametrize(("text", "quantity", "expected"), CASES)
def test_parse_to_si(text: str, quantity: str, expected: float) -> None:
    assert parse(text, quantity, "f") == pytest.approx(expected, rel=1e-9)


def test_bare_number_is_si() -> None:
    assert parse(0.01, "length", "f") == 0.01
    assert parse("0.01", "length", "f") == 0.01


def test_rpm_uses_explicit_two_pi_over_sixty() -> None:
    # pint treats the radian as dimensionless; rpm -> rad/s must still carry 2 pi.
    assert parse("60 rpm", "angular_speed", "f") == pytest.approx(2 * math.pi, rel=1e-12)
    assert to_rpm(2 * math.pi) == pytest.approx(60.0)
    assert convert(2 * math.pi, "angular_speed", "rpm") == pytest.approx(60.0)


def test_wrong_dimension_names_the_field() -> None:
    with pytest.raises(InputError) as err:
        parse("10 kg", "length", "mechanism.lead")
    assert err.value.field == "mechanism.lead"
    assert "wrong dimension" in str(err.value) and "10 kg" in str(err.value)


@pytest.mark.parametrize("bad", ["nan", "inf m", "1e30 m", "ten mm", "", True, None, [1], ")", "(("])
def test_bad_values_are_input_errors(bad: object) -> None:
    with pytest.raises(InputError):
        parse(bad, "length", "x")


def test_torque_and_energy_are_named_apart() -> None:
    assert parse("2 J", "energy", "e") == 2.0
    assert parse("2 N*m", "torque", "t") == 2.0


@given(st.floats(-1e6, 1e6, allow_nan=False), st.sampled_from([
    ("kg", "mass"), ("g", "mass"), ("lb", "mass"), ("mm", "length"), ("m/s", "speed"), ("mm/s^2", "acceleration"),
    ("kg*m^2", "inertia"), ("oz*in*s^2", "inertia"), ("N*m", "torque"), ("lbf*in", "torque"), ("rpm", "angular_speed"),
    ("1/min", "angular_speed"), ("deg/s", "angular_speed"), ("N/mm", "linear_stiffness"), ("N m/arcmin",
                                                                                       "torsional_stiffness")]))
@settings(max_examples=300, deadline=None)
def test_number_times_remembered_unit_equals_the_full_parse(number: float, unit_quantity: tuple[str, str]) -> None:
    """The fast path for "<number> <unit>" (the unit's SI factor remembered) gives pint's own answer."""
    from drivetrain.units import _parse_cached, _parse_string

    unit, quantity = unit_quantity
    text = f"{number!r} {unit}"
    assert _parse_cached(text, quantity) == pytest.approx(_parse_string(text, quantity, "f"), rel=1e-12, abs=1e-300)
