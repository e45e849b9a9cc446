"""Each axis of a machine sized on its own (a gantry once per motor with its load share), and its power at the bus.

Gantry assumption (docs/machine.md): the axis file describes the whole gantry axis as seen from
one motor (the whole load and mechanism). Mechanically coupled motors share the motor-shaft
torque in the stated split (or by stiffness: parallel drive trains under a rigid beam deflect
alike, so each carries k_i / sum k of the force); each motor's rotor and its drive are its own.
Each motor is sized for ``share x`` the axis's load torque and load inertia, with its own rotor
inertia. The mechanism's own checks (guide, slip, brake, mechanism limits, gearbox ratings) stay
those of the axis file as written. Each share goes through the sizing pipeline from its duty cycle
(``sizing.pipeline.size_duty``): a given motor's checks, or a catalog selection with the drive rule
(the selected motor has an orderable drive) and its drives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.duty.cycle import DutyCycle
from drivetrain.physics import motor_electrical, regen
from drivetrain.sizing.electrical import dc_bus
from drivetrain.sizing.pipeline import Context, size, size_duty
from drivetrain.sizing.result import SizingResult

if TYPE_CHECKING:
    from drivetrain.machine.model import MachineAxis

Array = np.ndarray


@dataclass
class AxisPower:
    """One machine axis: its sizing result per motor and its electrical power at the bus over its own cycle."""

    name: str
    results: list[SizingResult]
    t: Array
    """[s] the axis's sample times over its own cycle"""
    power: Array
    """[W] electrical power of all its motors together (positive drawn from the bus)"""
    motor_powers: list[Array]
    """[W] each motor's electrical power"""
    period: float
    motion_end: float
    """[s] end of the last move (``after:`` starts here)"""
    basis: str
    """"electrical" (shaft power + copper loss) or "shaft" (shaft power only)"""
    notes: list[str] = field(default_factory=list)
    capacitor_energy: list[float] = field(default_factory=list)
    """[J] per drive: energy its bus capacitors absorb per event (0 where unknown)"""
    capacitor_basis: list[str] = field(default_factory=list)
    min_resistance: list[float] = field(default_factory=list)
    regen_on_voltage: list[float] = field(default_factory=list)
    dc_bus_voltage: float | None = None


def scaled(duty: DutyCycle, share: float) -> DutyCycle:
    """The duty cycle of one motor carrying ``share`` of the load: torques and load inertia x share."""
    return replace(duty, torque=duty.torque * share, external=duty.external * share,
                   stage_torque=tuple(t * share for t in duty.stage_torque), load_inertia=duty.load_inertia * share)


def size_share(full: SizingResult, share: float, context: Context | None = None) -> SizingResult:
    """Size one motor of a gantry for its ``share`` of the load: the sizing pipeline from the scaled duty
    cycle (``size_duty``), the full axis's own checks kept."""
    return size_duty(full.axis, scaled(full.duty, share), own_checks=full, load_share=share, context=context)


def motor_power(res: SizingResult) -> tuple[Array, str, list[str]]:
    """Electrical power [W] of one motor over its cycle, its basis and notes.

    p = T omega + 3 I^2 R (physics.regen): the shaft power with the rotor and the four-quadrant
    losses of every stage (duty.cycle), plus the winding copper loss where Kt and R are known.
    """
    axis = res.axis
    notes: list[str] = []
    duty = res.duty
    if axis.motor is not None:
        j = axis.motor.inertia
    elif res.selection is not None and res.selection.selected is not None and res.ranking is not None:
        from drivetrain.sizing.selection import candidate_cycle

        duty, j = candidate_cycle(axis, res.duty, res.ranking)
        notes.append(f"selected motor {res.selection.selected.motor}: shaft power with its rotor")
    else:
        j = 0.0
        notes.append("no motor: the load's shaft power at the motor shaft, rotor left out")
    t_m = duty.motor_torque(j)
    p = t_m * duty.omega
    elec = axis.electrical
    kt = None if elec is None else motor_electrical.torque_constant(elec.kt, elec.ke)
    if axis.motor is not None and elec is not None and kt is not None and elec.resistance is not None:
        sat = motor_electrical.saturation(axis.motor.rated_torque, axis.motor.peak_torque, elec.peak_current)
        current = motor_electrical.phase_current(t_m, kt, sat)
        return p + regen.copper_loss(current, elec.resistance), "electrical", notes
    missing = [k for k, v in (("torque constant", kt), ("winding resistance", None if elec is None else
                                                             elec.resistance)) if v is None]
    notes.append(f"no {' or '.join(missing) or 'given motor'}: shaft power with its four-quadrant losses, "
                 "copper loss left out")
    return np.asarray(p, dtype=float), "shaft", notes


def axis_power(ma: MachineAxis, points_per_phase: int, supply_voltage: float) -> AxisPower:
    """Size a machine axis (each motor for its share) and sum its motors' electrical power."""
    context = Context(points_per_phase)
    full = size(ma.axis, points_per_phase, context=context)
    results = [full] if ma.motors == 1 else [size_share(full, s, context) for s in ma.shares]
    powers: list[Array] = []
    bases: list[str] = []
    notes: list[str] = []
    for r in results:
        p, b, n = motor_power(r)
        powers.append(p)
        bases.append(b)
        notes.extend(x for x in n if x not in notes)
    duty = full.duty
    period = float(duty.period)
    moves = [ph.t1 for ph in duty.cycle.phases if ph.kind != "dwell"]
    out = AxisPower(name=ma.name, results=results, t=duty.t - duty.t[0], power=np.sum(powers, axis=0),
                    motor_powers=powers, period=period, motion_end=float(max(moves)) if moves else 0.0,
                    basis="electrical" if all(b == "electrical" for b in bases) else "shaft", notes=notes)
    _drive_data(ma, out, supply_voltage)
    return out


def _drive_data(ma: MachineAxis, out: AxisPower, supply_voltage: float) -> None:
    """Each drive's capacitor energy per event, minimum braking resistance and chopper voltage."""
    axis = ma.axis
    drive = axis.drive
    _, bus = dc_bus(axis.electrical, drive)
    if bus is None:
        bus = float(motor_electrical.dc_bus_voltage(supply_voltage))
    out.dc_bus_voltage = bus
    for _ in range(ma.motors):
        e_c, basis = 0.0, "none"
        if drive is not None and drive.absorbable_energy is not None:
            e_c, basis = drive.absorbable_energy, "published"
        elif drive is not None and drive.bus_capacitance is not None and drive.bus_max_voltage is not None:
            e_c, basis = float(regen.capacitor_energy(drive.bus_capacitance, drive.bus_max_voltage, bus)), "capacitance"
        out.capacitor_energy.append(e_c)
        out.capacitor_basis.append(basis)
        if drive is not None and drive.min_resistance is not None:
            out.min_resistance.append(drive.min_resistance)
        if drive is not None and drive.regen_on_voltage is not None:
            out.regen_on_voltage.append(drive.regen_on_voltage)


def bom_items(ma: MachineAxis, ap: AxisPower) -> list[dict[str, Any]]:
    """Bill-of-materials rows of one axis: each motor (a gantry's may differ by share), its drive, gearboxes."""
    rows: list[dict[str, Any]] = []
    axis = ma.axis
    for res in ap.results:
        if axis.motor is not None:
            spec = axis.spec.motor
            code = spec.id if spec is not None and spec.id else axis.motor.name
            vendor = axis.motor.source.split(" ")[0] if spec is not None and spec.id else None
            rows.append({"kind": "motor", "order_code": code, "vendor": vendor, "quantity": 1, "axis": ma.name})
        elif res.selection is not None and res.selection.selected is not None:
            pick = res.selection.selected
            rows.append({"kind": "motor", "order_code": pick.motor, "vendor": pick.vendor, "quantity": 1,
                         "axis": ma.name})
            if pick.gearbox:
                rows.append({"kind": "gearbox", "order_code": pick.gearbox, "vendor": None, "quantity": 1,
                             "axis": ma.name})
        else:
            rows.append({"kind": "motor", "order_code": None, "vendor": None, "quantity": 1, "axis": ma.name,
                         "note": "no motor chosen"})
        if axis.drive is not None:
            rows.append({"kind": "drive", "order_code": axis.drive.name, "vendor": axis.drive.vendor, "quantity": 1,
                         "axis": ma.name})
        for k, st in enumerate(axis.spec.transmission):
            if getattr(st, "type", None) != "gearbox":
                continue
            cat = getattr(st, "catalog", None)
            if cat:
                rows.append({"kind": "gearbox", "order_code": str(cat), "vendor": None, "quantity": 1,
                             "axis": ma.name})
            else:
                ratio = getattr(st, "ratio", None)
                rows.append({"kind": "gearbox", "order_code": None, "vendor": None, "quantity": 1, "axis": ma.name,
                             "note": f"{getattr(st, 'kind', '')} gearbox"
                                     + (f" i = {ratio:g}" if isinstance(ratio, (int, float)) else "")
                                     + f" (transmission[{k}], no catalog part)"})
    return rows


def is_finite(x: float | None) -> bool:
    return x is not None and math.isfinite(x)
