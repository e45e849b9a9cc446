"""Yaskawa SGMP 100 V servomotors (``motors_yaskawa_sgmp.csv``), read from the vendor's ratings table.

Source: the Yaskawa Σ-Series SGM/SGMP servomotor manual (DR2 Servopack), 5.2 "SGM Servomotor", 8) "Ratings and
Specifications of 100-VAC SGMP Servomotors", p. 227, read at
https://manualshive.com/en/manual/yaskawa/sgm-a3/3742213?page=239. The spot checks assert the printed values in the
printed unit (W, N m, r/min, A rms, N m/A rms, x10^-4 kg m^2 = kg cm^2). The shared invariants run in
test_catalog_motor_families.py.
"""

from __future__ import annotations

import csv
import io
import math
from importlib import resources
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db

RPM = 2 * math.pi / 60
URL = "https://manualshive.com/en/manual/yaskawa/sgm-a3/3742213?page=239"


def _rows() -> dict[str, dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", "motors_yaskawa_sgmp.csv").read_text("utf-8")
    return {r["id"]: r for r in csv.DictReader(io.StringIO(text))}


ROWS = _rows()

PRINTED = [
    ("SGMP-01B", "rated_power [W]", 100),
    ("SGMP-01B", "rated_torque [N*m]", 0.318),
    ("SGMP-01B", "peak_torque [N*m]", 0.96),
    ("SGMP-01B", "rated_current [A]", 2.2),
    ("SGMP-01B", "rotor_inertia [kg*cm^2]", 0.065),
    ("SGMP-02B", "peak_current [A]", 8.4),
    ("SGMP-02B", "torque_constant [N*m/A]", 0.258),
    ("SGMP-02B", "rotor_inertia_brake [kg*cm^2]", 0.307),
    ("SGMP-03B", "rated_power [W]", 300),
    ("SGMP-03B", "rated_torque [N*m]", 0.955),
    ("SGMP-03B", "peak_torque [N*m]", 2.86),
    ("SGMP-03B", "rated_current [A]", 4.3),
    ("SGMP-03B", "peak_current [A]", 13.9),
    ("SGMP-03B", "torque_constant [N*m/A]", 0.246),
    ("SGMP-03B", "rotor_inertia [kg*cm^2]", 0.347),
    ("SGMP-03B", "rotor_inertia_brake [kg*cm^2]", 0.445),
]


@pytest.mark.parametrize(("rid", "column", "printed"), PRINTED)
def test_values_match_the_page_they_cite(rid: str, column: str, printed: float) -> None:
    row = ROWS[rid]
    assert float(row[column]) == printed  # exact: the file holds the printed figure in the printed unit
    assert row["source_page"] == "227" and row["source_url"] == URL and "p. 227:" in row["ratings_source"]


def test_the_table_speeds_voltage_and_columns() -> None:
    """Rated and maximum speed are printed once for the table (3000 and 4500 r/min); the voltage class is the
    table's title (100 VAC). Each column is headed by a B and a W code; the id takes the B code."""
    assert list(ROWS) == ["SGMP-01B", "SGMP-02B", "SGMP-03B"]
    for rid, r in ROWS.items():
        assert (r["rated_speed [rpm]"], r["max_speed [rpm]"], r["voltage [V]"]) == ("3000", "4500", "100")
        assert r["vendor"] == "Yaskawa" and r["series"] == "SGMP" and r["brake"] == "no"
        assert f"'{rid[5:7]}W'" in r["notes"]


def test_the_printed_power_rate_confirms_the_inertia_column() -> None:
    """The table prints the rated power rate T_N^2 / J (kW/s: 15.7, 19.4, 26.3) next to the inertia without brake
    (incremental encoder); recomputing it from the stored T_N and J within 1 % (J is printed to 0.001 x10^-4 kg m^2,
    0.8 % of the 01B value) shows that the stored inertia is that column: the absolute-encoder column (0.090) would
    give 11.2 kW/s for the 01B."""
    printed = {"SGMP-01B": 15.7, "SGMP-02B": 19.4, "SGMP-03B": 26.3}
    for rid, r in ROWS.items():
        t, j = float(r["rated_torque [N*m]"]), float(r["rotor_inertia [kg*cm^2]"]) * 1e-4
        assert t * t / j / 1e3 == pytest.approx(printed[rid], rel=0.01), rid
        assert f"rated power rate {printed[rid]} kW/s" in r["notes"]


def test_torque_constant_against_the_currents() -> None:
    """K_T * I_N / T_N = 1.09...1.11 and K_T * I_peak / T_peak = 1.13...1.20: K_T and the currents share the rms
    basis the table prints."""
    for rid, r in ROWS.items():
        kt = float(r["torque_constant [N*m/A]"])
        rated = kt * float(r["rated_current [A]"]) / float(r["rated_torque [N*m]"])
        peak = kt * float(r["peak_current [A]"]) / float(r["peak_torque [N*m]"])
        assert 1.09 <= rated <= 1.11 and 1.13 <= peak <= 1.20, (rid, rated, peak)


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-sgmp")
    db.builtin_db(directory)
    return directory


def test_database_holds_the_rows_traced_and_in_si(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(db.ENV_DATA_DIR, str(data_dir))
    catalog._CACHE.clear()
    row = catalog.get("SGMP-02B")
    assert row["vendor"] == "Yaskawa" and row["verified"] == 1 and not row["unverified"]
    assert row["rated_power_W"] == pytest.approx(200.0) and row["rated_torque_Nm"] == 0.637
    assert row["peak_torque_Nm"] == 1.91 and row["voltage_V"] == pytest.approx(100.0)
    assert row["rated_speed_rad_s"] == pytest.approx(3000 * RPM) and row["max_speed_rad_s"] == pytest.approx(4500 * RPM)
    assert row["rotor_inertia_kgm2"] == pytest.approx(0.209e-4)
    assert row["rotor_inertia_brake_kgm2"] == pytest.approx(0.307e-4)
    assert row["torque_constant_Nm_per_A"] == 0.258 and row["rated_current_A"] == 2.7 and row["peak_current_A"] == 8.4
    assert set(ROWS) <= set(catalog.motors(vendor="yaskawa", voltage="100 V").ids)
    catalog._CACHE.clear()
