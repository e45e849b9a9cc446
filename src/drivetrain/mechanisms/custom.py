"""A custom rotary mechanism given by its inertia and load torque at its input shaft."""

from __future__ import annotations

from typing import Literal

from drivetrain.fields import BackEfficiency, Efficiency, Inertia, Spec
from drivetrain.mechanisms.base import Mechanism, RotaryLoad, RotaryLoadSpec
from drivetrain.stage import Stage


class CustomSpec(Spec):
    """``mechanism: {type: custom, inertia: ..., load: {torque: ..., viscous: ..., ...}}``.

    The equation of motion is the lecture's T = J alpha + T_L with T_L from ``load``.
    """

    type: Literal["custom"]
    inertia: Inertia = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: RotaryLoadSpec = RotaryLoadSpec()

    def build(self, g: float) -> Mechanism:
        """All inertia inside the losses; the load torques as given."""
        spec = self.load
        load = RotaryLoad(
            inertia=spec.inertia, torque=spec.torque, unbalance_mass=spec.unbalance_mass,
            unbalance_radius=spec.unbalance_radius, unbalance_angle=spec.unbalance_angle,
            friction_torque=spec.friction_torque,
            static_friction_torque=spec.friction_torque if spec.static_friction_torque is None
            else spec.static_friction_torque,
            viscous=spec.viscous, turbulent=spec.turbulent, spring=spec.spring,
        )
        stage = Stage(name="custom", kind="custom", ratio=1.0, inertia_inside=self.inertia + spec.inertia,
                      efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="custom", motion="rotary", stage=stage, load=load,
                         inertia_parts={"mechanism": self.inertia, "load": spec.inertia})
