r"""Servo drive (amplifier) current checks: continuous, peak and the I²t overload limit.

A drive gives its continuous current I_c indefinitely and its peak current I_p for a limited
time. Copley Controls states the limit as an I²t accumulator (Xenus Plus User Guide, appendix
B "I2T Time Limit Algorithm", §B.1.2-B.1.3, pp. 130-132; the CME 2 and Xenus XTL guides print
the same algorithm):

.. math::
    \text{setpoint} = (I_p^2 - I_c^2)\,t_{I^2t}, \qquad
    A_{n+1} = \max\!\big(0,\ A_n + (I_{n+1}^2 - I_c^2)\,\Delta t\big)

and the drive limits its output to I_c (or faults) once A reaches the setpoint. The
accumulator "essentially calculates the RMS value of the output current" (ibid., p. 132), so
over a repeating cycle the limit is never reached in the long run only if
:math:`I_{rms} \le I_c`; then the accumulator settles into a periodic pattern whose largest
value must stay below the setpoint.

Vectorised: the clamped accumulator is a Lindley recursion, solved in closed form
:math:`A_n = S_n - \min(0, \min_{k \le n} S_k)` with S the cumulative sum of the increments
(no loop over samples). Increments are trapezoidal in I² between samples. Currents are rms
phase currents [A]; a current waveform is taken sample by sample as its rms magnitude (the
drive's own algorithm "operates the same way regardless of the output current frequency").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def i2t_setpoint(peak_current: ArrayLike, continuous_current: ArrayLike, time_limit: ArrayLike) -> FloatArray:
    r"""I²t setpoint [A² s] = (I_p² - I_c²) t_I2t.

    Source: Copley Controls, Xenus Plus User Guide, §B.1.2, p. 130; example §B.1.3, p. 131:
    12 A peak, 6 A continuous, 1 s -> 108 A² s.

    >>> float(i2t_setpoint(12.0, 6.0, 1.0))
    108.0
    """
    ip = np.asarray(peak_current, dtype=float)
    ic = np.asarray(continuous_current, dtype=float)
    return np.asarray((ip**2 - ic**2) * np.asarray(time_limit, dtype=float))


def peak_time(current: ArrayLike, continuous_current: ArrayLike, setpoint: ArrayLike) -> FloatArray:
    r"""How long [s] a constant current above I_c can flow from an empty accumulator: setpoint / (I² - I_c²).

    +inf at or below the continuous current. Source: Copley I²t algorithm (as above).

    >>> float(peak_time(12.0, 6.0, 108.0))
    1.0
    """
    i = np.asarray(current, dtype=float)
    ic = np.asarray(continuous_current, dtype=float)
    excess = i**2 - ic**2
    with np.errstate(divide="ignore"):
        return np.asarray(np.where(excess > 0, np.asarray(setpoint, dtype=float) / np.where(excess > 0, excess, 1.0),
                                   np.inf))


def _increments(t: FloatArray, current: FloatArray, continuous: FloatArray) -> FloatArray:
    i2 = current**2
    h = np.diff(t)
    return np.asarray(h * (0.5 * (i2[..., 1:] + i2[..., :-1]) - continuous[..., None] ** 2))


def i2t_accumulator(t: ArrayLike, current: ArrayLike, continuous_current: ArrayLike) -> FloatArray:
    r"""The Copley I²t accumulator [A² s] at each sample, starting empty, shape of ``current``.

    .. math:: A_n = S_n - \min\big(0, \min_{k\le n} S_k\big), \qquad
              S_n = \sum_{k<n} \tfrac{h_k}{2}\,(I_k^2 + I_{k+1}^2) - I_c^2 h_k

    Args:
        t: sample times [s], ascending. current: rms current [A], (N,) or (M, N).
        continuous_current: I_c [A], scalar or (M,).

    Source: Copley Controls, Xenus Plus User Guide, §B.1.2 (accumulator increment formula, not
    allowed below zero), p. 130.
    """
    tt = np.asarray(t, dtype=float)
    i = np.abs(np.asarray(current, dtype=float))
    ic = np.asarray(continuous_current, dtype=float)
    if i.ndim == 2:
        ic = np.broadcast_to(ic.reshape(-1), (i.shape[0],))
    d = _increments(tt, i, ic)
    s = np.concatenate([np.zeros((*d.shape[:-1], 1)), np.cumsum(d, axis=-1)], axis=-1)
    return np.asarray(s - np.minimum(np.minimum.accumulate(s, axis=-1), 0.0))


def i2t_trip_time(t: ArrayLike, current: ArrayLike, continuous_current: float, setpoint: float) -> float:
    """First time [s] the accumulator reaches the setpoint, linearly interpolated between samples; +inf if never.

    Source: Copley Xenus Plus User Guide, §B.1.3 (the drive then limits the output to I_c).
    """
    tt = np.asarray(t, dtype=float)
    acc = i2t_accumulator(tt, current, continuous_current)
    hit = np.flatnonzero(acc >= setpoint)
    if hit.size == 0:
        return float("inf")
    k = int(hit[0])
    if k == 0:
        return float(tt[0])
    a0, a1 = acc[k - 1], acc[k]
    return float(tt[k - 1] + (setpoint - a0) / (a1 - a0) * (tt[k] - tt[k - 1]))


@dataclass(frozen=True)
class PeriodicI2t:
    """The I²t accumulator over a repeating cycle (arrays over candidates where given)."""

    net_per_cycle: FloatArray
    """[A² s] (I_rms² - I_c²) x period: > 0 means the accumulator grows every cycle"""
    peak: FloatArray
    """[A² s] largest accumulator value in the periodic steady state (inf when it grows)"""
    ok: NDArray[np.bool_]
    """whether the drive never limits: net <= 0 and peak < setpoint"""


def i2t_periodic(t: ArrayLike, current: ArrayLike, continuous_current: ArrayLike, setpoint: ArrayLike) -> PeriodicI2t:
    r"""Steady state of the Copley I²t accumulator over a cycle repeated forever.

    With D the increment sum over one cycle: D > 0 (RMS above I_c) makes the accumulator grow
    without bound, so the drive limits sooner or later. For D <= 0 the Lindley recursion
    forgets its start after one cycle (every later cycle starts from the same value), so the
    second of two concatenated cycles is the exact periodic steady state:
    :math:`A_n = S_n - \min(\min_{cycle} S - D,\ \min_{k \le n} S_k)`.

    Args:
        t: sample times [s] of one cycle, t[-1] - t[0] the period. current: rms [A], (N,) or (M, N).
        continuous_current: I_c [A]. setpoint: [A² s] (:func:`i2t_setpoint`).

    Source: Copley Xenus Plus User Guide, §B.1.2-B.1.3; closed form of the Lindley recursion.
    """
    tt = np.asarray(t, dtype=float)
    i = np.abs(np.asarray(current, dtype=float))
    i2d = i.reshape(1, -1) if i.ndim == 1 else i
    ic = np.broadcast_to(np.asarray(continuous_current, dtype=float).reshape(-1), (i2d.shape[0],))
    d = _increments(tt, i2d, ic)
    s = np.concatenate([np.zeros((d.shape[0], 1)), np.cumsum(d, axis=-1)], axis=-1)
    net = s[:, -1]
    floor = s.min(axis=1) - net  # the lowest S of the previous cycle, seen from this one
    steady = s - np.minimum(floor[:, None], np.minimum.accumulate(s, axis=-1))
    peak = np.where(net > 0, np.inf, steady.max(axis=1))
    sp = np.broadcast_to(np.asarray(setpoint, dtype=float).reshape(-1), peak.shape)
    ok = (net <= 0) & (peak < sp)
    if i.ndim == 1:
        return PeriodicI2t(net[:1].reshape(()), peak[:1].reshape(()), ok[:1].reshape(()))
    return PeriodicI2t(net, peak, ok)


def rms_current(current: ArrayLike, weights: ArrayLike, period: float) -> FloatArray:
    r"""RMS current [A] over a cycle: :math:`\sqrt{\sum w I^2 / t_c}` (quadrature weights [s]).

    Source: the lecture's effective value (T_rms), applied to current; drive continuous-current
    rule (Yaskawa, Siemens: RMS current <= rated/continuous output current).
    """
    i = np.asarray(current, dtype=float)
    return np.asarray(np.sqrt(np.sum(np.asarray(weights, dtype=float) * i**2, axis=-1) / period))
