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
* the hull of the cycle behind a gearbox efficiency is computed once per variant, compiled
  (``sizing.hull``, equal to ``motor_fit.demand`` vertex for vertex), only for the efficiencies
  the search meets, and handed to ``evaluate`` for every motor table it evaluates;
* the margins that depend on the motor and the ratio alone (max speed, inertia ratio) or on the
  gearbox row alone (n1max, n1N, T2N, T2B) are computed first (``search_bounds``): a candidate
  whose pair or row fails one of them fails, and its worst margin is at most the least of them;
* for the objective ``smallest`` the motors are evaluated in chunks from the smallest up, each
  chunk direct and behind the gearbox rows it can pass with, and the search stops once no motor
  left can rank first (below);
* when nothing passes, the closest candidate is looked for among the candidates whose bound can
  reach it (``_closest_of_all``), not over the whole catalog;
* no Pareto front, next-smaller motor, optimal ratio, advice or ranked list of candidates: the
  answer holds the selected candidate (or, when nothing passes, the closest one) and, where the
  whole catalog was evaluated (objectives other than ``smallest``), the counts of ``select``;
* the drive post-pass (a drive for the selected motor, its currents, regen) runs only for an engine
  made with ``drives`` (a study that records one of its keys);
* the mechanism checks (screw buckling, critical and DN speed, nut life and static safety, guide
  life and static safety) of a task's variants are computed together, as arrays over the variants
  (``Engine.size_many``, ``mechanism_checks.prepare_many``: the same entries, to the bit), and
  ``size`` finds each variant's on its duty cycle;
* the variants of a task with the same motion (the runner puts e.g. the load masses of one lead and
  move time in one task) get the hulls of their first motor chunk from one compiled pass
  (``Engine.size_many``; ``fast_demands`` gives each torque array the hull it gives it alone).

The smallest-first search. ``selection.ranked`` orders the passing candidates by the objective
(motor size x 1e6 + the gearbox's rated torque, which is never negative), ties in candidate order,
and a pair not known to assemble after every pair known to. So a candidate known to assemble
with objective ``s`` ranks before every candidate of a motor of size key ``>= s / 1e6``. Motors
are taken by size key, a chunk at a time (motors of equal size in the same chunk), and the search
stops when the best of the chunks with a passing candidate (evaluated together, ranked by
``ranked``) is known to assemble and its objective is below the next motor's size key x 1e6.
Motors that fail the max-speed or the inertia-ratio check behind every ratio are not tried. A
chunk's gearbox rows keep their catalog order, so its candidates keep their relative order and
``ranked`` breaks ties as over the whole catalog.

``tests/test_study_batch.py`` asserts, on a fixed sample and on 60 random variants, that the
selected (or closest) motor and gearbox and every check's required, available and margin equal
those of ``drivetrain.size``, and checks the bounds against every candidate of the catalog.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.axis.model import Axis
from drivetrain.duty.cycle import duty_from_samples
from drivetrain.errors import InputError
from drivetrain.physics.averages import cubic_mean
from drivetrain.sizing.candidates import FIT_BIT
from drivetrain.sizing.checks import shock_factor
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
    from drivetrain.motion.cycle import Cycle, Samples
    from drivetrain.sizing.candidates import Candidates
    from drivetrain.sizing.demand import Demand
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
    group_eff: Array  # the gearbox efficiency of each group
    row_group: NDArray[np.intp]  # the group of each gearbox row
    size_key: Array  # the objective's motor size [W]
    order: NDArray[np.intp]  # motors by size key, ascending (stable; NaN last)
    _subs: dict[bytes, Any] = field(default_factory=dict)
    _speed: dict[tuple[float, ...], Array] = field(default_factory=dict)  # search_bounds' speed halves

    def speed_half(self, key: tuple[float, ...], make: Any) -> Array:
        """``make()``, the half of a search bound that depends on the motion alone (its top and mean
        speeds) and the margins, computed once for the variants of equal motion (the same array)."""
        hit = self._speed.get(key)
        if hit is None:
            if len(self._speed) > 256:  # (ratio groups x motors) floats each, ~150 kB
                self._speed.clear()
            hit = self._speed[key] = make()
        return hit

    def sub_table(self, members: NDArray[np.intp]) -> MotorTable:
        """The motors ``members`` (ascending) as a table, kept for the next variant that needs them."""
        return self._take(b"m" + members.tobytes(), self.motors, members)

    def sub_gearboxes(self, rows: NDArray[np.intp]) -> GearboxTable | None:
        """The gearbox rows ``rows`` (ascending) as a table (None when there are none), kept likewise."""
        if self.gb is None or not len(rows):
            return None
        if len(rows) == len(self.gb):
            return self.gb
        return self._take(b"g" + rows.tobytes(), self.gb, rows)

    def efficiencies(self, groups: NDArray[np.intp], direct: bool) -> list[float]:
        """The distinct gearbox efficiencies of these groups (and of direct drive, 1)."""
        effs = set(self.group_eff[groups].tolist())
        if direct:
            effs.add(1.0)
        return sorted(effs)

    def _take(self, key: bytes, table: Any, index: NDArray[np.intp]) -> Any:
        hit = self._subs.get(key)
        if hit is None:
            if len(self._subs) > 512:  # a gearbox sub-table is at most ~200 kB
                self._subs.clear()
            hit = self._subs[key] = table.take(index)
        return hit


def load_tables(axis: Axis, spec: SelectSpec) -> Tables:
    """The tables of a ``motor.select`` spec, as ``selection.select`` reads them."""
    motors, gb, allow_direct = catalog_tables(axis, spec)
    ratio, eff, rows, row_start = _gearbox_options(gb, allow_direct)
    row_group = np.zeros(0 if gb is None else len(gb), dtype=np.intp)
    of_slot = np.repeat(np.arange(len(ratio)), np.diff(row_start))
    row_group[rows[rows >= 0]] = of_slot[rows >= 0]
    size_key = _size_key(motors)
    return Tables(motors=motors, gb=gb, allow_direct=allow_direct, ratios=ratio, group_eff=eff,
                  row_group=row_group, size_key=size_key, order=np.argsort(size_key, kind="stable"))


SLACK = 1e-9
"""Relative slack of the search's necessary conditions and bounds, against rounding."""


@dataclass
class Search:
    """What one variant's search knows of it before any candidate is evaluated: margins that bound
    every candidate's (``search_bounds``), NaN where a rating is unknown."""

    pair: Array  # (group, motor): the least of the max-speed and inertia-ratio margins
    row: Array  # gearbox rows: the least margin of the row's own ratings

    @cached_property
    def feasible(self) -> NDArray[np.bool_]:
        """(group, motor): the max-speed and the inertia-ratio check can pass."""
        return np.asarray(~(self.pair < -SLACK), dtype=bool)

    @cached_property
    def row_ok(self) -> NDArray[np.bool_]:
        """Gearbox rows whose own ratings (n1max, n1N, T2N, T2B) can pass."""
        return np.asarray(~(self.row < -SLACK), dtype=bool)

    @cached_property
    def pair_bound(self) -> Array:
        """(group, motor): no candidate's worst margin is above this (+inf: no bound)."""
        return _raised(self.pair)

    @cached_property
    def row_bound(self) -> Array:
        """Gearbox rows: likewise."""
        return _raised(self.row)


def search_bounds(tb: Tables, duty: DutyCycle, margins: Margins, spec: SelectSpec) -> Search:
    """Margins of the checks that depend on the motor and the ratio alone or on the gearbox row alone,
    as kernel.py computes them:

    * max speed: the motor's max speed / (the cycle's top speed x ratio x speed margin) - 1 (a
      gearbox's input-speed limit only lowers the available speed);
    * inertia ratio: limit x rotor inertia / (load inertia / ratio^2) - 1 (a gearbox's input
      inertia only adds to the load side, so this is the largest over the gearbox rows);
    * the gearbox row: n1max against the top speed x ratio x speed margin, n1N against the mean
      speed x ratio, T2N against the cubic-mean output torque x torque margin, T2B against the peak
      output torque x torque margin x shock factor. These do not depend on the motor.

    A candidate whose pair or row margin is below -1e-9 fails (its check fails, whatever the other
    half of the pair); a candidate's worst margin (the least of its known margins) is at most the
    least of its pair's and its row's (each raised by a relative 1e-9 against rounding; unknown: +inf).
    """
    limit = margins.inertia_ratio if spec.max_inertia_ratio is None else min(spec.max_inertia_ratio,
                                                                             margins.inertia_ratio)
    w = np.abs(duty.omega)
    top = float(np.max(w)) if w.size else 0.0
    m = tb.motors
    with np.errstate(divide="ignore", invalid="ignore"):
        need = top * tb.ratios * margins.speed
        j_load = duty.load_inertia / tb.ratios**2
        # the max-speed half depends on the motion alone: one array for the variants of one motion
        pair = np.fmin(tb.speed_half((top, margins.speed), lambda: m.max_speed[None, :] / need[:, None] - 1.0),
                       limit * m.rotor_inertia[None, :] / j_load[:, None] - 1.0)
        row = np.zeros(0)
        if tb.gb is not None and len(tb.gb):
            gb = tb.gb
            ratio = tb.ratios[tb.row_group]
            mean = float(np.sum(duty.weights * w)) / duty.period
            speeds = tb.speed_half((top, margins.speed, mean), lambda: np.fmin(
                gb.max_input_speed / (top * margins.speed * ratio) - 1.0, gb.rated_input_speed / (mean * ratio) - 1.0))
            t2b_need = (float(np.max(np.abs(duty.torque))) if duty.torque.size else 0.0) * margins.torque * \
                shock_factor(duty.period, margins.gearbox_shock_factor)  # NaN: the T2B check is unknown
            t2n_need = cubic_mean(duty.torque, duty.omega, duty.weights) * margins.torque
            row = np.fmin(speeds, np.fmin(gb.rated_output_torque / t2n_need - 1.0,
                                          gb.max_output_torque / t2b_need - 1.0))
    return Search(pair=pair, row=row)


def _raised(bound: Array) -> Array:
    """An upper bound raised by a relative SLACK against rounding; NaN (unknown) as +inf."""
    finite = np.nan_to_num(bound, nan=0.0, posinf=0.0, neginf=0.0)
    return np.where(np.isnan(bound), np.inf, bound + SLACK * (1.0 + np.abs(finite)))


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

    def __init__(self, points_per_phase: int = 64, drives: bool = False) -> None:
        self.points = points_per_phase
        self.drives = drives  # the drive post-pass of size (a drive for the selected motor, its currents)
        self._tables: dict[str, Tables] = {}
        self._kinematics: dict[str, tuple[Cycle, Samples]] = {}
        # size_many: a variant's search bounds and the hulls computed with its motion's other variants
        self._prepared: dict[int, tuple[DutyCycle, Search, dict[float, Demand]]] = {}

    def tables(self, axis: Axis, spec: SelectSpec) -> Tables:
        """The catalog tables of this axis's selection (loaded on first use, then kept)."""
        own = any(st.kind == "gearbox" for st in axis.transmission)
        key = repr((spec, own))  # every field, floats to the last digit
        if key not in self._tables:
            self._tables[key] = load_tables(axis, spec)
        return self._tables[key]

    def duty(self, axis: Axis) -> DutyCycle:
        """The duty cycle, the profile's kinematics shared between axes with equal profiles."""
        key = repr((axis.spec.profile, axis.mechanism.motion, self.points))
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
        ``selection`` block holds the keys of :meth:`select`; the selected candidate's ``drive``,
        ``electrical`` and ``regen`` only where the engine was made with ``drives``)."""
        from drivetrain.sizing.result import size

        return answer(size(axis, self.points, duty=self.duty(axis), selector=self.select, drives=self.drives))

    def size_many(self, axes: list[Axis]) -> list[dict[str, Any] | InputError]:
        """:meth:`size` of each axis (or the InputError it raises), their mechanism checks computed
        together first (``mechanism_checks.prepare_many``: the same entries) and the hulls of
        variants of equal motion in one pass (``_prepare_hulls``)."""
        from drivetrain.sizing.mechanism_checks import prepare_many
        from drivetrain.sizing.result import size

        duties: list[DutyCycle | InputError] = []
        for axis in axes:
            try:
                duties.append(self.duty(axis))
            except InputError as exc:
                duties.append(exc)
        pairs = [(a, d) for a, d in zip(axes, duties, strict=True) if not isinstance(d, InputError)]
        prepare_many(pairs)
        out: list[dict[str, Any] | InputError] = []
        try:
            self._prepare_hulls(pairs)
            for axis, duty in zip(axes, duties, strict=True):
                if isinstance(duty, InputError):
                    out.append(duty)
                    continue
                try:
                    out.append(answer(size(axis, self.points, duty=duty, selector=self.select, drives=self.drives)))
                except InputError as exc:
                    out.append(exc)
        finally:
            self._prepared.clear()
        return out

    def _prepare_hulls(self, pairs: list[tuple[Axis, DutyCycle]]) -> None:
        """The search bounds of each variant whose selection searches smallest first, and the hulls
        its first motor chunk needs, computed in one compiled pass for the variants of equal motion
        (the same motor-shaft speeds and accelerations: e.g. the load masses of one lead and move
        time). ``fast_demands`` gives each torque array the hull it gives it alone, so each variant's
        hulls are those ``select`` would compute (the load inertia set to the variant's own)."""
        by_motion: dict[int, list[tuple[Axis, DutyCycle, list[float]]]] = {}
        for axis, duty in pairs:
            m = axis.spec.motor
            if axis.motor is not None or m is None or m.select is None or m.select.objective != "smallest":
                continue
            tb = self.tables(axis, m.select)
            bounds = search_bounds(tb, duty, m.margins, m.select)
            self._prepared[id(duty)] = (duty, bounds, {})
            order = _search_order(tb, bounds)
            first = _chunk_candidates(tb, bounds, _chunk(tb, order, 0)[0]) if len(order) else None
            if first is not None:
                effs = tb.efficiencies(tb.row_group[first[1]], first[0])
                by_motion.setdefault(id(duty.samples), []).append((axis, duty, effs))
        for members in by_motion.values():
            while members:
                ref = members[0][1]
                same = [x for x in members if x[1] is ref or (x[1].period == ref.period and np.array_equal(
                    x[1].omega, ref.omega) and np.array_equal(x[1].alpha, ref.alpha))]
                members = [x for x in members if not any(x is y for y in same)]
                if len(same) < 2:
                    continue  # alone: select computes its hulls as before
                owners = [(axis, duty, e) for axis, duty, effs in same for e in effs]
                demands = fast_demands(ref.omega, ref.alpha, [lossy_torque(a, d, e) for a, d, e in owners],
                                       ref.weights, ref.period, ref.load_inertia)
                for (_, duty, e), dem in zip(owners, demands, strict=True):
                    if duty.load_inertia != ref.load_inertia:
                        dem = replace(dem, load_inertia=duty.load_inertia)
                    self._prepared[id(duty)][2][e] = dem

    def select(self, axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins,
               all_pairs: bool = False) -> dict[str, Any]:
        """``selection.select``'s answer for its first candidate: the same selected (or closest)
        candidate, found by the search of the module docstring."""
        if all_pairs:
            return select(axis, duty, spec, margins, all_pairs=True)
        tb = self.tables(axis, spec)
        prepared = self._prepared.get(id(duty))  # made by size_many for this duty cycle and the axis's own spec
        if prepared is not None and (prepared[0] is not duty or axis.spec.motor is None
                                     or spec is not axis.spec.motor.select or margins is not axis.spec.motor.margins):
            prepared = None
        demands: dict[float, Demand] = {} if prepared is None else dict(prepared[2])

        def ev(motors: MotorTable, gb: GearboxTable | None, allow_direct: bool, effs: list[float]) -> Candidates:
            missing = [e for e in effs if e not in demands]
            if missing:  # the hulls of the efficiencies not met before, in one compiled pass
                torques = [lossy_torque(axis, duty, e) for e in missing]
                demands.update(zip(missing, fast_demands(duty.omega, duty.alpha, torques, duty.weights, duty.period,
                                                         duty.load_inertia), strict=True))
            return evaluate(axis, duty, motors, gb, margins, allow_direct=allow_direct,
                            max_inertia_ratio=spec.max_inertia_ratio, strict=spec.unknown == "fail",
                            given_demands=demands)

        if spec.objective == "smallest":
            bounds = search_bounds(tb, duty, margins, spec) if prepared is None else prepared[1]
            found = _smallest_first(ev, tb, bounds, duty)
            if found is not None:
                return _summary(*found, tb, spec, duty, evaluated_all=False)
            closest = _closest_of_all(ev, tb, bounds)
            if closest is not None:  # nothing passes: the closest candidate, found without the counts
                return _summary(*closest, np.zeros(0, dtype=np.intp), tb, spec, duty, evaluated_all=False)
        # every candidate, ranked as select ranks them
        c = ev(tb.motors, tb.gb, tb.allow_direct, tb.efficiencies(tb.row_group, tb.allow_direct))
        return _summary(c, tb.motors, tb.gb, ranked(c, tb.motors, tb.gb, spec.objective, duty), tb, spec, duty,
                        evaluated_all=True)


Found = tuple["Candidates", "MotorTable", "GearboxTable | None", NDArray[np.intp]]


def _smallest_first(ev: Any, tb: Tables, bounds: Search, duty: DutyCycle) -> Found | None:
    """The candidates that hold the best one (motors of the chunks with a passing candidate, the
    gearbox rows any of them can pass with), and their ranking; None when no candidate passes."""
    order = _search_order(tb, bounds)
    passing_chunks: list[NDArray[np.intp]] = []
    best: Found | None = None
    start = 0
    while start < len(order):
        members, stop = _chunk(tb, order, start)
        start = stop
        found = _evaluate_chunk(ev, tb, bounds, members)
        if found is not None and np.any(found[0].ok):
            passing_chunks.append(members)
            if len(passing_chunks) > 1:  # rank the passing chunks' candidates together
                found = _evaluate_chunk(ev, tb, bounds, np.sort(np.concatenate(passing_chunks)))
            assert found is not None
            c, sub, gb = found
            best = (c, sub, gb, ranked(c, sub, gb, "smallest", duty))
        if best is not None and (stop == len(order) or _beats_the_rest(best, tb, duty,
                                                                       float(tb.size_key[order[stop]]))):
            return best
    return best


def _evaluate_chunk(ev: Any, tb: Tables, bounds: Search,
                    members: NDArray[np.intp]) -> tuple[Candidates, MotorTable, GearboxTable | None] | None:
    """The candidates of the motors ``members`` (ascending) that can pass, None when none can.

    Only direct drive and the gearbox rows that pass their own ratings, of a ratio some of the
    motors can pass the max-speed and inertia-ratio checks with, are evaluated: every other
    candidate fails. The rows keep their catalog order, so the candidates keep theirs and
    ``ranked`` breaks ties as over the whole catalog.
    """
    which = _chunk_candidates(tb, bounds, members)
    if which is None:
        return None
    direct, rows = which
    sub, gb = tb.sub_table(members), tb.sub_gearboxes(rows)
    return ev(sub, gb, direct, tb.efficiencies(tb.row_group[rows], direct)), sub, gb


def _search_order(tb: Tables, bounds: Search) -> NDArray[np.intp]:
    """The motors some ratio can pass the max-speed and inertia-ratio checks with, by size key."""
    return tb.order[np.any(bounds.feasible, axis=0)[tb.order]]


def _chunk(tb: Tables, order: NDArray[np.intp], start: int) -> tuple[NDArray[np.intp], int]:
    """The motors of the chunk from ``order[start]`` (ascending), and where the next one starts:
    ``CHUNK`` motors, and those of the same size as the last."""
    stop = min(start + CHUNK, len(order))
    while stop < len(order) and tb.size_key[order[stop]] == tb.size_key[order[stop - 1]]:
        stop += 1  # motors of equal size go in the same chunk
    return np.sort(order[start:stop]), stop


def _chunk_candidates(tb: Tables, bounds: Search,
                      members: NDArray[np.intp]) -> tuple[bool, NDArray[np.intp]] | None:
    """What ``_evaluate_chunk`` evaluates for the motors ``members``: (direct drive, the gearbox
    rows), None when nothing of theirs can pass."""
    groups = np.any(bounds.feasible[:, members], axis=1)
    direct = tb.allow_direct and bool(groups[0])
    rows = np.flatnonzero(bounds.row_ok & groups[tb.row_group]) if tb.gb is not None else np.zeros(0, np.intp)
    if not direct and not len(rows):
        return None
    return direct, rows


def _closest_of_all(ev: Any, tb: Tables, bounds: Search) -> tuple[Candidates, MotorTable, GearboxTable | None] | None:
    """When no candidate passes: the candidates among which the closest one of the whole catalog is
    (``select``'s: the largest worst margin, ties in candidate order), None when it takes them all.

    Every candidate's worst margin is at most its bound (``search_bounds``). The candidates with a
    bound of at least ``tau`` are evaluated (the motors and gearbox rows that have one, so a few
    more): first with ``tau`` that of the ``CHUNK`` motors of the largest bounds, then, if the best
    worst margin ``w`` found is below ``tau``, with ``tau = w``. Every candidate left out then has a
    worst margin below ``w``: the best found is the best of all, and candidates keep their order.
    """
    n_rows = 0 if tb.gb is None else len(tb.gb)
    row_bound = bounds.row_bound if n_rows else np.zeros(0)
    group_row = np.full(len(tb.ratios), -np.inf)  # the largest row bound of each group
    np.maximum.at(group_row, tb.row_group, row_bound)
    if tb.allow_direct:
        group_row[0] = np.inf  # direct drive has no gearbox rating
    pair = np.minimum(bounds.pair_bound, group_row[:, None])
    motor = np.max(pair, axis=0)
    tau = float(np.sort(motor)[::-1][min(CHUNK, len(motor)) - 1])
    for _ in range(2):
        if not math.isfinite(tau):
            return None
        members = np.flatnonzero(motor >= tau)
        groups = np.any(pair[:, members] >= tau, axis=1)
        direct = tb.allow_direct and bool(groups[0])
        rows = np.flatnonzero((row_bound >= tau) & groups[tb.row_group]) if n_rows else np.zeros(0, np.intp)
        if not direct and not len(rows):
            return None
        sub, gb = tb.sub_table(members), tb.sub_gearboxes(rows)
        c = ev(sub, gb, direct, tb.efficiencies(tb.row_group[rows], direct))
        w = float(c.worst_margin[_closest_failing(c, 1)[0]])
        if w >= tau:
            return c, sub, gb
        tau = w
    return None


def _beats_the_rest(best: Found, tb: Tables, duty: DutyCycle, next_size: float) -> bool:
    """The first ranked candidate ranks before every candidate of a motor of size key >= ``next_size``."""
    c, sub, gb, order = best
    k = order[:1]
    obj = float(_objective(c, k, sub, gb, "smallest", duty)[0])
    known_fit = not (int(c.unknown[k[0]]) & FIT_BIT)
    return known_fit and math.isfinite(obj) and (math.isnan(next_size) or obj < next_size * 1e6)


def _summary(c: Candidates, motors: MotorTable, gb: GearboxTable | None, order: NDArray[np.intp], tb: Tables,
             spec: SelectSpec, duty: DutyCycle, evaluated_all: bool) -> dict[str, Any]:
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
        first = candidate_dict(c, k, motors, gb, 1)
        summary["_best"] = k
        summary["selected"] = first
    else:
        first = candidate_dict(c, int(_closest_failing(c, 1)[0]), motors, gb, None)
    summary["_candidates"] = c
    summary["_ranked"] = order
    summary["_tables"] = (motors, gb)
    return {"candidates": [first], "selection": summary}


def full_result(axis: Axis, points_per_phase: int = 64) -> dict[str, Any]:
    """``answer(drivetrain.size(axis))``: the unbatched path, for results that record keys the
    batched path does not compute."""
    from drivetrain.sizing.result import size

    return answer(size(axis, points_per_phase))


__all__ = ["CHUNK", "Engine", "Tables", "answer", "full_result", "load_tables", "motoring_energy", "search_bounds"]
