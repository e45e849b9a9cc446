"""The sub-commands of the core CLI: each loads its input, calls the library and writes its files.

Tables go to ``drivetrain.cli.sizing`` and ``drivetrain.cli.analyses``; every heavy module is imported
inside the command that needs it.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

EXIT_OK = 0
"""``size``/``select``/``machine size``: the answer passes (``pass``), or passes with checks that could not be
judged (``pass with unknowns``, under ``motor.select.unknown: flag``, the default)."""
EXIT_FAILS = 1
"""``size``/``select``/``machine size``: sized, but the answer fails (a check fails, nothing passes, or under
``motor.select.unknown: fail`` a check cannot be judged); the answer is printed."""
EXIT_INPUT = 2
"""Bad input: one line naming the field, no traceback."""


def _write_text(path: str, text: str, field: str = "--csv") -> None:
    """Write a text file whole or not at all (``drivetrain.files``); errors name ``field``."""
    from drivetrain.files import write_atomic

    write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8"), field)


PLOT_SUFFIXES = (".png", ".svg", ".pdf")
"""Figure formats ``simulate --plot`` writes, chosen by the file's suffix."""


def _check_outputs(args: argparse.Namespace) -> None:
    """Refuse an output path that cannot be written before the work that fills it."""
    if not any(getattr(args, name, None) for name in ("csv", "report", "plot", "bom")):
        return
    from drivetrain.files import check_target
    from drivetrain.report import REPORT_SUFFIXES

    for name in ("csv", "report", "plot", "bom"):
        path = getattr(args, name, None)
        if path:
            check_target(path, f"--{name}")
    report = getattr(args, "report", None)
    if report and Path(report).suffix.lower() not in REPORT_SUFFIXES:
        from drivetrain.errors import InputError

        raise InputError("--report", "must end in .html or .pdf", report)
    bom = getattr(args, "bom", None)
    if bom and Path(bom).suffix.lower() != ".csv":
        from drivetrain.errors import InputError

        raise InputError("--bom", "must end in .csv", bom)
    plot = getattr(args, "plot", None)
    if plot and Path(plot).suffix.lower() not in PLOT_SUFFIXES:
        from drivetrain.errors import InputError

        raise InputError("--plot", f"must end in {', '.join(PLOT_SUFFIXES)}", plot)


def size(args: argparse.Namespace, axis: str | dict[str, Any] | None = None) -> int:
    """``size``: the axis file (or ``axis``, its mapping as ``select`` rewrote it) sized and printed."""
    from drivetrain.dynamics.mechanism_modes import size  # the pipeline with its modes stage
    from drivetrain.errors import InputError

    if args.points < 3 or args.points > 100_000:
        raise InputError("--points", "must be between 3 and 100000", args.points)
    _check_outputs(args)
    try:
        result = size(args.axis if axis is None else axis, points_per_phase=args.points, all_pairs=args.all)
    except InputError as exc:
        if exc.field == "points_per_phase":
            raise InputError("--points", exc.rule, args.points) from None
        raise
    explanation = result.explain(args.explain) if args.explain else ""
    modes = result.modes  # attached by the pipeline's modes stage
    if args.csv:
        _write_csv(args.csv, result.series())
    if args.report:
        from drivetrain.report import write_report

        write_report(result, args.report, units=args.units)
    if args.aas:
        from drivetrain.machine.aas import axis_aas

        _write_text(args.aas, json.dumps(axis_aas(jsonable(result.to_dict())), indent=2), "--aas")
    if getattr(args, "bom", None):
        from drivetrain.cli.order import write_bom

        write_bom(args.bom, result)
    if args.json:
        print(json.dumps(jsonable(result.to_dict()), indent=2))
        return _exit_code(result)
    from drivetrain.cli.quantities import TableUnits
    from drivetrain.cli.sizing import print_sizing

    units = TableUnits(args.units, result.axis.raw)
    print_sizing(result, units)
    if modes is not None:
        from drivetrain.cli.analyses import print_modes_across
        from drivetrain.terminal import table_console

        print_modes_across(table_console(), modes, units)
    for warning in result.warnings:
        print(f"warning: {warning}")
    if explanation:
        print(explanation)
    if args.csv:
        print(f"time series written to {args.csv}")
    if args.report:
        print(f"report written to {Path(args.report).resolve()}")
    if getattr(args, "bom", None):
        print(f"order sheet written to {Path(args.bom).resolve()}")
    print(result.verdict_line())
    return _exit_code(result)


def _exit_code(result: Any) -> int:
    """0 when the answer passes, with or without unknowns (``status != "fail"``), 1 when it fails."""
    return EXIT_OK if result.ok else EXIT_FAILS


def machine_size(args: argparse.Namespace) -> int:
    from drivetrain.machine.result import size_machine

    result = size_machine(args.machine, phasing_samples=args.samples, seed=args.seed)
    out = jsonable(result.to_dict())
    if args.aas:
        from drivetrain.machine.aas import machine_aas

        _write_text(args.aas, json.dumps(machine_aas(out), indent=2), "--aas")
    if args.report:
        from drivetrain.report.machine import write_machine_report

        write_machine_report(result, args.report)
    if args.json:
        print(json.dumps(out, indent=2))
        return _exit_code(result)
    from drivetrain.cli.analyses import print_machine

    print_machine(out)
    if args.report:
        print(f"report written to {Path(args.report).resolve()}")
    if args.aas:
        print(f"AAS submodel written to {Path(args.aas).resolve()}")
    print(result.verdict_line())
    return _exit_code(result)


def modes(args: argparse.Namespace) -> int:
    from drivetrain.axis.model import load_axis
    from drivetrain.dynamics import modes_summary
    from drivetrain.dynamics.axis_model import model
    from drivetrain.dynamics.linear import critical_speeds, excitation_orders

    axis = load_axis(args.axis)
    dyn = model(axis)
    out: dict[str, Any] = {"axis": axis.name, "motor": dyn.motor, **modes_summary(dyn.chain)}
    across = None
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
            out["modes"] = across.to_dict()
            out["natural_frequencies_model"] = "motor and transmission, the mechanism rigid (modes: with its spring)"
    if args.json:
        print(json.dumps(jsonable(out), indent=2))
        return 0
    from drivetrain.cli.analyses import print_modes
    from drivetrain.cli.quantities import TableUnits

    print_modes(out, len(dyn.chain.inertia), TableUnits(args.units, axis.raw), across)
    return 0


def settling_at_load(axis: Any) -> dict[str, Any]:
    """The settling window at the load as ``simulate --json`` states it (m or rad, and where it came from)."""
    from drivetrain.axis.requirements import settling_window

    spec = axis.spec.requirements
    given = spec is not None and spec.settling is not None and spec.settling.window is not None
    unit = "m" if axis.mechanism.motion == "linear" else "rad"
    return {f"settling_window_{unit}": settling_window(spec, axis.mechanism.motion),
            "settling_window_source": "requirements.settling.window" if given else "default"}


def simulate(args: argparse.Namespace) -> int:
    from drivetrain.axis.model import load_axis
    from drivetrain.dynamics.axis_model import simulate_axis

    _check_outputs(args)
    axis = load_axis(args.axis)
    res = simulate_axis(axis, cycles=args.cycles, velocity_bandwidth_hz=args.bandwidth)
    out = {"axis": axis.name, **res.to_dict(), **settling_at_load(axis)}
    if args.csv:
        import io

        buf = io.StringIO()
        res.to_pandas().to_csv(buf)
        _write_text(args.csv, buf.getvalue(), "--csv")
    if args.plot:
        from drivetrain.files import write_atomic

        fig = res.plot()
        fmt = Path(args.plot).suffix.lower().lstrip(".")
        write_atomic(args.plot, lambda tmp: fig.savefig(tmp, dpi=120, format=fmt), "--plot")
    if args.json:
        print(json.dumps(jsonable(out), indent=2))
        return 0
    from drivetrain.cli.analyses import print_simulation
    from drivetrain.cli.quantities import TableUnits

    print_simulation(out, TableUnits(args.units, axis.raw))
    for path, what in ((args.csv, "time series"), (args.plot, "figure")):
        if path:
            print(f"{what} written to {Path(path).resolve()}")
    return 0


SELECT_TOP = (1, 1000)
"""Range of ``select --top`` (that of ``motor.select.top``)."""
SUPPLY_KEYS = ("supply_voltage", "dc_bus_voltage")
"""Keys of a named motor that apply to every catalog candidate (the machine's supply), kept by ``select``."""


def select(args: argparse.Namespace) -> int:
    """``select``: ``size`` of the axis with a catalog selection, even where the axis names a motor."""
    from drivetrain.errors import InputError

    if args.top is not None and not SELECT_TOP[0] <= args.top <= SELECT_TOP[1]:
        raise InputError("--top", f"must be between {SELECT_TOP[0]} and {SELECT_TOP[1]}", args.top)
    for name, default in (("points", 64), ("all", False), ("explain", None), ("csv", None), ("report", None),
                          ("aas", None)):
        if not hasattr(args, name):
            setattr(args, name, default)
    return size(args, selection_axis(args.axis, args.top))


def selection_axis(path: str, top: int | None = None) -> Any:
    """The axis file's mapping with a catalog selection as its motor.

    A motor the file names (by catalog id or by its parameters) gives way to ``motor: {select: {}}``,
    keeping its ``margins`` and the supply (``SUPPLY_KEYS``); a ``select`` the file has is kept. ``top``
    (``--top``) sets ``motor.select.top``, the number of motors listed. Anything else is the file's.
    """
    import copy

    from drivetrain.axis.yaml_text import read_yaml

    data = read_yaml(path)
    if not isinstance(data, dict):
        return data  # not an axis file: sizing names the problem
    data = copy.deepcopy(data)
    motor = data.get("motor")
    motor = dict(motor) if isinstance(motor, dict) else {}
    if motor.get("select") is None:
        motor = {**{k: motor[k] for k in ("margins", *SUPPLY_KEYS) if k in motor}, "select": {}}
    if top is not None and isinstance(motor["select"], dict):
        motor["select"] = {**motor["select"], "top": top}
    data["motor"] = motor
    return data


def _write_csv(path: str, cols: dict[str, Any]) -> None:
    import io

    import numpy as np

    names = list(cols)
    data = np.column_stack([np.asarray(cols[n], dtype=float) for n in names])
    buf = io.StringIO()
    np.savetxt(buf, data, delimiter=",", header=",".join(names), comments="", fmt="%.9g")
    _write_text(path, buf.getvalue())


def jsonable(obj: Any) -> Any:
    """Plain JSON types; non-finite floats become null."""
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    return obj

