"""The ``requirements:`` block of the axis file: how the axis must move, judged by simulation.

Keys (docs/axis-file.md, "Dynamic requirements"), all optional::

    requirements:
      settling: {window: 10 um, time: 20 ms}   # at the load, after each stop (rotary load: an angle)
      following_error: 0.5 mm                  # largest load position error during a move
      velocity_bandwidth: 40 Hz                # smallest velocity-loop bandwidth (-3 dB)
      stability: {phase_margin: 30 deg, gain_margin: 6 dB}
      loop: {current_bandwidth: 2000 Hz, loop_delay: 125 us, encoder_counts: 1048576,
             feedforward: true, notch: true}
      candidates: 20                           # static passes judged dynamically, best first
      settling_ratio: false                    # also scan the answer's ratio for the fastest settling

The block loads into the SI dataclass ``Requirements``. Absent, the selection is the static one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any

from pydantic import Field

from drivetrain.errors import InputError
from drivetrain.fields import Spec, quantity
from drivetrain.units import parse

Frequency = Annotated[float, quantity("frequency", gt=0.0, le=1e5)]
TimePos = Annotated[float, quantity("time", gt=0.0, le=3600.0)]
Degrees = Annotated[float, quantity("angle", gt=0.0, lt=math.pi)]

DEFAULT_WINDOW_LINEAR = 10e-6
"""[m] the settling window at a linear load when none is stated (docs/axis-file.md)."""
DEFAULT_WINDOW_ROTARY = math.radians(1.0 / 60.0)
"""[rad] the settling window at a rotary load when none is stated: one arcminute."""
MIN_PHASE_MARGIN_DEG = 30.0
MIN_GAIN_MARGIN_DB = 6.0
"""Default stability margins: phase >= 30 deg, gain >= 6 dB (Franklin, Powell, Emami-Naeini, *Feedback
Control of Dynamic Systems*, 7th ed. (2015), §6.4 "Stability margins"; Ellis, *Control System Design
Guide*, 4th ed. (2012), ch. 3, "Tuning a control system": PM 30-60 deg, GM 6-20 dB)."""
MAX_CANDIDATES = 200


class SettlingSpec(Spec):
    """``requirements.settling``: the position window at the load and the time to reach it."""

    window: str | float | None = None
    time: TimePos | None = None


class StabilitySpec(Spec):
    """``requirements.stability``: smallest phase and gain margins of the velocity loop."""

    phase_margin: Degrees = math.radians(MIN_PHASE_MARGIN_DEG)
    gain_margin: str | float = f"{MIN_GAIN_MARGIN_DB:g} dB"


class LoopContextSpec(Spec):
    """``requirements.loop``: the drive's loop where it differs from the defaults."""

    current_bandwidth: Frequency = 2000.0
    loop_delay: TimePos = 125e-6
    encoder_counts: int = Field(default=1 << 20, ge=16, le=1 << 40)
    feedforward: bool = True
    notch: bool = True


class RequirementsSpec(Spec):
    """``requirements:``: what the axis must do dynamically."""

    settling: SettlingSpec | None = None
    following_error: str | float | None = None
    velocity_bandwidth: Frequency | None = None
    stability: StabilitySpec = StabilitySpec()
    loop: LoopContextSpec = LoopContextSpec()
    candidates: int = Field(default=20, ge=1, le=MAX_CANDIDATES)
    settling_ratio: bool = False


@dataclass(frozen=True)
class Requirements:
    """The dynamic requirements in SI, at the load: [m] for a linear load, [rad] for a rotary one.

    Attributes:
        motion: "linear" or "rotary" (the load's; units of the windows and errors).
        settling_window: position window at the load after a stop [m or rad].
        settling_time: longest time from the end of a move into the window [s] (None: not stated).
        following_error: largest load position error during a move [m or rad] (None: not stated).
        velocity_bandwidth: smallest -3 dB bandwidth of the velocity loop [Hz] (None: not stated).
        phase_margin_deg, gain_margin_db: smallest velocity-loop margins [deg], [dB].
        current_bandwidth: the current loop's bandwidth [Hz].
        loop_delay: the velocity loop's sample time [s] (the drive's loop delay).
        encoder_counts: counts per motor revolution [-].
        feedforward: velocity and acceleration feed-forward on.
        notch: a notch filter on the first resonance is allowed.
        candidates: how many static passes are judged, best first [-].
        settling_ratio: scan the answer's ratio for the shortest settling (``settling_ratio``).
    """

    motion: str
    settling_window: float
    settling_time: float | None
    following_error: float | None
    velocity_bandwidth: float | None
    phase_margin_deg: float
    gain_margin_db: float
    current_bandwidth: float
    loop_delay: float
    encoder_counts: int
    feedforward: bool
    notch: bool
    candidates: int
    settling_ratio: bool = False

    @property
    def stated(self) -> tuple[str, ...]:
        """The checks the block asks for (stability always, once the block is given)."""
        names = []
        if self.settling_time is not None:
            names.append("settling_time")
        if self.following_error is not None:
            names.append("following_error")
        if self.velocity_bandwidth is not None:
            names.append("velocity_bandwidth")
        return (*names, "stability_margin")


def _position(value: Any, motion: str, field: str) -> float:
    x = parse(value, "length" if motion == "linear" else "angle", field, allow_zero=False)
    if not (math.isfinite(x) and x > 0.0):
        raise InputError(field, "must be a position tolerance > 0 at the load", value)
    if (motion == "linear" and x > 1.0) or (motion == "rotary" and x > math.pi):
        raise InputError(field, "is implausibly large for a position tolerance at the load "
                         "(at most 1 m or 180 deg)", value)
    return x


def settling_window(spec: RequirementsSpec | None, motion: str) -> float:
    """The settling window at the load [m or rad]: ``requirements.settling.window``, else the default
    (10 um for a linear load, one arcminute for a rotary one)."""
    window = None if spec is None or spec.settling is None else spec.settling.window
    if window is None:
        return DEFAULT_WINDOW_LINEAR if motion == "linear" else DEFAULT_WINDOW_ROTARY
    return _position(window, motion, "requirements.settling.window")


def requirements(spec: RequirementsSpec | None, motion: str) -> Requirements | None:
    """The SI requirements of ``spec`` for a load moving ``motion`` ("linear" or "rotary"); None if absent."""
    if spec is None:
        return None
    settling = spec.settling or SettlingSpec()
    window = settling_window(spec, motion)
    follow = None if spec.following_error is None else _position(spec.following_error, motion,
                                                                  "requirements.following_error")
    gm = spec.stability.gain_margin
    gm_db = _decibels(gm, "requirements.stability.gain_margin")
    return Requirements(
        motion=motion, settling_window=window, settling_time=settling.time, following_error=follow,
        velocity_bandwidth=spec.velocity_bandwidth, phase_margin_deg=math.degrees(spec.stability.phase_margin),
        gain_margin_db=gm_db, current_bandwidth=spec.loop.current_bandwidth, loop_delay=spec.loop.loop_delay,
        encoder_counts=spec.loop.encoder_counts, feedforward=spec.loop.feedforward, notch=spec.loop.notch,
        candidates=spec.candidates, settling_ratio=spec.settling_ratio)


def _decibels(value: str | float, field: str) -> float:
    """A gain margin in dB: '6 dB', or a bare number taken as dB."""
    text = str(value).strip()
    if text.lower().endswith("db"):
        text = text[:-2].strip()
    try:
        x = float(text)
    except ValueError:
        raise InputError(field, "must be a gain margin in dB, e.g. '6 dB'", value) from None
    if not (math.isfinite(x) and 0.0 < x <= 60.0):
        raise InputError(field, "must be between 0 and 60 dB", value)
    return x
