"""What every mechanism shares: the load it moves and the shared protocol.

A mechanism turns load motion and force into speed and torque at its input shaft. It is a
``Stage`` (ratio = input angle per load travel, its own inertia outside its losses, the
load's inertia reflected inside them) plus an external-load model. Linear mechanisms use a
lever arm r [m/rad]: lead / (2 pi) for a screw, the pulley, pinion, roll or drum radius
otherwise (docs/conventions.md, Linear mechanisms). Rotary mechanisms have r = 1 rad/rad.

These are the SI objects the formulas work on; the axis file's ``mechanism:`` entries that build
them are ``drivetrain.axis.mechanisms``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.physics.loads import (
    ThrustMode,
    coulomb_friction,
    linear_load_force,
    process_thrust,
    spring,
    turbulent,
    viscous,
)
from drivetrain.physics.stage import Stage

Array = NDArray[np.float64]
Motion = Literal["linear", "rotary"]


@dataclass(frozen=True)
class LinearLoad:
    """A load moving in a straight line (SI). See ``loads.linear_load_force``."""

    mass: float
    counterweight: float = 0.0
    incline: float = 0.0
    friction: float = 0.0
    static_friction: float = 0.0
    thrust: float = 0.0
    viscous: float = 0.0
    spring: float = 0.0
    spring_preload: float = 0.0
    press_force: float = 0.0
    thrust_mode: ThrustMode = "against_motion"

    @property
    def moving_mass(self) -> float:
        """Mass that accelerates with the load [kg]: M + M_C (ERRATA, vertical ball screw)."""
        return self.mass + self.counterweight

    def force(self, position: ArrayLike, speed: ArrayLike, direction: ArrayLike, thrust: ArrayLike | None,
              g: float, breakaway: ArrayLike | None = None) -> Array:
        """External force [N], positive resisting positive motion, vectorised over samples.

        ``thrust`` is the process force as written (None: the load's), applied by ``thrust_mode``;
        ``breakaway`` marks the samples where motion starts (``loads.coulomb_friction``).
        """
        f_thrust = self.thrust if thrust is None else thrust
        return linear_load_force(
            mass=self.mass, counterweight=self.counterweight, incline=self.incline, mu=self.friction,
            mu_static=self.static_friction, thrust=f_thrust, speed=speed, position=position,
            direction=direction, g=g, viscous_coefficient=self.viscous, spring_rate=self.spring,
            spring_preload=self.spring_preload, extra_normal=self.press_force, thrust_mode=self.thrust_mode,
            breakaway=breakaway,
        )


@dataclass(frozen=True)
class RotaryLoad:
    """A load turning about the mechanism's axis (SI).

    ``torque``: constant process torque [N m] (the ServoSoft T_Thrust); ``unbalance_mass`` [kg]
    at ``unbalance_radius`` [m] and angle ``unbalance_angle`` [rad] (beta) on a disc whose axis is
    inclined by ``incline`` [rad] (theta; 90 deg = disc in a vertical plane): the ServoSoft
    unbalanced-load term M g r sin(phi + beta) sin(theta).
    """

    inertia: float = 0.0
    torque: float = 0.0
    unbalance_mass: float = 0.0
    unbalance_radius: float = 0.0
    unbalance_angle: float = 0.0
    incline: float = 0.0
    friction_torque: float = 0.0
    static_friction_torque: float = 0.0
    viscous: float = 0.0
    turbulent: float = 0.0
    spring: float = 0.0
    thrust_mode: ThrustMode = "against_motion"

    def torque_at(self, angle: ArrayLike, omega: ArrayLike, direction: ArrayLike, thrust: ArrayLike | None,
                  g: float, breakaway: ArrayLike | None = None) -> Array:
        """External torque [N m], positive resisting positive rotation, vectorised over samples.

        The process torque (``thrust``, None: the load's ``torque``) acts by ``thrust_mode``
        (``loads.process_thrust``); ``breakaway`` marks where motion starts.
        """
        t_thrust = self.torque if thrust is None else thrust
        phi = np.asarray(angle, dtype=float)
        t = process_thrust(t_thrust, direction, self.thrust_mode) + self.unbalance_mass * g * self.unbalance_radius \
            * np.sin(phi + self.unbalance_angle) * math.sin(self.incline)
        t = t + coulomb_friction(1.0, self.friction_torque, self.static_friction_torque or self.friction_torque,
                                 omega, direction, breakaway)
        if self.viscous:
            t = t + viscous(self.viscous, omega)
        if self.turbulent:
            t = t + turbulent(self.turbulent, omega)
        if self.spring:
            t = t + spring(self.spring, phi)
        return np.asarray(t * np.ones_like(phi), dtype=float)


@dataclass(frozen=True)
class Mechanism:
    """A mechanism reduced to SI: its stage, its load and the breakdown of its inertia.

    ``stage.ratio`` is [rad/m] for a linear mechanism (1 / lever arm) and 1 for a rotary one.
    ``inertia_parts`` lists every contribution at the mechanism's input [kg m^2] for reports.
    ``slip_limit`` is the largest load acceleration before the load slips on its carrier
    [m/s^2] (conveyors), or None.
    """

    type: str
    motion: Motion
    stage: Stage
    load: LinearLoad | RotaryLoad
    inertia_parts: dict[str, float] = field(default_factory=dict)
    gravity_force: float = 0.0
    slip_limit: float | None = None

    @property
    def lever(self) -> float:
        """Load travel per input radian [m/rad] (or 1 for rotary)."""
        return 1.0 / self.stage.ratio

    def external_torque(self, position: ArrayLike, speed: ArrayLike, direction: ArrayLike,
                        thrust: ArrayLike | None, g: float, breakaway: ArrayLike | None = None) -> Array:
        """External load torque at the mechanism's input, before its losses [N m].

        ``position``, ``speed`` are the load's [m, m/s] or [rad, rad/s]. T = F r for a linear
        load (lecture: T = F / (2 pi p) for a screw, T = F r for a belt or pinion). ``breakaway``
        marks the samples where motion starts (static friction); None: every zero speed in a move.
        """
        if isinstance(self.load, LinearLoad):
            return self.load.force(position, speed, direction, thrust, g, breakaway) * self.lever
        return self.load.torque_at(position, speed, direction, thrust, g, breakaway)

    def holding_torque(self, g: float) -> float:
        """External torque at the input at standstill, gravity only [N m]."""
        return float(self.external_torque(np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), g)[0])


def part_inertia(inertia: float | None, mass: float | None, diameter: float, bore: float,
                 length: float | None, density: float | None, material: str | None, field: str) -> float:
    """Inertia of a cylindrical part from whichever description was given [kg m^2].

    Order: explicit inertia; mass with diameters (J = M (D_o^2 + D_i^2) / 8); density or
    material with length and diameters (J = pi rho L (D_o^4 - D_i^4) / 32); else 0.
    Lecture: solid and hollow cylinder pages (ERRATA: plus sign in the mass form).
    """
    from drivetrain.errors import InputError
    from drivetrain.physics import inertia as inertia_mod
    from drivetrain.physics.materials import density as density_of

    if inertia is not None:
        return inertia
    if bore and diameter and bore >= diameter:
        raise InputError(f"{field}.bore", f"must be smaller than the diameter {diameter:g} m", bore)
    if mass is not None:
        return inertia_mod.hollow_cylinder(mass, diameter, bore)
    if length is not None and diameter:
        rho = density if density is not None else density_of(material or "steel", f"{field}.material")
        return inertia_mod.cylinder_from_density(rho, length, diameter, bore)
    return 0.0


__all__ = ["Array", "LinearLoad", "Mechanism", "Motion", "RotaryLoad", "part_inertia"]
