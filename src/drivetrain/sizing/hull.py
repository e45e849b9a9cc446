"""The convex hull of a duty cycle's (acceleration, torque) points per speed bin: ``demand.chain``
for every bin in one pass. ``motor_fit.demand`` uses it for cycles of many points, and a study
(``study/batch.py``) for its many variants, several gearbox efficiencies in one pass
(``fast_demands``).

Most points of a bin lie well inside its hull. One numpy pass over every bin drops the points strictly
inside the quadrilateral of the bin's extreme points (leftmost, lowest, rightmost, highest) by a
relative turn of 1e-9, a thousand times the chain's collinearity tolerance, so no dropped point is a
hull vertex or within rounding of an edge; the survivors, a handful per bin, go through the same
monotone chain as ``demand.chain`` (Andrew's, collinear points within a relative turn of 1e-12 dropped; the
same floating-point operations in the same order), hence the same vertices, bins and padding as
``motor_fit.demand``: ``tests/sizing/test_hull.py`` and ``tests/study/test_study_batch.py`` assert equality
(hypothesis). Sources: A. M. Andrew, Another efficient algorithm for convex hulls in two dimensions,
Information Processing Letters 9 (1979) 216-219; S. G. Akl and G. T. Toussaint, A fast convex hull
algorithm, Information Processing Letters 7 (1978) 219-222 (the quadrilateral filter).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from drivetrain.sizing.demand import COLLINEAR, Demand, binned_points

Array = NDArray[np.float64]

_INSIDE = 1e-9
"""Relative turn by which a point must be inside the extreme points' quadrilateral to be dropped."""


def _half(x: list[float], y: list[float], idx: list[int]) -> list[int]:
    """One half of Andrew's monotone chain over the points ``idx`` (in order), as point indices."""
    out: list[int] = []
    for p in idx:
        while len(out) >= 2:
            x0, y0, x1, y1 = x[out[-2]], y[out[-2]], x[out[-1]], y[out[-1]]
            turn_a, turn_b = (x1 - x0) * (y[p] - y0), (y1 - y0) * (x[p] - x0)
            if turn_a - turn_b > COLLINEAR * (abs(turn_a) + abs(turn_b)):
                break
            out.pop()
        out.append(p)
    return out


def _inside(x: Array, y: Array, starts: NDArray[np.int64], stops: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Points strictly inside their run's quadrilateral of extreme points, by a relative turn of 1e-9."""
    n_runs = len(starts)
    run = np.repeat(np.arange(n_runs), stops - starts)
    corners = [starts, _first_at(y, run, starts, np.minimum), stops - 1, _first_at(y, run, starts, np.maximum)]
    inside = np.ones(len(x), dtype=bool)
    for c0, c1 in zip(corners, corners[1:] + corners[:1], strict=True):  # left, bottom, right, top, left
        x0, y0 = x[c0][run], y[c0][run]
        turn_a, turn_b = (x[c1][run] - x0) * (y - y0), (y[c1][run] - y0) * (x - x0)
        inside &= turn_a - turn_b > _INSIDE * (np.abs(turn_a) + np.abs(turn_b))
    return inside


def _first_at(y: Array, run: NDArray[np.int64], starts: NDArray[np.int64], extreme: np.ufunc) -> NDArray[np.int64]:
    """Index of each run's first point with its smallest (np.minimum) or largest (np.maximum) y."""
    value = extreme.reduceat(y, starts)
    hit = np.flatnonzero(y == value[run])
    return hit[np.searchsorted(run[hit], np.arange(len(starts)))]


def _hulls(x: Array, y: Array, starts: NDArray[np.int64], stops: NDArray[np.int64]) -> tuple[
        NDArray[np.int64], NDArray[np.int64]]:
    """Hull vertices (as point indices) of each run ``[starts[b], stops[b])`` of points sorted by (x, y).

    Returns the vertex indices of all runs one after the other and the count of each run,
    in the order of ``demand.chain``: lower chain without its last point, then upper chain
    without its last point; fewer than 3 points are returned as they are; an empty result is
    the first point.
    """
    keep = np.flatnonzero(~_inside(x, y, starts, stops)) if len(starts) else np.zeros(0, dtype=np.int64)
    bounds = np.searchsorted(keep, np.stack([starts, stops])).T.tolist()
    xs, ys, kept = x.tolist(), y.tolist(), keep.tolist()
    verts: list[int] = []
    count = np.empty(len(starts), dtype=np.int64)
    for b, (s, e) in enumerate(bounds):
        idx = kept[s:e]
        # (a run of fewer than 3 points has none inside, and is its own hull)
        chain = idx if len(idx) < 3 else _half(xs, ys, idx)[:-1] + _half(xs, ys, idx[::-1])[:-1] or idx[:1]
        verts += chain
        count[b] = len(chain)
    return np.array(verts, dtype=np.int64), count


def chains(alpha: Array, torque: Array, starts: NDArray[np.integer], stops: NDArray[np.integer]) -> tuple[
        Array, Array, NDArray[np.int64]]:
    """Hull vertices of the points ``[starts[b]:stops[b]]`` of each bin b, as ``demand.chain`` gives them.

    The points of each bin are sorted by (alpha, T) without repeats. Returns the vertices of every
    bin one after another (alpha [rad/s^2], T [N m]) and each bin's number of vertices.
    """
    a = np.ascontiguousarray(alpha, dtype=np.float64)
    t = np.ascontiguousarray(torque, dtype=np.float64)
    i64 = np.int64
    verts, count = _hulls(a, t, np.ascontiguousarray(starts, dtype=i64), np.ascontiguousarray(stops, dtype=i64))
    return a[verts], t[verts], count


def fast_demand(omega: Array, alpha: Array, torque: Array, weights: Array, period: float, load_inertia: float,
                bins: int = 64) -> Demand:
    """``motor_fit.demand`` with the hulls of every bin in one pass: the same bins, points, vertices and padding."""
    a_s, t_s, starts, stops, speeds = binned_points(omega, alpha, torque, bins)
    verts, count = _hulls(np.ascontiguousarray(a_s), np.ascontiguousarray(t_s), starts.astype(np.int64),
                          stops.astype(np.int64))
    width = int(count.max())
    first = np.concatenate([[0], np.cumsum(count)[:-1]])
    pos = np.minimum(np.arange(width)[None, :], count[:, None] - 1)  # padding repeats the last vertex
    sel = verts[first[:, None] + pos]
    ha, ht = a_s[sel], t_s[sel]
    # hull of every vertex: the distinct vertices sorted by (alpha, T)
    va, vt = a_s[verts], t_s[verts]
    o = np.lexsort((vt, va))
    va, vt = va[o], vt[o]
    k = np.ones(len(va), dtype=bool)
    k[1:] = (np.diff(va) != 0) | (np.diff(vt) != 0)
    va, vt = va[k], vt[k]
    all_v, _ = _hulls(va, vt, np.zeros(1, dtype=np.int64), np.array([len(va)], dtype=np.int64))
    return Demand(omega=omega, alpha=alpha, torque=torque, weights=weights, period=period,
                  load_inertia=load_inertia, hull_speed=np.asarray(speeds, dtype=float), hull_torque=ht, hull_alpha=ha,
                  all_torque=vt[all_v], all_alpha=va[all_v])


def fast_demands(omega: Array, alpha: Array, torques: list[Array], weights: Array, period: float,
                 load_inertia: float, bins: int = 64) -> list[Demand]:
    """``fast_demand`` of several torque arrays over the same motion (one per gearbox efficiency),
    with one sort and one pass for all of them (numpy's per-call cost dominates at this size).

    Each result equals ``motor_fit.demand`` of that torque: the points are sorted by (torque
    array, bin, alpha, T), so each array's points come in demand's own order.
    """
    n_e, n = len(torques), len(omega)
    w = np.abs(omega)
    top = float(w.max()) if w.size else 0.0
    edges = np.linspace(0.0, top if top > 0 else 1.0, bins + 1)
    idx = np.clip(np.searchsorted(edges, w, side="left") - 1, 0, bins - 1)
    t_all = np.concatenate(torques)
    a_all = np.tile(alpha, n_e)
    b_all = np.tile(idx, n_e)
    e_all = np.repeat(np.arange(n_e), n)
    order = np.lexsort((t_all, a_all, b_all, e_all))
    e_s, b_s, a_s, t_s = e_all[order], b_all[order], a_all[order], t_all[order]
    keep = np.ones(len(b_s), dtype=bool)
    keep[1:] = (np.diff(e_s) != 0) | (np.diff(b_s) != 0) | (np.diff(a_s) != 0) | (np.diff(t_s) != 0)
    e_s, b_s, a_s, t_s = e_s[keep], b_s[keep], a_s[keep], t_s[keep]
    run_key = e_s * bins + b_s
    new_run = np.ones(len(run_key), dtype=bool)
    new_run[1:] = np.diff(run_key) != 0
    starts = np.flatnonzero(new_run)
    stops = np.append(starts[1:], len(run_key))
    verts, count = _hulls(a_s, t_s, starts.astype(np.int64), stops.astype(np.int64))
    first = np.concatenate([[0], np.cumsum(count)[:-1]])
    run_e = e_s[starts]
    # hull of every vertex, per torque array: its distinct vertices sorted by (alpha, T)
    ve, va, vt = e_s[verts], a_s[verts], t_s[verts]
    o = np.lexsort((vt, va, ve))
    ve, va, vt = ve[o], va[o], vt[o]
    k = np.ones(len(va), dtype=bool)
    k[1:] = (np.diff(ve) != 0) | (np.diff(va) != 0) | (np.diff(vt) != 0)
    ve, va, vt = ve[k], va[k], vt[k]
    v_start = np.searchsorted(ve, np.arange(n_e), side="left")
    v_stop = np.searchsorted(ve, np.arange(n_e), side="right")
    all_v, all_count = _hulls(va, vt, v_start.astype(np.int64), v_stop.astype(np.int64))
    all_first = np.concatenate([[0], np.cumsum(all_count)[:-1]])
    out = []
    for e in range(n_e):
        runs = np.flatnonzero(run_e == e)
        c_e = count[runs]
        width = int(c_e.max())
        pos = np.minimum(np.arange(width)[None, :], c_e[:, None] - 1)  # padding repeats the last vertex
        sel = verts[first[runs][:, None] + pos]
        av = all_v[all_first[e]:all_first[e] + all_count[e]]
        out.append(Demand(omega=omega, alpha=alpha, torque=torques[e], weights=weights, period=period,
                          load_inertia=load_inertia, hull_speed=np.asarray(edges[b_s[starts[runs]] + 1], dtype=float),
                          hull_torque=t_s[sel], hull_alpha=a_s[sel], all_torque=vt[av], all_alpha=va[av]))
    return out


__all__ = ["chains", "fast_demand", "fast_demands"]
