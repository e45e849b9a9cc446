"""The sizing pipeline: one answer in every face, no hidden state (docs/architecture.md, "The sizing pipeline")."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import drivetrain
from drivetrain import cli
from drivetrain.cli.commands import jsonable
from drivetrain.sizing.pipeline import Context, size, size_duty, size_many

ROOT = Path(__file__).parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.yaml"))


def _keys(obj: Any, path: str = "") -> list[str]:
    """Every mapping key of a JSON object, with its path."""
    if isinstance(obj, dict):
        return [k for key, v in obj.items() for k in [f"{path}.{key}", *_keys(v, f"{path}.{key}")]]
    if isinstance(obj, list):
        return [k for i, v in enumerate(obj) for k in _keys(v, f"{path}[{i}]")]
    return []


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_size_json_is_to_dict_of_drivetrain_size(example: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``drivetrain size X --json`` prints ``drivetrain.size(X).to_dict()``: the same object, modes included,
    and no key of it starts with ``_``."""
    code = cli.main(["size", str(example), "--json"])
    printed = json.loads(capsys.readouterr().out)
    result = drivetrain.size(example)
    assert code == (0 if result.ok else 1)
    assert printed == json.loads(json.dumps(jsonable(result.to_dict())))
    assert not [k for k in _keys(printed) if k.rsplit(".", 1)[-1].startswith("_")]


def test_size_is_size_many_of_one_and_many_equal_each_alone() -> None:
    axes = [ROOT / "examples" / "ball_screw.yaml", ROOT / "examples" / "belt.yaml", ROOT / "examples" / "z_axis.yaml"]
    together = [r.to_dict() for r in size_many(axes)]
    assert together == [size(a).to_dict() for a in axes]
    assert [r.ok for r in size_many(axes)] == [size(a).ok for a in axes]


def test_a_selection_found_first_is_the_ranked_selections_pick() -> None:
    """``listing="selected"`` (the study's search) selects the candidate the whole ranking selects, with
    the same checks, and lists it alone."""
    path = ROOT / "examples" / "ball_screw.yaml"
    ranked, first = size(path), size(path, listing="selected")
    assert ranked.selection is not None and first.selection is not None
    assert first.selection.selected == ranked.selection.selected
    assert len(first.candidates) == 1 and first.ok == ranked.ok
    assert first.ranking is not None and ranked.ranking is not None
    assert first.ranking.best is not None


def test_the_pipeline_from_a_duty_cycle_equals_the_whole_pipeline() -> None:
    path = ROOT / "examples" / "z_axis.yaml"
    context = Context()
    axis = drivetrain.load_axis(str(path))
    assert size_duty(axis, context.duty(axis), context=context).to_dict() == size(path).to_dict()


def test_the_modes_stage_is_the_callers() -> None:
    """Sizing does not import dynamics: the modes stage runs only when a caller passes it."""
    path = ROOT / "examples" / "ball_screw.yaml"
    assert size(path).modes is None and "modes" not in size(path).to_dict()
    with_modes = drivetrain.size(path)
    assert with_modes.modes is not None and list(with_modes.to_dict())[-3:] == ["modes", "order", "verdict"]


def test_no_hidden_state_in_the_sizing_layer() -> None:
    """No stash on other objects, no cache keyed by id(), no module-level memo, no ``_`` answer keys."""
    # web/server.py keeps each running uvicorn server's pending connections by its ServerState (a registry of
    # the server's own connections, not a memo of answers): the one module left out
    text = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "src" / "drivetrain").glob("**/*.py")
                     if p.parent.name in ("sizing", "study", "machine", "web", "cli", "report")
                     and p.name != "server.py")
    for needle in ('"_best"', '"_candidates"', '"_ranked"', '"_tables"', '"_shown"', '"_drive"', '"_regen"',
                   "duty.__dict__", "[id(", "WeakKeyDictionary"):
        assert needle not in text, needle


def test_the_answer_reads_like_the_table() -> None:
    """The selected motor's own peak and RMS torque with its rotor, beside the demand and its ratings, and
    the cycle with load-side and motor-side columns."""
    res = size(ROOT / "examples" / "ball_screw.yaml")
    assert res.selection is not None
    pick = res.selection.selected
    table = res.torques()
    assert table.attrs["motor"] == pick.motor
    assert table.loc["peak_torque_Nm", "demand"] == res.metrics.peak_torque_Nm
    assert table.loc["peak_torque_Nm", "motor"] == pytest.approx(pick.peak_torque_Nm, rel=1e-12)
    assert table.loc["rms_torque_Nm", "motor"] == pytest.approx(pick.rms_torque_Nm, rel=1e-12)
    assert table.loc["rms_torque_Nm", "motor"] > table.loc["rms_torque_Nm", "demand"]  # the rotor adds torque
    df = res.to_pandas()
    assert {"load_x", "load_v", "shaft_torque_Nm", "motor_speed_rad_s", "motor_torque_Nm"} <= set(df.columns)
    assert float(abs(df["motor_torque_Nm"]).max()) == pytest.approx(pick.peak_torque_Nm, rel=1e-12)
    given = size(ROOT / "examples" / "belt_gantry_3m.yaml")
    assert given.motor is not None
    assert given.torques().loc["rms_torque_Nm", "motor"] == pytest.approx(given.motor.rms_torque_Nm, rel=1e-12)


def test_a_study_result_is_its_table_as_pandas() -> None:
    import pandas as pd

    from drivetrain.study import StudyResult

    table = pd.DataFrame({"variant": [0, 1], "ok": [True, False]})
    assert StudyResult(study=None, table=table).to_pandas() is table  # type: ignore[arg-type]


def test_machine_size_json_is_to_dict_of_size_machine(capsys: pytest.CaptureFixture[str],
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """``drivetrain machine size M --json`` prints ``drivetrain.size_machine(M).to_dict()``."""
    monkeypatch.chdir(ROOT / "examples" / "machine")
    code = cli.main(["machine", "size", "pick_and_place.yaml", "--json"])
    printed = json.loads(capsys.readouterr().out)
    result = drivetrain.size_machine("pick_and_place.yaml")
    assert code in (0, 1)
    assert printed == json.loads(json.dumps(jsonable(result.to_dict())))
    assert not [k for k in _keys(printed) if k.rsplit(".", 1)[-1].startswith("_")]
