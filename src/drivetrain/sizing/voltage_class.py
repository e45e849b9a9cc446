"""The voltage-class check: the machine's supply against the motor's (and so its drive's) voltage class.

A servo motor is wound for the DC bus of its class (200 V class: about 325 V; 400 V class: about
565 V); on another supply its envelope, its insulation and its drives differ. The check compares the
supply the axis states (``supply_voltage``, or ``dc_bus_voltage`` / sqrt(2), beside ``motor:`` or in
``drive:``) with the catalog motor's class (``voltage_V``: printed or from the vendor's model-code rule,
catalog.voltage_class) within ``catalog.VOLTAGE_TOLERANCE``. No stated supply: nothing to judge (the
motor's own class is the supply). A motor without a class on a stated supply: ``unknown``, said so.

Source: docs/checks.md, "Voltage class"; the classes and their rules: docs/catalog.md, "Voltage classes".
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis

SQRT2 = math.sqrt(2.0)


def stated_supply(axis: Axis) -> float | None:
    """The AC supply the axis states [V rms line-to-line], or None: the drive's keys first, then the motor's."""
    for spec in (axis.spec.drive, axis.spec.motor):
        if spec is None:
            continue
        if spec.supply_voltage is not None:
            return float(spec.supply_voltage)
        if spec.dc_bus_voltage is not None:
            return float(spec.dc_bus_voltage) / SQRT2
    return None


def voltage_class_check(supply: float | None, motor_voltage: float) -> dict[str, Any] | None:
    """``voltage_class``: required = the stated supply [V], available = the motor's class [V].

    None when no supply is stated. ``status`` pass / fail / unknown (the motor's class not known).
    """
    from drivetrain import catalog

    if supply is None:
        return None
    base: dict[str, Any] = {"name": "voltage_class", "required": supply, "unit": "V", "approximate": False}
    if not math.isfinite(motor_voltage):
        return {**base, "available": None, "margin": None, "ok": None, "status": "unknown",
                "note": f"the motor's voltage class is not known (docs/catalog.md, 'Voltage classes'): "
                        f"give its voltage to judge it on the {supply:.0f} V supply"}
    ok = abs(motor_voltage - supply) <= catalog.VOLTAGE_TOLERANCE * supply
    note = (f"{motor_voltage:.0f} V class motor on a {supply:.0f} V supply" if ok else
            f"a {motor_voltage:.0f} V class motor on a {supply:.0f} V supply: its drives are {motor_voltage:.0f} V "
            f"drives; choose a {supply:.0f} V class motor (or state the supply its drive will have)")
    return {**base, "available": motor_voltage, "margin": 0.0 if ok else -abs(motor_voltage - supply) / supply,
            "ok": ok, "status": "pass" if ok else "fail", "note": note}
