"""What the axis file's mechanisms share: the ``load:`` of a linear or rotary mechanism and a wheel.

Each model validates its keys (units parsed into SI by ``drivetrain.fields``) and builds the SI objects
of ``drivetrain.physics.mechanisms.base`` (``LinearLoad``, ``RotaryLoad``) or an inertia through
``part_inertia``.
"""

from __future__ import annotations

from pydantic import Field

from drivetrain.fields import (
    Angle,
    Coefficient,
    Density,
    Force,
    ForceNonNeg,
    Inertia,
    LengthNonNeg,
    LinearDamping,
    LinearStiffness,
    Mass,
    MassNonNeg,
    Spec,
    Torque,
    TorqueNonNeg,
    TorsionalDamping,
    TorsionalStiffnessNonNeg,
    Turbulent,
)
from drivetrain.physics.loads import ThrustMode
from drivetrain.physics.mechanisms.base import LinearLoad, part_inertia


class LinearLoadSpec(Spec):
    """``load:`` of a linear mechanism.

    ``normal_force`` adds to the weight's normal force on the guides (a gib or clamp force,
    e.g. FANUC's F = mu (W + F_g)); ``spring`` and ``spring_preload`` act along the travel.
    """

    mass: Mass
    counterweight: MassNonNeg = 0.0
    friction: Coefficient = 0.0
    static_friction: Coefficient | None = None
    thrust: Force = 0.0
    thrust_mode: ThrustMode = "against_motion"
    viscous: LinearDamping = 0.0
    spring: LinearStiffness = 0.0
    spring_preload: Force = 0.0
    normal_force: ForceNonNeg = 0.0

    def build(self, incline: float, press_force: float = 0.0) -> LinearLoad:
        """SI load model; static friction defaults to the sliding coefficient."""
        mu_st = self.friction if self.static_friction is None else self.static_friction
        return LinearLoad(mass=self.mass, counterweight=self.counterweight, incline=incline,
                          friction=self.friction, static_friction=mu_st, thrust=self.thrust,
                          viscous=self.viscous, spring=self.spring, spring_preload=self.spring_preload,
                          press_force=press_force + self.normal_force, thrust_mode=self.thrust_mode)


class RotaryLoadSpec(Spec):
    """``load:`` of a rotary mechanism (inertia and torques at the mechanism's output)."""

    inertia: Inertia = 0.0
    mass: MassNonNeg = 0.0
    diameter: LengthNonNeg = 0.0
    torque: Torque = 0.0
    thrust_mode: ThrustMode = "against_motion"
    unbalance_mass: MassNonNeg = 0.0
    unbalance_radius: LengthNonNeg = 0.0
    unbalance_angle: Angle = 0.0
    friction_torque: TorqueNonNeg = 0.0
    static_friction_torque: TorqueNonNeg | None = None
    viscous: TorsionalDamping = 0.0
    turbulent: Turbulent = 0.0
    spring: TorsionalStiffnessNonNeg = 0.0


class WheelSpec(Spec):
    """A pulley, pinion, sprocket, drum or idler: its diameter and how to get its inertia.

    Give ``inertia`` directly, or ``mass`` (solid, or hollow with ``bore``), or ``width`` with
    ``material`` or ``density`` (lecture: J = pi rho L (D_o^4 - D_i^4) / 32). Otherwise 0.
    """

    diameter: LengthNonNeg = 0.0
    inertia: Inertia | None = None
    mass: MassNonNeg | None = None
    width: LengthNonNeg | None = None
    bore: LengthNonNeg = 0.0
    density: Density | None = None
    material: str | None = None
    count: int = Field(default=1, ge=1, le=1000)

    def inertia_si(self, field: str, default_diameter: float = 0.0) -> float:
        """Inertia of one wheel about its axis [kg m^2]; its diameter defaults to ``default_diameter``."""
        return part_inertia(self.inertia, self.mass, self.diameter or default_diameter, self.bore, self.width,
                            self.density, self.material, field)


__all__ = ["LinearLoadSpec", "RotaryLoadSpec", "WheelSpec"]
