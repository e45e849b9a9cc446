"""``mechanism: {type: ball_screw | lead_screw}``: the screw of the axis file.

Its ``build`` applies the screw formulas of ``drivetrain.physics.mechanisms.screw`` (lever P_B / (2 pi),
the load's (M + M_C) r^2 inside the losses, the screw's inertia outside them; Shigley's lead-screw
efficiency when none is given).
"""

from __future__ import annotations

from typing import Literal

from drivetrain.axis.mechanisms.base import LinearLoadSpec
from drivetrain.axis.mechanisms.limits import NutSpec, ScrewLimitsSpec
from drivetrain.errors import InputError
from drivetrain.fields import (
    BackEfficiency,
    Coefficient,
    Density,
    Efficiency,
    Incline,
    Inertia,
    Lead,
    Length,
    LengthNonNeg,
    Spec,
    TorqueNonNeg,
)
from drivetrain.physics.inertia import cylinder_from_density, linear_mass_reflected
from drivetrain.physics.materials import density as density_of
from drivetrain.physics.mechanisms.base import Mechanism
from drivetrain.physics.mechanisms.screw import BALL_SCREW_EFFICIENCY, lead_screw_efficiency, screw_lever
from drivetrain.physics.stage import Stage


class ScrewSpec(Spec):
    """``mechanism: {type: ball_screw | lead_screw, ...}``."""

    type: Literal["ball_screw", "lead_screw"]
    lead: Lead
    diameter: Length | None = None
    length: LengthNonNeg | None = None
    density: Density | None = None
    material: str | None = None
    inertia: Inertia | None = None
    efficiency: Efficiency | None = None
    back_efficiency: BackEfficiency | None = None
    thread_friction: Coefficient = 0.1
    incline: Incline = 0.0
    friction_torque: TorqueNonNeg = 0.0
    load: LinearLoadSpec
    screw: ScrewLimitsSpec | None = None
    nut: NutSpec | None = None

    def build(self, g: float) -> Mechanism:
        """The screw as a Stage: screw inertia outside its losses, the load's (M + M_C) r^2 inside."""
        if self.inertia is not None:
            j_screw = self.inertia
        elif self.diameter is not None and self.length is not None:
            rho = self.density if self.density is not None else density_of(self.material or "steel",
                                                                            "mechanism.material")
            j_screw = cylinder_from_density(rho, self.length, self.diameter)
        elif self.length is not None:
            raise InputError("mechanism.diameter", "is required to compute the screw inertia from its length",
                             has_value=False)
        else:
            j_screw = 0.0
        eta, eta_back = self._efficiencies()
        r = screw_lever(self.lead)
        load = self.load.build(self.incline)
        j_load = linear_mass_reflected(load.moving_mass, r)
        stage = Stage(name=self.type, kind=self.type, ratio=1.0 / r, inertia_in=j_screw, inertia_inside=j_load,
                      efficiency=eta, back_efficiency=eta_back, friction_torque_in=self.friction_torque)
        return Mechanism(type=self.type, motion="linear", stage=stage, load=load,
                         inertia_parts={"screw": j_screw, "load (M + M_C) r^2": j_load})

    def _efficiencies(self) -> tuple[float, float]:
        if self.efficiency is not None:
            eta = self.efficiency
            return eta, eta if self.back_efficiency is None else self.back_efficiency
        if self.type == "ball_screw":
            return BALL_SCREW_EFFICIENCY, (BALL_SCREW_EFFICIENCY if self.back_efficiency is None
                                           else self.back_efficiency)
        if self.diameter is None:
            raise InputError("mechanism.efficiency", "is required for a lead screw without a diameter "
                             "(or give diameter and thread_friction to compute it)", has_value=False)
        eta, back = lead_screw_efficiency(self.lead, self.diameter, self.thread_friction)
        return eta, back if self.back_efficiency is None else self.back_efficiency
