"""A motor holding brake against the static load it must hold (SI units).

A holding brake clamps the motor shaft at standstill: it must hold, without slip, the torque the
load applies at the motor shaft when nothing moves (gravity on an incline or a vertical axis, an
unbalanced hoist, a spring). Its rating is the holding (static friction) torque, Siemens' M4: "the
highest permissible torque for the closed brake in steady-state operation without slip (holding
function when motor is at standstill)" (Siemens, SIMOTICS S-1FK2 Synchronous Motors, Configuration
Manual 02/2022, A5E46927724B AD, section 4.2 Holding brake, p. 63).
"""

from __future__ import annotations

from collections.abc import Iterable

BRAKE_SAFETY_FACTOR = 1.5
"""Default factor on the static load torque at the brake [-] (``motor.margins.brake``).

The holding torque needed is the load's torque worked back to the brake's shaft through the gear
ratio, times a service factor K: T_H = (T / GR) K, "K ... should be 1.5 to 3 depending on
application data", and for a motor driving its load through a ball or lead screw "the end result
should be multiplied by a service factor, usually 1.5" (Machine Design, "Mechatronics Q & A: Hold
It Steady", 21 Nov 2007, https://www.machinedesign.com/archive/mechantronics-q-hold-it-steady).
The factor covers lining wear and the spread of the holding torque; the lower end of that range is
the default here, and the field says where to raise it."""


def held_torque(torque_out: float, stages: Iterable[tuple[float, float]]) -> float:
    """The static torque that reaches the brake at the motor shaft [N m] from ``torque_out`` at the
    load side [N m or N], worked back through ``stages``, each (ratio [-, or rad/m for a linear
    mechanism], back efficiency [-]), load side first.

    At standstill the load drives back through every stage (the holding direction): the torque at a
    stage's input is T_out / i x eta_back (ServoSoft's quadrant rule for power flowing from the load,
    physics/efficiency.py ``torque_through_losses``; the motor-side brake sees the load's torque
    less the stage's losses). A self-locking stage (eta_back <= 0, e.g. a lead screw below its
    friction angle) passes nothing: the load holds itself. Coulomb friction outside the losses
    (a screw nut's preload) helps to hold and is not counted.

    >>> round(held_torque(9.81 * 60.0, [(2.0 * 3.141592653589793 / 0.01, 0.9)]), 4)  # 60 kg, 10 mm lead, eta' 0.9
    0.8431
    """
    t = abs(float(torque_out))
    for ratio, back in stages:
        if back <= 0.0:
            return 0.0
        t = t / ratio * back
    return t


__all__ = ["BRAKE_SAFETY_FACTOR", "held_torque"]
