"""Rack and pinion: load travel per pinion radian is the pinion's pitch radius.

Lecture, "Rack & Pinion Load" (Yaskawa page): T_L = (mu M g + F) D / (2 R eta),
J_W = M (D / 2R)^2, J_P = pi rho t D^4 / 32; ERRATA: N_M = R V_l / (pi D) (the notes copied
P_B from the ball screw page).
"""

from __future__ import annotations

from typing import Literal

from drivetrain.axis.mechanisms.base import LinearLoadSpec
from drivetrain.axis.mechanisms.limits import RackSpec
from drivetrain.fields import BackEfficiency, Density, Efficiency, Incline, Inertia, Length, LengthNonNeg, Spec
from drivetrain.physics.inertia import linear_mass_reflected
from drivetrain.physics.mechanisms.base import Mechanism, part_inertia
from drivetrain.physics.stage import Stage


class RackPinionSpec(Spec):
    """``mechanism: {type: rack_pinion, diameter: ..., thickness: ..., ...}``."""

    type: Literal["rack_pinion"]
    diameter: Length
    thickness: LengthNonNeg | None = None
    density: Density | None = None
    material: str | None = None
    inertia: Inertia | None = None
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    incline: Incline = 0.0
    load: LinearLoadSpec
    rack: RackSpec | None = None

    def build(self, g: float) -> Mechanism:
        """Pinion inertia outside the losses, the load's M r^2 inside."""
        r = self.diameter / 2.0
        j_p = part_inertia(self.inertia, None, self.diameter, 0.0, self.thickness, self.density, self.material,
                           "mechanism")
        load = self.load.build(self.incline)
        j_load = linear_mass_reflected(load.moving_mass, r)
        stage = Stage(name=self.type, kind=self.type, ratio=1.0 / r, inertia_in=j_p, inertia_inside=j_load,
                      efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type=self.type, motion="linear", stage=stage, load=load,
                         inertia_parts={"pinion": j_p, "load M r^2": j_load})
