"""Mechanisms: each turns load motion and force into speed and torque at its input shaft."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from drivetrain.physics.mechanisms.base import LinearLoad, Mechanism, RotaryLoad
from drivetrain.physics.mechanisms.belt import BeltSpec
from drivetrain.physics.mechanisms.chain import ChainSpec
from drivetrain.physics.mechanisms.custom import CustomSpec
from drivetrain.physics.mechanisms.hoist import HoistSpec
from drivetrain.physics.mechanisms.rack import RackPinionSpec
from drivetrain.physics.mechanisms.roll import RollSpec
from drivetrain.physics.mechanisms.rotary import RotarySpec
from drivetrain.physics.mechanisms.screw import ScrewSpec

MechanismSpec = Annotated[
    ScrewSpec | BeltSpec | RackPinionSpec | RollSpec | RotarySpec | HoistSpec | ChainSpec | CustomSpec,
    Field(discriminator="type"),
]

MECHANISM_TYPES: tuple[str, ...] = (
    "ball_screw", "lead_screw", "belt", "timing_belt", "conveyor", "rack_pinion", "roll", "rotary", "hoist",
    "chain", "custom",
)

__all__ = ["MECHANISM_TYPES", "LinearLoad", "Mechanism", "MechanismSpec", "RotaryLoad"]
