"""Projects of the web app in SQLite: one row per project, every save kept as a version.

The database is ``projects.sqlite`` in the user's data folder (``$DRIVETRAIN_DATA_DIR``, a
``--data-dir`` override, else ``~/.local/share/drivetrain``). It runs in WAL mode with
``synchronous=FULL``: each save is one ``BEGIN IMMEDIATE ... COMMIT`` transaction and is on
disk when the call returns, so a crash or a kill loses nothing that was acknowledged, and a
save cut short leaves no trace. Versions are never rewritten; undo restores an earlier version
as a new save, so the history only grows.

A project stores the axis as YAML text (the user's own units and layout); whether that text is
a valid axis is the sizing's business, so a draft can be saved while it still has errors. Its
``kind`` is ``axis`` (an axis file) or ``machine`` (a machine file, docs/machine.md, whose axes
are inline or name saved axis projects); both keep the same history. A database written before
kinds existed (schema 1) gains the column in place, every project in it an axis.
"""

from __future__ import annotations

import contextlib
import math
import sqlite3
import time
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

DB_NAME = "projects.sqlite"
ENV_DATA_DIR = "DRIVETRAIN_DATA_DIR"
SCHEMA_VERSION = 2
KINDS = ("axis", "machine")
"""What a project holds: an axis file or a machine file."""
MAX_NAME = 200
"""Longest project name [characters]."""
MAX_TEXT_BYTES = 1_000_000
"""Largest axis text stored per version [bytes] (the axis-file limit)."""

_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
    """CREATE TABLE IF NOT EXISTS projects (
        id INTEGER PRIMARY KEY AUTOINCREMENT,
        name TEXT NOT NULL,
        created REAL NOT NULL,
        updated REAL NOT NULL,
        head INTEGER NOT NULL,
        kind TEXT NOT NULL DEFAULT 'axis'
    )""",
    """CREATE TABLE IF NOT EXISTS versions (
        project_id INTEGER NOT NULL REFERENCES projects(id) ON DELETE CASCADE,
        version INTEGER NOT NULL,
        created REAL NOT NULL,
        text TEXT NOT NULL,
        restored_from INTEGER,
        note TEXT NOT NULL DEFAULT '',
        PRIMARY KEY (project_id, version)
    )""",
)


class StoreError(Exception):
    """A request the store cannot satisfy; ``status`` is the HTTP status the API answers with."""

    status = 400

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.field = field


class NotFound(StoreError):
    """No such project or version."""

    status = 404


class Conflict(StoreError):
    """The request contradicts the stored state (stale base version, nothing to undo)."""

    status = 409


def default_data_dir() -> Path:
    """The same folder as the catalog's: ``$DRIVETRAIN_DATA_DIR``, else the platform's user data folder."""
    from drivetrain.catalog.db import data_dir

    return data_dir()


@dataclass(frozen=True)
class ProjectInfo:
    """A project without its text: id, name, times [s since the epoch], current version."""

    id: int
    name: str
    created: float
    updated: float
    version: int
    kind: str = "axis"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class Version:
    """One saved version of a project; ``restored_from`` is set when it restored an earlier one."""

    project_id: int
    version: int
    created: float
    text: str
    restored_from: int | None
    note: str

    def info(self) -> dict[str, Any]:
        """The version without its text."""
        return {"version": self.version, "created": self.created, "restored_from": self.restored_from,
                "note": self.note, "bytes": len(self.text.encode("utf-8"))}


def clean_name(name: Any) -> str:
    """A project name: 1 to 200 printable characters, surrounding blanks removed."""
    if not isinstance(name, str):
        raise StoreError("must be text", "name")
    text = " ".join(name.split())
    if not text:
        raise StoreError("must not be empty", "name")
    if len(text) > MAX_NAME:
        raise StoreError(f"must be at most {MAX_NAME} characters, got {len(text)}", "name")
    if any(not ch.isprintable() for ch in text):
        raise StoreError("must contain printable characters only", "name")
    return text


def check_kind(kind: Any) -> str:
    """A project kind: axis or machine."""
    if kind not in KINDS:
        raise StoreError(f"must be one of {', '.join(KINDS)}, got {kind!r}"[:200], "kind")
    return str(kind)


def _check_text(text: Any) -> str:
    if not isinstance(text, str):
        raise StoreError("must be text", "yaml")
    if len(text.encode("utf-8", "replace")) > MAX_TEXT_BYTES:
        raise StoreError(f"is too large (at most {MAX_TEXT_BYTES} bytes)", "yaml")
    if "\x00" in text:
        raise StoreError("must not contain NUL characters", "yaml")
    return text


class Store:
    """The project database in ``directory`` (created on first use)."""

    def __init__(self, directory: Path | None = None) -> None:
        self.directory = (directory or default_data_dir()).expanduser().resolve()
        self.path = self.directory / DB_NAME
        self._ready = False

    # ------------------------------------------------------------------ connections

    @contextlib.contextmanager
    def _connect(self) -> Iterator[sqlite3.Connection]:
        if not self._ready:
            self._create()
        conn = sqlite3.connect(self.path, isolation_level=None, timeout=30.0)
        try:
            conn.execute("PRAGMA synchronous = FULL")
            conn.execute("PRAGMA foreign_keys = ON")
            conn.execute("PRAGMA busy_timeout = 30000")
            yield conn
        finally:
            conn.close()

    @contextlib.contextmanager
    def _write(self) -> Iterator[sqlite3.Connection]:
        """One write transaction: committed (durably) when the block ends, rolled back on error."""
        from drivetrain.catalog.db import immediate_transaction

        with self._connect() as conn, immediate_transaction(conn):
            yield conn

    def _create(self) -> None:
        self.directory.mkdir(parents=True, exist_ok=True)
        conn = sqlite3.connect(self.path, isolation_level=None, timeout=30.0)
        try:
            mode = conn.execute("PRAGMA journal_mode = WAL").fetchone()[0]
            if str(mode).lower() != "wal":
                raise OSError(f"cannot switch {self.path} to WAL mode (got {mode})")
            conn.execute("PRAGMA synchronous = FULL")
            conn.execute("BEGIN IMMEDIATE")
            try:
                for statement in _SCHEMA:
                    conn.execute(statement)
                conn.execute("INSERT OR IGNORE INTO meta VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))
                conn.execute("COMMIT")
            except BaseException:
                conn.execute("ROLLBACK")
                raise
            found = conn.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()[0]
            if found == "1":
                found = self._upgrade_from_1(conn)
            if found != str(SCHEMA_VERSION):
                raise OSError(f"{self.path} has schema version {found}; this drivetrain reads {SCHEMA_VERSION}")
        finally:
            conn.close()
        self._ready = True

    @staticmethod
    def _upgrade_from_1(conn: sqlite3.Connection) -> str:
        """Schema 1 to 2: the ``kind`` column (every earlier project is an axis), in one transaction."""
        conn.execute("BEGIN IMMEDIATE")
        try:
            columns = {r[1] for r in conn.execute("PRAGMA table_info(projects)")}
            if "kind" not in columns:
                conn.execute("ALTER TABLE projects ADD COLUMN kind TEXT NOT NULL DEFAULT 'axis'")
            conn.execute("UPDATE meta SET value = '2' WHERE key = 'schema_version'")
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            raise
        return "2"

    # ------------------------------------------------------------------ reading

    def projects(self, kind: str | None = None) -> list[ProjectInfo]:
        """Every project (of ``kind``, if given), most recently saved first."""
        if kind is not None:
            check_kind(kind)
        with self._connect() as conn:
            rows = conn.execute("SELECT id, name, created, updated, head, kind FROM projects "
                                "WHERE ? IS NULL OR kind = ? ORDER BY updated DESC, id DESC", (kind, kind)).fetchall()
        return [ProjectInfo(*r) for r in rows]

    def info(self, project_id: int) -> ProjectInfo:
        """One project's name, times and current version."""
        with self._connect() as conn:
            return self._info(conn, project_id)

    def head(self, project_id: int) -> tuple[ProjectInfo, Version]:
        """A project and its current version, read in one transaction."""
        with self._connect() as conn:
            conn.execute("BEGIN")
            try:
                info = self._info(conn, project_id)
                return info, self._version(conn, project_id, info.version)
            finally:
                conn.execute("COMMIT")

    def versions(self, project_id: int) -> list[Version]:
        """Every saved version of a project, newest first."""
        with self._connect() as conn:
            self._info(conn, project_id)
            rows = conn.execute("SELECT project_id, version, created, text, restored_from, note FROM versions "
                                "WHERE project_id = ? ORDER BY version DESC", (project_id,)).fetchall()
        return [Version(*r) for r in rows]

    def version(self, project_id: int, version: int) -> Version:
        """One saved version."""
        with self._connect() as conn:
            self._info(conn, project_id)
            return self._version(conn, project_id, version)

    # ------------------------------------------------------------------ writing

    def create(self, name: str, text: str, note: str = "created", kind: str = "axis") -> ProjectInfo:
        """A new project of ``kind`` (axis or machine) whose version 1 is ``text``."""
        name, text, kind = clean_name(name), _check_text(text), check_kind(kind)
        now = time.time()
        with self._write() as conn:
            cur = conn.execute("INSERT INTO projects (name, created, updated, head, kind) VALUES (?, ?, ?, 1, ?)",
                               (name, now, now, kind))
            pid = int(cur.lastrowid or 0)
            conn.execute("INSERT INTO versions VALUES (?, 1, ?, ?, NULL, ?)", (pid, now, text, note))
        return ProjectInfo(pid, name, now, now, 1, kind)

    def save(self, project_id: int, text: str, base_version: int | None = None, note: str = "") -> ProjectInfo:
        """Save ``text`` as the project's next version, in one transaction.

        ``base_version`` is the version the editor started from: if another save came in
        between, the save is refused (Conflict) rather than silently overwriting it. Saving the
        text the project already holds adds no version.
        """
        text = _check_text(text)
        with self._write() as conn:
            info = self._info(conn, project_id)
            if base_version is not None and base_version != info.version:
                raise Conflict(f"the project was saved elsewhere (now version {info.version}, "
                               f"this edit started from version {base_version}); reload it first",
                               "base_version")
            current = self._version(conn, project_id, info.version)
            if current.text == text:
                return info
            return self._append(conn, info, text, None, note)

    def rename(self, project_id: int, name: str) -> ProjectInfo:
        """Give a project a new name (the history is unchanged)."""
        name = clean_name(name)
        now = time.time()
        with self._write() as conn:
            info = self._info(conn, project_id)
            conn.execute("UPDATE projects SET name = ?, updated = ? WHERE id = ?", (name, now, project_id))
        return ProjectInfo(info.id, name, info.created, now, info.version, info.kind)

    def duplicate(self, project_id: int, name: str | None = None) -> ProjectInfo:
        """A new project starting from this one's current version."""
        info, head = self.head(project_id)
        new_name = clean_name(name) if name is not None else clean_name(f"{info.name} (copy)"[:MAX_NAME])
        return self.create(new_name, head.text, note=f"duplicated from project {info.id} version {info.version}",
                           kind=info.kind)

    def delete(self, project_id: int) -> None:
        """Delete a project with its whole history."""
        with self._write() as conn:
            self._info(conn, project_id)
            conn.execute("DELETE FROM versions WHERE project_id = ?", (project_id,))
            conn.execute("DELETE FROM projects WHERE id = ?", (project_id,))

    def restore(self, project_id: int, version: int) -> ProjectInfo:
        """Save an earlier version's text again as the newest version."""
        with self._write() as conn:
            info = self._info(conn, project_id)
            old = self._version(conn, project_id, version)
            return self._append(conn, info, old.text, version, f"restored version {version}")

    def undo(self, project_id: int) -> ProjectInfo:
        """Undo the last save: restore the version before it as a new save.

        Repeated undos walk further back: after restoring version k, the next undo restores k - 1.
        """
        with self._write() as conn:
            info = self._info(conn, project_id)
            head = self._version(conn, project_id, info.version)
            target = (head.restored_from if head.restored_from is not None else head.version) - 1
            if target < 1:
                raise Conflict("nothing to undo: this is the project's first version", "version")
            old = self._version(conn, project_id, target)
            return self._append(conn, info, old.text, target, f"undo: restored version {target}")

    # ------------------------------------------------------------------ helpers

    @staticmethod
    def _info(conn: sqlite3.Connection, project_id: int) -> ProjectInfo:
        row = conn.execute("SELECT id, name, created, updated, head, kind FROM projects WHERE id = ?",
                           (project_id,)).fetchone()
        if row is None:
            raise NotFound(f"no project with id {project_id}", "project_id")
        return ProjectInfo(*row)

    @staticmethod
    def _version(conn: sqlite3.Connection, project_id: int, version: int) -> Version:
        row = conn.execute("SELECT project_id, version, created, text, restored_from, note FROM versions "
                           "WHERE project_id = ? AND version = ?", (project_id, version)).fetchone()
        if row is None:
            raise NotFound(f"project {project_id} has no version {version}", "version")
        return Version(*row)

    @staticmethod
    def _append(conn: sqlite3.Connection, info: ProjectInfo, text: str, restored_from: int | None,
                note: str) -> ProjectInfo:
        now = max(time.time(), math.nextafter(info.updated, math.inf))
        version = info.version + 1
        conn.execute("INSERT INTO versions VALUES (?, ?, ?, ?, ?, ?)",
                     (info.id, version, now, text, restored_from, note))
        conn.execute("UPDATE projects SET head = ?, updated = ? WHERE id = ?", (version, now, info.id))
        return ProjectInfo(info.id, info.name, info.created, now, version, info.kind)

    def integrity(self) -> str:
        """``PRAGMA integrity_check``: 'ok' for a consistent database."""
        with self._connect() as conn:
            return str(conn.execute("PRAGMA integrity_check").fetchone()[0])
