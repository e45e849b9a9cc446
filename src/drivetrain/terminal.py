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
import re
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
    """The console for the tables and lines: in a pipe without colour (the usual case of a script, and of a
    file), a :class:`PlainConsole` that writes the characters rich would, without importing rich for
    them; else rich's console, wrapping at the fitted width (:func:`fitted_width`), or none at all in a
    pipe. Where it shows no colour (not a terminal, NO_COLOR ...), without rich's automatic
    highlighting of numbers and names in printed lines: highlighting only adds colour, so the
    characters are the same, for less work."""
    width = fitted_width()
    if width is None and _plain_pipe():
        return PlainConsole()
    return _rich_console(width)


def _rich_console(width: int | None) -> Any:
    """rich's console for the fitted ``width`` (None: a pipe), without highlighting where it shows no colour."""
    from rich.console import Console

    # in a pipe: no wrapping of printed lines (soft_wrap) and room for any table; the height is given
    # too, as rich keeps a width only with a height (else a TERM=dumb terminal is taken as 80 x 25)
    kw: dict[str, Any] = ({"width": width, "height": _height()} if width else
                          {"width": PIPE_WIDTH, "height": 25, "soft_wrap": True})
    console = Console(**kw)
    return console if console.color_system is not None else Console(**kw, highlight=False)


PIPE_WIDTH = 100_000
"""The width of rich's console in a pipe: room for any table; a line is never wrapped there."""


def _plain_pipe() -> bool:
    """Whether rich would show no colour on standard output (not a terminal, nor told it is one by
    ``FORCE_COLOR`` or ``TTY_COMPATIBLE``, not in a notebook) and draws its boxes with their own
    characters (a UTF encoding): then :class:`PlainConsole` writes what rich would."""
    if "FORCE_COLOR" in os.environ or os.environ.get("TTY_COMPATIBLE") == "1" or "IPython" in sys.modules:
        return False
    try:
        if sys.stdout.isatty():
            return False
    except ValueError:  # closed
        return False
    return (getattr(sys.stdout, "encoding", None) or "utf-8").lower().startswith("utf")


_CONTROL = re.compile(r"[\x00-\x09\x0b-\x1f\x7f-\x9f]")
"""What rich would change in a table's cell: a control character or a tab (removed or expanded)."""
_RICH_LINE = re.compile(r"[\x00-\x09\x0b-\x1f\x7f-\x9f]|:\S*?:")
"""What rich would change in a printed line: a control character or a tab, and a ``:name:`` emoji code; a
line with one is printed by rich itself."""
_TAG = re.compile(r"\[([a-z#/@][^[]*?)]")
"""A tag of rich's markup (``rich.markup.RE_TAGS`` without its escapes, which :func:`_markup_free` leaves
to rich)."""
_COLOURS = frozenset({"bold", "red", "green", "yellow", "bold red", "bold green", "bold yellow", "dim", "italic"})
"""The markup tags the command line prints: colour and weight only, no characters of their own."""


def _markup_free(text: str, markup: bool = True) -> str | None:
    """``text`` as rich prints it in a pipe without colour, or None where rich must print it: a control
    character, a tab or a ``:name:`` emoji code anywhere; with ``markup``, a backslash or a tag other than
    an opening colour tag of ``_COLOURS`` or ``[/]`` closing one (those are dropped, as rich drops them);
    a line long enough to be cut."""
    if len(text) >= PIPE_WIDTH // 2 or _RICH_LINE.search(text) is not None:
        return None
    if not markup or "[" not in text:
        return text
    if "\\" in text:
        return None
    depth = 0
    for tag in _TAG.findall(text):
        if tag in _COLOURS:
            depth += 1
        elif tag == "/" and depth:
            depth -= 1
        else:
            return None
    return _TAG.sub("", text)


def _plain(text: str) -> bool:
    """Whether rich prints ``text`` (a title, a column name) as it is."""
    return "[" not in text and _markup_free(text) is not None


class PlainConsole:
    """rich's console in a pipe without colour, for what it prints as plain characters: a line of text
    (``print``) and a table of :func:`print_table`; anything else (markup, a rich object ...) goes to
    rich's own console, made when first needed. rich is imported for neither: its import and its
    layout are most of the time a sizing's tables take. ``tests/cli/test_terminal.py`` compares the two
    on every example and on generated tables."""

    width = PIPE_WIDTH
    color_system = None

    def __init__(self) -> None:
        self._rich: Any = None

    @property
    def rich(self) -> Any:
        """rich's console in its place (a pipe), for what this one does not write itself."""
        if self._rich is None:
            self._rich = _rich_console(None)
        return self._rich

    def print(self, *objects: Any, markup: bool | None = None, highlight: bool | None = None, **kw: Any) -> None:
        """rich's ``Console.print``: one string without control characters or emoji codes, whose markup (if
        any) only colours, is written with a newline as rich writes it (:func:`_markup_free`); anything else
        by rich."""
        text = (_markup_free(objects[0], markup is not False)
                if len(objects) == 1 and not kw and isinstance(objects[0], str) else None)
        if text is not None:
            self.write(text + "\n")
        else:
            self.rich.print(*objects, markup=markup, highlight=highlight, **kw)

    def write(self, text: str) -> None:
        """Write and flush (as rich does after each print, so that the order against standard error holds)."""
        sys.stdout.write(text)
        sys.stdout.flush()


def _lines(cell: str) -> list[str]:
    return cell.split("\n") if cell else [""]


ONE_CELL = frozenset("†…°µ±×·–—²³≤≥Ωηωα")
"""Characters beyond ASCII the tables print that take one cell each (as rich counts them: a test compares)."""


def _cell_len(text: str) -> int:
    """Cells a text takes on a terminal, as rich counts them (wide and zero-width characters); printable ASCII
    and ``ONE_CELL`` take one cell a character, counted without importing rich."""
    if text.isprintable() and (text.isascii() or ONE_CELL.issuperset(c for c in text if not c.isascii())):
        return len(text)
    from rich.cells import cell_len

    return cell_len(text)


def _widths(col: Col, cells: Sequence[str]) -> tuple[int, int]:
    """(narrowest, natural) width of a column: a number column's narrowest is its widest cell (its
    header may wrap at spaces); a text column's is its longest word (the header's too), or
    ``ABBREVIATED_WIDTH`` when it may be shortened, or at most ``FOLDED_WIDTH`` when its words may fold."""
    cell_len = _cell_len
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
    width = fitted_width()
    shown, widths = layout(cols, rows, width)
    if isinstance(console, PlainConsole):
        text = None if width is not None else _plain_table(title, [cols[i] for i in shown],
                                                           [[r[i] for i in shown] for r in rows], widths,
                                                           show_header)
        if text is not None:
            console.write(text)
            return
        console = console.rich
    from rich.table import Table
    from rich.text import Text

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


_HEAVY_HEAD = ("┏━┳┓", "┃┃┃", "┡━╇┩", "│││", "└─┴┘")
_SQUARE = ("┌─┬┐", "│││", "", "│││", "└─┴┘")
"""rich's boxes (``rich.box.HEAVY_HEAD``, and ``SQUARE`` for a table without a header): the top rule, the
(left, divider, right) of the header row (or the first row), the rule under the header, those of the
other rows, the bottom rule."""


def _plain_table(title: str | None, cols: Sequence[Col], rows: Sequence[Sequence[str]], widths: Sequence[int],
                 show_header: bool) -> str | None:
    """The characters rich prints for this table in a pipe without colour (heavy-head box, a space of padding
    each side of a cell, every cell as wide as its column, none wrapped), or None where rich would change a
    text (markup or an emoji code in the title or a header, a control character or a tab anywhere): rich
    prints those. The title is printed as it is, as rich does in a pipe (its soft wrap: neither justified nor
    wrapped), so ``title_justify`` is not needed."""
    if not cols or min(widths) < 1:
        return None
    out: list[str] = []
    if title:  # in a pipe (rich's soft wrap) the title is printed as it is: neither justified nor wrapped
        if not _plain(title):
            return None
        out.append(title)
    box = _HEAVY_HEAD if show_header else _SQUARE
    top = box[0]
    out.append(top[0] + top[2].join(top[1] * (w + 2) for w in widths) + top[3])
    body: list[tuple[tuple[str, ...], str]] = []  # (cells, box edges of the row)
    if show_header:
        names = tuple(c.name for c in cols)
        if any("\n" in n or not _plain(n) for n in names):
            return None
        body.append((names, box[1]))
    body += [(tuple(r), box[3] if show_header or k else box[1]) for k, r in enumerate(rows)]
    for k, (cells, edges) in enumerate(body):
        if any(_CONTROL.search(c.replace("\n", " ")) for c in cells):  # a cell is rich text: no markup, no emoji
            return None
        parts = [_plain_cell(c, w, col.right) for c, w, col in zip(cells, widths, cols, strict=True)]
        for line in range(max(len(p) for p in parts)):
            out.append(edges[0] + edges[1].join(" " + (p[line] if line < len(p) else " " * w) + " "
                                                for p, w in zip(parts, widths, strict=True)) + edges[2])
        if k == 0 and show_header:
            rule = box[2]
            out.append(rule[0] + rule[2].join(rule[1] * (w + 2) for w in widths) + rule[3])
    bottom = box[4]
    out.append(bottom[0] + bottom[2].join(bottom[1] * (w + 2) for w in widths) + bottom[3])
    return "\n".join(out) + "\n"


def _plain_cell(cell: str, width: int, right: bool) -> list[str]:
    """The lines of a cell as rich justifies them in a column ``width`` wide that holds each whole: on the
    left, padded to the width; on the right, its trailing spaces dropped and padded in front."""
    if right:
        return [" " * (width - _cell_len(t)) + t for t in (ln.rstrip() for ln in _lines(cell))]
    return [ln + " " * (width - _cell_len(ln)) for ln in _lines(cell)]
