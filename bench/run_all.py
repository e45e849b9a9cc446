"""Run every benchmark in this folder and print their markdown tables (``make bench``).

Each benchmark measures drivetrain against a peer in the same run and reports ratios; the
tables in the README come from this output.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).parent
# the web load test twice: clients re-sizing at the page's own pace (one request, the answer, the
# page's 250 ms debounce, the next) and clients sending back to back (the server saturated); then the
# latency percentiles with 1, 4 and 16 clients (fairness: p99 within 3x p50 at 4 clients)
BENCHES: list[tuple[str, list[str]]] = [
    ("bench_size.py", []), ("bench_select.py", []), ("bench_select_drives.py", []), ("bench_dynamic_select.py", []),
    ("bench_dynamic_select.py", ["--study"]), ("bench_simulate.py", []),
    ("bench_study.py", []), ("bench_startup.py", []), ("bench_pip_first_run.py", []), ("bench_duty.py", []),
    ("bench_scale.py", []), ("bench_move.py", []),
    ("bench_web_load.py", ["--workers", "2", "--think", "250"]), ("bench_web_load.py", ["--workers", "2"]),
    ("bench_web_latency.py", []),
]


def main() -> int:
    status = 0
    for name, args in BENCHES:
        path = HERE / name
        if not path.exists():
            continue
        print(f"\n## {' '.join([name, *args])}\n", flush=True)
        proc = subprocess.run([sys.executable, str(path), *args], check=False)
        status = status or proc.returncode
    return status


if __name__ == "__main__":
    sys.exit(main())
