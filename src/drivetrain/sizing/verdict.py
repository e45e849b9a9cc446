"""The verdict of an answer in three outcomes (docs/checks.md, "The verdict"): the checks of a
``SizingResult`` that could not be judged, each with the part it concerns and what would decide it, and
what fails, read from the answer's blocks as its JSON states them."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, Protocol

from drivetrain.sizing.axis_blocks import GearboxCheck, own_checks

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.sizing.answer import MotorAnswer, SelectionSummary
    from drivetrain.sizing.axis_blocks import GearboxChecks, GuideReport, MechanismCheck, RatingCheck
    from drivetrain.sizing.checks import Check
    from drivetrain.sizing.electrical import DriveAnswer


class Answer(Protocol):
    """What the verdict reads of an answer (``SizingResult``; named here without importing it, which
    imports this module)."""

    guide: GuideReport | None
    slip_check: RatingCheck | None
    mechanism_checks: list[MechanismCheck]
    brake_check: RatingCheck | None
    gearbox_checks: GearboxChecks | None
    drive: DriveAnswer | None
    motor: MotorAnswer | None
    selection: SelectionSummary | None
    ranking: Any


Status = Literal["pass", "pass with unknowns", "fail"]
"""The three outcomes of an answer (``SizingResult.status``, docs/checks.md, "The verdict")."""


@dataclass(frozen=True)
class Unknown:
    """A check of the answer that could not be judged: its name, the part it concerns (``motor``,
    ``drive``, ``electrical``, ``gearbox`` (a catalog gearbox), ``gearbox stage (NAME)`` (one of
    ``transmission:``), ``motor-gearbox fit``, ``brake``, ``mechanism``, ``guide``, ``dynamics``) and what
    would decide it."""

    check: str
    part: str
    decide: str

    def to_dict(self) -> dict[str, str]:
        """JSON form (docs/axis-file.md, ``verdict.unknowns``)."""
        return {"check": self.check, "part": self.part, "decide": self.decide}


def unknown_fails(axis: Axis) -> bool:
    """Whether a check that cannot be judged fails the answer: ``motor.select.unknown: fail``."""
    spec = axis.spec.motor
    return spec is not None and spec.select is not None and spec.select.unknown == "fail"


def _not_judged(check: dict[str, Any]) -> bool:
    """Whether a check (a JSON check dict) could not be judged: status ``unknown``, or without a status an
    undecided ``ok`` (None) or a margin that is not a number."""
    status = check.get("status")
    if status is not None:
        return status == "unknown"
    margin = check.get("margin")
    return check.get("ok") is None or (margin is not None and isinstance(margin, float) and math.isnan(margin))


def _failed(check: dict[str, Any]) -> bool:
    status = check.get("status")
    return status in ("fail", "fails") if status is not None else check.get("ok") is False


def _check_list(block: Any) -> list[dict[str, Any]]:
    """The checks of a block: its ``checks`` list, or the block itself where it is one check."""
    if isinstance(block, list):
        return [c for c in block if isinstance(c, dict)]
    if not isinstance(block, dict):
        return []
    if isinstance(block.get("checks"), list):
        return [c for c in block["checks"] if isinstance(c, dict)]
    return [block] if "name" in block and ("ok" in block or "status" in block) else []


_OWN_PARTS: dict[str, tuple[str, str]] = {
    "slip_check": ("mechanism", "a rating it needs is not given"), "guide": ("guide", "a rating it needs is not given"),
    "brake_check": ("brake", "a rating it needs is not given"),
    "mechanism_checks": ("mechanism", "a dimension or rating it needs is not given"),
    "gearbox_checks": ("gearbox", "a rating of the gearbox is not given")}
"""The part of the answer each block of the axis's own checks concerns, and what decides a check of it that
could not be judged where the check does not say."""

_MOTOR_CHECKS = frozenset({"peak_torque", "rms_torque", "max_speed", "inertia_ratio", "speed_torque_envelope"})


def _decide(check: dict[str, Any], default: str) -> str:
    return str(check.get("note") or check.get("reason") or default)


def _motor_not_judged(check: Check) -> bool:
    """A given motor's check (``sizing.checks.Check``) that cannot be judged: its margin is NaN."""
    return math.isnan(check.margin)


def _drive_unknowns(block: DriveAnswer | None) -> list[Unknown]:
    """A drive block (``drive_select.pick_drive``, or a given motor's): unknown or none as a whole, or
    its own checks that cannot be judged."""
    if block is None:
        return []
    if block.status in ("unknown", "none"):
        what = "no drive in the catalog fits" if block.status == "none" else "cannot be checked"
        return [Unknown("drive", "drive", str(block.reason or what))]
    return [Unknown(c["name"], "drive", _decide(c, "the drive's rating is not known"))
            for c in block.checks or () if _not_judged(c)]


def collect_unknowns(result: Answer, sheet: Any = True) -> list[Unknown]:
    """Every check of the answer whose status is unknown (docs/checks.md, "The verdict"), in the order of
    the answer: the axis's own checks (load slip, guide, brake, mechanism), the transmission's gearbox
    ratings (``gearbox_checks``, the T2B shock-factor case included), the given motor (its checks and
    electrical half, drive) or the selected candidate (its checks, motor-gearbox fit, drive, voltage class,
    electrical) and the dynamic selection's chosen candidate. The regeneration block (``Regen``) holds no
    check: whether the drive's built-in braking resistor suffices is not one, since where that is not known
    the block's energy, powers and resistance window specify the external resistor to fit, which answers
    the question either way (docs/checks.md, "The verdict"). The modes' ``servo_bandwidth`` is reported,
    not judged: it is not part of the verdict."""
    out: list[Unknown] = []
    for key, own in own_checks(result):
        if not own.unknown:
            continue
        if isinstance(own, GearboxCheck):
            out.append(Unknown(own.name, f"gearbox stage ({own.stage})" if own.stage else "gearbox stage",
                               own.note or "a rating of the gearbox is not given"))
        else:
            part, default = _OWN_PARTS[key]
            out.append(Unknown(own.name, part, own.note or default))
    if result.motor is not None:
        out += [Unknown(c.name, "motor" if c.name in _MOTOR_CHECKS else "electrical",
                        c.note or "a rating of the motor is not given")
                for c in result.motor.checks if _motor_not_judged(c)]
        drive = result.drive
        out += _drive_unknowns(drive)
    elif result.selection is not None and result.selection.selected is not None:
        pick = result.selection.selected
        for row in pick.checks:
            if row.status == "unknown":
                part = ("motor" if row.name in _MOTOR_CHECKS else "brake" if row.name == "motor_brake" else
                        "motor-gearbox fit" if row.name == "mechanical_fit" else "gearbox")
                out.append(Unknown(row.name, part, row.note or "the catalog lacks a rating it needs"))
        vc = pick.voltage_class
        if vc is not None and _not_judged(vc):
            out.append(Unknown("voltage_class", "electrical", _decide(vc, "a voltage class is not known")))
        out += _drive_unknowns(pick.drive)
        out += [Unknown(c["name"], "electrical", _decide(c, "an electrical datum is not known"))
                for c in _check_list(pick.electrical) if _not_judged(c)]
        dyn = result.selection.dynamics
        chosen = dyn.get("chosen") if isinstance(dyn, dict) else None
        out += [Unknown(c["name"], "dynamics", _decide(c, "the simulation could not judge it"))
                for c in _check_list(chosen) if _not_judged(c)]
    if sheet is not False and hasattr(result, "duty"):  # a SizingResult: its order sheet (a bare Answer has none)
        out += order_unknowns(result, out, None if sheet is True else sheet)
    return out


SHEET_PARTS: dict[str, tuple[str, ...]] = {
    "motor": ("motor",), "electrical": ("motor", "drive"), "drive": ("drive",), "regen": ("drive", "braking_resistor"),
    "gearbox": ("gearbox",), "motor-gearbox fit": ("gearbox",), "brake": ("motor", "brake"), "mechanism": ("screw",),
    "guide": ("guide",)}
"""The order-sheet parts (``sizing.order_spec.PARTS``) a verdict part concerns: a part unknown in the verdict
leaves one of these rows incomplete (``gearbox stage (NAME)`` counts as ``gearbox``)."""


def sheet_parts(part: str) -> tuple[str, ...]:
    """The order-sheet parts of a verdict part (``SHEET_PARTS``); none for ``dynamics``."""
    return SHEET_PARTS.get("gearbox" if part.startswith("gearbox stage") else part, ())


def order_unknowns(result: Any, known: list[Unknown], sheet: Any = None) -> list[Unknown]:
    """What keeps a catalog part of the order sheet (``sizing.order.order_sheet``) from being ordered as
    written, as unknowns with check ``order_code`` and the sheet's part (docs/order-sheet.md, "The sheet and
    the verdict"): code positions still to choose, a holding-brake variant the catalog has no order code for,
    and any other incomplete catalog row whose part no unknown of ``known`` concerns. They are no check:
    ``motor.select.unknown: fail`` selects on checks and does not fail on them; an answer with one is
    ``pass with unknowns``, never ``pass``."""
    if sheet is None:  # the caller's sheet where it has one (``SizingResult.to_dict`` builds it once)
        import importlib  # the sheet reads the result, which imports this module: looked up by name

        sheet = importlib.import_module("drivetrain.sizing.order").order_sheet(result)
    covered = {p for u in known for p in sheet_parts(u.part)}
    out: list[Unknown] = []
    for row in sheet.rows:
        if row.kind != "catalog" or row.complete:
            continue
        own = [p for p in row.open_points if p.startswith(("code position", "holding-brake variant", "brake variant",
                                                           "confirm that"))]
        if not own and row.part not in covered:
            own = list(row.open_points)
        if own:
            text, who = "; ".join(own), str(row.catalog_id or row.name)
            out.append(Unknown("order_code", row.part, text if who in text else f"{who}: {text}"))
    return out


def failures(result: Answer) -> list[str]:
    """What fails in the answer, one short phrase each (``part: check``), in the order of
    :func:`collect_unknowns`; empty where nothing fails."""
    out: list[str] = []
    for key, own in own_checks(result):
        if own.failed:
            stage = own.stage if isinstance(own, GearboxCheck) else ""
            out.append(f"{_OWN_PARTS[key][0]}: {own.name}" + (f" [{stage}]" if stage else ""))
    if result.motor is not None:
        out += [f"motor: {c.name}" for c in result.motor.checks if not c.ok]
        drive = result.drive
        if drive is not None and (drive.status == "fails" or drive.ok is False):
            bad = ", ".join(c["name"] for c in drive.checks or () if _failed(c))
            out.append(f"drive: {drive.reason or bad}")
    elif result.selection is not None:
        sel = result.selection
        if sel.drive_advice:
            out.append(f"not orderable: {sel.drive_advice.split('; ')[0]}")
        elif sel.selected is None or result.ranking is None or result.ranking.best is None:
            out.append("no catalog motor passes every check")
    return out


__all__ = ["SHEET_PARTS", "Answer", "Status", "Unknown", "collect_unknowns", "failures", "order_unknowns",
           "sheet_parts", "unknown_fails"]
