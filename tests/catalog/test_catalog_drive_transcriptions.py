"""The drive output currents and motor pairings shipped from a third-party transcription (data/SOURCES.md, "Drives"):
laststudy2020/hdauto-chatbot at commit 084abb8e604a3f89254d1626692954d1f88e5217, register_yaskawa_servo.py
(YASKAWA_SGD7S) and register_mrj4_servo.py (_BASE_SPECS). Each value below is quoted from those files; the
pairings are checked against the vendor-traced motor currents, and the shipped examples that select a Yaskawa
or Mitsubishi motor answer its drive with current ratings.
"""

from __future__ import annotations

import csv
import io
import json
from importlib import resources
from pathlib import Path
from typing import Any

import pytest

from drivetrain import catalog, cli

Row = dict[str, str]
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
COMMIT = "084abb8e604a3f89254d1626692954d1f88e5217"


def load(name: str) -> list[Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return list(csv.DictReader(io.StringIO(text)))


def num(s: str | None) -> float | None:
    return None if s is None or s.strip() == "" else float(s)


DRIVES = {r["id"]: r for r in load("drives_servo.csv")}
PAIRS = load("drives_pairing.csv")
ELEC = {r["id"]: r for r in load("motors_ac_servo_electrical.csv")}
TRANSCRIBED = [p for p in PAIRS if COMMIT in p["source"]]

# register_yaskawa_servo.py, YASKAWA_SGD7S: (pack code, continuous output current A, instantaneous maximum A)
SGD7S = [("R70A", 0.66, 2.1), ("R90A", 0.91, 3.2), ("1R6A", 1.6, 5.9), ("2R8A", 2.8, 9.3), ("3R8A", 3.8, 11.0),
         ("5R5A", 5.5, 16.9), ("7R6A", 7.6, 17.0), ("120A", 11.6, 28.0), ("180A", 18.5, 42.0), ("200A", 19.6, 56.0),
         ("330A", 32.9, 84.0), ("470A", 46.9, 110.0), ("550A", 54.7, 130.0), ("590A", 58.6, 140.0),
         ("780A", 78.0, 170.0)]
# register_mrj4_servo.py, _SIZE_SUFFIXES with _BASE_SPECS: (size, rated output current A)
MRJ4 = [("10", 1.1), ("20", 1.5), ("40", 2.8), ("60", 3.2), ("70", 5.8), ("100", 6.0), ("200", 11.0), ("350", 17.0),
        ("500", 28.0), ("700", 37.0)]


@pytest.mark.parametrize(("code", "cont", "peak"), SGD7S)
def test_sgd7s_currents_as_transcribed(code: str, cont: float, peak: float) -> None:
    r = DRIVES[f"SGD7S-{code}"]
    assert (num(r["continuous_current_A"]), num(r["peak_current_A"])) == (cont, peak)
    assert num(r["voltage_V"]) == 200 and r["motor_series"] == "SGM7"
    assert r["verified"] == "no" and "register_yaskawa_servo.py" in r["ratings_source"] and COMMIT in r["source"]


@pytest.mark.parametrize(("size", "cont"), MRJ4)
@pytest.mark.parametrize("interface", ["A", "B"])
def test_mr_j4_rated_currents_as_transcribed(size: str, cont: float, interface: str) -> None:
    r = DRIVES[f"MR-J4-{size}{interface}"]
    assert num(r["continuous_current_A"]) == cont and num(r["voltage_V"]) == 200
    assert r["verified"] == "no" and "register_mrj4_servo.py" in r["ratings_source"] and COMMIT in r["source"]
    # the transcription prints no amplifier peak: only the size that runs HG-KR23 carries that motor's
    # "maximum current with MR-J4" (4.6 A, the vendor's HG-KR23BG1 page), and says so
    if size == "20":
        assert num(r["peak_current_A"]) == float(ELEC["HG-KR23"]["peak_current_A"]) == 4.6
        assert "HG-KR23" in r["ratings_source"] and "not an amplifier rating" in r["ratings_source"]
    else:
        assert num(r["peak_current_A"]) is None and "peak current empty" in r["notes"]


@pytest.mark.parametrize(("rid", "joule"), [
    # the vendor-traced regen values stay as they were: Sigma-7S manual 12.8.6 p. 12-37, MR-J4-_B manual p. 11-13
    ("SGD7S-R70A", 24.2), ("SGD7S-2R8A", 31.7), ("MR-J4-20B", 9), ("MR-J4-350B", 40), ("MR-J4-700B", 70),
])
def test_merged_rows_keep_their_traced_regen_data_and_document(rid: str, joule: float) -> None:
    r = DRIVES[rid]
    assert num(r["absorbable_energy [J]"]) == joule
    assert r["source_document"] and r["source_page"] in ("12-37", "11-13") and r["source_url"].startswith("http")
    assert "manual" in r["source"].split(";")[0].lower()  # the vendor document comes first, the transcription after
    assert COMMIT in r["source"] and COMMIT in r["ratings_source"]


def test_the_a_and_b_amplifiers_of_one_size_share_their_transcribed_values() -> None:
    """The transcription states the _A and _B electrical specifications equal (its docstring); the shipped rows agree,
    and only the _B rows carry the regen data read from the _B manual."""
    for size, _ in MRJ4:
        a, b = DRIVES[f"MR-J4-{size}A"], DRIVES[f"MR-J4-{size}B"]
        assert (a["continuous_current_A"], a["peak_current_A"]) == (b["continuous_current_A"], b["peak_current_A"])
        assert a["absorbable_energy [J]"] == "" and b["absorbable_energy [J]"] != ""


# ---------------------------------------------------------------------------------- pairings


def pairing_problems(pair: Row, drives: dict[str, Row], elec: dict[str, Row]) -> list[str]:
    """A stated pairing against the motor's vendor-traced currents: rated <= the drive's continuous current,
    peak <= the drive's maximum current (where the drive has one)."""
    motor, drive = elec.get(pair["motor_id"]), drives[pair["drive_id"]]
    if motor is None:
        return []
    out = []
    rated, peak = num(motor["rated_current_A"]), num(motor["peak_current_A"])
    cont, drive_peak = num(drive["continuous_current_A"]), num(drive["peak_current_A"])
    if rated is not None and cont is not None and rated > cont:
        out.append(f"motor rated {rated} A > drive continuous {cont} A")
    if peak is not None and drive_peak is not None and peak > drive_peak:
        out.append(f"motor peak {peak} A > drive maximum {drive_peak} A")
    return out


def test_every_stated_pairing_is_consistent_with_the_traced_motor_currents() -> None:
    checked = [p for p in TRANSCRIBED if p["motor_id"] in ELEC]
    problems = {f"{p['motor_id']} on {p['drive_id']}": pairing_problems(p, DRIVES, ELEC) for p in checked}
    assert {k: v for k, v in problems.items() if v} == {}
    sgd7s = [p for p in checked if p["drive_id"].startswith("SGD7S-")]
    # 7 SGM7J + 7 SGM7A + 11 SGM7G rows of motors_ac_servo_electrical.csv, each paired with one SERVOPACK
    assert len(sgd7s) == 25 and len({p["motor_id"] for p in sgd7s}) == 25
    mrj4 = [p for p in checked if p["drive_id"].startswith("MR-J4-")]
    assert {(p["motor_id"], p["drive_id"]) for p in mrj4} == {("HG-KR23", "MR-J4-20A"), ("HG-KR23", "MR-J4-20B")}


@pytest.mark.parametrize(("motor", "drive", "change", "problem"), [
    ("SGM7G-09A", "SGD7S-7R6A", {"continuous_current_A": "6.0"}, "continuous"),  # SGM7G-09A rated 6.9 A
    ("SGM7J-08A", "SGD7S-5R5A", {"peak_current_A": "15"}, "maximum"),  # SGM7J-08A peak 16.9 A
])
def test_the_pairing_check_catches_an_inconsistent_drive(motor: str, drive: str, change: Row, problem: str) -> None:
    pair = next(p for p in PAIRS if (p["motor_id"], p["drive_id"]) == (motor, drive))
    broken = {**DRIVES, drive: {**DRIVES[drive], **change}}
    assert any(problem in p for p in pairing_problems(pair, broken, ELEC))


def test_the_24_kw_rating_of_sgm7g_30a_is_not_stored_as_a_pairing() -> None:
    """'SGM7G-30A(2.4kW사양)' on SGD7S-200A is another rating of the motor than the catalog's 2.9 kW row; its 23.8 A
    rated current exceeds that SERVOPACK's 19.6 A, so only SGD7S-330A is the row's pairing."""
    assert [p["drive_id"] for p in PAIRS if p["motor_id"] == "SGM7G-30A"] == ["SGD7S-330A"]
    assert num(ELEC["SGM7G-30A"]["rated_current_A"]) == 23.8 > num(DRIVES["SGD7S-200A"]["continuous_current_A"])
    assert "2.4kW" in DRIVES["SGD7S-200A"]["notes"]


def test_pairings_follow_the_transcription_and_name_shipped_motors() -> None:
    shipped = {r["id"] for r in load("motors_ac_servo.csv")}
    for p in TRANSCRIBED:
        assert p["motor_id"] in shipped and p["drive_id"] in DRIVES
        assert p["motor_id"] in DRIVES[p["drive_id"]]["notes"]  # the drive's row lists the transcription's motors
        assert p["source_url"] == f"https://github.com/laststudy2020/hdauto-chatbot/blob/{COMMIT}/" + (
            "register_yaskawa_servo.py" if p["drive_id"].startswith("SGD7S") else "register_mrj4_servo.py")
    # the transcription's motors that the catalog does not ship are named in the drive rows, not paired
    for mid in ("HG-SR51", "HG-SR81", "HG-SR121", "HG-SR201", "HG-SR301", "HG-SR421"):
        assert mid not in shipped and not any(p["motor_id"] == mid for p in PAIRS)
        assert any(mid in r["notes"] for r in DRIVES.values() if r["id"].startswith("MR-J4-"))


def test_the_database_honours_the_pairings() -> None:
    pairs = catalog.drive_pairs()
    assert pairs["SGM7G-09A"] == ["SGD7S-7R6A"]
    assert pairs["HG-KR23"] == ["MR-J4-20B", "MR-J4-20A"]  # the _B row first: it carries the regen data
    assert pairs["1FT7044-5AK7"] == ["6SL312x-xTE21-0AAx"]
    row = catalog.get("SGD7S-7R6A")
    assert row["unverified"] and "hdauto-chatbot" in row["unverified_reason"]
    assert "register_yaskawa_servo.py" in row["sources"]["ratings"]


# ---------------------------------------------------------------------------------- the shipped examples


def _size_json(path: Path, capsys: pytest.CaptureFixture[str]) -> dict[str, Any]:
    assert cli.main(["size", str(path), "--json"]) == 0
    out: dict[str, Any] = json.loads(capsys.readouterr().out)
    return out


def test_a_yaskawa_pick_gets_its_sgd7s_with_current_ratings(capsys: pytest.CaptureFixture[str]) -> None:
    """`size examples/belt_gantry.yaml`: the Yaskawa pick SGM7G-09A runs on SGD7S-7R6A (its pairing row), whose
    transcribed 7.6 A / 17 A are checked against the motor's current over the cycle. (The hoist example picked
    it too until its brake had to be known: it now answers a motor whose brake's holding torque the catalog
    has, and SGM7G-09A's is not in it.)"""
    sel = _size_json(EXAMPLES / "belt_gantry.yaml", capsys)["selection"]["selected"]
    assert sel["motor"] == "SGM7G-09A"
    d = sel["drive"]
    assert d["id"] == "SGD7S-7R6A" and d["basis"] == "vendor pairing table" and d["status"] == "ok"
    assert (d["continuous_current_A"], d["peak_current_A"]) == (7.6, 17.0)
    checks = {c["name"]: c for c in d["checks"]}
    assert checks["drive_rms_current"]["available"] == 7.6 and checks["drive_peak_current"]["available"] == 17.0
    assert 0 < d["motor_rms_current_A"] <= 7.6 and d["motor_peak_current_A"] <= 17.0
    assert d["unverified"] is True and COMMIT in d["unverified_reason"]


def test_mr_j4_is_offered_only_to_the_mr_j4_motor_series(capsys: pytest.CaptureFixture[str]) -> None:
    """The MR-J4 amplifiers run the HG-MR/KR/SR/JR/RR/UR motors (Servo Motor Instruction Manual Vol. 3, SH(NA)030113,
    cover): a CNC (MELDAS) HC motor gets no MR-J4, and says why (before: HC52 was answered with MR-J4-20B)."""
    from drivetrain import catalog

    assert catalog.get("MR-J4-20B")["motor_series"] == "HG-MR HG-KR HG-SR HG-JR HG-RR HG-UR"
    out = _size_json(EXAMPLES / "rotary.yaml", capsys)
    sel = out["selection"]["selected"]
    assert sel["motor"].startswith("HC") and sel["drive"]["status"] == "none"
    assert "HG-MR HG-KR HG-SR HG-JR HG-RR HG-UR" in sel["drive"]["reason"]
    assert any(u["part"] == "drive" for u in out["verdict"]["unknowns"])


def test_ball_screw_example_gets_an_mr_j4_with_its_rated_current_checked(capsys: pytest.CaptureFixture[str]) -> None:
    """`size examples/ball_screw.yaml`: HG-KR23 runs on MR-J4-20B (pairing row; the _B row carries the regen data),
    1.5 A rated output current checked, the peak against HG-KR23's maximum current with MR-J4 (4.6 A)."""
    sel = _size_json(EXAMPLES / "ball_screw.yaml", capsys)["selection"]["selected"]
    assert sel["motor"] == "HG-KR23"
    d = sel["drive"]
    assert d["id"] == "MR-J4-20B" and d["candidates"] == ["MR-J4-20B", "MR-J4-20A"] and d["status"] == "ok"
    checks = {c["name"]: c for c in d["checks"]}
    assert checks["drive_rms_current"]["available"] == 1.5 and checks["drive_rms_current"]["ok"] is True
    assert checks["drive_peak_current"]["available"] == 4.6
    assert d["unverified"] is True
    assert sel["regen"]["capacitor_energy_per_event_J"] == 9.0  # MR-J4-_B manual p. 11-13, the traced value


def test_the_cli_table_flags_the_transcribed_drive(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["size", str(EXAMPLES / "belt_gantry.yaml")]) == 0
    text = " ".join(capsys.readouterr().out.split())  # the table wraps long lines
    assert "drive SGD7S-7R6A: OK" in text and "drive SGD7S-7R6A †: output currents and motor pairings from a " \
        "third-party transcription" in text
