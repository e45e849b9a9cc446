"""A catalog you can trace and manage: every shipped row traced or flagged unverified (and the answer
says so), sources per field group, the example import files, remove / replace / edit with a history,
and a user catalog from a path (--catalog, DRIVETRAIN_CATALOG)."""

from __future__ import annotations

import json
import math
import shutil
import sqlite3
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db, manage
from drivetrain.catalog.cli import UNVERIFIED_MARK
from drivetrain.catalog.schema import FIELD_GROUPS, GEARBOX, MOTOR, trace
from drivetrain.cli import main
from drivetrain.errors import InputError, InputErrors
from tests.catalog.folders import fresh_dir
from tests.conftest import family_motor_rows

EXAMPLES = Path(__file__).parents[2] / "examples" / "catalog"
RPM = 2 * math.pi / 60

MINE = (
    "id,vendor,series,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],"
    "rotor_inertia [kg*cm^2],source\n"
    "MINE-1,Userco,U,1.3,4.5,3000,6000,0.37,Userco U datasheet p. 4\n"
    "MINE-2,Userco,U,2.4,7.1,3000,6000,1.1,Userco U datasheet p. 4\n"
)


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return db.builtin_db(tmp_path_factory.mktemp("catalog-manage"))


@pytest.fixture(autouse=True)
def data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    base = fresh_dir(tmp_path / "data", built, monkeypatch)
    # set (empty: the default file), not deleted, so that teardown also undoes a --catalog of a test
    monkeypatch.setenv(db.ENV_CATALOG, "")
    catalog._CACHE.clear()
    return base


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def messages(exc: pytest.ExceptionInfo[InputError]) -> list[str]:
    errs = exc.value.errors if isinstance(exc.value, InputErrors) else [exc.value]
    return [e.message for e in errs]


# ---------------------------------------------------------------------------------- provenance


def test_every_shipped_row_is_traced_or_flagged_with_a_reason() -> None:
    with db.reader() as rd:
        for spec in (MOTOR, GEARBOX):
            rows = rd.rows(spec)
            assert rows
            for row in rows:
                unverified, reason = trace(row)
                if unverified:
                    assert reason.strip(), row["id"]
                else:  # traced: a vendor document with the address of the copy read
                    assert row["verified"] == 1, row["id"]
                    assert row["source_document"] and row["source_url"].startswith("https://"), row["id"]


def test_derived_ratings_and_configurator_rows_are_unverified_and_say_why() -> None:
    fanuc = catalog.motors(vendor="fanuc")
    assert len(fanuc) == 24 and fanuc.unverified.all()  # all 24 FANUC rated torques are P / omega
    assert all("rated torque derived" in r for r in fanuc.unverified_reason)
    hg = catalog.get("HG-KR43")
    assert hg["unverified"] and "configurator" in hg["unverified_reason"]
    assert "derived" not in hg["unverified_reason"]
    small = catalog.get("354723")  # an MGDB gearhead
    assert small["unverified"] and "MGDB" in small["unverified_reason"]
    gplus = catalog.get("GPB042-L1-i3")  # verified=no on the drawings: the notes' own reason
    assert gplus["unverified"] and "T2B is not printed on the drawings" in gplus["unverified_reason"]
    beckhoff = catalog.get("AG2250-PLE040-i3")
    assert not beckhoff["unverified"] and beckhoff["unverified_reason"] == ""


def test_the_1ft7044_row_cites_siemens_table_4_8_on_page_90() -> None:
    """Siemens 1FT7 Configuration Manual (PFT7S) 01/2009, Table 4-8, p. 90: rated 2 N m at 6,000 rpm,
    Mmax 23 N m, n max mech 9,000 rpm, J without brake 5.43e-4 kg m^2, 7.2 kg."""
    row = catalog.get("1FT7044-5AK7")
    assert not row["unverified"] and row["verified"] == 1
    assert row["source_page"] == "90" and "Table 4-8" in row["source_section"]
    assert row["source_url"] == "https://www.easymanua.ls/siemens/1ft7/manual/704590?p=90"
    assert row["rated_torque_Nm"] == 2 and row["peak_torque_Nm"] == 23
    assert row["rated_speed_rad_s"] == pytest.approx(6000 * RPM)
    assert row["max_speed_rad_s"] == pytest.approx(9000 * RPM)
    assert row["rotor_inertia_kgm2"] == pytest.approx(5.43e-4) and row["mass_kg"] == 7.2
    assert "Table 4-8, p. 90" in row["sources"]["ratings"] and "Configuration Manual" in row["sources"]["ratings"]


def test_sources_per_field_group() -> None:
    motor = catalog.get("HG-KR43")
    assert set(motor["sources"]) == {*FIELD_GROUPS, "curve"}
    assert motor["sources"]["ratings"] == motor["source"]
    assert motor["sources"]["curve"].startswith("none")
    gearbox = catalog.get("AG2250-PLE040-i3")
    assert "https://infosys.beckhoff.com" in gearbox["sources"]["ratings"]
    assert "electrical" not in gearbox["sources"] and "curve" not in gearbox["sources"]  # a gearbox has none
    assert catalog.get("HG-KR43")["sources"]["electrical"] == catalog.get("HG-KR43")["source"]  # its voltage


def test_catalog_show_prints_the_sources_and_the_flag(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "show", "HG-KR43"]) == 0
    out = capsys.readouterr().out
    for group in ("ratings", "mechanical", "electrical", "curve"):
        assert f"source: {group}" in out
    assert "verified" in out and "configurator" in out


def test_catalog_list_marks_unverified_rows(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "list", "--kind", "gearbox", "--vendor", "beckhoff", "--limit", "3"]) == 0
    assert UNVERIFIED_MARK.strip() not in capsys.readouterr().out  # Beckhoff rows are traced
    assert main(["catalog", "list", "--vendor", "fanuc", "--limit", "2"]) == 0
    out = capsys.readouterr().out
    assert f"beta 0.2/5000is{UNVERIFIED_MARK}" in out and "unverified: 2 of the rows shown" in out


def test_the_answer_carries_unverified_and_the_catalog_version() -> None:
    from drivetrain.axis.yaml_text import parse_yaml
    from drivetrain.sizing.pipeline import size

    axis = parse_yaml((Path(__file__).parents[2] / "examples" / "rotary.yaml").read_text())
    axis["motor"] = {"select": {"vendor": "fanuc"}}
    out = size(axis).to_dict()
    assert out["catalog_version"] == catalog.DATA_VERSION
    assert out["candidates"]
    for cand in out["candidates"]:
        assert cand["unverified"] is True and "motor: " in cand["unverified_reason"]
        assert "rated torque derived" in cand["unverified_reason"]
    axis["motor"] = {"id": "1FT7044-5AK7"}
    given = size(axis).to_dict()
    assert given["motor"]["unverified"] is False and given["motor"]["unverified_reason"] is None
    axis["motor"] = {"id": "HG-KR43"}
    given = size(axis).to_dict()
    assert given["motor"]["unverified"] is True and "configurator" in given["motor"]["unverified_reason"]


# ---------------------------------------------------------------------------------- example files


def test_each_example_file_imports(data_dir: Path) -> None:
    """examples/catalog: one file per table, imported in order (the curve needs its motor)."""
    reports = {f: catalog.import_file(EXAMPLES / f) for f in ("motors.csv", "curves.csv", "drives.csv",
                                                              "gearboxes.json")}
    assert [r.table for r in reports.values()] == ["motor", "curve", "drive", "gearbox"]
    motor = catalog.get("1FT7044-5AK7-brake")
    # Siemens Table 4-8 p. 90: with brake 6.3e-4 kg m^2 and 8.1 kg; k_T 0.88 N m/A; L_D 4.2 mH
    assert motor["rotor_inertia_kgm2"] == pytest.approx(6.3e-4) and motor["mass_kg"] == 8.1
    assert motor["torque_constant_Nm_per_A"] == 0.88 and motor["winding_inductance_H"] == pytest.approx(4.2e-3)
    assert motor["curve"]["continuous_torque_Nm"] == [5.0, 2.0] and motor["curve"]["peak_torque_Nm"] == [23.0, None]
    assert not motor["unverified"] and "Table 4-8" in motor["sources"]["curve"]
    drive = catalog.get("S120-MM-9A")
    assert (drive["continuous_current_A"], drive["peak_current_A"], drive["voltage_V"]) == (9, 18, 400)
    gearbox = catalog.get("MY-AG2250-PLE040-i5")
    shipped = catalog.get("AG2250-PLE040-i5")
    for key in ("ratio", "rated_output_torque_Nm", "max_output_torque_Nm", "efficiency", "inertia_input_kgm2",
                "max_input_speed_rad_s", "backlash_rad", "torsional_stiffness_Nm_per_rad"):
        assert gearbox[key] == pytest.approx(shipped[key]), key
    assert "S120-MM-9A" in set(catalog.drives().ids)  # the imported drive beside the shipped ones


# ---------------------------------------------------------------------------------- remove


def test_remove_takes_user_rows_with_their_curve_and_logs_it(tmp_path: Path, data_dir: Path) -> None:
    catalog.import_file(EXAMPLES / "motors.csv")
    catalog.import_file(EXAMPLES / "curves.csv")
    assert catalog.remove(["1FT7044-5AK7-brake"]) == 1
    with pytest.raises(InputError, match="no motor, gearbox or drive"):
        catalog.get("1FT7044-5AK7-brake")
    with db.reader() as rd:
        assert rd.curves(["1FT7044-5AK7-brake"]) == {}
    actions = [e["action"] for e in catalog.history("1FT7044-5AK7-brake")]
    assert actions == ["import", "import curve", "remove"]
    removed = catalog.history("1FT7044-5AK7-brake")[-1]
    assert removed["old_values"]["rotor_inertia_kgm2"] == pytest.approx(6.3e-4)
    assert removed["old_values"]["curve_points"] == 2 and removed["new_values"] is None


def test_remove_is_all_or_nothing_and_refuses_shipped_rows(tmp_path: Path) -> None:
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    with pytest.raises(InputErrors) as exc:
        catalog.remove(["MINE-1", "HG-KR43", "MINE-9"])
    found = messages(exc)
    assert any("HG-KR43" in m and "shipped catalog" in m for m in found)
    assert any("MINE-9" in m and "did you mean" in m and "MINE-1" in m for m in found)
    assert {"MINE-1", "MINE-2"} <= set(catalog.motors(vendor="userco").ids)  # nothing removed
    assert catalog.get("HG-KR43")["origin"] == "builtin"


def test_cli_remove_and_history(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "import", str(write(tmp_path, "mine.csv", MINE))]) == 0
    assert main(["catalog", "remove", "MINE-1", "MINE-2"]) == 0
    assert "removed 2 row(s)" in capsys.readouterr().out
    assert main(["catalog", "remove", "HG-KR43"]) == 2
    assert "shipped catalog" in capsys.readouterr().err
    assert main(["catalog", "history", "--json"]) == 0
    entries = json.loads(capsys.readouterr().out)
    assert [(e["action"], e["id"]) for e in entries] == [("import", "MINE-1"), ("import", "MINE-2"),
                                                         ("remove", "MINE-1"), ("remove", "MINE-2")]
    assert entries[0]["source"] == "Userco U datasheet p. 4"


# ---------------------------------------------------------------------------------- replace


def test_import_replace_updates_user_rows_in_one_transaction(tmp_path: Path, data_dir: Path) -> None:
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    changed = MINE.replace("MINE-1,Userco,U,1.3,", "MINE-1,Userco,U,1.4,") + (
        "MINE-3,Userco,U,3.2,9.5,3000,6000,1.6,Userco U datasheet p. 5\n")
    path = write(tmp_path, "mine2.csv", changed)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    assert any("use --replace to update it" in m for m in messages(exc))
    report = catalog.import_file(path, replace=True)
    assert report.rows == 3
    assert catalog.get("MINE-1")["rated_torque_Nm"] == 1.4
    assert catalog.get("MINE-3")["origin"] == "user"
    replaced = [e for e in catalog.history("MINE-1") if e["action"] == "replace"]
    assert len(replaced) == 1 and replaced[0]["old_values"]["rated_torque_Nm"] == 1.3
    assert replaced[0]["new_values"]["rated_torque_Nm"] == 1.4


def test_replace_never_touches_shipped_rows_and_a_bad_row_keeps_everything(tmp_path: Path, data_dir: Path) -> None:
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    before = (data_dir / db.USER_NAME).read_bytes()
    bad = MINE.replace("MINE-2,Userco,U,2.4,7.1,", "MINE-2,Userco,U,2.4,1.0,") + (
        "HG-KR43,Userco,U,1.3,4.5,3000,6000,0.37,x\n")
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(write(tmp_path, "bad.csv", bad), replace=True)
    found = messages(exc)
    assert any("peak_torque" in m and "must be >= rated_torque" in m for m in found)
    assert any("shipped catalog, which cannot be changed" in m for m in found)
    assert (data_dir / db.USER_NAME).read_bytes() == before


def test_replace_of_a_curve_file_renews_the_motors_curve(tmp_path: Path) -> None:
    catalog.import_file(EXAMPLES / "motors.csv")
    catalog.import_file(EXAMPLES / "curves.csv")
    again = write(tmp_path, "c.csv", "motor_id,speed [rpm],continuous_torque [N*m]\n1FT7044-5AK7-brake,0,4.4\n")
    with pytest.raises(InputErrors, match="already has a point at this speed"):
        catalog.import_file(again)
    catalog.import_file(again, replace=True)
    assert catalog.get("1FT7044-5AK7-brake")["curve"]["continuous_torque_Nm"] == [4.4]
    assert catalog.history("1FT7044-5AK7-brake")[-1]["action"] == "replace curve"


# ---------------------------------------------------------------------------------- edit


def test_edit_a_user_row_validated_as_an_import(tmp_path: Path) -> None:
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    row = catalog.update("MINE-1", {"rotor_inertia [kg*cm^2]": 0.41, "voltage": "400 V", "notes": "checked"})
    assert row["rotor_inertia_kgm2"] == pytest.approx(0.41e-4) and row["voltage_V"] == 400
    assert row["notes"] == "checked" and row["rated_torque_Nm"] == 1.3  # the rest unchanged
    assert catalog.motors(voltage="400 V", vendor="userco").ids.tolist() == ["MINE-1"]
    with pytest.raises(InputError, match="must be >= rated_torque"):
        catalog.update("MINE-1", {"peak_torque": 1.0})
    with pytest.raises(InputError, match="cannot be changed"):
        catalog.update("MINE-1", {"id": "MINE-X"})
    with pytest.raises(InputError, match="not a motor field"):
        catalog.update("MINE-1", {"colour": "red"})
    with pytest.raises(InputError, match="shipped catalog"):
        catalog.update("HG-KR43", {"rated_torque": 1.0})
    row = catalog.update("MINE-1", {"voltage": None})
    assert row["voltage_V"] is None
    edits = [e for e in catalog.history("MINE-1") if e["action"] == "edit"]
    assert len(edits) == 2 and edits[0]["old_values"]["rotor_inertia_kgm2"] == pytest.approx(0.37e-4)


# ---------------------------------------------------------------------------------- shared user catalog


def test_a_shared_catalog_file_serves_two_data_folders(tmp_path: Path, built: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    team = tmp_path / "team" / "team.sqlite"
    monkeypatch.setenv(db.ENV_CATALOG, str(team))
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    assert team.exists()
    other = tmp_path / "other"
    other.mkdir()
    shutil.copy(built, other / db.BUILTIN_NAME)
    monkeypatch.setenv(db.ENV_DATA_DIR, str(other))
    catalog._CACHE.clear()
    assert catalog.get("MINE-2")["origin"] == "user"
    assert not (other / db.USER_NAME).exists()
    shipped = 595 + family_motor_rows()  # shipped rows beside it
    assert len(catalog.motors()) == len(catalog.motors(vendor="userco")) + shipped


def test_cli_catalog_option(tmp_path: Path, data_dir: Path, capsys: pytest.CaptureFixture[str],
                            monkeypatch: pytest.MonkeyPatch) -> None:
    team = tmp_path / "team.sqlite"
    assert main(["--catalog", str(team), "catalog", "import", str(write(tmp_path, "mine.csv", MINE))]) == 0
    assert str(team) in capsys.readouterr().out
    assert not (data_dir / db.USER_NAME).exists()
    monkeypatch.setenv(db.ENV_CATALOG, "")
    catalog._CACHE.clear()
    assert main(["catalog", "--catalog", str(team), "list", "--source", "user"]) == 0
    out = capsys.readouterr().out
    assert "MINE-1" in out and "MINE-2" in out and "HG-KR43" not in out
    monkeypatch.setenv(db.ENV_CATALOG, "")
    assert main(["catalog", "list", "--source", "user"]) == 0
    assert "no motors in your catalog" in capsys.readouterr().out
    assert main(["--catalog", str(tmp_path), "catalog", "list"]) == 2
    assert "not a folder" in capsys.readouterr().err


def test_a_file_that_is_not_a_catalog_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    junk = write(tmp_path, "junk.sqlite", "this is not a database " * 100)
    monkeypatch.setenv(db.ENV_CATALOG, str(junk))
    with pytest.raises(InputError, match="not a drivetrain catalog"):
        catalog.motors()
    with pytest.raises(InputError, match="not a drivetrain catalog"):
        catalog.import_file(write(tmp_path, "mine.csv", MINE))


def test_a_schema_2_user_catalog_gains_the_new_columns_and_history(tmp_path: Path, data_dir: Path) -> None:
    catalog.import_file(write(tmp_path, "mine.csv", MINE))
    user = db.user_db_path(data_dir)
    added = ("source_document", "source_section", "source_page", "source_url", "verified", "unverified_reason",
             "ratings_source", "mechanical_source", "electrical_source")
    conn = sqlite3.connect(user)
    try:
        for column in added:
            conn.execute(f"ALTER TABLE motors DROP COLUMN {column}")
        conn.execute("ALTER TABLE gearboxes DROP COLUMN unverified_reason")
        conn.execute("DROP TABLE history")
        conn.execute("UPDATE meta SET value = '2' WHERE key = 'schema_version'")
        conn.commit()
    finally:
        conn.close()
    catalog._CACHE.clear()
    assert "MINE-1" in set(catalog.motors(vendor="userco").ids)
    assert catalog.history() == []
    catalog.remove(["MINE-2"])
    assert [e["action"] for e in catalog.history()] == ["remove"]
    assert manage.user_ids() == {"MINE-1": "motor"}


def test_the_report_and_the_size_table_say_the_motor_data_is_unverified(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("jinja2")
    from drivetrain.axis.yaml_text import parse_yaml
    from drivetrain.report.model import build_report
    from drivetrain.sizing.pipeline import size

    axis = parse_yaml((Path(__file__).parents[2] / "examples" / "rotary.yaml").read_text())
    axis["motor"] = {"id": "HG-KR43"}
    notes = build_report(size(axis)).notes
    assert any("catalog data is unverified" in n and "configurator" in n for n in notes)
    axis["motor"] = {"id": "1FT7044-5AK7"}
    assert not any("unverified:" in n for n in build_report(size(axis)).notes)
    assert main(["size", str(Path(__file__).parents[2] / "examples" / "rotary.yaml")]) in (0, 1)
    out = capsys.readouterr().out
    assert "†" in out and "unverified catalog data" in out
