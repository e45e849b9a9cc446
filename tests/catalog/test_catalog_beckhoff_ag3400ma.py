"""Beckhoff AG3400 NPT planetary gear units, MA version (``gearboxes_beckhoff_ag3400ma.csv``), from Beckhoff's pages.

Source: Beckhoff Automation, AG3400 planetary gear units, documentation (English), technical data, the topics
"NPT015 MA" (https://infosys.beckhoff.com/content/1033/ag3400_ba/9188174731.html), "NPT025 MA" (.../9188219531.html)
and "NPT035 MA" (.../9201608459.html). The online manual has no page numbers; the topic number is the page. The spot
checks assert the printed values in the printed unit (N m, min^-1, %, kg, kg cm^2). The shared invariants run in
test_catalog_data.py.
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
BASE = "https://infosys.beckhoff.com/content/1033/ag3400_ba/"
TOPIC = {"NPT015": "9188174731", "NPT025": "9188219531", "NPT035": "9201608459"}


def _rows(name: str) -> dict[str, dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text("utf-8")
    return {r["id"]: r for r in csv.DictReader(io.StringIO(text))}


ROWS = _rows("gearboxes_beckhoff_ag3400ma.csv")
MF = _rows("gearboxes_beckhoff_ag3400.csv")

# (id, column, printed value in the file's unit); kg*m^2 = printed kg*cm^2 * 1e-4, efficiency = printed % / 100
PRINTED = [
    ("AG3400-NPT015-MA-i3", "rated_output_torque_Nm", 29),
    ("AG3400-NPT015-MA-i3", "max_output_torque_Nm", 55),
    ("AG3400-NPT015-MA-i3", "max_input_speed_rpm", 8000),
    ("AG3400-NPT015-MA-i12", "max_output_torque_Nm", 39),
    ("AG3400-NPT015-MA-i20", "rated_output_torque_Nm", 21),
    ("AG3400-NPT015-MA-i40", "rated_input_speed_rpm", 4600),
    ("AG3400-NPT015-MA-i40", "max_input_speed_rpm", 10000),
    ("AG3400-NPT015-MA-i40", "emergency_stop_torque_Nm", 75),
    ("AG3400-NPT015-MA-i40", "mass_kg", 2.1),
    ("AG3400-NPT025-MA-i4", "rated_input_speed_rpm", 3300),
    ("AG3400-NPT025-MA-i9", "rated_output_torque_Nm", 63),
    ("AG3400-NPT025-MA-i28", "rated_output_torque_Nm", 53),
    ("AG3400-NPT025-MA-i30", "max_output_torque_Nm", 105),
    ("AG3400-NPT025-MA-i30", "emergency_stop_torque_Nm", 190),
    ("AG3400-NPT025-MA-i3", "inertia_input_kgm2", 2.0e-4),  # 24 mm hub: 2 kg*cm^2
    ("AG3400-NPT035-MA-i4", "inertia_input_kgm2", 7.8e-4),  # 38 mm hub: 7.8 kg*cm^2
    ("AG3400-NPT035-MA-i12", "rated_output_torque_Nm", 150),
    ("AG3400-NPT035-MA-i15", "max_output_torque_Nm", 300),
    ("AG3400-NPT035-MA-i28", "rated_output_torque_Nm", 137),
    ("AG3400-NPT035-MA-i30", "max_output_torque_Nm", 270),
    ("AG3400-NPT035-MA-i40", "rated_input_speed_rpm", 3900),
    ("AG3400-NPT035-MA-i40", "max_input_speed_rpm", 7000),
    ("AG3400-NPT035-MA-i40", "efficiency", 0.95),
    ("AG3400-NPT035-MA-i3", "efficiency", 0.97),
    ("AG3400-NPT035-MA-i9", "mass_kg", 9.8),
    ("AG3400-NPT035-MA-i9", "noise_dB", 61),
]


@pytest.mark.parametrize(("rid", "column", "printed"), PRINTED)
def test_values_match_the_page_they_cite(rid: str, column: str, printed: float) -> None:
    row = ROWS[rid]
    assert float(row[column]) == pytest.approx(printed, rel=1e-12)
    model = rid.split("-")[1]
    assert row["source_url"] == BASE + TOPIC[model] + ".html"
    assert row["source_page"].startswith(f"HTML topic {TOPIC[model]}")
    assert row["source_section"] == f"{model} MA technical data, Mechanical data, 1-stage and 2-stage"
    assert row["verified"] == "yes" and row["type"] == "planetary" and row["vendor"] == "Beckhoff Automation"


def test_the_ratios_of_each_page_and_their_stage_group() -> None:
    """Ratios 3 and 4 are the 1-stage column group (97 % efficiency), every other ratio is 2-stage (95 %)."""
    by_model: dict[str, list[int]] = {}
    for r in ROWS.values():
        by_model.setdefault(r["id"].split("-")[1], []).append(int(r["ratio"]))
        one_stage = int(r["ratio"]) in (3, 4)
        assert r["stages"] == ("1" if one_stage else "2"), r["id"]
        assert r["efficiency"] == ("0.97" if one_stage else "0.95"), r["id"]
        assert r["id"] == f"AG3400-{r['id'].split('-')[1]}-MA-i{r['ratio']}"
    assert by_model == {"NPT015": [3, 4, 12, 15, 16, 20, 28, 30, 40],
                        "NPT025": [3, 4, 9, 12, 15, 16, 20, 28, 30, 40],
                        "NPT035": [3, 4, 9, 12, 15, 16, 20, 28, 30, 40]}
    assert len(ROWS) == 29


@pytest.mark.parametrize("model", ["NPT015", "NPT025", "NPT035"])
def test_the_one_stage_columns_repeat_the_mf_pages_one_stage_values(model: str) -> None:
    """The stage assignment of the merged cells: on each MA page the columns i = 3 and 4 print the input inertia per
    hub, the weight and the nominal input speed that the MF page (all 1-stage) prints for i = 3 and 4."""
    for i in (3, 4):
        ma, mf = ROWS[f"AG3400-{model}-MA-i{i}"], MF[f"AG3400-{model}-MF-i{i}"]
        for column in ("inertia_input_kgm2", "mass_kg", "rated_input_speed_rpm", "input_bore_max_mm"):
            assert float(ma[column]) == float(mf[column]), (model, i, column)
        assert ma["rated_output_torque_Nm"] != mf["rated_output_torque_Nm"]  # the MA version is another product


def test_values_not_in_the_copy_read_stay_empty() -> None:
    """The copies read end at 'Torsion and forces'; the NPT025 MA row of n1Max is cut after its first value."""
    for r in ROWS.values():
        assert not any(r[c] for c in ("backlash_arcmin", "torsional_stiffness_Nm_per_arcmin", "max_axial_load_N",
                                      "max_radial_load_N", "max_tilting_moment_Nm")), r["id"]
        assert "the copy read ends at the heading 'Torsion and forces'" in r["notes"]
    missing = {rid for rid, r in ROWS.items() if not r["max_input_speed_rpm"]}
    assert missing == {f"AG3400-NPT025-MA-i{i}" for i in (9, 12, 15, 16, 20, 28, 30, 40)}
    assert all("maximum input speed left empty" in ROWS[rid]["notes"] for rid in missing)
    assert ROWS["AG3400-NPT025-MA-i3"]["max_input_speed_rpm"] == "7000"


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-ag3400ma")
    db.builtin_db(directory)
    return directory


def test_database_holds_the_rows_traced_and_in_si(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(db.ENV_DATA_DIR, str(data_dir))
    catalog._CACHE.clear()
    g = catalog.get("AG3400-NPT035-MA-i9")
    assert g["vendor"] == "Beckhoff Automation" and g["verified"] == 1 and g["type"] == "planetary"
    assert g["model"] == "AG3400-NPT035-MA" and g["ratio"] == 9 and g["stages"] == 2
    assert g["rated_output_torque_Nm"] == 155 and g["max_output_torque_Nm"] == 305
    assert g["emergency_stop_torque_Nm"] == 480 and g["efficiency"] == pytest.approx(0.95)
    assert g["rated_input_speed_rad_s"] == pytest.approx(3100 * RPM)
    assert g["max_input_speed_rad_s"] == pytest.approx(7000 * RPM)
    assert g["inertia_input_kgm2"] == pytest.approx(1.9e-4)
    assert (g["input_bore_min_m"], g["input_bore_max_m"]) == pytest.approx((0.014, 0.028))
    assert g["source_url"] == BASE + "9201608459.html"
    table = catalog.gearboxes(series="AG3400 NPT", kind="servo_gearbox")
    ids = set(table.ids)
    assert set(ROWS) <= ids and "AG3400-NPT035-MF-i10" in ids
    catalog._CACHE.clear()
