"""How the command line prints its tables and lines: whole cells in a pipe, fitted to the width on a terminal.

Every table ``drivetrain`` prints goes through :func:`print_table`: the sizing and analysis tables
(``cli/``) and those of the sub-commands that live with their subsystem (``catalog list``, ``show``,
``check``, ``history``). It sits in the base layer so that each of them may use it.

- Not a terminal (a pipe, a file) and ``COLUMNS`` not set: every table is as wide as its widest cells
  and every line as long as its text; nothing is wrapped or cut.
- A terminal, or ``COLUMNS`` set: the tables fit that width (``COLUMNS`` wins over the terminal's own
  size). A column of numbers is never narrower than its widest cell. To fit, first the text columns
  wrap at spaces (a ``fold`` column also inside a word longer than it, such as a web address), then a
  column marked ``abbreviate`` (the vendor) is shortened with "…", then the
  columns with a ``drop`` rank are left out, lowest rank first (the order is in docs/architecture.md,
  "Terminal output"); a note under the table names what was left out. A table that still does not
  fit is printed whole, wider than the terminal (the terminal wraps its lines), never cut.

Cells are plain text (no rich markup), so a name in square brackets prints as it is.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rich.console import JustifyMethod

ABBREVIATED_WIDTH = 8
"""Narrowest an ``abbreviate`` column gets on a terminal (its cells end in "…" beyond that)."""
FOLDED_WIDTH = 20
"""Narrowest a ``fold`` column gets on a terminal (a longer word continues on the next line)."""


@dataclass(frozen=True)
class Col:
    """A table column: ``number`` cells are never wrapped or cut; ``drop`` ranks the columns left out to
    fit a terminal (1 first; None: always shown); ``abbreviate`` text may end in "…" to fit; ``fold``
    text (sentences with a web address or a path) may break a word longer than the column across lines,
    every character printed; ``style`` is rich's style of its cells (colour and weight only: the
    characters are the same)."""

    name: str
    right: bool = False
    number: bool = False
    drop: int | None = None
    abbreviate: bool = False
    fold: bool = False
    style: str | None = None


def fitted_width() -> int | None:
    """The width the output must fit: ``COLUMNS`` when set to a number, else the terminal's width; None
    when standard output is not a terminal (whole cells, no width)."""
    columns = os.environ.get("COLUMNS", "")
    if columns.isdigit() and int(columns) > 0:
        return int(columns)
    if sys.stdout.isatty():
        try:
            return os.get_terminal_size(sys.stdout.fileno()).columns
        except (OSError, ValueError):  # a terminal that does not say its size
            return 80
    return None


def _height() -> int:
    """The terminal's height in lines (25 where it does not say)."""
    try:
        return os.get_terminal_size(sys.stdout.fileno()).lines or 25
    except (OSError, ValueError):
        return 25


def table_console() -> Any:
    """rich's console for the tables and lines: wrapping at the fitted width (:func:`fitted_width`), or
    none at all in a pipe. Where it shows no colour (not a terminal, NO_COLOR ...), without rich's
    automatic highlighting of numbers and names in printed lines: highlighting only adds colour, so the
    characters are the same, for less work."""
    from rich.console import Console

    width = fitted_width()
    # in a pipe: no wrapping of printed lines (soft_wrap) and room for any table; the height is given
    # too, as rich keeps a width only with a height (else a TERM=dumb terminal is taken as 80 x 25)
    kw: dict[str, Any] = ({"width": width, "height": _height()} if width else
                          {"width": 100_000, "height": 25, "soft_wrap": True})
    console = Console(**kw)
    return console if console.color_system is not None else Console(**kw, highlight=False)


def _lines(cell: str) -> list[str]:
    return cell.split("\n") if cell else [""]


def _widths(col: Col, cells: Sequence[str]) -> tuple[int, int]:
    """(narrowest, natural) width of a column: a number column's narrowest is its widest cell (its
    header may wrap at spaces); a text column's is its longest word (the header's too), or
    ``ABBREVIATED_WIDTH`` when it may be shortened, or at most ``FOLDED_WIDTH`` when its words may fold."""
    from rich.cells import cell_len

    lines = [ln for c in cells for ln in _lines(c)]
    natural = max([cell_len(col.name), *(cell_len(ln) for ln in lines)])
    header_word = max(cell_len(w) for w in col.name.split(" "))
    if col.number:
        return max([header_word, *(cell_len(ln) for ln in lines)]), natural
    longest = max([header_word, *(cell_len(w) for ln in lines for w in ln.split(" "))])
    if col.abbreviate:
        return min(natural, max(ABBREVIATED_WIDTH, header_word)), natural
    if col.fold:
        return min(longest, max(FOLDED_WIDTH, header_word)), natural
    return longest, natural


def _frame(widths: Sequence[int]) -> int:
    """Width of a rich table (heavy-head box) with these column widths: a space each side and the rules."""
    return sum(widths) + 3 * len(widths) + 1


def layout(cols: Sequence[Col], rows: Sequence[Sequence[str]], width: int | None) -> tuple[list[int], list[int]]:
    """(indices of the columns shown, their widths) for a terminal ``width`` (None: natural widths)."""
    ranges = [_widths(c, [r[i] for r in rows]) for i, c in enumerate(cols)]
    shown = list(range(len(cols)))
    if width is None:
        return shown, [ranges[i][1] for i in shown]
    droppable = sorted((c.drop, i) for i, c in enumerate(cols) if c.drop is not None)
    while _frame([ranges[i][0] for i in shown]) > width and droppable:
        shown.remove(droppable.pop(0)[1])
    widths = [ranges[i][0] for i in shown]
    spare = width - _frame(widths)
    # the spare room goes to the columns that need least to show whole, so that as few as possible wrap
    for k in sorted(range(len(shown)), key=lambda k: (ranges[shown[k]][1] - widths[k], k)):
        extra = max(0, min(spare, ranges[shown[k]][1] - widths[k]))
        widths[k] += extra
        spare -= extra
    return shown, widths


def print_table(console: Any, title: str | None, cols: Sequence[Col], rows: Sequence[Sequence[str]], *,
                show_header: bool = True, title_justify: JustifyMethod = "center") -> None:
    """Print one table on ``console`` (from :func:`table_console`) by the rules of this module; without
    ``show_header`` the column names are not printed (they still count towards the widths)."""
    from rich.table import Table
    from rich.text import Text

    width = fitted_width()
    shown, widths = layout(cols, rows, width)
    table = Table(title=title, show_header=show_header, title_justify=title_justify)
    for i, w in zip(shown, widths, strict=True):
        c = cols[i]
        table.add_column(c.name, justify="right" if c.right else "left", width=w, no_wrap=c.abbreviate,
                         overflow="ellipsis" if c.abbreviate else "fold", style=c.style or "")
    for r in rows:
        table.add_row(*(Text(r[i]) for i in shown))
    total = _frame(widths)
    if total > console.width:  # cannot fit: print whole, wider than the terminal
        old = console.size
        console.size = (total, old.height)
        try:
            console.print(table)
        finally:
            console.size = old
    else:
        console.print(table)
    left_out = [cols[i].name for i in range(len(cols)) if i not in shown]
    if left_out:
        console.print(Text(f"(left out to fit {width} columns: {', '.join(left_out)}; "
                           "a wider terminal or COLUMNS shows them)"))
