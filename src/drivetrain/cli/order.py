"""The order sheet after the answer (``drivetrain size``): one table row per part, then each row's
specification and open points (``drivetrain.sizing.order``; the values are SI, as in ``--json``)."""

from __future__ import annotations

from typing import Any

from drivetrain.report.order import order_cells, spec_text, state_text
from drivetrain.terminal import Col, print_table

__all__ = ["ORDER_COLUMNS", "bom_text", "order_cells", "print_order", "print_result_order", "spec_text", "write_bom"]

ORDER_COLUMNS = (Col("part"), Col("status"), Col("qty", right=True, number=True), Col("vendor", abbreviate=True),
                 Col("order code"), Col("what"))
"""The order-sheet table's columns (none is left out to fit a terminal); the cells are the report's
(``drivetrain.report.order.order_cells``)."""


def print_order(console: Any, order: dict[str, Any]) -> None:
    """The section "order sheet": the table, then each row's specification and open points."""
    print_table(console, f"order sheet ({state_text(order)})", ORDER_COLUMNS, order_cells(order))
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
