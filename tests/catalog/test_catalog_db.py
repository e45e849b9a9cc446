"""The SQLite catalog: where it lives, when it is rebuilt, the union with the user database,
query filters, lookups by id, and the ``catalog`` CLI."""

from __future__ import annotations

import csv
import io
import json
import math
import sqlite3
import sys
from pathlib import Path

import numpy as np
import pytest

from drivetrain import catalog
from drivetrain.catalog import cli, db
from drivetrain.catalog.schema import MOTOR, ROW_TABLES, SHIPPED_FILES
from drivetrain.errors import InputError
from tests.catalog.folders import fresh_dir
from tests.conftest import family_drive_rows, family_gearbox_rows, family_motor_rows

USER_MOTORS = (
    "id,vendor,series,kind,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],"
    "rotor_inertia [kg*cm^2],voltage [V],flange [mm],source\n"
    "U-400,Userco,U,ac_servo,1.27,4.46,3000,6000,0.486,400,60,bench measurement 2026-03\n"
    "U-200,Userco,U,ac_servo,2.39,8.36,3000,6000,1.59,200,80,bench measurement 2026-03\n"
)


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return db.builtin_db(tmp_path_factory.mktemp("catalog-db"))


@pytest.fixture(autouse=True)
def data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    return fresh_dir(tmp_path / "data", built, monkeypatch)


@pytest.fixture
def user_motors(tmp_path: Path) -> None:
    path = tmp_path / "user.csv"
    path.write_text(USER_MOTORS, encoding="utf-8")
    catalog.import_file(path)


def meta(path: Path, key: str) -> str:
    conn = sqlite3.connect(path)
    try:
        return str(conn.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()[0])
    finally:
        conn.close()


# ---------------------------------------------------------------------------------- building


def test_built_on_first_use_in_the_data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    empty = tmp_path / "nothing-yet"
    monkeypatch.setenv(db.ENV_DATA_DIR, str(empty))
    assert len(catalog.motors(kind="ac_servo")) == 297 + family_motor_rows()
    assert (empty / db.BUILTIN_NAME).exists()
    assert not (empty / db.USER_NAME).exists()  # queries never create the user database
    assert meta(empty / db.BUILTIN_NAME, "data_version") == catalog.DATA_VERSION
    assert not list(empty.glob(".catalog-*.tmp"))


def test_default_data_dir_is_the_platform_user_data_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(db.ENV_DATA_DIR)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("LOCALAPPDATA", str(tmp_path / "local"))
    expected = {"win32": tmp_path / "local", "darwin": tmp_path / "home" / "Library" / "Application Support"}
    assert db.data_dir() == (expected.get(sys.platform, tmp_path / "xdg") / "drivetrain").resolve()


def test_rebuilt_when_the_data_version_changes(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = data_dir / db.BUILTIN_NAME
    db.builtin_db(data_dir)
    assert meta(path, "data_version") == catalog.DATA_VERSION
    monkeypatch.setattr(db, "DATA_VERSION", "9999.01-1")
    monkeypatch.setattr(db, "_verified", set())
    db.builtin_db(data_dir)
    assert meta(path, "data_version") == "9999.01-1"
    assert len(catalog.motors()) == 595 + family_motor_rows()


def test_current_by_the_files_sizes_and_times_else_by_their_content(data_dir: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """Equal sizes and times: current without hashing. Other times, same content (a checkout): current,
    and the new times remembered. Another content: rebuilt."""
    path = data_dir / db.BUILTIN_NAME
    files = db.files_signature(f"{db.DATA_VERSION}/schema-{db.SCHEMA_VERSION}")
    assert files is not None and meta(path, "files") == files
    hashed: list[int] = []
    real_stamp = db.build_stamp
    monkeypatch.setattr(db, "build_stamp", lambda: hashed.append(1) or real_stamp())
    monkeypatch.setattr(db, "_verified", set())
    db.builtin_db(data_dir)
    assert hashed == []
    monkeypatch.setattr(db, "files_signature", lambda v: files + "|touched")
    monkeypatch.setattr(db, "_verified", set())
    db.builtin_db(data_dir)
    assert hashed == [1] and meta(path, "files") == files + "|touched" and meta(path, "stamp") == real_stamp()
    monkeypatch.setattr(db, "files_signature", lambda v: files + "|edited")
    monkeypatch.setattr(db, "build_stamp", lambda: "another content")
    monkeypatch.setattr(db, "_verified", set())
    db.builtin_db(data_dir)
    assert meta(path, "stamp") == "another content" and meta(path, "files") == files + "|edited"


def test_a_damaged_shipped_database_is_rebuilt(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (data_dir / db.BUILTIN_NAME).write_bytes(b"not a database at all")
    monkeypatch.setattr(db, "_verified", set())
    assert len(catalog.gearboxes()) == 1013 + 68 + family_gearbox_rows()  # 68 Beckhoff rows (data/SOURCES.md)


def test_imports_never_touch_the_shipped_database(data_dir: Path, user_motors: None) -> None:
    conn = sqlite3.connect(data_dir / db.BUILTIN_NAME)
    try:
        assert conn.execute("SELECT count(*) FROM motors WHERE id LIKE 'U-%'").fetchone()[0] == 0
    finally:
        conn.close()
    conn = sqlite3.connect(data_dir / db.USER_NAME)
    try:
        assert conn.execute("SELECT count(*) FROM motors").fetchone()[0] == 2
    finally:
        conn.close()


# ---------------------------------------------------------------------------------- union and filters


def test_queries_see_the_union_flagged_by_origin(user_motors: None) -> None:
    m = catalog.motors()
    assert len(m) == 595 + family_motor_rows() + 2
    assert list(m.ids[-2:]) == ["U-400", "U-200"]  # shipped rows first, then imports in order
    assert set(m.origin[:-2]) == {"builtin"} and set(m.origin[-2:]) == {"user"}
    assert catalog.get("U-400")["origin"] == "user"
    assert catalog.get("HG-KR43")["origin"] == "builtin"


def test_rows_read_each_database_in_file_order_as_the_sorted_union_does(user_motors: None) -> None:
    # rows() without a condition reads the databases one after the other; with one it sorts their union
    with db.reader() as rd:
        for spec in ROW_TABLES:
            assert rd.rows(spec) == rd.rows(spec, "1")
        motors = rd.rows(MOTOR)
    assert [r["origin"] for r in motors[-2:]] == ["user", "user"] and motors[0]["origin"] == "builtin"


def test_vendor_filter_is_case_insensitive_and_takes_several(user_motors: None) -> None:
    # configurator rows + the Yaskawa family files (motors_yaskawa_sigma2.csv, _sgm7d.csv, _sgmp.csv, ...)
    family = sum(len(list(csv.DictReader(io.StringIO(db.shipped_text(f.filename))))) for f in SHIPPED_FILES
                 if f.filename.startswith("motors_yaskawa_"))
    assert family >= 23 + 6 + 3
    assert len(catalog.motors(vendor="yaskawa")) == 38 + family
    assert len(catalog.motors(vendor=["Yaskawa", "siemens"])) == 38 + family + 31
    assert len(catalog.motors(vendor="userco")) == 2
    with pytest.raises(InputError, match="no motor vendor matches") as exc:
        catalog.motors(vendor="Rockwell")
    assert "Yaskawa" in exc.value.rule  # the message lists what exists


def test_kind_voltage_and_flange_filters(user_motors: None) -> None:
    assert len(catalog.motors(kind="small_dc")) == 298
    v400 = catalog.motors(voltage="400 V", kind="ac_servo")
    assert set(v400.voltage) == {400.0} and "U-400" in v400.ids
    # three shipped 400 V Omron motors and the 31 Siemens 1FT7 (400 V class by the series rule,
    # catalog.voltage_class); LS Mecapion has no voltage class
    assert len(v400) == 3 + 31 + 1
    v200 = catalog.motors(voltage=200, kind="ac_servo")
    assert set(v200.voltage) == {200.0} and len(v200) == 157 + 17 + 6 + 1  # 200 V rows: sigma2 17, sgm7d 6
    flange = catalog.motors(flange="80 mm")
    assert np.allclose(flange.flange, 0.080) and "U-200" in flange.ids
    with pytest.raises(InputError, match="kind"):
        catalog.motors(kind="servo")
    with pytest.raises(InputError, match="voltage"):
        catalog.motors(voltage="400 mm")


def test_ids_filter_keeps_the_order_and_names_close_matches() -> None:
    m = catalog.motors(ids=["SGM7J-04A", "HG-KR43"])
    assert list(m.ids) == ["SGM7J-04A", "HG-KR43"]
    with pytest.raises(InputError, match="did you mean HG-KR43"):
        catalog.motors(ids=["HG-KR43", "hg-kr43x"])


def test_gearbox_filters() -> None:
    assert len(catalog.gearboxes(series="gpbr")) > 0
    assert set(catalog.gearboxes(series=["GPB", "GPD"]).series) == {"GPB", "GPD"}
    small = catalog.gearboxes(kind="small_gearhead", vendor="faulhaber")
    assert len(small) == 100 and int(np.isnan(small.inertia_input).sum()) == 83  # not given in MGDB
    with pytest.raises(InputError, match="no gearbox series matches"):
        catalog.gearboxes(series="XYZ")


def test_motor_table_arrays_rows_and_take() -> None:
    m = catalog.motors(vendor="Mitsubishi")
    m = m.take(np.flatnonzero(~np.isin(m.series, ["HG-KN", "HC (MELDAS)"])))  # the 42 configurator rows
    assert m.rated_torque.dtype == np.float64 and len(m.rated_torque) == len(m) == 42
    assert np.all(np.isnan(m.stall_torque))  # Mitsubishi rows carry no stall torque
    assert not m.approx_rated.any()
    row = m.row(list(m.ids).index("HG-KR43"))
    assert row["id"] == "HG-KR43" and row["rated_torque_Nm"] == 1.3 and row["stall_torque_Nm"] is None
    assert row["approx_rated"] is False and row["curve"] is None
    json.dumps(row)  # JSON-ready
    small = m.take(m.rated_torque < 1.0)
    assert len(small) == int((m.rated_torque < 1.0).sum()) and np.all(small.rated_torque < 1.0)
    assert len(small.curves) == len(small)


def test_fanuc_rated_torques_are_flagged_derived() -> None:
    m = catalog.motors(vendor="FANUC")
    assert m.approx_rated.all() and len(m) == 24
    assert np.all(m.stall_torque >= m.rated_torque)


def test_shipped_drives_are_queryable_with_unknown_currents_as_nan() -> None:
    d = catalog.drives()
    n = 65 + family_drive_rows()  # drives_servo.csv plus the drives_<vendor>_<family>.csv files
    assert len(d) == n and d.continuous_current.shape == (n,)
    # MR-J4-_B manual 11 (b) p. 11-13: MR-J4-40B capacitor charging 11 J; 400 V class from the suffix 4
    mj4 = catalog.drives(ids=["MR-J4-40B", "MR-J4-60B4"])
    assert mj4.absorbable_energy.tolist() == [11.0, 12.0] and mj4.voltage.tolist() == [200.0, 400.0]
    yaskawa = catalog.drives(vendor="yaskawa", voltage="200 V")  # R70A...780A, currents from the transcription
    assert len(yaskawa) == 15 and not np.isnan(yaskawa.continuous_current).any()
    teco = catalog.drives(vendor="teco")  # regen data only: unknown currents are NaN
    assert len(teco) == 10 and np.isnan(teco.continuous_current).all() and np.isnan(teco.peak_current).all()
    # Yaskawa Sigma-7S manual 12.8.6 p. 12-37: SGD7S-2R8A absorbs 31.7 J
    assert yaskawa.absorbable_energy[list(yaskawa.ids).index("SGD7S-2R8A")] == pytest.approx(31.7)
    assert catalog.drive_pairs()["1FT7044-5AK7"] == ["6SL312x-xTE21-0AAx"]


# ---------------------------------------------------------------------------------- get


def test_get_returns_any_kind_with_provenance() -> None:
    motor = catalog.get("aiF4/4000")
    assert motor["table"] == "motor" and motor["derived"] == ["rated_torque"]
    assert motor["rated_torque_basis"] == "derived P/omega"
    assert motor["rated_torque_Nm"] == pytest.approx(1400 / (4000 * 2 * math.pi / 60), rel=1e-3)
    gearhead = catalog.get("354723")
    assert gearhead["table"] == "gearbox" and gearhead["kind"] == "small_gearhead"
    assert gearhead["source"].startswith("ekrimsk/MGDB@215cacc")


def test_motor_row_gives_the_columns_get_gives(user_motors: None) -> None:
    ids = [str(i) for i in catalog.motors().ids]
    for mid in [*ids[::max(1, len(ids) // 40)], "U-400"]:
        row, record = catalog.motor_row(mid), catalog.get(mid)
        assert row is not None and row["id"] == mid
        # get() gives derived as a list and derivation as {field: formula} (catalog.derive.formulas)
        skip = ("unverified", "unverified_reason", "derived", "derivation")
        assert {k: v for k, v in row.items() if k not in skip} == {k: record[k] for k in row if k not in skip}
    assert catalog.motor_row("no such motor") is None
    catalog._MOTOR_ROWS.clear()
    both = catalog.motor_rows(["U-400", "no such motor", ids[0], "U-400"])
    assert list(both) == ["U-400", ids[0]] and both["U-400"] == catalog.motor_row("U-400")
    assert list(catalog.motor_rows(i for i in ("U-400",))) == ["U-400"]  # any iterable
    assert catalog.motor_row(catalog.drives().ids[0]) is None  # a drive, not a motor


def test_get_unknown_id_suggests_close_matches() -> None:
    with pytest.raises(InputError) as exc:
        catalog.get("SGM7J-04")
    assert exc.value.field == "id" and exc.value.value == "SGM7J-04"
    assert "did you mean" in exc.value.rule and "SGM7J-04A" in exc.value.rule


def test_get_a_withheld_id_says_why() -> None:
    with pytest.raises(InputError, match="leaves it out") as exc:
        catalog.get("MPL-B320P")
    assert "2x" in exc.value.rule


# ---------------------------------------------------------------------------------- CLI


def test_cli_list_json_and_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["catalog", "list", "--vendor", "yaskawa", "--limit", "3", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["id"] for r in rows] == ["SGM7J-A5A", "SGM7J-01A", "SGM7J-C2A"]
    assert cli.main(["catalog", "list", "--kind", "gearbox", "--limit", "2"]) == 0
    out = capsys.readouterr().out
    assert "GPB042-L1-i3" in out and f"{1079 + family_gearbox_rows()} more" in out
    assert "T2B N·m" in out and "n1max rpm" in out and "bore mm" in out
    assert cli.main(["catalog", "list", "--kind", "drive"]) == 0
    out = capsys.readouterr().out
    n = 65 + family_drive_rows()  # the listing shows 50 rows unless --limit says otherwise
    assert f"drives ({min(n, 50)} of {n})" in out and "SGD7S-R70A" in out


def test_cli_show_prints_provenance(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["catalog", "show", "aiF4/4000"]) == 0
    out = capsys.readouterr().out
    assert "M000322" in out  # the source row
    assert "derived P/omega" in out and "not read from a datasheet" in out
    assert "approximate" in out
    assert "4000 rpm" in out


def test_cli_import_and_export(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "u.csv"
    path.write_text(USER_MOTORS, encoding="utf-8")
    assert cli.main(["catalog", "import", str(path)]) == 0
    assert "imported 2 motor row(s)" in capsys.readouterr().out
    out = tmp_path / "out.json"
    assert cli.main(["catalog", "export", "--origin", "user", "--format", "json", "--output", str(out)]) == 0
    assert [r["id"] for r in json.loads(out.read_text())["rows"]] == ["U-400", "U-200"]
    assert cli.main(["catalog", "export", "--kind", "gearbox", "--origin", "builtin"]) == 0
    assert len(capsys.readouterr().out.splitlines()) == 1 + 1013 + 68 + family_gearbox_rows()


def test_cli_bad_input_exits_2_without_traceback(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["catalog", "show", "NOPE-1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: id: no motor, gearbox or drive") and "Traceback" not in err
    bad = tmp_path / "bad.csv"
    bad.write_text(USER_MOTORS.replace("0.486", "-0.486"), encoding="utf-8")
    assert cli.main(["catalog", "import", str(bad)]) == 2
    assert f"{bad}:2:rotor_inertia [kg*cm^2]" in capsys.readouterr().err


def test_add_parser_registers_on_a_main_parser() -> None:
    import argparse

    parser = argparse.ArgumentParser(prog="drivetrain")
    cli.add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["catalog", "list", "--kind", "gearbox"])
    assert args.handler is cli.run and args.kind == "gearbox" and args.limit == cli.DEFAULT_LIMIT


def test_an_unwritable_data_dir_is_an_input_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(db.ENV_DATA_DIR, str(blocker / "data"))
    with pytest.raises(InputError, match=f"set {db.ENV_DATA_DIR} to a writable folder"):
        catalog.motors()


def test_a_user_catalog_of_schema_1_gains_the_new_gearbox_columns(data_dir: Path, user_motors: None) -> None:
    """Schema 2 only added gearbox columns (ratings' document, bore range, flange, pilot, verified):
    a schema-1 user catalog is brought up to date in place, its rows kept, not refused."""
    user = db.user_db_path(data_dir)
    added = ("input_bore_min_m", "input_flange_m", "input_pilot_m", "input_adapters", "verified",
             "source_document", "source_section", "source_page", "source_url")
    conn = sqlite3.connect(user)
    try:
        for column in added:
            conn.execute(f"ALTER TABLE gearboxes DROP COLUMN {column}")
        conn.execute("UPDATE meta SET value = '1' WHERE key = 'schema_version'")
        conn.commit()
    finally:
        conn.close()
    catalog._CACHE.clear()
    assert len(catalog.gearboxes(vendor="beckhoff")) == 68 + family_gearbox_rows("beckhoff_")
    assert "U-400" in set(catalog.motors(vendor="userco").ids)
    assert meta(user, "schema_version") == str(db.SCHEMA_VERSION)
    conn = sqlite3.connect(user)
    try:
        have = {r[1] for r in conn.execute("PRAGMA table_info(gearboxes)")}
    finally:
        conn.close()
    assert set(added) <= have


def test_a_user_catalog_of_an_unknown_schema_is_still_refused(data_dir: Path, user_motors: None) -> None:
    conn = sqlite3.connect(db.user_db_path(data_dir))
    try:
        conn.execute("UPDATE meta SET value = '99' WHERE key = 'schema_version'")
        conn.commit()
    finally:
        conn.close()
    catalog._CACHE.clear()
    with pytest.raises(InputError, match="schema version 99"):
        catalog.gearboxes()
