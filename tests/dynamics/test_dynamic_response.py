"""The dynamic answer of a candidate (dynamics/response.py) and the requirements block: the tuned loop
against python-control, settling on a rigid axis against the closed-loop poles, the two-mass limit on
bandwidth, and the invariants (a stiffer mechanism never settles slower, a wider window never later)."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import control
import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.axis.model import parse_axis
from drivetrain.dynamics.chain import Chain, two_mass_chain
from drivetrain.dynamics.control import analyse_loop, closed_loop_poles, tune
from drivetrain.dynamics.linear import motor_speed_tf, two_mass_resonance
from drivetrain.dynamics.reference import Reference
from drivetrain.dynamics.simulation import simulate
from drivetrain.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
BELT = yaml.safe_load((ROOT / "examples" / "belt.yaml").read_text())


def _python_control_loop(chain: Chain, loop: Any) -> Any:
    """L_v = PI * current lag * delay (Pade) * plant, built with python-control in state space (a
    product of polynomials of this order overflows)."""
    s = control.tf("s")
    plant = control.tf2ss(motor_speed_tf(chain, as_control=True))
    pi = control.tf2ss(loop.velocity_kp * (1 + 1 / (loop.velocity_ti * s)))
    current = control.tf2ss(1 / (1 + s / (2 * math.pi * loop.current_bandwidth_hz)))
    delay = control.tf2ss(control.tf(*control.pade(loop.velocity_delay, 6)))
    return control.series(plant, delay, current, pi)


@pytest.mark.parametrize("ratio, k", [(1.0, 2000.0), (5.0, 800.0), (0.0, 0.0)])
def test_tuned_loop_margins_and_bandwidth_agree_with_python_control(ratio: float, k: float) -> None:
    """Margins within 1 deg and 0.3 dB, velocity bandwidth within 2 % (Pade order 6 for the delay)."""
    j_m = 2e-4
    chain = two_mass_chain(j_m, ratio * j_m, k, damping=0.05) if k else Chain(inertia=np.array([j_m]),
                                                                             stiffness=np.zeros(0))
    loop = tune(chain, None)
    ours = analyse_loop(chain, loop)
    lv = _python_control_loop(chain, loop)
    gm, pm, *_ = control.stability_margins(lv)
    assert ours.velocity_margins.phase_margin_deg == pytest.approx(pm, abs=1.0)
    if math.isfinite(gm) and gm > 0:
        assert ours.velocity_margins.gain_margin_db == pytest.approx(20 * math.log10(gm), abs=0.3)
    # -3 dB bandwidth: the first frequency where |T| falls below 1/sqrt(2), T evaluated by python-control
    # (its own ``bandwidth`` root-finds from the origin and stops at a resonant peak of T)
    f = np.geomspace(0.1, 0.5 / loop.velocity_sample_time, 20000)
    mag = np.abs(control.frequency_response(control.feedback(lv, 1), 2 * math.pi * f).complex).ravel()
    bw = float(f[np.argmax(mag < 1 / math.sqrt(2))])
    assert ours.velocity_bandwidth_hz == pytest.approx(bw, rel=0.02)


def test_settling_of_a_rigid_axis_follows_its_slowest_closed_loop_pole() -> None:
    """Without feed-forward the error after a stop decays as the slowest closed-loop pole, exp(sigma t):
    two windows a factor e^3 apart are reached 3 / |sigma| apart (within 10 %)."""
    rigid = Chain(inertia=np.array([5e-4]), stiffness=np.zeros(0))
    loop = tune(rigid, 40.0).with_(velocity_ff=0.0, acceleration_ff=0.0)
    _, p_pos = closed_loop_poles(rigid, loop)
    sigma = float(np.max(p_pos.real))  # slowest decay (closest to the imaginary axis)
    t = np.linspace(0.0, 0.6, 6001)
    x = np.where(t < 0.05, 10.0 * (t / 0.05) ** 2 * (3 - 2 * t / 0.05), 10.0)  # a 10 rad smooth move
    ref = Reference.from_arrays(t, x)
    tol = 1e-3
    first = simulate(rigid, loop, ref, settle_tolerance=tol).settling_time[0]
    second = simulate(rigid, loop, ref, settle_tolerance=tol * math.exp(-3)).settling_time[0]
    assert second - first == pytest.approx(3.0 / abs(sigma), rel=0.10)


@pytest.mark.parametrize("inertia_ratio", [1.0, 10.0, 100.0])
def test_the_inertia_ratio_limits_bandwidth_through_the_anti_resonance(inertia_ratio: float) -> None:
    """Two-mass limit (Ellis, Control System Design Guide, 4th ed., ch. 16 "Mechanical Resonance"):
    f_R / f_AR = sqrt(1 + J_L / J_M), so at a fixed resonance a larger mismatch lowers the anti-resonance
    and with it the velocity bandwidth the tuning rule allows (half the anti-resonance): 1:1, 10:1 and
    100:1 give f_R / f_AR = 1.414, 3.317 and 10.05."""
    j_m, k = 1e-4, 5000.0
    chain = two_mass_chain(j_m, inertia_ratio * j_m, k)
    f_r, f_ar = two_mass_resonance(j_m, inertia_ratio * j_m, k)
    assert f_r / f_ar == pytest.approx(math.sqrt(1 + inertia_ratio), rel=1e-9)
    loop = tune(chain, None, current_bandwidth_hz=1e6, velocity_sample_time=1e-7, current_sample_time=1e-7)
    f_v = loop.velocity_kp / (2 * math.pi * chain.total_inertia)
    assert f_v <= 0.5 * f_ar * (1 + 1e-9)


def _belt(**req: Any) -> Any:
    data = copy.deepcopy(BELT)
    data["motor"] = {"id": "MQMF022L1"}
    data["requirements"] = {"settling": {"window": "50 um", "time": "60 ms"}, "following_error": "1 mm", **req}
    return data


def _response(data: dict[str, Any]) -> Any:
    from drivetrain.dynamics.axis_model import TABLE_POINTS, stages_with_gearbox
    from drivetrain.dynamics.mechanism_modes import mechanism_stiffness_of
    from drivetrain.dynamics.response import candidate_response

    axis = parse_axis(data)
    assert axis.motor is not None and axis.requirements is not None
    return candidate_response(axis, axis.motor.name, axis.motor.inertia, axis.motor.peak_torque,
                              stages_with_gearbox(axis, None), axis.requirements,
                              stiffness=mechanism_stiffness_of(axis, TABLE_POINTS))


def test_a_candidate_answer_has_its_checks_with_reasons() -> None:
    r = _response(_belt(velocity_bandwidth="500 Hz"))
    names = [c["name"] for c in r.checks]
    assert names == ["settling_time", "following_error", "velocity_bandwidth", "stability_margin"]
    bw = r.checks[2]
    assert bw["status"] == "fail" and "anti-resonance" in bw["note"]  # the belt's compliance sets the limit
    # a linear check fails the candidate already: its profile is not simulated, and the two checks say so
    assert not r.simulated and r.following_error.size == 0 and math.isinf(r.worst_settling)
    for c in r.checks[:2]:
        assert c["status"] == "unknown" and c["ok"] is None and c["available"] is None
        assert c["note"].startswith("not simulated: the candidate already fails velocity_bandwidth")
    assert r.resonance_hz > r.anti_resonance_hz > 0
    d = r.to_dict()
    assert d["status"] == "fail" and len(d["checks"]) == 4 and d["simulated"] is False
    # without the bandwidth asked, the linear checks pass and the profile is simulated: per move, per stop
    s = _response(_belt())
    assert s.simulated and s.following_error.shape == (2,) and s.settling_time.shape == (2,)
    assert [c["name"] for c in s.checks] == ["settling_time", "following_error", "stability_margin"]


def test_a_mechanism_without_stiffness_data_makes_a_pass_unknown() -> None:
    data = _belt(settling={"window": "5 mm", "time": "1 s"})
    del data["mechanism"]["belt"]
    r = _response(data)
    assert r.rigid and "belt" in r.rigid[0]
    assert {c["status"] for c in r.checks} == {"unknown"}
    assert all(c["ok"] is None for c in r.checks)


@settings(max_examples=4, deadline=None)
@given(st.floats(1.5, 20.0))
def test_a_stiffer_belt_never_settles_slower(factor: float) -> None:
    soft = _response(_belt())
    data = _belt()
    data["mechanism"]["belt"]["specific_stiffness"] = f"{1265000 * factor} N"
    stiff = _response(data)
    assert stiff.worst_settling <= soft.worst_settling * 1.001 + 1e-4


@settings(max_examples=4, deadline=None)
@given(st.floats(1.5, 50.0))
def test_a_wider_window_never_settles_later(factor: float) -> None:
    narrow = _response(_belt())
    wide = _response(_belt(settling={"window": f"{50 * factor} um", "time": "60 ms"}))
    assert np.all(np.nan_to_num(wide.settling_time, nan=np.inf) <= np.nan_to_num(narrow.settling_time, nan=np.inf))


@pytest.mark.parametrize("req, field", [
    ({"settling": {"window": "-1 um"}}, "requirements.settling.window"),
    ({"settling": {"window": "2 m"}}, "requirements.settling.window"),
    ({"following_error": "1 kg"}, "requirements.following_error"),
    ({"stability": {"gain_margin": "90 dB"}}, "requirements.stability.gain_margin"),
    ({"candidates": 0}, "requirements.candidates"),
    ({"colour": "red"}, "requirements.colour"),
])
def test_bad_requirements_name_the_field(req: dict[str, Any], field: str) -> None:
    data = copy.deepcopy(BELT)
    data["requirements"] = req
    with pytest.raises(InputError) as err:
        parse_axis(data)
    assert err.value.field == field


def test_requirements_in_si_at_the_load() -> None:
    axis = parse_axis(_belt())
    req = axis.requirements
    assert req is not None and req.motion == "linear"
    assert req.settling_window == pytest.approx(50e-6) and req.settling_time == pytest.approx(0.06)
    assert req.phase_margin_deg == pytest.approx(30.0) and req.gain_margin_db == 6.0
    assert parse_axis(copy.deepcopy(BELT)).requirements is None


def test_simulate_judges_settling_at_the_load_and_says_when_a_stop_never_settles(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The belt's gearbox backlash (5 arcmin, about 44 um at the carriage) keeps the load outside the
    default 10 um window: 'not settled', never '0.0 ms'; a 1 mm window is reached."""
    import json

    from drivetrain import cli

    path = tmp_path / "belt.yaml"
    path.write_text(yaml.safe_dump(BELT))
    assert cli.main(["simulate", str(path)]) == 0
    text = capsys.readouterr().out
    assert "load into 10 um, default" in text and "not settled" in text
    data = copy.deepcopy(BELT)
    data["requirements"] = {"settling": {"window": "1 mm"}}
    path.write_text(yaml.safe_dump(data))
    assert cli.main(["simulate", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["settling_window_m"] == pytest.approx(1e-3) and out["settling_window_source"] != "default"
    assert all(v is not None for v in out["settling_time_s"])


def test_modes_names_both_models(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from drivetrain import cli

    assert cli.main(["modes", str(ROOT / "examples" / "belt.yaml")]) == 0
    text = capsys.readouterr().out
    assert "the mechanism rigid: natural frequencies: 433.1 Hz" in text
    assert "weakest position (1200 mm): natural frequencies: 154.9 Hz" in text


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8])
def test_the_tridiagonal_frequency_response_equals_the_state_space_solve(n: int) -> None:
    """``linear.frequency_response`` (Thomas algorithm along the chain, vectorised over frequencies)
    against the (2n x 2n) state-space solve, every input and output, damped and undamped chains: within
    1e-8 of the largest magnitude over the band."""
    from drivetrain.dynamics.linear import _frequency_response_ss, frequency_response

    rng = np.random.default_rng(n)
    f = np.geomspace(0.1, 4000.0, 2400)
    for trial in range(4):
        chain = Chain(inertia=rng.uniform(1e-5, 1e-2, n), stiffness=rng.uniform(50.0, 5e4, n - 1),
                      damping=rng.uniform(0.0, 1.0, n - 1) * (trial % 2),
                      ground_damping=rng.uniform(0.0, 1e-3, n) * (trial >= 2))
        for inp in ("motor_torque", "load_torque"):
            for out in ("motor_position", "motor_speed", "load_position", "load_speed"):
                ours, ss = frequency_response(chain, f, inp, out), _frequency_response_ss(chain, f, inp, out)
                assert np.max(np.abs(ours - ss)) <= 1e-8 * np.max(np.abs(ss))


def test_closed_loop_poles_kept_for_the_same_chain_and_loop_only() -> None:
    """``tune`` checks the loop it returns; ``analyse_loop`` of that chain and loop reuses those poles: the
    same values as computed afresh, a copy the caller may change, and another loop's own poles."""
    from drivetrain.dynamics.control import _closed_loop_poles

    chain = Chain(inertia=np.array([5e-4, 2e-3]), stiffness=np.array([3000.0]))
    loop = tune(chain, None)
    fresh = _closed_loop_poles(chain, loop)
    first = closed_loop_poles(chain, loop)
    first[0][:] = 0.0  # the caller's copy
    again = closed_loop_poles(chain, loop)
    for a, b in zip(again, fresh, strict=True):
        assert np.array_equal(a, b)
    other = loop.with_(velocity_kp=loop.velocity_kp * 0.5)
    for a, b in zip(closed_loop_poles(chain, other), _closed_loop_poles(chain, other), strict=True):
        assert np.array_equal(a, b)
    assert not np.array_equal(closed_loop_poles(chain, other)[0], fresh[0])
