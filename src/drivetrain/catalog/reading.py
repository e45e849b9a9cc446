"""Reading a catalog file's text into raw rows: CSV with the line each row starts on, JSON with the line
of every object, within the limits of an import (nesting, digits), and the spreadsheet-formula escape.

Nothing is converted here (``catalog.columns`` does that); every problem is an ``InputError``
whose field is ``file:line:column``.
"""

from __future__ import annotations

import bisect
import csv
import io
import json
import json.decoder
import json.scanner
import re
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from drivetrain.catalog.columns import HEADER_LINE, valid_unicode, where
from drivetrain.catalog.schema import TABLES
from drivetrain.errors import InputError

MAX_DIGITS = 400
"""Longest number in a JSON file [characters]: a float needs 17 significant digits."""
MAX_JSON_DEPTH = 16
"""Deepest nesting of a JSON file: ``{"rows": [{"curve": [{...}]}]}`` is 4."""
_JSON_STRUCTURE = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]')
_FORMULA_START = frozenset("=+-@\t\r")


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
        bad_key = next((k for k in cells if not valid_unicode(k)), None)
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


def _raise(errors: list[InputError]) -> None:
    from drivetrain.errors import InputErrors

    if errors:
        raise InputErrors(errors)
