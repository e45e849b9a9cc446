"""Selection at scale: cost and peak memory against the number of samples per cycle.

The 10-move S-curve ball-screw cycle of ``bench_select.py`` sampled at 10^3 ... 10^6 points, each
size in a fresh process (so the peak resident memory is that size's own), through the whole
catalog selection (``selection.evaluate``: every catalog motor, direct and behind every servo
gearbox row) after one untimed call that loads the compiled pass. Times are CPU time of the
process (``time.process_time``, min of the runs; the machine may be shared, wall time is noisy);
peak memory is the process's maximum resident set (``resource.getrusage``) minus that before the
selection (imports, catalog, duty cycle). Also the selection's own memory per candidate.
Run: ``.venv/bin/python bench/bench_scale.py``.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from typing import Any

os.environ.setdefault("DRIVETRAIN_DATA_DIR", tempfile.mkdtemp(prefix="drivetrain-bench-"))

SIZES = (1_000, 10_000, 100_000, 1_000_000)
RUNS = 3


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def one(samples: int) -> dict[str, Any]:
    """Time and memory of the selection on a cycle of about ``samples`` samples (in this process)."""
    from drivetrain import catalog
    from drivetrain.axis.model import Margins, parse_axis
    from drivetrain.duty.cycle import duty_from_samples
    from drivetrain.motion import cycle as cycle_module
    from drivetrain.sizing.selection import evaluate

    cycle_module.MAX_SAMPLES = 2_000_000  # the axis file's guard (500,000) lifted to measure 10^6

    sys.path.insert(0, os.path.dirname(__file__))
    from bench_select import AXIS

    axis = parse_axis(AXIS)
    cycle = axis.cycle()
    pieces = 70  # 10 moves x 7 pieces
    grid = cycle.sample(max(2, samples // pieces + 1))
    m = catalog.motors()
    gb = catalog.gearboxes(kind="servo_gearbox")
    t0 = time.process_time()
    duty = duty_from_samples(axis, cycle, grid)
    t_duty = time.process_time() - t0
    small = parse_axis(AXIS)
    evaluate(small, duty_from_samples(small, cycle, cycle.sample(3)), m, gb, Margins())  # load the compiled pass
    before = _rss_mb()
    runs = []
    for _ in range(RUNS):
        t0 = time.process_time()
        c = evaluate(axis, duty, m, gb, Margins())
        runs.append(time.process_time() - t0)
    return {"samples": len(duty.t), "candidates": len(c.motor), "duty_s": t_duty, "select_s": min(runs),
            "peak_mb": _rss_mb() - before, "process_peak_mb": _rss_mb()}


def main() -> None:
    if len(sys.argv) > 2 and sys.argv[1] == "--one":
        print(json.dumps(one(int(sys.argv[2]))))
        return
    rows = []
    for n in SIZES:
        out = subprocess.run([sys.executable, __file__, "--one", str(n)], check=True, capture_output=True,
                             text=True).stdout
        rows.append(json.loads(out.strip().splitlines()[-1]))
    print(f"### selection against samples per cycle ({rows[0]['candidates']:,} candidates, CPU time, "
          f"min of {RUNS}, one process per size)\n")
    print("| samples | selection CPU time | per 10^6 candidate-samples | added peak memory | process peak |")
    print("|---:|---:|---:|---:|---:|")
    for r in rows:
        per = r["select_s"] / (r["samples"] * r["candidates"]) * 1e12
        print(f"| {r['samples']:,} | {r['select_s'] * 1e3:,.0f} ms | {per:.2f} us | {r['peak_mb']:,.0f} MB | "
              f"{r['process_peak_mb']:,.0f} MB |")
    big = rows[-1]
    print(f"\n| target (issue 16) | measured | required | met |\n|---|---:|---:|---|\n"
          f"| selection at {big['samples']:,} samples [s CPU] | {big['select_s']:.2f} | <= 1 | "
          f"{'yes' if big['select_s'] <= 1 else 'NO'} |\n"
          f"| its added peak memory [MB] | {big['peak_mb']:,.0f} | <= 200 | "
          f"{'yes' if big['peak_mb'] <= 200 else 'NO'} |")


if __name__ == "__main__":
    main()
