"""The plain console of a pipe writes the characters rich writes there: every shipped example's tables and
lines, generated tables (wide, multi-line and empty cells, markup-like text, control characters) and
lines with and without markup."""

from __future__ import annotations

import contextlib
import io
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain import terminal
from drivetrain.terminal import Col, PlainConsole, print_table, table_console

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.yaml"))

_PLAIN = st.sampled_from([*"ab Z9.-/%()", "  ", "\n", "†", "…", "中", "é", "\u00a0", "[1]", "[bold]", "[/]"])
_RARE = st.sampled_from(["[", "]", "[red]", "[/red]", ":", ":smile:", "\t", "\r", "\\", "\x1b"])
TEXT = st.lists(st.integers(0, 59).flatmap(lambda k: _RARE if k == 0 else _PLAIN), max_size=10).map("".join)
"""Cells, names and lines: mostly what the plain console writes itself (wide, zero-width-free non-ASCII,
multi-line, colour markup), sometimes what it hands to rich."""


@pytest.fixture(autouse=True)
def _pipe(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("FORCE_COLOR", "TTY_COMPATIBLE", "COLUMNS"):
        monkeypatch.delenv(name, raising=False)


def _rich() -> object:
    return terminal._rich_console(None)


def test_a_pipe_gets_the_plain_console(capsys: pytest.CaptureFixture[str]) -> None:  # capsys: not a terminal
    assert isinstance(table_console(), PlainConsole)
    assert _rich().color_system is None  # type: ignore[attr-defined]  # what it stands in for shows no colour


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_every_examples_tables_are_richs_characters(example: Path, capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.cli.analyses import print_modes_across
    from drivetrain.cli.quantities import TableUnits
    from drivetrain.cli.sizing import print_sizing
    from drivetrain.dynamics.mechanism_modes import size

    result = size(example)

    def show() -> str:
        units = TableUnits("si", result.axis.raw)
        print_sizing(result, units)
        if result.modes is not None:
            print_modes_across(table_console(), result.modes, units)
        return capsys.readouterr().out

    plain = show()
    monkeypatch.setattr(terminal, "_plain_pipe", lambda: False)
    assert show() == plain


def _both(draw: Callable[[Any], None]) -> tuple[str, str]:
    """What ``draw`` writes on the plain console and on rich's, in a pipe."""
    from rich.errors import MarkupError

    out = []
    for console in (PlainConsole(), _rich()):
        with contextlib.redirect_stdout(io.StringIO()) as buf:
            try:
                draw(console)
            except MarkupError as exc:  # rich refuses bad markup; the plain console hands it to rich
                print(f"MarkupError: {exc}")
        out.append(buf.getvalue())
    return out[0], out[1]


@settings(max_examples=150, deadline=None)
@given(names=st.lists(TEXT, min_size=1, max_size=4), data=st.data(), title=st.none() | TEXT,
       show_header=st.booleans(), right=st.lists(st.booleans(), min_size=4, max_size=4))
def test_a_generated_table_is_richs_characters(names: list[str], data: st.DataObject, title: str | None,
                                               show_header: bool, right: list[bool]) -> None:
    cols = [Col(n, right=r, number=r) for n, r in zip(names, right, strict=False)]
    rows = data.draw(st.lists(st.lists(TEXT, min_size=len(cols), max_size=len(cols)), max_size=4))
    plain, rich = _both(lambda c: print_table(c, title, cols, rows, show_header=show_header))
    assert plain == rich


@settings(max_examples=150, deadline=None)
@given(text=TEXT, markup=st.sampled_from([None, True, False]))
def test_a_printed_line_is_richs_characters(text: str, markup: bool | None) -> None:
    plain, rich = _both(lambda c: c.print(text, markup=markup, highlight=False))
    assert plain == rich


def test_the_lines_the_cli_colours_are_written_without_rich(capsys: pytest.CaptureFixture[str]) -> None:
    console = PlainConsole()
    console.print("f1 375.6 Hz, [yellow]unknown[/]; [green]ok[/] [bold red]FAIL: [1, 2][/]")
    assert capsys.readouterr().out == "f1 375.6 Hz, unknown; ok FAIL: [1, 2]\n"
    assert console._rich is None


def test_the_characters_counted_as_one_cell_are_one_cell_for_rich() -> None:
    from rich.cells import cell_len

    assert all(cell_len(c) == 1 for c in terminal.ONE_CELL)
    assert all(terminal._cell_len(t) == cell_len(t) for t in ("a†b", "中文", "x\ty", "\x1b[0m", "é", "…", ""))
