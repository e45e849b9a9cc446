"""A custom rotary mechanism given by its inertia and load torque at its input shaft."""

from __future__ import annotations

import math
from typing import Literal

from drivetrain.axis.mechanisms.base import RotaryLoadSpec
from drivetrain.fields import BackEfficiency, Efficiency, Inertia, Spec
from drivetrain.physics.inertia import point_mass, solid_cylinder
from drivetrain.physics.mechanisms.base import Mechanism, RotaryLoad
from drivetrain.physics.stage import Stage


class CustomSpec(Spec):
    """``mechanism: {type: custom, inertia: ..., load: {torque: ..., viscous: ..., ...}}``.

    The equation of motion is the lecture's T = J alpha + T_L with T_L from ``load``; an
    unbalanced mass turns in a vertical plane (M g r sin(phi + beta)).
    """

    type: Literal["custom"]
    inertia: Inertia = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: RotaryLoadSpec = RotaryLoadSpec()

    def build(self, g: float) -> Mechanism:
        """All inertia inside the losses; the load torques as given."""
        spec = self.load
        j_load = spec.inertia + (solid_cylinder(spec.mass, spec.diameter) if spec.mass else 0.0)
        j_unb = point_mass(spec.unbalance_mass, spec.unbalance_radius)
        load = RotaryLoad(
            inertia=j_load, torque=spec.torque, incline=math.pi / 2, unbalance_mass=spec.unbalance_mass,
            unbalance_radius=spec.unbalance_radius, unbalance_angle=spec.unbalance_angle,
            friction_torque=spec.friction_torque,
            static_friction_torque=spec.friction_torque if spec.static_friction_torque is None
            else spec.static_friction_torque,
            viscous=spec.viscous, turbulent=spec.turbulent, spring=spec.spring, thrust_mode=spec.thrust_mode,
        )
        stage = Stage(name="custom", kind="custom", ratio=1.0, inertia_inside=self.inertia + j_load + j_unb,
                      efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="custom", motion="rotary", stage=stage, load=load,
                         inertia_parts={"mechanism": self.inertia, "load": j_load, "unbalanced mass M r^2": j_unb})
