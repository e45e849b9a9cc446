"""Studies too large to hold in memory: variants made lazily, rows written to disk batch by batch.

A study of more than ``STREAM_ABOVE`` variants (only with ``--yes``) runs here: its variants come
one batch at a time from ``Study.iter_variants`` (a grid is never listed), at most
``INFLIGHT_PER_WORKER`` tasks per worker are queued on the Dask cluster at once, and the rows go to
a Parquet file (one row group per ``FLUSH_ROWS`` rows) and a CSV file as they arrive, so the
memory of the run does not grow with the number of variants. The table is complete when the run
ends (``out`` .parquet, .csv and .meta.json); an interrupted run leaves the rows finished so far in
the partial files, readable as they are. The rows are in the order their tasks finish (in
variant order when run in this process; sort by ``variant`` to have it otherwise). The returned
DataFrame holds no rows: its ``attrs`` say where the table is and how many variants pass.
"""

from __future__ import annotations

import json
import os
import pickle
from collections.abc import Callable, Iterator
from itertools import islice
from pathlib import Path
from typing import TYPE_CHECKING, Any

from drivetrain.errors import InputError
from drivetrain.study.spec import MAX_VARIANTS, Study

if TYPE_CHECKING:
    import pandas as pd
    import pyarrow as pa

    from drivetrain.study.runner import Plan

STREAM_ABOVE = MAX_VARIANTS
"""Studies of more variants than this stream their rows to disk (the table is not returned)."""
FLUSH_ROWS = 10_000
"""Rows held in memory before they are written (one Parquet row group)."""
INFLIGHT_PER_WORKER = 4
"""Tasks queued per Dask worker at once: enough to keep it busy, few enough to bound memory."""


def columns(plan: Plan, study: Study) -> list[tuple[str, str]]:
    """(column, kind) of the table: ``kind`` is int, float, bool or text; the recorded columns and
    their kinds are those of the base axis's row (made by sizing it once)."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.study.batch import full_result
    from drivetrain.study.record import row_from
    from drivetrain.study.runner import _engine

    axis = parse_axis(study.base)
    result = full_result(axis, plan.points) if plan.full else _engine(plan.points, plan.drives).size(axis)
    base_row = row_from(result, list(plan.record))
    out: list[tuple[str, str]] = [("variant", "int")]
    out += [(p.path, "float" if p.numeric else "text") for p in study.parameters]
    for name, value in base_row.items():
        if name in ("ok",):
            continue
        out.append((name, _kind(value)))
    out += [("ok", "bool"), ("error", "text")]
    seen: set[str] = set()
    return [c for c in out if not (c[0] in seen or seen.add(c[0]))]  # type: ignore[func-returns-value]


def _kind(value: Any) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, (int, float)):
        return "float"
    return "text"


def _cell(value: Any, kind: str) -> Any:
    """A row's value as its column's kind (a value of another kind is kept as text in a text column,
    else left empty)."""
    if value is None:
        return None
    if kind == "float":
        return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None
    if kind == "int":
        return int(value)
    if kind == "bool":
        return bool(value) if isinstance(value, bool) else None
    return value if isinstance(value, str) else str(value)


class RowSink:
    """Rows to a Parquet file (one row group per flush) and a CSV file beside it, with a fixed set
    of columns; at most ``flush_rows`` rows are held in memory."""

    def __init__(self, parquet: Path, csv: Path, cols: list[tuple[str, str]], meta: dict[str, Any],
                 flush_rows: int | None = None) -> None:
        import pyarrow as pa
        import pyarrow.csv as pacsv
        import pyarrow.parquet as pq

        from drivetrain.study.runner import META_KEY

        types = {"int": pa.int64(), "float": pa.float64(), "bool": pa.bool_(), "text": pa.string()}
        self.cols = cols
        self.schema: pa.Schema = pa.schema([(n, types[k]) for n, k in cols]).with_metadata(
            {META_KEY: json.dumps(meta).encode()})
        self.flush_rows = flush_rows or FLUSH_ROWS
        parquet.parent.mkdir(parents=True, exist_ok=True)
        self.parquet = pq.ParquetWriter(parquet, self.schema)
        self.csv = pacsv.CSVWriter(str(csv), self.schema.remove_metadata())
        self.buffer: list[dict[str, Any]] = []
        self.rows = 0
        self.passing = 0
        self.flushes = 0
        self.most_buffered = 0

    def add(self, rows: list[dict[str, Any]]) -> None:
        self.buffer.extend(rows)
        self.rows += len(rows)
        self.passing += sum(1 for r in rows if r.get("ok") is True)
        self.most_buffered = max(self.most_buffered, len(self.buffer))
        if len(self.buffer) >= self.flush_rows:
            self.flush()

    def flush(self) -> None:
        if not self.buffer:
            return
        import pyarrow as pa

        data = {n: [_cell(r.get(n), k) for r in self.buffer] for n, k in self.cols}
        table = pa.Table.from_pydict(data, schema=self.schema)
        self.parquet.write_table(table)
        self.csv.write_table(table.replace_schema_metadata(None))
        self.buffer = []
        self.flushes += 1

    def close(self) -> None:
        try:
            self.flush()
        finally:
            self.parquet.close()
            self.csv.close()


def run_streamed(study: Study, plan: Plan, *, out: Path | None, scheduler: str | None, workers: int | None,
                 batch: int, resume: bool, progress: bool,
                 on_rows: Callable[[int], None] | None = None) -> pd.DataFrame:
    """Size every variant of a large study, writing the rows to ``out`` as they come (see the module)."""
    import pandas as pd

    from drivetrain.study.runner import _Progress, metadata, partial_path, run_batch, scheduler_address

    if out is None:
        raise InputError("out", f"a study of more than {STREAM_ABOVE:,} variants writes its rows to a file as they "
                         "come: give the output file (-o FILE.parquet)", has_value=False)
    if resume:
        raise InputError("--resume", f"a study of more than {STREAM_ABOVE:,} variants cannot be resumed: its "
                         "partial table is complete up to where it stopped; narrow the study to the rest",
                         has_value=False)
    meta = metadata(study)
    part = partial_path(out)
    part_csv = part.with_suffix(".csv")
    sink = RowSink(part, part_csv, columns(plan, study), meta)
    total = study.n_variants()
    bar = _Progress(total, 0, progress, study.spec.name)
    chunks = _chunks(study, batch)

    def collect(rows: list[dict[str, Any]]) -> None:
        sink.add(rows)
        bar.advance(len(rows))
        if on_rows is not None:
            on_rows(sink.rows)

    try:
        address = scheduler_address(scheduler)
        if workers == 0 and address is None:
            for chunk in chunks:
                collect(run_batch(plan, chunk))
        else:
            _dask(plan, chunks, address, workers, collect)
    finally:
        bar.close()
        sink.close()
    pq_path, csv_path, meta_path = out.with_suffix(".parquet"), out.with_suffix(".csv"), out.with_suffix(".meta.json")
    os.replace(part, pq_path)
    os.replace(part_csv, csv_path)
    meta_path.write_text(json.dumps({**meta, "rows": sink.rows, "passing": sink.passing}, indent=1),
                         encoding="utf-8")
    df = pd.DataFrame(columns=[n for n, _ in sink.cols])
    df.attrs["drivetrain"] = {**meta, "streamed": str(pq_path), "rows": sink.rows, "passing": sink.passing}
    return df


def _chunks(study: Study, batch: int) -> Iterator[list[tuple[int, tuple[Any, ...]]]]:
    """The variants, numbered, ``batch`` at a time (made as they are asked for)."""
    numbered = enumerate(study.iter_variants())
    while True:
        chunk = list(islice(numbered, batch))
        if not chunk:
            return
        yield chunk


def _dask(plan: Plan, chunks: Iterator[list[tuple[int, tuple[Any, ...]]]], address: str | None,
          workers: int | None, collect: Callable[[list[dict[str, Any]]], None]) -> None:
    """Run the chunks on a Dask cluster (embedded, or at ``address``), at most
    ``INFLIGHT_PER_WORKER`` per worker queued at once."""
    from distributed import as_completed

    from drivetrain.study.runner import connect, run_packed

    client, cluster = connect(address, workers)
    try:
        n_workers = max(len(client.scheduler_info().get("workers", {})), 1)
        [plan_f] = client.scatter([plan], broadcast=True)

        def submit(chunk: list[tuple[int, tuple[Any, ...]]]) -> Any:
            return client.submit(run_packed, plan_f, pickle.dumps(chunk, protocol=pickle.HIGHEST_PROTOCOL),
                                 pure=False)

        queue = as_completed([submit(c) for c in islice(chunks, INFLIGHT_PER_WORKER * n_workers)])
        try:
            for fut in queue:
                collect(fut.result())
                fut.release()
                nxt = next(chunks, None)
                if nxt is not None:
                    queue.add(submit(nxt))
        except BaseException:
            client.cancel(list(queue.futures))
            raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


__all__ = ["FLUSH_ROWS", "INFLIGHT_PER_WORKER", "STREAM_ABOVE", "RowSink", "columns", "run_streamed"]


def run(study: Study, *, out: Path | None = None, scheduler: str | None = None, workers: int | None = None,
        batch: int = 200, resume: bool = False, progress: bool = False,
        on_rows: Callable[[int], None] | None = None) -> pd.DataFrame:
    """Size every variant of the study (``runner.run``), streamed to disk batch by batch above
    ``STREAM_ABOVE`` variants (``run_streamed``: never listed in memory). The entry point of ``sweep``."""
    from drivetrain.study.runner import check_run, make_plan
    from drivetrain.study.runner import run as run_in_memory

    if study.n_variants() > STREAM_ABOVE:
        check_run(batch, workers, resume, out)
        return run_streamed(study, make_plan(study), out=out, scheduler=scheduler, workers=workers, batch=batch,
                            resume=resume, progress=progress, on_rows=on_rows)
    return run_in_memory(study, out=out, scheduler=scheduler, workers=workers, batch=batch, resume=resume,
                         progress=progress, on_rows=on_rows)
