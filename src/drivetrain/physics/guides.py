"""Linear actuators and guides: moment loads on the carriage and the RMS force over the cycle.

Lecture, linear actuator pages: with the load's weight W_L and the thrust F_x along the travel,
offsets l_x, l_y, l_z of the load's centre from the carriage and d_p, d_r of the carriage's
pitch and roll axes,
    horizontal: F_z = W_L, M_p = F_z l_x + F_x (l_z + d_p), M_r = F_z l_y, M_y = F_x l_y;
    vertical:   F_y = W_L, M_p = F_x (l_z + d_p), M_r = F_y (l_z + d_r);
    wall:       F_y = W_L (sideways), M_p = F_x (l_z + d_p), M_y = F_x l_y, M_r = F_y (l_z + d_r);
and F_T,RMS = sqrt((F_acc^2 t_a + F_vel^2 t_v + F_dec^2 t_d + F_off^2 t_off) / (t_a + t_v + t_d + t_off)),
computed here exactly with the profile's quadrature weights. Forces [N], moments [N m]. The answer's
``guide`` and ``slip_check`` blocks are built from these by ``sizing.axis_blocks``.
"""

from __future__ import annotations

import math

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
