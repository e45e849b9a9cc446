"""The tables of a sizing result (``drivetrain size`` and ``select``): demand, checks, electrical, candidates."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from drivetrain.cli.order import print_result_order
from drivetrain.cli.quantities import TableUnits
from drivetrain.terminal import Col, print_table, table_console

if TYPE_CHECKING:
    from drivetrain.sizing.answer import Candidate, CheckRow, SelectionSummary
    from drivetrain.sizing.electrical import DriveAnswer, Regen

__all__ = ["CANDIDATE_COLUMNS", "print_sizing", "table_console"]


def print_sizing(result: Any, units: TableUnits | None = None) -> None:
    """The demand at the axis input (the motor shaft, unless the selection puts a catalog gearbox before it:
    then the selected motor's own figures too), every check block, and the ranked candidates with the
    selection."""
    from drivetrain.report.display import snapped_metrics

    u = units or TableUnits()
    console = table_console()
    m = snapped_metrics(result.metrics.to_dict())  # a figure that is zero to within round-off prints as 0
    torque = u.unit("torque", "N*m")
    rows = [
        ("cycle time", f"{m['cycle_time_s']:.4g} s"),
        ("load inertia", u.q(m["load_inertia_kgm2"], "inertia", "kg*cm^2", 1e4)),
        ("peak torque", f"{u.q(m['peak_torque_Nm'], 'torque', 'N*m')} at {m['peak_torque_speed_rpm']:.0f} rpm"),
        ("RMS torque", u.q(m["rms_torque_Nm"], "torque", "N*m")),
        ("accel / run / decel torque (move 1)",
         " / ".join(u.num(m[k], "torque") for k in ("accel_torque_Nm", "run_torque_Nm", "decel_torque_Nm"))
         + f" {torque}"),
        ("holding torque", u.q(m["holding_torque_Nm"], "torque", "N*m")),
        ("max / mean speed", f"{m['max_speed_rpm']:.0f} / {m['mean_speed_rpm']:.0f} rpm"),
        ("peak / average power", f"{m['peak_power_W']:.4g} / {m['average_power_W']:.4g} W"),
        ("regenerated energy per cycle", f"{m['regen_energy_J'] + 0.0:.4g} J"),
    ]
    for extra_key, label in (("gearbox_torque", "gearbox output torque"),):
        if extra_key in m:
            rows.append((label, str(m[extra_key])))
    rows += _motor_shaft_rows(result, u)
    print_table(console, _demand_title(result),
                (Col("quantity"), Col("value", right=True, number=True)), rows)
    mech = result.mechanism_checks
    if mech:  # printed as the motor's checks are, from their JSON
        _print_checks(console, f"mechanism {result.axis.mechanism.type}",
                      {"ok": all(c.ok for c in mech), "checks": [c.to_dict() for c in mech]}, u)
    if result.motor is not None:
        motor = result.motor
        _print_checks(console, f"motor {motor.name}", {"ok": motor.ok, "checks": [c.to_dict() for c in motor.checks]},
                      u)
        console.print(f"inertia ratio J_L/J_M = {motor.inertia_ratio:.3g} "
                      f"(lecture: below 5:1 recommended, 1:1 ideal); "
                      f"t_am = {motor.min_accel_time_s:.4g} s, t_dm = {motor.min_decel_time_s:.4g} s")
        _print_electrical(console, result, u)
    gear = result.gearbox_checks
    if gear is not None:
        _print_checks(console, "gearbox ratings (transmission)", gear.to_dict(), u)
    if result.candidates:
        _print_candidates(console, result, u)
    print_result_order(console, result, u)


def _motor_shaft_rows(result: Any, u: TableUnits) -> list[tuple[str, str]]:
    """Where the selection puts a catalog gearbox between the motor and the axis input, the selected motor's
    own figures at its shaft (speed x i; torque / (i eta) plus the gearbox input's and the rotor's inertia
    torque: ``SizingResult.motor_cycle``); nothing where the axis input is the motor shaft."""
    pick = result.selection.selected if result.selection is not None else None
    if pick is None or not pick.gearbox or result.axis.motor is not None:
        return []
    own = result.motor_cycle()
    if own is None:
        return []
    from drivetrain.duty.cycle import load_metrics
    from drivetrain.report.display import snapped_metrics

    cycle, rotor, _ = own
    m = snapped_metrics(load_metrics(cycle, cycle.motor_torque(rotor)))
    at = f"motor shaft (i = {pick.ratio:.4g})"
    return [
        (f"{at}: load inertia", u.q(cycle.load_inertia, "inertia", "kg*cm^2", 1e4)),
        (f"{at}: peak / RMS torque, rotor included", f"{u.num(m['peak_torque_Nm'], 'torque')} / "
                                                      f"{u.q(m['rms_torque_Nm'], 'torque', 'N*m')}"),
        (f"{at}: max / mean speed", f"{m['max_speed_rpm']:.0f} / {m['mean_speed_rpm']:.0f} rpm"),
    ]


def _demand_title(result: Any) -> str:
    """The demand table's title: at the axis input; and at the selected motor's shaft behind its catalog
    gearbox where the selection puts one there."""
    pick = result.selection.selected if result.selection is not None else None
    title = f"{result.axis.name}: demand at the axis input (rotor excluded)"
    if pick is not None and pick.gearbox and result.axis.motor is None:
        title += f"; at the shaft of {pick.motor} behind {pick.gearbox}"
    return title


def _pct(margin: float | None) -> str:
    if margin is None:
        return "n/a"
    p = margin * 100.0
    return f"{p:+.2g} %" if p != 0.0 and abs(p) < 0.1 else f"{p:+.1f} %"


CHECK_COLUMNS = (Col("check"), Col("required", right=True, number=True), Col("available", right=True, number=True),
                 Col("margin", right=True, number=True), Col("result", right=True, number=True))
"""The columns of a check block; none is left out to fit a terminal."""


def _print_checks(console: Any, title: str, block: dict[str, Any], u: TableUnits) -> None:
    rows: list[tuple[str, ...]] = []
    for c in block["checks"]:
        approx = " (approx. envelope)" if c.get("approximate") else ""
        stage = f" [{c['stage']}]" if c.get("stage") else ""
        status = c.get("status") or ("pass" if c["ok"] else "fail")
        rows.append((c["name"] + stage + approx, u.check(c["required"], c["unit"]),
                     u.check(c["available"], c["unit"]), _pct(c["margin"]),
                     {"pass": "yes", "fail": "NO"}.get(status, status)))
    print_table(console, f"{title}: {'OK' if block['ok'] else 'FAILS'}", CHECK_COLUMNS, rows)
    for c in block["checks"]:
        if c.get("note"):
            console.print(f"  {c['name']}: {c['note']}")


def _print_electrical(console: Any, result: Any, u: TableUnits) -> None:
    """The electrical half of a given motor: supply, envelope source, currents, winding, drive, regen."""
    _print_electrical_blocks(console, result.motor.electrical, result.drive, result.regen, u)


def _drive_label(drive: DriveAnswer | None) -> str:
    """A candidate's drive in one cell: its id and status (unknown / none / fails)."""
    if drive is None:
        return "-"
    status = drive.outcome
    return f"{drive.id or '-'}" + ("" if status == "ok" else f" ({status})")


def _print_selected_electrical(console: Any, pick: Candidate, u: TableUnits) -> None:
    """The selected candidate's drive, electrical figures and regen block (drivetrain.sizing.drive_select)."""
    drive = pick.drive
    if drive is not None and drive.status in ("unknown", "none"):
        console.print(f"drive: {drive.id or 'none'} ({drive.status}: {drive.reason or ''})")
        drive = None
    elec = pick.electrical or {}
    if elec.get("note"):
        console.print(f"electrical: {elec['note']}")
    _print_electrical_blocks(console, {**elec, "checks": elec.get("checks", [])}, drive, pick.regen, u)
    if elec.get("checks"):
        _print_checks(console, f"motor {pick.motor} electrical",
                      {"ok": all(c["ok"] for c in elec["checks"]), "checks": elec["checks"]}, u)


def _print_electrical_blocks(console: Any, m: dict[str, Any], drive: DriveAnswer | None,
                             rg: Regen | None, u: TableUnits) -> None:
    if m.get("rms_current_A") is None:
        if rg is not None:
            _print_regen(console, rg)
        if drive is not None:
            _print_drive(console, drive, u)
        return
    bus = m.get("dc_bus_voltage_V")
    supply = m.get("supply_voltage_V")
    where = (f"supply {supply:.0f} V, DC bus {bus:.0f} V" if supply and bus else
             (f"DC bus {bus:.0f} V" if bus else "supply voltage not given"))
    console.print(f"{where}; envelope: {m['envelope_source']}")
    console.print(f"motor current: RMS {m['rms_current_A']:.4g} A, peak {m['peak_current_A']:.4g} A "
                  f"(Kt {u.num(m['torque_constant_NmA'], 'torque')} {u.unit('torque', 'N*m')}/A)")
    rise = m.get("winding_temperature_rise_K")
    if rise is not None:
        console.print(f"winding temperature rise {rise:.4g} K (allowed {m['winding_allowed_rise_K']:.4g} K at "
                      f"{m['ambient_degC']:g} degC, {m['altitude_m']:g} m)")
    if drive is not None:
        _print_drive(console, drive, u)
    if rg is not None:
        _print_regen(console, rg)


def _print_drive(console: Any, drive: DriveAnswer, u: TableUnits) -> None:
    """The drive's checks, and why its ratings are not traced where the catalog flags it (data/SOURCES.md)."""
    _print_checks(console, f"drive {drive.id}", {"ok": drive.ok, "checks": list(drive.checks or ())}, u)
    if drive.unverified:
        console.print(f"drive {drive.id} †: {drive.unverified_reason}")


def _print_regen(console: Any, rg: Regen) -> None:
    window = (f", resistance {rg.resistor_min_ohm or 0:.4g} to {rg.resistor_max_ohm:.4g} ohm"
              if rg.resistor_max_ohm is not None else "")
    builtin = {True: "; built-in resistor suffices", False: "; built-in resistor does NOT suffice",
               None: ""}[rg.builtin_resistor_sufficient]
    console.print(f"regeneration into the bus {rg.energy_per_cycle_J:.4g} J per cycle, capacitors "
                  f"{rg.capacitor_absorbed_J:.4g} J; braking resistor {rg.resistor_energy_per_cycle_J:.4g} J "
                  f"per cycle, peak {rg.resistor_peak_power_W:.4g} W, average "
                  f"{rg.resistor_average_power_W:.4g} W{window}{builtin}")


def _mounting(c: Candidate, sel: SelectionSummary | None) -> str:
    """How the motor drives the axis: a catalog gearbox, the axis's own gearbox, or direct."""
    if c.gearbox:
        return f"{c.gearbox} (i = {c.ratio:.4g})"
    if sel is not None and sel.transmission_gearbox:
        return "axis gearbox"
    return "direct"


CANDIDATE_COLUMNS = (
    Col("rank", number=True), Col("motor"), Col("vendor", drop=3, abbreviate=True), Col("power", number=True, drop=2),
    Col("flange", number=True, drop=1), Col("gearbox"), Col("J_L/J_M", number=True, drop=4),
    Col("peak margin", number=True), Col("RMS margin", number=True), Col("result / why not"), Col("drive", drop=5))
"""The candidate table's columns. To fit a narrow terminal the vendor is abbreviated, then flange, power,
vendor, J_L/J_M and drive are left out in that order (docs/architecture.md, "Terminal output")."""


def _drive_unknown(drive: Any) -> bool:
    """Whether a candidate's drive could not be judged (status ``unknown`` or ``none``): an unknown of the
    verdict (``sizing.verdict``), so a passing row says ``yes, unknown: drive``."""
    return getattr(drive, "status", None) in ("unknown", "none")


def _print_candidates(console: Any, result: Any, u: TableUnits) -> None:
    sel: SelectionSummary | None = result.selection

    def count(name: str) -> str:  # a count the smallest-first search leaves out: "?"
        n = None if sel is None else getattr(sel, name)
        return "?" if n is None else str(n)

    per = ("every passing pair" if sel is not None and sel.listing == "all_pairs"
           else "best configuration of each motor")
    title = (f"candidates: {count('passing')} of {count('evaluated')} configurations pass, "
             f"{count('passing_motors')} motors (ranked by {count('objective')}; {per}; "
             "rejected ones below with the reason)")
    rows: list[tuple[str, ...]] = []
    c: Candidate
    for c in result.candidates:
        if c.ok:
            unknown = [*c.unknown, *(["drive"] if _drive_unknown(c.drive) else [])]
            why = "yes" if not unknown else "yes, unknown: " + ", ".join(unknown)
        else:
            bad = sorted((ch for ch in c.checks if ch.status == "fail"),
                         key=lambda ch: (ch.name != "max_speed", ch.margin or 0.0))
            why = "\n".join(f"{ch.name} {_pct(ch.margin)}" for ch in bad) or c.failed
        power = c.rated_power_W
        motor = c.motor + (" †" if c.unverified else "")
        peak, rms = c.check("peak_torque"), c.check("rms_torque")
        rows.append((str(c.rank) if c.rank else "-", motor, c.vendor,
                     "" if power is None or math.isnan(power) else f"{power:.0f} W",
                     _flange(c.flange_mm, u), _mounting(c, sel),
                     f"{c.inertia_ratio:.3g}", _pct(None if peak is None else peak.margin),
                     _pct(None if rms is None else rms.margin), why, _drive_label(c.drive)))
    print_table(console, title, CANDIDATE_COLUMNS, rows)
    if any(c.unverified for c in result.candidates):
        console.print("† unverified catalog data (not traced to a vendor document, or a derived rating): "
                      "see unverified_reason in --json, or `drivetrain catalog show ID`")
    if sel is None:
        return
    if sel.selected is not None:
        pick = sel.selected
        how = (f" + {pick.gearbox} ({pick.gearbox_vendor or 'catalog'}, i = {pick.ratio:.4g})"
               if pick.gearbox else (f", on the axis's {sel.transmission_gearbox}"
                                     if sel.transmission_gearbox else ", direct drive"))
        console.print(f"selected: {pick.motor} ({pick.vendor}){how}")
        if sel.drive_advice:
            console.print(f"[bold red]not orderable: {sel.drive_advice}[/]")
        else:
            for over in (sel.drive_passed_over or [])[:5]:
                what = {"dynamics": "how it moves"}.get(over.drive_status, "its drive")
                if over.reason.startswith("voltage_class:"):
                    what = "its voltage class"
                console.print(f"  passed over for {what}: {over.motor}: {over.reason}")
            more = (sel.drive_passed_over_count or 0) - 5
            if more > 0:
                console.print(f"  ... and {more} more passed over for their drive (selection.drive_passed_over)")
        dyn = sel.dynamics
        if dyn and dyn.get("chosen"):
            from drivetrain.report.dynamics import inertia_sentence

            console.print(f"dynamics of {dyn['chosen']['motor']} ({dyn['judged']} candidate(s) judged): "
                          + "; ".join(f"{ch['name']} {ch['status']}: {ch['note']}" for ch in dyn["chosen"]["checks"]))
            decided = inertia_sentence(result)
            if decided:
                console.print(f"  {decided}")
        elif dyn:
            console.print(f"[bold red]dynamics: none of the {dyn['judged']} candidates judged passes[/]")
        _print_selected_electrical(console, pick, u)
        if pick.unknown:
            console.print("  not judged (the catalog lacks the data): "
                          + "; ".join(f"{ch.name}: {ch.note or ''}" for ch in pick.checks if ch.status == "unknown"))
        if sel.unverified:
            console.print(f"  {sel.unverified}")
        nxt = sel.next_smaller
        if nxt is not None:
            console.print(f"next smaller motor {nxt.motor} fails:")
            checks = {ch.name: ch for ch in nxt.checks}
            for line in nxt.failures or [nxt.failed]:
                console.print(f"  {_failure(line, checks, u)}")
        opt = sel.optimal_ratio
        if opt is not None:
            near = opt.nearest_catalog_ratio
            console.print(f"optimal ratio for {opt.motor}: {opt.min_rms_ratio:.3g} (min RMS), "
                          f"{opt.inertia_match_ratio:.3g} (inertia match)"
                          + (f", nearest catalog ratio {near:g}" if near else ""))
        if dyn and dyn.get("settling_optimal_ratio"):
            from drivetrain.report.dynamics import settling_ratio_sentence

            console.print(settling_ratio_sentence(dyn))
    elif sel.advice:
        for line in sel.advice.splitlines():
            console.print(f"[bold red]{line}[/]")


def _flange(flange: float | None, u: TableUnits) -> str:
    """A motor's flange size [mm as the catalog gives it]."""
    if flange is None:
        return ""
    return f"{flange:.0f} mm" if u.system == "si" else u.q(flange * 1e-3, "length", "mm", spec=".3g")


def _failure(line: str, checks: dict[str, CheckRow], u: TableUnits) -> str:
    """A failing check's sentence (drivetrain.sizing.reasons, SI) in the table's units."""
    from drivetrain.sizing.reasons import percent

    ch = checks.get(line.split(":", 1)[0])
    if ch is None or ch.name == "mechanical_fit" or ch.margin is None or not u.converts(ch.unit):
        return line
    avail = "n/a" if ch.available is None else u.check(ch.available, ch.unit)
    return f"{ch.name}: required {u.check(ch.required, ch.unit)} > available {avail} ({percent(ch.margin)})"
