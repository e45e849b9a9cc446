"""Every mechanism and transmission type through the shared protocol (one interface test).

Each shipped example axis and each transmission type must: build a Stage with a positive
ratio and non-negative inertias; give finite external torques over arrays of samples; and
reflect energy consistently: with efficiency 1, the work the motor shaft does over a
rest-to-rest constant-acceleration step equals the load's kinetic energy change plus the
work of the external forces.
"""

from pathlib import Path

import numpy as np
import pytest

from drivetrain.axis.mechanisms import MECHANISM_TYPES
from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.axis.transmission import TRANSMISSION_TYPES
from drivetrain.physics.stage import torque_in

EXAMPLES = sorted((Path(__file__).parents[2] / "examples").glob("*.yaml"))

MINIMAL = {
    "ball_screw": {"lead": "10 mm", "diameter": "20 mm", "length": "0.5 m", "load": {"mass": 10}},
    "lead_screw": {"lead": "4 mm", "diameter": "16 mm", "length": "0.3 m", "load": {"mass": 5}},
    "belt": {"diameter": "50 mm", "drive_pulley": {"inertia": 1e-4}, "belt_mass": 0.5, "load": {"mass": 4}},
    "timing_belt": {"diameter": "50 mm", "idlers": [{"diameter": "30 mm", "inertia": 1e-5}], "load": {"mass": 4}},
    "conveyor": {"diameter": "80 mm", "carrier_friction": 0.3, "load": {"mass": 20, "friction": 0.05}},
    "rack_pinion": {"diameter": "40 mm", "thickness": "20 mm", "load": {"mass": 30}},
    "roll": {"diameter": "60 mm", "length": "0.2 m", "load": {"press_force": 100, "friction": 0.1}},
    "rotary": {"diameter": "300 mm", "thickness": "10 mm", "load": {"unbalance_mass": 1, "unbalance_radius": 0.1}},
    "hoist": {"diameter": "150 mm", "inertia": 0.01, "load": {"mass": 50, "counterweight": 20}},
    "chain": {"diameter": "100 mm", "loop_mass": 5, "passive_sprockets": [{"inertia": 1e-3}]},
    "custom": {"inertia": 0.5, "load": {"torque": 2.0, "viscous": 0.01}},
}

TRANSMISSIONS = {
    "gearbox": {"ratio": 7, "inertia": 1e-5},
    "belt": {"drive_diameter": "30 mm", "driven_diameter": "90 mm", "drive_pulley": {"inertia": 1e-5}},
    "gear_pair": {"drive_teeth": 20, "driven_teeth": 50, "drive_inertia": 1e-6, "driven_inertia": 1e-5},
    "chain": {"drive_teeth": 15, "driven_teeth": 30, "pitch": "12.7 mm", "chain_mass": 0.5},
    "coupling": {"inertia": 2e-5},
    "clutch": {"inertia": 1e-5, "holding_torque": 5},
    "brake": {"inertia": 1e-5, "holding_torque": 5},
}


def test_every_type_has_a_minimal_case() -> None:
    assert set(MINIMAL) == set(MECHANISM_TYPES)
    assert set(TRANSMISSIONS) == set(TRANSMISSION_TYPES)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_load(path: Path) -> None:
    axis = load_axis(path)
    assert axis.total_ratio > 0 and axis.load_inertia > 0


def _lossless(spec: dict) -> dict:
    out = dict(spec)
    out["efficiency"] = 1.0
    out["back_efficiency"] = 1.0
    return out


@pytest.mark.parametrize("mech_type", MECHANISM_TYPES)
@pytest.mark.parametrize("trans_type", TRANSMISSION_TYPES)
def test_protocol_and_energy(mech_type: str, trans_type: str) -> None:
    mech = {"type": mech_type, **MINIMAL[mech_type]}
    if mech_type == "lead_screw":
        mech["efficiency"] = 1.0
    mech = _lossless(mech) if mech_type != "lead_screw" else {**mech, "back_efficiency": 1.0}
    trans = {"type": trans_type, **TRANSMISSIONS[trans_type]}
    if trans_type not in ("coupling", "clutch", "brake"):
        trans = _lossless(trans)
    axis = parse_axis({"mechanism": mech, "transmission": [trans]})
    for st in axis.stages:
        assert st.ratio > 0 and st.inertia_in >= 0 and st.inertia_inside >= 0
    # One constant-acceleration step from rest: check the motor-shaft work against the load side.
    n = 2001
    t = np.linspace(0.0, 0.5, n)
    acc = 0.4 if axis.mechanism.motion == "linear" else 2.0
    v, x = acc * t, 0.5 * acc * t**2
    direction = np.ones(n)
    load = axis.mechanism.load
    thrust = np.full(n, getattr(load, "thrust", getattr(load, "torque", 0.0)))
    ext = axis.mechanism.external_torque(x, v, direction, thrust, axis.gravity)
    assert ext.shape == (n,) and np.all(np.isfinite(ext))
    t_out = ext * axis.mechanism.stage.ratio
    e_out = t_out
    omega, alpha = v * axis.mechanism.stage.ratio, np.full(n, acc * axis.mechanism.stage.ratio)
    for k, st in enumerate(reversed(axis.stages)):
        if k:
            omega, alpha = omega * st.ratio, alpha * st.ratio
        t_out, e_out = torque_in(st, t_out, e_out, omega, alpha, direction, "four_quadrant")
    work_motor = np.trapezoid(t_out * omega, t)
    kinetic = 0.5 * axis.load_inertia * omega[-1] ** 2
    work_ext = np.trapezoid(ext * axis.mechanism.stage.ratio * v if axis.mechanism.motion == "linear"
                            else ext * v, t)
    assert work_motor == pytest.approx(kinetic + work_ext, rel=1e-4, abs=1e-9)
