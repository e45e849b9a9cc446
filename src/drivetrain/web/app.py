"""The web app behind ``drivetrain serve``: a JSON API (FastAPI, described by its OpenAPI schema) and
one page built from plain JS modules in ``static/``.

No physics here: every number comes from ``drivetrain.sizing.size``, the catalog and the report.
The API takes the axis as the JSON form of the axis file (``AxisSpec``), so a bad value gets the
CLI's message, naming its field: ``{"detail": "mechanism.load.mass: must be > 0 kg, got -3 kg",
"field": "mechanism.load.mass"}`` with status 422.

Safe by default: the server binds loopback; requests must name a loopback host (no DNS
rebinding) and state-changing requests from another origin are refused; bodies are limited in
size and requests in time; no request path reaches the file system (static files come from the
package, reports and uploads go to temporary files inside the data folder and are removed).

The app is split by concern: this module builds it (middleware, error answers, the page and
static files); ``routes_meta``, ``routes_sizing``, ``routes_reports``, ``routes_projects`` and
``routes_catalog`` each add their resource's routes; ``payload`` turns a sizing into the JSON the
page draws, apart from HTTP; ``models`` holds the API's JSON models and ``common`` what the
route modules share.
"""

from __future__ import annotations

import contextlib
import html
import logging
import os
import re
import secrets
import tempfile
import threading
import time
from collections.abc import AsyncIterator, Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, TypeVar

import anyio
import anyio.to_thread
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.utils import get_openapi
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from drivetrain.errors import InputError
from drivetrain.version import __version__
from drivetrain.web import routes_catalog, routes_machine, routes_meta, routes_projects, routes_reports, routes_sizing
from drivetrain.web.common import (
    ApiError,
    Context,
    ResultCache,
    SafeJSONResponse,
    error_body,
    json_error,
)
from drivetrain.web.models import ERRORS, MAX_TEXT_BYTES
from drivetrain.web.payload import size_payload
from drivetrain.web.routes_catalog import MAX_UPLOAD_BYTES
from drivetrain.web.routes_machine import machine_size_payload
from drivetrain.web.store import ENV_DATA_DIR, StoreError, default_data_dir
from drivetrain.web.workers import WorkerPool

__all__ = ["LOOPBACK_HOSTS", "MAX_BODY_BYTES", "MAX_IN_FLIGHT", "UPLOAD_BODY_BYTES", "Guard", "allowed_methods",
           "create_app"]

log = logging.getLogger("drivetrain.web")

T = TypeVar("T")

MAX_BODY_BYTES = MAX_TEXT_BYTES + 65_536
"""Largest request body [bytes]: an axis file and its JSON wrapping."""
UPLOAD_BODY_BYTES = MAX_UPLOAD_BYTES + 65_536
"""Largest body of an upload (catalog import, axis file) [bytes]: the file (MAX_UPLOAD_BYTES, 20 MB) and
its multipart wrapping; the route itself refuses a file over MAX_UPLOAD_BYTES."""
MAX_IN_FLIGHT = 200
"""Requests one server process handles at once; one more is answered 503 (JSON, Retry-After) at once.
Slow clients cannot fill these places: a request counts only once its headers are complete
(``drivetrain.web.server`` closes connections whose headers do not come in time)."""
REQUEST_TIMEOUT_S = 20.0
"""Time limit of one request [s]; a report (PDF through a browser) gets REPORT_TIMEOUT_S. A server on a
slow or shared machine sets both higher with ``$DRIVETRAIN_REQUEST_TIMEOUT`` (seconds, the report's
limit rises with it: :func:`time_limits`) or ``drivetrain serve --timeout``."""
REPORT_TIMEOUT_S = 120.0


def time_limits(timeout: float | None = None) -> tuple[float, float]:
    """(request, report) time limits [s]: ``timeout`` where given, else ``$DRIVETRAIN_REQUEST_TIMEOUT``,
    else REQUEST_TIMEOUT_S; the report's is REPORT_TIMEOUT_S, or the request's where that is longer."""
    if timeout is None:
        text = os.environ.get("DRIVETRAIN_REQUEST_TIMEOUT", "").strip()
        try:
            timeout = float(text) if text else REQUEST_TIMEOUT_S
        except ValueError:
            raise InputError("DRIVETRAIN_REQUEST_TIMEOUT", "must be a number of seconds", text) from None
        if not 0.0 < timeout <= 86400.0:
            raise InputError("DRIVETRAIN_REQUEST_TIMEOUT", "must be between 0 and 86400 s", text)
    return timeout, max(REPORT_TIMEOUT_S, timeout)
MAX_PARALLEL_WORK = max(1, min(4, os.cpu_count() or 2))
"""Sizings, reports and imports computed at once (one per core, at most 4): a catalog selection
holds a few hundred MB of arrays while it runs; further requests wait within their time limit."""
LOOPBACK_HOSTS: tuple[str, ...] = ("127.0.0.1", "localhost", "::1", "[::1]")
STATIC_DIR = Path(__file__).resolve().parent / "static"
_TMP_PREFIX = "web-"
_STALE_TMP_S = 3600.0


# ---------------------------------------------------------------------------------- middleware


class Guard:
    """Pure ASGI middleware: host and origin checks, body size limit, time limit, security headers."""

    HEADERS: tuple[tuple[bytes, bytes], ...] = (
        (b"x-content-type-options", b"nosniff"),
        (b"x-frame-options", b"DENY"),
        (b"referrer-policy", b"no-referrer"),
        (b"cross-origin-resource-policy", b"same-origin"),
        (b"content-security-policy",
         b"default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
         b"connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'; form-action 'self'"),
    )

    def __init__(self, app: ASGIApp, allowed_hosts: Sequence[str] | None, max_body: int, upload_body: int,
                 timeout: float, report_timeout: float, token: str = "") -> None:
        self.app = app
        self.allowed = None if allowed_hosts is None else {h.lower() for h in allowed_hosts}
        self.max_body, self.upload_body = max_body, upload_body
        self.timeout, self.report_timeout = timeout, report_timeout
        self.token = token
        self.in_flight = 0

    @staticmethod
    def _host_of(value: str) -> str:
        value = value.strip().lower()
        if value.startswith("["):
            return value[: value.find("]") + 1] if "]" in value else value
        return value.rsplit(":", 1)[0] if value.count(":") == 1 else value

    @staticmethod
    def origin_of(scheme: str, authority: str) -> tuple[str, str, int] | None:
        """(scheme, host, port) of a URL's scheme and authority, the default port filled in."""
        scheme, authority = scheme.strip().lower(), authority.strip().lower()
        if scheme not in ("http", "https") or not authority or "@" in authority:
            return None
        m = re.fullmatch(r"(\[[0-9a-f:.]+\]|[^:\[\]/]+)(?::(\d{1,5}))?", authority)
        if m is None:
            return None
        port = int(m.group(2)) if m.group(2) else (443 if scheme == "https" else 80)
        return scheme, m.group(1), port

    @classmethod
    def origin_of_url(cls, url: str) -> tuple[str, str, int] | None:
        """(scheme, host, port) of an Origin or Referer value (None for "null" or anything else)."""
        m = re.match(r"^([a-z][a-z0-9+.-]*)://([^/?#]*)", url.strip().lower())
        return None if m is None else cls.origin_of(m.group(1), m.group(2))

    def cross_site(self, scope: Scope, headers: dict[str, str]) -> tuple[str, str] | None:
        """Why a state-changing request may come from another page, and the header at fault (None: it may not).

        The page's origin must be exactly the one served here (scheme, host and port): from the
        Origin header, else the Referer. A request naming neither is not a browser's form or
        fetch, unless it is a kind a page on another origin can send without asking first (a
        form or text body): such bodies carry the page's token (``X-Drivetrain-Token``), which
        another origin cannot read. A JSON body from another origin needs a CORS preflight,
        which this server never grants.
        """
        served = self.origin_of(str(scope.get("scheme", "http")), headers.get("host", ""))
        claimed = headers.get("origin")
        if claimed is None and headers.get("referer"):
            claimed = headers["referer"]
        if claimed is not None and (served is None or self.origin_of_url(claimed) != served):
            return (f"requests from another origin are refused (this server is "
                    f"{'://'.join(map(str, served[:2])) + ':' + str(served[2]) if served else 'unknown'})",
                    "origin" if "origin" in headers else "referer")
        media = headers.get("content-type", "").split(";", 1)[0].strip().lower()
        has_body = media != "" or headers.get("content-length", "0") not in ("0", "") or "transfer-encoding" in headers
        if has_body and media != "application/json":
            given = headers.get("x-drivetrain-token", "")
            if not self.token or not secrets.compare_digest(given.encode("latin-1"), self.token.encode("latin-1")):
                return (f"a {media or 'untyped'} body needs the page's X-Drivetrain-Token header "
                        "(send JSON, or use the page)", "x-drivetrain-token")
        return None

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        if self.in_flight >= MAX_IN_FLIGHT:
            await _send_json(send, 503, f"the server is busy ({MAX_IN_FLIGHT} requests at once); try again in a moment",
                             None, {"retry-after": "2"})
            return
        self.in_flight += 1  # one event loop per server process: no lock needed
        try:
            await self._guarded(scope, receive, send)
        finally:
            self.in_flight -= 1

    async def _guarded(self, scope: Scope, receive: Receive, send: Send) -> None:
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        host = self._host_of(headers.get("host", ""))
        if self.allowed is not None and host not in self.allowed:
            await _send_json(send, 403, f"host {host or '(none)'} is not served here; use 127.0.0.1 or localhost",
                             "host")
            return
        if scope["method"] not in ("GET", "HEAD", "OPTIONS"):
            refused = self.cross_site(scope, headers)
            if refused is not None:
                await _send_json(send, 403, *refused)
                return
        path: str = scope.get("path", "")
        limit = self.upload_body if path.endswith("/import") or path.endswith("/upload") else self.max_body
        length = headers.get("content-length")
        if length is not None:
            if not length.isdigit():
                await _send_json(send, 400, "content-length must be a number", "content-length")
                return
            if int(length) > limit:
                await _send_json(send, 413, f"the request body is too large ({length} bytes; at most {limit})", "body")
                return
        received = 0
        started = False

        async def limited_receive() -> Message:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > limit:
                    raise _BodyTooLarge(limit)
            return message

        async def send_with_headers(message: Message) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                message = dict(message)
                message["headers"] = list(message.get("headers", [])) + list(self.HEADERS)
            await send(message)

        timeout = self.report_timeout if path.startswith("/api/report") else self.timeout
        try:
            with anyio.fail_after(timeout):
                await self.app(scope, limited_receive, send_with_headers)
        except _BodyTooLarge as exc:
            if not started:
                await _send_json(send, 413, f"the request body is too large (at most {exc.limit} bytes)", "body")
        except TimeoutError:
            if not started:
                await _send_json(send, 503, f"the request took longer than {timeout:g} s and was stopped", None,
                                 {"retry-after": "5"})
        except Exception as exc:
            # Answered here rather than by Starlette's outermost handler, which sends its answer and
            # then re-raises, so the server closes the connection; here the connection is kept.
            log.error("unexpected error in %s %s", scope["method"], path, exc_info=exc)
            if not started:
                await _send_json(send, 500, f"internal error ({type(exc).__name__}); the server log has the details",
                                 None)
            else:
                raise


class _BodyTooLarge(Exception):
    def __init__(self, limit: int) -> None:
        super().__init__(limit)
        self.limit = limit


async def _send_json(send: Send, status: int, detail: str, field: str | None,
                     extra: dict[str, str] | None = None) -> None:
    import json

    from drivetrain.web.common import clip

    detail = clip(detail)
    body = json.dumps({"detail": detail, "field": field, "errors": [{"field": field, "message": detail}]}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    headers += [(k.encode(), v.encode()) for k, v in (extra or {}).items()]
    headers += list(Guard.HEADERS)
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})



# ---------------------------------------------------------------------------------- the app


def create_app(data_dir: Path | None = None, *, allowed_hosts: Sequence[str] | None = LOOPBACK_HOSTS,
               max_body: int = MAX_BODY_BYTES, timeout: float | None = None, token: str | None = None,
               servers: int = 1) -> FastAPI:
    """The FastAPI application.

    ``data_dir`` holds the project database, the user catalog and temporary files (default:
    ``$DRIVETRAIN_DATA_DIR`` or ``~/.local/share/drivetrain``); when given, it is also exported
    as ``$DRIVETRAIN_DATA_DIR`` so the catalog and sizing read the same folder. ``allowed_hosts``
    are the Host names served (None: any, for a deliberate non-loopback bind). ``token`` is the
    page's anti-forgery token (``X-Drivetrain-Token``, needed by form and text bodies; default: a new
    random one; ``serve --workers N`` gives its workers one to share); ``app.state.token`` holds it.
    ``servers``: the server processes sharing the machine (``serve --workers N``), which share
    ``MAX_PARALLEL_WORK`` sizing processes.
    """
    from drivetrain.web.store import Store

    if data_dir is not None:
        data_dir = Path(data_dir).expanduser().resolve()
        os.environ[ENV_DATA_DIR] = str(data_dir)
    directory = data_dir or default_data_dir()
    store = Store(directory)
    cache = ResultCache(directory)
    tmp_dir = directory / "tmp"
    # Heavy work (sizing, reports, imports) runs on a few long-lived threads: a bounded queue, and
    # the same threads' memory reused rather than a new thread's each time.
    pools: list[ThreadPoolExecutor] = []
    workers: list[WorkerPool] = []
    pools_lock = threading.Lock()

    def worker_pool() -> WorkerPool:
        with pools_lock:
            if not workers:
                workers.append(WorkerPool(sizing_processes(servers), directory))
            return workers[0]

    def work_pool() -> ThreadPoolExecutor:
        with pools_lock:
            if not pools:
                pools.append(ThreadPoolExecutor(max_workers=MAX_PARALLEL_WORK, thread_name_prefix="drivetrain-work"))
            return pools[0]

    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        worker_pool().start()  # the sizing processes warm up while the server starts
        yield
        with pools_lock:  # a later request (a test client restarting the app) makes new pools
            while pools:
                pools.pop().shutdown(wait=False, cancel_futures=True)
            while workers:
                workers.pop().close()

    app = FastAPI(title="drivetrain", version=__version__, responses=ERRORS, default_response_class=SafeJSONResponse,
                  lifespan=lifespan,
                  description="Size servo axes: the JSON API of `drivetrain serve`. The axis is the JSON form of "
                              "the axis file (docs/axis-file.md); quantities are numbers in SI or text with units.")
    app.state.store = store
    app.state.sizing_workers = worker_pool  # the app's WorkerPool (made on first use)
    app.state.data_dir = directory
    token = token or secrets.token_urlsafe(32)
    app.state.token = token
    request_limit, report_limit = time_limits(timeout)
    app.add_middleware(Guard, allowed_hosts=allowed_hosts, max_body=max_body, upload_body=UPLOAD_BODY_BYTES,
                       timeout=request_limit, report_timeout=report_limit, token=token)

    async def blocking(fn: Callable[..., T], *args: Any) -> T:
        """Run ``fn`` on the work pool; a request that times out drops its job if it has not started."""
        import asyncio

        future = work_pool().submit(fn, *args)
        try:
            return await asyncio.wrap_future(future)
        except BaseException:
            future.cancel()
            raise

    async def isolated(fn: Callable[..., T], *args: Any) -> T:
        """Run ``fn`` in a sizing process; a request that times out kills it (a new one takes its place)."""
        return await worker_pool().run(fn, *args)

    async def light(fn: Callable[..., T], *args: Any) -> T:
        return await anyio.to_thread.run_sync(fn, *args, abandon_on_cancel=True)

    def temp_path(suffix: str) -> Path:
        tmp_dir.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=_TMP_PREFIX, suffix=suffix, dir=tmp_dir)
        os.close(fd)
        return Path(name)

    def clean_stale() -> None:
        if not tmp_dir.is_dir():
            return
        now = time.time()
        for p in tmp_dir.glob(f"{_TMP_PREFIX}*"):
            try:
                if now - p.stat().st_mtime > _STALE_TMP_S:
                    p.unlink()
            except OSError:
                pass

    clean_stale()

    # ------------------------------------------------------------------ errors

    @app.exception_handler(InputError)
    async def _input_error(request: Request, exc: InputError) -> JSONResponse:
        return SafeJSONResponse(error_body(exc), status_code=422)

    @app.exception_handler(StoreError)
    async def _store_error(request: Request, exc: StoreError) -> JSONResponse:
        detail = f"{exc.field}: {exc.message}" if exc.field and exc.status in (400, 422) else exc.message
        return json_error(422 if exc.status == 400 else exc.status, detail, exc.field)

    @app.exception_handler(ApiError)
    async def _api_error(request: Request, exc: ApiError) -> JSONResponse:
        return json_error(exc.status, exc.detail, exc.field)

    @app.exception_handler(RequestValidationError)
    async def _validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
        from drivetrain.errors import format_value

        items: list[dict[str, Any]] = []
        for err in exc.errors():
            field = pydantic_field(err.get("loc", ()))
            msg = str(err.get("msg", "invalid")).removeprefix("Value error, ")
            if err.get("type") == "missing":
                msg = "is required"
            elif "input" in err and err.get("type") not in ("json_invalid",):
                value = err["input"]
                shown = format_value(value) if isinstance(value, (str, int, float, bool)) else type(value).__name__
                msg = f"{msg}, got {shown}"
            items.append({"field": field or None, "message": f"{field}: {msg}" if field else msg})
        detail = "\n".join(str(i["message"]) for i in items) or "invalid request"
        return json_error(422, detail, items[0]["field"] if items else None, errors=items)

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        detail = exc.detail if isinstance(exc.detail, str) and exc.detail else "error"
        headers = dict(exc.headers or {})
        if exc.status_code == 405:
            headers["Allow"] = ", ".join(allowed_methods(app, request.url.path))
            detail = f"method {request.method} is not allowed here; use {headers['Allow']}"
        return json_error(exc.status_code, detail, None, headers=headers)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error in %s %s", request.method, request.url.path)
        return json_error(500, f"internal error ({type(exc).__name__}); the server log has the details")

    # ------------------------------------------------------------------ page and static files

    page = (STATIC_DIR / "index.html").read_text(encoding="utf-8").replace(
        "<head>\n", f'<head>\n  <meta name="drivetrain-token" content="{html.escape(token)}">\n', 1)

    @app.get("/", include_in_schema=False)
    async def index() -> Response:
        return Response(page, media_type="text/html; charset=utf-8", headers={"Cache-Control": "no-store"})

    @app.get("/static/vendor/plotly.min.js", include_in_schema=False)
    async def plotly_js() -> FileResponse:
        import plotly

        path = Path(plotly.__file__).resolve().parent / "package_data" / "plotly.min.js"
        if not path.is_file():
            raise ApiError(503, "plotly.js is not available in the installed plotly package")
        return FileResponse(path, media_type="text/javascript", headers={"Cache-Control": "max-age=86400"})

    app.mount("/static", StaticFiles(directory=STATIC_DIR, follow_symlink=False), name="static")

    context = Context(store=store, cache=cache, directory=directory, blocking=blocking, light=light, isolated=isolated,
                      temp_path=temp_path, size_payload=size_payload, machine_payload=machine_size_payload)
    for module in (routes_meta, routes_sizing, routes_reports, routes_projects, routes_catalog, routes_machine):
        module.register(app, context)

    # ------------------------------------------------------------------ OpenAPI with the axis schema

    def openapi() -> dict[str, Any]:
        if app.openapi_schema:
            return app.openapi_schema
        from drivetrain.web.schema import openapi_components

        schema = get_openapi(title=app.title, version=app.version, description=app.description, routes=app.routes)
        axis, defs = openapi_components()
        components = schema.setdefault("components", {}).setdefault("schemas", {})
        components.update(defs)
        components["AxisSpec"] = axis
        app.openapi_schema = schema
        return schema

    app.openapi = openapi  # type: ignore[method-assign]
    return app


def sizing_processes(servers: int = 1) -> int:
    """Sizing processes of one server process: MAX_PARALLEL_WORK, shared among the ``servers`` server
    processes of ``serve --workers N`` (at least one each)."""
    return max(1, MAX_PARALLEL_WORK // max(1, servers))


def allowed_methods(app: FastAPI, path: str) -> list[str]:
    """Every method some route serves at ``path`` (routes are per method; Starlette names only one)."""
    from starlette.routing import Route

    methods: set[str] = set()
    for route in app.routes:
        if isinstance(route, Route) and route.path_regex.match(path) and route.methods:
            methods |= set(route.methods)
    return sorted(methods)



def pydantic_field(loc: Sequence[Any]) -> str:
    from drivetrain.fields import format_path

    parts = list(loc)
    if parts and parts[0] in ("body", "query", "path", "header", "cookie"):
        parts = parts[1:]
    clean: list[int | str] = [p if isinstance(p, int) else str(p) for p in parts]
    return format_path(clean)
