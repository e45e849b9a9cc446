"""Belt drives that carry a load: linear belt axis, timing belt, conveyor (with idlers, counterbalance).

ServoSoft pages of the lecture ("belt with idlers", "counterbalanced belt"):
J_1 = (m_Load + m_CB + m_Belt) r_DP^2 + J_IP (r_DP / r_IP)^2 + J_DnP (r_DP / r_DnP)^2,
J_DM = J_DP + J_1, T_DM = J_DP alpha + Q(J_1 alpha + ((m_Load - m_CB) g sin(theta) + F_Thrust) r_DP)
with Q = 1/eta motoring and eta braking. Yaskawa timing-belt page: T_L = (mu M g + F) D / (2 R eta),
J_W = M (D / 2R)^2, J_L = J_W + J_G + J_P / R^2. Conveyor: the incline slip limit
a_max < mu_0 g cos(alpha) (lecture, inclined plane), checked on the profile's accelerations.
"""

from __future__ import annotations

from typing import Literal

from drivetrain.axis.mechanisms.base import LinearLoadSpec, WheelSpec
from drivetrain.axis.mechanisms.limits import BeltDriveSpec
from drivetrain.fields import BackEfficiency, Coefficient, Efficiency, Incline, Length, MassNonNeg, Spec
from drivetrain.physics.inertia import linear_mass_reflected
from drivetrain.physics.loads import slip_limit_acceleration
from drivetrain.physics.mechanisms.base import Mechanism
from drivetrain.physics.stage import Stage


class BeltSpec(Spec):
    """``mechanism: {type: belt | timing_belt | conveyor, diameter: ..., ...}``."""

    type: Literal["belt", "timing_belt", "conveyor"]
    diameter: Length
    drive_pulley: WheelSpec = WheelSpec()
    driven_pulley: WheelSpec | None = None
    idlers: list[WheelSpec] = []
    belt_mass: MassNonNeg = 0.0
    efficiency: Efficiency = 1.0
    back_efficiency: BackEfficiency | None = None
    incline: Incline = 0.0
    carrier_friction: Coefficient | None = None
    load: LinearLoadSpec
    belt: BeltDriveSpec | None = None

    def build(self, g: float) -> Mechanism:
        """The belt as a Stage: drive pulley outside its losses; load, belt, idlers, driven pulley inside."""
        r = self.diameter / 2.0
        j_dp = self.drive_pulley.inertia_si("mechanism.drive_pulley", self.diameter)
        driven = self.driven_pulley or WheelSpec(diameter=self.diameter)
        r_dn = (driven.diameter or self.diameter) / 2.0
        j_dn = driven.inertia_si("mechanism.driven_pulley", self.diameter) * (r / r_dn) ** 2
        j_idlers = 0.0
        for k, idler in enumerate(self.idlers):
            r_ip = (idler.diameter or self.diameter) / 2.0
            j_idlers += idler.count * idler.inertia_si(f"mechanism.idlers[{k}]", self.diameter) * (r / r_ip) ** 2
        load = self.load.build(self.incline)
        j_load = linear_mass_reflected(load.moving_mass, r)
        j_belt = linear_mass_reflected(self.belt_mass, r)
        stage = Stage(name=self.type, kind=self.type, ratio=1.0 / r, inertia_in=j_dp,
                      inertia_inside=j_load + j_belt + j_idlers + j_dn, efficiency=self.efficiency,
                      back_efficiency=self.efficiency if self.back_efficiency is None else self.back_efficiency)
        slip = None
        if self.carrier_friction is not None:
            slip = slip_limit_acceleration(self.carrier_friction, self.incline, g)
        elif self.type == "conveyor":
            slip = slip_limit_acceleration(load.static_friction, self.incline, g) if load.static_friction else None
        return Mechanism(type=self.type, motion="linear", stage=stage, load=load, slip_limit=slip,
                         inertia_parts={"drive pulley": j_dp, "load (M + M_CB) r^2": j_load,
                                        "belt": j_belt, "idlers": j_idlers, "driven pulley": j_dn})
