"""``drivetrain sweep STUDY.yaml``: run a design-space study (grid, Monte Carlo, optimisation).

Importing this module is cheap: the study machinery, pandas and Dask load when the command runs.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any


def add_parser(subparsers: Any) -> None:
    """Register ``sweep`` with the drivetrain CLI."""
    p = subparsers.add_parser("sweep", help="a design-space study: grid, Monte Carlo or optimisation of an axis")
    p.add_argument("study", help="study file (YAML, see docs/studies.md)")
    p.add_argument("-o", "--out", metavar="FILE",
                   help="result table (.parquet; a .csv and .meta.json go beside it; default: STUDY_results.parquet "
                        "in the current folder)")
    p.add_argument("--report", metavar="FILE", help="write the study report (HTML)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="an existing Dask scheduler, e.g. tcp://host:8786 (default $DRIVETRAIN_SCHEDULER, else an "
                        "embedded cluster on every core)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="processes of the embedded cluster (default: every core; 0: run in this process)")
    p.add_argument("--batch", type=int, default=200, metavar="N", help="variants per task (default 200)")
    p.add_argument("--resume", action="store_true", help="continue from the partial result of an interrupted run")
    p.add_argument("--yes", action="store_true", help="run a design of more than a million variants")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--units", choices=("si", "imperial"), default="si",
                   help="units of the summary's objective (the result table stays SI, its columns name their unit)")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from drivetrain.study import load_study, sweep

    study = load_study(args.study, yes=args.yes)  # every check before any work
    out = Path(args.out) if args.out else Path(f"{Path(args.study).stem}_results.parquet")
    from drivetrain.study.stream import STREAM_ABOVE

    if args.report and study.spec.optimize is None and study.n_variants() > STREAM_ABOVE:
        from drivetrain.errors import InputError

        raise InputError("--report", f"a study of more than {STREAM_ABOVE:,} variants has no report (its table is "
                         "written to disk as it runs): read the table, or narrow the study", args.report)
    console = Console(stderr=True)
    try:
        result = sweep(study, out=out, scheduler=args.scheduler, workers=args.workers, batch=args.batch,
                       resume=args.resume, progress=not args.quiet, report=args.report)
    except KeyboardInterrupt:
        console.print(f"interrupted: the finished variants are in {out.with_suffix('.partial.parquet')}; "
                      "continue with --resume")
        return 130
    df = result.table
    streamed = df.attrs.get("drivetrain", {})
    if "streamed" in streamed:  # the rows are on disk only
        console.print(f"{streamed['rows']} variants, {streamed['passing']} pass every check")
    else:
        n_ok = int(df["ok"].sum()) if "ok" in df else 0
        console.print(f"{len(df)} variants, {n_ok} pass every check")
    if result.best is not None:
        b = result.best
        console.print(f"best: {objective_text(b['objective'], b['value'], args.units)} at " +
                      ", ".join(f"{k} = {v}" for k, v in b["parameters"].items()))
        sel = b["result"].get("selection", {}).get("selected") or {}
        if sel:
            console.print(f"  selected {sel.get('motor')}" + (f" + {sel['gearbox']}" if sel.get("gearbox") else ""))
    for f in result.files:
        console.print(f"wrote {f}")
    sys.stdout.flush()
    return 0


def objective_text(column: str, value: float, system: str = "si") -> str:
    """``column = value`` of the best variant; in imperial a column with an SI unit suffix (``rms_torque_Nm``)
    is converted through ``drivetrain.units.IMPERIAL_UNITS`` (``rms_torque = 4.112 lbf*in``)."""
    from drivetrain.units import IMPERIAL_UNITS, SI_UNITS, convert, quantity_of_key

    named = quantity_of_key(column) if system == "imperial" else None
    if named is None or IMPERIAL_UNITS.get(named[1], "") == SI_UNITS.get(named[1], ""):
        return f"{column} = {value:.6g}"
    unit = IMPERIAL_UNITS[named[1]]
    return f"{named[0]} = {convert(value, named[1], unit):.6g} {unit}"
