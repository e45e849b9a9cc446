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

import io
import math
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from drivetrain.errors import InputError
from drivetrain.fields import Spec, Voltage, quantity

Current = Annotated[float, quantity("current", gt=0.0)]
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
    supply_voltage: Voltage | None = None
    dc_bus_voltage: Voltage | None = None
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
    continuous_current: Current | None = None
    peak_current: Current | None = None
    peak_time: TimePos | None = None
    supply_voltage: Voltage | None = None
    dc_bus_voltage: Voltage | None = None
    bus_capacitance: Capacitance | None = None
    bus_max_voltage: Voltage | None = None
    regen_on_voltage: Voltage | None = None
    absorbable_energy: EnergyNonNeg | None = None
    min_resistance: Resistance | None = None
    builtin_resistor: BuiltinResistorSpec | None = None

    @model_validator(mode="after")
    def _drive(self) -> DriveSpec:
        if self.id is None and (self.continuous_current is None or self.peak_current is None):
            raise ValueError("a drive needs its catalog id, or continuous_current and peak_current")
        if (self.peak_current is not None and self.continuous_current is not None
                and self.peak_current < self.continuous_current):
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
    motor_series: str | None = None  # the motor series it runs (catalog column; None: not stated)


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
    """The SI drive of ``drive:``: the catalog's row for ``id`` (if any), overridden by the keys given."""
    base: dict[str, Any] = {}
    if spec.id is not None and (spec.continuous_current is None or spec.peak_current is None
                                or spec.vendor is None):
        from drivetrain import catalog

        try:
            row: dict[str, Any] | None = catalog.get(spec.id)
        except InputError:
            row = None
        if row is None or row.get("table") != "drive":
            if spec.continuous_current is None or spec.peak_current is None:
                raise InputError("drive.id", "is not a catalog drive (drivetrain catalog list --kind drive); "
                                 "give continuous_current and peak_current", spec.id)
        else:
            base = asdict(drive_from_catalog_row(row))
    b = spec.builtin_resistor
    given: dict[str, Any] = {
        "name": spec.id, "vendor": spec.vendor, "continuous_current": spec.continuous_current,
        "peak_current": spec.peak_current, "peak_time": spec.peak_time, "supply_voltage": spec.supply_voltage,
        "dc_bus_voltage": spec.dc_bus_voltage, "bus_capacitance": spec.bus_capacitance,
        "bus_max_voltage": spec.bus_max_voltage, "regen_on_voltage": spec.regen_on_voltage,
        "absorbable_energy": spec.absorbable_energy, "min_resistance": spec.min_resistance,
        "builtin_resistance": None if b is None else b.resistance,
        "builtin_average_power": None if b is None else b.average_power,
    }
    merged = {**base, **{k: v for k, v in given.items() if v is not None}}
    for key in ("continuous_current", "peak_current"):
        if _nan_none(merged.get(key)) is None:
            raise InputError(f"drive.{key}", f"the catalog drive {spec.id} has no {key.replace('_', ' ')} "
                             "(data/SOURCES.md): give it in the axis file", has_value=False)
    merged.setdefault("name", "drive")
    merged.setdefault("vendor", None)
    return DriveData(**merged)


def nominal_bus_voltage(*sources: Any) -> float | None:
    """The nominal DC bus [V] of the first source that states one: its ``dc_bus_voltage``, else
    sqrt(2) x its ``supply_voltage`` (line-to-line rms). Sources are DriveData, MotorElectrical or a
    motor spec, in order of precedence (the drive's keys first); None where none states either."""
    from drivetrain.physics.motor_electrical import dc_bus_voltage

    for src in sources:
        if src is None:
            continue
        if getattr(src, "dc_bus_voltage", None) is not None:
            return float(src.dc_bus_voltage)
        if getattr(src, "supply_voltage", None) is not None:
            return float(dc_bus_voltage(src.supply_voltage))
    return None


def check_bus_limits(nominal_bus: float | None, bus_max_voltage: float | None, regen_on_voltage: float | None,
                     where: str) -> None:
    """Refuse a capacitor maximum or a chopper switch-on voltage below the nominal DC bus [V].

    The capacitors take C/2 (U_max^2 - U_nom^2) only for U_max above the bus they idle at, and the
    braking chopper switches on above that bus (U_nom <= U_on); data below it is a typing slip or a
    drive of another voltage class, and would make the capacitors "absorb" negative energy and hand
    the resistor more than the cycle returns. Source: physics.regen.capacitor_energy; Yaskawa
    Sigma-7S SERVOPACK manual §12.8.6 (regeneration starts above the main-circuit bus voltage).
    """
    if nominal_bus is None:
        return
    for key, value in (("bus_max_voltage", bus_max_voltage), ("regen_on_voltage", regen_on_voltage)):
        if value is not None and value < nominal_bus:
            raise InputError(f"{where}.{key}", f"must be at least the nominal DC bus voltage "
                             f"({nominal_bus:.4g} V, from the supply or dc_bus_voltage)", f"{value:.4g} V")


def _nan_none(value: Any) -> float | None:
    if value is None:
        return None
    x = float(value)
    return None if math.isnan(x) else x


def electrical_from_catalog_row(row: dict[str, Any]) -> MotorElectrical:
    """A catalog motor's electrical columns (``catalog.get``: SI, unit in the key) as MotorElectrical.

    Bases: k_E as ``back_emf_basis`` says (line-to-line rms when empty), R and L per phase unless
    ``resistance_basis`` says line-to-line; pole count / 2 = pole pairs.
    """
    from drivetrain.physics.motor_electrical import ke_si, phase_value

    def num(key: str) -> float | None:
        return _nan_none(row.get(key))

    ke = num("back_emf_Vs_per_rad")
    basis = str(row.get("back_emf_basis") or "ll_rms")
    text = str(row.get("resistance_basis") or "").lower().replace("not phase-to-phase", "")
    r_basis = "line_to_line" if ("line" in text or "phase-to-phase" in text) else "phase"
    r, ind = num("winding_resistance_ohm"), num("winding_inductance_H")
    poles = num("pole_count")
    source = row.get("electrical_source") or row.get("source") or "catalog"
    return MotorElectrical(
        kt=num("torque_constant_Nm_per_A"),
        ke=None if ke is None else float(ke_si(ke, basis, per_krpm=False)),
        resistance=None if r is None else float(phase_value(r, r_basis)),
        inductance=None if ind is None else float(phase_value(ind, r_basis)),
        pole_pairs=None if poles is None else int(poles) // 2,
        rated_current=num("rated_current_A"), stall_current=num("stall_current_A"),
        peak_current=num("peak_current_A"), thermal_time_constant=num("thermal_time_constant_s"),
        rated_rise=num("rated_winding_rise_K"),
        sources=(f"catalog {row.get('id')}: {source}",),
    )


def drive_from_catalog_row(row: dict[str, Any]) -> DriveData:
    """A catalog drive (``catalog.get`` or ``DriveTable.row``: SI, unit in the key) as DriveData.

    Unknown currents stay NaN here (the selection answers their checks as unknown); ``drive_data``
    refuses them for a given drive.
    """
    def num(key: str) -> float | None:
        return _nan_none(row.get(key))

    cont, peak = num("continuous_current_A"), num("peak_current_A")
    builtin = row.get("builtin_braking_resistor")
    return DriveData(
        name=str(row.get("id")), vendor=row.get("vendor"),
        continuous_current=math.nan if cont is None else cont, peak_current=math.nan if peak is None else peak,
        peak_time=num("peak_time_s"), supply_voltage=num("voltage_V"), dc_bus_voltage=num("dc_bus_voltage_V"),
        bus_capacitance=num("dc_bus_capacitance_F"), bus_max_voltage=num("bus_max_voltage_V"),
        regen_on_voltage=num("regen_on_voltage_V"), absorbable_energy=num("absorbable_energy_J"),
        min_resistance=num("min_resistance_ohm"),
        builtin_resistance=None if builtin == 0 else num("braking_resistor_ohm"),
        builtin_average_power=None if builtin == 0 else num("braking_resistor_average_power_W"),
        motor_series=str(row.get("motor_series") or "") or None,
    )


def environment(spec: EnvironmentSpec | None) -> Environment:
    """The SI environment (defaults: 40 degC, sea level, Kollmorgen AKM derating rule)."""
    if spec is None:
        return Environment()
    return Environment(ambient=spec.ambient, altitude=spec.altitude, derating=spec.derating)


ELECTRICAL_FILE = "motors_ac_servo_electrical.csv"


@lru_cache(maxsize=1)
def _shipped_rows() -> dict[str, dict[str, str]]:
    import csv  # only where the shipped electrical table is read
    from importlib import resources

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
    stall = num("stall_current_A")
    # The table prints I_0 at a 60 K and at a 100 K winding rise (Siemens 1FT7, Table 4-8); the
    # stall current read is the 100 K one, so the rated rise that goes with it is 100 K.
    rated_rise = 100.0 if stall is not None and num("stall_current_60K_A") is not None else None
    return MotorElectrical(
        rated_rise=rated_rise,
        kt=num("torque_constant_Nm_per_A"),
        ke=None if ke is None else float(ke_si(ke, "ll_rms")),
        resistance=resistance,
        inductance=num("winding_inductance_H"),
        pole_pairs=None if poles is None else int(poles) // 2,
        rated_current=num("rated_current_A"),
        stall_current=stall,
        peak_current=num("peak_current_A"),
        thermal_time_constant=num("thermal_time_constant_s"),
        sources=(f"{ELECTRICAL_FILE}: {row.get('source', '')}" + _kt_basis_note(row),),
    )


def _kt_basis_note(row: dict[str, str]) -> str:
    """'; k_T derived = ...' where the shipped row's torque constant was derived, not printed."""
    from drivetrain.catalog.derive import DERIVED_KT

    return f"; k_T {DERIVED_KT}" if row.get("torque_constant_basis", "").startswith("derived") else ""
