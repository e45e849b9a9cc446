"""Speed-torque envelopes: the shape of the derived approximation, curve interpolation, flags, shapes."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain import catalog
from drivetrain.catalog import db
from drivetrain.sizing.envelope import (
    APPROXIMATE,
    Curve,
    continuous_torque,
    curve_torque,
    intermittent_torque,
    motor_envelopes,
)
from tests.conftest import family_motor_rows

RPM = 2 * math.pi / 60
# Mitsubishi HG-KR43 ratings: 1.3 N m rated, 4.5 N m peak, 3000 rpm rated, 6000 rpm max
T_N, T_MAX, W_N, W_MAX = 1.3, 4.5, 3000 * RPM, 6000 * RPM


def test_continuous_equals_rated_torque_at_and_below_rated_speed() -> None:
    w = np.linspace(0, W_N, 31)
    env = continuous_torque(T_N, W_N, W_MAX, w)
    np.testing.assert_allclose(env.torque, T_N)
    assert env.torque.shape == (1, 31)


def test_continuous_is_constant_power_between_rated_and_max_speed() -> None:
    w = np.linspace(W_N, W_MAX, 25)[1:]
    torque = continuous_torque(T_N, W_N, W_MAX, w).torque[0]
    np.testing.assert_allclose(torque * w, T_N * W_N, rtol=1e-12)
    assert torque[-1] == pytest.approx(T_N / 2)  # 6000 rpm is twice the rated speed


def test_continuous_is_zero_beyond_max_speed() -> None:
    w = np.array([W_MAX * 1.0001, W_MAX * 2, 1e6])
    assert np.all(continuous_torque(T_N, W_N, W_MAX, w).torque == 0.0)


def test_stall_torque_falls_linearly_to_rated_at_rated_speed() -> None:
    # FANUC aiF4/4000: 4 N m stall, rated torque derived 3.342 N m at 4000 rpm
    t0, tn, wn = 4.0, 3.342, 4000 * RPM
    torque = continuous_torque(tn, wn, wn, np.array([0.0, wn / 2, wn]), stall_torque=4.0).torque[0]
    np.testing.assert_allclose(torque, [t0, (t0 + tn) / 2, tn])


def test_unknown_stall_torque_means_flat_rated_torque() -> None:
    torque = continuous_torque([T_N, T_N], W_N, W_MAX, [0.0, W_N / 2], stall_torque=[np.nan, 2.0]).torque
    np.testing.assert_allclose(torque[0], [T_N, T_N])
    np.testing.assert_allclose(torque[1], [2.0, (2.0 + T_N) / 2])


def test_intermittent_is_peak_to_rated_speed_then_falls_to_continuous_at_max() -> None:
    w = np.array([0.0, W_N, 0.5 * (W_N + W_MAX), W_MAX, W_MAX * 1.01])
    torque = intermittent_torque(T_MAX, T_N, W_N, W_MAX, w).torque[0]
    t_c_max = T_N * W_N / W_MAX
    np.testing.assert_allclose(torque, [T_MAX, T_MAX, (T_MAX + t_c_max) / 2, t_c_max, 0.0])


def test_rated_speed_equal_to_max_speed_gives_no_nan() -> None:
    # several FANUC rows list the same rated and max speed
    w = np.linspace(0, 1.5 * W_N, 40)
    cont = continuous_torque(T_N, W_N, W_N, w).torque
    peak = intermittent_torque(T_MAX, T_N, W_N, W_N, w).torque[0]
    assert np.all(np.isfinite(cont)) and np.all(np.isfinite(peak))
    assert np.all(peak[w <= W_N] == T_MAX) and np.all(peak[w > W_N] == 0)


def test_direction_does_not_matter() -> None:
    w = np.array([-W_MAX, -W_N, -1.0, 1.0, W_N, W_MAX])
    torque = intermittent_torque(T_MAX, T_N, W_N, W_MAX, w).torque[0]
    np.testing.assert_allclose(torque, torque[::-1])


def test_broadcast_over_motors_and_speeds() -> None:
    rated = np.array([1.3, 2.0, 0.5])
    speeds = np.linspace(0, 700, 11)
    env = continuous_torque(rated, [W_N, W_N, 2 * W_N], [W_MAX, 9000 * RPM, W_MAX], speeds)
    assert env.torque.shape == (3, 11)
    own = np.vstack([speeds, speeds * 2, speeds / 2])  # each motor its own speeds, e.g. per gear ratio
    assert intermittent_torque([4.5, 6.0, 1.0], rated, W_N, W_MAX, own).torque.shape == (3, 11)
    for i in range(3):  # row i equals a one-motor call
        np.testing.assert_array_equal(env.torque[i], continuous_torque(
            rated[i], [W_N, W_N, 2 * W_N][i], [W_MAX, 9000 * RPM, W_MAX][i], speeds).torque[0])


def test_unknown_ratings_give_nan_where_they_matter() -> None:
    torque = continuous_torque(T_N, W_N, np.nan, [W_N / 2, 1.5 * W_N]).torque[0]
    assert torque[0] == T_N and np.isnan(torque[1])  # below rated speed the rating suffices
    assert np.all(np.isnan(intermittent_torque(np.nan, T_N, W_N, W_MAX, [0.0, W_N]).torque))


def test_derived_envelopes_are_flagged_approximate() -> None:
    assert APPROXIMATE is True
    assert continuous_torque(T_N, W_N, W_MAX, [0.0]).approximate is True
    assert intermittent_torque(T_MAX, T_N, W_N, W_MAX, [0.0]).approximate is True


@settings(max_examples=200, deadline=None)
@given(
    t_n=st.floats(1e-3, 1e3),
    stall_factor=st.floats(1.0, 1.5),
    peak_factor=st.floats(1.0, 6.0),
    w_n=st.floats(10.0, 2000.0),
    speed_factor=st.floats(1.0, 4.0),
)
def test_intermittent_is_never_below_continuous(t_n: float, stall_factor: float, peak_factor: float,
                                               w_n: float, speed_factor: float) -> None:
    w = np.linspace(0, 1.2 * w_n * speed_factor, 97)
    args = (t_n, w_n, w_n * speed_factor)
    cont = continuous_torque(*args, w, stall_torque=t_n * stall_factor).torque
    peak = intermittent_torque(t_n * max(peak_factor, stall_factor), *args, w, stall_torque=t_n * stall_factor)
    assert np.all(peak.torque >= cont * (1 - 1e-12))
    assert np.all(cont >= 0) and np.all(np.diff(cont[0]) <= 1e-9 * t_n)  # never rises with speed


# ---------------------------------------------------------------------------------- curves

CURVE = Curve.from_points([(0.0, 2.0, 6.0), (200.0, 1.8, 5.0), (400.0, 1.0, 2.0), (300.0, None, 3.5)])


def test_curve_points_are_sorted_and_interpolated() -> None:
    assert list(CURVE.speed) == [0.0, 200.0, 300.0, 400.0]
    cont = curve_torque(CURVE, [0.0, 100.0, 300.0, 400.0], "continuous")
    np.testing.assert_allclose(cont.torque[0], [2.0, 1.9, 1.4, 1.0])  # 300: between 200 and 400, gap skipped
    assert cont.approximate is False
    np.testing.assert_allclose(curve_torque(CURVE, [250.0], "peak").torque[0], [4.25])


def test_curve_promises_nothing_beyond_its_last_point() -> None:
    assert curve_torque(CURVE, [400.1, 1000.0], "peak").torque.tolist() == [[0.0, 0.0]]


def test_motor_envelopes_use_curves_where_present() -> None:
    w = np.array([0.0, 200.0])
    cont, peak = motor_envelopes([1.5, 1.5], [4.0, 4.0], [300.0, 300.0], [600.0, 600.0], w,
                                 curves=[None, CURVE])
    assert np.asarray(cont.approximate).tolist() == [True, False]
    assert np.asarray(peak.approximate).tolist() == [True, False]
    np.testing.assert_allclose(cont.torque[0], [1.5, 1.5])  # derived from ratings
    np.testing.assert_allclose(cont.torque[1], [2.0, 1.8])  # from the curve
    np.testing.assert_allclose(peak.torque[1], [6.0, 5.0])


def test_curve_with_only_peak_points_leaves_continuous_derived() -> None:
    only_peak = Curve.from_points([(0.0, None, 5.0), (500.0, None, 2.0)])
    cont, peak = motor_envelopes(1.0, 3.0, 300.0, 600.0, [100.0], curves=[only_peak])
    assert np.asarray(cont.approximate).tolist() == [True] and np.asarray(peak.approximate).tolist() == [False]


# ---------------------------------------------------------------------------------- the shipped catalog


@pytest.fixture
def data_dir(tmp_path_factory: pytest.TempPathFactory, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    built = tmp_path_factory.getbasetemp() / "envelope-build"
    if not (built / db.BUILTIN_NAME).exists():
        db.builtin_db(built)
    d = tmp_path / "data"
    d.mkdir()
    shutil.copy(built / db.BUILTIN_NAME, d / db.BUILTIN_NAME)
    monkeypatch.setenv(db.ENV_DATA_DIR, str(d))
    return d


def test_envelopes_of_every_shipped_ac_servo_are_sane(data_dir: Path) -> None:
    m = catalog.motors(kind="ac_servo")
    w = np.linspace(0, 1.1 * np.nanmax(m.max_speed), 200)
    cont, peak = motor_envelopes(m.rated_torque, m.peak_torque, m.rated_speed, m.max_speed, w,
                                 stall_torque=m.stall_torque, curves=m.curves)
    assert cont.torque.shape == (297 + family_motor_rows(), 200)
    assert np.all(np.isfinite(cont.torque)) and np.all(np.isfinite(peak.torque))
    assert np.all(peak.torque >= cont.torque)
    assert np.all(cont.approximate)  # the shipped catalog has no curves
    i = list(m.ids).index("HG-KR43")
    at = np.interp(4500 * RPM, w, cont.torque[i])
    assert at == pytest.approx(1.3 * 3000 / 4500, rel=1e-2)
