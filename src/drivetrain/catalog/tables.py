"""Catalog query results as arrays: one numpy array per field, SI, NaN where a value is unknown.

Selection works on whole columns at once (every motor against every ratio), so a query returns
a table of arrays rather than a list of objects. ``row(i)`` gives one row back as a dict keyed
like ``catalog.get()`` (SI with the unit in the key).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Self

import numpy as np
from numpy.typing import NDArray

from drivetrain.catalog.curves import Curve
from drivetrain.catalog.schema import DRIVE, GEARBOX, MOTOR, TableSpec, trace

FloatArray = NDArray[np.float64]
StrArray = NDArray[np.str_]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class _Table:
    """Common columns and behaviour; subclasses add their numeric arrays."""

    SPEC: ClassVar[TableSpec]

    ids: StrArray
    kind: StrArray
    vendor: StrArray
    series: StrArray
    model: StrArray
    source: StrArray
    notes: StrArray
    origin: StrArray  # "builtin" (shipped) or "user" (imported)
    unverified: BoolArray  # not traced to a vendor document, or a sizing rating derived (schema.trace)
    unverified_reason: StrArray  # why ("" where traced)

    def __len__(self) -> int:
        return len(self.ids)

    def take(self, index: Sequence[int] | NDArray[Any]) -> Self:
        """A table of the rows at ``index`` (integer positions or a boolean mask), in that order."""
        idx = np.asarray(index)
        changes = {f.name: _take(getattr(self, f.name), idx) for f in dataclasses.fields(self)}
        return dataclasses.replace(self, **changes)

    def row(self, i: int) -> dict[str, Any]:
        """Row ``i`` as a dict keyed by database column (SI, unit in the key); unknown values are None."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)[i]
            key = _KEYS.get(f.name) or self._column(f.name)
            out[key] = _plain(value)
        return out

    @classmethod
    def _column(cls, name: str) -> str:
        key = (cls, name)
        column = _COLUMNS.get(key)
        if column is None:  # looked up once per table class and field: ``row`` asks for every field of each row
            column = _COLUMNS[key] = next((f.column for f in cls.SPEC.fields if f.name == name), name)
        return column

    @classmethod
    def from_rows(cls, rows: Sequence[dict[str, Any]], **extra: Any) -> Self:
        """Build the table from database rows (dicts keyed by column)."""
        arrays: dict[str, Any] = {}
        traced = [trace(r) for r in rows]
        extra = {
            "unverified": np.array([t[0] for t in traced], dtype=bool),
            "unverified_reason": np.array([t[1] for t in traced], dtype=str),
            **extra,
        }
        for f in dataclasses.fields(cls):
            if f.name in extra:
                arrays[f.name] = extra[f.name]
                continue
            column = "id" if f.name == "ids" else cls._column(f.name)
            values = [r.get(column) for r in rows]
            if f.type == "StrArray":
                arrays[f.name] = np.array(["" if v is None else str(v) for v in values], dtype=str)
            elif f.type == "BoolArray":
                arrays[f.name] = np.array([bool(v) for v in values], dtype=bool)
            elif f.type == "FloatArray":
                arrays[f.name] = np.array([math.nan if v is None else float(v) for v in values], dtype=float)
        return cls(**arrays)


_KEYS = {"ids": "id"}
_COLUMNS: dict[tuple[type, str], str] = {}
"""The database column of each table class's field (``_column``)."""


def _take(value: Any, idx: NDArray[Any]) -> Any:
    if isinstance(value, np.ndarray):
        return value[idx]
    if isinstance(value, tuple):  # per-row tuples (curves)
        positions = np.flatnonzero(idx) if idx.dtype == bool else idx
        return tuple(value[int(i)] for i in positions)
    return value


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


@dataclass(frozen=True, eq=False)
class MotorTable(_Table):
    """Motors as arrays [SI]: torques [N m], speeds [rad/s], inertia [kg m^2], mass [kg], flange [m]...

    ``approx_rated`` is True where the rated torque or speed was derived (e.g. P/omega for the
    shipped FANUC rows), not read from a datasheet; ``derived`` lists the derived fields.
    ``curves[i]`` is the motor's speed-torque curve, or None where the envelope must be derived
    from the ratings (see drivetrain.sizing.envelope).
    """

    SPEC: ClassVar[TableSpec] = MOTOR

    type: StrArray
    rated_power: FloatArray  # [W]
    rated_torque: FloatArray  # [N m]
    stall_torque: FloatArray  # [N m]
    peak_torque: FloatArray  # [N m]
    rated_speed: FloatArray  # [rad/s]
    max_speed: FloatArray  # [rad/s]
    rotor_inertia: FloatArray  # [kg m^2]
    rotor_inertia_brake: FloatArray  # [kg m^2] the brake variant's (with-brake total; NaN: not in the catalog)
    brake_holding_torque: FloatArray  # [N m] the brake variant's holding torque (NaN: not in the catalog)
    brake_code: StrArray  # the brake variant's order code ("" where not in the catalog)
    mass: FloatArray  # [kg]
    flange: FloatArray  # [m]
    shaft_diameter: FloatArray  # [m] output shaft (NaN where unknown)
    pilot_diameter: FloatArray  # [m] centring spigot of the flange
    bolt_circle: FloatArray  # [m] flange bolt circle
    voltage: FloatArray  # [V] supply class (AC servo) or nominal terminal voltage (small DC)
    torque_constant: FloatArray  # [N m/A]
    winding_resistance: FloatArray  # [ohm]
    winding_inductance: FloatArray  # [H]
    rated_current: FloatArray  # [A]
    no_load_speed: FloatArray  # [rad/s]
    rated_torque_basis: StrArray
    derived: StrArray
    derivation: StrArray  # the formula of each derived field (catalog.derive.formulas reads it)
    approx_rated: BoolArray
    has_curve: BoolArray
    curves: tuple[Curve | None, ...]

    @classmethod
    def from_db(cls, rows: Sequence[dict[str, Any]], curves: dict[str, Curve]) -> MotorTable:
        derived = [set(filter(None, (r.get("derived") or "").split(","))) for r in rows]
        approx = np.array([bool(d & {"rated_torque", "rated_speed"}) for d in derived], dtype=bool)
        per_row = tuple(curves.get(r["id"]) for r in rows)
        has = np.array([c is not None for c in per_row], dtype=bool)
        return cls.from_rows(rows, approx_rated=approx, has_curve=has, curves=per_row)

    def row(self, i: int) -> dict[str, Any]:
        out = super().row(i)
        curve = out.pop("curves")
        out["curve"] = None if curve is None else curve.to_dict()
        return out


@dataclass(frozen=True, eq=False)
class GearboxTable(_Table):
    """Gearboxes as arrays [SI], one row per model and ratio (ratio = input / output speed)."""

    SPEC: ClassVar[TableSpec] = GEARBOX

    type: StrArray
    ratio: FloatArray  # [-]
    stages: FloatArray  # [-] (NaN where unknown)
    rated_output_torque: FloatArray  # [N m]
    max_output_torque: FloatArray  # [N m] T2B, max acceleration torque in cyclic operation
    emergency_stop_torque: FloatArray  # [N m] T2NOT, allowed only for rare emergency stops
    efficiency: FloatArray  # [-]
    max_input_speed: FloatArray  # [rad/s] n1max, short-time limit
    rated_input_speed: FloatArray  # [rad/s] n1N, thermal (mean) input speed limit
    inertia_input: FloatArray  # [kg m^2] at the input shaft
    backlash: FloatArray  # [rad]
    torsional_stiffness: FloatArray  # [N m/rad]
    max_radial_load: FloatArray  # [N] F2r
    max_axial_load: FloatArray  # [N] F2a
    mass: FloatArray  # [kg]
    input_bore_max: FloatArray  # [m] largest motor shaft the input takes (clamping hub)
    input_bore_min: FloatArray  # [m] smallest motor shaft (with the vendor's bushing); NaN: not printed
    input_flange: FloatArray  # [m] motor flange (square) the input adapter is made for; NaN: not printed
    input_pilot: FloatArray  # [m] motor pilot (centring) diameter of the input; NaN: not printed
    input_adapters: StrArray  # the drawn input adapters, "bore/pilot/bolt circle/screw" [mm] each ("": none)
    verified: BoolArray  # True: every number of the row traced to a vendor document


@dataclass(frozen=True, eq=False)
class DriveTable(_Table):
    """Servo drives as arrays [SI]."""

    SPEC: ClassVar[TableSpec] = DRIVE

    continuous_current: FloatArray  # [A]
    peak_current: FloatArray  # [A]
    voltage: FloatArray  # [V]
    rated_power: FloatArray  # [W]
    dc_bus_capacitance: FloatArray  # [F]
    braking_resistor: FloatArray  # [ohm]
    braking_resistor_power: FloatArray  # [W]
    peak_time: FloatArray  # [s] how long the peak current is allowed (NaN: not printed)
    dc_bus_voltage: FloatArray  # [V]
    bus_max_voltage: FloatArray  # [V]
    regen_on_voltage: FloatArray  # [V]
    absorbable_energy: FloatArray  # [J] regen energy the bus capacitors absorb, as the vendor prints it
    braking_resistor_average_power: FloatArray  # [W]
    min_resistance: FloatArray  # [ohm] smallest external braking resistor allowed
    motor_series: StrArray  # the motor series the drive runs ("" where not stated; schema.DRIVE_FIELDS)
