"""Catalog columns: a header (``name``, ``name [unit]``, ``name_<unit suffix>``) resolved against a table,
units converted to SI, and one cell converted to its stored value (SI float, int, flag or checked text);
the way back for an export or an edit: a field's ``header`` and a stored value in its unit (``display``).

Every problem is an ``InputError`` whose field is ``file:line:column``.
"""

from __future__ import annotations

import difflib
import functools
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from drivetrain import units
from drivetrain.catalog.schema import (
    DECIBEL,
    EXTRA_QUANTITIES,
    FLAG,
    INTEGER,
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
_BIDI = frozenset("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")
_TRUE = {"yes", "y", "true", "1"}
_FALSE = {"no", "n", "false", "0"}


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


def check_text(text: str, path: str, limit: int) -> str:
    """A text cell: at most ``limit`` characters, valid Unicode, no NUL, control or bidi characters."""
    if len(text) > limit:
        raise InputError(path, f"is too long ({len(text)} characters; at most {limit})", text[:40] + "...")
    if not valid_unicode(text):
        raise InputError(path, "is not valid Unicode text (a lone surrogate)", text)
    bad = next((c for c in text if (not c.isprintable() and c not in "\t\n") or c in _BIDI), None)
    if bad is not None:
        raise InputError(path, f"holds the invisible control character U+{ord(bad):04X}", text)
    return text


def valid_unicode(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def header(fld: Field) -> str:
    """Export header of a field: ``name [unit]``, or the bare name for text and pure numbers."""
    return f"{fld.name} [{fld.unit}]" if fld.unit else fld.name


def display(fld: Field, value: Any) -> Any:
    """A stored SI value in the field's export unit, rounded to 12 significant digits."""
    if fld.quantity == FLAG and value is not None:
        return "yes" if value else "no"
    if value is None or fld.quantity == TEXT or not fld.unit or fld.unit == "dB":
        return value
    return float(f"{value / _unit_si(fld.unit, fld.quantity):.12g}")


@functools.cache
def _unit_si(unit: str, quantity: str) -> float:
    return parse_quantity(f"1 {unit}", quantity, unit)


def did_you_mean(value: str, known: Sequence[str]) -> str:
    """"; did you mean A, B?" naming up to three ids close to ``value`` (case ignored), or ""."""
    by_upper = {k.upper(): k for k in known}
    close = difflib.get_close_matches(value.upper(), list(by_upper), n=3, cutoff=0.6)
    return f"; did you mean {', '.join(by_upper[c] for c in close)}?" if close else ""
