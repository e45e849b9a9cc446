"""The mechanism spring that follows the load in ``simulate``, and the servo-bandwidth requirement in ``modes``.

- With a position-independent table the simulation equals the one of the chain without a table
  (both kernels), so axes without mechanism stiffness data simulate as before.
- A two-mass chain whose spring changes with the load angle rings, open loop, at
  sqrt(k(x) (1/J_m + 1/J_l)) / 2 pi of the position it rests at (lecture, "Resonant Frequency").
- The 3 m belt gantry (examples/belt_gantry_3m.yaml) after a move rings at ``drivetrain modes``'
  f1 of the position it stopped at: the far end (the belt's long spans) in the following error,
  the home end (short spans, the gearbox mode) in the mechanism spring's torque.
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
from drivetrain.dynamics import Chain, move_reference, simulate, simulate_open_loop, tune, two_mass_chain
from drivetrain.dynamics.axis_model import model, simulate_axis, with_mechanism_spring
from drivetrain.dynamics.mechanism_modes import BANDWIDTH_FACTOR, modes_across_stroke
from drivetrain.errors import InputError

ROOT = Path(__file__).parents[2]
GANTRY = ROOT / "examples" / "belt_gantry_3m.yaml"


def _peak_hz(signal: np.ndarray, step: float, lo: float, hi: float) -> float:
    """Frequency [Hz] of the largest spectral peak in (lo, hi) (Hann window, zero-padded FFT)."""
    y = (signal - signal.mean()) * np.hanning(signal.size)
    n = 1 << 20
    spec = np.abs(np.fft.rfft(y, n))
    f = np.fft.rfftfreq(n, step)
    band = (f > lo) & (f < hi)
    return float(f[band][np.argmax(spec[band])])


@pytest.mark.parametrize("chain", [
    two_mass_chain(2e-4, 6e-4, 900.0, damping=0.01),
    Chain(inertia=np.array([2e-4, 1e-4, 6e-4]), stiffness=np.array([3000.0, 900.0]), damping=np.array([0.01, 0.01])),
], ids=["run_two", "run_chain"])
def test_a_constant_table_simulates_as_the_chain_without_one(chain: Chain) -> None:
    ref = move_reference(20.0, 150.0, 3000.0, dwell=0.1, repeat=2, step=1e-4)
    loop = tune(chain, 30.0)
    plain = simulate(chain, loop, ref, load_torque=0.05)
    k = float(chain.stiffness[-1])
    tabled = chain.with_(spring_table=(np.array([-100.0, 0.0, 100.0]), np.array([k, k, k])))
    res = simulate(tabled, loop, ref, load_torque=0.05)
    for key, series in plain.states.items():
        np.testing.assert_allclose(res.states[key], series, rtol=0.0, atol=1e-12 * max(1.0, np.abs(series).max()))


@pytest.mark.parametrize("rest", [0.0, 1.0])
def test_open_loop_ringing_follows_the_table(rest: float) -> None:
    # k(theta_l) = 400 N m/rad at theta_l = 0 rising to 1600 at 1 rad: resting there the chain
    # rings at sqrt(k (1/J_m + 1/J_l)) / 2 pi.
    jm, jl = 2e-4, 6e-4
    table = (np.array([-1.0, 0.0, 1.0, 2.0]), np.array([400.0, 400.0, 1600.0, 1600.0]))
    chain = two_mass_chain(jm, jl, float(np.interp(rest, *table))).with_(spring_table=table)
    h = 2e-5
    t = np.arange(100_001) * h
    r = simulate_open_loop(chain, t, np.zeros_like(t), theta0=[rest + 1e-4, rest], omega0=[0.0, 0.0])
    twist = r.states[f"theta_{chain.names[0]}"] - r.states[f"theta_{chain.names[1]}"]
    k = float(np.interp(rest, *table))
    expected = math.sqrt(k * (1 / jm + 1 / jl)) / (2 * math.pi)
    assert _peak_hz(twist, h, 10.0, 1000.0) == pytest.approx(expected, rel=5e-3)


def test_spring_table_inputs_are_refused_by_name() -> None:
    base = two_mass_chain(1e-4, 1e-4, 100.0)
    for table in ((np.array([0.0, 0.0]), np.array([1.0, 1.0])), (np.array([0.0, 1.0]), np.array([1.0, -1.0])),
                  (np.array([0.0]), np.array([1.0]))):
        with pytest.raises(InputError) as err:
            base.with_(spring_table=table)
        assert err.value.field == "dynamics.chain.spring_table"


def _gantry(bandwidth_hz: float) -> Any:
    raw = copy.deepcopy(load_axis(GANTRY).raw)
    raw["profile"] = [{"move": "3000 mm", "time": "2.0 s", "shape": "trapezoid"}, {"dwell": "1 s"},
                      {"move": "-3000 mm", "time": "2.0 s", "shape": "trapezoid"}, {"dwell": "1 s"}]
    raw["dynamics"] = {"loop": {"velocity_bandwidth": f"{bandwidth_hz} Hz"}}
    return parse_axis(raw)


def test_belt_gantry_rings_at_modes_f1_of_each_end() -> None:
    # A slow velocity loop (3 Hz) barely shifts the mode; the dwell after each move is 1 s.
    axis = _gantry(3.0)
    dyn = model(axis)
    modes = modes_across_stroke(axis, dyn.stages, dyn.motor_inertia)
    assert modes is not None
    rows = modes.f1_by_position
    f_home, f_far = rows[0].f1_Hz, rows[-1].f1_Hz
    assert f_far == pytest.approx(modes.f1_min_Hz) and f_home > 3 * f_far
    res = simulate_axis(axis)
    t = res.time
    h = float(t[1] - t[0])
    far = (t >= 2.0) & (t < 3.0)    # resting at 3 m
    home = (t >= 5.0) & (t < 6.0)   # back at 0
    assert _peak_hz(res.following_error[far], h, 20.0, 400.0) == pytest.approx(f_far, rel=0.05)
    assert _peak_hz(res.states["shaft_torque_1"][home], h, 20.0, 400.0) == pytest.approx(f_home, rel=0.05)
    # the chain simulated has the belt as its last spring, its table over the whole stroke
    chain = with_mechanism_spring(axis, dyn).chain
    assert chain.spring_table is not None
    assert chain.stiffness.size == 2
    assert float(chain.spring_table[1].min()) == pytest.approx(
        modes.springs_at_motor_Nm_per_rad["timing_belt belt"], rel=1e-9)


def test_an_axis_without_stiffness_data_keeps_its_chain() -> None:
    axis = load_axis(ROOT / "examples" / "rotary.yaml")
    dyn = model(axis)
    assert with_mechanism_spring(axis, dyn) is dyn


def test_modes_json_has_the_servo_bandwidth_check() -> None:
    proc = subprocess.run([sys.executable, "-m", "drivetrain.cli", "modes", str(GANTRY), "--json"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    modes = json.loads(proc.stdout)["modes"]
    (check,) = modes["checks"]
    assert check["name"] == "servo_bandwidth"
    assert modes["velocity_bandwidth_Hz"] == pytest.approx(12.0)
    assert check["required"] == pytest.approx(BANDWIDTH_FACTOR * 12.0)
    assert check["available"] == pytest.approx(modes["f1_min_Hz"])
    assert check["ok"] and check["margin"] == pytest.approx(modes["f1_min_Hz"] / 24.0 - 1.0)
    assert "belt" in check["note"] and check["source"]


def test_servo_bandwidth_fails_when_the_loop_needs_more() -> None:
    axis = _gantry(30.0)
    dyn = model(axis)
    modes = modes_across_stroke(axis, dyn.stages, dyn.motor_inertia)
    assert modes is not None
    (check,) = modes.checks
    assert not check.ok
    assert check.required == pytest.approx(60.0)


def test_without_a_bandwidth_the_check_is_unknown_not_failed() -> None:
    raw = copy.deepcopy(load_axis(GANTRY).raw)
    raw.pop("dynamics")
    axis = parse_axis(raw)
    dyn = model(axis)
    modes = modes_across_stroke(axis, dyn.stages, dyn.motor_inertia)
    assert modes is not None
    (check,) = modes.checks
    # What the application needs is an input: no default stands in for it, so nothing fails.
    assert modes.velocity_bandwidth_Hz is None and modes.bandwidth_source == "not stated"
    assert check.status == "unknown" and check.ok is None
    assert math.isnan(check.required) and math.isnan(check.margin)
    assert check.available == pytest.approx(modes.f1_min_Hz)
    assert modes.max_velocity_bandwidth_Hz == pytest.approx(modes.f1_min_Hz / BANDWIDTH_FACTOR)
    # The note still gives the default tuning on the rigid inertia, for information:
    # min(2000 Hz / 4, 20 deg / (360 x 156.25 us)) = 355.6 Hz.
    assert "355.6 Hz" in check.note and "velocity_bandwidth" in check.note


def test_bad_bandwidth_names_its_field() -> None:
    raw = copy.deepcopy(load_axis(GANTRY).raw)
    raw["dynamics"] = {"loop": {"velocity_bandwidth": "-3 Hz"}}
    axis = parse_axis(raw)
    with pytest.raises(InputError) as err:  # the dynamics block is checked whole when the model is built
        dyn = model(axis)
        modes_across_stroke(axis, dyn.stages, dyn.motor_inertia)
    assert err.value.field == "dynamics.loop.velocity_bandwidth"


GUIDE = {"guide_life", "guide_static_safety"}
SCREW = {"screw_buckling", "screw_tensile_compressive", "screw_critical_speed", "screw_dn_speed", "nut_life",
         "nut_static_safety"}


@pytest.mark.parametrize(("example", "weakest", "checks"), [
    ("ball_screw.yaml", "ball_screw shaft", SCREW | GUIDE),
    ("belt.yaml", "timing_belt belt", {"belt_slack_side", "belt_tension"} | GUIDE),
    ("belt_gantry_3m.yaml", "timing_belt belt", {"belt_slack_side", "belt_tension"}),
    ("rack_pinion.yaml", "rack_pinion rack mesh", GUIDE),
])
def test_shipped_examples_report_modes_across_the_stroke(example: str, weakest: str, checks: set[str]) -> None:
    from drivetrain.dynamics.mechanism_modes import modes_of_result
    from drivetrain.sizing.pipeline import size

    res = size(ROOT / "examples" / example)
    assert {c.name for c in res.mechanism_checks} == checks
    modes = modes_of_result(res)
    assert modes is not None
    assert modes.weakest_link == weakest
    assert len(modes.f1_by_position) == 41
    assert modes.checks[0].name == "servo_bandwidth"
    # No shipped example fails for want of an input: without a stated bandwidth the check is unknown.
    assert modes.checks[0].status == ("pass" if example == "belt_gantry_3m.yaml" else "unknown")
    assert all(c.ok for c in res.mechanism_checks)
