"""Units at the boundary: one pint registry, parse once, SI floats inside.

A bare number is SI. Strings carry units ("10 mm", "0.5 kg*cm^2", "3000 rpm", "30 m/min",
"15 ft/s", "5 lb", "4.5 lb*in^2", "oz*in*s^2", "lbf", "deg"). pint is imported lazily so that
``drivetrain --help`` stays fast; hot code never sees a Quantity.

Traps handled here (style.md, pint section): angles are dimensionless in pint, so a speed in
rpm is converted with an explicit 2*pi/60 rather than trusting radian bookkeeping; torque and
energy share a dimension, so each field names the quantity it expects; ``Nm`` is read as
newton-metre.
"""

from __future__ import annotations

import math
import re
import tokenize
from functools import lru_cache
from typing import TYPE_CHECKING, Any

from drivetrain import unit_cache
from drivetrain.errors import InputError

if TYPE_CHECKING:
    import pint

RPM_TO_RAD_S = 2.0 * math.pi / 60.0
"""[rad/s per rpm] one revolution is 2 pi rad, one minute 60 s."""

# quantity name -> (SI unit string for pint, pint dimensionality string, human description)
QUANTITIES: dict[str, tuple[str, str]] = {
    "length": ("m", "[length]"),
    "mass": ("kg", "[mass]"),
    "time": ("s", "[time]"),
    "inertia": ("kg*m^2", "[mass]*[length]^2"),
    "force": ("N", "[mass]*[length]/[time]^2"),
    "torque": ("N*m", "[mass]*[length]^2/[time]^2"),
    "energy": ("J", "[mass]*[length]^2/[time]^2"),
    "power": ("W", "[mass]*[length]^2/[time]^3"),
    "speed": ("m/s", "[length]/[time]"),
    "acceleration": ("m/s^2", "[length]/[time]^2"),
    "jerk": ("m/s^3", "[length]/[time]^3"),
    "angle": ("rad", ""),
    "angular_speed": ("rad/s", "1/[time]"),
    "angular_acceleration": ("rad/s^2", "1/[time]^2"),
    "angular_jerk": ("rad/s^3", "1/[time]^3"),
    "density": ("kg/m^3", "[mass]/[length]^3"),
    "pressure": ("Pa", "[mass]/[length]/[time]^2"),
    "linear_stiffness": ("N/m", "[mass]/[time]^2"),
    "torsional_stiffness": ("N*m/rad", "[mass]*[length]^2/[time]^2"),
    "linear_damping": ("N*s/m", "[mass]/[time]"),
    "torsional_damping": ("N*m*s/rad", "[mass]*[length]^2/[time]"),
    "turbulent_coefficient": ("N*m*s^2/rad^2", "[mass]*[length]^2"),
    "voltage": ("V", "[mass]*[length]^2/[time]^3/[current]"),
    "current": ("A", "[current]"),
    "frequency": ("Hz", "1/[time]"),
    "dimensionless": ("", ""),
}

_ROTATIONAL_SPEED = re.compile(r"(rpm|rps|r/min|rev|revolution|turn)")
_ANGLE_UNIT = re.compile(r"(rad|deg|degree|arcmin|arcsec)")
_NM = re.compile(r"(?<![A-Za-z_])Nm(?![A-Za-z_])")
_MAX_MAGNITUDE = 1e15
_POUND_OUNCE = re.compile(r"(?<![A-Za-z_])(oz|lb)(?![A-Za-z_])")


@lru_cache(maxsize=1)
def registry() -> pint.UnitRegistry:
    """The one shared pint registry (created on first use)."""
    import pint

    ureg: pint.UnitRegistry = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    ureg.define("kgf = kilogram * gravity = kilogram_force")
    ureg.define("rev = revolution")
    return ureg


def _normalise(text: str) -> str:
    text = text.strip().replace("·", "*").replace("²", "^2").replace("³", "^3").replace("−", "-")
    text = _NM.sub("N*m", text)
    return text.replace("r/min", "rpm").replace("min^-1", "rpm")


def parse(value: Any, quantity: str, field: str, *, allow_zero: bool = True) -> float:
    """Parse ``value`` into an SI float of the named ``quantity``.

    A bare number (int/float) is taken as SI. A string is parsed with pint and converted to
    the SI unit of ``quantity`` (see ``QUANTITIES``). Angular speeds in rpm are converted with
    the explicit factor 2*pi/60 [rad/s per rpm]. Raises ``InputError`` naming ``field`` for a
    wrong dimension, an unparsable string, NaN, infinity or an absurd magnitude (> 1e15 SI).
    """
    if quantity not in QUANTITIES:
        raise KeyError(f"unknown quantity {quantity!r}")
    if isinstance(value, bool) or value is None:
        raise InputError(field, f"must be a number or a quantity with units of {_describe(quantity)}", value)
    if isinstance(value, (int, float)):
        result = float(value)
    elif isinstance(value, str):
        try:
            result = _parse_cached(value, quantity)
        except InputError as exc:
            raise InputError(field, exc.rule, exc.value, has_value=exc.has_value) from None
    else:
        raise InputError(field, f"must be a number or a quantity with units of {_describe(quantity)}", value)
    if not math.isfinite(result):
        raise InputError(field, "must be a finite number", value)
    if abs(result) > _MAX_MAGNITUDE:
        raise InputError(field, f"magnitude is absurd (> {_MAX_MAGNITUDE:g} in SI)", value)
    if not allow_zero and result == 0.0:
        raise InputError(field, "must not be zero", value)
    return result


def _describe(quantity: str) -> str:
    si = QUANTITIES[quantity][0]
    return f"{quantity.replace('_', ' ')} ({si or 'dimensionless'})"


_NUMBER_UNIT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.+?)\s*")
_SIMPLE_UNIT = re.compile(r"[A-Za-zµΩ°_]+(?:\^-?\d+)?(?:\s*[*/]?\s*[A-Za-zµΩ°_]+(?:\^-?\d+)?)*")


@lru_cache(maxsize=4096)
def _parse_cached(text: str, quantity: str) -> float:
    """``_parse_string`` remembered: an axis re-sized again and again repeats the same strings.

    "<number> <unit>" with a plain product of units is the number times the unit's SI factor, the
    factor remembered per unit: an engineer editing a value changes the number, not the unit.
    """
    m = _NUMBER_UNIT.fullmatch(text)
    if m is not None and _SIMPLE_UNIT.fullmatch(m.group(2)):
        try:
            scale, offset = _unit_factor(m.group(2), quantity)
        except InputError:
            pass  # let the whole text be parsed, for the whole text's message
        else:
            if offset == 0.0:  # not an offset unit such as degC
                return float(m.group(1)) * scale
    return _parse_string(text, quantity, "")


@lru_cache(maxsize=512)
def _unit_factor(unit: str, quantity: str) -> tuple[float, float]:
    """SI value of one and of zero ``unit`` [SI per unit] (remembered on disk: ``unit_cache``)."""
    known = unit_cache.get(unit, quantity)
    if known is not None:
        return known
    factors = _parse_string(f"1 {unit}", quantity, ""), _parse_string(f"0 {unit}", quantity, "")
    unit_cache.put(unit, quantity, factors)
    return factors


def _parse_string(text: str, quantity: str, field: str) -> float:
    if len(text) > 200:
        raise InputError(field, "quantity text is too long (over 200 characters)", text[:40] + "...")
    norm = _normalise(text)
    try:
        number = float(norm)
    except ValueError:
        pass
    else:
        return number
    import pint

    ureg = registry()
    si_unit, _ = QUANTITIES[quantity]
    try:
        q: Any = ureg.Quantity(norm)
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, ValueError, TypeError,
            AttributeError, SyntaxError, AssertionError, KeyError, ZeroDivisionError, tokenize.TokenError,
            IndexError, RecursionError) as exc:
        raise InputError(field, f"is not a quantity with units of {_describe(quantity)} ({exc})", text) from None
    if quantity == "angular_speed" and not _ANGLE_UNIT.search(norm):
        # Revolutions per time ("3000 rpm", "3000 1/min", "50 Hz") -> rad/s with the explicit
        # 2 pi / 60: pint treats the radian as dimensionless, so a bare 1/min would lose 2 pi.
        try:
            if _ROTATIONAL_SPEED.search(norm):
                return float(q.to("revolution/minute").magnitude) * RPM_TO_RAD_S
            return float(q.to("1/minute").magnitude) * RPM_TO_RAD_S
        except pint.errors.DimensionalityError:
            pass
    try:
        if not si_unit:
            return float(q.to("dimensionless").magnitude)
        return float(q.to(si_unit).magnitude)
    except pint.errors.DimensionalityError:
        # Imperial habit: "oz*in*s^2" and "lb*in" mean ounce- and pound-force.
        forced = _POUND_OUNCE.sub(lambda m: m.group(1) + "f", norm)
        if forced != norm:
            try:
                return float(ureg.Quantity(forced).to(si_unit).magnitude)
            except pint.errors.DimensionalityError:
                pass
        raise InputError(
            field, f"has the wrong dimension: expected {_describe(quantity)}", text
        ) from None


def to_rpm(omega: float) -> float:
    """[rpm] from [rad/s]: omega * 60 / (2 pi)."""
    return omega / RPM_TO_RAD_S


def from_rpm(n: float) -> float:
    """[rad/s] from [rpm]: n * 2 pi / 60."""
    return n * RPM_TO_RAD_S


def convert(value: float, quantity: str, unit: str) -> float:
    """Convert an SI float of ``quantity`` to ``unit`` for display (e.g. N*m -> lbf*in)."""
    if quantity == "angular_speed" and unit in ("rpm", "r/min", "min^-1"):
        return to_rpm(value)
    ureg = registry()
    return float(ureg.Quantity(value, QUANTITIES[quantity][0] or "dimensionless").to(_normalise(unit)).magnitude)
