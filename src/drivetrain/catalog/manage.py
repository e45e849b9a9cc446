"""Managing the user catalog: replace, edit and remove your rows, with a history of every change.

The shipped catalog is read-only: every function here changes the user database only (the
data folder's ``user.sqlite`` or ``$DRIVETRAIN_CATALOG``), each call in one SQLite transaction,
and logs what it did in the ``history`` table (time, action, table, id, source, the row before
and after as JSON in SI units).
"""

from __future__ import annotations

import datetime as _dt
import json
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from drivetrain.catalog import db
from drivetrain.catalog.derive import complete_row
from drivetrain.catalog.schema import CURVE, HISTORY_COLUMNS, MOTOR, TABLES, TableSpec
from drivetrain.errors import InputError, InputErrors

if TYPE_CHECKING:
    import sqlite3

    from drivetrain.catalog.records import Row

MAX_EDIT_FIELDS = 200
"""An edit names at most this many fields (a table has fewer; more is not an edit)."""


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _json(values: Mapping[str, Any] | None) -> str | None:
    if values is None:
        return None
    return json.dumps({k: v for k, v in values.items() if v is not None}, ensure_ascii=False, sort_keys=True)


def _log(
    conn: sqlite3.Connection,
    action: str,
    table: str,
    rid: str,
    source: str,
    old: Mapping[str, Any] | None,
    new: Mapping[str, Any] | None,
) -> None:
    conn.execute(
        f"INSERT INTO main.history ({', '.join(HISTORY_COLUMNS)}) VALUES (?, ?, ?, ?, ?, ?, ?)",
        (_now(), action, table, rid, source, _json(old), _json(new)),
    )


def _fetch(conn: sqlite3.Connection, spec: TableSpec, rid: str) -> dict[str, Any] | None:
    cursor = conn.execute(f"SELECT * FROM main.{spec.sql} WHERE id = ?", (rid,))
    found = cursor.fetchone()
    return None if found is None else dict(zip([d[0] for d in cursor.description], found, strict=True))


def _points(conn: sqlite3.Connection, motor_id: str) -> list[dict[str, Any]]:
    cursor = conn.execute(f"SELECT * FROM main.{CURVE.sql} WHERE motor_id = ? ORDER BY speed_rad_s", (motor_id,))
    names = [d[0] for d in cursor.description]
    return [dict(zip(names, r, strict=True)) for r in cursor]


def _si(spec: TableSpec, row: Row) -> dict[str, Any]:
    return {f.column: row.values.get(f.name) for f in spec.fields}


def write_import(conn: sqlite3.Connection, spec: TableSpec, rows: Sequence[Row], replace: bool, filename: str) -> None:
    """Write an import's validated rows inside the caller's transaction, replacing user rows if asked."""
    name = Path(filename).name
    if spec is CURVE:
        motors = list(dict.fromkeys(str(p.values.get("motor_id")) for p in rows))
        for mid in motors:
            before = _points(conn, mid) if replace else []
            if before:
                conn.execute(f"DELETE FROM main.{CURVE.sql} WHERE motor_id = ?", (mid,))
            given = [p for p in rows if p.values.get("motor_id") == mid]
            _log(conn, "replace curve" if before else "import curve", "curve", mid,
                 str(given[0].values.get("source")), {"points": before} if before else None,
                 {"points": [_si(CURVE, p) for p in given]})
        db.insert_rows(conn, "main", spec, rows)
        return
    for row in rows:
        rid = row.id or ""
        old = _fetch(conn, spec, rid) if replace else None
        if old is not None:
            conn.execute(f"DELETE FROM main.{spec.sql} WHERE id = ?", (rid,))
            if spec is MOTOR and row.curve:
                conn.execute(f"DELETE FROM main.{CURVE.sql} WHERE motor_id = ?", (rid,))
        new = _si(spec, row)
        if row.curve:
            new["curve_points"] = len(row.curve)
        _log(conn, "replace" if old is not None else "import", spec.name, rid,
             str(row.values.get("source") or name), old, new)
    db.insert_rows(conn, "main", spec, rows)


def _user_rows(ids: Sequence[str], directory: Path | None) -> dict[str, TableSpec]:
    """The table of each id, which must be a row of your catalog (InputErrors naming every bad one)."""
    from drivetrain.catalog.columns import did_you_mean

    with db.reader(directory) as rd:
        known = rd.ids()
    found: dict[str, TableSpec] = {}
    errors: list[InputError] = []
    for rid in ids:
        if rid not in known:
            mine = [k for k, (_, origin) in known.items() if origin == "user"]
            errors.append(InputError("id", "no row of your catalog has this id" + did_you_mean(rid, mine), rid))
        elif known[rid][1] == "builtin":
            errors.append(InputError("id", "is a row of the shipped catalog, which cannot be changed", rid))
        else:
            found[rid] = TABLES[known[rid][0]]
    if errors:
        raise errors[0] if len(errors) == 1 else InputErrors(errors)
    return found


def remove(ids: Iterable[str], *, directory: Path | None = None, source: str = "drivetrain catalog remove") -> int:
    """Remove rows of your catalog by id (a motor with its curve points), all in one transaction.

    Every id must name a row you imported; otherwise nothing is removed (InputError naming each bad id).
    Returns the number of rows removed.
    """
    wanted = list(dict.fromkeys(ids))
    if not wanted:
        raise InputError("id", "name at least one id to remove", has_value=False)
    tables = _user_rows(wanted, directory)
    with db.user_writer(directory) as conn:
        for rid, spec in tables.items():
            old = _fetch(conn, spec, rid)
            if old is None:  # removed meanwhile by another process
                raise InputError("id", "was removed from your catalog meanwhile; nothing was removed", rid)
            conn.execute(f"DELETE FROM main.{spec.sql} WHERE id = ?", (rid,))
            points = _points(conn, rid) if spec is MOTOR else []
            if points:
                conn.execute(f"DELETE FROM main.{CURVE.sql} WHERE motor_id = ?", (rid,))
                old["curve_points"] = len(points)
            _log(conn, "remove", spec.name, rid, source, old, None)
    return len(tables)


def update(rid: str, changes: Mapping[str, Any], *, directory: Path | None = None, source: str = "edit") -> None:
    """Change fields of one row of your catalog (one transaction); ``catalog.update`` returns the row after.

    ``changes`` maps a field name (``rated_torque``) or a header with a unit (``rotor_inertia [kg*cm^2]``)
    to its new value (a number in that unit, or text with a unit, e.g. "1.2 kg*cm^2"); None or ""
    clears the field. The edited row is validated exactly as an import is; the id cannot change.
    """
    from drivetrain.catalog.columns import display, field_of_header, header
    from drivetrain.catalog.reading import RawFile, RawRow
    from drivetrain.catalog.records import parse_rows

    if not isinstance(changes, Mapping) or not changes:
        raise InputError("changes", "must name at least one field and its new value", has_value=False)
    if len(changes) > MAX_EDIT_FIELDS:
        raise InputError("changes", f"names more than {MAX_EDIT_FIELDS} fields", len(changes))
    spec = _user_rows([rid], directory)[rid]
    with db.reader(directory) as rd:
        current = rd.rows(spec, "id = ? AND origin = 'user'", (rid,))[0]
    cells: dict[str, Any] = {header(f): display(f, current.get(f.column)) for f in spec.fields}
    label = f"edit of {rid}"
    errors: list[InputError] = []
    for key, value in changes.items():
        fld = field_of_header(spec, str(key))
        if fld is None:
            errors.append(InputError(f"{label}:{key}", f"is not a {spec.name} field", has_value=False))
            continue
        if fld.name == "id" and value != rid:
            errors.append(InputError(f"{label}:id", "cannot be changed (remove the row and import it anew)", value))
            continue
        for h in [h for h in cells if field_of_header(spec, h) is fld]:
            del cells[h]
        cells[str(key)] = value
    if errors:
        raise errors[0] if len(errors) == 1 else InputErrors(errors)
    raw = RawFile(label, "json", list(cells), [RawRow(1, cells)])
    parsed = parse_rows(raw, spec)
    if parsed.errors:
        raise parsed.errors[0] if len(parsed.errors) == 1 else InputErrors(parsed.errors)
    row = parsed.rows[0]
    _rederive(spec, row.values, {f.name for k in changes if (f := field_of_header(spec, str(k))) is not None})
    from drivetrain.catalog.check import IMPORT_CONSISTENCY, row_findings

    broken = [row.error(label, name, f"breaks the rule {rule} (docs/catalog.md): {message}")
              for rule, name, message in row_findings(spec, row.values) if rule in IMPORT_CONSISTENCY]
    if broken:
        raise broken[0] if len(broken) == 1 else InputErrors(broken)
    with db.user_writer(directory) as conn:
        old = _fetch(conn, spec, rid)
        if old is None:
            raise InputError("id", "was removed from your catalog meanwhile; nothing was changed", rid)
        conn.execute(f"DELETE FROM main.{spec.sql} WHERE id = ?", (rid,))
        db.insert_rows(conn, "main", spec, [row])
        _log(conn, "edit", spec.name, rid, source, old, _si(spec, row))


def _rederive(spec: TableSpec, values: dict[str, Any], changed: set[str]) -> None:
    """An edited row's derived values computed again from its current values (catalog.derive, voltage_class):
    a derived field the edit sets becomes a given one; the others are cleared and recomputed, so none is
    left stale by a change of what it was computed from."""
    from drivetrain.catalog.voltage_class import SEPARATOR

    names = [n for n in str(values.get("derived") or "").split(",") if n]
    recompute = {"torque_constant", "stall_torque", "rated_torque", "voltage"}
    kept = [n for n in names if n not in recompute]
    for name in names:
        if name in recompute and name not in changed:
            values.pop(name, None)
    formulas = [f for f in str(values.get("derivation") or "").split(SEPARATOR)
                if f and f.partition(" = ")[0] not in recompute]
    values["derived"] = ",".join(kept) or None
    values["derivation"] = SEPARATOR.join(formulas) or None
    complete_row(spec.name, values)


def history(rid: str | None = None, *, directory: Path | None = None) -> list[dict[str, Any]]:
    """Every change to your catalog (oldest first), or those of one id: time (UTC), action (import,
    replace, edit, remove, import curve, replace curve), table, id, source, and the row before and
    after (SI, unit in each key)."""
    with db.reader(directory) as rd:
        entries = rd.history(rid)
    for e in entries:
        for key in ("old_values", "new_values"):
            e[key] = None if e[key] is None else json.loads(e[key])
    return entries


def user_ids(directory: Path | None = None) -> dict[str, str]:
    """Every id of your catalog -> its table."""
    with db.reader(directory) as rd:
        return {rid: table for rid, (table, origin) in rd.ids().items() if origin == "user"}


__all__ = ["history", "remove", "update", "user_ids", "write_import"]
