"""Run every benchmark in this folder and print their markdown tables (``make bench``).

Each benchmark measures drivetrain against a peer in the same run and reports ratios; the
tables in the README come from this output.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).parent
BENCHES = ["bench_size.py", "bench_select.py", "bench_simulate.py", "bench_web_load.py"]


def main() -> int:
    status = 0
    for name in BENCHES:
        path = HERE / name
        if not path.exists():
            continue
        print(f"\n## {name}\n", flush=True)
        proc = subprocess.run([sys.executable, str(path)], check=False)
        status = status or proc.returncode
    return status


if __name__ == "__main__":
    sys.exit(main())
