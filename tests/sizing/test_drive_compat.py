"""Which motor series a drive runs (the drive column ``motor_series``): a drive that lists it is offered only to
motors of those series, the pairing table still comes first, and the column survives import, export and ``show``
(docs/checks.md, "Drive selection"; docs/catalog.md, "Columns")."""

from __future__ import annotations

import csv
import io
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from drivetrain import catalog, cli
from drivetrain.sizing import drive_select
from drivetrain.sizing.pipeline import size
from tests.sizing.test_drive_select import USER_MOTORS, axis, import_catalog

SERIES_RULE = "vendor, voltage and motor series"

# TC-04 (series T) and TQ-04 (series QZ, the same motor otherwise): one vendor, one voltage, two motor series
MOTORS = USER_MOTORS + USER_MOTORS.splitlines()[-1].replace("TC-04,Testco,T,", "TQ-04,Testco,QZ,") + "\n"
DRIVES = """\
id,vendor,continuous_current [A],peak_current [A],peak_time [s],voltage [V],motor_series,source
TD-M,Testco,1.6,4.8,3,200,"t, TY",test fixture
TD-L,Testco,5,15,3,200,T,test fixture
"""
ANY_DRIVE = "TD-ANY,Testco,5,15,3,200,,test fixture\n"


def blocks(result: Any) -> dict[str, dict[str, Any]]:
    """The drive block of each listed candidate, by motor."""
    return {c.motor: c.drive for c in result.candidates}


def select_testco() -> Any:
    return size(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}))


def test_a_drive_listing_motor_series_is_offered_only_to_those_series(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES)
    by_motor = blocks(select_testco())
    own = by_motor["TC-04"]  # series T: "t" matches case-insensitively, as a prefix
    assert own.basis == SERIES_RULE and list(own.candidates) == ["TD-M", "TD-L"]
    assert own.status == "ok" and own.id == "TD-M"
    other = by_motor["TQ-04"]  # series QZ: the same motor, no drive of its vendor runs its series
    assert other.basis == SERIES_RULE and list(other.candidates) == []
    assert other.status == "none" and other.id is None and other.ok is None
    assert "series (QZ)" in other.reason and "t, TY; T" in other.reason and "motor_series" in other.reason
    assert other.motor_rms_current_A > 0  # its current is known: only the drive is missing


def test_a_drive_without_motor_series_keeps_the_vendor_and_voltage_rule(tmp_path: Path,
                                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES + ANY_DRIVE)
    by_motor = blocks(select_testco())
    assert list(by_motor["TQ-04"].candidates) == ["TD-ANY"] and by_motor["TQ-04"].status == "ok"
    assert by_motor["TQ-04"].basis == SERIES_RULE
    assert list(by_motor["TC-04"].candidates) == ["TD-M", "TD-L", "TD-ANY"]
    # no drive of the vendor lists motor_series: the rule and the basis are as before
    plain = DRIVES.replace('"t, TY"', "").replace(",T,test", ",,test")
    (tmp_path / "plain").mkdir()
    import_catalog(tmp_path / "plain", monkeypatch, MOTORS, plain)
    by_motor = blocks(select_testco())
    assert {d.basis for d in by_motor.values()} == {"vendor and supply voltage"}
    assert list(by_motor["TQ-04"].candidates) == ["TD-M", "TD-L"]


def test_the_pairing_table_comes_before_the_series_rule(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES)
    monkeypatch.setattr(catalog, "drive_pairs", lambda: {"TQ-04": ["TD-L"]})
    pool, basis, why = drive_select._pool("TQ-04", "Testco", 200.0)
    assert [d.name for d in pool] == ["TD-L"] and basis == "vendor pairing table" and why == ""


def test_a_motor_without_series_is_not_offered_a_drive_that_lists_series(tmp_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    motors = MOTORS + USER_MOTORS.splitlines()[-1].replace("TC-04,Testco,T,", "TN-04,Testco,,") + "\n"
    import_catalog(tmp_path, monkeypatch, motors, DRIVES)
    _, block, _ = drive_select.prospect("TN-04", "Testco", 200.0)
    assert block.status == "none" and "series (not given)" in block.reason


# ---------------------------------------------------------------------------------- shipped data

SIGMA_OLD = ("SGMAH", "SGMPH", "SGMSH", "SGMP")  # Sigma-II and Sigma motors shipped


def test_shipped_sigma_ii_and_sigma_motors_are_not_offered_the_sigma_7_servopack() -> None:
    """The SGD7S rows come from the Sigma-7S SERVOPACK product manual (drives_servo.csv, SOURCES.md "Drives"):
    motor_series SGM7, so the older Yaskawa motors of the same voltage no longer list them."""
    assert set(catalog.drives(vendor="yaskawa").motor_series) == {"SGM7"}
    motors = catalog.motors(vendor="yaskawa")
    pairs = catalog.drive_pairs()  # the SGM7J/A/P/G rows are paired by drives_pairing.csv (SOURCES.md "Drives")
    seen = set()
    for i in range(len(motors)):
        mid, series = str(motors.ids[i]), str(motors.series[i])
        _, block, _ = drive_select.prospect(mid, "Yaskawa", float(motors.voltage[i]))
        assert block.basis == ("vendor pairing table" if mid in pairs else SERIES_RULE), mid
        if series.startswith("SGM7"):
            assert block.candidates and all(d.startswith("SGD7S-") for d in block.candidates), mid
        else:
            assert series in SIGMA_OLD and list(block.candidates) == [], mid
            assert block.status in ("none", "unknown")  # unknown first where the motor has no torque constant
            if block.status == "none":
                assert f"series ({series})" in block.reason and "SGM7" in block.reason
        seen.add(series[:4] if series.startswith("SGM7") else series)
    assert seen >= {"SGM7", *SIGMA_OLD}


def test_shipped_100_v_yaskawa_selection_answers_none_naming_the_series_rule() -> None:
    r = size(axis(motor={"select": {"vendor": "yaskawa", "voltage": "100 V", "gearbox": "none"}}))  # SGMAH, SGMP
    with_kt = [d for d in blocks(r).values() if d.motor_rms_current_A]
    assert with_kt, "Yaskawa 100 V rows with a torque constant are among the candidates"
    for d in blocks(r).values():
        assert not any(x.startswith("SGD7S") for x in d.candidates)
    for d in with_kt:
        assert d.status == "none" and "motor_series" in d.reason


def test_other_shipped_drives_keep_the_vendor_and_voltage_rule() -> None:
    """The SGD7S and MR-J4 rows state the motor series they run (the MR-J4 list from the Servo Motor Instruction
    Manual Vol. 3's cover; the transcription's motors stay pairings); the JSDG2S and S120 documents recorded name
    no motor series (SOURCES.md, "Drives")."""
    for vendor in ("teco", "siemens"):
        assert set(catalog.drives(vendor=vendor).motor_series) == {""}, vendor
    mitsubishi = catalog.drives(vendor="mitsubishi electric")
    assert {str(s) for s, i in zip(mitsubishi.motor_series, mitsubishi.ids, strict=True)
            if str(i).startswith("MR-J4-")} == {"HG-MR HG-KR HG-SR HG-JR HG-RR HG-UR"}
    # HG-JR53 has no pairing row (the MR-J4 transcription pairs HG-KR, HG-MR and HG-SR only): its series decides
    assert "HG-JR53" not in catalog.drive_pairs()
    _, block, _ = drive_select.prospect("HG-JR53", "Mitsubishi Electric", 200.0)
    assert block.basis == "vendor, voltage and motor series" and "MR-J4-10B" in block.candidates
    # a CNC (MELDAS) HC motor is not an MR-J4 motor: no drive of its vendor runs it
    _, block, _ = drive_select.prospect("HC52", "Mitsubishi Electric", 200.0)
    assert block.status == "none" and "HG-MR HG-KR HG-SR HG-JR HG-RR HG-UR" in str(block.reason)


# ---------------------------------------------------------------------------------- import, export, show


def test_motor_series_round_trips_through_export_and_import(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES)
    assert catalog.get("TD-M")["motor_series"] == "t, TY"
    for fmt in ("csv", "json"):
        out = tmp_path / f"drives.{fmt}"
        assert catalog.export(out, "drive", fmt, origin="user") == 2
        if fmt == "csv":
            rows = list(csv.DictReader(io.StringIO(out.read_text(encoding="utf-8"))))
            assert {r["id"]: r["motor_series"] for r in rows} == {"TD-M": "t, TY", "TD-L": "T"}
        monkeypatch.setenv("DRIVETRAIN_DATA_DIR", str(tmp_path / f"fresh-{fmt}"))
        catalog.import_file(out)
        assert catalog.get("TD-M")["motor_series"] == "t, TY" and catalog.get("TD-L")["motor_series"] == "T"
    assert cli.main(["catalog", "show", "TD-M"]) == 0
    assert "motor_series" in capsys.readouterr().out
    assert cli.main(["catalog", "show", "SGD7S-R70A"]) == 0
    text = capsys.readouterr().out
    assert "motor_series" in text and "SGM7" in text


def test_a_schema_3_user_catalog_gains_the_motor_series_column(tmp_path: Path,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.catalog import db

    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES)
    user = db.user_db_path()
    conn = sqlite3.connect(user)
    try:
        conn.execute("ALTER TABLE drives DROP COLUMN motor_series")
        conn.execute("UPDATE meta SET value = '3' WHERE key = 'schema_version'")
        conn.commit()
    finally:
        conn.close()
    catalog._CACHE.clear()
    drives = catalog.drives(vendor="testco")
    assert set(drives.ids) == {"TD-M", "TD-L"} and set(drives.motor_series) == {""}
    conn = sqlite3.connect(user)
    try:
        assert "motor_series" in {r[1] for r in conn.execute("PRAGMA table_info(drives)")}
        version = conn.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()[0]
    finally:
        conn.close()
    assert version == str(db.SCHEMA_VERSION) == "5"


def test_a_given_drive_runs_only_its_series_in_a_selection(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """drive: {id: TD-L} beside a selection: a motor of another series fails with that drive whatever its
    current, so the selection passes over it for one TD-L runs."""
    import_catalog(tmp_path, monkeypatch, MOTORS, DRIVES)
    r = size(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}, drive={"id": "TD-L"}))
    by_motor = blocks(r)
    other = by_motor["TQ-04"]
    assert other.status == "fails" and other.ok is False and other.id == "TD-L"
    assert "runs only the motor series T" in other.reason and "not QZ" in other.reason
    assert by_motor["TC-04"].status == "ok"
    assert r.selection.selected.motor == "TC-04" and r.ok
