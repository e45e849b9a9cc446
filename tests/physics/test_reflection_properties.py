"""Invariants of reflection and four-quadrant efficiency (hypothesis property tests)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.physics.efficiency import torque_through_losses
from drivetrain.physics.stage import Stage, chain_inertia, torque_in

ratios = st.floats(0.05, 200.0)
effs = st.floats(0.05, 1.0)
torques = st.floats(-1e3, 1e3)
speeds = st.floats(-1e3, 1e3)


@given(t=torques, w=speeds, eta=effs, back=st.floats(-1.0, 1.0))
def test_no_element_creates_energy(t: float, w: float, eta: float, back: float) -> None:
    """Power into the element from the motor side is never less than what it delivers."""
    t_in = float(torque_through_losses(np.array([t]), np.array([w]), np.array([1.0]), eta, back)[0])
    p_out, p_in = t * w, t_in * w
    assert p_in >= p_out - 1e-9 * (1 + abs(p_out))


@given(t=torques, w=speeds)
def test_lossless_element_changes_nothing(t: float, w: float) -> None:
    t_in = torque_through_losses(np.array([t]), np.array([w]), np.array([1.0]), 1.0, 1.0)
    assert t_in[0] == t


@given(st.lists(ratios, min_size=1, max_size=6), st.floats(1e-6, 10.0), st.floats(0.1, 10.0))
@settings(max_examples=200)
def test_reflected_inertia_scales_as_inverse_square(ratios_: list[float], j_load: float, k: float) -> None:
    """Through any chain the load reflects as J / (prod i)^2; scaling one ratio by k divides it by k^2."""
    stages = [Stage("s", "gearbox", ratio=r) for r in ratios_]
    total = float(np.prod(ratios_))
    assert np.isclose(chain_inertia(stages, j_load), j_load / total**2, rtol=1e-12)
    scaled = [*stages[:-1], Stage("s", "gearbox", ratio=ratios_[-1] * k)]
    assert np.isclose(chain_inertia(scaled, j_load), chain_inertia(stages, j_load) / k**2, rtol=1e-12)


@given(ratios, st.floats(0, 1e-2), st.floats(0, 1e-2), st.floats(0, 10.0))
def test_own_inertia_adds_unreflected(r: float, j_in: float, j_inside: float, j_load: float) -> None:
    stage = Stage("s", "gearbox", ratio=r, inertia_in=j_in, inertia_inside=j_inside)
    assert chain_inertia([stage], j_load) == j_in + j_inside + j_load / r**2


@given(t=torques, w=speeds, a=st.floats(-1e4, 1e4))
def test_unit_stage_changes_nothing(t: float, w: float, a: float) -> None:
    """A ratio of 1 with efficiency 1 and no inertia passes torque unchanged in every model."""
    unit = Stage("c", "coupling")
    for model in ("four_quadrant", "load_torque_only"):
        tin, ext = torque_in(unit, np.array([t]), np.array([t]), np.array([w]), np.array([a]), np.array([1.0]),
                             model)  # type: ignore[arg-type]
        assert tin[0] == t and ext[0] == t


def test_self_locking_worm_needs_motor_torque_to_lower() -> None:
    """eta_back <= 0: lowering a hanging load (speed < 0, load torque > 0) needs driving torque."""
    t_load, w = np.array([10.0]), np.array([-5.0])
    t_in = torque_through_losses(t_load, w, np.array([-1.0]), 0.4, -0.2)
    assert t_in[0] < 0.0  # same sign as the speed: the motor drives the load down
    # ... and it holds the load by itself at standstill in a dwell:
    held = torque_through_losses(t_load, np.zeros(1), np.zeros(1), 0.4, -0.2)
    assert held[0] == 0.0


def test_zero_speed_inside_a_move_follows_the_move_direction() -> None:
    """At the start of an upward move the gearbox is motoring (T / eta), not braking."""
    t_in = torque_through_losses(np.array([5.0]), np.zeros(1), np.array([1.0]), 0.5, 0.5)
    assert t_in[0] == 10.0
    t_dn = torque_through_losses(np.array([5.0]), np.zeros(1), np.array([-1.0]), 0.5, 0.5)
    assert t_dn[0] == 2.5


def test_holding_is_safe_side_motoring() -> None:
    held = torque_through_losses(np.array([5.0]), np.zeros(1), np.zeros(1), 0.5, 0.5)
    assert held[0] == 10.0


def test_load_torque_only_divides_only_external_torque() -> None:
    """Vendor selection-guide model: inertial torque passes without loss in every quadrant."""
    st_ = Stage("g", "gearbox", ratio=2.0, efficiency=0.5)
    tin, _ = torque_in(st_, np.array([10.0]), np.array([4.0]), np.array([-1.0]), np.zeros(1), np.array([-1.0]),
                       "load_torque_only")
    assert tin[0] == (10.0 - 4.0) / 2 + 4.0 / (2 * 0.5)
