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
from typing import TYPE_CHECKING, Any, Final

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
    "resistance": ("ohm", "[mass]*[length]^2/[time]^3/[current]^2"),
    "inductance": ("H", "[mass]*[length]^2/[time]^2/[current]^2"),
    "capacitance": ("F", "[current]^2*[time]^4/[mass]/[length]^2"),
    "torque_constant": ("N*m/A", "[mass]*[length]^2/[time]^2/[current]"),
    "back_emf_constant": ("V*s", "[mass]*[length]^2/[time]^2/[current]"),
    "celsius": ("degC", "[temperature]"),
    "temperature_difference": ("K", "[temperature]"),
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
    if isinstance(value, int) and abs(value) > _MAX_MAGNITUDE:
        raise InputError(field, f"magnitude is absurd (> {_MAX_MAGNITUDE:g} in SI)", value)
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
    check_grammar(_normalise(text))
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


MAX_QUANTITY_TEXT = 100
"""Longest quantity text accepted [characters]: "0.5 kg*cm^2" is 11, a vendor's longest unit about 30."""
MAX_UNIT_POWER = 12
"""Largest power of one unit in a quantity text (``m^3``, ``1/s^2``; nothing real goes past 4)."""
_MAX_DIGITS = 40
_MAX_PAREN_DEPTH = 3
_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|(?P<name>[^\W\d][\w°]*|°)"
    r"|(?P<pow>\*\*|\^)|(?P<op>[*/()])|(?P<sign>[-+])|(?P<pct>%))"
)


def check_grammar(text: str, field: str = "") -> None:
    """Refuse quantity text that is not ``[sign] [number] [unit expression]``, before pint sees it.

    A unit expression is unit names joined by ``*``, ``/`` or a space, each optionally raised to a
    small literal power (``^2``, ``**-1``), grouped by at most three levels of parentheses; ``1``
    may stand for a missing numerator (``1/min``). Nothing computes: no operator applies to the
    number, no power is larger than ``MAX_UNIT_POWER`` once the groups are multiplied out, and the
    text is at most ``MAX_QUANTITY_TEXT`` characters. pint's own parser evaluates arithmetic
    (``9**9**9 mm`` would run for minutes), so every string goes through here first.
    """
    if len(text) > MAX_QUANTITY_TEXT:
        raise InputError(field, f"quantity text is too long (over {MAX_QUANTITY_TEXT} characters)",
                         text[:40] + "...")
    tokens: list[tuple[str, str]] = []
    pos = 0
    stripped = text.rstrip()
    while pos < len(stripped):
        m = _TOKEN.match(stripped, pos)
        if m is None or m.end() == pos:
            raise InputError(field, f"is not a quantity: unexpected {stripped[pos:pos + 10]!r}", text)
        kind = m.lastgroup or ""
        tokens.append((kind, m.group(kind)))
        pos = m.end()
    _Grammar(tokens, text, field).quantity()


class _Grammar:
    """Recursive descent over the tokens of one quantity text (see ``check_grammar``)."""

    def __init__(self, tokens: list[tuple[str, str]], text: str, field: str) -> None:
        self.tokens = tokens
        self.i = 0
        self.text = text
        self.field = field

    def _peek(self) -> tuple[str, str]:
        return self.tokens[self.i] if self.i < len(self.tokens) else ("end", "")

    def _fail(self, rule: str) -> InputError:
        return InputError(self.field, f"is not a quantity: {rule} (write a number and a unit, e.g. 10 mm)",
                          self.text)

    def quantity(self) -> None:
        if self._peek()[0] == "sign":
            self.i += 1
        kind, tok = self._peek()
        if kind == "num":
            mantissa = re.split(r"[eE]", tok)
            if len(mantissa[0]) > _MAX_DIGITS or (len(mantissa) > 1 and len(mantissa[1].lstrip("+-")) > 4):
                raise self._fail(f"the number has more than {_MAX_DIGITS} digits")
            self.i += 1
            if self._peek()[0] == "pow":
                raise self._fail("a number cannot be raised to a power")
            if self._peek()[0] == "end":
                return
        elif kind == "end":
            raise self._fail("the text is empty")
        if self._peek()[0] == "pct" and self.i == len(self.tokens) - 1:
            self.i += 1
            return
        powers: dict[str, float] = {}
        self._product(powers, 1.0, 0)
        if self.i != len(self.tokens):
            raise self._fail(f"unexpected {self._peek()[1]!r}")
        for name, p in powers.items():
            if abs(p) > MAX_UNIT_POWER:
                raise self._fail(f"the power of {name} is larger than {MAX_UNIT_POWER}")

    def _product(self, powers: dict[str, float], scale: float, depth: int) -> None:
        self._factor(powers, scale, depth)
        while True:
            kind, tok = self._peek()
            if kind == "op" and tok in "*/":
                self.i += 1
                self._factor(powers, -scale if tok == "/" else scale, depth)
            elif kind == "name" or (kind == "op" and tok == "("):
                self._factor(powers, scale, depth)  # "N m": a space multiplies
            else:
                return

    def _factor(self, powers: dict[str, float], scale: float, depth: int) -> None:
        kind, tok = self._peek()
        inner: dict[str, float] = {}
        if kind == "name":
            self.i += 1
            inner[tok] = 1.0
        elif kind == "num" and tok == "1":
            self.i += 1
        elif kind == "op" and tok == "(":
            if depth >= _MAX_PAREN_DEPTH:
                raise self._fail(f"more than {_MAX_PAREN_DEPTH} levels of parentheses")
            self.i += 1
            self._product(inner, 1.0, depth + 1)
            if self._peek() != ("op", ")"):
                raise self._fail("a parenthesis is not closed")
            self.i += 1
        else:
            raise self._fail(f"expected a unit, got {tok!r}" if tok else "a unit is missing at the end")
        power = 1.0
        if self._peek()[0] == "pow":
            self.i += 1
            negative = False
            if self._peek()[0] == "sign":
                negative = self._peek()[1] == "-"
                self.i += 1
            kind, tok = self._peek()
            if kind != "num" or not re.fullmatch(r"\d{1,2}(\.\d{1,3})?", tok):
                raise self._fail("a unit's power must be a small number such as ^2 or ^-1")
            self.i += 1
            power = -float(tok) if negative else float(tok)
            if self._peek()[0] == "pow":
                raise self._fail("a power cannot be raised to a power")
        for name, p in inner.items():
            powers[name] = powers.get(name, 0.0) + p * power * scale


def _parse_string(text: str, quantity: str, field: str) -> float:
    norm = _normalise(text)
    check_grammar(norm, field)
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


# --------------------------------------------------------------------------- display unit systems
# The one table of display units: the report (drivetrain.report.display), the CLI tables and the
# study summary all convert through it.

UNIT_CHOICES: Final = ("si", "imperial", "as-given")
"""``--units``: SI, imperial, or the units the axis file used."""

SI_UNITS: Final[dict[str, str]] = {
    "torque": "N*m",
    "angular_speed": "rpm",
    "inertia": "kg*cm^2",
    "length": "mm",
    "speed": "m/s",
    "acceleration": "m/s^2",
    "jerk": "m/s^3",
    "angle": "deg",
    "angular_acceleration": "rad/s^2",
    "angular_jerk": "rad/s^3",
    "mass": "kg",
    "force": "N",
    "power": "W",
    "energy": "J",
    "time": "s",
    "linear_stiffness": "N/um",
}
"""Display units of ``--units si`` (motion-control habits: N·m, rpm, kg·cm², mm)."""

IMPERIAL_UNITS: Final[dict[str, str]] = {
    **SI_UNITS,
    "torque": "lbf*in",
    "inertia": "lb*in^2",
    "length": "in",
    "speed": "in/s",
    "acceleration": "in/s^2",
    "jerk": "in/s^3",
    "mass": "lb",
    "force": "lbf",
    "linear_stiffness": "lbf/in",
}
"""Display units of ``--units imperial`` (US servo catalogs: lbf·in, rpm, lb·in², in); speed of a shaft
stays rpm, power W, energy J."""

KEY_SUFFIXES: Final[tuple[tuple[str, str], ...]] = (
    ("_m_s2", "acceleration"), ("_kgm2", "inertia"), ("_Nm", "torque"), ("_N", "force"), ("_W", "power"),
    ("_J", "energy"), ("_s", "time"), ("_m", "length"))
"""The unit suffixes of result keys (``rms_torque_Nm``, ``load_inertia_kgm2``) and the quantity each
names, longest match first; every such key holds an SI value."""


def quantity_of_key(key: str) -> tuple[str, str] | None:
    """(name without the suffix, quantity) of a result key with an SI unit suffix, or None."""
    for suffix, quantity in KEY_SUFFIXES:
        if key.endswith(suffix) and len(key) > len(suffix):
            return key[: -len(suffix)], quantity
    return None
