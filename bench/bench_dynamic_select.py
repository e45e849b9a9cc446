"""Benchmark: `drivetrain size` of examples/belt_dynamic.yaml with its dynamic requirements against the same
axis without them, whole process, alternated in one run.

Four commands, each a fresh `drivetrain` process (warm: bytecode, catalog and the simulation's compiled
kernels cached by a first run): the axis without `requirements:` (the static selection); with them as
shipped (2 candidates judged: the first fails its phase margin, a linear check, and is not simulated; the
second is simulated and passes); `candidates: 20` with an 80 deg phase margin no candidate meets (20
judged, each decided by its linear loop: nothing simulated, the compiled kernel never loaded); and
`candidates: 20` with a settling window (1 um in 1 ms) no candidate meets and the default margins (20
judged and 20 simulated). Reported: the median CPU time of each and the ratios to the static one; the
target is at most 1.5 for 20 candidates.

Then a study (``--study``): the same axis over a 16-value grid of load mass, with and without its
requirements (as shipped, and with a 30 deg phase margin that the static pick meets), in this process
after a warm-up run, CPU per variant; the target is at most 3x per variant.
Run: ``.venv/bin/python bench/bench_dynamic_select.py [--study]`` (``BENCH_RUNS`` alternated runs, default 5).
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "belt_dynamic.yaml"
RUNS = int(os.environ.get("BENCH_RUNS", "5"))


def _cpu(cmd: list[str]) -> float:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    exe = str(Path(sys.executable).with_name("drivetrain"))
    data = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))
    with tempfile.TemporaryDirectory() as folder:
        static = dict(data)
        static.pop("requirements")
        twenty = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))
        twenty["requirements"].update({"candidates": 20, "stability": {"phase_margin": "80 deg"}})
        simulated = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))
        simulated["requirements"].update({"candidates": 20, "settling": {"window": "1 um", "time": "1 ms"},
                                          "stability": {"phase_margin": "30 deg"}})
        files = {"static": Path(folder, "static.yaml"), "shipped": EXAMPLE, "20 linear": Path(folder, "twenty.yaml"),
                 "20 simulated": Path(folder, "simulated.yaml")}
        files["static"].write_text(yaml.safe_dump(static), encoding="utf-8")
        files["20 linear"].write_text(yaml.safe_dump(twenty), encoding="utf-8")
        files["20 simulated"].write_text(yaml.safe_dump(simulated), encoding="utf-8")
        env = dict(os.environ)
        cmds = {k: [exe, "size", str(p)] for k, p in files.items()}
        for c in cmds.values():  # warm-up
            subprocess.run(c, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        times: dict[str, list[float]] = {k: [] for k in cmds}
        for _ in range(RUNS):  # alternated, so a drift of the machine's speed hits all alike
            for k, c in cmds.items():
                times[k].append(_cpu(c))
    base = statistics.median(times["static"])
    print(f"drivetrain size, whole process, warm, CPU median of {RUNS} (alternated):")
    for k, t in times.items():
        m = statistics.median(t)
        print(f"  {k:14s} {m:.3f} s  ratio {m / base:.2f}")


def study() -> None:
    """CPU per variant of a study with requirements against the same study without them."""
    import copy
    import time

    from drivetrain.study import sweep

    data = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))
    static = copy.deepcopy(data)
    del static["requirements"]
    met = copy.deepcopy(data)
    met["requirements"]["stability"] = {"phase_margin": "30 deg"}
    per: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as folder:
        for name, base in (("static", static), ("requirements (shipped)", data), ("requirements (30 deg)", met)):
            b = Path(folder, "base.yaml")
            b.write_text(yaml.safe_dump(base), encoding="utf-8")
            s = Path(folder, "study.yaml")
            s.write_text(yaml.safe_dump({"study": 1, "base": str(b), "design": "grid", "parameters": {
                "mechanism.load.mass": {"start": "6 kg", "stop": "20 kg", "num": 16}}}), encoding="utf-8")
            sweep(s, workers=0)  # warm
            runs = []
            for _ in range(3):
                t = time.process_time()
                n = len(sweep(s, workers=0).table)
                runs.append((time.process_time() - t) / n)
            per[name] = statistics.median(runs)
    print("study, 16 variants in this process, CPU per variant, median of 3:")
    for k, v in per.items():
        print(f"  {k:24s} {v * 1e3:.1f} ms  ratio {v / per['static']:.2f}")


if __name__ == "__main__":
    study() if "--study" in sys.argv else main()
