r"""Speed-torque envelopes of servo motors: continuous (S1) and intermittent torque against speed.

A sizing check compares the torque a cycle needs at a speed with what the motor can give at
that speed. Vendors publish this as a T-n characteristic. Where a motor has curve points
(imported by the user), they are interpolated and the result is exact to the data
(``approximate`` False). The shipped catalog has no curves (data/SOURCES.md, "Known
limitations"), so the envelope is derived from the ratings, and every result that used the
derivation carries ``approximate`` True.

The derived envelope (approximation documented in docs/checks.md; the typical AC servo T-n
characteristic, e.g. Yaskawa Sigma-7 ratings and Siemens 1FT7 configuration manual, shows this
shape, but it is an approximation, not a vendor curve):

* continuous: the stall torque T_0 at standstill falling linearly to the rated torque T_N at the
  rated speed omega_N (flat at T_N when no stall torque is known), then constant power
  T_N omega_N / omega up to the maximum speed omega_max, zero beyond it;
* intermittent: the peak torque T_max up to omega_N, then falling linearly to the continuous
  torque at omega_max, never below the continuous torque, zero beyond omega_max.

Real curves differ: the voltage limit bends the intermittent curve down earlier at high speed
on a low bus voltage, and small DC motors follow their own linear speed-torque line. Treat a
check that passes with a thin margin on a derived envelope as unverified.

All speeds are magnitudes |omega| [rad/s] (the envelope is symmetric in direction); torques are
[N m]. Per-motor parameters are 1-D arrays of length M (or scalars); ``omega`` is 1-D (S speeds
shared by every motor) or 2-D (M, S) (each motor its own speeds, e.g. one per gear ratio). Every
function returns a 2-D (M, S) array. NaN in a rating gives NaN where that rating matters.
"""

from __future__ import annotations

from typing import Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.catalog.curves import Curve

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

APPROXIMATE: Final = True
"""The flag carried by envelopes derived from ratings rather than from curve points."""


class Envelope(NamedTuple):
    """Available torque [N m], shape (M, S), and whether it was derived from ratings (bool or per motor)."""

    torque: FloatArray
    approximate: bool | BoolArray


def _speeds(omega: ArrayLike) -> FloatArray:
    w = np.abs(np.asarray(omega, dtype=float))
    return w.reshape(1, -1) if w.ndim <= 1 else w


def _per_motor(value: ArrayLike) -> FloatArray:
    return np.asarray(value, dtype=float).reshape(-1, 1)


def continuous_torque(
    rated_torque: ArrayLike,
    rated_speed: ArrayLike,
    max_speed: ArrayLike,
    omega: ArrayLike,
    stall_torque: ArrayLike | None = None,
) -> Envelope:
    r"""Continuous (S1) torque [N m] available at speed ``omega``, derived from the ratings.

    .. math::
        T_c(\omega) = \begin{cases}
            T_0 + (T_N - T_0)\,\omega/\omega_N & \omega \le \omega_N \\
            T_N\,\omega_N/\omega & \omega_N < \omega \le \omega_{max} \\
            0 & \omega > \omega_{max}
        \end{cases}

    with T_0 the stall torque where known (NaN or None: T_0 = T_N, flat to rated speed).

    Args:
        rated_torque: T_N [N m], per motor (M,).
        rated_speed: omega_N [rad/s], per motor.
        max_speed: omega_max [rad/s], per motor.
        omega: speeds [rad/s], (S,) shared or (M, S).
        stall_torque: T_0 [N m] at standstill, per motor, optional.

    Returns:
        Envelope(torque (M, S) [N m], approximate=APPROXIMATE).

    Source: approximation documented in docs/checks.md and in this module's docstring; the
    typical AC servo T-n characteristic (e.g. Yaskawa Sigma-7 ratings, Siemens 1FT7
    configuration manual) shows this shape. The stall-to-rated segment is linear because the
    stall torque is defined at standstill and the rated torque at rated speed; a straight line
    joins them without claiming more than either datum.

    HG-KR43 (1.3 N m at 3000 rpm, 6000 rpm max) at 4500 rpm: 1.3 * 3000 / 4500 N m.

    >>> rpm = 2 * np.pi / 60
    >>> round(float(continuous_torque(1.3, 3000 * rpm, 6000 * rpm, 4500 * rpm).torque[0, 0]), 4)
    0.8667
    """
    t_n, w_n, w_max = _per_motor(rated_torque), _per_motor(rated_speed), _per_motor(max_speed)
    w = _speeds(omega)
    t_0 = t_n if stall_torque is None else _per_motor(stall_torque)
    t_0 = np.where(np.isnan(t_0), t_n, t_0)
    with np.errstate(divide="ignore", invalid="ignore"):
        below = t_0 + (t_n - t_0) * (w / w_n)
        above = t_n * w_n / w
    torque = np.where(w <= w_n, below, above)
    # unknown max speed: nothing is known past rated speed
    torque = np.where(np.isnan(w_max) & ~(w <= w_n), np.nan, torque)
    torque = np.where(w > w_max, 0.0, torque)
    return Envelope(torque.astype(float), APPROXIMATE)


def intermittent_torque(
    peak_torque: ArrayLike,
    rated_torque: ArrayLike,
    rated_speed: ArrayLike,
    max_speed: ArrayLike,
    omega: ArrayLike,
    stall_torque: ArrayLike | None = None,
) -> Envelope:
    r"""Intermittent (peak) torque [N m] available at speed ``omega``, derived from the ratings.

    .. math::
        T_i(\omega) = \begin{cases}
            \max(T_{max}, T_c) & \omega \le \omega_N \\
            \max\!\big(T_{max} + (T_c(\omega_{max}) - T_{max})
                \tfrac{\omega - \omega_N}{\omega_{max} - \omega_N},\ T_c(\omega)\big)
                & \omega_N < \omega \le \omega_{max} \\
            0 & \omega > \omega_{max}
        \end{cases}

    with T_c the continuous envelope of :func:`continuous_torque`.

    Args:
        peak_torque: T_max [N m], per motor (M,).
        rated_torque: T_N [N m], per motor.
        rated_speed: omega_N [rad/s], per motor.
        max_speed: omega_max [rad/s], per motor.
        omega: speeds [rad/s], (S,) shared or (M, S).
        stall_torque: T_0 [N m], per motor, optional (passed to the continuous envelope).

    Returns:
        Envelope(torque (M, S) [N m], approximate=APPROXIMATE).

    Source: approximation documented in docs/checks.md and in this module's docstring; the
    typical AC servo T-n characteristic (e.g. Yaskawa Sigma-7 ratings, Siemens 1FT7
    configuration manual) shows the peak torque available to about rated speed and shrinking
    towards the continuous curve at maximum speed. The linear fall is a simplification.

    HG-KR43 (4.5 N m peak) at 4500 rpm, halfway from rated to max speed: 4.5 + (0.65 - 4.5) / 2.

    >>> rpm = 2 * np.pi / 60
    >>> round(float(intermittent_torque(4.5, 1.3, 3000 * rpm, 6000 * rpm, 4500 * rpm).torque[0, 0]), 4)
    2.575
    """
    t_max, w_n, w_max = _per_motor(peak_torque), _per_motor(rated_speed), _per_motor(max_speed)
    w = _speeds(omega)
    t_c = continuous_torque(rated_torque, rated_speed, max_speed, w, stall_torque).torque
    # w_max is (M, 1), so this is each motor's own continuous torque at its own max speed
    t_c_at_max = continuous_torque(rated_torque, rated_speed, max_speed, w_max, stall_torque).torque
    with np.errstate(divide="ignore", invalid="ignore"):
        falling = t_max + (t_c_at_max - t_max) * (w - w_n) / (w_max - w_n)
    torque = np.where(w <= w_n, t_max, falling)
    torque = np.maximum(torque, t_c)  # NaN (unknown peak) stays NaN
    torque = np.where(w > w_max, 0.0, torque)
    return Envelope(torque.astype(float), APPROXIMATE)


def curve_torque(curve: Curve, omega: ArrayLike, which: str = "continuous") -> Envelope:
    """Torque [N m] of one motor's curve points at speeds ``omega`` [rad/s], linearly interpolated.

    Below the first point the first value holds; beyond the last point the torque is 0 (the
    data says nothing there, so nothing is promised). Points without a value for ``which`` are
    skipped; a curve with none gives NaN. Returns Envelope(torque (1, S) or the shape of omega,
    approximate=False).

    Source: the vendor's T-n characteristic points (catalog/data/SOURCES.md), interpolated linearly.
    """
    if which not in ("continuous", "peak"):
        raise ValueError(f"which must be 'continuous' or 'peak', got {which!r}")
    w = _speeds(omega)
    values = curve.continuous if which == "continuous" else curve.peak
    ok = ~np.isnan(values)
    if not ok.any():
        return Envelope(np.full(w.shape, np.nan), False)
    torque = np.interp(w, curve.speed[ok], values[ok], right=0.0)
    torque = np.where(w > curve.speed[ok][-1], 0.0, torque)
    return Envelope(torque, False)


def motor_envelopes(
    rated_torque: ArrayLike,
    peak_torque: ArrayLike,
    rated_speed: ArrayLike,
    max_speed: ArrayLike,
    omega: ArrayLike,
    stall_torque: ArrayLike | None = None,
    curves: tuple[Curve | None, ...] | list[Curve | None] | None = None,
) -> tuple[Envelope, Envelope]:
    """Continuous and intermittent envelopes [N m] of M motors at speeds ``omega`` [rad/s].

    Motors with curve points use them (per envelope, where the curve gives that torque);
    the others use the derived approximation. ``approximate`` of each returned Envelope is a
    bool array (M,) telling which motors' values are derived. Arguments as in
    :func:`continuous_torque` and :func:`intermittent_torque`; ``curves`` is aligned with the
    motors (e.g. ``MotorTable.curves``).

    Source: see :func:`continuous_torque`, :func:`intermittent_torque`, :func:`curve_torque`.
    """
    w = _speeds(omega)
    cont = continuous_torque(rated_torque, rated_speed, max_speed, w, stall_torque).torque
    peak = intermittent_torque(peak_torque, rated_torque, rated_speed, max_speed, w, stall_torque).torque
    shape = np.broadcast_shapes(cont.shape, peak.shape)
    cont, peak = np.array(np.broadcast_to(cont, shape)), np.array(np.broadcast_to(peak, shape))
    approx_c = np.ones(shape[0], dtype=bool)
    approx_p = np.ones(shape[0], dtype=bool)
    for i, curve in enumerate(curves or ()):
        if curve is None:
            continue
        w_i = w[i] if w.shape[0] > 1 else w[0]
        for target, approx, which in ((cont, approx_c, "continuous"), (peak, approx_p, "peak")):
            values = curve.continuous if which == "continuous" else curve.peak
            if np.isnan(values).all():
                continue
            target[i] = curve_torque(curve, w_i, which).torque[0]
            approx[i] = False
    return Envelope(cont, approx_c), Envelope(peak, approx_p)
