"""The README's figures are the ones scripts/readme_figures.py computes from the code and the catalog; the
quick start names files that exist; `make browser` stops with one line where it cannot install; the
default settling window of `simulate` is documented as the code has it (issue 31, "The README and the docs")."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
sys.path.insert(0, str(ROOT / "scripts"))

import readme_figures  # noqa: E402


def test_the_readmes_figures_are_the_ones_the_script_computes() -> None:
    figs = readme_figures.figures()
    marked = {m["name"]: m["value"] for m in readme_figures.FIGURE.finditer(README)}
    assert {"ac_servo_motors", "drives", "ball_screw_candidates", "unverified_rows"} <= set(marked)
    wrong = {name: (shown, figs[name]) for name, shown in marked.items() if figs[name] != shown}
    assert not wrong, f"README.md (shown, computed); run scripts/readme_figures.py --write: {wrong}"
    assert readme_figures.render(README, figs, readme_figures.counts()) == README


def test_the_candidate_count_is_the_one_a_sizing_answers() -> None:
    from drivetrain.sizing.pipeline import size

    evaluated = size(ROOT / "examples" / "ball_screw.yaml").selection.evaluated
    assert f"<!--fig:ball_screw_candidates-->{evaluated:,}<!--/fig-->" in README


def test_an_unknown_mark_is_refused() -> None:
    with pytest.raises(KeyError, match="no_such_figure"):
        readme_figures.render("<!--fig:no_such_figure-->1<!--/fig-->", {}, "")


def test_the_quick_start_names_files_that_exist_and_says_how_to_set_the_supply() -> None:
    quick = README.split("## Quick start", 1)[1].split("## Features", 1)[0]
    for path in re.findall(r"\b(examples/[\w/.-]+\.(?:yaml|csv|json))", quick):
        assert (ROOT / path).is_file(), path
    assert "catalog import examples/catalog/motors.csv" in quick
    assert "supply_voltage: 400 V" in quick and "dc_bus_voltage" in quick
    assert "root or `sudo`" in quick
    import yaml

    from drivetrain.axis.yaml_text import parse_yaml

    block = re.search(r"```yaml\n(motor:.*?)```", quick, re.S)
    assert block, "the supply example"
    axis = yaml.safe_load((ROOT / "examples" / "ball_screw.yaml").read_text(encoding="utf-8"))
    axis.update(yaml.safe_load(block.group(1)))
    parse_yaml(yaml.safe_dump(axis))  # the snippet is a valid part of an axis file


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_browser_stops_with_one_line_without_root_or_sudo(tmp_path: Path) -> None:
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "id").write_text("#!/bin/sh\necho 1000\n", encoding="utf-8")  # not root
    (bin_dir / "id").chmod(0o755)
    env = {**os.environ, "PATH": str(bin_dir)}  # no chromium, no pdftoppm, no sudo, no apt-get
    run = subprocess.run([shutil.which("make") or "make", "-s", "-C", str(ROOT), "browser"], env=env,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode != 0
    ours = [line for line in run.stderr.splitlines() if line.startswith("make browser:")]
    assert len(ours) == 1, run.stderr
    assert "root or sudo" in ours[0] and "chromium" in ours[0] and "poppler-utils" in ours[0]


def test_the_default_settling_window_of_simulate_is_documented() -> None:
    """The window at the load (10 um for a linear load) is the one docs/checks.md states, and the
    answer's window at the motor shaft is it times the motor angle per metre of load travel."""
    from drivetrain.axis.model import load_axis
    from drivetrain.axis.requirements import DEFAULT_WINDOW_LINEAR, DEFAULT_WINDOW_ROTARY
    from drivetrain.dynamics.axis_model import simulate_axis

    doc = (ROOT / "docs" / "checks.md").read_text(encoding="utf-8")
    section = doc.split("### Settling time in `drivetrain simulate`", 1)[1].split("\n#", 1)[0]
    assert "**10 um** for a linear load" in section and "**1 arcmin** for a rotary one" in section
    assert DEFAULT_WINDOW_LINEAR == 10e-6 and abs(DEFAULT_WINDOW_ROTARY * 180 * 60 / 3.141592653589793 - 1) < 1e-12
    axis = load_axis(ROOT / "examples" / "belt.yaml")
    res = simulate_axis(axis)
    assert res.to_dict()["settle_tolerance_rad"] == DEFAULT_WINDOW_LINEAR * axis.total_ratio
