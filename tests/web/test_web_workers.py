"""The sizing workers are handed out first come, first served (web/workers.py).

A fake worker stands for a process: its job blocks until the test opens that job's gate, so the
test decides when each job ends and checks the order in which the waiting requests got a
worker. No clock is involved: every wait is for a condition.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest

from drivetrain.web.common import ApiError
from drivetrain.web.workers import WorkerPool

STEP_LIMIT = 20_000
"""Event-loop turns a condition may take (each turn yields 1 ms): a broken pool fails, it does not hang."""


class FakeProcess:
    def __init__(self) -> None:
        self.alive = True

    def is_alive(self) -> bool:
        return self.alive


class FakeWorker:
    """Runs a job named by its first argument: records its start, waits for its gate."""

    def __init__(self, started: list[str], gates: dict[str, threading.Event], killed: list[FakeWorker]) -> None:
        self.process = FakeProcess()
        self.started, self.gates, self.killed = started, gates, killed

    def poll_ready(self, timeout: float = 0.0) -> bool:
        return True

    def call(self, fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[str, Any]:
        name = str(args[0])
        self.started.append(name)
        if not self.gates[name].wait(timeout=120):
            raise OSError("the test never opened this gate")
        return "ok", name

    def kill(self) -> None:
        self.process.alive = False
        self.killed.append(self)


def job(name: str) -> str:
    return name


class Harness:
    def __init__(self, tmp_path: Path, size: int = 1, max_waiting: int = 64) -> None:
        self.started: list[str] = []
        self.gates: dict[str, threading.Event] = {}
        self.killed: list[FakeWorker] = []
        self.pool = WorkerPool(size, tmp_path, max_waiting=max_waiting,
                               spawn=lambda: FakeWorker(self.started, self.gates, self.killed))
        self.tasks: dict[str, asyncio.Task[str]] = {}

    def submit(self, name: str) -> asyncio.Task[str]:
        self.gates[name] = threading.Event()
        task = asyncio.get_running_loop().create_task(self.pool.run(job, name))
        self.tasks[name] = task
        return task

    def finish(self, name: str) -> None:
        self.gates[name].set()

    async def queue(self, names: str) -> None:
        """Submit ``names`` one by one, each after the one before is waiting: their order in the queue."""
        for name in names:
            waiting = len(self.pool.waiting)
            self.submit(name)
            await until(lambda waiting=waiting: len(self.pool.waiting) == waiting + 1)  # type: ignore[misc]


async def until(condition: Callable[[], bool]) -> None:
    for _ in range(STEP_LIMIT):
        if condition():
            return
        await asyncio.sleep(0.001)
    raise AssertionError("the condition never held")


def run(body: Callable[[], Awaitable[None]]) -> None:
    asyncio.run(body())


def test_a_freed_worker_goes_to_the_longest_waiting_request(tmp_path: Path) -> None:
    async def body() -> None:
        h = Harness(tmp_path)
        h.submit("A")
        await until(lambda: h.started == ["A"])
        await h.queue("BCD")
        h.finish("A")
        assert await h.tasks["A"] == "A"
        # a request arriving the moment a worker comes free queues behind the ones already waiting
        h.submit("E")
        for name in "BCDE":
            await until(lambda name=name: h.started[-1] == name)  # type: ignore[misc]
            h.finish(name)
            assert await h.tasks[name] == name
        assert h.started == list("ABCDE")
        assert not h.pool.waiting and len(h.pool.idle) == 1

    run(body)


def test_with_two_workers_the_order_holds(tmp_path: Path) -> None:
    async def body() -> None:
        h = Harness(tmp_path, size=2)
        h.submit("A")
        h.submit("B")
        await until(lambda: sorted(h.started) == ["A", "B"])
        await h.queue("CDEF")
        h.finish("B")
        await until(lambda: len(h.started) == 3)
        h.finish("A")
        await until(lambda: len(h.started) == 4)
        assert h.started[2:] == ["C", "D"]
        h.submit("G")
        # one job ended at a time, each next start awaited: the order of the starts is the order of the hand-outs
        for ended, starts in (("C", "E"), ("D", "F"), ("E", "G")):
            h.finish(ended)
            await until(lambda starts=starts: h.started[-1] == starts)  # type: ignore[misc]
        for name in "FG":
            h.finish(name)
        for name in "ABCDEFG":
            assert await h.tasks[name] == name
        assert h.started[2:] == list("CDEFG")

    run(body)


def test_a_waiter_that_gives_up_is_skipped(tmp_path: Path) -> None:
    async def body() -> None:
        h = Harness(tmp_path)
        h.submit("A")
        await until(lambda: h.started == ["A"])
        await h.queue("BCD")
        h.tasks["C"].cancel()  # its time limit fired while it waited
        await until(lambda: len(h.pool.waiting) == 2)
        for name in "ABD":
            h.finish(name)
        assert [await h.tasks[n] for n in "ABD"] == list("ABD")
        with pytest.raises(asyncio.CancelledError):
            await h.tasks["C"]
        assert h.started == list("ABD")

    run(body)


def test_a_killed_workers_replacement_goes_to_the_head_of_the_queue(tmp_path: Path) -> None:
    async def body() -> None:
        h = Harness(tmp_path)
        h.submit("A")
        await until(lambda: h.started == ["A"])
        h.submit("B")
        h.submit("C")
        await until(lambda: len(h.pool.waiting) == 2)
        h.tasks["A"].cancel()  # A ran past its limit: its worker is killed, a fresh one takes its place
        with pytest.raises(asyncio.CancelledError):
            await h.tasks["A"]
        assert len(h.killed) == 1
        h.submit("D")
        await until(lambda: h.started[-1] == "B")
        for name in "BCD":
            await until(lambda name=name: h.started[-1] == name)  # type: ignore[misc]
            h.finish(name)
            assert await h.tasks[name] == name
        assert h.started == list("ABCD") and h.pool.count == 1
        h.finish("A")  # let the abandoned thread end

    run(body)


def test_past_the_queue_bound_a_request_is_refused_at_once(tmp_path: Path) -> None:
    async def body() -> None:
        h = Harness(tmp_path, max_waiting=2)
        h.submit("A")
        await until(lambda: h.started == ["A"])
        h.submit("B")
        h.submit("C")
        await until(lambda: len(h.pool.waiting) == 2)
        with pytest.raises(ApiError) as refused:
            await h.submit("D")
        assert refused.value.status == 503 and "2 requests are waiting" in refused.value.detail
        for name in "ABC":
            h.finish(name)
            assert await h.tasks[name] == name

    run(body)
