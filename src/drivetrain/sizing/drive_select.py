"""Drives for a catalog selection: a post-pass after the motor/gearbox selection.

For each listed candidate (and the selected one) this picks the smallest catalog drive of the
motor's vendor and supply voltage that passes the current checks, honouring the vendors' pairing
tables (``catalog.drive_pairs``), and, for the selected candidate, adds the electrical answer:
motor currents, the envelope at the supply voltage, the winding temperature and the regen block
(``drivetrain.sizing.electrical``). A drive given in the axis file (``drive: {id: ...}``) is
checked instead of picked.

The rules (docs/checks.md, "Drive selection"):

* motor current over the cycle: I = T / K_t (with the datasheet's saturation where it prints the
  peak current), from the candidate's own torque over its own cycle;
* a drive passes when RMS current <= its continuous current, peak current <= its peak current and,
  where the vendor prints how long the peak may last, the I^2 t accumulator stays below its
  set point (``drivetrain.physics.drive_overload``);
* candidates: the drives the pairing table lists for the motor; without an entry, the drives of
  the motor's vendor whose supply voltage matches the motor's (within ``catalog.VOLTAGE_TOLERANCE``;
  a voltage missing on either side matches, and the answer says so) and, where a drive lists the
  motor series it runs (``motor_series``), whose list holds the motor's series;
* smallest: least continuous current, then least peak current;
* by vendor pairing: where the pairing table names the motor's drives and the currents cannot be
  checked (the motor has no torque constant, or no paired drive has both current ratings), the
  smallest paired drive is judged by the pairing itself. The vendor states that drive for the motor,
  so it delivers the motor's rated torque continuously and its peak torque momentarily: the drive
  passes when the motor's RMS torque over the cycle <= its rated torque and its peak torque <= its
  peak torque (``judged_by: vendor pairing``, flagged unverified where the pairing is a third-party
  transcription); beyond those ratings it is ``unknown`` (the pairing says nothing there). A drive
  that only lists the motor series it runs (``motor_series``) names no drive size and is not a
  pairing;
* a motor without a torque constant, or drives without current ratings, and no pairing, give
  ``status: unknown`` with the reason; no candidate drive at all gives ``status: none``;
* the selected motor is the best-ranked passing one whose drive can be ordered (``orderable``, run
  by ``size`` whether or not the post-pass is): one whose drive fails is passed over, and under
  ``unknown: fail`` so is one whose drive cannot be checked; the answer names them and why.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.axis.electrical import DriveData, MotorElectrical, drive_from_catalog_row, electrical_from_catalog_row
from drivetrain.errors import InputError
from drivetrain.physics import drive_overload, motor_electrical
from drivetrain.sizing.answer import PassedOver
from drivetrain.sizing.electrical import (
    DriveAnswer,
    Regen,
    _check,
    _drive_block,
    _regen_block,
    dc_bus,
    electrical_answer,
)
from drivetrain.sizing.voltage_class import stated_supply, voltage_class_check

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis, Margins, MotorData
    from drivetrain.catalog.tables import DriveTable, MotorTable
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.sizing.candidates import Ranking, Selection


def catalog_electrical(motor_id: str) -> MotorElectrical:
    """The catalog motor's electrical data (its electrical columns; empty where not known)."""
    from drivetrain import catalog

    row = catalog.motor_row(motor_id)  # the motor's columns (read once, see attach_drives)
    return electrical_from_catalog_row(catalog.get(motor_id) if row is None else row)


def _currents(cycle: DutyCycle, inertia: float, elec: MotorElectrical, rated: float,
              peak: float) -> np.ndarray | None:
    """|I(t)| [A rms] of the motor over its cycle, or None without a torque constant."""
    kt = motor_electrical.torque_constant(elec.kt, elec.ke)
    if kt is None:
        return None
    sat = motor_electrical.saturation(rated, peak, elec.peak_current)
    return motor_electrical.phase_current(cycle.motor_torque(inertia), kt, sat)


@dataclass
class DriveMemo:
    """What the drive rule reads of the catalog, kept for the axes of one sizing run (a ``size_many``
    call, or a study's worker): each drive table's rows as DriveData and their ``motor_series``
    prefixes, and each catalog motor's drive prospect. Keyed by the catalog's table objects, which are
    immutable and new whenever the catalog changes."""

    drives: dict[DriveTable, tuple[DriveData, ...]] = field(default_factory=dict)
    series: dict[DriveTable, tuple[tuple[str, ...], ...]] = field(default_factory=dict)
    prospects: dict[tuple[MotorTable, int, DriveData | None], DriveAnswer] = field(default_factory=dict)
    unverified: dict[str, str] = field(default_factory=dict)

    def drive_data(self, table: DriveTable) -> tuple[DriveData, ...]:
        """Every row of a drive table as DriveData, once per table; its unverified rows noted in
        ``unverified`` (id -> why; schema.trace)."""
        found = self.drives.get(table)
        if found is None:
            found = self.drives[table] = tuple(drive_from_catalog_row(table.row(i)) for i in range(len(table)))
            for i in np.flatnonzero(table.unverified):
                self.unverified[str(table.ids[i])] = str(table.unverified_reason[i])
            for i in np.flatnonzero(~table.unverified):
                self.unverified.pop(str(table.ids[i]), None)
        return found

    def series_prefixes(self, table: DriveTable) -> tuple[tuple[str, ...], ...]:
        """Each drive's ``motor_series`` prefixes, once per table."""
        found = self.series.get(table)
        if found is None:
            found = self.series[table] = tuple(_prefixes(text) for text in table.motor_series)
        return found

    def motor_prospect(self, motors: MotorTable, m: int, given: DriveData | None) -> DriveAnswer:
        """``prospect``'s block for row ``m`` of a motor table, once per table and row."""
        key = (motors, m, given)
        found = self.prospects.get(key)
        if found is None:
            if len(self.prospects) > 8192:  # a study's worker meets many sub-tables: keep the memo small
                self.prospects.clear()
            found = self.prospects[key] = prospect(str(motors.ids[m]), str(motors.vendor[m]),
                                                   _motor_voltage(motors, m), given, self)[1]
        return found


PAIRING_BASIS = "vendor pairing table"
"""The ``basis`` of a drive block whose candidates are the pairing table's (``catalog.drive_pairs``)."""


def _prefixes(text: object) -> tuple[str, ...]:
    """A ``motor_series`` text as case-folded prefixes (space- or comma-separated; empty: not stated)."""
    return tuple(p.casefold() for p in re.split(r"[\s,]+", str(text or "")) if p)


def _pool(motor_id: str, vendor: str, voltage: float,
          memo: DriveMemo | None = None) -> tuple[list[DriveData], str, str]:
    """The drives a motor may use, the basis and, when the series rule left none, why: the pairing
    table's, else its vendor's at its voltage whose ``motor_series`` (where a drive states one) holds
    the motor's series as a prefix (case-insensitive)."""
    from drivetrain import catalog

    memo = DriveMemo() if memo is None else memo
    pairs = catalog.drive_pairs().get(motor_id)
    if pairs:
        return list(memo.drive_data(catalog.drives(ids=pairs))), PAIRING_BASIS, ""
    try:
        table = catalog.drives(vendor=vendor) if vendor else catalog.drives()
    except InputError:  # the catalog has no drive of this vendor
        return [], "vendor and supply voltage", ""
    series = str((catalog.motor_row(motor_id) or {}).get("series") or "")
    out, other, by_series = [], [], False
    for i, (drive, runs) in enumerate(zip(memo.drive_data(table), memo.series_prefixes(table), strict=True)):
        v = float(table.voltage[i])
        if math.isfinite(voltage) and math.isfinite(v) and abs(v - voltage) > catalog.VOLTAGE_TOLERANCE * voltage:
            continue
        if runs:
            by_series = True
            if not (series and any(series.casefold().startswith(p) for p in runs)):
                other.append(str(table.motor_series[i]))
                continue
        out.append(drive)
    if by_series:
        basis = ("vendor, voltage and motor series" if math.isfinite(voltage)
                 else "vendor and motor series (the motor's voltage is not known)")
    else:
        basis = "vendor and supply voltage" if math.isfinite(voltage) else "vendor (the motor's voltage is not known)"
    why = ""
    if other and not out:
        where = " at its supply voltage" if math.isfinite(voltage) else ""
        why = (f"the catalog has no {vendor} drive for this motor's series ({series or 'not given'}): the {vendor} "
               f"drives{where} run only the motor series {'; '.join(dict.fromkeys(other))} (their motor_series)")
    return out, basis, why


def prospect(motor_id: str, vendor: str, voltage: float, given: DriveData | None = None,
             memo: DriveMemo | None = None) -> tuple[list[DriveData], DriveAnswer, MotorElectrical]:
    """What can be said of a motor's drive before its current is known: the drives it may use, the
    block's ``basis`` and ``candidates``, and (``status`` and ``reason`` in the block) why its drive
    cannot be checked: no torque constant (``unknown``), no drive (``none``), no drive with current
    ratings (``unknown``). A block whose ``status`` is None means the drive can be checked."""
    from drivetrain import catalog

    elec = catalog_electrical(motor_id)
    if given is not None:
        pool, basis, why = [given], "given in the axis file", ""
    else:
        pool, basis, why = _pool(motor_id, vendor, voltage, memo)
    base = DriveAnswer("not checked", basis=basis, candidates=tuple(d.name for d in pool))
    first = pool[0].name if len(pool) == 1 else None
    runs = () if given is None else _prefixes(given.motor_series)
    series = str((catalog.motor_row(motor_id) or {}).get("series") or "") if runs else ""
    if runs and not (series and any(series.casefold().startswith(p) for p in runs)):
        # the given drive cannot run this motor at all: it fails, whatever the current
        base = replace(base, status="fails", id=given.name if given else None, ok=False, checks=(),
                       reason=f"the given drive runs only the motor series {given.motor_series if given else ''} "
                              f"(its motor_series), not {series or 'a motor of no stated series'}")
    elif given is None and basis == PAIRING_BASIS and pool:
        pass  # checkable: by the currents where both are known, else by the pairing (pick_drive)
    elif elec.kt is None and elec.ke is None:
        base = replace(base, status="unknown", id=first, ok=None,
                       reason=f"the catalog has no torque constant for {motor_id}: its current, and so the drive, "
                              "cannot be checked")
    elif not pool:
        base = replace(base, status="none", id=None, ok=None,
                       reason=why or f"the catalog has no {vendor} drive for this motor's supply voltage")
    elif not any(math.isfinite(d.continuous_current) and math.isfinite(d.peak_current) for d in pool):
        base = replace(base, status="unknown", id=first, ok=None,
                       reason=f"no {vendor} drive in the catalog has current ratings (data/SOURCES.md, \"Drives\")")
    return pool, base, elec


def pick_drive(cycle: DutyCycle, inertia: float, motor_id: str, vendor: str, voltage: float,
               rated: float, peak: float, given: DriveData | None = None,
               memo: DriveMemo | None = None) -> tuple[DriveAnswer, DriveData | None]:
    """The drive block of one candidate and the DriveData chosen (None when none can be named).

    ``status``: ``ok`` (a drive passes), ``fails`` (the largest drive with ratings fails; or the
    given drive fails), ``unknown`` (no torque constant, or no drive with current ratings),
    ``none`` (no drive of the vendor and voltage in the catalog).
    """
    memo = DriveMemo() if memo is None else memo
    pool, base, elec = prospect(motor_id, vendor, voltage, given, memo)
    current = _currents(cycle, inertia, elec, rated, peak)
    if current is not None:
        base = replace(base, motor_rms_current_A=float(drive_overload.rms_current(current, cycle.weights,
                                                                                  cycle.period)),
                       motor_peak_current_A=float(current.max()) if current.size else 0.0)
    if base.status is not None:
        named = [d for d in pool if d.name == base.id]
        return base, (named[0] if named else None)
    checkable = [d for d in pool if math.isfinite(d.continuous_current) and math.isfinite(d.peak_current)]
    if current is None or not checkable:  # a paired motor whose current cannot be checked (prospect)
        return _by_pairing(base, pool, cycle, inertia, motor_id, rated, peak)
    i_rms, i_peak = base.motor_rms_current_A, base.motor_peak_current_A
    assert i_rms is not None and i_peak is not None
    rated_drives = sorted((d for d in pool if math.isfinite(d.continuous_current) and math.isfinite(d.peak_current)),
                          key=lambda d: (d.continuous_current, d.peak_current))
    chosen = rated_drives[-1]
    for d in rated_drives:
        block = _drive_block(d, cycle, current, i_rms, i_peak)
        if block.ok:
            chosen = d
            break
    else:
        block = _drive_block(chosen, cycle, current, i_rms, i_peak)
    # a catalog drive whose ratings are a third-party transcription says so (data/SOURCES.md, "Drives")
    unverified = given is None and chosen.name in memo.unverified
    return replace(block, layout="currents", basis=base.basis, candidates=base.candidates, motor_rms_current_A=i_rms,
                   motor_peak_current_A=i_peak, status="ok" if block.ok else "fails", vendor=chosen.vendor,
                   supply_voltage_V=chosen.supply_voltage, peak_time_s=chosen.peak_time, unverified=unverified,
                   unverified_reason=memo.unverified[chosen.name] if unverified else None), chosen


def _by_pairing(base: DriveAnswer, pool: list[DriveData], cycle: DutyCycle, inertia: float, motor_id: str,
                rated: float, peak: float) -> tuple[DriveAnswer, DriveData]:
    """The drive block of a motor judged by its vendor pairing (docs/checks.md, "Drive selection").

    The pairing table names the drive(s) the vendor states for the motor; a stated drive delivers the
    motor's rated torque continuously and its peak torque momentarily. So the drive's current checks
    pass when the motor's RMS torque [N m] over the cycle (the same weighted RMS as the currents,
    ``drive_overload.rms_current``) <= the rated torque and its peak torque <= the motor's peak torque;
    beyond either the pairing says nothing and the block is ``unknown``. The smallest paired drive
    (least continuous, then peak current, unknown last; the table's order on equal ratings) is named.
    Source of the pairings: data/drives_pairing.csv (data/SOURCES.md, "Drives").
    """
    from drivetrain import catalog

    def size(d: DriveData) -> tuple[float, float]:
        return (d.continuous_current if math.isfinite(d.continuous_current) else math.inf,
                d.peak_current if math.isfinite(d.peak_current) else math.inf)

    chosen = min(pool, key=size)
    torque = np.abs(cycle.motor_torque(inertia))
    t_rms = float(drive_overload.rms_current(torque, cycle.weights, cycle.period))
    t_peak = float(torque.max()) if torque.size else 0.0
    pair = catalog.drive_pair_sources().get((motor_id, chosen.name), {})
    third_party = pair.get("verified") is False
    says = f"{chosen.name} is the drive the pairing table states for {motor_id}" + (
        " (a third-party transcription, not verified)" if third_party else "")
    checks = [_check("drive_continuous_by_pairing", t_rms, rated, "N*m",
                     f"{says}: it delivers the motor's rated torque continuously"),
              _check("drive_peak_by_pairing", t_peak, peak, "N*m",
                     f"{says}: it delivers the motor's peak torque momentarily")]
    ok = all(c.ok for c in checks) and math.isfinite(rated) and math.isfinite(peak)
    why = ("the catalog has no torque constant for " + motor_id if base.motor_rms_current_A is None
           else "no paired drive has both current ratings")
    reason = (f"by vendor pairing ({why}): the cycle stays within the motor's rated and peak torque, which the "
              "paired drive delivers" if ok else
              f"{why}, and the cycle needs more than the motor's rated or peak torque, beyond what the pairing "
              "states: the drive cannot be judged by its pairing")
    cont, top = chosen.continuous_current, chosen.peak_current
    return replace(base, layout="pairing", id=chosen.name, vendor=chosen.vendor, judged_by="vendor pairing",
                   pairing_source=pair.get("source"), checks=tuple(c.to_dict() for c in checks),
                   continuous_current_A=cont if math.isfinite(cont) else None,
                   peak_current_A=top if math.isfinite(top) else None, status="ok" if ok else "unknown",
                   ok=True if ok else None, reason=reason, supply_voltage_V=chosen.supply_voltage,
                   peak_time_s=chosen.peak_time, unverified=third_party,
                   unverified_reason=f"motor-drive pairing from {pair.get('source')}" if third_party else None), chosen


def _motor_voltage(motors: MotorTable, m: int) -> float:
    return float(motors.voltage[m])


_WALK = 200
"""Passing motors tried, in ranked order, for one whose drive passes (each costs one current trace)."""


def _candidate_drive(axis: Axis, duty: DutyCycle, ranking: Ranking, k: int,
                     memo: DriveMemo) -> tuple[DriveAnswer, DriveData | None]:
    """The drive block of candidate ``k`` (its own cycle behind its own gearbox) and the drive chosen."""
    from drivetrain.sizing.selection import candidate_cycle

    cycle, inertia = candidate_cycle(axis, duty, ranking, k)
    motors = ranking.motors
    m = int(ranking.candidates.motor[k])
    return pick_drive(cycle, inertia, str(motors.ids[m]), str(motors.vendor[m]), _motor_voltage(motors, m),
                      float(motors.rated_torque[m]), float(motors.peak_torque[m]), axis.drive, memo)


def _drive_reason(block: DriveAnswer) -> str:
    """Why a candidate's drive is not an answer, in one sentence."""
    if block.status == "fails" and block.reason:  # a given drive that cannot run the motor
        return f"its drive fails: {block.reason}"
    if block.status == "fails":
        bad = [ch["name"] for ch in block.checks or () if not ch.get("ok", True)]
        return f"its drive fails: the largest it may use, {block.id}, fails {', '.join(bad)}"
    return f"its drive is {block.status}: {block.reason or ''}"


Judge = Callable[[str, str | None], tuple[bool, str]]
"""A further rule a candidate must pass once its drive can be ordered: (motor id, catalog gearbox id or
None) -> (accepted, why not). The dynamic selection is one (``dynamics.dynamic_selection.Judge``)."""


def _walk(axis: Axis, duty: DutyCycle, ranking: Ranking, strict: bool,
          memo: DriveMemo, judge: Judge | None = None) -> tuple[int | None, list[PassedOver]]:
    """The first passing motor (best configuration, ranked order) whose drive can be ordered.

    A drive is an answer when it passes its current checks (``ok``); under ``unknown: flag`` a drive
    that cannot be checked (``unknown``, ``none``) is an answer too, marked so, but one that fails is
    not: a motor no drive can feed cannot be ordered. Returns the candidate (None when no motor within
    the first ``_WALK`` has one) and the motors passed over with why.
    """
    from drivetrain.sizing.selection import best_per_motor

    c, motors = ranking.candidates, ranking.motors
    passed: list[PassedOver] = []
    supply = stated_supply(axis)
    for k in best_per_motor(c, ranking.ranked)[:_WALK]:
        if judge is not None and getattr(judge, "exhausted", False):
            break  # the rule judged all it may: the rest would be refused unjudged
        m = int(c.motor[k])
        vc = voltage_class_check(supply, _motor_voltage(motors, m))
        if vc is not None and (vc["status"] == "fail" or (strict and vc["status"] == "unknown")):
            passed.append(PassedOver(str(motors.ids[m]), f"voltage_class {vc['status']}",
                                     f"voltage_class: {vc['note']}"))
            continue
        block = memo.motor_prospect(motors, m, axis.drive)
        if block.status is None:  # checkable: its current decides
            block, _ = _candidate_drive(axis, duty, ranking, int(k), memo)
        if block.status == "ok" or (not strict and block.status != "fails"):
            if judge is None:
                return int(k), passed
            gb = ranking.gearboxes
            g = int(c.gearbox(int(k)))
            ok, why = judge(str(motors.ids[m]), str(gb.ids[g]) if g >= 0 and gb is not None else None)
            if ok:
                return int(k), passed
            passed.append(PassedOver(str(motors.ids[m]), "dynamics", why))
            continue
        passed.append(PassedOver(str(motors.ids[m]), str(block.status), _drive_reason(block)))
    return None, passed


def _needs_walk(axis: Axis, duty: DutyCycle, ranking: Ranking, strict: bool, memo: DriveMemo) -> bool:
    """Whether the best-ranked motor's drive keeps it from being the answer (cheap when its drive
    cannot be checked: no current trace then)."""
    assert ranking.best is not None
    best = ranking.best
    vc = voltage_class_check(stated_supply(axis), _motor_voltage(ranking.motors, int(ranking.candidates.motor[best])))
    if vc is not None and (vc["status"] == "fail" or (strict and vc["status"] == "unknown")):
        return True
    block = memo.motor_prospect(ranking.motors, int(ranking.candidates.motor[best]), axis.drive)
    if block.status is not None:
        return strict
    block, _ = _candidate_drive(axis, duty, ranking, best, memo)
    return block.status != "ok"


def orderable(axis: Axis, duty: DutyCycle, chosen: Selection, reselect: Callable[[], Selection] | None = None,
              memo: DriveMemo | None = None, judge: Judge | None = None) -> Selection:
    """The selection with an orderable drive (docs/checks.md, "Drive selection"), in place.

    The selected motor becomes the best-ranked passing one whose drive can be ordered (``_walk``);
    the motors passed over for their drive go to ``selection.drive_passed_over``; when none
    qualifies the best-ranked stays, ``selection.drive_advice`` says why and the answer fails.
    ``reselect`` gives the whole ranked selection where ``chosen`` ranks only near its pick (the
    search of ``listing="selected"``); it is called only when the best-ranked motor's drive matters.
    """
    if chosen.ranking.best is None:
        return chosen
    memo = DriveMemo() if memo is None else memo
    spec = axis.spec.motor.select if axis.spec.motor is not None else None
    strict = spec is not None and spec.unknown == "fail"
    if judge is None and not _needs_walk(axis, duty, chosen.ranking, strict, memo):
        return chosen
    if reselect is not None:
        chosen = reselect()
    sel, ranking = chosen.summary, chosen.ranking
    best, passed = _walk(axis, duty, ranking, strict, memo, judge)
    if passed:  # the first ones, and how many in all
        sel.drive_passed_over, sel.drive_passed_over_count = passed[:20], len(passed)
    if best is None:  # keep the best-ranked motor and say why it cannot be ordered
        rule = "passes its current checks" + (" (unknown: fail)" if strict else "") + (
            " and passes the dynamic requirements" if judge is not None else "")
        sel.drive_advice = (f"none of the {len(passed)} passing motors tried has a drive that {rule}; "
                            f"the best-ranked, {passed[0].motor}: {passed[0].reason}")
    elif best != ranking.best:
        _reselect(axis, duty, chosen, best, passed)
    return chosen


def attach_drives(axis: Axis, duty: DutyCycle, chosen: Selection, margins: Margins | None,
                  memo: DriveMemo | None = None) -> None:
    """Add a ``drive`` block to every listed candidate and to ``selection.selected`` (in place).

    The selected candidate (made orderable by ``orderable`` before) also gets ``electrical`` (motor
    currents, envelope source, winding temperature, with their checks) and ``regen`` (energy into
    the bus, braking resistor).
    """
    memo = DriveMemo() if memo is None else memo
    sel, ranking = chosen.summary, chosen.ranking
    c, motors, shown = ranking.candidates, ranking.motors, ranking.shown
    from drivetrain import catalog

    ks = [k for _, k in zip(chosen.listed, shown, strict=False)]
    ks += [ranking.best] if sel.selected is not None and ranking.best is not None else []
    catalog.motor_rows([str(motors.ids[int(c.motor[k])]) for k in ks])  # one query for the motors below
    done: dict[int, tuple[DriveAnswer, DriveData | None]] = {}
    supply = stated_supply(axis)
    for cand, k in zip(chosen.listed, shown, strict=False):
        done[k] = _candidate_drive(axis, duty, ranking, k, memo)
        cand.drive = done[k][0]
        vc = voltage_class_check(supply, _motor_voltage(ranking.motors, int(ranking.candidates.motor[k])))
        if vc is not None:
            cand.voltage_class = vc
    if sel.selected is None or ranking.best is None:
        return
    best = ranking.best
    block, drive = done[best] if best in done else _candidate_drive(axis, duty, ranking, best, memo)
    from drivetrain.sizing.selection import candidate_cycle

    cycle, _ = candidate_cycle(axis, duty, ranking, best)
    pick = sel.selected
    pick.drive = block
    vc = voltage_class_check(supply, _motor_voltage(motors, int(c.motor[best])))
    if vc is not None:
        pick.voltage_class = vc
    pick.electrical, pick.regen = selected_electrical(axis, cycle, motors, int(c.motor[best]), drive, margins)


def _reselect(axis: Axis, duty: DutyCycle, chosen: Selection, best: int, passed: list[PassedOver]) -> None:
    """Make candidate ``best`` the selection: its row, the next smaller motor (the last one passed
    over for its drive, which is smaller) and its optimal ratio."""
    from drivetrain.sizing.reasons import candidate_answer
    from drivetrain.sizing.selection import best_per_motor, next_smaller, optimal_ratio, size_key

    sel, ranking = chosen.summary, chosen.ranking
    c, motors, gb = ranking.candidates, ranking.motors, ranking.gearboxes
    order = [int(k) for k in best_per_motor(c, ranking.ranked)]
    ranking.best = best
    sel.selected = candidate_answer(c, best, motors, gb, order.index(best) + 1)
    # the last one passed over that is smaller: a candidate known to assemble or to hold with its brake ranks
    # before a smaller one not known to (selection.ranked), so the one just before may be larger
    size = size_key(motors)
    before = order[:order.index(best)]  # each passed over, in the order of ``passed`` (_walk)
    smaller = [i for i, k in enumerate(before) if size[c.motor[k]] < size[c.motor[best]]]
    if smaller:
        last, last_why = before[smaller[-1]], passed[smaller[-1]]
        nxt = candidate_answer(c, last, motors, gb, None)
        why = last_why.reason if last_why.drive_status == "dynamics" or last_why.reason.startswith(
            "voltage_class:") else f"drive: {last_why.reason}"
        nxt.failed, nxt.failures = why, [why]
        sel.next_smaller = nxt
    else:
        sel.next_smaller = next_smaller(c, motors, gb, best)
    sel.optimal_ratio = optimal_ratio(axis, duty, motors, int(c.motor[best]), gb)


def selected_electrical(axis: Axis, cycle: DutyCycle, motors: MotorTable, m: int, drive: DriveData | None,
                        margins: Margins | None) -> tuple[dict[str, Any], Regen | None]:
    """``electrical`` (the figures joining the selected candidate: ``Candidate.electrical``) and ``regen`` of the
    selected motor with its drive (None where not known)."""
    from drivetrain import catalog
    from drivetrain.axis.model import motor_from_catalog_row

    mid = str(motors.ids[m])
    elec = catalog_electrical(mid)
    voltage = float(motors.voltage[m])
    spec = axis.spec.motor
    if spec is not None and (spec.supply_voltage is not None or spec.dc_bus_voltage is not None):
        # the machine's supply, given beside the selection, wins (docs/axis-file.md)
        elec = replace(elec, supply_voltage=spec.supply_voltage, dc_bus_voltage=spec.dc_bus_voltage,
                       sources=(*elec.sources, "axis file (supply)"))
    elif elec.supply_voltage is None and math.isfinite(voltage):
        elec = replace(elec, supply_voltage=voltage)
    motor: MotorData = motor_from_catalog_row(catalog.get(mid))
    rated_drive = drive if drive is not None and math.isfinite(drive.continuous_current) else None
    regen_drive = drive
    if not elec.any:
        return ({"envelope_source": "derived" if motor.approximate_envelope else "datasheet", "rms_current_A": None,
                 "peak_current_A": None, "winding_temperature_rise_K": None,
                 "note": f"the catalog has no electrical data for {mid}"},
                _mechanical_regen(cycle, motor, regen_drive, elec))
    ax = replace(axis, electrical=elec, drive=rated_drive)
    try:
        ans = electrical_answer(ax, cycle, motor, margins)
    except Exception as exc:  # an electrical datum the model needs is missing: say so, keep the answer
        from drivetrain.errors import InputError

        if not isinstance(exc, InputError):
            raise
        return ({"note": str(exc), "winding_temperature_rise_K": None},
                _mechanical_regen(cycle, motor, regen_drive, elec))
    electrical = {**ans.motor, "checks": [ch.to_dict() for ch in ans.checks]}
    if ans.curve is not None:
        electrical["curve"] = ans.curve
    regen = ans.regen
    if rated_drive is None and regen_drive is not None:
        regen = _mechanical_regen(cycle, motor, regen_drive, elec)
    return electrical, regen


def _mechanical_regen(cycle: DutyCycle, motor: MotorData, drive: DriveData | None,
                      elec: MotorElectrical) -> Regen:
    """The regen block from the motor torque and speed (copper loss where R and K_t are known)."""
    t_m = cycle.motor_torque(motor.inertia)
    current = np.zeros_like(t_m)
    if elec.kt is not None:
        current = np.abs(t_m) / elec.kt
    _, bus = dc_bus(elec, drive)
    return _regen_block(cycle, t_m, current, elec, drive, bus)
