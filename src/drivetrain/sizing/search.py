"""The selection's search for its first candidate (``listing="selected"`` of the sizing pipeline):
the same selected (or, when nothing passes, closest) candidate as ``selection.select``, found without
evaluating the whole catalog.

What it saves, without changing the candidate found or any of its figures:

* the catalog tables and the motor order by size are loaded once per :class:`Tables` (kept by the
  pipeline's ``Context``, so once per study worker), not once per axis;
* the hull of the cycle behind a gearbox efficiency is computed once per axis, compiled
  (``sizing.hull``, equal to ``motor_fit.demand`` vertex for vertex), only for the efficiencies
  the search meets, and handed to ``evaluate`` for every motor table it evaluates;
* the margins that depend on the motor and the ratio alone (max speed, inertia ratio) or on the
  gearbox row alone (n1max, n1N, T2N, T2B) are computed first (:func:`search_bounds`): a candidate
  whose pair or row fails one of them fails, and its worst margin is at most the least of them;
* for the objective ``smallest`` the motors are evaluated in chunks from the smallest up, each
  chunk direct and behind the gearbox rows it can pass with, and the search stops once no motor
  left can rank first (below);
* when nothing passes, the closest candidate is looked for among the candidates whose bound can
  reach it (``_closest_of_all``), not over the whole catalog;
* the axes of one ``size_many`` call with the same motion (e.g. the load masses of one lead and
  move time) get the hulls of their first motor chunk from one compiled pass (:func:`prepare_hulls`;
  ``fast_demands`` gives each torque array the hull it gives it alone);
* no Pareto front, next-smaller motor, optimal ratio, advice or ranked list of candidates: the
  answer holds the selected candidate (or, when nothing passes, the closest one) and, where the
  whole catalog was evaluated (objectives other than ``smallest``), the counts of ``select``.

The smallest-first search. ``selection.ranked`` orders the passing candidates by the objective
(motor size x 1e6 + the gearbox's rated torque, which is never negative), ties in candidate order,
and a pair not known to assemble (or, on an axis that needs a brake, whose brake's holding torque is
not known) after every one known to. So a candidate known to assemble (and to hold)
with objective ``s`` ranks before every candidate of a motor of size key ``>= s / 1e6``. Motors
are taken by size key, a chunk at a time (motors of equal size in the same chunk), and the search
stops when the best of the chunks with a passing candidate (evaluated together, ranked by
``ranked``) is known to assemble (and to hold) and its objective is below the next motor's size key x 1e6.
Where the best is known to assemble but its brake's holding torque is not known, only a pair known to
assemble and to hold can rank before it: the search goes on through the motors whose brake's holding
torque the catalog has, and no other.
Motors that fail the max-speed or the inertia-ratio check behind every ratio are not tried. A
chunk's gearbox rows keep their catalog order, so its candidates keep their relative order and
``ranked`` breaks ties as over the whole catalog.

``tests/study/test_study_batch.py`` asserts, on a fixed sample and on 60 random variants, that the
selected (or closest) motor and gearbox and every check's required, available and margin equal
those of ``select``, and checks the bounds against every candidate of the catalog.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.physics.averages import cubic_mean
from drivetrain.sizing.candidates import BRAKE_BIT, KNOWN_FIRST, Ranking, Selection
from drivetrain.sizing.checks import shock_factor
from drivetrain.sizing.hull import fast_demands
from drivetrain.sizing.motor_brake import holding_need
from drivetrain.sizing.selection import (
    catalog_tables,
    closest_failing,
    evaluate,
    gearbox_options,
    lossy_torque,
    objective_scores,
    ranked,
    select,
    size_key,
)

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis, Margins, SelectSpec
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.sizing.candidates import Candidates
    from drivetrain.sizing.motor_fit import Demand

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


def load_tables(axis: Axis, spec: SelectSpec, brake: bool = False) -> Tables:
    """The tables of a ``motor.select`` spec, as ``selection.select`` reads them (``brake``: the brake
    variants, ``selection.catalog_tables``)."""
    motors, gb, allow_direct = catalog_tables(axis, spec, brake)
    ratio, eff, rows, row_start = gearbox_options(gb, allow_direct)
    row_group = np.zeros(0 if gb is None else len(gb), dtype=np.intp)
    of_slot = np.repeat(np.arange(len(ratio)), np.diff(row_start))
    row_group[rows[rows >= 0]] = of_slot[rows >= 0]
    sizes = size_key(motors)
    return Tables(motors=motors, gb=gb, allow_direct=allow_direct, ratios=ratio, group_eff=eff,
                  row_group=row_group, size_key=sizes, order=np.argsort(sizes, kind="stable"))


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


@dataclass
class Prepared:
    """What :func:`prepare_hulls` computed for one axis before its search: its search bounds and the
    hulls of its first motor chunk (by gearbox efficiency), computed with the axes of equal motion."""

    bounds: Search
    demands: dict[float, Demand] = field(default_factory=dict)


def selection_tables(known: dict[str, Tables], axis: Axis, spec: SelectSpec, duty: DutyCycle) -> Tables:
    """The catalog tables of this axis's selection from ``known`` (loaded on first use, then kept there)."""
    own = any(st.kind == "gearbox" for st in axis.transmission)
    brake = holding_need(axis, duty).needed
    key = repr((spec, own, brake))  # every field, floats to the last digit
    if key not in known:
        known[key] = load_tables(axis, spec, brake)
    return known[key]


def prepare_hulls(known: dict[str, Tables], pairs: list[tuple[Axis, DutyCycle]]) -> list[Prepared | None]:
    """For each (axis, duty cycle) whose selection searches smallest first: its search bounds and the
    hulls its first motor chunk needs, computed in one compiled pass for the axes of equal motion
    (the same motor-shaft speeds and accelerations: e.g. the load masses of one lead and move
    time). ``fast_demands`` gives each torque array the hull it gives it alone, so each axis's
    hulls are those ``select`` would compute (the load inertia set to the axis's own). None for the
    other pairs."""
    out: list[Prepared | None] = [None] * len(pairs)
    by_motion: dict[Any, list[tuple[int, Axis, DutyCycle, list[float]]]] = {}
    for index, (axis, duty) in enumerate(pairs):
        m = axis.spec.motor
        if axis.motor is not None or m is None or m.select is None or m.select.objective != "smallest":
            continue
        tb = selection_tables(known, axis, m.select, duty)
        bounds = search_bounds(tb, duty, m.margins, m.select)
        out[index] = Prepared(bounds)
        order = _search_order(tb, bounds)
        first = _chunk_candidates(tb, bounds, _chunk(tb, order, 0)[0]) if len(order) else None
        if first is not None:
            effs = tb.efficiencies(tb.row_group[first[1]], first[0])
            group = next((g for g in by_motion.values() if g[0][2].samples is duty.samples), None)
            if group is None:
                by_motion[len(by_motion)] = [(index, axis, duty, effs)]
            else:
                group.append((index, axis, duty, effs))
    for members in by_motion.values():
        while members:
            ref = members[0][2]
            same = [x for x in members if x[2] is ref or (x[2].period == ref.period and np.array_equal(
                x[2].omega, ref.omega) and np.array_equal(x[2].alpha, ref.alpha))]
            members = [x for x in members if not any(x is y for y in same)]
            if len(same) < 2:
                continue  # alone: the search computes its hulls as before
            owners = [(index, axis, duty, e) for index, axis, duty, effs in same for e in effs]
            demands = fast_demands(ref.omega, ref.alpha, [lossy_torque(a, d, e) for _, a, d, e in owners],
                                   ref.weights, ref.period, ref.load_inertia)
            for (index, _, duty, e), dem in zip(owners, demands, strict=True):
                if duty.load_inertia != ref.load_inertia:
                    dem = replace(dem, load_inertia=duty.load_inertia)
                prep = out[index]
                assert prep is not None
                prep.demands[e] = dem
    return out


def select_first(known: dict[str, Tables], axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins,
                 prepared: Prepared | None = None, *, whole: bool = False) -> Selection:
    """``selection.select``'s answer for its first candidate: the same selected (or closest)
    candidate, found by the search of the module docstring (``prepared``: what :func:`prepare_hulls`
    computed for this axis with this spec and margins; the hulls computed here are added to it).
    ``whole``: every candidate evaluated and ranked as ``select`` ranks them (the ranking a walk goes
    down, ``drive_select.orderable``), with the counts, but only the first candidate's row (no
    listing, Pareto front or next smaller motor)."""
    tb = selection_tables(known, axis, spec, duty)
    # the hulls computed are kept in ``prepared`` for a later ranking of the same axis (``whole``)
    demands: dict[float, Demand] = {} if prepared is None else prepared.demands

    def ev(motors: MotorTable, gb: GearboxTable | None, allow_direct: bool, effs: list[float]) -> Candidates:
        missing = [e for e in effs if e not in demands]
        if missing:  # the hulls of the efficiencies not met before, in one compiled pass
            torques = [lossy_torque(axis, duty, e) for e in missing]
            demands.update(zip(missing, fast_demands(duty.omega, duty.alpha, torques, duty.weights, duty.period,
                                                     duty.load_inertia), strict=True))
        return evaluate(axis, duty, motors, gb, margins, allow_direct=allow_direct,
                        max_inertia_ratio=spec.max_inertia_ratio, strict=spec.unknown == "fail",
                        given_demands=demands)

    if spec.objective == "smallest" and not whole:
        bounds = search_bounds(tb, duty, margins, spec) if prepared is None else prepared.bounds
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
            if int(c.unknown[best[3][0]]) & KNOWN_FIRST == BRAKE_BIT:
                # known to assemble, its brake not known: only a pair known to assemble and to hold ranks
                # before it, so only a motor whose brake's holding torque is known is still worth a chunk
                rest = order[start:]
                order = np.concatenate([order[:start], rest[np.isfinite(tb.motors.brake_holding_torque[rest])]])
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
        w = float(c.worst_margin[closest_failing(c, 1)[0]])
        if w >= tau:
            return c, sub, gb
        tau = w
    return None


def _beats_the_rest(best: Found, tb: Tables, duty: DutyCycle, next_size: float) -> bool:
    """The first ranked candidate ranks before every candidate of a motor of size key >= ``next_size``."""
    c, sub, gb, order = best
    k = order[:1]
    obj = float(objective_scores(c, k, sub, gb, "smallest", duty)[0])
    known_fit = not (int(c.unknown[k[0]]) & KNOWN_FIRST)
    return known_fit and math.isfinite(obj) and (math.isnan(next_size) or obj < next_size * 1e6)


def _summary(c: Candidates, motors: MotorTable, gb: GearboxTable | None, order: NDArray[np.intp], tb: Tables,
             spec: SelectSpec, duty: DutyCycle, evaluated_all: bool) -> Selection:
    """``select``'s answer, keys as there: the first candidate, and the counts where every candidate
    was evaluated."""
    from drivetrain.sizing.answer import SelectionSummary
    from drivetrain.sizing.reasons import candidate_answer

    summary = SelectionSummary(objective=spec.objective, motors=len(tb.motors),
                               gearbox_rows=0 if tb.gb is None else len(tb.gb), unknown_policy=spec.unknown,
                               cycles_per_hour=3600.0 / duty.period)
    if evaluated_all:
        summary.evaluated, summary.passing = len(c.motor), len(order)
        summary.passing_motors = len(np.unique(c.motor[order]))
        summary.failures_by_check, summary.unknown_by_check = c.failures(), c.unknowns()
    best: int | None = None
    if len(order):
        best = k = int(order[0])
        first = candidate_answer(c, k, motors, gb, 1)
        summary.selected = first  # the same object as the listed one: what joins it later joins both
    else:
        k = int(closest_failing(c, 1)[0])
        first = candidate_answer(c, k, motors, gb, None)
    return Selection(listed=[first], summary=summary,
                     ranking=Ranking(candidates=c, ranked=order, motors=motors, gearboxes=gb, best=best, shown=[k]))


def select_all(axis: Axis, duty: DutyCycle, spec: SelectSpec, margins: Margins) -> Selection:
    """``selection.select`` of the whole catalog (the ranking ``orderable`` walks when the search's
    first candidate has no orderable drive)."""
    return select(axis, duty, spec, margins)


__all__ = ["CHUNK", "SLACK", "Prepared", "Search", "Tables", "load_tables", "prepare_hulls", "search_bounds",
           "select_all", "select_first", "selection_tables"]
