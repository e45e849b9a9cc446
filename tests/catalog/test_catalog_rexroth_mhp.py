"""Bosch Rexroth MHP servo motors (``motors_rexroth_mhp.csv``), read from the vendor's technical-data pages.

Each row is one page ("10.1 Technical data" MHP093A-024, "12.1 Technical data" MHP112A-024) of the Rexroth MHP
synchronous-motor documentation as mirrored at 123dok.org; the spot checks assert the values printed there, in the
printed unit. The shared invariants (power = T * omega, peak >= rated, ...) run in test_catalog_motor_families.py.
"""

from __future__ import annotations

import csv
import io
import math
from importlib import resources
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db, schema

RPM = 2 * math.pi / 60
_URL = "https://123dok.org/article/technical-data-mhp-rexroth-mhpsynchronous-motors-powerdrive-{}.yj7vjmp5"


def _rows() -> dict[str, dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", "motors_rexroth_mhp.csv").read_text("utf-8")
    return {r["id"]: r for r in csv.DictReader(io.StringIO(text))}


ROWS = _rows()

# (id, column, printed value, section); MHP093A-024: 10.1 'Technical data', MHP112A-024: 12.1 'Technical data'.
PRINTED = [
    ("MHP093A-024", "rated_power [kW]", 1.7, "10.1"),
    ("MHP093A-024", "rated_torque [N*m]", 8.3, "10.1"),
    ("MHP093A-024", "stall_torque [N*m]", 12.0, "10.1"),
    ("MHP093A-024", "peak_torque [N*m]", 44.0, "10.1"),
    ("MHP093A-024", "rated_speed [rpm]", 2000, "10.1"),
    ("MHP093A-024", "max_speed [rpm]", 6000, "10.1"),
    ("MHP093A-024", "rotor_inertia [kg*cm^2]", 17.3, "10.1"),
    ("MHP093A-024", "peak_current [A]", 23.9, "10.1"),
    ("MHP093A-024", "mass [kg]", 14.5, "10.1"),
    ("MHP112A-024", "rated_power [kW]", 2.6, "12.1"),
    ("MHP112A-024", "rated_torque [N*m]", 10.1, "12.1"),
    ("MHP112A-024", "peak_torque [N*m]", 54.0, "12.1"),
    ("MHP112A-024", "rated_speed [rpm]", 2500, "12.1"),
    ("MHP112A-024", "max_speed [rpm]", 4500, "12.1"),
    ("MHP112A-024", "rotor_inertia [kg*cm^2]", 110, "12.1"),
    ("MHP112A-024", "rated_current [A]", 6.2, "12.1"),
    ("MHP112A-024", "stall_current [A]", 9.2, "12.1"),
    ("MHP112A-024", "thermal_time_constant [min]", 90, "12.1"),
]


@pytest.mark.parametrize(("rid", "column", "printed", "section"), PRINTED)
def test_values_match_the_page_they_cite(rid: str, column: str, printed: float, section: str) -> None:
    row = ROWS[rid]
    assert float(row[column]) == printed  # exact: the file holds the printed figure in the printed unit
    assert row["source_section"].split(", ")[1].startswith(section) and row["source_page"].startswith(section)
    assert row["source_url"] == _URL.format({"10.1": 2, "12.1": 4}[section])


def test_every_row_is_traced_to_its_own_page() -> None:
    assert set(ROWS) == {"MHP093A-024", "MHP112A-024"}
    assert "rexroth_mhp" in schema.TRACED_MOTOR_FAMILIES
    for rid, r in ROWS.items():
        assert r["vendor"] == "Bosch Rexroth" and r["series"] == "MHP" and r["model"] == rid
        assert r["verified"] == "yes" and r["rated_torque_basis"] == "source"
        assert r["source_url"] in r["source"] and r["brake"] == "no"


def test_values_whose_basis_is_not_printed_stay_in_the_notes() -> None:
    """K_m, K_E, R12 and L12 are printed without their basis (phase or line-to-line): notes only, never numbers."""
    for rid, r in ROWS.items():
        for column in r:
            assert not column.startswith(("torque_constant", "winding_", "back_emf", "voltage")), (rid, column)
    assert "KmE 2.5 Nm/A" in ROWS["MHP093A-024"]["notes"]
    assert "R12 1.45 ohm" in ROWS["MHP112A-024"]["notes"] and "R1 0.73 ohm" in ROWS["MHP112A-024"]["notes"]


def test_rated_power_is_torque_times_base_speed_within_the_printed_rounding() -> None:
    """PN is printed to 0.1 kW: MN * nN lies within 2.5 % of it, and the electrical frequency fN printed on the
    page equals nN * PZ / 60 (PZ = 4 pole pairs), which confirms that the base speed is the rated point."""
    for rid, fn in (("MHP093A-024", 133), ("MHP112A-024", 167)):
        r = ROWS[rid]
        p = float(r["rated_power [kW]"]) * 1000
        tn = float(r["rated_torque [N*m]"]) * float(r["rated_speed [rpm]"]) * RPM
        assert abs(tn - p) <= 0.025 * p
        assert float(r["rated_speed [rpm]"]) * int(r["pole_count"]) / 2 / 60 == pytest.approx(fn, abs=0.5)
        assert f"fN {fn} Hz" in r["notes"]


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-mhp")
    db.builtin_db(directory)
    return directory


def test_database_holds_the_rows_traced_and_in_si(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(db.ENV_DATA_DIR, str(data_dir))
    catalog._CACHE.clear()
    row = catalog.get("MHP112A-024")
    assert row["vendor"] == "Bosch Rexroth" and row["kind"] == "ac_servo"
    assert row["verified"] == 1 and not row["unverified"]
    assert row["rated_power_W"] == pytest.approx(2600.0) and row["rated_torque_Nm"] == 10.1
    assert row["stall_torque_Nm"] == 15.0 and row["peak_torque_Nm"] == 54.0
    assert row["rated_speed_rad_s"] == pytest.approx(2500 * RPM) and row["max_speed_rad_s"] == pytest.approx(4500 * RPM)
    assert row["rotor_inertia_kgm2"] == pytest.approx(110e-4) and row["mass_kg"] == 23.0
    assert row["peak_current_A"] == 41.4 and row["pole_count"] == 8
    assert row["thermal_time_constant_s"] == pytest.approx(90 * 60.0)
    # k_T not stored as printed (20 degC, basis not stated): derived from the printed stall pair, T_0 / I_0
    assert row["torque_constant_Nm_per_A"] == pytest.approx(15.0 / 9.2) and row["winding_resistance_ohm"] is None
    assert row["derived"] == ["torque_constant"]
    assert "stall_torque / stall_current" in row["derivation"]["torque_constant"]
    assert "123dok.org" in row["source_url"]
    assert set(catalog.motors(vendor="rexroth").ids) == {"MHP093A-024", "MHP112A-024"}
