"""The report's mechanism section: the mechanism's own checks, and its first mode across the stroke.

``mechanism_checks_table`` lists ``mechanism_checks`` of the sizing result (screw limits, nut and
guide life, belt tension, rack force) with name, required, available, margin and source.
``mechanism_modes`` solves the N-mass chain with the mechanism's spring at positions across the
stroke (``dynamics.mechanism_modes``) for the given or selected motor; ``modes_table`` and
``modes_plot`` show f1 against the load position, the worst position, the weakest link and the
servo-bandwidth requirement (f1 >= 2 x velocity bandwidth).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.report.blocks import Cell, Table
from drivetrain.report.checks import check_value
from drivetrain.report.display import DisplayUnits, fmt_number, fmt_percent
from drivetrain.report.plots import COLORS, Note, Panel, PlotSpec, Trace, VLine

if TYPE_CHECKING:
    from collections.abc import Sequence

    from drivetrain.sizing.axis_blocks import BandwidthCheck, MechanismCheck, Modes
    from drivetrain.sizing.result import SizingResult

MECHANISM_CHECK_NAMES: dict[str, str] = {
    "screw_buckling": "Screw buckling",
    "screw_tensile_compressive": "Screw tensile/compressive",
    "screw_critical_speed": "Screw critical speed",
    "screw_dn_speed": "Screw DN value",
    "nut_life": "Nut life L10",
    "nut_static_safety": "Nut static safety",
    "guide_life": "Guide life L10",
    "guide_static_safety": "Guide static safety",
    "belt_slack_side": "Belt pretension",
    "belt_tension": "Belt tension",
    "rack_feed_force": "Rack feed force",
    "servo_bandwidth": "Servo bandwidth (f1)",
}
"""Readable names of the mechanism checks and the modes check."""


def _rows(checks: Sequence[MechanismCheck | BandwidthCheck], du: DisplayUnits) -> list[list[Cell]]:
    rows = []
    for c in checks:
        status = c.status or ("pass" if c.ok else "fail")
        style = {"pass": "pass", "fail": "fail"}.get(status, "muted")
        avail = c.available
        finite = avail is not None and math.isfinite(float(avail))
        need = math.nan if c.required is None else float(c.required)
        known = math.isfinite(need)
        rows.append([
            Cell(MECHANISM_CHECK_NAMES.get(c.name, c.name.replace("_", " "))),
            Cell(check_value(need, c.unit, du) if known else "not stated"),
            Cell(check_value(float(avail or 0.0), c.unit, du) if finite else "no limit"),
            Cell(fmt_percent(c.margin) if known else "n/a", style),
            Cell(status.upper(), style),
            Cell(c.source + (f" ({c.note})" if c.note else ""), "muted"),
        ])
    return rows


def _table(key: str, title: str, rows: list[list[Cell]], note: str) -> Table:
    return Table(key, title, ["check", "required", "available", "margin", "result", "source"], rows, "lrrrll",
                 note, [0.15, 0.1, 0.11, 0.11, 0.08, 0.45])


def mechanism_checks_table(result: SizingResult, du: DisplayUnits) -> Table | None:
    """The ``mechanism_checks`` of the result as a table, or None when the axis has none."""
    checks = result.mechanism_checks
    if not checks:
        return None
    return _table("mechanism-checks", "Checks of the mechanism", _rows(checks, du),
                  "Each check runs where the axis file gives the ratings it needs; margin = available / "
                  "required − 1; the source names the catalog procedure (docs/checks.md).")


def mechanism_modes(result: SizingResult) -> Modes | None:
    """``modes`` across the stroke for the result's motor: the answer's, where the pipeline's modes stage
    attached them (``drivetrain.size``), else that stage run on the result (``sizing.pipeline.attach_modes``
    with ``dynamics.mechanism_modes.modes_of_result``)."""
    if result.modes is not None:
        return result.modes
    from drivetrain.dynamics.mechanism_modes import modes_of_result
    from drivetrain.sizing.pipeline import attach_modes

    return attach_modes(result, modes_of_result).modes


def modes_table(modes: Modes, du: DisplayUnits) -> Table:
    """The servo-bandwidth check and the figures of the modes: f1 at the worst position, the weakest link."""
    rows = _rows(modes.checks, du)
    springs = ", ".join(f"{name} {fmt_number(k)} N·m/rad" for name, k in modes.springs_at_motor_Nm_per_rad.items())
    note = (f"Lowest first mode {fmt_number(modes.f1_min_Hz)} Hz at load position "
            f"{du.fmt(modes.worst_position_m, 'length')} with motor {modes.motor or ''}; weakest link: "
            f"{modes.weakest_link} (springs at the motor shaft there: {springs}). " + _bandwidth_text(modes))
    return _table("modes", "First mode across the stroke", rows, note)


def _bandwidth_text(modes: Modes) -> str:
    """The velocity bandwidth the check used, or that none was stated, and the most f1 allows."""
    allows = f"f1 allows up to {fmt_number(modes.max_velocity_bandwidth_Hz)} Hz."
    if modes.velocity_bandwidth_Hz is None:
        return f"Velocity bandwidth not stated (dynamics.loop.velocity_bandwidth): {allows}"
    return (f"Velocity bandwidth {fmt_number(modes.velocity_bandwidth_Hz)} Hz from {modes.bandwidth_source}; "
            f"{allows}")


def modes_plot(modes: Modes, du: DisplayUnits) -> PlotSpec:
    """f1 against the load position, the worst position marked, the required f1 as a line."""
    rows = modes.f1_by_position
    x = du.array(np.array([r.position_m for r in rows], dtype=float), "length")
    f1 = np.array([r.f1_Hz for r in rows], dtype=float)
    label = du.label("length")
    traces = [Trace(x, f1, "first natural frequency f1", COLORS["position"], unit="Hz")]
    checks = modes.checks
    need = float(checks[0].required) if checks and checks[0].required is not None else math.nan
    if math.isfinite(need):
        traces.append(Trace(x, np.full_like(f1, need), "required: 2 × velocity bandwidth", COLORS["peak"],
                            dash="dash", unit="Hz"))
    worst = float(du.array(np.array([modes.worst_position_m]), "length")[0])
    panel = Panel("f1 [Hz]", traces, vlines=[VLine(worst, "worst position", COLORS["limit"])],
                  notes=[Note(worst, float(modes.f1_min_Hz),
                              [f"f1 = {fmt_number(modes.f1_min_Hz)} Hz", modes.weakest_link],
                              COLORS["limit"], dx=-110.0, dy=30.0)], ymin=0.0)
    return PlotSpec("modes", "First natural frequency across the stroke", f"load position [{label}]", [panel],
                    "First natural frequency of the drive train with the mechanism's own spring, against the "
                    "load position; the worst position and the weakest link marked.", height=360, hover="closest")
