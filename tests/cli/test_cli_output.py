"""The CLI's faces: whole cells in a pipe, tables fitted to a terminal's width without cutting a number,
zero printed as zero, and ``--help`` answered before the sizing stack is loaded (issue 31)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from drivetrain.cli.sizing import CANDIDATE_COLUMNS, _pct
from drivetrain.report.display import ZERO_TOLERANCE, snap_zero, snapped_metrics
from drivetrain.terminal import Col, _frame, layout

ROOT = Path(__file__).resolve().parents[2]

HELP_PROBE = """
import json, sys
sys.argv = ["drivetrain", *sys.argv[1:]]
from drivetrain.cli import main
try:
    main()
except SystemExit:
    pass
# (pydantic.plugin._loader is the stand-in the CLI puts in sys.modules, not pydantic)
sys.stderr.write(json.dumps(sorted(m for m in sys.modules if m in ("numpy", "pydantic", "rich")
                 or m.startswith(("numpy.", "rich.", "drivetrain.sizing", "drivetrain.axis")))))
"""


def _env(tmp_path: Path, **extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    return {**env, "PYTHONPATH": str(ROOT / "src"), "DRIVETRAIN_CACHE_DIR": str(tmp_path), **extra}


@pytest.mark.parametrize("words", [["--help"], ["size", "--help"], ["select", "-h"], ["sweep", "--help"],
                                   ["machine", "size", "--help"]])
def test_help_is_answered_without_loading_the_sizing_stack(tmp_path: Path, words: list[str]) -> None:
    run = subprocess.run([sys.executable, "-c", HELP_PROBE, *words], env=_env(tmp_path), capture_output=True,
                         text=True, check=True)
    assert "usage: drivetrain" in run.stdout
    assert json.loads(run.stderr.splitlines()[-1]) == []


def _size(tmp_path: Path, example: str, **env: str) -> tuple[str, dict]:
    args = [sys.executable, "-m", "drivetrain.cli", "size", str(ROOT / "examples" / example)]
    text = subprocess.run(args, env=_env(tmp_path, **env), capture_output=True, text=True).stdout
    answer = json.loads(subprocess.run([*args, "--json"], env=_env(tmp_path), capture_output=True, text=True).stdout)
    return text, answer


def _cells(answer: dict) -> list[str]:
    """Cells of the candidate table that must appear whole: motors, vendors and the two margins."""
    out = []
    for c in answer["candidates"]:
        checks = {ch["name"]: ch for ch in c["checks"]}
        out += [c["motor"], _pct(checks["peak_torque"]["margin"]), _pct(checks["rms_torque"]["margin"])]
    return out


def test_piped_output_prints_every_cell_whole(tmp_path: Path) -> None:
    text, answer = _size(tmp_path, "ball_screw.yaml")
    assert "…" not in text
    for cell in _cells(answer) + [c["vendor"] for c in answer["candidates"]]:
        assert cell in text, cell
    title = f"candidates: {answer['selection']['passing']} of {answer['selection']['evaluated']} configurations pass"
    assert title in text  # the title on one line, not wrapped at 120 columns
    # printed lines are not wrapped either: the regeneration sentence is one line
    assert any(line.startswith("regeneration into the bus") and line.rstrip().endswith(" W")
               for line in text.splitlines())


@pytest.mark.parametrize("columns", [80, 100, 120, 160])
def test_columns_fits_the_tables_without_cutting_a_number(tmp_path: Path, columns: int) -> None:
    text, answer = _size(tmp_path, "ball_screw.yaml", COLUMNS=str(columns))
    table = [line for line in text.splitlines() if line[:1] in "┏┃┡│└"]
    assert table and max(len(line) for line in table) <= columns
    rows = {line.split("│")[1].strip() + "|" + line.split("│")[2].strip() for line in table if line.startswith("│ ")}
    for c in answer["candidates"]:
        checks = {ch["name"]: ch for ch in c["checks"]}
        for pct in (_pct(checks["peak_torque"]["margin"]), _pct(checks["rms_torque"]["margin"])):
            assert f"│ {pct}" in text, pct  # a margin is whole on its line
    assert rows
    if columns < 120:
        assert "left out to fit" in text


def test_the_columns_are_left_out_in_the_documented_order() -> None:
    order = [c.name for c in sorted((c for c in CANDIDATE_COLUMNS if c.drop), key=lambda c: c.drop or 0)]
    assert order == ["flange", "power", "vendor", "J_L/J_M", "drive"]
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    assert "flange, power, vendor, J_L/J_M, drive" in doc


@pytest.mark.parametrize("width", [None, 30, 45, 60, 75, 90, 120, 200])
def test_layout_keeps_numbers_whole_and_fits_when_it_can(width: int | None) -> None:
    cols = (Col("name"), Col("value", number=True), Col("vendor", abbreviate=True, drop=2),
            Col("note", drop=1), Col("margin", number=True))
    rows = [("a long name here", "1234.5678 N*m", "Mitsubishi Electric", "some words to wrap", "+33.3 %"),
            ("b", "-0.0001 N*m", "FANUC", "x", "-1.0 %")]
    shown, widths = layout(cols, rows, width)
    for i, w in zip(shown, widths, strict=True):
        if cols[i].number:
            assert w >= max(len(r[i]) for r in rows)
    assert 1 in shown and 4 in shown  # number columns without a drop rank are never left out
    if width is None:
        assert shown == [0, 1, 2, 3, 4]
    elif _frame([len("value"), 13, 7]) <= width:
        assert _frame(widths) <= width
    if width is not None and 3 not in shown:
        assert 2 not in shown or _frame(widths) <= width  # the note (rank 1) goes before the vendor (rank 2)


def test_a_round_off_residue_prints_as_zero() -> None:
    assert snap_zero(3.79e-14, 3993.0) == 0.0
    assert snap_zero(-2e-10, 1.0) == 0.0
    assert snap_zero(4e-6 * 3993.0, 3993.0) == 4e-6 * 3993.0  # small but real stays
    assert snap_zero(1e-20, 0.0) == 1e-20  # no scale: unchanged
    assert ZERO_TOLERANCE == 1e-9
    m = snapped_metrics({"peak_power_W": 3993.0, "average_power_W": 3.79e-14, "peak_torque_Nm": 2.0,
                         "run_torque_Nm": -1e-15, "rms_torque_Nm": 1.0})
    assert m["average_power_W"] == 0.0 and m["run_torque_Nm"] == 0.0 and m["rms_torque_Nm"] == 1.0


def test_the_demand_table_prints_a_zero_average_power_as_zero(capsys: pytest.CaptureFixture[str],
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.cli.sizing import print_sizing
    from drivetrain.sizing.pipeline import size

    monkeypatch.delenv("COLUMNS", raising=False)
    result = size(ROOT / "examples" / "ball_screw.yaml")
    result.metrics.average_power_W = 3.79e-14 * result.metrics.peak_power_W / 3993.0
    print_sizing(result)
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "peak / average power" in ln)
    assert line.rstrip(" │").endswith(" / 0 W") and "e-" not in line


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="no pseudo-terminal")
def test_on_a_terminal_the_tables_fit_its_width(tmp_path: Path) -> None:
    import fcntl
    import struct
    import termios

    columns = 90
    main_fd, child_fd = os.openpty()
    fcntl.ioctl(child_fd, termios.TIOCSWINSZ, struct.pack("HHHH", 50, columns, 0, 0))
    env = {**_env(tmp_path), "NO_COLOR": "1", "TERM": "dumb"}
    proc = subprocess.Popen([sys.executable, "-m", "drivetrain.cli", "size", str(ROOT / "examples" / "belt.yaml")],
                            stdin=subprocess.DEVNULL, stdout=child_fd, stderr=subprocess.PIPE, env=env)
    os.close(child_fd)
    chunks = []
    while True:
        try:
            chunk = os.read(main_fd, 65536)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        chunks.append(chunk)
    proc.wait(timeout=120)
    os.close(main_fd)
    text = b"".join(chunks).decode("utf-8", "replace").replace("\r\n", "\n")
    table = [line for line in text.splitlines() if line[:1] in "┏┃┡│└"]
    assert table and max(len(line) for line in table) <= columns, max(len(line) for line in table)
    assert "left out to fit 90 columns" in text
    answer = json.loads(subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", "--json",
                                        str(ROOT / "examples" / "belt.yaml")], env=_env(tmp_path),
                                       capture_output=True, text=True).stdout)
    for c in answer["candidates"]:
        checks = {ch["name"]: ch for ch in c["checks"]}
        for pct in (_pct(checks["peak_torque"]["margin"]), _pct(checks["rms_torque"]["margin"])):
            assert f"│ {pct}" in text, pct  # a margin is whole on its line
        for word in c["motor"].split(" "):  # a name may wrap at its spaces, never inside a word
            assert word in text, c["motor"]
