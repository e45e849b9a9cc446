"""Import user motors, gearboxes, drives and curve points into the user database; export any table.

An import validates every row first and reports all problems together, each as
``file:line:column`` (an ``InputErrors``); only a clean file is written, in one SQLite
transaction, so an import either lands whole or not at all, even if the process is killed.
The shipped database is never written.

Exports write unit headers in catalogue units (``rated_speed [rpm]``,
``rotor_inertia [kg*cm^2]``) and re-import unchanged; files are written to a temporary name
and moved into place, so an existing file is never left half-written.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from drivetrain.catalog import db
from drivetrain.catalog.columns import HEADER_LINE, display, header, infer_table
from drivetrain.catalog.derive import complete_row
from drivetrain.catalog.reading import escape_cell, read_text
from drivetrain.catalog.records import Parsed, Row, parse_rows
from drivetrain.catalog.schema import CURVE, DATA_VERSION, MOTOR, TABLES, TableSpec
from drivetrain.errors import InputError, InputErrors, listing
from drivetrain.files import write_atomic

FORMATS = ("csv", "json")
MAX_IMPORT_ROWS = 5_000
"""Rows and curve points one import file may hold (the shipped catalog has about 1,600 rows)."""
MAX_USER_ROWS = 10_000
"""Rows and curve points the user catalog holds at most: selection stays well under a second."""
MAX_IMPORT_BYTES = 20_000_000
"""Largest import file [bytes]."""
MAX_IMPORT_COLUMNS = 200
"""Columns (CSV headers, JSON keys) an import file may have: about four times the widest table, so
two columns for one field and unit variants fit; every unknown one is looked up for a suggestion."""


@dataclass(frozen=True)
class ImportReport:
    """What an import wrote: the table, how many rows (and curve points), their ids, the database."""

    path: str
    table: str
    rows: int
    curve_points: int
    ids: tuple[str, ...]
    database: str
    flags: tuple[str, ...] = ()  # what `catalog check` would flag without refusing: a missing voltage class

    def __str__(self) -> str:
        if self.table == "curve":
            return f"imported {self.curve_points} curve point(s) from {self.path} into {self.database}"
        points = f" and {self.curve_points} curve point(s)" if self.curve_points else ""
        text = f"imported {self.rows} {self.table} row(s){points} from {self.path} into {self.database}"
        return "\n".join([text, *(f"flagged: {f}" for f in self.flags)])


# ---------------------------------------------------------------------------------- import


def import_file(
    path: str | os.PathLike[str],
    kind: str | None = None,
    *,
    directory: Path | None = None,
    replace: bool = False,
    source: str | None = None,
) -> ImportReport:
    """Validate ``path`` (CSV or JSON) and add its rows to the user database in one transaction.

    ``kind`` is the table: "motor", "gearbox", "drive" or "curve" (default: from the file's
    ``table`` key or its columns). Raises InputErrors listing every bad cell, missing column and
    duplicate id as ``file:line:column``; nothing is written then.

    ``replace``: rows whose id is already in your catalog are updated (the whole row; a motor's curve
    too when the file gives one; a curve file replaces the user curve of each motor it names), in the
    same transaction as the new rows. Shipped rows are never replaced. ``source``: recorded for rows
    that name none (default "imported from FILE"). Every change is logged (``catalog.history``).
    """
    filename = os.fspath(path)
    text = _read(filename)
    raw = read_text(text, filename)
    if len(raw.headers) > MAX_IMPORT_COLUMNS:
        widest = max(len(t.fields) for t in TABLES.values())
        raise InputError(filename, f"has {len(raw.headers):,} columns ({listing(raw.headers)}); an import file has "
                         f"at most {MAX_IMPORT_COLUMNS} (a table has at most {widest} fields)", has_value=False)
    given = len(raw.rows) + sum(len(r.curve) for r in raw.rows)
    if given > MAX_IMPORT_ROWS:
        raise InputError(filename, f"has {given} rows and curve points; an import takes at most {MAX_IMPORT_ROWS} "
                         "(split the file)", has_value=False)
    spec = _table(kind, raw.table, raw.headers, filename)
    parsed = parse_rows(raw, spec)
    _default_source(parsed.rows, source or f"imported from {Path(filename).name}")
    for row in parsed.rows:
        complete_row(spec.name, row.values)  # the values a row implies and its voltage class, flagged derived
    consistency_errors, flags = _consistency(parsed, filename)
    with db.reader(directory) as rd:
        existing = rd.ids()
        motor_curves = rd.curves() if spec in (MOTOR, CURVE) else {}
        if replace and spec is CURVE:
            replaced_curves = {p.values.get("motor_id") for p in parsed.rows} - {None}
            motor_curves = {m: rd_points for m, rd_points in motor_curves.items() if m not in replaced_curves}
        user_rows = sum(rd.count(t, "user") for t in TABLES.values())
    adding = len(parsed.rows) + sum(len(r.curve) for r in parsed.rows)
    if replace and spec is not CURVE:  # a replaced row takes the place of the one it replaces
        adding -= sum(1 for r in parsed.rows if r.id is not None and existing.get(r.id, ("", ""))[1] == "user")
    if user_rows + adding > MAX_USER_ROWS:
        raise InputError(filename, f"would bring your catalog to {user_rows + adding} rows and curve points; "
                         f"it holds at most {MAX_USER_ROWS} (remove rows you no longer need: catalog remove)",
                         has_value=False)
    errors = parsed.errors + consistency_errors + _cross_row_errors(parsed, filename, existing, motor_curves, replace)
    if errors:
        raise InputErrors(sorted(errors, key=_error_order))
    import sqlite3

    from drivetrain.catalog import manage

    try:
        with db.user_writer(directory) as conn:
            manage.write_import(conn, spec, parsed.rows, replace, filename)
            database = db.user_path_of(conn, "main")
    except sqlite3.IntegrityError as exc:  # another import added the same id since the check above
        raise InputError(
            filename, f"conflicts with rows imported meanwhile ({exc}); nothing was imported", has_value=False
        ) from None
    points = sum(len(r.curve) for r in parsed.rows) + (len(parsed.rows) if spec is CURVE else 0)
    ids = tuple(r.id or "" for r in parsed.rows) if spec is not CURVE else ()
    return ImportReport(filename, spec.name, len(parsed.rows) if spec is not CURVE else 0, points, ids, database,
                        tuple(flags))




def _consistency(parsed: Parsed, filename: str) -> tuple[list[InputError], list[str]]:
    """The consistency rules of ``catalog check`` on each imported row: a rule of IMPORT_CONSISTENCY refuses
    the row (naming the field and the rule), one of IMPORT_FLAGS is listed in the import report."""
    from drivetrain.catalog.check import IMPORT_CONSISTENCY, IMPORT_FLAGS, row_findings

    errors: list[InputError] = []
    flags: list[str] = []
    if parsed.spec is CURVE:
        return errors, flags
    for row in parsed.rows:
        for rule, name, message in row_findings(parsed.spec, row.values):
            if rule in IMPORT_CONSISTENCY and name not in row.bad:
                errors.append(row.error(filename, name, f"breaks the rule {rule} (docs/catalog.md): {message}"))
            elif rule in IMPORT_FLAGS:
                flags.append(f"{row.id}: {name}: rule {rule}: {message}")
    return errors, flags


def _default_source(rows: Sequence[Row], source: str) -> None:
    """A row without a source still has one: the file it came from."""
    for row in rows:
        row.values.setdefault("source", source)
        for point in row.curve:
            point.values.setdefault("source", row.values["source"])


def _read(filename: str) -> str:
    """The import file's text: a regular file of at most MAX_IMPORT_BYTES (``drivetrain.userfile``)."""
    from drivetrain.userfile import read_text as read_user_text

    return read_user_text(filename, "file", MAX_IMPORT_BYTES, "import file", encoding="utf-8-sig")  # Excel's BOM


def _table(kind: str | None, declared: str | None, headers: list[str], filename: str) -> TableSpec:
    name = kind or declared
    if name is not None:
        if name not in TABLES:
            raise InputError("kind", f"must be one of {', '.join(TABLES)}", name)
        return TABLES[name]
    spec = infer_table(headers)
    if spec is None:
        raise InputError(
            "kind",
            f"cannot tell whether {filename} holds motors, gearboxes, drives or curve "
            "points; pass kind (--kind motor|gearbox|drive|curve)",
            has_value=False,
        )
    return spec


def _cross_row_errors(
    parsed: Parsed,
    filename: str,
    existing: dict[str, tuple[str, str]],
    curves: dict[str, list[tuple[float, float | None, float | None]]],
    replace: bool = False,
) -> list[InputError]:
    """Duplicate ids (in the file, against both databases) and curve points' motors and speeds.

    With ``replace`` an id already in the user catalog is not a duplicate (the row is updated); one in
    the shipped catalog still is, and so is one used by another table."""
    errors: list[InputError] = []
    if parsed.spec is CURVE:
        return _curve_errors(parsed.rows, filename, existing, set(), curves)
    replaced: set[str] = set()
    first_line: dict[str, int] = {}
    folded = {k.casefold(): k for k in existing}
    folded_here: dict[str, str] = {}
    for row in parsed.rows:
        rid = row.id
        if rid is None:
            continue
        if rid in first_line:
            errors.append(row.error(filename, "id", f"duplicate id: already used at line {first_line[rid]}"))
        elif rid in existing:
            table, origin = existing[rid]
            if replace and origin == "user" and table == parsed.spec.name:
                replaced.add(rid)
            elif origin == "builtin":
                errors.append(
                    row.error(
                        filename,
                        "id",
                        f"duplicate id: a {table} with this id is already in the shipped catalog, which cannot be "
                        "changed; import your version under another id",
                    )
                )
            else:
                hint = "" if table != parsed.spec.name else " (use --replace to update it)"
                errors.append(
                    row.error(filename, "id", f"duplicate id: a {table} with this id is already in your catalog{hint}")
                )
        elif rid.casefold() in folded:
            other = folded[rid.casefold()]
            place = "the shipped catalog" if existing[other][1] == "builtin" else "your catalog"
            errors.append(row.error(filename, "id", f"differs only by letter case from {other} in {place}"))
        elif rid.casefold() in folded_here:
            errors.append(row.error(filename, "id", f"differs only by letter case from {folded_here[rid.casefold()]} "
                                                    "in this file"))
        first_line.setdefault(rid, row.line)
        folded_here.setdefault(rid.casefold(), rid)
    if parsed.spec is MOTOR:
        points = [p for r in parsed.rows for p in r.curve]
        renewed = {r.id for r in parsed.rows if r.curve and r.id in replaced}
        kept = {m: p for m, p in curves.items() if m not in renewed}
        errors.extend(_curve_errors(points, filename, existing, set(first_line), kept))
    return errors


def _curve_errors(
    points: Sequence[Row],
    filename: str,
    existing: dict[str, tuple[str, str]],
    motors_here: set[str],
    curves: dict[str, list[tuple[float, float | None, float | None]]],
) -> list[InputError]:
    errors: list[InputError] = []
    seen: dict[tuple[str, float], int] = {}
    for p in points:
        mid, speed = p.values.get("motor_id"), p.values.get("speed")
        if not isinstance(mid, str) or not isinstance(speed, float):
            continue
        if mid not in motors_here and existing.get(mid, ("",))[0] != "motor":
            errors.append(p.error(filename, "motor_id", "no motor with this id in the file or the catalog"))
        key = (mid, speed)
        if key in seen:
            errors.append(
                p.error(filename, "speed", f"this motor already has a point at this speed (line {seen[key]})")
            )
        elif any(math.isclose(s, speed, rel_tol=1e-12, abs_tol=1e-12) for s, _, _ in curves.get(mid, [])):
            errors.append(
                p.error(filename, "speed", "this motor's curve in the catalog already has a point at this speed")
            )
        seen.setdefault(key, p.line)
    return errors


def _error_order(e: InputError) -> tuple[int, str]:
    parts = e.field.rsplit(":", 2)
    try:
        return int(parts[1]), e.field
    except (IndexError, ValueError):
        return HEADER_LINE, e.field


# ---------------------------------------------------------------------------------- export


def export(
    path: str | os.PathLike[str],
    kind: str = "motor",
    format: str = "csv",
    *,
    origin: str = "all",
    ids: Iterable[str] | None = None,
    directory: Path | None = None,
) -> int:
    """Write the rows of table ``kind`` to ``path`` as CSV or JSON with unit headers; return the count.

    ``origin`` picks "builtin" (shipped), "user" (imported) or "all" rows; ``ids`` limits the
    export to those ids. JSON nests each motor's curve points under "curve"; CSV exports them
    with ``kind="curve"``. The file re-imports as it is (with ids not already in the catalog).
    """
    text, count = export_text(kind, format, origin=origin, ids=ids, directory=directory)
    _write_text(Path(path), text)
    return count


def export_text(
    kind: str = "motor",
    format: str = "csv",
    *,
    origin: str = "all",
    ids: Iterable[str] | None = None,
    directory: Path | None = None,
) -> tuple[str, int]:
    """The export file's text and its row count (see :func:`export`)."""
    if kind not in TABLES:
        raise InputError("kind", f"must be one of {', '.join(TABLES)}", kind)
    if format not in FORMATS:
        raise InputError("format", f"must be one of {', '.join(FORMATS)}", format)
    if origin not in ("all", "builtin", "user"):
        raise InputError("origin", "must be all, builtin or user", origin)
    spec = TABLES[kind]
    wanted = None if ids is None else set(ids)
    with db.reader(directory) as rd:
        rows = [r for r in rd.rows(spec) if origin in ("all", r["origin"])]
        id_key = "motor_id" if spec is CURVE else "id"
        if wanted is not None:
            rows = [r for r in rows if r[id_key] in wanted]
        curves = rd.curves([r["id"] for r in rows]) if spec is MOTOR and format == "json" else {}
        point_sources = {mid: rd.curve_sources(mid) for mid in curves}
    headers = [header(f) for f in spec.fields]
    records = [[display(f, r.get(f.column)) for f in spec.fields] for r in rows]
    if format == "csv":
        return _csv_text(headers, records), len(rows)
    out_rows: list[dict[str, Any]] = []
    for r, values in zip(rows, records, strict=True):
        obj = {h: v for h, v in zip(headers, values, strict=True) if v is not None}
        if r.get("id") in curves:
            obj["curve"] = [
                _curve_point(p, src) for p, src in zip(curves[r["id"]], point_sources[r["id"]], strict=True)
            ]
        out_rows.append(obj)
    doc = {"table": spec.name, "data_version": DATA_VERSION, "rows": out_rows}
    return json.dumps(doc, indent=1, ensure_ascii=False) + "\n", len(rows)


def _curve_point(point: tuple[float, float | None, float | None], source: str = "") -> dict[str, float | str]:
    names = ("speed", "continuous_torque", "peak_torque")
    out: dict[str, float | str] = {}
    for name, value in zip(names, point, strict=True):
        fld = CURVE.field(name)
        if value is not None:
            out[header(fld)] = display(fld, value)
    if source:
        out["source"] = source
    return out


def _csv_text(headers: list[str], records: list[list[Any]]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(headers)
    writer.writerows([["" if v is None else (repr(v) if isinstance(v, float) else escape_cell(v)) for v in rec]
                      for rec in records])
    return buffer.getvalue()


def _write_text(path: Path, text: str) -> None:
    """Write ``text`` whole or not at all (``drivetrain.files``); file-system errors name ``output``."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as f:
            f.write(text)

    write_atomic(path, write, "output")
