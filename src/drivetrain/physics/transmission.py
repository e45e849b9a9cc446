"""Transmission elements between the motor and the mechanism: their ratios and default efficiencies.

Each element becomes a ``Stage`` (ratio = input speed / output speed; its own inertia on the
motor side of its losses; downstream inertia reflected J / i^2). Lecture: "Gear system-motor
connections" (T_1 = T_2 / n, J_2' = J_2 / n^2), belt-pulley (Ratio = D_L / D_m), gears
(Ratio = N_teeth(load) / N_teeth(motor)), harmonic drive (GR = FS / (CS - FS)), worm (50-80 %
efficiency, self-locking at high ratio), chains (about 80 % efficiency).

The axis file's transmission entries, which build these stages, are ``drivetrain.axis.transmission``.
"""

from __future__ import annotations

from typing import Any

from drivetrain.errors import InputError

GEARBOX_EFFICIENCY: dict[str, float] = {
    "spur": 0.98,
    "helical": 0.98,
    "bevel": 0.96,
    "planetary": 0.97,
    "worm": 0.65,
    "harmonic": 0.80,
    "cycloidal": 0.90,
}
"""Default efficiency per gearbox kind and stage [-], overridable in the axis file.

worm 0.65: middle of the lecture's 50-80 % range (Worm Gears). planetary 0.97 per stage: the
one-stage catalog value of the shipped planetary gearboxes (G+ GPB/GPD drawings; 0.94 for two
stages). spur and helical 0.98, bevel 0.96: common handbook figures for one mesh. harmonic 0.80
and cycloidal 0.90: mid-range of strain-wave and cycloidal catalog ratings at rated load. Set
the datasheet value of the real part whenever it is known.
"""

CHAIN_EFFICIENCY = 0.80
"""Chain drive efficiency [-]: lecture, belt-pulley systems: chains, "approximately 80%"."""

GEAR_PAIR_EFFICIENCY = 0.98
BELT_EFFICIENCY = 0.95
"""Default belt-stage efficiency [-]: timing belts are typically rated 0.94-0.98 by belt vendors."""


def harmonic_ratio(flexspline_teeth: int, circular_spline_teeth: int) -> float:
    """Harmonic drive ratio GR = FS / (CS - FS) [-] (lecture, harmonic drive; circular spline fixed).

    >>> harmonic_ratio(200, 202)
    100.0
    """
    if circular_spline_teeth <= flexspline_teeth:
        raise InputError("circular_spline_teeth", f"must exceed the flexspline teeth {flexspline_teeth}",
                         circular_spline_teeth)
    return flexspline_teeth / (circular_spline_teeth - flexspline_teeth)


def teeth_ratio(drive_teeth: int, driven_teeth: int) -> float:
    """Ratio = N_teeth(load) / N_teeth(motor) [-] (lecture, gear and belt-pulley ratio)."""
    return driven_teeth / drive_teeth


def compliance_at_input(stiffness: float | None, damping: float, backlash: float, ratio: float) -> dict[str, Any]:
    """Output-side stiffness [N m/rad], damping [N m s/rad] and backlash [rad] seen at the input of a
    stage of ``ratio`` [-]: K / i^2, B / i^2, play * i (docs/conventions.md: downstream stiffness and
    viscous damping reflect like inertia, lecture "Energy Equivalence Principle"; an angle at the
    output is i times that angle at the input). Keys as ``Stage`` names them; ``stiffness`` None: rigid.
    """
    return {
        "stiffness": None if stiffness is None else stiffness / ratio**2,
        "damping": damping / ratio**2,
        "backlash": backlash * ratio,
    }
