"""The mechanism's own stiffness across the stroke of an axis file: the screw (shaft to the nut, nut,
support bearings, housings), the belt (its free lengths) or the rack mesh, from ``mechanism.screw/nut``,
``belt`` or ``rack`` and the axis's duty cycle (the formulas are in ``mechanism_stiffness``).

``axis_model.with_mechanism_spring`` (the simulation) and ``mechanism_modes`` (the first mode across
the stroke) both read it here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.axis.model import Axis
from drivetrain.dynamics import mechanism_stiffness as ms
from drivetrain.errors import InputError

if TYPE_CHECKING:
    from drivetrain.duty.cycle import DutyCycle

POINTS = 41
"""Positions across the stroke at which the chain is solved."""


def _stroke(axis: Axis, points: int, duty: DutyCycle | None = None) -> np.ndarray:
    from drivetrain.duty.cycle import duty_cycle

    x = np.asarray((duty if duty is not None else duty_cycle(axis)).samples.x, dtype=float)
    return np.linspace(float(x.min()), float(x.max()), points)


def mechanism_stiffness_of(axis: Axis, points: int = POINTS,
                           duty: DutyCycle | None = None) -> ms.MechanismStiffness | None:
    """The mechanism's stiffness across the axis's stroke, from ``mechanism.screw/nut``, ``belt`` or ``rack``.

    ``duty``: the axis's ``duty.cycle.duty_cycle`` where the caller has it (sampled at its default
    points per phase: the stroke is read from its positions), else computed here.

    None when the axis file gives no stiffness data for its mechanism (the mechanism is then
    rigid in the chain, as before). Positions in the result are the load positions [m].
    """
    spec = axis.spec.mechanism
    mech = axis.mechanism
    if mech.motion != "linear":
        return None
    kind = mech.type
    screw = getattr(spec, "screw", None)
    belt = getattr(spec, "belt", None)
    rack = getattr(spec, "rack", None)
    if kind in ("ball_screw", "lead_screw") and screw is not None:
        from drivetrain.duty.cycle import duty_cycle
        from drivetrain.sizing.mechanism_checks import nut_travel_positions

        nut = getattr(spec, "nut", None)
        pos, span = nut_travel_positions(axis, duty if duty is not None else duty_cycle(axis), points)
        parts = ms.screw_drive_stiffness(screw.root_diameter, pos, span, screw.mounting,
                                         nut_stiffness=nut.stiffness if nut is not None and nut.stiffness else math.inf,
                                         bearing_stiffness=screw.support_bearing_stiffness or math.inf,
                                         housing_stiffness=screw.housing_stiffness or math.inf,
                                         youngs_modulus=screw.youngs_modulus)
        parts.pop("total")
        parts = {k: v for k, v in parts.items() if np.all(np.isfinite(v))}
        return ms.MechanismStiffness(position=pos - screw.home_position, parts=parts, lever=mech.lever)
    if kind in ("belt", "timing_belt", "conveyor") and belt is not None:
        c = belt.specific_stiffness
        if c is None and belt.permissible_tension is not None:
            c = ms.belt_specific_stiffness_from_tension(belt.permissible_tension, belt.strain_at_permissible)
        if c is None or belt.centre_distance is None:
            return None
        x = _stroke(axis, points, duty)
        try:
            k = ms.linear_belt_stiffness(c, belt.home_position + x, belt.centre_distance, belt.layout,
                                         belt.clamp_offset)
        except InputError as exc:
            raise InputError("mechanism.belt.home_position", f"the carriage leaves the belt over the stroke "
                             f"({exc.rule})", belt.home_position) from None
        return ms.MechanismStiffness(position=x, parts={"belt": k}, lever=mech.lever)
    if kind == "rack_pinion" and rack is not None and rack.face_width is not None:
        x = _stroke(axis, points, duty)
        k_mesh = ms.rack_mesh_stiffness(rack.face_width, rack.mesh_stiffness, rack.pressure_angle)
        return ms.MechanismStiffness(position=x, parts={"rack mesh": np.full_like(x, k_mesh)}, lever=mech.lever)
    return None
