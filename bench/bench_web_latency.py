"""Latency of a sizing request with 1, 4 and 16 clients: is the server fair?

For each client count, starts `drivetrain serve` (one server process, a temporary data folder),
warms it up, and keeps that many clients posting the shipped example to /api/size back to back
for ``--seconds`` (each request a slightly different load mass, so each is a full sizing). Prints a
markdown table of p50 / p95 / p99 / max latency per client count and the fairness target: at 4
clients, p99 within 3x p50 (the sizing workers are handed out first come, first served, so no
request waits behind newer ones; before, p99 was 24-40x p50 and the maximum 17.6 s).

The load comes from wrk when it is on PATH, else from one Python thread per client (which then
competes with the server for the cores: the figures include that). The machine's load average is
printed with the table: on a shared machine the absolute figures move with it, the ratio less.

    python bench/bench_web_latency.py                  # 1, 4 and 16 clients, 30 s each
    python bench/bench_web_latency.py --clients 4 --seconds 60
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_web_load

ROOT = Path(__file__).resolve().parents[1]
TARGET_RATIO = 3.0
"""p99 / p50 at 4 clients must be at most this."""
TARGET_CLIENTS = 4


def measure(clients: int, seconds: float, client: str) -> dict[str, Any]:
    args = argparse.Namespace(clients=clients, seconds=seconds, max_requests=None,
                              axis=str(ROOT / "examples" / "ball_screw.yaml"), motor=None, same=False, client=client,
                              workers=1, think=0.0)
    return bench_web_load.run(args)


def table(rows: list[dict[str, Any]], load: tuple[float, float, float]) -> str:
    out = [f"load average before: {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min) on "
           f"{os.cpu_count()} cores; {rows[0]['generator']}; one server process, "
           f"{rows[0]['seconds']:.0f} s per client count", "",
           "| clients | requests | throughput | p50 | p95 | p99 | max | p99 / p50 | errors |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = r["p99"] / r["p50"] if r["p50"] > 0 else float("nan")
        mark = ""
        if r["clients"] == TARGET_CLIENTS:
            mark = f" ({'met' if ratio <= TARGET_RATIO else 'missed'}: target <= {TARGET_RATIO:g})"
        out.append(f"| {r['clients']} | {r['requests']} | {r['throughput']:.1f} req/s | {r['p50']:.0f} ms | "
                   f"{r['p95']:.0f} ms | {r['p99']:.0f} ms | {r['max']:.0f} ms | {ratio:.2f}{mark} | "
                   f"{r['errors']}{' (' + r['error_detail'] + ')' if r['error_detail'] else ''} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--clients", type=int, nargs="+", default=[1, 4, 16])
    p.add_argument("--seconds", type=float, default=30.0)
    have_wrk = shutil.which("wrk") is not None
    p.add_argument("--client", choices=["wrk", "python"], default="wrk" if have_wrk else "python",
                   help="load generator (default wrk when it is on PATH, else Python threads)")
    args = p.parse_args(argv)
    if not all(1 <= c <= 200 for c in args.clients) or not 0 < args.seconds <= 600:
        p.error("--clients 1..200 and --seconds up to 600")
    load = os.getloadavg()
    rows = [measure(c, args.seconds, args.client) for c in args.clients]
    print(table(rows, load))
    target = [r for r in rows if r["clients"] == TARGET_CLIENTS]
    met = all(r["p99"] <= TARGET_RATIO * r["p50"] for r in target)
    return 0 if met and all(r["errors"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
