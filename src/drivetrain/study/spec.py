"""The study file: a base axis file, the parameters to vary, a design, what to record, an optimisation.

Everything is validated before any variant runs: an unknown path, a unit of the wrong dimension,
an empty range, a distribution in a grid or a design of more than ``MAX_VARIANTS`` variants
without ``yes`` is an InputError naming the field (``parameters.mechanism.lead.stop``).

A parameter is kept in the unit the study gives (its table column holds that unit) and written
into each variant's axis mapping in SI (a bare number is SI in an axis file).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from drivetrain.errors import InputError
from drivetrain.fields import input_error_from_pydantic
from drivetrain.study.paths import Token, get_path, parse_path, set_path

VERSION = 1
"""The study-file format this version reads (``study: 1``)."""
MAX_VARIANTS = 1_000_000
"""More variants than this need ``--yes`` (``yes=True``)."""
MAX_STUDY_VARIANTS = 10**10
"""No study has more variants, even with ``--yes`` (at a thousand variants a second, four months)."""
MAX_PARAMETER_VALUES = 1_000_000
"""Values one parameter (a list or a gridded range) may take: its values are held in memory."""
MAX_DESIGN_BYTES = 1 << 30
"""Memory the points of a sampled design (random, lhs, sobol, saltelli, morris) may take [bytes]:
they are drawn at once (8 bytes per parameter and point, times ``DESIGN_BYTES_FACTOR``)."""
DESIGN_BYTES_FACTOR = 4
"""Copies of the point array a sampler and the values made from it hold at once (a bound, measured
below 3 for SALib's saltelli and morris samplers)."""
MAX_SEED = 2**32 - 1
"""Largest seed: SALib's samplers seed numpy's legacy generator, which takes 0 to 2**32 - 1."""
DESIGNS = ("grid", "random", "lhs", "sobol", "saltelli", "morris")
RECORD_GROUPS = ("motor", "gearbox", "margins", "rms", "peak", "energy", "checks")
DYNAMICS_GROUP = "dynamics"
"""The dynamic answer's figures; recorded by default when the study has requirements (``parse_study``)."""
GROUPS = (*RECORD_GROUPS, DYNAMICS_GROUP)
OBJECTIVES = {"motor_size": ("rated_power_W", "minimize"), "energy": ("energy_per_cycle_J", "minimize"),
              "rms_margin": ("margin_rms_torque", "maximize"), "peak_margin": ("margin_peak_torque", "maximize"),
              "worst_margin": ("worst_margin", "maximize"),
              "settling_time": ("dynamics_settling_time_s", "minimize")}
"""Named objectives: the result column and its direction."""

Scalar = float | int | str | bool


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class ParameterSpec(_Model):
    """One parameter: ``values`` (a list), a range (``start``, ``stop`` and ``num`` or ``step``) or a
    ``distribution`` (uniform: low, high; normal: mean, std, optional low/high; triangular: low, mode,
    high). ``unit`` applies to bare numbers; numbers may also carry their unit (``"5 kg"``)."""

    values: list[Scalar] | None = None
    start: float | str | None = None
    stop: float | str | None = None
    num: int | None = Field(default=None, ge=1)
    step: float | str | None = None
    distribution: Literal["uniform", "normal", "triangular"] | None = None
    low: float | str | None = None
    high: float | str | None = None
    mean: float | str | None = None
    std: float | str | None = None
    mode: float | str | None = None
    unit: str | None = None


class OptimizeSpec(_Model):
    """Minimise (or maximise) a result column over the parameters, every check passing."""

    objective: str = "motor_size"
    direction: Literal["minimize", "maximize"] | None = None
    method: Literal["optuna", "differential_evolution"] = "optuna"
    trials: int = Field(default=200, ge=1, le=100_000)


class ReportSpec(_Model):
    """The study report's two map axes (parameter paths) and the output of the sensitivity ranking."""

    x: str | None = None
    y: str | None = None
    output: str = "worst_margin"


class StudySpec(_Model):
    """A study file (YAML)."""

    study: int = Field(description="format version, 1")
    name: str = "study"
    base: str
    parameters: dict[str, ParameterSpec | list[Scalar]]
    design: Literal["grid", "random", "lhs", "sobol", "saltelli", "morris"] = "grid"
    samples: int | None = Field(default=None, ge=1)
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    points: int = Field(default=64, ge=3, le=100_000)
    record: list[str] = Field(default_factory=lambda: list(RECORD_GROUPS))
    report: ReportSpec = Field(default_factory=ReportSpec)
    optimize: OptimizeSpec | None = None

    @field_validator("study")
    @classmethod
    def _version(cls, v: int) -> int:
        if v != VERSION:
            raise ValueError(f"must be {VERSION} (the study-file format this drivetrain reads)")
        return v


# ---------------------------------------------------------------------------------------------
# parameters


@dataclass(frozen=True)
class Parameter:
    """A validated parameter: its path, unit and SI factor, and its values or distribution (in ``unit``)."""

    path: str
    tokens: tuple[Token, ...]
    unit: str | None
    si: float  # SI value = value x si (1 for unitless and non-numeric values)
    values: tuple[Any, ...] | None  # a list or a gridded range
    low: float | None = None  # continuous range (optimisation / Monte Carlo) or distribution bounds
    high: float | None = None
    distribution: str | None = None
    mean: float | None = None
    std: float | None = None
    mode: float | None = None

    @property
    def numeric(self) -> bool:
        return self.values is None or all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                          for v in self.values)

    def ppf(self, u: np.ndarray) -> np.ndarray | list[Any]:
        """Values at the unit-cube coordinates ``u`` (inverse CDF; a list is picked uniformly)."""
        if self.values is not None:
            k = np.minimum((np.asarray(u) * len(self.values)).astype(int), len(self.values) - 1)
            return [self.values[i] for i in k]
        from scipy import stats

        if self.distribution == "normal":
            assert self.mean is not None and self.std is not None
            lo = -math.inf if self.low is None else (self.low - self.mean) / self.std
            hi = math.inf if self.high is None else (self.high - self.mean) / self.std
            uu = np.clip(u, 1e-6, 1 - 1e-6)  # a Morris level at 0 or 1 stays finite
            return np.asarray(stats.truncnorm.ppf(uu, lo, hi, loc=self.mean, scale=self.std), dtype=float)
        assert self.low is not None and self.high is not None
        if self.distribution == "triangular":
            assert self.mode is not None
            c = (self.mode - self.low) / (self.high - self.low)
            return np.asarray(stats.triang.ppf(u, c, loc=self.low, scale=self.high - self.low), dtype=float)
        return self.low + np.asarray(u, dtype=float) * (self.high - self.low)

    def to_si(self, value: Any) -> Any:
        """The value as the axis file gets it (SI float for a number with a unit)."""
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value) * self.si if self.unit else value
        return value

    def as_quantity(self, value: Any) -> Any:
        """The value with its unit as text (``"5.0 kg"``), for the unit-dimension check of the axis file."""
        if self.unit and isinstance(value, (int, float)) and not isinstance(value, bool):
            return f"{float(value)!r} {self.unit}"
        return value


def _quantity(value: Any, unit: str | None, field: str) -> tuple[float, str | None]:
    """(magnitude in ``unit``, unit): a number is in ``unit``; a string carries its own unit and is
    converted to ``unit`` when one is given."""
    if isinstance(value, bool) or value is None:
        raise InputError(field, "must be a number or a quantity with a unit", value)
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise InputError(field, "must be a finite number", value)
        return float(value), unit
    known = _known_quantity(str(value))
    if known is not None and (unit is None or known[1] == unit):  # "<number> <unit>", a unit seen before
        return known[0], known[1]
    from drivetrain.units import _normalise, check_grammar, registry

    check_grammar(_normalise(str(value)), field)  # nothing that computes reaches pint's parser
    ureg = registry()
    try:
        q: Any = ureg.Quantity(_normalise(str(value)))
    except Exception:
        raise InputError(field, "is not a number or a quantity with a unit", value) from None
    if unit is None:
        u = str(q.units) if not q.dimensionless or str(q.units) != "dimensionless" else None
        return float(q.magnitude), (None if u == "dimensionless" else f"{q.units:~}".replace(" ", ""))
    try:
        return float(q.to(_normalise(unit)).magnitude), unit
    except Exception:
        raise InputError(field, f"has a unit of another dimension than {unit}", value) from None


def _cached_unit(unit: str) -> tuple[str, float] | None:
    """(quantity, SI value of one ``unit``) from the units remembered on disk (``unit_cache``: what
    ``drivetrain.units.parse`` returns for ``"1 <unit>"``), None when not remembered or an offset unit.
    A study file's units are thus read without building pint's registry (about 0.6 s)."""
    from drivetrain import unit_cache
    from drivetrain.units import _SIMPLE_UNIT, QUANTITIES

    if not _SIMPLE_UNIT.fullmatch(unit):
        return None
    seen: set[str] = set()
    for q, (_, dim) in QUANTITIES.items():
        known = unit_cache.get(unit, q)
        # _si_factor takes the first quantity pint accepts: a remembered one is that one when no
        # quantity before it has its dimension (angles and rpm, dimensionless in pint, are left to pint)
        if known is not None and known[1] == 0.0 and dim not in seen and dim not in ("", "1/[time]"):
            return q, known[0]
        seen.add(dim)
    return None


def _known_quantity(text: str) -> tuple[float, str] | None:
    """(number, unit) of ``"<number> <unit>"`` whose unit is remembered (``_cached_unit``), else None."""
    from drivetrain.units import _NUMBER_UNIT

    m = _NUMBER_UNIT.fullmatch(text)
    if m is None or _cached_unit(m.group(2)) is None:
        return None
    number = float(m.group(1))
    return (number, m.group(2)) if math.isfinite(number) else None


def _si_factor(unit: str | None, field: str) -> float:
    """SI value of one ``unit`` (rpm with the explicit 2 pi / 60, as drivetrain.units parses it)."""
    if not unit:
        return 1.0
    known = _cached_unit(unit)
    if known is not None:
        return known[1]
    from drivetrain.units import QUANTITIES, parse

    for q in QUANTITIES:
        try:
            return parse(f"1 {unit}", q, field)
        except InputError:
            continue
    raise InputError(field, "is not a unit drivetrain knows", unit)


def build_parameter(path: str, raw: ParameterSpec | list[Any], design: str, optimizing: bool) -> Parameter:
    """Validate one parameter and bring its numbers to one unit."""
    field = f"parameters.{path}"
    tokens = parse_path(path, field)
    spec = ParameterSpec(values=raw) if isinstance(raw, list) else raw
    kinds = [spec.values is not None, spec.start is not None or spec.stop is not None, spec.distribution is not None]
    if sum(kinds) != 1:
        raise InputError(field, "give exactly one of values (a list), start/stop (a range) or distribution",
                         has_value=False)
    unit = spec.unit
    if spec.values is not None:
        if not spec.values:
            raise InputError(f"{field}.values", "is empty: give at least one value", has_value=False)
        vals: list[Any] = []
        for k, v in enumerate(spec.values):
            if isinstance(v, str):
                try:
                    mag, unit2 = _quantity(v, unit, f"{field}.values[{k}]")
                except InputError:
                    if unit is not None:
                        raise
                    vals.append(v)  # a name (a material, a catalog id): no unit
                    continue
                unit = unit or unit2
                vals.append(mag)
            else:
                vals.append(v)
        return Parameter(path, tokens, unit, _si_factor(unit, f"{field}.unit"), tuple(vals))
    if kinds[1]:
        if spec.start is None or spec.stop is None:
            raise InputError(field, "a range needs both start and stop", has_value=False)
        start, unit = _quantity(spec.start, unit, f"{field}.start")
        stop, unit = _quantity(spec.stop, unit, f"{field}.stop")
        si = _si_factor(unit, f"{field}.unit")
        if spec.num is not None and spec.step is not None:
            raise InputError(field, "give num or step, not both", has_value=False)
        if spec.num is not None:
            if spec.num > MAX_PARAMETER_VALUES:
                raise InputError(f"{field}.num", f"must be at most {MAX_PARAMETER_VALUES:,} (the values of one "
                                 "parameter are held in memory)", spec.num)
            values = tuple(np.linspace(start, stop, spec.num).tolist())
            if spec.num > 1 and start == stop:
                raise InputError(f"{field}.stop", "equals start: the range is empty", spec.stop)
            return Parameter(path, tokens, unit, si, values, low=min(start, stop), high=max(start, stop))
        if spec.step is not None:
            step, _ = _quantity(spec.step, unit, f"{field}.step")
            if step <= 0:
                raise InputError(f"{field}.step", "must be > 0", spec.step)
            if stop < start:
                raise InputError(f"{field}.stop", f"is below start ({start:g}): the range is empty", spec.stop)
            span = (stop - start) / step
            if not math.isfinite(span) or span >= MAX_PARAMETER_VALUES:
                raise InputError(f"{field}.step", f"gives {_count(span + 1)} values from start to stop; one "
                                 f"parameter takes at most {MAX_PARAMETER_VALUES:,} (the smallest step that fits is "
                                 f"{(stop - start) / (MAX_PARAMETER_VALUES - 1):.6g})", spec.step)
            n = math.floor(span * (1 + 1e-12) + 1e-9) + 1
            return Parameter(path, tokens, unit, si, tuple(np.round(start + step * np.arange(n), 12).tolist()),
                             low=start, high=stop)
        if design == "grid" and not optimizing:
            raise InputError(field, "a range in a grid needs num or step", has_value=False)
        if not stop > start:
            raise InputError(f"{field}.stop", f"must be above start ({start:g}): the range is empty", spec.stop)
        return Parameter(path, tokens, unit, si, None, low=start, high=stop, distribution="uniform")
    # a distribution
    if design == "grid":
        raise InputError(f"{field}.distribution", "is for Monte Carlo designs (random, lhs, sobol, saltelli, "
                         "morris), not a grid", spec.distribution)
    if optimizing:
        raise InputError(f"{field}.distribution", "an optimisation varies ranges and lists, not distributions",
                         spec.distribution)

    def num(name: str, required: bool) -> float | None:
        nonlocal unit
        v = getattr(spec, name)
        if v is None:
            if required:
                raise InputError(f"{field}.{name}", f"is required for a {spec.distribution} distribution",
                                 has_value=False)
            return None
        mag, unit = _quantity(v, unit, f"{field}.{name}")
        return mag

    if spec.distribution == "normal":
        mean, std = num("mean", True), num("std", True)
        low, high = num("low", False), num("high", False)
        assert mean is not None and std is not None
        if not std > 0:
            raise InputError(f"{field}.std", "must be > 0", spec.std)
        if low is not None and high is not None and not high > low:
            raise InputError(f"{field}.high", "must be above low: the range is empty", spec.high)
        return Parameter(path, tokens, unit, _si_factor(unit, f"{field}.unit"), None, low=low, high=high,
                         distribution="normal", mean=mean, std=std)
    low, high = num("low", True), num("high", True)
    assert low is not None and high is not None
    if not high > low:
        raise InputError(f"{field}.high", f"must be above low ({low:g}): the range is empty", spec.high)
    mode = num("mode", spec.distribution == "triangular")
    if mode is not None and not low <= mode <= high:
        raise InputError(f"{field}.mode", "must lie between low and high", spec.mode)
    return Parameter(path, tokens, unit, _si_factor(unit, f"{field}.unit"), None, low=low, high=high,
                     distribution=spec.distribution, mode=mode)


# ---------------------------------------------------------------------------------------------
# the study


@dataclass(frozen=True)
class Study:
    """A validated study: the base axis mapping, its parameters and the design's variants."""

    spec: StudySpec
    text: str  # the study file as given
    source: str  # where it came from
    base: dict[str, Any]
    base_text: str
    parameters: tuple[Parameter, ...]

    @property
    def names(self) -> list[str]:
        return [p.path for p in self.parameters]

    def n_variants(self) -> int:
        """How many variants the design gives."""
        d = self.spec.design
        if d == "grid":
            return math.prod(len(p.values or ()) for p in self.parameters)
        n = self.spec.samples or 0
        if d == "saltelli":
            return n * (len(self.parameters) + 2)
        if d == "morris":
            return n * (len(self.parameters) + 1)
        return n

    def unit_cube(self) -> np.ndarray:
        """The design's points in the unit cube, (variants, parameters) (not for a grid)."""
        d, n, k = self.spec.design, self.spec.samples or 0, len(self.parameters)
        if d == "random":
            return np.random.default_rng(self.spec.seed).random((n, k))
        from scipy.stats import qmc

        if d == "lhs":
            return qmc.LatinHypercube(d=k, seed=self.spec.seed).random(n)
        if d == "sobol":
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # a count that is not a power of two loses balance only
                return qmc.Sobol(d=k, scramble=True, seed=self.spec.seed).random(n)
        problem = self.salib_problem()
        if d == "saltelli":
            from SALib.sample import sobol

            return np.asarray(sobol.sample(problem, n, calc_second_order=False, seed=self.spec.seed))
        from SALib.sample import morris

        return np.asarray(morris.sample(problem, n, num_levels=4, seed=self.spec.seed))

    def salib_problem(self) -> dict[str, Any]:
        """The SALib problem over the unit cube (values are mapped by each parameter's ppf)."""
        return {"num_vars": len(self.parameters), "names": self.names, "bounds": [[0.0, 1.0]] * len(self.parameters)}

    def variants(self) -> list[tuple[Any, ...]]:
        """Every variant's parameter values (in each parameter's unit), in design order."""
        return list(self.iter_variants())

    def iter_variants(self, chunk: int = 10_000) -> Iterator[tuple[Any, ...]]:
        """``variants`` one at a time: a grid is never held in memory, a sampled design's values are
        made ``chunk`` points at a time from its unit-cube points (bounded by ``MAX_DESIGN_BYTES``)."""
        if self.spec.design == "grid":
            yield from itertools.product(*(p.values or () for p in self.parameters))
            return
        u = self.unit_cube()
        for k in range(0, u.shape[0], chunk):
            part = u[k:k + chunk]
            cols = [p.ppf(part[:, j]) for j, p in enumerate(self.parameters)]
            for i in range(part.shape[0]):
                yield tuple(_plain(c[i]) for c in cols)

    def axis_dict(self, values: tuple[Any, ...]) -> dict[str, Any]:
        """The axis mapping of one variant (SI numbers at the parameters' paths)."""
        return variant_mapping(self.base, self.parameters, values)


def variant_mapping(base: dict[str, Any], parameters: tuple[Parameter, ...], values: tuple[Any, ...]) -> dict[str, Any]:
    """The axis mapping of one variant: ``base`` with each parameter's value, in SI, at its path."""
    data: Any = base
    for p, v in zip(parameters, values, strict=True):
        data = set_path(data, p.tokens, p.to_si(v), f"parameters.{p.path}")
    out: dict[str, Any] = data
    return out


def _count(n: float) -> str:
    """A count for a message: exact with thousands separators, or its order of magnitude."""
    if not math.isfinite(n):
        return "infinitely many"
    return f"{int(n):,}" if n < 1e15 else f"about {n:.3g}"


def _plain(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


def parse_study(text: str, source: str = "<text>", base_dir: Path | None = None, yes: bool = False) -> Study:
    """Validate a study file's text (and its base axis file) into a Study; nothing is sized yet."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.axis.yaml_text import parse_yaml, read_yaml_text

    data = parse_yaml(text, source)
    if not isinstance(data, dict):
        raise InputError("", "a study file must be a mapping (study, base, parameters, design, ...)",
                         type(data).__name__)
    try:
        spec = StudySpec.model_validate(data)
    except ValidationError as exc:
        raise input_error_from_pydantic(exc, data) from None
    folder = base_dir if base_dir is not None else (Path(source).parent if not source.startswith("<") else Path())
    base_path = (folder / spec.base) if not Path(spec.base).is_absolute() else Path(spec.base)
    try:
        base_text, base = read_yaml_text(base_path, "base")
    except InputError as exc:
        raise InputError("base", exc.rule, str(base_path)) from None
    if not isinstance(base, dict):
        raise InputError("base", "is not an axis file (a mapping)", str(base_path))
    try:
        parse_axis(base)
    except InputError as exc:
        raise exc.at(f"base({spec.base})") from None
    if not spec.parameters:
        raise InputError("parameters", "is empty: name at least one parameter to vary", has_value=False)
    optimizing = spec.optimize is not None
    params = tuple(build_parameter(path, raw, spec.design, optimizing) for path, raw in spec.parameters.items())
    if spec.design != "grid" and not optimizing and spec.samples is None:
        raise InputError("samples", f"is required for the {spec.design} design", has_value=False)
    if optimizing:
        for p in params:
            if p.values is None and (p.low is None or p.high is None):
                raise InputError(f"parameters.{p.path}", "an optimisation needs a range or a list", has_value=False)
    if "record" not in spec.model_fields_set and ("requirements" in base or any(
            p.path.startswith("requirements.") or p.path == "requirements" for p in params)):
        # requirements swept or stated: their figures are recorded with the default groups
        spec = spec.model_copy(update={"record": [*spec.record, DYNAMICS_GROUP]})
    study = Study(spec=spec, text=text, source=source, base=base, base_text=base_text,
                  parameters=params)
    _check_paths(study)
    if not optimizing:
        n = study.n_variants()
        if n == 0:
            raise InputError("parameters", "the design gives no variant", has_value=False)
        if n > MAX_STUDY_VARIANTS:
            raise InputError("design", f"gives {_count(n)} variants; a study has at most {MAX_STUDY_VARIANTS:,}, "
                             "even with --yes: narrow the parameters", spec.design)
        if n > MAX_VARIANTS and not yes:
            raise InputError("design", f"gives {n:,} variants, more than {MAX_VARIANTS:,}: confirm with --yes "
                             "(yes=True) or narrow the parameters", spec.design)
        _check_design_memory(study)
    _check_record(study)
    return study


def _check_design_memory(study: Study) -> None:
    """A sampled design's points are drawn at once: refuse, before drawing, a design whose points
    take more than ``MAX_DESIGN_BYTES``, saying how many samples fit."""
    if study.spec.design == "grid":
        return
    k = max(len(study.parameters), 1)
    per_sample = study.n_variants() // max(study.spec.samples or 1, 1) * k * 8 * DESIGN_BYTES_FACTOR
    need = (study.spec.samples or 0) * per_sample
    if need > MAX_DESIGN_BYTES:
        fits = MAX_DESIGN_BYTES // per_sample
        raise InputError("samples", f"the {study.spec.design} design's points would take {need / 2**30:,.1f} GiB "
                         f"(at most {MAX_DESIGN_BYTES / 2**30:g} GiB): at most {fits:,} samples fit with "
                         f"{len(study.parameters)} parameter(s)", study.spec.samples)


def _check_paths(study: Study) -> None:
    """Every parameter path must name a key of the axis file and accept the parameter's unit.

    The base with each parameter's extreme values written with their unit (``"40.0 kg"``) is parsed
    as an axis file: a key the axis file does not know, a position that does not exist or a unit of
    the wrong dimension is an InputError, renamed to the parameter."""
    from drivetrain.axis.model import parse_axis

    for p in study.parameters:
        field = f"parameters.{p.path}"
        found, old = get_path(study.base, p.tokens)
        probes: list[Any] = list(p.values[:1] + p.values[-1:]) if p.values else [
            x for x in (p.low, p.high, p.mean) if x is not None][:2]
        for v in probes:
            data = set_path(study.base, p.tokens, p.as_quantity(v), field)
            try:
                parse_axis(data)
            except InputError as exc:
                where = "" if found else " (the base axis file has no such key)"
                if exc.field == p.path:  # the parameter's own field: its rule and value
                    raise InputError(field, exc.rule + where, exc.value, has_value=exc.has_value) from None
                raise InputError(field, f"{exc}{where}", has_value=False) from None
        if found and isinstance(old, str) and p.unit:
            _same_dimension(old, p.unit, field)


def _same_dimension(base_value: str, unit: str, field: str) -> None:
    from drivetrain.units import _NUMBER_UNIT, _normalise, registry

    m = _NUMBER_UNIT.fullmatch(base_value)
    if m is not None:
        old, new = _cached_unit(m.group(2)), _cached_unit(unit)
        if old is not None and new is not None and old[0] == new[0]:
            return  # both remembered as the same quantity
    ureg = registry()
    try:
        q: Any = ureg.Quantity(_normalise(base_value))
        u = ureg.Quantity(1.0, _normalise(unit))
    except Exception:
        return
    if q.dimensionality != u.dimensionality:
        raise InputError(f"{field}.unit", f"has another dimension than the base axis file's {base_value!r}", unit)


def _check_record(study: Study) -> None:
    for k, name in enumerate(study.spec.record):
        if name in GROUPS:
            continue
        try:
            parse_path(name, f"record[{k}]")
        except InputError:
            raise InputError(f"record[{k}]", f"is neither one of {', '.join(GROUPS)} nor a dotted key of "
                             "the size result", name) from None


def load_study(path: str | Path, yes: bool = False) -> Study:
    """Read and validate a study file."""

    from drivetrain.axis.yaml_text import MAX_FILE_BYTES
    from drivetrain.userfile import read_text

    text = read_text(path, "file", MAX_FILE_BYTES, "study file")
    p = Path(path)
    return parse_study(text, str(p), p.parent, yes=yes)


__all__ = ["DESIGNS", "DYNAMICS_GROUP", "GROUPS", "MAX_PARAMETER_VALUES", "MAX_SEED", "MAX_STUDY_VARIANTS",
           "MAX_VARIANTS", "OBJECTIVES", "RECORD_GROUPS", "VERSION", "Parameter", "Study", "StudySpec",
           "build_parameter", "load_study", "parse_study"]
