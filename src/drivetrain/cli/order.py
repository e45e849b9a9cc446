"""The order sheet after the answer (``drivetrain size``): one table row per part, then each row's
specification and open points (``drivetrain.sizing.order``). The values are SI, as in ``--json``, or in the
system of ``--units`` (torques, inertias, lengths and forces, as the other tables: ``cli.quantities``)."""

from __future__ import annotations

from typing import Any

from drivetrain.cli.quantities import TableUnits
from drivetrain.report.order import _value, order_cells, spec_items, spec_text, state_text
from drivetrain.terminal import Col, print_table

__all__ = ["ORDER_COLUMNS", "bom_text", "order_cells", "print_order", "print_result_order", "spec_text",
           "spec_text_in", "write_bom"]

ORDER_COLUMNS = (Col("part"), Col("status"), Col("qty", right=True, number=True), Col("vendor", abbreviate=True),
                 Col("order code"), Col("what"))
"""The order-sheet table's columns (none is left out to fit a terminal); the cells are the report's
(``drivetrain.report.order.order_cells``)."""


_QUANTITY = {"N*m": ("torque", 1.0), "kg*m^2": ("inertia", 1.0), "mm": ("length", 1e-3), "N": ("force", 1.0)}
"""A spec unit (``report.order.UNIT_SUFFIXES``) that ``--units`` converts: its quantity and the SI value of
one unit; the others (rpm, V, A, ohm, J, W, s, h, arcmin, stiffnesses, k_T) print the same in every system."""


def spec_text_in(spec: dict[str, Any], units: TableUnits | None = None) -> str:
    """A row's specification in one line (``report.order.spec_text``) with its torques, inertias, lengths and
    forces in the system of ``units`` (``--units``); in SI the report's text exactly."""
    if units is None or units.system == "si":
        return spec_text(spec)
    parts = []
    for label, value, unit in spec_items(spec):
        if unit in _QUANTITY and isinstance(value, (int, float)) and not isinstance(value, bool):
            quantity, si = _QUANTITY[unit]
            parts.append(f"{label} {units.q(float(value) * si, quantity, unit, 1.0 / si)}")
        else:
            parts.append(f"{label} {_value(value)}{' ' + unit if unit else ''}")
    return "; ".join(parts)


def print_order(console: Any, order: dict[str, Any], units: TableUnits | None = None) -> None:
    """The section "order sheet": the table, then each row's specification (in ``units``) and open points."""
    print_table(console, f"order sheet ({state_text(order)})", ORDER_COLUMNS, order_cells(order))
    for r in order["rows"]:
        text = spec_text_in(r["spec"], units)
        if text:
            console.print(f"  {r['part']}: {text}", markup=False, highlight=False)
        for p in r["open_points"]:
            console.print(f"    open: {p}", markup=False, highlight=False)
    if any(r["unverified"] for r in order["rows"]):
        console.print("† unverified catalog data: see unverified_reason in --json", markup=False, highlight=False)


def print_result_order(console: Any, result: Any, units: TableUnits | None = None) -> None:
    """The order sheet of a ``SizingResult`` (the same rows as its JSON ``order`` block), in ``units``."""
    from drivetrain.sizing.order import order_sheet

    print_order(console, order_sheet(result).to_dict(), units)


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
