"""``drivetrain select``: what its help says (a catalog selection even where the axis names a motor, ``--top``
motors listed), as ``size`` does everything else."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from drivetrain.cli import main
from drivetrain.cli.commands import EXIT_INPUT, selection_axis

ROOT = Path(__file__).resolve().parents[2]
NAMED = ROOT / "examples" / "belt_gantry_3m.yaml"  # names its motor by its parameters
SELECTS = ROOT / "examples" / "ball_screw.yaml"  # motor: {select: ...}


def _json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict[str, Any]:
    main(list(argv))
    out: dict[str, Any] = json.loads(capsys.readouterr().out)
    return out


def test_select_of_an_axis_that_names_a_motor_selects_from_the_catalog(capsys: pytest.CaptureFixture[str]) -> None:
    given = _json(capsys, "size", str(NAMED), "--json")
    assert given["motor"]["name"] == "servo 1.8 kW" and "candidates" not in given
    chosen = _json(capsys, "select", str(NAMED), "--json")
    assert chosen.get("motor") is None
    assert chosen["candidates"] and chosen["selection"]["selected"]["motor"]
    assert chosen["peak_torque_Nm"] == given["peak_torque_Nm"]  # the same axis, the same demand


def test_the_named_motor_gives_way_but_its_margins_and_supply_stay(tmp_path: Path) -> None:
    axis = tmp_path / "a.yaml"
    axis.write_text(SELECTS.read_text(encoding="utf-8").split("\nmotor:")[0] + "\nmotor: {id: SGM7J-04A, "
                    "supply_voltage: 230 V, margins: {torque: 1.5}, kt: 0.9}\n", encoding="utf-8")
    motor = selection_axis(str(axis))["motor"]
    assert motor == {"margins": {"torque": 1.5}, "supply_voltage": "230 V", "select": {}}


@pytest.mark.parametrize("top", [1, 3])
def test_top_is_the_number_of_motors_listed(capsys: pytest.CaptureFixture[str], top: int) -> None:
    default = _json(capsys, "select", str(NAMED), "--json")
    assert sum(1 for c in default["candidates"] if c["ok"]) == 10  # motor.select.top's default
    listed = _json(capsys, "select", str(NAMED), "--json", "--top", str(top))
    passing = [c for c in listed["candidates"] if c["ok"]]
    assert len(passing) == top
    assert len({c["motor"] for c in passing}) == top  # each motor in its best configuration
    assert listed["selection"]["selected"] == default["selection"]["selected"]


def test_top_overrides_the_files_select_top(tmp_path: Path) -> None:
    axis = tmp_path / "a.yaml"
    axis.write_text(SELECTS.read_text(encoding="utf-8"), encoding="utf-8")
    assert selection_axis(str(axis), 4)["motor"]["select"]["top"] == 4
    assert "top" not in selection_axis(str(axis))["motor"]["select"]


@pytest.mark.parametrize("top", ["0", "1001"])
def test_top_out_of_range_is_an_input_error_naming_it(capsys: pytest.CaptureFixture[str], top: str) -> None:
    assert main(["select", str(NAMED), "--top", top]) == EXIT_INPUT
    assert capsys.readouterr().err.startswith("error: --top: must be between 1 and 1000")


def test_select_of_an_axis_that_selects_is_size(capsys: pytest.CaptureFixture[str]) -> None:
    code_size = main(["size", str(SELECTS)])
    size_out = capsys.readouterr().out
    code_select = main(["select", str(SELECTS)])
    assert (code_select, capsys.readouterr().out) == (code_size, size_out)
