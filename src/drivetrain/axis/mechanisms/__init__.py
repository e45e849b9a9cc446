"""The axis file's ``mechanism:`` entries: one pydantic model per type, each building its SI ``Mechanism``.

``MechanismSpec`` picks the model by ``type``; the formulas and the SI types the models build live in
``drivetrain.physics`` (``physics.mechanisms``, ``physics.stage``, ``physics.inertia``, ``physics.loads``).
"""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from drivetrain.axis.mechanisms.belt import BeltSpec
from drivetrain.axis.mechanisms.chain import ChainSpec
from drivetrain.axis.mechanisms.custom import CustomSpec
from drivetrain.axis.mechanisms.hoist import HoistSpec
from drivetrain.axis.mechanisms.rack import RackPinionSpec
from drivetrain.axis.mechanisms.roll import RollSpec
from drivetrain.axis.mechanisms.rotary import RotarySpec
from drivetrain.axis.mechanisms.screw import ScrewSpec

MechanismSpec = Annotated[
    ScrewSpec | BeltSpec | RackPinionSpec | RollSpec | RotarySpec | HoistSpec | ChainSpec | CustomSpec,
    Field(discriminator="type"),
]

MECHANISM_TYPES: tuple[str, ...] = (
    "ball_screw", "lead_screw", "belt", "timing_belt", "conveyor", "rack_pinion", "roll", "rotary", "hoist",
    "chain", "custom",
)

__all__ = ["MECHANISM_TYPES", "MechanismSpec"]
