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
    from drivetrain.motion.cycle import Cycle

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
MAX_TOTAL_RATIO = 1e12
"""Largest product of the ratios from the motor to the load [-, or rad/m]: a harmonic drive, a worm
and a planetary stage on a 1 mm screw come to about 1e10."""



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


def read_yaml(path: str | Path, field: str = "file") -> Any:
    """Read an axis YAML file safely (``read_yaml_text``); an error names ``field`` and the path."""
    return read_yaml_text(path, field)[1]


def read_yaml_text(path: str | Path, field: str = "file") -> tuple[str, Any]:
    """(text, data) of a YAML file: read through ``drivetrain.userfile`` (a regular file of at most
    ``MAX_FILE_BYTES``: no device, FIFO, directory or NUL in the path), then parsed by ``parse_yaml``
    (the data of a text read before comes from ``yaml_cache``: what the loader gave for it then)."""
    from drivetrain.userfile import read_text

    text = read_text(path, field, MAX_FILE_BYTES, "YAML file")
    from drivetrain.axis import yaml_cache

    found, data = yaml_cache.get(text)  # a text read before: its data, without the YAML library
    if not found:
        try:
            data = parse_yaml(text, str(path))
        except InputError as exc:
            if field != "file" and exc.field == "file":
                raise InputError(field, exc.rule, str(path)) from None
            raise
        yaml_cache.put(text, data)
    return text, data


class _Refused(Exception):
    """A bound of ``parse_yaml`` broken while the document is composed (its rule, and its line)."""

    def __init__(self, rule: str, line: int | None) -> None:
        super().__init__(rule)
        self.rule = f"{rule} (line {line})" if line is not None else rule


def parse_yaml(text: str, source: str = "<text>") -> Any:
    """Parse YAML text with the safe loader and the limits of an input file.

    Bounds, each refused as soon as it is passed, while the document is read: ``MAX_FILE_BYTES``,
    ``MAX_DEPTH`` levels of nesting in block or flow style, ``MAX_NODES`` values, ``MAX_ALIASES``
    aliases and ``MAX_NODES`` values once the aliases are expanded, numbers of ``MAX_DIGITS``
    digits; a key given twice in one mapping is refused naming the key and both lines. The parse
    time is thus bounded (under a second for the largest file within the bounds, bench/RESULTS.md).
    """

    if len(text) > MAX_FILE_BYTES or len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise InputError("file", f"is too large (an axis file is at most {MAX_FILE_BYTES} bytes)", _src(source))
    try:
        return _parse(text, source, _loader_class())
    except _Escape:  # libyaml refuses a "\ud800" escape: PyYAML's parser reads it, check_text then names the field
        return _parse(text, source, _loader_class(python=True))


class _Escape(Exception):
    """libyaml refused a Unicode escape that PyYAML's own parser reads."""


def _parse(text: str, source: str, loader_class: Any) -> Any:
    import yaml

    try:
        loader = loader_class(text)
    except yaml.YAMLError as exc:  # the reader refuses NUL and other special characters at once
        raise InputError("file", f"is not valid YAML: {str(exc).splitlines()[0]}", _src(source)) from None
    except UnicodeEncodeError:  # the C reader takes UTF-8: a lone surrogate has none
        raise InputError("file", "is not valid YAML: it holds a character that is not valid Unicode "
                         "(a lone surrogate)", _src(source)) from None
    try:
        try:
            node = loader.get_single_node()
        except _Refused as exc:
            raise InputError("file", exc.rule, _src(source)) from None
        except RecursionError:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source)) from None
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
            problem = str(getattr(exc, "problem", None) or str(exc).splitlines()[0])
            if "nesting depth" in problem:  # libyaml's own bound (1000 levels), met while it reads ahead
                raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels){where}",
                                 _src(source)) from None
            if "Unicode character escape" in problem and loader_class is not _loader_class(python=True):
                raise _Escape from None
            raise InputError("file", f"is not valid YAML{where}: {problem}", _src(source)) from None
        if node is None:
            raise InputError("file", "is empty", _src(source))
        _check_graph(node, source)
        try:
            data = loader.construct_document(node)
        except yaml.YAMLError as exc:
            raise InputError("file", f"is not valid YAML: {str(exc)[:200]}", _src(source)) from None
        except (ValueError, OverflowError, RecursionError) as exc:  # e.g. an integer past Python's digit limit
            raise InputError("file", f"holds a value that cannot be read ({str(exc)[:200]})", _src(source)) from None
    finally:
        loader.dispose()
    return data


@functools.cache
def _loader_class(python: bool = False) -> Any:
    """The safe loader, counting while it composes: past ``MAX_DEPTH`` levels, ``MAX_NODES`` values
    or ``MAX_ALIASES`` aliases it stops at once (``_Refused``, with the line).

    The events come from libyaml's parser where PyYAML has it (``CParser``: 5-10 times faster than
    the pure-Python scanner, whose cost also grows with the flow nesting) and from PyYAML's own
    parser otherwise; the document is composed by PyYAML's composer with these counts and built by
    its safe constructor, so the data are those of ``yaml.safe_load``. ``python``: PyYAML's parser
    even where libyaml is installed. Both parsers read tokens
    only as the composer asks for events, so a file nested 20,000 levels deep is refused after
    reading its first hundred levels.
    """
    import yaml
    from yaml.constructor import SafeConstructor
    from yaml.resolver import Resolver

    composer: Any = yaml.composer.Composer

    class Counting(composer):
        _depth = 0
        _nodes = 0
        _aliases = 0

        def _line(self) -> int | None:
            mark = getattr(self.peek_event(), "start_mark", None)
            return None if mark is None else mark.line + 1

        def compose_node(self, parent: Any, index: Any) -> Any:
            if self.check_event(yaml.AliasEvent):
                self._aliases += 1
                if self._aliases > MAX_ALIASES:
                    raise _Refused(f"uses more than {MAX_ALIASES} YAML aliases", self._line())
                return super().compose_node(parent, index)
            self._nodes += 1
            if self._nodes > MAX_NODES:
                raise _Refused(f"holds more than {MAX_NODES} values", self._line())
            if not self.check_event(yaml.MappingStartEvent, yaml.SequenceStartEvent):  # (CParser: no base class)
                return super().compose_node(parent, index)
            if self._depth >= MAX_DEPTH:
                raise _Refused(f"is nested too deeply (over {MAX_DEPTH} levels)", self._line())
            self._depth += 1
            try:
                return super().compose_node(parent, index)
            finally:
                self._depth -= 1

    cparser: Any = None
    if getattr(yaml, "__with_libyaml__", False) and not python:
        cparser = yaml.cyaml.CParser  # type: ignore[attr-defined]
    constructor: Any = SafeConstructor
    resolver: Any = Resolver
    if cparser is not None:
        class CLoader(Counting, cparser, constructor, resolver):
            def __init__(self, stream: str) -> None:
                cparser.__init__(self, stream)
                composer.__init__(self)
                constructor.__init__(self)
                resolver.__init__(self)

        return CLoader

    class Loader(Counting, yaml.SafeLoader):
        pass

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
    """Refuse alias bombs (the values the aliases expand to), long numbers and keys given twice.

    The composer has bounded the depth, the values as written and the aliases; only aliases can
    make the expanded document larger than the file, so the expansion bound names them."""
    import yaml

    seen_ids: dict[int, int] = {}

    def expanded(node: Any, depth: int, path: str) -> int:
        if depth > MAX_DEPTH:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source))
        key = id(node)
        if key in seen_ids:
            return seen_ids[key]
        if isinstance(node, yaml.MappingNode):
            _check_keys(node, path)
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
            raise InputError("file", f"expands to more than {MAX_NODES} values through its YAML aliases "
                             "(an alias bomb?)", _src(source))
        return n

    expanded(root, 0, "")


def _check_keys(node: Any, path: str) -> None:
    """A key written twice in one mapping is refused (YAML forbids it; the loader would keep the last)."""
    import yaml

    first: dict[tuple[str, str], int] = {}
    for k, _ in node.value:
        if not isinstance(k, yaml.ScalarNode) or k.tag == "tag:yaml.org,2002:merge":
            continue  # a merge (<<) may be overridden; complex keys are refused by the schema
        line = k.start_mark.line + 1
        if (k.tag, k.value) in first:
            raise InputError(_key_path(path, k), f"is given twice (lines {first[(k.tag, k.value)]} and {line}): "
                             "give each key once", has_value=False)
        first[(k.tag, k.value)] = line


def _key_path(path: str, key: Any) -> str:
    import yaml

    name = str(key.value)[:100] if isinstance(key, yaml.ScalarNode) else "?"
    return f"{path}.{name}" if path else name


def load_axis(path: str | Path) -> Axis:
    """Read and validate an axis file."""
    return parse_axis(read_yaml(path))
