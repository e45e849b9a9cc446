"""The axis file's JSON schema for the API, and the form description the page builds its editor from.

Both come from ``drivetrain.axis.AxisSpec``, the model the CLI validates files with, so the form
offers every mechanism and transmission type the engine knows, and the API's schema describes
exactly what the engine accepts. Quantity fields take a number (SI) or a string with units
("10 mm"); the schema says so and names the quantity (``x-quantity``) and its SI unit
(``x-unit``), which the form shows beside each input.
"""

from __future__ import annotations

import copy
import inspect
from functools import lru_cache
from typing import Any

from pydantic.json_schema import GenerateJsonSchema, JsonSchemaValue
from pydantic_core import core_schema

MAX_QUANTITY_TEXT = 200
"""Longest text accepted for one quantity in the schema [characters]."""

EXAMPLE_UNITS: dict[str, str] = {
    "length": "mm", "mass": "kg", "time": "s", "inertia": "kg*cm^2", "force": "N", "torque": "N*m",
    "energy": "J", "power": "W", "speed": "m/s", "acceleration": "m/s^2", "jerk": "m/s^3", "angle": "deg",
    "angular_speed": "rpm", "angular_acceleration": "rad/s^2", "density": "kg/m^3", "voltage": "V",
    "linear_stiffness": "N/mm", "torsional_stiffness": "N*m/rad", "linear_damping": "N*s/m",
    "torsional_damping": "N*m*s/rad", "turbulent_coefficient": "N*m*s^2/rad^2", "current": "A",
    "frequency": "Hz", "pressure": "Pa",
}
"""A unit a user is likely to type for each quantity (shown as the input's hint)."""

ADVANCED: frozenset[str] = frozenset({
    "gravity", "efficiency_model", "extra_inertia", "stiffness", "damping", "backlash", "back_efficiency",
    "static_friction", "static_friction_torque", "viscous", "turbulent", "spring", "spring_preload",
    "normal_force", "thread_friction", "friction_torque", "density", "carrier_friction", "catalog",
    "flexspline_teeth", "circular_spline_teeth", "dynamics", "rated_torque_gearbox", "idlers",
    "drive_pulley", "driven_pulley", "passive_sprockets", "loop_friction", "bore",
})
"""Fields the form tucks under "More" (shown open when they hold a value)."""

PROFILE_COLUMNS: tuple[dict[str, Any], ...] = (
    {"key": "move", "label": "Distance", "quantity": "length", "hint": "200 mm (or deg for rotary axes)"},
    {"key": "time", "label": "Time", "quantity": "time", "hint": "0.5 s (a dwell's duration)"},
    {"key": "accel", "label": "Accel time", "quantity": "time", "hint": "0.1 s"},
    {"key": "decel", "label": "Decel time", "quantity": "time", "hint": "= accel"},
    {"key": "shape", "label": "Shape", "options": ["", "trapezoid", "triangle", "s_curve"]},
    {"key": "jerk_fraction", "label": "Jerk fraction", "quantity": "dimensionless", "hint": "0.5"},
    {"key": "jerk", "label": "Jerk", "quantity": "jerk", "hint": "50 m/s^3 (or rad/s^3)"},
    {"key": "speed", "label": "Speed", "quantity": "speed", "hint": "15 m/min (or rpm; distance = movement amount)"},
    {"key": "max_speed", "label": "Max speed", "quantity": "speed", "hint": "1 m/s (or rpm)"},
    {"key": "max_accel", "label": "Max accel", "quantity": "acceleration", "hint": "10 m/s^2 (or rad/s^2)"},
    {"key": "max_jerk", "label": "Max jerk", "quantity": "jerk", "hint": "500 m/s^3 (optional)"},
    {"key": "law", "label": "Cam law", "options": ["", "cycloidal", "modified_sine", "modified_trapezoid", "poly345"]},
    {"key": "thrust", "label": "Thrust", "quantity": "force", "hint": "0 N"},
    {"key": "holding", "label": "Holding", "options": ["", "motor", "brake"]},
)
"""Fields of a profile step, one per key of the axis file's steps (``drivetrain.motion.profiles.VALID_KEYS``);
a dwell row keeps its duration in the Time column (key ``dwell``), a move given by speed its speed
in the Distance column (key ``speed``)."""

STEP_KINDS: tuple[dict[str, Any], ...] = (
    {"kind": "move", "label": "move", "hint": "a move: distance and time (ramps, shape)",
     "keys": ["move", "time", "accel", "decel", "shape", "jerk_fraction", "jerk", "thrust"]},
    {"kind": "speed", "label": "by speed", "hint": "a move given by its speed and time (distance = movement amount)",
     "keys": ["speed", "time", "accel", "decel", "shape", "jerk_fraction", "jerk", "thrust"]},
    {"kind": "optimal", "label": "optimal", "hint": "a time-optimal move: distance, max speed, max accel (max jerk)",
     "keys": ["move", "max_speed", "max_accel", "max_jerk", "thrust"]},
    {"kind": "cam", "label": "cam law", "hint": "a move along a cam law: distance, time and law",
     "keys": ["move", "time", "law", "thrust"]},
    {"kind": "dwell", "label": "dwell", "hint": "a dwell: its time (motor or brake holding)",
     "keys": ["dwell", "holding"]},
)
"""The kinds of profile step and the keys each takes (as ``drivetrain.motion.profiles`` parses them)."""

TYPE_INDEPENDENT: frozenset[str] = frozenset({"efficiency", "back_efficiency", "incline", "load", "gravity"})
"""Fields that mean the same for every mechanism (or transmission) type that has them: kept when the
type changes (an object field only when the new type's model of it is the same). Any other field
(diameter, length, lead, ...) describes the part of one type and is cleared on a change to a type
of another model (a screw's diameter is not a pinion's pitch diameter)."""


def _quantity_of(function: Any) -> dict[str, Any] | None:
    """The quantity name and SI bounds of a ``drivetrain.fields.quantity`` validator, else None."""
    if getattr(function, "__qualname__", "") != "quantity.<locals>.validate":
        return None
    try:
        names = inspect.getclosurevars(function).nonlocals
    except (TypeError, ValueError):
        return None
    if not isinstance(names.get("quantity"), str):
        return None
    return {k: names.get(k) for k in ("quantity", "gt", "ge", "lt", "le")}


class AxisJsonSchema(GenerateJsonSchema):
    """Pydantic's JSON schema, with quantity fields described as 'number (SI) or text with units'."""

    def function_before_schema(self, schema: core_schema.BeforeValidatorFunctionSchema) -> JsonSchemaValue:
        function = schema.get("function", {}).get("function")
        q = _quantity_of(function)
        if q is None:
            return super().function_before_schema(schema)
        from drivetrain.units import QUANTITIES

        name = str(q["quantity"])
        unit = QUANTITIES.get(name, ("",))[0]
        bounds = {k: q[k] for k in ("gt", "ge", "lt", "le") if q[k] is not None}
        rule = ", ".join(f"{k} {v:g}" for k, v in bounds.items())
        example = EXAMPLE_UNITS.get(name, unit)
        described = f"{name.replace('_', ' ')}: a number in {unit or 'SI'} or text with units"
        described += f" (e.g. '2 {example}')" if example else ""
        described += f"; in SI {rule}" if rule else ""
        number: dict[str, Any] = {"type": "number"}
        keys = {"gt": "exclusiveMinimum", "ge": "minimum", "lt": "exclusiveMaximum", "le": "maximum"}
        number.update({keys[k]: v for k, v in bounds.items()})
        return {
            "anyOf": [number, {"type": "string", "maxLength": MAX_QUANTITY_TEXT}],
            "description": described,
            "x-quantity": name,
            "x-unit": unit,
            "x-example-unit": example,
        }


@lru_cache(maxsize=4)
def axis_json_schema(ref_template: str = "#/$defs/{model}") -> dict[str, Any]:
    """JSON schema (validation mode) of the axis file, with quantity hints."""
    from drivetrain.axis.model import AxisSpec

    schema = AxisSpec.model_json_schema(ref_template=ref_template, schema_generator=AxisJsonSchema)
    profile = schema["properties"]["profile"]
    profile["description"] = ("moves and dwells in order, e.g. {move: 200 mm, time: 0.5 s, accel: 0.1 s} "
                              "or {dwell: 0.3 s}; the cycle repeats")
    return schema


def openapi_components() -> tuple[dict[str, Any], dict[str, Any]]:
    """(AxisSpec schema, its definitions) with references into ``#/components/schemas``."""
    schema = copy.deepcopy(axis_json_schema("#/components/schemas/{model}"))
    defs = schema.pop("$defs", {})
    return schema, defs


# ---------------------------------------------------------------------------------- form


def _resolve(node: dict[str, Any], defs: dict[str, Any]) -> dict[str, Any]:
    ref = node.get("$ref")
    if isinstance(ref, str):
        return _resolve(defs[ref.rsplit("/", 1)[-1]], defs)
    return node


def _field(name: str, node: dict[str, Any], defs: dict[str, Any], required: bool) -> dict[str, Any]:
    """One form field from a JSON schema node."""
    node = _resolve(node, defs)
    out: dict[str, Any] = {"name": name, "label": name.replace("_", " "), "required": required,
                           "advanced": name in ADVANCED}
    if "default" in node:
        out["default"] = node["default"]
    if node.get("description") and "x-quantity" not in node:
        out["help"] = str(node["description"]).replace("``", "")
    nullable = False
    if "anyOf" in node and "x-quantity" not in node:
        options = [_resolve(o, defs) for o in node["anyOf"]]
        non_null = [o for o in options if o.get("type") != "null"]
        nullable = len(non_null) < len(options)
        if len(non_null) == 1:
            inner = _field(name, non_null[0], defs, required)
            inner["nullable"] = nullable
            if "default" in node:
                inner["default"] = node["default"]
            return inner
        node = next((o for o in non_null if o.get("type") == "string"), non_null[0])
    out["nullable"] = nullable
    if "x-quantity" in node:
        out.update(kind="quantity", quantity=node["x-quantity"], unit=node["x-unit"],
                   example_unit=node["x-example-unit"])
    elif "oneOf" in node and "discriminator" in node:
        tag = node["discriminator"]["propertyName"]
        variants: dict[str, Any] = {}
        for value, ref in node["discriminator"]["mapping"].items():
            sub = _object(_resolve({"$ref": ref}, defs), defs)
            sub["fields"] = [f for f in sub["fields"] if f["name"] != tag]
            variants[value] = sub
        out.update(kind="union", tag=tag, variants=variants)
    elif "enum" in node or "const" in node:
        out.update(kind="enum", options=list(node.get("enum") or [node["const"]]))
    elif node.get("type") == "object" and "properties" in node:
        out.update(kind="object", **_object(node, defs))
    elif node.get("type") == "object":
        out.update(kind="mapping")
    elif node.get("type") == "array":
        items = node.get("items", {})
        if _resolve(items, defs).get("type") == "object" and "properties" not in _resolve(items, defs):
            out.update(kind="mapping")
        else:
            out.update(kind="list", item=_field("item", items, defs, True))
    elif node.get("type") == "boolean":
        out.update(kind="bool")
    elif node.get("type") == "integer":
        out.update(kind="integer", **{k: node[k] for k in ("minimum", "maximum", "exclusiveMinimum") if k in node})
    elif node.get("type") == "number":
        out.update(kind="number", **{k: node[k] for k in ("minimum", "maximum", "exclusiveMinimum") if k in node})
    else:
        out.update(kind="text")
    return out


def _object(node: dict[str, Any], defs: dict[str, Any]) -> dict[str, Any]:
    required = set(node.get("required", []))
    fields = [_field(name, sub, defs, name in required) for name, sub in node.get("properties", {}).items()]
    return {"title": node.get("title", ""), "fields": fields}


@lru_cache(maxsize=1)
def form_description() -> dict[str, Any]:
    """What the page needs to build the axis editor: the axis fields, profile columns, type lists."""
    from drivetrain.axis.mechanisms import MECHANISM_TYPES
    from drivetrain.axis.transmission import TRANSMISSION_TYPES
    from drivetrain.motion.cams import CAM_LAWS
    from drivetrain.motion.profiles import HOLDING, SHAPES, VALID_KEYS

    schema = axis_json_schema()
    defs = schema.get("$defs", {})
    axis = _object(schema, defs)
    for f in axis["fields"]:
        if f["name"] == "profile":
            f["kind"] = "profile"
    columns = [dict(c) for c in PROFILE_COLUMNS]
    for c in columns:
        if c["key"] == "shape":
            c["options"] = ["", *SHAPES]
        elif c["key"] == "holding":
            c["options"] = ["", *HOLDING]
        elif c["key"] == "law":
            c["options"] = ["", *CAM_LAWS]
    missing = set(VALID_KEYS) - {c["key"] for c in columns} - {"dwell"}
    if missing:  # every step key has a field
        raise RuntimeError(f"profile keys without a form field: {sorted(missing)}")
    return {
        "axis": axis,
        "mechanism_types": list(MECHANISM_TYPES),
        "transmission_types": list(TRANSMISSION_TYPES),
        "profile": {"columns": columns, "keys": list(VALID_KEYS), "kinds": [dict(k) for k in STEP_KINDS]},
        "type_independent": sorted(TYPE_INDEPENDENT),
        "example_units": EXAMPLE_UNITS,
    }
