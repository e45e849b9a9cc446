"""Warnings for a physically absurd answer: a duty cycle far beyond what the load itself can explain.

The input rules (``drivetrain.fields.PLAUSIBLE``) refuse a bare number that reads as a slip of unit;
what slips past them (a profile distance in mm written bare, a process torque in N cm) shows in the
answer as a torque out of all scale with the load. These rules compare the motor-shaft demand with
the load's own scale and say so in the result (``warnings``); they never change a number.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.physics.mechanisms.base import LinearLoad, RotaryLoad
from drivetrain.units import to_rpm

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.duty.cycle import DutyCycle

LOAD_SCALE_FACTOR = 15.0
"""Largest plausible ratio of the load's peak demand to its own static scale [-].

Linear: the peak force on the load against its weight plus its process and press forces, i.e. an
acceleration of about 15 g; the fastest linear-motor pick-and-place axes stay below 10 g. Rotary: the
peak torque at the load against its weight at its rim plus its process and friction torques; for a disc
T / (m g R) = R alpha / (2 g), so 15 is a rim acceleration of about 30 g."""
MAX_MOTOR_TORQUE = 20_000.0
"""[N m] beyond the largest catalogued servo and direct-drive torque motors (a few thousand N m)."""
MAX_MOTOR_SPEED = 30_000.0 * 2.0 * math.pi / 60.0
"""[rad/s] 30,000 rpm: beyond servo motors (6,000 rpm typical) and most small DC motors."""
MAX_LINEAR_SPEED = 20.0
"""[m/s] beyond linear motors (about 10 m/s) and belt axes."""


def _fmt(x: float) -> str:
    return f"{x:,.0f}" if abs(x) >= 1000 else f"{x:.3g}"


def sanity_warnings(axis: Axis, duty: DutyCycle) -> list[str]:
    """Sentences naming each implausible figure of the duty cycle, with what it was compared to."""
    out: list[str] = []
    torque = np.abs(np.asarray(duty.torque, dtype=float))
    peak = float(torque.max()) if torque.size else 0.0
    hint = "check the units of the profile and the mechanism (a bare number is SI: m, kg, s, rad)"
    load = axis.mechanism.load
    # Motor-shaft torque T carries the load's force T * i_total (rad/m) or torque T * i_total.
    at_load = peak * axis.total_ratio
    g = axis.gravity
    if isinstance(load, LinearLoad):
        scale = (load.mass + load.counterweight) * g + abs(load.thrust) + load.press_force
        thrust = np.asarray(duty.samples.thrust, dtype=float)
        if np.isfinite(thrust).any():
            scale += float(np.nanmax(np.abs(thrust)))
        if scale > 0.0 and at_load > LOAD_SCALE_FACTOR * scale:
            out.append(f"the peak torque at the motor shaft, {_fmt(peak)} N*m, pushes the load with {_fmt(at_load)} N, "
                       f"{at_load / scale:.0f} times its weight and process forces ({_fmt(scale)} N): {hint}")
        v = float(np.max(np.abs(np.asarray(duty.samples.v, dtype=float)))) if duty.t.size else 0.0
        if v > MAX_LINEAR_SPEED:
            out.append(f"the load's peak speed is {v:.3g} m/s, beyond any servo axis ({MAX_LINEAR_SPEED:g} m/s): "
                       f"{hint}")
    elif isinstance(load, RotaryLoad):
        spec = axis.spec.mechanism
        radius = 0.5 * max(float(getattr(spec, "diameter", 0.0) or 0.0),
                           float(getattr(getattr(spec, "load", None), "diameter", 0.0) or 0.0))
        radius = max(radius, load.unbalance_radius)
        mass = float(getattr(spec, "mass", None) or 0.0) + float(getattr(getattr(spec, "load", None), "mass", 0.0))
        mass += load.unbalance_mass
        scale = mass * g * radius + abs(load.torque) + load.friction_torque
        thrust = np.asarray(duty.samples.thrust, dtype=float)
        if np.isfinite(thrust).any():
            scale += float(np.nanmax(np.abs(thrust)))
        if scale > 0.0 and mass * radius > 0.0 and at_load > LOAD_SCALE_FACTOR * scale:
            out.append(f"the peak torque at the motor shaft, {_fmt(peak)} N*m, turns the load with "
                       f"{_fmt(at_load)} N*m, {at_load / scale:.0f} times its weight at its rim and its process "
                       f"torques ({_fmt(scale)} N*m): {hint}")
    if peak > MAX_MOTOR_TORQUE:
        out.append(f"the peak torque at the motor shaft is {_fmt(peak)} N*m, beyond any servo or torque motor "
                   f"({_fmt(MAX_MOTOR_TORQUE)} N*m): {hint}")
    w = float(np.max(np.abs(duty.omega))) if duty.omega.size else 0.0
    if w > MAX_MOTOR_SPEED:
        out.append(f"the motor speed reaches {_fmt(to_rpm(w))} rpm, beyond servo motors "
                   f"({_fmt(to_rpm(MAX_MOTOR_SPEED))} rpm): {hint}")
    return out
