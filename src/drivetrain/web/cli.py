"""``drivetrain serve``: the local web app on loopback (127.0.0.1 and a free port by default).

Importing this module is cheap: FastAPI and uvicorn are imported when the command runs.
"""

from __future__ import annotations

import argparse
import ipaddress
import os
import socket
import sys
from pathlib import Path
from typing import Any


def add_parser(subparsers: Any) -> None:
    """Register ``serve`` with the drivetrain CLI."""
    p = subparsers.add_parser("serve", help="the web app: size axes in the browser, save projects, browse the catalog")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to bind (default 127.0.0.1; anything else exposes the app to the network)")
    p.add_argument("--port", type=int, default=0, help="port (default 0: a free port, printed)")
    p.add_argument("--data-dir", metavar="DIR",
                   help="folder for projects and the user catalog (default $DRIVETRAIN_DATA_DIR or "
                        "~/.local/share/drivetrain)")
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
    sock = socket.socket(family, socket.SOCK_STREAM)
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


def run(args: argparse.Namespace) -> int:
    """Start the server; returns when it is stopped (Ctrl+C)."""
    import uvicorn

    from drivetrain.web.app import LOOPBACK_HOSTS, create_app
    from drivetrain.web.store import ENV_DATA_DIR

    data_dir = Path(args.data_dir).expanduser().resolve() if args.data_dir else None
    if data_dir is not None:
        os.environ[ENV_DATA_DIR] = str(data_dir)
    loopback = is_loopback(args.host)
    sock = bind(args.host, args.port)
    allowed = LOOPBACK_HOSTS if loopback else None
    app = create_app(data_dir, allowed_hosts=allowed)
    if not loopback:
        print(f"warning: serving on {args.host}: anyone who can reach this address can use the app and its "
              "projects", file=sys.stderr)
    print(f"drivetrain web app on {url_of(sock)} (data in {app.state.data_dir}); Ctrl+C stops it", flush=True)
    config = uvicorn.Config(app, log_level=args.log_level, access_log=args.log_level in ("info", "debug"),
                            timeout_keep_alive=5, limit_concurrency=200, server_header=False)
    server = uvicorn.Server(config)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
    return 0
