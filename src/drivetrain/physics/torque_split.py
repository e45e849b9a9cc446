"""How a motor's torque splits between its own rotor and the gearbox behind it while it accelerates.

Inertias [kg m^2] and torques [N m] at the motor shaft.
"""

from __future__ import annotations


def gearbox_torque_split(motor_inertia: float, reflected_load_inertia: float) -> float:
    """k = J_M / (J_M + J_LR) [-] (lecture, Dynamic Loading and Gearbox Sizing).

    During pure acceleration a share k of the motor's torque accelerates its own rotor; only
    (1 - k) passes through the gearbox, so T_GR = (1 - k) T_M for a purely inertial load.
    """
    return motor_inertia / (motor_inertia + reflected_load_inertia)


def gearbox_peak_torque(motor_peak_torque: float, motor_inertia: float, reflected_load_inertia: float,
                        load_torque: float = 0.0) -> float:
    """Torque through the gearbox when the motor gives ``motor_peak_torque`` [N m, motor side].

    T_GR = (1 - k)(T_M - T_L) + T_L with k = J_M / (J_M + J_LR): the static load torque T_L
    passes entirely, the accelerating surplus splits by inertia (lecture, gearbox sizing).
    """
    k = gearbox_torque_split(motor_inertia, reflected_load_inertia)
    return (1.0 - k) * (motor_peak_torque - load_torque) + load_torque
