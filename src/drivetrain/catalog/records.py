"""Reading catalog rows from CSV or JSON text: unit headers, SI conversion and validation.

Both the shipped data files and user imports go through this module, so the shipped catalog
obeys exactly the rules an import is held to. Nothing here touches a database.

A header is ``name`` (SI) or ``name [unit]`` (``rotor_inertia [kg*cm^2]``); the shipped files'
suffixed names (``rated_speed_rpm``, ``rotor_inertia_kgm2``) are understood too. A cell may be a
plain number (in the header's unit) or carry its own unit (``"0.371 kg*cm^2"``).
Every problem becomes an ``InputError`` whose field is ``file:line:column``.
"""

from __future__ import annotations

import bisect
import csv
import difflib
import io
import json
import json.decoder
import json.scanner
import math
import re
from collections import Counter
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from drivetrain import units
from drivetrain.catalog.schema import (
    CURVE,
    DECIBEL,
    EXTRA_QUANTITIES,
    FLAG,
    INTEGER,
    MOTOR,
    TABLES,
    TEXT,
    Field,
    TableSpec,
)
from drivetrain.errors import InputError

HEADER_LINE = 1

_HEADER = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\[\s*([^\]]*?)\s*\])?\s*$")
# Unit suffixes of the shipped files' column names, longest first so "_mm" wins over "_m".
_SUFFIX_UNITS: tuple[tuple[str, str], ...] = (
    ("_Nm_per_arcmin", "N*m/arcmin"),
    ("_Nm_per_rad", "N*m/rad"),
    ("_Nm_per_A", "N*m/A"),
    ("_K_per_W", "K/W"),
    ("_rad_s", "rad/s"),
    ("_kgm2", "kg*m^2"),
    ("_kgcm2", "kg*cm^2"),
    ("_arcmin", "arcmin"),
    ("_rpm", "rpm"),
    ("_ohm", "ohm"),
    ("_rad", "rad"),
    ("_Nm", "N*m"),
    ("_mm", "mm"),
    ("_kg", "kg"),
    ("_dB", "dB"),
    ("_W", "W"),
    ("_V", "V"),
    ("_A", "A"),
    ("_H", "H"),
    ("_F", "F"),
    ("_N", "N"),
    ("_m", "m"),
)
MAX_ID_CHARS = 100
"""Longest id [characters]: vendor order codes are under 40."""
MAX_TEXT_CHARS = 2_000
"""Longest text cell (source, notes) [characters]."""
MAX_DIGITS = 400
"""Longest number in a JSON file [characters]: a float needs 17 significant digits."""
MAX_JSON_DEPTH = 16
"""Deepest nesting of a JSON file: ``{"rows": [{"curve": [{...}]}]}`` is 4."""
_JSON_STRUCTURE = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]')
_FORMULA_START = frozenset("=+-@\t\r")
_BIDI = frozenset("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")
_TRUE = {"yes", "y", "true", "1"}
_FALSE = {"no", "n", "false", "0"}
# Two columns for one field (e.g. no_load_speed_rad_s and no_load_speed_rpm) must agree this well.
_SAME_VALUE_RTOL = 1e-3


def where(filename: str, line: int, column: str) -> str:
    """The error field of a problem: ``file:line:column``."""
    return f"{filename}:{line}:{column}"


# ---------------------------------------------------------------------------------- units


def parse_quantity(value: Any, quantity: str, field_path: str) -> float:
    """SI float of ``value`` (number or text with a unit) for a units.py or EXTRA_QUANTITIES quantity."""
    if quantity in units.QUANTITIES:
        return units.parse(value, quantity, field_path)
    si_unit, description = EXTRA_QUANTITIES[quantity]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InputError(field_path, f"must be a number or a quantity with units of {description}", value)
    if isinstance(value, str):
        try:
            result = float(value)
        except ValueError:
            result = _pint_to(value, si_unit, description, field_path)
    else:
        result = float(value)
    if not math.isfinite(result):
        raise InputError(field_path, "must be a finite number", value)
    return result


def _pint_to(text: str, si_unit: str, description: str, field_path: str) -> float:
    import pint

    units.check_grammar(text.strip(), field_path)
    try:
        q: Any = units.registry().Quantity(text.strip().replace("·", "*").replace("µ", "u"))
        return float(q.to(si_unit).magnitude)
    except pint.errors.DimensionalityError:
        raise InputError(field_path, f"has the wrong dimension: expected {description}", text) from None
    except Exception as exc:  # pint raises many types for unparsable text
        raise InputError(field_path, f"is not a quantity with units of {description} ({exc})", text) from None


def unit_factor(fld: Field, unit: str | None, field_path: str) -> float:
    """SI value of one header ``unit`` of ``fld`` (1.0 for none); InputError on a wrong dimension."""
    if not unit:
        return 1.0
    if fld.quantity in (TEXT, FLAG, INTEGER):
        raise InputError(field_path, "takes no unit", unit)
    if fld.quantity == DECIBEL:
        if unit not in ("dB", "dBA", "dB(A)"):
            raise InputError(field_path, "is a sound level: the only unit is dB", unit)
        return 1.0
    return parse_quantity(f"1 {unit}", fld.quantity, field_path)


# ---------------------------------------------------------------------------------- headers


@dataclass(frozen=True)
class Column:
    """A header resolved against a table: the field it fills and the SI factor of its unit."""

    header: str
    field: Field
    unit: str
    factor: float


def lookup(spec: TableSpec, name: str) -> Field | None:
    """The field a header name (without unit) means in ``spec``, by name or alias."""
    key = name.strip().lower()
    key = spec.aliases.get(key, key)
    return next((f for f in spec.fields if f.name == key), None)


def _split_header(spec: TableSpec, header: str) -> tuple[str, Field | None, str | None] | None:
    """(name, field or None, unit or None) of a header; None if it is not ``name`` or ``name [unit]``."""
    m = _HEADER.match(header)
    if m is None:
        return None
    name, unit = m.group(1), m.group(2)
    fld = lookup(spec, name)
    if fld is None and unit is None:
        for suffix, suffix_unit in _SUFFIX_UNITS:
            if name.endswith(suffix) and (fld := lookup(spec, name[: -len(suffix)])) is not None:
                return name, fld, suffix_unit
    return name, fld, unit


def resolve_header(spec: TableSpec, header: str, filename: str, line: int = HEADER_LINE) -> Column:
    """Resolve one header (``name``, ``name [unit]`` or ``name_<unit suffix>``); raises InputError.

    ``line``: where the header is written (the header row of a CSV, the first object with the key in JSON).
    """
    path = where(filename, line, header)
    split = _split_header(spec, header)
    if split is None:
        raise InputError(path, "is not a column name (expected name or name [unit])", header)
    name, fld, unit = split
    if fld is None:
        known = list(spec.names) + list(spec.aliases)
        close = difflib.get_close_matches(name.lower(), known, n=3, cutoff=0.6)
        hint = f"; did you mean {', '.join(close)}?" if close else f"; known columns: {', '.join(spec.names)}"
        raise InputError(path, f"unknown {spec.name} column{hint}", header)
    return Column(header, fld, unit or "", unit_factor(fld, unit, path))


def field_of_header(spec: TableSpec, header: str) -> Field | None:
    """The field a header names, whether or not its unit is valid (None if it names none)."""
    split = _split_header(spec, header)
    return None if split is None else split[1]


# Columns every table has: they say nothing about which table a file holds.
_SHARED = frozenset(
    (
        "id",
        "kind",
        "vendor",
        "series",
        "model",
        "type",
        "source",
        "notes",
        "mass",
        "voltage",
        "rated_power",
        "peak_torque",
    )
)


def infer_table(headers: list[str]) -> TableSpec | None:
    """Guess the table from headers: the one that recognises most of its distinctive columns."""
    scores: dict[str, int] = {}
    for spec in TABLES.values():
        names = {f.name for h in headers if (f := field_of_header(spec, h)) is not None}
        scores[spec.name] = len(names - _SHARED)
    best = max(scores.values())
    winners = [name for name, score in scores.items() if score == best]
    return TABLES[winners[0]] if best > 0 and len(winners) == 1 else None


# ---------------------------------------------------------------------------------- cells


def convert(raw: Any, column: Column, path: str) -> Any:
    """Convert one cell to its stored value: SI float, int, 0/1 flag, text, or None when empty."""
    if raw is None or (isinstance(raw, str) and not raw.strip()):
        return None
    fld = column.field
    if fld.quantity == TEXT:
        if isinstance(raw, (dict, list)):
            raise InputError(path, "must be text", raw)
        return check_text(str(raw).strip(), path, MAX_ID_CHARS if fld.name in ("id", "motor_id") else MAX_TEXT_CHARS)
    if fld.quantity == FLAG:
        return _flag(raw, path)
    if fld.quantity == INTEGER:
        return _integer(raw, path)
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        raise InputError(path, "must be a number", raw)
    text = raw.strip() if isinstance(raw, str) else raw
    try:
        number = float(text)
    except OverflowError:
        raise InputError(path, "must be a finite number", raw) from None
    except ValueError:
        if fld.quantity == DECIBEL:
            raise InputError(path, "must be a number (dB)", raw) from None
        return parse_quantity(text, fld.quantity, path)  # the cell carries its own unit
    value = number * column.factor
    if not math.isfinite(value):
        raise InputError(path, "must be a finite number", raw)
    return value


def _flag(raw: Any, path: str) -> int:
    if isinstance(raw, bool):
        return int(raw)
    text = str(raw).strip().lower()
    if text in _TRUE:
        return 1
    if text in _FALSE:
        return 0
    raise InputError(path, "must be yes or no", raw)


def _integer(raw: Any, path: str) -> int:
    if isinstance(raw, bool):
        raise InputError(path, "must be a whole number", raw)
    try:
        number = float(raw)
    except (TypeError, ValueError, OverflowError):
        raise InputError(path, "must be a whole number", raw) from None
    if not math.isfinite(number) or number != int(number):
        raise InputError(path, "must be a whole number", raw)
    return int(number)


# ---------------------------------------------------------------------------------- reading


@dataclass
class RawRow:
    """One row as read: its line, header -> raw cell, and (JSON motors) nested curve points."""

    line: int
    cells: dict[str, Any]
    curve: list[RawRow] = field(default_factory=list)


@dataclass
class RawFile:
    """A parsed file: headers (CSV: the header row; JSON: keys in order of appearance) and rows."""

    filename: str
    fmt: str
    headers: list[str]
    rows: list[RawRow]
    table: str | None = None
    header_lines: dict[str, int] = field(default_factory=dict)  # JSON: first line using each key


def read_csv(text: str, filename: str) -> RawFile:
    """Read CSV text; each row keeps the line it starts on. Raises InputErrors for ragged rows."""
    reader = csv.reader(io.StringIO(text))
    try:
        headers = [h.strip() for h in next(reader)]
    except StopIteration:
        raise InputError(filename, "is empty: expected a header row", has_value=False) from None
    except csv.Error as exc:
        raise InputError(where(filename, HEADER_LINE, "-"), f"is not valid CSV ({exc})", has_value=False) from None
    rows: list[RawRow] = []
    errors: list[InputError] = []
    seen: set[str] = set()
    for h in headers:
        if h in seen:
            errors.append(InputError(where(filename, HEADER_LINE, h), "column is given twice", has_value=False))
        seen.add(h)
    _raise(errors)
    last = reader.line_num
    try:
        for cells in reader:
            start, last = last + 1, reader.line_num
            if not any(c.strip() for c in cells):
                continue  # blank line
            if len(cells) != len(headers):
                errors.append(
                    InputError(
                        where(filename, start, "-"),
                        f"row has {len(cells)} cells but the header has {len(headers)} columns",
                        has_value=False,
                    )
                )
                continue
            rows.append(RawRow(start, dict(zip(headers, map(unescape_cell, cells), strict=True))))
    except csv.Error as exc:
        errors.append(InputError(where(filename, reader.line_num, "-"), f"is not valid CSV ({exc})", has_value=False))
    _raise(errors)
    return RawFile(filename, "csv", headers, rows)


class _Obj(dict[str, Any]):
    """A JSON object that remembers the line it starts on and any key given twice."""

    line = 0
    duplicates: tuple[str, ...] = ()


def _pairs(pairs: list[tuple[str, Any]]) -> _Obj:
    obj = _Obj(pairs)
    if len(obj) != len(pairs):
        counts = Counter(k for k, _ in pairs)
        obj.duplicates = tuple(k for k, n in counts.items() if n > 1)
    return obj


def _json_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise InputError("number", f"has more than {MAX_DIGITS} digits", text[:20] + "...")
    return int(text)


def _json_float(text: str) -> float:
    if len(text) > MAX_DIGITS:
        raise InputError("number", f"has more than {MAX_DIGITS} digits", text[:20] + "...")
    return float(text)


def _json_depth(text: str) -> int:
    """Deepest nesting of arrays and objects in JSON ``text``, strings skipped (a linear scan)."""
    depth = deepest = 0
    for m in _JSON_STRUCTURE.finditer(text):
        ch = m.group()
        if ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


class _LineDecoder(json.JSONDecoder):
    """json's pure-Python scanner with a hook that stamps every object with its start line."""

    def __init__(self, text: str) -> None:
        super().__init__(object_pairs_hook=_pairs, parse_int=_json_int, parse_float=_json_float)
        self._newlines = [i for i, ch in enumerate(text) if ch == "\n"]
        self._object: Callable[..., tuple[Any, int]] = vars(json.decoder)["JSONObject"]
        self.parse_object = self._parse_object
        self.scan_once = vars(json.scanner)["py_make_scanner"](self)

    def _parse_object(self, s_and_end: tuple[str, int], *args: Any) -> tuple[Any, int]:
        obj, end = self._object(s_and_end, *args)
        if isinstance(obj, _Obj):
            obj.line = bisect.bisect_left(self._newlines, s_and_end[1]) + 1
        return obj, end


def unescape_cell(cell: str) -> str:
    """A CSV cell as meant: export writes ``'=...`` for text starting with = + - @ (see ``escape_cell``)."""
    return cell[1:] if len(cell) > 1 and cell[0] == "'" and cell[1] in _FORMULA_START else cell


def escape_cell(value: Any) -> Any:
    """A text cell a spreadsheet would take for a formula (= + - @ tab CR first) gets a leading ``'``.

    OWASP, "CSV Injection": spreadsheets evaluate such cells; the apostrophe makes them text.
    Numbers are not text and stay numeric (a negative torque stays ``-1.5``).
    """
    if isinstance(value, str) and value[:1] in _FORMULA_START:
        return "'" + value
    return value


def check_text(text: str, path: str, limit: int) -> str:
    """A text cell: at most ``limit`` characters, valid Unicode, no NUL, control or bidi characters."""
    if len(text) > limit:
        raise InputError(path, f"is too long ({len(text)} characters; at most {limit})", text[:40] + "...")
    if not _valid_unicode(text):
        raise InputError(path, "is not valid Unicode text (a lone surrogate)", text)
    bad = next((c for c in text if (not c.isprintable() and c not in "\t\n") or c in _BIDI), None)
    if bad is not None:
        raise InputError(path, f"holds the invisible control character U+{ord(bad):04X}", text)
    return text


def _valid_unicode(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def read_json(text: str, filename: str) -> RawFile:
    """Read JSON: a list of row objects, or ``{"table": ..., "rows": [...]}`` as export writes it."""
    depth = _json_depth(text)
    if depth > MAX_JSON_DEPTH:
        raise InputError(filename, f"is nested too deeply ({depth} levels; a catalog file needs at most 4)",
                         has_value=False)
    try:
        data = _LineDecoder(text).decode(text)
    except RecursionError:
        raise InputError(filename, f"is nested too deeply (over {MAX_JSON_DEPTH} levels)", has_value=False) from None
    except InputError as exc:  # a number past MAX_DIGITS
        raise InputError(filename, f"holds a number that {exc.rule}", exc.value) from None
    except json.JSONDecodeError as exc:
        raise InputError(
            where(filename, exc.lineno, f"col {exc.colno}"), f"is not valid JSON ({exc.msg})", has_value=False
        ) from None
    table: str | None = None
    if isinstance(data, dict):
        table = data.get("table")
        if table is not None and (not isinstance(table, str) or table not in TABLES):
            raise InputError(
                where(filename, getattr(data, "line", 1), "table"),
                f"must be one of {', '.join(TABLES)}",
                table,
            )
        data = data.get("rows")
    if not isinstance(data, list) or not all(isinstance(r, dict) for r in data):
        raise InputError(filename, 'must hold a list of row objects, or {"table": ..., "rows": [...]}', has_value=False)
    headers: dict[str, int] = {}
    rows: list[RawRow] = []
    errors: list[InputError] = []
    for obj in data:
        line = getattr(obj, "line", 0)
        errors.extend(
            InputError(where(filename, line, k), "is given twice in this object", has_value=False)
            for k in getattr(obj, "duplicates", ())
        )
        cells = {k: v for k, v in obj.items() if k != "curve"}
        bad_key = next((k for k in cells if not _valid_unicode(k)), None)
        if bad_key is not None:
            errors.append(InputError(where(filename, line, "-"), "a key is not valid Unicode (a lone surrogate)",
                                     bad_key))
            continue
        for key in cells:
            headers.setdefault(key, line)
        points = obj.get("curve") or []
        if not isinstance(points, list) or not all(isinstance(p, dict) for p in points):
            errors.append(
                InputError(where(filename, line, "curve"), "must be a list of point objects", has_value=False)
            )
            points = []
        rows.append(RawRow(line, cells, [RawRow(getattr(p, "line", line), dict(p)) for p in points]))
    _raise(errors)
    return RawFile(filename, "json", list(headers), rows, table, headers)


def read_text(text: str, filename: str) -> RawFile:
    """CSV or JSON by file name, else by the first character."""
    lower = filename.lower()
    if lower.endswith(".json") or (not lower.endswith(".csv") and text.lstrip()[:1] in ("[", "{")):
        return read_json(text, filename)
    return read_csv(text, filename)


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


# ---------------------------------------------------------------------------------- rules
# Plausibility rules mirroring the shipped data's own checks (check_catalog.py, data/SOURCES.md).
# Each yields (field, rule); a rule fires only when the values it needs are given and positive.

Rule = Callable[[Mapping[str, Any], str], Iterator[tuple[str, str]]]


def _pos(v: Mapping[str, Any], *names: str) -> bool:
    return all(isinstance(v.get(n), (int, float)) and v[n] > 0 for n in names)


def motor_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "rated_torque", "peak_torque") and v["peak_torque"] < v["rated_torque"]:
        yield "peak_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if _pos(v, "rated_torque", "stall_torque") and v["stall_torque"] < v["rated_torque"] * (1 - 1e-6):
        yield "stall_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if _pos(v, "rotor_inertia", "rated_torque") and not 1e-6 < v["rotor_inertia"] / v["rated_torque"] < 1e-2:
        # catalogue range is ~1e-5..1e-3 s^2; a kg*cm^2 figure read as kg*m^2 lands far above
        yield (
            "rotor_inertia",
            (
                f"rotor_inertia / rated_torque = {v['rotor_inertia'] / v['rated_torque']:.2e} s^2 "
                "is outside the plausible 1e-6..1e-2 s^2 (unit slip? write the unit in the "
                "header, e.g. rotor_inertia [kg*cm^2])"
            ),
        )
    if _pos(v, "rotor_inertia", "rotor_inertia_brake") and v["rotor_inertia_brake"] < v["rotor_inertia"]:
        yield "rotor_inertia_brake", "must be >= rotor_inertia (the brake adds inertia)"
    if kind == "ac_servo":
        yield from _ac_servo_rules(v)
    elif kind == "small_dc":
        yield from _small_dc_rules(v)


def _ac_servo_rules(v: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    if _pos(v, "rated_speed", "max_speed") and v["max_speed"] < v["rated_speed"]:
        yield "max_speed", f"must be >= rated_speed ({units.to_rpm(v['rated_speed']):.6g} rpm)"
    if _pos(v, "rotor_inertia") and not 1e-8 < v["rotor_inertia"] < 1.0:
        yield "rotor_inertia", "is outside the plausible 1e-8..1 kg*m^2 for an AC servo (unit slip?)"
    if _pos(v, "rated_power", "rated_torque", "rated_speed"):
        mech = v["rated_torque"] * v["rated_speed"]
        dev = (mech - v["rated_power"]) / v["rated_power"]
        if abs(dev) > 0.15:
            yield (
                "rated_power",
                (
                    f"disagrees with rated_torque x rated_speed = {mech:.4g} W by {dev:+.0%} "
                    "(more than 15 %: check the units of torque, speed and power)"
                ),
            )
    if _pos(v, "mass") and not 0.05 < v["mass"] < 500:
        yield "mass", "is outside the plausible 0.05..500 kg for an AC servo"


def _small_dc_rules(v: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    if _pos(v, "voltage", "torque_constant", "winding_resistance", "no_load_speed"):
        inl = v.get("no_load_current") or 0.0
        ideal = (v["voltage"] - v["winding_resistance"] * inl) / v["torque_constant"]
        if abs(ideal - v["no_load_speed"]) / v["no_load_speed"] > 0.10:
            yield (
                "no_load_speed",
                (
                    f"disagrees by more than 10 % with (V - R*I_nl)/k_t = "
                    f"{units.to_rpm(ideal):.6g} rpm (check the units of k_t, R and speed)"
                ),
            )
    if _pos(v, "rated_torque", "stall_torque") and not v["rated_torque"] < v["stall_torque"]:
        yield "rated_torque", f"must be < stall_torque ({v['stall_torque']:.6g} N*m)"
    if _pos(v, "rated_speed", "no_load_speed") and not v["rated_speed"] < v["no_load_speed"]:
        yield "rated_speed", f"must be < no_load_speed ({units.to_rpm(v['no_load_speed']):.6g} rpm)"


def gearbox_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "efficiency") and v["efficiency"] > 1:
        yield "efficiency", "must be in (0, 1] (write 95 % or 0.95)"
    rated = v.get("rated_output_torque")
    for name in ("max_output_torque", "emergency_stop_torque"):
        if _pos(v, "rated_output_torque", name) and v[name] < rated:
            yield name, f"must be >= rated_output_torque ({rated:.6g} N*m)"
    if _pos(v, "max_output_torque", "emergency_stop_torque") and v["emergency_stop_torque"] < v["max_output_torque"]:
        yield "emergency_stop_torque", f"must be >= max_output_torque ({v['max_output_torque']:.6g} N*m)"
    if _pos(v, "input_bore_min", "input_bore_max") and v["input_bore_min"] > v["input_bore_max"]:
        yield "input_bore_min", f"must be <= input_bore_max ({v['input_bore_max'] * 1e3:.6g} mm)"
    if _pos(v, "max_input_speed", "rated_input_speed") and v["max_input_speed"] < v["rated_input_speed"]:
        yield (
            "max_input_speed",
            f"must be >= rated_input_speed ({units.to_rpm(v['rated_input_speed']):.6g} rpm)",
        )
    if v.get("direction") is not None and v["direction"] not in (1, -1):
        yield "direction", "must be 1 (output turns like the input) or -1"
    if kind == "servo_gearbox":
        if _pos(v, "inertia_input") and not v["inertia_input"] < 0.1:
            yield "inertia_input", "is outside the plausible 0..0.1 kg*m^2 (unit slip?)"
        elif _pos(v, "inertia_input", "rated_output_torque") and not 1e-8 < v["inertia_input"] / rated < 1e-3:
            yield (
                "inertia_input",
                (
                    f"inertia_input / rated_output_torque = {v['inertia_input'] / rated:.2e} s^2 "
                    "is outside the plausible 1e-8..1e-3 s^2 (unit slip?)"
                ),
            )
        if v.get("stages") is not None and v["stages"] not in (1, 2, 3):
            yield "stages", "must be 1, 2 or 3"


def drive_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "continuous_current", "peak_current") and v["peak_current"] < v["continuous_current"]:
        yield "peak_current", f"must be >= continuous_current ({v['continuous_current']:.6g} A)"


def curve_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if v.get("continuous_torque") is None and v.get("peak_torque") is None:
        yield "continuous_torque", "a curve point needs continuous_torque, peak_torque or both"
    if _pos(v, "continuous_torque", "peak_torque") and v["peak_torque"] < v["continuous_torque"]:
        yield "peak_torque", f"must be >= continuous_torque ({v['continuous_torque']:.6g} N*m)"


RULES: dict[str, Rule] = {
    "motor": motor_rules,
    "gearbox": gearbox_rules,
    "drive": drive_rules,
    "curve": curve_rules,
}


def _raise(errors: list[InputError]) -> None:
    from drivetrain.errors import InputErrors

    if errors:
        raise InputErrors(errors)
