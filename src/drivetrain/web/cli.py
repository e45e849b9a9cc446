"""``drivetrain serve``: the local web app on loopback (127.0.0.1 and a free port by default).

``--workers N`` (N > 1) runs N uvicorn worker processes on the one socket bound here; each builds
its app with ``app_from_env`` from the environment this process exports.

uvicorn's settings and the guard against slow clients are in ``drivetrain.web.server``.

Importing this module is cheap: FastAPI and uvicorn are imported when the command runs.
"""

from __future__ import annotations

import argparse
import ipaddress
import os
import secrets
import socket
import sys
from pathlib import Path
from typing import Any

MAX_WORKERS = 32
"""Most worker processes ``--workers`` accepts."""
ENV_ANY_HOST = "DRIVETRAIN_SERVE_ANY_HOST"
"""Set to "1" by ``serve --workers N`` on a non-loopback address: the workers answer any Host."""
ENV_TOKEN = "DRIVETRAIN_SERVE_TOKEN"
"""The page's anti-forgery token, set by ``serve --workers N`` so that every worker shares it."""
ENV_SERVERS = "DRIVETRAIN_SERVE_WORKERS"
"""The number of server processes of ``serve --workers N``, set for its workers."""
APP_FACTORY = "drivetrain.web.cli:app_from_env"


def add_parser(subparsers: Any) -> None:
    """Register ``serve`` with the drivetrain CLI."""
    p = subparsers.add_parser("serve", help="the web app: size axes in the browser, save projects, browse the catalog")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to bind (default 127.0.0.1; anything else exposes the app to the network)")
    p.add_argument("--port", type=int, default=0, help="port (default 0: a free port, printed)")
    p.add_argument("--data-dir", metavar="DIR",
                   help="folder for projects and the user catalog (default $DRIVETRAIN_DATA_DIR or "
                        "~/.local/share/drivetrain)")
    p.add_argument("--workers", type=int, default=1, metavar="N",
                   help=f"server processes sharing the socket (default 1; at most {MAX_WORKERS}): more requests "
                        "computed at once on a machine with several cores")
    p.add_argument("--timeout", type=float, metavar="S",
                   help="time limit of one request in seconds (default $DRIVETRAIN_REQUEST_TIMEOUT or 20; a report "
                        "gets at least 120): raise it on a slow or shared machine")
    p.add_argument("--log-level", default="warning", choices=["critical", "error", "warning", "info", "debug"])
    p.set_defaults(handler=run)


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and localhost."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host:port`` (port 0: the OS picks a free one)."""
    from drivetrain.errors import InputError

    if not 0 <= port <= 65535:
        raise InputError("--port", "must be between 0 and 65535", port)
    try:
        infos = socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM)
    except socket.gaierror as exc:
        raise InputError("--host", f"cannot be resolved ({exc.strerror})", host) from None
    family, _, _, _, address = infos[0]
    # IPPROTO_TCP explicitly: asyncio turns Nagle's algorithm off (TCP_NODELAY) only on sockets that
    # say they are TCP; with proto 0 a response larger than one segment waited ~40 ms for a delayed ACK.
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind(address)
    except OSError as exc:
        sock.close()
        raise InputError("--port", f"cannot be bound on {host} ({exc.strerror})", port) from None
    sock.listen(128)
    sock.set_inheritable(True)
    return sock


def url_of(sock: socket.socket) -> str:
    host, port = sock.getsockname()[:2]
    shown = f"[{host}]" if ":" in host else host
    return f"http://{shown}:{port}/"


def app_from_env() -> Any:
    """The app of one worker process of ``serve --workers N`` (uvicorn calls it: ``factory=True``).

    The data folder comes from ``$DRIVETRAIN_DATA_DIR`` (or the default one), the Host check from
    ``$DRIVETRAIN_SERVE_ANY_HOST``, the shared page token from ``$DRIVETRAIN_SERVE_TOKEN`` and the
    number of server processes from ``$DRIVETRAIN_SERVE_WORKERS``, all exported by ``run`` before it
    starts the workers.
    """
    from drivetrain.web.app import LOOPBACK_HOSTS, create_app

    _exit_with_parent()
    any_host = os.environ.get(ENV_ANY_HOST) == "1"
    try:
        servers = max(1, int(os.environ.get(ENV_SERVERS, "1")))
    except ValueError:
        servers = 1
    return create_app(None, allowed_hosts=None if any_host else LOOPBACK_HOSTS, token=os.environ.get(ENV_TOKEN),
                      servers=servers)


def _exit_with_parent() -> None:
    """In a worker started by multiprocessing: stop (as on SIGTERM) when the supervisor dies.

    The supervisor stops its workers when it is terminated; this covers SIGKILL or a crash, which
    would otherwise leave orphans serving on the socket.
    """
    import multiprocessing
    import multiprocessing.connection
    import signal
    import threading

    parent = multiprocessing.parent_process()
    if parent is None:
        return
    sentinel = parent.sentinel

    def watch() -> None:
        multiprocessing.connection.wait([sentinel])
        os.kill(os.getpid(), signal.SIGTERM)

    threading.Thread(target=watch, name="drivetrain-parent-watch", daemon=True).start()


def run(args: argparse.Namespace) -> int:
    """Start the server; returns when it is stopped (Ctrl+C)."""
    from drivetrain.errors import InputError

    if not 1 <= args.workers <= MAX_WORKERS:
        raise InputError("--workers", f"must be between 1 and {MAX_WORKERS}", args.workers)
    if args.workers > 1:
        return _run_workers(args)

    import uvicorn

    from drivetrain.web import server as web_server
    from drivetrain.web.app import LOOPBACK_HOSTS, create_app
    from drivetrain.web.store import ENV_DATA_DIR

    data_dir = Path(args.data_dir).expanduser().resolve() if args.data_dir else None
    if data_dir is not None:
        os.environ[ENV_DATA_DIR] = str(data_dir)
    if args.timeout is not None:
        from drivetrain.errors import InputError

        if not 0.0 < args.timeout <= 86400.0:
            raise InputError("--timeout", "must be between 0 and 86400 s", args.timeout)
        os.environ["DRIVETRAIN_REQUEST_TIMEOUT"] = repr(args.timeout)  # the workers of --workers N read it too
    loopback = is_loopback(args.host)
    sock = bind(args.host, args.port)
    allowed = LOOPBACK_HOSTS if loopback else None
    app = create_app(data_dir, allowed_hosts=allowed)
    if not loopback:
        print(f"warning: serving on {args.host}: anyone who can reach this address can use the app and its "
              "projects", file=sys.stderr)
    print(f"drivetrain web app on {url_of(sock)} (data in {app.state.data_dir}); Ctrl+C stops it", flush=True)
    config = web_server.config(app, log_level=args.log_level, access_log=args.log_level in ("info", "debug"))
    server = uvicorn.Server(config)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
    return 0


def _run_workers(args: argparse.Namespace) -> int:
    """``serve --workers N``: uvicorn's supervisor runs N worker processes on the socket bound here.

    Workers are spawned (not forked), so they get the app as an import string and their settings
    through the environment; they share the data folder (SQLite in WAL mode is safe across processes).
    """
    import inspect

    import uvicorn
    from uvicorn.config import STARTUP_FAILURE
    from uvicorn.supervisors import Multiprocess

    from drivetrain.web import server as web_server
    from drivetrain.web.store import ENV_DATA_DIR, default_data_dir

    data_dir = Path(args.data_dir).expanduser().resolve() if args.data_dir else None
    if data_dir is not None:
        os.environ[ENV_DATA_DIR] = str(data_dir)
    if args.timeout is not None:
        from drivetrain.errors import InputError

        if not 0.0 < args.timeout <= 86400.0:
            raise InputError("--timeout", "must be between 0 and 86400 s", args.timeout)
        os.environ["DRIVETRAIN_REQUEST_TIMEOUT"] = repr(args.timeout)  # the workers of --workers N read it too
    loopback = is_loopback(args.host)
    # Always set, so a value left in the user's environment cannot lift the loopback Host check.
    os.environ[ENV_ANY_HOST] = "0" if loopback else "1"
    # One anti-forgery token for every worker: the page from one worker posts to any other.
    os.environ[ENV_TOKEN] = secrets.token_urlsafe(32)
    os.environ[ENV_SERVERS] = str(args.workers)  # the workers share the cores for their sizing processes
    sock = bind(args.host, args.port)
    if not loopback:
        print(f"warning: serving on {args.host}: anyone who can reach this address can use the app and its "
              "projects", file=sys.stderr)
    print(f"drivetrain web app on {url_of(sock)} (data in {data_dir or default_data_dir()}, {args.workers} worker "
          "processes); Ctrl+C stops it", flush=True)
    config = web_server.config(APP_FACTORY, factory=True, workers=args.workers, log_level=args.log_level,
                               access_log=args.log_level in ("info", "debug"))
    # Older uvicorn versions take the worker's entry point as ``target``; newer ones make it themselves.
    extra: dict[str, Any] = {}
    if "target" in inspect.signature(Multiprocess).parameters:
        extra["target"] = uvicorn.Server(config).run
    supervisor = Multiprocess(config, sockets=[sock], **extra)
    try:
        supervisor.run()
    finally:
        sock.close()
    failed = any(getattr(p, "exitcode", None) == STARTUP_FAILURE for p in supervisor.processes)
    return 1 if failed else 0
