"""Plausibility of bare numbers (a bare number is SI; one implausible in SI and plausible in the usual
unit is refused naming the likely unit), and warnings for a physically absurd answer (issue 12)."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain.axis.model import parse_axis
from drivetrain.errors import InputError
from drivetrain.fields import PLAUSIBLE, plausibility
from drivetrain.sizing.pipeline import size

SCREW: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "16 mm", "length": "0.5 m",
                  "load": {"mass": 20, "friction": 0.1}},
    "transmission": [{"type": "gearbox", "ratio": 3, "inertia": "0.2 kg*cm^2"}],
    "motor": {"inertia": "0.3 kg*cm^2", "rated_torque": 1.3, "peak_torque": 3.8, "max_speed": "6000 rpm"},
    "profile": [{"move": 0.2, "time": 1.0, "accel": 0.2}, {"dwell": 0.5}],
}


def with_value(path: str, value: Any) -> dict[str, Any]:
    data = copy.deepcopy(SCREW)
    node: Any = data
    keys = path.replace("[", ".").replace("]", "").split(".")
    for key in keys[:-1]:
        node = node[int(key)] if key.isdigit() else node[key]
    node[keys[-1]] = value
    return data


def refusal(path: str, value: Any) -> str:
    with pytest.raises(InputError) as err:
        parse_axis(with_value(path, value))
    assert err.value.field == path
    return str(err.value)


def test_the_issues_incline() -> None:
    msg = refusal("mechanism.incline", 90)
    assert msg.startswith("mechanism.incline: 90 rad is 5157 deg; write '90 deg'")


@pytest.mark.parametrize(("path", "value", "suggestion"), [
    ("mechanism.lead", 10, "write '10 mm'"),
    ("mechanism.lead", "5", "write '5 mm'"),
    ("mechanism.diameter", 16, "write '16 mm'"),
    ("mechanism.length", 500, "write '500 mm'"),
    ("mechanism.density", 7.85, "write '7.85 g/cm^3'"),
    ("mechanism.efficiency", 90, "write '90 %' or 0.9"),
    ("mechanism.load.mass", 250_000, "write '250000 g'"),
    ("motor.max_speed", 3000, "3000 rad/s is 28648 rpm; write '3000 rpm'"),
    ("motor.rated_speed", 2000, "write '2000 rpm'"),
    ("motor.inertia", 1.2, "write '1.2 kg*cm^2'"),
    ("transmission[0].inertia", 2, "write '2 kg*cm^2'"),
    ("transmission[0].backlash", 5, "write '5 arcmin'"),
])
def test_bare_numbers_in_the_usual_unit_are_refused_with_it(path: str, value: Any, suggestion: str) -> None:
    msg = refusal(path, value)
    assert suggestion in msg
    assert msg.startswith(f"{path}: ")


@pytest.mark.parametrize(("path", "value"), [
    ("mechanism.incline", "90 rad"),      # written with a unit: the user's explicit choice
    ("mechanism.lead", "10 m"),
    ("mechanism.diameter", "6 m"),
    ("motor.max_speed", "3000 rad/s"),
    ("motor.inertia", "1.2 kg*m^2"),
    ("mechanism.incline", 1.0),           # 57 deg: plausible in SI
    ("mechanism.lead", 0.02),
    ("motor.max_speed", 628.0),           # 6000 rpm in rad/s
    ("mechanism.efficiency", 0.9),
    ("mechanism.density", 7850),
])
def test_plausible_or_explicit_values_pass(path: str, value: Any) -> None:
    parse_axis(with_value(path, value))


def test_an_efficiency_a_little_above_one_gets_the_bound() -> None:
    assert "must be <= 1" in refusal("mechanism.efficiency", 1.5)


def test_every_rule_has_its_unit_and_says_so() -> None:
    """Each rule refuses just past its limit and converts into its usual unit (pint parses it)."""
    from drivetrain.fields import _RULE_QUANTITY
    from drivetrain.units import parse

    for name, rule in PLAUSIBLE.items():
        x = rule.high * 1.5 if rule.high is not None else rule.low / 2  # type: ignore[operator]
        if rule.ceiling is not None:
            x = min(x, rule.ceiling)
        msg = plausibility(x, x, name)
        assert msg is not None and f"write '{x:g} {rule.usual}'" in msg, name
        assert parse(f"{x:g} {rule.usual}", _RULE_QUANTITY[name], name) != x, name
        assert plausibility(f"{x:g} {rule.usual}", x, name) is None


def test_refused_through_the_cli_with_exit_2(tmp_path: Path) -> None:
    path = tmp_path / "axis.yaml"
    path.write_text(yaml.safe_dump(with_value("mechanism.incline", 90)), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", str(path)], capture_output=True,
                          text=True, timeout=120, check=False)
    assert proc.returncode == 2
    assert "mechanism.incline: 90 rad is 5157 deg; write '90 deg'" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_refused_through_the_web_api_at_the_field() -> None:
    pytest.importorskip("fastapi")
    pytest.importorskip("httpx")
    from fastapi.testclient import TestClient

    from drivetrain.web.app import create_app

    with pytest.MonkeyPatch.context() as mp:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            mp.setenv("DRIVETRAIN_DATA_DIR", tmp)
            with TestClient(create_app(Path(tmp)), base_url="http://127.0.0.1") as client:
                r = client.post("/api/size", json=with_value("mechanism.lead", 10))
    assert r.status_code == 422, r.text
    body = r.json()
    assert body["field"] == "mechanism.lead"
    assert body["detail"].startswith("mechanism.lead: 10 m is 10000 mm; write '10 mm'")


# --------------------------------------------------------------------------- absurd answers


def table(profile_move: Any, time: float) -> dict[str, Any]:
    """A 40 kg steel table, 500 mm across, turned by a given motor."""
    return {"mechanism": {"type": "rotary", "diameter": "500 mm", "mass": 40},
            "profile": [{"move": profile_move, "time": time, "accel": time / 3}, {"dwell": 0.5}]}


def test_a_sensible_axis_has_no_warnings() -> None:
    assert size(SCREW).warnings == []
    assert size(table("90 deg", 0.5)).warnings == []


def test_an_absurd_torque_for_the_load_is_warned() -> None:
    """90 written bare is 90 rad (14 turns) in 0.2 s: the table's rim would accelerate at ~250 g."""
    res = size(table(90, 0.2))
    warnings = res.warnings
    assert len(warnings) == 1 and "times its weight at its rim" in warnings[0]
    assert res.to_dict()["warnings"] == warnings


def test_an_absurd_linear_force_and_speed_are_warned() -> None:
    """200 written bare in the profile is 200 m in 1 s (the user meant mm)."""
    res = size(with_value("profile", [{"move": 200, "time": 1.0, "accel": 0.2}, {"dwell": 0.5}]))
    text = " | ".join(res.warnings)
    assert "times its weight and process forces" in text
    assert "peak speed is 250 m/s" in text
    assert "motor speed reaches" in text


def test_the_cli_prints_the_warnings(tmp_path: Path) -> None:
    path = tmp_path / "axis.yaml"
    path.write_text(yaml.safe_dump(table(90, 0.2)), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", str(path)], capture_output=True,
                          text=True, timeout=120, check=False)
    assert "warning: the peak torque at the motor shaft" in proc.stdout
    js = subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", str(path), "--json"], capture_output=True,
                        text=True, timeout=120, check=False)
    assert json.loads(js.stdout)["warnings"]


ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted([*ROOT.glob("examples/*.yaml"), *ROOT.glob("tests/axes/*.yaml")])


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_no_shipped_example_is_warned(path: Path) -> None:
    """Every shipped example and published axis is a real machine: none is out of scale with its load."""
    from drivetrain.axis.model import load_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.duty.sanity import sanity_warnings

    axis = load_axis(path)
    if not axis.spec.profile:
        pytest.skip("no profile")
    assert sanity_warnings(axis, duty_cycle(axis)) == []


def test_warnings_lead_the_report_notes() -> None:
    """The report says a warning first, as the CLI prints it and the web page shows it."""
    from drivetrain.report.model import build_report

    notes = build_report(size(table(90, 0.2))).notes
    assert notes[0].startswith("Warning: ") and "times its weight at its rim" in notes[0]
    assert not any(n.startswith("Warning: ") for n in build_report(size(table("90 deg", 0.5))).notes)
