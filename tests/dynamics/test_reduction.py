"""The model reduction of the dynamic selection's simulation (dynamics/reduction.py): what is lumped and
what is kept, and the reduced chain's closed-loop answer against the full chain's on the belt example's
chain (following error within 2 %, settling time within 10 %, the full chain at its own default step)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import analyse_loop, tune
from drivetrain.dynamics.friction import Friction
from drivetrain.dynamics.kernel_io import default_step
from drivetrain.dynamics.linear import natural_frequencies
from drivetrain.dynamics.reduction import MIN_DAMPING, lump_inertia, reduce_for_simulation, reduced_step
from drivetrain.dynamics.reference import move_reference
from drivetrain.dynamics.simulation import simulate


def _belt_chain(**changes: object) -> Chain:
    """The chain of examples/belt_dynamic.yaml's MQMF042L1 at the motor shaft (motor, gearbox output with
    the drive pulley, carriage): a 1.8 kHz pulley mode over a 250 Hz first mode."""
    chain = Chain(inertia=np.array([1.11e-4, 7.2e-6, 4.734e-4]), stiffness=np.array([412.53, 472.27]),
                  damping=np.array([0.02, 0.0]), backlash=np.array([7.27e-3, 0.0]),
                  efficiency=np.array([0.97, 0.95]), back_efficiency=np.array([0.97, 0.95]),
                  friction=(None, None, Friction(coulomb=0.0141)),
                  names=("motor", "gearbox", "load"))
    return chain.with_(**changes) if changes else chain


def test_lumping_keeps_the_total_inertia_and_puts_the_springs_in_series() -> None:
    chain = _belt_chain(spring_table=(np.array([0.0, 200.0]), np.array([472.27, 65.4])))
    red = lump_inertia(chain, 1)
    ka, kb = 412.53, 472.27
    assert red.n == 2
    assert red.total_inertia == pytest.approx(chain.total_inertia, rel=1e-12)
    assert red.inertia[0] == pytest.approx(1.11e-4 + 7.2e-6 * ka / (ka + kb), rel=1e-12)
    assert red.stiffness[0] == pytest.approx(ka * kb / (ka + kb), rel=1e-12)
    assert red.backlash[0] == pytest.approx(7.27e-3)
    assert red.efficiency[0] == pytest.approx(0.97 * 0.95)
    assert red.friction[-1] == chain.friction[-1]
    assert red.spring_table is not None
    assert red.spring_table[1] == pytest.approx(ka * chain.spring_table[1] / (ka + chain.spring_table[1]))
    # the series damping at the weakest belt: d = k^2 d_a / k_a^2
    kw = ka * 65.4 / (ka + 65.4)
    assert red.damping[0] == pytest.approx(kw**2 * 0.02 / ka**2, rel=1e-12)
    # the first mode moves by the O(epsilon^2) of the time-scale separation: well under 2 %
    assert natural_frequencies(red)[0] == pytest.approx(natural_frequencies(chain)[0], rel=0.02)


def test_only_a_damped_interior_inertia_far_above_the_loop_is_lumped() -> None:
    chain = _belt_chain()
    red, notes = reduce_for_simulation(chain, 27.5, 1000.0)
    assert red.n == 2 and len(notes) == 1 and "gearbox lumped" in notes[0]
    # the loop within a tenth of the mode, or a current loop above it: kept
    assert reduce_for_simulation(chain, 200.0, 1000.0)[0].n == 3
    assert reduce_for_simulation(chain, 27.5, 2000.0)[0].n == 3
    # an undamped pulley mode rings under the backlash's impacts: kept
    assert reduce_for_simulation(chain.with_(damping=[0.0, 0.0]), 27.5, 1000.0)[0].n == 3
    assert MIN_DAMPING > 0
    # friction on the pulley: kept
    assert reduce_for_simulation(chain.with_(friction=(None, Friction(coulomb=0.01), None)), 27.5, 1000.0)[0].n == 3
    # a heavy middle inertia (a mode the loop acts on): kept
    heavy = chain.with_(inertia=[1.11e-4, 2e-4, 4.734e-4])
    assert reduce_for_simulation(heavy, 27.5, 1000.0)[0].n == 3


def test_the_reduced_chain_moves_as_the_full_one() -> None:
    """Closed loop, tuned on the full chain: back-and-forth moves of 30 mm-equivalent at the motor with
    dwells; the reduced chain at ``reduced_step`` against the full chain at ``default_step``."""
    chain = _belt_chain()
    loop = tune(chain, None, current_bandwidth_hz=1000.0, velocity_sample_time=250e-6,
                current_sample_time=125e-6, position_sample_time=500e-6, notch=False, torque_limit=4.46)
    bw = analyse_loop(chain, loop).velocity_bandwidth_hz
    red, notes = reduce_for_simulation(chain, bw, 1000.0)
    assert notes
    h_red = reduced_step(chain, red, loop)
    assert h_red > 1.5 * default_step(chain, loop)
    ref = move_reference(20.0, 300.0, 3000.0, dwell=0.2, repeat=2)
    window = 20e-6 * 166.7  # 20 um at the load through the belt's 166.7 rad/m
    full = simulate(chain, loop, ref, step=default_step(chain, loop), settle_tolerance=window)
    fast = simulate(red, loop, ref, step=h_red, settle_tolerance=window)
    assert np.max(np.abs(fast.load_error)) == pytest.approx(np.max(np.abs(full.load_error)), rel=0.02)
    s_full, s_red = np.asarray(full.settling_time), np.asarray(fast.settling_time)
    assert np.all(np.isfinite(s_full)) and np.all(s_full > 0)
    assert s_red == pytest.approx(s_full, rel=0.10)
    assert math.isclose(red.total_inertia, chain.total_inertia, rel_tol=1e-12)


def test_a_reference_kept_on_the_simulation_grid_gives_the_same_run() -> None:
    """``reference_on_grid`` (the selection's candidates share it) changes no number of the run."""
    from drivetrain.dynamics.response import reference_on_grid

    chain = _belt_chain()
    loop = tune(chain, None, current_bandwidth_hz=1000.0, velocity_sample_time=250e-6,
                current_sample_time=125e-6, position_sample_time=500e-6, torque_limit=4.46)
    ref = move_reference(20.0, 300.0, 3000.0, dwell=0.05, repeat=2, step=3e-4)
    h = default_step(chain, loop)
    grid = reference_on_grid(ref, h)
    assert reference_on_grid(ref, h) is grid  # kept for the next candidate
    a = simulate(chain, loop, ref, step=h, settle_tolerance=1e-3)
    b = simulate(chain, loop, grid, step=h, settle_tolerance=1e-3)
    for name in ("load_error", "following_error", "torque"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    assert np.array_equal(a.settling_time, b.settling_time)
