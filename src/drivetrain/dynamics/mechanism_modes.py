r"""First natural frequency across the stroke, with the mechanism's own spring in the N-mass chain.

The axis's chain (``axis_model.model``: motor, couplings, gearboxes) gains one more spring: the
mechanism's stiffness at its input shaft, k_theta(x) = k_x(x) r^2 (``mechanism_stiffness``),
placed between the mechanism's input inertia (screw, drive pulley, pinion) and the load. The
chain is solved at positions across the stroke; the lowest first mode, where it occurs, and the
most compliant spring at the motor shaft there (the weakest link; lecture, "High Stiffness":
"a single element with inadequate stiffness can compromise the integrity of the entire
system") are reported as ``modes``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from drivetrain.axis.model import Axis
from drivetrain.dynamics import mechanism_stiffness as ms
from drivetrain.dynamics.chain import model_from_stages
from drivetrain.dynamics.linear import natural_frequencies
from drivetrain.errors import InputError

POINTS = 41
"""Positions across the stroke at which the chain is solved."""


def _stroke(axis: Axis, points: int) -> np.ndarray:
    from drivetrain.duty.cycle import duty_cycle

    x = np.asarray(duty_cycle(axis).samples.x, dtype=float)
    return np.linspace(float(x.min()), float(x.max()), points)


def mechanism_stiffness_of(axis: Axis, points: int = POINTS) -> ms.MechanismStiffness | None:
    """The mechanism's stiffness across the axis's stroke, from ``mechanism.screw/nut``, ``belt`` or ``rack``.

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
        pos, span = nut_travel_positions(axis, duty_cycle(axis), points)
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
        x = _stroke(axis, points)
        try:
            k = ms.linear_belt_stiffness(c, belt.home_position + x, belt.centre_distance, belt.layout,
                                         belt.clamp_offset)
        except InputError as exc:
            raise InputError("mechanism.belt.home_position", f"the carriage leaves the belt over the stroke "
                             f"({exc.rule})", belt.home_position) from None
        return ms.MechanismStiffness(position=x, parts={"belt": k}, lever=mech.lever)
    if kind == "rack_pinion" and rack is not None and rack.face_width is not None:
        x = _stroke(axis, points)
        k_mesh = ms.rack_mesh_stiffness(rack.face_width, rack.mesh_stiffness, rack.pressure_angle)
        return ms.MechanismStiffness(position=x, parts={"rack mesh": np.full_like(x, k_mesh)}, lever=mech.lever)
    return None


def modes_across_stroke(axis: Axis, stages: tuple[Any, ...], motor_inertia: float,
                        stiffness: ms.MechanismStiffness | None = None) -> dict[str, Any] | None:
    """``modes`` of ``drivetrain modes``: f1 at each position, its minimum, where, and the weakest link.

    ``stages`` from the motor outward with the mechanism's stage last (``AxisDynamics.stages``),
    ``motor_inertia`` [kg m^2]. Returns None when the mechanism has no stiffness data.
    """
    stiff = stiffness if stiffness is not None else mechanism_stiffness_of(axis)
    if stiff is None:
        return None
    mech_stage = stages[-1]
    head = tuple(stages[:-1])
    f1 = np.empty(stiff.position.size)
    for i, k_theta in enumerate(stiff.torsional):
        chain = model_from_stages(motor_inertia, (*head, replace(mech_stage, stiffness=float(k_theta))), 0.0)
        f1[i] = natural_frequencies(chain)[0]
    worst = int(np.argmin(f1))
    chain = model_from_stages(motor_inertia, (*head, replace(mech_stage, stiffness=float(stiff.torsional[worst]))),
                              0.0)
    compliant = [st for st in (*head, mech_stage) if st.stiffness is not None or st is mech_stage]
    names = [f"{axis.mechanism.type} {stiff.weakest_link(worst)}" if st is mech_stage else (st.name or st.kind)
             for st in compliant]
    k_motor = [float(k) for k in chain.stiffness]
    weakest = names[int(np.argmin(k_motor))]
    return {
        "f1_min_Hz": float(f1[worst]),
        "worst_position_m": float(stiff.position[worst]),
        "weakest_link": weakest,
        "springs_at_motor_Nm_per_rad": dict(zip(names, k_motor, strict=True)),
        "natural_frequencies_at_worst_Hz": [float(f) for f in natural_frequencies(chain)],
        "f1_by_position": [{"position_m": float(x), "f1_Hz": float(f), "axial_stiffness_N_per_m": float(k)}
                           for x, f, k in zip(stiff.position, f1, stiff.axial, strict=True)],
    }
