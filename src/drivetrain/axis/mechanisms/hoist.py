"""Hoist / drum with counterbalance: the lecture's M1/M2 pulley.

Lecture: T = J dw/dt + T_y, T_y = (M_1 - M_2) g r, J = (M_1 + M_2) r^2:
T = (M_1 + M_2) r^2 dw/dt + (M_1 - M_2) g r. The drum's own inertia adds outside the losses.
"""

from __future__ import annotations

import math
from typing import Literal

from drivetrain.axis.mechanisms.base import LinearLoadSpec
from drivetrain.fields import (
    BackEfficiency,
    Density,
    Efficiency,
    Inertia,
    Length,
    LengthNonNeg,
    MassNonNeg,
    Spec,
)
from drivetrain.physics.inertia import linear_mass_reflected
from drivetrain.physics.mechanisms.base import Mechanism, part_inertia
from drivetrain.physics.stage import Stage


class HoistSpec(Spec):
    """``mechanism: {type: hoist, diameter: ..., load: {mass: M1, counterweight: M2}}``.

    The load hangs vertically (incline 90 deg); a positive move lifts it.
    """

    type: Literal["hoist"]
    diameter: Length
    width: LengthNonNeg | None = None
    mass: MassNonNeg | None = None
    density: Density | None = None
    material: str | None = None
    inertia: Inertia | None = None
    rope_mass: MassNonNeg = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: LinearLoadSpec

    def build(self, g: float) -> Mechanism:
        """Drum outside the losses; (M_1 + M_2 + rope) r^2 inside; gravity (M_1 - M_2) g r."""
        r = self.diameter / 2.0
        j_drum = part_inertia(self.inertia, self.mass, self.diameter, 0.0, self.width, self.density,
                              self.material, "mechanism")
        load = self.load.build(math.pi / 2.0)
        j_load = linear_mass_reflected(load.moving_mass + self.rope_mass, r)
        stage = Stage(name="hoist", kind="hoist", ratio=1.0 / r, inertia_in=j_drum, inertia_inside=j_load,
                      efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="hoist", motion="linear", stage=stage, load=load,
                         inertia_parts={"drum": j_drum, "(M_1 + M_2 + rope) r^2": j_load})


