"""The web server stays up (issue 30): slow clients, bodies that are slow to parse, machine sizings
past the time limit, bursts, oversized uploads and error messages, each on a real server on
loopback (uvicorn in a thread, with the settings of ``drivetrain serve``), which keeps answering
other requests throughout. Every wait polls for a condition; no test depends on how fast the
machine is.
"""

from __future__ import annotations

import json
import re
import signal
import socket
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("uvicorn")

from drivetrain.catalog.importer import MAX_IMPORT_BYTES
from drivetrain.web import app as web_app
from drivetrain.web import common
from drivetrain.web.routes_machine import machine_size_payload
from tests.web.test_web_hostile import CLIENT_TIMEOUT_S, Server

ROOT = Path(__file__).resolve().parents[2]
LIMIT_S = 20.0
"""The test server's request time limit [s]."""
HEADER_TIMEOUT_S = 3.0
"""The test server's header timeout [s] (``drivetrain serve``: web.server.HEADER_TIMEOUT_S)."""
WAIT_S = 120.0
"""The longest any condition may take to come true on a loaded machine (a failure, not a hang)."""
SMALL_ANSWER = 64_000
"""An error answer is at most this long [bytes] (20 listed errors of at most 1000 characters, and the rest)."""


def machine_with_stall(resolved: dict[str, Any], links: dict[int, dict[str, Any]], samples: int,
                       seed: int) -> dict[str, Any]:
    """The app's machine sizing, except that a machine named "stall" computes for two minutes
    (holding a core, as a pathological machine would). Module level: the workers import it by name."""
    if resolved.get("machine") == "stall":
        end = time.monotonic() + 120.0
        n = 0
        while time.monotonic() < end:
            n += 1
        return {"n": n}
    return machine_size_payload(resolved, links, samples, seed)


def until(condition: Callable[[], bool], what: str, timeout: float = WAIT_S) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"{what}: not within {timeout:g} s"
        time.sleep(0.05)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("web-stays-up")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(data))
        mp.setattr(web_app, "machine_size_payload", machine_with_stall)
        app = web_app.create_app(data, timeout=LIMIT_S)
        assert app.state.sizing_workers().wait_ready(WAIT_S), "the sizing workers did not start"
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(("127.0.0.1", 0))
        srv = Server(app, sock, header_timeout=HEADER_TIMEOUT_S)
        try:
            yield srv
        finally:
            srv.stop()


def healthy(server: Server) -> bool:
    status, body = server.request("GET", "/api/health")
    assert status == 200, body
    return body["status"] == "ok"  # type: ignore[no-any-return]


def while_running(server: Server, work: Callable[[], Any]) -> tuple[Any, int]:
    """Run ``work`` on a thread and ask for /api/health until it ends (each answer must be 200);
    returns ``work``'s result and how many health answers came meanwhile."""
    with ThreadPoolExecutor(1) as pool:
        future: Future[Any] = pool.submit(work)
        answered = 0
        while not future.done() or answered == 0:
            assert healthy(server)
            answered += 1
        return future.result(), answered


def workers_idle(server: Server) -> None:
    """Every sizing worker warmed up and idle (a killed one's replacement may still be starting)."""
    pool = server.app.state.sizing_workers()
    until(lambda: pool.wait_ready(5.0) and len(pool.idle) == pool.size, "the sizing workers are idle")


def read_answer(sock: socket.socket) -> bytes:
    """Everything the server sends until it closes the connection."""
    sock.settimeout(CLIENT_TIMEOUT_S)
    chunks = []
    while True:
        try:
            chunk = sock.recv(65536)
        except ConnectionResetError:
            break
        if not chunk:
            break
        chunks.append(chunk)
    return b"".join(chunks)


def json_answer(raw: bytes) -> tuple[int, dict[str, Any]]:
    head, _, body = raw.partition(b"\r\n\r\n")
    status = int(head.split(b" ", 2)[1])
    assert b"content-type: application/json" in head.lower(), head
    return status, json.loads(body)


def open_partial(server: Server, n: int) -> list[socket.socket]:
    """``n`` connections, each having sent part of a request's headers and nothing more."""
    socks = []
    for _ in range(n):
        s = socket.create_connection(("127.0.0.1", server.port), timeout=CLIENT_TIMEOUT_S)
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        socks.append(s)
    return socks


# ---------------------------------------------------------------------------------- slow clients


def test_200_connections_holding_unfinished_headers_do_not_take_the_server(server: Server) -> None:
    socks = open_partial(server, 200)
    try:
        for _ in range(5):  # was: 503 at once
            assert healthy(server)
        answers: list[bytes] = [b""] * len(socks)

        def read(k: int) -> None:
            answers[k] = read_answer(socks[k])

        with ThreadPoolExecutor(16) as pool:
            list(pool.map(read, range(len(socks))))
        # every one was closed, with a JSON 408: the oldest at once (at most 32 may wait per client), the
        # rest when their time to send the headers was up
        for raw in answers:
            status, body = json_answer(raw)
            assert status == 408, body
            assert "request headers did not come" in body["detail"]
        assert healthy(server)
    finally:
        for s in socks:
            s.close()


def test_a_client_dribbling_its_headers_is_cut_off(server: Server) -> None:
    s = socket.create_connection(("127.0.0.1", server.port), timeout=CLIENT_TIMEOUT_S)
    try:
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        s.settimeout(0.2)
        answer = b""
        deadline = time.monotonic() + WAIT_S
        while not answer:  # a header line a little at a time: each byte would reset a plain idle timeout
            assert time.monotonic() < deadline, "the server kept the connection"
            try:
                s.sendall(b"X")
                answer = s.recv(65536)
            except TimeoutError:
                continue
            except (BrokenPipeError, ConnectionResetError):
                break
        s.settimeout(CLIENT_TIMEOUT_S)
        status, body = json_answer(answer + read_answer(s))
        assert status == 408 and f"within {HEADER_TIMEOUT_S:g} s" in body["detail"]
    finally:
        s.close()


def test_a_slow_second_request_on_a_kept_connection_is_cut_off(server: Server) -> None:
    s = socket.create_connection(("127.0.0.1", server.port), timeout=CLIENT_TIMEOUT_S)
    try:
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        first = b""
        while b"\r\n\r\n" not in first or not first.rstrip().endswith(b"}"):
            chunk = s.recv(65536)
            assert chunk, first
            first += chunk
        assert first.startswith(b"HTTP/1.1 200")
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # and never the end of the headers
        status, body = json_answer(read_answer(s))
        assert status == 408, body
    finally:
        s.close()


def test_oversized_headers_are_refused_in_json(server: Server) -> None:
    from drivetrain.web.server import MAX_HEADER_BYTES

    s = socket.create_connection(("127.0.0.1", server.port), timeout=CLIENT_TIMEOUT_S)
    try:
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        try:
            for _ in range(MAX_HEADER_BYTES // 1000 + 2):
                s.sendall(b"X-Pad-" + b"a" * 990 + b": 1\r\n")
        except (BrokenPipeError, ConnectionResetError):
            pass
        status, body = json_answer(read_answer(s))
        assert status in (400, 431), body
        assert body["detail"]
    finally:
        s.close()


def test_a_request_that_is_not_http_gets_json(server: Server) -> None:
    s = socket.create_connection(("127.0.0.1", server.port), timeout=CLIENT_TIMEOUT_S)
    try:
        s.sendall(b"\x16\x03\x01 this is not HTTP\r\n\r\n")
        status, body = json_answer(read_answer(s))
        assert status == 400 and "not valid HTTP" in body["detail"]
    finally:
        s.close()


def test_past_the_connection_bound_a_connection_gets_a_json_503(server: Server,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(server.protocol, "max_connections", 3)
    held = open_partial(server, 3)
    try:
        extra = open_partial(server, 1)[0]
        try:
            status, body = json_answer(read_answer(extra))
        finally:
            extra.close()
        assert status == 503 and "connections open" in body["detail"]
    finally:
        for s in held:
            s.close()
    monkeypatch.undo()
    until(lambda: healthy(server), "the server answers again")


def test_the_503_of_a_burst_is_json(server: Server, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(web_app, "MAX_IN_FLIGHT", 0)  # every request is one too many
    conn = server.connection()
    try:
        conn.request("GET", "/api/health")
        response = conn.getresponse()
        body = json.loads(response.read())
    finally:
        conn.close()
    assert response.status == 503
    assert response.getheader("content-type") == "application/json" and response.getheader("retry-after")
    assert "busy" in body["detail"]


# ---------------------------------------------------------------------------------- machine sizing


def test_machine_sizings_past_the_limit_free_their_workers(server: Server) -> None:
    status, names = server.request("GET", "/api/machine/examples")
    assert status == 200 and names, names
    status, example = server.request("GET", f"/api/machine/examples/{names[0]}")
    assert status == 200, example
    machine = example["machine"]
    workers_idle(server)
    pool = server.app.state.sizing_workers()
    before = [w.process for w in pool.idle]
    stall = {**machine, "machine": "stall"}

    def stalled() -> list[tuple[int, Any]]:
        with ThreadPoolExecutor(2) as two:
            return list(two.map(lambda _: server.post_json("/api/machine/size", stall), range(2)))

    def facets_meanwhile() -> tuple[list[tuple[int, Any]], int]:
        with ThreadPoolExecutor(1) as one:
            future = one.submit(stalled)
            seen = 0
            while not future.done() or seen == 0:
                status, body = server.request("GET", "/api/catalog/facets")
                assert status == 200, body
                seen += 1
            return future.result(), seen

    answers, seen = facets_meanwhile()
    assert seen >= 1
    for status, body in answers:
        assert status == 503, body
        assert f"longer than {LIMIT_S:g} s" in body["detail"]
    # at once after: unrelated requests are answered (was: 503 for 20 s more)
    status, body = server.request("GET", "/api/catalog/facets")
    assert status == 200, body
    # the stalled computations are gone: their processes were killed (the server reaps them on a thread of
    # its own, so the exit code may be stored a moment after the answer)
    until(lambda: sum(p.exitcode == -signal.SIGKILL for p in before) == min(2, len(before)),
          "the stalled workers were killed")
    workers_idle(server)
    status, body = server.post_json("/api/machine/size", machine)
    assert status == 200, body
    assert body["table"]


# ---------------------------------------------------------------------------------- bodies slow to parse

DEEP_FLOW_YAML = "[" * 10_000 + "]" * 10_000
"""20 kB of YAML nested 10,000 deep (flow style)."""


def test_deep_flow_yaml_is_refused_while_the_server_answers(server: Server) -> None:
    assert len(DEEP_FLOW_YAML) == 20_000
    workers_idle(server)
    (status, body), answered = while_running(server, lambda: server.post_json("/api/yaml/parse",
                                                                              {"yaml": DEEP_FLOW_YAML}))
    assert answered >= 1 and isinstance(body, dict) and body["detail"]
    assert status == 422, body  # the shared parser's depth bound refuses it at once
    assert body["field"].startswith("yaml"), body  # the parser's own message (its depth bound) at the field


def unknown_columns_csv(columns: int) -> bytes:
    names = ",".join(f"col{k}" for k in range(columns))
    return f"id,vendor,{names}\nA,B{',' * columns}\n".encode()


def test_a_470_kb_header_of_unknown_columns_gets_a_short_answer(server: Server) -> None:
    csv = unknown_columns_csv(58_000)
    assert 450_000 < len(csv) < 600_000
    workers_idle(server)
    (status, body), answered = while_running(
        server, lambda: server.post_file("/api/catalog/import", "m.csv", csv, {"x-drivetrain-token": server.token},
                                         {"kind": "motor"}))
    assert answered >= 1
    assert len(json.dumps(body)) < SMALL_ANSWER, len(json.dumps(body))  # was 95.6 MB
    assert status == 422, body  # the importer's column bound refuses it at once
    assert len(body["errors"]) <= common.MAX_ERROR_ITEMS + 1


BAD_ROWS = 500


def bad_rows_csv() -> bytes:
    """A motor import whose every row has a torque that is not a quantity: one error per row."""
    rows = "".join(f"M{k},ACME,abc,3,3000,6000,1e-4,ACME datasheet p. 1\n" for k in range(BAD_ROWS))
    return ("id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
            + rows).encode()


def test_error_answers_name_the_first_errors_and_count_the_rest(server: Server) -> None:
    status, body = server.post_file("/api/catalog/import", "m.csv", bad_rows_csv(),
                                    {"x-drivetrain-token": server.token}, {"kind": "motor"})
    assert status == 422, body
    assert len(json.dumps(body)) < SMALL_ANSWER
    errors = body["errors"]
    assert len(errors) == common.MAX_ERROR_ITEMS + 1
    assert errors[-1]["message"] == (f"and {BAD_ROWS - common.MAX_ERROR_ITEMS} more errors (the first "
                                     f"{common.MAX_ERROR_ITEMS} are listed)")
    assert all(e["field"].startswith("m.csv:") and "rated_torque" in e["field"] for e in errors[:-1])
    assert "/tmp" not in json.dumps(body)


def test_bounding_twice_keeps_the_count_and_messages_stay_short() -> None:
    from drivetrain.errors import InputError, InputErrors

    many = InputErrors([InputError(f"c{k}", "unknown column; known: " + "x, " * 2000) for k in range(2003)])
    once = common.bounded(many)
    assert isinstance(once, InputErrors) and len(once.errors) == common.MAX_ERROR_ITEMS + 1
    assert once.errors[-1].rule == f"and {2003 - common.MAX_ERROR_ITEMS} more errors (the first 20 are listed)"
    assert all(len(e.rule) <= common.MAX_MESSAGE_CHARS for e in once.errors)
    assert common.bounded(once) is once  # a worker bounds what it sends, the answer bounds it again
    body = common.error_body(many)
    assert len(json.dumps(body)) < SMALL_ANSWER and body["errors"][-1]["message"].startswith("and 1983 more")
    text = "a" * 5000
    assert len(common.clip(text)) <= common.MAX_MESSAGE_CHARS and common.clip(common.clip(text)) == common.clip(text)
    assert common.clip(text).endswith(f"({5000 - common.MAX_MESSAGE_CHARS + 40} more characters)")


# ---------------------------------------------------------------------------------- the upload limit


def test_the_upload_limit_is_the_documented_one(server: Server) -> None:
    docs = (ROOT / "docs" / "limits.md").read_text(encoding="utf-8")
    web = docs[docs.index("## The web app"):]
    row = next(line for line in web.splitlines() if line.startswith("| request body"))
    documented = re.search(r"uploads (\d+) MB", row)
    assert documented is not None, row
    assert web_app.MAX_UPLOAD_BYTES == MAX_IMPORT_BYTES == int(documented.group(1)) * 1_000_000
    # a file of the limit is read (and refused for what it holds), one byte more for its size; never a 413
    status, body = server.post_file("/api/catalog/import", "m.csv", b"\xff" * web_app.MAX_UPLOAD_BYTES,
                                    {"x-drivetrain-token": server.token}, {"kind": "motor"})
    assert status == 422 and "UTF-8" in body["detail"], body
    status, body = server.post_file("/api/catalog/import", "m.csv", b"\xff" * (web_app.MAX_UPLOAD_BYTES + 1),
                                    {"x-drivetrain-token": server.token}, {"kind": "motor"})
    assert status == 422 and f"at most {web_app.MAX_UPLOAD_BYTES} bytes" in body["detail"], body
