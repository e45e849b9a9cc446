r"""First natural frequency across the stroke, with the mechanism's own spring in the N-mass chain.

The axis's chain (``axis_model.model``: motor, couplings, gearboxes) gains one more spring: the
mechanism's stiffness at its input shaft, k_theta(x) = k_x(x) r^2 (``axis_stiffness``),
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
from drivetrain.dynamics.axis_stiffness import mechanism_stiffness_of
from drivetrain.dynamics.chain import model_from_stages
from drivetrain.dynamics.linear import natural_frequencies
from drivetrain.errors import InputError
from drivetrain.sizing.axis_blocks import BandwidthCheck, ModeAtPosition, Modes

BANDWIDTH_FACTOR = 2.0
"""k of the servo-bandwidth requirement f1 >= k f_v: the velocity-loop bandwidth may reach at most
half the first (anti-)resonance (Ellis, *Control System Design Guide*, 4th ed. (2012), chapter
"Compliance and Resonance"; the tuning rule of ``control.tune``, ``fraction_of_anti_resonance``
0.5, so k = 1 / 0.5)."""

SRC_BANDWIDTH = ("lecture, five requirements of a servo transmission, 2 'High Resonant Frequency'; "
                 "Ellis, Control System Design Guide, 4th ed., ch. Compliance and Resonance (f_v <= 0.5 f_r)")


def modes_across_stroke(axis: Axis, stages: tuple[Any, ...], motor_inertia: float,
                        stiffness: ms.MechanismStiffness | None = None) -> Modes | None:
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
    bandwidth = servo_bandwidth_check(axis, chain, float(f1[worst]), weakest)
    return Modes(
        f1_min_Hz=float(f1[worst]),
        worst_position_m=float(stiff.position[worst]),
        weakest_link=weakest,
        springs_at_motor_Nm_per_rad=dict(zip(names, k_motor, strict=True)),
        natural_frequencies_at_worst_Hz=tuple(float(f) for f in natural_frequencies(chain)),
        f1_by_position=tuple(ModeAtPosition(float(x), float(f), float(k))
                             for x, f, k in zip(stiff.position, f1, stiff.axial, strict=True)),
        velocity_bandwidth_Hz=bandwidth["velocity_bandwidth_Hz"],
        bandwidth_source=bandwidth["bandwidth_source"],
        max_velocity_bandwidth_Hz=bandwidth["max_velocity_bandwidth_Hz"],
        checks=(bandwidth["check"],),
    )


def required_velocity_bandwidth(axis: Axis) -> tuple[float | None, str]:
    """The velocity-loop bandwidth the axis asks for [Hz] and where it comes from.

    ``dynamics.loop.velocity_bandwidth`` when the axis file gives it (the bandwidth the
    application needs); otherwise ``(None, "not stated")``: what the application needs is the
    user's figure, and no default stands in for it (:func:`servo_bandwidth_check`).
    """
    from drivetrain.units import parse

    block = axis.spec.dynamics or {}
    loop = block.get("loop") or {}
    if isinstance(loop, dict) and "velocity_bandwidth" in loop:
        f_v = parse(loop["velocity_bandwidth"], "frequency", "dynamics.loop.velocity_bandwidth", allow_zero=False)
        if not (math.isfinite(f_v) and f_v > 0.0):
            raise InputError("dynamics.loop.velocity_bandwidth", "must be > 0 Hz", loop["velocity_bandwidth"])
        return float(f_v), "dynamics.loop.velocity_bandwidth"
    return None, "not stated"


def rigid_velocity_bandwidth(axis: Axis, chain: Any) -> float:
    """The bandwidth the tuning rule (``control.tune``) reaches on the chain's inertia taken rigid [Hz].

    With the loop settings of ``dynamics.loop`` (current-loop bandwidth / 4 and the loop delay's
    20 deg of phase): what the drive would give a rigid mechanism. Reported for information when
    the axis states no bandwidth; it is not a requirement.
    """
    from drivetrain.dynamics.axis_model import servo_loop
    from drivetrain.dynamics.chain import Chain

    rigid = Chain(inertia=np.array([chain.total_inertia]), stiffness=np.zeros(0))
    tuned = servo_loop(rigid, axis.spec.dynamics or {})
    return float(tuned.velocity_kp / (2.0 * math.pi * rigid.total_inertia))


def servo_bandwidth_check(axis: Axis, chain: Any, f1_min: float, weakest: str,
                          factor: float = BANDWIDTH_FACTOR) -> dict[str, Any]:
    r"""The lecture's second requirement: the lowest first mode lies above the servo bandwidth.

    .. math:: f_1(x_{worst}) \ge k\, f_v, \qquad k = 2

    ``chain`` at the worst position, ``f1_min`` [Hz] its first mode, ``weakest`` the weakest
    link's name; f_v [Hz] from :func:`required_velocity_bandwidth`; k :data:`BANDWIDTH_FACTOR`.
    Returns {"velocity_bandwidth_Hz", "bandwidth_source", "max_velocity_bandwidth_Hz", "check"},
    the check a ``sizing.axis_blocks.BandwidthCheck``. ``max_velocity_bandwidth_Hz`` = f1 / k is the
    highest velocity bandwidth the mechanism allows. Without a stated f_v the check is ``unknown``
    (required and margin NaN, ``ok`` None): the application's bandwidth is an input, and a default (the
    drive's rigid tuning, given in the note) would judge the mechanism against a loop nobody asked for.
    """
    f_v, origin = required_velocity_bandwidth(axis)
    f_max = f1_min / factor
    if f_v is None:
        rigid = rigid_velocity_bandwidth(axis, chain)
        check = BandwidthCheck(
            "servo_bandwidth", f1_min, "Hz", SRC_BANDWIDTH, False, math.nan, math.nan, None, "unknown",
            f"no dynamics.loop.velocity_bandwidth given: the bandwidth the axis needs is unknown; "
            f"f1 allows a velocity loop up to f1 / {factor:g} = {f_max:.1f} Hz (the default tuning "
            f"would reach {rigid:.1f} Hz on the rigid inertia); weakest link: {weakest}")
        return {"velocity_bandwidth_Hz": None, "bandwidth_source": origin, "max_velocity_bandwidth_Hz": f_max,
                "check": check}
    required = factor * f_v
    margin = f1_min / required - 1.0
    check = BandwidthCheck("servo_bandwidth", f1_min, "Hz", SRC_BANDWIDTH, False, required, margin,
                           bool(margin >= 0.0), "pass" if margin >= 0.0 else "fail",
                           f"f1 >= {factor:g} x velocity bandwidth {f_v:.1f} Hz ({origin}); weakest link: {weakest}")
    return {"velocity_bandwidth_Hz": f_v, "bandwidth_source": origin, "max_velocity_bandwidth_Hz": f_max,
            "check": check}


def modes_of_result(result: Any) -> Modes | None:
    """``modes`` for a sizing result (report, web app): the chain with its given or selected motor.

    None when the mechanism has no stiffness data, the axis gives an explicit
    ``dynamics.chain``, or there is no motor (none given and no catalog motor passes). The
    result carries ``motor``, the motor the chain assumes.
    """
    from drivetrain.dynamics.axis_model import model

    axis = result.axis
    if axis.mechanism.motion != "linear" or not axis.spec.profile or "chain" in (axis.spec.dynamics or {}):
        return None
    stiff = mechanism_stiffness_of(axis)
    if stiff is None:
        return None
    if axis.motor is None and (result.selection is None or result.selection.selected is None):
        return None
    dyn = model(axis, result)
    out = modes_across_stroke(axis, dyn.stages, dyn.motor_inertia, stiff)
    return None if out is None else replace(out, motor=dyn.motor)


def size_many(axes: Any, points_per_phase: int = 64, all_pairs: bool = False, **kwargs: Any) -> list[Any]:
    """The sizing pipeline (``sizing.pipeline.size_many``) with its modes stage (``modes_of_result``): the
    answer every face gives (``drivetrain.size``, the CLI, the web app, the report)."""
    from drivetrain.sizing.pipeline import size_many as pipeline_size_many

    return pipeline_size_many(list(axes), points_per_phase, all_pairs, modes=modes_of_result, **kwargs)


def size(axis: Any, points_per_phase: int = 64, all_pairs: bool = False, **kwargs: Any) -> Any:
    """``size_many([axis])[0]``: one axis's answer with its modes stage (``to_dict()`` is ``size --json``)."""
    return size_many([axis], points_per_phase, all_pairs, **kwargs)[0]
