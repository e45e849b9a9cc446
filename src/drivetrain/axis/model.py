"""The axis file (YAML, v1): pydantic models that validate it, and the SI ``Axis`` it loads into.

The ``mechanism:`` and ``transmission:`` entries have their models in ``axis.mechanisms`` and
``axis.transmission``. See docs/axis-file.md for every key, with one example per mechanism. Bad input raises
``InputError`` naming the field path (``mechanism.load.mass: must be > 0 kg, got -3 kg``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, ValidationError, model_validator

from drivetrain.axis.electrical import (
    ELECTRICAL_KEYS,
    DriveData,
    DriveSpec,
    Environment,
    EnvironmentSpec,
    MotorElectrical,
    MotorElectricalSpec,
    check_bus_limits,
    drive_data,
    environment,
    motor_electrical,
    nominal_bus_voltage,
)
from drivetrain.axis.mechanisms import MechanismSpec
from drivetrain.axis.requirements import Requirements, RequirementsSpec, requirements
from drivetrain.axis.resolve import resolve_transmission
from drivetrain.axis.transmission import TransmissionSpec
from drivetrain.axis.yaml_text import check_text, read_yaml
from drivetrain.errors import InputError
from drivetrain.fields import (
    Acceleration,
    ComponentInertia,
    ForcePos,
    Length,
    LengthAny,
    RotorInertia,
    Spec,
    SpeedPos,
    Time,
    TorquePos,
    Voltage,
    input_error_from_pydantic,
)
from drivetrain.physics.brake import BRAKE_SAFETY_FACTOR
from drivetrain.physics.efficiency import EfficiencyModel
from drivetrain.physics.loads import G_STANDARD
from drivetrain.physics.mechanisms import Mechanism
from drivetrain.physics.stage import Stage, chain_inertia

if TYPE_CHECKING:
    from drivetrain.motion.cycle import Cycle

MAX_TOTAL_RATIO = 1e12
"""Largest product of the ratios from the motor to the load [-, or rad/m]: a harmonic drive, a worm
and a planetary stage on a 1 mm screw come to about 1e10."""



class Margins(Spec):
    """Safety factors and limits: required x factor must not exceed the available.

    Defaults as servo sizing guides use them (docs/checks.md, "Default margins"): torque and RMS
    torque x 1.2, speed x 1.1, inertia ratio 5 (lecture: below 5:1). ``gearbox_shock_factor`` is
    the vendor's fs on T2B above 1000 cycles/h, read from the vendor's chart; unset, T2B is then
    unknown. ``brake`` is the factor on the static load torque a motor holding brake must hold
    (physics/brake.py ``BRAKE_SAFETY_FACTOR``, docs/checks.md "Motor holding brake").
    """

    torque: float = Field(default=1.2, ge=1.0, le=10.0)
    rms_torque: float | None = Field(default=None, ge=1.0, le=10.0)
    speed: float = Field(default=1.1, ge=1.0, le=10.0)
    inertia_ratio: float = Field(default=5.0, gt=0.0, le=1000.0)
    gearbox_shock_factor: float | None = Field(default=None, ge=1.0, le=10.0)
    brake: float = Field(default=BRAKE_SAFETY_FACTOR, ge=1.0, le=10.0)


class SelectSpec(Spec):
    """``motor: {select: {...}}``: pick motors (and gearbox ratios) from the catalog.

    ``gearbox``: ``auto`` tries every catalog gearbox ratio and direct drive, unless the axis's
    transmission already has a gearbox (then motors go direct onto it); ``none`` direct drive
    only; ``only`` catalog gearboxes only. ``unknown``: a check the catalog cannot judge (a
    rating or dimension missing) passes flagged (``flag``) or rejects the candidate (``fail``).
    """

    catalog: Literal["builtin", "user", "all"] = "all"
    kind: Literal["ac_servo", "small_dc", "any"] = "ac_servo"
    vendor: list[str] | str | None = None
    voltage: Voltage | None = None
    flange: Length | None = None
    gearbox: Literal["auto", "none", "only"] = "auto"
    gearbox_series: list[str] | str | None = None
    max_inertia_ratio: float | None = Field(default=None, gt=0.0)
    objective: Literal["smallest", "rms_utilisation", "inertia_match", "energy", "fastest_settling"] = "smallest"
    top: int = Field(default=10, ge=1, le=1000)
    unknown: Literal["flag", "fail"] = "flag"


class MotorSpec(MotorElectricalSpec):
    """``motor:``: a given motor by its parameters or catalog id, or a catalog selection.

    The electrical keys (kt, ke, resistance, ..., see ``drivetrain.axis.electrical``) are optional."""

    name: str | None = None
    id: str | None = None
    inertia: RotorInertia | None = None
    rated_torque: TorquePos | None = None
    stall_torque: TorquePos | None = None
    peak_torque: TorquePos | None = None
    rated_speed: SpeedPos | None = None
    max_speed: SpeedPos | None = None
    select: SelectSpec | None = None
    margins: Margins = Margins()

    @model_validator(mode="after")
    def _complete(self) -> MotorSpec:
        if self.select is not None:
            # each candidate has its own winding data; the supply is the machine's, the same for all
            own = [k for k in ELECTRICAL_KEYS if k not in ("supply_voltage", "dc_bus_voltage")
                   and getattr(self, k) is not None]
            if own:
                raise ValueError(f"{', '.join(own)} cannot go with select: each catalog candidate has its own "
                                 "(only supply_voltage or dc_bus_voltage applies to every candidate)")
            return self
        if self.id is not None:
            return self
        missing = [k for k in ("inertia", "rated_torque", "peak_torque", "max_speed") if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a given motor needs {', '.join(missing)} (or an id from the catalog, or select)")
        if self.peak_torque is not None and self.rated_torque is not None and self.peak_torque < self.rated_torque:
            raise ValueError("peak_torque must be >= rated_torque")
        return self


class GuideSpec(Spec):
    """Linear guide / actuator carriage: load offsets and ratings for the moment-load check.

    Lecture, linear actuators: M_p = F_x (l_z + d_p), M_r = F_z l_y, M_y = F_x l_y.
    """

    l_x: LengthAny = 0.0
    l_y: LengthAny = 0.0
    l_z: LengthAny = 0.0
    d_p: LengthAny = 0.0
    d_r: LengthAny = 0.0
    orientation: Literal["horizontal", "vertical", "wall"] = "horizontal"
    rated_force: ForcePos | None = None
    rated_pitch_moment: TorquePos | None = None
    rated_roll_moment: TorquePos | None = None
    rated_yaw_moment: TorquePos | None = None
    # Rolling-contact life of the carriages (docs/axis-file.md, "Mechanism limits"): checked when C is given.
    dynamic_rating: ForcePos | None = None
    static_rating: ForcePos | None = None
    rating_distance: Length = 50e3
    rolling: Literal["ball", "roller"] = "ball"
    carriages: int = Field(default=1, ge=1, le=16)
    load_factor: float = Field(default=1.0, ge=1.0, le=10.0)
    moment_factors: dict[Literal["pitch", "roll", "yaw"], float] | None = None
    required_life: Time = 20_000.0 * 3600.0
    static_safety: float = Field(default=1.0, ge=1.0, le=10.0)


class AxisSpec(Spec):
    """The whole axis file."""

    axis: str = "axis"
    gravity: Acceleration = G_STANDARD
    efficiency_model: Literal["four_quadrant", "load_torque_only"] = "four_quadrant"
    mechanism: MechanismSpec
    transmission: list[TransmissionSpec] = []
    profile: list[dict[str, Any]] = []
    motor: MotorSpec | None = None
    guide: GuideSpec | None = None
    dynamics: dict[str, Any] | None = None
    extra_inertia: ComponentInertia = 0.0
    drive: DriveSpec | None = None
    environment: EnvironmentSpec | None = None
    requirements: RequirementsSpec | None = None


@dataclass(frozen=True)
class MotorData:
    """A motor in SI: inertia [kg m^2], torques [N m], speeds [rad/s]."""

    name: str
    inertia: float
    rated_torque: float
    peak_torque: float
    rated_speed: float
    max_speed: float
    stall_torque: float | None = None
    approximate_envelope: bool = True
    source: str = "axis file"
    unverified_reason: str = ""  # catalog row not traced to a vendor document, or a derived rating ("" = traced)


@dataclass(frozen=True)
class Axis:
    """An axis in SI, ready for the duty cycle, sizing and dynamics.

    ``stages`` run from the motor outward: the transmission elements, then the mechanism's stage.
    """

    name: str
    gravity: float
    efficiency_model: EfficiencyModel
    mechanism: Mechanism
    transmission: tuple[Stage, ...]
    spec: AxisSpec
    motor: MotorData | None = None
    raw: dict[str, Any] = field(default_factory=dict, compare=False)
    electrical: MotorElectrical | None = None
    drive: DriveData | None = None
    environment: Environment = field(default_factory=Environment)

    @property
    def stages(self) -> tuple[Stage, ...]:
        """Transmission stages then the mechanism, from the motor outward."""
        return (*self.transmission, self.mechanism.stage)

    @property
    def total_ratio(self) -> float:
        """Motor angle per load travel: product of ratios [-] or [rad/m]."""
        return math.prod(s.ratio for s in self.stages)

    @property
    def requirements(self) -> Requirements | None:
        """The dynamic requirements in SI at the load (``requirements:``; None when absent)."""
        return requirements(self.spec.requirements, self.mechanism.motion)

    @property
    def load_inertia(self) -> float:
        """Everything but the motor, at the motor shaft [kg m^2]."""
        return chain_inertia(list(self.stages)) + self.spec.extra_inertia

    def cycle(self) -> Cycle:
        """The motion profile as an exact cycle (InputError naming ``profile[i]`` if impossible)."""
        from drivetrain.motion.profiles import parse_profile

        cached: Cycle | None = self.__dict__.get("_cycle")  # a Cycle is immutable: parsed once per axis
        if cached is not None:
            return cached
        if not self.spec.profile:
            raise InputError("profile", "is empty: give at least one move", has_value=False)
        cycle = parse_profile(self.spec.profile, self.mechanism.motion, "profile")
        self.__dict__["_cycle"] = cycle  # (not a field: equality, replace() and the repr ignore it)
        return cycle


def parse_axis(data: Any, *, text_checked: bool = False) -> Axis:
    """Validate an axis-file mapping and build the SI ``Axis``.

    ``text_checked``: the caller has checked every key and text value of ``data`` with
    :func:`check_text` already (a study checks its base file once and each variant's new values).
    """
    if not isinstance(data, dict):
        raise InputError("", "an axis file must be a mapping of keys (axis, mechanism, transmission, profile, ...)",
                         type(data).__name__)
    if not text_checked:
        check_text(data, "")
    try:
        spec = AxisSpec.model_validate(data)
    except ValidationError as exc:
        raise input_error_from_pydantic(exc, data) from None
    try:
        mechanism = spec.mechanism.build(spec.gravity)
        stages = tuple(t.build(k) for k, t in enumerate(resolve_transmission(spec.transmission)))
    except InputError as exc:
        raise exc.at("") from None
    check_ratio_chain([*stages, mechanism.stage], len(stages))
    requirements(spec.requirements, mechanism.motion)  # its windows' units depend on the mechanism: checked here
    if (spec.requirements is None and spec.motor is not None and spec.motor.select is not None
            and spec.motor.select.objective == "fastest_settling"):
        raise InputError("motor.select.objective", "fastest_settling needs a requirements: block (at least "
                         "settling: {window: ...}) to simulate the candidates against", "fastest_settling")
    motor = _motor_data(spec.motor) if spec.motor is not None else None
    electrical = None
    if spec.motor is not None and spec.motor.select is None:
        try:
            electrical = motor_electrical(spec.motor, spec.motor.id)
        except InputError as exc:
            raise exc.at("") from None
    drive = None if spec.drive is None else drive_data(spec.drive)
    if drive is not None:
        check_bus_limits(nominal_bus_voltage(drive, electrical, spec.motor), drive.bus_max_voltage,
                         drive.regen_on_voltage, "drive")
    return Axis(name=spec.axis, gravity=spec.gravity, efficiency_model=spec.efficiency_model,
                mechanism=mechanism, transmission=stages, spec=spec, motor=motor, raw=data,
                electrical=electrical, drive=drive, environment=environment(spec.environment))


def check_ratio_chain(stages: list[Stage], n_transmission: int) -> None:
    """The product of the ratios from the motor outward must stay within ``MAX_TOTAL_RATIO`` (and
    above its inverse): each speed, torque and inertia is carried through it (J / i^2 at each
    stage), so a chain of large ratios would overflow a float in the sizing. The error names the
    element at which the product leaves the bound (``transmission[k]`` or ``mechanism``)."""
    total = 1.0
    for k, st in enumerate(stages):
        total *= abs(st.ratio)
        if not 1.0 / MAX_TOTAL_RATIO <= total <= MAX_TOTAL_RATIO:  # (also catches inf and nan)
            where = f"transmission[{k}]" if k < n_transmission else "mechanism"
            raise InputError(where, f"brings the product of the ratios from the motor to {total:.3g}; it must lie "
                             f"between {1.0 / MAX_TOTAL_RATIO:g} and {MAX_TOTAL_RATIO:g} (in SI: rad/m for a "
                             "linear mechanism)", st.ratio)


def _motor_data(m: MotorSpec) -> MotorData | None:
    if m.select is not None:
        return None
    if m.id is not None:
        from dataclasses import replace

        from drivetrain import catalog

        try:
            row = catalog.get(m.id)
        except InputError as exc:
            raise exc.at("motor") from None
        base = motor_from_catalog_row(row, m.name)
        # Values given beside the id override the catalog's (e.g. the with-brake inertia).
        given = {k: getattr(m, k) for k in ("inertia", "rated_torque", "stall_torque", "peak_torque", "rated_speed",
                                            "max_speed") if getattr(m, k) is not None}
        return replace(base, **given)
    if m.inertia is None or m.rated_torque is None or m.peak_torque is None or m.max_speed is None:
        raise InputError("motor", "a given motor needs inertia, rated_torque, peak_torque and max_speed",
                         has_value=False)
    return MotorData(name=m.name or m.id or "motor", inertia=m.inertia, rated_torque=m.rated_torque,
                     peak_torque=m.peak_torque, rated_speed=m.rated_speed or m.max_speed, max_speed=m.max_speed,
                     stall_torque=m.stall_torque)


def motor_from_catalog_row(row: dict[str, Any], name: str | None = None) -> MotorData:
    """A catalog motor record (``catalog.get``: SI values keyed with their unit) as MotorData."""
    def num(key: str) -> float:
        value = row.get(key)
        if value is None or (isinstance(value, float) and math.isnan(value)):
            raise InputError("motor.id", f"the catalog motor has no {key}", row.get("id"))
        return float(value)

    stall = row.get("stall_torque_Nm")
    return MotorData(
        name=name or str(row.get("id")), inertia=num("rotor_inertia_kgm2"), rated_torque=num("rated_torque_Nm"),
        peak_torque=num("peak_torque_Nm"), rated_speed=num("rated_speed_rad_s"), max_speed=num("max_speed_rad_s"),
        stall_torque=None if stall is None else float(stall), approximate_envelope=row.get("curve") is None,
        source=f"{row.get('vendor', '')} {row.get('id')}: {row.get('source', 'catalog')}",
        unverified_reason=str(row.get("unverified_reason") or "") if row.get("unverified") else "",
    )


def load_axis(path: str | Path) -> Axis:
    """Read and validate an axis file."""
    return parse_axis(read_yaml(path))
