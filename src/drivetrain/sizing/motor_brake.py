"""Whether an axis needs a motor holding brake, and the static torque it must hold (docs/checks.md,
"Motor holding brake").

An axis needs one when its profile holds a dwell on the brake (``holding: brake``) or when its load
applies a torque at standstill (gravity on an incline or a vertical axis, an unbalanced hoist, a
spring), unless its transmission has a ``brake`` element of its own (that brake holds; ``brake_check``
judges it): then every catalog candidate is taken as its brake variant (the with-brake rotor inertia in
its duty cycle, ``braked_motors``) and checked on ``motor_brake`` (kernel.py): the brake's holding
torque against the static torque at the motor shaft, through the candidate's gearbox, x
``motor.margins.brake``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.physics.brake import held_torque
from drivetrain.sizing.answer import BrakeVariant

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.catalog import MotorTable
    from drivetrain.duty.cycle import DutyCycle

STATIC_TOLERANCE = 1e-9
"""[N m] a static torque at the motor shaft at most this is none (the round-off of a balanced load)."""


@dataclass(frozen=True)
class HoldingNeed:
    """An axis's need of a motor holding brake.

    ``needed``: a brake dwell or a static load; ``torque``: the static torque at the axis's motor
    shaft (through its own transmission, holding direction) [N m]; ``why``: the reason in words.
    """

    needed: bool
    torque: float
    why: str


def holding_need(axis: Axis, duty: DutyCycle) -> HoldingNeed:
    """The static torque the load applies at the motor shaft over the cycle's positions, worked back
    through every stage in the holding direction (``physics.brake.held_torque``), and whether the
    axis needs a holding brake (a ``holding: brake`` dwell, or that torque above ``STATIC_TOLERANCE``)."""
    mech = axis.mechanism
    x = np.asarray(duty.samples.x, dtype=float)
    zero = np.zeros_like(x)
    with np.errstate(all="ignore"):
        t_mech_in = mech.external_torque(x, zero, zero, zero, axis.gravity)  # at the mechanism's input, loss-free
    # the load side of the mechanism: F = T_in x i (its "output"); then every stage back to the motor
    load = float(np.max(np.abs(t_mech_in))) * mech.stage.ratio if x.size else 0.0
    torque = held_torque(load, [(st.ratio, st.back_efficiency) for st in reversed(axis.stages)])
    braked = bool(np.any(duty.braked))
    static = torque > STATIC_TOLERANCE
    if any(st.kind == "brake" for st in axis.transmission):  # the axis's own brake holds (result.brake_check)
        return HoldingNeed(needed=False, torque=torque, why="the brake in transmission: holds the load")
    why = " and ".join(filter(None, ["a dwell holds on the brake (holding: brake)" if braked else "",
                                     f"the load holds {torque:.4g} N*m at the motor shaft at standstill"
                                     if static else ""]))
    return HoldingNeed(needed=braked or static, torque=torque, why=why)


def braked_motors(motors: MotorTable) -> MotorTable:
    """The motors as their brake variants: the with-brake rotor inertia where the catalog gives it
    (motor_brakes.csv ``rotor_inertia_brake_kgm2``), the plain one elsewhere (the ``motor_brake``
    check says so)."""
    j_b = np.asarray(motors.rotor_inertia_brake, dtype=float)
    return replace(motors, rotor_inertia=np.where(np.isnan(j_b), motors.rotor_inertia, j_b))





def brake_variant(motors: MotorTable, m: int) -> BrakeVariant:
    """A candidate's brake variant as the answer names it: order code, holding torque [N m], the
    with-brake rotor inertia [kg m^2] (None where the catalog lacks one) and what is missing."""
    code = str(motors.brake_code[m])
    t_h = float(motors.brake_holding_torque[m])
    j_b = float(motors.rotor_inertia_brake[m])
    missing = [what for what, gap in (("order code", not code), ("holding torque", np.isnan(t_h)),
                                      ("with-brake rotor inertia (the plain rotor's is used)", np.isnan(j_b))) if gap]
    return BrakeVariant(order_code=code or None, holding_torque_Nm=None if np.isnan(t_h) else t_h,
                        rotor_inertia_kgm2=None if np.isnan(j_b) else j_b,
                        note="the catalog lacks the brake variant's " + ", ".join(missing) + ": ask the vendor"
                        if missing else None)

__all__ = ["STATIC_TOLERANCE", "HoldingNeed", "brake_variant", "braked_motors", "holding_need"]
