"""Importing user data: units in headers, validation with line and column, all-or-nothing writes,
surviving a killed import, and export/import round trips."""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import db, importer
from drivetrain.errors import InputError, InputErrors
from tests.catalog.folders import fresh_dir
from tests.conftest import family_gearbox_rows, family_motor_rows

RPM = 2 * math.pi / 60
LBF_IN = 0.1129848290276167  # N m per lbf*in (exact: 4.4482216152605 N x 0.0254 m)

GOOD_MOTORS = (
    "id,vendor,series,rated_torque [N*m],peak_torque [lbf*in],rated_speed [rpm],max_speed [rpm],"
    "rotor_inertia [kg*cm^2],rated_power [kW],flange [mm],voltage [V],source\n"
    "ACME-04,Acme,A1,1.27,39.5,3000,6000,0.486,0.4,60,400,Acme A1 datasheet rev 3 p. 12\n"
    "ACME-08,Acme,A1,2.39,74,3000,6000,1.59,0.75,80,400,Acme A1 datasheet rev 3 p. 12\n"
)


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-import")
    return db.builtin_db(directory)


@pytest.fixture(autouse=True)
def data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    return fresh_dir(tmp_path / "data", built, monkeypatch)


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.exists() else "absent"


def snapshot(data_dir: Path) -> tuple[int, int, int, str, str]:
    """Everything an import could change: the union's row counts and both database files."""
    return (len(catalog.motors()), len(catalog.gearboxes()), len(catalog.drives()),
            digest(data_dir / db.USER_NAME), digest(data_dir / db.BUILTIN_NAME))


def user_count(data_dir: Path) -> int:
    conn = sqlite3.connect(data_dir / db.USER_NAME)
    try:
        return int(conn.execute("SELECT count(*) FROM motors").fetchone()[0])
    finally:
        conn.close()


def errors_of(exc: pytest.ExceptionInfo[InputError]) -> dict[str, str]:
    errs = exc.value.errors if isinstance(exc.value, InputErrors) else [exc.value]
    return {e.field: e.rule for e in errs}


# ---------------------------------------------------------------------------------- happy paths


def test_import_csv_with_units_in_the_header(tmp_path: Path, data_dir: Path) -> None:
    before = len(catalog.motors())
    report = catalog.import_file(write(tmp_path, "acme.csv", GOOD_MOTORS))
    assert (report.table, report.rows, report.ids) == ("motor", 2, ("ACME-04", "ACME-08"))
    assert Path(report.database) == data_dir / db.USER_NAME
    m = catalog.motors(vendor="acme")
    assert len(catalog.motors()) == before + 2
    assert list(m.origin) == ["user", "user"]
    assert m.peak_torque[0] == pytest.approx(39.5 * LBF_IN)
    assert m.rated_speed[0] == pytest.approx(3000 * RPM)
    assert m.rotor_inertia[1] == pytest.approx(1.59e-4)
    assert m.rated_power[1] == pytest.approx(750.0)
    assert m.flange[1] == pytest.approx(0.080)
    assert math.isnan(m.stall_torque[0])  # not given: NaN
    assert m.kind[0] == "ac_servo"  # the default kind
    row = catalog.get("ACME-04")
    assert row["origin"] == "user" and row["source"] == "Acme A1 datasheet rev 3 p. 12"


def test_import_json_with_unit_keys_quantity_strings_and_a_curve(tmp_path: Path) -> None:
    doc = [{"id": "J-1", "vendor": "Jay", "rated_torque [N*m]": 2.0, "peak_torque": "6 N*m",
            "rated_speed [rpm]": 3000, "max_speed": "5000 rpm", "rotor_inertia [kg*cm^2]": 2.5,
            "curve": [{"speed [rpm]": 0, "continuous_torque [N*m]": 2.2, "peak_torque [N*m]": 6.0},
                      {"speed [rpm]": 5000, "continuous_torque [N*m]": 1.0, "peak_torque [N*m]": 2.0}]}]
    path = tmp_path / "jay.json"
    path.write_text(json.dumps(doc, indent=1), encoding="utf-8")
    report = catalog.import_file(path)
    assert (report.rows, report.curve_points) == (1, 2)
    m = catalog.motors(ids=["J-1"])
    assert m.max_speed[0] == pytest.approx(5000 * RPM)
    assert m.peak_torque[0] == 6.0
    assert m.has_curve.tolist() == [True]
    curve = m.curves[0]
    assert curve is not None and curve.speed.tolist() == pytest.approx([0.0, 5000 * RPM])
    assert catalog.get("J-1")["curve"]["continuous_torque_Nm"] == [2.2, 1.0]


def test_import_drives_gearboxes_and_curve_points(tmp_path: Path) -> None:
    catalog.import_file(write(tmp_path, "d.csv", """\
        id,vendor,continuous_current [A],peak_current [A],voltage [V],dc_bus_capacitance [uF],source
        DRV-1,Acme,4.5,13.5,400,470,Acme drive manual
        """))
    d = catalog.drives(ids=["DRV-1"])
    assert len(d) == 1 and d.dc_bus_capacitance[0] == pytest.approx(470e-6)
    catalog.import_file(write(tmp_path, "g.csv", """\
        id,vendor,ratio,efficiency [%],rated_output_torque [N*m],backlash [arcmin],inertia_input [kg*cm^2]
        GB-10,Acme,10,95,40,3,0.2
        """))
    g = catalog.gearboxes(ids=["GB-10"])
    assert g.efficiency[0] == pytest.approx(0.95)
    assert g.backlash[0] == pytest.approx(3 * math.pi / 180 / 60)
    assert g.source[0] == "imported from g.csv"  # no source column: the file is the source
    catalog.import_file(write(tmp_path, "c.csv", """\
        motor_id,speed [rpm],continuous_torque [N*m],peak_torque [N*m]
        HG-KR43,0,1.3,4.5
        HG-KR43,3000,1.3,4.5
        """))
    assert catalog.motors(ids=["HG-KR43"]).has_curve.tolist() == [True]  # a curve for a shipped motor


def test_import_accepts_the_shipped_files_column_names(tmp_path: Path) -> None:
    text = """\
        id,vendor,rated_power_W,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2
        OLD-1,Acme,400,1.3,4.5,3000,6000,3.7e-05
        """
    catalog.import_file(write(tmp_path, "old.csv", text))
    assert catalog.get("OLD-1")["rated_speed_rad_s"] == pytest.approx(3000 * RPM)


# ---------------------------------------------------------------------------------- malformed files


@pytest.fixture
def prior(tmp_path: Path) -> None:
    """A user database that already holds two rows, so 'unchanged' is not just 'still empty'."""
    catalog.import_file(write(tmp_path, "prior.csv", GOOD_MOTORS))


def test_missing_column_is_reported_at_the_header(tmp_path: Path, data_dir: Path, prior: None) -> None:
    path = write(tmp_path, "bad.csv", """\
        id,vendor,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm]
        M-1,Acme,1.3,4.5,3000,6000
        """)
    before = snapshot(data_dir)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    assert f"{path}:1:rotor_inertia" in errors_of(exc)
    assert "required column is missing" in errors_of(exc)[f"{path}:1:rotor_inertia"]
    assert snapshot(data_dir) == before


def test_wrong_unit_dimension_in_header_and_in_a_cell(tmp_path: Path, data_dir: Path, prior: None) -> None:
    path = write(tmp_path, "bad.csv", """\
        id,vendor,rated_torque [kg],peak_torque,rated_speed [rpm],max_speed [rpm],rotor_inertia [kg*cm^2]
        M-1,Acme,1.3,4.5 N*m,3000,6000,0.37
        M-2,Acme,1.3,4.5 m/s,3000,6000,0.37
        """)
    before = snapshot(data_dir)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = errors_of(exc)
    assert "wrong dimension" in errs[f"{path}:1:rated_torque [kg]"]
    assert "wrong dimension" in errs[f"{path}:3:peak_torque"]
    assert f"{path}:2:peak_torque" not in errs  # a cell with the right unit is fine
    assert snapshot(data_dir) == before


def test_negative_inertia_is_reported_with_line_and_column(tmp_path: Path, data_dir: Path, prior: None) -> None:
    path = write(tmp_path, "bad.csv", GOOD_MOTORS.replace("ACME-04", "N-1").replace("ACME-08", "N-2")
                 .replace(",1.59,", ",-1.59,"))
    before = snapshot(data_dir)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = exc.value.errors
    assert [(e.field, e.value) for e in errs] == [(f"{path}:3:rotor_inertia [kg*cm^2]", "-1.59")]
    assert "must be > 0" in errs[0].rule
    assert snapshot(data_dir) == before


def test_duplicate_ids_in_the_file_and_in_both_databases(tmp_path: Path, data_dir: Path, prior: None) -> None:
    path = write(tmp_path, "dup.csv", """\
        id,vendor,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],rotor_inertia [kg*cm^2]
        NEW-1,Acme,1.3,4.5,3000,6000,0.37
        NEW-1,Acme,1.3,4.5,3000,6000,0.37
        HG-KR43,Acme,1.3,4.5,3000,6000,0.37
        ACME-04,Acme,1.3,4.5,3000,6000,0.37
        GPB042-L1-i3,Acme,1.3,4.5,3000,6000,0.37
        """)
    before = snapshot(data_dir)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = errors_of(exc)
    assert "already used at line 2" in errs[f"{path}:3:id"]
    assert "already in the shipped catalog" in errs[f"{path}:4:id"]
    assert "already in your catalog" in errs[f"{path}:5:id"]
    assert "a gearbox with this id" in errs[f"{path}:6:id"]  # ids are unique across tables
    assert f"{path}:2:id" not in errs
    assert snapshot(data_dir) == before


def test_every_problem_is_reported_at_once(tmp_path: Path, data_dir: Path) -> None:
    path = write(tmp_path, "many.csv", """\
        id,vendor,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],rotor_inertia,rated_powr
        A,Acme,1.3,1.0,3000,6000,0.37e-4,1
        B,,1.3,4.5,3000,2000,0.37e-4,1
        C,Acme,1.3,4.5,3000,6000,0.37,1
        D,Acme,abc,4.5,3000,6000,0.37e-4,1
        """)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = errors_of(exc)
    assert "did you mean rated_power" in errs[f"{path}:1:rated_powr"]
    assert "must be >= rated_torque" in errs[f"{path}:2:peak_torque [N*m]"]
    assert errs[f"{path}:3:vendor"] == "is required"
    assert "must be >= rated_speed" in errs[f"{path}:3:max_speed [rpm]"]
    assert "1e-6..1e-2 s^2" in errs[f"{path}:4:rotor_inertia"]  # kg*cm^2 figure with no unit: read as SI
    assert f"{path}:5:rated_torque [N*m]" in errs
    lines = [int(e.field.split(":")[-2]) for e in exc.value.errors]
    assert lines == sorted(lines)
    assert not (data_dir / db.USER_NAME).exists()


def test_power_that_disagrees_with_torque_times_speed(tmp_path: Path) -> None:
    header = ("id,vendor,rated_torque [N*m],peak_torque [N*m],rated_speed [rad/s],max_speed [rad/s],"
              "rotor_inertia [kg*cm^2],rated_power [W]\n")
    path = write(tmp_path, "p.csv", header + "P-1,Acme,1.3,4.5,3000,6000,0.37,400\n")  # rpm under a rad/s header
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    assert "disagrees with rated_torque x rated_speed" in errors_of(exc)[f"{path}:2:rated_power [W]"]


def test_small_dc_motors_follow_their_own_rules(tmp_path: Path) -> None:
    header = ("id,vendor,kind,voltage [V],torque_constant [mN*m/A],winding_resistance [ohm],no_load_speed [rpm],"
              "rotor_inertia [g*cm^2]\n")
    path = write(tmp_path, "dc.csv", header + "DC-1,Acme,small_dc,24,25.5,1.2,8900,10\n"
                 "DC-2,Acme,small_dc,24,25.5,1.2,5000,10\nDC-3,Acme,tiny_dc,24,25.5,1.2,8900,10\n")
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = errors_of(exc)
    assert "(V - R*I_nl)/k_t" in errs[f"{path}:3:no_load_speed [rpm]"]
    assert "must be one of ac_servo, small_dc" in errs[f"{path}:4:kind"]
    assert len(errs) == 2


def test_file_level_problems(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file"):
        catalog.import_file(tmp_path / "nope.csv")
    with pytest.raises(InputError, match="cannot tell whether"):
        catalog.import_file(write(tmp_path, "x.csv", "id,vendor,notes\nX,Acme,hello\n"))
    with pytest.raises(InputError, match="not valid JSON") as exc:
        catalog.import_file(write(tmp_path, "x.json", '[\n {"id": "X",\n  "vendor": }\n]'))
    assert exc.value.field.startswith(f"{tmp_path / 'x.json'}:3:")
    with pytest.raises(InputErrors, match="row has 2 cells"):
        catalog.import_file(write(tmp_path, "r.csv", GOOD_MOTORS + "X-1,Acme\n"))
    with pytest.raises(InputError, match="must be one of motor, gearbox, drive, curve"):
        catalog.import_file(write(tmp_path, "k.csv", GOOD_MOTORS), kind="motors")


def test_json_errors_carry_the_line_of_their_object(tmp_path: Path) -> None:
    doc = ('{"table": "motor", "rows": [\n'
           ' {"id": "J-1", "vendor": "Jay", "rated_torque": 1.3, "peak_torque": 4.5, "rated_speed [rpm]": 3000,\n'
           '  "max_speed [rpm]": 6000, "rotor_inertia [kg*cm^2]": 0.37},\n'
           ' {"id": "J-2", "vendor": "Jay", "rated_torque": 1.3, "peak_torque": 4.5, "rated_speed [rpm]": 3000,\n'
           '  "max_speed [rpm]": 6000, "rotor_inertia [kg*cm^2]": -0.37}\n'
           ']}\n')
    path = write(tmp_path, "j.json", doc)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    assert list(errors_of(exc)) == [f"{path}:4:rotor_inertia [kg*cm^2]"]


def test_a_bom_from_excel_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + GOOD_MOTORS.encode())
    assert catalog.import_file(path).rows == 2


# ---------------------------------------------------------------------------------- all or nothing


def test_failure_during_insert_rolls_everything_back(tmp_path: Path, data_dir: Path, prior: None,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    rows = "\n".join(f"R-{i},Acme,1.3,4.5,3000,6000,0.37" for i in range(200))
    path = write(tmp_path, "big.csv", "id,vendor,rated_torque,peak_torque,rated_speed [rpm],max_speed [rpm],"
                                      "rotor_inertia [kg*cm^2]\n" + rows + "\n")
    before = snapshot(data_dir)
    original = db._values

    def failing(spec: object, rows: list[object]) -> object:
        for k, values in enumerate(original(spec, rows)):  # type: ignore[arg-type]
            if k == 100:
                raise OSError("disk full")
            yield values

    monkeypatch.setattr(db, "_values", failing)
    with pytest.raises(OSError, match="disk full"):
        catalog.import_file(path)
    assert snapshot(data_dir) == before


KILL_SCRIPT = """
import sys, time
from drivetrain.catalog import db, importer

original = db._values

def slow(spec, rows):
    for k, values in enumerate(original(spec, rows)):
        if k == 2000:
            print("inserting", flush=True)  # half the rows are in the open transaction
            time.sleep(60)
        yield values

db._values = slow
importer.import_file(sys.argv[1])
print("finished", flush=True)
"""


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="needs SIGKILL")
def test_an_import_killed_midway_leaves_the_database_intact(tmp_path: Path, data_dir: Path, prior: None) -> None:
    header = "id,vendor,rated_torque,peak_torque,rated_speed [rpm],max_speed [rpm],rotor_inertia [kg*cm^2]\n"
    path = write(tmp_path, "big.csv", header + "".join(f"K-{i:05d},Acme,1.3,4.5,3000,6000,0.37\n"
                                                       for i in range(4000)))
    before_rows = user_count(data_dir)
    builtin_before = digest(data_dir / db.BUILTIN_NAME)
    env = {**os.environ, db.ENV_DATA_DIR: str(data_dir)}
    proc = subprocess.Popen([sys.executable, "-c", KILL_SCRIPT, str(path)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        assert line.strip() == "inserting", proc.stderr.read() if proc.stderr else ""
        assert (data_dir / (db.USER_NAME + "-journal")).exists()  # a transaction is open
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    conn = sqlite3.connect(data_dir / db.USER_NAME)
    try:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        assert conn.execute("SELECT count(*) FROM motors").fetchone()[0] == before_rows
        assert conn.execute("SELECT count(*) FROM motors WHERE id LIKE 'K-%'").fetchone()[0] == 0
    finally:
        conn.close()
    assert digest(data_dir / db.BUILTIN_NAME) == builtin_before
    assert catalog.import_file(path).rows == 4000  # the same import succeeds afterwards
    assert user_count(data_dir) == before_rows + 4000


# ---------------------------------------------------------------------------------- export and round trips


def comparable(record: dict[str, object]) -> dict[str, object]:
    return {k: (round(v, 9) if isinstance(v, float) else v) for k, v in record.items()}


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_export_then_import_into_a_fresh_data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch,
                                                  fmt: str) -> None:
    catalog.import_file(write(tmp_path, "acme.csv", GOOD_MOTORS))
    catalog.import_file(write(tmp_path, "c.csv", "motor_id,speed [rpm],peak_torque [N*m]\nACME-04,0,4.46\n"
                                                 "ACME-04,6000,1.0\n"))
    originals = {rid: catalog.get(rid) for rid in ("ACME-04", "ACME-08")}
    out = tmp_path / f"export.{fmt}"
    assert catalog.export(out, "motor", fmt, origin="user") == 2
    if fmt == "csv":
        assert next(csv.reader(io.StringIO(out.read_text())))[:4] == ["id", "kind", "vendor", "series"]
        assert "rated_speed [rpm]" in out.read_text()
    fresh_dir(tmp_path / "fresh", built, monkeypatch)
    assert catalog.import_file(out).rows == 2
    for rid, original in originals.items():
        again = catalog.get(rid)
        if fmt == "csv":  # CSV motors carry no curve; export kind="curve" holds the points
            curve_source = "none: the envelope is derived from the ratings (approximate)"
            original = {**original, "curve": None, "sources": {**original["sources"], "curve": curve_source}}
        assert comparable(again) == comparable(original)


@pytest.mark.parametrize("kind", ["motor", "gearbox"])
def test_the_whole_shipped_catalog_exports_and_reimports(tmp_path: Path, built: Path,
                                                         monkeypatch: pytest.MonkeyPatch, kind: str) -> None:
    text, count = importer.export_text(kind, "csv", origin="builtin")
    rows = list(csv.reader(io.StringIO(text)))
    for r in rows[1:]:
        r[0] = "COPY-" + r[0]
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(rows)
    path = write(tmp_path, "copy.csv", buffer.getvalue())
    ids = ("HG-KR43", "GPB042-L1-i3", "AG2400-TP010-MF-i5", "354723", "aiF4/4000")
    originals = {rid: catalog.get(rid) for rid in ids if catalog.get(rid)["table"] == kind}
    fresh_dir(tmp_path / "fresh", built, monkeypatch)
    report = catalog.import_file(path)  # every shipped row passes the import rules
    shipped = {"motor": 595 + family_motor_rows(), "gearbox": 1013 + 68 + family_gearbox_rows()}
    assert report.rows == count == shipped[kind]
    for rid, original in originals.items():
        again = catalog.get("COPY-" + rid)
        assert comparable({**again, "id": rid, "origin": "builtin"}) == comparable(original)


def test_export_json_and_csv_of_curve_points(tmp_path: Path) -> None:
    catalog.import_file(write(tmp_path, "c.csv", "motor_id,speed [rpm],continuous_torque [N*m]\n"
                                                 "HG-KR43,0,1.3\nHG-KR43,3000,1.3\n"))
    text, count = importer.export_text("curve", "csv")
    assert count == 2
    assert text.splitlines()[1].startswith("HG-KR43,0.0,1.3")
    doc = json.loads(importer.export_text("motor", "json", ids=["HG-KR43"])[0])
    assert doc["table"] == "motor" and doc["data_version"] == catalog.DATA_VERSION
    assert doc["rows"][0]["curve"][1] == {"speed [rpm]": 3000.0, "continuous_torque [N*m]": 1.3,
                                          "source": "imported from c.csv"}


def test_export_rejects_bad_arguments(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="format"):
        catalog.export(tmp_path / "x", "motor", "xml")
    with pytest.raises(InputError, match="kind"):
        catalog.export(tmp_path / "x", "motors")
    assert not (tmp_path / "x").exists()


def test_json_key_errors_point_at_the_object_that_uses_the_key(tmp_path: Path) -> None:
    doc = ('[\n {"id": "J-1", "vendor": "Jay", "rated_torque": 1.3, "peak_torque": 4.5, "rated_speed [rpm]": 3000,\n'
           '  "max_speed [rpm]": 6000, "rotor_inertia [kg*cm^2]": 0.37,\n'
           '  "curve": [{"speed [rpm]": 0, "peak_torque [N*m]": 4.5},\n'
           '            {"speed [rpm]": 6000, "peak_torq [N*m]": 1.0}]},\n'
           ' {"id": "J-2", "vendor": "Jay", "rated_torque": 1.3, "peak_torque": 4.5, "rated_speed [rpm]": 3000,\n'
           '  "max_speed [rpm]": 6000, "rotor_inertia [kg*cm^2]": 0.37, "colour": "blue"}\n'
           ']\n')
    path = write(tmp_path, "j.json", doc)
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(path)
    errs = errors_of(exc)
    assert "unknown curve column" in errs[f"{path}:5:peak_torq [N*m]"]
    assert "unknown motor column" in errs[f"{path}:6:colour"]


def test_gearbox_ratings_bore_and_document_columns_import_and_are_checked(tmp_path: Path) -> None:
    head = ("id,vendor,ratio,efficiency,rated_output_torque [N*m],max_output_torque [N*m],"
            "emergency_stop_torque [N*m],input_bore_min [mm],input_bore_max [mm]")
    path = tmp_path / "g.csv"
    path.write_text(head + ",rated_input_speed [rpm],max_input_speed [rpm],input_pilot [mm],verified,source_url\n"
                    "GB-20,Acme,20,0.94,40,80,120,11,19,3000,6000,50,yes,https://example.com/acme-gb.pdf\n",
                    encoding="utf-8")
    catalog.import_file(path)
    g = catalog.gearboxes(ids=["GB-20"])
    assert (g.input_bore_min[0], g.input_bore_max[0], g.input_pilot[0]) == pytest.approx((0.011, 0.019, 0.050))
    assert (g.max_output_torque[0], g.emergency_stop_torque[0]) == (80, 120)
    assert bool(g.verified[0]) and catalog.get("GB-20")["source_url"] == "https://example.com/acme-gb.pdf"
    bad = tmp_path / "bad.csv"
    bad.write_text(head + "\nGB-21,Acme,20,0.94,40,80,60,24,19\n", encoding="utf-8")
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(bad)
    rules = {k.rsplit(":", 1)[1]: v for k, v in errors_of(exc).items()}
    assert rules["emergency_stop_torque [N*m]"] == "must be >= max_output_torque (80 N*m)"
    assert rules["input_bore_min [mm]"] == "must be <= input_bore_max (19 mm)"
