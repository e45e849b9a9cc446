"""The typed blocks of a motor's answer (``sizing.answer``: ``Candidate``, ``CheckRow``, ``SelectionSummary``,
``OptimalRatio``, ``PassedOver``, ``MotorAnswer``): every field documented with its unit, each block's
``to_dict()`` the JSON saved before the blocks were typed (key order and floats included), and the Python
answer read by attribute."""

from __future__ import annotations

import ast
import copy
import dataclasses
import json
from pathlib import Path
from typing import Any

import pytest

from drivetrain.cli.commands import jsonable
from drivetrain.dynamics.mechanism_modes import size as size_with_modes
from drivetrain.sizing.answer import (
    BrakeVariant,
    Candidate,
    CheckRow,
    MotorAnswer,
    OptimalRatio,
    PassedOver,
    SelectionSummary,
)
from drivetrain.sizing.checks import Check
from drivetrain.sizing.pipeline import size
from tests.sizing.test_typed_blocks import assert_documented

ROOT = Path(__file__).resolve().parents[2]
JSON_DATA = ROOT / "tests" / "data" / "json"
TYPED = (Candidate, CheckRow, BrakeVariant, SelectionSummary, OptimalRatio, PassedOver, MotorAnswer)
SAVED = ("ball_screw", "z_axis", "hoist", "belt_gantry_3m", "belt_dynamic", "lead_screw", "rack_pinion")
"""Examples whose ``--json`` of the code before the blocks were typed is in tests/data/json/ (see
scripts/example_json.py): selections with a brake, voltage classes, drives passed over, the dynamic rule, a
next smaller motor of none, derived catalog values; a given motor behind a gearbox (belt_gantry_3m)."""


def _text(block: Any) -> str:
    """A block as ``--json`` writes it (commands.jsonable, then json.dumps): key order and float repr count."""
    return json.dumps(jsonable(block), indent=2)


@pytest.fixture(scope="module", params=SAVED)
def example(request: pytest.FixtureRequest) -> tuple[Any, dict[str, Any]]:
    """The example's answer (the pipeline with its modes stage, as ``drivetrain size``) and its saved JSON."""
    name = request.param
    saved = json.loads((JSON_DATA / f"{name}.json").read_text(encoding="utf-8"))
    return size_with_modes(ROOT / "examples" / f"{name}.yaml"), saved


@pytest.mark.parametrize("cls", TYPED, ids=lambda c: c.__name__)
def test_every_field_is_documented_in_order_with_its_unit(cls: type) -> None:
    assert_documented(cls)


def test_each_block_is_its_saved_json_byte_for_byte(example: tuple[Any, dict[str, Any]]) -> None:
    """``to_dict()`` of the selection, of every listed candidate (and its checks), of the selected one and of a
    given motor is the JSON the code wrote before these blocks were typed."""
    result, saved = example
    if result.motor is not None:
        assert isinstance(result.motor, MotorAnswer)
        assert _text(result.motor.to_dict()) == _text(saved["motor"])
    if result.selection is not None:
        assert _text(result.selection.to_dict()) == _text(saved["selection"])
        assert result.selection.selected is not None
        assert _text(result.selection.selected.to_dict()) == _text(saved["selection"]["selected"])
        assert len(result.candidates) == len(saved["candidates"])
        for cand, want in zip(result.candidates, saved["candidates"], strict=True):
            assert _text(cand.to_dict()) == _text(want)
            assert [_text(ch.to_dict()) for ch in cand.checks] == [_text(ch) for ch in want["checks"]]


def test_the_answer_reads_like_its_json(example: tuple[Any, dict[str, Any]]) -> None:
    """Attribute access gives what the JSON says: the selected motor, its checks by name, the optimal ratio, the
    motors passed over; a given motor's figures and checks."""
    result, saved = example
    if result.motor is not None:
        m, want = result.motor, saved["motor"]
        assert (m.name, m.ok, m.rms_torque_Nm, m.inertia_ratio) == (want["name"], want["ok"], want["rms_torque_Nm"],
                                                                    want["inertia_ratio"])
        assert all(isinstance(c, Check) for c in m.checks)
        peak = m.check("peak_torque")
        assert peak is not None and peak.margin == next(c for c in want["checks"] if c["name"] == "peak_torque")[
            "margin"]
        return
    sel, want = result.selection, saved["selection"]
    pick = sel.selected
    assert (pick.motor, pick.gearbox, pick.ratio, pick.rank) == (want["selected"]["motor"],
                                                                  want["selected"]["gearbox"],
                                                                  want["selected"]["ratio"], want["selected"]["rank"])
    rms = pick.check("rms_torque")
    assert isinstance(rms, CheckRow)
    assert rms.margin == next(c for c in want["selected"]["checks"] if c["name"] == "rms_torque")["margin"]
    assert pick.check("no such check") is None
    if "brake" in want["selected"]:  # a vertical axis: the brake variant, typed
        assert isinstance(pick.brake, BrakeVariant)
        assert pick.brake.holding_torque_Nm == want["selected"]["brake"]["holding_torque_Nm"]
    else:
        assert pick.brake is None
    assert isinstance(sel.optimal_ratio, OptimalRatio)
    assert sel.optimal_ratio.min_rms_ratio == want["optimal_ratio"]["min_rms_ratio"]
    assert (sel.next_smaller is None) == (want["next_smaller"] is None)
    assert [p.motor for p in sel.drive_passed_over or []] == [p["motor"] for p in want.get("drive_passed_over", [])]
    assert all(isinstance(p, PassedOver) for p in sel.drive_passed_over or [])
    assert sel.evaluated == want["evaluated"] and sel.failures_by_check == want["failures_by_check"]


def test_z_axis_attributes() -> None:
    """examples/z_axis.yaml on a 400 V supply: the selected 1FT7 with its voltage class judged and its drive, the
    200 V motors passed over for their class."""
    r = size(ROOT / "examples" / "z_axis.yaml")
    assert r.selection is not None and r.selection.selected is not None
    pick = r.selection.selected
    assert pick.voltage_class is not None and pick.voltage_class["status"] == "pass"
    assert pick.drive is not None and pick.drive.status == "ok"
    assert pick.electrical is not None and pick.electrical["supply_voltage_V"] == 400.0
    assert pick.regen is not None and pick.regen.energy_per_cycle_J > 0
    assert any(p.reason.startswith("voltage_class:") for p in r.selection.drive_passed_over or [])


def test_a_search_keeps_its_key_order_and_leaves_out_what_it_did_not_count() -> None:
    """``listing="selected"`` (the smallest-first search a study runs): the summary's keys in the search's order,
    no counts where it did not evaluate every candidate, no next smaller motor; the selected candidate is the
    listed one (one object)."""
    r = size(ROOT / "examples" / "ball_screw.yaml", listing="selected")
    assert r.selection is not None and r.selection.listing is None
    keys = list(r.selection.to_dict())
    assert keys[:5] == ["objective", "motors", "gearbox_rows", "unknown_policy", "cycles_per_hour"]
    assert "next_smaller" not in keys and "optimal_ratio" not in keys and "listing" not in keys
    assert r.candidates[0] is r.selection.selected


def test_nothing_passing_gives_advice_and_no_selected_keys() -> None:
    """A load no catalog motor moves: the summary ends with ``advice``; ``selected``, ``next_smaller`` and
    ``optimal_ratio`` are left out of the JSON (as before they were typed), and the closest candidates listed."""
    data = json.loads(json.dumps(_ball_screw_raw()))
    data["mechanism"]["load"] = {**data["mechanism"]["load"], "mass": "200000 kg"}
    r = size(data)
    assert r.selection is not None and r.selection.selected is None and r.selection.advice
    keys = list(r.selection.to_dict())
    assert keys[-1] == "advice" and not {"selected", "next_smaller", "optimal_ratio", "pareto_front"} & set(keys)
    assert r.candidates and all(not c.ok and c.rank is None for c in r.candidates)
    assert r.to_dict()["selection"] == r.selection.to_dict()


def _ball_screw_raw() -> dict[str, Any]:
    from drivetrain.axis.model import load_axis

    return copy.deepcopy(load_axis(ROOT / "examples" / "ball_screw.yaml").raw)


def test_optional_keys_only_where_the_answer_has_them() -> None:
    """A candidate's ``note``-less checks, its absent brake, drive, voltage class, electrical and regen are left
    out; ``regen`` is in wherever ``electrical`` is (null when not known), as the JSON had it."""
    row = CheckRow("max_speed", 3000.0, 5000.0, "rpm", 2000.0 / 3000.0, True, "pass", False)
    assert list(row.to_dict()) == ["name", "required", "available", "unit", "margin", "ok", "status", "approximate"]
    unknown = dataclasses.replace(row, available=None, margin=None, status="unknown", note="the catalog lacks it")
    assert unknown.to_dict()["note"] == "the catalog lacks it"
    cand = Candidate(None, "M", "V", "S", 100.0, 40.0, None, None, None, 1.0, 2.0, 0.1, 0.3, True, "ok", [], "", [],
                     False, False, None, False, None, [row])
    keys = list(cand.to_dict())
    assert keys[-3:] == ["unverified", "unverified_reason", "checks"] and "derived" not in keys
    cand.electrical = {"note": "the catalog has no electrical data for M"}
    assert list(cand.to_dict())[-2:] == ["electrical", "regen"] and cand.to_dict()["regen"] is None


def test_the_answer_fields_are_typed_not_dicts() -> None:
    """``SizingResult.motor``, ``.candidates`` and ``.selection`` and ``Selection.listed`` and ``.summary`` are
    the typed blocks, not ``dict[str, Any]`` (read from the source, as the annotations are strings)."""
    def annotations(path: Path, cls: str) -> dict[str, str]:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        node = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == cls)
        return {s.target.id: ast.unparse(s.annotation) for s in node.body
                if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)}

    sizing = ROOT / "src" / "drivetrain" / "sizing"
    result = annotations(sizing / "result.py", "SizingResult")
    assert result["motor"] == "MotorAnswer | None"
    assert result["candidates"] == "list[Candidate]"
    assert result["selection"] == "SelectionSummary | None"
    selection = annotations(sizing / "candidates.py", "Selection")
    assert selection == {"listed": "list[Candidate]", "summary": "SelectionSummary", "ranking": "Ranking"}
    for name in ("motor", "candidates", "selection"):
        assert "dict" not in result[name]
