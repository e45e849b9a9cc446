"""The tables of ``drivetrain modes``, ``drivetrain simulate`` and ``drivetrain machine size``.

Each takes the command's JSON-ready dictionary (the same one ``--json`` prints) and prints it with rich.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from drivetrain.cli.quantities import TableUnits
from drivetrain.terminal import Col, print_table, table_console

if TYPE_CHECKING:
    from drivetrain.sizing.axis_blocks import Modes


def bus_window(b: dict[str, Any]) -> str:
    """A DC bus's braking-resistor window in one cell, from the formula of the order sheet
    (``sizing.order_spec.resistor_spec``: the drives' largest minimum resistance, and U_on^2 / P_peak at the
    lowest switch-on voltage, else at the nominal DC bus, a safe lower bound); where a bound is not known the
    cell says why."""
    from drivetrain.sizing.order_spec import resistor_spec

    if not b.get("resistor_needed"):
        return "none needed"
    spec, _ = resistor_spec(b["resistor_peak_power_W"], b["resistor_average_power_W"],
                            b["resistor_energy_per_cycle_J"], None, b.get("resistor_min_ohm"),
                            b.get("resistor_max_ohm"), None, b.get("dc_bus_voltage_V"))
    lo, hi = spec["resistance_min_ohm"], spec["resistance_max_ohm"]
    low = "no drive minimum given" if lo is None else f"{lo:.4g}"
    high = "no bus voltage" if hi is None else f"{hi:.4g}"
    at_bus = " (max at U_bus)" if hi is not None and b.get("resistor_max_ohm") is None else ""
    return f"{low} .. {high} ohm{at_bus}"


def print_machine(out: dict[str, Any]) -> None:
    """The machine: its axes, DC buses, phasing and bill of materials."""
    console = table_console()
    m = out["machine"]
    console.print(f"[bold]{m['name']}[/]: cycle {m['cycle_time_s']:.4g} s, supply {m['supply_voltage_V']:.0f} V "
                  f"{m['supply_phases']}-phase; " + ("[green]ok[/]" if m["ok"] else "[bold red]FAILS[/]"))
    rows: list[tuple[str, ...]] = []
    for a in out["axes"]:
        rows.append((a["name"], " + ".join(f"{s * 100:.0f} %" for s in a["load_shares"]) if a["motors"] > 1 else "1",
                  f"{a['offset_s']:.4g} s ({a['phasing']})", a["power_basis"], f"{a['peak_power_W']:.4g} W",
                  f"{a['regen_energy_J']:.4g} J", "yes" if a["ok"] else "NO"))
    print_table(console, "axes", (Col("axis"), Col("motors", number=True), Col("start"), Col("power basis"),
                                  Col("peak power", number=True), Col("regen", number=True), Col("ok")), rows)
    rows = []  # the DC buses
    for b in out["buses"]:
        window = bus_window(b)
        rows.append((b["name"], ", ".join(b["axes"]), f"{b['bus_peak_power_W']:.4g} W",
                     f"{b['bus_rms_power_W']:.4g} W", f"{b['regen_shared_J']:.4g} J",
                     f"{b['resistor_energy_per_cycle_J']:.4g} J",
                     f"{b['resistor_peak_power_W']:.4g} / {b['resistor_average_power_W']:.4g} W", window,
                     f"{b['supply_peak_power_W']:.4g} / {b['supply_continuous_power_W']:.4g} W"))
    print_table(console, "DC buses", (
        Col("bus"), Col("axes"), *(Col(n, number=True) for n in (
            "peak", "RMS", "shared regen", "resistor J/cycle", "resistor peak / avg", "R window",
            "supply peak / cont."))), rows)
    ph = out.get("phasing")
    if ph:
        r = ph["random"]
        console.print(f"phasing of {', '.join(ph['free_axes'])}: in phase peak "
                      f"{ph['in_phase']['bus_peak_power_W']:.4g} W;"
                      f" random ({ph['samples']} samples, seed {ph['seed']}) peak p50 "
                      f"{r['bus_peak_power_W']['p50']:.4g} W, p95 {r['bus_peak_power_W']['p95']:.4g} W, max "
                      f"{r['bus_peak_power_W']['p100']:.4g} W")
    rows = [(row["kind"], str(row["order_code"] or row.get("note", "-")), str(row["vendor"] or "-"),
             str(row["quantity"]), ", ".join(row["used_by"])) for row in out["bill_of_materials"]]
    print_table(console, "bill of materials", (Col("kind"), Col("order code"), Col("vendor", abbreviate=True),
                                               Col("qty", number=True), Col("used by")), rows)


def print_modes(out: dict[str, Any], inertias: int, units: TableUnits | None = None,
                modes: Modes | None = None) -> None:
    """Natural frequencies, resonance, critical speeds and (``modes``, the JSON's ``out["modes"]``) the first
    mode across the stroke."""
    console = table_console()
    u = units or TableUnits()
    console.print(f"[bold]{out['axis']}[/] with motor {out['motor']}: {inertias} inertias at the motor shaft")
    if modes is not None:
        print_modes_across(console, modes, u)
    if not out["natural_frequencies_Hz"]:
        console.print("rigid drive train: no stiffness given (add stiffness to a coupling, gearbox or belt, or "
                      "a dynamics.chain), so there is no resonance to report")
        return
    # Two models when the mechanism has stiffness data: name each (the table above has the mechanism's spring)
    rigid = "motor and transmission, the mechanism rigid: " if modes is not None else ""
    console.print(f"{rigid}natural frequencies: " + ", ".join(f"{f:.1f} Hz" for f in out["natural_frequencies_Hz"]))
    console.print(f"{rigid}two-mass resonance {out['resonance_Hz']:.1f} Hz, anti-resonance "
                  f"{out['anti_resonance_Hz']:.1f} Hz")
    if modes is not None:
        console.print(f"with the mechanism's spring at its weakest position ({_position(modes.worst_position_m, u)}): "
                      "natural frequencies: " + ", ".join(f"{f:.1f} Hz" for f in modes.natural_frequencies_at_worst_Hz))
    for c in out.get("critical_speeds", []):
        console.print(f"critical speed: {c['excitation']} crosses {c['natural_frequency_Hz']:.1f} Hz at "
                      f"{c['speed_rpm']:.0f} rpm")


def _position(x: float, u: TableUnits) -> str:
    """A position on the stroke [m]: whole mm, or in the system's length unit."""
    return f"{x * 1e3:.0f} mm" if u.system == "si" else u.q(x, "length", "mm", spec=".3g")


def _stiffness(k: float, u: TableUnits) -> str:
    """A mechanism stiffness [N/m] in the system's unit, three significant digits, no exponent."""
    text = u.num(k, "linear_stiffness", spec=".3g")
    if "e" in text:
        text = f"{float(text):,.0f}"
    return f"{text} {u.unit('linear_stiffness', 'N/um')}"


def print_modes_across(console: Any, modes: Modes, u: TableUnits) -> None:
    console.print(f"with the mechanism's stiffness: lowest first mode {modes.f1_min_Hz:.1f} Hz at position "
                  f"{_position(modes.worst_position_m, u)}; weakest link: {modes.weakest_link}")
    rows = list(modes.f1_by_position)
    table = []
    for r in rows[:: max(1, len(rows) // 10)] + ([rows[-1]] if (len(rows) - 1) % max(1, len(rows) // 10) else []):
        k = r.axial_stiffness_N_per_m
        table.append((_position(r.position_m, u), f"{r.f1_Hz:.1f} Hz",
                      f"{k / 1e6:.3g} N/um" if u.system == "si" else _stiffness(k, u)))
    print_table(console, "first natural frequency across the stroke",
                tuple(Col(n, right=True, number=True) for n in ("position", "f1", "mechanism stiffness")), table)
    for c in modes.checks:
        if c.status == "unknown":
            console.print(f"{c.name}: f1 {c.available:.1f} Hz, [yellow]unknown[/]; {c.note}")
            continue
        verdict = "[green]ok[/]" if c.ok else "[red]FAIL[/]"
        console.print(f"{c.name}: f1 {c.available:.1f} Hz against {c.required:.1f} Hz required "
                      f"(margin {c.margin:+.0%}) {verdict}; {c.note}")


def print_simulation(out: dict[str, Any], units: TableUnits | None = None) -> None:
    """The closed-loop simulation in one table."""
    u = units or TableUnits()
    torque = u.unit("torque", "N*m")
    rows: list[tuple[str, str]] = [
        ("simulated time", f"{out['duration_s']:.3g} s"),
        ("max following error (motor)", f"{out['max_following_error_rad'] * 1e3:.4g} mrad"),
        ("max load position error", f"{out['max_load_error_rad'] * 1e3:.4g} mrad"),
        ("load vibration amplitude", f"{out['load_vibration_amplitude_rad'] * 1e3:.4g} mrad"),
    ]
    settle = [f"{v * 1e3:.1f} ms" if v is not None else "not settled" for v in out["settling_time_s"]]
    if "settling_window_m" in out:
        window = f"{out['settling_window_m'] * 1e6:.4g} um"
    else:
        window = f"{out['settling_window_rad'] * 180 / 3.141592653589793 * 60:.4g} arcmin"
    source = "" if out.get("settling_window_source") != "default" else ", default"
    rows += [
        (f"settling time per stop (load into {window}{source})", ", ".join(settle) or "no stop"),
        ("peak / RMS motor torque",
         f"{u.num(out['peak_torque_Nm'], 'torque')} / {u.num(out['rms_torque_Nm'], 'torque')} {torque}"),
        ("peak shaft torque per spring",
         ", ".join(u.num(v, "torque") for v in out["peak_shaft_torque_Nm"]) + f" {torque}"),
        ("motor energy", f"{out['energy_J']:.4g} J"),
    ]
    print_table(table_console(), f"{out['axis']}: closed-loop simulation",
                (Col("quantity"), Col("value", right=True, number=True)), rows)
