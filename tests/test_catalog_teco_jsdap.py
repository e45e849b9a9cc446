"""TECO JSDAP servo drives (``drives_teco_jsdap.csv``), read from the vendor's regeneration tables.

Source: the TECO JSDAP series AC servo drive user manual, 5-6-7 "Selecting for External Regeneration Resistor",
p. 5-70 (built-in regeneration resistor: resistance, power, average regeneration power it absorbs, minimum allowed
external resistance), read at https://www.easymanua.ls/teco/jsdap-15a/manual?p=156, and the table on p. 5-72 (main
capacitor energy absorption capacity E_C in joules, printed once per drive for JSDAP-15 ... JSDAP-75), read at
https://www.easymanua.ls/teco/jsdap-15a/manual?p=158. The spot checks assert the printed values in the printed unit.
"""

from __future__ import annotations

import csv
import io
from importlib import resources
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db
from drivetrain.catalog.schema import SHIPPED_FILES, TRACED_DRIVE_FAMILIES

P156 = "https://www.easymanua.ls/teco/jsdap-15a/manual?p=156"
P158 = "https://www.easymanua.ls/teco/jsdap-15a/manual?p=158"


def _rows() -> dict[str, dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", "drives_teco_jsdap.csv").read_text("utf-8")
    return {r["id"]: r for r in csv.DictReader(io.StringIO(text))}


ROWS = _rows()

# (row id, column, value printed on p. 5-70)
PRINTED_P70 = [
    ("JSDAP-15", "braking_resistor_ohm", 25),
    ("JSDAP-15", "braking_resistor_power_W", 60),
    ("JSDAP-30", "braking_resistor_average_power_W", 24),
    ("JSDAP-30", "min_resistance_ohm", 25),
    ("JSDAP-50", "braking_resistor_ohm", 20),
    ("JSDAP-50", "min_resistance_ohm", 15),
    ("JSDAP-75", "braking_resistor_ohm", 12.5),
    ("JSDAP-100", "braking_resistor_power_W", 150),
    ("JSDAP-100", "min_resistance_ohm", 10),
    ("JSDAP-150", "braking_resistor_ohm", 8),
    ("JSDAP-150", "braking_resistor_power_W", 200),
    ("JSDAP-150", "braking_resistor_average_power_W", 80),
    ("JSDAP-150", "min_resistance_ohm", 6),
    ("JSDAP-300", "min_resistance_ohm", 3),
]

# (row id, E_C in J printed on p. 5-72)
PRINTED_P72 = [("JSDAP-15", 6), ("JSDAP-20", 9), ("JSDAP-30", 13), ("JSDAP-50", 13), ("JSDAP-75", 18)]


def test_the_family_is_shipped_as_a_traced_drive_file() -> None:
    assert "teco_jsdap" in TRACED_DRIVE_FAMILIES
    assert any(f.filename == "drives_teco_jsdap.csv" and f.table.name == "drive" for f in SHIPPED_FILES)
    assert list(ROWS) == [f"JSDAP-{n}" for n in (15, 20, 30, 50, 75, 100, 150, 200, 300)]
    for r in ROWS.values():
        assert r["vendor"] == "TECO" and r["series"] == "JSDAP" and r["model"] == r["id"]
        assert r["source_page"] == "5-70" and r["source_url"] == P156 and "p. 5-70" in r["source"]


@pytest.mark.parametrize(("rid", "column", "printed"), PRINTED_P70)
def test_regeneration_resistor_values_match_page_5_70(rid: str, column: str, printed: float) -> None:
    assert float(ROWS[rid][column]) == printed  # exact: the file holds the printed figure


@pytest.mark.parametrize(("rid", "printed"), PRINTED_P72)
def test_capacitor_energy_matches_page_5_72(rid: str, printed: float) -> None:
    row = ROWS[rid]
    assert float(row["absorbable_energy [J]"]) == printed
    assert P158 in row["source"] and f"E_C = {printed} J" in row["notes"]


def test_what_the_pages_do_not_print_stays_empty() -> None:
    """JSDAP-200/300 print '─' for the built-in resistor; p. 5-72 stops at JSDAP-75; no page read prints the
    supply voltage or an output current, so those cells are empty (never estimated)."""
    for rid in ("JSDAP-200", "JSDAP-300"):
        r = ROWS[rid]
        assert r["builtin_braking_resistor"] == "no"
        assert r["braking_resistor_ohm"] == r["braking_resistor_power_W"] == r["braking_resistor_average_power_W"] == ""
    for rid in ("JSDAP-100", "JSDAP-150", "JSDAP-200", "JSDAP-300"):
        assert ROWS[rid]["absorbable_energy [J]"] == ""
    for r in ROWS.values():
        assert r["continuous_current_A"] == r["peak_current_A"] == r["peak_time [s]"] == r["voltage_V"] == ""


def test_average_regeneration_power_is_40_percent_of_the_resistor_rating() -> None:
    """The printed average power is 40 % of the built-in resistor's rating on every drive that has one (the
    JSDG2S manual prints 20 %): a cross-check that no cell slipped a column."""
    for rid, r in ROWS.items():
        if r["builtin_braking_resistor"] == "yes":
            assert float(r["braking_resistor_average_power_W"]) == pytest.approx(
                0.4 * float(r["braking_resistor_power_W"])), rid
            assert float(r["min_resistance_ohm"]) <= float(r["braking_resistor_ohm"]), rid


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-jsdap")
    db.builtin_db(directory)
    return directory


def test_database_holds_the_drives_in_si(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(db.ENV_DATA_DIR, str(data_dir))
    catalog._CACHE.clear()
    row = catalog.get("JSDAP-75")
    assert row["table"] == "drive" and row["vendor"] == "TECO" and row["origin"] == "builtin"
    assert row["braking_resistor_ohm"] == 12.5 and row["braking_resistor_power_W"] == 150.0
    assert row["braking_resistor_average_power_W"] == 60.0 and row["min_resistance_ohm"] == 10.0
    assert row["absorbable_energy_J"] == 18.0 and row["builtin_braking_resistor"] == 1
    assert row["continuous_current_A"] is None and row["peak_current_A"] is None
    assert catalog.get("JSDAP-300")["builtin_braking_resistor"] == 0
    assert {"JSDAP-15", "JSDAP-300"} <= set(catalog.drives().ids)
    catalog._CACHE.clear()
