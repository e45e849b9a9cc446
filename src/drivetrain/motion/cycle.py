"""A profile's exact form and its sampling: ``Segment`` pieces (a polynomial in local time plus,
for cam laws, one sinusoid), the ``Step`` and ``Phase`` they belong to, and ``Cycle``, which
evaluates them at any time and samples every segment on a (segment x point) grid (Simpson weights,
``Samples``). Parsing a profile into a ``Cycle`` is ``profiles.parse_profile``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Any, Literal, NamedTuple

import numpy as np
import numpy.typing as npt

from drivetrain.errors import InputError
from drivetrain.motion.cams import DEGREE, derivatives, evaluate_derivatives, evaluate_pieces, horner_into

FloatArray = npt.NDArray[np.float64]
Motion = Literal["linear", "rotary"]
PhaseKind = Literal["accel", "run", "decel", "dwell"]

_N_COEF = DEGREE + 1

class Kinematics(NamedTuple):
    """Position [m or rad], speed, acceleration and jerk at given times (arrays)."""

    x: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray


@dataclass(frozen=True)
class Segment:
    """One exact piece on [t0, t1] [s]: ``x(tau) = sum(coeffs[k] tau^k) + A sin(w tau + p)``.

    ``tau = t - t0`` is local time [s], from 0 to ``span`` [s]: the piece's exact duration, which
    ``t1 - t0`` matches only to the rounding of absolute time (local time keeps a short jerk
    piece late in a long cycle exact). ``coeffs`` [m/s^k or rad/s^k] hold DEGREE + 1 ascending
    coefficients; ``sine`` is ``(A [m or rad], w [rad/s], p [rad])``, all zero except in cam-law
    pieces. ``step`` and ``phase`` index ``Cycle.steps`` and ``Cycle.phases``.
    """

    t0: float
    t1: float
    coeffs: tuple[float, ...]
    step: int
    phase: int
    span: float
    sine: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def evaluate(self, t: npt.ArrayLike) -> Kinematics:
        """x, v, a, j at times ``t`` [s] in [t0, t1] (clipped to it)."""
        tt = np.asarray(t, dtype=float)
        return _PieceTable((self,)).evaluate_in(np.zeros(tt.shape, dtype=np.intp), tt)


class Phase(NamedTuple):
    """A phase of the cycle: ``kind`` over [t0, t1] [s] in step ``step``; ``move`` counts moves only
    (None in a dwell). An s-curve's accel phase spans its jerk pieces; a cam move is accel for
    its first half and decel for its second."""

    kind: PhaseKind
    t0: float
    t1: float
    step: int
    move: int | None


@dataclass(frozen=True)
class Step:
    """A parsed step with its kinematics (SI; peaks are magnitudes, ``direction`` gives the sign).

    ``shape`` is trapezoid, triangle, s_curve, time_optimal, a cam law name, or dwell.
    ``t_accel``/``t_decel`` [s] are the ramp times and ``t_jerk_accel``/``t_jerk_decel`` [s] the
    duration of each jerk piece within them. ``peak_jerk`` is the largest finite jerk: a
    trapezoid's jerk is impulsive at its corners and counted as 0. ``thrust`` [N or N m] replaces
    the load's thrust during a move (None: keep the load's); ``holding`` is set for dwells.
    """

    index: int
    kind: Literal["move", "dwell"]
    shape: str
    t0: float
    duration: float
    x0: float
    distance: float
    direction: int
    peak_speed: float = 0.0
    peak_accel: float = 0.0
    peak_decel: float = 0.0
    peak_jerk: float = 0.0
    t_accel: float = 0.0
    t_decel: float = 0.0
    t_jerk_accel: float = 0.0
    t_jerk_decel: float = 0.0
    thrust: float | None = None
    holding: Literal["motor", "brake"] | None = None
    move_index: int | None = None

    @property
    def t1(self) -> float:
        """End time [s] of the step."""
        return self.t0 + self.duration


@dataclass(frozen=True)
class Samples:
    """The cycle sampled per segment, for plots, speed-dependent loads and integrals.

    Every segment is sampled on its own with both end points (a boundary appears twice: left
    and right limit) and an odd number of points; ``weights`` [s] are composite Simpson weights
    per segment, so ``sum(weights * f)`` integrates ``f`` over one period, exactly for
    piecewise cubic ``f`` (e.g. the square of a piecewise-linear torque). ``t``, ``j``, ``step`` and
    ``segment``, which a duty cycle does not read, are computed on first use (the same floats).

    ``breakaway`` marks one extra sample where each move starts from rest: a copy of the move's first
    sample with zero quadrature weight. Static friction acts there (an instant: it counts in the
    peak, never in an integral, so the RMS does not depend on the number of points); at every other
    sample, the start and the arrival at rest included, friction slides.
    """

    x: FloatArray
    v: FloatArray
    a: FloatArray
    direction: npt.NDArray[np.int8]
    phase: npt.NDArray[np.intp]
    holding: npt.NDArray[np.bool_]
    braked: npt.NDArray[np.bool_]
    thrust: FloatArray
    weights: FloatArray
    breakaway: npt.NDArray[np.bool_] | None
    layout: _Layout = field(repr=False, compare=False)
    """Where the columns computed on first use (``t``, ``j``, ``step``, ``segment``) come from."""

    @cached_property
    def t(self) -> FloatArray:
        """Sample times [s]."""
        return self.layout.cycle._column("t", self.layout.counts)

    @cached_property
    def j(self) -> FloatArray:
        """Jerk [m/s^3 or rad/s^3]."""
        return self.layout.cycle._column("j", self.layout.counts)

    @cached_property
    def step(self) -> npt.NDArray[np.intp]:
        """Index of each sample's step in ``Cycle.steps``."""
        return self.layout.cycle._column("step", self.layout.counts)

    @cached_property
    def segment(self) -> npt.NDArray[np.intp]:
        """Index of each sample's segment in ``Cycle.segments``."""
        return self.layout.cycle._column("segment", self.layout.counts)

    def integral(self, y: npt.ArrayLike) -> float:
        """Integral of the sampled ``y`` over one period [unit of y times s]."""
        return float(np.dot(self.weights, np.asarray(y, dtype=float)))

    def rms(self, y: npt.ArrayLike) -> float:
        """Root mean square of the sampled ``y`` over one period."""
        yy = np.asarray(y, dtype=float)
        return math.sqrt(max(self.integral(yy * yy), 0.0) / float(self.weights.sum()))


class _PieceTable:
    """Segments packed into arrays for vectorised evaluation."""

    def __init__(self, segments: Sequence[Segment]) -> None:
        self.t0 = np.array([s.t0 for s in segments], dtype=float)
        self.t1 = np.array([s.t1 for s in segments], dtype=float)
        self.span = np.array([s.span for s in segments], dtype=float)
        self.coeffs = np.array([s.coeffs for s in segments], dtype=float).reshape(len(segments), _N_COEF)
        sine = np.array([s.sine for s in segments], dtype=float).reshape(len(segments), 3)
        self.amp, self.omega, self.phase = sine[:, 0], sine[:, 1], sine[:, 2]

    def locate(self, t: FloatArray) -> npt.NDArray[np.intp]:
        """Index of the segment holding each time (the later one at a boundary)."""
        return np.clip(np.searchsorted(self.t0, t, side="right") - 1, 0, len(self.t0) - 1)

    def evaluate_in(self, idx: npt.NDArray[np.intp], t: FloatArray) -> Kinematics:
        """Evaluate segment ``idx`` at absolute times ``t`` (local time clipped to the piece)."""
        return self.evaluate_local(idx, np.clip(t - self.t0[idx], 0.0, self.span[idx]))

    def evaluate_local(self, idx: npt.NDArray[np.intp], tau: FloatArray) -> Kinematics:
        """Evaluate segment ``idx`` at local times ``tau`` [s]."""
        x, v, a, j = evaluate_pieces(self.coeffs[idx], self.amp[idx], self.omega[idx], self.phase[idx], tau)
        return Kinematics(x, v, a, j)


@dataclass(frozen=True)
class Cycle:
    """A repeating cycle of moves and dwells: the exact truth, and its sampling.

    ``period`` [s]; ``motion`` linear (m) or rotary (rad); ``steps`` as parsed; ``segments`` the
    exact pieces in time order; ``phases`` the accel/run/decel/dwell spans. Position starts at 0
    and is absolute over the cycle (a cycle need not return to 0).
    """

    period: float
    motion: Motion
    steps: tuple[Step, ...]
    segments: tuple[Segment, ...]
    phases: tuple[Phase, ...]

    @cached_property
    def _table(self) -> _PieceTable:
        return _PieceTable(self.segments)

    def evaluate(self, t: npt.ArrayLike) -> Kinematics:
        """Exact x, v, a, j at times ``t`` in [0, period] [s] (right limits at boundaries)."""
        tt = np.asarray(t, dtype=float)
        return self._table.evaluate_in(self._table.locate(tt), tt)

    def sample(self, points_per_phase: int = 64) -> Samples:
        """Sample every segment (a phase or a piece of one) with ``points_per_phase`` points,
        rounded up to odd and at least 3, both ends included; see ``Samples``."""
        n = max(3, int(points_per_phase) | 1)
        tab = self._table
        nseg = len(self.segments)
        if n * nseg > MAX_SAMPLES:
            raise InputError("points_per_phase", f"{n} points on each of {nseg} segments are {n * nseg} samples, "
                             f"more than {MAX_SAMPLES}; at most {max(3, (MAX_SAMPLES // nseg - 1) | 1)} points "
                             "per phase fit", points_per_phase)
        frac, simpson = _fractions(n)
        dur = tab.t1 - tab.t0
        per = self._per_segment
        # Where a move starts from rest: one more sample, a copy of its first, with zero weight (breakaway),
        # right before it (np.insert's order). Columns constant over a segment are repeated n (or n + 1)
        # times; the others are copied once, by slices between the copies (a copy, not a gather).
        first = per.move_starts
        if n >= DIRECT_POINTS:
            if first.size:  # the speed at each move's first sample: the grid's operations at tau = 0
                derivs = (per.derivatives[0][first], per.derivatives[1][first], per.derivatives[2][first],
                          per.derivatives[3][first])
                at_start = evaluate_derivatives(derivs, tab.amp[first, None], tab.omega[first, None],
                                                tab.phase[first, None], np.zeros((first.size, 1)))
                first = first[at_start[1][:, 0] == 0.0]
            counts = np.full(nseg, n, dtype=np.intp)
            counts[first] += 1
            return self._sample_by_segment(n, frac, dur, simpson, counts)
        weights = (dur[:, None] / (3.0 * (n - 1))) * simpson[None, :]
        # every segment on its own row of the grid: its coefficients broadcast, never gathered per sample
        d = per.derivatives
        grid = evaluate_derivatives((d[0], d[1], d[2], d[3][..., :0]), tab.amp[:, None], tab.omega[:, None],
                                    tab.phase[:, None], tab.span[:, None] * frac[None, :])
        copied = first[grid[1][first, 0] == 0.0] if first.size else first
        counts = np.full(nseg, n, dtype=np.intp)
        counts[copied] += 1
        copy_at = copied * n + np.arange(copied.size)
        cuts = (copied * n).tolist()
        w_col = _spread(weights, cuts)
        w_col[copy_at] = 0.0
        breakaway = np.zeros(w_col.size, dtype=bool)
        breakaway[copy_at] = True
        return Samples(
            x=_spread(grid[0], cuts), v=_spread(grid[1], cuts), a=_spread(grid[2], cuts),
            direction=per.direction.repeat(counts), phase=per.phase.repeat(counts), holding=per.holding.repeat(counts),
            braked=per.braked.repeat(counts), thrust=per.thrust.repeat(counts), weights=w_col, breakaway=breakaway,
            layout=_Layout(self, counts),
        )

    def _column(self, name: str, counts: npt.NDArray[np.intp]) -> Any:
        """A column ``sample`` leaves for later (t, j, step or segment), by the grid's operations."""
        per, tab = self._per_segment, self._table
        if name == "step":
            return per.step.repeat(counts)
        if name == "segment":
            return np.arange(counts.size, dtype=np.intp).repeat(counts)
        n = int(counts.min())
        frac = _fractions(n)[0]
        cuts = (np.flatnonzero(counts > n) * n).tolist()
        if name == "t":
            t = tab.t0[:, None] + (tab.t1 - tab.t0)[:, None] * frac[None, :]
            t[:, -1] = tab.t1
            return _spread(t, cuts)
        d = per.derivatives
        grid = evaluate_derivatives((d[0][..., :0], d[1][..., :0], d[2][..., :0], d[3]), tab.amp[:, None],
                                    tab.omega[:, None], tab.phase[:, None], tab.span[:, None] * frac[None, :])
        return _spread(grid[3], cuts)

    def _sample_by_segment(self, n: int, frac: FloatArray, dur: FloatArray, simpson: FloatArray,
                           counts: npt.NDArray[np.intp]) -> Samples:
        """``sample`` for many points per segment: each segment written in place into the columns, the
        same floats by the same operations as the grid, without the copies the breakaway samples take
        there. A Python loop over the segments only (each holds at least DIRECT_POINTS samples)."""
        tab, per = self._table, self._per_segment
        offsets = np.concatenate([[0], np.cumsum(counts)]).tolist()
        total = offsets[-1]
        x, v, a, weights = (np.empty(total) for _ in range(4))
        consts: list[tuple[npt.NDArray[Any], npt.NDArray[Any]]] = [
            (per.direction, np.empty(total, dtype=np.int8)), (per.phase, np.empty(total, dtype=np.intp)),
            (per.holding, np.empty(total, dtype=bool)), (per.braked, np.empty(total, dtype=bool)),
            (per.thrust, np.empty(total))]
        breakaway = np.zeros(total, dtype=bool)
        scale = dur / (3.0 * (n - 1))
        sine = bool(np.any(tab.amp))
        for k in range(len(counts)):
            start, end = offsets[k], offsets[k + 1]
            copy = end - start > n
            rows = slice(start + copy, end)
            np.multiply(scale[k:k + 1], simpson, out=weights[rows])
            tau = tab.span[k:k + 1] * frac
            for col, coef in zip((x, v, a), per.derivatives, strict=False):
                horner_into(coef[k, 0], tau, col[rows])
            if sine:
                amp, om = tab.amp[k:k + 1], tab.omega[k:k + 1]
                arg = om * tau + tab.phase[k:k + 1]
                sin, cos = np.sin(arg), np.cos(arg)
                x[rows] += amp * sin
                v[rows] += amp * om * cos
                a[rows] -= amp * om**2 * sin
            for value, col in consts:
                col[start:end] = value[k]
            if copy:
                for col in (x, v, a):
                    col[start] = col[start + 1]
                weights[start] = 0.0
                breakaway[start] = True
        return Samples(x=x, v=v, a=a, direction=consts[0][1], phase=consts[1][1], holding=consts[2][1],
                       braked=consts[3][1], thrust=consts[4][1], weights=weights, breakaway=breakaway,
                       layout=_Layout(self, counts))

    @cached_property
    def _per_segment(self) -> _PerSegment:
        steps = self.steps
        step_of = np.array([s.step for s in self.segments], dtype=np.intp)
        first_seg: dict[int, int] = {}
        for k, sg in enumerate(self.segments):
            if steps[sg.step].kind == "move" and steps[sg.step].direction != 0:
                first_seg.setdefault(sg.step, k)
        return _PerSegment(
            step=step_of, phase=np.array([s.phase for s in self.segments], dtype=np.intp),
            direction=np.array([steps[i].direction for i in step_of], dtype=np.int8),
            holding=np.array([steps[i].holding == "motor" for i in step_of], dtype=bool),
            braked=np.array([steps[i].holding == "brake" for i in step_of], dtype=bool),
            thrust=np.array([math.nan if steps[i].thrust is None else steps[i].thrust for i in step_of], dtype=float),
            move_starts=np.array(sorted(first_seg.values()), dtype=np.intp),
            derivatives=derivatives(self._table.coeffs[:, None, :]),
        )


class _Layout(NamedTuple):
    """A sampled cycle's layout: its cycle and the samples of each segment (n, or n + 1 with a copy)."""

    cycle: Cycle
    counts: npt.NDArray[np.intp]


@lru_cache(maxsize=16)
def _fractions(n: int) -> tuple[FloatArray, FloatArray]:
    """n points from 0 to 1 (both ends) and the composite Simpson factors 1 4 2 ... 4 1 (read-only)."""
    frac = np.linspace(0.0, 1.0, n)
    simpson = np.ones(n)
    simpson[1:-1:2], simpson[2:-1:2] = 4.0, 2.0
    frac.flags.writeable = simpson.flags.writeable = False
    return frac, simpson


def _spread(rows: npt.NDArray[Any], cuts: list[int]) -> npt.NDArray[Any]:
    """The (segment x point) grid ``rows`` as one column, with a copy of the sample at each flat index of
    ``cuts`` (ascending) right before it (np.insert's order), by slices (a copy, not a gather)."""
    flat = rows.reshape(-1)
    if not cuts:
        return flat
    out = np.empty(flat.size + len(cuts), dtype=flat.dtype)
    prev = dst = 0
    for c in cuts:
        out[dst:dst + c - prev] = flat[prev:c]
        dst += c - prev
        out[dst] = flat[c]
        dst += 1
        prev = c
    out[dst:] = flat[prev:]
    return out


class _PerSegment(NamedTuple):
    """What ``Cycle.sample`` repeats over each segment's samples, and the segments that start a move."""

    step: npt.NDArray[np.intp]
    phase: npt.NDArray[np.intp]
    direction: npt.NDArray[np.int8]
    holding: npt.NDArray[np.bool_]
    braked: npt.NDArray[np.bool_]
    thrust: FloatArray
    move_starts: npt.NDArray[np.intp]
    derivatives: tuple[FloatArray, FloatArray, FloatArray, FloatArray]


DIRECT_POINTS = 2048
"""Points per segment from which ``Cycle.sample`` writes each segment in place (fewer: one grid)."""

MAX_SAMPLES = 500_000
"""Samples one cycle may be cut into (points per phase x segments): a catalog selection holds a few
kB per sample, so this bounds it near 1 GB."""
