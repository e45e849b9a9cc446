"""Command line: ``drivetrain size AXIS``, ``drivetrain catalog ...``, ``drivetrain modes AXIS`` ...

No physics here: each command calls the library and formats its result. Bad input prints one
line naming the field and exits with status 2, without a traceback. Heavy modules are
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

EXIT_INPUT = 2


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every sub-command."""
    parser = argparse.ArgumentParser(prog="drivetrain", description="Size and analyse servo axes.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("size", help="duty cycle at the motor shaft, motor checks and selection")
    p.add_argument("axis", help="axis file (YAML)")
    p.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    p.add_argument("--csv", metavar="FILE", help="write the sampled time series to FILE")
    p.add_argument("--report", metavar="FILE", help="write an HTML (.html) or PDF (.pdf) report")
    p.add_argument("--units", choices=["si", "imperial", "as-given"], default="si", help="units of the report")
    p.add_argument("--explain", metavar="MODEL", help="say why a catalog motor was accepted or rejected")
    p.add_argument("--points", type=int, default=64, help="samples per profile phase (default 64)")
    p.set_defaults(handler=_cmd_size)

    p = sub.add_parser("select", help="same as size, with a catalog selection even if the axis names a motor")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true")
    p.add_argument("--top", type=int, default=10)
    p.set_defaults(handler=_cmd_select)

    _optional_parser(sub, "drivetrain.catalog.cli")
    _optional_parser(sub, "drivetrain.dynamics.cli")
    _optional_parser(sub, "drivetrain.web.cli")
    return parser


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


def _write_atomic(path: str, text: str) -> None:
    """Write a file through a temporary sibling and rename, so a reader never sees half of it."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".{target.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(target)


def _cmd_size(args: argparse.Namespace) -> int:
    from drivetrain.sizing import size

    if args.points < 3 or args.points > 100_000:
        from drivetrain.errors import InputError

        raise InputError("--points", "must be between 3 and 100000", args.points)
    result = size(args.axis, points_per_phase=args.points)
    if getattr(args, "explain", None):
        from drivetrain.errors import InputError

        explain = getattr(result, "explain", None)
        if explain is None:
            raise InputError("--explain", "needs a catalog selection (motor: {select: ...})", args.explain)
    if args.csv:
        _write_csv(args.csv, result.series())
    if args.report:
        from drivetrain.report import write_report

        write_report(result, args.report, units=args.units)
    if args.json:
        print(json.dumps(_jsonable(result.to_dict()), indent=2))
        return 0
    _print_table(result)
    if args.explain:
        print(result.explain(args.explain))  # type: ignore[attr-defined]
    if args.csv:
        print(f"time series written to {args.csv}")
    if args.report:
        print(f"report written to {Path(args.report).resolve()}")
    return 0


def _cmd_select(args: argparse.Namespace) -> int:
    from drivetrain.axis import load_axis
    from drivetrain.sizing import size

    axis = load_axis(args.axis)
    result = size(axis)
    if args.json:
        print(json.dumps(_jsonable(result.to_dict()), indent=2))
    else:
        _print_table(result)
    return 0


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

    console = Console()
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
    if result.motor is not None:
        _print_checks(console, f"motor {result.motor['name']}", result.motor)
    if result.candidates:
        _print_candidates(console, result)


def _print_checks(console: Any, title: str, block: dict[str, Any]) -> None:
    from rich.table import Table

    t = Table(title=f"{title}: {'OK' if block['ok'] else 'FAILS'}")
    for col in ("check", "required", "available", "margin", "ok"):
        t.add_column(col, justify="right" if col != "check" else "left")
    for c in block["checks"]:
        approx = " (approx. envelope)" if c.get("approximate") else ""
        t.add_row(c["name"] + approx, f"{c['required']:.4g} {c['unit']}", f"{c['available']:.4g} {c['unit']}",
                  f"{c['margin'] * 100:+.1f} %", "yes" if c["ok"] else "NO")
    console.print(t)
    if "inertia_ratio" in block:
        console.print(f"inertia ratio J_L/J_M = {block['inertia_ratio']:.3g} "
                      f"(lecture: below 5:1 recommended, 1:1 ideal); "
                      f"t_am = {block['min_accel_time_s']:.4g} s, t_dm = {block['min_decel_time_s']:.4g} s")


def _print_candidates(console: Any, result: Any) -> None:
    from rich.table import Table

    t = Table(title="candidates (best first)")
    for col in ("rank", "motor", "gearbox", "ratio", "J_L/J_M", "peak margin", "RMS margin", "ok / reason"):
        t.add_column(col)
    for k, c in enumerate(result.candidates, 1):
        checks = {ch["name"]: ch for ch in c["checks"]}
        t.add_row(str(k), c["motor"], c.get("gearbox") or "-", f"{c['ratio']:.4g}", f"{c['inertia_ratio']:.3g}",
                  f"{checks['peak_torque']['margin'] * 100:+.0f} %", f"{checks['rms_torque']['margin'] * 100:+.0f} %",
                  "yes" if c["ok"] else c.get("failed", "NO"))
    console.print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point: returns the exit status (0 ok, 2 bad input, 1 a check failed where asked)."""
    parser = build_parser()
    args = parser.parse_args(argv)
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
