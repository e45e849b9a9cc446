"""``mechanism: {type: chain}``: a chain loop with drive and passive sprockets (ServoSoft chain-loop page).

Its ``build`` reflects the sprockets, the loop and the carried load (J_1 = n_PR J_PR (r_DR / r_PR)^2
+ m_Loop r_DR^2, J_DM = n_DR J_DR + J_1) and drags the loop on its guide with ``ChainLoad``
(drivetrain.physics.mechanisms.chain).
"""

from __future__ import annotations

from dataclasses import fields
from typing import Literal

from pydantic import Field

from drivetrain.axis.mechanisms.base import LinearLoadSpec, WheelSpec
from drivetrain.fields import (
    BackEfficiency,
    Coefficient,
    Efficiency,
    Incline,
    Length,
    MassNonNeg,
    Spec,
)
from drivetrain.physics.inertia import linear_mass_reflected
from drivetrain.physics.mechanisms.base import LinearLoad, Mechanism
from drivetrain.physics.mechanisms.chain import ChainLoad
from drivetrain.physics.stage import Stage


class ChainSpec(Spec):
    """``mechanism: {type: chain, diameter: ..., loop_mass: ..., drive_sprockets: ..., passive_sprockets: [...]}``."""

    type: Literal["chain"]
    diameter: Length
    drive_sprocket: WheelSpec = WheelSpec()
    drive_sprockets: int = Field(default=1, ge=1, le=100)
    passive_sprockets: list[WheelSpec] = []
    loop_mass: MassNonNeg = 0.0
    loop_friction: Coefficient = 1.0
    incline: Incline = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    load: LinearLoadSpec | None = None

    def build(self, g: float) -> Mechanism:
        """n_DR J_DR outside the losses; passive sprockets, loop and carried load inside."""
        r = self.diameter / 2.0
        j_dr = self.drive_sprockets * self.drive_sprocket.inertia_si("mechanism.drive_sprocket", self.diameter)
        j_pr = 0.0
        for k, spr in enumerate(self.passive_sprockets):
            r_pr = (spr.diameter or self.diameter) / 2.0
            j_pr += spr.count * spr.inertia_si(f"mechanism.passive_sprockets[{k}]", self.diameter) * (r / r_pr) ** 2
        base = self.load.build(self.incline) if self.load is not None else LinearLoad(mass=0.0, incline=self.incline)
        load = ChainLoad(**{f.name: getattr(base, f.name) for f in fields(LinearLoad)},
                         loop_mass=self.loop_mass, loop_friction=self.loop_friction)
        j_loop = linear_mass_reflected(self.loop_mass, r)
        j_load = linear_mass_reflected(load.moving_mass, r)
        stage = Stage(name="chain", kind="chain", ratio=1.0 / r, inertia_in=j_dr,
                      inertia_inside=j_pr + j_loop + j_load, efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        return Mechanism(type="chain", motion="linear", stage=stage, load=load,
                         inertia_parts={"drive sprockets": j_dr, "passive sprockets": j_pr,
                                        "loop m_Loop r^2": j_loop, "carried load": j_load})
