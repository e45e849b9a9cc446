"""Benchmark of a design-space study: the issue's 10,000-variant grid with full catalog selection.

25 load masses (5-40 kg) x 20 leads (4-24 mm) x 20 move times (0.3-1.0 s) on
examples/ball_screw.yaml; every variant gets the catalog selection of the example (every motor,
each direct and behind every gearbox row). Measured in the same run, wall and CPU time (the CPU
time is what compares on a shared, loaded machine):

* the obvious loop: ``drivetrain.size`` of each variant's axis mapping, one after the other (timed on
  an evenly spaced sample of the grid and extrapolated to the grid; one core);
* the study's batched path in one process (every variant, in the runner's order and batches of
  200), with the mechanism checks of each batch computed together and, side by side, axis by axis;
* ``drivetrain.sweep`` as a user runs it, on the embedded LocalCluster of 2 worker processes, in a
  new Python process: everything (imports, catalog, cluster start, the result table) included, CPU
  time of that process and of its worker processes;
* throughput with 1, 2 and 4 warm local workers (LocalCluster on loopback, the embedded cluster's
  settings), CPU time of the workers;
* agreement: the selected motor, gearbox and every margin of a sample of variants against
  ``drivetrain.size``.

"2 cores from CPU" is the CPU time of every process of the run divided by 2: the wall time on 2
otherwise idle cores if both stay busy.

Run: ``.venv/bin/python bench/bench_study.py [--sample N] [--grid 25,20,20] [--workers 1,2,4]``;
``--against OTHER/src [--rounds 3]`` also times the cold ``sweep`` of another checkout (e.g. the
main branch exported with ``git archive main src | tar -x -C OTHER``) alternately with this one's,
side by side in the same run (run this one with ``PYTHONPATH=src``).
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

import drivetrain
from drivetrain.axis.model import parse_axis
from drivetrain.study import load_study, sweep
from drivetrain.study.batch import Engine
from drivetrain.study.runner import BATCH, EMBEDDED_CONFIG, _by_motion, make_plan, run_batch

ROOT = Path(__file__).parents[1]
STUDY = {"study": 1, "name": "10,000-variant grid", "base": str(ROOT / "examples" / "ball_screw.yaml"),
         "parameters": {"mechanism.load.mass": {"start": "5 kg", "stop": "40 kg", "num": 25},
                        "mechanism.lead": {"start": "4 mm", "stop": "24 mm", "num": 20},
                        "profile[0].time": {"start": "0.3 s", "stop": "1.0 s", "num": 20}},
         "design": "grid"}


def _load() -> str:
    try:
        return ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "n/a"


def _agree(fast: dict[str, Any], ref: dict[str, Any]) -> bool:
    sel = ref["selection"].get("selected") or ref["candidates"][0]
    got = fast["selection"].get("selected") or fast["candidates"][0]
    if (got["motor"], got["gearbox"]) != (sel["motor"], sel["gearbox"]):
        return False
    return all(a["name"] == b["name"] and (a["margin"] == b["margin"] or (
        a["margin"] is not None and b["margin"] is not None and math.isclose(a["margin"], b["margin"], rel_tol=1e-12)))
        for a, b in zip(got["checks"], ref["checks"] if "checks" in ref else sel["checks"], strict=True))


def _children_cpu() -> float:
    """CPU time of this process's ended child processes (the embedded cluster's workers) [s]."""
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _cold_sweep(path: Path, src: str, extra_env: dict[str, str] | None = None) -> tuple[float, float]:
    """Wall and CPU time of ``sweep`` on 2 workers in a new Python process (with ``src`` first on
    its path if given, and ``extra_env`` in its environment); the CPU time of that process and its workers."""
    code = ("import sys; from drivetrain.study import load_study, sweep; "
            "sweep(load_study(sys.argv[1]), workers=2)")
    env = {**os.environ, **(extra_env or {})}
    if src:
        env["PYTHONPATH"] = os.pathsep.join([str(Path(src).resolve()), env.get("PYTHONPATH", "")])
    k0 = _children_cpu()
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", code, str(path)], check=True, env=env)
    return time.perf_counter() - t0, _children_cpu() - k0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sample", type=int, default=250, help="variants of the obvious loop (extrapolated)")
    ap.add_argument("--grid", default="25,20,20",
                    help="masses,leads,times of the grid (default the issue's 25,20,20; a smaller grid over the same "
                         "ranges is reported with its times scaled to 10,000 variants)")
    ap.add_argument("--workers", default="1,2,4", help="warm LocalCluster sizes to time")
    ap.add_argument("--against", default="", help="the src directory of another checkout: its cold `sweep` "
                    "and this one's, alternated --rounds times, side by side")
    ap.add_argument("--rounds", type=int, default=3, help="alternations of --against")
    ap.add_argument("--against-env", default="", help="VAR=VALUE[,VAR=VALUE] for the --against side only "
                    "(e.g. its own DRIVETRAIN_DATA_DIR and DRIVETRAIN_CACHE_DIR)")
    args = ap.parse_args()
    counts = [int(x) for x in args.grid.split(",")]
    for key, num in zip(STUDY["parameters"], counts, strict=True):
        STUDY["parameters"][key]["num"] = num
    against_env = dict(kv.split("=", 1) for kv in args.against_env.split(",") if kv)
    load0 = _load()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "grid.yaml"
        path.write_text(yaml.safe_dump(STUDY, sort_keys=False), encoding="utf-8")
        study = load_study(path)
        variants = study.variants()
        n = len(variants)
        plan = make_plan(study)  # warms this process (catalog, compiled code)
        # the obvious loop, on an evenly spaced sample
        step = max(1, n // args.sample)
        sample = list(range(0, n, step))[: args.sample]
        drivetrain.size(plan.axis_dict(variants[0]))
        t0, c0 = time.perf_counter(), time.process_time()
        for i in sample:
            drivetrain.size(plan.axis_dict(variants[i]))
        loop_per = (time.perf_counter() - t0) / len(sample)
        loop_cpu = (time.process_time() - c0) / len(sample)
        # agreement on a sample
        engine = Engine(study.spec.points)
        checked = sample[:: max(1, len(sample) // 100)]
        fast = engine.size_many([parse_axis(plan.axis_dict(variants[i])) for i in checked])  # as a task sizes them
        agree = sum(not isinstance(f, Exception) and _agree(f, drivetrain.size(plan.axis_dict(variants[i])).to_dict())
                    for f, i in zip(fast, checked, strict=True))
        # batched path, one process, every variant, in the runner's batches; side by side with the
        # mechanism checks computed axis by axis (prepare_many off), as before they were batched
        import drivetrain.sizing.mechanism_checks as mc

        items = _by_motion(list(enumerate(variants)), study.parameters)  # the runner's order
        prepare = mc.prepare_many
        times: dict[str, tuple[float, float]] = {}
        for mode in ("axis by axis", "batched"):
            mc.prepare_many = prepare if mode == "batched" else (lambda pairs: [None] * len(pairs))  # type: ignore[assignment]
            t0, c0 = time.perf_counter(), time.process_time()
            rows = [r for k in range(0, n, BATCH) for r in run_batch(plan, items[k:k + BATCH])]
            times[mode] = (time.perf_counter() - t0, time.process_time() - c0)
        mc.prepare_many = prepare
        one, one_cpu = times["batched"]
        n_ok = sum(bool(r["ok"]) for r in rows)
        # sweep on 2 local workers, as a user runs it: a new Python process (imports, catalog, cluster
        # start and the result table included)
        cold, cold_cpu = _cold_sweep(path, "")
        against: dict[str, list[tuple[float, float]]] = {"this": [], "against": []}
        for _ in range(args.rounds if args.against else 0):
            against["against"].append(_cold_sweep(path, args.against, against_env))
            against["this"].append(_cold_sweep(path, ""))
        # warm clusters of 1, 2, 4 workers
        import dask
        from distributed import Client, LocalCluster

        warm: dict[int, tuple[float, float]] = {}
        for w in (int(x) for x in args.workers.split(",")):
            with dask.config.set(EMBEDDED_CONFIG), LocalCluster(
                    n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
                    Client(cl) as client:
                client.run(run_batch, plan, list(enumerate(variants[:3])))  # every worker loads the catalog
                cpu0 = sum(client.run(time.process_time).values())
                t0 = time.perf_counter()
                sweep(study, scheduler=cl.scheduler_address)
                wall = time.perf_counter() - t0
                warm[w] = (wall, sum(client.run(time.process_time).values()) - cpu0)
                client.close()
    scale = 10_000 / n
    print(f"### study: {n:,}-variant grid ({' x '.join(map(str, counts))} masses x leads x move times), full catalog "
          "selection\n")
    if n != 10_000:
        print(f"Times below are for the {n:,} variants; the issue's 10,000-variant grid takes about {scale:.1f}x "
              "as long (the same ranges, per-variant cost independent of the grid's density).\n")
    print(f"{os.cpu_count()} CPUs; load average (1, 5, 15 min) {load0} at the start, {_load()} at the end; "
          f"{n_ok:,} variants pass.\n")
    print("| measure | wall time | CPU time (all processes) | CPU per variant | 2 cores from CPU | "
          "vs the obvious loop (wall; CPU) |")
    print("|---|---:|---:|---:|---:|---:|")
    loop_total, loop_cpu_total = loop_per * n, loop_cpu * n
    print(f"| obvious loop `drivetrain.size` per variant, 1 core ({len(sample)} variants, extrapolated) | "
          f"{loop_total:.1f} s | {loop_cpu_total:.1f} s | {loop_cpu * 1e3:.2f} ms | | 1x |")
    a_wall, a_cpu = times["axis by axis"]
    print(f"| batched path, 1 process, mechanism checks axis by axis (as before) | {a_wall:.1f} s | {a_cpu:.1f} s | "
          f"{a_cpu / n * 1e3:.2f} ms | | {loop_total / a_wall:.1f}x; {loop_cpu_total / a_cpu:.1f}x |")
    print(f"| batched path, 1 process | {one:.1f} s | {one_cpu:.1f} s | {one_cpu / n * 1e3:.2f} ms | | "
          f"{loop_total / one:.1f}x; {loop_cpu_total / one_cpu:.1f}x |")
    print(f"| `sweep`, embedded LocalCluster of 2 processes, everything included | {cold:.1f} s | {cold_cpu:.1f} s | "
          f"{cold_cpu / n * 1e3:.2f} ms | {cold_cpu / 2:.1f} s | {loop_total / cold:.1f}x; "
          f"{loop_cpu_total / (cold_cpu / 2):.1f}x |")
    for w, (t, cpu) in warm.items():
        print(f"| `sweep`, warm LocalCluster {w} process{'es' if w > 1 else ''} | {t:.1f} s | {cpu:.1f} s (workers) | "
              f"{cpu / n * 1e3:.2f} ms | | {loop_total / t:.1f}x; |")
    if warm:
        base = min(warm)
        print("\nThroughput of the warm clusters (variants per second of wall time): " + ", ".join(
            f"{w} worker{'s' if w > 1 else ''} {n / t:,.0f} ({(warm[base][0] / t):.2f}x {base})"
            for w, (t, _) in warm.items()) + f"; {os.cpu_count()} CPUs.")
    if against["this"]:
        def med(xs: list[tuple[float, float]], k: int) -> float:
            return sorted(x[k] for x in xs)[len(xs) // 2]

        print(f"\nCold `sweep` on 2 workers, alternated {len(against['this'])} times with `{args.against}`: "
              + "; ".join(f"{name}: wall {', '.join(f'{x[0]:.1f}' for x in xs)} s (median {med(xs, 0):.1f} s), "
                          f"CPU {', '.join(f'{x[1]:.1f}' for x in xs)} s (median {med(xs, 1):.1f} s)"
                          for name, xs in against.items()) + ".")
    print(f"\nAgreement with `drivetrain.size` (selected motor, gearbox, every margin): {agree} of {len(checked)} "
          "sampled variants. Target (issue 15): < 10 s on 2 cores, >= 20x the obvious loop.")


if __name__ == "__main__":
    main()
