"""``drivetrain catalog check``: every row of the catalog (shipped and user) against the consistency rules.

The rules a single row is judged on are ``catalog.rules.CONSISTENCY`` (the same that ``catalog import``
applies, plus the import's plausibility rules ``catalog.rules.RULES``); this module adds the ones that
need more than the row: the stated motor-drive pairings against the currents, and the voltage class of
every AC servo motor and servo drive (present, and equal to its vendor's model-code rule where one
applies, ``catalog.voltage_class``). A shipped row that breaks a rule on purpose carries a documented
exception in ``data/check_exceptions.csv`` (table, id or id pattern, rule, reason); the check reports it
as excused with the reason. docs/catalog.md, "Consistency check", lists every rule with its tolerance.
"""

from __future__ import annotations

import csv
import fnmatch
import io
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from drivetrain.catalog import db
from drivetrain.catalog.rules import CONSISTENCY, RULES
from drivetrain.catalog.schema import DRIVE, GEARBOX, MOTOR, TableSpec

EXCEPTIONS_FILE = "check_exceptions.csv"
"""Documented exceptions of shipped rows: table, id (or an fnmatch pattern), rule, reason."""


IMPORT_CONSISTENCY = frozenset({"kt_ke", "mass_for_flange", "inertia_for_flange", "shaft_pilot_flange", "voltage_rule"})
"""The ``catalog check`` rules an import refuses a row for, beyond the plausibility rules every row is read
with (catalog.rules.RULES, which hold the others: rated <= peak, n1N <= n1max, ...)."""
IMPORT_FLAGS = frozenset({"kt_rated_current", "kt_stall_current", "kt_peak_current", "voltage_class"})
"""The ``catalog check`` rules an import only flags (the import report names the field and the rule): a vendor
table may print a K_t x I / T outside the band (Yaskawa SGM7D-02K: 1.42), and many datasheets print no
voltage class."""

@dataclass(frozen=True)
class Finding:
    """One rule a row breaks: where (table, id, origin), which field, which rule, and why."""

    table: str
    id: str
    origin: str
    field: str
    rule: str
    message: str
    excused: str = ""  # the documented exception's reason, "" when the finding counts

    def to_dict(self) -> dict[str, str]:
        return {"table": self.table, "id": self.id, "origin": self.origin, "field": self.field, "rule": self.rule,
                "message": self.message, "excused": self.excused}


@dataclass
class Report:
    """What the check found: counts of rows per table, every finding, exceptions that matched nothing."""

    rows: dict[str, int] = field(default_factory=dict)
    findings: list[Finding] = field(default_factory=list)
    unused_exceptions: list[dict[str, str]] = field(default_factory=list)

    @property
    def failures(self) -> list[Finding]:
        return [f for f in self.findings if not f.excused]

    @property
    def ok(self) -> bool:
        return not self.failures

    def to_dict(self) -> dict[str, Any]:
        return {"ok": self.ok, "rows": self.rows, "failures": [f.to_dict() for f in self.failures],
                "excused": [f.to_dict() for f in self.findings if f.excused],
                "unused_exceptions": self.unused_exceptions}


def exceptions() -> list[dict[str, str]]:
    """The shipped exceptions file's rows (table, id, rule, reason)."""
    rows = list(csv.DictReader(io.StringIO(db.shipped_text(EXCEPTIONS_FILE))))
    for r in rows:
        if not (r.get("table") and r.get("id") and r.get("rule") and (r.get("reason") or "").strip()):
            raise RuntimeError(f"{EXCEPTIONS_FILE}: every exception needs table, id, rule and a reason: {r}")
    return rows


def by_field(spec: TableSpec, row: Mapping[str, Any]) -> dict[str, Any]:
    """A database row (keyed by column) keyed by field name, as the rules take it."""
    return {f.name: row.get(f.column) for f in spec.fields}


def row_findings(spec: TableSpec, values: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(rule, field, message) of every single-row rule one row breaks: the consistency rules, the import's
    plausibility rules (rule ``import``) and, for AC servo motors and drives, the voltage class."""
    kind = str(values.get("kind") or spec.default_kind)
    out = [(rule, fld, msg) for rule, fld, msg in CONSISTENCY[spec.name](values, kind)]
    seen = {(fld, msg) for _, fld, msg in out}
    out += [("import", fld, msg) for fld, msg in RULES[spec.name](values, kind) if (fld, msg) not in seen]
    out += voltage_findings(spec, values)
    return out


def voltage_findings(spec: TableSpec, values: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """The voltage class of an AC servo motor or a servo drive: present, and as its vendor's rule says."""
    from drivetrain.catalog import voltage_class

    if spec.name not in ("motor", "drive") or (spec is MOTOR and values.get("kind") != "ac_servo"):
        return []
    rid, vendor = str(values.get("id") or ""), str(values.get("vendor") or "")
    volts = values.get("voltage")
    if volts is None:
        return [("voltage_class", "voltage", "no voltage class: " + voltage_class.explain(spec.name, vendor, rid))]
    found = voltage_class.rule_for(spec.name, vendor, rid)
    if found is not None and abs(float(volts) - found[1]) > 0.15 * found[1]:
        return [("voltage_rule", "voltage", f"{float(volts):g} V disagrees with the model-code rule {found[0].key} "
                                            f"({found[1]:g} V class)")]
    return []


def pairing_findings(pairs: Mapping[str, Iterable[str]], motors: Mapping[str, Mapping[str, Any]],
                     drives: Mapping[str, Mapping[str, Any]]) -> list[tuple[str, str, str, str]]:
    """(motor id, rule, field, message) for each stated pairing whose currents do not fit: the motor's
    continuous current (stall, else rated) above the drive's continuous output current, or the motor's
    maximum current above the drive's maximum output current."""
    out: list[tuple[str, str, str, str]] = []
    for mid, dids in pairs.items():
        m = motors.get(mid)
        for did in dids:
            d = drives.get(did)
            if m is None or d is None:
                out.append((mid, "pairing_ids", "id", f"pairing with {did} names a "
                            + ("motor" if m is None else "drive") + " the catalog does not have"))
                continue
            cont = m.get("stall_current") or m.get("rated_current")
            if cont and d.get("continuous_current") and cont > d["continuous_current"] * (1 + 1e-9):
                out.append((mid, "pairing_continuous_current", "rated_current",
                            f"{cont:.4g} A continuous is above the paired drive {did}'s "
                            f"{d['continuous_current']:.4g} A"))
            if m.get("peak_current") and d.get("peak_current") and m["peak_current"] > d["peak_current"] * (1 + 1e-9):
                out.append((mid, "pairing_peak_current", "peak_current",
                            f"{m['peak_current']:.4g} A maximum is above the paired drive {did}'s "
                            f"{d['peak_current']:.4g} A maximum"))
    return out


def run(directory: Any = None) -> Report:
    """Check every row of the shipped catalog and of the user catalog (``$DRIVETRAIN_CATALOG`` or the data
    folder's user.sqlite); shipped rows' findings that a documented exception names are excused."""
    report = Report()
    raw: list[tuple[str, str, str, str, str, str]] = []  # table, id, origin, rule, field, message
    values: dict[str, dict[str, dict[str, Any]]] = {"motor": {}, "drive": {}}
    with db.reader(directory) as rd:
        for spec in (MOTOR, GEARBOX, DRIVE):
            rows = rd.rows(spec)
            report.rows[spec.name] = len(rows)
            for row in rows:
                v = by_field(spec, row)
                if spec.name in values:
                    values[spec.name].setdefault(str(v["id"]), v)
                raw += [(spec.name, str(v["id"]), row["origin"], rule, fld, msg)
                        for rule, fld, msg in row_findings(spec, v)]
        curves = rd.curves()
        report.rows["curve"] = sum(len(p) for p in curves.values())
        for mid, points in curves.items():
            for speed, cont, peak in points:
                pt = {"motor_id": mid, "speed": speed, "continuous_torque": cont, "peak_torque": peak}
                raw += [("curve", mid, "", rule, fld, f"at {speed * 30 / 3.141592653589793:.6g} rpm: {msg}")
                        for rule, fld, msg in CONSISTENCY["curve"](pt, "")]
                if mid not in values["motor"]:
                    raw.append(("curve", mid, "", "curve_motor", "motor_id", "no motor with this id"))
        pairs = rd.drive_pairs()
    raw += [("motor", mid, "builtin", rule, fld, msg)
            for mid, rule, fld, msg in pairing_findings(pairs, values["motor"], values["drive"])]
    excuses = exceptions()
    used = [False] * len(excuses)
    for table, rid, origin, rule, fld, msg in raw:
        reason = ""
        if origin in ("builtin", ""):
            for k, e in enumerate(excuses):
                if e["table"] == table and e["rule"] == rule and fnmatch.fnmatchcase(rid, e["id"]):
                    reason, used[k] = e["reason"], True
                    break
        report.findings.append(Finding(table, rid, origin or "builtin", fld, rule, msg, reason))
    report.unused_exceptions = [e for e, u in zip(excuses, used, strict=True) if not u]
    return report

