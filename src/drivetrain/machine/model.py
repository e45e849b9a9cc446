"""The machine file: several axes, their timing in one machine cycle, the supply and the DC-bus groups.

A machine file (YAML, ``version: 1``) names its axes (inline axis files or ``include:`` of axis
files, relative to the machine file), a common cycle time, each axis's start (a fixed ``offset``,
``offset: free`` for an axis whose phase is not fixed, or ``after: OTHER`` to start when another
axis's last move ends), gantries (``motors: 2`` with a ``split``), the supply and the DC-bus
groups. docs/machine.md describes every key. Every error names its field (``axes[2].after``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from drivetrain.axis.electrical import check_bus_limits, nominal_bus_voltage
from drivetrain.axis.model import Axis, parse_axis
from drivetrain.axis.yaml_text import read_yaml
from drivetrain.errors import InputError, format_value, listing
from drivetrain.physics.motor_electrical import dc_bus_voltage
from drivetrain.units import parse

MACHINE_KEYS = {"version", "machine", "cycle_time", "supply", "axes", "buses"}
AXIS_KEYS = {"name", "include", "axis", "offset", "after", "delay", "motors", "split", "stiffness"}
SUPPLY_KEYS = {"voltage", "phases", "power_factor"}
BUS_KEYS = {"name", "axes", "supply_module", "resistors", "capacitance", "bus_max_voltage", "absorbable_energy",
            "regen_on_voltage", "min_resistance"}
MODULE_KEYS = {"id", "vendor", "continuous_power", "peak_power"}
RESISTOR_KEYS = {"id", "vendor", "resistance", "continuous_power", "peak_power", "quantity"}
MAX_AXES = 64
MAX_MOTORS = 8


@dataclass(frozen=True)
class MachineAxis:
    """One axis of the machine (SI)."""

    name: str
    axis: Axis
    offset: float | None
    """fixed start in the machine cycle [s]; None when ``free`` or ``after`` another axis"""
    after: str | None
    delay: float
    shares: tuple[float, ...]
    """load share of each motor (sum 1); one motor -> (1.0,)"""
    split_basis: str
    """"single", "stated" or "stiffness\""""
    source: str
    """the included file, or "inline\""""

    @property
    def motors(self) -> int:
        return len(self.shares)

    @property
    def free(self) -> bool:
        return self.offset is None and self.after is None


@dataclass(frozen=True)
class Resistor:
    """A braking resistor on a DC bus (SI; None where not given)."""

    id: str
    vendor: str | None
    resistance: float | None
    continuous_power: float | None
    peak_power: float | None
    quantity: int = 1


@dataclass(frozen=True)
class SupplyModule:
    """A common supply (infeed) module of a DC bus (SI)."""

    id: str
    vendor: str | None
    continuous_power: float | None
    peak_power: float | None


@dataclass(frozen=True)
class BusGroup:
    """Drives sharing one DC bus."""

    name: str
    axes: tuple[str, ...]
    supply_module: SupplyModule | None = None
    resistors: tuple[Resistor, ...] = ()
    capacitance: float | None = None
    """[F] extra bus capacitance of the supply module, added to the drives' own"""
    bus_max_voltage: float | None = None
    absorbable_energy: float | None = None
    """[J] the supply module's published absorbable energy, added to the drives' own"""
    regen_on_voltage: float | None = None
    min_resistance: float | None = None
    declared: bool = True
    """False for an axis on its own bus because no group names it"""


@dataclass(frozen=True)
class Supply:
    """The mains supply: line-to-line rms voltage [V], phases (1 or 3), power factor [-]."""

    voltage: float
    phases: int = 3
    power_factor: float = 1.0
    power_factor_given: bool = False


@dataclass(frozen=True)
class Machine:
    """A validated machine file in SI."""

    name: str
    cycle_time: float
    supply: Supply
    axes: tuple[MachineAxis, ...]
    buses: tuple[BusGroup, ...]
    path: str | None = None
    raw: dict[str, Any] = field(default_factory=dict, compare=False)

    def axis(self, name: str) -> MachineAxis:
        return next(a for a in self.axes if a.name == name)


def _unknown(data: dict[str, Any], allowed: set[str], where: str) -> None:
    for key in data:
        if key not in allowed:
            raise InputError(f"{where}{key}" if not where else f"{where}.{key}",
                             f"is not a known key (known: {', '.join(sorted(allowed))})", has_value=False)


def _mapping(value: Any, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise InputError(where, "must be a mapping of keys", type(value).__name__)
    return value


def _opt(data: dict[str, Any], key: str, quantity: str, where: str, *, positive: bool = True) -> float | None:
    if data.get(key) is None:
        return None
    v = parse(data[key], quantity, f"{where}.{key}")
    if positive and not v > 0:
        raise InputError(f"{where}.{key}", "must be > 0", data[key])
    return v


def load_machine(path: str | Path) -> Machine:
    """Read and validate a machine file; ``include:`` paths are relative to it."""
    p = Path(path)
    return parse_machine(read_yaml(p), base=p.parent, path=str(p))


def parse_machine(data: Any, base: str | Path | None = None, path: str | None = None, *,
                  allow_include: bool = True, max_axes: int = MAX_AXES) -> Machine:
    """Validate a machine-file mapping (includes read relative to ``base``) into a ``Machine``.

    ``allow_include=False`` refuses ``include:`` (a server must not read files named by a request);
    ``max_axes`` caps the number of axes."""
    if not isinstance(data, dict):
        raise InputError("", "a machine file must be a mapping of keys (version, machine, cycle_time, axes, ...)",
                         type(data).__name__)
    _unknown(data, MACHINE_KEYS, "")
    if data.get("version") != 1:
        raise InputError("version", "must be 1 (the machine-file format version)", data.get("version"),
                         has_value="version" in data)
    name = str(data.get("machine", "machine"))
    if "cycle_time" not in data:
        raise InputError("cycle_time", "is required: the machine's cycle time", has_value=False)
    cycle_time = parse(data["cycle_time"], "time", "cycle_time", allow_zero=False)
    if not cycle_time > 0:
        raise InputError("cycle_time", "must be > 0", data["cycle_time"])
    supply = _supply(data.get("supply"))
    raw_axes = data.get("axes")
    if not isinstance(raw_axes, list) or not raw_axes:
        raise InputError("axes", "must be a non-empty list of axes", raw_axes, has_value=raw_axes is not None)
    if len(raw_axes) > max_axes:
        raise InputError("axes", f"has more than {max_axes} axes", len(raw_axes))
    root = Path(base) if base is not None else Path.cwd()
    axes = [_axis(a, k, root, allow_include) for k, a in enumerate(raw_axes)]
    names = [a.name for a in axes]
    for k, n in enumerate(names):
        if n in names[:k]:
            raise InputError(f"axes[{k}].name", "must be unique in the machine", n)
    for k, a in enumerate(axes):
        if a.after is not None and a.after not in names:
            raise InputError(f"axes[{k}].after", f"names no axis of this machine (axes: {listing(names)})", a.after)
        if a.after == a.name:
            raise InputError(f"axes[{k}].after", "an axis cannot start after itself", a.after)
        period = a.axis.cycle().period
        if period > cycle_time * (1 + 1e-9):
            raise InputError("cycle_time", f"is shorter than the own cycle of axis {a.name!r} ({period:.6g} s)",
                             data["cycle_time"])
    _check_after_cycles(axes)
    buses = _buses(data.get("buses"), names)
    _check_bus_voltages(axes, buses, supply)
    return Machine(name=name, cycle_time=cycle_time, supply=supply, axes=tuple(axes), buses=buses, path=path, raw=data)


def _check_bus_voltages(axes: list[MachineAxis], buses: tuple[BusGroup, ...], supply: Supply) -> None:
    """Capacitor maxima and chopper switch-on voltages at least the nominal bus: each axis's drive
    against its own stated supply (else the machine's), each bus group against the machine's."""
    mains_bus = float(dc_bus_voltage(supply.voltage))
    for k, a in enumerate(axes):
        d = a.axis.drive
        if d is None:
            continue
        where = f"axes[{k}].axis.drive" if a.source == "inline" else f"axes[{k}].include({a.source}).drive"
        own = nominal_bus_voltage(d, a.axis.electrical, a.axis.spec.motor)
        check_bus_limits(mains_bus if own is None else own, d.bus_max_voltage, d.regen_on_voltage, where)
    for g, grp in enumerate(buses):
        if grp.declared:
            check_bus_limits(mains_bus, grp.bus_max_voltage, grp.regen_on_voltage, f"buses[{g}]")


def _supply(raw: Any) -> Supply:
    if raw is None:
        raise InputError("supply", "is required: the mains voltage (supply: {voltage: 400 V, phases: 3})",
                         has_value=False)
    d = _mapping(raw, "supply")
    _unknown(d, SUPPLY_KEYS, "supply")
    if "voltage" not in d:
        raise InputError("supply.voltage", "is required (line-to-line rms, e.g. 400 V)", has_value=False)
    u = parse(d["voltage"], "voltage", "supply.voltage")
    if not 1.0 <= u <= 1000.0:
        raise InputError("supply.voltage", "must be a mains voltage between 1 V and 1000 V (line-to-line rms)",
                         d["voltage"])
    phases = d.get("phases", 3)
    if phases not in (1, 3) or isinstance(phases, bool):
        raise InputError("supply.phases", "must be 1 or 3", phases)
    pf_given = "power_factor" in d
    pf = float(d.get("power_factor", 1.0)) if isinstance(d.get("power_factor", 1.0), (int, float)) else math.nan
    if not 0.0 < pf <= 1.0:
        raise InputError("supply.power_factor", "must be a number in (0, 1]", d.get("power_factor"))
    return Supply(voltage=u, phases=int(phases), power_factor=pf, power_factor_given=pf_given)


def _axis(raw: Any, k: int, root: Path, allow_include: bool = True) -> MachineAxis:
    where = f"axes[{k}]"
    d = _mapping(raw, where)
    _unknown(d, AXIS_KEYS, where)
    if "include" in d and not allow_include:
        raise InputError(f"{where}.include", "is not available here: give the axis inline (axis: {...})",
                         d["include"])
    if ("include" in d) == ("axis" in d):
        raise InputError(where, "needs exactly one of include: (an axis file) or axis: (the axis inline)",
                         has_value=False)
    if "include" in d:
        inc = d["include"]
        if not isinstance(inc, str) or not inc:
            raise InputError(f"{where}.include", "must be the path of an axis file", inc)
        if "\x00" in inc:
            raise InputError(f"{where}.include", "contains a NUL byte, which no file name can hold", inc)
        target = Path(inc) if Path(inc).is_absolute() else root / inc
        try:
            axis_data = read_yaml(target, f"{where}.include")  # a regular file within the axis-file bounds
            axis = parse_axis(axis_data)
        except InputError as exc:
            if exc.field == f"{where}.include":  # the file itself (no file, a device, too large, bad YAML)
                raise
            raise exc.at(f"{where}.include({inc})") from None
        source = inc
    else:
        try:
            axis = parse_axis(d["axis"])
        except InputError as exc:
            raise exc.at(f"{where}.axis") from None
        source = "inline"
    if not axis.spec.profile:
        raise InputError(f"{where}.axis.profile" if source == "inline" else f"{where}.include",
                         "the axis needs a motion profile to join a machine cycle", has_value=False)
    name = str(d.get("name", axis.name))
    after = d.get("after")
    if after is not None and not isinstance(after, str):
        raise InputError(f"{where}.after", "must be the name of another axis", after)
    offset_raw = d.get("offset", None if after is not None else 0.0)
    if after is not None and "offset" in d:
        raise InputError(f"{where}.offset", "give either offset or after, not both", d["offset"])
    if offset_raw == "free":
        offset: float | None = None
    elif offset_raw is None:
        offset = None
    else:
        offset = parse(offset_raw, "time", f"{where}.offset")
        if offset < 0:
            raise InputError(f"{where}.offset", "must be >= 0 (or free)", offset_raw)
    delay = 0.0
    if "delay" in d:
        if after is None:
            raise InputError(f"{where}.delay", "applies only with after:", d["delay"])
        delay = parse(d["delay"], "time", f"{where}.delay")
        if delay < 0:
            raise InputError(f"{where}.delay", "must be >= 0", d["delay"])
    shares, basis = _shares(d, where)
    return MachineAxis(name=name, axis=axis, offset=offset, after=after, delay=delay, shares=shares,
                       split_basis=basis, source=source)


def _shares(d: dict[str, Any], where: str) -> tuple[tuple[float, ...], str]:
    """Load share of each motor of a gantry: a stated split, or by stiffness (share_i = k_i / sum k)."""
    n = d.get("motors", 1)
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_MOTORS:
        raise InputError(f"{where}.motors", f"must be an integer from 1 to {MAX_MOTORS}", n)
    split = d.get("split")
    if n == 1:
        if split is not None or "stiffness" in d:
            raise InputError(f"{where}.split", "applies only to an axis with motors: 2 or more", split)
        return (1.0,), "single"
    if split is None:
        split = [1.0 / n] * n
    if split == "stiffness":
        ks = d.get("stiffness")
        if not isinstance(ks, list) or len(ks) != n:
            raise InputError(f"{where}.stiffness", f"split: stiffness needs a list of {n} stiffnesses", ks)
        values = [parse(k, "linear_stiffness", f"{where}.stiffness[{i}]") if not _is_torsional(k) else
                  parse(k, "torsional_stiffness", f"{where}.stiffness[{i}]") for i, k in enumerate(ks)]
        if any(not v > 0 for v in values):
            raise InputError(f"{where}.stiffness", "every stiffness must be > 0", ks)
        total = sum(values)
        return tuple(v / total for v in values), "stiffness"
    if not isinstance(split, list) or len(split) != n:
        raise InputError(f"{where}.split", f"must be a list of {n} shares (e.g. [50 %, 50 %]) or 'stiffness'", split)
    shares = []
    for i, s in enumerate(split):
        v = _share(s, f"{where}.split[{i}]")
        shares.append(v)
    total = sum(shares)
    if abs(total - 1.0) > 1e-6:
        raise InputError(f"{where}.split", "the shares must add up to 100 %", split)
    return tuple(shares), "stated" if d.get("split") is not None else "equal"


def _is_torsional(k: Any) -> bool:
    return isinstance(k, str) and "rad" in k


def _share(s: Any, where: str) -> float:
    if isinstance(s, str) and s.strip().endswith("%"):
        try:
            v = float(s.strip()[:-1]) / 100.0
        except ValueError:
            raise InputError(where, "must be a share like 50 % or 0.5", s) from None
    elif isinstance(s, (int, float)) and not isinstance(s, bool):
        v = float(s)
    else:
        raise InputError(where, "must be a share like 50 % or 0.5", s)
    if not 0.0 < v < 1.0:
        raise InputError(where, "must be between 0 and 100 %", s)
    return v


def _check_after_cycles(axes: list[MachineAxis]) -> None:
    by = {a.name: a for a in axes}
    for k, a in enumerate(axes):
        seen = {a.name}
        cur = a
        while cur.after is not None:
            cur = by[cur.after]
            if cur.name in seen:
                raise InputError(f"axes[{k}].after", "the after: chain runs in a circle", a.after)
            seen.add(cur.name)


def _buses(raw: Any, names: list[str]) -> tuple[BusGroup, ...]:
    groups: list[BusGroup] = []
    placed: dict[str, str] = {}
    if raw is not None and not isinstance(raw, list):
        raise InputError("buses", "must be a list of DC-bus groups", type(raw).__name__)
    for g, item in enumerate(raw or []):
        where = f"buses[{g}]"
        d = _mapping(item, where)
        _unknown(d, BUS_KEYS, where)
        members = d.get("axes")
        if not isinstance(members, list) or not members:
            raise InputError(f"{where}.axes", "must list the axes sharing this bus", members)
        for i, m in enumerate(members):
            if not isinstance(m, str) or m not in names:
                raise InputError(f"{where}.axes[{i}]", f"names no axis of this machine (axes: {listing(names)})", m)
            if m in members[:i]:
                raise InputError(f"{where}.axes[{i}]", f"lists this axis a second time (first at {where}.axes"
                                 f"[{members.index(m)}]): an axis is on a bus once", m)
            if m in placed:
                raise InputError(f"{where}.axes[{i}]", f"is already on bus {format_value(placed[m])!r}", m)
        gname = str(d.get("name", f"bus {g + 1}"))
        for m in members:
            placed[m] = gname
        module = None
        if d.get("supply_module") is not None:
            md = _mapping(d["supply_module"], f"{where}.supply_module")
            _unknown(md, MODULE_KEYS, f"{where}.supply_module")
            module = SupplyModule(id=str(md.get("id", "supply module")), vendor=md.get("vendor"),
                                  continuous_power=_opt(md, "continuous_power", "power", f"{where}.supply_module"),
                                  peak_power=_opt(md, "peak_power", "power", f"{where}.supply_module"))
        resistors = []
        rl = d.get("resistors", [])
        if not isinstance(rl, list):
            raise InputError(f"{where}.resistors", "must be a list of braking resistors", rl)
        for r, rr in enumerate(rl):
            rw = f"{where}.resistors[{r}]"
            rd = _mapping(rr, rw)
            _unknown(rd, RESISTOR_KEYS, rw)
            q = rd.get("quantity", 1)
            if isinstance(q, bool) or not isinstance(q, int) or q < 1:
                raise InputError(f"{rw}.quantity", "must be an integer >= 1", q)
            resistors.append(Resistor(id=str(rd.get("id", f"resistor {r + 1}")), vendor=rd.get("vendor"),
                                      resistance=_opt(rd, "resistance", "resistance", rw),
                                      continuous_power=_opt(rd, "continuous_power", "power", rw),
                                      peak_power=_opt(rd, "peak_power", "power", rw), quantity=q))
        umax = _opt(d, "bus_max_voltage", "voltage", where)
        groups.append(BusGroup(
            name=gname, axes=tuple(members), supply_module=module, resistors=tuple(resistors),
            capacitance=_opt(d, "capacitance", "capacitance", where), bus_max_voltage=umax,
            absorbable_energy=_opt(d, "absorbable_energy", "energy", where),
            regen_on_voltage=_opt(d, "regen_on_voltage", "voltage", where),
            min_resistance=_opt(d, "min_resistance", "resistance", where)))
    for n in names:
        if n not in placed:
            groups.append(BusGroup(name=n, axes=(n,), declared=False))
    return tuple(groups)
