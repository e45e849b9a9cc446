"""Counts of the shipped catalog by table and by vendor, as the Markdown tables of the README's
catalog section: ``python scripts/catalog_counts.py``.

Only the shipped data is counted (a temporary data folder, so no user catalog is read); a row is
"traced" when it names its vendor document and is not flagged unverified (drivetrain.catalog.schema.trace).
A table counts the AC servo motors and drives with a voltage class (read, or by the vendor's model-code
rule: drivetrain.catalog.voltage_class) and the rows with values computed from others
(drivetrain.catalog.derive); the last one the drives with output current ratings, by vendor.
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections import Counter
from typing import Any


def tables() -> str:
    """The Markdown tables (by table and kind, by vendor, voltage classes, drive currents) of the shipped
    data the catalog reads now."""
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
    out += ["", "| table | kind | rows | with voltage class | of them by model-code rule | voltage class unknown "
            "| rows with derived values |", "|---|---|---:|---:|---:|---:|---:|"]
    for name, kind in (("motor", "ac_servo"), ("drive", "servo_drive")):
        rows = [r for r in rows_of[name] if r["kind"] == kind]
        given = [r for r in rows if r["voltage_V"] is not None]
        by_rule = sum("voltage" in str(r.get("derived") or "").split(",") for r in given)
        derived = sum(bool(r.get("derived")) for r in rows)
        out.append(f"| {name} | {kind} | {len(rows)} | {len(given)} | {by_rule} | {len(rows) - len(given)} "
                   f"| {derived} |")
    out += ["", *_drive_currents(rows_of["drive"]), "", *_pairings()]
    return "\n".join(out)


def _pairings() -> list[str]:
    """The stated motor-drive pairings (drives_pairing.csv) by source: a vendor document or a third-party
    transcription (flagged unverified); a paired motor without a torque constant is judged by its pairing."""
    from drivetrain.catalog import db

    with db.reader() as rd:
        sources = rd.drive_pair_sources()
    out = ["| pairings stated by | pairs | motors |", "|---|---:|---:|"]
    for label, verified in (("the vendor's document", True), ("a third-party transcription (unverified)", False)):
        pairs = [k for k, v in sources.items() if v["verified"] is verified]
        out.append(f"| {label} | {len(pairs)} | {len({m for m, _ in pairs})} |")
    return out


def _drive_currents(drives: list[dict[str, Any]]) -> list[str]:
    """Drives with output current ratings by vendor: both continuous and peak (the selection checks them), only the
    continuous one (its peak check is unknown), and how many of those are flagged unverified (a transcription)."""
    from drivetrain.catalog.schema import trace

    out = ["| drive vendor | drives | continuous and peak current | continuous only | of these unverified |",
           "|---|---:|---:|---:|---:|"]
    by_vendor: dict[str, list[dict[str, Any]]] = {}
    for r in drives:
        by_vendor.setdefault(str(r["vendor"]), []).append(r)
    for vendor in sorted(by_vendor, key=str.lower):
        rows = by_vendor[vendor]
        both = [r for r in rows if r["continuous_current_A"] is not None and r["peak_current_A"] is not None]
        cont = [r for r in rows if r["continuous_current_A"] is not None and r["peak_current_A"] is None]
        flagged = sum(trace(r)[0] for r in both + cont)
        out.append(f"| {vendor} | {len(rows)} | {len(both)} | {len(cont)} | {flagged} |")
    return out


def main() -> int:
    with tempfile.TemporaryDirectory() as folder:
        os.environ["DRIVETRAIN_DATA_DIR"] = folder
        os.environ.pop("DRIVETRAIN_CATALOG", None)
        print(tables())
    return 0


if __name__ == "__main__":
    sys.exit(main())
