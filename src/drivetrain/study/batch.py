"""The batched sizing path of a study: many variants of one axis against one loaded catalog.

A variant is sized by ``sizing.result.size`` itself (the same checks, the same ``ok``, the same
answer keys), with two things handed in: its duty cycle, and a selector that stands in for
``selection.select`` and is built from the selection's own functions (``catalog_tables``,
``evaluate``, ``ranked``, ``candidate_dict``). A change of the engine's checks or ranking is thus
met here without an edit. What the batched path saves per variant, without changing any answer:

* the catalog tables and the motor order by size are loaded once per engine (once per worker
  process), not once per variant;
* profiles equal (same profile entries, same kind of motion, same points per phase) share their
  sampled kinematics (``Cycle`` and ``Samples`` are functions of those alone);
* the hull of the cycle behind each gearbox efficiency is computed once per variant, compiled
  (``sizing.hull``, equal to ``motor_fit.demand`` vertex for vertex), and handed to ``evaluate``
  for every motor table the search evaluates;
* for the objective ``smallest`` the motors are evaluated in chunks from the smallest up, and the
  search stops once no motor left can rank first (below);
* no Pareto front, next-smaller motor, optimal ratio, advice or ranked list of candidates: the
  answer holds the selected candidate (or, when nothing passes, the closest one) and, where the
  whole catalog was evaluated, the counts of ``select``.

The smallest-first search. ``selection.ranked`` orders the passing candidates by the objective
(motor size x 1e6 + the gearbox's rated torque, which is never negative), ties in candidate order,
and a pair not known to assemble after every pair known to. So a candidate known to assemble
with objective ``s`` ranks before every candidate of a motor of size key ``>= s / 1e6``. Motors
are taken by size key, a chunk at a time (motors of equal size in the same chunk), and the search
stops when the best of the chunks with a passing candidate (evaluated together, ranked by
``ranked``) is known to assemble and its objective is below the next motor's size key x 1e6. Motors
that fail every candidate on a check no gearbox row can change are not tried: max speed below the
cycle's (x margin) behind every ratio, or the load inertia behind every ratio above the limit x
the rotor inertia (both with a relative slack of 1e-9). When nothing passes, the whole catalog is
evaluated, as ``select`` does.

``tests/test_study_batch.py`` asserts, on a sample of variants, that the selected motor and
gearbox and every check's required, available and margin equal those of ``drivetrain.size``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.axis.model import Axis
from drivetrain.duty.cycle import duty_from_samples
from drivetrain.sizing.candidates import FIT_BIT
from drivetrain.sizing.hull import fast_demands
from drivetrain.sizing.selection import (
    _closest_failing,
    _gearbox_options,
    _objective,
    _size_key,
    catalog_tables,
    evaluate,
    lossy_torque,
    ranked,
    select,
)

if TYPE_CHECKING:
    from drivetrain.axis.model import Margins, SelectSpec
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.motion.profiles import Cycle, Samples
    from drivetrain.sizing.candidates import Candidates
    from drivetrain.sizing.result import SizingResult

Array = NDArray[np.float64]

CHUNK = 12
"""Motors per chunk of the smallest-first search (extended to include motors of equal size)."""


@dataclass
class Tables:
    """One selection's catalog tables and what the search derives from them once."""

    motors: MotorTable
    gb: GearboxTable | None
    allow_direct: bool
    ratios: Array  # the ratio of each (ratio, efficiency) group, direct drive included where allowed
    efficiencies: list[float]  # the distinct gearbox efficiencies of the groups
    size_key: Array  # the objective's motor size [W]
    order: NDArray[np.intp]  # motors by size key, ascending (stable; NaN last)
    _subs: dict[bytes, MotorTable] = field(default_factory=dict)

    def sub_table(self, members: NDArray[np.intp]) -> MotorTable:
        """The motors ``members`` (ascending) as a table, kept for the next variant that needs them."""
        key = members.tobytes()
        hit = self._subs.get(key)
        if hit is None:
            if len(self._subs) > 2048:
                self._subs.clear()
            hit = self._subs[key] = self.motors.take(members)
        return hit


def load_tables(axis: Axis, spec: SelectSpec) -> Tables:
    """The tables of a ``motor.select`` spec, as ``selection.select`` reads them."""
    motors, gb, allow_direct = catalog_tables(axis, spec)
    ratio, eff, _, _ = _gearbox_options(gb, allow_direct)
    size_key = _size_key(motors)
    return Tables(motors=motors, gb=gb, allow_direct=allow_direct, ratios=ratio,
                  efficiencies=list(dict.fromkeys(eff.tolist())), size_key=size_key,
                  order=np.argsort(size_key, kind="stable"))


def feasible_motors(tb: Tables, duty: DutyCycle, margins: Margins, spec: SelectSpec) -> NDArray[np.bool_]:
    """Motors that pass the max-speed and the inertia-ratio check behind at least one ratio: a
    necessary condition of any passing candidate (a gearbox's input-speed limit only lowers the
    available speed, its input inertia only adds to the load side), with a relative slack of 1e-9
    so that a motor at a limit to rounding is evaluated."""
    limit = margins.inertia_ratio if spec.max_inertia_ratio is None else min(spec.max_inertia_ratio,
                                                                             margins.inertia_ratio)
    top = float(np.max(np.abs(duty.omega))) if duty.omega.size else 0.0
    need = top * tb.ratios * margins.speed
    j_load = duty.load_inertia / tb.ratios**2
    m = tb.motors
    speed_ok = ~(m.max_speed[None, :] < need[:, None] * (1.0 - 1e-9))  # an unknown max speed: kept
    inertia_ok = ~(j_load[:, None] > limit * m.rotor_inertia[None, :] * (1.0 + 1e-9))
    return np.asarray(np.any(speed_ok & inertia_ok, axis=0), dtype=bool)


def motoring_energy(duty: DutyCycle, rotor_inertia: float) -> float:
    """Energy the motor delivers per cycle [J]: the integral of max(T omega, 0) dt, rotor included
    (``selection._energy``'s measure, regenerated energy not credited)."""
    p = duty.motor_torque(rotor_inertia) * duty.omega
    return float(np.sum(duty.weights * np.maximum(p, 0.0)))


def answer(r: SizingResult) -> dict[str, Any]:
    """``r.to_dict()`` with ``ok`` and ``energy_per_cycle_J`` (the selected candidate's, none when
    nothing passes)."""
    from drivetrain.sizing.selection import candidate_cycle

    out = r.to_dict()
    out["ok"] = r.ok
    if r.axis.motor is not None:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, r.axis.motor.inertia)
    elif r.selection is not None and "_best" in r.selection:
        cycle, j = candidate_cycle(r.axis, r.duty, r.selection)
        out["energy_per_cycle_J"] = motoring_energy(cycle, j)
    elif r.selection is not None:
        out["energy_per_cycle_J"] = math.nan
    else:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, 0.0)
    return out


class Engine:
    """Sizes many axes against the catalog loaded once; a worker process keeps one engine."""

    def __init__(self, points_per_phase: int = 64) -> None:
        self.points = points_per_phase
        self._tables: dict[str, Tables] = {}
        self._kinematics: dict[str, tuple[Cycle, Samples]] = {}

    def tables(self, axis: Axis, spec: SelectSpec) -> Tables:
        """The catalog tables of this axis's selection (loaded on first use, then kept)."""
        own = any(st.kind == "gearbox" for st in axis.transmission)
        key = json.dumps([spec.model_dump(mode="json"), own], sort_keys=True, default=str)
        if key not in self._tables:
            self._tables[key] = load_tables(axis, spec)
        return self._tables[key]

    def duty(self, axis: Axis) -> DutyCycle:
        """The duty cycle, the profile's kinematics shared between axes with equal profiles."""
        key = json.dumps([axis.spec.profile, axis.mechanism.motion, self.points], sort_keys=True, default=str)
        hit = self._kinematics.get(key)
        if hit is None:
            cycle = axis.cycle()
            hit = (cycle, cycle.sample(self.points))
            if len(self._kinematics) > 4096:
                self._kinematics.clear()
            self._kinematics[key] = hit
        return duty_from_samples(axis, hit[0], hit[1])

    def size(self, axis: Axis) -> dict[str, Any]:
        """A variant's result: ``answer(drivetrain.size(axis))`` with the batched selection (its
        ``selection`` block holds the keys of :meth:`select`)."""
        from drivetrain.sizing.result import size

        return answer(size(axis, self.points, duty=self.duty(axis), selector=self.select))

    def select(self, axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins,
               all_pairs: bool = False) -> dict[str, Any]:
        """``selection.select``'s answer for its first candidate: the same selected (or closest)
        candidate, found by the search of the module docstring."""
        if all_pairs:
            return select(axis, duty, spec, margins, all_pairs=True)
        tb = self.tables(axis, spec)
        torques = [lossy_torque(axis, duty, e) for e in tb.efficiencies]
        demands = dict(zip(tb.efficiencies, fast_demands(duty.omega, duty.alpha, torques, duty.weights, duty.period,
                                                         duty.load_inertia), strict=True))

        def ev(motors: MotorTable) -> Candidates:
            return evaluate(axis, duty, motors, tb.gb, margins, allow_direct=tb.allow_direct,
                            max_inertia_ratio=spec.max_inertia_ratio, strict=spec.unknown == "fail",
                            given_demands=demands)

        found = _smallest_first(ev, tb, duty, margins, spec) if spec.objective == "smallest" else None
        if found is None:  # every candidate, ranked as select ranks them
            c = ev(tb.motors)
            found = (c, tb.motors, ranked(c, tb.motors, tb.gb, spec.objective, duty))
            return _summary(*found, tb, spec, duty, evaluated_all=True)
        return _summary(*found, tb, spec, duty, evaluated_all=False)


def _smallest_first(ev: Any, tb: Tables, duty: DutyCycle, margins: Margins,
                    spec: SelectSpec) -> tuple[Candidates, MotorTable, NDArray[np.intp]] | None:
    """The candidates of the motors that hold the best one, and their ranking; None when no feasible
    motor has a passing candidate."""
    order = tb.order[feasible_motors(tb, duty, margins, spec)[tb.order]]
    passing_chunks: list[NDArray[np.intp]] = []
    best: tuple[Candidates, MotorTable, NDArray[np.intp]] | None = None
    start = 0
    while start < len(order):
        stop = min(start + CHUNK, len(order))
        while stop < len(order) and tb.size_key[order[stop]] == tb.size_key[order[stop - 1]]:
            stop += 1  # motors of equal size go in the same chunk
        members = np.sort(order[start:stop])
        sub = tb.sub_table(members)
        c = ev(sub)
        start = stop
        if np.any(c.ok):
            passing_chunks.append(members)
            if len(passing_chunks) > 1:  # rank the passing chunks' candidates together
                members = np.sort(np.concatenate(passing_chunks))
                sub = tb.sub_table(members)
                c = ev(sub)
            best = (c, sub, ranked(c, sub, tb.gb, "smallest", duty))
        if best is not None and (stop == len(order) or _beats_the_rest(best, tb, duty,
                                                                       float(tb.size_key[order[stop]]))):
            return best
    return best


def _beats_the_rest(best: tuple[Candidates, MotorTable, NDArray[np.intp]], tb: Tables, duty: DutyCycle,
                    next_size: float) -> bool:
    """The first ranked candidate ranks before every candidate of a motor of size key >= ``next_size``."""
    c, sub, order = best
    k = order[:1]
    obj = float(_objective(c, k, sub, tb.gb, "smallest", duty)[0])
    known_fit = not (int(c.unknown[k[0]]) & FIT_BIT)
    return known_fit and math.isfinite(obj) and (math.isnan(next_size) or obj < next_size * 1e6)


def _summary(c: Candidates, motors: MotorTable, order: NDArray[np.intp], tb: Tables, spec: SelectSpec,
             duty: DutyCycle, evaluated_all: bool) -> dict[str, Any]:
    """``select``'s answer, keys as there: the first candidate, and the counts where every candidate
    was evaluated."""
    from drivetrain.sizing.reasons import candidate_dict

    summary: dict[str, Any] = {"objective": spec.objective, "motors": len(tb.motors),
                               "gearbox_rows": 0 if tb.gb is None else len(tb.gb), "unknown_policy": spec.unknown,
                               "cycles_per_hour": 3600.0 / duty.period}
    if evaluated_all:
        summary.update({"evaluated": len(c.motor), "passing": len(order),
                        "passing_motors": len(np.unique(c.motor[order])), "failures_by_check": c.failures(),
                        "unknown_by_check": c.unknowns()})
    if len(order):
        k = int(order[0])
        first = candidate_dict(c, k, motors, tb.gb, 1)
        summary["_best"] = k
        summary["selected"] = first
    else:
        first = candidate_dict(c, int(_closest_failing(c, 1)[0]), motors, tb.gb, None)
    summary["_candidates"] = c
    summary["_ranked"] = order
    summary["_tables"] = (motors, tb.gb)
    return {"candidates": [first], "selection": summary}


def full_result(axis: Axis, points_per_phase: int = 64) -> dict[str, Any]:
    """``answer(drivetrain.size(axis))``: the unbatched path, for results that record keys the
    batched path does not compute."""
    from drivetrain.sizing.result import size

    return answer(size(axis, points_per_phase))


__all__ = ["CHUNK", "Engine", "Tables", "answer", "feasible_motors", "full_result", "load_tables", "motoring_energy"]
