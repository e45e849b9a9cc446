"""What the report says, independent of how it is drawn: title block, verdict, tables, plots, formulas.

:func:`build_report` reads a ``SizingResult`` once and returns a :class:`ReportModel` of plain
strings (not escaped: each renderer escapes for its medium) and plot specs in display units.
The HTML and the PDF renderers draw the same model, so they show the same numbers.

The blocks (cells, tables, verdict) are in ``report.blocks``, the checks in words and the verdict in
``report.checks``, the other tables in ``report.tables``; this module assembles them.
"""

from __future__ import annotations

import datetime as _dt
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from drivetrain.report import tables
from drivetrain.report.blocks import KeyFigure, Table, Verdict
from drivetrain.report.checks import checks_table, verdict
from drivetrain.report.diagram import Diagram, build_diagram
from drivetrain.report.display import DisplayUnits, display_units
from drivetrain.report.focus import focus_of
from drivetrain.report.formulas import Formula, formulas_for
from drivetrain.report.plots import PlotSpec, all_plots

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

__all__ = ["ReportModel", "build_report", "catalog_version", "report_date"]


@dataclass
class ReportModel:
    """Everything the report shows, as strings and plot specs."""

    title: str
    axis_name: str
    subtitle: str
    meta: list[tuple[str, str]]
    verdict: Verdict
    key_figures: list[KeyFigure]
    checks: Table | None
    diagram: Diagram
    inertia: Table
    motion: PlotSpec
    steps: Table
    motor_shaft: PlotSpec
    demand: Table
    segments: Table
    speed_torque: PlotSpec
    motor_data: Table | None
    candidates: Table | None
    ratios: Table | None
    inputs: Table
    formulas: list[Formula]
    notes: list[str]
    footer: str
    units: DisplayUnits
    mechanism_checks: Table | None = None
    modes: Table | None = None
    modes_plot: PlotSpec | None = None
    dynamics: list[Table] = field(default_factory=list)
    """how the axis will move, with requirements (drivetrain.report.dynamics)"""
    electrical: Table | None = None
    """drive, motor current, winding temperature and regen (drivetrain.report.electrical)"""
    regen: PlotSpec | None = None
    order: tuple[Table, ...] = ()
    """the order sheet: parts, then specifications and open points (drivetrain.report.order)"""


def report_date() -> str:
    """Date and time of the report (UTC from ``SOURCE_DATE_EPOCH`` when set, for reproducible files)."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch and epoch.strip().isdigit():
        return _dt.datetime.fromtimestamp(int(epoch), tz=_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return _dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z").strip()


def catalog_version(result: SizingResult) -> str:
    """The catalog data version when the sizing used the catalog, else "no catalog used"."""
    spec_motor = result.axis.spec.motor
    used = bool(result.candidates) or result.selection is not None or (
        spec_motor is not None and (spec_motor.id is not None or spec_motor.select is not None))
    if result.axis.motor is not None and result.axis.motor.source not in ("axis file", ""):
        used = True
    if not used:
        return "no catalog used"
    try:
        from drivetrain.catalog import DATA_VERSION
    except ImportError:
        return "catalog used, data version unknown"
    return str(DATA_VERSION)


def build_report(result: SizingResult, units: str = "si") -> ReportModel:
    """The report's content for ``result`` in the chosen units (si, imperial, as-given)."""
    from drivetrain.report.dynamics import dynamics_tables
    from drivetrain.report.electrical import electrical_table, regen_plot, supply_curve_traces
    from drivetrain.report.mechanism import mechanism_checks_table, mechanism_modes, modes_plot, modes_table
    from drivetrain.report.order import order_tables
    from drivetrain.version import __version__

    du = display_units(units, result.axis.raw)
    focus = focus_of(result)
    modes = mechanism_modes(result)
    supply = supply_curve_traces(result, du) if focus is not None else []
    plots = {p.key: p for p in all_plots(result, du, focus, supply)}
    notes = []
    if focus is not None:
        notes.append("The motor's speed-torque envelope is derived from its ratings (rated, stall and peak torque, "
                     "rated and maximum speed), not read from a vendor curve: a check that passes with a thin margin "
                     "is unverified until compared with the datasheet's T-n characteristic.")
    if focus is not None and focus.motor.unverified_reason:
        notes.append(f"The motor's catalog data is unverified: {focus.motor.unverified_reason}. Check the ratings "
                     "against the vendor's datasheet before relying on this sizing.")
    # An answer out of all scale with its load (a unit slip) is said first (duty.sanity).
    notes[:0] = [f"Warning: {w}" for w in result.warnings]
    notes.append(f"Efficiency model: {result.axis.efficiency_model.replace('_', ' ')}. Mechanical quantities at the "
                 "motor shaft, before motor and drive losses.")
    date = report_date()
    meta = [
        ("Date", date),
        ("Software", f"drivetrain {__version__}"),
        ("Catalog data", catalog_version(result)),
        ("Units", du.describe()),
        ("Efficiency model", result.axis.efficiency_model.replace("_", " ")),
    ]
    return ReportModel(
        title="Servo axis sizing report",
        axis_name=result.axis.name,
        subtitle=tables.subtitle(result, focus),
        meta=meta,
        verdict=verdict(result, du, focus),
        key_figures=tables.key_figures(result, du, focus),
        checks=checks_table(result, du, focus),
        diagram=build_diagram(result, du, focus),
        inertia=tables.inertia_table(result, du, focus),
        motion=plots["motion"],
        steps=tables.steps_table(result, du),
        motor_shaft=plots["motor"],
        demand=tables.demand_table(result, du, focus),
        segments=tables.segments_table(result, du, focus),
        speed_torque=plots["speed_torque"],
        motor_data=tables.motor_table(result, du, focus),
        candidates=tables.candidates_table(result, du),
        ratios=tables.ratios_table(result, du, focus),
        inputs=tables.inputs_table(result),
        formulas=formulas_for(result, focus is not None and focus.gearbox is not None),
        notes=notes,
        footer=f"drivetrain {__version__} · {date}",
        units=du,
        mechanism_checks=mechanism_checks_table(result, du),
        modes=modes_table(modes, du) if modes is not None else None,
        modes_plot=modes_plot(modes, du) if modes is not None else None,
        dynamics=dynamics_tables(result, du),
        electrical=electrical_table(result, du),
        regen=regen_plot(result, du, focus),
        order=tuple(order_tables(result)),
    )
