"""What a `size` loads: only the modules its answer needs (no study, web, report or pint on a run with
remembered units; numba's absence is in test_kernel.py), and the
replacements that keep it so give the values of what they replace."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from drivetrain import catalog
from drivetrain.cli import CORE_COMMANDS, _command
from drivetrain.sizing.checks import running_torque

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import json, sys
from drivetrain.cli import main
code = main(["size", sys.argv[1], "--json"])
print(json.dumps({"code": code, "modules": sorted(m for m in sys.modules if m.split(".")[0] in
      ("pint", "pandas", "dask", "matplotlib") or m.startswith(("drivetrain.study", "drivetrain.web",
      "drivetrain.catalog.cli", "drivetrain.report", "drivetrain.dynamics.simulation",
      "drivetrain.dynamics._kernel", "drivetrain.dynamics.kernel_io")))}))
"""


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, st.integers(0, 60), elements=st.floats(-1e6, 1e6, allow_subnormal=False)))
def test_running_torque_is_numpys_median_of_the_magnitudes(external: np.ndarray) -> None:
    want = float(np.median(np.abs(external))) if external.size else 0.0
    assert running_torque(external) == want


def test_running_torque_of_a_nan_sample_is_nan() -> None:
    assert np.isnan(running_torque(np.array([1.0, np.nan, 2.0])))


def test_the_command_word_is_found_past_the_global_options() -> None:
    assert _command(["size", "a.yaml"]) == "size"
    assert _command(["--catalog", "size", "simulate", "a.yaml"]) == "simulate"  # "size" is the catalog file
    assert _command(["--version"]) is None
    assert _command(["sweep", "s.yaml"]) not in CORE_COMMANDS


def test_a_size_loads_no_study_web_report_or_unit_registry(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "DRIVETRAIN_CACHE_DIR": str(tmp_path)}
    run = [sys.executable, "-c", PROBE, str(ROOT / "examples" / "ball_screw.yaml")]
    subprocess.run(run, env=env, capture_output=True, text=True, check=True)  # remembers the unit factors
    out = json.loads(subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout.splitlines()[-1])
    assert out["code"] in (0, 1)
    assert out["modules"] == []


TEXT_PROBE = """
import contextlib, io, json, sys
from drivetrain.cli import main
with contextlib.redirect_stdout(io.StringIO()):  # a pipe: the tables without rich (test_terminal.py)
    code = main(["size", sys.argv[1]])
print(json.dumps({"code": code, "rich": sorted(m for m in sys.modules if m.split(".")[0] == "rich")}))
"""


def test_a_size_in_a_pipe_imports_no_rich(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "TTY_COMPATIBLE", "COLUMNS")}
    env.update({"PYTHONPATH": str(ROOT / "src"), "DRIVETRAIN_CACHE_DIR": str(tmp_path)})
    run = [sys.executable, "-c", TEXT_PROBE, str(ROOT / "examples" / "ball_screw.yaml")]
    out = json.loads(subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout.splitlines()[-1])
    assert out["code"] in (0, 1)
    assert out["rich"] == []


def test_a_catalog_record_is_the_callers_own_copy() -> None:
    first = catalog.get("SGM7J-04A")
    first["rated_torque_Nm"] = -1.0
    first["sources"].clear()
    again = catalog.get("SGM7J-04A")
    assert again["rated_torque_Nm"] > 0 and again["sources"]


def test_the_tables_without_highlighting_are_the_same_characters(capsys: pytest.CaptureFixture[str],
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    import rich.console

    from drivetrain import terminal
    from drivetrain.cli import sizing
    from drivetrain.cli.quantities import TableUnits
    from drivetrain.sizing.pipeline import size

    monkeypatch.setattr(terminal, "_plain_pipe", lambda: False)  # rich's console (the plain one: test_terminal)
    result = size(ROOT / "examples" / "ball_screw.yaml")
    assert sizing.table_console().color_system is None  # captured: no colour, no highlighting
    sizing.print_sizing(result, TableUnits("si", result.axis.raw))
    plain = capsys.readouterr().out
    default = rich.console.Console
    monkeypatch.setattr(rich.console, "Console", lambda **kw: default(**{**kw, "highlight": True}))
    sizing.print_sizing(result, TableUnits("si", result.axis.raw))
    assert capsys.readouterr().out == plain


@pytest.mark.parametrize("columns", [None, "100", "37", "0", "-5", "wide", " 90 "])
def test_the_help_is_as_wide_as_argparse_makes_it(columns: str | None, monkeypatch: pytest.MonkeyPatch) -> None:
    import shutil

    from drivetrain.cli import _help_width, build_parser

    if columns is None:
        monkeypatch.delenv("COLUMNS", raising=False)
    else:
        monkeypatch.setenv("COLUMNS", columns)
    assert _help_width() == shutil.get_terminal_size().columns - 2
    parser = build_parser()
    assert parser._get_formatter()._width == argparse_width()  # the sub-parsers are of the same class
    assert all(type(p) is type(parser) for p in parser._subparsers._group_actions[0].choices.values())


def argparse_width() -> int:
    """What argparse's own formatter takes."""
    import argparse

    return argparse.HelpFormatter("drivetrain")._width
