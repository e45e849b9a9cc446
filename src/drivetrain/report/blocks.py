"""The building blocks of a report: cells, tables, the verdict and the headline figures, as plain strings.

Strings are not escaped: each renderer (HTML, PDF) escapes for its medium.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

Status = Literal["pass", "unknowns", "fail", "info"]
"""``unknowns``: pass with unknowns (``SizingResult.status``, docs/checks.md, "The verdict")."""


@dataclass
class Cell:
    """A table cell: text and a style class (pass, fail, warn, muted, or "")."""

    text: str
    cls: str = ""


@dataclass
class Table:
    """A titled table. ``align`` has one letter per column: l(eft) or r(ight)."""

    key: str
    title: str
    columns: list[str]
    rows: list[list[Cell]]
    align: str
    note: str = ""
    widths: list[float] | None = None


@dataclass
class Verdict:
    """The summary at the top: pass, pass with unknowns, fail, or info (no motor given)."""

    status: Status
    headline: str
    details: list[str] = field(default_factory=list)


@dataclass
class KeyFigure:
    """A headline number: label, value with unit, and a short note."""

    label: str
    value: str
    note: str = ""
