"""Holding-brake variants of shipped motors (data/motor_brakes.csv, SOURCES.md "Brake variants"): every value as
printed on the vendor page its row names, checked against the family files, merged into the motor rows, and the
brake columns of a user catalog of schema 4 added in place."""

from __future__ import annotations

import csv
import io
import re
import sqlite3
from importlib import resources
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db, side_tables
from tests.sizing.test_drive_select import USER_MOTORS, import_catalog

Row = dict[str, str]


def load(name: str) -> list[Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return list(csv.DictReader(io.StringIO(text)))


BRAKES = {r["id"]: r for r in load("motor_brakes.csv")}
HC = {r["id"]: r for r in load("motors_mitsubishi_hc_meldas.csv")}
KN = {r["id"]: r for r in load("motors_mitsubishi_hg_kn.csv")}


def num(s: str) -> float | None:
    return float(s) if s.strip() else None


@pytest.mark.parametrize(("mid", "printed"), [
    # Sigma-7 rotary servomotor manual SIEP S800001 36, "Motor Moment of Inertia, With Holding Brake" (x10^-4 kg m^2)
    ("SGM7J-A5A", 0.0475), ("SGM7J-08A", 1.77),  # 4.2.2, p. 4-4
    ("SGM7A-15A", 2.25), ("SGM7A-50A", 14.5),  # 5.2.4, p. 5-7
    ("SGM7G-03A", 2.73), ("SGM7G-09A", 16.0), ("SGM7G-20A", 28.1),  # 7.2.2, p. 7-4
])
def test_yaskawa_with_brake_inertia_as_printed(mid: str, printed: float) -> None:
    r = BRAKES[mid]
    assert num(r["rotor_inertia_brake_kgm2"]) == pytest.approx(printed * 1e-4, rel=1e-12)
    assert r["brake_holding_torque_Nm"] == "" and r["brake_code"] == ""  # merged cells / page not read: not guessed
    row = catalog.get(mid)
    assert row["rotor_inertia_brake_kgm2"] == pytest.approx(printed * 1e-4)
    assert row["rotor_inertia_brake_kgm2"] > row["rotor_inertia_kgm2"]
    assert f"{printed}" in row["sources"]["brake"] and "SIEP S800001 36" in row["sources"]["brake"]


def test_sgm7a_70a_has_no_brake_variant_and_no_row() -> None:
    # p. 5-7 prints "-" for the SGM7A-70A's holding brake: no brake variant
    assert "SGM7A-70A" not in BRAKES and catalog.get("SGM7A-70A")["rotor_inertia_brake_kgm2"] is None


@pytest.mark.parametrize(("mid", "torque", "added"), [
    # MELDAS HC manual, Table 4-1 p. 4-3: static friction torque (N m) and the inertia the brake adds (kg cm^2)
    ("HC52", 8.3, "2.0"), ("HC153", 8.3, "2.0"), ("HC352", 43.1, "10"), ("HC703", 43.1, "10"),
    ("HC103R", 6.8, "0.4"), ("HC503R", 16.7, "3.5"),
])
def test_meldas_hc_holding_torque_as_printed(mid: str, torque: float, added: str) -> None:
    r = BRAKES[mid]
    assert num(r["brake_holding_torque_Nm"]) == torque and r["brake_code"] == mid + "B"
    assert f"{added} kg·cm²" in r["brake_source"] and "Table 4-1, p. 4-3" in r["brake_source"]
    row = catalog.get(mid)
    assert row["brake_holding_torque_Nm"] == torque and row["brake_code"] == mid + "B"


def test_the_brake_table_agrees_with_the_ratings_tables_with_brake_inertia() -> None:
    """Table 4-1's added inertia per motor-type group against J with brakes - J of the ratings tables (pp. 2-2...2-4):
    19 of 20 rows agree, which confirms the group each type was read into; HC202 prints 8.6 kg cm^2 added (51.1 -
    42.5) where Table 4-1 prints 10 for its group, kept as printed on both pages."""
    added = {mid: float(re.search(r"added by the brake ([0-9.]+) kg", r["brake_source"]).group(1))  # type: ignore[union-attr]
             for mid, r in BRAKES.items() if mid in HC}
    assert len(added) == len(HC) == 20
    off = {mid: round(float(HC[mid]["rotor_inertia_brake [kg*cm^2]"]) - float(HC[mid]["rotor_inertia [kg*cm^2]"]), 3)
           for mid in HC}
    assert {mid for mid in HC if off[mid] != added[mid]} == {"HC202"}
    assert (off["HC202"], added["HC202"]) == (8.6, 10.0)


@pytest.mark.parametrize("mid", ["HG-KN13J", "HG-KN23J", "HG-KN43J", "HG-KN73J"])
def test_hg_kn_brake_variant_code_from_the_column_head(mid: str) -> None:
    # "HG-KN 13(B)J": the brake variant is the code with B before the J
    r = BRAKES[mid]
    assert r["brake_code"] == mid[:-1] + "BJ" and f"'HG-KN {mid[5:-1]}(B)J'" in r["brake_source"]
    assert num(KN[mid]["rotor_inertia_brake [kg*cm^2]"]) is not None  # its with-brake inertia is in the family file


def test_every_brake_row_names_a_shipped_motor_and_its_source() -> None:
    for mid, r in BRAKES.items():
        row = catalog.get(mid)
        assert row["table"] == "motor" and "http" in r["brake_source"]
        if row["rotor_inertia_brake_kgm2"] is not None:
            assert row["rotor_inertia_brake_kgm2"] > row["rotor_inertia_kgm2"]


def test_a_brake_value_that_contradicts_the_family_file_is_refused() -> None:
    with pytest.raises(RuntimeError, match="rotor_inertia_brake"):
        side_tables.merge_brake({"id": "X", "rotor_inertia_brake": 1e-4}, {"rotor_inertia_brake_kgm2": "2e-4"})
    values = {"id": "X", "rotor_inertia_brake": 1e-4}
    side_tables.merge_brake(values, {"rotor_inertia_brake_kgm2": "1e-4", "brake_code": "XB", "brake_source": "s"})
    assert values == {"id": "X", "rotor_inertia_brake": 1e-4, "brake_code": "XB", "brake_source": "s"}


def test_a_schema_4_user_catalog_gains_the_brake_and_ratings_source_columns(tmp_path: Path,
                                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    drives = "id,vendor,continuous_current [A],peak_current [A],voltage [V],source\nTD-1,Testco,2,6,200,fixture\n"
    import_catalog(tmp_path, monkeypatch, USER_MOTORS, drives)
    user = db.user_db_path()
    conn = sqlite3.connect(user)
    try:
        for table, column in (("motors", "brake_holding_torque_Nm"), ("motors", "brake_code"),
                              ("motors", "brake_source"), ("drives", "ratings_source")):
            conn.execute(f"ALTER TABLE {table} DROP COLUMN {column}")
        conn.execute("UPDATE meta SET value = '4' WHERE key = 'schema_version'")
        conn.commit()
    finally:
        conn.close()
    catalog._CACHE.clear()
    assert catalog.get("TC-04")["brake_code"] is None and catalog.get("TD-1")["ratings_source"] is None
    conn = sqlite3.connect(user)
    try:
        have = {r[1] for r in conn.execute("PRAGMA table_info(motors)")}
        version = conn.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()[0]
    finally:
        conn.close()
    assert {"brake_holding_torque_Nm", "brake_code", "brake_source"} <= have and version == "5"


def test_1ft7044_brake_variant_as_printed_in_table_4_8() -> None:
    """Siemens 1FT7 configuration manual (PFT7S) 01/2009, Table 4-8 p. 90: J with brake 6.3, without 5.43
    x10^-4 kg m^2; weight with brake 8.1 kg, without 7.2 kg. No holding torque or brake code on that page."""
    r = BRAKES["1FT7044-5AK7"]
    assert num(r["rotor_inertia_brake_kgm2"]) == pytest.approx(6.3e-4, rel=1e-12)
    assert num(r["mass_brake_kg"]) == pytest.approx(8.1)
    assert r["brake_holding_torque_Nm"] == "" and r["brake_code"] == ""
    assert "Table 4-8" in r["brake_source"] and "p. 90" in r["brake_source"]
    row = catalog.get("1FT7044-5AK7")
    assert row["rotor_inertia_brake_kgm2"] == pytest.approx(6.3e-4) and row["mass_kg"] == pytest.approx(7.2)
    assert num(r["mass_brake_kg"]) > row["mass_kg"] and row["rotor_inertia_brake_kgm2"] > row["rotor_inertia_kgm2"]


def test_brake_mass_column_is_read_and_refuses_a_bad_value(monkeypatch: pytest.MonkeyPatch) -> None:
    assert side_tables.motor_brakes()["1FT7044-5AK7"]["mass_brake_kg"] == "8.1"
    text = side_tables.shipped_text("motor_brakes.csv").replace(",8.1,", ",-8.1,")
    monkeypatch.setattr(side_tables, "shipped_text", lambda name: text)
    with pytest.raises(RuntimeError, match="mass_brake_kg"):
        side_tables.motor_brakes()
