"""One element of the drive train between the motor and the load, in SI, and the chain of them.

Every mechanism and transmission element reduces to a ``Stage``: a ratio, inertia on the
motor side of its own losses, inertia reflected to its input but inside its losses, an
efficiency by direction of power flow, and (for dynamics) stiffness, damping and backlash.

Conventions (docs/conventions.md): the ratio ``i`` is input speed / output speed; for a linear
mechanism it is input angle per load travel [rad/m] (1 / lever arm). Downstream inertia,
stiffness and viscous damping reflect as J/i^2, K/i^2, B/i^2; torque as T/i with losses.
Lecture: "Gear system-motor connections", energy equivalence: J_2' = J_2 / n^2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from drivetrain.physics.efficiency import EfficiencyModel, losses_by_sign, speed_sign


@dataclass(frozen=True)
class Stage:
    """A lossy, possibly compliant element of the drive train, ordered from the motor outward.

    Attributes (SI):
        name: label for tables ("gearbox", "belt", "ball_screw").
        kind: element type as written in the axis file.
        ratio: input speed / output speed [-], or [rad/m] for a linear mechanism.
        inertia_in: inertia on the motor side of the element's own losses, at its input [kg m^2]
            (drive pulley, screw shaft, gearbox input inertia, coupling).
        inertia_inside: inertia inside the losses, already reflected to the input [kg m^2]
            (driven pulley, idlers, belt mass, the load's mass for a mechanism).
        efficiency: forward efficiency eta in (0, 1].
        back_efficiency: efficiency when the load drives back, in [-1, 1]; <= 0 is self-locking.
        friction_torque_in: Coulomb torque at the input, outside the losses [N m] (screw-nut preload).
        stiffness: torsional stiffness seen at the input [N m/rad] (None: rigid).
        damping: viscous damping across the compliance, at the input [N m s/rad].
        backlash: total angular play at the input [rad].
        holding_torque: clutch/brake holding torque at the input [N m] (None: not a brake).
    """

    name: str
    kind: str
    ratio: float = 1.0
    inertia_in: float = 0.0
    inertia_inside: float = 0.0
    efficiency: float = 1.0
    back_efficiency: float = 1.0
    friction_torque_in: float = 0.0
    stiffness: float | None = None
    damping: float = 0.0
    backlash: float = 0.0
    holding_torque: float | None = None

    @property
    def self_locking(self) -> bool:
        """True when the load cannot drive the element backwards (eta_back <= 0)."""
        return self.back_efficiency <= 0.0

    @property
    def inertia(self) -> float:
        """All of the element's own inertia at its input [kg m^2]."""
        return self.inertia_in + self.inertia_inside


def reflect_inertia(inertia: float, ratio: float) -> float:
    """Inertia seen at the input of a stage of ratio ``ratio`` [kg m^2]: J / i^2.

    Lecture, "Energy Equivalence Principle": (1/2) J_2' w_1^2 = (1/2) J_2 w_2^2 => J_2' = J_2 / n^2.
    For a linear mechanism ``inertia`` is a mass [kg] and ``ratio`` is [rad/m].
    """
    return inertia / ratio**2


def chain_inertia(stages: list[Stage], load_inertia: float = 0.0) -> float:
    """Total inertia at the motor shaft of a chain (motor excluded) [kg m^2].

    ``stages`` run from the motor outward; ``load_inertia`` sits at the output of the last one
    [kg m^2, or kg for a linear load]. Each stage adds its own inertia and divides everything
    downstream by i^2 (lecture: J_total = J_m + J_L / N^2, applied stage by stage).
    """
    j = load_inertia
    for st in reversed(stages):
        j = st.inertia + reflect_inertia(j, st.ratio)
    return j


def torque_in(
    stage: Stage,
    torque_out: NDArray[np.float64],
    external_out: NDArray[np.float64],
    omega_in: NDArray[np.float64],
    alpha_in: NDArray[np.float64],
    direction: NDArray[np.float64],
    model: EfficiencyModel,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Torque at a stage's input from the torque at its output [N m], vectorised over samples.

    ``torque_out`` is the total torque the stage delivers at its output; ``external_out`` the
    part of it that is external load (gravity, friction, thrust, springs), used only by the
    ``load_torque_only`` model. ``omega_in``, ``alpha_in`` [rad/s, rad/s^2] at the input.
    Returns (total input torque, external part of it).

    ``four_quadrant`` (docs/conventions.md): T_in = J_in alpha + Q(J_inside alpha + T_out / i), where Q
    divides by eta when power flows to the load and multiplies by eta_back when it flows back
    (ServoSoft quadrant pages). ``load_torque_only`` (vendor selection guides, e.g. Yaskawa
    T_L = (9.8 mu M + F) P_B / (2 pi R eta)): only the external torque is divided by eta, in
    every quadrant; inertial torque passes without loss.
    """
    i = stage.ratio
    # sign(omega, or the move direction at rest) serves the stage's Coulomb friction and the quadrant
    s = speed_sign(omega_in, direction)
    coulomb = stage.friction_torque_in * s if stage.friction_torque_in else None
    if model == "load_torque_only":
        ext = external_out / (i * stage.efficiency)
        if coulomb is not None:
            ext = ext + coulomb
        inertial = (torque_out - external_out) / i + stage.inertia * alpha_in
        return inertial + ext, ext
    bracket = torque_out / i
    if stage.inertia_inside:
        bracket = stage.inertia_inside * alpha_in + bracket
    total = losses_by_sign(bracket, s, stage.efficiency, stage.back_efficiency)
    if stage.inertia_in:
        total = stage.inertia_in * alpha_in + total
    if coulomb is not None:
        total = total + coulomb
    return total, external_out / i
