"""The order sheet after the answer (``drivetrain size``): one table row per part, then each row's
specification and open points (``drivetrain.sizing.order``; the values are SI, as in ``--json``)."""

from __future__ import annotations

import math
from typing import Any

from drivetrain.cli.tables import Col, print_table

ORDER_COLUMNS = (Col("part"), Col("status"), Col("qty", right=True, number=True), Col("vendor", abbreviate=True),
                 Col("order code"), Col("what"))
"""The order-sheet table's columns (none is left out to fit a terminal)."""

UNIT_SUFFIXES = (("_Nm_per_arcmin", "N*m/arcmin"), ("_Nm_per_rad", "N*m/rad"), ("_NmA", "N*m/A"),
                 ("_kgm2", "kg*m^2"), ("_Nm", "N*m"), ("_rpm", "rpm"), ("_ohm", "ohm"), ("_arcmin", "arcmin"),
                 ("_mm", "mm"), ("_A", "A"), ("_V", "V"), ("_s", "s"), ("_J", "J"), ("_W", "W"), ("_N", "N"),
                 ("_h", "h"))
"""A spec key's unit suffix and how it prints."""


def order_cells(order: dict[str, Any]) -> list[tuple[str, ...]]:
    """The table's cells of the JSON ``order`` block, one tuple per row (``ORDER_COLUMNS``): the order code
    as written, or the catalog id with "(choose ...)" where positions are open, or "specification"."""
    out: list[tuple[str, ...]] = []
    for r in order["rows"]:
        if r["order_code"]:
            code = r["order_code"]
        elif r["catalog_id"] and r["choose"]:
            code = f"{r['catalog_id']} (choose position {', '.join(str(c['position']) for c in r['choose'])})"
        elif r["catalog_id"]:
            code = f"{r['catalog_id']} (not as written)"
        else:
            code = "specification"
        flag = " †" if r["unverified"] else ""
        out.append((r["part"].replace("_", " "), r["status"], str(r["quantity"]), r["vendor"] or "-", code + flag,
                    r["name"]))
    return out


def spec_text(spec: dict[str, Any]) -> str:
    """A row's specification in one line: ``name value unit`` pairs (the unit from the key's suffix)."""
    parts = []
    for key, value in spec.items():
        if value is None:
            continue
        name, unit = key, ""
        for suffix, shown in UNIT_SUFFIXES:
            if key.endswith(suffix):
                name, unit = key[: -len(suffix)], shown
                break
        parts.append(f"{name.replace('_', ' ')} {_value(value)}{' ' + unit if unit else ''}")
    return "; ".join(parts)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return "n/a" if not math.isfinite(v) else f"{v:.4g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(_value(x) for x in v)
    return str(v)


def print_order(console: Any, order: dict[str, Any]) -> None:
    """The section "order sheet": the table, then each row's specification and open points."""
    state = ("complete: every part orderable as written" if order["complete"] else
             f"{order['complete_rows']} complete, {order['incomplete_rows']} incomplete, "
             f"{order['specification_rows']} specification(s): not every part can be ordered as written")
    print_table(console, f"order sheet ({state})", ORDER_COLUMNS, order_cells(order))
    for r in order["rows"]:
        text = spec_text(r["spec"])
        if text:
            console.print(f"  {r['part']}: {text}", markup=False, highlight=False)
        for p in r["open_points"]:
            console.print(f"    open: {p}", markup=False, highlight=False)
    if any(r["unverified"] for r in order["rows"]):
        console.print("† unverified catalog data: see unverified_reason in --json", markup=False, highlight=False)


def print_result_order(console: Any, result: Any) -> None:
    """The order sheet of a ``SizingResult`` (the same rows as its JSON ``order`` block)."""
    from drivetrain.sizing.order import order_sheet

    print_order(console, order_sheet(result).to_dict())


def bom_text(result: Any) -> str:
    """The order sheet as CSV text: a header of ``sizing.order.BOM_COLUMNS``, one line per part."""
    import csv
    import io

    from drivetrain.sizing.order import BOM_COLUMNS, bom_records, order_sheet

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(BOM_COLUMNS), lineterminator="\n")
    writer.writeheader()
    writer.writerows(bom_records(order_sheet(result)))
    return buf.getvalue()


def write_bom(path: str, result: Any) -> None:
    """``--bom FILE.csv``: the order sheet written whole or not at all (``drivetrain.files.write_atomic``)."""
    from drivetrain.files import write_atomic

    text = bom_text(result)
    write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8"), "--bom")
