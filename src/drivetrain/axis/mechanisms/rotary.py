"""Rotary table / disc, with an unbalanced mass at a radius and an inclined axis.

Lecture, "Disk Load" (Yaskawa page): N_M = R omega_l, T_L = T_l / R, J_L = J_G + J_W / R^2,
J_W = M D^2 / 8 = pi rho t D^4 / 32. ServoSoft "Unbalanced Load": J_1 = J_Disc + J_Load + M r^2,
J_DM = J_Coupling + J_1, T_DM = J_Coupling alpha + Q(J_1 alpha +- T_Thrust + M g r sin(phi + beta) sin(theta)).
"""

from __future__ import annotations

from typing import Literal

from drivetrain.axis.mechanisms.base import RotaryLoadSpec
from drivetrain.fields import (
    BackEfficiency,
    Density,
    Efficiency,
    Incline,
    Inertia,
    LengthNonNeg,
    MassNonNeg,
    Spec,
)
from drivetrain.physics.inertia import point_mass, solid_cylinder
from drivetrain.physics.mechanisms.base import Mechanism, RotaryLoad, part_inertia
from drivetrain.physics.stage import Stage


class RotarySpec(Spec):
    """``mechanism: {type: rotary, diameter: ..., thickness: ..., material: ..., load: {...}}``."""

    type: Literal["rotary"]
    diameter: LengthNonNeg = 0.0
    thickness: LengthNonNeg | None = None
    mass: MassNonNeg | None = None
    density: Density | None = None
    material: str | None = None
    inertia: Inertia | None = None
    incline: Incline = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: RotaryLoadSpec = RotaryLoadSpec()

    def build(self, g: float) -> Mechanism:
        """Everything turning with the table lies inside the table's losses (ServoSoft J_1)."""
        j_disc = part_inertia(self.inertia, self.mass, self.diameter, 0.0, self.thickness, self.density,
                              self.material, "mechanism")
        spec = self.load
        j_load = spec.inertia + (solid_cylinder(spec.mass, spec.diameter) if spec.mass else 0.0)
        j_unb = point_mass(spec.unbalance_mass, spec.unbalance_radius)
        load = RotaryLoad(
            inertia=j_load, torque=spec.torque, unbalance_mass=spec.unbalance_mass,
            unbalance_radius=spec.unbalance_radius, unbalance_angle=spec.unbalance_angle, incline=self.incline,
            friction_torque=spec.friction_torque,
            static_friction_torque=spec.friction_torque if spec.static_friction_torque is None
            else spec.static_friction_torque,
            viscous=spec.viscous, turbulent=spec.turbulent, spring=spec.spring, thrust_mode=spec.thrust_mode,
        )
        stage = Stage(name="rotary", kind="rotary", ratio=1.0, inertia_in=0.0,
                      inertia_inside=j_disc + j_load + j_unb, efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="rotary", motion="rotary", stage=stage, load=load,
                         inertia_parts={"disc": j_disc, "load": j_load, "unbalanced mass M r^2": j_unb})
