"""The motor's electrical model and the drive's current checks: published examples and invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.physics.drive_overload import (
    i2t_accumulator,
    i2t_periodic,
    i2t_setpoint,
    i2t_trip_time,
    peak_time,
    rms_current,
)
from drivetrain.physics.motor_electrical import (
    SQRT2,
    Saturation,
    base_speed,
    current_from_torque,
    dc_bus_voltage,
    ke_line_rms,
    ke_si,
    kt_from_ke,
    max_phase_voltage,
    no_load_speed,
    phase_value,
    terminal_voltage,
    torque_from_current,
    torque_speed_curve,
    voltage_limited_current,
)

RPM = 2 * math.pi / 60

# MathWorks Motor Control Blockset, mcb.getPMSMParameters("BLY171D") (Anaheim BLY171D-24V-4000):
# p = 4, Rs = 0.75 ohm, Ld = Lq = 0.001 H, Ke = 3.8 (V peak line-to-line per krpm), I_rated = 1.8 A
# (dq amplitude), FluxPM = 0.0052 Wb, T_rated = 0.0566 N m; mcb.getInverterParameters("DRV8312-C2-KIT"):
# V_dc = 24 V. https://uk.mathworks.com/help/mcb/ref/mcb.getpmsmparameters.html,
# https://www.mathworks.com/help/mcb/ref/mcb.getinverterparameters.html
BLY_P, BLY_R, BLY_L, BLY_KE, BLY_I_AMPL, BLY_VDC = 4, 0.75, 0.001, 3.8, 1.8, 24.0

# Siemens SINAMICS S120 1FT7 Configuration Manual (PFT7S) 01/2009, Table 4-8 "1FT7044-AK7", p. 90
# (shipped in catalog/data/motors_ac_servo_electrical.csv): rated 2 N m at 6000 rpm (catalog row),
# I_N 2.5 A, M_0 5 N m at I_0 5.7 A (100 K), I_max 30 A at M_max 23 N m, k_T 0.88 N m/A,
# k_E 57 V/krpm, R_ph 0.61 ohm, L_D 4.2 mH, 6 poles; S120 on 400 V 3 AC: 600 V DC link.
FT_KT, FT_KE, FT_R, FT_L, FT_P = 0.88, 57.0, 0.61, 0.0042, 3
FT_TN, FT_NN, FT_IN, FT_M0, FT_I0, FT_TMAX, FT_IMAX = 2.0, 6000.0, 2.5, 5.0, 5.7, 23.0, 30.0
FT_SAT = Saturation(np.array(FT_TN), np.array(FT_TMAX), np.array(FT_IMAX))
FT_VDC = 600.0


# ------------------------------------------------------------------------------ constants


def test_flux_linkage_of_the_bly171d_from_its_ke() -> None:
    """MathWorks prints FluxPM = 0.0052 Wb for Ke = 3.8 V/krpm (line-to-line peak), p = 4 (to its 4 decimals)."""
    psi = float(ke_si(BLY_KE, "ll_peak")) / BLY_P
    assert psi == pytest.approx(0.0052, abs=0.5e-4)


def test_rated_and_base_torque_of_the_bly171d() -> None:
    """T = 3/2 p psi i_q: MathWorks T_rated 0.0566 N m at 1.8 A and T_base 0.2718 N m at I_base 8.6478 A.

    Sources: mcb.getPMSMParameters (T_rated), mcb.getPUSystemParameters (T_base, I_base), both for
    the BLY171D; the printed values carry 3 significant figures (T_rated) and 4 decimals (T_base).
    """
    kt = float(kt_from_ke(ke_si(BLY_KE, "ll_peak")))
    assert kt * BLY_I_AMPL / SQRT2 == pytest.approx(0.0566, abs=0.5e-4)
    assert kt * 8.6478 / SQRT2 == pytest.approx(0.2718, abs=0.5e-4)


def test_ke_conventions_agree() -> None:
    ll_rms = ke_si(57.0, "ll_rms")
    assert float(ke_si(57.0 * SQRT2, "ll_peak")) == pytest.approx(float(ll_rms), rel=1e-12)
    assert float(ke_si(57.0 / math.sqrt(3), "phase_rms")) == pytest.approx(float(ll_rms), rel=1e-12)
    assert float(ke_line_rms(ll_rms)) == pytest.approx(57.0 / 1000 * 60 / (2 * math.pi), rel=1e-12)
    # Kt = sqrt(3) Ke_LL,rms (SI) = 0.01654 Ke [V/krpm]
    assert float(kt_from_ke(ll_rms)) == pytest.approx(0.016540 * 57.0, rel=1e-4)
    with pytest.raises(ValueError, match="basis"):
        ke_si(57.0, "rms")


def test_siemens_kt_is_the_hot_value_below_the_ideal_sqrt3_ke() -> None:
    """1FT7044-5AK7: sqrt(3) k_E = 0.943 N m/A at 20 degC; the printed k_T (100 K rise) is 0.88, 7 % less."""
    ideal = float(kt_from_ke(ke_si(FT_KE, "ll_rms")))
    assert ideal == pytest.approx(0.943, abs=0.5e-3)
    assert 0.90 < FT_KT / ideal < 0.95  # NdFeB loses about 0.1 %/K of remanence; 100 K -> about 7-10 %


def test_phase_values_and_bus_voltage() -> None:
    assert float(phase_value(1.22, "line_to_line")) == pytest.approx(0.61)
    assert float(phase_value(0.61, "phase")) == 0.61
    with pytest.raises(ValueError):
        phase_value(1.0, "delta")
    assert float(dc_bus_voltage(400.0)) == pytest.approx(565.69, abs=0.01)
    assert float(max_phase_voltage(24.0)) == pytest.approx(13.8564, abs=1e-4)  # MathWorks V_base of the DRV8312


# --------------------------------------------------------------------- voltage-limited speed


def test_base_speed_of_the_bly171d_on_a_24_v_bus() -> None:
    """MathWorks mcb.PMSMSpeeds, BLY171D on DRV8312-C2-KIT: first milestone (base) speed 5393 rpm at i_q = 1.8 A.

    Source: https://uk.mathworks.com/help/mcb/ref/mcb.pmsmspeeds.html (output 5393; electrical
    speed 2259.1 rad/s). MathWorks' approximate voltage equations take R i_max off v_max
    arithmetically (mcb.getMotorBaseSpeed); that method reproduces the published value within
    0.1 % (FluxPM is printed to 2 significant figures, so Ke is the better input). The exact dq
    solution puts the resistive drop in quadrature with the inductive one and lands 0.5 % higher.
    """
    i = BLY_I_AMPL / SQRT2
    ke = ke_si(BLY_KE, "ll_peak")
    approx = float(base_speed(ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i, method="resistive_drop")) / RPM
    exact = float(base_speed(ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i, method="dq")) / RPM
    assert approx == pytest.approx(5393, rel=1e-3)
    assert approx * BLY_P * RPM == pytest.approx(2259.1, rel=1e-3)
    assert exact == pytest.approx(5393, rel=6e-3)
    assert exact > approx
    with pytest.raises(ValueError, match="method"):
        base_speed(ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i, method="mtpa")


def test_base_speed_is_where_the_curve_leaves_the_current_limit() -> None:
    i = BLY_I_AMPL / SQRT2
    ke = ke_si(BLY_KE, "ll_peak")
    w_b = float(base_speed(ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i))
    kt = kt_from_ke(ke)
    below = torque_speed_curve(np.array([0.999 * w_b]), kt, ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i, i).peak
    above = torque_speed_curve(np.array([1.001 * w_b]), kt, ke, BLY_R, BLY_L, BLY_P, BLY_VDC, i, i).peak
    assert float(below[0, 0]) == pytest.approx(float(kt) * i, rel=1e-12)
    assert float(above[0, 0]) < float(kt) * i
    assert float(terminal_voltage(w_b, i, ke, BLY_R, BLY_L, BLY_P)) == pytest.approx(BLY_VDC / math.sqrt(3), rel=1e-9)


def test_1ft7044_rated_point_lies_inside_its_curve_at_600_v() -> None:
    """Siemens 1FT7044-5AK7 at its rated point (2 N m, 6000 rpm, 2.5 A) on the S120's 600 V DC link."""
    ke = ke_si(FT_KE, "ll_rms")
    v_need = float(terminal_voltage(FT_NN * RPM, FT_IN, ke, FT_R, FT_L, FT_P))
    assert v_need < float(max_phase_voltage(FT_VDC))
    curve = torque_speed_curve(np.array([FT_NN * RPM]), FT_KT, ke, FT_R, FT_L, FT_P, FT_VDC, FT_I0, FT_IMAX, FT_SAT)
    assert float(curve.continuous[0, 0]) >= FT_TN
    assert float(curve.peak[0, 0]) >= FT_TN
    # at standstill the peak curve is the datasheet peak torque at the datasheet peak current
    still = torque_speed_curve(np.array([0.0]), FT_KT, ke, FT_R, FT_L, FT_P, FT_VDC, FT_I0, FT_IMAX, FT_SAT)
    assert float(still.peak[0, 0]) == pytest.approx(FT_TMAX, rel=1e-12)


def test_1ft7044_currents_from_torque() -> None:
    """I = T / Kt below the rated torque; exactly I_max at M_max; M_0 = 5 N m within 3 % of I_0 = 5.7 A.

    The stall point lies on the interpolated Kt segment (an interpolation, not a datasheet
    curve): 5.79 A against the printed 5.7 A, the safe side.
    """
    assert float(current_from_torque(1.5, FT_KT, FT_SAT)) == pytest.approx(1.5 / FT_KT, rel=1e-12)
    assert float(current_from_torque(-FT_TMAX, FT_KT, FT_SAT)) == pytest.approx(-FT_IMAX, rel=1e-12)
    i0 = float(current_from_torque(FT_M0, FT_KT, FT_SAT))
    assert i0 == pytest.approx(FT_I0, rel=0.03)
    assert i0 >= FT_I0
    # without saturation data the plain ratio holds
    assert float(current_from_torque(FT_TMAX, FT_KT)) == pytest.approx(FT_TMAX / FT_KT)


def test_no_load_speed_and_voltage_limit_cut_the_curve() -> None:
    ke = ke_si(FT_KE, "ll_rms")
    w0 = float(no_load_speed(ke, FT_VDC))
    i_v = voltage_limited_current(np.array([0.99 * w0, 1.01 * w0]), ke, FT_R, FT_L, FT_P, max_phase_voltage(FT_VDC))
    assert i_v[0, 0] > 0.0
    assert i_v[0, 1] == 0.0
    # braking: the resistive drop helps, more current is possible at the same speed
    gen = voltage_limited_current(np.array([0.9 * w0]), ke, FT_R, FT_L, FT_P, max_phase_voltage(FT_VDC),
                                  generating=True)
    mot = voltage_limited_current(np.array([0.9 * w0]), ke, FT_R, FT_L, FT_P, max_phase_voltage(FT_VDC))
    assert gen[0, 0] > mot[0, 0]


def test_curves_vectorise_over_motors_and_speeds() -> None:
    w = np.linspace(0, 9000 * RPM, 50)
    kts = np.array([FT_KT, 0.5])
    kes = ke_si(np.array([FT_KE, 30.0]), "ll_rms")
    c = torque_speed_curve(w, kts, kes, [FT_R, 0.3], [FT_L, 0.002], [3, 4], FT_VDC, [5.7, 8.0], [30.0, 24.0])
    assert c.peak.shape == (2, 50)
    one = torque_speed_curve(w, 0.5, kes[1], 0.3, 0.002, 4, FT_VDC, 8.0, 24.0)
    np.testing.assert_allclose(c.peak[1], one.peak[0], rtol=1e-12)
    assert np.all(c.continuous <= c.peak + 1e-12)
    assert np.all(np.diff(c.peak, axis=1) <= 1e-12)  # never rises with speed


@given(st.floats(0.01, 22.99), st.floats(0.3, 2.0), st.floats(1.0, 20.0), st.floats(1.05, 3.0))
@settings(max_examples=200, deadline=None)
def test_torque_from_current_inverts_current_from_torque(torque: float, kt: float, t_n: float, over: float) -> None:
    t_max = t_n * over
    sat = Saturation(np.array(t_n), np.array(t_max), np.array(t_max / (kt * 0.85)))
    t = min(torque, 1.5 * t_max)
    i = current_from_torque(t, kt, sat)
    assert float(torque_from_current(i, kt, sat)) == pytest.approx(t, rel=1e-9)
    assert float(current_from_torque(t * 1.01, kt, sat)) > float(i)  # monotone


@given(st.floats(100.0, 800.0), st.floats(20.0, 150.0), st.floats(0.05, 3.0), st.floats(1e-4, 0.02),
       st.integers(1, 8), st.floats(0.0, 1.0))
@settings(max_examples=200, deadline=None)
def test_voltage_limited_current_meets_the_voltage_exactly(vdc: float, ke_v: float, r: float, ll: float, p: int,
                                                           frac: float) -> None:
    ke = ke_si(ke_v, "ll_rms")
    w = frac * float(no_load_speed(ke, vdc))
    i = float(voltage_limited_current(np.array([w]), ke, r, ll, p, max_phase_voltage(vdc))[0, 0])
    v = float(terminal_voltage(w, i, ke, r, ll, p))
    assert v == pytest.approx(float(max_phase_voltage(vdc)), rel=1e-9)


# ----------------------------------------------------------------------------- drive: I2t


def test_copley_i2t_example() -> None:
    """Copley Controls Xenus Plus User Guide, §B.1.3, pp. 131-132.

    12 A peak, 6 A continuous, 1 s I2T time limit -> setpoint 108 A^2 s. The command rises
    linearly from 6 A to 12 A over 1.2 s and stays at 12 A; "at about 1.6 seconds" the
    accumulator reaches the setpoint. Exactly: 57.6 A^2 s after the ramp, then 108 A^2/s, so
    1.2 + 50.4 / 108 = 1.667 s; the guide reads it off a plot, hence 0.1 s tolerance.
    """
    assert float(i2t_setpoint(12.0, 6.0, 1.0)) == 108.0
    t = np.linspace(0.0, 7.0, 7001)
    command = np.where(t < 1.2, 6.0 + 5.0 * t, 12.0)
    trip = i2t_trip_time(t, command, 6.0, 108.0)
    assert trip == pytest.approx(1.6, abs=0.1)
    assert trip == pytest.approx(1.2 + 50.4 / 108.0, abs=1e-3)
    assert float(peak_time(12.0, 6.0, 108.0)) == pytest.approx(1.0)
    assert math.isinf(float(peak_time(5.0, 6.0, 108.0)))


def test_accumulator_never_negative_and_drains_below_continuous() -> None:
    t = np.linspace(0, 4, 401)
    i = np.where(t < 1, 10.0, 2.0)
    acc = i2t_accumulator(t, i, 6.0)
    assert acc.min() >= 0.0
    assert acc[-1] == 0.0
    assert acc[99] == pytest.approx(0.99 * (100.0 - 36.0), rel=1e-9)


@given(st.lists(st.floats(0.0, 20.0), min_size=2, max_size=30), st.floats(1.0, 15.0))
@settings(max_examples=150, deadline=None)
def test_periodic_i2t_equals_a_long_run(levels: list[float], ic: float) -> None:
    """The closed-form steady state equals the accumulator's last cycle after many repeated cycles."""
    i = np.array([*levels, levels[0]])  # a cycle ends where it starts, so cycles join without a jump
    n = i.size
    t = np.arange(n, dtype=float) * 0.1
    per = i2t_periodic(t, i, ic, 1e9)
    cycles = 30
    tt = np.concatenate([t] + [t[1:] + k * t[-1] for k in range(1, cycles)])
    ii = np.concatenate([i] + [i[1:]] * (cycles - 1))
    long = i2t_accumulator(tt, ii, ic)
    if float(per.net_per_cycle) > 0.0:
        assert math.isinf(float(per.peak))
        assert not bool(per.ok)
    else:
        assert float(per.peak) == pytest.approx(float(long[-n:].max()), rel=1e-9, abs=1e-9)
        assert bool(per.ok)


def test_periodic_i2t_vectorises_over_drives() -> None:
    t = np.linspace(0, 1, 11)
    i = np.vstack([np.full(11, 5.0), np.full(11, 7.0)])
    per = i2t_periodic(t, i, [6.0, 6.0], [10.0, 10.0])
    assert per.ok.tolist() == [True, False]


def test_rms_current() -> None:
    w = np.array([0.5, 0.5])
    assert float(rms_current(np.array([3.0, 4.0]), w, 1.0)) == pytest.approx(math.sqrt(12.5))


# ------------------------------------------------------------------------ shipped data


def _rows(name: str) -> dict[str, dict[str, str]]:
    import csv
    import io
    from importlib import resources

    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return {r["id"]: r for r in csv.DictReader(io.StringIO(text))}


def test_shipped_electrical_data_matches_the_motor_table() -> None:
    """Every electrical row names a catalog motor whose rated and peak torque equal the same vendor table's."""
    elec = _rows("motors_ac_servo_electrical.csv")
    motors = _rows("motors_ac_servo.csv")
    assert len(elec) == 27
    for mid, row in elec.items():
        assert mid in motors, mid
        assert float(row["table_rated_torque_Nm"]) == pytest.approx(float(motors[mid]["rated_torque_Nm"]))
        if row["table_peak_torque_Nm"] or mid != "HG-KR23":  # HG-KR23: the page refers it to the reducer
            assert float(row["table_peak_torque_Nm"]) == pytest.approx(float(motors[mid]["peak_torque_Nm"]))
        assert row["source"] and row["source_url"].startswith("https://")
        if row["torque_constant_basis"].startswith("derived"):
            # not printed: k_T = T_N / I_N of the same table (data/SOURCES.md, "Derived torque constants")
            kt = float(row["torque_constant_Nm_per_A"])
            assert kt == pytest.approx(float(row["table_rated_torque_Nm"]) / float(row["rated_current_A"]), rel=1e-4)
        elif row["torque_constant_Nm_per_A"]:
            assert row["torque_constant_basis"] == "printed", mid
            kt = float(row["torque_constant_Nm_per_A"])
            ratio_n = kt * float(row["rated_current_A"]) / float(row["table_rated_torque_Nm"])
            ratio_p = kt * float(row["peak_current_A"]) / float(row["table_peak_torque_Nm"])
            assert 1.0 < ratio_n < 1.2, mid
            assert 1.0 < ratio_p < 1.25, mid
            assert ratio_n == pytest.approx(float(row["check_kt_x_Irated_over_Trated"]), abs=1e-3)


def test_siemens_constants_used_here_are_the_shipped_row() -> None:
    row = _rows("motors_ac_servo_electrical.csv")["1FT7044-5AK7"]
    motor = _rows("motors_ac_servo.csv")["1FT7044-5AK7"]
    assert float(row["torque_constant_Nm_per_A"]) == FT_KT
    assert float(row["back_emf_V_per_krpm"]) == FT_KE
    assert float(row["winding_resistance_ohm"]) == FT_R
    assert float(row["winding_inductance_H"]) == FT_L
    assert int(row["pole_count"]) == 2 * FT_P
    assert float(row["rated_current_A"]) == FT_IN
    assert float(row["stall_current_A"]) == FT_I0
    assert float(row["stall_torque_Nm"]) == FT_M0
    assert float(row["peak_current_A"]) == FT_IMAX
    assert float(motor["rated_torque_Nm"]) == FT_TN
    assert float(motor["rated_speed_rpm"]) == FT_NN
    assert float(motor["peak_torque_Nm"]) == FT_TMAX
