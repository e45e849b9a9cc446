"""The first ``drivetrain size examples/ball_screw.yaml`` after a plain ``pip install`` (issue 31).

Builds a wheel of this checkout (``pip wheel --no-deps``), installs it with its dependencies into a
fresh virtual environment in a temporary folder (with ``constraints.txt``: the tested versions; pip's
own download cache serves them when warm), then runs ``drivetrain size examples/ball_screw.yaml`` as a
user would: the first time with empty data, cache and numba cache folders (``DRIVETRAIN_DATA_DIR``,
``DRIVETRAIN_CACHE_DIR``, ``NUMBA_CACHE_DIR``: the catalog database is built, nothing is remembered),
then a second and later times in the same folders. Each figure is one whole process: its wall time and
its CPU time (user + system, ``resource.getrusage(RUSAGE_CHILDREN)``); the first run is repeated in
fresh folders ``--runs`` times, and the later ones as often, and the median and range are printed.
Also printed: whether the sizing imported numba (it must not: the checks are numpy), and how long the
wheel and the install took. Run: ``python bench/bench_pip_first_run.py [--runs N] [--keep DIR]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
AXIS = ROOT / "examples" / "ball_screw.yaml"
TARGET_FIRST = 2.0
"""[s] the first answer after a plain pip install, whole process (issue 31)."""
PROBE = ("import sys; from drivetrain.cli import main; code = main(['size', sys.argv[1]]); "
         "print('numba imported:', 'numba' in sys.modules, file=sys.stderr)")


def _timed(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(wall, CPU) seconds of one whole process; its output is discarded, a failure raised."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):  # 1: sized, nothing passes
        raise RuntimeError(f"{' '.join(cmd)} exited {done.returncode}: {done.stderr[-2000:]}")
    return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


def _row(label: str, runs: list[tuple[float, float]], target: float | None = None) -> str:
    wall = [r[0] for r in runs]
    cpu = [r[1] for r in runs]
    met = "" if target is None else ("yes" if statistics.median(wall) <= target else "NO")
    return (f"| {label} | {len(runs)} | {statistics.median(wall):.2f} ({min(wall):.2f}-{max(wall):.2f}) | "
            f"{statistics.median(cpu):.2f} ({min(cpu):.2f}-{max(cpu):.2f}) | "
            f"{'' if target is None else f'<= {target}'} | {met} |")


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--keep", type=Path, help="build the environment in this folder and keep it")
    opts = parser.parse_args()
    work = opts.keep or Path(tempfile.mkdtemp(prefix="drivetrain-pip-"))
    base = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONDONTWRITEBYTECODE", "VIRTUAL_ENV")}
    base["PIP_CONSTRAINT"] = str(ROOT / "constraints.txt")
    try:
        t0 = time.perf_counter()
        dist = work / "dist"
        subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", str(dist), str(ROOT)],
                       env=base, check=True)
        (wheel,) = dist.glob("drivetrain-*.whl")
        t_wheel = time.perf_counter() - t0
        env_dir = work / "venv"
        venv.EnvBuilder(with_pip=True, clear=True).create(env_dir)
        python = env_dir / "bin" / "python"
        t0 = time.perf_counter()
        subprocess.run([str(python), "-m", "pip", "install", "--quiet", str(wheel)], env=base, check=True)
        t_install = time.perf_counter() - t0
        cli = [str(env_dir / "bin" / "drivetrain"), "size", str(AXIS)]
        firsts, laters = [], []
        for k in range(opts.runs):
            state = work / f"state-{k}"
            env = {**base, "DRIVETRAIN_DATA_DIR": str(state / "data"), "DRIVETRAIN_CACHE_DIR": str(state / "cache"),
                   "NUMBA_CACHE_DIR": str(state / "numba"), "HOME": str(state / "home")}
            firsts.append(_timed(cli, env))
            laters.append(_timed(cli, env))
        probe = subprocess.run([str(python), "-c", PROBE, str(AXIS)], env=env, capture_output=True, text=True,
                               check=False).stderr.strip().splitlines()[-1]
    finally:
        if opts.keep is None:
            shutil.rmtree(work, ignore_errors=True)
    print("### first `drivetrain size examples/ball_screw.yaml` after `pip install` of a wheel, whole process "
          "(median, range in brackets)\n")
    print("| run | processes | wall time [s] | CPU time [s] | target (wall) [s] | met |")
    print("|---|---:|---:|---:|---:|---|")
    print(_row("first, empty data, cache and numba cache folders", firsts, TARGET_FIRST))
    print(_row("second, same folders", laters))
    print(f"\nWheel built in {t_wheel:.1f} s, installed with its dependencies (constraints.txt; pip's download cache "
          f"as this machine had it) in {t_install:.1f} s; the sizing process: {probe}. Load average (1 min) at the "
          f"end: {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
