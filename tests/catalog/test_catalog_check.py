"""The catalog's consistency check, the values a row implies and the voltage classes by model-code rule:
``drivetrain catalog check`` on the shipped catalog, the same rules on ``catalog import``, derived values
with their formula, and the vendors' voltage rules."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import pytest

from drivetrain import catalog
from drivetrain.catalog import check, db, voltage_class
from drivetrain.catalog.cli import main
from drivetrain.catalog.derive import derive_motor, kt_from_back_emf
from drivetrain.errors import InputErrors
from tests.catalog.folders import fresh_dir

RPM = 2 * math.pi / 60
HEAD = ("id,vendor,series,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],"
        "rotor_inertia [kg*cm^2],flange [mm],voltage [V],torque_constant [N*m/A],rated_current [A],"
        "stall_current [A],back_emf [V*s],back_emf_basis,source\n")


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return db.builtin_db(tmp_path_factory.mktemp("catalog-check"))


@pytest.fixture(autouse=True)
def data_dir(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    base = fresh_dir(tmp_path / "data", built, monkeypatch)
    monkeypatch.delenv(db.ENV_CATALOG, raising=False)
    return base


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


# ---------------------------------------------------------------------------------- the shipped catalog


def test_every_shipped_row_passes_or_carries_a_documented_exception(capsys: pytest.CaptureFixture[str]) -> None:
    report = check.run()
    assert report.ok, [f.to_dict() for f in report.failures]
    assert report.rows["motor"] >= 662 and report.rows["gearbox"] >= 1110 and report.rows["drive"] >= 44
    assert not report.unused_exceptions  # every documented exception still excuses a row
    excused = {(f.id, f.rule) for f in report.findings}
    # what the check finds in the shipped data, each with its documented reason
    assert ("SGM7D-02K", "kt_rated_current") in excused
    assert ("1FT7044-5AK7", "pairing_peak_current") in excused
    assert all(f.excused for f in report.findings)
    assert main(["catalog", "check"]) == 0
    assert "0 finding(s) fail" in capsys.readouterr().out


def test_check_json_lists_the_excused_findings_with_their_reason(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "check", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is True and doc["failures"] == []
    apm = [e for e in doc["excused"] if e["id"].startswith("APM-")]
    assert apm and all(e["rule"] == "voltage_class" and "rated speed" in e["excused"] for e in apm)


def test_a_failing_user_row_makes_the_check_exit_1_naming_the_field_and_rule(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # k_T x I_N / T_N = 2.0: an import only flags this rule (vendors print up to 1.42), the check fails it
    path = write(tmp_path, "m.csv", HEAD + "U-KT,Userco,U,1.0,3.0,3000,5000,1.0,80,200,0.8,2.5,,,,sheet\n")
    report = catalog.import_file(path)
    assert any("rated_torque: rule kt_rated_current" in f for f in report.flags)
    assert main(["catalog", "check", "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert [(f["id"], f["field"], f["rule"], f["origin"]) for f in doc["failures"]] == [
        ("U-KT", "rated_torque", "kt_rated_current", "user")]
    assert main(["catalog", "check"]) == 1
    assert "kt_rated_current" in capsys.readouterr().out


def test_check_of_a_catalog_file_that_does_not_exist_is_bad_input(tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    from drivetrain import cli as drivetrain_cli

    assert drivetrain_cli.main(["catalog", "check", "--catalog", str(tmp_path / "absent.sqlite")]) == 2
    err = capsys.readouterr().err
    assert "--catalog: no such catalog file" in err and "Traceback" not in err
    assert main(["catalog", "check", "--catalog", str(tmp_path / "absent.sqlite")]) == 2


# ---------------------------------------------------------------------------------- import


def test_import_refuses_a_row_naming_the_field_and_the_rule(tmp_path: Path) -> None:
    # k_E given per phase rms but labelled line-to-line: k_T / (sqrt(3) k_E,LL,rms) = 1.73, outside 0.85..1.05
    ke_ll_rms = 0.9 / math.sqrt(3)
    bad_ke = HEAD + f"U-KE,Userco,U,1.0,3.0,3000,5000,1.0,80,200,0.9,1.2,,{ke_ll_rms / math.sqrt(3)},ll_rms,sheet\n"
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(write(tmp_path, "ke.csv", bad_ke))
    text = str(exc.value)
    assert "ke.csv:2:torque_constant [N*m/A]" in text and "kt_ke" in text
    # rotor inertia 1 kg*m^2 written in a kg*cm^2 column's place: outside the band for an 80 mm flange
    slip = HEAD.replace("rotor_inertia [kg*cm^2]", "rotor_inertia [kg*m^2]") + (
        "U-J,Userco,U,1.0,3.0,3000,5000,1.0,80,200,,,,,,sheet\n")
    with pytest.raises(InputErrors) as exc:
        catalog.import_file(write(tmp_path, "j.csv", slip))
    assert "j.csv:2:rotor_inertia [kg*m^2]" in str(exc.value) and "inertia_for_flange" in str(exc.value)
    assert "U-J" not in catalog.motors().ids  # nothing was written


def test_import_refuses_a_voltage_that_contradicts_the_model_code() -> None:
    values = {"id": "R88M-K90010F", "vendor": "Omron", "kind": "ac_servo", "voltage": 200.0}
    found = check.voltage_findings(catalog.schema.MOTOR, values)
    assert [f[0] for f in found] == ["voltage_rule"] and "400 V class" in found[0][2]


def test_imported_row_gets_its_implied_values_flagged_derived(tmp_path: Path) -> None:
    text = HEAD + "U-T0,Userco,U,1.0,3.0,3000,5000,1.0,80,,0.5,2.1,2.4,,,sheet\n"
    report = catalog.import_file(write(tmp_path, "d.csv", text))
    assert any("voltage" in f and "voltage_class" in f for f in report.flags)  # no class: flagged, not refused
    row = catalog.get("U-T0")
    assert row["stall_torque_Nm"] == pytest.approx(0.5 * 2.4)
    assert row["derived"] == ["stall_torque"]
    assert row["derivation"]["stall_torque"].startswith("stall_torque = torque_constant x stall_current")


# ---------------------------------------------------------------------------------- derived values


def test_torque_constant_from_the_back_emf_on_its_basis() -> None:
    # 57 V/krpm line-to-line rms (Siemens 1FT7044-5AK7): sqrt(3) x 0.5443 V s/rad = 0.943 N m/A
    ke = 57.0 / (1000 * RPM)
    assert kt_from_back_emf(ke, "ll_rms") == pytest.approx(math.sqrt(3) * ke)
    assert kt_from_back_emf(ke, "ll_rms") == pytest.approx(0.943, abs=5e-4)
    assert kt_from_back_emf(ke * math.sqrt(2), "ll_peak") == pytest.approx(math.sqrt(3) * ke)
    assert kt_from_back_emf(ke / math.sqrt(3), "phase_rms") == pytest.approx(math.sqrt(3) * ke)
    row = {"kind": "ac_servo", "back_emf": ke, "back_emf_basis": "ll_rms", "stall_current": 5.7}
    assert derive_motor(row) == ["torque_constant", "stall_torque"]
    assert row["stall_torque"] == pytest.approx(0.943 * 5.7, rel=1e-3)
    assert "sqrt(3) x k_E,LL,rms" in row["derivation"]


def test_a_printed_value_is_never_replaced_and_a_torque_pair_gives_k_t() -> None:
    row = {"kind": "ac_servo", "torque_constant": 0.88, "stall_current": 5.7, "stall_torque": 5.0}
    assert derive_motor(row) == [] and row["stall_torque"] == 5.0
    mhp = catalog.get("MHP093A-024")  # stall 12 N m at 5.3 A printed, k_T not
    assert mhp["torque_constant_Nm_per_A"] == pytest.approx(12.0 / 5.3)
    assert mhp["derivation"]["torque_constant"] == "torque_constant = stall_torque / stall_current = 12 N*m / 5.3 A"


def test_1ft7044_uses_its_printed_stall_torque() -> None:
    row = catalog.get("1FT7044-5AK7")
    assert row["stall_torque_Nm"] == 5.0  # M_0 (100 K), Table 4-8, read from the electrical table: not derived
    assert "stall_torque" not in row["derived"]
    # and the printed pair agrees with k_T x I_0 = 0.88 x 5.7 = 5.016 N m
    assert not [f for f in check.row_findings(catalog.schema.MOTOR, check.by_field(catalog.schema.MOTOR, row))
                if f[0] == "kt_stall_current"]


# ---------------------------------------------------------------------------------- voltage classes


@pytest.mark.parametrize(("table", "vendor", "rid", "volts"), [
    ("motor", "Yaskawa", "SGMAH-01B", 100.0), ("motor", "Yaskawa", "SGMPH-04A", 200.0),
    ("motor", "Yaskawa", "SGMSH-10DA", 400.0), ("drive", "Mitsubishi Electric", "MR-J4-10B", 200.0),
    ("drive", "Mitsubishi Electric", "MR-J4-60B4", 400.0), ("drive", "Mitsubishi Electric", "MR-J4-40B1", 100.0),
    ("drive", "Mitsubishi Electric", "MR-J4-22KA4", 400.0), ("motor", "Omron", "R88M-K05030H/T", 200.0),
    ("motor", "Omron", "R88M-K90010F", 400.0), ("motor", "Omron", "R88M-K7K515C", 400.0),
    ("motor", "FANUC", "aiS 8/4000", 200.0), ("motor", "FANUC", "aiS 8/4000HV", 400.0),
    ("motor", "FANUC", "beta 1.0/5000is", 200.0), ("motor", "Siemens", "1FT7044-5AK7", 400.0),
    ("drive", "Siemens", "6SL312x-xTE21-0AAx", 400.0),
])
def test_model_code_rules(table: str, vendor: str, rid: str, volts: float) -> None:
    found = voltage_class.rule_for(table, vendor, rid)
    assert found is not None and found[1] == volts


def test_no_rule_is_said_so() -> None:
    assert voltage_class.rule_for("motor", "LS Mecapion", "APM-FB01A") is None
    assert "rated speed" in voltage_class.explain("motor", "LS Mecapion", "APM-FB01A")
    assert voltage_class.explain("motor", "Nobody", "X-1").startswith("unknown: no model-code rule")


def test_voltage_classes_before_and_after() -> None:
    servo = catalog.motors(kind="ac_servo")
    missing = int(sum(1 for v in servo.voltage if math.isnan(v)))
    assert len(servo) == 364 and missing == 172 - 31  # the 31 Siemens 1FT7 gained the S120 400 V class
    assert len(catalog.motors(voltage="400 V", kind="ac_servo")) == 3 + 31  # was 3 (Omron F/C)
    drives = catalog.drives(vendor="Mitsubishi")
    by_id = dict(zip(drives.ids, drives.voltage, strict=True))
    assert by_id["MR-J4-10B1"] == 100.0 and by_id["MR-J4-60B4"] == 400.0
    rule_rows = [r for r in catalog.motors(vendor="Siemens").ids]
    assert all("voltage" in catalog.get(r)["derivation"] for r in rule_rows[:3])


def test_pairing_currents() -> None:
    motors = {"M": {"rated_current": 2.0, "peak_current": 9.0}, "N": {"stall_current": 5.0, "peak_current": 9.0}}
    drives = {"D": {"continuous_current": 4.0, "peak_current": 12.0}}
    assert check.pairing_findings({"M": ["D"]}, motors, drives) == []
    found = check.pairing_findings({"N": ["D"], "X": ["D"]}, motors, drives)
    assert [(m, r) for m, r, _, _ in found] == [("N", "pairing_continuous_current"), ("X", "pairing_ids")]


def test_an_edit_computes_the_derived_values_again_and_keeps_the_rules(tmp_path: Path) -> None:
    text = HEAD + "U-E,Userco,U,1.0,3.0,3000,5000,1.0,80,200,0.5,2.1,2.4,,,sheet\n"
    catalog.import_file(write(tmp_path, "e.csv", text))
    assert catalog.get("U-E")["stall_torque_Nm"] == pytest.approx(1.2)
    row = catalog.update("U-E", {"torque_constant": 0.55})
    assert row["stall_torque_Nm"] == pytest.approx(0.55 * 2.4) and row["derived"] == ["stall_torque"]
    row = catalog.update("U-E", {"stall_torque": 1.3})  # given now: no longer derived
    assert row["stall_torque_Nm"] == 1.3 and row["derived"] == []
    from drivetrain.errors import InputError

    with pytest.raises(InputError, match="shaft_pilot_flange"):
        catalog.update("U-E", {"shaft_diameter [mm]": 19, "pilot_diameter [mm]": 14})
