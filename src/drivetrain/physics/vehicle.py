"""Vehicle reduction ratios from tyre size, top speed and motor speed.

Lecture, electric-vehicle transmission: a single reduction chosen so that the motor's maximum
speed gives the target top speed: tyre 245/45-17 (diameter 65.2297 cm), 160 km/h, 9000 rpm
-> 1301.29 wheel rpm -> ratio 6.9162.
"""

from __future__ import annotations

import math
import re

from drivetrain.errors import InputError

_TYRE = re.compile(r"^\s*(\d{3})\s*/\s*(\d{2,3})\s*(?:[-R ]|ZR|R)\s*(\d{2}(?:\.\d)?)\s*$", re.IGNORECASE)


def tyre_diameter(code: str, field: str = "tyre") -> float:
    """Outer diameter of a tyre from its ISO size code, e.g. ``245/45-17`` or ``245/45R17`` [m].

    D = rim diameter (inches x 25.4 mm) + 2 x width [mm] x aspect ratio / 100.
    245/45-17: 431.8 + 220.5 = 652.3 mm (lecture: 65.2297 cm).
    """
    m = _TYRE.match(code)
    if not m:
        raise InputError(field, "must be a tyre size code like 245/45-17 or 245/45R17", code)
    width_mm, aspect, rim_in = float(m.group(1)), float(m.group(2)), float(m.group(3))
    return (rim_in * 25.4 + 2.0 * width_mm * aspect / 100.0) / 1000.0


def wheel_speed(vehicle_speed: float, diameter: float) -> float:
    """Wheel speed [rad/s] at ``vehicle_speed`` [m/s] for a wheel of ``diameter`` [m]: omega = v / r."""
    return vehicle_speed / (diameter / 2.0)


def reduction_ratio(motor_speed: float, vehicle_speed: float, diameter: float) -> float:
    """Single-reduction ratio i = omega_motor / omega_wheel [-] (lecture, EV example: 6.9162).

    ``motor_speed`` [rad/s] at ``vehicle_speed`` [m/s], wheel ``diameter`` [m].
    """
    return motor_speed / wheel_speed(vehicle_speed, diameter)


def top_speed(motor_speed: float, ratio: float, diameter: float) -> float:
    """Vehicle speed [m/s] at ``motor_speed`` [rad/s] through ``ratio`` on a wheel of ``diameter`` [m]."""
    return motor_speed / ratio * diameter / 2.0


def rollout(diameter: float, ratio: float) -> float:
    """Travel per motor revolution [m] = pi D / i (RC 'rollout')."""
    return math.pi * diameter / ratio
