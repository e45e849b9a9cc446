"""The tables of ``drivetrain modes``, ``drivetrain simulate`` and ``drivetrain machine size``.

Each takes the command's JSON-ready dictionary (the same one ``--json`` prints) and prints it with rich.
"""

from __future__ import annotations

import sys
from typing import Any

from drivetrain.cli.quantities import TableUnits


def print_machine(out: dict[str, Any]) -> None:
    """The machine: its axes, DC buses, phasing and bill of materials."""
    from rich.console import Console
    from rich.table import Table

    console = Console(width=None if sys.stdout.isatty() else 120)
    m = out["machine"]
    console.print(f"[bold]{m['name']}[/]: cycle {m['cycle_time_s']:.4g} s, supply {m['supply_voltage_V']:.0f} V "
                  f"{m['supply_phases']}-phase; " + ("[green]ok[/]" if m["ok"] else "[bold red]FAILS[/]"))
    t = Table(title="axes")
    for col in ("axis", "motors", "start", "power basis", "peak power", "regen", "ok"):
        t.add_column(col)
    for a in out["axes"]:
        t.add_row(a["name"], " + ".join(f"{s * 100:.0f} %" for s in a["load_shares"]) if a["motors"] > 1 else "1",
                  f"{a['offset_s']:.4g} s ({a['phasing']})", a["power_basis"], f"{a['peak_power_W']:.4g} W",
                  f"{a['regen_energy_J']:.4g} J", "yes" if a["ok"] else "NO")
    console.print(t)
    t = Table(title="DC buses")
    for col in ("bus", "axes", "peak", "RMS", "shared regen", "resistor J/cycle", "resistor peak / avg", "R window",
                "supply peak / cont."):
        t.add_column(col)
    for b in out["buses"]:
        lo, hi = b.get("resistor_min_ohm"), b.get("resistor_max_ohm")
        window = f"{f'{lo:.4g}' if lo is not None else '-'} .. {f'{hi:.4g}' if hi is not None else '-'} ohm"
        t.add_row(b["name"], ", ".join(b["axes"]), f"{b['bus_peak_power_W']:.4g} W", f"{b['bus_rms_power_W']:.4g} W",
                  f"{b['regen_shared_J']:.4g} J", f"{b['resistor_energy_per_cycle_J']:.4g} J",
                  f"{b['resistor_peak_power_W']:.4g} / {b['resistor_average_power_W']:.4g} W", window,
                  f"{b['supply_peak_power_W']:.4g} / {b['supply_continuous_power_W']:.4g} W")
    console.print(t)
    ph = out.get("phasing")
    if ph:
        r = ph["random"]
        console.print(f"phasing of {', '.join(ph['free_axes'])}: in phase peak "
                      f"{ph['in_phase']['bus_peak_power_W']:.4g} W;"
                      f" random ({ph['samples']} samples, seed {ph['seed']}) peak p50 "
                      f"{r['bus_peak_power_W']['p50']:.4g} W, p95 {r['bus_peak_power_W']['p95']:.4g} W, max "
                      f"{r['bus_peak_power_W']['p100']:.4g} W")
    t = Table(title="bill of materials")
    for col in ("kind", "order code", "vendor", "qty", "used by"):
        t.add_column(col)
    for row in out["bill_of_materials"]:
        t.add_row(row["kind"], str(row["order_code"] or row.get("note", "-")), str(row["vendor"] or "-"),
                  str(row["quantity"]), ", ".join(row["used_by"]))
    console.print(t)


def print_modes(out: dict[str, Any], inertias: int, units: TableUnits | None = None) -> None:
    """Natural frequencies, resonance, critical speeds and the first mode across the stroke."""
    from rich.console import Console

    console = Console(width=None if sys.stdout.isatty() else 120)
    u = units or TableUnits()
    console.print(f"[bold]{out['axis']}[/] with motor {out['motor']}: {inertias} inertias at the motor shaft")
    if "modes" in out:
        print_modes_across(console, out["modes"], u)
    if not out["natural_frequencies_Hz"]:
        console.print("rigid drive train: no stiffness given (add stiffness to a coupling, gearbox or belt, or "
                      "a dynamics.chain), so there is no resonance to report")
        return
    # Two models when the mechanism has stiffness data: name each (the table above has the mechanism's spring)
    rigid = "motor and transmission, the mechanism rigid: " if "modes" in out else ""
    console.print(f"{rigid}natural frequencies: " + ", ".join(f"{f:.1f} Hz" for f in out["natural_frequencies_Hz"]))
    console.print(f"{rigid}two-mass resonance {out['resonance_Hz']:.1f} Hz, anti-resonance "
                  f"{out['anti_resonance_Hz']:.1f} Hz")
    if "modes" in out:
        m = out["modes"]
        console.print(f"with the mechanism's spring at its weakest position ({_position(m['worst_position_m'], u)}): "
                      "natural frequencies: " + ", ".join(f"{f:.1f} Hz" for f in m["natural_frequencies_at_worst_Hz"]))
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


def print_modes_across(console: Any, modes: dict[str, Any], u: TableUnits) -> None:
    from rich.table import Table

    console.print(f"with the mechanism's stiffness: lowest first mode {modes['f1_min_Hz']:.1f} Hz at position "
                  f"{_position(modes['worst_position_m'], u)}; weakest link: {modes['weakest_link']}")
    rows = modes["f1_by_position"]
    t = Table(title="first natural frequency across the stroke")
    for col in ("position", "f1", "mechanism stiffness"):
        t.add_column(col, justify="right")
    for r in rows[:: max(1, len(rows) // 10)] + ([rows[-1]] if (len(rows) - 1) % max(1, len(rows) // 10) else []):
        k = r["axial_stiffness_N_per_m"]
        t.add_row(_position(r["position_m"], u), f"{r['f1_Hz']:.1f} Hz",
                  f"{k / 1e6:.3g} N/um" if u.system == "si" else _stiffness(k, u))
    console.print(t)
    for c in modes.get("checks", []):
        if c.get("status") == "unknown":
            console.print(f"{c['name']}: f1 {c['available']:.1f} Hz, [yellow]unknown[/]; {c['note']}")
            continue
        verdict = "[green]ok[/]" if c["ok"] else "[red]FAIL[/]"
        console.print(f"{c['name']}: f1 {c['available']:.1f} Hz against {c['required']:.1f} Hz required "
                      f"(margin {c['margin']:+.0%}) {verdict}; {c['note']}")


def print_simulation(out: dict[str, Any], units: TableUnits | None = None) -> None:
    """The closed-loop simulation in one table."""
    from rich.console import Console
    from rich.table import Table

    u = units or TableUnits()
    torque = u.unit("torque", "N*m")

    t = Table(title=f"{out['axis']}: closed-loop simulation")
    t.add_column("quantity")
    t.add_column("value", justify="right")
    t.add_row("simulated time", f"{out['duration_s']:.3g} s")
    t.add_row("max following error (motor)", f"{out['max_following_error_rad'] * 1e3:.4g} mrad")
    t.add_row("max load position error", f"{out['max_load_error_rad'] * 1e3:.4g} mrad")
    t.add_row("load vibration amplitude", f"{out['load_vibration_amplitude_rad'] * 1e3:.4g} mrad")
    settle = [f"{v * 1e3:.1f} ms" if v is not None else "not settled" for v in out["settling_time_s"]]
    if "settling_window_m" in out:
        window = f"{out['settling_window_m'] * 1e6:.4g} um"
    else:
        window = f"{out['settling_window_rad'] * 180 / 3.141592653589793 * 60:.4g} arcmin"
    source = "" if out.get("settling_window_source") != "default" else ", default"
    t.add_row(f"settling time per stop (load into {window}{source})", ", ".join(settle) or "no stop")
    t.add_row("peak / RMS motor torque",
              f"{u.num(out['peak_torque_Nm'], 'torque')} / {u.num(out['rms_torque_Nm'], 'torque')} {torque}")
    t.add_row("peak shaft torque per spring",
              ", ".join(u.num(v, "torque") for v in out["peak_shaft_torque_Nm"]) + f" {torque}")
    t.add_row("motor energy", f"{out['energy_J']:.4g} J")
    Console(width=None if sys.stdout.isatty() else 120).print(t)
