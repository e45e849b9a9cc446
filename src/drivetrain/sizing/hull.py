"""The convex hull of each speed bin's (alpha, T) points, compiled: ``motor_fit._chain`` for every
bin in one pass. Imported lazily by ``motor_fit.demand`` for cycles with many points (importing
this module imports numba); a short cycle keeps the plain-float ``_chain``, whose per-call cost
is lower there.

Same algorithm and the same floating-point operations in the same order as ``_chain`` (Andrew's
monotone chain, collinear points within a relative turn of 1e-12 dropped; no fast-math, so no
fused multiply-add), hence the same vertices: ``tests/test_hull.py`` asserts equality on random
points. Source: A. M. Andrew, Another efficient algorithm for convex hulls in two dimensions,
Information Processing Letters 9 (1979) 216-219.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from drivetrain.jit import njit

_COLLINEAR = 1e-12  # as motor_fit._COLLINEAR


@njit(cache=True, nogil=True, error_model="numpy")
def _half(a: NDArray[np.float64], t: NDArray[np.float64], first: int, last: int, step: int,
          sa: NDArray[np.float64], st: NDArray[np.float64]) -> int:
    """One half of the chain over points first, first + step, ... last: its length in sa/st."""
    m = 0
    k = first
    while True:
        px, py = a[k], t[k]
        while m >= 2:
            x0, y0, x1, y1 = sa[m - 2], st[m - 2], sa[m - 1], st[m - 1]
            turn_a = (x1 - x0) * (py - y0)
            turn_b = (y1 - y0) * (px - x0)
            if turn_a - turn_b > _COLLINEAR * (abs(turn_a) + abs(turn_b)):
                break
            m -= 1
        sa[m], st[m] = px, py
        m += 1
        if k == last:
            return m
        k += step


@njit(cache=True, nogil=True, error_model="numpy")
def _chains(a: NDArray[np.float64], t: NDArray[np.float64], starts: NDArray[np.int64],
            stops: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    n_b = len(starts)
    out_a = np.empty(2 * len(a) + n_b)
    out_t = np.empty(2 * len(a) + n_b)
    counts = np.zeros(n_b, dtype=np.int64)
    sa = np.empty(len(a) + 1)
    st = np.empty(len(a) + 1)
    pos = 0
    for b in range(n_b):
        s, e = starts[b], stops[b]
        if e - s < 3:
            for k in range(s, e):
                out_a[pos], out_t[pos] = a[k], t[k]
                pos += 1
            counts[b] = e - s
            continue
        begin = pos
        m = _half(a, t, s, e - 1, 1, sa, st)
        for k in range(m - 1):
            out_a[pos], out_t[pos] = sa[k], st[k]
            pos += 1
        m = _half(a, t, e - 1, s, -1, sa, st)
        for k in range(m - 1):
            out_a[pos], out_t[pos] = sa[k], st[k]
            pos += 1
        if pos == begin:  # every point the same: ``or pts[:1]``
            out_a[pos], out_t[pos] = a[s], t[s]
            pos += 1
        counts[b] = pos - begin
    return out_a[:pos], out_t[:pos], counts


def chains(alpha: NDArray[np.float64], torque: NDArray[np.float64], starts: NDArray[np.int64],
           stops: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Hull vertices of the points ``[starts[b]:stops[b]]`` of each bin b, as ``_chain`` gives them.

    The points of each bin are sorted by (alpha, T) without repeats. Returns the vertices of every
    bin one after another (alpha [rad/s^2], T [N m]) and each bin's number of vertices.
    """
    return _chains(np.ascontiguousarray(alpha, dtype=np.float64), np.ascontiguousarray(torque, dtype=np.float64),
                   np.ascontiguousarray(starts, dtype=np.int64), np.ascontiguousarray(stops, dtype=np.int64))
