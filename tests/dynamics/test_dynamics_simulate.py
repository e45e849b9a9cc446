"""The compiled nonlinear simulation: integrator accuracy, physics of the nonlinear elements,
closed-loop behaviour, and clear errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drivetrain.dynamics import (
    Chain,
    Friction,
    Notch,
    Reference,
    SimulationDivergedError,
    move_reference,
    natural_frequencies,
    simulate,
    simulate_open_loop,
    sweep,
    tune,
    two_mass_chain,
)
from drivetrain.dynamics.friction import friction_torque_exponential, friction_torque_tanh
from drivetrain.dynamics.kernel_io import default_step
from drivetrain.dynamics.linear import second_order_step
from drivetrain.dynamics.simulation import simulate_linear_exact
from drivetrain.dynamics.simulation_result import chain_energy
from drivetrain.errors import InputError


def _stick_phases(speed: np.ndarray) -> int:
    """Number of intervals (>= 2 samples) in which the speed is exactly zero."""
    d = np.diff(np.r_[0, (speed == 0.0).astype(int), 0])
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
    return int(np.sum(ends - starts >= 2))


def test_default_integrator_energy_error_is_bounded_and_does_not_drift() -> None:
    # Semi-implicit Euler on a lossless chain: the energy error oscillates with a relative amplitude
    # below h * omega_max / 2 and does not drift (symplectic), here over 1e5 steps.
    chain = Chain(inertia=np.array([1e-4, 3e-4, 5e-4]), stiffness=np.array([500.0, 800.0]))
    w_max = 2 * math.pi * natural_frequencies(chain)[-1]
    h = 5e-5
    t = np.arange(100_001) * h
    r = simulate_open_loop(chain, t, np.zeros_like(t), theta0=[0.01, 0.0, -0.004], omega0=[2.0, 0.0, -1.0])
    th = np.column_stack([r.states[f"theta_{n}"] for n in chain.names])
    w = np.column_stack([r.states[f"omega_{n}"] for n in chain.names])
    e = chain_energy(chain, th, w)
    assert np.max(np.abs(e - e[0])) / e[0] < h * w_max / 2
    drift = abs(np.mean(e[-10_000:]) - np.mean(e[:10_000])) / e[0]
    assert drift < 1e-3


def test_two_mass_twist_step_matches_second_order_closed_form() -> None:
    # A step torque T on the motor of a two-mass chain: the twist d = th_m - th_l obeys
    # mu d'' + D d' + K d = T J_l / (J_m + J_l), mu = J_m J_l / (J_m + J_l) (Ogata 5th ed., sec. 5-3).
    jm, jl, k, d = 2e-4, 6e-4, 800.0, 0.02
    chain = two_mass_chain(jm, jl, k, damping=d)
    mu = jm * jl / (jm + jl)
    torque = 0.5
    h = 1e-5
    t = np.arange(0, 0.1 + h / 2, h)
    closed = second_order_step(mu, d, k, t, force=torque * jl / (jm + jl))
    x = simulate_linear_exact(chain, t, np.full_like(t, torque))
    assert np.max(np.abs((x[:, 0] - x[:, 1]) - closed)) < 1e-9 * np.max(np.abs(closed))
    r = simulate_open_loop(chain, t, np.full_like(t, torque))
    twist = r.states["theta_motor"] - r.states["theta_load"]
    assert np.max(np.abs(twist - closed)) < 2e-2 * np.max(np.abs(closed))
    assert twist[-1] == pytest.approx(torque * jl / (jm + jl) / k, rel=0.05)


@pytest.mark.parametrize("static", [1.5, 1.0])
def test_stick_slip_appears_only_with_static_above_sliding(static: float) -> None:
    # A slow drive through a soft spring: a heavy motor turning at 0.5 rad/s pulls a 0.01 kg m^2 load
    # through a 10 N m/rad spring against Coulomb friction 1 N m. With a breakaway of 1.5 N m the load
    # sticks again and again; with breakaway == sliding it sticks once (at the start) and then slides.
    fr = Friction(coulomb=1.0, static=static, stribeck_speed=0.05)
    chain = Chain(inertia=np.array([1e3, 0.01]), stiffness=np.array([10.0]), damping=np.array([0.05]),
                  friction=(None, fr))
    t = np.arange(0, 4.0 + 1e-9, 1e-4)
    r = simulate_open_loop(chain, t, np.zeros_like(t), omega0=[0.5, 0.0])
    w = r.states["omega_load"]
    late = w[t > 1.0]
    if static > 1.0:
        assert _stick_phases(late) >= 5
        assert np.max(w) > 1.5 * 0.5  # slips overshoot the drive speed
    else:
        assert _stick_phases(w) == 1
        assert np.min(late) > 0.1


def test_elasto_backlash_no_torque_in_gap_and_no_pulling() -> None:
    # Modelica ElastoBacklash: zero torque inside the gap, never pulling, continuous at contact.
    gap = 0.02
    chain = Chain(inertia=np.array([1e-3, 1e-3]), stiffness=np.array([100.0]), damping=np.array([0.05]),
                  backlash=np.array([gap]))
    h = 1e-5
    t = np.arange(0, 0.5, h)
    u = 0.05 * np.sign(np.sin(2 * math.pi * 4 * t))
    r = simulate_open_loop(chain, t, u)
    rel = r.states["theta_motor"] - r.states["theta_load"]
    tau = r.states["shaft_torque_0"]
    inside = np.abs(rel) < gap / 2
    assert inside.any() and (~inside).any()
    assert np.all(tau[inside] == 0.0)
    assert np.all(tau * np.sign(rel) >= 0.0)  # pushes in the direction of the twist, never pulls
    # continuity: no sample jumps by more than what the spring and damper can build in one step
    assert np.max(np.abs(np.diff(tau))) < 100.0 * np.max(np.abs(np.diff(rel))) * 2 + 1e-9


def test_lossy_gear_self_locking_holds_and_backdrivable_runs_away() -> None:
    # Modelica LossyGear: with back_efficiency <= 0 the load cannot drive the gear back.
    t = np.arange(0, 0.3, 1e-4)
    for back, moves in ((-0.2, False), (0.5, True)):
        chain = Chain(inertia=np.array([1e-4, 1e-3]), stiffness=np.array([200.0]),
                      efficiency=np.array([0.6]), back_efficiency=np.array([back]))
        r = simulate_open_loop(chain, t, np.zeros_like(t), load_torque=0.1)
        assert bool(abs(r.states["theta_load"][-1]) > 1.0) == moves
    # forward, the gear passes eta times the spring torque: twist at constant acceleration
    chain = Chain(inertia=np.array([1e-4, 1e-3]), stiffness=np.array([2000.0]), damping=np.array([0.5]),
                  efficiency=np.array([0.6]), back_efficiency=np.array([0.5]))
    r = simulate_open_loop(chain, np.arange(0, 0.2, 1e-5), np.full(20000, 0.07))
    # steady state: J_l a = 0.6 T_s, J_m a = T - T_s -> T_s = T / (1 + 0.6 J_m / J_l)
    ts_expected = 0.07 / (1 + 0.6 * 1e-4 / 1e-3)
    assert r.states["shaft_torque_0"][-1] == pytest.approx(ts_expected, rel=0.02)


def test_friction_forms() -> None:
    # exponential: T_S at zero speed (from either side), T_C + b w far away; tanh: peak near T_S
    assert float(friction_torque_exponential(1e-9, 1.0, 1.5, 0.01, 0.1)) == pytest.approx(1.5, rel=1e-6)
    assert float(friction_torque_exponential(-10.0, 1.0, 1.5, 0.01, 0.1)) == pytest.approx(-1.1)
    w = np.linspace(0, 1.0, 20001)
    tanh = friction_torque_tanh(w, 1.0, 1.5, 0.0, 0.1)
    assert np.max(tanh) == pytest.approx(1.5, rel=0.03)
    assert float(tanh[-1]) == pytest.approx(1.0, rel=1e-3)
    with pytest.raises(InputError) as err:
        Friction(coulomb=1.0, static=1.0, method="magic")
    assert err.value.field == "friction.method"


def _axis(method: str = "exponential") -> Chain:
    fr = Friction(coulomb=0.02, static=0.03, viscous=1e-5, stribeck_speed=1.0, method=method)
    chain = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002, backlash=1e-3)
    return chain.with_(friction=(fr, fr))


def test_closed_loop_follows_the_profile_and_reports() -> None:
    chain = _axis()
    loop = tune(chain, torque_limit=2.0, encoder_resolution=2 * math.pi / 2**20)
    ref = move_reference(10.0, 100.0, 2000.0, dwell=0.3, repeat=2)
    res = simulate(chain, loop, ref)
    assert res.max_load_error < 0.05
    assert res.peak_torque <= 2.0 + 1e-12
    assert res.settling_time.size == 2 and np.all(np.isfinite(res.settling_time))
    assert res.load_error[-1] == pytest.approx(0.0, abs=5e-3)
    assert res.peak_shaft_torque[0] > 0.0
    assert res.energy > 0.0
    # the encoder quantises the measured position; the following error is sampled with the
    # position loop, so reference and measurement are compared at the same instants
    q = loop.encoder_resolution
    step = res.time[1] - res.time[0]
    n_pos = round(loop.position_sample_time / step)
    at = np.arange(0, res.time.size, n_pos)
    meas = res.states["reference_position"][at] - res.following_error[at]
    assert np.max(np.abs(meas / q - np.round(meas / q))) < 1e-6
    held = res.following_error[at[:-1, None] + np.arange(n_pos)[None, :]]
    assert np.all(held == held[:, :1])
    d = res.to_dict()
    assert set(d) >= {"max_following_error_rad", "settling_time_s", "overshoot_rad", "energy_J",
                      "peak_shaft_torque_Nm", "load_vibration_amplitude_rad"}
    df = res.to_pandas()
    assert len(df) == res.time.size and "omega_load" in df
    fig = res.plot()
    assert len(fig.axes) == 3
    tanh = simulate(_axis("tanh"), loop, ref)
    assert tanh.max_load_error < 0.05


def test_gravity_start_is_in_equilibrium() -> None:
    # Holding a constant load torque from the start: no transient; the motor sits on its target and
    # the load sags by the spring's twist T/K (motor-side feedback cannot see it).
    chain = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002)
    loop = tune(chain)
    t = np.linspace(0, 0.2, 11)
    ref = Reference.from_arrays(t, np.zeros_like(t))
    res = simulate(chain, loop, ref, load_torque=0.3)
    assert np.max(np.abs(res.following_error)) < 1e-9
    assert res.load_error == pytest.approx(np.full(res.time.size, 0.3 / 500.0), rel=1e-6)
    assert np.max(np.abs(res.states["omega_load"])) < 1e-9
    assert res.torque == pytest.approx(np.full(res.time.size, 0.3), rel=1e-9)


def test_diverging_simulation_raises_a_clear_error() -> None:
    chain = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002)
    loop = tune(chain)
    bad = loop.with_(velocity_kp=30 * loop.velocity_kp)
    ref = move_reference(5.0, 50.0, 1000.0, dwell=0.2)
    with pytest.raises(InputError) as err:
        simulate(chain, bad, ref)
    assert err.value.field == "dynamics.loop"
    with pytest.raises(SimulationDivergedError) as div:
        simulate(chain, bad, ref, check_stability=False)
    assert "diverged at t =" in str(div.value) and "unstable" in str(div.value)


def test_step_and_sample_time_checks() -> None:
    chain = two_mass_chain(1e-4, 5e-4, 500.0)
    loop = tune(chain)
    ref = move_reference(1.0, 10.0, 100.0)
    with pytest.raises(InputError) as err:
        simulate(chain, loop, ref, step=2e-3)
    assert err.value.field == "simulation.step"
    with pytest.raises(InputError) as err:
        simulate(chain, loop.with_(velocity_sample_time=1e-4), ref, step=62.5e-6)
    assert err.value.field == "dynamics.control.velocity_sample_time"


def test_sweep_runs_many_and_flags_divergence() -> None:
    chain = _axis()
    loop = tune(chain, current_sample_time=1e-4, velocity_sample_time=1e-4, position_sample_time=2e-4)
    ref = move_reference(5.0, 100.0, 2000.0, dwell=0.1)
    kp = np.array([1.0, 0.5, 30.0]) * loop.velocity_kp
    out = sweep(chain, loop, ref, velocity_kp=kp, stiffness=[500.0, 300.0, 500.0], step=1e-4)
    assert out["diverged"].tolist() == [False, False, True]
    single = simulate(chain.with_(stiffness=[300.0]), loop.with_(velocity_kp=kp[1]), ref, step=1e-4,
                      check_stability=False)
    assert out["max_load_error_rad"][1] == pytest.approx(single.max_load_error, rel=1e-9)
    assert out["peak_shaft_torque_Nm"][1, 0] == pytest.approx(single.peak_shaft_torque[0], rel=1e-9)


def test_two_mass_kernel_matches_the_general_kernel(monkeypatch: pytest.MonkeyPatch) -> None:
    # The two-mass kernel (state in scalars) and the N-mass kernel (state in arrays) carry the same
    # equations; run both on the same axis: closed loop with stick friction, backlash, a notch and a
    # torque limit; the smooth friction form; and open loop through a lossy gear.
    from drivetrain.dynamics import _kernel

    chain = _axis()
    loop = tune(chain, torque_limit=0.8, encoder_resolution=2 * math.pi / 2**16)
    loop = loop.with_(notch=Notch(center_hz=400.0, width_hz=200.0, depth=0.2), lowpass_hz=2000.0)
    ref = move_reference(5.0, 100.0, 2000.0, dwell=0.1)
    geared = Chain(inertia=np.array([1e-4, 1e-3]), stiffness=np.array([2000.0]), damping=np.array([0.5]),
                   efficiency=np.array([0.6]), back_efficiency=np.array([0.5]))
    t = np.arange(0, 0.05, 1e-5)
    u = 0.07 * np.sign(np.sin(2 * math.pi * 40 * t))

    def runs() -> list[np.ndarray]:
        out = []
        for c in (chain, _axis("tanh")):
            res = simulate(c, loop, ref, check_stability=False)
            out.append(np.vstack([res.states[k] for k in res.states]))
            out.append(np.array([res.energy, res.peak_torque, res.max_load_error, *res.peak_shaft_torque]))
        res = simulate_open_loop(geared, t, u, load_torque=0.01)
        out.append(np.vstack([res.states[k] for k in res.states]))
        return out

    fast = runs()
    monkeypatch.setattr(_kernel, "run_two", _kernel.run_chain)
    general = runs()
    for a, b in zip(fast, general, strict=True):
        scale = np.maximum(np.max(np.abs(a), axis=-1, keepdims=True), 1e-12)
        assert np.max(np.abs(a - b) / scale) < 1e-9


def test_kernels_compile_one_specialisation_each() -> None:
    # simulate, simulate_open_loop and sweep all call the kernels with the same argument types, so each
    # kernel is compiled (or loaded from the cache) once, whatever the model
    from drivetrain.dynamics import _kernel

    three = Chain(inertia=np.array([1e-4, 3e-4, 5e-4]), stiffness=np.array([500.0, 800.0]),
                  friction=(Friction(coulomb=0.01, static=0.02, stribeck_speed=0.5), None, None))
    ref = move_reference(1.0, 20.0, 400.0, dwell=0.05)
    for chain in (_axis(), three):
        loop = tune(chain)
        simulate(chain, loop, ref)
        simulate_open_loop(chain, np.arange(0, 0.01, 1e-5), np.full(1000, 0.01))
        sweep(chain, loop, ref, velocity_kp=[loop.velocity_kp, 0.8 * loop.velocity_kp])
    assert len(_kernel.run_two.signatures) == 1
    assert len(_kernel.run_chain.signatures) == 1


def test_sweep_of_a_three_mass_chain_matches_single_runs() -> None:
    chain = Chain(inertia=np.array([1e-4, 3e-4, 5e-4]), stiffness=np.array([500.0, 800.0]),
                  damping=np.array([0.002, 0.002]), backlash=np.array([0.0, 1e-3]))
    loop = tune(chain)
    ref = move_reference(2.0, 50.0, 1000.0, dwell=0.05)
    kk = np.array([[500.0, 800.0], [400.0, 900.0]])
    out = sweep(chain, loop, ref, stiffness=kk)
    h = default_step(chain.with_(stiffness=kk.max(axis=0)), loop)  # sweep's step (simulate's own is refined)
    for s in range(2):
        single = simulate(chain.with_(stiffness=kk[s]), loop, ref, step=h, check_stability=False)
        assert out["max_load_error_rad"][s] == pytest.approx(single.max_load_error, rel=1e-9)
        assert out["peak_shaft_torque_Nm"][s] == pytest.approx(single.peak_shaft_torque, rel=1e-9)
        assert out["energy_J"][s] == pytest.approx(single.energy, rel=1e-9)


def _settling_agrees(a: np.ndarray, b: np.ndarray, sample: float) -> bool:
    """Settling times agree within simulate's stated tolerance: 2 % or one position-loop sample."""
    if a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
        return False
    ok = ~np.isnan(b)
    return bool(np.all(np.abs(a[ok] - b[ok]) <= np.maximum(0.02 * b[ok], sample)))


def test_automatic_step_settling_agrees_with_a_four_times_finer_run() -> None:
    # a compliant chain with backlash and load friction, settling into a window a third of the play:
    # at default_step (step x omega_max <= 0.2) the second stop never settles, at a 4x finer step it does
    fr = Friction(coulomb=0.02, static=0.03, viscous=1e-5, stribeck_speed=1.0)
    chain = two_mass_chain(1e-4, 5e-4, 2000.0, damping=0.002, backlash=1e-3).with_(friction=(None, fr))
    loop = tune(chain)
    ref = move_reference(2.0, 50.0, 1000.0, dwell=0.15, repeat=2)
    window = 3e-4
    h0 = default_step(chain, loop)
    plain = simulate(chain, loop, ref, step=h0, settle_tolerance=window)
    plain_fine = simulate(chain, loop, ref, step=h0 / 4, settle_tolerance=window)
    assert not _settling_agrees(plain.settling_time, plain_fine.settling_time, loop.position_sample_time)

    auto = simulate(chain, loop, ref, settle_tolerance=window)
    assert auto.step_converged is True
    assert auto.step < h0
    finer = simulate(chain, loop, ref, step=auto.step / 4, settle_tolerance=window)
    assert np.all(~np.isnan(finer.settling_time))
    assert _settling_agrees(auto.settling_time, finer.settling_time, loop.position_sample_time)
    for got, want in ((auto.max_following_error, finer.max_following_error),
                      (auto.max_load_error, finer.max_load_error)):
        assert abs(got - want) <= max(0.02 * want, 0.02 * window)


def test_a_given_step_is_kept_and_reported() -> None:
    chain = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002)
    loop = tune(chain)
    ref = move_reference(1.0, 50.0, 1000.0, dwell=0.05)
    h0 = default_step(chain, loop)
    given = simulate(chain, loop, ref, step=h0 / 2)
    assert given.step == h0 / 2 and given.step_converged is None
    assert given.to_dict()["step_s"] == h0 / 2
    auto = simulate(chain, loop, ref)
    assert auto.step_converged is True and auto.step in {h0 / 2**k for k in range(1, 6)}


def test_a_step_refined_as_far_as_allowed_without_agreeing_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.dynamics import simulation

    fr = Friction(coulomb=0.02, static=0.03, viscous=1e-5, stribeck_speed=1.0)
    chain = two_mass_chain(1e-4, 5e-4, 2000.0, damping=0.002, backlash=1e-3).with_(friction=(None, fr))
    loop = tune(chain)
    ref = move_reference(2.0, 50.0, 1000.0, dwell=0.15, repeat=2)
    monkeypatch.setattr(simulation, "MAX_REFINEMENT", 2)  # this case needs default_step / 4
    res = simulate(chain, loop, ref, settle_tolerance=3e-4)
    assert res.step == default_step(chain, loop) / 2
    assert res.step_converged is False
    assert res.to_dict()["step_converged"] is False
