"""The electrical part of the axis file: the motor's electrical data, the drive, the environment.

Keys (docs/axis-file.md, "Electrical data"):

    motor:    kt, ke, ke_basis, resistance, resistance_basis, inductance, inductance_basis,
              pole_pairs, rated_current, stall_current, peak_current, supply_voltage,
              dc_bus_voltage, thermal_time_constant, rated_rise, insulation_class
    drive:    id, vendor, continuous_current, peak_current, peak_time, supply_voltage,
              dc_bus_voltage, bus_capacitance, bus_max_voltage, regen_on_voltage,
              absorbable_energy, min_resistance, builtin_resistor: {resistance, average_power}
    environment: ambient, altitude, derating

They load into SI dataclasses (``MotorElectrical``, ``DriveData``, ``Environment``). A catalog
motor (``motor: {id: ...}``) takes whatever the shipped electrical table
(catalog/data/motors_ac_servo_electrical.csv) has for it; values in the axis file win.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from importlib import resources
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from drivetrain.errors import InputError
from drivetrain.fields import Spec, quantity

Current = Annotated[float, quantity("current", gt=0.0)]
VoltagePos = Annotated[float, quantity("voltage", gt=0.0)]
Resistance = Annotated[float, quantity("resistance", gt=0.0)]
Inductance = Annotated[float, quantity("inductance", gt=0.0)]
Capacitance = Annotated[float, quantity("capacitance", gt=0.0)]
TorqueConstant = Annotated[float, quantity("torque_constant", gt=0.0)]
BackEmf = Annotated[float, quantity("back_emf_constant", gt=0.0)]
TimePos = Annotated[float, quantity("time", gt=0.0)]
EnergyNonNeg = Annotated[float, quantity("energy", ge=0.0)]
PowerPos = Annotated[float, quantity("power", gt=0.0)]
Celsius = Annotated[float, quantity("celsius", ge=-50.0, le=100.0)]
RisePos = Annotated[float, quantity("temperature_difference", gt=0.0, le=300.0)]
Altitude = Annotated[float, quantity("length", ge=-500.0, le=10000.0)]

KE_BASIS = Literal["ll_rms", "ll_peak", "phase_rms", "phase_peak"]
RL_BASIS = Literal["phase", "line_to_line"]

ELECTRICAL_KEYS = ("kt", "ke", "resistance", "inductance", "pole_pairs", "rated_current", "stall_current",
                   "peak_current", "supply_voltage", "dc_bus_voltage", "thermal_time_constant", "rated_rise",
                   "insulation_class")


class MotorElectricalSpec(Spec):
    """Electrical keys of ``motor:`` (all optional; SI inside, units as strings outside)."""

    kt: TorqueConstant | None = None
    ke: BackEmf | None = None
    ke_basis: KE_BASIS = "ll_rms"
    resistance: Resistance | None = None
    resistance_basis: RL_BASIS = "phase"
    inductance: Inductance | None = None
    inductance_basis: RL_BASIS = "phase"
    pole_pairs: int | None = Field(default=None, ge=1, le=100)
    rated_current: Current | None = None
    stall_current: Current | None = None
    peak_current: Current | None = None
    supply_voltage: VoltagePos | None = None
    dc_bus_voltage: VoltagePos | None = None
    thermal_time_constant: TimePos | None = None
    rated_rise: RisePos | None = None
    insulation_class: Literal["B", "F", "H"] | None = None

    @model_validator(mode="after")
    def _electrical(self) -> MotorElectricalSpec:
        if self.ke is not None and self.ke > 20.0:
            raise ValueError(f"ke: {self.ke:g} V*s/rad is implausible; a bare number is SI (V*s/rad): "
                             "give the unit, e.g. '57 V/krpm'")
        cont = self.stall_current or self.rated_current
        if self.peak_current is not None and cont is not None and self.peak_current < cont:
            raise ValueError("peak_current must be >= the continuous (stall or rated) current")
        return self


class BuiltinResistorSpec(Spec):
    """``drive.builtin_resistor``: the drive's own braking resistor."""

    resistance: Resistance
    average_power: PowerPos


class DriveSpec(Spec):
    """``drive:``: a given servo drive (amplifier)."""

    id: str | None = None
    vendor: str | None = None
    continuous_current: Current
    peak_current: Current
    peak_time: TimePos | None = None
    supply_voltage: VoltagePos | None = None
    dc_bus_voltage: VoltagePos | None = None
    bus_capacitance: Capacitance | None = None
    bus_max_voltage: VoltagePos | None = None
    regen_on_voltage: VoltagePos | None = None
    absorbable_energy: EnergyNonNeg | None = None
    min_resistance: Resistance | None = None
    builtin_resistor: BuiltinResistorSpec | None = None

    @model_validator(mode="after")
    def _drive(self) -> DriveSpec:
        if self.peak_current < self.continuous_current:
            raise ValueError("peak_current must be >= continuous_current")
        return self


class EnvironmentSpec(Spec):
    """``environment:``: ambient temperature, installation altitude and the vendor derating rule."""

    ambient: Celsius = 40.0
    altitude: Altitude = 0.0
    derating: Literal["kollmorgen_akm", "siemens_1ft7", "none"] = "kollmorgen_akm"


@dataclass(frozen=True)
class MotorElectrical:
    """A motor's electrical data in SI (None: not known). ke is phase-peak [V s/rad]; R, L per phase."""

    kt: float | None = None
    ke: float | None = None
    resistance: float | None = None
    inductance: float | None = None
    pole_pairs: int | None = None
    rated_current: float | None = None
    stall_current: float | None = None
    peak_current: float | None = None
    supply_voltage: float | None = None
    dc_bus_voltage: float | None = None
    thermal_time_constant: float | None = None
    rated_rise: float | None = None
    sources: tuple[str, ...] = field(default_factory=tuple)

    @property
    def continuous_current(self) -> float | None:
        """I_0 (stall) where known, else the rated current [A rms]."""
        return self.stall_current if self.stall_current is not None else self.rated_current

    @property
    def has_voltage_model(self) -> bool:
        """Ke, R, L and the pole pairs are known: the voltage-limited curve can be drawn."""
        return None not in (self.ke, self.resistance, self.inductance, self.pole_pairs)

    @property
    def any(self) -> bool:
        """Any electrical datum at all."""
        return any(getattr(self, k) is not None for k in ("kt", "ke", "resistance", "peak_current",
                                                          "rated_current", "stall_current"))


@dataclass(frozen=True)
class DriveData:
    """A servo drive in SI."""

    name: str
    vendor: str | None
    continuous_current: float
    peak_current: float
    peak_time: float | None = None
    supply_voltage: float | None = None
    dc_bus_voltage: float | None = None
    bus_capacitance: float | None = None
    bus_max_voltage: float | None = None
    regen_on_voltage: float | None = None
    absorbable_energy: float | None = None
    min_resistance: float | None = None
    builtin_resistance: float | None = None
    builtin_average_power: float | None = None


@dataclass(frozen=True)
class Environment:
    """Ambient [degC], altitude [m] and the derating method."""

    ambient: float = 40.0
    altitude: float = 0.0
    derating: str = "kollmorgen_akm"


def motor_electrical(spec: MotorElectricalSpec, catalog_id: str | None = None) -> MotorElectrical:
    """The SI electrical data of ``motor:``: the shipped table's row for ``catalog_id``, overridden by the file."""
    from drivetrain.physics.motor_electrical import ke_si, phase_value
    from drivetrain.physics.motor_thermal import INSULATION_RISE_K

    base = shipped_electrical(catalog_id) if catalog_id else MotorElectrical()
    given: dict[str, Any] = {}
    if spec.kt is not None:
        given["kt"] = spec.kt
    if spec.ke is not None:
        given["ke"] = float(ke_si(spec.ke, spec.ke_basis, per_krpm=False))
    if spec.resistance is not None:
        given["resistance"] = float(phase_value(spec.resistance, spec.resistance_basis))
    if spec.inductance is not None:
        given["inductance"] = float(phase_value(spec.inductance, spec.inductance_basis))
    for key in ("pole_pairs", "rated_current", "stall_current", "peak_current", "supply_voltage", "dc_bus_voltage",
                "thermal_time_constant", "rated_rise"):
        if getattr(spec, key) is not None:
            given[key] = getattr(spec, key)
    if spec.rated_rise is None and spec.insulation_class is not None:
        given["rated_rise"] = INSULATION_RISE_K[spec.insulation_class]
    if given:
        given["sources"] = (*base.sources, "axis file")
    return replace(base, **given)


def drive_data(spec: DriveSpec) -> DriveData:
    """The SI drive of ``drive:``."""
    b = spec.builtin_resistor
    return DriveData(
        name=spec.id or "drive", vendor=spec.vendor, continuous_current=spec.continuous_current,
        peak_current=spec.peak_current, peak_time=spec.peak_time, supply_voltage=spec.supply_voltage,
        dc_bus_voltage=spec.dc_bus_voltage, bus_capacitance=spec.bus_capacitance,
        bus_max_voltage=spec.bus_max_voltage, regen_on_voltage=spec.regen_on_voltage,
        absorbable_energy=spec.absorbable_energy, min_resistance=spec.min_resistance,
        builtin_resistance=None if b is None else b.resistance,
        builtin_average_power=None if b is None else b.average_power,
    )


def environment(spec: EnvironmentSpec | None) -> Environment:
    """The SI environment (defaults: 40 degC, sea level, Kollmorgen AKM derating rule)."""
    if spec is None:
        return Environment()
    return Environment(ambient=spec.ambient, altitude=spec.altitude, derating=spec.derating)


ELECTRICAL_FILE = "motors_ac_servo_electrical.csv"


@lru_cache(maxsize=1)
def _shipped_rows() -> dict[str, dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", ELECTRICAL_FILE).read_text(encoding="utf-8")
    return {row["id"]: row for row in csv.DictReader(io.StringIO(text))}


def shipped_electrical(motor_id: str) -> MotorElectrical:
    """The shipped electrical data of a catalog motor (empty if the table has no row for it).

    Bases as the table states them (catalog/data/SOURCES.md): currents A rms; k_E of the Siemens
    row read as line-to-line rms V/1000 rpm; R and L per phase; pole count / 2 = pole pairs.
    """
    from drivetrain.physics.motor_electrical import ke_si

    row = _shipped_rows().get(motor_id)
    if row is None:
        return MotorElectrical()

    def num(key: str) -> float | None:
        text = row.get(key, "")
        if not text:
            return None
        value = float(text)
        return value if math.isfinite(value) else None

    ke = num("back_emf_V_per_krpm")
    poles = num("pole_count")
    basis_r = (row.get("resistance_basis") or "").lower()
    resistance = num("winding_resistance_ohm")
    if resistance is not None and "per phase" not in basis_r:
        raise InputError("motor.id", f"the shipped resistance basis is not per phase ({basis_r})", motor_id)
    return MotorElectrical(
        kt=num("torque_constant_Nm_per_A"),
        ke=None if ke is None else float(ke_si(ke, "ll_rms")),
        resistance=resistance,
        inductance=num("winding_inductance_H"),
        pole_pairs=None if poles is None else int(poles) // 2,
        rated_current=num("rated_current_A"),
        stall_current=num("stall_current_A"),
        peak_current=num("peak_current_A"),
        thermal_time_constant=num("thermal_time_constant_s"),
        sources=(f"{ELECTRICAL_FILE}: {row.get('source', '')}",),
    )
