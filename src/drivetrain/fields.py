"""Pydantic field types for quantities with units, and pydantic errors turned into InputError.

The axis file and the web API share these models, so a bad value gets the same message
everywhere: ``mechanism.load.mass: must be > 0 kg, got -3 kg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict

from drivetrain.errors import InputError, InputErrors
from drivetrain.units import QUANTITIES, parse

if TYPE_CHECKING:
    from pydantic import ValidationError


class Spec(BaseModel):
    """Base of every axis-file model: unknown keys are errors, values are validated on assignment."""

    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)


@dataclass(frozen=True)
class Plausible:
    """When a bare number (SI, as documented) is a slip of unit: outside [``low``, ``high``] in SI.

    ``what`` names the quantity in the message; ``usual`` is the unit such a number is most likely
    written in (the catalog's or the drawing's unit). Only bare numbers are judged: a number written
    with its unit ("10 m") is the user's explicit choice and is taken as written.
    """

    what: str
    usual: str
    high: float | None = None
    low: float | None = None
    ceiling: float | None = None
    """Above it a number is not judged (a plain error for the bounds): an efficiency of 400 is no percentage."""


PLAUSIBLE: dict[str, Plausible] = {
    "incline": Plausible("an incline", "deg", high=math.pi / 2),
    "angle": Plausible("an angle", "deg", high=2 * math.pi),
    "backlash": Plausible("a backlash", "arcmin", high=0.05),
    "lead": Plausible("a screw lead", "mm", high=0.25),
    "length": Plausible("a length, diameter or offset", "mm", high=5.0),
    "component_inertia": Plausible("a motor, gearbox, coupling or gear inertia", "kg*cm^2", high=1.0),
    "inertia": Plausible("an inertia", "kg*cm^2", high=1.0e4),
    "mass": Plausible("a mass", "g", high=1.0e5),
    "motor_speed": Plausible("a motor speed", "rpm", high=1500.0),
    "density": Plausible("a density", "g/cm^3", low=50.0),
    "efficiency": Plausible("an efficiency", "%", high=5.0, ceiling=100.0),
    "time": Plausible("a time", "ms", high=3600.0),
}
"""The plausibility rules, one per kind of field (docs/axis-file.md, "Bare numbers").

incline above 90 deg (1.571 rad): an incline is between -90 and 90 deg, so 90 is degrees.
angle above 360 deg (6.283 rad): an unbalance angle is one turn at most.
backlash above 0.05 rad (172 arcmin): gearbox backlash is a few arcmin.
lead above 0.25 m: ball and lead screw leads are 1 to about 100 mm.
length above 5 m: pulley, pinion, drum, roll and screw diameters, widths, bores, offsets and flanges
    are millimetres on the drawing; a longer part is written with its unit ("6 m").
component inertia above 1 kg m^2: rotor, gearbox, coupling and gear inertias are catalogued in
    kg cm^2 and are far below 1 kg m^2.
inertia above 1e4 kg m^2 (a load): beyond the largest direct-drive tables.
mass above 100 t: beyond a servo axis; a number in grams.
motor speed above 1500 rad/s (14,324 rpm): servo motors are rated in rpm, 1000 to 6000.
density below 50 kg/m^3: lighter than any solid part; g/cm^3 (steel 7.85).
efficiency from 5 to 100: a percentage (between 1 and 5 the bound "must be <= 1" answers).
time above 1 h: a number in milliseconds.
"""


def _fmt(x: float) -> str:
    return f"{x:.0f}" if 1000.0 <= abs(x) < 1e15 else f"{x:.4g}"


def plausibility(value: Any, si_value: float, rule: str) -> str | None:
    """The message refusing a bare number that is a slip of unit, or None when it is plausible.

    ``value`` as written, ``si_value`` the parsed SI float, ``rule`` a key of ``PLAUSIBLE``:
    ``90`` for an incline gives "90 rad is 5157 deg; write '90 deg' ...".
    """
    if not _is_bare(value):
        return None
    p = PLAUSIBLE[rule]
    x = abs(si_value)
    if p.ceiling is not None and not 0.0 < si_value <= p.ceiling:
        return None
    if not ((p.high is not None and x > p.high) or (p.low is not None and 0.0 < x < p.low)):
        return None
    from drivetrain.units import convert

    quantity = _RULE_QUANTITY[rule]
    si = QUANTITIES[quantity][0]
    written = f"{si_value:g}"
    shown = convert(si_value, quantity, p.usual)
    limit = f"above {p.high:g}" if p.high is not None and x > p.high else f"below {p.low:g}"
    if not si:
        return (f"{written} is no fraction: {p.what} is at most 1; write '{written} {p.usual}' "
                f"or {si_value / 100.0:g}")
    return (f"{written} {si} is {_fmt(shown)} {p.usual}; write '{written} {p.usual}' (a bare number is SI, and "
            f"{limit} {si} it is implausible for {p.what}; write '{written} {si}' with its unit to keep it)")


_RULE_QUANTITY = {
    "incline": "angle", "angle": "angle", "backlash": "angle", "lead": "length", "length": "length",
    "component_inertia": "inertia", "inertia": "inertia", "mass": "mass", "motor_speed": "angular_speed",
    "density": "density", "efficiency": "dimensionless", "time": "time",
}


def _is_bare(value: Any) -> bool:
    """A number without a unit: an int or float, or a string that is only a number."""
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, float)):
        return True
    if isinstance(value, str):
        try:
            float(value.strip())
        except ValueError:
            return False
        return True
    return False


def _bound_text(op: str, bound: float, quantity: str) -> str:
    unit = QUANTITIES[quantity][0]
    return f"must be {op} {bound:g}{' ' + unit if unit else ''}"


def quantity(quantity: str, *, gt: float | None = None, ge: float | None = None,
             lt: float | None = None, le: float | None = None, plausible: str | None = None) -> BeforeValidator:
    """A validator for ``Annotated[float, ...]`` that parses units into SI and checks bounds (in SI).

    ``plausible`` names a rule of ``PLAUSIBLE``: a bare number that breaks it is refused first.
    """

    def validate(value: Any) -> float:
        x = parse(value, quantity, "")
        if plausible is not None:
            slip = plausibility(value, x, plausible)
            if slip is not None:
                raise InputError("", slip, has_value=False)
        if gt is not None and not x > gt:
            raise InputError("", _bound_text(">", gt, quantity), value)
        if gt == 0.0 and x < 1e-15:
            # A strictly positive size this small is a typo, and dividing by it overflows.
            raise InputError("", "magnitude is absurd (below 1e-15 in SI)", value)
        if ge is not None and not x >= ge:
            raise InputError("", _bound_text(">=", ge, quantity), value)
        if lt is not None and not x < lt:
            raise InputError("", _bound_text("<", lt, quantity), value)
        if le is not None and not x <= le:
            raise InputError("", _bound_text("<=", le, quantity), value)
        return x

    return BeforeValidator(validate)


Length = Annotated[float, quantity("length", gt=0.0, plausible="length")]
LengthAny = Annotated[float, quantity("length", plausible="length")]
LengthNonNeg = Annotated[float, quantity("length", ge=0.0, plausible="length")]
Lead = Annotated[float, quantity("length", gt=0.0, plausible="lead")]
Mass = Annotated[float, quantity("mass", gt=0.0, plausible="mass")]
MassNonNeg = Annotated[float, quantity("mass", ge=0.0, plausible="mass")]
Inertia = Annotated[float, quantity("inertia", ge=0.0, plausible="inertia")]
InertiaPos = Annotated[float, quantity("inertia", gt=0.0, plausible="inertia")]
ComponentInertia = Annotated[float, quantity("inertia", ge=0.0, plausible="component_inertia")]
RotorInertia = Annotated[float, quantity("inertia", gt=0.0, plausible="component_inertia")]
Angle = Annotated[float, quantity("angle", plausible="angle")]
Incline = Annotated[float, quantity("angle", plausible="incline")]
Force = Annotated[float, quantity("force")]
ForceNonNeg = Annotated[float, quantity("force", ge=0.0)]
Torque = Annotated[float, quantity("torque")]
TorqueNonNeg = Annotated[float, quantity("torque", ge=0.0)]
TorquePos = Annotated[float, quantity("torque", gt=0.0)]
Density = Annotated[float, quantity("density", gt=0.0, plausible="density")]
Efficiency = Annotated[float, quantity("dimensionless", gt=0.0, le=1.0, plausible="efficiency")]
BackEfficiency = Annotated[float, quantity("dimensionless", ge=-1.0, le=1.0, plausible="efficiency")]
Ratio = Annotated[float, quantity("dimensionless", gt=0.0)]
Coefficient = Annotated[float, quantity("dimensionless", ge=0.0, le=5.0)]
Time = Annotated[float, quantity("time", gt=0.0, plausible="time")]
Speed = Annotated[float, quantity("angular_speed", gt=0.0, plausible="motor_speed")]
LinearStiffness = Annotated[float, quantity("linear_stiffness", ge=0.0)]
TorsionalStiffness = Annotated[float, quantity("torsional_stiffness", gt=0.0)]
TorsionalStiffnessNonNeg = Annotated[float, quantity("torsional_stiffness", ge=0.0)]
LinearDamping = Annotated[float, quantity("linear_damping", ge=0.0)]
TorsionalDamping = Annotated[float, quantity("torsional_damping", ge=0.0)]
Turbulent = Annotated[float, quantity("turbulent_coefficient", ge=0.0)]
Acceleration = Annotated[float, quantity("acceleration", gt=0.0)]
Voltage = Annotated[float, quantity("voltage", gt=0.0)]
SpeedPos = Annotated[float, quantity("angular_speed", gt=0.0, plausible="motor_speed")]
Backlash = Annotated[float, quantity("angle", ge=0.0, plausible="backlash")]
ForcePos = Annotated[float, quantity("force", gt=0.0)]


def _strip_tags(loc: tuple[int | str, ...], data: Any) -> list[int | str]:
    """Drop the discriminator tags pydantic inserts into ``loc`` (e.g. 'ball_screw')."""
    path: list[int | str] = []
    node = data
    for item in loc:
        if isinstance(node, dict) and isinstance(item, str) and item not in node and node.get("type") == item:
            continue
        if isinstance(item, str) and item.startswith("function-") :
            continue
        path.append(item)
        if isinstance(node, dict) and isinstance(item, str):
            node = node.get(item)
        elif isinstance(node, list) and isinstance(item, int) and 0 <= item < len(node):
            node = node[item]
        else:
            node = None
    return path


def format_path(path: list[int | str], prefix: str = "") -> str:
    """``['mechanism', 'load', 'mass']`` -> ``mechanism.load.mass``; ints become ``[i]``."""
    out = prefix
    for item in path:
        if isinstance(item, int):
            out += f"[{item}]"
        else:
            out += ("." if out else "") + item
    return out


def input_error_from_pydantic(exc: ValidationError, data: Any, prefix: str = "") -> InputError:
    """Turn a pydantic ValidationError into InputError(s) naming each field path."""
    errors: list[InputError] = []
    for err in exc.errors(include_url=False):
        path = format_path(_strip_tags(tuple(err["loc"]), data), prefix)
        ctx = err.get("ctx") or {}
        original = ctx.get("error")
        kind = err["type"]
        if isinstance(original, InputError):
            errors.append(InputError(format_path([], path) if not original.field else f"{path}.{original.field}",
                                     original.rule, original.value, has_value=original.has_value))
            continue
        msg = str(err["msg"]).removeprefix("Value error, ")
        if kind == "extra_forbidden":
            errors.append(InputError(path, "unknown key", has_value=False))
        elif kind == "missing":
            errors.append(InputError(path, "is required", has_value=False))
        elif kind == "union_tag_invalid":
            tags = ctx.get("expected_tags", "")
            errors.append(InputError(f"{path}.type" if path else "type",
                                     f"unknown type; valid: {tags}", ctx.get("tag")))
        elif kind == "union_tag_not_found":
            errors.append(InputError(f"{path}.type" if path else "type", "is required", has_value=False))
        elif kind == "literal_error":
            errors.append(InputError(path, msg.replace("Input should be", "must be one of"), err.get("input")))
        elif kind in ("list_type", "dict_type", "model_type"):
            shape = {"list_type": "a list", "dict_type": "a mapping", "model_type": "a mapping of keys"}[kind]
            errors.append(InputError(path, f"must be {shape}", err.get("input")))
        else:
            errors.append(InputError(path, msg.replace("Input should be", "must be"), err.get("input")))
    return errors[0] if len(errors) == 1 else InputErrors(errors)
