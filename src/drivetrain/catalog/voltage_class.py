"""Voltage class of AC servo motors and drives from the vendors' model-code rules.

A servo motor and its drive belong to one mains family (100 V, 200 V or 400 V class); most vendors
encode it in the model code (Yaskawa's third character after the dash, Mitsubishi's ``4`` suffix,
Omron's last letter) or sell a whole series for one family (Siemens 1FT7 on SINAMICS S120). The
table below holds each rule this catalog applies, with the vendor page it was read from. A rule is
applied when the catalog table is built (``db.shipped_rows``) and on ``catalog import``: it fills an
empty ``voltage`` and flags it derived (``derived`` lists ``voltage``, ``derivation`` names the rule);
a voltage the row's own source gives is kept and only compared with the rule (``catalog check``).

Where no rule was found for a vendor or series, the class stays unknown and :func:`explain` says so
and what would decide it (docs/catalog.md, "Voltage classes").
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class VoltageRule:
    """One vendor's rule for one series: the model-code pattern and what each code means.

    table: "motor" or "drive". vendor: case-insensitive part of the row's vendor. pattern: regex on
    the row id; its first group is the code looked up in ``classes`` (no group: the whole series is
    one class, ``classes[""]``). citation: the vendor page the rule was read from.
    """

    key: str
    table: str
    vendor: str
    series: str
    pattern: str
    classes: Mapping[str, float]
    citation: str

    def match(self, row_id: str) -> float | None:
        m = re.match(self.pattern, row_id)
        if m is None:
            return None
        code = m.group(1) if m.groups() else ""
        return self.classes.get(code or "")


_YASKAWA_SIGMA2 = (
    "Yaskawa, Sigma-II Series SGM□H/SGDM User's Manual (SIEP S800000 15), 2.1 'Servomotor Model Designations', "
    "p. 2-3 ('3rd digit: Voltage A: 200V, B: 100V, D: 400V'; p. 2-7 and 2-11 the same for SGMGH and SGMSH), "
    "https://www.easymanua.ls/yaskawa/sgdh/manual?p=37"
)
_MR_J4 = (
    "Mitsubishi Electric, MR-J4-_A Servo Amplifier Instruction Manual, App. 4.8.1 'MR-J4 servo amplifier': "
    "(1) 200 V class MR-J4-10_ to MR-J4-22K_, (2) 400 V class MR-J4-60_4 to MR-J4-22K_4, "
    "https://www.easymanua.ls/mitsubishi/mr-j4-350a/manual?p=599; 100 V class MR-J4-10_1 to MR-J4-40_1: "
    "MELSERVO-J4 'Instructions and Cautions for Safe Use of AC Servos' IB(NA)0300175, model list "
    "(https://manuzoid.jp/manuals/J6q9Q-Mitsubishi%20Electric%20AC%20Servos%20%E5%8F%96%E6%89%B1%E8%AA%AC%E6%98%8E%E6%9B%B8)"
)
_OMRON_G5 = (
    "Omron, OMNUC G5-Series AC Servo Drives User's Manual (built-in MECHATROLINK-II), 3-3 'Servomotor "
    "Specifications', p. 3-55: the 400 VAC table lists R88M-K90010F/K2K010F/K3K010F and -K90010C/K2K010C/"
    "K3K010C (last letter F: 400 V incremental, C: 400 V absolute encoder); the 200 VAC tables of the same "
    "section list the H (incremental) and T (absolute) models, https://www.easymanua.ls/omron/r88d-kn-ml2-sries/manual?p=150"
)
_FANUC_HV = (
    "FANUC, SERVO AMPLIFIER βi series DESCRIPTIONS, B-65322EN/02-02, addition of the β(HV)i series: the HV "
    "amplifiers run on 400-480 V AC, the others on the 200 V class; HV motor models carry 'HV' in their name "
    "(FANUC AC SERVO MOTOR αi series DESCRIPTIONS B-65262EN), https://www.scribd.com/document/498400922/05009E-B-65322EN-0202-DOC"
)
_SIEMENS_S120 = (
    "Siemens: 1FT7 motors are sold for SINAMICS S120 only (SINAMICS S120 1FT7 Synchronous Motors, Configuration "
    "Manual PFT7S, 6SN1197-0AD13-0BP2, title); SINAMICS S120 booksize line voltage 3 AC 380-480 V, DC link 600 V "
    "(ALM) / 540 V (BLM) at 400 V (SIMOTICS S-1FK2 Configuration Manual 02/2022, 6.1 'Explanations', "
    "converter output voltages, p. 82, https://www.easymanua.ls/siemens/simotics-s-1fk2/manual/753620?p=84): "
    "one 400 V class for the series, not a model-code position"
)

RULES: tuple[VoltageRule, ...] = (
    VoltageRule("yaskawa-sigma2", "motor", "yaskawa", "SGMAH SGMPH SGMSH SGMGH SGMDH",
                r"^SGM[APSGD]H-[0-9A-Z]{2}([ABD])", {"A": 200.0, "B": 100.0, "D": 400.0}, _YASKAWA_SIGMA2),
    VoltageRule("mitsubishi-mr-j4", "drive", "mitsubishi", "MR-J4",
                r"^MR-J4-[0-9]+K?[AB](4|1)?$", {"": 200.0, "4": 400.0, "1": 100.0}, _MR_J4),
    VoltageRule("omron-g5", "motor", "omron", "R88M-K",
                r"^R88M-K[0-9K]{3}[0-9]{2}([HTFC])", {"H": 200.0, "T": 200.0, "F": 400.0, "C": 400.0}, _OMRON_G5),
    VoltageRule("fanuc-hv", "motor", "fanuc", "alpha iS alpha iF beta iS",
                r"^(?:beta|ai[SF])\s?[0-9.]+/[0-9]+\s*(?:is)?\s*(HV)?", {"": 200.0, "HV": 400.0}, _FANUC_HV),
    VoltageRule("siemens-1ft7", "motor", "siemens", "1FT7", r"^1FT7", {"": 400.0}, _SIEMENS_S120),
    VoltageRule("siemens-s120-motor-module", "drive", "siemens", "SINAMICS S120 Motor Module",
                r"^6SL312", {"": 400.0}, _SIEMENS_S120),
)
"""Every rule applied, one per vendor series (docs/catalog.md, "Voltage classes")."""

NOT_FOUND: dict[str, str] = {
    "yaskawa": "the Sigma-7 (SGM7_, SGD7S) and Sigma (SGMP) model-designation pages were not found in the documents "
               "searched (the Sigma-II rule, A 200 V / B 100 V / D 400 V, is not assumed to carry over); "
               "the rows give their class from their own tables",
    "mitsubishi": "no Mitsubishi page stating the HG motor voltage code (the '4' suffix of 400 V models) was found; "
                  "the HG-KN and CNC MELDAS HC tables read print no voltage class",
    "panasonic": "the MINAS A6 model-designation page (voltage position: 1 100 V, 2 200 V, Z 100/200 V) was found "
                 "only in a third-party transcription, not on a Panasonic page",
    "ls mecapion": "no LS Mecapion page giving the APM voltage code was found; the last letter of the shipped ids "
                   "is the rated speed (A 3000, D 2000, G 1500, M 1000 rpm), not the voltage",
    "teco": "no TECO page giving the JSMA/JSDG2S voltage code was found; the pages read print no voltage class",
    "bosch rexroth": "no Rexroth page giving the MHP supply class was found (the MHP page prints a nominal motor "
                     "voltage, 324 V, not the drive's mains class)",
}
"""Why a vendor's series has no rule here: what was searched and not found (docs/catalog.md)."""


SEPARATOR = " | "
"""Between the formulas of a row's ``derivation`` (one per derived field, ``field = formula``)."""


def rule_for(table: str, vendor: str, row_id: str) -> tuple[VoltageRule, float] | None:
    """The rule that applies to a row and the class it gives, or None."""
    v = vendor.lower()
    for rule in RULES:
        if rule.table == table and rule.vendor in v:
            volts = rule.match(row_id)
            if volts is not None:
                return rule, volts
    return None


def derivation_text(rule: VoltageRule, volts: float) -> str:
    return f"voltage = {volts:g} V class by the model-code rule {rule.key} ({rule.citation})"


def apply(values: dict[str, Any], table: str) -> bool:
    """Fill an empty ``voltage`` of one row (field names as keys) from its vendor's rule; True if filled.

    The field is added to ``derived`` and the rule to ``derivation``; a given voltage is never replaced.
    """
    if values.get("voltage") is not None or table not in ("motor", "drive"):
        return False
    if table == "motor" and values.get("kind") not in (None, "ac_servo"):
        return False
    found = rule_for(table, str(values.get("vendor") or ""), str(values.get("id") or ""))
    if found is None:
        return False
    rule, volts = found
    values["voltage"] = volts
    add_derived(values, "voltage", derivation_text(rule, volts))
    return True


def add_derived(values: dict[str, Any], name: str, formula: str) -> None:
    """Record that field ``name`` was computed, with its formula (``derived`` and ``derivation``)."""
    names = [n for n in str(values.get("derived") or "").split(",") if n]
    values["derived"] = ",".join(dict.fromkeys([*names, name]))
    parts = [p for p in str(values.get("derivation") or "").split(SEPARATOR) if p and not p.startswith(f"{name} = ")]
    values["derivation"] = SEPARATOR.join([*parts, formula])


def explain(table: str, vendor: str, row_id: str) -> str:
    """Why a row has no voltage class: the rule that would apply, or what was not found for its vendor."""
    found = rule_for(table, vendor, row_id)
    if found is not None:
        return f"the rule {found[0].key} gives {found[1]:g} V"
    v = vendor.lower()
    reason = next((text for name, text in NOT_FOUND.items() if name in v), "")
    return ("unknown: " + reason if reason else "unknown: no model-code rule of this vendor is in the catalog") + (
        "; give the row's voltage (the class its drive is sold for) to decide it")
