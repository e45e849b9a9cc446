"""Accelerating a motor and its load: the shortest acceleration and deceleration times the motor's peak
torque allows, the powers of running and accelerating the load, and the acceleration torque under a
position loop's lag.

SI throughout: speeds [rad/s], inertias [kg m^2] at the motor shaft, torques [N m], times [s], powers [W].
"""

from __future__ import annotations

import math


def minimum_accel_time(speed: float, motor_inertia: float, load_inertia: float, peak_torque: float,
                       load_torque: float) -> float:
    """t_am = 2 pi N_M (J_M + J_L) / (60 (T_PM - T_L)) [s] (lecture; ``speed`` in rad/s here).

    ERRATA: the accel time must be at least t_am. Infinite when T_PM <= T_L.
    """
    margin = peak_torque - load_torque
    return math.inf if margin <= 0.0 else speed * (motor_inertia + load_inertia) / margin


def minimum_decel_time(speed: float, motor_inertia: float, load_inertia: float, peak_torque: float,
                       load_torque: float) -> float:
    """t_dm = 2 pi N_M (J_M + J_L) / (60 (T_PM + T_L)) [s] (lecture; ``speed`` in rad/s here)."""
    margin = peak_torque + load_torque
    return math.inf if margin <= 0.0 else speed * (motor_inertia + load_inertia) / margin


def operation_power(speed: float, load_torque: float) -> float:
    """P_o = 2 pi N_M T_L / 60 = omega T_L [W] (lecture, Load Operation Power)."""
    return speed * load_torque


def acceleration_power(speed: float, load_inertia: float, accel_time: float) -> float:
    """P_a = (2 pi N_M / 60)^2 J_L / t_a = omega^2 J_L / t_a [W] (lecture, Load Acceleration Power)."""
    return speed**2 * load_inertia / accel_time


def fanuc_accel_torque(speed: float, accel_time: float, position_gain: float, motor_inertia: float,
                       load_inertia: float, efficiency: float) -> float:
    """Acceleration torque of a linear accel/decel under a position loop [N m].

    T_a = omega (1 / t_a) (J_M + J_L / eta) (1 - exp(-k_s t_a)): the position loop's first-order
    lag (gain k_s [1/s]) rounds the corner, so the torque peak comes at t_a. FANUC AC Servo
    Motor alpha-i series Descriptions B-65262EN/03, 3.2.4.1. ``speed`` [rad/s], times [s].
    """
    return speed / accel_time * (motor_inertia + load_inertia / efficiency) * (
        1.0 - math.exp(-position_gain * accel_time))


def fanuc_speed_at_peak_torque(speed: float, accel_time: float, position_gain: float) -> float:
    """Motor speed when the acceleration torque peaks [same unit as ``speed``].

    V_r = V_m (1 - (1 / (t_a k_s)) (1 - exp(-k_s t_a))) (FANUC B-65262EN/03, 3.2.4.1).
    """
    return speed * (1.0 - (1.0 - math.exp(-position_gain * accel_time)) / (accel_time * position_gain))
