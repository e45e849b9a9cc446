r"""Several drives on one DC bus: the bus power over a machine cycle, energy shared between axes, supply current.

Power signs: positive = drawn from the bus (motoring), negative = fed into the bus (braking).

* Each axis's electrical power :math:`p_a(t) = T\omega + p_{Cu}` (:mod:`drivetrain.physics.regen`)
  runs once per machine cycle of length :math:`T_c`, started at its offset :math:`t_a`; it
  holds its last value (at rest, the holding power) from the end of its own cycle to the next
  machine cycle. On a periodic grid of the machine cycle its value at :math:`\tau` is
  :math:`p_a(((\tau - t_a) \bmod T_c))`, interpolated linearly between the axis's samples.
* The bus power is the sum :math:`P(t) = \sum_a p_a(t)`. Drives on a common bus pass
  braking energy straight to motoring drives (the shared DC link: Siemens SINAMICS S120
  system manual, "DC link energy exchange"; Rockwell Kinetix 5700 design guide, shared-bus
  configurations); the energy so exchanged over one cycle is
  :math:`E_{shared} = \int \min\big(\sum_a \max(-p_a, 0), \sum_a \max(p_a, 0)\big)\,dt`.
* What the bus still receives, :math:`\max(-P, 0)`, goes to the capacitors and then the
  braking resistor as for one drive (:func:`drivetrain.physics.regen.regen_cycle`).
* A diode-rectifier supply cannot feed back: it delivers :math:`\max(P, 0)`. Its line current
  for a three-phase supply of line-to-line voltage U and power factor :math:`\lambda` is
  :math:`I = P / (\sqrt3\,U\,\lambda)`, single-phase :math:`I = P / (U \lambda)` (the definition of
  active power, IEC 60050-131).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def periodic_grid(times: list[ArrayLike], cycle_time: float, uniform: int) -> tuple[FloatArray, NDArray[np.bool_],
                                                                                     FloatArray]:
    r"""A periodic grid over the machine cycle that keeps every jump: (times [s], right-limit flags, weights [s]).

    ``times``: each axis's sample times already shifted into the machine cycle, [0, T_c). With
    ``uniform`` evenly spaced points they form the grid; every point appears twice, its left and
    its right limit (a step in torque at a phase joint is a step in power), and the trapezoidal
    weights of the closed periodic grid (the point at T_c is the first point) make
    :math:`\sum_k w_k f_k = \int_0^{T_c} f\,dt` exactly for a piecewise-linear f.

    >>> t, right, w = periodic_grid([[0.5]], 1.0, 2)
    >>> t.tolist(), right.tolist(), float(w.sum())
    ([0.0, 0.0, 0.5, 0.5], [False, True, False, True], 1.0)
    """
    base = np.arange(max(int(uniform), 1)) * (cycle_time / max(int(uniform), 1))
    pts = np.unique(np.concatenate([base, *[np.mod(np.asarray(x, dtype=float), cycle_time) for x in times]]))
    pts = pts[pts < cycle_time]
    t = np.repeat(pts, 2)
    right = np.tile(np.array([False, True]), pts.size)
    closed = np.append(t, cycle_time)
    h = np.diff(closed)
    w = np.zeros_like(closed)
    w[:-1] += h / 2.0
    w[1:] += h / 2.0
    w[0] += w[-1]
    return t, right, w[:-1]


def periodic_resample(t: ArrayLike, p: ArrayLike, grid: ArrayLike, offset: float, cycle_time: float,
                      right: ArrayLike | None = None) -> FloatArray:
    r"""An axis's power (or any quantity) on the machine grid, started at ``offset``, periodic over the machine cycle.

    Args:
        t: the axis's sample times [s], ascending from 0 (a repeated time is a jump: left value first).
        p: its values at ``t`` (e.g. power [W]).
        grid: machine-cycle times [s] in [0, cycle_time).
        offset: start of the axis in the machine cycle [s].
        cycle_time: machine cycle :math:`T_c` [s] (>= the axis's own cycle).
        right: per grid point, True for the right limit (default), False for the left limit.

    Returns:
        :math:`p(((\tau - t_a) \bmod T_c))`, linear between samples, the last value after the
        axis's own cycle ends (it rests until it starts again).

    >>> periodic_resample([0.0, 1.0], [0.0, 10.0], [0.0, 0.5, 1.0], 0.5, 3.0).tolist()
    [10.0, 0.0, 5.0]
    """
    tt = np.asarray(t, dtype=float)
    pp = np.asarray(p, dtype=float)
    g = np.asarray(grid, dtype=float)
    s = np.mod(g - float(offset), cycle_time)
    # snap to the axis's own sample times (the grid was built from them; rounding must not cross a jump)
    k = np.clip(np.searchsorted(tt, s), 1, tt.size - 1)
    near = np.where(np.abs(tt[k] - s) < np.abs(tt[k - 1] - s), tt[k], tt[k - 1])
    s = np.where(np.abs(near - s) <= 1e-9 * cycle_time, near, s)
    s = np.where(np.abs(s - cycle_time) <= 1e-9 * cycle_time, 0.0, s)
    out = np.interp(s, tt, pp, right=pp[-1])
    if right is not None:
        left_side = ~np.asarray(right, dtype=bool)
        lv = np.interp(-s, -tt[::-1], pp[::-1], left=pp[-1])
        lv = np.where(s == 0.0, pp[-1], lv)  # just before the start: the rest at the end of the cycle
        out = np.where(left_side, lv, out)
    return np.asarray(out)


def shared_energy(powers: ArrayLike, weights: ArrayLike) -> float:
    r"""Energy exchanged on a shared bus between braking and motoring drives [J].

    :math:`E = \int \min\big(\sum_a \max(-p_a, 0), \sum_a \max(p_a, 0)\big)\,dt` with ``powers``
    of shape (A, N) [W] and quadrature ``weights`` (N,) [s]. Source: module docstring.

    >>> shared_energy([[100.0, -50.0], [-30.0, 80.0]], [1.0, 1.0])
    80.0
    """
    p = np.atleast_2d(np.asarray(powers, dtype=float))
    braking = np.maximum(-p, 0.0).sum(axis=0)
    motoring = np.maximum(p, 0.0).sum(axis=0)
    return float(np.sum(np.asarray(weights, dtype=float) * np.minimum(braking, motoring)))


def line_current(power: ArrayLike, voltage: float, phases: int = 3, power_factor: float = 1.0) -> FloatArray:
    r"""Supply line current [A rms] for an active power [W]: :math:`P / (\sqrt3 U \lambda)` (3 phases),
    :math:`P/(U\lambda)` (1 phase).

    ``voltage`` line-to-line rms [V]; ``power_factor`` :math:`\lambda` (a diode rectifier's is
    below 1; the caller states which it used). Source: IEC 60050-131, active power of a
    three-phase system :math:`P = \sqrt3 U I \lambda`.

    >>> round(float(line_current(6928.2, 400.0)), 2)
    10.0
    """
    k = np.sqrt(3.0) if phases == 3 else 1.0
    return np.asarray(np.asarray(power, dtype=float) / (k * voltage * power_factor))


def start_at_rest(p: ArrayLike) -> int:
    """Index where a periodic bus-power trace should start so that no braking event is cut in two.

    The first sample with p >= 0 (the bus is not receiving); 0 if there is none (the bus receives
    power all the time, one event).

    >>> start_at_rest([-1.0, -2.0, 3.0, -1.0])
    2
    """
    pp = np.asarray(p, dtype=float)
    idx = np.flatnonzero(pp >= 0.0)
    return int(idx[0]) if idx.size else 0
