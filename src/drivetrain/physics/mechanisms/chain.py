"""Chain loop with drive and passive sprockets (ServoSoft chain-loop page of the lecture).

J_1 = n_PR J_PR (r_DR / r_PR)^2 + m_Loop r_DR^2, J_DM = n_DR J_DR + J_1,
T_DM = n_DR J_DR alpha + Q(J_1 alpha + (m_Loop g +- F_Thrust) r_DR), Q = 1/eta motoring, eta braking.
The page's resisting force m_Loop g is the loop's weight dragged on its guide with a friction
coefficient of 1; ``loop_friction`` sets the real coefficient (1 reproduces the page).
Products carried on the loop are an ordinary linear ``load`` (mass, friction, thrust).

The axis file's chain (``mechanism: {type: chain}``), which builds it, is ``drivetrain.axis.mechanisms.chain``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from drivetrain.physics.loads import coulomb_friction, normal_force
from drivetrain.physics.mechanisms.base import Array, LinearLoad


@dataclass(frozen=True)
class ChainLoad(LinearLoad):
    """Carried load plus the loop's own weight dragged on its guide (friction ``loop_friction``)."""

    loop_mass: float = 0.0
    loop_friction: float = 1.0

    def force(self, position: ArrayLike, speed: ArrayLike, direction: ArrayLike, thrust: ArrayLike | None,
              g: float, breakaway: ArrayLike | None = None) -> Array:
        """Carried-load force plus mu_loop m_Loop g cos(alpha) against the motion [N]."""
        drag = coulomb_friction(normal_force(self.loop_mass, self.incline, g), self.loop_friction,
                                self.loop_friction, speed, direction, breakaway)
        return np.asarray(super().force(position, speed, direction, thrust, g, breakaway) + drag, dtype=float)
