"""The axis file (YAML, v1): pydantic models that validate it, and the SI ``Axis`` it loads into.

See docs/axis-file.md for every key, with one example per mechanism. Bad input raises
``InputError`` naming the field path (``mechanism.load.mass: must be > 0 kg, got -3 kg``).
"""

from __future__ import annotations

import functools
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
from drivetrain.axis.requirements import Requirements, RequirementsSpec, requirements
from drivetrain.axis.resolve import resolve_transmission
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
from drivetrain.physics.efficiency import EfficiencyModel
from drivetrain.physics.loads import G_STANDARD
from drivetrain.physics.mechanisms import Mechanism, MechanismSpec
from drivetrain.physics.stage import Stage, chain_inertia
from drivetrain.physics.transmission import TransmissionSpec

if TYPE_CHECKING:
    from drivetrain.motion.profiles import Cycle

MAX_FILE_BYTES = 1_000_000
"""Largest axis file accepted [bytes]: a real axis is a few kB."""
MAX_ALIASES = 100
"""YAML aliases allowed: enough for shared blocks, far too few for an alias bomb."""
MAX_NODES = 100_000
"""Values a file may expand to, aliases included."""
MAX_DEPTH = 100
"""Deepest nesting of mappings and lists: a real axis file is under 8 levels deep."""
MAX_DIGITS = 400
"""Longest number written in a file [digits]: a float has 17 significant digits."""



class Margins(Spec):
    """Safety factors and limits: required x factor must not exceed the available.

    Defaults as servo sizing guides use them (docs/checks.md, "Default margins"): torque and RMS
    torque x 1.2, speed x 1.1, inertia ratio 5 (lecture: below 5:1). ``gearbox_shock_factor`` is
    the vendor's fs on T2B above 1000 cycles/h, read from the vendor's chart; unset, T2B is then
    unknown.
    """

    torque: float = Field(default=1.2, ge=1.0, le=10.0)
    rms_torque: float | None = Field(default=None, ge=1.0, le=10.0)
    speed: float = Field(default=1.1, ge=1.0, le=10.0)
    inertia_ratio: float = Field(default=5.0, gt=0.0, le=1000.0)
    gearbox_shock_factor: float | None = Field(default=None, ge=1.0, le=10.0)


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
    objective: Literal["smallest", "rms_utilisation", "inertia_match", "energy"] = "smallest"
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
    requirements(spec.requirements, mechanism.motion)  # its windows' units depend on the mechanism: checked here
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


def read_yaml(path: str | Path) -> Any:
    """Read an axis YAML file safely: size limit, safe loader, alias-bomb and depth guards (the data of a
    text read before comes from ``yaml_cache``: what the loader gave for it then)."""
    p = Path(path)
    try:
        size = p.stat().st_size
    except OSError as exc:
        raise InputError("file", f"cannot be read ({exc.strerror})", str(path)) from None
    if size > MAX_FILE_BYTES:
        raise InputError("file", f"is too large ({size} bytes; an axis file is at most {MAX_FILE_BYTES} bytes)",
                         str(path))
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError("file", f"cannot be read as UTF-8 text ({exc})", str(path)) from None
    from drivetrain.axis import yaml_cache

    found, data = yaml_cache.get(text)  # a text read before: its data, without the YAML library
    if not found:
        data = parse_yaml(text, str(path))
        yaml_cache.put(text, data)
    return data


def parse_yaml(text: str, source: str = "<text>") -> Any:
    """Parse YAML text with the safe loader and the same limits as files (one pass over the text)."""
    import yaml

    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise InputError("file", f"is too large (an axis file is at most {MAX_FILE_BYTES} bytes)", _src(source))
    try:
        loader = _loader_class()(text)
    except yaml.YAMLError as exc:  # the reader refuses NUL and other special characters at once
        raise InputError("file", f"is not valid YAML: {str(exc).splitlines()[0]}", _src(source)) from None
    try:
        try:
            node = loader.get_single_node()
        except RecursionError:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source)) from None
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
            problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
            raise InputError("file", f"is not valid YAML{where}: {problem}", _src(source)) from None
        if node is None:
            raise InputError("file", "is empty", _src(source))
        if loader.too_deep is not None:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels) (line {loader.too_deep})",
                             _src(source))
        _check_graph(node, source)
        try:
            data = loader.construct_document(node)
        except yaml.YAMLError as exc:
            raise InputError("file", f"is not valid YAML: {exc}", _src(source)) from None
        except (ValueError, OverflowError, RecursionError) as exc:  # e.g. an integer past Python's digit limit
            raise InputError("file", f"holds a value that cannot be read ({exc})", _src(source)) from None
    finally:
        loader.dispose()
    return data


@functools.cache
def _loader_class() -> Any:
    """``yaml.SafeLoader`` whose composer stops descending past ``MAX_DEPTH`` levels.

    The scanner and parser are iterative; the composer recurses once per level, so a file nested
    500 levels deep would end in RecursionError. Past the limit the rest of the nesting is
    skipped as events (no recursion) and the depth is reported once the document is read.
    """
    import yaml

    class Loader(yaml.SafeLoader):
        too_deep: int | None = None
        _depth = 0

        def compose_node(self, parent: Any, index: Any) -> Any:
            if self._depth >= MAX_DEPTH and self.check_event(yaml.CollectionStartEvent):
                if self.too_deep is None:
                    self.too_deep = self.peek_event().start_mark.line + 1
                self._skip_collection()
                return yaml.ScalarNode("tag:yaml.org,2002:null", "")
            self._depth += 1
            try:
                return super().compose_node(parent, index)
            finally:
                self._depth -= 1

        def _skip_collection(self) -> None:
            level = 0
            while True:
                event = self.get_event()
                if isinstance(event, yaml.CollectionStartEvent):
                    level += 1
                elif isinstance(event, yaml.CollectionEndEvent):
                    level -= 1
                    if level == 0:
                        return

    return Loader


def check_text(data: Any, path: str) -> None:
    """Every key and text value must be valid Unicode (a lone surrogate cannot be printed or stored)."""
    if isinstance(data, dict):
        for key, value in data.items():
            sub = f"{path}.{key}" if path else str(key)
            if isinstance(key, str) and not _valid_unicode(key):
                raise InputError(path or "file", "has a key that is not valid Unicode (a lone surrogate)", key)
            if isinstance(key, str) and not key:
                raise InputError(f"{path}.''" if path else "''", "unknown key (the key is empty)", has_value=False)
            check_text(value, sub)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            check_text(value, f"{path}[{i}]")
    elif isinstance(data, str) and not _valid_unicode(data):
        raise InputError(path, "is not valid Unicode text (a lone surrogate)", data)



def _valid_unicode(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _src(source: str | None) -> str | None:
    return None if source is None or source.startswith("<") else source


def _check_graph(root: Any, source: str) -> None:
    """Refuse alias bombs: count aliases and expanded nodes before constructing Python objects."""
    import yaml

    seen_ids: dict[int, int] = {}
    aliases = 0

    def expanded(node: Any, depth: int, path: str) -> int:
        nonlocal aliases
        if depth > MAX_DEPTH:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source))
        key = id(node)
        if key in seen_ids:
            aliases += 1
            if aliases > MAX_ALIASES:
                raise InputError("file", f"uses more than {MAX_ALIASES} YAML aliases", _src(source))
            return seen_ids[key]
        if isinstance(node, yaml.MappingNode):
            n = 1 + sum(expanded(k, depth + 1, path) + expanded(v, depth + 1, _key_path(path, k))
                        for k, v in node.value)
        elif isinstance(node, yaml.SequenceNode):
            n = 1 + sum(expanded(v, depth + 1, f"{path}[{i}]") for i, v in enumerate(node.value))
        else:
            n = 1
            if (isinstance(node, yaml.ScalarNode) and node.tag.endswith((":int", ":float"))
                    and len(node.value) > MAX_DIGITS):
                raise InputError(path or "file", f"is a number of more than {MAX_DIGITS} digits",
                                 node.value[:20] + "...")
        seen_ids[key] = n
        if n > MAX_NODES:
            raise InputError("file", f"expands to more than {MAX_NODES} values (YAML alias bomb?)", _src(source))
        return n

    expanded(root, 0, "")


def _key_path(path: str, key: Any) -> str:
    import yaml

    name = str(key.value)[:100] if isinstance(key, yaml.ScalarNode) else "?"
    return f"{path}.{name}" if path else name


def load_axis(path: str | Path) -> Axis:
    """Read and validate an axis file."""
    return parse_axis(read_yaml(path))
