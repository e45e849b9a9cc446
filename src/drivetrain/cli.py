"""Command line: ``drivetrain size AXIS``, ``drivetrain catalog ...``, ``drivetrain modes AXIS`` ...

No physics here: each command calls the library and formats its result. Bad input prints one
line naming the field and exits with status 2, without a traceback; ``size`` and ``select`` exit 0
when the motor or the selection passes and 1 when the axis was sized but nothing passes. Heavy modules are
imported inside the handlers so ``drivetrain --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

EXIT_OK = 0
"""``size``/``select``: the given motor, or the selection, passes every check."""
EXIT_FAILS = 1
"""``size``/``select``: sized, but the motor (or every candidate, or an axis check) fails; the answer is printed."""
EXIT_INPUT = 2
"""Bad input: one line naming the field, no traceback."""


CORE_COMMANDS = ("size", "select", "modes", "simulate", "machine")
"""Sub-commands defined here; the others live with their subsystem (catalog, serve, sweep ...)."""


def build_parser(optional: bool = True) -> argparse.ArgumentParser:
    """The argument parser with every sub-command (``optional=False``: only ``CORE_COMMANDS``, so a
    ``size`` does not import the study, web and catalog command modules to build its parser)."""
    parser = argparse.ArgumentParser(prog="drivetrain", description="Size and analyse servo axes.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    parser.add_argument("--catalog", dest="user_catalog", metavar="FILE.sqlite",
                        help="your catalog file, e.g. one a team shares (default: $DRIVETRAIN_CATALOG, else "
                             "user.sqlite in the data folder); the shipped data is read beside it")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("size", help="duty cycle at the motor shaft, motor checks and selection")
    p.add_argument("axis", help="axis file (YAML)")
    p.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    p.add_argument("--csv", metavar="FILE", help="write the sampled time series to FILE")
    p.add_argument("--report", metavar="FILE", help="write an HTML (.html) or PDF (.pdf) report")
    p.add_argument("--units", choices=["si", "imperial", "as-given"], default="si", help="units of the report")
    p.add_argument("--explain", metavar="MODEL", help="say why a catalog motor was accepted or rejected")
    p.add_argument("--points", type=int, default=64, help="samples per profile phase (default 64)")
    p.add_argument("--all", action="store_true",
                   help="list every passing motor-gearbox pair, not only the best configuration of each motor")
    p.add_argument("--aas", metavar="FILE", help="write an IDTA 02021 sizing submodel (AAS JSON) to FILE")
    p.set_defaults(handler=_cmd_size)

    p = sub.add_parser("select", help="same as size, with a catalog selection even if the axis names a motor")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true")
    p.add_argument("--top", type=int, default=10)
    p.set_defaults(handler=_cmd_select)

    p = sub.add_parser("modes", help="natural frequencies, two-mass resonance and critical speeds of the axis")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true", help="print only the JSON on standard output")
    p.set_defaults(handler=_cmd_modes)

    p = sub.add_parser("simulate", help="closed-loop nonlinear simulation of the axis on its own profile")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true", help="print only the JSON on standard output")
    p.add_argument("--csv", metavar="FILE", help="write the simulated time series to FILE")
    p.add_argument("--plot", metavar="FILE", help="write a figure (PNG, PDF or SVG) to FILE")
    p.add_argument("--cycles", type=int, default=None, help="profile repetitions (default: dynamics.cycles or 1)")
    p.add_argument("--bandwidth", type=float, default=None, help="velocity-loop bandwidth [Hz] (default: tuned)")
    p.set_defaults(handler=_cmd_simulate)

    p = sub.add_parser("machine", help="machine projects: several axes on shared DC buses, one report and BOM")
    msub = p.add_subparsers(dest="machine_command", metavar="ACTION", required=True)
    q = msub.add_parser("size", help="size every axis, the DC bus(es), braking resistors and supply; BOM")
    q.add_argument("machine", help="machine file (YAML, docs/machine.md)")
    q.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    q.add_argument("--report", metavar="FILE", help="write an HTML (.html) or PDF (.pdf) machine report")
    q.add_argument("--aas", metavar="FILE", help="write an IDTA 02021 sizing submodel (AAS JSON) to FILE")
    q.add_argument("--samples", type=int, default=500, help="random-phasing samples for free axes (default 500)")
    q.add_argument("--seed", type=int, default=0, help="seed of the random phasing (default 0)")
    q.set_defaults(handler=_cmd_machine_size)

    if optional:
        _optional_parser(sub, "drivetrain.catalog.cli")
        _optional_parser(sub, "drivetrain.web.cli")
        _optional_parser(sub, "drivetrain.study.cli")
    return parser


def _command(argv: Sequence[str]) -> str | None:
    """The sub-command named in ``argv`` (the first word that is not an option or --catalog's value)."""
    skip = False
    for word in argv:
        if skip:
            skip = False
        elif word == "--catalog":
            skip = True
        elif not word.startswith("-"):
            return word
    return None


def _optional_parser(sub: Any, module: str) -> None:
    """Register a sub-command group that lives with its subsystem."""
    import importlib

    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and module.startswith(exc.name):
            return
        raise
    mod.add_parser(sub)


def _write_atomic(path: str, text: str, field: str = "--csv") -> None:
    """Write a file through a unique temporary sibling and rename, so a reader never sees half of it."""
    from drivetrain.report import write_atomic

    def write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    write_atomic(path, write, field)


PLOT_SUFFIXES = (".png", ".svg", ".pdf")
"""Figure formats ``simulate --plot`` writes, chosen by the file's suffix."""


def _check_outputs(args: argparse.Namespace) -> None:
    """Refuse an output path that cannot be written before the work that fills it."""
    if not any(getattr(args, name, None) for name in ("csv", "report", "plot")):
        return
    from drivetrain.report import REPORT_SUFFIXES, check_target

    for name in ("csv", "report", "plot"):
        path = getattr(args, name, None)
        if path:
            check_target(path, f"--{name}")
    report = getattr(args, "report", None)
    if report and Path(report).suffix.lower() not in REPORT_SUFFIXES:
        from drivetrain.errors import InputError

        raise InputError("--report", "must end in .html or .pdf", report)
    plot = getattr(args, "plot", None)
    if plot and Path(plot).suffix.lower() not in PLOT_SUFFIXES:
        from drivetrain.errors import InputError

        raise InputError("--plot", f"must end in {', '.join(PLOT_SUFFIXES)}", plot)


def _cmd_size(args: argparse.Namespace) -> int:
    from drivetrain.errors import InputError
    from drivetrain.sizing.result import size

    if args.points < 3 or args.points > 100_000:
        raise InputError("--points", "must be between 3 and 100000", args.points)
    _check_outputs(args)
    try:
        result = size(args.axis, points_per_phase=args.points, all_pairs=args.all)
    except InputError as exc:
        if exc.field == "points_per_phase":
            raise InputError("--points", exc.rule, args.points) from None
        raise
    explanation = result.explain(args.explain) if args.explain else ""
    if args.csv:
        _write_csv(args.csv, result.series())
    if args.report:
        from drivetrain.report import write_report

        write_report(result, args.report, units=args.units)
    if args.aas:
        from drivetrain.machine.aas import axis_aas

        _write_atomic(args.aas, json.dumps(axis_aas(_jsonable(result.to_dict())), indent=2))
    if args.json:
        print(json.dumps(_jsonable(result.to_dict()), indent=2))
        return _exit_code(result)
    _print_table(result)
    for warning in result.extras.get("warnings", []):
        print(f"warning: {warning}")
    if explanation:
        print(explanation)
    if args.csv:
        print(f"time series written to {args.csv}")
    if args.report:
        print(f"report written to {Path(args.report).resolve()}")
    return _exit_code(result)


def _exit_code(result: Any) -> int:
    """0 when the given motor or the selection (and the axis's own checks) pass, 1 when not."""
    return EXIT_OK if result.ok else EXIT_FAILS


def _cmd_machine_size(args: argparse.Namespace) -> int:
    from drivetrain.machine.result import size_machine

    result = size_machine(args.machine, phasing_samples=args.samples, seed=args.seed)
    out = _jsonable(result.to_dict())
    if args.aas:
        from drivetrain.machine.aas import machine_aas

        _write_atomic(args.aas, json.dumps(machine_aas(out), indent=2))
    if args.report:
        from drivetrain.report.machine import write_machine_report

        write_machine_report(result, args.report)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    _print_machine(out)
    if args.report:
        print(f"report written to {Path(args.report).resolve()}")
    if args.aas:
        print(f"AAS submodel written to {Path(args.aas).resolve()}")
    return 0


def _print_machine(out: dict[str, Any]) -> None:
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


def _cmd_modes(args: argparse.Namespace) -> int:
    from drivetrain.axis.model import load_axis
    from drivetrain.dynamics import modes_summary
    from drivetrain.dynamics.axis_model import model
    from drivetrain.dynamics.linear import critical_speeds, excitation_orders

    axis = load_axis(args.axis)
    dyn = model(axis)
    out: dict[str, Any] = {"axis": axis.name, "motor": dyn.motor, **modes_summary(dyn.chain)}
    if axis.spec.profile and out["natural_frequencies_Hz"]:
        from drivetrain.duty.cycle import duty_cycle

        ratio = math.prod(s.ratio for s in dyn.stages) / axis.total_ratio
        top = float(abs(duty_cycle(axis).omega).max()) * ratio
        out["critical_speeds"] = [
            {"excitation": c.excitation, "order": c.order, "speed_rpm": c.speed_rad_s * 60 / (2 * math.pi),
             "natural_frequency_Hz": c.frequency_hz}
            for c in critical_speeds(out["natural_frequencies_Hz"], 0.0, top, excitation_orders())]
    if axis.spec.profile and "chain" not in (axis.spec.dynamics or {}):
        from drivetrain.dynamics.mechanism_modes import modes_across_stroke

        across = modes_across_stroke(axis, dyn.stages, dyn.motor_inertia)
        if across is not None:
            out["modes"] = across
    if args.json:
        print(json.dumps(_jsonable(out), indent=2))
        return 0
    from rich.console import Console

    console = Console(width=None if sys.stdout.isatty() else 120)
    console.print(f"[bold]{axis.name}[/] with motor {dyn.motor}: {len(dyn.chain.inertia)} inertias at the motor shaft")
    if "modes" in out:
        _print_modes_across(console, out["modes"])
    if not out["natural_frequencies_Hz"]:
        console.print("rigid drive train: no stiffness given (add stiffness to a coupling, gearbox or belt, or "
                      "a dynamics.chain), so there is no resonance to report")
        return 0
    console.print("natural frequencies: " + ", ".join(f"{f:.1f} Hz" for f in out["natural_frequencies_Hz"]))
    console.print(f"two-mass resonance {out['resonance_Hz']:.1f} Hz, anti-resonance {out['anti_resonance_Hz']:.1f} Hz")
    for c in out.get("critical_speeds", []):
        console.print(f"critical speed: {c['excitation']} crosses {c['natural_frequency_Hz']:.1f} Hz at "
                      f"{c['speed_rpm']:.0f} rpm")
    return 0


def _print_modes_across(console: Any, modes: dict[str, Any]) -> None:
    from rich.table import Table

    console.print(f"with the mechanism's stiffness: lowest first mode {modes['f1_min_Hz']:.1f} Hz at position "
                  f"{modes['worst_position_m'] * 1e3:.0f} mm; weakest link: {modes['weakest_link']}")
    rows = modes["f1_by_position"]
    t = Table(title="first natural frequency across the stroke")
    for col in ("position", "f1", "mechanism stiffness"):
        t.add_column(col, justify="right")
    for r in rows[:: max(1, len(rows) // 10)] + ([rows[-1]] if (len(rows) - 1) % max(1, len(rows) // 10) else []):
        t.add_row(f"{r['position_m'] * 1e3:.0f} mm", f"{r['f1_Hz']:.1f} Hz",
                  f"{r['axial_stiffness_N_per_m'] / 1e6:.3g} N/um")
    console.print(t)
    for c in modes.get("checks", []):
        verdict = "[green]ok[/]" if c["ok"] else "[red]FAIL[/]"
        console.print(f"{c['name']}: f1 {c['available']:.1f} Hz against {c['required']:.1f} Hz required "
                      f"(margin {c['margin']:+.0%}) {verdict}; {c['note']}")


def _cmd_simulate(args: argparse.Namespace) -> int:
    from drivetrain.axis.model import load_axis
    from drivetrain.dynamics.axis_model import simulate_axis

    _check_outputs(args)
    axis = load_axis(args.axis)
    res = simulate_axis(axis, cycles=args.cycles, velocity_bandwidth_hz=args.bandwidth)
    out = {"axis": axis.name, **res.to_dict()}
    if args.csv:
        import io

        buf = io.StringIO()
        res.to_pandas().to_csv(buf)
        _write_atomic(args.csv, buf.getvalue(), "--csv")
    if args.plot:
        from drivetrain.report import write_atomic

        fig = res.plot()
        fmt = Path(args.plot).suffix.lower().lstrip(".")
        write_atomic(args.plot, lambda tmp: fig.savefig(tmp, dpi=120, format=fmt), "--plot")
    if args.json:
        print(json.dumps(_jsonable(out), indent=2))
        return 0
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"{axis.name}: closed-loop simulation")
    t.add_column("quantity")
    t.add_column("value", justify="right")
    t.add_row("simulated time", f"{out['duration_s']:.3g} s")
    t.add_row("max following error (motor)", f"{out['max_following_error_rad'] * 1e3:.4g} mrad")
    t.add_row("max load position error", f"{out['max_load_error_rad'] * 1e3:.4g} mrad")
    t.add_row("load vibration amplitude", f"{out['load_vibration_amplitude_rad'] * 1e3:.4g} mrad")
    settle = [f"{v * 1e3:.1f}" if v is not None else "-" for v in out["settling_time_s"]]
    t.add_row("settling time per stop", ", ".join(settle) + " ms")
    t.add_row("peak / RMS motor torque", f"{out['peak_torque_Nm']:.4g} / {out['rms_torque_Nm']:.4g} N*m")
    t.add_row("peak shaft torque per spring", ", ".join(f"{v:.4g}" for v in out["peak_shaft_torque_Nm"]) + " N*m")
    t.add_row("motor energy", f"{out['energy_J']:.4g} J")
    Console(width=None if sys.stdout.isatty() else 120).print(t)
    for path, what in ((args.csv, "time series"), (args.plot, "figure")):
        if path:
            print(f"{what} written to {Path(path).resolve()}")
    return 0


def _cmd_select(args: argparse.Namespace) -> int:
    from drivetrain.axis.model import load_axis
    from drivetrain.sizing.result import size

    axis = load_axis(args.axis)
    result = size(axis)
    if args.json:
        print(json.dumps(_jsonable(result.to_dict()), indent=2))
    else:
        _print_table(result)
    return _exit_code(result)


def _write_csv(path: str, cols: dict[str, Any]) -> None:
    import io

    import numpy as np

    names = list(cols)
    data = np.column_stack([np.asarray(cols[n], dtype=float) for n in names])
    buf = io.StringIO()
    np.savetxt(buf, data, delimiter=",", header=",".join(names), comments="", fmt="%.9g")
    _write_atomic(path, buf.getvalue())


def _jsonable(obj: Any) -> Any:
    """Plain JSON types; non-finite floats become null."""
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    return obj


def _print_table(result: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console(width=None if sys.stdout.isatty() else 120)
    m = result.metrics
    t = Table(title=f"{result.axis.name}: demand at the motor shaft (rotor excluded)")
    t.add_column("quantity")
    t.add_column("value", justify="right")
    rows = [
        ("cycle time", f"{m['cycle_time_s']:.4g} s"),
        ("load inertia at motor", f"{m['load_inertia_kgm2'] * 1e4:.4g} kg*cm^2"),
        ("peak torque", f"{m['peak_torque_Nm']:.4g} N*m at {m['peak_torque_speed_rpm']:.0f} rpm"),
        ("RMS torque", f"{m['rms_torque_Nm']:.4g} N*m"),
        ("accel / run / decel torque (move 1)",
         f"{m['accel_torque_Nm']:.4g} / {m['run_torque_Nm']:.4g} / {m['decel_torque_Nm']:.4g} N*m"),
        ("holding torque", f"{m['holding_torque_Nm']:.4g} N*m"),
        ("max / mean speed", f"{m['max_speed_rpm']:.0f} / {m['mean_speed_rpm']:.0f} rpm"),
        ("peak / average power", f"{m['peak_power_W']:.4g} / {m['average_power_W']:.4g} W"),
        ("regenerated energy per cycle", f"{m['regen_energy_J'] + 0.0:.4g} J"),
    ]
    for extra_key, label in (("gearbox_torque", "gearbox output torque"),):
        if extra_key in m:
            rows.append((label, str(m[extra_key])))
    for k, v in rows:
        t.add_row(k, v)
    console.print(t)
    mech = result.extras.get("mechanism_checks")
    if mech:
        _print_checks(console, f"mechanism {result.axis.mechanism.type}",
                      {"ok": all(c["ok"] for c in mech), "checks": mech})
    if result.motor is not None:
        _print_checks(console, f"motor {result.motor['name']}", result.motor)
        _print_electrical(console, result)
    gear = result.extras.get("gearbox_checks")
    if gear:
        _print_checks(console, "gearbox ratings (transmission)", gear)
    if result.candidates:
        _print_candidates(console, result)


def _pct(margin: float | None) -> str:
    if margin is None:
        return "n/a"
    p = margin * 100.0
    return f"{p:+.2g} %" if p != 0.0 and abs(p) < 0.1 else f"{p:+.1f} %"


def _value(x: float | None, unit: str) -> str:
    return "n/a" if x is None else f"{x:.4g} {unit}"


def _print_checks(console: Any, title: str, block: dict[str, Any]) -> None:
    from rich.table import Table

    t = Table(title=f"{title}: {'OK' if block['ok'] else 'FAILS'}")
    for col in ("check", "required", "available", "margin", "result"):
        t.add_column(col, justify="right" if col != "check" else "left")
    for c in block["checks"]:
        approx = " (approx. envelope)" if c.get("approximate") else ""
        stage = f" [{c['stage']}]" if c.get("stage") else ""
        status = c.get("status") or ("pass" if c["ok"] else "fail")
        t.add_row(c["name"] + stage + approx, _value(c["required"], c["unit"]), _value(c["available"], c["unit"]),
                  _pct(c["margin"]), {"pass": "yes", "fail": "NO"}.get(status, status))
    console.print(t)
    for c in block["checks"]:
        if c.get("note"):
            console.print(f"  {c['name']}: {c['note']}")
    if "inertia_ratio" in block:
        console.print(f"inertia ratio J_L/J_M = {block['inertia_ratio']:.3g} "
                      f"(lecture: below 5:1 recommended, 1:1 ideal); "
                      f"t_am = {block['min_accel_time_s']:.4g} s, t_dm = {block['min_decel_time_s']:.4g} s")


def _print_electrical(console: Any, result: Any) -> None:
    """The electrical half of a given motor: supply, envelope source, currents, winding, drive, regen."""
    _print_electrical_blocks(console, result.motor, result.extras.get("drive"), result.extras.get("regen"))


def _drive_label(drive: dict[str, Any] | None) -> str:
    """A candidate's drive in one cell: its id and status (unknown / none / fails)."""
    if not drive:
        return "-"
    status = drive.get("status", "ok" if drive.get("ok") else "fails")
    return f"{drive.get('id') or '-'}" + ("" if status == "ok" else f" ({status})")


def _print_selected_electrical(console: Any, pick: dict[str, Any]) -> None:
    """The selected candidate's drive, electrical figures and regen block (drivetrain.sizing.drive_select)."""
    drive = pick.get("drive")
    if drive and drive.get("status") in ("unknown", "none"):
        console.print(f"drive: {drive.get('id') or 'none'} ({drive['status']}: {drive.get('reason', '')})")
        drive = None
    elec = pick.get("electrical") or {}
    if elec.get("note"):
        console.print(f"electrical: {elec['note']}")
    _print_electrical_blocks(console, {**elec, "checks": elec.get("checks", [])}, drive, pick.get("regen"))
    if elec.get("checks"):
        _print_checks(console, f"motor {pick['motor']} electrical",
                      {"ok": all(c["ok"] for c in elec["checks"]), "checks": elec["checks"]})


def _print_electrical_blocks(console: Any, m: dict[str, Any], drive: dict[str, Any] | None,
                             rg: dict[str, Any] | None) -> None:
    if m.get("rms_current_A") is None:
        if rg is not None:
            _print_regen(console, rg)
        if drive is not None:
            _print_checks(console, f"drive {drive['id']}", drive)
        return
    bus = m.get("dc_bus_voltage_V")
    supply = m.get("supply_voltage_V")
    where = (f"supply {supply:.0f} V, DC bus {bus:.0f} V" if supply and bus else
             (f"DC bus {bus:.0f} V" if bus else "supply voltage not given"))
    console.print(f"{where}; envelope: {m['envelope_source']}")
    console.print(f"motor current: RMS {m['rms_current_A']:.4g} A, peak {m['peak_current_A']:.4g} A "
                  f"(Kt {m['torque_constant_NmA']:.4g} N*m/A)")
    rise = m.get("winding_temperature_rise_K")
    if rise is not None:
        console.print(f"winding temperature rise {rise:.4g} K (allowed {m['winding_allowed_rise_K']:.4g} K at "
                      f"{m['ambient_degC']:g} degC, {m['altitude_m']:g} m)")
    if drive is not None:
        _print_checks(console, f"drive {drive['id']}", drive)
    if rg is not None:
        _print_regen(console, rg)


def _print_regen(console: Any, rg: dict[str, Any]) -> None:
    if rg is not None:
        window = (f", resistance {rg['resistor_min_ohm'] or 0:.4g} to {rg['resistor_max_ohm']:.4g} ohm"
                  if rg.get("resistor_max_ohm") is not None else "")
        builtin = {True: "; built-in resistor suffices", False: "; built-in resistor does NOT suffice",
                   None: ""}[rg["builtin_resistor_sufficient"]]
        console.print(f"regeneration into the bus {rg['energy_per_cycle_J']:.4g} J per cycle, capacitors "
                      f"{rg['capacitor_absorbed_J']:.4g} J; braking resistor {rg['resistor_energy_per_cycle_J']:.4g} J "
                      f"per cycle, peak {rg['resistor_peak_power_W']:.4g} W, average "
                      f"{rg['resistor_average_power_W']:.4g} W{window}{builtin}")


def _mounting(c: dict[str, Any], sel: dict[str, Any]) -> str:
    """How the motor drives the axis: a catalog gearbox, the axis's own gearbox, or direct."""
    if c.get("gearbox"):
        return f"{c['gearbox']} (i = {c['ratio']:.4g})"
    if sel.get("transmission_gearbox"):
        return "axis gearbox"
    return "direct"


def _print_candidates(console: Any, result: Any) -> None:
    from rich.table import Table

    sel = result.selection or {}
    per = "every passing pair" if sel.get("listing") == "all_pairs" else "best configuration of each motor"
    t = Table(title=f"candidates: {sel.get('passing', '?')} of {sel.get('evaluated', '?')} configurations pass, "
                    f"{sel.get('passing_motors', '?')} motors (ranked by {sel.get('objective', '?')}; {per}; "
                    "rejected ones below with the reason)")
    for col in ("rank", "motor", "vendor", "power", "flange", "gearbox", "J_L/J_M", "peak margin", "RMS margin",
                "result / why not", "drive"):
        t.add_column(col, no_wrap=col in ("motor", "gearbox"))
    for c in result.candidates:
        checks = {ch["name"]: ch for ch in c["checks"]}
        if c["ok"]:
            why = "yes" if not c.get("unknown") else "yes, unknown: " + ", ".join(c["unknown"])
        else:
            bad = sorted((ch for ch in c["checks"] if ch.get("status", "fail" if not ch["ok"] else "pass") == "fail"),
                         key=lambda ch: (ch["name"] != "max_speed", ch["margin"] or 0.0))
            why = "\n".join(f"{ch['name']} {_pct(ch['margin'])}" for ch in bad) or c["failed"]
        power = c.get("rated_power_W")
        flange = c.get("flange_mm")
        motor = c["motor"] + (" †" if c.get("unverified") else "")
        t.add_row(str(c["rank"]) if c.get("rank") else "-", motor, c.get("vendor", ""),
                  "" if power is None or math.isnan(power) else f"{power:.0f} W",
                  "" if flange is None else f"{flange:.0f} mm", _mounting(c, sel),
                  f"{c['inertia_ratio']:.3g}", _pct(checks["peak_torque"]["margin"]),
                  _pct(checks["rms_torque"]["margin"]), why, _drive_label(c.get("drive")))
    console.print(t)
    if any(c.get("unverified") for c in result.candidates):
        console.print("† unverified catalog data (not traced to a vendor document, or a derived rating): "
                      "see unverified_reason in --json, or `drivetrain catalog show ID`")
    if sel.get("selected"):
        pick = sel["selected"]
        how = (f" + {pick['gearbox']} ({pick.get('gearbox_vendor') or 'catalog'}, i = {pick['ratio']:.4g})"
               if pick.get("gearbox") else (f", on the axis's {sel['transmission_gearbox']}"
                                            if sel.get("transmission_gearbox") else ", direct drive"))
        console.print(f"selected: {pick['motor']} ({pick['vendor']}){how}")
        _print_selected_electrical(console, pick)
        if pick.get("unknown"):
            console.print("  not judged (the catalog lacks the data): "
                          + "; ".join(f"{ch['name']}: {ch.get('note', '')}" for ch in pick["checks"]
                                      if ch.get("status") == "unknown"))
        if sel.get("unverified"):
            console.print(f"  {sel['unverified']}")
        nxt = sel.get("next_smaller")
        if nxt:
            console.print(f"next smaller motor {nxt['motor']} fails:")
            for line in nxt.get("failures") or [nxt["failed"]]:
                console.print(f"  {line}")
        opt = sel.get("optimal_ratio")
        if opt:
            near = opt.get("nearest_catalog_ratio")
            console.print(f"optimal ratio for {opt['motor']}: {opt['min_rms_ratio']:.3g} (min RMS), "
                          f"{opt['inertia_match_ratio']:.3g} (inertia match)"
                          + (f", nearest catalog ratio {near:g}" if near else ""))
    elif sel.get("advice"):
        for line in str(sel["advice"]).splitlines():
            console.print(f"[bold red]{line}[/]")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point: returns the exit status (0 passes, 1 sized but nothing passes, 2 bad input)."""
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(optional=_command(words) not in CORE_COMMANDS)
    args = parser.parse_args(words)
    if args.version:
        from drivetrain import __version__

        print(__version__)
        return 0
    handler: Callable[[argparse.Namespace], int] | None = getattr(args, "handler", None)
    if handler is None:
        parser.print_help()
        return EXIT_INPUT
    from drivetrain.errors import InputError

    try:
        if getattr(args, "user_catalog", None):
            from drivetrain.catalog.cli import use_catalog

            use_catalog(args.user_catalog)
        return handler(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
