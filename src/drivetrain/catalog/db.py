"""The embedded SQLite catalog: a shipped database built from package data, and a user database.

Two files live in the data folder (``DRIVETRAIN_DATA_DIR``, else the platform's user data
folder, e.g. ``~/.local/share/drivetrain``):

* ``catalog.sqlite`` is built on first use from the CSV files shipped in
  ``drivetrain/catalog/data`` and rebuilt whenever their version or content changes. It is
  written to a temporary file and moved into place, so a reader never sees half of it, and it is
  only ever opened read-only.
* ``user.sqlite`` holds the user's imports. Every import is one transaction. A team can share one
  user catalog anywhere: ``$DRIVETRAIN_CATALOG`` (or ``drivetrain --catalog FILE.sqlite``) names
  it; the shipped data is still read beside it.

Queries see the union of both; each row carries ``origin`` = ``"builtin"`` or ``"user"``.
"""

from __future__ import annotations

import contextlib
import hashlib
import operator
import os
import re
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from drivetrain.catalog.derive import complete_row
from drivetrain.catalog.freshness import RULE_MODULES, files_signature, remember_files
from drivetrain.catalog.schema import (
    BRAKES_FILE,
    CURVE,
    DATA_VERSION,
    ELECTRICAL_FILE,
    GEARBOX,
    HISTORY_COLUMNS,
    MOTOR,
    MOTOR_DOCUMENTS_FILE,
    PAIRING_FILE,
    REJECTS_FILE,
    ROW_TABLES,
    SCHEMA_VERSION,
    SHIPPED_FILES,
    ShippedFile,
    TableSpec,
    ddl,
    sql_type,
)
from drivetrain.catalog.side_tables import merge_brake, merge_electrical, motor_brakes, motor_documents, shipped_text
from drivetrain.errors import InputError, InputErrors, write_failure
from drivetrain.files import atomic_target

if TYPE_CHECKING:
    import sqlite3

    from drivetrain.catalog.records import Row

BUILTIN_NAME = "catalog.sqlite"
USER_NAME = "user.sqlite"
ENV_DATA_DIR = "DRIVETRAIN_DATA_DIR"
ENV_CATALOG = "DRIVETRAIN_CATALOG"
_STALE_TEMP_S = 3600.0  # a build temp file this old was left by a killed process

_verified: set[Path] = set()  # shipped databases checked up to date in this process


# ---------------------------------------------------------------------------------- places


def data_dir() -> Path:
    """The folder holding both databases: $DRIVETRAIN_DATA_DIR, else the platform's user data folder."""
    env = os.environ.get(ENV_DATA_DIR)
    if env:
        return _resolved(Path(env).expanduser())
    home = Path.home()
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = home / "Library" / "Application Support"
    else:
        base = Path(os.environ.get("XDG_DATA_HOME") or home / ".local" / "share")
    return _resolved(base / "drivetrain")


_RESOLVED: dict[Path, Path] = {}


def _resolved(path: Path) -> Path:
    """``path.resolve()``, once per path in a process: every catalog query asks for the data folder (a
    sizing makes about 50), and resolving reads each component's link status from the file system."""
    hit = _RESOLVED.get(path)
    if hit is None:
        if len(_RESOLVED) > 64:
            _RESOLVED.clear()
        hit = _RESOLVED[path] = path.resolve()
    return hit


def user_db_path(directory: Path | None = None) -> Path:
    """The user catalog: ``$DRIVETRAIN_CATALOG`` when set (a shared file), else user.sqlite in the data folder."""
    env = os.environ.get(ENV_CATALOG)
    if env:
        path = Path(env).expanduser().resolve()
        if path.is_dir():
            raise InputError(ENV_CATALOG, "must name a catalog file (e.g. team.sqlite), not a folder", env)
        return path
    return (directory or data_dir()) / USER_NAME


def build_stamp() -> str:
    """Identifies the shipped data: DATA_VERSION, schema version and a hash of the files."""
    digest = hashlib.sha256()
    for name in [f.filename for f in SHIPPED_FILES] + [REJECTS_FILE, ELECTRICAL_FILE, PAIRING_FILE,
                                                         MOTOR_DOCUMENTS_FILE, BRAKES_FILE]:
        digest.update(name.encode())
        digest.update(shipped_text(name).encode())
    from importlib import resources  # only at a build check: its import brings tempfile and shutil

    for module in RULE_MODULES:  # the derived values and voltage classes are computed at the build
        digest.update(module.encode() + resources.files("drivetrain.catalog").joinpath(module).read_bytes())
    return f"{DATA_VERSION}/schema-{SCHEMA_VERSION}/{digest.hexdigest()[:16]}"


# ---------------------------------------------------------------------------------- shipped database


def builtin_db(directory: Path | None = None) -> Path:
    """Path of the shipped database in ``directory``, built or rebuilt first if it is missing or stale."""
    path = (directory or data_dir()) / BUILTIN_NAME
    if path in _verified and path.exists():
        return path
    files = files_signature(f"{DATA_VERSION}/schema-{SCHEMA_VERSION}")
    if files is not None and _meta_of(path, "files") == files:  # the same files as at the build: no hashing
        _verified.add(path)
        return path
    stamp = build_stamp()
    if _meta_of(path, "stamp") == stamp and files is not None:
        remember_files(path, files)  # same content, touched files (a checkout): compare sizes and times next time
    if _meta_of(path, "stamp") != stamp:
        try:
            _build(path, stamp, files)
        except OSError as exc:
            if _meta_of(path, "stamp") != stamp:  # not built meanwhile by another process either
                raise InputError(
                    ENV_DATA_DIR,
                    f"cannot write the catalog database in {path.parent} ({exc.strerror or exc}); "
                    f"set {ENV_DATA_DIR} to a writable folder",
                    str(path.parent),
                ) from None
    _verified.add(path)
    return path


def _meta_of(path: Path, key: str) -> str | None:
    import sqlite3

    if not path.exists():
        return None
    try:
        conn = sqlite3.connect(_ro_uri(path), uri=True)
        try:
            row = conn.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()
        finally:
            conn.close()
    except sqlite3.Error:
        return None  # unreadable or foreign file: rebuild it
    return str(row[0]) if row else None


def _build(path: Path, stamp: str, files: str | None = None) -> None:
    """Write the shipped database to a temporary file, then move it into place atomically."""
    import sqlite3

    path.parent.mkdir(parents=True, exist_ok=True)
    _remove_stale_temps(path.parent)
    with atomic_target(path, durable=False, prefix=".catalog-", suffix=".tmp") as tmp:
        conn = sqlite3.connect(tmp, isolation_level=None)
        try:
            conn.execute("BEGIN")
            for statement in ddl():
                conn.execute(statement)
            for shipped, rows in shipped_rows():
                insert_rows(conn, "main", shipped.table, rows)
            conn.executemany("INSERT INTO rejects VALUES (?, ?, ?, ?, ?, ?)", _rejects())
            conn.executemany("INSERT INTO drive_pairs VALUES (?, ?, ?, ?, ?)", _pairs())
            conn.executemany(
                "INSERT INTO meta VALUES (?, ?)",
                [
                    ("stamp", stamp),
                    ("data_version", DATA_VERSION),
                    ("schema_version", str(SCHEMA_VERSION)),
                    ("origin", "builtin"),
                    *([("files", files)] if files is not None else []),
                ],
            )
            conn.execute("COMMIT")
        finally:
            conn.close()


def _remove_stale_temps(directory: Path) -> None:
    for tmp in directory.glob(".catalog-*.tmp"):
        with contextlib.suppress(OSError):
            if time.time() - tmp.stat().st_mtime > _STALE_TEMP_S:
                tmp.unlink()


def shipped_rows() -> Iterator[tuple[ShippedFile, list[Row]]]:
    """Every shipped file converted and validated; a problem is a packaging bug, so it raises."""
    from drivetrain.catalog.reading import read_csv
    from drivetrain.catalog.records import parse_rows

    documents = motor_documents()
    brakes = motor_brakes()
    for shipped in SHIPPED_FILES:
        raw = read_csv(shipped_text(shipped.filename), shipped.filename)
        parsed = parse_rows(
            raw, shipped.table, kind=shipped.kind, constants=dict(shipped.constants), derived=shipped.derived
        )
        if parsed.errors:
            raise RuntimeError(f"shipped catalog data is invalid:\n{InputErrors(parsed.errors)}")
        for row in parsed.rows:
            if shipped.table is MOTOR and row.id in documents:
                for name, value in documents.pop(row.id).items():
                    row.values[name] = value
            if shipped.unverified and row.values.get("verified") != 1:
                row.values["verified"] = 0
                row.values.setdefault("unverified_reason", _reason_of(row.values, shipped.unverified))
            m = re.match(shipped.model_pattern, row.id or "") if shipped.model_pattern else None
            if m is not None:
                row.values["model"] = m.group(1)
            if shipped.table is MOTOR and shipped.kind == "ac_servo":
                merge_electrical(row.values)
            if shipped.table is MOTOR and row.id in brakes:
                merge_brake(row.values, brakes.pop(row.id))
            complete_row(shipped.table.name, row.values)  # implied values and voltage class (catalog.derive)
            if shipped.table is GEARBOX and shipped.kind == "servo_gearbox":
                # right-angle series end in R (GPBR, GPDR, GPVR, GPER; data/SOURCES.md)
                row.values["right_angle"] = int(str(row.values.get("series", "")).endswith("R"))
        yield shipped, parsed.rows
    if documents:
        raise RuntimeError(f"{MOTOR_DOCUMENTS_FILE} names motors that are not shipped: {', '.join(documents)}")
    if brakes:
        raise RuntimeError(f"{BRAKES_FILE} names motors that are not shipped: {', '.join(brakes)}")


def _reason_of(values: dict[str, Any], default: str) -> str:
    """Why a shipped row is unverified: the notes' own "not verified: ..." clause, else the file's reason."""
    notes = str(values.get("notes") or "")
    m = re.search(r"not verified: ([^;]*(?:;[^;]*)*)$", notes)
    return m.group(1).strip() if m else default


def _pairs() -> Iterator[tuple[str, ...]]:
    import csv
    import io

    for r in csv.DictReader(io.StringIO(shipped_text(PAIRING_FILE))):
        yield r["motor_id"], r["drive_id"], r["source"], r["source_url"], r["verified"]


def _rejects() -> Iterator[tuple[str, ...]]:
    import csv
    import io

    for r in csv.DictReader(io.StringIO(shipped_text(REJECTS_FILE))):
        yield r["target_file"], r["id"], r["vendor"], r["reason"], r["source"], r["source_values"]


# ---------------------------------------------------------------------------------- writing


def insert_rows(conn: sqlite3.Connection, schema: str, spec: TableSpec, rows: Sequence[Row]) -> int:
    """Insert converted rows (and motors' curve points) into ``schema``; the caller owns the transaction."""
    columns = [f.column for f in spec.fields]
    sql = f"INSERT INTO {schema}.{spec.sql} ({', '.join(columns)}) VALUES ({', '.join('?' * len(columns))})"
    conn.executemany(sql, _values(spec, rows))
    points = [p for r in rows for p in r.curve]
    if points:
        insert_rows(conn, schema, CURVE, points)
    return len(rows)


def _values(spec: TableSpec, rows: Sequence[Row]) -> Iterator[tuple[Any, ...]]:
    for row in rows:
        yield tuple(row.values.get(f.name) for f in spec.fields)


@contextlib.contextmanager
def user_writer(directory: Path | None = None) -> Iterator[sqlite3.Connection]:
    """A connection in one write transaction on the user database (created if absent).

    The transaction commits when the block ends normally and rolls back on any exception; a
    killed process leaves a journal that SQLite rolls back on the next open, so the file is never
    half-written.
    """
    import sqlite3

    directory = directory or data_dir()
    builtin_db(directory)  # creates the folder, and the user rows' ids were checked against it
    path = user_db_path(directory)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        conn = sqlite3.connect(path, isolation_level=None, timeout=30.0)
    except (OSError, sqlite3.Error) as exc:
        raise InputError("catalog", f"cannot open the user catalog ({exc})", str(path)) from None
    try:
        conn.execute("PRAGMA synchronous = FULL")
        try:
            _ensure_user_schema(conn)
        except sqlite3.OperationalError as exc:
            raise write_failure("catalog", exc, path, "the catalog") from None
        except sqlite3.DatabaseError as exc:
            raise InputError("catalog", f"is not a drivetrain catalog database ({exc})", str(path)) from None
        try:
            with immediate_transaction(conn):
                yield conn
        except sqlite3.OperationalError as exc:  # read-only file or folder, full disk, I/O error: nothing written
            raise write_failure("catalog", exc, path, "the catalog") from None
    finally:
        conn.close()


def _rollback(conn: sqlite3.Connection) -> None:
    """Roll back unless SQLite did (a full disk); a failing rollback must not hide the first error."""
    import sqlite3

    if conn.in_transaction:
        with contextlib.suppress(sqlite3.Error):
            conn.execute("ROLLBACK")


@contextlib.contextmanager
def immediate_transaction(conn: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """One write transaction on an autocommit connection: all of it is committed (or rolled back), or none."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        yield conn
        conn.execute("COMMIT")
    except BaseException:
        _rollback(conn)
        raise


def _ensure_user_schema(conn: sqlite3.Connection) -> None:
    with immediate_transaction(conn):
        has_meta = conn.execute("SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'meta'").fetchone()
        if not has_meta:
            for statement in ddl():
                conn.execute(statement)
            conn.executemany(
                "INSERT INTO meta VALUES (?, ?)",
                [("schema_version", str(SCHEMA_VERSION)), ("origin", "user")],
            )
    _check_user_version(conn, "main")


_UPGRADABLE = ("1", "2", "3", "4")
"""User database versions brought up to SCHEMA_VERSION in place: they lack only columns and tables added
since (version 2 added the gearbox fields source document, bore range, flange, pilot, verified; version 3
the drives' regen fields, the motors' electrical columns, the motor and drive documents, the unverified
reasons, the motor field-group sources and the history; version 4 the drives' motor series; version 5 the
motors' brake-variant fields, the drives' ratings source and the derivations of computed values)."""


def _upgrade_user(conn: sqlite3.Connection, schema: str) -> None:
    """Add the columns a user database of an older, compatible version lacks (one transaction)."""
    row = conn.execute(f"SELECT value FROM {schema}.meta WHERE key = 'schema_version'").fetchone()
    if row is None or row[0] not in _UPGRADABLE:
        return
    with immediate_transaction(conn):
        for spec in ROW_TABLES:
            have = {r[1] for r in conn.execute(f"PRAGMA {schema}.table_info({spec.sql})")}
            for f in spec.fields:
                if f.column not in have:
                    conn.execute(f"ALTER TABLE {schema}.{spec.sql} ADD COLUMN {f.column} {sql_type(f)}")
        has_history = conn.execute(
            f"SELECT 1 FROM {schema}.sqlite_master WHERE type = 'table' AND name = 'history'"
        ).fetchone()
        if not has_history:
            conn.execute(f"CREATE TABLE {schema}.history ({', '.join(c + ' TEXT' for c in HISTORY_COLUMNS)})")
        conn.execute(
            f"UPDATE {schema}.meta SET value = ? WHERE key = 'schema_version'", (str(SCHEMA_VERSION),)
        )


def _check_user_version(conn: sqlite3.Connection, schema: str) -> None:
    _upgrade_user(conn, schema)
    row = conn.execute(f"SELECT value FROM {schema}.meta WHERE key = 'schema_version'").fetchone()
    if row is None or row[0] != str(SCHEMA_VERSION):
        found = row[0] if row else "none"
        raise InputError(
            "catalog",
            f"the user catalog has schema version {found}, this drivetrain reads "
            f"version {SCHEMA_VERSION}; export it with the drivetrain that wrote it and "
            "re-import",
            str(user_path_of(conn, schema)),
        )


def user_path_of(conn: sqlite3.Connection, schema: str) -> str:
    return next((str(r[2]) for r in conn.execute("PRAGMA database_list") if r[1] == schema), "")


# ---------------------------------------------------------------------------------- reading


@contextlib.contextmanager
def reader(directory: Path | None = None) -> Iterator[Reader]:
    """A read connection seeing the shipped database (``builtin``) and, if it exists, the user one."""
    import sqlite3

    directory = directory or data_dir()
    builtin = builtin_db(directory)
    conn = sqlite3.connect(":memory:", uri=True, timeout=30.0)
    try:
        conn.execute("ATTACH DATABASE ? AS builtin", (_ro_uri(builtin),))
        user = user_db_path(directory)
        has_user = user.exists()
        if has_user:
            try:
                # read-write on purpose: a journal left by a killed import is rolled back on open
                conn.execute("ATTACH DATABASE ? AS user", (str(user),))
                has_user = bool(
                    conn.execute(
                        "SELECT 1 FROM user.sqlite_master WHERE type = 'table' AND name = 'meta'"
                    ).fetchone()
                )
            except sqlite3.DatabaseError as exc:
                raise InputError("catalog", f"is not a drivetrain catalog database ({exc})", str(user)) from None
            if has_user:
                _check_user_version(conn, "user")
        yield Reader(conn, has_user)
    finally:
        conn.close()


class Reader:
    """Queries over the union of the shipped and user databases."""

    def __init__(self, conn: sqlite3.Connection, has_user: bool) -> None:
        self.conn = conn
        self.has_user = has_user

    def _union(self, table: str, columns: str) -> str:
        parts = [f"SELECT {columns}, 'builtin' AS origin, 0 AS _db, rowid AS _rowid FROM builtin.{table}"]
        if self.has_user:
            parts.append(f"SELECT {columns}, 'user' AS origin, 1 AS _db, rowid AS _rowid FROM user.{table}")
        return " UNION ALL ".join(parts)

    def rows(self, spec: TableSpec, where: str = "", params: Sequence[Any] = ()) -> list[dict[str, Any]]:
        """Rows of ``spec`` as dicts keyed by column (plus ``origin``), shipped rows first, in file order."""
        columns = [f.column for f in spec.fields]
        if not where:
            # Each database in its file (rowid) order, one after the other: the rows and order of the
            # sorted union below, without SQLite sorting every row of the union (about 3x faster).
            out: list[dict[str, Any]] = []
            for schema in ("builtin", "user") if self.has_user else ("builtin",):
                cursor = self.conn.execute(
                    f"SELECT {', '.join(columns)}, '{schema}' AS origin FROM {schema}.{spec.sql} ORDER BY rowid")
                names = [d[0] for d in cursor.description]
                out += [dict(zip(names, r, strict=True)) for r in cursor]
            return out
        sql = f"SELECT * FROM ({self._union(spec.sql, ', '.join(columns))})"
        sql += f" WHERE {where}"
        sql += " ORDER BY _db, _rowid"
        cursor = self.conn.execute(sql, tuple(params))
        names = [d[0] for d in cursor.description]
        keep = [i for i, k in enumerate(names) if not k.startswith("_")]  # id and at least one more
        kept, pick = [names[i] for i in keep], operator.itemgetter(*keep)
        return [dict(zip(kept, pick(r), strict=True)) for r in cursor]

    def ids(self) -> dict[str, tuple[str, str]]:
        """Every row id -> (table name, origin)."""
        found: dict[str, tuple[str, str]] = {}
        for spec in ROW_TABLES:
            for rid, origin in self.conn.execute(f"SELECT id, origin FROM ({self._union(spec.sql, 'id')})"):
                found[rid] = (spec.name, origin)
        return found

    def curves(
        self, motor_ids: Sequence[str] | None = None
    ) -> dict[str, list[tuple[float, float | None, float | None]]]:
        """Speed-torque points per motor id: (speed [rad/s], continuous [N m], peak [N m]), by speed."""
        cols = "motor_id, speed_rad_s, continuous_torque_Nm, peak_torque_Nm"
        sql = f"SELECT {cols} FROM ({self._union(CURVE.sql, cols)}) ORDER BY motor_id, speed_rad_s"
        wanted = None if motor_ids is None else set(motor_ids)
        out: dict[str, list[tuple[float, float | None, float | None]]] = {}
        for mid, speed, cont, peak in self.conn.execute(sql):
            if wanted is None or mid in wanted:
                out.setdefault(mid, []).append((speed, cont, peak))
        return out

    def drive_pairs(self) -> dict[str, list[str]]:
        """The shipped motor-drive pairing table: motor id -> drive ids (data/drives_pairing.csv)."""
        out: dict[str, list[str]] = {}
        for mid, did in self.conn.execute("SELECT motor_id, drive_id FROM builtin.drive_pairs ORDER BY rowid"):
            out.setdefault(mid, []).append(did)
        return out

    def drive_pair_sources(self) -> dict[tuple[str, str], dict[str, Any]]:
        """Each shipped pairing's provenance: (motor id, drive id) -> source, source_url and verified
        (False where the pairing is a third-party transcription, data/drives_pairing.csv)."""
        sql = "SELECT motor_id, drive_id, source, source_url, verified FROM builtin.drive_pairs ORDER BY rowid"
        return {(m, d): {"source": s, "source_url": u, "verified": v == "yes"}
                for m, d, s, u, v in self.conn.execute(sql)}

    def curve_sources(self, motor_id: str) -> list[str]:
        """The ``source`` of each curve point of one motor, by speed (as :meth:`curves` orders them)."""
        cols = "motor_id, speed_rad_s, source"
        sql = f"SELECT source FROM ({self._union(CURVE.sql, cols)}) WHERE motor_id = ? ORDER BY speed_rad_s"
        return [str(r[0] or "") for r in self.conn.execute(sql, (motor_id,))]

    def rejected(self, rid: str) -> dict[str, str] | None:
        """The shipped data's reject record for ``rid`` (a row left out, with the reason), if any."""
        cursor = self.conn.execute("SELECT * FROM builtin.rejects WHERE id = ?", (rid,))
        row = cursor.fetchone()
        return None if row is None else dict(zip([d[0] for d in cursor.description], row, strict=True))

    def history(self, rid: str | None = None) -> list[dict[str, Any]]:
        """The user catalog's change log (oldest first), of one id or of all; empty without a user catalog."""
        if not self.has_user:
            return []
        sql = f"SELECT {', '.join(HISTORY_COLUMNS)} FROM user.history"
        params: tuple[Any, ...] = ()
        if rid is not None:
            sql += " WHERE id = ?"
            params = (rid,)
        cursor = self.conn.execute(sql + " ORDER BY rowid", params)
        return [dict(zip(HISTORY_COLUMNS, r, strict=True)) for r in cursor]

    def count(self, spec: TableSpec, origin: str | None = None) -> int:
        dbs = [d for d in ("builtin", "user") if origin in (None, d) and (d == "builtin" or self.has_user)]
        return sum(int(self.conn.execute(f"SELECT count(*) FROM {d}.{spec.sql}").fetchone()[0]) for d in dbs)


def _ro_uri(path: Path) -> str:
    return path.resolve().as_uri() + "?mode=ro"
