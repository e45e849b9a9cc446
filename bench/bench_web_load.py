"""Load test of the web app on loopback: N concurrent clients re-sizing an axis for a fixed time.

Starts `drivetrain serve` on 127.0.0.1 (a free port, a temporary data folder), warms it up, then
runs ``--clients`` threads, each posting the axis to /api/size in a loop until ``--seconds`` have
passed or ``--max-requests`` were sent in all. Prints a markdown table: throughput, latency
percentiles, errors and the server's resident memory at the start and the end.

    python bench/bench_web_load.py                       # the shipped example: 20 clients, 60 s
    python bench/bench_web_load.py --motor HG-KR43       # same axis with a given motor (no selection)
    python bench/bench_web_load.py --same                # the identical axis every time (answered from the cache)

By default every request carries a slightly different load mass, so each one is a real sizing
(the server keeps the answers to identical axes); ``--same`` measures the cached path.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx

ROOT = Path(__file__).resolve().parents[1]
TARGET_P95_MS = 100.0


def rss_mb(pid: int) -> float:
    """Resident set size of a process [MB] (Linux /proc)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return float("nan")
    m = re.search(r"^VmRSS:\s+(\d+)\s+kB", text, re.M)
    return int(m.group(1)) / 1024 if m else float("nan")


def percentile(sorted_values: list[float], q: float) -> float:
    if not sorted_values:
        return float("nan")
    k = min(len(sorted_values) - 1, max(0, round(q / 100 * (len(sorted_values) - 1))))
    return sorted_values[k]


def start_server(data_dir: str) -> tuple[subprocess.Popen[str], str]:
    env = {**os.environ, "DRIVETRAIN_DATA_DIR": data_dir, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "drivetrain.cli", "serve", "--host", "127.0.0.1", "--port", "0",
                             "--data-dir", data_dir], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    assert proc.stdout is not None
    line = proc.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:\d+", line)
    if not m:
        proc.kill()
        raise SystemExit(f"the server did not start: {line}{proc.stderr.read() if proc.stderr else ''}")
    return proc, m.group(0)


def load_axis(path: Path, motor: str | None) -> dict[str, Any]:
    from drivetrain.axis import parse_yaml

    axis = parse_yaml(path.read_text(encoding="utf-8"))
    assert isinstance(axis, dict)
    if motor:
        margins = (axis.get("motor") or {}).get("margins")
        axis["motor"] = {"id": motor, **({"margins": margins} if margins else {})}
    return axis


def vary(axis: dict[str, Any], n: int) -> dict[str, Any]:
    """The axis with the load mass changed by n micrograms: a distinct axis for every request."""
    mech = dict(axis["mechanism"])
    load = dict(mech.get("load") or {})
    from drivetrain.units import parse

    base = parse(load.get("mass", 1.0), "mass", "mass")
    load["mass"] = f"{base + n * 1e-9:.12g} kg"
    mech["load"] = load
    return {**axis, "mechanism": mech}


def run(args: argparse.Namespace) -> dict[str, Any]:
    axis = load_axis(Path(args.axis), args.motor)
    with tempfile.TemporaryDirectory(prefix="drivetrain-bench-") as data_dir:
        proc, url = start_server(data_dir)
        try:
            with httpx.Client(base_url=url, timeout=60) as c:
                for _ in range(3):  # warm-up: catalog build, first imports
                    r = c.post("/api/size", json=axis)
                    if r.status_code != 200:
                        raise SystemExit(f"the axis does not size: {r.status_code} {r.text[:300]}")
            rss_start = rss_mb(proc.pid)
            latencies: list[float] = []
            errors: list[str] = []
            lock = threading.Lock()
            sent = 0
            deadline = time.monotonic() + args.seconds
            rss_peak = rss_start

            def client() -> None:
                nonlocal sent
                with httpx.Client(base_url=url, timeout=args.seconds + 30) as c:
                    while time.monotonic() < deadline:
                        with lock:
                            if sent >= args.max_requests:
                                return
                            sent += 1
                            n = sent
                        body = axis if args.same else vary(axis, n)
                        t0 = time.perf_counter()
                        try:
                            r = c.post("/api/size", json=body)
                            ok = r.status_code == 200
                            detail = f"{r.status_code}" if not ok else ""
                        except httpx.HTTPError as exc:
                            ok, detail = False, type(exc).__name__
                        dt = (time.perf_counter() - t0) * 1e3
                        with lock:
                            latencies.append(dt)
                            if not ok:
                                errors.append(detail)

            threads = [threading.Thread(target=client, daemon=True) for _ in range(args.clients)]
            t_start = time.monotonic()
            for t in threads:
                t.start()
            while any(t.is_alive() for t in threads):
                time.sleep(1.0)
                rss_peak = max(rss_peak, rss_mb(proc.pid))
            elapsed = time.monotonic() - t_start
            rss_end = rss_mb(proc.pid)
        finally:
            proc.terminate()
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
    lat = sorted(latencies)
    return {"clients": args.clients, "seconds": elapsed, "requests": len(lat), "throughput": len(lat) / elapsed,
            "p50": percentile(lat, 50), "p95": percentile(lat, 95), "p99": percentile(lat, 99),
            "max": lat[-1] if lat else float("nan"), "errors": len(errors), "rss_start": rss_start,
            "rss_end": rss_end, "rss_peak": rss_peak,
            "axis": Path(args.axis).name + (f" + motor {args.motor}" if args.motor else "")
            + (", identical every time (cache)" if args.same else ", a different mass every request")}


def table(r: dict[str, Any]) -> str:
    verdict = "met" if r["p95"] < TARGET_P95_MS else "missed"
    rows = [
        ("axis", r["axis"]),
        ("clients x duration", f"{r['clients']} x {r['seconds']:.1f} s"),
        ("requests", f"{r['requests']}"),
        ("throughput", f"{r['throughput']:.1f} req/s"),
        ("latency p50 / p95 / p99", f"{r['p50']:.0f} / {r['p95']:.0f} / {r['p99']:.0f} ms"),
        ("latency max", f"{r['max']:.0f} ms"),
        (f"target p95 < {TARGET_P95_MS:.0f} ms", verdict),
        ("errors", f"{r['errors']}"),
        ("server RSS start / peak / end", f"{r['rss_start']:.0f} / {r['rss_peak']:.0f} / {r['rss_end']:.0f} MB"),
    ]
    out = ["| quantity | value |", "|---|---|"]
    out += [f"| {k} | {v} |" for k, v in rows]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--clients", type=int, default=20)
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--max-requests", type=int, default=200_000, help="stop after this many requests in all")
    p.add_argument("--axis", default=str(ROOT / "examples" / "ball_screw.yaml"))
    p.add_argument("--motor", help="replace the axis's motor section by this catalog motor (no selection)")
    p.add_argument("--same", action="store_true", help="send the identical axis every time (measures the cache)")
    args = p.parse_args(argv)
    if not 1 <= args.clients <= 200 or not 0 < args.seconds <= 600:
        p.error("--clients 1..200 and --seconds up to 600")
    result = run(args)
    print(table(result))
    return 0 if result["errors"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
