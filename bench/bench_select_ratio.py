"""The selection of this checkout against another's, alternated in one run (CPU ratios).

The measurements of ``bench_select.py`` and ``bench_select_drives.py`` (``unknown: flag``), in CPU
time (``time.process_time``) so that waiting on a shared machine does not count: the whole-catalog
evaluation (every motor direct and behind every gearbox row, 10,020-sample cycle), a whole ``size``
of examples/ball_screw.yaml, the selection alone (``select``) and with the drive rule and post-pass
(``orderable`` + ``attach_drives``). Each side runs in its own new Python process (its ``src`` on the
path, its own environment), warmed by one call of each, then the median of ``--runs`` calls; the sides
alternate ``--rounds`` times and each round's ratio this / other is printed, with the median of them.

Run (from this checkout): ``PYTHONPATH=src .venv/bin/python bench/bench_select_ratio.py
--against OTHER/src [--against-env VAR=VALUE,...] [--this-env VAR=VALUE,...] [--rounds 5]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).parents[1]
MEASURES = ("evaluate, whole catalog", "size ball_screw.yaml", "select", "select + drive rule + post-pass")


def _cpu(fn: Callable[[], Any], runs: int) -> float:
    fn()  # warm
    out = []
    for _ in range(runs):
        c0 = time.process_time()
        fn()
        out.append(time.process_time() - c0)
    return statistics.median(out)


def _child(runs: int) -> None:
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_select import AXIS, POINTS  # the axis of both selection benchmarks
    from drivetrain import catalog
    from drivetrain.axis.model import Margins, load_axis, parse_axis
    from drivetrain.duty.cycle import duty_cycle, duty_from_samples
    from drivetrain.sizing.drive_select import attach_drives, orderable
    from drivetrain.sizing.pipeline import size
    from drivetrain.sizing.selection import evaluate, select

    axis = parse_axis(AXIS)
    cycle = axis.cycle()
    duty = duty_from_samples(axis, cycle, cycle.sample(POINTS))
    m, gb = catalog.motors(), catalog.gearboxes(kind="servo_gearbox")
    full = load_axis(str(ROOT / "examples" / "ball_screw.yaml"))
    sel_axis = parse_axis({**AXIS, "motor": {"select": {"objective": "smallest", "unknown": "flag"}}})
    sel_duty = duty_cycle(sel_axis, POINTS)
    assert sel_axis.spec.motor is not None and sel_axis.spec.motor.select is not None
    spec, margins = sel_axis.spec.motor.select, sel_axis.spec.motor.margins

    def with_drives() -> None:
        attach_drives(sel_axis, sel_duty, orderable(sel_axis, sel_duty, select(sel_axis, sel_duty, spec, margins)),
                      margins)

    fns: list[Callable[[], Any]] = [lambda: evaluate(axis, duty, m, gb, Margins()), lambda: size(full),
                                    lambda: select(sel_axis, sel_duty, spec, margins), with_drives]
    print(json.dumps([_cpu(f, runs) for f in fns]))


def _run(src: str, env_extra: dict[str, str], runs: int) -> list[float]:
    env = {**os.environ, **env_extra, "PYTHONPATH": str(Path(src).resolve())}
    out = subprocess.run([sys.executable, __file__, "--child", "--runs", str(runs)], check=True, env=env,
                         capture_output=True, text=True).stdout
    return list(json.loads(out.strip().splitlines()[-1]))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--against", default="", help="the src directory of the other checkout")
    ap.add_argument("--this", default=str(ROOT / "src"), help="this checkout's src directory")
    ap.add_argument("--against-env", default="", help="VAR=VALUE[,VAR=VALUE] for the other side")
    ap.add_argument("--this-env", default="", help="VAR=VALUE[,VAR=VALUE] for this side")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--runs", type=int, default=5, help="timed calls per measure in each process")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        _child(args.runs)
        return
    envs = {side: dict(kv.split("=", 1) for kv in spec.split(",") if kv)
            for side, spec in (("before", args.against_env), ("after", args.this_env))}
    srcs = {"before": args.against, "after": args.this}
    load0 = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    res: dict[str, list[list[float]]] = {"before": [], "after": []}
    for _ in range(args.rounds):
        for side in ("before", "after"):
            res[side].append(_run(srcs[side], envs[side], args.runs))
    print(f"### selection, in-process CPU, median of {args.runs} calls per process, {args.rounds} alternated "
          f"processes each\n")
    print(f"before: `{args.against}`; after: `{args.this}`; load average {load0} at the start, "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())} at the end.\n")
    print("| measure | before: CPU (median of rounds) | after: CPU | ratio per round | median ratio |")
    print("|---|---:|---:|---|---:|")
    for i, name in enumerate(MEASURES):
        b = [r[i] for r in res["before"]]
        a = [r[i] for r in res["after"]]
        ratios = [x / y for x, y in zip(a, b, strict=True)]
        print(f"| {name} | {statistics.median(b) * 1e3:.0f} ms | {statistics.median(a) * 1e3:.0f} ms | "
              f"{', '.join(f'{r:.2f}' for r in ratios)} | {statistics.median(ratios):.2f} |")


if __name__ == "__main__":
    main()
