"""A duty cycle reduced to what the motor checks need: speed bins and the convex hull of the
(acceleration, torque) points in each (``Demand``), and the plain-float hull (``chain``).

``motor_fit.demand`` builds a ``Demand`` with ``chain`` for short cycles and with the compiled
``hull.fast_demand`` for long ones: both start from ``binned_points`` and drop collinear points
within ``COLLINEAR``, so they give the same vertices.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Demand:
    """A duty cycle reduced to what motor checks need (motor-shaft, rotor excluded, SI)."""

    omega: Array
    alpha: Array
    torque: Array
    weights: Array
    period: float
    load_inertia: float
    hull_speed: Array  # (B,) upper-edge speed of each bin [rad/s]
    hull_torque: Array  # (B, V) torque of hull vertices (padded with the first vertex)
    hull_alpha: Array  # (B, V)
    all_torque: Array  # (V,) vertices of the hull of every sample
    all_alpha: Array  # (V,)

    @property
    def max_speed(self) -> float:
        """Largest |omega| [rad/s]."""
        return float(np.max(np.abs(self.omega)))

    @property
    def mean_speed(self) -> float:
        """Time-mean |omega| over the cycle [rad/s]."""
        return float(np.sum(self.weights * np.abs(self.omega)) / self.period)


def binned_points(omega: Array, alpha: Array, torque: Array,
                  bins: int) -> tuple[Array, Array, NDArray[np.intp], NDArray[np.intp], Array]:
    """The distinct (alpha, T) points of each speed bin, sorted by (bin, alpha, T), with each used bin's
    start and stop index into them and its upper edge speed [rad/s]."""
    w = np.abs(omega)
    top = float(w.max()) if w.size else 0.0
    edges = np.linspace(0.0, top if top > 0 else 1.0, bins + 1)
    idx = np.clip(np.searchsorted(edges, w, side="left") - 1, 0, bins - 1)
    # Group the distinct (alpha, T) points by bin with one sort (constant phases repeat points).
    order = np.lexsort((torque, alpha, idx))
    b_s, a_s, t_s = idx[order], alpha[order], torque[order]
    keep = np.ones(len(b_s), dtype=bool)
    keep[1:] = (np.diff(b_s) != 0) | (np.diff(a_s) != 0) | (np.diff(t_s) != 0)
    b_s, a_s, t_s = b_s[keep], a_s[keep], t_s[keep]
    bins_used, starts = np.unique(b_s, return_index=True)
    stops = np.append(starts[1:], len(b_s))
    speeds = edges[bins_used + 1]
    return a_s, t_s, starts, stops, speeds


COLLINEAR = 1e-12
"""Relative size of a turn below which three hull points count as collinear (rounding of the samples)."""


def chain(alpha: list[float], torque: list[float]) -> list[tuple[float, float]]:
    """Vertices of the convex hull of points sorted by (alpha, T), without repeats (Andrew's monotone chain).

    Collinear points (to rounding: a relative turn under 1e-12) keep only their ends, so a
    constant-acceleration phase or a ramp (points on a line) gives two vertices. Plain floats: a
    bin holds a handful of points, where numpy's per-call cost would dominate. Source: A. M.
    Andrew, Another efficient algorithm for convex hulls in two dimensions, Information Processing
    Letters 9 (1979) 216-219.

    A diamond with a point inside, and three points on a line:

    >>> chain([0.0, 1.0, 1.0, 1.0, 2.0], [0.0, -1.0, 0.5, 1.0, 0.0])
    [(0.0, 0.0), (1.0, -1.0), (2.0, 0.0), (1.0, 1.0)]
    >>> chain([0.0, 1.0, 2.0], [0.0, 1.0, 2.0])
    [(0.0, 0.0), (2.0, 2.0)]
    """
    pts = list(zip(alpha, torque, strict=True))
    if len(pts) < 3:
        return pts

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2:
                (x0, y0), (x1, y1) = out[-2], out[-1]
                turn_a, turn_b = (x1 - x0) * (p[1] - y0), (y1 - y0) * (p[0] - x0)
                # a middle point within rounding of the line is dropped (cf. qhull's merging), else a
                # ramp of samples would keep every one of them
                if turn_a - turn_b > COLLINEAR * (abs(turn_a) + abs(turn_b)):
                    break
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return lower[:-1] + upper[:-1] or pts[:1]
