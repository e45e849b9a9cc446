"""Linear actuators and guides: moment loads on the carriage and the RMS force over the cycle.

Lecture, linear actuator pages: with the load's weight W_L and the thrust F_x along the travel,
offsets l_x, l_y, l_z of the load's centre from the carriage and d_p, d_r of the carriage's
pitch and roll axes,
    horizontal: F_z = W_L, M_p = F_z l_x + F_x (l_z + d_p), M_r = F_z l_y, M_y = F_x l_y;
    vertical:   F_y = W_L, M_p = F_x (l_z + d_p), M_r = F_y (l_z + d_r);
    wall:       F_y = W_L (sideways), M_p = F_x (l_z + d_p), M_y = F_x l_y, M_r = F_y (l_z + d_r);
and F_T,RMS = sqrt((F_acc^2 t_a + F_vel^2 t_v + F_dec^2 t_d + F_off^2 t_off) / (t_a + t_v + t_d + t_off)),
computed here exactly with the profile's quadrature weights. Forces [N], moments [N m].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def carriage_moments(thrust: Array, weight: float, l_x: float, l_y: float, l_z: float, d_p: float, d_r: float,
                     orientation: str) -> dict[str, Array]:
    """Normal force and pitch, roll, yaw moments on the carriage over the cycle [N, N m].

    ``thrust`` is F_x along the travel (process force plus m a), ``weight`` W_L = m g [N].
    """
    fx = np.asarray(thrust, dtype=float)
    if orientation == "horizontal":
        return {"normal_N": np.full_like(fx, weight), "pitch_Nm": weight * l_x + fx * (l_z + d_p),
                "roll_Nm": np.full_like(fx, weight * l_y), "yaw_Nm": fx * l_y}
    if orientation == "vertical":
        return {"normal_N": np.zeros_like(fx), "pitch_Nm": fx * (l_z + d_p),
                "roll_Nm": np.full_like(fx, weight * (l_z + d_r)), "yaw_Nm": np.zeros_like(fx)}
    return {"normal_N": np.full_like(fx, weight), "pitch_Nm": fx * (l_z + d_p),
            "roll_Nm": np.full_like(fx, weight * (l_z + d_r)), "yaw_Nm": fx * l_y}


def rms_force(force: Array, weights: Array, period: float) -> float:
    """F_T,RMS = sqrt(sum(w F^2) / t_cycle) [N] (lecture, linear actuator RMS force)."""
    return math.sqrt(float(np.sum(weights * np.asarray(force) ** 2)) / period)


def guide_report(axis: Any, duty: Any) -> dict[str, Any]:
    """Forces and moments on the carriage of a linear axis, checked against the guide's ratings.

    The actuator force is the lecture's F_actuator = (W_L / g) a + F_applied + F_friction (+ F_gravity
    on a slope or vertical): the moving mass times the acceleration plus the load's whole external
    force along the travel (process force by its thrust_mode, friction mu W_L, gravity, springs).
    Its RMS over the cycle is F_T,RMS. The carriage moments use F_x = m a + F_applied.
    """
    from drivetrain.physics.loads import process_thrust

    spec = axis.spec.guide
    load = axis.mechanism.load
    s = duty.samples
    a = np.asarray(s.a, dtype=float)
    direction = np.asarray(s.direction, dtype=float)
    thrust = np.asarray(s.thrust, dtype=float)
    f_given = np.where(np.isnan(thrust), load.thrust, thrust)
    f_proc = process_thrust(f_given, direction, load.thrust_mode)
    f_x = load.mass * a + f_proc
    weight = load.mass * axis.gravity
    mom = carriage_moments(f_x, weight, spec.l_x, spec.l_y, spec.l_z, spec.d_p, spec.d_r, spec.orientation)
    breakaway = getattr(s, "breakaway", None)
    f_actuator = load.moving_mass * a + load.force(np.asarray(s.x, dtype=float), np.asarray(s.v, dtype=float),
                                                   direction, f_given, axis.gravity, breakaway)
    out: dict[str, Any] = {
        "actuator_rms_force_N": rms_force(f_actuator, duty.weights, duty.period),
        "actuator_peak_force_N": float(np.max(np.abs(f_actuator))),
        "peak_thrust_N": float(np.max(np.abs(f_x))),
    }
    checks = []
    for key, rating in (("normal_N", spec.rated_force), ("pitch_Nm", spec.rated_pitch_moment),
                        ("roll_Nm", spec.rated_roll_moment), ("yaw_Nm", spec.rated_yaw_moment)):
        peak = float(np.max(np.abs(mom[key])))
        out[f"peak_{key}"] = peak
        if rating is not None:
            margin = rating / peak - 1.0 if peak > 0 else math.inf
            checks.append({"name": f"guide_{key.split('_')[0]}", "required": peak, "available": rating,
                           "unit": key.split("_")[1], "margin": margin, "ok": margin >= 0.0, "approximate": False})
    out["checks"] = checks
    out["ok"] = all(c["ok"] for c in checks)
    return out


def slip_check(accel: Array, limit: float, incline: float, g: float) -> dict[str, Any]:
    """The load must not slip on its carrier [m/s^2].

    Lecture, inclined plane: m a_max < mu_0 m g cos(alpha), the limit ``limit`` = mu_0 g cos(alpha).
    On an incline the weight's component adds to the force friction must supply when the load
    accelerates up the slope and subtracts going down: a_up < mu_0 g cos(alpha) - g sin(alpha),
    a_down < mu_0 g cos(alpha) + g sin(alpha) (positive travel is up the slope). Both are checked;
    the worse one is reported.
    """
    a = np.asarray(accel, dtype=float)
    up_need, down_need = float(max(np.max(a), 0.0)), float(max(-np.min(a), 0.0))
    up_limit = limit - g * math.sin(incline)
    down_limit = limit + g * math.sin(incline)
    cases = [(up_limit / up_need - 1.0 if up_need > 0 else math.inf, up_need, up_limit),
             (down_limit / down_need - 1.0 if down_need > 0 else math.inf, down_need, down_limit)]
    if min(up_limit, down_limit) <= 0.0:
        # mu_0 < tan(alpha): the load slides down the slope even at rest, whatever the profile.
        need, avail = (up_need, up_limit) if up_limit <= 0.0 else (down_need, down_limit)
        return {"name": "slip_limit", "required": need, "available": avail, "unit": "m/s^2", "margin": -1.0,
                "ok": False, "approximate": False,
                "note": "the load slides on its carrier at rest: the friction coefficient is below tan(incline)"}
    margin, need, avail = min(cases)
    out = {"name": "slip_limit", "required": need, "available": avail, "unit": "m/s^2",
           "margin": margin, "ok": margin >= 0.0, "approximate": False}
    if need == 0.0:
        out["note"] = "the profile never accelerates the load: nothing can slip (the margin is unbounded)"
    return out
