"""Closed forms of one rest-to-rest move: the lecture's movement amount, trapezoid and s-curve peaks,
and the jerk-limited time-optimal move (its parameters and duration, with a scalar path for one move
given as numbers). Units SI: m (or rad), s, m/s, m/s^2, m/s^3.

Sources: the lecture (trapezoidal profile: trapezoid ``v_max = x_f / t_2``, ``a_max = x_f /
(t_1 t_2)``; movement amount ``L_s = V (2 t_s - t_a - t_d) / 2``); jerk-limited time-optimal
rest-to-rest moves: L. Biagiotti, C. Melchiorri, *Trajectory Planning for Automatic Machines and
Robots*, Springer (2008), sec. 3.4 (double S). ``time_optimal_duration`` equals ruckig's duration
within 1e-9 s (``tests/motion/test_profiles_random.py``).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

def movement_amount(
    speed: npt.ArrayLike, t_s: npt.ArrayLike, t_a: npt.ArrayLike, t_d: npt.ArrayLike
) -> FloatArray:
    """Distance [m or rad] of a trapezoid move at peak ``speed`` [m/s or rad/s].

    ``L_s = V (2 t_s - t_a - t_d) / 2`` with positioning time ``t_s``, acceleration time ``t_a``
    and deceleration time ``t_d`` [s]; the sign follows the speed. Lecture, "Movement Amount"
    (ball screw, belt, rack, roll and disc pages; the lecture's V is in m/min, hence its /60).

    >>> round(float(movement_amount(15 / 60, 1.2, 0.1, 0.1)), 12)  # Yaskawa Sigma-II: 15 m/min
    0.275
    """
    return np.asarray(speed, dtype=float) * (2.0 * np.asarray(t_s) - np.asarray(t_a) - np.asarray(t_d)) / 2.0


def trapezoid_peak_speed(
    distance: npt.ArrayLike, t_total: npt.ArrayLike, t_accel: npt.ArrayLike, t_decel: npt.ArrayLike
) -> FloatArray:
    """Peak speed [m/s or rad/s] of a rest-to-rest move of ``distance`` [m or rad] in ``t_total`` [s].

    The lecture's movement amount solved for V: ``V = 2 L / (2 t_s - t_a - t_d)``; it holds for
    any ramp whose speed is symmetric about its mid-time (trapezoid and s-curve ramps alike).
    """
    t_s, t_a, t_d = np.asarray(t_total), np.asarray(t_accel), np.asarray(t_decel)
    return 2.0 * np.asarray(distance, dtype=float) / (2.0 * t_s - t_a - t_d)


def symmetric_trapezoid_peak_speed(distance: npt.ArrayLike, t_2: npt.ArrayLike) -> FloatArray:
    """``v_max = x_f / t_2`` [m/s] for a symmetric trapezoid; ``t_2 = t_f - t_1`` [s] is when decel starts.

    Lecture, trapezoidal profile (ERRATA lists it as reproducible).
    """
    return np.asarray(distance, dtype=float) / np.asarray(t_2)


def symmetric_trapezoid_peak_accel(
    distance: npt.ArrayLike, t_1: npt.ArrayLike, t_2: npt.ArrayLike
) -> FloatArray:
    """``a_max = x_f / (t_1 t_2)`` [m/s^2] for a symmetric trapezoid with accel time ``t_1`` [s].

    Lecture, trapezoidal profile, with ``t_f = t_1 + t_2``.
    """
    return np.asarray(distance, dtype=float) / (np.asarray(t_1) * np.asarray(t_2))


def symmetric_accel_time(distance: npt.ArrayLike, speed: npt.ArrayLike, t_s: npt.ArrayLike) -> FloatArray:
    """Accel (= decel) time [s] that moves ``distance`` [m] at ``speed`` [m/s] within ``t_s`` [s].

    The lecture's movement amount with ``t_a = t_d``: ``L_s = V (t_s - t_a)``, so
    ``t_a = t_s - L_s / V`` (how the Yaskawa selection examples find ``t_a``).
    """
    return np.asarray(t_s, dtype=float) - np.asarray(distance) / np.asarray(speed)


def s_curve_peak_accel(
    peak_speed: npt.ArrayLike, t_ramp: npt.ArrayLike, jerk_fraction: npt.ArrayLike
) -> FloatArray:
    """Peak acceleration [m/s^2] of a ramp from rest to ``peak_speed`` [m/s] in ``t_ramp`` [s].

    The ramp spends ``f t_r / 2`` in each of its two jerk pieces (``f`` = jerk fraction), so
    ``v = a (t_r - f t_r / 2)`` and ``a = v / (t_r (1 - f / 2))``: ``f = 0`` is the trapezoid's
    ``v / t_r``, ``f = 1`` the pure s-curve's ``2 v / t_r`` (Biagiotti & Melchiorri, sec. 3.4).
    """
    f = np.asarray(jerk_fraction, dtype=float)
    return np.asarray(peak_speed, dtype=float) / (np.asarray(t_ramp) * (1.0 - f / 2.0))


def s_curve_jerk_time(peak_speed: npt.ArrayLike, t_ramp: npt.ArrayLike, jerk: npt.ArrayLike) -> FloatArray:
    """Duration [s] of each jerk piece of a ramp to ``peak_speed`` in ``t_ramp`` at ``jerk`` [m/s^3].

    From ``v = J t_j (t_r - t_j)``, the root ``t_j <= t_r / 2``:
    ``t_j = 2 (v / J) / (t_r + sqrt(t_r^2 - 4 v / J))`` (written without cancellation). NaN when
    ``J < 4 v / t_r^2``: no ramp of that jerk reaches the speed in time.
    """
    q = np.asarray(peak_speed, dtype=float) / np.asarray(jerk, dtype=float)
    t_r = np.asarray(t_ramp, dtype=float)
    with np.errstate(invalid="ignore"):
        return 2.0 * q / (t_r + np.sqrt(t_r**2 - 4.0 * q))


class TimeOptimal(NamedTuple):
    """Time-optimal rest-to-rest move (arrays, magnitudes): symmetric ramps of
    ``t_jerk, t_const, t_jerk`` [s] around a cruise of ``t_cruise`` [s]."""

    duration: FloatArray
    peak_speed: FloatArray
    peak_accel: FloatArray
    t_jerk: FloatArray
    t_const: FloatArray
    t_cruise: FloatArray


def time_optimal_parameters(
    distance: npt.ArrayLike, vmax: npt.ArrayLike, amax: npt.ArrayLike, jmax: npt.ArrayLike = math.inf
) -> TimeOptimal:
    """Closed-form time-optimal rest-to-rest move under speed, acceleration and jerk limits.

    Vectorised over arrays. ``jmax = inf`` gives the trapezoid or triangle. A ramp from rest to
    speed ``v`` takes ``t_r = v / a_p + t_j`` with ``a_p = min(A, sqrt(v J))``, ``t_j = a_p / J``
    and covers ``v t_r / 2``; the move reaches ``V`` if ``|d| >= V t_r(V)``, else its peak speed
    solves ``|d| = v t_r(v)``: ``v = 2 |d| A / (A^2/J + sqrt(A^4/J^2 + 4 |d| A))`` when the
    acceleration limit is reached (``|d| >= 2 A^3 / J^2``), ``v = (|d| sqrt(J) / 2)^(2/3)``
    otherwise. Biagiotti & Melchiorri, *Trajectory Planning for Automatic Machines and Robots*,
    sec. 3.4.2 (double S with zero end speeds). Units: m, m/s, m/s^2, m/s^3 (or rad...), s.
    """
    one = _time_optimal_scalar(distance, vmax, amax, jmax) if _scalar_move(distance, vmax, amax, jmax) else None
    if one is not None:
        return TimeOptimal(*map(np.float64, one))  # type: ignore[arg-type]
    d = np.abs(np.asarray(distance, dtype=float))
    vm, am, jm = (np.asarray(x, dtype=float) for x in (vmax, amax, jmax))
    with np.errstate(invalid="ignore", divide="ignore"):
        a2j = am**2 / jm  # speed at which a ramp first touches the acceleration limit
        ramp_at_vmax = np.where(vm >= a2j, vm / am + am / jm, 2.0 * np.sqrt(vm / jm))
        reach = d >= vm * ramp_at_vmax
        v_acc = np.where(d > 0.0, 2.0 * d * am / (a2j + np.sqrt(a2j**2 + 4.0 * d * am)), 0.0)
        v_jerk = np.cbrt((d * np.sqrt(jm) / 2.0) ** 2)
        v_p = np.where(reach, vm, np.where(d >= 2.0 * am * a2j / jm, v_acc, v_jerk))
        a_p = np.minimum(am, np.sqrt(v_p * jm))
        t_j = np.where(np.isinf(jm), 0.0, a_p / jm)
        t_c = np.where(v_p > 0.0, np.maximum(v_p / a_p - t_j, 0.0), 0.0)
        t_v = np.where(reach, np.maximum(d / vm - (2.0 * t_j + t_c), 0.0), 0.0)
    duration = 2.0 * (2.0 * t_j + t_c) + t_v
    return TimeOptimal(duration, v_p, np.where(v_p > 0.0, a_p, 0.0), t_j, t_c, t_v)


_SCALAR = (float, int, np.float64)


def _scalar_move(d: Any, vm: Any, am: Any, jm: Any) -> bool:
    """One move given as numbers: finite distance, finite positive speed and acceleration, positive jerk."""
    return (type(d) in _SCALAR and type(vm) in _SCALAR and type(am) in _SCALAR and type(jm) in _SCALAR
            and math.isfinite(d) and 0.0 < vm < math.inf and 0.0 < am < math.inf and jm > 0.0)


def _time_optimal_scalar(d: Any, vm: Any, am: Any, jm: Any) -> tuple[float, ...] | None:
    """``time_optimal_parameters`` for one move (``_scalar_move``) as Python floats, in TimeOptimal's order:
    the same operations in the same order (no array set-up), so the same values to the bit. None where
    a quotient meets zero (underflow): the array path then answers by numpy's rules."""
    try:
        return _scalar_core(abs(float(d)), float(vm), float(am), float(jm))
    except ZeroDivisionError:
        return None


def _scalar_core(d: float, vm: float, am: float, jm: float) -> tuple[float, ...]:
    a2j = am * am / jm
    ramp_at_vmax = vm / am + am / jm if vm >= a2j else 2.0 * math.sqrt(vm / jm)
    reach = d >= vm * ramp_at_vmax
    if reach:
        v_p = vm
    elif d >= 2.0 * am * a2j / jm:
        v_p = 2.0 * d * am / (a2j + math.sqrt(a2j * a2j + 4.0 * d * am)) if d > 0.0 else 0.0
    else:
        half = d * math.sqrt(jm) / 2.0
        v_p = float(np.cbrt(half * half))
    root = math.sqrt(v_p * jm)  # NaN only for v_p = 0 under no jerk limit, where a_p enters nothing
    a_p = root if root < am else am
    t_j = 0.0 if jm == math.inf else a_p / jm
    if v_p > 0.0:
        t_c = v_p / a_p - t_j
        t_c = t_c if t_c > 0.0 else 0.0
    else:
        t_c = a_p = 0.0
    if reach:
        t_v = d / vm - (2.0 * t_j + t_c)
        t_v = t_v if t_v > 0.0 else 0.0
    else:
        t_v = 0.0
    return 2.0 * (2.0 * t_j + t_c) + t_v, v_p, a_p, t_j, t_c, t_v


def time_optimal_duration(
    distance: npt.ArrayLike, vmax: npt.ArrayLike, amax: npt.ArrayLike, jmax: npt.ArrayLike = math.inf
) -> FloatArray:
    """Shortest duration [s] of a rest-to-rest move under the limits (see ``time_optimal_parameters``)."""
    one = _time_optimal_scalar(distance, vmax, amax, jmax) if _scalar_move(distance, vmax, amax, jmax) else None
    if one is not None:
        return np.float64(one[0])  # type: ignore[return-value]
    return time_optimal_parameters(distance, vmax, amax, jmax).duration
