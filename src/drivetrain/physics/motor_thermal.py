r"""Winding temperature of a servo motor over a repeating cycle: a first-order thermal model.

.. math::
    C_{th}\,\frac{d\theta}{dt} = P(t) - \frac{\theta}{R_{th}}, \qquad \tau = R_{th} C_{th}

with :math:`\theta` the winding rise over ambient [K], P the losses [W] (copper
:math:`3 I^2 R_{ph}`, plus iron losses where data exist), R_th [K/W] and the thermal time
constant tau [s] (datasheet, e.g. Siemens 1FT7 "T_th").

The thermal resistance comes from the rating: at the continuous (stall) current I_0 the
winding reaches the rated rise :math:`\Delta\theta_N` (Siemens 1FT7: 100 K data; insulation
class limits of IEC 60034-1), so :math:`R_{th} = \Delta\theta_N / (3 I_0^2 R_{ph})` and the
steady rise of an RMS current is :math:`\Delta\theta_N (I_{rms}/I_0)^2`: the basis of every
vendor's "RMS current <= continuous current" rule (Yaskawa Sigma-7 selection: effective torque
<= rated torque). The resistance's own rise with temperature (copper, k = 235 K) is left to
the caller (:func:`copper_resistance`): with R_th calibrated at the rated point the same R
cancels.

Over a repeating cycle the system settles into a periodic solution; it is computed exactly
(:func:`periodic_rise`), not by marching many cycles. The loss is taken piecewise-linear
between samples, which the recursion integrates exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]

COPPER_K: Final = 235.0
"""[K] inferred zero-resistance temperature of copper (IEC 60034-1, resistance method)."""

INSULATION_RISE_K: Final = {"B": 80.0, "F": 105.0, "H": 125.0}
"""Winding temperature-rise limits [K] by the resistance method, IEC 60034-1 Table 7 (item 1c,
machines up to 200 kW, indirectly cooled windings), over a 40 degC coolant."""


def copper_resistance(r_ref: ArrayLike, temperature: ArrayLike, reference: float = 20.0) -> FloatArray:
    r"""Copper winding resistance [ohm] at ``temperature`` [degC] from its value at ``reference`` [degC].

    .. math:: R(\theta) = R_{ref}\,\frac{k + \theta}{k + \theta_{ref}}, \quad k = 235

    Source: IEC 60034-1, determination of winding temperature by the resistance method (k = 235
    for copper).

    >>> round(float(copper_resistance(0.61, 120.0)), 4)
    0.8492
    """
    return np.asarray(np.asarray(r_ref, dtype=float) * (COPPER_K + np.asarray(temperature, dtype=float))
                      / (COPPER_K + reference))


def thermal_resistance(rated_rise: ArrayLike, rated_current: ArrayLike, r_phase: ArrayLike) -> FloatArray:
    r"""Winding-to-ambient thermal resistance [K/W]: :math:`R_{th} = \Delta\theta_N / (3 I_0^2 R_{ph})`.

    Args:
        rated_rise: winding rise at the continuous rating [K] (datasheet, or
            :data:`INSULATION_RISE_K` of the insulation class).
        rated_current: continuous (stall) current I_0 [A rms] that gives that rise.
        r_phase: phase resistance [ohm] at the hot winding (:func:`copper_resistance`).

    Derivation: steady state of the first-order model at the rating, P = 3 I_0^2 R_ph.
    """
    i = np.asarray(rated_current, dtype=float)
    return np.asarray(np.asarray(rated_rise, dtype=float) / (3.0 * i**2 * np.asarray(r_phase, dtype=float)))


def steady_rise(rms_current: ArrayLike, rated_current: ArrayLike, rated_rise: ArrayLike) -> FloatArray:
    r"""Mean winding rise [K] in the periodic steady state of copper loss only: :math:`\Delta\theta_N (I_{rms}/I_0)^2`.

    Source: the first-order model's mean over a cycle equals R_th times the mean loss
    3 I_rms^2 R_ph, with R_th of :func:`thermal_resistance`.

    >>> round(float(steady_rise(5.0, 5.7, 100.0)), 2)
    76.95
    """
    ratio = np.asarray(rms_current, dtype=float) / np.asarray(rated_current, dtype=float)
    return np.asarray(np.asarray(rated_rise, dtype=float) * ratio**2)


def time_to_fraction(tau: ArrayLike, fraction: float = 0.95) -> FloatArray:
    r"""Time [s] for the mean rise to reach ``fraction`` of its steady value from cold: :math:`-\tau\ln(1-f)`.

    Derivation: step response 1 - exp(-t / tau) of the first-order model (95 %: 3.0 tau).

    >>> round(float(time_to_fraction(2100.0)), 1)
    6291.0
    """
    if not 0.0 < fraction < 1.0:
        raise ValueError(f"fraction must lie in (0, 1), got {fraction}")
    return np.asarray(-np.asarray(tau, dtype=float) * np.log1p(-fraction))


@dataclass(frozen=True)
class PeriodicRise:
    """Periodic steady-state winding rise over one cycle (SI; arrays over candidates where given)."""

    rise: FloatArray
    """[K] at every sample, shape (..., N)"""
    mean: FloatArray
    """[K] time mean over the cycle, exactly R_th x mean loss (integral of the ODE over a period)"""
    peak: FloatArray
    """[K] highest rise over the cycle, including maxima between samples (exact for the piecewise-linear loss)"""
    ripple: FloatArray
    """[K] peak - mean"""
    time_to_95: FloatArray
    """[s] time for the mean rise to reach 95 % of its steady value from cold"""


def periodic_rise(t: ArrayLike, loss: ArrayLike, r_th: ArrayLike, tau: ArrayLike) -> PeriodicRise:
    r"""Exact periodic solution of :math:`\tau\dot\theta = R_{th} P(t) - \theta` for a loss repeated every cycle.

    Between samples k and k+1 (step h, :math:`a = e^{-h/\tau}`) with the loss linear from P_k to
    P_{k+1}:

    .. math::
        \theta_{k+1} = a\,\theta_k + R_{th}\Big[P_{k+1} - a P_k
            - (P_{k+1} - P_k)\frac{\tau}{h}(1 - a)\Big]

    A linear recursion :math:`\theta_{k+1} = a_k\theta_k + b_k`: with
    :math:`A_n = \prod_{j<n} a_j = e^{-(t_n - t_0)/\tau}`,
    :math:`\theta_n = A_n(\theta_0 + \sum_{k<n} b_k / A_{k+1})`, and periodicity
    :math:`\theta_N = \theta_0` gives :math:`\theta_0 = A_N S_N / (1 - A_N)`. The sums are
    cumulative (no loop over samples); cycles much longer than tau are split into blocks of at
    most 200 tau so the exponentials stay finite.

    Args:
        t: sample times [s], ascending over one cycle, t[-1] - t[0] = the period (repeated
            times at phase joints allowed).
        loss: winding losses [W] per sample, shape (N,) or (M, N) for M candidates.
        r_th: thermal resistance [K/W], scalar or (M,). tau: thermal time constant [s].

    Returns:
        :class:`PeriodicRise`.

    Source: first-order (single-body) thermal model of a motor winding (e.g. Siemens 1FT7
    Configuration Manual: thermal time constant T_th; Kollmorgen, Yaskawa overload
    characteristics derive from it); exact discretisation of a linear ODE with piecewise-linear
    input (first-order hold).
    """
    tt = np.asarray(t, dtype=float)
    p = np.asarray(loss, dtype=float)
    two_d = p.ndim == 2
    p2 = p if two_d else p.reshape(1, -1)
    rth = np.asarray(r_th, dtype=float).reshape(-1, 1)
    tau_ = np.asarray(tau, dtype=float).reshape(-1, 1)
    if np.any(tau_ <= 0) or np.any(rth < 0):
        raise InputError("motor.thermal_time_constant", "the thermal time constant must be positive and R_th >= 0",
                         float(tau_.min()))
    h = np.diff(tt).reshape(1, -1)
    x = h / tau_  # (M or 1, N-1)
    a = np.exp(-x)
    one_minus_a = -np.expm1(-x)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope_term = np.where(x > 0, one_minus_a / x, 1.0)
    b = rth * (p2[:, 1:] - a * p2[:, :-1] - (p2[:, 1:] - p2[:, :-1]) * slope_term)
    m = max(b.shape[0], a.shape[0])
    a = np.broadcast_to(a, (m, a.shape[1]))
    b = np.broadcast_to(b, (m, b.shape[1]))
    x = np.broadcast_to(x, (m, x.shape[1]))
    theta_free = _zero_start(a, b, x)  # response from theta_0 = 0, (m, N)
    decay = np.exp(-np.sum(x, axis=1))  # A_N per row
    theta0 = theta_free[:, -1] / (1.0 - decay)
    # add the decaying response of theta0: theta0 * A_n
    growth = np.concatenate([np.zeros((m, 1)), np.cumsum(x, axis=1)], axis=1)
    rise = theta_free + theta0[:, None] * np.exp(-growth)
    period = float(tt[-1] - tt[0])
    w = _trapezoid(tt)
    # the exact periodic mean: integrating the ODE over one period gives mean(theta) = R_th mean(P)
    mean = np.broadcast_to(rth[:, 0] * (p2 * w).sum(axis=1) / period, (m,))
    peak = np.maximum(rise.max(axis=1), _interior_peak(rise, p2, rth, tau_, h, m))
    t95 = time_to_fraction(tau_.reshape(-1), 0.95)
    if not two_d and np.ndim(r_th) == 0 and np.ndim(tau) == 0:
        return PeriodicRise(rise[0], mean[0], peak[0], peak[0] - mean[0], t95[0])
    return PeriodicRise(rise, mean, peak, peak - mean, np.broadcast_to(t95, mean.shape).copy())


def _interior_peak(rise: FloatArray, p: FloatArray, rth: FloatArray, tau: FloatArray, h: FloatArray,
                   m: int) -> FloatArray:
    r"""Largest rise strictly inside the sample intervals [K], per row (-inf if none).

    With the loss linear, P = P_k + q s on an interval, the solution is
    :math:`\theta(s) = R(P_k + q(s - \tau)) + (\theta_k - R(P_k - q\tau)) e^{-s/\tau}`; where
    :math:`\theta' = 0` inside, :math:`e^{-s^*/\tau} = R q \tau / (\theta_k - R P_k + R q \tau)` and
    :math:`\theta(s^*) = R P(s^*)`.
    """
    p = np.broadcast_to(p, (m, p.shape[1]))
    hh = np.broadcast_to(h, (m, h.shape[1]))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        q = np.where(hh > 0, (p[:, 1:] - p[:, :-1]) / hh, 0.0)
        num = rth * q * tau
        den = rise[:, :-1] - rth * p[:, :-1] + num
        ratio = num / den
        s_star = -tau * np.log(ratio)
        inside = (hh > 0) & (ratio > 0) & (s_star > 0) & (s_star < hh)
        value = np.where(inside, rth * (p[:, :-1] + q * s_star), -np.inf)
    return np.asarray(value.max(axis=1, initial=-np.inf))


def _trapezoid(t: FloatArray) -> FloatArray:
    h = np.diff(t)
    w = np.zeros_like(t)
    w[:-1] += h / 2.0
    w[1:] += h / 2.0
    return w


def _zero_start(a: FloatArray, b: FloatArray, x: FloatArray, block: float = 200.0) -> FloatArray:
    """theta_n of theta_{k+1} = a_k theta_k + b_k from theta_0 = 0, by cumulative sums in blocks.

    Within a block starting at step lo the first step is applied directly and the rest is
    referred to it: theta_{k+1} = e^{-(g_k - g_lo)} (theta_{lo+1} + sum_{lo<j<=k} b_j e^{g_j - g_lo}),
    g the cumulative h / tau; blocks keep g_k - g_lo below ``block`` so no exponential overflows.
    """
    m, n1 = b.shape
    out = np.zeros((m, n1 + 1))
    if n1 == 0:
        return out
    growth = np.cumsum(x, axis=1)  # (m, N-1)
    g_max = growth.max(axis=0)  # rows differ only by tau, so every row is proportional to this one
    cuts = np.searchsorted(g_max, np.arange(block, g_max[-1] + block, block))
    edges = np.unique(np.concatenate([[0], cuts, [n1]]))
    theta = np.zeros(m)
    for lo, hi in zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True):
        first = a[:, lo] * theta + b[:, lo]
        g = growth[:, lo + 1:hi] - growth[:, lo:lo + 1]  # (m, hi - lo - 1), in [0, block)
        s = np.cumsum(b[:, lo + 1:hi] * np.exp(g), axis=1)
        out[:, lo + 1] = first
        out[:, lo + 2:hi + 1] = np.exp(-g) * (first[:, None] + s)
        theta = out[:, hi]
    return out


# ----------------------------------------------------------------------------------- derating

DERATING_METHODS: Final = ("kollmorgen_akm", "siemens_1ft7")

_KOLLMORGEN_ALTITUDE = ((1000.0, 0.0), (2000.0, 0.06), (3000.0, 0.17), (4000.0, 0.30), (5000.0, 0.55))
_SIEMENS_1FT7_1000M = ((30.0, 1.07), (40.0, 1.00), (45.0, 0.96), (50.0, 0.92), (55.0, 0.87))


def derating(ambient: ArrayLike, altitude: ArrayLike, method: str = "kollmorgen_akm") -> FloatArray:
    r"""Factor [-] on a motor's continuous (standstill) torque and current for ambient [degC] and altitude [m].

    ``method="kollmorgen_akm"``: Kollmorgen AKM motors: no derating up to 40 degC and 1000 m;
    1 %/K from 40 to 50 degC; at 40 degC 6 % for 1000-2000 m, 17 % for 2000-3000 m, 30 % for
    3000-4000 m, 55 % for 4000-5000 m (bands as printed, each applied to its whole band). Both
    together multiply. Source: Kollmorgen Developer Network, "Derating"
    (https://kdn.kollmorgen.com/content/derating), servo motors table, rows AKM1-AKM7.

    ``method="siemens_1ft7"``: Siemens S-1FT7 Configuration Manual 09/2018, A5E45099423B AA,
    §2.4 "Derating factors", Table 2-3, p. 32, row 1000 m (the row read): ambient rounded up
    to 5 degC; below 30 degC 1.07, 30-40 degC 1.00, 45 degC 0.96, 50 degC 0.92, 55 degC 0.87 (torque
    and speed reduced by the factor). Only installation altitudes up to 1000 m are covered.

    Outside a method's range the answer is an :class:`~drivetrain.errors.InputError` naming
    ``environment.ambient`` or ``environment.altitude``.

    >>> round(float(derating(45.0, 1500.0)), 4)
    0.893
    """
    t = np.asarray(ambient, dtype=float)
    h = np.asarray(altitude, dtype=float)
    if method == "kollmorgen_akm":
        if np.any(t > 50.0):
            raise InputError("environment.ambient", "the Kollmorgen AKM derating covers ambients up to 50 degC",
                             float(np.max(t)))
        if np.any(h > 5000.0):
            raise InputError("environment.altitude", "the Kollmorgen AKM derating covers altitudes up to 5000 m",
                             float(np.max(h)))
        f_t = 1.0 - 0.01 * np.maximum(t - 40.0, 0.0)
        tops = np.array([a for a, _ in _KOLLMORGEN_ALTITUDE])
        cuts = np.array([c for _, c in _KOLLMORGEN_ALTITUDE])
        f_h = 1.0 - cuts[np.searchsorted(tops, h, side="left").clip(0, len(tops) - 1)]
        f_h = np.where(h <= 1000.0, 1.0, f_h)
        return np.asarray(f_t * f_h)
    if method == "siemens_1ft7":
        if np.any(h > 1000.0):
            raise InputError("environment.altitude", "the Siemens 1FT7 derating read covers altitudes up to 1000 m",
                             float(np.max(h)))
        if np.any(t > 55.0):
            raise InputError("environment.ambient", "the Siemens 1FT7 derating covers ambients up to 55 degC",
                             float(np.max(t)))
        tops = np.array([a for a, _ in _SIEMENS_1FT7_1000M])
        factors = np.array([f for _, f in _SIEMENS_1FT7_1000M])
        idx = np.where(t < 30.0, 0, np.searchsorted(tops, t, side="left").clip(1, len(tops) - 1))
        return np.asarray(factors[idx])
    raise ValueError(f"method must be one of {DERATING_METHODS}, got {method!r}")
