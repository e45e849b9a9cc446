"""Rows of ``motors_ac_servo.csv`` re-sourced from the vendor's own tables through ``motor_documents.csv``
(issue #17): the Yaskawa Sigma-7 rows.

The spot checks assert the values printed on the quoted pages; every documented row's quoted values must
equal the motor row (so a later edit of either is caught); rows only partly read stay unverified with
the reason. The family files (``motors_<vendor>_<family>.csv``) are tested in test_catalog_motor_families.py.
"""

from __future__ import annotations

import csv
import io
import math
import re
from importlib import resources

import pytest

from drivetrain import catalog

RPM = 2 * math.pi / 60
Row = dict[str, str]


def load(name: str) -> list[Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return list(csv.DictReader(io.StringIO(text)))


def num(s: str | None) -> float | None:
    return None if s is None or s.strip() == "" else float(s)


AC = {r["id"]: r for r in load("motors_ac_servo.csv")}
DOCUMENTS = {r["id"]: r for r in load("motor_documents.csv")}


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
