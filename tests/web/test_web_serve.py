"""`drivetrain serve --workers N`: N uvicorn worker processes on one socket, stopped with their supervisor."""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("uvicorn")
pytest.importorskip("httpx")

import httpx

from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.cli import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "ball_screw.yaml"


def children(pid: int) -> set[int]:
    """Direct children of a process (Linux /proc), e.g. the supervisor's workers."""
    out: set[int] = set()
    for path in Path(f"/proc/{pid}/task").glob("*/children"):
        with contextlib.suppress(OSError):  # the process ended meanwhile
            out.update(int(p) for p in path.read_text().split())
    return out


def running(pid: int) -> bool:
    """True while ``pid`` exists and is not a zombie."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


@pytest.fixture()
def server(tmp_path: Path) -> Iterator[tuple[subprocess.Popen[str], str]]:
    env = {**os.environ, "DRIVETRAIN_DATA_DIR": str(tmp_path), "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "drivetrain.cli", "serve", "--port", "0", "--workers", "2",
                             "--data-dir", str(tmp_path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        m = re.search(r"http://127\.0\.0\.1:\d+", line)
        assert m, line + (proc.stderr.read() if proc.stderr else "")
        yield proc, m.group(0)
    finally:
        if proc.poll() is None:  # the test failed before stopping it: do not leave a server behind
            proc.send_signal(signal.SIGKILL)  # the workers follow their supervisor (they watch it)
            proc.wait(timeout=10)
        for stream in (proc.stdout, proc.stderr):
            if stream is not None:
                stream.close()


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs Linux /proc")
def test_two_workers_serve_and_stop_with_the_supervisor(server: tuple[subprocess.Popen[str], str]) -> None:
    proc, url = server
    axis = parse_yaml(EXAMPLE.read_text(encoding="utf-8"))
    with httpx.Client(base_url=url, timeout=60) as c:
        r = c.get("/api/health")
        assert r.status_code == 200, r.text
        assert r.json()["status"] == "ok"
        # the sizing processes warm up after the server starts: on a loaded machine that can take longer than a
        # request's time limit, whose answer is then a 503 (JSON); wait for a first sizing
        deadline = time.monotonic() + 180
        while (r := c.post("/api/size", json=axis)).status_code == 503 and time.monotonic() < deadline:
            assert r.json()["detail"], r.text
        assert r.status_code == 200, r.text
        for _ in range(3):  # more than one request: both workers may answer
            r = c.post("/api/size", json=axis)
            assert r.status_code == 200, r.text
            assert r.json()["result"]["peak_torque_Nm"] > 0
    workers = {pid for pid in children(proc.pid)
               if "spawn_main" in Path(f"/proc/{pid}/cmdline").read_text(errors="replace")}
    assert len(workers) == 2, workers

    proc.terminate()
    assert proc.wait(timeout=30) == 0, proc.stderr.read() if proc.stderr else ""
    deadline = time.monotonic() + 10
    while any(running(pid) for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [pid for pid in workers if running(pid)], "worker processes outlived the server"


@pytest.mark.parametrize("workers", ["0", "33"])
def test_workers_out_of_range_is_an_input_error(workers: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--port", "0", "--workers", workers]) == 2
    err = capsys.readouterr().err
    assert "--workers" in err and "between 1 and 32" in err


def test_accepted_connections_send_without_nagle_delay() -> None:
    """The listening socket says it is TCP, so asyncio sets TCP_NODELAY on every accepted connection:
    a response of more than one segment is not held back waiting for the client's delayed ACK."""
    import asyncio
    import socket

    from drivetrain.web.cli import bind

    sock = bind("127.0.0.1", 0)
    port = sock.getsockname()[1]
    seen: list[int] = []

    async def main_() -> None:
        async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            seen.append(writer.get_extra_info("socket").getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))
            writer.close()

        server = await asyncio.start_server(handle, sock=sock)
        async with server:
            _, writer = await asyncio.open_connection("127.0.0.1", port)
            for _ in range(100):
                if seen:
                    break
                await asyncio.sleep(0.01)
            writer.close()

    asyncio.run(main_())
    assert seen and seen[0] != 0
