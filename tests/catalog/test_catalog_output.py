"""The tables of ``drivetrain catalog`` (list, show, check, history) by the rules of drivetrain.terminal
(docs/architecture.md, "Terminal output"), as the sizing tables: every cell whole in a pipe; with COLUMNS
(80, 120, 200) the table fits, the vendor is abbreviated, columns are left out in the stated order and
no number or id is cut (issue 31)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from rich.cells import cell_len

from drivetrain import catalog
from drivetrain.catalog import db
from drivetrain.catalog.check import run as run_check
from drivetrain.catalog.cli import _LIST_COLUMNS, CHECK_DROP, UNVERIFIED_MARK, _cell, _list_columns
from drivetrain.catalog.schema import TABLES
from drivetrain.cli import main
from drivetrain.terminal import _frame, layout
from tests.catalog.folders import fresh_dir

ROOT = Path(__file__).resolve().parents[2]
BOX = "┏┃┡│└"
UNITS = {"N·m", "rpm", "kg·cm²", "mm", "arcmin", "A"}


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return db.builtin_db(tmp_path_factory.mktemp("catalog-output"))


@pytest.fixture(autouse=True)
def data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    base = fresh_dir(tmp_path / "data", built, monkeypatch)
    monkeypatch.setenv(db.ENV_CATALOG, "")
    monkeypatch.delenv("COLUMNS", raising=False)
    catalog._CACHE.clear()
    return base


def _run(capsys: pytest.CaptureFixture[str], *words: str) -> str:
    assert main(["catalog", *words]) == 0
    return capsys.readouterr().out


def _rows(text: str) -> list[list[str]]:
    """The body lines of the table in ``text``, split into their cells (stripped)."""
    return [[c.strip() for c in line.split("│")[1:-1]] for line in text.splitlines() if line.startswith("│")]


def _left_out(text: str) -> list[str]:
    found = re.search(r"\(left out to fit \d+ columns: ([^;]+);", " ".join(text.split()))  # the note may wrap
    return found.group(1).split(", ") if found else []


def _expected(kind: str, rows: list[dict]) -> dict[str, list[str]]:
    """Each row's cells as ``catalog list`` must print them, by id (the id without its mark)."""
    spec = TABLES[kind]
    return {row["id"]: [_cell(spec, name, row) for _, name, _ in _LIST_COLUMNS[kind]] for row in rows}


def _list_json(capsys: pytest.CaptureFixture[str], kind: str) -> list[dict]:
    return json.loads(_run(capsys, "list", "--kind", kind, "--limit", "0", "--json"))


def _same_cell(printed: str, expected: str) -> bool:
    # a motor whose rated torque is derived says so beside the number
    return printed in (expected, expected + " (derived)")


@pytest.mark.parametrize("kind", ["motor", "gearbox", "drive"])
def test_piped_list_prints_every_cell_whole_on_one_line(capsys: pytest.CaptureFixture[str], kind: str) -> None:
    expected = _expected(kind, _list_json(capsys, kind))
    text = _run(capsys, "list", "--kind", kind, "--limit", "0")
    assert "…" not in text and "left out" not in text
    rows = _rows(text)
    assert len(rows) == len(expected)  # one line per row: nothing wrapped
    for cells in rows:
        want = expected[cells[0].removesuffix(UNVERIFIED_MARK)]
        assert len(cells) == len(want)
        for printed, cell in zip(cells[1:], want[1:], strict=True):
            assert _same_cell(printed, cell), (printed, cell)
    assert f"{UNVERIFIED_MARK} unverified:" in text or UNVERIFIED_MARK not in text


@pytest.mark.parametrize("columns", [80, 120, 200])
@pytest.mark.parametrize("kind", ["motor", "gearbox", "drive"])
def test_list_fits_columns_without_cutting_a_number_or_an_id(capsys: pytest.CaptureFixture[str],
                                                             monkeypatch: pytest.MonkeyPatch, kind: str,
                                                             columns: int) -> None:
    listed = _list_json(capsys, kind)
    expected = _expected(kind, listed)
    monkeypatch.setenv("COLUMNS", str(columns))
    text = _run(capsys, "list", "--kind", kind, "--limit", "0")
    table = [line for line in text.splitlines() if line[:1] in BOX]
    assert table and max(cell_len(line) for line in table) <= columns
    titles = [title for title, _, _ in _LIST_COLUMNS[kind]]
    left_out = _left_out(text)
    drops = [title for title, _, drop in sorted(_LIST_COLUMNS[kind], key=lambda c: c[2] or 0) if drop]
    assert set(left_out) == set(drops[:len(left_out)])  # the lowest ranks first
    shown = [i for i, title in enumerate(titles) if title not in left_out]
    rows = [cells for cells in _rows(text) if cells[0]]  # the first line of each row
    assert len(rows) == len(expected)
    numbers = {i for i, c in enumerate(_list_columns(kind)) if c.number}
    assert numbers
    for cells in rows:
        ident = cells[0].removesuffix(UNVERIFIED_MARK)
        assert ident in expected, ident  # the id is whole on its line (its mark may wrap)
        want = expected[ident]
        assert len(cells) == len(shown)
        for k, i in enumerate(shown):
            if i in numbers:
                assert _same_cell(cells[k], want[i]), (titles[i], cells[k], want[i])
            elif titles[i] == "vendor":
                assert cells[k] == want[i] or (cells[k].endswith("…") and want[i].startswith(cells[k][:-1]))
    natural = layout(_list_columns(kind), list(expected.values()), None)[1]
    if _frame(natural) <= columns:  # room for the whole table: nothing left out or abbreviated
        assert not left_out and "…" not in text


def test_the_list_columns_are_left_out_in_the_documented_order() -> None:
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    doc = " ".join(doc.split())
    for kind, plural in (("motor", "motors"), ("gearbox", "gearboxes"), ("drive", "drives")):
        ranked = sorted((c for c in _LIST_COLUMNS[kind] if c[2]), key=lambda c: c[2] or 0)
        names = [" ".join(w for w in title.split(" ") if w not in UNITS) for title, _, _ in ranked]
        assert f"{plural}: {', '.join(names)}" in doc, names
    check = ", ".join(sorted(CHECK_DROP, key=CHECK_DROP.__getitem__))
    assert f"`catalog check` leaves out {check};" in doc


def _squeeze(text: str) -> str:
    return "".join(text.split())


def test_show_is_whole_in_a_pipe_and_every_character_is_printed_at_80_columns(
        capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    piped = _rows(_run(capsys, "show", "HG-KR23"))
    assert all(len(cells) == 2 for cells in piped)
    fields = dict(piped)
    assert fields["rated_torque"] == "0.64 N*m"
    electrical = fields["source: electrical"]
    assert electrical.startswith("Mitsubishi Electric") and "<https://" in electrical  # one line, with its address
    for columns in (80, 120, 200):
        monkeypatch.setenv("COLUMNS", str(columns))
        text = _run(capsys, "show", "HG-KR23")
        table = [line for line in text.splitlines() if line[:1] in BOX]
        assert max(cell_len(line) for line in table) <= columns
        rows = _rows(text)
        # a sentence wraps at spaces and a web address continues on the next line: the characters, in order,
        # are the piped ones
        assert _squeeze("".join(r[1] for r in rows)) == _squeeze("".join(v for _, v in piped))
        assert _squeeze("".join(r[0] for r in rows)) == _squeeze("".join(f for f, _ in piped))


def test_check_is_whole_in_a_pipe_and_fits_80_120_200_columns(capsys: pytest.CaptureFixture[str],
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    findings = run_check().findings
    assert findings  # the shipped catalog has excused findings, listed with --all
    rows = _rows(_run(capsys, "check", "--all"))
    assert [r[5] for r in rows] == [f.message for f in findings]  # each whole, on one line
    assert [r[6] for r in rows] == [f.excused or "-" for f in findings]
    for columns in (80, 120, 200):
        monkeypatch.setenv("COLUMNS", str(columns))
        text = _run(capsys, "check", "--all")
        table = [line for line in text.splitlines() if line[:1] in BOX]
        assert max(cell_len(line) for line in table) <= columns
        left_out = _left_out(text)
        order = sorted(CHECK_DROP, key=CHECK_DROP.__getitem__)
        assert left_out == [t for t in ("table", "origin", "field", "exception") if t in order[:len(left_out)]]
        titles = [t for t in ("table", "id", "origin", "field", "rule", "what is wrong", "exception")
                  if t not in left_out]
        rows = _rows(text)
        what = titles.index("what is wrong")
        assert _squeeze("".join(r[what] for r in rows)) == _squeeze("".join(f.message for f in findings))
        ids = [r[titles.index("id")] for r in rows if r[titles.index("id")]]
        assert ids == [f.id for f in findings]  # every id whole on its row's first line
    assert "left out to fit 80 columns" in _run_at(capsys, monkeypatch, 80, "check", "--all")


def _run_at(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, columns: int, *words: str) -> str:
    monkeypatch.setenv("COLUMNS", str(columns))
    return _run(capsys, *words)


def test_history_is_whole_in_a_pipe_and_fits_80_columns(capsys: pytest.CaptureFixture[str],
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    _run(capsys, "import", str(ROOT / "examples" / "catalog" / "motors.csv"))
    entries = catalog.history(None)
    assert entries
    piped = _rows(_run(capsys, "history"))
    assert [r[3] for r in piped] == [e["id"] for e in entries]
    assert [r[4] for r in piped] == [e["source"] or "-" for e in entries]  # the source whole, on one line
    for columns in (80, 120, 200):
        text = _run_at(capsys, monkeypatch, columns, "history")
        table = [line for line in text.splitlines() if line[:1] in BOX]
        assert max(cell_len(line) for line in table) <= columns
        rows = _rows(text)
        assert [r[0] for r in rows if r[0]] == [e["at"] for e in entries]  # the time is never cut
        assert _squeeze("".join(r[-1] for r in rows)) == _squeeze("".join(e["source"] or "-" for e in entries))
