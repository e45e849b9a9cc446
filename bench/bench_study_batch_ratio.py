"""The study's batched path of this checkout against another's, alternated in one run (CPU ratio).

Each side runs in its own new Python process (its ``src`` first on the path, its own environment,
e.g. its own ``DRIVETRAIN_DATA_DIR`` and ``DRIVETRAIN_CACHE_DIR``): the issue's 10,000-variant grid
of ``bench_study.py`` (25 load masses x 20 leads x 20 move times on examples/ball_screw.yaml, full
catalog selection) is planned (``make_plan``), one batch is run to warm the process (catalog,
compiled code), then every variant is sized with ``run_batch`` in the runner's order and batches of
200, as a worker does; the wall and CPU time (``time.process_time``) of that loop is the figure.
The sides alternate ``--rounds`` times (other, this, other, this, ...) so a drift of the shared
machine's speed touches both; each round's CPU ratio this / other is printed, with the rows of
both sides compared variant by variant (every recorded value equal).

Run (from this checkout): ``PYTHONPATH=src .venv/bin/python bench/bench_study_batch_ratio.py
--against OTHER/src [--against-env VAR=VALUE,...] [--this-env VAR=VALUE,...] [--rounds 2]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).parents[1]


def _child(grid: str, rows_out: str) -> None:
    """Time the batched path over the grid in this process; print wall and CPU as JSON."""
    sys.path.insert(0, str(ROOT / "bench"))
    import yaml

    from bench_study import STUDY  # the grid of bench_study.py
    from drivetrain.study import load_study
    from drivetrain.study.runner import BATCH, _by_motion, make_plan, run_batch

    for key, num in zip(STUDY["parameters"], (int(x) for x in grid.split(",")), strict=True):
        STUDY["parameters"][key]["num"] = num
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "grid.yaml"
        path.write_text(yaml.safe_dump(STUDY, sort_keys=False), encoding="utf-8")
        study = load_study(path)
        variants = study.variants()
        plan = make_plan(study)
        items = _by_motion(list(enumerate(variants)), study.parameters)
        run_batch(plan, items[:BATCH])  # warm: catalog tables, compiled code
        t0, c0 = time.perf_counter(), time.process_time()
        rows = [r for k in range(0, len(items), BATCH) for r in run_batch(plan, items[k:k + BATCH])]
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    Path(rows_out).write_text(json.dumps(rows, default=str), encoding="utf-8")
    print(json.dumps({"wall": wall, "cpu": cpu, "n": len(rows), "ok": sum(bool(r["ok"]) for r in rows)}))


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=1e-12)
    return bool(a == b)


def _run(src: str, env_extra: dict[str, str], grid: str, rows_out: str) -> dict[str, float]:
    env = {**os.environ, **env_extra, "PYTHONPATH": str(Path(src).resolve())}
    out = subprocess.run([sys.executable, __file__, "--child", "--grid", grid, "--rows", rows_out],
                         check=True, env=env, capture_output=True, text=True).stdout
    return dict(json.loads(out.strip().splitlines()[-1]))


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--against", default="", help="the src directory of the other checkout")
    ap.add_argument("--this", default=str(ROOT / "src"), help="this checkout's src directory")
    ap.add_argument("--against-env", default="", help="VAR=VALUE[,VAR=VALUE] for the other side")
    ap.add_argument("--this-env", default="", help="VAR=VALUE[,VAR=VALUE] for this side")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--grid", default="25,20,20", help="masses,leads,times (bench_study.py's grid)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--rows", default="", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        _child(args.grid, args.rows)
        return
    envs = {side: dict(kv.split("=", 1) for kv in spec.split(",") if kv)
            for side, spec in (("before", args.against_env), ("after", args.this_env))}
    srcs = {"before": args.against, "after": args.this}
    load0 = _load()
    res: dict[str, list[dict[str, float]]] = {"before": [], "after": []}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.rounds):
            for side in ("before", "after"):
                res[side].append(_run(srcs[side], envs[side], args.grid, f"{tmp}/{side}.json"))
        rows = {side: json.loads(Path(f"{tmp}/{side}.json").read_text(encoding="utf-8")) for side in res}
    keys = [k for k in rows["before"][0] if k != "error"]
    same = sum(all(_same(a.get(k), b.get(k)) for k in keys) and a.get("error", "") == b.get("error", "")
               for a, b in zip(rows["before"], rows["after"], strict=True))
    print(f"### the study's batched path, one process each, alternated {args.rounds} times (grid {args.grid})\n")
    print(f"before: `{args.against}`; after: `{args.this}`; {os.cpu_count()} CPUs; load average {load0} at the "
          f"start, {_load()} at the end.\n")
    print("| round | before: wall | before: CPU | after: wall | after: CPU | after / before (CPU) |")
    print("|---|---:|---:|---:|---:|---:|")
    for i, (b, a) in enumerate(zip(res["before"], res["after"], strict=True), 1):
        print(f"| {i} | {b['wall']:.1f} s | {b['cpu']:.1f} s | {a['wall']:.1f} s | {a['cpu']:.1f} s | "
              f"{a['cpu'] / b['cpu']:.2f} |")
    tb, ta = sum(x["cpu"] for x in res["before"]), sum(x["cpu"] for x in res["after"])
    print(f"| all | | {tb:.1f} s | | {ta:.1f} s | {ta / tb:.2f} |")
    print(f"\n{res['after'][0]['n']:,} variants; pass: before {res['before'][0]['ok']:,}, after "
          f"{res['after'][0]['ok']:,}; rows equal in all {len(keys)} recorded columns (motor, gearbox, margins, "
          f"torques, ...) and the error: {same:,} of "
          f"{len(rows['after']):,}.")


if __name__ == "__main__":
    main()
