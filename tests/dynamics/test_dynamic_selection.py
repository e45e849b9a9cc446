"""The selection that knows how the axis will move (docs/checks.md, "Dynamic selection"): with a
``requirements:`` block the walk simulates each candidate it would answer and passes over those whose
tuned loop does not meet the requirements, with the reason; without the block nothing changes."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain import cli
from drivetrain.sizing.pipeline import size

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "belt_dynamic.yaml"
DATA: dict[str, Any] = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def dynamic() -> Any:
    return size(EXAMPLE)


@pytest.fixture(scope="module")
def static() -> Any:
    data = copy.deepcopy(DATA)
    del data["requirements"]
    return size(data)


def test_the_static_pick_is_passed_over_for_how_it_moves(dynamic: Any, static: Any) -> None:
    """The smallest motor passes torque, speed and inertia ratio, but its tuned loop on the belt has too
    little phase margin for the 45 deg asked: the next one, with more rotor inertia, is the answer."""
    pick, first = dynamic.selection["selected"], static.selection["selected"]
    assert pick["motor"] != first["motor"]
    over = {p["motor"]: p for p in dynamic.selection["drive_passed_over"]}
    assert over[first["motor"]]["drive_status"] == "dynamics"
    assert over[first["motor"]]["reason"].startswith("stability_margin: velocity loop phase margin")
    dyn = dynamic.selection["dynamics"]
    assert dyn["chosen"]["motor"] == pick["motor"] and dyn["chosen"]["status"] == "pass"
    judged = {c["motor"]: c for c in dyn["candidates"]}
    assert judged[first["motor"]]["phase_margin_deg"] < 45.0 <= judged[pick["motor"]]["phase_margin_deg"]
    assert dyn["requirements"]["phase_margin_deg"] == pytest.approx(45.0)
    assert dynamic.ok


def test_the_cli_names_the_static_pick_and_why(capsys: pytest.CaptureFixture[str], static: Any) -> None:
    assert cli.main(["size", str(EXAMPLE)]) == 0
    out = capsys.readouterr().out
    assert f"passed over for how it moves: {static.selection['selected']['motor']}: stability_margin" in out
    assert "dynamics of " in out and "settling_time pass" in out
    assert cli.main(["size", str(EXAMPLE), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["selection"]["dynamics"]["judged"] >= 2


def test_requirements_no_candidate_meets_fail_the_answer(tmp_path: Path) -> None:
    data = copy.deepcopy(DATA)
    data["requirements"]["settling"] = {"window": "1 um", "time": "1 ms"}
    data["requirements"]["candidates"] = 3
    r = size(data)
    assert not r.ok and "dynamic requirements" in r.selection["drive_advice"]
    assert r.selection["dynamics"]["judged"] == 3 and r.selection["dynamics"]["chosen"] is None


def test_without_requirements_the_answer_has_no_dynamics_block(static: Any) -> None:
    assert "dynamics" not in static.selection
