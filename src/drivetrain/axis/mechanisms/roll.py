"""Roll / feed roll: material fed at the roll's surface speed, pressed by a nip force.

Lecture, "Roll Load" (Yaskawa page): T_L = (mu P + F) D / (2 R eta), J_L = J_G + J_R / R^2,
J_R = M D^2 / 8 = pi rho L D^4 / 32 (hollow: M (D_o^2 + D_i^2) / 8, ERRATA), N_M = R V_l / (pi D).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from drivetrain.fields import (
    BackEfficiency,
    Coefficient,
    Density,
    Efficiency,
    Force,
    ForceNonNeg,
    Inertia,
    Length,
    LengthNonNeg,
    MassNonNeg,
    Spec,
)
from drivetrain.physics.inertia import linear_mass_reflected
from drivetrain.physics.mechanisms.base import LinearLoad, Mechanism, part_inertia
from drivetrain.physics.stage import Stage


class RollLoadSpec(Spec):
    """``load:`` of a roll: nip (pressing) force, friction at the nip, web tension, fed mass."""

    press_force: ForceNonNeg = 0.0
    friction: Coefficient = 0.0
    static_friction: Coefficient | None = None
    tension: Force = 0.0
    mass: MassNonNeg = 0.0


class RollSpec(Spec):
    """``mechanism: {type: roll, diameter: ..., length: ..., material: steel, load: {...}}``."""

    type: Literal["roll"]
    diameter: Length
    bore: LengthNonNeg = 0.0
    length: LengthNonNeg | None = None
    mass: MassNonNeg | None = None
    density: Density | None = None
    material: str | None = None
    inertia: Inertia | None = None
    rolls: int = Field(default=1, ge=1, le=100)
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: RollLoadSpec = RollLoadSpec()

    def build(self, g: float) -> Mechanism:
        """Roll inertia (times the number of driven rolls) outside the losses; fed mass inside."""
        r = self.diameter / 2.0
        j_roll = self.rolls * part_inertia(self.inertia, self.mass, self.diameter, self.bore, self.length,
                                           self.density, self.material, "mechanism")
        mu_st = self.load.friction if self.load.static_friction is None else self.load.static_friction
        # The nip force is the normal force on the material: friction mu P (lecture's T_L); the
        # fed mass (if any) lies flat, its weight adding to the normal force. The web tension pulls one
        # way whatever the roll's direction: a signed force.
        load = LinearLoad(mass=self.load.mass, friction=self.load.friction, static_friction=mu_st,
                          thrust=self.load.tension, press_force=self.load.press_force, thrust_mode="signed")
        j_load = linear_mass_reflected(load.moving_mass, r)
        stage = Stage(name="roll", kind="roll", ratio=1.0 / r, inertia_in=j_roll, inertia_inside=j_load,
                      efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="roll", motion="linear", stage=stage, load=load,
                         inertia_parts={"roll": j_roll, "fed material M r^2": j_load})
