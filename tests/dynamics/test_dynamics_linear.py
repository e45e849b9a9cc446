"""Linear models of the torsional chain: lecture numbers, closed forms, python-control parity."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from drivetrain.dynamics import (
    Chain,
    anti_resonance_frequencies,
    chain_from_spec,
    critical_speeds,
    discretize_zoh,
    excitation_orders,
    frequency_response,
    model_from_stages,
    modes,
    modes_summary,
    natural_frequencies,
    state_space,
    transfer_function,
    two_mass_chain,
    two_mass_reduction,
    two_mass_resonance,
)
from drivetrain.dynamics.linear import (
    mass_spring_damper,
    mass_spring_damper_final_value,
    mass_spring_damper_tf,
    state_space_matrices,
)
from drivetrain.dynamics.simulation import simulate_linear_exact
from drivetrain.dynamics.simulation_result import chain_energy
from drivetrain.errors import InputError
from drivetrain.physics.stage import Stage


def test_lecture_two_mass_82_7_hz() -> None:
    # Lecture, "Mechanical Vibration in Drive Trains", Example: a.c. motor 0.5 kg m^2 coupled to a
    # 0.4 kg m^2 load by a 60e3 N m/rad shaft: f_ntf = 82.7 Hz.
    f_r, f_ar = two_mass_resonance(0.5, 0.4, 60e3)
    assert f_r == pytest.approx(82.7, abs=0.1)
    assert f_ar == pytest.approx(math.sqrt(60e3 / 0.4) / (2 * math.pi))
    chain = chain_from_spec([{"inertia": "0.5 kg*m^2"}, {"stiffness": "60e3 N*m/rad"}, {"inertia": 0.4}])
    assert natural_frequencies(chain) == pytest.approx([82.7], abs=0.1)
    tm = two_mass_reduction(chain)
    assert tm.resonance_hz == pytest.approx(f_r)
    assert tm.anti_resonance_hz == pytest.approx(f_ar)
    assert tm.stiffness == pytest.approx(60e3)
    summary = modes_summary(chain)
    assert summary["natural_frequencies_Hz"] == pytest.approx([82.7], abs=0.1)


def test_three_equal_discs_closed_form() -> None:
    # Three equal discs J on two equal shafts K (free-free): omega^2 = K/J * {0, 1, 3}, the closed form
    # (the published numerical example is test_thomson_holzer_example_three_discs). Rigid-body mode left
    # out, ascending.
    j, k = 0.02, 5000.0
    chain = Chain(inertia=np.array([j, j, j]), stiffness=np.array([k, k]))
    freqs, shapes = modes(chain)
    expected = np.sqrt(np.array([1.0, 3.0]) * k / j) / (2 * math.pi)
    assert freqs == pytest.approx(expected, rel=1e-12)
    # mode shapes: (1, 0, -1) and (1, -2, 1), scaled to a largest entry of +1
    assert shapes[:, 0] == pytest.approx([1.0, 0.0, -1.0], abs=1e-9) or shapes[:, 0] == pytest.approx(
        [-1.0, 0.0, 1.0], abs=1e-9)
    assert shapes[:, 1] == pytest.approx([-0.5, 1.0, -0.5], abs=1e-9)


def test_thomson_holzer_example_three_discs() -> None:
    # Published multi-inertia chain: W. T. Thomson, "Theory of Vibration with Applications", chap. 12
    # "Classical Methods", sec. 12.4 "Holzer Method", Example 12.4-1 (Fig. 12.4-2) and Table 12.4-1,
    # book pp. 388-389 (Taylor & Francis printing; scanned at
    # https://digilib.universitaspertamina.ac.id/ebook/Theory%20of%20Vibration%20with%20Applications/files/basic-html/page401.html
    # and .../page402.html). Free-free disks J = 5, 11, 22 kg m^2 on shafts K1 = 0.10e6, K2 = 0.20e6 N m/rad.
    # The Holzer table starts with theta_1 = 1 and prints, for omega = 20 and 40 rad/s, the disk amplitudes,
    # the torque in shaft 2 (T2 = sum of the inertia torques of disks 1 and 2) and the torque T3 that must
    # act on the free end to keep the motion (zero at a natural frequency):
    #   omega  theta_2  theta_3  T2 [N m]   T3 [N m]
    #    20    0.980    0.9484   6.312e3   14.66e3
    #    40    0.920    0.799    24.19e3   52.32e3
    # Our model reproduces them as its steady-state response to a harmonic torque on the last disk (the
    # load-torque input, which enters with a minus sign: T_L = T3), to the rounding printed (half a unit
    # in the last printed digit). The book gives the natural frequencies only graphically (Fig. 12.4-3,
    # T3 against omega); the last check is that Holzer's residual torque vanishes at ours.
    chain = Chain(inertia=np.array([5.0, 11.0, 22.0]), stiffness=np.array([0.10e6, 0.20e6]))
    m = state_space_matrices(chain)
    eye = np.eye(6)
    for omega, th2, th3, t2, t3, d_th2, d_th3 in ((20.0, 0.980, 0.9484, 6.312e3, 14.66e3, 5e-4, 5e-5),
                                                  (40.0, 0.920, 0.799, 24.19e3, 52.32e3, 5e-4, 5e-4)):
        x = np.linalg.solve(1j * omega * eye - m.A, m.B[:, 1])  # response to T_L = 1 N m
        theta = x[:3].real / x[0].real  # undamped: in phase; normalised to theta_1 = 1 as the table
        assert np.max(np.abs(x[:3].imag)) < 1e-12 * np.max(np.abs(x[:3].real))
        assert theta[1] == pytest.approx(th2, abs=d_th2)
        assert theta[2] == pytest.approx(th3, abs=d_th3)
        assert 0.20e6 * (theta[1] - theta[2]) == pytest.approx(t2, abs=5.0)  # shaft-2 torque
        assert 1.0 / x[0].real == pytest.approx(t3, abs=5.0)  # T_L per unit theta_1
        g = frequency_response(chain, omega / (2 * math.pi), "load_torque", "motor_position")[0]
        assert 1.0 / g.real == pytest.approx(t3, abs=5.0)
    for f in natural_frequencies(chain):
        w2 = (2 * math.pi * f) ** 2
        th = [1.0]
        torque = w2 * 5.0
        th.append(th[0] - torque / 0.10e6)
        torque += w2 * 11.0 * th[1]
        th.append(th[1] - torque / 0.20e6)
        torque += w2 * 22.0 * th[2]
        assert abs(torque) < 1e-9 * w2 * 38.0  # the Holzer residual, relative to the inertia torques


def test_three_disc_general_characteristic_equation() -> None:
    # Free-free three-disc system: omega^4 - omega^2 (K1/J1 + K1/J2 + K2/J2 + K2/J3)
    #   + K1 K2 (J1 + J2 + J3) / (J1 J2 J3) = 0 (Den Hartog, Mechanical Vibrations, 4th ed., ch. 5).
    j1, j2, j3, k1, k2 = 1.3e-3, 4.0e-4, 2.2e-3, 900.0, 2500.0
    b = k1 / j1 + k1 / j2 + k2 / j2 + k2 / j3
    c = k1 * k2 * (j1 + j2 + j3) / (j1 * j2 * j3)
    w2 = np.array([(b - math.sqrt(b * b - 4 * c)) / 2, (b + math.sqrt(b * b - 4 * c)) / 2])
    chain = Chain(inertia=np.array([j1, j2, j3]), stiffness=np.array([k1, k2]))
    assert natural_frequencies(chain) == pytest.approx(np.sqrt(w2) / (2 * math.pi), rel=1e-10)


def test_state_space_load_torque_enters_negative() -> None:
    # ERRATA: J_y w_y' = K(th_m - th_y) - B_y w_y - T_y: the load torque enters with -1/J_y.
    chain = two_mass_chain(2e-4, 8e-4, 1000.0, damping=0.1)
    m = state_space_matrices(chain)
    assert m.B[2, 0] == pytest.approx(1 / 2e-4)
    assert m.B[3, 1] == pytest.approx(-1 / 8e-4)
    assert m.A[2, 0] == pytest.approx(-1000.0 / 2e-4)
    assert m.A[2, 1] == pytest.approx(1000.0 / 2e-4)
    assert m.A[3, 3] == pytest.approx(-0.1 / 8e-4)


def test_transfer_functions_python_control_and_numpy_agree() -> None:
    control = pytest.importorskip("control")
    chain = two_mass_chain(2e-4, 8e-4, 1000.0, damping=0.05)
    f = np.array([1.0, 30.0, 150.0, 400.0])
    s = 2j * math.pi * f
    for inp, out in (("motor_torque", "motor_speed"), ("motor_torque", "load_position"),
                     ("load_torque", "load_position")):
        direct = frequency_response(chain, f, inp, out)
        tf_np = transfer_function(chain, inp, out, as_control=False)
        tf_ct = transfer_function(chain, inp, out)
        assert isinstance(tf_ct, control.TransferFunction)
        assert tf_np(s) == pytest.approx(direct, rel=1e-8)
        assert np.asarray(tf_ct(s)).ravel() == pytest.approx(direct, rel=1e-8)
    # motor torque -> motor speed: 1/(J s) * (J_L s^2 + B s + K) / (J_L J_m / J s^2 + B s + K) type:
    # zero at the anti-resonance, pole at the resonance
    tf = transfer_function(chain, "motor_torque", "motor_speed", as_control=False)
    zeros = np.roots(tf.num)
    f_ar = anti_resonance_frequencies(chain)[0]
    assert np.max(np.abs(zeros)) / (2 * math.pi) == pytest.approx(f_ar, rel=1e-3)
    ss = state_space(chain)
    assert isinstance(ss, control.StateSpace)
    assert isinstance(state_space(chain, as_control=False).A, np.ndarray)


def test_mass_spring_damper_final_value_is_one_over_k() -> None:
    # Lecture, "Example: Mass-Spring-Damper": X(s) = 1/(s(m s^2 + B s + k)), x_inf = 1/k.
    m, b, k = 2.0, 3.0, 50.0
    assert mass_spring_damper_final_value(k) == pytest.approx(1 / k)
    sys = mass_spring_damper(m, b, k)
    phi, gamma = discretize_zoh(sys.A, sys.B, 0.01)
    x = np.zeros(2)
    for _ in range(5000):  # 50 s, many time constants (2 m / B = 1.33 s)
        x = phi @ x + gamma[:, 0] * 1.0
    assert x[0] == pytest.approx(1 / k, rel=1e-9)
    tf = mass_spring_damper_tf(m, b, k)
    assert tf(np.array([1e-9j]))[0].real == pytest.approx(1 / k, rel=1e-6)


def test_zoh_matches_closed_form_of_first_order() -> None:
    # y' = -a y + b u (lecture, "Continuous time"): Phi = e^{-aT}, Gamma = b (1 - e^{-aT}) / a
    a, b, t = 3.0, 2.0, 0.05
    phi, gamma = discretize_zoh([[-a]], [[b]], t)
    assert phi[0, 0] == pytest.approx(math.exp(-a * t), rel=1e-14)
    assert gamma[0, 0] == pytest.approx(b * (1 - math.exp(-a * t)) / a, rel=1e-12)


def test_exact_stepping_conserves_energy_over_1e5_steps() -> None:
    # A lossless three-mass chain stepped by the matrix exponential keeps its energy to 1e-9.
    chain = Chain(inertia=np.array([1e-4, 3e-4, 5e-4]), stiffness=np.array([500.0, 800.0]))
    n_steps = 100_000
    t = np.arange(n_steps + 1) * 1e-4
    x0 = np.array([0.01, 0.0, -0.004, 0.0, 2.0, -1.0])
    x = simulate_linear_exact(chain, t, 0.0, 0.0, x0)
    e = chain_energy(chain, x[:, :3], x[:, 3:])
    assert np.max(np.abs(e - e[0])) / e[0] < 1e-9


def test_exact_and_kernel_match_python_control_forced_response() -> None:
    control = pytest.importorskip("control")
    chain = two_mass_chain(2e-4, 6e-4, 800.0, damping=0.02)
    h = 2e-5
    t = np.arange(0, 0.2 + h / 2, h)
    u = 0.3 * np.sin(2 * math.pi * 25 * t) + 0.1 * (t > 0.05)
    sys = state_space(chain)
    ref = control.forced_response(sys, t, np.vstack([u, np.zeros_like(u)]))
    y_ref = np.asarray(ref.outputs)  # (4, samples): angles then speeds
    scale = np.max(np.abs(y_ref[1]))
    # exact ZOH stepping: differs from forced_response's interpolated input only by O(h^2)
    x = simulate_linear_exact(chain, t, u)
    assert np.max(np.abs(x[:, 1] - y_ref[1])) < 5e-4 * scale
    # the nonlinear kernel with no nonlinearity (semi-implicit Euler, O(h))
    from drivetrain.dynamics import simulate_open_loop

    res = simulate_open_loop(chain, t, u)
    assert np.max(np.abs(res.states["theta_load"] - y_ref[1])) < 1e-5 * scale
    assert np.max(np.abs(res.states["omega_motor"] - y_ref[2])) < 2e-3 * np.max(np.abs(y_ref[2]))


def test_critical_speeds_campbell() -> None:
    # the lecture's 82.7 Hz shaft: 1x unbalance crosses at 82.7 rev/s = 4962 rpm; 6x ripple at 827 rpm
    chain = two_mass_chain(0.5, 0.4, 60e3)
    f = natural_frequencies(chain)
    orders = excitation_orders(torque_ripple=(6,), gear_teeth=[(20, 1.0)])
    hits = critical_speeds(f, 0.0, 6000 * 2 * math.pi / 60, orders)
    rpm = {h.excitation: h.speed_rpm for h in hits}
    assert rpm["unbalance (1x)"] == pytest.approx(f[0] * 60, rel=1e-12)
    assert rpm["torque ripple (6x)"] == pytest.approx(f[0] * 10, rel=1e-12)
    assert rpm["gear mesh (20 teeth)"] == pytest.approx(f[0] * 3, rel=1e-12)
    assert [h.speed_rad_s for h in hits] == sorted(h.speed_rad_s for h in hits)
    assert critical_speeds(f, 0.0, 100.0, {"1x": 1.0}) == []


@pytest.mark.parametrize(
    ("spec", "field"),
    [
        ([{"inertia": 0.5}, {"stiffness": -5}, {"inertia": 0.4}], "dynamics.chain[1].stiffness"),
        ([{"inertia": 0.0}, {"stiffness": 5}, {"inertia": 0.4}], "dynamics.chain[0].inertia"),
        ([{"inertia": 0.5}, {"inertia": 0.4}, {"inertia": 0.4}], "dynamics.chain[1]"),
        ([{"inertia": 0.5}, {"backlash": "1 arcmin"}, {"inertia": 0.4}], "dynamics.chain[1].stiffness"),
        ([{"inertia": 0.5}, {"stiffness": float("nan")}, {"inertia": 0.4}], "dynamics.chain[1].stiffness"),
        ([{"inertia": 0.5}, {"stiffness": 100.0}], "dynamics.chain[1]"),
        ([{"inertia": 0.5}, {"stiffness": "3 kg"}, {"inertia": 0.4}], "dynamics.chain[1].stiffness"),
        ([{"inertia": 0.5}, {"stiffness": 10, "backlash": -1e-3}, {"inertia": 0.4}], "dynamics.chain[1].backlash"),
        ([{"inertia": 0.5, "colour": "red"}], "dynamics.chain[0].colour"),
        ([{"inertia": 0.5, "friction": {"coulomb": 1.0, "static": 0.5}}], "dynamics.chain[0].friction.static"),
        ([], "dynamics.chain"),
    ],
)
def test_chain_spec_errors_name_the_field(spec: list[dict[str, Any]], field: str) -> None:
    with pytest.raises(InputError) as err:
        chain_from_spec(spec)
    assert err.value.field == field
    assert field in str(err.value)


def test_chain_spec_units_and_round_trip() -> None:
    chain = chain_from_spec([
        {"inertia": "1 kg*cm^2", "friction": {"coulomb": "0.02 N*m", "static": 0.03, "method": "tanh"}},
        {"stiffness": "500 N*m/rad", "damping": 0.01, "backlash": "1 arcmin", "efficiency": 0.9},
        {"inertia": "5 kg*cm^2", "name": "table"},
    ])
    assert chain.inertia == pytest.approx([1e-4, 5e-4])
    assert chain.backlash[0] == pytest.approx(math.pi / 10800)
    assert chain.back_efficiency[0] == pytest.approx(0.9)
    assert chain.names == ("motor", "table")
    assert chain.friction[0] is not None and chain.friction[0].method == "tanh"
    again = chain_from_spec(chain.to_spec())
    assert again.inertia == pytest.approx(chain.inertia)
    assert again.stiffness == pytest.approx(chain.stiffness)
    assert again.backlash == pytest.approx(chain.backlash)


def test_model_from_stages_reflects_through_ratios() -> None:
    # motor 1e-4; gearbox i = 5 (input inertia 2e-5, output stiffness 3437.7 N m/rad reflected to its
    # input as given: 137.5 N m/rad there, backlash 0.6 mrad at its input) -> coupling (rigid, 1e-5 at
    # the gearbox output) -> load 0.05 kg m^2 at the output.
    gear = Stage(name="gearbox", kind="gearbox", ratio=5.0, inertia_in=2e-5, inertia_inside=1e-5,
                 efficiency=0.95, back_efficiency=0.9, stiffness=137.5, damping=0.02, backlash=6e-4)
    coupling = Stage(name="coupling", kind="coupling", ratio=1.0, inertia_in=1e-5, efficiency=0.99)
    chain = model_from_stages(1e-4, [gear, coupling], 0.05)
    assert chain.n == 2
    assert chain.inertia[0] == pytest.approx(1e-4 + 2e-5)
    assert chain.inertia[1] == pytest.approx(1e-5 + (1e-5 + 0.05) / 25.0)
    assert chain.stiffness[0] == pytest.approx(137.5)
    assert chain.backlash[0] == pytest.approx(6e-4)
    assert chain.efficiency[0] == pytest.approx(0.95 * 0.99)
    assert chain.ratio == pytest.approx(5.0)
    # a second compliance after the gearbox is reflected by 1/i^2 and its backlash by i
    shaft = Stage(name="shaft", kind="coupling", ratio=1.0, inertia_in=0.0, inertia_inside=2e-3,
                  stiffness=2000.0, backlash=1e-3)
    chain3 = model_from_stages(1e-4, [gear, shaft], 0.05)
    assert chain3.n == 3
    assert chain3.stiffness[1] == pytest.approx(2000.0 / 25.0)
    assert chain3.backlash[1] == pytest.approx(5e-3)
    assert chain3.inertia[2] == pytest.approx((2e-3 + 0.05) / 25.0)
    # all rigid: one inertia, total equals the rigid sum
    rigid = model_from_stages(1e-4, [coupling], 0.01)
    assert rigid.n == 1
    assert rigid.total_inertia == pytest.approx(1e-4 + 1e-5 + 0.01)
    with pytest.raises(InputError) as err:
        model_from_stages(1e-4, [Stage(name="g", kind="gearbox", ratio=2.0, stiffness=-1.0)], 0.01)
    assert err.value.field == "transmission[0].stiffness"
