"""The sizing report: one self-contained HTML file or a PDF, and the notebook view of a result.

    from drivetrain import size
    from drivetrain.report import write_report
    result = size("examples/ball_screw.yaml")
    write_report(result, "z_lift.html")                    # interactive, works offline
    write_report(result, "z_lift.pdf", units="imperial")   # A4 pages

Contents: title block and verdict; key figures and every check with its margin; the axis as a
diagram with ratios, efficiencies and inertias; the load's motion profile; the motor shaft's
speed and torque with the phases shaded, RMS and peak; the speed-torque plane with the motor's
envelopes; tables of reflected inertia, per-move torques, candidates and ratios; the inputs as
given and in SI; the formulas used with their sources; versions of software and catalog data.

Units follow ``units``: ``si`` (N·m, rpm, kg·cm², mm), ``imperial`` (lbf·in, rpm, lb·in², in)
or ``as-given`` (the units the axis file used, SI otherwise). Files are written atomically: a
temporary sibling is renamed over the target only once complete. plotly and matplotlib are
imported on first use, so ``import drivetrain`` stays fast. (``drivetrain.files`` writes every file.)
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from drivetrain.errors import InputError
from drivetrain.files import check_target, write_atomic

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

__all__ = ["REPORT_SUFFIXES", "render_html", "render_pdf", "repr_html", "write_report"]

REPORT_SUFFIXES: dict[str, str] = {".html": "html", ".htm": "html", ".pdf": "pdf"}
"""File suffixes ``write_report`` understands, and the format each writes."""


def _check_units(units: str) -> str:
    from drivetrain.units import UNIT_CHOICES

    if units not in UNIT_CHOICES:
        raise InputError("--units", f"must be one of {', '.join(UNIT_CHOICES)}", units)
    return units


def render_html(result: SizingResult, units: str = "si") -> str:
    """The report as one HTML document (plotly.js embedded, no network needed)."""
    from drivetrain.report.html import render_html as _render

    return _render(result, _check_units(units))


def repr_html(result: SizingResult, units: str = "si") -> str:
    """The report as an HTML fragment for Jupyter: same content, static SVG plots, no script."""
    from drivetrain.report.html import repr_html as _repr

    return _repr(result, _check_units(units))


def render_pdf(result: SizingResult, path: str | os.PathLike[str], units: str = "si") -> Path:
    """Write the report as a PDF (A4) to ``path``, atomically; returns the path."""
    from drivetrain.report.model import build_report
    from drivetrain.report.pdf import write_pdf

    model = build_report(result, _check_units(units))
    target = Path(path)
    return write_atomic(target, lambda tmp: write_pdf(model, tmp), "--report")


def write_report(result: SizingResult, path: str | os.PathLike[str], units: str = "si") -> Path:
    """Write an HTML (``.html``) or PDF (``.pdf``) report of ``result`` to ``path``; returns the path.

    Raises ``InputError`` for another suffix or an unknown ``units``. An existing file at
    ``path`` is replaced only by a complete report; if rendering fails it is left untouched.
    """
    target = Path(path)
    kind = REPORT_SUFFIXES.get(target.suffix.lower())
    if kind is None:
        raise InputError("--report", "must end in .html or .pdf", str(path))
    _check_units(units)
    check_target(target, "--report")
    if kind == "pdf":
        return render_pdf(result, target, units)
    data = render_html(result, units).encode("utf-8")

    def write(tmp: Path) -> None:
        tmp.write_bytes(data)

    return write_atomic(target, write, "--report")
