"""Pydantic field types for quantities with units, and pydantic errors turned into InputError.

The axis file and the web API share these models, so a bad value gets the same message
everywhere: ``mechanism.load.mass: must be > 0 kg, got -3 kg``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict

from drivetrain.errors import InputError, InputErrors
from drivetrain.units import QUANTITIES, parse

if TYPE_CHECKING:
    from pydantic import ValidationError


class Spec(BaseModel):
    """Base of every axis-file model: unknown keys are errors, values are validated on assignment."""

    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)


def _bound_text(op: str, bound: float, quantity: str) -> str:
    unit = QUANTITIES[quantity][0]
    return f"must be {op} {bound:g}{' ' + unit if unit else ''}"


def quantity(quantity: str, *, gt: float | None = None, ge: float | None = None,
             lt: float | None = None, le: float | None = None) -> BeforeValidator:
    """A validator for ``Annotated[float, ...]`` that parses units into SI and checks bounds (in SI)."""

    def validate(value: Any) -> float:
        x = parse(value, quantity, "")
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


Length = Annotated[float, quantity("length", gt=0.0)]
LengthAny = Annotated[float, quantity("length")]
LengthNonNeg = Annotated[float, quantity("length", ge=0.0)]
Mass = Annotated[float, quantity("mass", gt=0.0)]
MassNonNeg = Annotated[float, quantity("mass", ge=0.0)]
Inertia = Annotated[float, quantity("inertia", ge=0.0)]
InertiaPos = Annotated[float, quantity("inertia", gt=0.0)]
Angle = Annotated[float, quantity("angle")]
Force = Annotated[float, quantity("force")]
ForceNonNeg = Annotated[float, quantity("force", ge=0.0)]
Torque = Annotated[float, quantity("torque")]
TorqueNonNeg = Annotated[float, quantity("torque", ge=0.0)]
TorquePos = Annotated[float, quantity("torque", gt=0.0)]
Density = Annotated[float, quantity("density", gt=0.0)]
Efficiency = Annotated[float, quantity("dimensionless", gt=0.0, le=1.0)]
BackEfficiency = Annotated[float, quantity("dimensionless", ge=-1.0, le=1.0)]
Ratio = Annotated[float, quantity("dimensionless", gt=0.0)]
Coefficient = Annotated[float, quantity("dimensionless", ge=0.0, le=5.0)]
Time = Annotated[float, quantity("time", gt=0.0)]
Speed = Annotated[float, quantity("angular_speed", gt=0.0)]
LinearStiffness = Annotated[float, quantity("linear_stiffness", ge=0.0)]
TorsionalStiffness = Annotated[float, quantity("torsional_stiffness", gt=0.0)]
TorsionalStiffnessNonNeg = Annotated[float, quantity("torsional_stiffness", ge=0.0)]
LinearDamping = Annotated[float, quantity("linear_damping", ge=0.0)]
TorsionalDamping = Annotated[float, quantity("torsional_damping", ge=0.0)]
Turbulent = Annotated[float, quantity("turbulent_coefficient", ge=0.0)]
Acceleration = Annotated[float, quantity("acceleration", gt=0.0)]
Voltage = Annotated[float, quantity("voltage", gt=0.0)]
SpeedPos = Annotated[float, quantity("angular_speed", gt=0.0)]
Backlash = Annotated[float, quantity("angle", ge=0.0)]
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
