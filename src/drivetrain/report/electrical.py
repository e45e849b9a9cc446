"""The report's electrical part: the drive and electrical checks table, the regen/energy plot and the
speed-torque curves at the supply voltage.

The figures come from the result (a given motor: ``result.motor`` and ``result.drive``, ``result.regen``;
a selection: ``selection.selected.drive``, ``.electrical``, ``.regen``, drivetrain.sizing.drive_select).
The plot recomputes the bus power over the cycle with the same model as the regen block
(``drivetrain.physics.regen.regen_cycle``, copper loss from I = T / K_t where K_t and R are known).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.report.display import DisplayUnits, fmt_number, fmt_percent
from drivetrain.report.plots import COLORS, Band, Note, Panel, PlotSpec, Trace

if TYPE_CHECKING:
    from drivetrain.axis.electrical import MotorElectrical
    from drivetrain.report.blocks import Table
    from drivetrain.report.focus import Focus
    from drivetrain.sizing.electrical import DriveAnswer, Regen
    from drivetrain.sizing.result import SizingResult

REGEN_COLORS = {"bus": "#ef6c00", "resistor": "#c62828", "capacitor": "#2e7d32", "supply": "#6a1b9a"}


def blocks(result: SizingResult) -> tuple[dict[str, Any], DriveAnswer | None, Regen | None]:
    """(electrical figures of the motor, drive block, regen block) of the report's motor; {} / None if absent."""
    if result.motor is not None:
        # the checks as the JSON has them, as a selected motor's electrical block holds them
        elec = {**result.motor.electrical,
                "checks": [c.to_dict() for c in result.motor.checks if _electrical_check(c.name)]}
        return elec, result.drive, result.regen
    sel = result.selection.selected if result.selection is not None else None
    if sel is None:
        return {}, None, None
    return dict(sel.electrical or {}), sel.drive, sel.regen


def _electrical_check(name: str) -> bool:
    return name.startswith(("motor_rms_current", "motor_peak_current", "peak_torque_at_supply", "winding_"))


def _motor_electrical(result: SizingResult, focus: Focus) -> MotorElectrical | None:
    if focus.origin == "axis":
        return result.axis.electrical
    if focus.candidate is None:
        return None
    from drivetrain.sizing.drive_select import catalog_electrical

    return catalog_electrical(focus.candidate.motor)


def regen_plot(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> PlotSpec | None:
    """Power into the DC bus over the cycle and the energy it sends to the braking resistor."""
    _, _, rg = blocks(result)
    if focus is None or rg is None:
        return None
    from drivetrain.physics import motor_electrical, regen

    duty = result.duty
    t = np.asarray(duty.t, dtype=float)
    shaft = np.asarray(focus.torque * focus.omega, dtype=float)
    elec = _motor_electrical(result, focus)
    copper = np.zeros_like(t)
    if elec is not None and elec.kt is not None and elec.resistance is not None:
        copper = np.asarray(regen.copper_loss(np.abs(motor_electrical.current_from_torque(focus.torque, elec.kt)),
                                              elec.resistance))
    e_c = float(rg.capacitor_energy_per_event_J)
    r = regen.regen_cycle(t, shaft, copper, e_c, weights=duty.weights, period=duty.period)
    bus = np.asarray(r.bus_power, dtype=float)
    step = np.asarray(duty.weights, dtype=float) * bus
    to_resistor = np.zeros_like(t)
    for a, b in zip(r.events.start, r.events.stop, strict=True):
        e = np.cumsum(step[int(a):int(b) + 1])
        to_resistor[int(a):int(b) + 1] = np.maximum(e - e_c, 0.0)
    # energy carried from one event to the next: cumulative over the cycle
    bus_cum = np.maximum.accumulate(np.cumsum(step))
    res_cum = np.zeros_like(t)
    done = 0.0
    for a, b in zip(r.events.start, r.events.stop, strict=True):
        res_cum[int(a):int(b) + 1] = done + to_resistor[int(a):int(b) + 1]
        done += float(to_resistor[int(b)])
        res_cum[int(b) + 1:] = done
    bands = [Band(float(ph.t0), float(ph.t1), ph.kind) for ph in duty.cycle.phases if ph.t1 > ph.t0]
    power = Panel("power [W]", bands=bands)
    power.traces.append(Trace(t, shaft, "motor shaft power T·ω (negative: generating)", COLORS["motor_torque"],
                              width=1.2, unit="W"))
    power.traces.append(Trace(t, bus, "power into the DC bus (regeneration, after copper loss)",
                              REGEN_COLORS["bus"], width=2.0, unit="W"))
    energy = Panel("energy per cycle [J]", bands=bands, ymin=0.0)
    energy.traces.append(Trace(t, bus_cum, "regenerated into the bus (cumulative)", REGEN_COLORS["bus"], unit="J"))
    energy.traces.append(Trace(t, res_cum, "to the braking resistor (cumulative)", REGEN_COLORS["resistor"],
                               width=2.2, unit="J"))
    if bus.size and float(np.max(bus)) > 0:
        k = int(np.argmax(bus))
        power.notes.append(Note(float(t[k]), float(bus[k]), [f"peak into the bus {fmt_number(float(bus[k]))} W"],
                                REGEN_COLORS["bus"], dx=45, dy=20))
    caption = (f"Regeneration over one cycle: {fmt_number(rg.energy_per_cycle_J)} J into the DC bus, "
               f"{fmt_number(rg.capacitor_absorbed_J)} J absorbed by the bus capacitors "
               f"({rg.capacitor_basis}), {fmt_number(rg.resistor_energy_per_cycle_J)} J to the "
               f"braking resistor (peak {fmt_number(rg.resistor_peak_power_W)} W, average "
               f"{fmt_number(rg.resistor_average_power_W)} W).")
    return PlotSpec("regen", "Regeneration: DC-bus power and braking-resistor energy", "time [s]", [power, energy],
                    caption, height=480, phase_legend=True, xrange=(0.0, float(duty.period)))


def supply_curve_traces(result: SizingResult, du: DisplayUnits) -> list[Trace]:
    """The voltage- and current-limited T-n curves at the supply voltage (sizing.electrical), if computed."""
    elec, _, _ = blocks(result)
    curve = elec.get("curve") or elec.get("supply_curve")
    if not curve:
        return []
    tq = du.label("torque")
    w = du.array(np.asarray(curve["speed_rad_s"], dtype=float), "angular_speed")
    bus = curve.get("dc_bus_voltage_V")
    tag = f" at {fmt_number(bus, 3)} V DC bus" if bus else " at the supply voltage"
    return [
        Trace(w, du.array(np.asarray(curve["peak_torque_Nm"], dtype=float), "torque"), f"peak{tag}",
              REGEN_COLORS["supply"], dash="dash", width=2.0, unit=tq),
        Trace(w, du.array(np.asarray(curve["continuous_torque_Nm"], dtype=float), "torque"), f"continuous{tag}",
              REGEN_COLORS["supply"], dash="dot", width=2.0, unit=tq),
    ]


def electrical_table(result: SizingResult, du: DisplayUnits) -> Table | None:
    """Drive, motor currents, winding temperature and regen as one table with the checks' margins."""
    from drivetrain.report.blocks import Cell, Table

    elec, drive, rg = blocks(result)
    if not elec and drive is None and rg is None:
        return None
    rows: list[list[Cell]] = []

    def add(label: str, value: str, required: str = "", margin: str = "", cls: str = "") -> None:
        rows.append([Cell(label), Cell(value), Cell(required), Cell(margin, cls)])

    def check(c: dict[str, Any], label: str | None = None) -> None:
        unit = c.get("unit", "")
        avail = c.get("available")
        add(label or c["name"].replace("_", " "), "" if avail is None else f"{fmt_number(avail)} {unit}",
            f"{fmt_number(c['required'])} {unit}", fmt_percent(c.get("margin")), "pass" if c.get("ok") else "fail")

    if drive is not None:
        status = drive.outcome
        what = drive.id or "none"
        if drive.basis:
            what += f" ({drive.basis})"
        add("Drive", what, "", status, {"ok": "pass", "fails": "fail"}.get(status, "warn"))
        if drive.reason:
            add("", drive.reason, "", "", "warn")
        for c in drive.checks or ():
            check(c)
    if elec:
        src = elec.get("envelope_source")
        if src:
            add("Envelope source", str(src))
        if elec.get("supply_voltage_V"):
            add("Supply voltage", f"{fmt_number(elec['supply_voltage_V'])} V")
        if elec.get("rms_current_A") is not None:
            add("Motor current RMS / peak", f"{fmt_number(elec['rms_current_A'])} / "
                f"{fmt_number(elec['peak_current_A'])} A")
        for c in elec.get("checks", []):
            check(c)
        if elec.get("winding_temperature_rise_K") is None:
            add("Winding temperature rise", "not known (the motor's thermal data are missing)", "", "", "warn")
        if elec.get("note"):
            add("", str(elec["note"]), "", "", "warn")
    if rg is not None:
        add("Regen into the DC bus per cycle", f"{fmt_number(rg.energy_per_cycle_J)} J")
        add("Absorbed by the bus capacitors", f"{fmt_number(rg.capacitor_absorbed_J)} J "
            f"({rg.capacitor_basis})")
        add("Braking resistor: energy per cycle", f"{fmt_number(rg.resistor_energy_per_cycle_J)} J")
        add("Braking resistor: peak / average power", f"{fmt_number(rg.resistor_peak_power_W)} / "
            f"{fmt_number(rg.resistor_average_power_W)} W")
        lo, hi = rg.resistor_min_ohm, rg.resistor_max_ohm
        if lo is not None or hi is not None:
            add("Braking resistor: resistance window", f"{fmt_number(lo) if lo is not None else '-'} to "
                f"{fmt_number(hi) if hi is not None else '-'} ohm")
        suff = rg.builtin_resistor_sufficient
        add("Built-in resistor sufficient", {True: "yes", False: "no", None: "not known"}[suff],
            cls={True: "pass", False: "fail", None: "muted"}[suff])
    return Table("electrical", "Drive, motor current, winding temperature and regeneration",
                 ["", "value / available", "required", "margin"], rows, "lrrr",
                 "Currents in A rms; checks from drivetrain.sizing.electrical and drive_select (docs/checks.md).",
                 [0.36, 0.34, 0.15, 0.15])
