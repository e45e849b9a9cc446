"""Four-quadrant efficiency: which way power flows through a lossy element decides the loss.

Source: ServoSoft four-quadrant pages of the lecture (Quadrants 1-4: T_DM = J_DP alpha +
(1/eta)[...] when motoring, + eta[...] when braking) and ``docs/conventions.md`` (Four
quadrants). Modelica's ``LossyGear`` follows the same rule. All torques in [N m].
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

EfficiencyModel = Literal["four_quadrant", "load_torque_only"]
EFFICIENCY_MODELS: tuple[str, ...] = ("four_quadrant", "load_torque_only")


def speed_sign(omega: ArrayLike, direction: ArrayLike) -> NDArray[np.float64]:
    """Sign of motion [-1, 0, 1]: the sign of ``omega``, or of the move ``direction`` where omega is 0.

    At zero speed inside a move the quadrant follows the move's direction, so the ends of a
    segment carry no spurious jump (docs/conventions.md). ``direction`` is 0 in a dwell.
    """
    w = np.asarray(omega, dtype=float)
    # sign(where(...)) equals where(w != 0, sign(w), sign(direction)), in fewer passes
    return np.sign(np.where(w != 0.0, w, np.asarray(direction, dtype=float)))


def torque_through_losses(
    torque: ArrayLike,
    omega: ArrayLike,
    direction: ArrayLike,
    efficiency: float,
    back_efficiency: float,
) -> NDArray[np.float64]:
    r"""Torque on the motor side of an element's losses [N m].

    ``torque`` [N m] is what the element must pass on, already divided by its ratio (the
    bracket of the ServoSoft quadrant formulas, inertia inside the losses included); ``omega``
    [rad/s] is the speed on the motor side; ``direction`` the move direction (used at zero speed).

    .. math::
        T_{in} = \begin{cases} T/\eta & T\,\omega > 0 \ \text{(motoring, quadrants 1 and 3)}\\
                               T\,\eta_{back} & T\,\omega < 0 \ \text{(braking, quadrants 2 and 4)}\end{cases}

    At standstill in a dwell (``direction`` 0) the element holds: computed as motoring (the safe
    side), except a self-locking element (``back_efficiency <= 0``) that holds the load by
    itself and passes no torque (docs/conventions.md). A self-locking element lowering a load (braking
    quadrant) gives ``T * eta_back`` of the opposite sign: the motor must drive the load down.
    """
    return losses_by_sign(np.asarray(torque, dtype=float), speed_sign(omega, direction), efficiency, back_efficiency)


def losses_by_sign(t: NDArray[np.float64], s: NDArray[np.float64], efficiency: float,
                   back_efficiency: float) -> NDArray[np.float64]:
    """:func:`torque_through_losses` with the sign of motion ``s`` (:func:`speed_sign`) already known [N m]."""
    motoring = t * s > 0.0
    out = np.where(motoring, t / efficiency, t * back_efficiency)
    holding = s == 0.0
    if np.any(holding):
        held = np.zeros_like(t) if back_efficiency <= 0.0 else t / efficiency
        out = np.where(holding, held, out)
    return np.asarray(out, dtype=float)
