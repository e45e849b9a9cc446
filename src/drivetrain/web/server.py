"""How ``drivetrain serve`` runs uvicorn: its limits, set deliberately, and a guard against slow clients.

uvicorn bounds how long a connection may sit idle between requests (``timeout_keep_alive``) but
not how long a client may take to send a request's headers: a client that opens connections and
sends a byte now and then holds them for ever ("slowloris"), and since uvicorn's
``limit_concurrency`` counts open connections, 200 such connections made every other request a
(plain-text) 503. So the HTTP protocol here is uvicorn's own (httptools when installed, else h11)
with a guard around it, per server process:

- the headers of a request must be complete ``HEADER_TIMEOUT_S`` after the connection opened or
  its previous answer was sent, and within ``MAX_HEADER_BYTES``; else the answer is 408 (431) and
  the connection is closed; a request that is not valid HTTP gets a JSON 400 (uvicorn's is text);
- one client address holds at most ``MAX_PENDING_PER_CLIENT`` connections whose headers are not
  complete, all clients together ``MAX_PENDING``: one more closes the oldest of them (a client
  that sends its request at once is never the oldest for long);
- at most ``MAX_CONNECTIONS`` connections are open: one more is answered 503 and closed.

Why a protocol subclass: an ASGI middleware sees a request only once its headers are complete,
too late; a bounded accept loop in front of uvicorn would be a second server to keep correct.
The guard hooks the moments uvicorn's protocol already has (connection made, data received,
response complete, connection lost) and leaves the HTTP parsing to it.

The number of requests handled at once is bounded by the app (``app.MAX_IN_FLIGHT``, a JSON 503),
not by uvicorn's ``limit_concurrency`` (set to None): that one answers in plain text and counts
idle connections too. Every refusal here is JSON as well.
"""

from __future__ import annotations

import asyncio
import json
import weakref
from typing import Any

from uvicorn.protocols.http.h11_impl import H11Protocol

try:
    from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol
except ImportError:  # pragma: no cover - httptools is optional
    HttpToolsProtocol = None  # type: ignore[assignment,misc]

HEADER_TIMEOUT_S = 10.0
"""Time a client has to send a request's headers [s], from the connection's opening or its previous answer."""
MAX_HEADER_BYTES = 65_536
"""Largest request line and headers [bytes] (also h11's ``max_incomplete_event_size``)."""
MAX_PENDING_PER_CLIENT = 32
"""Connections of one client address whose request headers are not complete (or idle between requests)."""
MAX_PENDING = 256
"""Such connections of all clients together."""
MAX_CONNECTIONS = 512
"""Open connections of one server process (well below the usual limit of 1024 open files)."""
KEEP_ALIVE_S = 5.0
"""An idle connection is closed after this long without a new request [s] (uvicorn's ``timeout_keep_alive``)."""

_REASONS = {400: "Bad Request", 408: "Request Timeout", 431: "Request Header Fields Too Large",
            503: "Service Unavailable"}


class _Pending:
    """The connections of one server whose request headers are not complete, oldest first."""

    def __init__(self) -> None:
        self.all: dict[Any, None] = {}
        self.by_client: dict[str, dict[Any, None]] = {}

    def add(self, conn: Any, client: str) -> None:
        self.all[conn] = None
        self.by_client.setdefault(client, {})[conn] = None

    def discard(self, conn: Any, client: str) -> None:
        self.all.pop(conn, None)
        mine = self.by_client.get(client)
        if mine is not None:
            mine.pop(conn, None)
            if not mine:
                del self.by_client[client]

    def oldest(self, client: str | None = None) -> Any:
        pool = self.all if client is None else self.by_client.get(client, {})
        return next(iter(pool), None)

    def count(self, client: str | None = None) -> int:
        return len(self.all) if client is None else len(self.by_client.get(client, {}))


_SERVERS: weakref.WeakKeyDictionary[Any, _Pending] = weakref.WeakKeyDictionary()
"""The pending connections of each running uvicorn server (by its ServerState)."""


def refusal(status: int, detail: str) -> bytes:
    """A complete HTTP/1.1 answer with the app's JSON error body that closes the connection."""
    body = json.dumps({"detail": detail, "field": None, "errors": [{"field": None, "message": detail}]}).encode()
    head = (f"HTTP/1.1 {status} {_REASONS.get(status, 'Error')}\r\ncontent-type: application/json\r\n"
            f"content-length: {len(body)}\r\nconnection: close\r\n")
    if status == 503:
        head += "retry-after: 2\r\n"
    return head.encode("latin-1") + b"\r\n" + body


class Guard:
    """The guard against slow clients (module docstring), mixed into one of uvicorn's HTTP protocols.

    Its bounds are class attributes, so a subclass can change them (tests shorten the timeout);
    the classes ``drivetrain serve`` uses are module-level, so ``serve --workers N`` can send them
    to its worker processes.
    """

    header_timeout: float = HEADER_TIMEOUT_S
    max_header_bytes: int = MAX_HEADER_BYTES
    max_pending_per_client: int = MAX_PENDING_PER_CLIENT
    max_pending: int = MAX_PENDING
    max_connections: int = MAX_CONNECTIONS

    # attributes of uvicorn's protocols that the guard uses
    transport: Any
    connections: set[Any]
    client: tuple[str, int] | None
    cycle: Any
    loop: asyncio.AbstractEventLoop

    def __init__(self, config: Any, server_state: Any, app_state: dict[str, Any],
                 _loop: asyncio.AbstractEventLoop | None = None) -> None:
        super().__init__(config, server_state, app_state, _loop)  # type: ignore[call-arg]
        pending = _SERVERS.get(server_state)
        if pending is None:
            pending = _SERVERS[server_state] = _Pending()
        self._pending_of = pending
        self._waiting = False
        self._timer: asyncio.TimerHandle | None = None
        self._header_bytes = 0
        self._cycle_before: Any = None
        self._client_key = ""

    # -------------------------------------------------------------------- uvicorn's moments

    def connection_made(self, transport: Any) -> None:
        super().connection_made(transport)  # type: ignore[misc]
        self._client_key = str(self.client[0]) if self.client else ""
        if len(self.connections) > self.max_connections:
            self._refuse(503, f"the server has {self.max_connections} connections open; try again in a moment")
            return
        self._arm()

    def data_received(self, data: bytes) -> None:
        if self._waiting:
            self._header_bytes += len(data)
        super().data_received(data)  # type: ignore[misc]
        if self._waiting:
            if self.cycle is not self._cycle_before:  # the headers are complete: a request began
                self._disarm()
            elif self._header_bytes > self.max_header_bytes:
                self._refuse(431, f"the request headers are larger than {self.max_header_bytes} bytes")

    def on_response_complete(self) -> None:
        super().on_response_complete()  # type: ignore[misc]
        if not self.transport.is_closing() and (self.cycle is None or self.cycle.response_complete):
            self._arm()  # waiting for the next request on this connection

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)  # type: ignore[misc]

    def send_400_response(self, msg: str) -> None:
        """A request uvicorn cannot parse: answered in JSON like every other error."""
        self._refuse(400, f"the request is not valid HTTP/1.1 ({msg.rstrip('.')})")

    # -------------------------------------------------------------------- the guard

    def _arm(self) -> None:
        self._disarm()
        pending = self._pending_of
        while pending.count(self._client_key) >= self.max_pending_per_client:
            pending.oldest(self._client_key)._evict()
        while pending.count() >= self.max_pending:
            pending.oldest()._evict()
        self._waiting, self._header_bytes, self._cycle_before = True, 0, self.cycle
        pending.add(self, self._client_key)
        self._timer = self.loop.call_later(self.header_timeout, self._timed_out)

    def _disarm(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        if self._waiting:
            self._waiting = False
            self._pending_of.discard(self, self._client_key)

    def _timed_out(self) -> None:
        self._timer = None
        if self._waiting:
            self._refuse(408, f"the request headers did not come within {self.header_timeout:g} s")

    def _evict(self) -> None:
        self._refuse(408, "the request headers did not come in time (too many connections of this client, or of "
                          "all clients, were waiting for theirs)")

    def _refuse(self, status: int, detail: str) -> None:
        self._disarm()
        if not self.transport.is_closing():
            self.transport.write(refusal(status, detail))
            self.transport.close()


class GuardedH11Protocol(Guard, H11Protocol):
    """uvicorn's h11 protocol with the guard."""


if HttpToolsProtocol is not None:
    class GuardedHttpToolsProtocol(Guard, HttpToolsProtocol):
        """uvicorn's httptools protocol with the guard."""

    DEFAULT_PROTOCOL: type[asyncio.Protocol] = GuardedHttpToolsProtocol
else:  # pragma: no cover - httptools is optional
    DEFAULT_PROTOCOL = GuardedH11Protocol


def http_protocol(**limits: Any) -> type[asyncio.Protocol]:
    """The guarded protocol on uvicorn's fastest HTTP implementation installed (httptools, else h11);
    ``limits`` (the class attributes of ``Guard``) override its bounds in a subclass (tests use a
    short header timeout; such a class serves in this process only)."""
    if not limits:
        return DEFAULT_PROTOCOL
    unknown = set(limits) - {"header_timeout", "max_header_bytes", "max_pending_per_client", "max_pending",
                             "max_connections"}
    if unknown:
        raise TypeError(f"unknown limits: {', '.join(sorted(unknown))}")
    return type(f"Test{DEFAULT_PROTOCOL.__name__}", (DEFAULT_PROTOCOL,), dict(limits))


def config(app: Any, **options: Any) -> Any:
    """The ``uvicorn.Config`` of ``drivetrain serve`` for ``app`` (an app, or an import string with
    ``factory=True``): the guarded protocol and every limit set here; ``options`` add to them."""
    import uvicorn

    limits = {k: options.pop(k) for k in ("header_timeout", "max_header_bytes", "max_pending_per_client",
                                          "max_pending", "max_connections") if k in options}
    settings: dict[str, Any] = {
        "http": http_protocol(**limits),
        "timeout_keep_alive": KEEP_ALIVE_S,
        "limit_concurrency": None,  # the app bounds requests at once (app.MAX_IN_FLIGHT) and answers JSON
        "h11_max_incomplete_event_size": MAX_HEADER_BYTES,
        "server_header": False,
        "ws": "none",  # no WebSocket routes
        "lifespan": "on",
    }
    settings.update(options)
    return uvicorn.Config(app, **settings)
