"""Reading catalog rows from CSV or JSON text: unit headers, SI conversion and validation.

Both the shipped data files and user imports go through this module, so the shipped catalog
obeys exactly the rules an import is held to. Nothing here touches a database.

A header is ``name`` (SI) or ``name [unit]`` (``rotor_inertia [kg*cm^2]``); the shipped files'
suffixed names (``rated_speed_rpm``, ``rotor_inertia_kgm2``) are understood too. A cell may be a
plain number (in the header's unit) or carry its own unit (``"0.371 kg*cm^2"``).
Every problem becomes an ``InputError`` whose field is ``file:line:column``.

The file is read by ``catalog.reading``, headers and cells converted by ``catalog.columns``, rows checked
against ``catalog.rules``; this module turns a read file into checked rows of one table.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from drivetrain.catalog.columns import (
    HEADER_LINE,
    Column,
    convert,
    field_of_header,
    lookup,
    resolve_header,
    where,
)
from drivetrain.catalog.reading import RawFile, RawRow
from drivetrain.catalog.rules import RULES
from drivetrain.catalog.schema import CURVE, DECIBEL, FLAG, MOTOR, TableSpec
from drivetrain.errors import InputError

__all__ = ["Parsed", "Row", "parse_rows", "resolve_headers"]

# Two columns for one field (e.g. no_load_speed_rad_s and no_load_speed_rpm) must agree this well.
_SAME_VALUE_RTOL = 1e-3


# ---------------------------------------------------------------------------------- rows


@dataclass
class Row:
    """A converted row: field name -> stored value (SI float, int, text or None)."""

    line: int
    values: dict[str, Any]
    columns: dict[str, str]  # field name -> header as written, for error messages
    raw: dict[str, Any]  # field name -> cell as written
    curve: list[Row] = field(default_factory=list)
    bad: set[str] = field(default_factory=set)  # fields whose cell or header was already reported

    @property
    def id(self) -> str | None:
        value = self.values.get("id")
        return value if isinstance(value, str) else None

    def error(self, filename: str, name: str, rule: str) -> InputError:
        column = self.columns.get(name, name)
        if name in self.raw:
            return InputError(where(filename, self.line, column), rule, self.raw[name])
        return InputError(where(filename, self.line, column), rule, has_value=False)


@dataclass
class Parsed:
    """A file converted to rows of one table; ``errors`` holds every problem found."""

    spec: TableSpec
    rows: list[Row]
    errors: list[InputError]


def resolve_headers(
    spec: TableSpec, headers: list[str], filename: str, lines: Mapping[str, int] | None = None
) -> tuple[dict[str, Column], list[InputError], set[str]]:
    """Resolve every header; also return the fields named by headers that failed (e.g. a wrong unit),
    so that the field is not reported missing on top of its header error."""
    columns: dict[str, Column] = {}
    errors: list[InputError] = []
    claimed: set[str] = set()
    for h in headers:
        try:
            columns[h] = resolve_header(spec, h, filename, (lines or {}).get(h, HEADER_LINE))
        except InputError as exc:
            errors.append(exc)
            fld = field_of_header(spec, h)
            if fld is not None:
                claimed.add(fld.name)
    return columns, errors, claimed


def parse_rows(
    raw: RawFile,
    spec: TableSpec,
    *,
    kind: str | None = None,
    constants: Mapping[str, Any] | None = None,
    derived: Sequence[str] = (),
) -> Parsed:
    """Convert and validate every row of ``raw`` as rows of ``spec``; collect all problems.

    ``kind`` is the default for rows without a kind column; ``constants`` fill fields the file
    does not have and ``derived`` names motor fields the file derived rather than read from a
    datasheet (both used for the shipped files, see schema.SHIPPED_FILES).
    """
    filename = raw.filename
    columns, errors, claimed = resolve_headers(spec, raw.headers, filename, raw.header_lines)
    default_kind = kind or spec.default_kind
    present: set[str] | None = None  # JSON: every row says for itself which fields it has
    if raw.fmt == "csv":
        present = {c.field.name for c in columns.values()} | claimed
        errors.extend(_missing_columns(spec, raw, columns, present, default_kind))
    curve_columns: dict[str, Column] = {}
    rows: list[Row] = []
    for raw_row in raw.rows:
        row, row_errors = _convert_row(raw_row, columns, filename)
        row.bad |= claimed
        errors.extend(row_errors)
        for name, value in (constants or {}).items():
            row.values.setdefault(name, value)
        if spec.kinds:
            row.values["kind"] = row.values.get("kind") or default_kind
        if spec is MOTOR:
            errors.extend(_mark_derived(row, derived, filename))
        errors.extend(_check_row(row, spec, filename, present))
        if raw_row.curve:
            if spec is not MOTOR:
                errors.append(row.error(filename, "curve", "only motors have a speed-torque curve"))
            else:
                new: dict[str, int] = {}
                for p in raw_row.curve:
                    for h in p.cells:
                        if h not in curve_columns:
                            new.setdefault(h, p.line)
                found, header_errors, _ = resolve_headers(CURVE, list(new), filename, new)
                curve_columns.update(found)
                errors.extend(header_errors)
                for point in raw_row.curve:
                    pt, pt_errors = _convert_row(point, curve_columns, filename)
                    errors.extend(pt_errors)
                    pt.values.setdefault("motor_id", row.id)
                    errors.extend(_check_row(pt, CURVE, filename, None))
                    row.curve.append(pt)
        rows.append(row)
    return Parsed(spec, rows, errors)


def _missing_columns(
    spec: TableSpec, raw: RawFile, columns: dict[str, Column], present: set[str], default_kind: str
) -> list[InputError]:
    have = set(present)
    kinds = {default_kind}
    kind_header = next((h for h, c in columns.items() if c.field.name == "kind"), None)
    if kind_header is not None:
        kinds = {str(r.cells.get(kind_header) or "").strip() or default_kind for r in raw.rows} or kinds
    errors = []
    for k in sorted(kinds & set(spec.required)):
        for name in spec.required[k]:
            if name not in have:
                what = f"a {spec.name} of kind {k!r}" if k else f"a {spec.name} row"
                errors.append(
                    InputError(
                        where(raw.filename, HEADER_LINE, name),
                        f"required column is missing ({what} needs {', '.join(spec.required[k])})",
                        has_value=False,
                    )
                )
                have.add(name)  # report each missing column once
    return errors


def _convert_row(raw_row: RawRow, columns: dict[str, Column], filename: str) -> tuple[Row, list[InputError]]:
    row = Row(raw_row.line, {}, {}, {})
    errors: list[InputError] = []
    for header, cell in raw_row.cells.items():
        column = columns.get(header)
        if column is None:
            continue  # header error already reported
        name = column.field.name
        path = where(filename, raw_row.line, header)
        try:
            value = convert(cell, column, path)
        except InputError as exc:
            errors.append(exc)
            row.bad.add(name)
            continue
        if value is None:
            continue
        if name in row.values:
            first = row.values[name]
            if not _same(first, value):
                errors.append(InputError(path, f"disagrees with column {row.columns[name]!r} ({row.raw[name]})", cell))
            continue
        row.values[name], row.columns[name], row.raw[name] = value, header, cell
    return row, errors


def _mark_derived(row: Row, derived: Sequence[str], filename: str) -> list[InputError]:
    """Normalise the ``derived`` list: named fields, plus any the file or rated_torque_basis implies."""
    names: list[str] = []
    for name in re.split(r"[,;\s]+", row.values.get("derived") or ""):
        fld = lookup(MOTOR, name) if name else None
        if name and (fld is None or not fld.numeric):
            return [row.error(filename, "derived", f"names an unknown numeric motor field {name!r}")]
        if fld is not None:
            names.append(fld.name)
    names += [n for n in derived if row.values.get(n) is not None]
    if row.values.get("rated_torque_basis") not in (None, "source"):
        names.append("rated_torque")
    row.values["derived"] = ",".join(dict.fromkeys(names)) or None
    return []


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return abs(a - b) <= _SAME_VALUE_RTOL * max(abs(a), abs(b))
    return bool(a == b)


def _check_row(row: Row, spec: TableSpec, filename: str, present: set[str] | None) -> list[InputError]:
    """Kind, required cells, positivity and the plausibility rules of ``spec``.

    ``present``: fields the CSV header has (a required column missing from the header is
    reported once, at the header); ``None`` for JSON, where each row is checked on its own.
    """
    errors: list[InputError] = []
    kind = row.values.get("kind", "")
    if spec.kinds and kind not in spec.kinds:
        errors.append(row.error(filename, "kind", f"must be one of {', '.join(spec.kinds)}"))
        kind = spec.default_kind
    for name in spec.required.get(kind, ()):
        if row.values.get(name) is None and name not in row.bad and (present is None or name in present):
            errors.append(row.error(filename, name, "is required"))
    for fld in spec.fields:
        value = row.values.get(fld.name)
        if isinstance(value, (int, float)) and fld.quantity not in (FLAG, DECIBEL):
            if fld.positive and value <= 0:
                errors.append(row.error(filename, fld.name, "must be > 0 (leave the cell empty if unknown)"))
            elif not fld.positive and fld.name != "direction" and value < 0:
                errors.append(row.error(filename, fld.name, "must be >= 0"))
    errors.extend(row.error(filename, name, rule) for name, rule in RULES[spec.name](row.values, kind))
    return errors
