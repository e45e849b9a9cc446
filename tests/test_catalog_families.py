"""Vendor-sourced motor rows (issue #17): the family files ``motors_<vendor>_<family>.csv`` and the rows of
``motors_ac_servo.csv`` re-sourced through ``motor_documents.csv``.

Every family row must name its vendor document, section, page and the address of the copy read; the spot
checks assert the value printed on the quoted page; the invariants (power = T * omega within the vendor's
rounding, peak >= rated, brake inertia >= inertia, max speed >= rated speed) run over every row and over a
deliberately broken row, so a check that can no longer fail is noticed.
"""

from __future__ import annotations

import csv
import io
import math
import re
from importlib import resources

import pytest

from drivetrain import catalog
from drivetrain.catalog.schema import MOTOR, SHIPPED_FILES

RPM = 2 * math.pi / 60
Row = dict[str, str]
BASE = ("motors_ac_servo.csv", "motors_small_dc.csv")


def load(name: str) -> list[Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return list(csv.DictReader(io.StringIO(text)))


def num(s: str | None) -> float | None:
    return None if s is None or s.strip() == "" else float(s)


FAMILY_FILES = [f.filename for f in SHIPPED_FILES if f.table is MOTOR and f.filename not in BASE]
FAMILIES = {name: load(name) for name in FAMILY_FILES}
AC = {r["id"]: r for r in load("motors_ac_servo.csv")}
DOCUMENTS = {r["id"]: r for r in load("motor_documents.csv")}


def inertia(r: Row, key: str) -> float | None:
    """A family row's inertia in kg m^2, from the column ``key [kg*cm^2]`` (the unit printed by the vendors)."""
    v = num(r.get(f"{key} [kg*cm^2]"))
    return None if v is None else v * 1e-4


def family_problems(r: Row) -> list[str]:
    """Invariants of one family row (strings as in the CSV)."""
    out = []
    p, t, tpk = num(r["rated_power_W"]), num(r["rated_torque_Nm"]), num(r["peak_torque_Nm"])
    n, nmax = num(r["rated_speed_rpm"]), num(r["max_speed_rpm"])
    j, jb = inertia(r, "rotor_inertia"), inertia(r, "rotor_inertia_brake")
    if t is None or tpk is None or not tpk >= t > 0:
        out.append("need peak >= rated > 0")
    if n is None or nmax is None or not nmax >= n > 0:
        out.append("need max speed >= rated speed > 0")
    if j is None or not j > 0:
        out.append("inertia missing or <= 0")
    if jb is not None and j is not None and jb < j:
        out.append("inertia with brake < inertia")
    # vendors print 2-3 significant digits: 1.3 N m at 3000 rpm is 408 W for a 400 W motor (2 %)
    if p is not None and t is not None and n is not None and abs(t * n * RPM - p) > 0.03 * p:
        out.append("rated power != T * omega within 3 %")
    i, imax = num(r.get("rated_current_A")), num(r.get("peak_current_A"))
    if i is not None and imax is not None and not imax >= i > 0:
        out.append("need peak current >= rated current > 0")
    if r["verified"] != "yes":
        out.append("family rows are read from the vendor document: verified must be yes")
    if not all(r[k].strip() for k in ("source_document", "source_section", "source_page")):
        out.append("row without document, section and page")
    if not r["source_url"].startswith("https://"):
        out.append("row without the https address of the copy read")
    return out


ALL_FAMILY_ROWS = [(name, r["id"]) for name, rows in FAMILIES.items() for r in rows]


def test_every_family_file_is_shipped_and_has_rows() -> None:
    assert "motors_mitsubishi_hg_kn.csv" in FAMILY_FILES
    assert all(FAMILIES.values())
    ids = [rid for _name, rid in ALL_FAMILY_ROWS]
    assert len(ids) == len(set(ids))
    assert not set(ids) & set(AC)  # a family row never repeats a configurator row


@pytest.mark.parametrize(("name", "rid"), ALL_FAMILY_ROWS)
def test_family_rows_keep_the_invariants_and_are_sourced(name: str, rid: str) -> None:
    r = next(r for r in FAMILIES[name] if r["id"] == rid)
    assert family_problems(r) == []


BROKEN = [
    ({"peak_torque_Nm": "0.2"}, "need peak >= rated > 0"),
    ({"max_speed_rpm": "2000"}, "need max speed >= rated speed > 0"),
    ({"rotor_inertia_brake [kg*cm^2]": "0.05"}, "inertia with brake < inertia"),
    ({"rated_power_W": "150"}, "rated power != T * omega within 3 %"),
    ({"peak_current_A": "0.5"}, "need peak current >= rated current > 0"),
    ({"verified": "no"}, "family rows are read from the vendor document: verified must be yes"),
    ({"source_page": ""}, "row without document, section and page"),
    ({"source_url": "http://example.org"}, "row without the https address of the copy read"),
]


@pytest.mark.parametrize(("change", "problem"), BROKEN)
def test_each_family_invariant_catches_a_broken_row(change: Row, problem: str) -> None:
    row = {**FAMILIES["motors_mitsubishi_hg_kn.csv"][0], **change}
    assert problem in family_problems(row)


# ---------------------------------------------------------------------------------- spot checks


def test_hg_kn_against_the_vendor_specification_page() -> None:
    """Mitsubishi Electric, MELSERVO-JE rotary servo motor specifications, HG-KN series table
    (https://www.mitsubishielectric.com/fa/products/drv/servo/pmerit/mr_je/motor/specifications.html):
    HG-KN13J 100 W, 0.32 / 0.95 N m, J 0.0783 (brake 0.0843) x10^-4 kg m^2; HG-KN73J 750 W, 2.4 / 7.2 N m,
    4.8 / 14 A, J 1.28 (brake 1.39) x10^-4 kg m^2; 3000 r/min rated for all. Exact: the file holds the printed
    values."""
    rows = {r["id"]: r for r in FAMILIES["motors_mitsubishi_hg_kn.csv"]}
    assert set(rows) == {"HG-KN13J", "HG-KN23J", "HG-KN43J", "HG-KN73J"}
    k13, k73 = rows["HG-KN13J"], rows["HG-KN73J"]
    assert (num(k13["rated_power_W"]), num(k13["rated_torque_Nm"]), num(k13["peak_torque_Nm"])) == (100, 0.32, 0.95)
    assert inertia(k13, "rotor_inertia") == pytest.approx(0.0783e-4)
    assert inertia(k13, "rotor_inertia_brake") == pytest.approx(0.0843e-4)
    assert (num(k73["rated_torque_Nm"]), num(k73["peak_torque_Nm"])) == (2.4, 7.2)
    assert (num(k73["rated_current_A"]), num(k73["peak_current_A"])) == (4.8, 14)
    assert inertia(k73, "rotor_inertia") == pytest.approx(1.28e-4)
    assert inertia(k73, "rotor_inertia_brake") == pytest.approx(1.39e-4)
    assert {num(r["rated_speed_rpm"]) for r in rows.values()} == {3000}


def test_hg_kn_in_the_built_catalog_is_traced_with_brake_inertia_and_currents() -> None:
    row = catalog.get("HG-KN43J")
    assert not row["unverified"] and row["verified"] == 1
    assert row["rotor_inertia_kgm2"] == pytest.approx(0.375e-4)
    assert row["rotor_inertia_brake_kgm2"] == pytest.approx(0.397e-4)
    assert row["rated_current_A"] == 2.6 and row["peak_current_A"] == 7.8
    assert row["max_speed_rad_s"] == pytest.approx(5000 * RPM)  # the unconditional value, not "(6000)"
    assert row["sources"]["ratings"].startswith("Mitsubishi Electric, MELSERVO-JE")
    assert "https://www.mitsubishielectric.com/" in row["sources"]["mechanical"]


# Yaskawa, Sigma-7 Rotary Servomotor Product Manual (SIEP S800001 36): (table page, rated W, rated N m,
# instantaneous max N m, rated min^-1, max min^-1, J x10^-4 kg m^2, J with holding brake x10^-4 kg m^2)
YASKAWA = {
    "SGM7J-04A": ("4-4", 400, 1.27, 4.46, 3000, 6000, 0.486, "0.556"),
    "SGM7J-08A": ("4-4", 750, 2.39, 8.36, 3000, 6000, 1.59, "1.77"),
    "SGM7A-30A": ("5-7", 3000, 9.80, 29.4, 3000, 6000, 7.00, "9.20"),
    "SGM7A-70A": ("5-7", 7000, 22.3, 54.0, 3000, 6000, 12.3, None),  # prints 12.3 like the -50A, no brake
    "SGM7G-09A": ("7-4", 850, 5.39, 14.2, 1500, 3000, 13.9, "16.0"),
    "SGM7G-20A": ("7-4", 1800, 11.5, 28.7, 1500, 3000, 26.0, "28.1"),
}


@pytest.mark.parametrize("rid", list(YASKAWA))
def test_resourced_yaskawa_rows_equal_the_vendor_table(rid: str) -> None:
    page, p, t, tpk, n, nmax, j, jb = YASKAWA[rid]
    r, doc = AC[rid], DOCUMENTS[rid]
    assert doc["verified"] == "yes" and doc["source_page"] == page
    assert doc["source_url"].startswith("https://manualshive.com/")
    assert (num(r["rated_power_W"]), num(r["rated_torque_Nm"]), num(r["peak_torque_Nm"])) == (p, t, tpk)
    assert (num(r["rated_speed_rpm"]), num(r["max_speed_rpm"])) == (n, nmax)
    assert num(r["rotor_inertia_kgm2"]) == pytest.approx(j * 1e-4)
    if jb is None:
        assert "no holding-brake variant printed" in doc["mechanical_source"]
    else:
        assert f"with holding brake {jb}e-4 kg m^2" in doc["mechanical_source"]


NUMBER = r"([0-9]+(?:\.[0-9]+)?)"


def document_values(doc: Row) -> dict[str, float]:
    """The values a motor_documents row says it read (its ratings and mechanical texts)."""
    text = doc["ratings_source"] + " " + doc["mechanical_source"]
    out: dict[str, float] = {}
    patterns = {
        "rated_torque_Nm": rf"rated torque {NUMBER} N m",
        "peak_torque_Nm": rf"(?:instantaneous maximum|max\.) torque {NUMBER} N m",
        "rated_speed_rpm": rf"rated (?:motor )?speed {NUMBER} ",
        "max_speed_rpm": rf"maximum motor speed {NUMBER} ",
        "rotor_inertia_kgm2": rf"moment of inertia {NUMBER}e-4 kg m\^2",
    }
    for key, pattern in patterns.items():
        m = re.search(pattern, text)
        if m:
            out[key] = float(m.group(1)) * (1e-4 if key == "rotor_inertia_kgm2" else 1.0)
    m = re.search(rf"rated output {NUMBER} (k?W)", text)
    if m:
        out["rated_power_W"] = float(m.group(1)) * (1000.0 if m.group(2) == "kW" else 1.0)
    return out


YASKAWA_DOCUMENTED = sorted(k for k in DOCUMENTS if k.startswith("SGM7"))


def test_every_yaskawa_sigma7_row_but_the_unread_ones_is_documented() -> None:
    assert len(YASKAWA_DOCUMENTED) == 25  # SGM7J 7, SGM7A-15..70 7, SGM7G 11
    verified = [k for k in YASKAWA_DOCUMENTED if DOCUMENTS[k]["verified"] == "yes"]
    assert len(verified) == 19
    unread = sorted(set(YASKAWA_DOCUMENTED) - set(verified))
    assert unread == ["SGM7G-1AA", "SGM7G-1EA", "SGM7G-30A", "SGM7G-44A", "SGM7G-55A", "SGM7G-75A"]


@pytest.mark.parametrize("rid", YASKAWA_DOCUMENTED)
def test_documented_values_equal_the_row(rid: str) -> None:
    """What each motor_documents row says it read is what the motor row holds (so a later edit of either is
    caught); a verified row states every rating and its inertia."""
    doc, r = DOCUMENTS[rid], AC[rid]
    read = document_values(doc)
    expected = {"rated_power_W", "rated_torque_Nm", "peak_torque_Nm"}
    if doc["verified"] == "yes":
        expected |= {"rated_speed_rpm", "max_speed_rpm", "rotor_inertia_kgm2"}
    assert set(read) == expected
    for key, value in read.items():
        assert num(r[key]) == pytest.approx(value, rel=1e-9), key


def test_document_values_notice_a_changed_row() -> None:
    doc = DOCUMENTS["SGM7J-04A"]
    read = document_values(doc)
    assert read["rated_torque_Nm"] == 1.27 and read["rotor_inertia_kgm2"] == pytest.approx(0.486e-4)
    assert read["rated_power_W"] != pytest.approx(num(AC["SGM7J-06A"]["rated_power_W"]))


def test_the_partly_read_sgm7g_rows_stay_unverified_and_say_why() -> None:
    row = catalog.get("SGM7G-44A")
    assert row["unverified"] and row["verified"] == 0
    assert "speed and inertia are not on the copy read" in row["unverified_reason"]
    assert "p. 7-5" in row["sources"]["ratings"]
    row = catalog.get("SGM7G-13A")
    assert not row["unverified"] and row["verified"] == 1 and row["source_page"] == "7-4"
