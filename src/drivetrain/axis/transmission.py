"""The axis file's ``transmission:`` entries (pydantic models), ordered from the motor outward.

Each entry builds a ``Stage`` (drivetrain.physics.stage) with the ratios, default efficiencies and
reflections of ``drivetrain.physics.transmission``: ratio = input speed / output speed, its own inertia
on the motor side of its losses, downstream inertia reflected J / i^2, compliance K / i^2, B / i^2.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from drivetrain.axis.mechanisms.base import WheelSpec
from drivetrain.errors import InputError
from drivetrain.fields import (
    BackEfficiency,
    Backlash,
    ComponentInertia,
    Efficiency,
    LengthNonNeg,
    MassNonNeg,
    Ratio,
    Spec,
    SpeedPos,
    TorqueNonNeg,
    TorsionalDamping,
    TorsionalStiffness,
)
from drivetrain.physics.stage import Stage
from drivetrain.physics.transmission import (
    BELT_EFFICIENCY,
    CHAIN_EFFICIENCY,
    GEAR_PAIR_EFFICIENCY,
    GEARBOX_EFFICIENCY,
    compliance_at_input,
    harmonic_ratio,
    teeth_ratio,
)


class _Compliance(Spec):
    """Stiffness, damping and backlash of an element, for the dynamics (at its output shaft)."""

    stiffness: TorsionalStiffness | None = None
    damping: TorsionalDamping = 0.0
    backlash: Backlash = 0.0


class GearboxSpec(_Compliance):
    """``{type: gearbox, kind: planetary, ratio: 5, efficiency: 0.95, inertia: 0.4 kg*cm^2}``.

    ``inertia`` is at the input (catalog convention); ``stiffness`` [N m/rad, e.g. "3 N*m/arcmin"]
    and ``backlash`` [e.g. "5 arcmin"] at the output, as catalogs give them.
    """

    type: Literal["gearbox"]
    kind: Literal["spur", "helical", "bevel", "planetary", "worm", "harmonic", "cycloidal"] = "planetary"
    ratio: Ratio | None = None
    stages: int = Field(default=1, ge=1, le=4)
    flexspline_teeth: int | None = Field(default=None, gt=0)
    circular_spline_teeth: int | None = Field(default=None, gt=0)
    efficiency: Efficiency | None = None
    back_efficiency: BackEfficiency | None = None
    inertia: ComponentInertia = 0.0
    catalog: str | None = None
    rated_torque: TorqueNonNeg | None = None
    max_torque: TorqueNonNeg | None = None
    emergency_stop_torque: TorqueNonNeg | None = None
    max_input_speed: SpeedPos | None = None
    rated_input_speed: SpeedPos | None = None

    @model_validator(mode="after")
    def _ratio_given(self) -> GearboxSpec:
        if self.ratio is None and self.flexspline_teeth is None and self.catalog is None:
            raise ValueError("give ratio, or flexspline_teeth and circular_spline_teeth for a harmonic drive")
        if self.flexspline_teeth is not None and self.circular_spline_teeth is None:
            raise ValueError("circular_spline_teeth is required with flexspline_teeth")
        return self

    def gear_ratio(self, index: int = 0) -> float:
        """Input / output speed [-]."""
        if self.ratio is not None:
            return self.ratio
        if self.flexspline_teeth is not None and self.circular_spline_teeth is not None:
            try:
                return harmonic_ratio(self.flexspline_teeth, self.circular_spline_teeth)
            except InputError as exc:
                raise exc.at(f"transmission[{index}]") from None
        # A catalog row is resolved where the axis file is read (drivetrain.axis.resolve), which fills the ratio.
        raise InputError(f"transmission[{index}].catalog", "was not resolved from the catalog", self.catalog)

    def build(self, index: int) -> Stage:
        """Gearbox as a Stage: its input inertia outside its losses.

        A ``catalog: ID`` gearbox arrives here with its datasheet values already filled in
        (drivetrain.axis.resolve); the id names the stage.
        """
        if self.catalog is not None:
            return self._stage(index, name=f"{self.catalog} ({self.gear_ratio(index):g}:1)")
        return self._stage(index)

    def _stage(self, index: int, name: str | None = None) -> Stage:
        i = self.gear_ratio(index)
        eta = self.efficiency if self.efficiency is not None else GEARBOX_EFFICIENCY[self.kind] ** self.stages
        back = eta if self.back_efficiency is None else self.back_efficiency
        return Stage(name=name or f"gearbox {self.kind} {i:g}:1", kind="gearbox", ratio=i, inertia_in=self.inertia,
                     efficiency=eta, back_efficiency=back, **_compliance_at_input(self, i))


class BeltStageSpec(_Compliance):
    """``{type: belt, drive_diameter: 30 mm, driven_diameter: 60 mm}`` or teeth; pulleys, idlers, belt mass."""

    type: Literal["belt"]
    drive_diameter: LengthNonNeg | None = None
    driven_diameter: LengthNonNeg | None = None
    drive_teeth: int | None = Field(default=None, gt=0)
    driven_teeth: int | None = Field(default=None, gt=0)
    drive_pulley: WheelSpec = WheelSpec()
    driven_pulley: WheelSpec = WheelSpec()
    idlers: list[WheelSpec] = []
    belt_mass: MassNonNeg = 0.0
    efficiency: Efficiency = BELT_EFFICIENCY
    back_efficiency: BackEfficiency | None = None

    @model_validator(mode="after")
    def _ratio_given(self) -> BeltStageSpec:
        by_d = self.drive_diameter and self.driven_diameter
        by_t = self.drive_teeth and self.driven_teeth
        if not (by_d or by_t):
            raise ValueError("give drive_diameter and driven_diameter, or drive_teeth and driven_teeth")
        return self

    def build(self, index: int) -> Stage:
        """Drive pulley outside the losses; driven pulley, idlers and belt inside (ServoSoft J_1)."""
        if self.drive_teeth and self.driven_teeth:
            i = teeth_ratio(self.drive_teeth, self.driven_teeth)
        else:
            assert self.drive_diameter and self.driven_diameter
            i = self.driven_diameter / self.drive_diameter
        r_dp = (self.drive_diameter or self.drive_pulley.diameter) / 2.0
        field = f"transmission[{index}]"
        j_dp = self.drive_pulley.inertia_si(f"{field}.drive_pulley", self.drive_diameter or 0.0)
        j_dn = self.driven_pulley.inertia_si(f"{field}.driven_pulley", self.driven_diameter or 0.0) / i**2
        j_idlers = 0.0
        for k, idler in enumerate(self.idlers):
            if r_dp <= 0.0 or idler.diameter <= 0.0:
                raise InputError(f"{field}.idlers[{k}].diameter",
                                 "idlers need their diameter and the drive_diameter", idler.diameter)
            j_idlers += idler.count * idler.inertia_si(f"{field}.idlers[{k}]") * (r_dp * 2 / idler.diameter) ** 2
        if self.belt_mass and r_dp <= 0.0:
            raise InputError(f"{field}.drive_diameter", "is required to reflect the belt mass", has_value=False)
        j_belt = self.belt_mass * r_dp**2
        return Stage(name=f"belt {i:g}:1", kind="belt", ratio=i, inertia_in=j_dp,
                     inertia_inside=j_dn + j_idlers + j_belt, efficiency=self.efficiency,
                     back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency,
                     **_compliance_at_input(self, i))


class GearPairSpec(_Compliance):
    """``{type: gear_pair, drive_teeth: 20, driven_teeth: 60, drive_inertia: ..., driven_inertia: ...}``."""

    type: Literal["gear_pair"]
    drive_teeth: int = Field(gt=0)
    driven_teeth: int = Field(gt=0)
    drive_inertia: ComponentInertia = 0.0
    driven_inertia: ComponentInertia = 0.0
    efficiency: Efficiency = GEAR_PAIR_EFFICIENCY
    back_efficiency: BackEfficiency | None = None

    def build(self, index: int) -> Stage:
        """Pinion outside the losses, wheel inside (reflected / i^2)."""
        i = teeth_ratio(self.drive_teeth, self.driven_teeth)
        return Stage(name=f"gears {self.drive_teeth}/{self.driven_teeth}", kind="gear_pair", ratio=i,
                     inertia_in=self.drive_inertia, inertia_inside=self.driven_inertia / i**2,
                     efficiency=self.efficiency,
                     back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency,
                     **_compliance_at_input(self, i))


class ChainStageSpec(_Compliance):
    """``{type: chain, drive_teeth: 15, driven_teeth: 45, chain_mass: ...}`` (sprocket stage)."""

    type: Literal["chain"]
    drive_teeth: int = Field(gt=0)
    driven_teeth: int = Field(gt=0)
    pitch: LengthNonNeg = 0.0
    drive_inertia: ComponentInertia = 0.0
    driven_inertia: ComponentInertia = 0.0
    chain_mass: MassNonNeg = 0.0
    efficiency: Efficiency = CHAIN_EFFICIENCY
    back_efficiency: BackEfficiency | None = None

    def build(self, index: int) -> Stage:
        """Drive sprocket outside the losses; driven sprocket and chain inside."""
        i = teeth_ratio(self.drive_teeth, self.driven_teeth)
        # Pitch diameter of the drive sprocket: d = p / sin(pi / z) (standard roller-chain geometry).
        r_dp = self.pitch / (2.0 * math.sin(math.pi / self.drive_teeth)) if self.pitch else 0.0
        if self.chain_mass and not self.pitch:
            raise InputError(f"transmission[{index}].pitch", "is required to reflect the chain mass",
                             has_value=False)
        return Stage(name=f"chain {self.drive_teeth}/{self.driven_teeth}", kind="chain", ratio=i,
                     inertia_in=self.drive_inertia,
                     inertia_inside=self.driven_inertia / i**2 + self.chain_mass * r_dp**2,
                     efficiency=self.efficiency,
                     back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency,
                     **_compliance_at_input(self, i))


class CouplingSpec(_Compliance):
    """``{type: coupling, inertia: 0.2 kg*cm^2, stiffness: ..., backlash: ...}`` (ratio 1, lossless)."""

    type: Literal["coupling"]
    inertia: ComponentInertia = 0.0

    def build(self, index: int) -> Stage:
        """Coupling as a rigid or compliant Stage of ratio 1."""
        return Stage(name="coupling", kind="coupling", inertia_in=self.inertia, **_compliance_at_input(self, 1.0))


class ClutchBrakeSpec(Spec):
    """``{type: brake | clutch, inertia: ..., holding_torque: ...}`` (ratio 1, lossless)."""

    type: Literal["brake", "clutch"]
    inertia: ComponentInertia = 0.0
    holding_torque: TorqueNonNeg | None = None

    def build(self, index: int) -> Stage:
        """Clutch or brake as a Stage of ratio 1 with its holding torque."""
        return Stage(name=self.type, kind=self.type, inertia_in=self.inertia, holding_torque=self.holding_torque)


def _compliance_at_input(spec: _Compliance, ratio: float) -> dict[str, Any]:
    """The element's output-side compliance seen at its input (``physics.transmission.compliance_at_input``)."""
    return compliance_at_input(spec.stiffness, spec.damping, spec.backlash, ratio)


TransmissionSpec = Annotated[
    GearboxSpec | BeltStageSpec | GearPairSpec | ChainStageSpec | CouplingSpec | ClutchBrakeSpec,
    Field(discriminator="type"),
]

TRANSMISSION_TYPES: tuple[str, ...] = ("gearbox", "belt", "gear_pair", "chain", "coupling", "clutch", "brake")
