"""Mechanism checks in the sizing result and the first mode across the stroke, through the axis file and CLI.

The formulas are validated in tests/physics/test_mechanism_limits.py and tests/dynamics/test_mechanism_stiffness.py;
here: the axis file reaches them with the right values, the result carries them, bad inputs name
their field, and the 3 m belt gantry's first mode lies in the tens of Hz with the belt named.
"""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.dynamics import model
from drivetrain.dynamics.mechanism_modes import modes_across_stroke
from drivetrain.errors import InputError
from drivetrain.physics import belt_rack, rolling_life, screw_limits
from drivetrain.sizing.mechanism_checks import axial_force
from drivetrain.sizing.pipeline import size

ROOT = Path(__file__).parents[2]
GANTRY = ROOT / "examples" / "belt_gantry_3m.yaml"
KEYS = {"name", "required", "available", "margin", "ok", "unit", "source"}

SCREW: dict[str, Any] = {
    "axis": "screw", "gravity": 9.8,
    "mechanism": {"type": "ball_screw", "lead": "5 mm", "diameter": "15 mm", "length": "820 mm", "efficiency": 0.9,
                  "load": {"mass": "40 kg", "friction": 0.02},
                  "screw": {"root_diameter": "12.5 mm", "mounting": "fixed_supported", "home_position": "100 mm",
                            "dn_limit": 70000},
                  "nut": {"C_a": "4400 N", "C_0a": "9000 N", "load_factor": 1.2, "preload": "50 N"}},
    "profile": [{"move": "500 mm", "time": "4 s"}, {"dwell": "0.5 s"}, {"move": "-500 mm", "time": "4 s"},
                {"dwell": "0.5 s"}],
}


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "drivetrain.cli", *args], capture_output=True, text=True,
                          timeout=300)


def checks_of(data: dict[str, Any]) -> dict[str, dict[str, Any]]:
    res = size(parse_axis(data))
    return {c["name"]: c for c in res.to_dict()["mechanism_checks"]}


def test_screw_checks_use_the_physics_functions_at_the_worst_position() -> None:
    checks = checks_of(SCREW)
    assert set(checks) == {"screw_buckling", "screw_tensile_compressive", "screw_critical_speed", "screw_dn_speed",
                           "nut_life", "nut_static_safety"}
    for c in checks.values():
        assert set(c) >= KEYS and c["source"]
        assert c["margin"] == pytest.approx(c["available"] / c["required"] - 1.0)
    # Buckling at the farthest nut position: home 100 mm + stroke 500 mm = 600 mm from the fixed bearing.
    assert checks["screw_buckling"]["available"] == pytest.approx(float(screw_limits.buckling_load(12.5e-3, 0.6)))
    # Critical speed over the whole unsupported length (mechanism.length), in rpm.
    crit = float(screw_limits.critical_speed(12.5e-3, 0.82)) * 60 / (2 * math.pi)
    assert checks["screw_critical_speed"]["available"] == pytest.approx(crit)
    assert checks["screw_dn_speed"]["available"] == pytest.approx(70000 / 15.0)
    axis = parse_axis(SCREW)
    res = size(axis)
    force = axial_force(axis, res.duty)
    assert checks["screw_buckling"]["required"] == pytest.approx(float(np.max(np.abs(force))))
    # Nut life from the same cycle through the physics function.
    omega = np.asarray(res.duty.samples.v) / axis.mechanism.lever
    life = screw_limits.nut_life(4400.0, force, omega, res.duty.weights, 5e-3, preload=50.0, load_factor=1.2)
    assert checks["nut_life"]["available"] == pytest.approx(life.hours)
    assert checks["nut_life"]["required"] == pytest.approx(20000.0)


def test_axial_force_is_external_plus_inertial() -> None:
    axis = parse_axis(SCREW)
    duty = size(axis).duty
    a = np.asarray(duty.samples.a)
    v = np.asarray(duty.samples.v)
    moving = (np.abs(v) > 1e-9) & (np.abs(a) < 1e-9)
    # Horizontal, constant speed: only the guide friction mu m g opposes the motion.
    assert np.allclose(np.abs(axial_force(axis, duty)[moving]), 0.02 * 40 * 9.8)


def test_a_failing_mechanism_check_fails_the_result() -> None:
    data = copy.deepcopy(SCREW)
    data["mechanism"]["nut"]["required_life"] = "1e8 h"
    data["mechanism"]["nut"]["load_factor"] = 10
    res = size(parse_axis(data))
    checks = {c.name: c for c in res.mechanism_checks}
    assert not checks["nut_life"].ok
    assert not res.ok


def test_guide_life_by_hand_for_a_horizontal_axis() -> None:
    # Two carriages share m g; the cubic mean of a constant load is that load; life by THK's form.
    data = copy.deepcopy(SCREW)
    data["guide"] = {"dynamic_rating": "10 kN", "static_rating": "15 kN", "carriages": 2}
    res = size(parse_axis(data))
    checks = {c.name: c for c in res.mechanism_checks}
    p = 40 * 9.8 / 2
    life_m = float(rolling_life.guide_life(10e3, p, 50e3))
    hours = life_m / 1.0 * res.duty.period / 3600.0  # 1.0 m travelled per cycle (500 mm out and back)
    assert checks["guide_life"].available == pytest.approx(hours, rel=1e-6)
    assert checks["guide_static_safety"].available == pytest.approx(15e3 / p)


def test_rack_feed_force_with_application_factor() -> None:
    data = {"axis": "rack", "mechanism": {"type": "rack_pinion", "diameter": "50 mm", "load": {"mass": "80 kg"},
                                          "rack": {"permissible_force": "3000 N", "application_factor": 1.5}},
            "profile": [{"move": "1 m", "time": "1 s"}, {"dwell": "0.5 s"}]}
    axis = parse_axis(data)
    res = size(axis)
    c = res.mechanism_checks[0]
    assert c.name == "rack_feed_force"
    assert c.required == pytest.approx(1.5 * float(np.max(np.abs(axial_force(axis, res.duty)))))


def test_gantry_belt_checks_and_tensions() -> None:
    res = size(load_axis(GANTRY))
    checks = {c.name: c for c in res.mechanism_checks}
    assert set(checks) == {"belt_slack_side", "belt_tension"}
    assert checks["belt_tension"].available == 5060.0
    pull = np.abs(axial_force(res.axis, res.duty))
    # Default pretension = the largest pull (ELATECH p. 54), so the tight span never exceeds twice it.
    assert checks["belt_slack_side"].available == pytest.approx(float(pull.max()))
    assert pull.max() < checks["belt_tension"].required <= 2 * pull.max()
    assert res.ok


def test_three_metre_gantry_first_mode_in_tens_of_hz_with_the_belt_weakest() -> None:
    proc = run("modes", str(GANTRY), "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    modes = out["modes"]
    assert 10.0 <= modes["f1_min_Hz"] < 100.0
    assert "belt" in modes["weakest_link"]
    assert modes["worst_position_m"] == pytest.approx(3.0)
    assert len(modes["f1_by_position"]) == 41
    assert modes["f1_min_Hz"] == pytest.approx(min(r["f1_Hz"] for r in modes["f1_by_position"]))
    # The rigid-mechanism chain (gearbox spring only) is far stiffer, as before this change.
    assert out["natural_frequencies_Hz"][0] > 3 * modes["f1_min_Hz"]


def test_a_very_stiff_belt_leaves_the_gearbox_mode() -> None:
    axis = load_axis(GANTRY)
    raw = copy.deepcopy(axis.raw)
    raw["mechanism"]["belt"]["specific_stiffness"] = "1e13 N"
    stiff = parse_axis(raw)
    dyn = model(stiff)
    modes = modes_across_stroke(stiff, dyn.stages, dyn.motor_inertia)
    assert modes is not None
    from drivetrain.dynamics.linear import natural_frequencies

    assert modes.f1_min_Hz == pytest.approx(float(natural_frequencies(dyn.chain)[0]), rel=1e-3)
    assert "gearbox" in modes.weakest_link


def test_belt_tensions_follow_the_span_split() -> None:
    # The check's tight tension equals the physics function on the same spans.
    res = size(load_axis(GANTRY))
    belt = res.axis.spec.mechanism.belt  # type: ignore[union-attr]
    force = axial_force(res.axis, res.duty)
    lp, lo = belt_rack.linear_belt_spans(belt.home_position + np.asarray(res.duty.samples.x), belt.centre_distance,
                                         "loop")
    lp, lo = np.where(force >= 0, lo, lp), np.where(force >= 0, lp, lo)
    tight, _ = belt_rack.linear_belt_tensions(np.abs(force), float(np.abs(force).max()), lp, lo)
    checks = {c.name: c for c in res.mechanism_checks}
    assert checks["belt_tension"].required == pytest.approx(float(tight.max()))


@pytest.mark.parametrize(("patch", "field"), [
    ({"screw": {"root_diameter": "-3 mm"}}, "mechanism.screw.root_diameter"),
    ({"screw": {"root_diameter": "12 mm", "home_position": "500 mm"}}, "mechanism.screw.home_position"),
    ({"nut": {"preload": "10 N"}}, "mechanism.nut.C_a"),
    ({"screw": {"root_diameter": "12 mm", "mounting": "welded"}}, "mechanism.screw.mounting"),
])
def test_bad_mechanism_inputs_name_their_field(patch: dict[str, Any], field: str) -> None:
    data = copy.deepcopy(SCREW)
    data["mechanism"].pop("screw")
    data["mechanism"].pop("nut")
    data["mechanism"].update(patch)
    with pytest.raises(InputError) as err:
        size(parse_axis(data))
    assert err.value.field == field


def test_cli_exits_2_naming_the_field(tmp_path: Path) -> None:
    text = GANTRY.read_text(encoding="utf-8").replace("home_position: 50 mm", "home_position: 500 mm")
    bad = tmp_path / "bad.yaml"
    bad.write_text(text, encoding="utf-8")
    proc = run("size", str(bad))
    assert proc.returncode == 2
    assert "mechanism.belt.home_position" in proc.stderr + proc.stdout
    assert "Traceback" not in proc.stderr
