"""Whole-process start-up: ``drivetrain size examples/ball_screw.yaml`` and ``drivetrain simulate
examples/belt.yaml`` as a user runs them, warm and the first time.

"warm", which is also the first run after ``make setup``: numba's cache of the simulation's kernels,
the catalog database and the remembered unit factors exist (make setup's warm-up step runs these
commands once; a sizing needs no compiled code). "first run after make setup of a file its warm-up
did not run": the caches as the warm-up left them (copied afresh for each run), another example
(other units to convert, other kernel arguments). "first run, no warm-up": a copy of
the package (its bytecode kept, as pip leaves it) with no compiled-kernel cache, an empty data
folder and an empty cache folder: what the first command costs when nothing ran before it.
Each figure is the min over the runs of the child's CPU time (user + system, from
``resource.getrusage(RUSAGE_CHILDREN)``) and, beside it, its wall time: the machine may be shared,
so wall time is noisy; CPU time is not inflated by waiting (on an idle machine the wall time
approaches it). The warm ``size`` is also timed against ``python -c "import numpy"`` (the start-up
target of issue 28: at most 2.5 times its CPU time), the two alternating, the ratio taken pair by pair
so that a change of the machine's load during the run moves both. Run:
``.venv/bin/python bench/bench_startup.py [--runs N]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = {"size": ["size", str(ROOT / "examples" / "ball_screw.yaml")],
            "simulate": ["simulate", str(ROOT / "examples" / "belt.yaml")]}
OTHER = {"size": ["size", str(ROOT / "examples" / "rack_pinion.yaml")],
         "simulate": ["simulate", str(ROOT / "examples" / "ball_screw.yaml")]}
"""First run after ``make setup`` of an axis file its warm-up did not run (units not yet remembered ...)."""
TARGETS = {("size", "after-setup"): 2.0, ("simulate", "after-setup"): 2.0}
NUMPY_RATIO = 2.5
"""Target of the warm ``size``: at most this many times the CPU time of ``python -c "import numpy"``."""


def _package_dir() -> Path:
    import drivetrain

    return Path(drivetrain.__file__).parent


def _run(args: list[str], env: dict[str, str], command: list[str] | None = None) -> tuple[float, float]:
    """(CPU time, wall time) of one whole ``python -m drivetrain.cli`` process (or ``command``) [s]."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    cmd = command if command is not None else [sys.executable, "-m", "drivetrain.cli", *args]
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, wall


def _fresh_copy(into: Path) -> Path:
    """A copy of the package without numba's cache files (bytecode kept), on its own path."""
    dest = into / "site" / "drivetrain"
    shutil.copytree(_package_dir(), dest, ignore=shutil.ignore_patterns("*.nbi", "*.nbc"))
    return dest.parent


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=7)
    opts = parser.parse_args()
    base = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    base["PYTHONPATH"] = str(_package_dir().parent)
    rows: list[tuple[str, str, float, float]] = []
    with tempfile.TemporaryDirectory(prefix="drivetrain-startup-") as tmp:
        warm_env = {**base, "DRIVETRAIN_DATA_DIR": str(Path(tmp) / "warm-data"),
                    "DRIVETRAIN_CACHE_DIR": str(Path(tmp) / "warm-cache")}
        for args in COMMANDS.values():
            _run(args, warm_env)  # the warm-up of make setup
        setup = Path(tmp) / "after-setup"
        shutil.copytree(Path(tmp) / "warm-cache", setup / "cache")
        shutil.copytree(Path(tmp) / "warm-data", setup / "data")
        for name, args in COMMANDS.items():
            runs = [_run(args, warm_env) for _ in range(opts.runs)]
            rows.append((name, "warm", min(r[0] for r in runs), min(r[1] for r in runs)))
        numpy_cmd = [sys.executable, "-c", "import numpy"]
        pairs = [(_run(COMMANDS["size"], warm_env), _run([], warm_env, numpy_cmd)) for _ in range(opts.runs)]
        for name, args in OTHER.items():
            firsts = []
            for k in range(max(1, opts.runs // 3)):  # each on a fresh copy of the caches as make setup left them
                state = Path(tmp) / f"after-setup-{name}-{k}"
                shutil.copytree(setup, state)
                env = {**base, "DRIVETRAIN_DATA_DIR": str(state / "data"), "DRIVETRAIN_CACHE_DIR": str(state / "cache")}
                firsts.append(_run(args, env))
            rows.append((name, "after-setup", min(r[0] for r in firsts), min(r[1] for r in firsts)))
        for name, args in COMMANDS.items():
            firsts = []
            for k in range(max(1, opts.runs // 3)):
                site = _fresh_copy(Path(tmp) / f"{name}-{k}")
                env = {**base, "PYTHONPATH": str(site), "DRIVETRAIN_DATA_DIR": str(site.parent / "data"),
                       "DRIVETRAIN_CACHE_DIR": str(site.parent / "cache")}
                firsts.append(_run(args, env))
            rows.append((name, "first", min(r[0] for r in firsts), min(r[1] for r in firsts)))
    print(f"### whole process, `python -m drivetrain.cli ...` (min of {opts.runs} warm runs, "
          f"{max(1, opts.runs // 3)} first runs)\n")
    print("| command | state | CPU time [s] | wall time [s] | target [s] | met (CPU) |")
    print("|---|---|---:|---:|---:|---|")
    label = {"warm": "warm (also its first run after `make setup`, whose warm-up runs it)",
             "after-setup": "first run after `make setup` of a file its warm-up did not run",
             "first": "first run, no `make setup` (empty caches)"}
    for name, state, cpu, wall in rows:
        target = TARGETS.get((name, state))
        met = "" if target is None else ("yes" if cpu <= target else "NO")
        cmd = OTHER[name] if state == "after-setup" else COMMANDS[name]
        print(f"| `drivetrain {cmd[0]} examples/{Path(cmd[1]).name}` | "
              f"{label[state]} | {cpu:.2f} | {wall:.2f} | {'' if target is None else f'<= {target}'} | {met} |")
    ratios = sorted(a[0] / b[0] for a, b in pairs)
    walls = sorted(a[1] / b[1] for a, b in pairs)
    median = ratios[len(ratios) // 2]
    print(f"\nWarm `drivetrain size examples/ball_screw.yaml` against `python -c \"import numpy\"`, {len(pairs)} "
          f"alternating pairs: CPU ratio {median:.2f} ({ratios[0]:.2f}-{ratios[-1]:.2f}), wall ratio "
          f"{walls[len(walls) // 2]:.2f} ({walls[0]:.2f}-{walls[-1]:.2f}); numpy's import "
          f"{sorted(b[0] for _, b in pairs)[len(pairs) // 2]:.3f} s CPU (median); target <= {NUMPY_RATIO} x: "
          f"{'met' if median <= NUMPY_RATIO else 'NOT met'}.")
    print(f"\nLoad average (1 min) at the end: {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs.")


if __name__ == "__main__":
    main()
