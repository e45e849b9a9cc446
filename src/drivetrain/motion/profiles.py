"""Motion profiles: moves and dwells in a repeating cycle, their exact segments and sampling.

A profile is a list of steps, run in order; the cycle repeats. A step is a move or a dwell
(the axis file's ``profile:`` key, docs/axis-file.md)::

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

Guarantees (tested on seeded random moves in ``tests/motion/test_profiles_random.py``):

- every move ends at its target, start + distance, within 1e-9 relative (in practice a few ulp);
- every move starts and ends at rest: speed zero within 1e-12 of its peak, and acceleration as
  well for jerk-limited shapes (s-curves, time-optimal with ``max_jerk``, cam laws);
- sampled |v|, |a|, |j| never exceed the step's ``peak_speed``, ``peak_accel``/``peak_decel``,
  ``peak_jerk`` by more than 1e-12 relative, and a time-optimal move never exceeds its limits;
- no NaN for any accepted input; impossible requests raise ``InputError`` naming the field;
- ``time_optimal_duration`` equals ruckig's duration within 1e-9 s (seeded comparison).

The module parses; the exact form and its sampling are in ``cycle.py`` and the closed forms of one
move (peaks, time-optimal) in ``moves.py``.

Sources: the lecture (trapezoidal profile: trapezoid ``v_max = x_f / t_2``, ``a_max = x_f /
(t_1 t_2)``; movement amount ``L_s = V (2 t_s - t_a - t_d) / 2``); cam laws in ``cams.py``
(Norton); jerk-limited time-optimal rest-to-rest moves: L. Biagiotti, C. Melchiorri,
*Trajectory Planning for Automatic Machines and Robots*, Springer (2008), sec. 3.4 (double S).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple

import numpy as np
import numpy.typing as npt

from drivetrain import units
from drivetrain.errors import InputError
from drivetrain.motion.cams import CAM_LAWS, DEGREE, cam_law
from drivetrain.motion.cycle import (
    Cycle,
    Kinematics,
    Motion,
    Phase,
    PhaseKind,
    Segment,
    Step,
    _PieceTable,
)
from drivetrain.motion.moves import (
    movement_amount,
    s_curve_jerk_time,
    s_curve_peak_accel,
    time_optimal_parameters,
    trapezoid_peak_speed,
)

FloatArray = npt.NDArray[np.float64]

SHAPES: tuple[str, ...] = ("trapezoid", "triangle", "s_curve")
HOLDING: tuple[str, ...] = ("motor", "brake")
DEFAULT_JERK_FRACTION = 1.0
"""``shape: s_curve`` without ``jerk_fraction`` or ``jerk`` is the pure s-curve."""

_N_COEF = DEGREE + 1
_MIN_JERK_FRACTION = 1e-9
"""Jerk fractions below this are taken as 0 (a trapezoid)."""


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


__all__ = ["DEFAULT_JERK_FRACTION", "HOLDING", "MAX_PROFILE_STEPS", "SHAPES", "VALID_KEYS", "FreeMove", "parse_profile",
           "ruckig_move"]
