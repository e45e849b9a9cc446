"""Motion profiles: moves and dwells in a repeating cycle, their exact segments and sampling.

A profile is a list of steps, run in order; the cycle repeats. A step is a move or a dwell
(the axis file's ``profile:`` key, as in design.md)::

    {move: 200 mm, time: 0.5 s, accel: 0.1 s[, decel: 0.1 s]}       trapezoid, given ramp times
    {move: 200 mm, time: 0.5 s, shape: trapezoid | triangle | s_curve
        [, accel: ...][, jerk_fraction: 0.5 | jerk: 50 m/s^3]}        trapezoid 1/3-1/3-1/3 by default
    {speed: 15 m/min, time: 1.2 s, accel: 0.1 s[, decel: ...]}       distance = movement amount
    {move: 200 mm, max_speed: 1 m/s, max_accel: 10 m/s^2[, max_jerk: 500 m/s^3]}   time-optimal
    {move: 90 deg, time: 0.5 s, law: cycloidal | modified_sine | modified_trapezoid | poly345}
    {dwell: 0.3 s[, holding: motor | brake]}

Any move may carry ``thrust:`` (a force, or a torque on a rotary axis) that replaces the load's
thrust during that move. A linear profile takes lengths and m/s..., a rotary one angles and
rad/s (rpm accepted). Inside, everything is SI floats: m or rad, s.

Every move is rest to rest. Its exact form is a list of ``Segment`` pieces: a polynomial in
local time plus, for cam laws, one sinusoid. The timed shapes share one seven-piece form
(jerk, constant accel, jerk, cruise, jerk, constant decel, jerk; zero-length pieces dropped):
a ramp of duration ``t_r`` with jerk fraction ``f`` spends ``f t_r / 2`` in each jerk piece,
so its mean speed is half the peak and the lecture's movement amount holds for every shape.

Guarantees (tested on seeded random moves in ``tests/test_profiles_random.py``):

- every move ends at its target, start + distance, within 1e-9 relative (in practice a few ulp);
- every move starts and ends at rest: speed zero within 1e-12 of its peak, and acceleration as
  well for jerk-limited shapes (s-curves, time-optimal with ``max_jerk``, cam laws);
- sampled |v|, |a|, |j| never exceed the step's ``peak_speed``, ``peak_accel``/``peak_decel``,
  ``peak_jerk`` by more than 1e-12 relative, and a time-optimal move never exceeds its limits;
- no NaN for any accepted input; impossible requests raise ``InputError`` naming the field;
- ``time_optimal_duration`` equals ruckig's duration within 1e-9 s (seeded comparison).

Sources: the lecture notes in ``seed/`` (trapezoid ``v_max = x_f / t_2``, ``a_max = x_f /
(t_1 t_2)``; movement amount ``L_s = V (2 t_s - t_a - t_d) / 2``); cam laws in ``cams.py``
(Norton); jerk-limited time-optimal rest-to-rest moves: L. Biagiotti, C. Melchiorri,
*Trajectory Planning for Automatic Machines and Robots*, Springer (2008), sec. 3.4 (double S).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Literal, NamedTuple

import numpy as np
import numpy.typing as npt

from drivetrain import units
from drivetrain.errors import InputError
from drivetrain.motion.cams import CAM_LAWS, DEGREE, cam_law, evaluate_pieces

FloatArray = npt.NDArray[np.float64]
Motion = Literal["linear", "rotary"]
PhaseKind = Literal["accel", "run", "decel", "dwell"]

SHAPES: tuple[str, ...] = ("trapezoid", "triangle", "s_curve")
HOLDING: tuple[str, ...] = ("motor", "brake")
DEFAULT_JERK_FRACTION = 1.0
"""``shape: s_curve`` without ``jerk_fraction`` or ``jerk`` is the pure s-curve."""

_N_COEF = DEGREE + 1
_MIN_JERK_FRACTION = 1e-9
"""Jerk fractions below this are taken as 0 (a trapezoid)."""


# --------------------------------------------------------------------------- formula functions


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


# --------------------------------------------------------------------------- exact representation


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
    piecewise cubic ``f`` (e.g. the square of a piecewise-linear torque).

    ``breakaway`` marks one extra sample where each move starts from rest: a copy of the move's first
    sample with zero quadrature weight. Static friction acts there (an instant: it counts in the
    peak, never in an integral, so the RMS does not depend on the number of points); at every other
    sample, the start and the arrival at rest included, friction slides.
    """

    t: FloatArray
    x: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    direction: npt.NDArray[np.int8]
    step: npt.NDArray[np.intp]
    phase: npt.NDArray[np.intp]
    segment: npt.NDArray[np.intp]
    holding: npt.NDArray[np.bool_]
    braked: npt.NDArray[np.bool_]
    thrust: FloatArray
    weights: FloatArray
    breakaway: npt.NDArray[np.bool_] | None = None

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
        frac = np.linspace(0.0, 1.0, n)
        dur = tab.t1 - tab.t0
        t = tab.t0[:, None] + dur[:, None] * frac[None, :]
        t[:, -1] = tab.t1
        simpson = np.ones(n)
        simpson[1:-1:2], simpson[2:-1:2] = 4.0, 2.0
        weights = (dur[:, None] / (3.0 * (n - 1))) * simpson[None, :]
        seg = np.repeat(np.arange(nseg, dtype=np.intp), n)
        # every segment on its own row of the grid: its coefficients broadcast, never gathered per sample
        grid = evaluate_pieces(tab.coeffs[:, None, :], tab.amp[:, None], tab.omega[:, None], tab.phase[:, None],
                               tab.span[:, None] * frac[None, :])
        kin = Kinematics(*(g.ravel() for g in grid))
        step_of = np.array([s.step for s in self.segments], dtype=np.intp)
        phase_of = np.array([s.phase for s in self.segments], dtype=np.intp)
        steps = self.steps
        direction = np.array([steps[i].direction for i in step_of], dtype=np.int8)
        holding = np.array([steps[i].holding == "motor" for i in step_of], dtype=bool)
        braked = np.array([steps[i].holding == "brake" for i in step_of], dtype=bool)
        thrust = np.array([math.nan if steps[i].thrust is None else steps[i].thrust for i in step_of])
        cols: dict[str, Any] = {
            "t": t.ravel(), "x": kin.x, "v": kin.v, "a": kin.a, "j": kin.j,
            "direction": direction[seg], "step": step_of[seg], "phase": phase_of[seg], "segment": seg,
            "holding": holding[seg], "braked": braked[seg], "thrust": thrust[seg], "weights": weights.ravel(),
            "breakaway": np.zeros(seg.size, dtype=bool),
        }
        # Where a move starts from rest: one more sample, a copy of its first, with zero weight (breakaway).
        first_seg: dict[int, int] = {}
        for k, sg in enumerate(self.segments):
            if steps[sg.step].kind == "move" and steps[sg.step].direction != 0:
                first_seg.setdefault(sg.step, k)
        starts = np.array(sorted(k * n for k in first_seg.values()), dtype=np.intp)
        starts = starts[cols["v"][starts] == 0.0] if starts.size else starts
        if starts.size:
            copies = {key: col[starts] for key, col in cols.items()}
            copies["weights"] = np.zeros(starts.size)
            copies["breakaway"] = np.ones(starts.size, dtype=bool)
            cols = {key: np.insert(col, starts, copies[key]) for key, col in cols.items()}
        return Samples(**cols)


# --------------------------------------------------------------------------- building pieces


class _Piece(NamedTuple):
    """A piece of a step on [t0, t1] in absolute time [s], with coefficients in its local time."""

    kind: PhaseKind
    t0: float
    t1: float
    span: float
    coeffs: tuple[float, ...]
    sine: tuple[float, float, float] = (0.0, 0.0, 0.0)


class _Ramp(NamedTuple):
    """Ramp from rest to peak speed (or back): jerk pieces of ``t_jerk``, a flat of ``t_const`` [s]
    at ``accel`` [m/s^2] (magnitude)."""

    t_jerk: float
    t_const: float
    accel: float

    @property
    def jerk(self) -> float:
        """Jerk [m/s^3] of the jerk pieces (0 for a trapezoid ramp)."""
        return self.accel / self.t_jerk if self.t_jerk > 0.0 else 0.0


def _poly(x: float, v: float, a: float, j: float) -> tuple[float, ...]:
    """Position coefficients of constant-jerk motion from state (x, v, a)."""
    return (x, v, a / 2.0, j / 6.0) + (0.0,) * (_N_COEF - 4)


def _grid(t0: float, duration: float, dts: Sequence[float]) -> list[tuple[float, float]]:
    """Absolute spans of consecutive pieces of durations ``dts``; the last ends at ``t0 + duration``."""
    t_end = t0 + duration
    ends = np.minimum(t0 + np.cumsum(dts), t_end)
    ends[-1] = t_end
    starts = np.r_[t0, ends[:-1]]
    return [(float(a), float(b)) for a, b in zip(starts, ends, strict=True)]


def _ramp_spec(ramp: _Ramp, a_sign: float) -> list[tuple[float, float, float, float]]:
    """(dt, accel at start, accel at end, jerk) of a ramp's three pieces; ``a_sign`` signs its accel."""
    a, j = a_sign * ramp.accel, a_sign * ramp.jerk
    return [(ramp.t_jerk, 0.0, a, j), (ramp.t_const, a, a, 0.0), (ramp.t_jerk, a, 0.0, -j)]


def _double_s_pieces(
    t0: float, duration: float, x0: float, distance: float, v_peak: float, acc: _Ramp, dec: _Ramp,
    t_cruise: float,
) -> list[_Piece]:
    """Pieces of a rest-to-rest move: accel ramp forward from the start, decel ramp backward from
    the target at rest (so the move ends exactly there), and the cruise between at the peak speed."""
    sign = 1.0 if distance >= 0.0 else -1.0
    head = [*_ramp_spec(acc, sign), (t_cruise, 0.0, 0.0, 0.0)]
    tail = _ramp_spec(dec, -sign)
    spans = _grid(t0, duration, [p[0] for p in head + tail])
    pieces: list[_Piece] = []
    x, v = x0, 0.0
    for k, ((t_a, t_b), (dt, a, _, j)) in enumerate(zip(spans, head, strict=False)):
        if k == len(head) - 1:
            v = sign * v_peak  # cruise at the exact peak speed
        if dt > 0.0:
            pieces.append(_Piece("run" if k == len(head) - 1 else "accel", t_a, t_b, dt, _poly(x, v, a, j)))
            x, v = x + dt * (v + dt * (a / 2.0 + dt * j / 6.0)), v + dt * (a + dt * j / 2.0)
    back: list[_Piece] = []
    x, v = x0 + distance, 0.0
    for (t_a, t_b), (dt, _, a_end, j) in zip(reversed(spans[len(head):]), reversed(tail), strict=True):
        if dt > 0.0:
            a = a_end - j * dt
            v = v - dt * (a + dt * j / 2.0)
            x = x - dt * (v + dt * (a / 2.0 + dt * j / 6.0))
            back.append(_Piece("decel", t_a, t_b, dt, _poly(x, v, a, j)))
    return pieces + back[::-1]


def _cam_pieces(t0: float, duration: float, x0: float, distance: float, law: str) -> list[_Piece]:
    """Pieces of a cam-law move: ``x = x0 + h s(t / T)`` scaled into each piece's local time."""
    cam = cam_law(law).pieces
    dts = [(p.u1 - p.u0) * duration for p in cam]
    scale = distance / duration ** np.arange(_N_COEF)
    pieces = []
    for p, dt, (t_a, t_b) in zip(cam, dts, _grid(t0, duration, dts), strict=True):
        coeffs = np.asarray(p.poly) * scale
        coeffs[0] += x0
        kind: PhaseKind = "accel" if p.u1 <= 0.5 else "decel"
        sine = (distance * p.amp, p.omega / duration, p.phase)
        pieces.append(_Piece(kind, t_a, t_b, dt, tuple(float(c) for c in coeffs), sine))
    return pieces


# --------------------------------------------------------------------------- parsing

_QUANTITY: dict[str, dict[str, str]] = {
    "linear": {
        "distance": "length", "speed": "speed", "accel": "acceleration", "jerk": "jerk", "thrust": "force",
    },
    "rotary": {
        "distance": "angle", "speed": "angular_speed", "accel": "angular_acceleration",
        "jerk": "angular_jerk", "thrust": "torque",
    },
}
_TIMED_KEYS = ("move", "speed", "time", "accel", "decel", "shape", "jerk_fraction", "jerk", "thrust")
_CAM_KEYS = ("move", "time", "law", "thrust")
_OPTIMAL_KEYS = ("move", "max_speed", "max_accel", "max_jerk", "thrust")
_DWELL_KEYS = ("dwell", "holding")
VALID_KEYS: tuple[str, ...] = tuple(dict.fromkeys(_TIMED_KEYS + _CAM_KEYS + _OPTIMAL_KEYS + _DWELL_KEYS))


class _StepParser:
    """Parses one step dict at ``path`` (e.g. ``profile[2]``) for a linear or rotary axis."""

    def __init__(self, raw: Mapping[str, Any], path: str, motion: Motion) -> None:
        self.raw, self.path, self.q = raw, path, _QUANTITY[motion]
        self.unit = "m" if motion == "linear" else "rad"

    def field(self, key: str) -> str:
        """Field path of ``key`` for error messages."""
        return f"{self.path}.{key}"

    def value(self, key: str, quantity: str) -> float:
        """SI value of ``key`` as ``quantity`` (see units.parse)."""
        return units.parse(self.raw[key], quantity, self.field(key))

    def positive(self, key: str, quantity: str) -> float:
        """SI value of ``key``, which must be > 0."""
        value = self.value(key, quantity)
        if value <= 0.0:
            raise InputError(self.field(key), "must be positive", self.raw[key])
        return value

    def nonzero(self, key: str, quantity: str, hint: str) -> float:
        """Signed SI value of ``key``, which must not be 0."""
        value = self.value(key, quantity)
        if value == 0.0:
            raise InputError(self.field(key), f"must not be zero ({hint})", self.raw[key])
        return value

    def only(self, allowed: tuple[str, ...], what: str) -> None:
        """Reject keys that do not belong to this form of step."""
        for key in self.raw:
            if key not in allowed:
                raise InputError(self.field(key), f"does not apply to {what}; it takes: {', '.join(allowed)}",
                                 self.raw[key])

    def choice(self, key: str, valid: tuple[str, ...], default: str) -> str:
        """The value of ``key`` (or ``default``), which must be one of ``valid``."""
        value = self.raw.get(key, default)
        if value not in valid:
            raise InputError(self.field(key), f"unknown {key}; valid: {', '.join(valid)}", value)
        return str(value)

    def require(self, key: str, rule: str) -> None:
        """Raise naming ``key`` when it is missing."""
        if key not in self.raw:
            raise InputError(self.field(key), rule, has_value=False)


class _Parsed(NamedTuple):
    """A parsed step and its pieces in absolute time."""

    step: Step
    pieces: list[_Piece]


def _parse_dwell(p: _StepParser, index: int, t0: float, x0: float) -> _Parsed:
    p.only(_DWELL_KEYS, "a dwell")
    duration = p.positive("dwell", "time")
    braked = p.choice("holding", HOLDING, "motor") == "brake"
    holding: Literal["motor", "brake"] = "brake" if braked else "motor"
    step = Step(index, "dwell", "dwell", t0, duration, x0, 0.0, 0, holding=holding)
    return _Parsed(step, [_Piece("dwell", t0, step.t1, duration, _poly(x0, 0.0, 0.0, 0.0))])


def _parse_thrust(p: _StepParser) -> float | None:
    return p.value("thrust", p.q["thrust"]) if "thrust" in p.raw else None


def _parse_cam(p: _StepParser, index: int, t0: float, x0: float, move: int) -> _Parsed:
    p.only(_CAM_KEYS, "a cam-law move")
    p.require("move", "a cam-law move needs its distance")
    p.require("time", "a cam-law move needs its time")
    distance = p.nonzero("move", p.q["distance"], "use a dwell to stand still")
    duration = p.positive("time", "time")
    law = cam_law(p.choice("law", CAM_LAWS, ""))
    h = abs(distance)
    step = Step(
        index, "move", law.name, t0, duration, x0, distance, 1 if distance > 0 else -1,
        peak_speed=law.c_v * h / duration, peak_accel=law.c_a * h / duration**2,
        peak_decel=law.c_a * h / duration**2, peak_jerk=law.c_j * h / duration**3,
        t_accel=duration / 2.0, t_decel=duration / 2.0, thrust=_parse_thrust(p), move_index=move,
    )
    return _Parsed(step, _cam_pieces(t0, duration, x0, distance, law.name))


def _parse_optimal(p: _StepParser, index: int, t0: float, x0: float, move: int) -> _Parsed:
    p.only(_OPTIMAL_KEYS, "a time-optimal move (move, max_speed, max_accel[, max_jerk])")
    p.require("move", "a time-optimal move needs its distance")
    p.require("max_speed", "a time-optimal move needs max_speed")
    p.require("max_accel", "a time-optimal move needs max_accel")
    distance = p.nonzero("move", p.q["distance"], "use a dwell to stand still")
    vmax = p.positive("max_speed", p.q["speed"])
    amax = p.positive("max_accel", p.q["accel"])
    jmax = p.positive("max_jerk", p.q["jerk"]) if "max_jerk" in p.raw else math.inf
    opt = time_optimal_parameters(distance, vmax, amax, jmax)
    v_p, a_p, t_j, t_c, t_v = (float(x) for x in (opt.peak_speed, opt.peak_accel, opt.t_jerk, opt.t_const,
                                                  opt.t_cruise))
    ramp = _Ramp(t_j, t_c, a_p)
    duration = float(opt.duration)
    step = Step(
        index, "move", "time_optimal", t0, duration, x0, distance, 1 if distance > 0 else -1,
        peak_speed=v_p, peak_accel=a_p, peak_decel=a_p, peak_jerk=ramp.jerk,
        t_accel=2.0 * t_j + t_c, t_decel=2.0 * t_j + t_c, t_jerk_accel=t_j, t_jerk_decel=t_j,
        thrust=_parse_thrust(p), move_index=move,
    )
    return _Parsed(step, _double_s_pieces(t0, duration, x0, distance, v_p, ramp, ramp, t_v))


def _ramp_times(p: _StepParser, shape: str, duration: float) -> tuple[float, float]:
    """Accel and decel times [s] of a timed move: given, or the shape's default."""
    if shape == "triangle":
        for key in ("accel", "decel"):
            if key in p.raw:
                raise InputError(p.field(key), "does not apply to shape triangle (accel = decel = time / 2); "
                                 "use shape trapezoid to set ramp times", p.raw[key])
        return duration / 2.0, duration / 2.0
    if "accel" not in p.raw:
        if "decel" in p.raw:
            raise InputError(p.field("decel"), "needs accel as well", p.raw["decel"])
        return duration / 3.0, duration / 3.0
    t_a = p.positive("accel", "time")
    t_d = p.positive("decel", "time") if "decel" in p.raw else t_a
    return t_a, t_d


def _s_curve_ramp(p: _StepParser, v_peak: float, t_ramp: float, which: str) -> _Ramp:
    """The ramp of an s-curve from its jerk fraction or jerk limit."""
    if "jerk" in p.raw:
        if "jerk_fraction" in p.raw:
            raise InputError(p.field("jerk"), "give either jerk or jerk_fraction, not both", p.raw["jerk"])
        jerk = p.positive("jerk", p.q["jerk"])
        t_j = float(s_curve_jerk_time(v_peak, t_ramp, jerk))
        if not math.isfinite(t_j):
            need = 4.0 * v_peak / t_ramp**2
            rule = (f"is too low to reach the peak speed {v_peak:.6g} {p.unit}/s within the {which} time "
                    f"{t_ramp:.6g} s (needs at least {need:.6g} {p.unit}/s^3)")
            raise InputError(p.field("jerk"), rule, p.raw["jerk"])
        t_j = min(t_j, t_ramp / 2.0)
        return _Ramp(t_j, max(t_ramp - 2.0 * t_j, 0.0), v_peak / (t_ramp - t_j))
    f = DEFAULT_JERK_FRACTION
    if "jerk_fraction" in p.raw:
        f = p.value("jerk_fraction", "dimensionless")
        if not 0.0 <= f <= 1.0:
            raise InputError(p.field("jerk_fraction"), "must be within [0, 1] (0 trapezoid, 1 pure s-curve)",
                             p.raw["jerk_fraction"])
    if f < _MIN_JERK_FRACTION:
        f = 0.0  # jerk pieces that short would only carry an overflowing jerk
    t_j = 0.5 * f * t_ramp
    return _Ramp(t_j, t_ramp - 2.0 * t_j, float(s_curve_peak_accel(v_peak, t_ramp, f)))


def _parse_timed(p: _StepParser, index: int, t0: float, x0: float, move: int) -> _Parsed:
    p.only(_TIMED_KEYS, "a move given by distance (or speed) and time")
    if "move" in p.raw and "speed" in p.raw:
        raise InputError(p.field("speed"), "give either move (a distance) or speed, not both", p.raw["speed"])
    p.require("time", "a move needs its time (or max_speed and max_accel for a time-optimal move)")
    duration = p.positive("time", "time")
    shape = p.choice("shape", SHAPES, "trapezoid")
    if shape != "s_curve":
        for key in ("jerk_fraction", "jerk"):
            if key in p.raw:
                raise InputError(p.field(key), "applies only to shape s_curve", p.raw[key])
    t_a, t_d = _ramp_times(p, shape, duration)
    if "speed" in p.raw:
        speed = p.nonzero("speed", p.q["speed"], "use a dwell to stand still")
        if 2.0 * duration < t_a + t_d:
            rule = ("the movement amount V (2 t_s - t_a - t_d) / 2 would be negative: "
                    f"2 time must be at least accel + decel = {t_a + t_d:.6g} s")
            raise InputError(p.field("time"), rule, p.raw["time"])
        distance = float(movement_amount(speed, duration, t_a, t_d))
    else:
        distance = p.nonzero("move", p.q["distance"], "use a dwell to stand still")
    if t_a + t_d > duration * (1.0 + 1e-12):
        raise InputError(p.field("accel"), f"accel + decel must not exceed the move time {duration:.6g} s",
                         f"{t_a + t_d:.6g} s")
    t_cruise = max(duration - t_a - t_d, 0.0)
    v_peak = float(trapezoid_peak_speed(abs(distance), duration, t_a, t_d))
    if shape == "s_curve":
        acc, dec = _s_curve_ramp(p, v_peak, t_a, "accel"), _s_curve_ramp(p, v_peak, t_d, "decel")
    else:
        acc, dec = _Ramp(0.0, t_a, v_peak / t_a), _Ramp(0.0, t_d, v_peak / t_d)
    step = Step(
        index, "move", shape, t0, duration, x0, distance, 1 if distance > 0 else -1,
        peak_speed=v_peak, peak_accel=acc.accel, peak_decel=dec.accel, peak_jerk=max(acc.jerk, dec.jerk),
        t_accel=t_a, t_decel=t_d, t_jerk_accel=acc.t_jerk, t_jerk_decel=dec.t_jerk,
        thrust=_parse_thrust(p), move_index=move,
    )
    return _Parsed(step, _double_s_pieces(t0, duration, x0, distance, v_peak, acc, dec, t_cruise))


def _parse_step(raw: Any, path: str, motion: Motion, index: int, t0: float, x0: float, move: int) -> _Parsed:
    if not isinstance(raw, Mapping):
        rule = "a step must be a mapping such as {move: 200 mm, time: 0.5 s} or {dwell: 0.3 s}"
        raise InputError(path, rule, raw)
    for key in raw:
        if key not in VALID_KEYS:
            raise InputError(f"{path}.{key}", f"unknown key; valid keys: {', '.join(VALID_KEYS)}", raw[key])
    is_move = "move" in raw or "speed" in raw
    if is_move and "dwell" in raw:
        raise InputError(path, "a step is either a move (move or speed) or a dwell, not both", dict(raw))
    if not is_move and "dwell" not in raw:
        raise InputError(path, "a step needs move (or speed) or dwell", dict(raw))
    p = _StepParser(raw, path, motion)
    if "dwell" in raw:
        return _parse_dwell(p, index, t0, x0)
    if "law" in raw:
        return _parse_cam(p, index, t0, x0, move)
    if any(k in raw for k in ("max_speed", "max_accel", "max_jerk")):
        return _parse_optimal(p, index, t0, x0, move)
    return _parse_timed(p, index, t0, x0, move)


def _place(parsed: Sequence[_Parsed]) -> tuple[list[Segment], list[Phase]]:
    """Segments of every step in time order; consecutive pieces of a kind merge into a phase."""
    segments: list[Segment] = []
    phases: list[Phase] = []
    for step, pieces in parsed:
        for piece in pieces:
            if not piece.t1 > piece.t0:
                continue  # a piece too short to register in absolute time
            if not phases or phases[-1].step != step.index or phases[-1].kind != piece.kind:
                phases.append(Phase(piece.kind, piece.t0, piece.t1, step.index, step.move_index))
            else:
                phases[-1] = phases[-1]._replace(t1=piece.t1)
            phase = len(phases) - 1
            segments.append(Segment(piece.t0, piece.t1, piece.coeffs, step.index, phase, piece.span, piece.sine))
    return segments, phases


MAX_PROFILE_STEPS = 1_000
"""Moves and dwells one profile may hold (the axis file and the web API): sizing stays interactive."""
MAX_SAMPLES = 500_000
"""Samples one cycle may be cut into (points per phase x segments): a catalog selection holds a few
kB per sample, so this bounds it near 1 GB."""


def parse_profile(raw: Any, motion: Motion, field: str = "profile") -> Cycle:
    """Parse the axis file's ``profile:`` list into a ``Cycle`` (see the module docstring).

    Raises ``InputError`` naming the step and field (``profile[2].accel``) for any impossible or
    malformed request.
    """
    if motion not in _QUANTITY:
        raise InputError("motion", "must be linear or rotary", motion)
    if not isinstance(raw, Sequence) or isinstance(raw, (str, bytes)):
        raise InputError(field, "must be a list of moves and dwells", raw)
    if len(raw) == 0:
        raise InputError(field, "the cycle is empty: list at least one move or dwell", has_value=False)
    if len(raw) > MAX_PROFILE_STEPS:
        raise InputError(field, f"has {len(raw)} moves and dwells; at most {MAX_PROFILE_STEPS} are accepted "
                         "(a cycle that long is better split into the axis's typical cycles)", has_value=False)
    parsed: list[_Parsed] = []
    t0 = x0 = 0.0
    moves = 0
    for i, item in enumerate(raw):
        result = _parse_step(item, f"{field}[{i}]", motion, i, t0, x0, moves)
        parsed.append(result)
        t0 = result.step.t1
        x0 = x0 + result.step.distance
        moves += result.step.kind == "move"
    segments, phases = _place(parsed)
    return Cycle(t0, motion, tuple(r.step for r in parsed), tuple(segments), tuple(phases))


# --------------------------------------------------------------------------- arbitrary states: ruckig


@dataclass(frozen=True)
class FreeMove:
    """A jerk-limited time-optimal move between arbitrary states, planned by ruckig.

    ``duration`` [s]; ``segments`` the exact constant-jerk pieces of ruckig's profile (its brake
    pieces first, when the start state exceeds the limits); ``evaluate(t)`` samples them.
    """

    duration: float
    segments: tuple[Segment, ...]

    def evaluate(self, t: npt.ArrayLike) -> Kinematics:
        """x, v, a, j at times ``t`` in [0, duration] [s]."""
        tab = _PieceTable(self.segments)
        tt = np.asarray(t, dtype=float)
        return tab.evaluate_in(tab.locate(tt), tt)


def ruckig_move(
    x0: float, v0: float, a0: float, x1: float, v1: float, a1: float, vmax: float, amax: float, jmax: float
) -> FreeMove:
    """Time-optimal move from state (x0, v0, a0) to (x1, v1, a1) under symmetric limits, by ruckig.

    Units: m (or rad), m/s, m/s^2, m/s^3; ``jmax = inf`` for acceleration-limited moves. Uses
    the ``ruckig`` library (L. Berscheid, T. Kroeger, "Jerk-limited real-time trajectory
    generation with arbitrary target states", RSS 2021), imported here only when needed.
    Raises ``InputError`` for bad limits or a target ruckig cannot reach.
    """
    from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory

    for name, value in (("vmax", vmax), ("amax", amax), ("jmax", jmax)):
        if not value > 0.0 or (name != "jmax" and not math.isfinite(value)):
            raise InputError(name, "must be positive" + (" and finite" if name != "jmax" else ""), value)
    for name, value in (("x0", x0), ("v0", v0), ("a0", a0), ("x1", x1), ("v1", v1), ("a1", a1)):
        if not math.isfinite(value):
            raise InputError(name, "must be finite", value)
    if abs(v1) > vmax or abs(a1) > amax:
        raise InputError("v1" if abs(v1) > vmax else "a1", "the target state must lie within the limits",
                         v1 if abs(v1) > vmax else a1)
    inp = InputParameter(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [x0], [v0], [a0]
    inp.target_position, inp.target_velocity, inp.target_acceleration = [x1], [v1], [a1]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [vmax], [amax], [jmax]
    otg, traj = Ruckig(1), Trajectory(1)
    try:
        result = otg.calculate(inp, traj)
    except RuckigError as exc:
        raise InputError("x1", f"ruckig cannot reach the target state ({str(exc).strip()})", x1) from None
    if result != Result.Working:
        raise InputError("x1", f"ruckig could not plan the move ({result})", x1)
    return FreeMove(traj.duration, tuple(_ruckig_segments(traj.profiles[0][0])))


def _ruckig_segments(prof: Any) -> list[Segment]:
    """Constant-jerk pieces of a ruckig profile: p, v, a hold each piece's start state (for
    infinite jerk, ``a`` holds each piece's constant acceleration and ``j`` is 0)."""
    pieces: list[tuple[float, float, float, float, float]] = []
    brake = prof.brake
    if brake.duration > 0.0:
        pieces += [(brake.t[k], brake.p[k], brake.v[k], brake.a[k], brake.j[k]) for k in range(2)]
    pieces += [(prof.t[k], prof.p[k], prof.v[k], prof.a[k], prof.j[k]) for k in range(7)]
    segments: list[Segment] = []
    t = 0.0
    for dt, x, v, a, j in pieces:
        if dt > 0.0:
            segments.append(Segment(t, t + dt, _poly(x, v, a, j), 0, 0, dt))
            t += dt
    if not segments:  # already at the target
        segments.append(Segment(0.0, 0.0, _poly(prof.p[7], prof.v[7], prof.a[7], 0.0), 0, 0, 0.0))
    return segments
