"""Counts of the shipped catalog by table and by vendor, as the Markdown tables of the README's
catalog section: ``python scripts/catalog_counts.py``.

Only the shipped data is counted (a temporary data folder, so no user catalog is read); a row is
"traced" when it names its vendor document and is not flagged unverified (drivetrain.catalog.schema.trace).
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections import Counter


def tables() -> str:
    """The two Markdown tables (by table and kind, by vendor) of the shipped data the catalog reads now."""
    from drivetrain.catalog import db
    from drivetrain.catalog.schema import CURVE, DATA_VERSION, ROW_TABLES, trace

    with db.reader() as rd:
        rows_of = {spec.name: [r for r in rd.rows(spec) if r.get("origin", "builtin") == "builtin"]
                   for spec in ROW_TABLES}
        points = rd.count(CURVE)
    out = [f"Shipped catalog, data version {DATA_VERSION}.", "",
           "| table | kind | rows | traced | unverified |", "|---|---|---:|---:|---:|"]
    for name, rows in rows_of.items():
        kinds = Counter(str(r["kind"]) for r in rows)
        for kind in sorted(kinds) or ["-"]:
            of_kind = [r for r in rows if r["kind"] == kind]
            flagged = sum(trace(r)[0] for r in of_kind)
            out.append(f"| {name} | {kind} | {len(of_kind)} | {len(of_kind) - flagged} | {flagged} |")
    out += [f"| curve points | - | {points} | - | - |", "",
            "| vendor | motors | gearbox rows | drives |", "|---|---:|---:|---:|"]
    by_vendor: dict[str, Counter[str]] = {}
    for name, rows in rows_of.items():
        for r in rows:
            by_vendor.setdefault(str(r["vendor"]), Counter())[name] += 1
    for vendor in sorted(by_vendor, key=str.lower):
        c = by_vendor[vendor]
        out.append(f"| {vendor} | {c['motor']} | {c['gearbox']} | {c['drive']} |")
    out.append(f"| **{len(by_vendor)} vendors** | {sum(c['motor'] for c in by_vendor.values())} | "
               f"{sum(c['gearbox'] for c in by_vendor.values())} | {sum(c['drive'] for c in by_vendor.values())} |")
    return "\n".join(out)


def main() -> int:
    with tempfile.TemporaryDirectory() as folder:
        os.environ["DRIVETRAIN_DATA_DIR"] = folder
        os.environ.pop("DRIVETRAIN_CATALOG", None)
        print(tables())
    return 0


if __name__ == "__main__":
    sys.exit(main())
