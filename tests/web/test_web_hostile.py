"""Hostile requests to the web app, on a real server on loopback (uvicorn in a thread).

Cross-origin writes are refused unless the page's exact origin and, for form and text bodies, its
token come with them; an internal error is a JSON 500 on a connection that stays open; requests
that run past the time limit are stopped and do not hold the sizing for other users; the seeds of
the hostile-input probe (a power tower in a unit, deep nesting, lone surrogates, 400-digit and
1e400 numbers, a 45,000-move profile) through /api/size, the YAML routes and the catalog import
get a 4xx naming the field, never a 500, within the client's time limit.
"""

from __future__ import annotations

import http.client
import json
import random
import signal
import socket
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("fastapi")
uvicorn = pytest.importorskip("uvicorn")

from drivetrain.axis.yaml_text import parse_yaml  # noqa: E402
from drivetrain.motion.profiles import MAX_PROFILE_STEPS  # noqa: E402
from drivetrain.web import app as web_app  # noqa: E402
from drivetrain.web.payload import size_payload  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "ball_screw.yaml"
LIMIT_S = 20.0
"""The test server's request time limit [s]."""
CLIENT_TIMEOUT_S = 60.0
"""No request may take longer than this on the client side (a hang fails the test, it does not stall it)."""


def sizing_with_faults(axis: dict[str, Any]) -> dict[str, Any]:
    """The app's sizing, except for two axis names: "stall" computes for two minutes (holding a core
    and the interpreter, as the quadratic phase table did), "fault" fails as a bug would.

    Module level: the app runs it in its worker processes, which import it by name.
    """
    if axis.get("axis") == "stall":
        end = time.monotonic() + 120.0
        n = 0
        while time.monotonic() < end:
            n += 1
        return {"n": n}
    if axis.get("axis") == "fault":
        raise RuntimeError("a fault inside the sizing")
    return size_payload(axis)


def example_axis(name: str | None = None) -> dict[str, Any]:
    data = parse_yaml(EXAMPLE.read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    if name is not None:
        data["axis"] = name
    return data


class Server:
    """``app`` served on ``sock`` in a thread with the settings of ``drivetrain serve`` (``web.server.config``);
    ``limits`` change the slow-client guard's bounds (``web.server.Guard``)."""

    def __init__(self, app: Any, sock: socket.socket, **limits: Any) -> None:
        from drivetrain.web import server as web_server

        self.app, self.port = app, sock.getsockname()[1]
        self.config = web_server.config(app, log_level="warning", timeout_keep_alive=30, **limits)
        self.protocol: Any = self.config.http
        self.server = uvicorn.Server(self.config)
        self.thread = threading.Thread(target=self.server.run, kwargs={"sockets": [sock]}, daemon=True)
        self.thread.start()
        deadline = time.monotonic() + 60
        while not self.server.started:
            assert time.monotonic() < deadline and self.thread.is_alive(), "the server did not start"
            time.sleep(0.05)

    @property
    def origin(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def token(self) -> str:
        return str(self.app.state.token)

    def connection(self) -> http.client.HTTPConnection:
        return http.client.HTTPConnection("127.0.0.1", self.port, timeout=CLIENT_TIMEOUT_S)

    def request(self, method: str, path: str, body: bytes | None = None,
                headers: dict[str, str] | None = None) -> tuple[int, Any]:
        conn = self.connection()
        try:
            conn.request(method, path, body=body, headers=headers or {})
            response = conn.getresponse()
            raw = response.read()
        finally:
            conn.close()
        text = raw.decode("utf-8")
        is_json = response.getheader("content-type", "").startswith("application/json")
        return response.status, json.loads(text) if is_json else text

    def post_json(self, path: str, data: Any, headers: dict[str, str] | None = None) -> tuple[int, Any]:
        raw = data if isinstance(data, bytes) else json.dumps(data).encode()
        return self.request("POST", path, raw, {"content-type": "application/json", **(headers or {})})

    def post_file(self, path: str, name: str, content: bytes, headers: dict[str, str] | None = None,
                  fields: dict[str, str] | None = None) -> tuple[int, Any]:
        boundary = "----drivetrain-test-boundary"
        parts = [f'--{boundary}\r\nContent-Disposition: form-data; name="{k}"\r\n\r\n{v}\r\n'.encode()
                 for k, v in (fields or {}).items()]
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="file"; filename="{name}"\r\n'
                     "Content-Type: application/octet-stream\r\n\r\n".encode() + content + b"\r\n")
        body = b"".join(parts) + f"--{boundary}--\r\n".encode()
        return self.request("POST", path, body, {"content-type": f"multipart/form-data; boundary={boundary}",
                                                 **(headers or {})})

    def stop(self) -> None:
        self.server.should_exit = True
        self.thread.join(timeout=30)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("web-hostile")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(data))
        mp.setattr(web_app, "size_payload", sizing_with_faults)
        app = web_app.create_app(data, timeout=LIMIT_S)
        assert app.state.sizing_workers().wait_ready(120.0), "the sizing workers did not start"
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(("127.0.0.1", 0))
        srv = Server(app, sock)
        try:
            yield srv
        finally:
            srv.stop()


def assert_refused(status: int, body: Any, field: str) -> None:
    assert status == 403, body
    assert body["field"] == field, body
    assert body["detail"].strip()


# ---------------------------------------------------------------------------------- cross-origin writes

CSV = ("id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
       "{id},ACME,1,3,3000,6000,1e-4,ACME datasheet p. 1\n")


def imported(server: Server, motor_id: str) -> int:
    status, body = server.request("GET", f"/api/catalog/motors?q={motor_id}")
    assert status == 200, body
    return int(body["total"])


def test_a_write_from_another_port_or_scheme_is_refused(server: Server) -> None:
    other_port = f"http://127.0.0.1:{server.port + 1 if server.port < 65535 else server.port - 1}"
    for origin in (other_port, f"https://127.0.0.1:{server.port}", f"http://localhost:{server.port + 1}", "null"):
        status, body = server.post_json("/api/yaml/parse", {"yaml": "a: 1"}, {"origin": origin})
        assert_refused(status, body, "origin")
        status, body = server.post_file("/api/catalog/import", "evil.csv", CSV.format(id="EVIL-1").encode(),
                                        {"origin": origin, "x-drivetrain-token": server.token})
        assert_refused(status, body, "origin")
    # without Origin, the Referer stands for it
    status, body = server.post_json("/api/yaml/parse", {"yaml": "a: 1"}, {"referer": f"{other_port}/page.html"})
    assert_refused(status, body, "referer")
    assert imported(server, "EVIL-1") == 0


def test_the_exact_origin_is_served(server: Server) -> None:
    for headers in ({"origin": server.origin}, {"referer": f"{server.origin}/"}, {},
                    {"host": f"localhost:{server.port}", "origin": f"http://localhost:{server.port}"}):
        status, body = server.post_json("/api/yaml/parse", {"yaml": "a: 1"}, headers)
        assert status == 200, (headers, body)


def test_form_and_text_bodies_need_the_page_token(server: Server) -> None:
    csv = CSV.format(id="FORM-1").encode()
    for headers in ({"origin": server.origin}, {}, {"origin": server.origin, "x-drivetrain-token": "guess"}):
        status, body = server.post_file("/api/catalog/import", "m.csv", csv, headers)
        assert_refused(status, body, "x-drivetrain-token")
    # a text/plain body is what a cross-origin fetch can send without a preflight
    raw = json.dumps(example_axis()).encode()
    status, body = server.request("POST", "/api/size", raw, {"content-type": "text/plain", "origin": server.origin})
    assert_refused(status, body, "x-drivetrain-token")
    status, body = server.request("POST", "/api/size", raw, {"origin": server.origin})  # no content type at all
    assert_refused(status, body, "x-drivetrain-token")
    assert imported(server, "FORM-1") == 0
    status, body = server.post_file("/api/catalog/import", "m.csv", csv,
                                    {"origin": server.origin, "x-drivetrain-token": server.token})
    assert status == 200, body
    assert imported(server, "FORM-1") == 1


def test_the_page_carries_its_token(server: Server) -> None:
    status, page = server.request("GET", "/")
    assert status == 200
    assert f'<meta name="drivetrain-token" content="{server.token}">' in page
    assert len(server.token) >= 32


# ---------------------------------------------------------------------------------- errors keep the connection


def test_an_internal_error_is_json_and_keeps_the_connection(server: Server) -> None:
    conn = server.connection()
    try:
        conn.request("POST", "/api/size", body=json.dumps(example_axis("fault")),
                     headers={"content-type": "application/json"})
        first = conn.getresponse()
        body = json.loads(first.read())
        assert first.status == 500
        assert first.getheader("content-type", "").startswith("application/json")
        assert "internal error (WorkerError)" in body["detail"] and "a fault inside" not in body["detail"]
        assert first.getheader("connection", "").lower() != "close"
        conn.request("GET", "/api/health")  # the same connection
        second = conn.getresponse()
        assert second.status == 200 and json.loads(second.read())["status"] == "ok"
    finally:
        conn.close()


# ---------------------------------------------------------------------------------- work past the time limit


def test_requests_past_the_time_limit_are_stopped_and_others_still_size(server: Server) -> None:
    stall = json.dumps(example_axis("stall")).encode()
    # every worker of this server warmed up and idle first (on a loaded machine an earlier test's request may
    # still be computing, or the replacement of a worker it stopped still starting): then each stalled request
    # takes one of the workers listed here, none waits for a busy one past the limit
    pool = server.app.state.sizing_workers()
    deadline = time.monotonic() + 120.0
    while not (pool.wait_ready(5.0) and len(pool.idle) == pool.size):
        assert time.monotonic() < deadline, "the sizing workers did not become idle"
        time.sleep(0.2)
    before = [w.process for w in pool.idle]
    assert 0 < len(before) <= web_app.MAX_PARALLEL_WORK
    stalls = max(2, web_app.MAX_PARALLEL_WORK)  # as many as there are workers: every one of them is stalled
    with ThreadPoolExecutor(stalls) as pool:
        answers = list(pool.map(lambda _: server.post_json("/api/size", stall), range(stalls)))
    for status, body in answers:
        assert status == 503, body
        assert f"longer than {LIMIT_S:g} s" in body["detail"]
    # the stalled computations are gone: their processes were killed. The server reaps a killed worker on
    # a thread of its own (workers._Worker.kill), in this process: when that thread's waitpid wins, this
    # join returns before the exit code is stored, so wait a moment for it
    for worker in before:
        worker.join(timeout=CLIENT_TIMEOUT_S)
        deadline = time.monotonic() + 5.0
        while worker.exitcode is None and time.monotonic() < deadline:
            time.sleep(0.01)
        assert worker.exitcode == -signal.SIGKILL, worker
    status, body = server.request("GET", "/api/health")
    assert status == 200 and body["status"] == "ok"
    # a normal sizing answers within the server's own limit (else it would be a 503), on a fresh
    # worker: the killed ones were replaced at once (on a loaded machine their start-up can take
    # most of the limit, so the test lets them warm up first; the server's own start does the same)
    assert server.app.state.sizing_workers().wait_ready(120.0)
    status, body = server.post_json("/api/size", example_axis())
    assert status == 200, body
    assert body["result"]["rms_torque_Nm"] > 0 and body["selected"]["motor"]


# ---------------------------------------------------------------------------------- hostile seeds

LONG_PROFILE = json.dumps(
    {**example_axis(), "profile": [{"move": 0.001, "time": 0.1}, {"dwell": 0.1}] * 22_500},
    separators=(",", ":")).encode()
DEEP_JSON = b'{"axis": "x", "mechanism": ' + b"[" * 100_000 + b"]" * 100_000 + b"}"


def _with(path: tuple[Any, ...], value: Any, axis: dict[str, Any] | None = None) -> dict[str, Any]:
    data = axis if axis is not None else example_axis()
    node: Any = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data


def _raw(path: tuple[Any, ...], literal: str) -> bytes:
    """The example axis as JSON text with ``literal`` (JSON number text) at ``path``."""
    mark = "@@hostile@@"
    return json.dumps(_with(path, mark)).replace(f'"{mark}"', literal).encode()


SIZE_SEEDS: list[tuple[str, bytes, str]] = [
    ("power tower in a unit", json.dumps(_with(("mechanism", "lead"), "9**9**9 mm")).encode(), "mechanism.lead"),
    ("2**1024 in a unit", json.dumps(_with(("mechanism", "diameter"), "2**1024 mm")).encode(), "mechanism.diameter"),
    ("400-digit integer", _raw(("mechanism", "load", "mass"), "1" + "0" * 400), "mechanism.load.mass"),
    ("5,000-digit integer", _raw(("mechanism", "length"), "1" + "0" * 5000), "body"),  # past Python's int text limit
    ("1e400", _raw(("mechanism", "load", "mass"), "1e400"), "mechanism.load.mass"),
    ("lone surrogate", json.dumps(_with(("axis",), "\ud800")).encode(), "axis"),
    ("surrogate in a key", json.dumps(_with(("mechanism", "load", "\udc80"), 1)).encode(), "mechanism.load"),
    ("deep JSON", DEEP_JSON, "body"),
    ("45,000-move profile", LONG_PROFILE, "profile"),
]


@pytest.mark.parametrize(("raw", "field"), [(raw, field) for _, raw, field in SIZE_SEEDS],
                         ids=[name for name, _, _ in SIZE_SEEDS])
def test_hostile_axes_get_the_field_not_a_500(server: Server, raw: bytes, field: str) -> None:
    assert len(raw) < web_app.MAX_BODY_BYTES
    status, body = server.post_json("/api/size", raw)
    assert status == 422, body
    assert body["field"] is not None and body["field"].startswith(field), body
    assert body["detail"].strip()


def test_a_profile_longer_than_the_cap_is_refused_before_sizing(server: Server) -> None:
    axis = example_axis()
    axis["profile"] = [{"move": 0.001, "time": 0.1}] * (MAX_PROFILE_STEPS + 1)
    status, body = server.post_json("/api/size", axis)
    assert status == 422 and body["field"] == "profile"
    assert f"at most {MAX_PROFILE_STEPS}" in body["detail"]


DEEP_YAML = "axis: x\nmechanism: " + "[" * 600 + "]" * 600 + "\n"

YAML_SEEDS: list[tuple[str, str, str]] = [
    ("deep YAML", DEEP_YAML, ""),
    ("surrogate escape", 'axis: "\\ud800"\n', "axis"),
    ("power tower", "axis: x\nmechanism: {type: belt, lead: 9**9**9 mm}\n", ""),
]


@pytest.mark.parametrize(("text", "field"), [(t, f) for _, t, f in YAML_SEEDS], ids=[n for n, _, _ in YAML_SEEDS])
def test_hostile_yaml_through_parse_and_upload(server: Server, text: str, field: str) -> None:
    status, body = server.post_json("/api/yaml/parse", {"yaml": text})
    assert status in (200, 422), body
    if status == 422:
        assert body["field"] is not None and body["field"].startswith("yaml"), body
        assert field in body["field"]
    status, body = server.post_file("/api/yaml/upload", "a.yaml", text.encode(), {"x-drivetrain-token": server.token})
    assert status in (200, 422), body
    if status == 422:
        assert body["field"].startswith("file"), body
    else:  # parsed: sizing it names the field
        status, body = server.post_json("/api/size", body["axis"])
        assert status == 422 and body["field"], body


JSON_ROW = {"id": "J1", "vendor": "A", "rated_torque_Nm": 1, "peak_torque_Nm": 3, "rated_speed_rpm": 3000,
            "max_speed_rpm": 6000, "rotor_inertia_kgm2": 1e-4, "source": "A datasheet p. 1"}
IMPORT_SEEDS: list[tuple[str, str, str]] = [
    ("power tower in a cell", "m.csv", CSV.format(id="U1").replace(",1,3,", ",9**9**9 N*m,3,")),
    ("table of a list", "m.json", '{"table": []}'),
    ("deep nesting", "m.json", "[" * 100_000 + "]" * 100_000),
    ("400-digit number", "m.json", json.dumps([JSON_ROW]).replace('"rated_torque_Nm": 1',
                                                                   '"rated_torque_Nm": 1' + "0" * 400)),
    ("1e400", "m.json", json.dumps([JSON_ROW]).replace('"rated_torque_Nm": 1', '"rated_torque_Nm": 1e400')),
    ("surrogate id", "m.json", json.dumps([JSON_ROW]).replace('"J1"', '"J\\ud800"')),
    ("surrogate bytes", "m.csv", CSV.format(id="S1").replace("ACME,", "AC\udc80ME,")),
]


@pytest.mark.parametrize(("name", "text"), [(n, t) for _, n, t in IMPORT_SEEDS], ids=[i for i, _, _ in IMPORT_SEEDS])
def test_hostile_catalog_imports_name_the_field(server: Server, name: str, text: str) -> None:
    status, body = server.post_file("/api/catalog/import", name, text.encode("utf-8", "surrogatepass"),
                                    {"x-drivetrain-token": server.token}, {"kind": "motor"} if name.endswith("csv")
                                    else None)
    assert status == 422, body
    assert body["field"] and body["field"].split(":")[0] in (name, "file"), body


HOSTILE_VALUES: list[Any] = ["9**9**9 mm", "2**1024 mm", 10**400, -(10**300), "\ud800", "1e400 kg", "",
                             "nan", "inf mm", [], {}, None, True, "a" * 10_000, {"\udc80": 1},
                             "1 mm" * 1000, [[[[[[[[[[[]]]]]]]]]]], -1, 0, 1e308, 5e-324]


def _leaves(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _leaves(v, (*path, k))]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in _leaves(v, (*path, i))]
    return [path]


def test_seeded_mutations_of_an_axis_never_get_a_500(server: Server) -> None:
    """60 axes, each with one to three leaves replaced by a hostile value (the same on every run)."""
    rng = random.Random(20)
    leaves = _leaves(example_axis())
    seen: dict[int, int] = {}
    for _ in range(60):
        axis = example_axis()
        for path in rng.sample(leaves, rng.randint(1, 3)):
            _with(path, rng.choice(HOSTILE_VALUES), axis)
        raw = json.dumps(axis).encode()
        status, body = server.post_json("/api/size", raw)
        seen[status] = seen.get(status, 0) + 1
        assert status < 500, (status, body, axis)
        if status >= 400:
            assert isinstance(body, dict) and body["detail"].strip(), body
            assert status != 422 or body["field"] is not None, body
    assert seen.get(422, 0) >= 30, seen
