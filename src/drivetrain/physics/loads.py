"""Force and torque models at the load, vectorised over time samples.

Source: lecture, "The causes for the motor load" (gravity, dry friction with sticktion and
slip coefficients, viscous, turbulent sigma*omega^2, springs), "Centrifugal force", the
inclined-plane pages (F_N = m g cos(alpha), F_G = m g sin(alpha), a_max < mu_0 g cos(alpha))
and ERRATA (gravity is not scaled by mu; a counterweight adds inertia but no guide friction).
Forces in [N], torques in [N m], speeds in [m/s] or [rad/s].
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

G_STANDARD = 9.80665
"""Standard gravity [m/s^2] (the axis file's default; vendor examples use 9.8)."""

Array = NDArray[np.float64]


def gravity_force(mass: float, incline: float, g: float = G_STANDARD) -> float:
    """F_G = m g sin(alpha) [N]: the weight component along an incline.

    ``mass`` [kg] (net of a counterweight if any), ``incline`` [rad] above horizontal
    (lecture, inclined plane: F_F = F_G sin(alpha)). Positive resists upward motion.
    """
    return mass * g * math.sin(incline)


def normal_force(mass: float, incline: float, g: float = G_STANDARD) -> float:
    """F_N = m g cos(alpha) [N] (lecture, inclined plane)."""
    return mass * g * math.cos(incline)


def coulomb_friction(normal: float, mu_sliding: float, mu_static: float, speed: ArrayLike,
                     direction: ArrayLike, breakaway: ArrayLike | None = None) -> Array:
    """Dry (Coulomb) friction force opposing motion [N], with sticktion at breakaway.

    F = mu_sl F_N sign(v) while moving, and at zero speed inside a move (the limit from the moving
    side: the start and the arrival at rest) mu_sl F_N in the move's ``direction``; zero in a dwell
    (``direction`` 0: friction holds nothing, the safe side). Breakaway mu_st F_N in the move's
    direction acts only where motion starts: at the samples marked ``breakaway`` (the profile's
    zero-weight sample at the start of each move). Without a mask (``None``) every zero-speed sample
    inside a move is taken as a start (a standstill query, e.g. the breakaway torque of the dynamics).
    Lecture, "Friction (dry)": F = mu M g, with separate sticktion mu_st and slip mu_sl.
    """
    v = np.asarray(speed, dtype=float)
    d = np.sign(np.asarray(direction, dtype=float))
    # a sign (-1, 0, 1) times mu F_N: the same floats as (sign mu) F_N, in fewer passes
    sliding = np.sign(np.where(v != 0.0, v, d)) * (mu_sliding * normal)
    start = (v == 0.0) if breakaway is None else np.asarray(breakaway, dtype=bool)
    if not start.any():
        return sliding
    return np.asarray(np.where(start, d * (mu_static * normal), sliding), dtype=float)


ThrustMode = Literal["against_motion", "signed"]
THRUST_MODES: tuple[str, ...] = ("against_motion", "signed")


def process_thrust(thrust: ArrayLike, direction: ArrayLike, mode: ThrustMode = "against_motion") -> Array:
    """The process force (or torque) acting on the load over the samples [N or N m], positive resisting
    positive motion; zero in a dwell (``direction`` 0): a process force belongs to the moves.

    ``against_motion`` (default): F = F_thrust sign(direction), the thrust resists the motion in all four
    quadrants, as the ServoSoft quadrant pages of the lecture write it (+T_Thrust in quadrants 1 and 2,
    -T_Thrust in quadrants 3 and 4; also the belt, screw and conveyor pages). ``signed``: an external force
    of fixed direction (a constant push, a web tension) that keeps its sign on the return move.
    """
    t = np.asarray(thrust, dtype=float)
    d = np.sign(np.asarray(direction, dtype=float))
    if mode == "signed":
        return np.asarray(np.where(d == 0.0, 0.0, t), dtype=float)
    return np.asarray(t * d, dtype=float)


def viscous(coefficient: float, speed: ArrayLike) -> Array:
    """F = B v [N] or T = B omega [N m] (lecture, "Friction (viscous)", mass-spring-damper F_y = B v)."""
    return coefficient * np.asarray(speed, dtype=float)


def turbulent(sigma: float, omega: ArrayLike) -> Array:
    """T = sigma omega |omega| [N m]: fan and pump loss, the lecture's T_y = sigma omega^2 with its sign.

    ``sigma`` [N m s^2/rad^2], ``omega`` [rad/s].
    """
    w = np.asarray(omega, dtype=float)
    return sigma * w * np.abs(w)


def spring(stiffness: float, displacement: ArrayLike, preload: float = 0.0) -> Array:
    """F = K_x x + F_0 [N] (linear) or T = K_theta theta + T_0 [N m] (torsional); lecture, springs."""
    return stiffness * np.asarray(displacement, dtype=float) + preload


def slip_limit_acceleration(mu_static: float, incline: float, g: float = G_STANDARD) -> float:
    """Largest acceleration before a load slips on its carrier [m/s^2]: a_max < mu_0 g cos(alpha).

    Lecture, inclined plane: m a_max < mu_0 m g cos(alpha). With mu_0 = 0.1 and a small
    incline, a_max stays below about 1 m/s^2.

    >>> round(slip_limit_acceleration(0.1, 0.0, 9.81), 3)
    0.981
    """
    return mu_static * g * math.cos(incline)


def linear_load_force(
    *,
    mass: float,
    counterweight: float,
    incline: float,
    mu: float,
    mu_static: float,
    thrust: ArrayLike,
    speed: ArrayLike,
    position: ArrayLike,
    direction: ArrayLike,
    g: float = G_STANDARD,
    viscous_coefficient: float = 0.0,
    spring_rate: float = 0.0,
    spring_preload: float = 0.0,
    extra_normal: float = 0.0,
    thrust_mode: ThrustMode = "against_motion",
    breakaway: ArrayLike | None = None,
) -> Array:
    """External force on a linear load along its travel, positive resisting positive motion [N].

    F = (M - M_C) g sin(alpha) + F_fr + F_thrust + B v + K x, with the friction on the guides
    F_fr = mu (M g cos(alpha) + F_press) by the direction of motion (ERRATA: gravity is not scaled
    by mu; the counterweight hangs apart from the guides, so it adds inertia (M + M_C) but no
    friction). Thrust [N] is the process force the load pushes against, applied by ``thrust_mode``
    (``process_thrust``); ``breakaway`` marks where motion starts (``coulomb_friction``).
    Vectorised over samples.
    """
    normal = normal_force(mass, incline, g) + extra_normal
    f = gravity_force(mass - counterweight, incline, g) + process_thrust(thrust, direction, thrust_mode)
    f = f + coulomb_friction(normal, mu, mu_static, speed, direction, breakaway)
    if viscous_coefficient:
        f = f + viscous(viscous_coefficient, speed)
    if spring_rate or spring_preload:
        f = f + spring(spring_rate, position, spring_preload)
    return np.asarray(f, dtype=float)
