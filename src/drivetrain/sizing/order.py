"""The order sheet of an answer: one row per part of the axis, each a catalog part that can be ordered as
written or a vendor-neutral specification a buyer can send to any vendor (docs/order-sheet.md).

``order_sheet(result)`` reads the answer's own blocks (the given motor or the selected candidate, its
drive and regen blocks, the gearbox rows and the transmission, the mechanism and brake checks, the
guide) and the catalog rows of the parts it names (through the catalog API, never its files). It adds
no check of its own to the verdict: a row that cannot be completed lists its open points, and a
sheet with an open point is not complete, whatever the verdict says.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from drivetrain.sizing import order_rows
from drivetrain.sizing.order_spec import (
    BRAKE_SERVICE_FACTOR,
    E12,
    PARTS,
    OrderRow,
    brake_holding_torque,
    choice_text,
    code_choices,
    nearest_standard,
    peak_duration,
    required_rating,
    standard_values,
)

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

__all__ = ["BOM_COLUMNS", "BRAKE_SERVICE_FACTOR", "E12", "PARTS", "OrderRow", "OrderSheet", "bom_records",
           "brake_holding_torque", "code_choices", "nearest_standard", "order_sheet", "peak_duration",
           "required_rating", "standard_values"]


@dataclass(frozen=True)
class OrderSheet:
    """The order sheet of one answer.

    Attributes
    ----------
    axis : str
        The axis's name.
    rows : tuple of OrderRow
        One row per part, in the order of ``PARTS``.
    """

    axis: str
    rows: tuple[OrderRow, ...]

    @property
    def complete(self) -> bool:
        """Every row is a catalog part orderable as written with nothing open."""
        return all(r.complete for r in self.rows)

    def to_dict(self) -> dict[str, Any]:
        """The JSON ``order`` block: ``complete``, the rows by status (``complete_rows``, ``incomplete_rows``,
        ``specification_rows``), ``rows``, ``open_points``."""
        counts = {f"{s}_rows": sum(r.status == s for r in self.rows)
                  for s in ("complete", "incomplete", "specification")}
        return {"complete": self.complete, **counts, "rows": [r.to_dict() for r in self.rows],
                "open_points": [f"{r.part}: {p}" for r in self.rows for p in r.open_points]}


BOM_COLUMNS = ("axis", "part", "kind", "status", "quantity", "vendor", "order_code", "catalog_id", "name",
               "specification", "choose", "open_points", "unverified", "source")
"""The columns of ``drivetrain size --bom FILE.csv`` (docs/axis-file.md)."""


def bom_records(sheet: OrderSheet | dict[str, Any], axis: str | None = None) -> list[dict[str, str]]:
    """The rows of an order sheet (or its ``to_dict()``) as text cells of ``BOM_COLUMNS``: the spec as
    ``key=value`` pairs joined by ``; ``, the positions to choose and the open points joined by ``; ``."""
    d = sheet.to_dict() if isinstance(sheet, OrderSheet) else sheet
    name = axis if axis is not None else (sheet.axis if isinstance(sheet, OrderSheet) else "")
    out = []
    for r in d["rows"]:
        out.append({
            "axis": name, "part": r["part"], "kind": r["kind"], "status": r["status"], "quantity": str(r["quantity"]),
            "vendor": r["vendor"] or "", "order_code": r["order_code"] or "", "catalog_id": r["catalog_id"] or "",
            "name": r["name"],
            "specification": "; ".join(f"{k}={_cell(v)}" for k, v in r["spec"].items() if v is not None),
            "choose": "; ".join(choice_text(c) for c in r["choose"]), "open_points": "; ".join(r["open_points"]),
            "unverified": {True: "yes", False: "no", None: ""}[r["unverified"]], "source": r["source"] or ""})
    return out


def _cell(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return " ".join(_cell(x) for x in v)
    return str(v)


def order_sheet(result: SizingResult) -> OrderSheet:
    """The order sheet of ``result``: one row per part (motor, drive, gearbox, braking resistor, brake,
    coupling, screw, guide; the ones the axis has)."""
    ctx = order_rows.context(result)
    out: list[OrderRow] = [order_rows.motor_row(ctx), order_rows.drive_row(ctx), *order_rows.gearbox_rows(ctx)]
    resistor = order_rows.resistor_row(ctx)
    if resistor is not None:
        out.append(resistor)
    out.extend(order_rows.transmission_part_rows(ctx))
    out.extend(order_rows.mechanism_rows(ctx))
    order = {p: k for k, p in enumerate(PARTS)}
    return OrderSheet(axis=result.axis.name, rows=tuple(sorted(out, key=lambda r: order[r.part])))
