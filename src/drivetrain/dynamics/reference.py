"""The motion reference a simulation follows, at the motor shaft: given arrays, a load-side profile
through the chain's ratio, or trapezoidal test moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Reference:
    """Motion reference at the motor shaft: time [s], position [rad], speed [rad/s], accel [rad/s^2]."""

    time: FloatArray
    position: FloatArray
    speed: FloatArray
    acceleration: FloatArray

    @staticmethod
    def from_arrays(time: ArrayLike, position: ArrayLike, speed: ArrayLike | None = None,
                    acceleration: ArrayLike | None = None) -> Reference:
        """Build from arrays (speed and acceleration by finite differences when not given)."""
        t = np.asarray(time, dtype=float).reshape(-1)
        x = np.asarray(position, dtype=float).reshape(-1)
        if t.size < 2 or x.size != t.size:
            raise InputError("reference", "needs time and position arrays of the same length >= 2",
                             f"{t.size} and {x.size}")
        if not np.all(np.isfinite(t)) or not np.all(np.isfinite(x)) or np.any(np.diff(t) <= 0):
            raise InputError("reference.time", "must be finite and strictly increasing", has_value=False)
        v = np.gradient(x, t) if speed is None else np.asarray(speed, dtype=float).reshape(-1)
        a = np.gradient(v, t) if acceleration is None else np.asarray(acceleration, dtype=float).reshape(-1)
        for name, arr in (("speed", v), ("acceleration", a)):
            if arr.size != t.size or not np.all(np.isfinite(arr)):
                raise InputError(f"reference.{name}", "must be finite and as long as the time array", arr.size)
        return Reference(t, x, v, a)

    @staticmethod
    def from_load(time: ArrayLike, position: ArrayLike, speed: ArrayLike, acceleration: ArrayLike,
                  ratio: float) -> Reference:
        """From a load-side profile [m or rad] through the chain's ratio (motor rad per load unit)."""
        return Reference.from_arrays(time, np.asarray(position) * ratio, np.asarray(speed) * ratio,
                                     np.asarray(acceleration) * ratio)

    def resample(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, speed, acceleration at times ``t`` (linear interpolation, held at the ends). At the
        reference's own instants (a reference already on a simulation's grid,
        ``response.reference_on_grid``) the samples themselves, which is what the interpolation gives."""
        tt = np.asarray(t, dtype=float)
        if tt.shape == self.time.shape and np.array_equal(tt, self.time):
            return self.position, self.speed, self.acceleration
        return (np.interp(tt, self.time, self.position), np.interp(tt, self.time, self.speed),
                np.interp(tt, self.time, self.acceleration))


def move_reference(distance: float, speed: float, accel: float, dwell: float = 0.0, *, repeat: int = 1,
                   back_and_forth: bool = True, step: float = 1e-4) -> Reference:
    """Trapezoidal (or triangular) point-to-point moves at the motor shaft, each followed by a dwell.

    distance [rad], peak speed [rad/s], acceleration [rad/s^2], dwell [s]. With ``back_and_forth``
    the moves alternate direction. A helper for tests and benchmarks; the axis's own duty-cycle
    profile is passed as arrays through ``Reference.from_arrays``.
    """
    for name, v in (("distance", abs(distance)), ("speed", speed), ("accel", accel)):
        if not (v > 0 and math.isfinite(v)):
            raise InputError(name, "must be > 0", v)
    d = abs(distance)
    ta = speed / accel
    if accel * ta * ta > d:  # triangular
        ta = math.sqrt(d / accel)
        speed = accel * ta
    tc = (d - accel * ta * ta) / speed
    t_move = 2 * ta + tc
    t_one = t_move + dwell
    t = np.arange(0.0, repeat * t_one + step / 2, step)
    x = np.zeros_like(t)
    vel = np.zeros_like(t)
    acc_all = np.zeros_like(t)
    start = 0.0
    for r in range(repeat):
        sgn = -1.0 if (back_and_forth and r % 2 == 1) else 1.0
        tau = t - r * t_one
        inside = (tau >= 0) & (tau < t_one + (step / 2 if r == repeat - 1 else 0.0))
        tt = tau[inside]
        ph1 = tt < ta
        ph2 = (tt >= ta) & (tt < ta + tc)
        ph3 = (tt >= ta + tc) & (tt < t_move)
        ph4 = tt >= t_move
        xs = np.empty_like(tt)
        vs = np.zeros_like(tt)
        acc = np.zeros_like(tt)
        xs[ph1] = 0.5 * accel * tt[ph1] ** 2
        vs[ph1] = accel * tt[ph1]
        acc[ph1] = accel
        xs[ph2] = 0.5 * accel * ta**2 + speed * (tt[ph2] - ta)
        vs[ph2] = speed
        td = t_move - tt[ph3]
        xs[ph3] = d - 0.5 * accel * td**2
        vs[ph3] = accel * td
        acc[ph3] = -accel
        xs[ph4] = d
        x[inside] = start + sgn * xs
        vel[inside] = sgn * vs
        acc_all[inside] = sgn * acc
        start += sgn * d
    return Reference(t, x, vel, acc_all)
