"""The motor and gearbox tables of the catalog's queries (all but those by id) kept on disk, so that a new
process (``drivetrain size``) reads them in about 3 ms instead of building them from the databases' rows
(about 30 ms for the shipped catalog).

A stored table is used only when everything it was built from is as it was then: the shipped data files
(names, sizes and times: ``freshness.files_signature``, which is also what tells ``db.builtin_db`` that
the shipped database is current), the shipped database file and the user catalog (size, time, inode
and SQLite's change counter; absent stays absent), the data and schema versions, the modules that
define the tables, numpy's and the interpreter's versions, and the query. Anything else, or any error
reading it, builds the table from the databases as before and stores it again. The files live in the cache folder
(``unit_cache.cache_dir()``), one per query and catalog state,
the newest ``KEEP`` kept. A stored table's arrays are views of its file, mapped copy-on-write: a run
reads only the pages it uses (a sizing never reads the notes and sources columns, most of the bytes).
"""

from __future__ import annotations

import hashlib
import pickle
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from drivetrain.catalog import db
from drivetrain.catalog.freshness import files_signature
from drivetrain.catalog.schema import DATA_VERSION, SCHEMA_VERSION
from drivetrain.files import atomic_target

T = TypeVar("T")

FORMAT = "1"
"""Bumped when the stored form changes."""


def _stat(path: Path, database: bool = False) -> str:
    """Size, time and inode of a file; for a database also its change counter (SQLite's file header,
    bytes 24-27, incremented by every write transaction in rollback-journal mode, which the catalog uses)."""
    try:
        st = path.stat()
        counter = ""
        if database:
            with path.open("rb") as fh:
                counter = fh.read(28)[24:].hex()
    except OSError:
        return "absent"
    return f"{st.st_size}:{st.st_mtime_ns}:{st.st_ino}:{counter}"


def _key(query: str) -> str | None:
    """Everything the table of ``query`` depends on, or None when it cannot be told (not plain files)."""
    import numpy as np

    files = files_signature(f"{DATA_VERSION}/schema-{SCHEMA_VERSION}")
    if files is None:
        return None
    folder = db.data_dir()
    here = Path(__file__).parent
    parts = [FORMAT, query, files, str(folder), _stat(folder / db.BUILTIN_NAME, True),
             _stat(db.user_db_path(folder), True), np.__version__, sys.version,
             *(_stat(here / name) for name in ("tables.py", "curves.py", "schema.py"))]
    return "\n".join(parts)


def _path(key: str) -> Path:
    from drivetrain.unit_cache import cache_dir

    return cache_dir() / "catalog" / f"table-{hashlib.sha256(key.encode()).hexdigest()[:24]}.bin"


def cached(query: str, build: Callable[[], T]) -> T:
    """The table of ``query`` from disk when it is current, else ``build()`` (then stored)."""
    try:
        key = _key(query)
    except OSError:
        key = None
    if key is None:
        return build()
    path = _path(key)
    try:
        found = _read(path, key)
    except Exception:  # damaged or from another version: build it again
        found = None
    if found is not None:
        return found
    table = build()
    _store(path, key, table)
    return table


def _read(path: Path, key: str) -> Any:
    """The table stored at ``path`` for ``key``, or None. Its arrays are views of the file mapped
    copy-on-write (pages are read when used; writing to an array never changes the file)."""
    import mmap

    import numpy as np

    try:
        fh = path.open("rb")
    except OSError:
        return None
    with fh:
        if fh.read(len(MAGIC)) != MAGIC:
            return None
        size = int.from_bytes(fh.read(8), "little")
        stored_key, cls, plain, arrays = pickle.loads(fh.read(size))
        if stored_key != key:
            return None
        mapped = mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_COPY)
    fields = dict(plain)
    for name, dtype, count, offset in arrays:
        fields[name] = np.frombuffer(mapped, dtype=np.dtype(dtype), count=count, offset=offset)
    return cls(**fields)


MAGIC = b"drivetrain-table-1\n"
_ALIGN = 64


def _store(path: Path, key: str, table: Any) -> None:
    """Write atomically (a reader never sees half a file); best effort: a read-only folder keeps building.

    The file: MAGIC, the header's length (8 bytes), the header (a pickle of the key, the table's class,
    its fields that are not numeric or text arrays, and each array's dtype, length and offset), then
    each array's bytes at an offset aligned to 64 bytes.
    """
    import dataclasses

    import numpy as np

    plain: dict[str, Any] = {}
    blobs: list[tuple[str, Any]] = []
    for f in dataclasses.fields(table):
        value = getattr(table, f.name)
        if isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind in "biufU":
            blobs.append((f.name, np.ascontiguousarray(value)))
        else:
            plain[f.name] = value
    arrays: list[tuple[str, str, int, int]] = []
    header = b""
    for _ in range(2):  # the offsets depend on the header's length, which depends on the offsets' digits
        offset = _aligned(len(MAGIC) + 8 + len(header) + 64)
        arrays = []
        for name, arr in blobs:
            arrays.append((name, arr.dtype.str, len(arr), offset))
            offset = _aligned(offset + arr.nbytes)
        header = pickle.dumps((key, type(table), plain, arrays), protocol=pickle.HIGHEST_PROTOCOL)
    start = arrays[0][3] if arrays else len(MAGIC) + 8 + len(header)
    if len(MAGIC) + 8 + len(header) > start:
        return
    try:
        with atomic_target(path, durable=False, prefix=".table-", suffix=".bin") as tmp, open(tmp, "wb") as fh:
            fh.write(MAGIC + len(header).to_bytes(8, "little") + header)
            for (_, arr), (_, _, _, at) in zip(blobs, arrays, strict=True):
                fh.write(b"\0" * (at - fh.tell()))
                fh.write(arr.tobytes())
        _prune(path.parent)
    except OSError:
        pass


KEEP = 8
"""Stored tables kept: the newest; older ones (another catalog state or query) are removed."""


def _prune(folder: Path) -> None:
    stored = sorted(folder.glob("table-*.bin"), key=lambda p: p.stat().st_mtime_ns, reverse=True)
    for old in stored[KEEP:]:
        old.unlink(missing_ok=True)


def _aligned(n: int) -> int:
    return -(-n // _ALIGN) * _ALIGN
