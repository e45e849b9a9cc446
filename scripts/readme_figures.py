"""The README's figures of the code and the catalog, computed from them: the single source of those numbers.

The README marks each such number inline, ``<!--fig:NAME-->364<!--/fig-->`` (invisible when rendered), and
the catalog's count tables between ``<!-- catalog-counts:begin -->`` and ``<!-- catalog-counts:end -->``
(``scripts/catalog_counts.py``). This script computes every one of them from the shipped catalog and the
shipped examples:

    .venv/bin/python scripts/readme_figures.py             # print the figures
    .venv/bin/python scripts/readme_figures.py --check     # exit 1, with a diff, if README.md differs
    .venv/bin/python scripts/readme_figures.py --write     # rewrite them in README.md
    .venv/bin/python scripts/readme_figures.py --write --pictures   # and the report pictures in docs/

``--pictures`` runs ``scripts/make_report_images.py`` (Debian's Chromium: ``make browser``), which
redraws ``docs/report-*.png`` (the catalog version and counts they show included). Run it after any change
to the catalog data or to what a sizing answers; ``tests/project/test_readme_figures.py`` fails until the
README's numbers are the ones computed here. Measured figures (benchmarks) are not generated: they say
what was measured and when.
"""

from __future__ import annotations

import argparse
import difflib
import os
import re
import sys
import tempfile
from collections import Counter
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
FIGURE = re.compile(r"<!--fig:(?P<name>[a-z_]+)-->(?P<value>.*?)<!--/fig-->")
COUNTS = re.compile(r"(<!-- catalog-counts:begin -->\n)(.*?)(\n<!-- catalog-counts:end -->)", re.S)


def _n(value: int) -> str:
    """A count as the README writes it: 1,588."""
    return f"{value:,}"


def figures() -> dict[str, str]:
    """Every figure the README marks, by name, as text (reads the catalog the process is set up with)."""
    import numpy as np

    from drivetrain import catalog
    from drivetrain.catalog import db
    from drivetrain.catalog.schema import DATA_VERSION, ROW_TABLES, trace

    with db.reader() as rd:
        rows = {spec.name: [r for r in rd.rows(spec) if r.get("origin", "builtin") == "builtin"]
                for spec in ROW_TABLES}
    flagged = sum(trace(r)[0] for table in rows.values() for r in table)
    total = sum(len(table) for table in rows.values())
    kinds = {name: Counter(str(r["kind"]) for r in table) for name, table in rows.items()}
    servo = [r for r in rows["motor"] if r["kind"] == "ac_servo"]
    motors = catalog.motors()
    shipped = motors.origin == "builtin"
    drives = catalog.drives()
    drives = drives.take(np.flatnonzero(drives.origin == "builtin"))

    from drivetrain.sizing.pipeline import size

    selection = size(ROOT / "examples" / "ball_screw.yaml").selection
    out = {
        "data_version": DATA_VERSION,
        "ac_servo_motors": _n(len(servo)),
        "ac_servo_vendors": _n(len({r["vendor"] for r in servo})),
        "ac_servo_traced": _n(sum(not trace(r)[0] for r in servo)),
        "servo_gearbox_rows": _n(kinds["gearbox"]["servo_gearbox"]),
        "small_dc_motors": _n(kinds["motor"]["small_dc"]),
        "small_gearheads": _n(kinds["gearbox"]["small_gearhead"]),
        "drives": _n(len(drives)),
        "drives_with_currents": _n(int(np.isfinite(drives.continuous_current).sum())),
        "motors": _n(len(rows["motor"])),
        "motor_vendors": _n(len({r["vendor"] for r in rows["motor"]})),
        "traced_rows": _n(total - flagged),
        "unverified_rows": _n(flagged),
        "derived_rated_torques": _n(int(np.sum(shipped & (motors.rated_torque_basis == "derived P/omega")))),
        "ball_screw_candidates": _n(0 if selection is None else selection.evaluated or 0),
        "ball_screw_passing": _n(0 if selection is None else selection.passing or 0),
        "ball_screw_selected": "none" if selection is None or selection.selected is None else selection.selected.motor,
    }
    return out


def counts() -> str:
    """The catalog's count tables (scripts/catalog_counts.py)."""
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        from catalog_counts import tables
    finally:
        sys.path.remove(str(ROOT / "scripts"))
    text: str = tables()
    return text


def render(text: str, figs: dict[str, str], tables: str) -> str:
    """``text`` (the README) with every marked figure and the count tables as computed."""
    unknown = sorted({m["name"] for m in FIGURE.finditer(text)} - set(figs))
    if unknown:
        raise KeyError(f"README.md marks figures this script does not compute: {', '.join(unknown)}")
    text = FIGURE.sub(lambda m: f"<!--fig:{m['name']}-->{figs[m['name']]}<!--/fig-->", text)
    if not COUNTS.search(text):
        raise KeyError("README.md has no <!-- catalog-counts:begin --> ... <!-- catalog-counts:end --> block")
    return COUNTS.sub(lambda m: m.group(1) + tables + m.group(3), text)


def _isolated(work: Callable[[], int]) -> int:
    """Run ``work`` on the shipped catalog only: a temporary data folder, no user catalog."""
    with tempfile.TemporaryDirectory() as folder:
        os.environ["DRIVETRAIN_DATA_DIR"] = folder
        os.environ["DRIVETRAIN_CACHE_DIR"] = folder
        os.environ.pop("DRIVETRAIN_CATALOG", None)
        return work()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="exit 1 (with a diff) when README.md differs")
    mode.add_argument("--write", action="store_true", help="rewrite the figures in README.md")
    parser.add_argument("--pictures", action="store_true", help="also redraw docs/report-*.png (needs Chromium)")
    args = parser.parse_args(argv)

    def work() -> int:
        figs = figures()
        old = README.read_text(encoding="utf-8")
        new = render(old, figs, counts())
        if args.check:
            if new != old:
                sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                                           "README.md", "README.md (computed)"))
                return 1
            print("README.md figures are current")
        elif args.write:
            if new != old:
                README.write_text(new, encoding="utf-8")
            print("README.md " + ("rewritten" if new != old else "already current"))
        else:
            for name, value in figs.items():
                print(f"{name} = {value}")
        if args.pictures:
            sys.path.insert(0, str(ROOT / "scripts"))
            from make_report_images import main as pictures

            return pictures([])
        return 0

    return _isolated(work)


if __name__ == "__main__":
    sys.exit(main())
