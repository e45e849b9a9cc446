"""The typed blocks of the axis's own checks and modes (``sizing.axis_blocks``) and the demand
(``duty.cycle.Demand``): every field documented with its unit, read by attribute, and their ``to_dict()`` the
JSON the answer had before they were typed (tests/data/json, saved with the code before the change)."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path
from typing import Any

import pytest

from drivetrain import cli
from drivetrain.duty.cycle import Demand
from drivetrain.sizing.axis_blocks import (
    AxisChecks,
    BandwidthCheck,
    GearboxCheck,
    GearboxChecks,
    GuideReport,
    MechanismCheck,
    ModeAtPosition,
    Modes,
    RatingCheck,
    own_checks,
)
from drivetrain.sizing.pipeline import size
from drivetrain.sizing.result import SizingResult
from drivetrain.sizing.verdict import collect_unknowns, failures
from tests.sizing.test_typed_blocks import assert_documented

ROOT = Path(__file__).resolve().parents[2]
JSON_DATA = ROOT / "tests" / "data" / "json"
TYPED = (RatingCheck, GuideReport, MechanismCheck, GearboxCheck, GearboxChecks, BandwidthCheck, ModeAtPosition,
         Modes, AxisChecks, Demand, SizingResult)
VOLATILE = re.compile(r'^  "(drivetrain_version|catalog_version)": .*\n', re.MULTILINE)
GEARBOX_AXIS: dict[str, Any] = {
    "axis": "rated gearbox", "mechanism": {"type": "rotary", "load": {"inertia": "0.05 kg*m^2"}},
    "transmission": [{"type": "gearbox", "ratio": 5, "max_torque": "200 N*m", "rated_torque": "1 N*m",
                      "max_input_speed": "6000 rpm"}],
    "profile": [{"move": "90 deg", "time": "0.5 s"}, {"dwell": "2 s"}],
    "motor": {"margins": {"torque": 1.2, "speed": 1.1}, "inertia": "1 kg*cm^2", "rated_torque": "2 N*m",
              "peak_torque": "6 N*m", "rated_speed": "3000 rpm", "max_speed": "6000 rpm"}}


@pytest.mark.parametrize("cls", TYPED, ids=lambda c: c.__name__)
def test_every_field_is_documented_in_order_with_its_unit(cls: type) -> None:
    assert_documented(cls)


@pytest.mark.parametrize(("name", "keys"), [
    ("ball_screw", ("guide", "mechanism_checks", "modes")), ("z_axis", ("mechanism_checks", "brake_check", "modes")),
    ("conveyor", ("slip_check", "mechanism_checks")), ("belt_gantry_3m", ("mechanism_checks", "modes"))])
def test_the_json_of_an_example_is_unchanged(name: str, keys: tuple[str, ...],
                                             capsys: pytest.CaptureFixture[str]) -> None:
    """``drivetrain size examples/NAME.yaml --json`` byte for byte against the output saved before these blocks
    were typed (``python scripts/example_json.py`` with that code; the version lines left out)."""
    assert cli.main(["size", str(ROOT / "examples" / f"{name}.yaml"), "--json"]) in (0, 1)
    out = VOLATILE.sub("", capsys.readouterr().out)
    expected = (JSON_DATA / f"{name}.json").read_text(encoding="utf-8")
    assert all(f'"{key}": ' in expected for key in keys)  # the typed blocks are in it
    assert out == expected


@pytest.mark.parametrize("name", ["ball_screw", "z_axis", "conveyor", "belt_gantry_3m"])
def test_each_block_is_typed_and_its_to_dict_is_its_json(name: str) -> None:
    from drivetrain.dynamics.mechanism_modes import size as size_with_modes

    result = size_with_modes(ROOT / "examples" / f"{name}.yaml")
    answer = result.to_dict()
    kinds = {"guide": GuideReport, "slip_check": RatingCheck, "brake_check": RatingCheck,
             "gearbox_checks": GearboxChecks}
    for key, kind in kinds.items():
        block = getattr(result, key)
        assert (block is None) == (key not in answer)
        if block is not None:
            assert isinstance(block, kind)
            assert json.dumps(block.to_dict()) == json.dumps(answer[key])
    assert all(isinstance(c, MechanismCheck) for c in result.mechanism_checks)
    assert json.dumps([c.to_dict() for c in result.mechanism_checks]) == json.dumps(answer["mechanism_checks"])
    assert json.dumps(result.own_blocks()) == json.dumps({k: answer[k] for k in result.own_blocks()})
    assert isinstance(result.metrics, Demand)
    assert list(answer)[4:4 + len(result.metrics.to_dict())] == list(result.metrics.to_dict())
    assert json.dumps(result.metrics.to_dict()) == json.dumps({k: answer[k] for k in result.metrics.to_dict()})
    if result.modes is not None:
        assert isinstance(result.modes, Modes) and json.dumps(result.modes.to_dict()) == json.dumps(answer["modes"])


def test_the_blocks_read_by_attribute() -> None:
    z = size(ROOT / "examples" / "z_axis.yaml")
    brake = z.brake_check
    assert brake.name == "brake_holding_torque" and brake.unit == "N*m" and brake.ok
    assert brake.margin == pytest.approx(brake.available / brake.required - 1.0)
    assert z.metrics.peak_torque_Nm >= z.metrics.rms_torque_Nm > 0.0
    assert z.metrics.max_speed_rpm > z.metrics.mean_speed_rpm > 0.0
    ball = size(ROOT / "examples" / "ball_screw.yaml")
    guide = ball.guide
    assert guide.actuator_peak_force_N >= guide.actuator_rms_force_N > 0.0
    assert guide.ok == all(c.ok for c in guide.checks)
    checks = {c.name: c for c in ball.mechanism_checks}
    assert checks["nut_life"].unit == "h" and checks["nut_life"].source
    assert checks["nut_life"].ok == (checks["nut_life"].margin >= 0.0)  # type: ignore[operator]


def test_a_mechanism_check_keeps_the_key_order_of_its_kind() -> None:
    judged = MechanismCheck("nut_life", 1.0, 2.0, 1.0, True, "h", "src", note="n")
    assert list(judged.to_dict()) == ["name", "required", "available", "margin", "ok", "unit", "source",
                                      "approximate", "note"]
    unknown = MechanismCheck("screw_buckling", 1.0, None, None, True, "N", "src", note="give", status="unknown")
    assert list(unknown.to_dict()) == ["name", "required", "available", "margin", "ok", "status", "unit", "source",
                                       "approximate", "note"]
    assert unknown.unknown and not unknown.failed
    bound = MechanismCheck("screw_buckling", 2.0, 1.0, -0.5, False, "N", "src", note="bound", status="fail")
    assert list(bound.to_dict())[-1] == "status" and bound.failed and not bound.unknown
    with pytest.raises(dataclasses.FrozenInstanceError):
        judged.ok = False  # type: ignore[misc]


def test_a_gantry_share_keeps_the_order_of_its_blocks() -> None:
    """A share keeps its whole axis's checks and gearbox ratings, then its load_share, then its drive's blocks."""
    from drivetrain.machine.axes import size_share

    full = size(ROOT / "examples" / "z_axis.yaml")
    share = size_share(full, 0.25)
    assert share.load_share == 0.25 and share.mechanism_checks == full.mechanism_checks
    assert share.brake_check == full.brake_check and share.gearbox_checks == full.gearbox_checks
    blocks = list(share.own_blocks())
    assert blocks.index("load_share") == len(blocks) - 1 - sum(b is not None for b in (share.drive, share.regen))
    assert list(share.to_dict())[4 + len(share.metrics.to_dict()):][:len(blocks)] == blocks
    assert "load_share" not in full.own_blocks()


def test_a_rating_check_has_a_note_only_where_one_is_said() -> None:
    keys = ["name", "required", "available", "unit", "margin", "ok", "approximate"]
    assert list(RatingCheck("slip_limit", 1.0, 2.0, "m/s^2", 1.0, True).to_dict()) == keys
    assert list(RatingCheck("slip_limit", 0.0, 2.0, "m/s^2", math.inf, True, note="x").to_dict()) == [*keys, "note"]
    assert RatingCheck("guide_pitch", 1.0, 1.0, "Nm", math.nan, True).unknown


def test_transmission_gearbox_checks_are_typed_and_judged() -> None:
    res = size(GEARBOX_AXIS)
    gear = res.gearbox_checks
    assert isinstance(gear, GearboxChecks) and len(gear.checks) == 5
    checks = {c.name: c for c in gear.checks}
    rated = checks["gearbox_rated_torque"]
    stage = res.axis.transmission[0].name
    assert rated.stage == stage and rated.unit == "N*m" and rated.status == "fail" and rated.failed
    assert rated.note is None and "note" not in rated.to_dict()
    stop = checks["gearbox_emergency_stop_torque"]  # T2NOT not given
    assert stop.unknown and stop.margin is None and stop.available is None
    assert list(stop.to_dict()) == ["name", "stage", "required", "available", "unit", "margin", "status", "ok",
                                    "approximate", "note"]
    assert gear.unknown == tuple(f"{c.stage}: {c.name}" for c in gear.checks if c.unknown)
    assert list(gear.to_dict()) == ["checks", "ok", "unknown"] and not gear.ok
    assert res.to_dict()["gearbox_checks"] == gear.to_dict()
    # the verdict reads the typed checks: what fails and what could not be judged, by stage
    assert f"gearbox: gearbox_rated_torque [{stage}]" in failures(res)
    assert any(u.check == "gearbox_emergency_stop_torque" and u.part == f"gearbox stage ({stage})"
               for u in collect_unknowns(res, sheet=False))
    assert [c for _, c in own_checks(res)] == list(gear.checks)


def test_the_demand_is_a_dataclass_of_the_json_keys() -> None:
    res = size(ROOT / "examples" / "rotary.yaml")
    demand = res.metrics.to_dict()
    assert list(demand) == [f.name for f in dataclasses.fields(Demand)]
    assert demand["segments"] is res.metrics.segments and res.metrics.segments[0]["kind"] in ("accel", "dwell")


def test_the_axis_checks_stage_returns_the_blocks_the_answer_carries() -> None:
    from drivetrain.axis.model import load_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing.pipeline import axis_checks

    axis = load_axis(ROOT / "examples" / "ball_screw.yaml")
    own = axis_checks(axis, duty_cycle(axis))
    assert isinstance(own, AxisChecks) and isinstance(own.guide, GuideReport) and own.slip_check is None
    res = size(ROOT / "examples" / "ball_screw.yaml")
    assert own.guide == res.guide and list(own.mechanism_checks) == res.mechanism_checks
    assert list(own.warnings) == res.warnings and own.brake_check == res.brake_check
