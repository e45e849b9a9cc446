"""Averages and extremes of a quantity over a repeating cycle, with the profile's quadrature weights
(Simpson per phase: the integrals of piecewise-polynomial torques are exact to rounding).

``values`` and ``speeds`` are arrays over the samples, ``weights`` [s] the quadrature weights of the
samples, ``period`` [s] the cycle time; results are in the unit of ``values``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def rms(values: Array, weights: Array, period: float) -> float:
    """Root mean square over a cycle: sqrt(sum(w T^2) / t_c) [same unit as values].

    Lecture, Torque Effective Value: T_rms = sqrt((T_P^2 t_a + T_L^2 t_c + T_S^2 t_d) / t_c).
    """
    return math.sqrt(float(np.sum(weights * values**2)) / period)


def cubic_mean(values: Array, speeds: Array, weights: Array) -> float:
    """Speed-weighted cubic mean T_av = (sum n_i t_i |T_i|^3 / sum n_i t_i)^(1/3) [N m].

    Harmonic Drive / strain-wave gear selection (average load torque); see the example
    harmonic_average_load_torque (published 89 N m). Standstill carries no weight.
    """
    n = np.abs(speeds)
    den = float(np.sum(weights * n))
    if den <= 0.0:
        return float(np.max(np.abs(values))) if values.size else 0.0
    return (float(np.sum(weights * n * np.abs(values) ** 3)) / den) ** (1.0 / 3.0)


def signed_extreme(values: Array) -> float:
    """The value of largest magnitude, with its sign (0 for an empty array)."""
    if values.size == 0:
        return 0.0
    return float(values[int(np.argmax(np.abs(values)))])
