r"""The N-mass torsional chain: inertias joined by springs, everything at the motor shaft.

    J_0 --(K_01, B_01, backlash, gear efficiency)-- J_1 --(K_12, ...)-- J_2 ... J_{n-1}

Inertia 0 is the motor (it receives the motor torque and carries the encoder), the last one is
the load (it receives the load torque). Each inertia may also have viscous damping to ground
[N m s/rad] and friction (``Friction``). Each spring has stiffness [N m/rad], viscous damping
across it [N m s/rad], total backlash [rad] and, optionally, a lossy gear at its load end
(forward and back efficiency, Modelica ``LossyGear`` semantics; see ``simulate``).

Two ways in:
- ``chain_from_spec``: the axis file's explicit form
  ``dynamics: {chain: [{inertia: ...}, {stiffness: ..., damping: ..., backlash: ...}, {inertia: ...}]}``
- ``model_from_stages``: from the motor inertia, the drive-train ``Stage`` list and the load,
  splitting at every compliant stage and reflecting through the ratios (K/i^2, B/i^2, J/i^2,
  backlash * i; docs/conventions.md, Ratios and reflection).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.dynamics.friction import Friction, friction_from_spec
from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]

_INERTIA_KEYS = ("inertia", "damping", "friction", "name")
_SPRING_KEYS = ("stiffness", "damping", "backlash", "efficiency", "back_efficiency", "name")


def _spring_table(table: Any, springs: int, path: str) -> tuple[FloatArray, FloatArray]:
    """Checked (angles, stiffness) table of the last spring (``Chain.spring_table``)."""
    angle = np.array(table[0], dtype=float).reshape(-1)
    k = np.array(table[1], dtype=float).reshape(-1)
    if springs < 1:
        raise InputError(f"{path}.spring_table", "needs a chain with at least one spring", springs)
    if angle.size < 2 or k.size != angle.size:
        raise InputError(f"{path}.spring_table", "needs angles and stiffnesses of the same length >= 2",
                         f"{angle.size} and {k.size}")
    if not (np.all(np.isfinite(angle)) and np.all(np.diff(angle) > 0.0)):
        raise InputError(f"{path}.spring_table", "angles must be finite and strictly increasing", has_value=False)
    if not (np.all(np.isfinite(k)) and np.all(k > 0.0)):
        raise InputError(f"{path}.spring_table", "stiffnesses must be finite and > 0 N*m/rad", has_value=False)
    return angle, k


@dataclass(frozen=True)
class Chain:
    """An N-mass torsional chain reflected to the motor shaft (SI).

    Attributes:
        inertia: (n,) inertias from the motor outward [kg m^2], each > 0.
        stiffness: (n-1,) spring stiffnesses [N m/rad], each > 0.
        damping: (n-1,) viscous damping across each spring [N m s/rad], >= 0.
        backlash: (n-1,) total play of each spring [rad], >= 0.
        ground_damping: (n,) viscous damping of each inertia to ground [N m s/rad], >= 0.
        efficiency: (n-1,) forward efficiency of a gear at the spring's load end, (0, 1].
        back_efficiency: (n-1,) efficiency when the load drives back, [-1, 1]; <= 0 self-locks.
        friction: (n,) ``Friction`` or None per inertia.
        names: (n,) labels of the inertias.
        ratio: motor angle per unit of load motion [rad/rad or rad/m]: divide a load angle at the
            motor shaft by it to get the load's own position.
        path: where the chain sits in the axis file, for error messages.
        spring_table: None, or (angles, stiffness): the LAST spring's stiffness [N m/rad] as a
            function of the last inertia's angle [rad at the motor shaft], angles strictly
            increasing (a mechanism spring that changes with the load position: a belt's free
            lengths, a screw shaft's length to the nut). ``simulate`` interpolates it linearly
            along the move and holds the end values beyond; ``stiffness[-1]`` is the value the
            linear analyses use (set it to the table's value at the start).
    """

    inertia: FloatArray
    stiffness: FloatArray
    damping: FloatArray = field(default_factory=lambda: np.zeros(0))
    backlash: FloatArray = field(default_factory=lambda: np.zeros(0))
    ground_damping: FloatArray = field(default_factory=lambda: np.zeros(0))
    efficiency: FloatArray = field(default_factory=lambda: np.zeros(0))
    back_efficiency: FloatArray = field(default_factory=lambda: np.zeros(0))
    friction: tuple[Friction | None, ...] = ()
    names: tuple[str, ...] = ()
    ratio: float = 1.0
    path: str = "dynamics.chain"
    spring_table: tuple[FloatArray, FloatArray] | None = None

    def __post_init__(self) -> None:
        j = np.array(self.inertia, dtype=float).reshape(-1)
        n = j.size
        m = max(n - 1, 0)

        def fill(name: str, size: int, default: float) -> FloatArray:
            v = getattr(self, name)
            a = np.full(size, default) if v is None or np.size(v) == 0 else np.array(v, dtype=float).reshape(-1)
            if a.size != size:
                raise InputError(f"{self.path}.{name}", f"must have {size} entries", a.size)
            return a

        object.__setattr__(self, "inertia", j)
        object.__setattr__(self, "stiffness", fill("stiffness", m, math.nan))
        object.__setattr__(self, "damping", fill("damping", m, 0.0))
        object.__setattr__(self, "backlash", fill("backlash", m, 0.0))
        object.__setattr__(self, "ground_damping", fill("ground_damping", n, 0.0))
        object.__setattr__(self, "efficiency", fill("efficiency", m, 1.0))
        object.__setattr__(self, "back_efficiency", fill("back_efficiency", m, 1.0))
        fr = tuple(self.friction) if self.friction else (None,) * n
        if len(fr) != n:
            raise InputError(f"{self.path}.friction", f"must have {n} entries", len(fr))
        object.__setattr__(self, "friction", fr)
        names = tuple(self.names) if self.names else tuple(_default_names(n))
        object.__setattr__(self, "names", names)
        if self.spring_table is not None:
            object.__setattr__(self, "spring_table", _spring_table(self.spring_table, m, self.path))
        self._validate()

    def _validate(self) -> None:
        f = self.path
        if self.inertia.size == 0:
            raise InputError(f, "needs at least one inertia", [])
        for k, v in enumerate(self.inertia):
            _check(v, f"{f}[{2 * k}].inertia", "must be > 0 kg*m^2", strict=True)
            _check(self.ground_damping[k], f"{f}[{2 * k}].damping", "must be >= 0 N*m*s/rad", strict=False)
        for k in range(self.stiffness.size):
            p = f"{f}[{2 * k + 1}]"
            _check(self.stiffness[k], f"{p}.stiffness", "must be > 0 N*m/rad", strict=True)
            _check(self.damping[k], f"{p}.damping", "must be >= 0 N*m*s/rad", strict=False)
            _check(self.backlash[k], f"{p}.backlash", "must be >= 0 rad", strict=False)
            e, eb = self.efficiency[k], self.back_efficiency[k]
            if not (math.isfinite(e) and 0.0 < e <= 1.0):
                raise InputError(f"{p}.efficiency", "must be in (0, 1]", e)
            if not (math.isfinite(eb) and -1.0 <= eb <= 1.0):
                raise InputError(f"{p}.back_efficiency", "must be in [-1, 1] (<= 0: self-locking)", eb)
        if not (math.isfinite(self.ratio) and self.ratio != 0.0):
            raise InputError(f"{f}.ratio", "must be a finite, non-zero number", self.ratio)

    @property
    def n(self) -> int:
        """Number of inertias."""
        return int(self.inertia.size)

    @property
    def total_inertia(self) -> float:
        """Rigid-body inertia at the motor shaft [kg m^2]: the sum of all inertias."""
        return float(self.inertia.sum())

    @property
    def has_nonlinearity(self) -> bool:
        """True when backlash, lossy gears or friction make the chain nonlinear."""
        return bool(
            np.any(self.backlash > 0.0)
            or np.any(self.efficiency < 1.0)
            or np.any(self.back_efficiency < 1.0)
            or any(fr is not None for fr in self.friction)
        )

    def inertia_matrix(self) -> FloatArray:
        """Diagonal inertia matrix M [kg m^2]."""
        return np.diag(self.inertia)

    def stiffness_matrix(self) -> FloatArray:
        """Tridiagonal stiffness matrix K [N m/rad] (backlash ignored: linear model in contact)."""
        return _tridiag(self.stiffness, self.n)

    def damping_matrix(self) -> FloatArray:
        """Damping matrix C [N m s/rad]: spring dampers plus damping to ground plus viscous friction."""
        c = _tridiag(self.damping, self.n)
        c += np.diag(self.ground_damping)
        for k, fr in enumerate(self.friction):
            if fr is not None:
                c[k, k] += fr.viscous
        return c

    def with_(self, **changes: Any) -> Chain:
        """A copy with some attributes changed (e.g. ``chain.with_(stiffness=[800.0])``)."""
        values = {name: getattr(self, name) for name in self.__dataclass_fields__}
        values.update(changes)
        return Chain(**values)

    def to_spec(self) -> list[dict[str, Any]]:
        """The axis-file form of this chain (SI numbers), the inverse of ``chain_from_spec``."""
        out: list[dict[str, Any]] = []
        for k in range(self.n):
            entry: dict[str, Any] = {"inertia": float(self.inertia[k]), "name": self.names[k]}
            if self.ground_damping[k]:
                entry["damping"] = float(self.ground_damping[k])
            fr = self.friction[k]
            if fr is not None:
                entry["friction"] = {"coulomb": fr.coulomb, "static": fr.breakaway, "viscous": fr.viscous,
                                     "stribeck_speed": fr.stribeck_speed, "method": fr.method}
            out.append(entry)
            if k < self.n - 1:
                spring: dict[str, Any] = {"stiffness": float(self.stiffness[k])}
                for name in ("damping", "backlash"):
                    v = float(getattr(self, name)[k])
                    if v:
                        spring[name] = v
                if self.efficiency[k] < 1.0 or self.back_efficiency[k] < 1.0:
                    spring["efficiency"] = float(self.efficiency[k])
                    spring["back_efficiency"] = float(self.back_efficiency[k])
                out.append(spring)
        return out


def _default_names(n: int) -> list[str]:
    if n == 1:
        return ["motor"]
    if n == 2:
        return ["motor", "load"]
    return ["motor"] + [f"mass{k}" for k in range(1, n - 1)] + ["load"]


def _check(value: float, where: str, rule: str, *, strict: bool) -> None:
    v = float(value)
    if not math.isfinite(v) or (v <= 0.0 if strict else v < 0.0):
        raise InputError(where, rule, value)


def _tridiag(k: FloatArray, n: int) -> FloatArray:
    m = np.zeros((n, n))
    for e, kk in enumerate(k):
        m[e, e] += kk
        m[e + 1, e + 1] += kk
        m[e, e + 1] -= kk
        m[e + 1, e] -= kk
    return m


def chain_from_spec(chain: Sequence[dict[str, Any]], field: str = "dynamics.chain") -> Chain:
    """Build a ``Chain`` from the axis-file list of alternating inertia and spring entries.

    ``[{inertia: 0.5 kg*m^2}, {stiffness: 60e3 N*m/rad, damping: 2, backlash: 1 arcmin}, {inertia: 0.4}]``

    Inertia entries: ``inertia`` (required, > 0), ``damping`` (to ground), ``friction``
    (``{coulomb, static, viscous, stribeck_speed, method}``), ``name``. Spring entries:
    ``stiffness`` (required, > 0), ``damping``, ``backlash``, ``efficiency``, ``back_efficiency``,
    ``name``. Values take units ("60e3 N*m/rad", "1 arcmin"); a bare number is SI. Every error
    names its entry, e.g. ``dynamics.chain[1].stiffness: must be > 0 N*m/rad, got -5``.
    """
    from drivetrain.units import parse

    if not isinstance(chain, (list, tuple)):
        raise InputError(field, "must be a list of alternating inertia and spring entries", chain)
    if len(chain) == 0:
        raise InputError(field, "must hold at least one inertia entry", chain)
    inertia: list[float] = []
    ground: list[float] = []
    friction: list[Friction | None] = []
    names: list[str] = []
    stiff: list[float] = []
    damp: list[float] = []
    back: list[float] = []
    eff: list[float] = []
    beff: list[float] = []
    for idx, entry in enumerate(chain):
        p = f"{field}[{idx}]"
        if not isinstance(entry, dict):
            raise InputError(p, "must be a mapping", entry)
        is_inertia = idx % 2 == 0
        keys = _INERTIA_KEYS if is_inertia else _SPRING_KEYS
        if is_inertia and "inertia" not in entry:
            if "stiffness" in entry or "backlash" in entry:
                raise InputError(p, "must be an inertia entry: entries alternate inertia, spring, inertia, ...",
                                 entry)
            raise InputError(f"{p}.inertia", "is required", has_value=False)
        if not is_inertia and "stiffness" not in entry:
            if "inertia" in entry:
                raise InputError(p, "must be a spring entry: entries alternate inertia, spring, inertia, ...",
                                 entry)
            if "backlash" in entry:
                raise InputError(f"{p}.stiffness", "is required where backlash is given (the contact stiffness "
                                 "of the elasto-backlash)", has_value=False)
            raise InputError(f"{p}.stiffness", "is required", has_value=False)
        for key in entry:
            if key not in keys:
                raise InputError(f"{p}.{key}", f"is not allowed here (allowed: {', '.join(keys)})", entry[key])
        if is_inertia:
            inertia.append(parse(entry["inertia"], "inertia", f"{p}.inertia"))
            ground.append(parse(entry.get("damping", 0.0), "torsional_damping", f"{p}.damping"))
            friction.append(friction_from_spec(entry["friction"], f"{p}.friction") if "friction" in entry else None)
            names.append(str(entry.get("name", "")))
        else:
            stiff.append(parse(entry["stiffness"], "torsional_stiffness", f"{p}.stiffness"))
            damp.append(parse(entry.get("damping", 0.0), "torsional_damping", f"{p}.damping"))
            back.append(parse(entry.get("backlash", 0.0), "angle", f"{p}.backlash"))
            eff.append(parse(entry.get("efficiency", 1.0), "dimensionless", f"{p}.efficiency"))
            beff.append(parse(entry.get("back_efficiency", eff[-1]), "dimensionless", f"{p}.back_efficiency"))
    if len(chain) % 2 == 0:
        raise InputError(f"{field}[{len(chain) - 1}]", "a chain must end with an inertia entry (inertia, spring, "
                         "inertia, ...): the last spring connects to nothing", chain[-1])
    default = _default_names(len(inertia))
    return Chain(
        inertia=np.array(inertia),
        stiffness=np.array(stiff),
        damping=np.array(damp),
        backlash=np.array(back),
        ground_damping=np.array(ground),
        efficiency=np.array(eff),
        back_efficiency=np.array(beff),
        friction=tuple(friction),
        names=tuple(nm or default[k] for k, nm in enumerate(names)),
        path=field,
    )


def model_from_stages(motor_inertia: float, stages: Sequence[Any], load_inertia: float) -> Chain:
    """Compliant chain at the motor shaft from the motor, the drive-train stages and the load.

    ``motor_inertia`` [kg m^2]; ``stages`` (``drivetrain.physics.stage.Stage``) from the motor outward;
    ``load_inertia`` at the output of the last stage [kg m^2, or kg for a linear mechanism].

    Rule (lecture, "Energy Equivalence Principle"; docs/conventions.md): walking outward with
    the cumulative ratio r (motor angle per angle at the current point), every inertia adds J/r^2
    to the current lump. A compliant stage (``stiffness`` not None, given at its input) closes the
    lump: its ``inertia_in`` (motor side) joins the lump before the spring, its spring enters as
    K/r^2 with damping B/r^2 and backlash * r, and its ``inertia_inside`` starts the next lump.
    Rigid stages just lump. Losses: a spring carries, as a lossy gear at its load end, the product
    of the efficiencies of its own stage and the rigid stages after it up to the next compliance
    (losses of rigid stages between the motor and the first compliance are not modelled: they sit
    inside the motor lump). A stage's ``friction_torque_in`` becomes Coulomb friction T/r on the
    lump that holds its input. With no compliant stage the result is one rigid inertia.
    """
    if not math.isfinite(motor_inertia) or motor_inertia <= 0.0:
        raise InputError("motor.inertia", "must be > 0 kg*m^2", motor_inertia)
    if not math.isfinite(load_inertia) or load_inertia < 0.0:
        raise InputError("load.inertia", "must be >= 0", load_inertia)
    lumps = [float(motor_inertia)]
    coulomb = [0.0]
    lump_names = ["motor"]
    lump_stage = [-1]
    stiff: list[float] = []
    damp: list[float] = []
    back: list[float] = []
    eff: list[float] = []
    beff: list[float] = []
    r = 1.0
    for k, st in enumerate(stages):
        ratio = float(st.ratio)
        if not math.isfinite(ratio) or ratio == 0.0:
            raise InputError(f"transmission[{k}].ratio", "must be a finite, non-zero number", ratio)
        r2 = r * r
        lumps[-1] += st.inertia_in / r2
        coulomb[-1] += abs(getattr(st, "friction_torque_in", 0.0)) / abs(r)
        if st.stiffness is not None:
            if not math.isfinite(st.stiffness) or st.stiffness <= 0.0:
                raise InputError(f"transmission[{k}].stiffness", "must be > 0 N*m/rad", st.stiffness)
            stiff.append(st.stiffness / r2)
            damp.append(st.damping / r2)
            back.append(st.backlash * abs(r))
            eff.append(st.efficiency)
            beff.append(st.back_efficiency)
            lumps.append(st.inertia_inside / r2)
            coulomb.append(0.0)
            lump_names.append(st.name or st.kind)
            lump_stage.append(k)
        else:
            lumps[-1] += st.inertia_inside / r2
            if eff:
                eff[-1] *= st.efficiency
                beff[-1] = beff[-1] * st.back_efficiency if beff[-1] > 0 else beff[-1]
        r *= ratio
    lumps[-1] += load_inertia / (r * r)
    lump_names[-1] = "load" if len(lumps) > 1 else "motor"
    for k, j in enumerate(lumps):
        if j <= 0.0:
            raise InputError(f"transmission[{lump_stage[k]}].inertia",
                             "the lump between two compliant stages has no inertia: give the inertia of the "
                             "parts there", j)
    friction = tuple(Friction(coulomb=c) if c > 0.0 else None for c in coulomb)
    return Chain(
        inertia=np.array(lumps),
        stiffness=np.array(stiff),
        damping=np.array(damp),
        backlash=np.array(back),
        efficiency=np.array(eff),
        back_efficiency=np.array(beff),
        friction=friction,
        names=tuple(lump_names),
        ratio=r,
        path="transmission",
    )


def two_mass_chain(j_motor: float, j_load: float, stiffness: float, damping: float = 0.0,
                   backlash: float = 0.0) -> Chain:
    """Convenience: the lecture's two-mass system (motor and load on one spring), SI."""
    return Chain(inertia=np.array([j_motor, j_load]), stiffness=np.array([stiffness]),
                 damping=np.array([damping]), backlash=np.array([backlash]))
