"""Moments of inertia of bodies [kg m^2]: point mass, cylinders, blocks, parallel axis, composites.

Source: lecture, "Mass and Moment of Inertia", "Parallel-Axis Theorem" and the cylinder pages.
ERRATA: the hollow cylinder is J = M (D_o^2 + D_i^2) / 8 (the roll page's minus sign is a slip);
the density form pi rho L (D_o^4 - D_i^4) / 32 is right.
"""

from __future__ import annotations

import math
from collections.abc import Iterable


def point_mass(mass: float, radius: float) -> float:
    """J = m r^2 [kg m^2] of a point mass ``mass`` [kg] at ``radius`` [m] (lecture, I = m r^2).

    >>> point_mass(2.0, 0.5)
    0.5
    """
    return mass * radius**2


def solid_cylinder(mass: float, diameter: float) -> float:
    """J = M D^2 / 8 [kg m^2] of a solid cylinder about its axis (lecture, solid cylinder).

    ``mass`` [kg], ``diameter`` [m].
    """
    return mass * diameter**2 / 8.0


def hollow_cylinder(mass: float, outer_diameter: float, inner_diameter: float) -> float:
    """J = M (D_o^2 + D_i^2) / 8 [kg m^2] of a hollow cylinder (lecture; ERRATA fixes the sign).

    ``mass`` [kg], diameters [m].
    """
    return mass * (outer_diameter**2 + inner_diameter**2) / 8.0


def cylinder_mass(density: float, length: float, outer_diameter: float, inner_diameter: float = 0.0) -> float:
    """M = rho pi (D_o^2 - D_i^2) L / 4 [kg] (lecture, Volume = pi/4 (D_o^2 - D_i^2) L)."""
    return density * math.pi * (outer_diameter**2 - inner_diameter**2) * length / 4.0


def cylinder_from_density(density: float, length: float, outer_diameter: float,
                          inner_diameter: float = 0.0) -> float:
    """J = pi rho L (D_o^4 - D_i^4) / 32 [kg m^2] (lecture, roll and ball screw pages).

    ``density`` [kg/m^3], ``length`` [m], diameters [m]. Yaskawa's J_B = pi rho L_B D_B^4 / 32.

    >>> round(cylinder_from_density(7870.0, 1.4, 0.04), 8)  # Yaskawa Sigma-II: J_B = 0.00277
    0.00276913
    """
    return math.pi * density * length * (outer_diameter**4 - inner_diameter**4) / 32.0


def rectangular_block(mass: float, height: float, width: float) -> float:
    """J = M (h^2 + w^2) / 12 [kg m^2] of a block about its centroidal axis along its length (lecture)."""
    return mass * (height**2 + width**2) / 12.0


def parallel_axis(inertia_cm: float, mass: float, distance: float) -> float:
    """J = J_cm + m d^2 [kg m^2] (lecture, Parallel-Axis Theorem)."""
    return inertia_cm + mass * distance**2


def composite(inertias: Iterable[float]) -> float:
    """Sum of inertias about the same axis [kg m^2] (lecture: I = sum m_i r_i^2)."""
    return float(sum(inertias))


def linear_mass_reflected(mass: float, lever: float) -> float:
    """J = M r^2 [kg m^2] of a mass moving at r per rad of the shaft (lecture: J_eqv = M / (2 pi p)^2).

    ``lever`` [m/rad] is lead / (2 pi) for a screw or the radius for a pulley or pinion.
    """
    return mass * lever**2


def steel_screw_imperial(length_in: float, diameter_in: float) -> float:
    """Lecture's J_S = 0.0012 L D^4 for a steel screw [oz in s^2], L and D in inches.

    ERRATA: the unit is oz-in-s^2, from pi rho / (32 g) with rho = 0.28 lb/in^3 and g = 386
    in/s^2, times 16 oz/lb: pi * 0.28 * 16 / (32 * 386) = 0.001139, which the notes round to 0.0012.
    """
    return 0.0012 * length_in * diameter_in**4
