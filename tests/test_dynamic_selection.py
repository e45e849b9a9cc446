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

ROOT = Path(__file__).resolve().parents[1]
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


def test_linear_checks_decide_before_the_simulation(dynamic: Any) -> None:
    """The static pick fails its phase margin, a linear check: it is not simulated, and its settling is
    unknown with why, never a made-up figure; the answer is simulated."""
    judged = {c["motor"]: c for c in dynamic.selection["dynamics"]["candidates"]}
    over = dynamic.selection["dynamics"]["passed_over"][0]
    first = judged[over["motor"]]
    assert first["simulated"] is False and first["settling_time_per_stop_s"] == []
    settle = next(c for c in first["checks"] if c["name"] == "settling_time")
    assert settle["status"] == "unknown" and "already fails stability_margin" in settle["note"]
    assert dynamic.selection["dynamics"]["chosen"]["simulated"] is True
    assert dynamic.selection["dynamics"]["stopped_early"] is True


def test_the_walk_stops_once_the_candidates_are_judged() -> None:
    data = copy.deepcopy(DATA)
    data["requirements"].update({"candidates": 4, "stability": {"phase_margin": "80 deg"}})
    r = size(data)
    assert r.selection["dynamics"]["judged"] == 4 and r.selection["drive_passed_over_count"] == 4
    assert "none of the 4 passing motors tried" in r.selection["drive_advice"]


def _fastest(window: str) -> Any:
    data = copy.deepcopy(DATA)
    data["motor"]["select"]["objective"] = "fastest_settling"
    data["requirements"].update({"candidates": 6, "settling": {"window": window, "time": "50 ms"},
                                 "stability": {"phase_margin": "30 deg"}})
    return size(data)


def test_fastest_settling_answers_the_candidate_that_settles_fastest() -> None:
    """Among the first 6 static passes (all meeting a 30 deg margin and 50 ms into 20 um), the answer is
    the one with the shortest worst settling time; the ones ranked before it are passed over with both
    times."""
    r = _fastest("20 um")
    dyn = r.selection["dynamics"]
    assert dyn["objective"] == "fastest_settling" and dyn["judged"] == 6
    worst = {c["motor"]: max(c["settling_time_per_stop_s"]) for c in dyn["candidates"] if c["status"] == "pass"}
    assert len(worst) >= 2
    best = min(worst, key=lambda m: worst[m])
    assert r.selection["selected"]["motor"] == best == dyn["chosen"]["motor"]
    order = [c["motor"] for c in dyn["candidates"]]
    before = order[: order.index(best)]
    assert [p["motor"] for p in r.selection["drive_passed_over"]] == before
    for p in r.selection["drive_passed_over"]:
        assert p["reason"].startswith("fastest_settling: settles in") and f"{best} in" in p["reason"]
    assert r.ok


def test_fastest_settling_needs_requirements() -> None:
    from drivetrain.axis.model import parse_axis
    from drivetrain.errors import InputError

    data = copy.deepcopy(DATA)
    del data["requirements"]
    data["motor"]["select"]["objective"] = "fastest_settling"
    with pytest.raises(InputError) as err:
        parse_axis(data)
    assert err.value.field == "motor.select.objective"
