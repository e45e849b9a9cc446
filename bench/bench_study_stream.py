"""Memory of a streamed study: a 10^9-variant grid run with ``--yes`` in this process, its resident
memory printed every 2,000 rows; it stops after ``--rows`` rows (the rows so far stay in the partial
table). Run: ``python bench/bench_study_stream.py --rows 40000``.
"""

from __future__ import annotations

import argparse
import contextlib
import tempfile
import time
from pathlib import Path

import yaml

from drivetrain.study import load_study
from drivetrain.study.stream import run

BASE = Path(__file__).resolve().parents[1] / "tests" / "axes" / "yaskawa_es_30w.yaml"


class _Enough(Exception):
    pass


def _rss_mb() -> int:
    with open("/proc/self/status", encoding="ascii") as fh:
        for line in fh:
            if line.startswith("VmRSS"):
                return int(line.split()[1]) // 1024
    return -1


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rows", type=int, default=40_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        study_file = Path(tmp) / "big.yaml"
        study_file.write_text(yaml.safe_dump({"study": 1, "base": str(BASE), "parameters": {
            "mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "num": 31_623},
            "profile[0].time": {"start": 0.5, "stop": 1.5, "num": 31_623}}}), encoding="utf-8")
        study = load_study(study_file, yes=True)
        print(f"{study.n_variants():,} variants")
        print("| rows | resident memory | time |")
        print("|---|---|---|")
        t0 = time.monotonic()
        last = [0]

        def on_rows(n: int) -> None:
            if n - last[0] >= 2000:
                last[0] = n
                print(f"| {n:,} | {_rss_mb()} MB | {time.monotonic() - t0:.0f} s |", flush=True)
            if n >= args.rows:
                raise _Enough

        with contextlib.suppress(_Enough):
            run(study, out=Path(tmp) / "big.parquet", workers=0, batch=200, on_rows=on_rows)


if __name__ == "__main__":
    main()
