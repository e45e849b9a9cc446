"""Whether the shipped catalog database is current, cheaply: the shipped files' sizes and times
against those stored at its build (``db.builtin_db``), so a run does not hash the files' content
(``db.build_stamp``) unless they were touched.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from drivetrain.catalog.schema import (
    BRAKES_FILE,
    ELECTRICAL_FILE,
    MOTOR_DOCUMENTS_FILE,
    PAIRING_FILE,
    REJECTS_FILE,
    SHIPPED_FILES,
)

RULE_MODULES = ("derive.py", "voltage_class.py")
"""Modules whose rules compute values of the shipped rows when the database is built (derive.complete_row)."""


def files_signature(versions: str) -> str | None:
    """Shipped files' names, sizes and times after ``versions`` (the data and schema versions), None if
    not plain files: equal to the one stored at the build, the database is current without hashing
    the files (``db.build_stamp``)."""
    parts = [versions]
    folder = Path(__file__).parent / "data"  # the package's own folder (as importlib.resources finds it
    # for a package installed as files; a zipped one has no folder: None, as resources' non-Path entry)
    for name in [f.filename for f in SHIPPED_FILES] + [REJECTS_FILE, ELECTRICAL_FILE, PAIRING_FILE,
                                                         MOTOR_DOCUMENTS_FILE, BRAKES_FILE]:
        entry = folder / name
        if not entry.is_file():
            return None
        st = entry.stat()
        parts.append(f"{name}:{st.st_size}:{st.st_mtime_ns}")
    for name in RULE_MODULES:
        entry = folder.parent / name
        if not entry.is_file():
            return None
        st = entry.stat()
        parts.append(f"{name}:{st.st_size}:{st.st_mtime_ns}")
    return "|".join(parts)


def remember_files(path: Path, files: str) -> None:
    """Store the files' signature in a current database (best effort: a read-only folder keeps hashing)."""
    import sqlite3

    with contextlib.suppress(sqlite3.Error, OSError):
        conn = sqlite3.connect(path, timeout=5.0)
        with contextlib.closing(conn), conn:
            conn.execute("INSERT OR REPLACE INTO meta VALUES ('files', ?)", (files,))
