"""The component catalog: motors, gearboxes and drives from several vendors, with their sources.

The shipped data (``drivetrain/catalog/data``, provenance in ``data/SOURCES.md``) is built into
an SQLite database on first use; the user's own imports live in a second database next to it.
Queries see both and return arrays (SI, NaN where a value is unknown)::

    from drivetrain import catalog
    m = catalog.motors(vendor="Yaskawa")          # MotorTable of numpy arrays
    m.rated_torque, m.rotor_inertia, m.ids        # [N m], [kg m^2], ids
    catalog.get("SGM7J-04A")                      # one row as a dict, with source and notes
    catalog.import_file("my_motors.csv")          # validated, one transaction
    catalog.import_file("my_motors.csv", replace=True)  # update your rows of the same ids
    catalog.update("MY-1", {"rated_torque": 1.3})  # edit one of your rows
    catalog.remove(["MY-1"]); catalog.history()   # remove rows; every change is logged
    catalog.export("motors.json", "motor", "json")

The data folder is ``$DRIVETRAIN_DATA_DIR`` or the platform's user data folder; the user catalog is
``$DRIVETRAIN_CATALOG`` when set (a file a team can share), else ``user.sqlite`` in that folder.
"""

from __future__ import annotations

import copy
import functools
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, ParamSpec, TypeVar

from drivetrain import units
from drivetrain.catalog import db
from drivetrain.catalog.schema import (
    DATA_VERSION,
    DRIVE,
    FIELD_GROUPS,
    GEARBOX,
    MOTOR,
    ROW_TABLES,
    TableSpec,
    trace,
)
from drivetrain.errors import InputError

if TYPE_CHECKING:
    from pathlib import Path

    from drivetrain.catalog.importer import ImportReport, export, import_file
    from drivetrain.catalog.manage import history, remove
    from drivetrain.catalog.tables import DriveTable, GearboxTable, MotorTable

_LAZY = {"ImportReport": "importer", "export": "importer", "import_file": "importer", "DriveTable": "tables",
         "GearboxTable": "tables", "MotorTable": "tables", "history": "manage", "remove": "manage"}


def __getattr__(name: str) -> Any:
    """numpy-backed parts load on first use, so the CLI's --help stays fast."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f"drivetrain.catalog.{_LAZY[name]}"), name)
    raise AttributeError(name)

__all__ = [
    "DATA_VERSION",
    "DriveTable",
    "GearboxTable",
    "ImportReport",
    "MotorTable",
    "drives",
    "export",
    "gearboxes",
    "get",
    "history",
    "import_file",
    "motor_row",
    "motor_rows",
    "motors",
    "remove",
    "update",
]

VOLTAGE_TOLERANCE = 0.15
"""Relative window of the voltage filter: vendors name one mains family 200/230 V or 400/460 V."""
FLANGE_TOLERANCE = 0.5e-3
"""[m] flange filter window: flange widths are whole millimetres."""

Names = str | Sequence[str] | None


_CACHE: dict[tuple[Any, ...], Any] = {}
_ON_DISK = ("motor", "gearbox")
"""Queries whose tables a new process reads from disk while the catalog is unchanged (catalog.table_cache)."""
P = ParamSpec("P")
R = TypeVar("R")


def _state() -> tuple[Any, ...]:
    """What a query's answer depends on besides its arguments: the data folder and the user database."""
    folder = db.data_dir()
    try:
        st = db.user_db_path(folder).stat()
        user = (st.st_mtime_ns, st.st_size)
    except OSError:
        user = None
    return (str(folder), DATA_VERSION, user)


def _cached(kind: str) -> Callable[[Callable[P, R]], Callable[P, R]]:
    """Tables are immutable: repeat queries (a web session re-sizing) reuse them until the data changes."""

    def wrap(fn: Callable[P, R]) -> Callable[P, R]:
        @functools.wraps(fn)
        def query(*args: P.args, **kwargs: P.kwargs) -> R:
            try:
                key = (kind, _state(), repr(args), repr(sorted(kwargs.items())))
            except TypeError:
                return fn(*args, **kwargs)
            if key not in _CACHE:
                if len(_CACHE) > 64:
                    _CACHE.clear()
                if kind in _ON_DISK and "ids" not in kwargs and not args:
                    from drivetrain.catalog.table_cache import cached

                    _CACHE[key] = cached(f"{kind}|{key[3]}", lambda: fn(*args, **kwargs))
                else:
                    _CACHE[key] = fn(*args, **kwargs)
            return _CACHE[key]

        return query

    return wrap


@_cached("rows")
def _rows(table: str) -> list[dict[str, Any]]:
    """Every row of a table (shipped then user, in file order), read once per catalog state; the
    queries below filter these (never change them)."""
    with db.reader() as rd:
        return rd.rows(next(spec for spec in ROW_TABLES if spec.name == table))


@_cached("motor")
def motors(
    vendor: Names = None,
    kind: str | None = None,
    voltage: float | str | None = None,
    flange: float | str | None = None,
    ids: Iterable[str] | None = None,
) -> MotorTable:
    """Motors of the shipped and user catalogs as arrays (SI).

    Args:
        vendor: case-insensitive part of the vendor name ("yaskawa"), or several.
        kind: "ac_servo" or "small_dc".
        voltage: voltage class, e.g. 400 or "400 V"; matches within 15 % (400 also finds
            460 V motors). Motors whose voltage is unknown are left out.
        flange: square flange width, e.g. "80 mm" or 0.08 [m]; matches within 0.5 mm.
        ids: exactly these motors, in this order (an unknown id is an InputError).

    An empty result is not an error; a vendor or kind that matches nothing in the catalog is.
    """
    with db.reader() as rd:
        rows = _filter(MOTOR, _rows(MOTOR.name), vendor, kind, ids)
        if voltage is not None:
            v = units.parse(voltage, "voltage", "voltage", allow_zero=False)
            rows = [
                r for r in rows if r["voltage_V"] is not None and abs(r["voltage_V"] - v) <= VOLTAGE_TOLERANCE * abs(v)
            ]
        if flange is not None:
            f = units.parse(flange, "length", "flange", allow_zero=False)
            rows = [r for r in rows if r["flange_m"] is not None and abs(r["flange_m"] - f) <= FLANGE_TOLERANCE]
        points = rd.curves([r["id"] for r in rows])
    from drivetrain.catalog.curves import Curve
    from drivetrain.catalog.tables import MotorTable

    curves = {mid: Curve.from_points(p) for mid, p in points.items()}
    return MotorTable.from_db(rows, curves)


@_cached("gearbox")
def gearboxes(
    vendor: Names = None, series: Names = None, kind: str | None = None, ids: Iterable[str] | None = None
) -> GearboxTable:
    """Gearboxes (one row per model and ratio) as arrays (SI).

    Args:
        vendor: case-insensitive part of the vendor name, or several.
        series: series name(s), case-insensitive ("GPB", "GPBR").
        kind: "servo_gearbox" (precision gearboxes for servo motors) or "small_gearhead".
        ids: exactly these rows, in this order.
    """
    rows = _filter(GEARBOX, _rows(GEARBOX.name), vendor, kind, ids)
    if series is not None:
        wanted = _names("series", series)
        known = {str(r["series"]).lower() for r in rows if r["series"]}
        unknown = [s for s in wanted if s not in known]
        if unknown:
            raise InputError(
                "series", f"no gearbox series matches (known: {', '.join(sorted(known))})", ", ".join(unknown)
            )
        rows = [r for r in rows if str(r["series"] or "").lower() in wanted]
    from drivetrain.catalog.tables import GearboxTable

    return GearboxTable.from_rows(rows)


@_cached("drive")
def drives(vendor: Names = None, voltage: float | str | None = None, ids: Iterable[str] | None = None) -> DriveTable:
    """Servo drives as arrays (SI): the shipped rows (data/drives_servo.csv, SOURCES.md "Drives") and imports."""
    rows = _filter(DRIVE, _rows(DRIVE.name), vendor, None, ids)
    if voltage is not None:
        v = units.parse(voltage, "voltage", "voltage", allow_zero=False)
        rows = [r for r in rows if r["voltage_V"] is not None and abs(r["voltage_V"] - v) <= VOLTAGE_TOLERANCE * abs(v)]
    from drivetrain.catalog.tables import DriveTable

    return DriveTable.from_rows(rows)


@_cached("drive_pairs")
def drive_pairs() -> dict[str, list[str]]:
    """The vendors' motor-drive pairing tables: motor id -> the drive ids printed for it (data/SOURCES.md)."""
    with db.reader() as rd:
        return rd.drive_pairs()


@_cached("drive_pair_sources")
def drive_pair_sources() -> dict[tuple[str, str], dict[str, Any]]:
    """Each pairing's provenance: (motor id, drive id) -> ``source``, ``source_url`` and ``verified`` (False:
    a third-party transcription, data/SOURCES.md "Output currents from a third-party transcription")."""
    with db.reader() as rd:
        return rd.drive_pair_sources()


def get(id: str) -> dict[str, Any]:
    """One motor, gearbox or drive by id, as a dict: SI values keyed with their unit, plus
    ``table``, ``origin`` ("builtin" or "user"), ``source``, ``notes``, ``derived`` (fields not
    read from a datasheet), ``derivation`` (each derived field with its formula) and, for motors,
    ``curve`` (None: envelope derived, approximate).

    Raises InputError('id', ...) naming close matches, or why the shipped data left it out.
    """
    return copy.deepcopy(_get(id))  # the caller's own copy of the remembered record


def update(id: str, changes: Mapping[str, Any], *, directory: Path | None = None,
           source: str = "edit") -> dict[str, Any]:
    """Change fields of one row of your catalog (``manage.update``: validated as an import is, one
    transaction, logged); returns the row as ``get`` does."""
    from drivetrain.catalog import manage

    manage.update(id, changes, directory=directory, source=source)
    return get(id)


def motor_row(id: str) -> dict[str, Any] | None:
    """One motor's database columns (SI, unit in the key: the values ``get`` gives for them) without its
    curve and provenance, or None when no motor has this id (``motor_rows``)."""
    found = motor_rows([id]).get(id)
    return None if found is None else dict(found)


_MOTOR_ROWS: dict[tuple[Any, ...], dict[str, dict[str, Any] | None]] = {}


def motor_rows(ids: Iterable[str]) -> dict[str, dict[str, Any]]:
    """The database columns of these motors (as ``motor_row``; the ids no motor has are left out), read
    with one query for those not read before while the catalog is unchanged: for callers that need a
    few columns of several motors (the drive post-pass) without reading every row. Do not change them."""
    ids = list(ids)
    state = _state()
    if state not in _MOTOR_ROWS:
        _MOTOR_ROWS.clear()
    known = _MOTOR_ROWS.setdefault(state, {})
    wanted = [i for i in dict.fromkeys(ids) if i not in known]
    if wanted:
        with db.reader() as rd:
            for start in range(0, len(wanted), 500):  # SQLite's limit on parameters
                part = wanted[start:start + 500]
                for found in rd.rows(MOTOR, f"id IN ({', '.join('?' * len(part))})", part):
                    known.setdefault(found["id"], found)  # the first row of an id, as get() finds it
        for i in wanted:
            known.setdefault(i, None)
    return {i: row for i in ids if (row := known.get(i)) is not None}


@_cached("get")
def _get(id: str) -> dict[str, Any]:
    with db.reader() as rd:
        for spec in ROW_TABLES:
            # this id's rows in the order of _rows (one query: the tables may come from disk, unread)
            found = rd.rows(spec, "id = ?", (id,))
            if found:
                return _record(spec, found[0], rd.curves([id]).get(id), rd.curve_sources(id))
        rejected = rd.rejected(id)
        known = list(rd.ids())
    if rejected is not None:
        raise InputError(
            "id",
            f"no motor, gearbox or drive with this id: the shipped data leaves it out ({rejected['reason']})",
            id,
        )
    from drivetrain.catalog.columns import did_you_mean  # only for an unknown id

    raise InputError("id", "no motor, gearbox or drive with this id" + did_you_mean(id, known), id)


def _record(
    spec: TableSpec,
    row: dict[str, Any],
    points: list[tuple[float, float | None, float | None]] | None,
    curve_sources: Sequence[str] = (),
) -> dict[str, Any]:
    record: dict[str, Any] = {"table": spec.name, **row}
    record["unverified"], record["unverified_reason"] = trace(row)
    record["sources"] = sources(spec, row, points, curve_sources)
    if spec in (MOTOR, DRIVE):
        from drivetrain.catalog.derive import formulas

        record["derivation"] = formulas(row)  # derived field -> how it was computed
        record["derived"] = [d for d in (row.get("derived") or "").split(",") if d]
    if spec is MOTOR:
        from drivetrain.catalog.curves import Curve

        record["curve"] = None if not points else Curve.from_points(points).to_dict()
    return record


def sources(
    spec: TableSpec,
    row: dict[str, Any],
    points: list[tuple[float, float | None, float | None]] | None = None,
    curve_sources: Sequence[str] = (),
) -> dict[str, str]:
    """Where each field group of a row was read: ratings, mechanical, electrical (and, for motors, curve).

    A group's own source (``ratings_source`` ...) where the row has one, else the row's vendor document
    (title, section, page, URL), else its ``source`` text; a group the row has no value of says so.
    """
    doc = ", ".join(
        str(row[k]) for k in ("source_document", "source_section") if row.get(k)
    )
    if row.get("source_page"):
        page = str(row["source_page"])
        doc += f", p. {page}" if page[:1].isdigit() else f", {page}"
    if row.get("source_url"):
        doc += f" ({row['source_url']})"
    default = doc or str(row.get("source") or "no source recorded")
    out: dict[str, str] = {}
    for group, names in FIELD_GROUPS.items():
        columns = [f.column for f in spec.fields if f.name in names]
        if not columns:
            continue
        if not any(row.get(c) is not None for c in columns):
            out[group] = "no values"
            continue
        own = row.get(f"{group}_source")
        out[group] = f"{own} [{doc}]" if own and doc else str(own or default)
    if spec is MOTOR:
        if not points:
            out["curve"] = "none: the envelope is derived from the ratings (approximate)"
        else:
            named = sorted({s for s in curve_sources if s})
            out["curve"] = f"{len(points)} points from " + ("; ".join(named) if named else default)
    return out


def _names(field: str, value: str | Sequence[str]) -> list[str]:
    items = [value] if isinstance(value, str) else list(value)
    if not items or not all(isinstance(v, str) and v.strip() for v in items):
        raise InputError(field, "must be a name or a list of names", value)
    return [v.strip().lower() for v in items]


def _filter(
    spec: TableSpec, rows: list[dict[str, Any]], vendor: Names, kind: str | None, ids: Iterable[str] | None
) -> list[dict[str, Any]]:
    if kind is not None:
        if kind not in spec.kinds:
            raise InputError("kind", f"must be one of {', '.join(spec.kinds)}", kind)
        rows = [r for r in rows if r["kind"] == kind]
    if vendor is not None:
        wanted = _names("vendor", vendor)
        vendors = sorted({str(r["vendor"]) for r in rows})
        unknown = [w for w in wanted if not any(w in v.lower() for v in vendors)]
        if unknown:
            raise InputError(
                "vendor", f"no {spec.name} vendor matches (known: {', '.join(vendors)})", ", ".join(unknown)
            )
        rows = [r for r in rows if any(w in str(r["vendor"]).lower() for w in wanted)]
    if ids is not None:
        by_id = {r["id"]: r for r in rows}
        wanted_ids = [ids] if isinstance(ids, str) else list(ids)
        missing = [i for i in wanted_ids if i not in by_id]
        if missing:
            from drivetrain.catalog.columns import did_you_mean  # only for an unknown id

            raise InputError("ids", f"no {spec.name} with this id" + did_you_mean(missing[0], list(by_id)),
                             missing[0])
        rows = [by_id[i] for i in wanted_ids]
    return rows
