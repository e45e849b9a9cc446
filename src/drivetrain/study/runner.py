"""Running a study: variants in batches on a Dask cluster (embedded or existing) or in this process.

The variants are a pure function of the study file (design and seed), so a resumed run regenerates
them and skips those whose rows the partial result already holds. A worker process keeps one
:class:`~drivetrain.study.batch.Engine` (the catalog loaded once per worker; a task carries only
its variants' parameter values). Rows come back as their tasks finish (``as_completed``); the
partial result is rewritten atomically every few seconds and on Ctrl-C.
"""

from __future__ import annotations

import json
import logging
import math
import os
import pickle
import sys
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from drivetrain.errors import InputError
from drivetrain.files import write_atomic
from drivetrain.study.record import fast_covers, row_from
from drivetrain.study.spec import Parameter, Study, variant_mapping

if TYPE_CHECKING:
    import pandas as pd

    from drivetrain.axis.model import Axis

ENV_SCHEDULER = "DRIVETRAIN_SCHEDULER"
BATCH = 200
"""Variants per task."""
PARTIAL_EVERY = 5.0
"""Seconds between rewrites of the partial result."""
META_KEY = b"drivetrain.study"
CONNECT_TIMEOUT = "10s"
"""How long to try reaching an existing scheduler."""
EMBEDDED_CONFIG: dict[str, Any] = {"distributed.worker.profile.enabled": False,
                                   "distributed.admin.system-monitor.gil.enabled": False,
                                   "distributed.admin.tick.interval": "1s",
                                   "distributed.admin.system-monitor.interval": "5s",
                                   "distributed.admin.system-monitor.disk": False,
                                   "distributed.worker.memory.monitor-interval": "1s"}
"""Dask settings of the embedded cluster: no statistical profiler or GIL monitor beside the sizing;
the event-loop tick, the system monitor (no disk counters) and the workers' memory monitor at
1-5 s instead of 20-500 ms (their bookkeeping took about 6 % of a core in this process while the
workers sized, measured); and on Linux worker processes forked from this one, so that they start
with the modules, the unit registry, the compiled code and the catalog tables this process has
loaded (``make_plan`` sized the base axis); elsewhere Dask's default start method."""
if sys.platform.startswith("linux"):
    EMBEDDED_CONFIG["distributed.worker.multiprocessing-method"] = "fork"


@dataclass(frozen=True)
class Plan:
    """What a worker needs to size variants: small, sent to each worker once."""

    base: dict[str, Any]
    parameters: tuple[Parameter, ...]
    record: tuple[str, ...]
    points: int
    full: bool  # a recorded key needs the unbatched drivetrain.size
    drives: bool = False  # a recorded key needs the drive post-pass (selection.selected.drive, ...)

    def axis_dict(self, values: tuple[Any, ...]) -> dict[str, Any]:
        """The axis mapping of one variant (``spec.variant_mapping``, as ``Study.axis_dict``)."""
        return variant_mapping(self.base, self.parameters, values)


_ENGINE: Any = None


def _engine(points: int, drives: bool = False) -> Any:
    """This process's engine (catalog tables loaded on its first selection, then kept)."""
    global _ENGINE
    from drivetrain.study.batch import Engine

    if _ENGINE is None or _ENGINE.points != points:
        _ENGINE = Engine(points)
    _ENGINE.drives = drives
    return _ENGINE


def size_variant(plan: Plan, values: tuple[Any, ...]) -> dict[str, Any]:
    """One variant's result mapping (batched path, or ``size().to_dict()`` when the record needs it)."""
    from drivetrain.study.batch import full_result

    axis = variant_axis(plan, values)
    return full_result(axis, plan.points) if plan.full else _engine(plan.points, plan.drives).size(axis)


def variant_axis(plan: Plan, values: tuple[Any, ...]) -> Axis:
    """A variant's axis (InputError naming the field if its values make bad input)."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.axis.yaml_text import check_text

    # the base's text was checked by make_plan (parse_axis of the base); only the new values need it
    for p, v in zip(plan.parameters, values, strict=True):
        check_text(v, p.path)
    return parse_axis(plan.axis_dict(values), text_checked=True)


def run_batch(plan: Plan, items: list[tuple[int, tuple[Any, ...]]]) -> list[dict[str, Any]]:
    """Size a batch of variants; a variant whose values make bad input gets its error in its row.

    On the batched path the batch's axes are sized together (``Engine.size_many``: their
    mechanism checks as arrays over the batch), each with the answer it gets alone."""
    results: list[dict[str, Any] | InputError] = []
    if plan.full:
        for _, values in items:
            try:
                results.append(size_variant(plan, values))
            except InputError as exc:
                results.append(exc)
    else:
        axes: list[Axis | InputError] = []
        for _, values in items:
            try:
                axes.append(variant_axis(plan, values))
            except InputError as exc:
                axes.append(exc)
        sized = iter(_engine(plan.points, plan.drives).size_many([a for a in axes if not isinstance(a, InputError)]))
        results = [a if isinstance(a, InputError) else next(sized) for a in axes]
    rows = []
    for (idx, values), res in zip(items, results, strict=True):
        row: dict[str, Any] = {"variant": idx}
        row.update({p.path: v for p, v in zip(plan.parameters, values, strict=True)})
        if isinstance(res, InputError):
            row.update({"ok": False, "error": str(res)})
        else:
            row.update(row_from(res, list(plan.record)))
            row["error"] = ""
        rows.append(row)
    return rows


def run_packed(plan: Plan, packed: bytes) -> list[dict[str, Any]]:
    """``run_batch`` of a pickled list of variants: a task's argument is one opaque object, which
    Dask sends as it is instead of walking its 10,000 values when the task graph is built."""
    items: list[tuple[int, tuple[Any, ...]]] = pickle.loads(packed)  # made by _run_dask
    return run_batch(plan, items)


def make_plan(study: Study) -> Plan:
    """The worker plan; the recorded keys are checked against a sizing of the base axis first."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.study.batch import full_result

    axis = parse_axis(study.base)
    fast = _engine(study.spec.points).size(axis)
    # the full result only where the batched one lacks a recorded key (to tell unknown keys apart)
    full = fast if not fast_covers(fast, fast, study.spec.record)[1] else full_result(axis, study.spec.points)
    covered, unknown = fast_covers(fast, full, study.spec.record)
    if unknown:
        k = study.spec.record.index(unknown[0])
        raise InputError(f"record[{k}]", "is not a key of the size result of the base axis (e.g. "
                         "selection.selected.motor, rms_torque_Nm, selection.passing)", unknown[0])
    drives = False
    if not covered:  # a key of the drive post-pass (selection.selected.drive.id, ...)?
        drives = True
        covered, _ = fast_covers(_engine(study.spec.points, drives).size(axis), full, study.spec.record)
    return Plan(base=study.base, parameters=study.parameters, record=tuple(study.spec.record),
                points=study.spec.points, full=not covered, drives=drives and covered)


# ---------------------------------------------------------------------------------------------
# files


def metadata(study: Study) -> dict[str, Any]:
    """What the result files record about their making."""
    from drivetrain.catalog.schema import DATA_VERSION
    from drivetrain.version import __version__

    return {"study_file": study.text, "study_source": study.source, "base_axis_file": study.base_text,
            "drivetrain_version": __version__, "catalog_data_version": DATA_VERSION,
            "design": study.spec.design, "variants": study.n_variants(),
            "units": {p.path: p.unit for p in study.parameters}}


def frame(rows: list[dict[str, Any]], study: Study) -> pd.DataFrame:
    """Rows as a DataFrame in variant order, with the metadata in ``attrs``."""
    import pandas as pd

    df = pd.DataFrame(rows)
    if len(df):
        df = df.sort_values("variant", kind="stable").reset_index(drop=True)
    df.attrs["drivetrain"] = metadata(study)
    return df


def _write_text(path: Path, text: str) -> None:
    path.write_text(text, encoding="utf-8")


def write_parquet(df: pd.DataFrame, path: Path, meta: dict[str, Any]) -> None:
    """Parquet through pyarrow, the study's metadata in the schema (``drivetrain.study``), atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_pandas(_arrow_safe(df), preserve_index=False)
    table = table.replace_schema_metadata({**(table.schema.metadata or {}), META_KEY: json.dumps(meta).encode()})
    write_atomic(path, lambda tmp: pq.write_table(table, tmp))


def _arrow_safe(df: pd.DataFrame) -> pd.DataFrame:
    """Object columns of mixed types (a list of names and numbers) as text, so Arrow can type them."""
    out = df.copy()
    for col in out.columns:
        if out[col].dtype == object:
            kinds = {type(v) for v in out[col] if v is not None and not (isinstance(v, float) and math.isnan(v))}
            if len(kinds) > 1 and not kinds <= {int, float} and not kinds <= {bool}:
                out[col] = out[col].map(lambda v: None if v is None else str(v))
    return out


def read_parquet(path: Path) -> tuple[pd.DataFrame, dict[str, Any]]:
    """A study result (or partial result) and its metadata."""
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    meta = json.loads((table.schema.metadata or {}).get(META_KEY, b"{}"))
    df = table.to_pandas()
    df.attrs["drivetrain"] = meta
    return df, meta


def write_results(df: pd.DataFrame, out: Path, study: Study) -> list[Path]:
    """``out`` (.parquet), the same table as CSV beside it and the metadata as JSON; returns the paths."""
    meta = {**metadata(study), **df.attrs.get("drivetrain", {})}
    pq_path = out.with_suffix(".parquet")
    csv_path = out.with_suffix(".csv")
    meta_path = out.with_suffix(".meta.json")
    write_parquet(df, pq_path, meta)
    write_atomic(csv_path, lambda tmp: df.to_csv(tmp, index=False))
    write_atomic(meta_path, lambda tmp: _write_text(tmp, json.dumps(meta, indent=1)))
    return [pq_path, csv_path, meta_path]


def partial_path(out: Path) -> Path:
    return out.with_suffix(".partial.parquet")


# ---------------------------------------------------------------------------------------------
# running


def _batches(items: list[tuple[int, tuple[Any, ...]]], size: int) -> Iterator[list[tuple[int, tuple[Any, ...]]]]:
    for k in range(0, len(items), size):
        yield items[k:k + size]


MOTION_NEUTRAL = ("mechanism.load.", "motor.", "guide.", "mechanism.nut.", "mechanism.screw.", "drive.",
                  "environment.")
"""Parameter paths that never change the motor shaft's speeds (loads, ratings, margins)."""


def _by_motion(items: list[tuple[int, tuple[Any, ...]]],
               parameters: tuple[Parameter, ...]) -> list[tuple[int, tuple[Any, ...]]]:
    """The variants with the values that can change the motion (profile, lead, ratios) next to each
    other, in order of first appearance: a task then holds whole groups of variants of one motion,
    whose hulls the engine computes together (``Engine.size_many``). Rows are sorted by variant at
    the end, so the order changes nothing else."""
    moving = [k for k, p in enumerate(parameters) if not p.path.startswith(MOTION_NEUTRAL)]
    if len(moving) == len(parameters):
        return items
    groups: dict[str, list[tuple[int, tuple[Any, ...]]]] = {}
    for it in items:
        groups.setdefault(repr([it[1][k] for k in moving]), []).append(it)
    return [it for group in groups.values() for it in group]


def _tasks(items: list[tuple[int, tuple[Any, ...]]], size: int,
           n_workers: int) -> Iterator[list[tuple[int, tuple[Any, ...]]]]:
    """Batches of ``size`` variants, the last ``2 x n_workers`` of them cut in quarters: the workers'
    last tasks end closer together (one worker idles for at most a short task at the end)."""
    tail = min(len(items), 2 * n_workers * size)
    yield from _batches(items[:len(items) - tail], size)
    yield from _batches(items[len(items) - tail:], max(1, size // 4))


class _Progress:
    """A rich progress bar with rate and ETA (silent when disabled)."""

    def __init__(self, total: int, done: int, enabled: bool, label: str) -> None:
        self.bar: Any = None
        if enabled:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(),
                                TextColumn("ETA"), TimeRemainingColumn(), transient=False,
                                console=Console(stderr=True))
            self.bar.start()
            self.task = self.bar.add_task(label, total=total, completed=done)

    def advance(self, n: int) -> None:
        if self.bar is not None:
            self.bar.advance(self.task, n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


MALLOC_SETTINGS = ((-1, 256 << 20), (-2, 16 << 20), (-3, 16 << 20))
"""glibc ``mallopt`` settings of the embedded cluster's workers: M_TRIM_THRESHOLD 256 MiB,
M_TOP_PAD 16 MiB, M_MMAP_THRESHOLD 16 MiB (glibc malloc.h; mallopt(3)). With glibc's defaults a
sizing's arrays of 0.1-1 MB are given back to the system when freed and faulted in again, zeroed,
by the next variant: about 440,000 page faults and 0.9 s of system time per 10,000 variants,
130,000 and 0.5 s with these (measured, bench/RESULTS.md). The workers end with the study."""


def _keep_freed_memory() -> bool:
    """Apply MALLOC_SETTINGS in this process (an embedded worker); False where there is no glibc."""
    import ctypes

    try:
        libc = ctypes.CDLL("libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    return all(mallopt(ctypes.c_int(k), ctypes.c_int(v)) == 1 for k, v in MALLOC_SETTINGS)


_FREEZE_AT_EXIT: list[bool] = []


def _freeze_at_exit() -> None:
    """Once per process: at its end, freeze the objects that exist (``gc.freeze``) before the
    interpreter's last collections, which would otherwise examine every object of the modules a
    study imports (Dask, pandas, pyarrow) and its rows once more just before the memory is given
    back: 0.15-0.2 s at the end of a 10,000-variant ``sweep`` on 2 workers, 0.01-0.03 s with it
    (measured, bench/RESULTS.md). Objects still go when nothing refers to them; only cyclic
    garbage left at the very end is not collected, as the operating system frees it anyway."""
    if not _FREEZE_AT_EXIT:
        import atexit
        import gc

        atexit.register(gc.freeze)
        _FREEZE_AT_EXIT.append(True)


def scheduler_address(scheduler: str | None) -> str | None:
    """``--scheduler`` or ``$DRIVETRAIN_SCHEDULER`` (None: an embedded cluster)."""
    return scheduler or os.environ.get(ENV_SCHEDULER) or None


def check_run(batch: int, workers: int | None, resume: bool, out: Path | None) -> None:
    """The run's own arguments, checked before anything is sized (both ``run`` and ``stream.run_streamed``)."""
    if batch < 1:
        raise InputError("--batch", "must be at least 1", batch)
    if workers is not None and workers < 0:
        raise InputError("--workers", "must be 0 (this process) or more", workers)
    if resume and out is None:
        raise InputError("--resume", "needs the output file whose partial result to continue", has_value=False)


def run(study: Study, *, out: Path | None = None, scheduler: str | None = None, workers: int | None = None,
        batch: int = BATCH, resume: bool = False, progress: bool = False,
        on_rows: Callable[[int], None] | None = None) -> pd.DataFrame:
    """Size every variant of the study; returns the table (written to ``out`` when given).

    ``workers=0`` runs in this process; otherwise on ``scheduler`` (an address, or
    ``$DRIVETRAIN_SCHEDULER``) or an embedded ``LocalCluster`` of ``workers`` processes (default:
    every core). Ctrl-C writes the finished rows to ``out``'s partial file and re-raises.
    """
    check_run(batch, workers, resume, out)
    plan = make_plan(study)
    _freeze_at_exit()
    variants = study.variants()
    rows: list[dict[str, Any]] = []
    if resume and out is not None:
        rows = _resume_rows(study, out)
    done = {int(r["variant"]) for r in rows}
    todo = _by_motion([(i, v) for i, v in enumerate(variants) if i not in done], study.parameters)
    bar = _Progress(len(variants), len(done), progress, study.spec.name)
    last = time.monotonic()

    def collect(new: Iterable[dict[str, Any]]) -> None:
        nonlocal last
        got = list(new)
        rows.extend(got)
        bar.advance(len(got))
        if on_rows is not None:
            on_rows(len(rows))
        if out is not None and time.monotonic() - last > PARTIAL_EVERY:
            write_parquet(frame(rows, study), partial_path(out), metadata(study))
            last = time.monotonic()

    try:
        if workers == 0 and scheduler_address(scheduler) is None:
            for chunk in _batches(todo, batch):
                collect(run_batch(plan, chunk))
        else:
            _run_dask(plan, todo, batch, scheduler_address(scheduler), workers, collect)
    except KeyboardInterrupt:
        if out is not None:
            write_parquet(frame(rows, study), partial_path(out), metadata(study))
        raise
    finally:
        bar.close()
    df = frame(rows, study)
    if out is not None:
        write_results(df, out, study)
        partial_path(out).unlink(missing_ok=True)
    return df


def _resume_rows(study: Study, out: Path) -> list[dict[str, Any]]:
    part = partial_path(out)
    if not part.exists():
        raise InputError("--resume", "there is no partial result to continue", str(part))
    df, meta = read_parquet(part)
    if meta.get("study_file") != study.text or meta.get("base_axis_file") != study.base_text:
        raise InputError("--resume", "the partial result is of another study file or base axis file", str(part))
    return [{str(k): v for k, v in r.items()} for r in df.to_dict("records")]


def connect(address: str | None, workers: int | None) -> tuple[Any, Any]:
    """A Dask client (and its embedded ``LocalCluster`` of ``workers`` processes, or None when ``address``
    names a scheduler to connect to): the set-up of every study run on Dask."""
    import dask
    from distributed import Client, LocalCluster

    cluster = None
    if address is None:
        n = workers or os.cpu_count() or 1
        import gc

        frozen = sys.platform.startswith("linux") and gc.isenabled()
        if frozen:
            # the workers fork from this process with every object it holds frozen: their collector
            # never examines (nor writes to, copying the pages) the modules and tables they inherit
            # (0.4-1.3 s less CPU of the workers per 10,000 variants, bench/RESULTS.md); this process
            # unfreezes its own at once, so nothing changes for it
            gc.freeze()
        try:
            with dask.config.set(EMBEDDED_CONFIG):
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                       silence_logs=logging.ERROR)
        finally:
            if frozen:
                gc.unfreeze()
        client = Client(cluster)
        if sys.platform.startswith("linux"):
            client.run(_keep_freed_memory)
    else:
        try:
            client = Client(address, timeout=CONNECT_TIMEOUT)
        except OSError as exc:
            raise InputError("--scheduler", f"cannot reach the Dask scheduler ({exc})", address) from None
    return client, cluster


def _run_dask(plan: Plan, todo: list[tuple[int, tuple[Any, ...]]], batch: int, address: str | None,
              workers: int | None, collect: Callable[[Iterable[dict[str, Any]]], None]) -> None:
    from distributed import as_completed

    client, cluster = connect(address, workers)
    try:
        n_workers = max(len(client.scheduler_info().get("workers", {})), 1)
        # small studies: enough tasks for every worker
        size = max(1, min(batch, math.ceil(len(todo) / (4 * n_workers))))
        [plan_f] = client.scatter([plan], broadcast=True)
        futures = [client.submit(run_packed, plan_f, pickle.dumps(chunk, protocol=pickle.HIGHEST_PROTOCOL),
                                 pure=False) for chunk in _tasks(todo, size, n_workers)]
        import pandas  # noqa: F401  (for the result table, imported while the workers size rather than after)

        try:
            for fut in as_completed(futures):
                collect(fut.result())
        except BaseException:
            client.cancel(futures)
            raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


__all__ = ["BATCH", "ENV_SCHEDULER", "Plan", "make_plan", "read_parquet", "run", "run_batch", "run_packed",
           "variant_axis", "write_results"]
