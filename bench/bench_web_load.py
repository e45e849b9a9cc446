"""Load test of the web app on loopback: N concurrent clients re-sizing an axis for a fixed time.

Starts `drivetrain serve` on 127.0.0.1 (a free port, a temporary data folder, ``--workers``
server processes), warms it up, then keeps ``--clients`` connections posting the axis to /api/size
until ``--seconds`` have passed (or, with ``--client python``, ``--max-requests`` were sent).
Prints a markdown table: throughput, latency percentiles, errors and the server's resident memory
(summed over its processes) at the start, the peak and the end.

The load comes from wrk (Debian package ``wrk``; ``make bench`` installs it) when it is on PATH:
a C client that leaves the cores to the server. ``--client python`` uses one Python thread per
client instead, which competes with the server for the same cores and so measures both.

    python bench/bench_web_load.py                       # the shipped example: 20 clients, 60 s
    python bench/bench_web_load.py --motor HG-KR43       # same axis with a given motor (no selection)
    python bench/bench_web_load.py --same                # the identical axis every time (answered from the cache)
    python bench/bench_web_load.py --workers 2           # two server processes on one socket
    python bench/bench_web_load.py --think 250           # each client waits 250 ms between its requests

``--think 250`` is the page's own pace: the page sends a re-size 250 ms after the last edit
(SIZE_DELAY_MS in static/app.js), so a user who keeps typing makes it send one request, wait for
the answer, wait 250 ms, and send the next; without ``--think`` the clients saturate the server.

By default every request carries a slightly different load mass, so each one is a real sizing
(the server keeps the answers to identical axes); ``--same`` measures the cached path.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

import httpx

ROOT = Path(__file__).resolve().parents[1]
TARGET_P95_MS = 100.0
WRK_THREADS = 2
MASS_MARKER = "@@MASS@@"
"""Stands for the load mass in the JSON body template the wrk script fills in."""


def rss_mb(pid: int) -> float:
    """Resident set size of a process [MB] (Linux /proc)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return float("nan")
    m = re.search(r"^VmRSS:\s+(\d+)\s+kB", text, re.M)
    return int(m.group(1)) / 1024 if m else float("nan")


def process_tree(pid: int) -> list[int]:
    """``pid`` and all its descendants (Linux /proc): the server's supervisor and its workers."""
    parents: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue  # the process ended meanwhile
        parents.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo.extend(parents.get(p, []))
    return out


def tree_rss_mb(pid: int) -> float:
    """Resident memory of a process and its descendants [MB] (shared pages counted in each)."""
    return sum(v for v in (rss_mb(p) for p in process_tree(pid)) if v == v)  # v == v: skip NaN (ended)


def percentile(sorted_values: list[float], q: float) -> float:
    if not sorted_values:
        return float("nan")
    k = min(len(sorted_values) - 1, max(0, round(q / 100 * (len(sorted_values) - 1))))
    return sorted_values[k]


def start_server(data_dir: str, workers: int, log: IO[str]) -> tuple[subprocess.Popen[str], str]:
    """``drivetrain serve`` on a free loopback port; its stderr goes to ``log`` (a pipe nobody reads
    could fill and stall the server)."""
    env = {**os.environ, "DRIVETRAIN_DATA_DIR": data_dir, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "drivetrain.cli", "serve", "--host", "127.0.0.1", "--port", "0",
                             "--data-dir", data_dir, "--workers", str(workers)], stdout=subprocess.PIPE, stderr=log,
                            text=True, env=env)
    assert proc.stdout is not None
    line = proc.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:\d+", line)
    if not m:
        proc.kill()
        proc.wait()
        log.seek(0)
        raise SystemExit(f"the server did not start: {line}{log.read()}")
    return proc, m.group(0)


def stop_server(proc: subprocess.Popen[str]) -> None:
    """SIGTERM (the supervisor stops its workers), SIGKILL if it hangs (the workers follow it)."""
    proc.terminate()
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def load_axis(path: Path, motor: str | None) -> dict[str, Any]:
    from drivetrain.axis.yaml_text import parse_yaml

    axis = parse_yaml(path.read_text(encoding="utf-8"))
    assert isinstance(axis, dict)
    if motor:
        margins = (axis.get("motor") or {}).get("margins")
        axis["motor"] = {"id": motor, **({"margins": margins} if margins else {})}
    return axis


def base_mass(axis: dict[str, Any]) -> float:
    """The axis's load mass [kg]."""
    from drivetrain.units import parse

    return parse((axis["mechanism"].get("load") or {}).get("mass", 1.0), "mass", "mass")


def with_mass(axis: dict[str, Any], mass: str) -> dict[str, Any]:
    """The axis with the load mass replaced by the text ``mass``."""
    mech = dict(axis["mechanism"])
    mech["load"] = {**(mech.get("load") or {}), "mass": mass}
    return {**axis, "mechanism": mech}


def vary(axis: dict[str, Any], n: int) -> dict[str, Any]:
    """The axis with the load mass changed by n micrograms: a distinct axis for every request."""
    return with_mass(axis, f"{base_mass(axis) + n * 1e-9:.12g} kg")


def lua_string(text: str) -> str:
    """``text`` as a Lua long-bracket literal (no escapes to get wrong)."""
    level = 0
    while (text + f"]{'=' * level}]").find(f"]{'=' * level}]") != len(text):  # the first close must be ours
        level += 1
    eq = "=" * level
    return f"[{eq}[{text}]{eq}]"


def wrk_script(axis: dict[str, Any], same: bool, threads: int, think_ms: float) -> str:
    """The wrk Lua script: POST /api/size, each request a distinct axis unless ``same``.

    The body is the axis's JSON with the load mass formatted in per request, as ``vary`` does:
    request k of thread i (1-based) gets n = (k - 1) * threads + i, unique across threads. A
    ``delay()`` is defined only for a think time, since wrk then schedules every request on a timer.
    """
    lines = [
        'wrk.method = "POST"',
        'wrk.path = "/api/size"',
        'wrk.headers["Content-Type"] = "application/json"',
        "local threads = {}",
        "function setup(thread)",
        "  table.insert(threads, thread)",
        '  thread:set("id", #threads)',
        "end",
        "function init(args)",
        "  sent = 0",
        "end",
    ]
    if same:  # no request(): wrk sends its one prepared request
        lines.insert(0, f"wrk.body = {lua_string(json.dumps(axis))}")
    else:
        prefix, suffix = json.dumps(with_mass(axis, MASS_MARKER)).split(MASS_MARKER)
        lines += [
            f"local prefix, suffix = {lua_string(prefix)}, {lua_string(suffix)}",
            f"local base = {base_mass(axis)!r}",
            "function request()",
            "  sent = sent + 1",
            f"  local n = (sent - 1) * {threads} + id",
            '  return wrk.format(nil, nil, nil, prefix .. string.format("%.12g kg", base + n * 1e-9) .. suffix)',
            "end",
        ]
    if think_ms > 0:
        lines += ["function delay()", f"  return {think_ms:g}", "end"]
    lines += [
        "function done(summary, latency, requests)",
        "  local e = summary.errors",
        "  local out = {requests = summary.requests, duration_us = summary.duration,",
        "    connect = e.connect, read = e.read, write = e.write, status = e.status, timeout = e.timeout,",
        "    p50_us = latency:percentile(50), p95_us = latency:percentile(95), p99_us = latency:percentile(99),",
        "    max_us = latency.max}",
        "  for k, v in pairs(out) do",
        '    io.write(string.format("drivetrain-wrk %s %d\\n", k, v))',
        "  end",
        "end",
    ]
    return "\n".join(lines) + "\n"


def wrk_version() -> str:
    """wrk's version, e.g. "4.1" ("" if it does not say)."""
    try:
        out = subprocess.run(["wrk", "-v"], capture_output=True, text=True, timeout=10, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    m = re.search(r"(\d+\.\d+)", out.stdout + out.stderr)
    return m.group(1) if m else ""


def parse_wrk(output: str) -> dict[str, int]:
    """The ``drivetrain-wrk KEY VALUE`` lines the script's ``done()`` prints."""
    return {k: int(v) for k, v in re.findall(r"^drivetrain-wrk (\w+) (-?\d+)$", output, re.M)}


def warm_up(url: str, axis: dict[str, Any], workers: int) -> None:
    """A few sizings in every worker (catalog build, first imports) before the clock starts.

    Connections are spread over the workers by whichever accepts first, so several concurrent
    clients each open a new connection per request: every worker gets some with high probability.
    """
    failures: list[str] = []

    def one() -> None:
        for _ in range(3):
            r = httpx.post(url + "/api/size", json=axis, timeout=60)
            if r.status_code != 200:
                failures.append(f"{r.status_code} {r.text[:300]}")
                return

    threads = [threading.Thread(target=one) for _ in range(1 if workers == 1 else 2 * workers)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if failures:
        raise SystemExit(f"the axis does not size: {failures[0]}")


def python_load(args: argparse.Namespace, url: str, axis: dict[str, Any], sample: Callable[[], None]) -> dict[str, Any]:
    """One Python thread (httpx, keep-alive) per client; ``sample()`` is called every 0.5 s meanwhile."""
    latencies: list[float] = []
    errors: list[str] = []
    lock = threading.Lock()
    sent = 0
    deadline = time.monotonic() + args.seconds
    think = args.think / 1e3

    def client() -> None:
        nonlocal sent
        with httpx.Client(base_url=url, timeout=args.seconds + 30) as c:
            while time.monotonic() < deadline:
                with lock:
                    if args.max_requests is not None and sent >= args.max_requests:
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
                if think:
                    time.sleep(min(think, max(0.0, deadline - time.monotonic())))

    threads = [threading.Thread(target=client, daemon=True) for _ in range(args.clients)]
    t_start = time.monotonic()
    for t in threads:
        t.start()
    while any(t.is_alive() for t in threads):
        time.sleep(0.5)
        sample()
    elapsed = time.monotonic() - t_start
    lat = sorted(latencies)
    return {"seconds": elapsed, "requests": len(lat), "p50": percentile(lat, 50), "p95": percentile(lat, 95),
            "p99": percentile(lat, 99), "max": lat[-1] if lat else float("nan"), "errors": len(errors),
            "error_detail": "", "generator": "Python threads (httpx), one per client"}


def wrk_load(args: argparse.Namespace, url: str, axis: dict[str, Any], sample: Callable[[], None]) -> dict[str, Any]:
    """wrk with the script of ``wrk_script``; ``sample()`` is called every 0.5 s while it runs."""
    threads = min(WRK_THREADS, args.clients)  # wrk needs a connection per thread at least
    seconds = max(1, round(args.seconds))  # wrk takes whole seconds
    with tempfile.NamedTemporaryFile("w", suffix=".lua", prefix="drivetrain-wrk-") as script:
        script.write(wrk_script(axis, args.same, threads, args.think))
        script.flush()
        cmd = ["wrk", "-t", str(threads), "-c", str(args.clients), "-d", f"{seconds}s", "--timeout", "30s",
               "-s", script.name, url + "/api/size"]
        with tempfile.TemporaryFile("w+") as out:
            wrk = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, text=True)
            deadline = time.monotonic() + seconds + 60
            while wrk.poll() is None:
                if time.monotonic() > deadline:
                    wrk.kill()
                    wrk.wait()
                    raise SystemExit("wrk did not finish")
                time.sleep(0.5)
                sample()
            out.seek(0)
            text = out.read()
    r = parse_wrk(text)
    if wrk.returncode != 0 or "requests" not in r:
        raise SystemExit(f"wrk failed ({wrk.returncode}): {text[-2000:]}")
    kinds = ("connect", "read", "write", "status", "timeout")
    errors = sum(r[k] for k in kinds)
    version = wrk_version()
    return {"seconds": r["duration_us"] / 1e6, "requests": r["requests"], "p50": r["p50_us"] / 1e3,
            "p95": r["p95_us"] / 1e3, "p99": r["p99_us"] / 1e3, "max": r["max_us"] / 1e3, "errors": errors,
            "error_detail": ", ".join(f"{r[k]} {k}" for k in kinds if r[k]),
            "generator": f"wrk{' ' + version if version else ''}, {threads} thread{'s' if threads > 1 else ''}"}


def run(args: argparse.Namespace) -> dict[str, Any]:
    """Start the server, warm it up, load it with the chosen client; the numbers of the table."""
    axis = load_axis(Path(args.axis), args.motor)
    with tempfile.TemporaryDirectory(prefix="drivetrain-bench-") as data_dir, \
            tempfile.TemporaryFile("w+", prefix="drivetrain-bench-log-") as log:
        proc, url = start_server(data_dir, args.workers, log)
        try:
            warm_up(url, axis, args.workers)
            rss_start = tree_rss_mb(proc.pid)
            rss_peak = rss_start

            def sample() -> None:
                nonlocal rss_peak
                rss_peak = max(rss_peak, tree_rss_mb(proc.pid))

            load = wrk_load if args.client == "wrk" else python_load
            r = load(args, url, axis, sample)
            rss_end = tree_rss_mb(proc.pid)
            processes = len(process_tree(proc.pid))
        finally:
            stop_server(proc)
    return {**r, "clients": args.clients, "throughput": r["requests"] / r["seconds"], "rss_start": rss_start,
            "rss_end": rss_end, "rss_peak": rss_peak, "workers": args.workers, "processes": processes,
            "think": args.think,
            "axis": Path(args.axis).name + (f" + motor {args.motor}" if args.motor else "")
            + (", identical every time (cache)" if args.same else ", a different mass every request")}


def table(r: dict[str, Any]) -> str:
    verdict = "met" if r["p95"] < TARGET_P95_MS else "missed"
    rows = [
        ("axis", r["axis"]),
        ("load generator", r["generator"]),
        ("server processes", f"{r['workers']}" if r["workers"] == 1 else f"{r['workers']} workers under a supervisor"),
        ("clients x duration", f"{r['clients']} x {r['seconds']:.1f} s"),
        ("think time between a client's requests", f"{r['think']:g} ms"),
        ("requests", f"{r['requests']}"),
        ("throughput", f"{r['throughput']:.1f} req/s"),
        ("latency p50 / p95 / p99", f"{r['p50']:.0f} / {r['p95']:.0f} / {r['p99']:.0f} ms"),
        ("latency max", f"{r['max']:.0f} ms"),
        (f"target p95 < {TARGET_P95_MS:.0f} ms", verdict),
        ("errors", f"{r['errors']}" + (f" ({r['error_detail']})" if r["error_detail"] else "")),
        ("server RSS start / peak / end", f"{r['rss_start']:.0f} / {r['rss_peak']:.0f} / {r['rss_end']:.0f} MB"
         + (f" (sum over {r['processes']} processes)" if r["processes"] > 1 else "")),
    ]
    out = ["| quantity | value |", "|---|---|"]
    out += [f"| {k} | {v} |" for k, v in rows]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--clients", type=int, default=20)
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--max-requests", type=int,
                   help="stop after this many requests in all (--client python only: wrk runs for --seconds)")
    p.add_argument("--axis", default=str(ROOT / "examples" / "ball_screw.yaml"))
    p.add_argument("--motor", help="replace the axis's motor section by this catalog motor (no selection)")
    p.add_argument("--same", action="store_true", help="send the identical axis every time (measures the cache)")
    have_wrk = shutil.which("wrk") is not None
    p.add_argument("--client", choices=["wrk", "python"], default="wrk" if have_wrk else "python",
                   help="load generator (default wrk when it is on PATH, else Python threads)")
    p.add_argument("--workers", type=int, default=1, help="server processes (drivetrain serve --workers)")
    p.add_argument("--think", type=float, default=0.0, metavar="MS",
                   help="time each client waits between its requests [ms] (default 0)")
    args = p.parse_args(argv)
    if not 1 <= args.clients <= 200 or not 0 < args.seconds <= 600:
        p.error("--clients 1..200 and --seconds up to 600")
    if not 1 <= args.workers <= 32 or not 0 <= args.think <= 60_000:
        p.error("--workers 1..32 and --think 0..60000 ms")
    if args.client == "wrk" and not have_wrk:
        p.error("wrk is not on PATH (apt-get install wrk, or make bench)")
    if args.max_requests is not None and (args.client == "wrk" or args.max_requests < 1):
        p.error("--max-requests must be at least 1 and needs --client python")
    result = run(args)
    print(table(result))
    return 0 if result["errors"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
