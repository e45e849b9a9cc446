"""Dynamics from the axis file: ``drivetrain modes`` and ``drivetrain simulate`` end to end."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.dynamics import model
from drivetrain.errors import InputError

ROOT = Path(__file__).parents[2]


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "drivetrain.cli", *args], capture_output=True, text=True,
                          timeout=300)


def test_lecture_82_7_hz_through_the_cli() -> None:
    proc = run("modes", str(ROOT / "tests" / "axes" / "lecture_two_inertias.yaml"), "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["natural_frequencies_Hz"] == pytest.approx([82.7], abs=0.05)
    assert out["resonance_Hz"] == pytest.approx(82.7, abs=0.05)
    # anti-resonance of the two-mass system: sqrt(K / J_load) / (2 pi)
    assert out["anti_resonance_Hz"] == pytest.approx(math.sqrt(60e3 / 0.4) / (2 * math.pi), rel=1e-9)


def test_chain_from_the_transmission_stiffness() -> None:
    """The shipped ball screw: motor + coupling half | coupling spring | screw and load."""
    axis = load_axis(ROOT / "examples" / "ball_screw.yaml")
    dyn = model(axis)
    from drivetrain import catalog

    j_m = catalog.get(dyn.motor)["rotor_inertia_kgm2"]
    coupling, screw = axis.transmission[0], axis.mechanism.stage
    j1 = j_m + coupling.inertia_in
    j2 = screw.inertia_in + screw.inertia_inside
    assert list(dyn.chain.inertia) == pytest.approx([j1, j2], rel=1e-12)
    f = math.sqrt(3000 * (j1 + j2) / (j1 * j2)) / (2 * math.pi)
    proc = run("modes", str(ROOT / "examples" / "ball_screw.yaml"), "--json")
    assert json.loads(proc.stdout)["natural_frequencies_Hz"] == pytest.approx([f], rel=1e-9)


def test_simulate_the_shipped_example() -> None:
    proc = run("simulate", str(ROOT / "examples" / "belt.yaml"), "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert 0 < out["max_following_error_rad"] < 0.5
    assert out["peak_torque_Nm"] > 0 and out["energy_J"] > 0


def test_rigid_axis_has_no_modes() -> None:
    proc = run("modes", str(ROOT / "examples" / "hoist.yaml"), "--json")
    assert proc.returncode == 0 and json.loads(proc.stdout)["natural_frequencies_Hz"] == []


@pytest.mark.parametrize(("dyn", "field"), [
    ({"chain": [{"inertia": 1.0}, {"stiffness": -5.0}, {"inertia": 1.0}]}, "dynamics.chain[1].stiffness"),
    ({"chain": [{"inertia": 1.0}, {"backlash": 0.01}, {"inertia": 1.0}]}, "dynamics.chain[1]"),
    ({"loop": {"bandwith": 10}}, "dynamics.loop.bandwith"),
    ({"friction": {"coulomb": 1.0, "static": 0.5}}, "dynamics.friction"),
])
def test_bad_dynamics_input_names_the_field(dyn: dict, field: str) -> None:
    raw = load_axis(ROOT / "tests" / "axes" / "lecture_two_inertias.yaml").raw
    axis = parse_axis({**raw, "dynamics": {**raw["dynamics"], **dyn}})
    from drivetrain.dynamics.axis_model import simulate_axis

    with pytest.raises(InputError) as err:
        simulate_axis(axis)
    assert err.value.field.startswith(field)


def test_unstable_gains_exit_2(tmp_path: Path) -> None:
    raw = load_axis(ROOT / "tests" / "axes" / "lecture_two_inertias.yaml").raw
    import yaml

    bad = tmp_path / "unstable.yaml"
    bad.write_text(yaml.safe_dump({**raw, "dynamics": {**raw["dynamics"], "loop": {"velocity_kp": 1.0e5}}}))
    proc = run("simulate", str(bad))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "dynamics" in proc.stderr
