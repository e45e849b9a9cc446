"""The order sheet in the report (``sizing.order``): one table of the parts (status, vendor, order code) and
one of each part's specification and open points. The CLI prints the same cells (``cli/order.py``)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from drivetrain.report.blocks import Cell, Table

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

UNIT_SUFFIXES = (("_Nm_per_arcmin", "N*m/arcmin"), ("_Nm_per_rad", "N*m/rad"), ("_NmA", "N*m/A"),
                 ("_kgm2", "kg*m^2"), ("_Nm", "N*m"), ("_rpm", "rpm"), ("_ohm", "ohm"), ("_arcmin", "arcmin"),
                 ("_mm", "mm"), ("_A", "A"), ("_V", "V"), ("_s", "s"), ("_J", "J"), ("_W", "W"), ("_N", "N"),
                 ("_h", "h"))
"""A spec key's unit suffix and how it prints (the keys of ``OrderRow.spec`` carry their SI unit)."""

STATUS_CLASS = {"complete": "pass", "incomplete": "warn", "specification": "warn"}
"""The report's cell style of a row's status."""


def code_cell(r: dict[str, Any]) -> str:
    """A row's order code as written; the catalog id with the positions to choose; or "specification"."""
    if r["order_code"]:
        code = r["order_code"]
    elif r["catalog_id"] and r["choose"]:
        code = f"{r['catalog_id']} (choose position {', '.join(str(c['position']) for c in r['choose'])})"
    elif r["catalog_id"]:
        code = f"{r['catalog_id']} (not as written)"
    else:
        code = "specification"
    return code + (" †" if r["unverified"] else "")


def order_cells(order: dict[str, Any]) -> list[tuple[str, ...]]:
    """The parts table's cells of the JSON ``order`` block, one tuple per row: part, status, quantity, vendor,
    order code (``code_cell``), what."""
    return [(r["part"].replace("_", " "), r["status"], str(r["quantity"]), r["vendor"] or "-", code_cell(r), r["name"])
            for r in order["rows"]]


def spec_items(spec: dict[str, Any]) -> list[tuple[str, Any, str]]:
    """A row's specification as (label, value, unit) with the unit read from the key's suffix (``_Nm``:
    N*m, ...); the keys without a value left out."""
    out = []
    for key, value in spec.items():
        if value is None:
            continue
        name, unit = key, ""
        for suffix, shown in UNIT_SUFFIXES:
            if key.endswith(suffix):
                name, unit = key[: -len(suffix)], shown
                break
        out.append((name.replace("_", " "), value, unit))
    return out


def spec_text(spec: dict[str, Any]) -> str:
    """A row's specification in one line: ``name value unit`` pairs (the unit from the key's suffix)."""
    return "; ".join(f"{label} {_value(value)}{' ' + unit if unit else ''}" for label, value, unit in spec_items(spec))


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return "n/a" if not math.isfinite(v) else f"{v:.4g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(_value(x) for x in v)
    return str(v)


def state_text(order: dict[str, Any]) -> str:
    """The sheet's state in words: complete, or how many rows are complete, incomplete and specifications."""
    if order["complete"]:
        return "complete: every part orderable as written"
    return (f"{order['complete_rows']} complete, {order['incomplete_rows']} incomplete, "
            f"{order['specification_rows']} specification(s): not every part can be ordered as written")


def order_tables(result: SizingResult) -> list[Table]:
    """The report's order-sheet tables: the parts, and each part's specification and open points."""
    from drivetrain.sizing.order import order_sheet

    order = order_sheet(result).to_dict()
    parts = [[Cell(a), Cell(b, STATUS_CLASS.get(b, "")), Cell(q), Cell(v), Cell(code, "strong"), Cell(what)]
             for a, b, q, v, code, what in order_cells(order)]
    note = ("† unverified catalog data (not traced to a vendor document). A specification or an incomplete row "
            "is not a pass: its open points say what is still to choose or check.")
    details = [[Cell(r["part"].replace("_", " ")), Cell(spec_text(r["spec"]) or "-"),
                Cell("; ".join(r["open_points"]) or "none", "warn" if r["open_points"] else "")]
               for r in order["rows"]]
    return [Table("order", f"Order sheet ({state_text(order)})", ["part", "status", "qty", "vendor", "order code",
                                                                  "what"], parts, "llrlll", note=note),
            Table("order-spec", "Specifications and open points", ["part", "specification", "open points"],
                  details, "lll", widths=[1.2, 4.0, 3.2])]
