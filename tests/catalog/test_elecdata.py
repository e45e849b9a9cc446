"""The shipped electrical data (drives, motor currents and torque constants) against the vendor pages
they cite, its invariants, and what a shipped selection answers with it.

Each printed value below is quoted from the page named beside it (catalog/data/SOURCES.md,
"Drives" and "Motor electrical data"); a test per table asserts the value as printed. The
invariants run over every shipped row and over a deliberately broken row, so a check that can no
longer fail is noticed.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import pytest

from drivetrain import catalog, cli
from drivetrain.catalog.derive import DERIVED_KT
from drivetrain.catalog.schema import TRACED_DRIVE_FAMILIES

Row = dict[str, str]
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def load(name: str, key: str = "id") -> dict[str, Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return {r[key]: r for r in csv.DictReader(io.StringIO(text))}


def num(s: str | None) -> float | None:
    if s is None or s.strip() == "":
        return None
    return float(s)


DRIVES = load("drives_servo.csv")
for _family in TRACED_DRIVE_FAMILIES:  # the drives_<vendor>_<family>.csv files share its columns and invariants
    DRIVES |= load(f"drives_{_family}.csv")
ELEC = load("motors_ac_servo_electrical.csv")
MOTORS = load("motors_ac_servo.csv")

# ------------------------------------------------------------------------ a test per table, as printed

_YASKAWA_REGEN = "12.8.6 Selecting External Regenerative Resistor"  # Sigma-7S SERVOPACK manual, p. 12-37
_TECO = "5-6-7"  # TECO JSDG2S user manual, 5-6-7 'Selection of External Regenerative Resistor', p. 5-136
_MRJ4 = "p. 11-13"  # MR-J4-_B(-RJ) instruction manual, 11 (b) 'Losses ... in regenerative mode'


@pytest.mark.parametrize(("rid", "column", "printed"), [
    # Yaskawa Sigma-7S SERVOPACK manual, 12.8.6, p. 12-37: "Processable Regenerative Energy (Joules)"
    ("SGD7S-R70A", "absorbable_energy [J]", 24.2),
    ("SGD7S-2R8A", "absorbable_energy [J]", 31.7),
    ("SGD7S-2R8F", "absorbable_energy [J]", 48.4),
])
def test_yaskawa_sgd7s_regen_table_p12_37(rid: str, column: str, printed: float) -> None:
    row = DRIVES[rid]
    assert num(row[column]) == printed
    assert row["source_section"].startswith("12.8.6") and row["source_page"] == "12-37"
    assert row["builtin_braking_resistor"] == "no"  # "regenerative resistors are not built into" these models


@pytest.mark.parametrize(("rid", "ohm", "watt", "average", "minimum"), [
    # TECO JSDG2S user manual, 5-6-7, p. 5-136: built-in resistor (ohm, W), regen power it absorbs
    # on average (W), minimum resistance (ohm)
    ("JSDG2S-10A-(E)", 25, 40, 8, 17.1),
    ("JSDG2S-75A3-(E)", 12.5, 60, 12, 6.8),
    ("JSDG2S-200A3-(E)", 5, 200, 40, 4.8),
    ("JSDG2S-300A3-(E)", None, None, None, 3.2),  # printed "--(No)": no built-in resistor
])
def test_teco_jsdg2s_regen_table_p5_136(rid: str, ohm: float | None, watt: float | None, average: float | None,
                                        minimum: float) -> None:
    row = DRIVES[rid]
    assert num(row["braking_resistor_ohm"]) == ohm
    assert num(row["braking_resistor_power_W"]) == watt
    assert num(row["braking_resistor_average_power_W"]) == average
    assert num(row["min_resistance_ohm"]) == minimum
    assert row["builtin_braking_resistor"] == ("no" if ohm is None else "yes")
    assert row["source_page"] == "5-136"


@pytest.mark.parametrize(("rid", "joule", "volt"), [
    # MR-J4-_B(-RJ) instruction manual, 11 (b), p. 11-13: "Capacitor charging [J]"; the supply class
    # from the MR-J4-_A(-RJ) manual App. 4.8.1, p. App.-16 (200 V class; models ending 4: 400 V class)
    ("MR-J4-20B", 9, 200),
    ("MR-J4-350B", 40, 200),
    ("MR-J4-350B4", 43, 400),
    ("MR-J4-22KB4", 250, 400),
    ("MR-J4-40B1", 10, None),  # 100 V class: no voltage read
])
def test_mitsubishi_mr_j4_capacitor_table_p11_13(rid: str, joule: float, volt: float | None) -> None:
    row = DRIVES[rid]
    assert num(row["absorbable_energy [J]"]) == joule
    assert num(row["voltage_V"]) == volt
    assert row["source_page"] == "11-13"


def test_siemens_motor_module_of_table_4_8_p90() -> None:
    # SINAMICS S120 1FT7 configuration manual (PFT7S) 01/2009, Table 4-8 (1FT7044-AK7), p. 90:
    # "Rated inverter current 9 A", "Maximum inverter current 18 A"
    row = DRIVES["6SL312x-xTE21-0AAx"]
    assert (num(row["continuous_current_A"]), num(row["peak_current_A"])) == (9, 18)
    assert row["source_page"] == "90"
    pair = load("drives_pairing.csv", "motor_id")
    assert pair["1FT7044-5AK7"]["drive_id"] == "6SL312x-xTE21-0AAx"


@pytest.mark.parametrize(("mid", "rated", "peak", "kt", "page"), [
    # Yaskawa Sigma-7 rotary servomotor manual (SIEP S800001 36): rated current, instantaneous maximum
    # current [Arms], torque constant [N m/Arms] as printed
    ("SGM7J-02A", 1.6, 5.8, 0.444, "p. 4-4"),
    ("SGM7J-08A", 4.4, 16.9, 0.584, "p. 4-4"),
    ("SGM7A-15A", 9.3, 28, 0.59, "p. 5-7"),
    ("SGM7G-09A", 6.9, 17, 0.859, "p. 7-4"),
    ("SGM7G-44A", 32.8, 84, None, "p. 7-5"),  # the copy ends before the torque-constant row
    # Siemens 1FT7 configuration manual 01/2009, Table 4-8, p. 90
    ("1FT7044-5AK7", 2.5, 30, 0.88, "p. 90"),
    # Mitsubishi Electric FA specification page of HG-KR23BG1 1/20 (web page, no page number):
    # "定格電流 [A] 1.3", "最大電流 [A] MR-J4-, MR-J4W_-: 4.6 / MR-JN-: 3.9"; no torque constant printed
    ("HG-KR23", 1.3, 4.6, None, "HG-KR23BG1 1/20"),
])
def test_motor_currents_and_torque_constants_as_printed(mid: str, rated: float, peak: float, kt: float | None,
                                                        page: str) -> None:
    row = ELEC[mid]
    assert (num(row["rated_current_A"]), num(row["peak_current_A"])) == (rated, peak)
    assert page in row["source"]
    if kt is None:
        assert row["torque_constant_basis"].startswith("derived")
    else:
        assert num(row["torque_constant_Nm_per_A"]) == kt and row["torque_constant_basis"] == "printed"


# ------------------------------------------------------------------------ derived torque constants


def test_derived_torque_constants_are_rated_torque_over_rated_current_and_only_where_none_is_printed() -> None:
    derived = {mid for mid, r in ELEC.items() if r["torque_constant_basis"].startswith("derived")}
    assert derived == {"SGM7G-30A", "SGM7G-44A", "SGM7G-55A", "SGM7G-75A", "SGM7G-1AA", "SGM7G-1EA", "HG-KR23"}
    for mid in derived:
        r = ELEC[mid]
        t_n, i_n = float(MOTORS[mid]["rated_torque_Nm"]), float(r["rated_current_A"])
        assert float(r["torque_constant_Nm_per_A"]) == pytest.approx(t_n / i_n, abs=5e-5), mid
        assert float(r["check_kt_x_Irated_over_Trated"]) == pytest.approx(1.0, abs=1e-3)
        assert "DERIVED" in r["notes"]
    # SGM7G-44A, Sigma-7 manual 7.2.4 p. 7-5: 28.4 N m at 32.8 A rms -> 0.8659 N m/A
    assert float(ELEC["SGM7G-44A"]["torque_constant_Nm_per_A"]) == 0.8659
    # HG-KR23, the HG-KR23BG1 1/20 specification page: 0.64 N m at 1.3 A -> 0.4923 N m/A
    assert float(ELEC["HG-KR23"]["torque_constant_Nm_per_A"]) == 0.4923


def test_hg_kr23_row_is_the_motor_of_the_page_it_cites() -> None:
    """The page is the HG-KR23 with brake and G1 reducer: the row is used for HG-KR23 only because the
    page's motor ratings equal the catalog row's, and the MR-J4 maximum current is the one stored."""
    row, motor = ELEC["HG-KR23"], MOTORS["HG-KR23"]
    assert "formNm=HG-KR23BG1" in row["source_url"] and row["source_url"].startswith("https://www.mitsubishielectric")
    # printed on the page: rated output 0.2 kW, rated torque 0.64 N m, rated speed 3000 r/min
    assert (float(motor["rated_power_W"]), float(motor["rated_torque_Nm"]), float(motor["rated_speed_rpm"])) == (
        200, 0.64, 3000)
    assert num(row["table_rated_torque_Nm"]) == 0.64 and num(row["table_peak_torque_Nm"]) is None
    assert "MR-JN-: 3.9" in row["notes"] and num(row["peak_current_A"]) == 4.6  # the MR-J4 value
    # the derived k_T reproduces the catalog's peak point within the spread of the printed Yaskawa rows
    assert 1.0 < 0.4923 * 4.6 / float(motor["peak_torque_Nm"]) < 1.25


def test_a_derived_torque_constant_is_flagged_in_the_catalog_and_in_the_answer() -> None:
    row = catalog.get("SGM7G-44A")
    assert row["torque_constant_Nm_per_A"] == 0.8659
    assert "torque_constant" in row["derived"]
    assert DERIVED_KT in row["electrical_source"]
    printed = catalog.get("SGM7G-09A")
    assert "torque_constant" not in (printed["derived"] or []) and DERIVED_KT not in printed["electrical_source"]
    # a derived k_T is a formula on two printed ratings: it neither makes the row unverified for that
    # reason nor marks the rated torque as derived
    assert not catalog.motors(ids=["SGM7G-44A"]).approx_rated[0]


# ------------------------------------------------------------------------ drive invariants

DriveCheck = Callable[[Row], list[str]]


_COMMIT = re.compile(r"[\w.-]+/[\w.-]+@[0-9a-f]{40}")  # owner/repository@full commit


def _provenance(r: Row) -> list[str]:
    """A row is traced to its vendor document, or flagged unverified with the transcription (repository and full
    commit) its ratings come from; a merged row has both (SOURCES.md, "Drives")."""
    out = []
    if r["verified"] not in ("yes", "no"):
        out.append("verified must be yes or no")
    if r["verified"] == "no":
        out += [f"{k} is empty" for k in ("unverified_reason", "ratings_source") if not r[k]]
        if not _COMMIT.search(r["ratings_source"]) or not _COMMIT.search(r["source"]):
            out.append("no repository@commit in ratings_source and source")
    traced = r["verified"] == "yes" or r["source_document"]
    if traced:
        out += [f"{k} is empty" for k in ("source_document", "source_section", "source_page", "source_url")
                if not r[k]]
    if r["source_url"] and not r["source_url"].startswith(("http://", "https://")):
        out.append("source_url is not a web address")
    return out


def _currents(r: Row) -> list[str]:
    cont, peak = num(r["continuous_current_A"]), num(r["peak_current_A"])
    if peak is not None and cont is None:
        return ["a peak current without a continuous current"]
    if cont is not None and peak is None and "no amplifier peak current" not in r["notes"]:
        # only the MR-J4 transcription gives a rated current without a peak, and its rows say so
        return ["a continuous current without a peak current, and the notes do not say why"]
    if cont is not None and peak is not None and not 0 < cont <= peak:
        return [f"continuous {cont} A, peak {peak} A: need 0 < continuous <= peak"]
    return []


def _regen(r: Row) -> list[str]:
    out = []
    e = num(r["absorbable_energy [J]"])
    if e is not None and e < 0:
        out.append("negative absorbable energy")
    builtin = r["builtin_braking_resistor"]
    ohm, watt = num(r["braking_resistor_ohm"]), num(r["braking_resistor_power_W"])
    if builtin == "yes" and (ohm is None or watt is None):
        out.append("built-in resistor without its ohm and W")
    if builtin == "no" and (ohm is not None or watt is not None):
        out.append("resistor values on a drive without a built-in resistor")
    avg = num(r["braking_resistor_average_power_W"])
    if avg is not None and watt is not None and avg > watt:
        out.append("average regen power above the resistor's rating")
    r_min = num(r["min_resistance_ohm"])
    if r_min is not None and r_min <= 0:
        out.append("minimum resistance <= 0")
    return out


def _voltage(r: Row) -> list[str]:
    v = num(r["voltage_V"])
    return [] if v is None or v in (100.0, 200.0, 400.0) else [f"supply voltage {v} V is not a class the pages print"]


DRIVE_CHECKS: dict[str, DriveCheck] = {"provenance": _provenance, "currents": _currents, "regen": _regen,
                                       "voltage": _voltage}


@pytest.mark.parametrize("name", sorted(DRIVE_CHECKS))
def test_every_shipped_drive_holds_its_invariants(name: str) -> None:
    problems = {rid: p for rid, r in DRIVES.items() if (p := DRIVE_CHECKS[name](r))}
    assert problems == {}


@pytest.mark.parametrize(("name", "rid", "change"), [
    ("provenance", "MR-J4-20B", {"source_page": ""}),
    ("provenance", "SGD7S-330A", {"ratings_source": "laststudy2020/hdauto-chatbot, register_yaskawa_servo.py"}),
    ("provenance", "MR-J4-60A", {"unverified_reason": ""}),
    ("provenance", "SGD7S-330A", {"verified": "yes"}),  # traced needs its vendor document
    ("currents", "MR-J4-60A", {"notes": "rated output current only"}),
    ("currents", "SGD7S-330A", {"continuous_current_A": ""}),
    ("currents", "6SL312x-xTE21-0AAx", {"peak_current_A": "4"}),
    ("currents", "6SL312x-xTE21-0AAx", {"peak_current_A": ""}),
    ("regen", "JSDG2S-10A-(E)", {"braking_resistor_ohm": ""}),
    ("regen", "JSDG2S-10A-(E)", {"braking_resistor_average_power_W": "80"}),
    ("regen", "SGD7S-R70A", {"absorbable_energy [J]": "-1"}),
    ("voltage", "MR-J4-20B", {"voltage_V": "230"}),
])
def test_each_drive_invariant_catches_a_broken_row(name: str, rid: str, change: Row) -> None:
    assert DRIVE_CHECKS[name]({**DRIVES[rid], **change})


def test_pairings_name_shipped_motors_and_drives() -> None:
    for motor_id, pair in load("drives_pairing.csv", "motor_id").items():
        assert motor_id in MOTORS and pair["drive_id"] in DRIVES
        assert pair["source"] and pair["source_url"].startswith("https://")


# ------------------------------------------------------------------------ what a shipped selection answers


def _size_json(path: Path, capsys: pytest.CaptureFixture[str]) -> dict[str, Any]:
    assert cli.main(["size", str(path), "--json"]) == 0
    out: dict[str, Any] = json.loads(capsys.readouterr().out)
    return out


def test_ball_screw_example_answers_the_drive_as_far_as_the_catalog_allows(
        capsys: pytest.CaptureFixture[str]) -> None:
    """`size examples/ball_screw.yaml --json`: every candidate has a drive block; a motor with a torque
    constant gets its currents, one without says so; the selected one has the regen block."""
    out = _size_json(EXAMPLES / "ball_screw.yaml", capsys)
    sel = out["selection"]["selected"]
    for block in [sel, *out["candidates"]]:
        d = block["drive"]
        assert d["status"] in ("ok", "fails", "unknown", "none")
        kt = catalog.get(block["motor"])["torque_constant_Nm_per_A"]
        if kt is None and d.get("judged_by") == "vendor pairing":  # a paired motor: the pairing decides
            assert d["id"] in catalog.drive_pairs()[block["motor"]] and "torque constant" in d["reason"]
        elif kt is None:
            assert d["status"] == "unknown" and "torque constant" in d["reason"]
        else:
            assert d["motor_rms_current_A"] > 0 and d["motor_peak_current_A"] >= d["motor_rms_current_A"]
            if d["status"] == "unknown":  # the motor's currents are known: what is missing is the drive's
                assert "current ratings" in d["reason"]
        if d.get("judged_by") == "vendor pairing":
            assert {c["name"] for c in d["checks"]} == {"drive_continuous_by_pairing", "drive_peak_by_pairing"}
        elif d["status"] in ("unknown", "none"):  # none: no drive runs the motor (its vendor, voltage, series)
            assert d["reason"]
        else:
            assert {c["name"] for c in d["checks"]} >= {"drive_rms_current", "drive_peak_current"}
    regen = sel["regen"]
    assert regen["energy_per_cycle_J"] == pytest.approx(regen["capacitor_absorbed_J"]
                                                        + regen["resistor_energy_per_cycle_J"])
    assert regen["resistor_peak_power_W"] > 0 and regen["energy_per_cycle_J"] > 0  # it lowers a load
    assert "envelope_source" in sel["electrical"] and "winding_temperature_rise_K" in sel["electrical"]


def test_ball_screw_with_hg_kr23_answers_the_motor_currents_of_the_vendor_page(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The HG-KR23 (the shipped ball-screw selection) has its currents and a derived k_T: the answer gives
    the motor's current checks against the page's 1.3 A / 4.6 A and says that k_T was derived."""
    text = (EXAMPLES / "ball_screw.yaml").read_text(encoding="utf-8")
    head, _ = text.split("\nmotor:", 1)
    path = tmp_path / "z.yaml"
    path.write_text(head + "\nmotor: {id: HG-KR23, margins: {torque: 1.2, inertia_ratio: 10}}\n", encoding="utf-8")
    e = _size_json(path, capsys)["motor"]  # a given catalog motor: its electrical answer is in the motor block
    assert e["torque_constant_NmA"] == 0.4923
    checks = {c["name"]: c for c in e["checks"]}
    assert checks["motor_rms_current"]["available"] == 1.3
    assert checks["motor_peak_current"]["available"] == 4.6
    assert 0 < e["rms_current_A"] <= e["peak_current_A"]
    assert any(DERIVED_KT in s for s in e["electrical_sources"])


HEAVY_Z = """\
axis: Z heavy
efficiency_model: four_quadrant
mechanism:
  type: ball_screw
  lead: 10 mm
  diameter: 40 mm
  length: 800 mm
  material: steel
  efficiency: 0.9
  incline: 90 deg
  load: {mass: 1200 kg, counterweight: 0 kg, friction: 0.05, thrust: 0 N}
profile:
  - {move: 200 mm, time: 0.8 s, accel: 0.2 s}
  - {dwell: 0.5 s}
  - {move: -200 mm, time: 0.8 s, accel: 0.2 s}
  - {dwell: 0.5 s, holding: brake}
motor:
  select: {vendor: yaskawa, gearbox: none}
"""


def test_a_derived_torque_constant_gives_the_selected_motor_its_currents(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "heavy.yaml"
    path.write_text(HEAVY_Z, encoding="utf-8")
    out = _size_json(path, capsys)
    sel = out["selection"]["selected"]
    assert ELEC[sel["motor"]]["torque_constant_basis"].startswith("derived")  # an SGM7G-30A...1EA motor
    e = sel["electrical"]
    kt = float(ELEC[sel["motor"]]["torque_constant_Nm_per_A"])
    assert e["torque_constant_NmA"] == kt
    assert any(DERIVED_KT in s for s in e["electrical_sources"])  # the answer says k_T was derived
    checks = {c["name"]: c for c in e["checks"]}
    # below the rated torque I = T / k_T; k_T = T_N / I_N, so the RMS current check is the RMS torque
    # check in amperes: the rated current is the continuous current of these rows (no stall current)
    assert checks["motor_rms_current"]["available"] == float(ELEC[sel["motor"]]["rated_current_A"])
    assert checks["motor_peak_current"]["available"] == float(ELEC[sel["motor"]]["peak_current_A"])
    assert e["rms_current_A"] >= sel["rms_torque_Nm"] / kt * (1 - 1e-9)
    d = sel["drive"]
    # the SERVOPACK its pairing row names (drives_pairing.csv, the third-party transcription), its currents checked
    assert d["basis"] == "vendor pairing table" and d["id"] in catalog.drive_pairs()[sel["motor"]]
    assert d["status"] == "ok" and d["unverified"] is True
    assert d["motor_rms_current_A"] <= d["continuous_current_A"] and d["motor_peak_current_A"] <= d["peak_current_A"]
    assert math.isclose(d["motor_rms_current_A"], e["rms_current_A"], rel_tol=1e-9)
