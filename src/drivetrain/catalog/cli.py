"""``drivetrain catalog``: list, show, import and export catalog components.

The main CLI calls :func:`add_parser` with its sub-parsers and dispatches to :func:`run` (set as
``handler`` on the parsed arguments). Bad input raises InputError; the main CLI prints it and exits
with status 2. No physics here: every number comes from ``drivetrain.catalog``.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from drivetrain.catalog.schema import DRIVE, GEARBOX, MOTOR, TABLES, TEXT, TableSpec

if TYPE_CHECKING:
    from rich.console import Console

    from drivetrain.terminal import Col

LIST_KINDS = ("motor", "gearbox", "drive")
_PLURAL = {"motor": "motors", "gearbox": "gearboxes", "drive": "drives"}
DEFAULT_LIMIT = 50
UNVERIFIED_MARK = " †"
"""Marks an unverified row (not traced to a vendor document, or a derived rating) in tables."""
# (column title, field name, drop rank) per table for `catalog list`; values shown in the field's export unit.
# On a terminal too narrow for the table the vendor is abbreviated first, then the columns with a drop rank
# are left out, lowest first (docs/architecture.md, "Terminal output"); id and the ratings stay.
_LIST_COLUMNS: dict[str, tuple[tuple[str, str, int | None], ...]] = {
    "motor": (
        ("id", "id", None),
        ("vendor", "vendor", 5),
        ("series", "series", 2),
        ("T rated N·m", "rated_torque", None),
        ("T peak N·m", "peak_torque", None),
        ("n rated rpm", "rated_speed", 4),
        ("n max rpm", "max_speed", None),
        ("J kg·cm²", "rotor_inertia", None),
        ("V", "voltage", 3),
        ("origin", "origin", 1),
    ),
    "gearbox": (
        ("id", "id", None),
        ("vendor", "vendor", 9),
        ("series", "series", 6),
        ("i", "ratio", None),
        ("stages", "stages", 5),
        ("T2N N·m", "rated_output_torque", None),
        ("T2B N·m", "max_output_torque", None),
        ("T2NOT N·m", "emergency_stop_torque", 2),
        ("eta", "efficiency", None),
        ("n1N rpm", "rated_input_speed", 4),
        ("n1max rpm", "max_input_speed", None),
        ("bore mm", "input_bore_max", 3),
        ("J1 kg·cm²", "inertia_input", 7),
        ("backlash arcmin", "backlash", 8),
        ("origin", "origin", 1),
    ),
    "drive": (
        ("id", "id", None),
        ("vendor", "vendor", 4),
        ("series", "series", 2),
        ("I cont A", "continuous_current", None),
        ("I peak A", "peak_current", None),
        ("V", "voltage", 3),
        ("runs motors", "motor_series", 5),
        ("origin", "origin", 1),
    ),
}


CHECK_DROP = {"origin": 1, "table": 2, "field": 3, "exception": 4}
"""The columns of ``catalog check`` left out to fit a terminal, lowest first (docs/architecture.md)."""


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    """Register ``catalog`` and its sub-commands on the main CLI's sub-parsers."""
    parser = subparsers.add_parser(
        "catalog",
        help="list, show, import and export motors, gearboxes and drives",
        description="The component catalog: shipped data (with sources) plus your own imports.",
    )
    parser.add_argument(
        "--catalog",
        metavar="FILE.sqlite",
        help="your catalog file (shared by a team; default: $DRIVETRAIN_CATALOG, else user.sqlite in the data "
        "folder); the shipped data is read beside it",
    )
    sub = parser.add_subparsers(dest="catalog_command", metavar="COMMAND", required=True)

    p = sub.add_parser("list", help="list components (motors by default)")
    p.add_argument("--vendor", help="part of the vendor name, case-insensitive")
    p.add_argument("--kind", choices=LIST_KINDS, default="motor", help="table to list (default: motor)")
    p.add_argument(
        "--source",
        choices=("all", "builtin", "user"),
        default="all",
        help="shipped rows (builtin), your rows (user) or both (default)",
    )
    p.add_argument(
        "--limit",
        type=int,
        default=DEFAULT_LIMIT,
        metavar="N",
        help=f"show at most N rows (default {DEFAULT_LIMIT}; 0: all)",
    )
    p.add_argument("--json", action="store_true", help="print JSON (SI, unit in each key)")

    p = sub.add_parser("show", help="show one component with its source and notes")
    p.add_argument("id", metavar="ID")
    p.add_argument("--json", action="store_true", help="print JSON (SI, unit in each key)")

    p = sub.add_parser("import", help="import a CSV or JSON file into your catalog (all rows or none)")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--kind", choices=tuple(TABLES), help="table (default: from the file)")
    p.add_argument(
        "--replace",
        action="store_true",
        help="update rows of your catalog that have the same id (in the same transaction)",
    )

    p = sub.add_parser(
        "check",
        help="check every row (shipped and yours) against the consistency rules; exit 1 if a row fails",
        description="Every motor, gearbox, drive and curve point against the consistency rules of docs/catalog.md "
        "('Consistency check'); shipped rows that break a rule on purpose carry a documented exception. Exit "
        "status 0 when every row passes, 1 when a row fails, 2 on bad input.",
    )
    p.add_argument("--catalog", dest="check_catalog", metavar="FILE.sqlite",
                   help="check this catalog file beside the shipped data (default: as for every catalog command)")
    p.add_argument("--json", action="store_true", help="print JSON: failures, excused findings, row counts")
    p.add_argument("--all", action="store_true", help="list the excused findings too (with their reason)")

    p = sub.add_parser("remove", help="remove rows of your catalog by id (all or none)")
    p.add_argument("ids", metavar="ID", nargs="+")

    p = sub.add_parser("history", help="the changes to your catalog: imports, replacements, edits, removals")
    p.add_argument("id", metavar="ID", nargs="?", help="only this id")
    p.add_argument("--json", action="store_true", help="print JSON (old and new values in SI)")

    p = sub.add_parser("export", help="export a table as CSV or JSON with unit headers")
    p.add_argument("--kind", choices=tuple(TABLES), default="motor", help="table (default: motor)")
    p.add_argument("--format", choices=("csv", "json"), default="csv")
    p.add_argument(
        "--origin",
        choices=("all", "builtin", "user"),
        default="all",
        help="shipped rows, your imports, or both (default)",
    )
    p.add_argument("--output", "-o", metavar="FILE", help="write to FILE (default: standard output)")

    parser.set_defaults(handler=run)
    return parser


def run(args: argparse.Namespace) -> int:
    """Run a ``catalog`` sub-command; returns the exit status. Raises InputError on bad input."""
    handlers = {
        "list": _list,
        "show": _show,
        "import": _import,
        "export": _export,
        "remove": _remove,
        "history": _history,
        "check": _check,
    }
    checked = getattr(args, "check_catalog", None)
    if checked is not None:
        import os

        from drivetrain.errors import InputError

        if not os.path.isfile(os.path.expanduser(checked)):
            raise InputError("--catalog", "no such catalog file", checked)
    use_catalog(checked or getattr(args, "catalog", None))
    return handlers[args.catalog_command](args)


def use_catalog(path: str | None) -> None:
    """``--catalog FILE``: the user catalog of this run (as ``$DRIVETRAIN_CATALOG``)."""
    if not path:
        return
    import os
    import stat

    from drivetrain.catalog.db import ENV_CATALOG
    from drivetrain.errors import InputError
    from drivetrain.userfile import check_path

    path = os.path.expanduser(check_path(path, "--catalog"))
    if os.path.isdir(path):
        raise InputError("--catalog", "must name a catalog file (e.g. team.sqlite), not a folder", path)
    if os.path.exists(path) and not stat.S_ISREG(os.stat(path).st_mode):
        # a device, FIFO or socket: SQLite would read zeros from it, or wait on it for ever
        raise InputError("--catalog", "must name a regular catalog file, not a device, FIFO or socket", path)
    os.environ[ENV_CATALOG] = os.path.abspath(path)


def main(argv: Sequence[str] | None = None) -> int:
    """Stand-alone entry (``python -m drivetrain.catalog.cli``): same commands, status 2 on bad input."""
    from drivetrain.errors import InputError

    parser = argparse.ArgumentParser(prog="drivetrain")
    add_parser(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    try:
        return run(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


# ---------------------------------------------------------------------------------- handlers


def _console() -> Console:
    """The console of every table and line: whole cells and lines in a pipe, the terminal's width (or
    ``COLUMNS``) on a terminal (drivetrain.terminal)."""
    from drivetrain.terminal import table_console

    console: Console = table_console()
    return console


def _list_columns(kind: str) -> list[Col]:
    """The columns of ``catalog list --kind KIND``: numbers right-aligned and never cut, the vendor
    abbreviated to fit, the drop ranks of ``_LIST_COLUMNS``."""
    from drivetrain.terminal import Col

    spec = TABLES[kind]
    text = {f.name for f in spec.fields if f.quantity == TEXT} | {"id", "origin"}
    return [Col(title, right=name not in text, number=name not in text, drop=drop, abbreviate=name == "vendor")
            for title, name, drop in _LIST_COLUMNS[kind]]


def _list(args: argparse.Namespace) -> int:
    from drivetrain import catalog
    from drivetrain.errors import InputError

    if args.limit < 0:
        raise InputError("--limit", "must be >= 0", args.limit)
    table: catalog.MotorTable | catalog.GearboxTable | catalog.DriveTable
    if args.kind == "motor":
        table = catalog.motors(vendor=args.vendor)
    elif args.kind == "gearbox":
        table = catalog.gearboxes(vendor=args.vendor)
    else:
        table = catalog.drives(vendor=args.vendor)
    source = getattr(args, "source", "all")
    if source != "all":
        table = table.take(table.origin == source)
    shown = len(table) if args.limit == 0 else min(args.limit, len(table))
    if args.json:
        print(json.dumps([table.row(i) for i in range(shown)], indent=1, ensure_ascii=False))
        return 0
    console = _console()
    if len(table) == 0:
        console.print(
            f"no {_PLURAL[args.kind]} in your catalog; add some with `drivetrain catalog import FILE`"
            if source == "user"
            else _empty_message(args.kind, args.vendor)
        )
        return 0
    spec = TABLES[args.kind]
    from drivetrain.terminal import print_table

    rows = []
    for i in range(shown):
        row = table.row(i)
        cells = [_cell(spec, name, row) for _, name, _ in _LIST_COLUMNS[args.kind]]
        if args.kind == "motor" and row.get("approx_rated"):
            cells[3] += " (derived)"
        if row.get("unverified"):
            cells[0] += UNVERIFIED_MARK
        rows.append(cells)
    print_table(console, f"{_PLURAL[args.kind]} ({shown} of {len(table)})", _list_columns(args.kind), rows,
                title_justify="left")
    flagged = int(table.unverified[:shown].sum())
    if flagged:
        console.print(
            f"{UNVERIFIED_MARK} unverified: {flagged} of the rows shown are not traced to a vendor document or "
            "carry a derived rating; `drivetrain catalog show ID` says why"
        )
    if shown < len(table):
        console.print(f"{len(table) - shown} more; use --limit 0 to list all, or --vendor to narrow")
    return 0


def _empty_message(kind: str, vendor: str | None) -> str:
    if kind == "drive":
        return (
            "no drives in the catalog: the shipped data has none (no sourced drive data); "
            "add yours with `drivetrain catalog import FILE --kind drive`"
        )
    return f"no {_PLURAL[kind]}" + (f" from vendor {vendor!r}" if vendor else "")


def _cell(spec: TableSpec, name: str, row: dict[str, Any]) -> str:
    fld = next((f for f in spec.fields if f.name == name), None)
    key = "id" if name == "id" else (fld.column if fld else name)
    value = row.get(key)
    if value is None or value == "":
        return "-"
    if fld is None or fld.quantity == TEXT:
        return str(value)
    from drivetrain.catalog.columns import display

    shown = display(fld, value)
    return _number(shown) if isinstance(shown, float) else str(shown)


def _number(x: float) -> str:
    """Four significant digits without exponent in the usual range (10000, 0.1194, 3.342)."""
    if x != 0 and not 1e-4 <= abs(x) < 1e7:
        return f"{x:.4g}"
    import numpy as np

    return np.format_float_positional(x, precision=4, unique=False, fractional=False, trim="-")


def _show(args: argparse.Namespace) -> int:
    from drivetrain import catalog

    record = catalog.get(args.id)
    if args.json:
        print(json.dumps(record, indent=1, ensure_ascii=False))
        return 0
    spec = {"motor": MOTOR, "gearbox": GEARBOX, "drive": DRIVE}[record["table"]]
    from drivetrain.terminal import Col, print_table

    rows: list[tuple[str, str]] = []

    def add(field: str, value: str) -> None:
        rows.append((field, value))

    provenance = (
        "source",
        "notes",
        "rated_torque_basis",
        "derived",
        "derivation",
        "verified",
        "unverified_reason",
        "ratings_source",
        "mechanical_source",
        "electrical_source",
    )
    for fld in spec.fields:
        if fld.name in provenance or fld.name == "id":
            continue
        value = record.get(fld.column)
        derived_mark = " (derived)" if fld.name in (record.get("derivation") or {}) else ""
        if fld.name == "voltage" and value is None and (record["table"] == "drive" or record.get("kind") == "ac_servo"):
            from drivetrain.catalog.voltage_class import explain

            add("voltage", "class " + explain(record["table"], str(record.get("vendor") or ""), record["id"]))
            continue
        if value is None or value == "":
            continue
        add(fld.name, _with_unit(spec, fld.name, record) + derived_mark)
    add("origin", "shipped catalog" if record["origin"] == "builtin" else "your import")
    add("source", str(record.get("source") or "-"))
    for group, where in record.get("sources", {}).items():
        add(f"source: {group}", str(where))
    add(
        "verified",
        f"no: {record['unverified_reason']}" if record.get("unverified") else "yes (traced to the document above)"
        if record.get("verified") == 1
        else "not marked (no reason to doubt it is recorded)",
    )
    if record.get("notes"):
        add("notes", str(record["notes"]))
    if record["table"] == "motor" and record.get("rated_torque_basis"):
        add("rated_torque_basis", str(record["rated_torque_basis"]))
    if record["table"] in ("motor", "drive"):
        derivation = record.get("derivation") or {}
        add("derived", ", ".join(derivation) + " (computed, not read from a datasheet)" if derivation
                    else "none")
        for name, formula in derivation.items():
            add(f"derived: {name}", formula)
    if record["table"] == "motor":
        add(
            "speed-torque curve",
            f"{len(record['curve']['speed_rad_s'])} points"
            if record.get("curve")
            else "none: envelope derived from the ratings (approximate, see drivetrain.sizing.envelope)",
        )
    cols = [Col("field", style="bold"), Col("value", fold=True)]
    print_table(_console(), f"{record['table']} {record['id']}", cols, rows, show_header=False, title_justify="left")
    return 0


def _with_unit(spec: TableSpec, name: str, record: dict[str, Any]) -> str:
    fld = spec.field(name)
    text = _cell(spec, name, {fld.column: record.get(fld.column)})
    return f"{text} {fld.unit}" if fld.unit and fld.quantity != TEXT else text


def _import(args: argparse.Namespace) -> int:
    from drivetrain import catalog

    report = catalog.import_file(args.file, kind=args.kind, replace=args.replace)
    _console().print(str(report))
    return 0


def _check(args: argparse.Namespace) -> int:
    from drivetrain.catalog import check

    report = check.run()
    if args.json:
        print(json.dumps(report.to_dict(), indent=1, ensure_ascii=False))
        return 0 if report.ok else 1
    console = _console()
    shown = report.findings if args.all else report.failures
    if shown:
        from drivetrain.terminal import Col, print_table

        # on a narrow terminal the sentences wrap, then origin, table, field and exception are left out in
        # this order (CHECK_DROP); the id, the rule and what is wrong stay
        cols = [Col(title, drop=CHECK_DROP.get(title), fold=title in ("what is wrong", "exception"))
                for title in ("table", "id", "origin", "field", "rule", "what is wrong", "exception")]
        print_table(console, "catalog check: " + ("excused and failing findings" if args.all else "failing rows"),
                    cols, [(f.table, f.id, f.origin, f.field, f.rule, f.message, f.excused or "-") for f in shown],
                    title_justify="left")
    counts = ", ".join(f"{n} {_PLURAL.get(t, t + ' points')}" for t, n in report.rows.items())
    excused = len(report.findings) - len(report.failures)
    console.print(f"checked {counts}: {len(report.failures)} finding(s) fail, {excused} excused by a documented "
                  "exception (data/check_exceptions.csv; --all lists them)")
    for e in report.unused_exceptions:
        console.print(f"exception no longer needed: {e['table']} {e['id']} {e['rule']}")
    return 0 if report.ok else 1


def _remove(args: argparse.Namespace) -> int:
    from drivetrain import catalog
    from drivetrain.catalog.db import user_db_path

    count = catalog.remove(args.ids)
    print(f"removed {count} row(s) from {user_db_path()}")
    return 0


def _history(args: argparse.Namespace) -> int:
    from drivetrain import catalog

    entries = catalog.history(args.id)
    if args.json:
        print(json.dumps(entries, indent=1, ensure_ascii=False))
        return 0
    console = _console()
    if not entries:
        console.print("no changes recorded" + (f" for {args.id}" if args.id else " in your catalog"))
        return 0
    from drivetrain.terminal import Col, print_table

    cols = [Col("time (UTC)", number=True), Col("action"), Col("table", drop=1), Col("id"), Col("source", fold=True)]
    print_table(console, "catalog history", cols,
                [(e["at"], e["action"], e["table_name"], e["id"], e["source"] or "-") for e in entries],
                title_justify="left")
    return 0


def _export(args: argparse.Namespace) -> int:
    from drivetrain.catalog.importer import export, export_text

    if args.output:
        count = export(args.output, args.kind, args.format, origin=args.origin)
        print(f"exported {count} {args.kind} row(s) to {args.output}", file=sys.stderr)
    else:
        text, _ = export_text(args.kind, args.format, origin=args.origin)
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
