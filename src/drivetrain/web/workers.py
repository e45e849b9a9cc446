"""Heavy work in worker processes that a request's time limit can stop.

A sizing holds the interpreter for its whole run, and a thread cannot be stopped: a request that
timed out would keep computing, and a few such requests would hold every worker thread (and the
interpreter lock) while other users wait. So the web app runs its heavy work (axis and machine
sizing, reports, AAS downloads, catalog imports, the YAML parse routes) in a few long-lived worker
processes: a request sends its job to an idle one and waits for the answer; when its time limit
fires, the worker is killed and a fresh one takes its place at once. Requests that find every
worker busy are served first come, first served. Bad input comes back as the same
``InputError`` (or ``ApiError``) the engine raised, at most the first errors of it (``common.
bounded``); anything else as ``WorkerError`` with the worker's traceback in its notes.

Workers are spawned, not forked (the server process runs threads), and import the engine when
they start, so a fresh worker is ready in about the time of one ``import drivetrain``.
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import importlib
import multiprocessing
import os
import pickle
import signal
import threading
import traceback
from collections.abc import Callable
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Any, TypeVar

import anyio
import anyio.to_thread

from drivetrain.errors import InputError, InputErrors
from drivetrain.web.common import ApiError, bounded

__all__ = ["WorkerError", "WorkerPool", "encoded"]

T = TypeVar("T")

WARM_MODULES = ("drivetrain.web.payload", "drivetrain.axis.model", "drivetrain.sizing.result",
                "drivetrain.sizing.selection", "drivetrain.catalog")
"""Imported by a worker when it starts, before its first job."""
WARM_AXIS: dict[str, Any] = {
    "axis": "warm-up", "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "800 mm",
                                     "load": {"mass": "25 kg", "friction": 0.05}},
    "profile": [{"move": "200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}],
    "motor": {"select": {"objective": "smallest"}}}
"""Sized once by a worker when it starts: the unit registry, the catalog and the compiled selection
load then, not during a user's first request."""
MAX_WAITING = 64
"""Requests that may wait for a busy pool (per server process); one more is answered 503 at once."""


class WorkerError(RuntimeError):
    """An unexpected error in a worker process (its traceback is in the notes)."""


def encoded(fn: Callable[..., dict[str, Any]], *args: Any) -> bytes:
    """``fn(*args)`` as the page's compact JSON (run in the worker: bytes cross the pipe cheaply)."""
    from drivetrain.web.payload import encode

    return encode(fn(*args))


# ---------------------------------------------------------------------------------- errors across the pipe


def _portable_value(value: Any) -> Any:
    try:
        pickle.dumps(value)
    except Exception:
        from drivetrain.errors import format_value

        return format_value(value)
    return value


def _input_error_state(err: InputError) -> tuple[str, str, Any, bool]:
    return err.field, err.rule, _portable_value(err.value), err.has_value


def _error_state(exc: BaseException) -> tuple[Any, ...]:
    if isinstance(exc, InputError):  # the answer lists only the first errors: send no more than those
        exc = bounded(exc)
    if isinstance(exc, InputErrors):
        return ("inputs", [_input_error_state(e) for e in exc.errors])
    if isinstance(exc, InputError):
        return ("input", _input_error_state(exc))
    if isinstance(exc, ApiError):
        return ("api", exc.status, exc.detail, exc.field)
    return ("other", type(exc).__name__, str(exc)[:2000], traceback.format_exc())


def _error_from(state: tuple[Any, ...]) -> BaseException:
    kind = state[0]
    if kind == "inputs":
        return InputErrors([InputError(f, r, v, has_value=h) for f, r, v, h in state[1]])
    if kind == "input":
        f, r, v, h = state[1]
        return InputError(f, r, v, has_value=h)
    if kind == "api":
        return ApiError(state[1], state[2], state[3])
    err = WorkerError(f"{state[1]}: {state[2]}")
    err.add_note(f"in the sizing worker:\n{state[3]}")
    return err


# ---------------------------------------------------------------------------------- the worker side


def _serve(conn: Connection, data_dir: str) -> None:
    """A worker's life: warm up, then run jobs until the server closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops the server, which stops its workers
    os.environ["DRIVETRAIN_DATA_DIR"] = data_dir
    for name in WARM_MODULES:
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    try:
        from drivetrain.web.payload import size_payload

        size_payload(WARM_AXIS)
    except Exception:  # a broken catalog: the requests will say so
        pass
    try:
        conn.send(("ready", None))
    except (EOFError, OSError):
        return
    while True:
        try:
            fn, args = conn.recv()
        except (EOFError, OSError):
            return
        try:
            answer: tuple[str, Any] = ("ok", fn(*args))
        except Exception as exc:  # every failure goes back to the request
            answer = ("error", _error_state(exc))
        try:
            conn.send(answer)
        except (EOFError, OSError):
            return
        except Exception as exc:  # an answer that does not pickle
            conn.send(("error", _error_state(exc)))


# ---------------------------------------------------------------------------------- the server side


class _Worker:
    def __init__(self, ctx: Any, data_dir: Path) -> None:
        self.conn, child = ctx.Pipe(duplex=True)
        self.process: BaseProcess = ctx.Process(target=_serve, args=(child, str(data_dir)),
                                                name="drivetrain-sizing", daemon=True)
        self.process.start()
        child.close()
        self.ready = False

    def poll_ready(self, timeout: float = 0.0) -> bool:
        """Whether the worker has warmed up (reads its "ready" message, waiting at most ``timeout`` s)."""
        try:
            if not self.ready and self.conn.poll(timeout):
                kind, _ = self.conn.recv()
                self.ready = kind == "ready"
        except (EOFError, OSError):  # it died while starting: the next take replaces it
            return False
        return self.ready

    def call(self, fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[str, Any]:
        self.conn.send((fn, args))
        while True:
            answer: tuple[str, Any] = self.conn.recv()
            if answer[0] != "ready":
                return answer
            self.ready = True

    def kill(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self.process.kill()
        with contextlib.suppress(OSError):
            self.conn.close()
        # reap it without making anyone wait
        threading.Thread(target=self.process.join, name="drivetrain-reap", daemon=True).start()


class WorkerPool:
    """At most ``size`` worker processes, handed out first come, first served.

    ``run`` sizes on one and kills it if the request is cancelled (its time limit). A request that
    finds no idle worker joins a queue; a worker that comes free (or the fresh replacement of a
    killed one) goes to the request at the head of the queue, never to one that arrived later, so
    no request waits behind newer ones. At most ``max_waiting`` requests queue; one more is
    answered 503 at once (the client retries) rather than after the time limit.

    The queue is resolved on the event loop: ``run``, and so every hand-over, runs there;
    ``spawn`` makes a worker (a test passes a fake one).
    """

    def __init__(self, size: int, data_dir: Path, max_waiting: int = MAX_WAITING,
                 spawn: Callable[[], Any] | None = None) -> None:
        self.size, self.data_dir, self.max_waiting = size, data_dir, max_waiting
        self.ctx = multiprocessing.get_context("spawn")
        self.spawn: Callable[[], Any] = spawn or (lambda: _Worker(self.ctx, self.data_dir))
        self.idle: list[Any] = []
        self.waiting: collections.deque[asyncio.Future[Any]] = collections.deque()
        self.count = 0
        self.lock = threading.Lock()
        self.closed = False

    def start(self) -> None:
        """Start every worker now (they warm up while the server starts), rather than on first use."""
        with self.lock:
            while not self.closed and self.count < self.size:
                self.idle.append(self.spawn())
                self.count += 1

    def _take(self) -> Any | None:
        """An idle worker (a warm one first) or a new one if the pool is not full; None if all are busy."""
        if self.closed:
            raise ApiError(503, "the server is stopping")
        for worker in [w for w in self.idle if not w.process.is_alive()]:
            self.idle.remove(worker)
            worker.kill()
            self.count -= 1
        if self.idle:
            worker = next((w for w in reversed(self.idle) if w.poll_ready()), self.idle[-1])
            self.idle.remove(worker)
            return worker
        if self.count < self.size:
            self.count += 1
            try:
                return self.spawn()
            except BaseException:
                self.count -= 1
                raise
        return None

    async def _acquire(self) -> Any:
        """A worker for this request: at once if one is free and nobody waits, else in arrival order."""
        with self.lock:
            worker = None if self.waiting else self._take()
            if worker is not None:
                return worker
            if len(self.waiting) >= self.max_waiting:
                raise ApiError(503, f"the server is busy ({len(self.waiting)} requests are waiting for a sizing "
                               "worker); try again in a moment")
            turn: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
            self.waiting.append(turn)
        try:
            return await turn
        except BaseException:  # cancelled while waiting (its time limit)
            with self.lock:
                if turn in self.waiting:
                    self.waiting.remove(turn)
                    raise
            if turn.done() and not turn.cancelled() and turn.exception() is None:
                self._release(turn.result())  # handed over just as it was cancelled: pass it on
            raise

    def _release(self, worker: Any) -> None:
        """Hand ``worker`` to the longest-waiting request, else put it back among the idle ones."""
        with self.lock:
            if self.closed:
                worker.kill()
                self.count -= 1
                return
            while self.waiting:
                turn = self.waiting.popleft()
                if not turn.done():
                    turn.set_result(worker)
                    return
            self.idle.append(worker)

    def _drop(self, worker: Any) -> None:
        """Kill ``worker`` and start its replacement at once (it warms up while the next request waits)."""
        worker.kill()
        with self.lock:
            self.count -= 1
            if self.closed:
                return
            try:
                fresh = self.spawn()
            except OSError:
                fresh = None
            else:
                self.count += 1
        if fresh is not None:
            self._release(fresh)
        else:  # no process could be started: the next request tries again
            self._wake_one()

    def _wake_one(self) -> None:
        """Let the longest-waiting request try to start a worker of its own (the pool has room)."""
        with self.lock:
            while self.waiting and self.count < self.size and not self.closed:
                turn = self.waiting.popleft()
                if turn.done():
                    continue
                try:
                    worker = self._take()
                except BaseException as exc:
                    turn.set_exception(exc)
                    return
                if worker is None:
                    self.waiting.appendleft(turn)
                    return
                turn.set_result(worker)
                return

    async def run(self, fn: Callable[..., T], *args: Any) -> T:
        """``fn(*args)`` in a worker process; ``fn`` and its arguments must pickle (module-level functions)."""
        worker = await self._acquire()
        try:
            kind, value = await anyio.to_thread.run_sync(worker.call, fn, args, abandon_on_cancel=True)
        except BaseException as exc:  # cancelled (time limit), or the worker died
            self._drop(worker)
            if isinstance(exc, (EOFError, OSError)):
                raise ApiError(503, "the sizing worker stopped before it answered (out of memory?); try again") \
                    from None
            raise
        self._release(worker)
        if kind == "error":
            raise _error_from(value)
        result: T = value
        return result

    def wait_ready(self, timeout: float) -> bool:
        """Start the workers and wait until every idle one has warmed up (at most ``timeout`` s)."""
        import time

        self.start()
        deadline = time.monotonic() + timeout
        with self.lock:
            workers = list(self.idle)
        return all(w.poll_ready(max(0.0, deadline - time.monotonic())) for w in workers)

    def close(self) -> None:
        """Stop every worker (idle ones now; busy ones when their request ends) and refuse the waiting requests."""
        with self.lock:
            self.closed = True
            idle, self.idle = self.idle, []
            self.count -= len(idle)
            waiting, self.waiting = list(self.waiting), collections.deque()
        for worker in idle:
            worker.kill()
        for turn in waiting:
            if not turn.done():
                turn.set_exception(ApiError(503, "the server is stopping"))
