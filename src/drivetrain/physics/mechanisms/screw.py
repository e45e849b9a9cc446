"""Ball screw and lead screw: load travel per screw revolution is the lead.

Lecture: "Horizontal/Vertical Ball Screw Load" (Yaskawa selection pages): N_M = R V_l / P_B,
T_L = (mu M g + F) P_B / (2 pi R eta), J_W = M (P_B / (2 pi R))^2, J_B = pi rho L_B D_B^4 / 32;
ERRATA for the vertical case: {(M - M_C) g sin(theta) + mu M g cos(theta) + F} P_B / (2 pi R eta),
inertia (M + M_C). ServoSoft leadscrew page: T_RL = F_t / (2 pi p e) + T_PL (the preload torque
sits outside the efficiency).

The axis file's screw (``mechanism: {type: ball_screw | lead_screw}``) is ``drivetrain.axis.mechanisms.screw``.
"""

from __future__ import annotations

import math

BALL_SCREW_EFFICIENCY = 0.9
"""Default ball screw efficiency: the value every selection example of the lecture uses (eta = 0.9)."""


def screw_lever(lead: float) -> float:
    """Load travel per screw radian r = P_B / (2 pi) [m/rad]; ``lead`` [m/rev] (lecture, N_M = V / P_B)."""
    return lead / (2.0 * math.pi)


def screw_torque(force: float, lead: float, efficiency: float) -> float:
    """T = F P_B / (2 pi eta) [N m] to push ``force`` [N] through a screw of ``lead`` [m].

    Lecture, ball screw load torque with R = 1. FANUC alpha-i example: F = 612.5 N, l = 20 mm,
    eta = 0.9 gives 2.166 N m, plus the nut's 0.8 N m preload torque = 2.97 N m (published 3.0).

    >>> round(screw_torque(612.5, 0.02, 0.9) + 0.8, 3)
    2.966
    """
    return force * lead / (2.0 * math.pi * efficiency)


def minimum_lead(max_speed: float, motor_speed: float) -> float:
    """Smallest lead that reaches ``max_speed`` [m/s] at ``motor_speed`` [rad/s]: P_h >= v / n [m].

    THK General Catalog, Examples of Selecting a Ball Screw (B15-69): P_h >= V_max 1000 60 / N_max
    [mm] with V in m/s and N in rpm. 1 m/s at 3000 rpm needs 20 mm.
    """
    return max_speed * 2.0 * math.pi / motor_speed


def feed_per_pulse(lead: float, pulses_per_rev: float) -> float:
    """Travel per encoder pulse [m] = lead / pulses per revolution (THK B15-70)."""
    return lead / pulses_per_rev


def lead_screw_efficiency(lead: float, mean_diameter: float, mu: float) -> tuple[float, float]:
    """Forward and back efficiency of a square-thread power screw [-].

    eta = tan(lambda) / tan(lambda + phi), eta_back = tan(lambda - phi) / tan(lambda), with the
    lead angle tan(lambda) = l / (pi d_m) and friction angle tan(phi) = mu (Shigley's Mechanical
    Engineering Design, power screws). eta_back <= 0 when lambda <= phi: the screw self-locks.
    ``lead``, ``mean_diameter`` [m].
    """
    lam = math.atan(lead / (math.pi * mean_diameter))
    phi = math.atan(mu)
    return math.tan(lam) / math.tan(lam + phi), math.tan(lam - phi) / math.tan(lam)
