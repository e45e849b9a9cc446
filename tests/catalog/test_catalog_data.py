"""The shipped catalog data: row counts, provenance, invariants and spot checks against vendor values.

These tests read the package's own data files (drivetrain/catalog/data) and the database built
from them. Each invariant is a small function returning the problems of one row; it is run over
every shipped row (no problem allowed) and over a deliberately broken row (the problem is found),
so a check that can no longer fail is noticed.
"""

from __future__ import annotations

import collections
import csv
import io
import math
import shutil
from collections.abc import Callable
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from drivetrain import catalog
from drivetrain.catalog import db
from drivetrain.catalog.schema import SHIPPED_FILES, TRACED_GEARBOX_FAMILIES
from tests.conftest import family_drive_rows

RPM = 2 * math.pi / 60
Row = dict[str, str]


def load(name: str) -> list[Row]:
    text = resources.files("drivetrain.catalog").joinpath("data", name).read_text(encoding="utf-8")
    return list(csv.DictReader(io.StringIO(text)))


def num(s: str | None) -> float | None:
    if s is None or s == "":
        return None
    v = float(s)
    return v if math.isfinite(v) else None


AC = load("motors_ac_servo.csv")
PLANETARY = load("gearboxes_planetary.csv")
SMALL_DC = load("motors_small_dc.csv")
SMALL_GB = load("gearboxes_small.csv")
REJECTS = load("rejects.csv")
BECKHOFF = {family: load(f"gearboxes_beckhoff_{family}.csv") for family in ("ag2250", "ag2400", "ag3400")}
# servo gearbox families shipped as gearboxes_<vendor>_<family>.csv (schema.TRACED_GEARBOX_FAMILIES)
TRACED_GB = {family: load(f"gearboxes_{family}.csv") for family in TRACED_GEARBOX_FAMILIES}
SERVO_GEARBOXES = {"gearboxes_planetary.csv": PLANETARY} | {
    f"gearboxes_beckhoff_{k}.csv": v for k, v in BECKHOFF.items()} | {
    f"gearboxes_{k}.csv": v for k, v in TRACED_GB.items()}
FILES = {"motors_ac_servo.csv": AC, "motors_small_dc.csv": SMALL_DC, "gearboxes_small.csv": SMALL_GB,
         **SERVO_GEARBOXES}


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("catalog-data")
    db.builtin_db(directory)
    return directory


@pytest.fixture
def use_data_dir(data_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    d = tmp_path / "data"
    d.mkdir()
    shutil.copy(data_dir / db.BUILTIN_NAME, d / db.BUILTIN_NAME)
    monkeypatch.setenv(db.ENV_DATA_DIR, str(d))
    return d


# ---------------------------------------------------------------------------------- counts and provenance


def test_row_counts_match_the_data_readme() -> None:
    assert len(AC) == 297
    assert len(PLANETARY) == 713
    assert len(SMALL_DC) == 298
    assert len(SMALL_GB) == 300
    assert len(REJECTS) == 256
    assert load("drives.csv") == []  # schema only: no sourced drive data exists
    assert {k: len(v) for k, v in BECKHOFF.items()} == {"ag2250": 22, "ag2400": 23, "ag3400": 23}


def test_ac_servo_vendors_and_counts() -> None:
    counts = collections.Counter(r["vendor"] for r in AC)
    assert counts == {"FANUC": 24, "LS Mecapion": 106, "Mitsubishi Electric": 42, "Omron": 24, "Panasonic": 32,
                      "Siemens": 31, "Yaskawa": 38}


def test_rockwell_is_withheld_and_every_reject_has_a_reason() -> None:
    assert not any("Rockwell" in r["vendor"] for r in AC)
    rockwell = [r for r in REJECTS if r["vendor"].startswith("Rockwell")]
    assert len(rockwell) == 154
    assert all(r["reason"] for r in REJECTS)
    assert "MPL-B320P" in {r["id"] for r in REJECTS}
    kept = {(name, r["id"]) for name, rows in FILES.items() for r in rows}
    assert not [r["id"] for r in REJECTS if (r["target_file"], r["id"]) in kept]


def test_model_counts_of_the_other_files() -> None:
    assert len({r["id"].rsplit("-", 2)[0] for r in PLANETARY}) == 42
    assert sorted({r["series"] for r in PLANETARY}) == ["GPB", "GPBR", "GPD", "GPDR", "GPE", "GPER", "GPV", "GPVR"]
    assert collections.Counter(r["vendor"] for r in SMALL_DC) == {"Maxon": 140, "Faulhaber": 80,
                                                                  "Allied Motion": 70, "Tmotor": 8}
    assert collections.Counter(r["vendor"] for r in SMALL_GB) == {"Maxon": 200, "Faulhaber": 100}


@pytest.mark.parametrize("name", list(FILES))
def test_every_row_has_a_source_and_a_unique_id(name: str) -> None:
    rows = FILES[name]
    assert all(r["source"].strip() for r in rows)
    ids = collections.Counter(r["id"] for r in rows)
    assert [k for k, v in ids.items() if v > 1] == []


def test_ids_are_unique_across_all_files() -> None:
    ids = collections.Counter(r["id"] for rows in FILES.values() for r in rows)
    assert [k for k, v in ids.items() if v > 1] == []


REQUIRED = {
    "motors_ac_servo.csv": ["id", "vendor", "series", "rated_power_W", "rated_torque_Nm", "peak_torque_Nm",
                            "stall_torque_Nm", "rated_speed_rpm", "max_speed_rpm", "rotor_inertia_kgm2", "mass_kg",
                            "flange_mm", "voltage_class_V", "brake", "source", "notes", "rated_torque_basis"],
    "gearboxes_planetary.csv": ["id", "vendor", "series", "ratio", "stages", "rated_output_torque_Nm",
                                "max_output_torque_Nm", "efficiency", "max_input_speed_rpm", "rated_input_speed_rpm",
                                "inertia_input_kgm2", "mass_kg", "max_radial_load_N", "max_axial_load_N",
                                "torsional_stiffness_Nm_per_arcmin", "backlash_arcmin", "source", "notes"],
    "motors_small_dc.csv": ["id", "vendor", "nominal_voltage_V", "torque_constant_Nm_per_A",
                            "terminal_resistance_ohm", "no_load_speed_rad_s", "no_load_speed_rpm",
                            "rotor_inertia_kgm2", "source", "notes"],
    "gearboxes_small.csv": ["id", "vendor", "ratio", "efficiency", "max_continuous_torque_Nm",
                            "max_intermittent_torque_Nm", "inertia_input_kgm2", "source", "notes"],
}
# every servo gearbox file: the planetary file's columns plus the ratings, bore and the document read
SERVO_GEARBOX_COLUMNS = [*REQUIRED["gearboxes_planetary.csv"], "emergency_stop_torque_Nm", "input_bore_max_mm",
                         "input_bore_min_mm", "input_flange_mm", "input_pilot_mm", "input_adapters", "verified",
                         "source_document", "source_section", "source_page", "source_url"]
for _name in SERVO_GEARBOXES:
    REQUIRED[_name] = SERVO_GEARBOX_COLUMNS


@pytest.mark.parametrize("name", list(REQUIRED))
def test_required_columns_are_present(name: str) -> None:
    assert set(REQUIRED[name]) <= set(FILES[name][0])


# ---------------------------------------------------------------------------------- invariants per row


def ac_servo_problems(r: Row) -> list[str]:
    """check_catalog.py's AC servo invariants for one row."""
    out = []
    p, t, tpk, tst = (num(r[k]) for k in ("rated_power_W", "rated_torque_Nm", "peak_torque_Nm", "stall_torque_Nm"))
    n, nmax, j, m = (num(r[k]) for k in ("rated_speed_rpm", "max_speed_rpm", "rotor_inertia_kgm2", "mass_kg"))
    if not (t and t > 0):
        out.append("rated torque missing or <= 0")
    if not (tpk and t and tpk >= t):
        out.append("peak < rated")
    if not (n and n > 0 and nmax and nmax >= n):
        out.append("max speed < rated speed")
    if not (j and j > 0):
        out.append("inertia missing")
    elif not 1e-8 < j < 1.0:
        out.append("inertia outside 1e-8..1 kg*m^2")
    elif t and not 1e-6 < j / t < 1e-2:
        out.append("inertia/rated torque outside 1e-6..1e-2 s^2")
    if not (p and p > 0):
        out.append("rated power missing")
    elif t and n and abs(t * n * RPM - p) / p > 0.15:
        out.append("|P - T omega|/P > 15 %")
    if tst is not None and t is not None and tst < t * (1 - 1e-6):
        out.append("stall < rated")
    if r["brake"] not in ("yes", "no"):
        out.append("brake not yes/no")
    if r["voltage_class_V"] not in ("", "200", "230", "400", "460"):
        out.append("voltage class")
    if m is not None and not 0.05 < m < 500:
        out.append("mass implausible")
    if not r["source"]:
        out.append("source empty")
    if r["rated_torque_basis"] != "source" and "derived" not in r["notes"]:
        out.append("derived rated torque without a note")
    return out


def planetary_problems(r: Row) -> list[str]:
    out = []
    i, eff, t = num(r["ratio"]), num(r["efficiency"]), num(r["rated_output_torque_Nm"])
    j, m, nr, nm = (num(r[k]) for k in ("inertia_input_kgm2", "mass_kg", "rated_input_speed_rpm",
                                        "max_input_speed_rpm"))
    if not (i and i > 1):
        out.append("ratio <= 1")
    if not (eff and 0 < eff <= 1):
        out.append("efficiency outside (0,1]")
    if not (t and t > 0):
        out.append("rated output torque missing")
    if j is not None and not 0 < j < 0.1:
        out.append("input inertia implausible")
    elif j is not None and t and not 1e-8 < j / t < 1e-3:
        out.append("input inertia/output torque implausible")
    if m is not None and not m > 0:
        out.append("mass <= 0")
    if nr and nm and nm < nr:
        out.append("max input speed < rated input speed")
    es, mx = num(r["emergency_stop_torque_Nm"]), num(r["max_output_torque_Nm"])
    if es is not None and t and es < t:
        out.append("emergency-stop torque < rated")
    if mx is not None and t and mx < t:
        out.append("max output torque < rated")
    if num(r["stages"]) not in (1, 2, 3):
        out.append("stages")
    if not r["vendor"]:
        out.append("vendor empty")
    return out + servo_rating_problems(r)


def servo_rating_problems(r: Row) -> list[str]:
    """Issue #12's gearbox ratings and issue #17's traceability, for one servo gearbox row.

    T2N <= T2B <= T2NOT where printed, n1N <= n1max, plausible units (a unit slip of mm/m, rpm/rad/s or
    kg*cm^2/kg*m^2 lands outside these windows), and every row names its document, page and URL or says
    verified = no with the reason in its notes.
    """
    out = []
    t2n, t2b, t2not = (num(r[k]) for k in ("rated_output_torque_Nm", "max_output_torque_Nm",
                                             "emergency_stop_torque_Nm"))
    n1n, n1max = num(r["rated_input_speed_rpm"]), num(r["max_input_speed_rpm"])
    if t2n is not None and t2b is not None and t2b < t2n:
        out.append("T2B < T2N")
    if t2b is not None and t2not is not None and t2not < t2b:
        out.append("T2NOT < T2B")
    if t2n is not None and t2b is not None and t2b > 5 * t2n:
        out.append("T2B > 5 T2N (unit slip?)")
    if n1n is not None and n1max is not None and n1max < n1n:
        out.append("n1max < n1N")
    for speed in (n1n, n1max):
        if speed is not None and not 300 <= speed <= 20000:
            out.append("input speed outside 300..20000 rpm")
    bmin, bmax = num(r["input_bore_min_mm"]), num(r["input_bore_max_mm"])
    for bore in (bmin, bmax, num(r["input_pilot_mm"]), num(r["input_flange_mm"])):
        if bore is not None and not 3 <= bore <= 300:
            out.append("input bore/pilot/flange outside 3..300 mm")
    if bmin is not None and bmax is not None and bmin > bmax:
        out.append("input bore min > max")
    if r["verified"] not in ("yes", "no"):
        out.append("verified not yes/no")
    documented = all(r[k].strip() for k in ("source_document", "source_page", "source_url"))
    if r["verified"] == "yes" and not (documented and r["source_url"].startswith("https://")):
        out.append("verified row without document, page and URL")
    if r["verified"] == "no" and "not verified" not in r["notes"] and "no vendor document" not in r["notes"]:
        out.append("unverified row without the reason in its notes")
    if not documented and r["verified"] != "no":
        out.append("row without document, page and URL must be verified = no")
    return out


def small_dc_problems(r: Row) -> list[str]:
    out = []
    v, kt, res, w, j = (num(r[k]) for k in ("nominal_voltage_V", "torque_constant_Nm_per_A",
                                            "terminal_resistance_ohm", "no_load_speed_rad_s", "rotor_inertia_kgm2"))
    if not (v and kt and res and w and j and min(v, kt, res, w, j) > 0):
        return ["V, k_t, R, no-load speed and inertia must be > 0"]
    inl = num(r["no_load_current_A"]) or 0.0
    if abs((v - res * inl) / kt - w) / w > 0.10:
        out.append("no-load speed inconsistent with (V - R I_nl)/k_t")
    ts, tn, wn = num(r["stall_torque_Nm"]), num(r["nominal_torque_Nm"]), num(r["nominal_speed_rad_s"])
    if tn is not None and not (ts and 0 < tn < ts):
        out.append("nominal torque not in (0, stall)")
    if wn is not None and not 0 < wn < w:
        out.append("nominal speed not in (0, no-load speed)")
    rpm = num(r["no_load_speed_rpm"])
    if rpm is None or abs(rpm * RPM - w) > 1e-3 * w:
        out.append("rpm and rad/s columns disagree")
    return out


def small_gearhead_problems(r: Row) -> list[str]:
    out = []
    i, eff, mc, mi, j = (num(r[k]) for k in ("ratio", "efficiency", "max_continuous_torque_Nm",
                                             "max_intermittent_torque_Nm", "inertia_input_kgm2"))
    if not (i and i > 1):
        out.append("ratio <= 1")
    if not (eff and 0 < eff <= 1):
        out.append("efficiency outside (0,1]")
    if not (mc and mc > 0 and mi and mi >= mc):
        out.append("need max intermittent >= max continuous > 0")
    if j is not None and not j > 0:
        out.append("inertia <= 0")
    return out


CHECKS: dict[str, tuple[list[Row], Callable[[Row], list[str]]]] = {
    "ac_servo": (AC, ac_servo_problems),
    "planetary": (PLANETARY, planetary_problems),
    **{f"beckhoff_{k}": (v, planetary_problems) for k, v in BECKHOFF.items()},
    **{k: (v, planetary_problems) for k, v in TRACED_GB.items()},
    "small_dc": (SMALL_DC, small_dc_problems),
    "small_gearhead": (SMALL_GB, small_gearhead_problems),
}


@pytest.mark.parametrize("name", list(CHECKS))
def test_every_shipped_row_passes_its_invariants(name: str) -> None:
    rows, problems = CHECKS[name]
    bad = {r["id"]: problems(r) for r in rows if problems(r)}
    assert bad == {}


# One broken copy of a real row per invariant: the check must see it.
BROKEN = [
    ("ac_servo", "HG-KR43", {"peak_torque_Nm": "1.0"}, "peak < rated"),
    ("ac_servo", "HG-KR43", {"max_speed_rpm": "2000"}, "max speed < rated speed"),
    ("ac_servo", "HG-KR43", {"rotor_inertia_kgm2": "0.371"}, "inertia/rated torque outside 1e-6..1e-2 s^2"),
    ("ac_servo", "HG-KR43", {"rated_power_W": "600"}, "|P - T omega|/P > 15 %"),
    ("ac_servo", "aiF4/4000", {"stall_torque_Nm": "3"}, "stall < rated"),
    ("ac_servo", "aiF4/4000", {"notes": ""}, "derived rated torque without a note"),
    ("ac_servo", "HG-KR43", {"source": ""}, "source empty"),
    ("planetary", "GPB042-L1-i3", {"efficiency": "1.2"}, "efficiency outside (0,1]"),
    ("planetary", "GPB042-L1-i3", {"inertia_input_kgm2": "0.03"}, "input inertia/output torque implausible"),
    ("planetary", "GPB042-L1-i3", {"emergency_stop_torque_Nm": "10"}, "emergency-stop torque < rated"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"max_output_torque_Nm": "80"}, "T2B < T2N"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"emergency_stop_torque_Nm": "170"}, "T2NOT < T2B"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"max_output_torque_Nm": "1720"}, "T2B > 5 T2N (unit slip?)"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"max_input_speed_rpm": "2000"}, "n1max < n1N"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"rated_input_speed_rpm": "272"},
     "input speed outside 300..20000 rpm"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"input_bore_max_mm": "0.024"},
     "input bore/pilot/flange outside 3..300 mm"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"input_bore_min_mm": "28"}, "input bore min > max"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"verified": "maybe"}, "verified not yes/no"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"source_url": ""}, "verified row without document, page and URL"),
    ("beckhoff_ag2400", "AG2400-TP010-MF-i4", {"source_page": ""},
     "row without document, page and URL must be verified = no"),
    ("planetary", "GPB042-L1-i3", {"notes": "backlash per drawing"}, "unverified row without the reason in its notes"),
    ("small_dc", "ECXZ06M1VF44N1IL1D659A", {"no_load_speed_rad_s": "5000"},
     "no-load speed inconsistent with (V - R I_nl)/k_t"),
    ("small_gearhead", "354723", {"max_intermittent_torque_Nm": "0.5"},
     "need max intermittent >= max continuous > 0"),
]


@pytest.mark.parametrize(("name", "rid", "change", "problem"), BROKEN)
def test_each_invariant_catches_a_broken_row(name: str, rid: str, change: Row, problem: str) -> None:
    rows, problems = CHECKS[name]
    row = {**next(r for r in rows if r["id"] == rid), **change}
    assert problem in problems(row)


def test_derived_rated_torques_are_exactly_the_fanuc_rows() -> None:
    derived = [r for r in AC if r["rated_torque_basis"] != "source"]
    assert len(derived) == 24
    assert {r["vendor"] for r in derived} == {"FANUC"}
    assert all(r["stall_torque_Nm"] for r in derived)


def test_datasheet_rows_agree_with_power_within_six_percent() -> None:
    devs = [abs(float(r["rated_torque_Nm"]) * float(r["rated_speed_rpm"]) * RPM - float(r["rated_power_W"]))
            / float(r["rated_power_W"]) for r in AC if r["rated_torque_basis"] == "source"]
    assert len(devs) == 273
    assert max(devs) == pytest.approx(0.058, abs=0.001)  # HG-JR353, flagged in SOURCES.md


# ---------------------------------------------------------------------------------- spot checks

# Published values quoted in the catalog's check script: (rated W, rated N m, peak N m, rated rpm,
# max rpm, inertia kg m^2, document).
REFERENCE = {
    "HG-KR43": (400, 1.3, 4.5, 3000, 6000, 0.371e-4, "Mitsubishi HG-KR43 reference values"),
    "SGM7J-A5A": (50, 0.159, 0.557, 3000, 6000, 0.0395e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-01A": (100, 0.318, 1.11, 3000, 6000, 0.0659e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-C2A": (150, 0.477, 1.67, 3000, 6000, 0.0915e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-02A": (200, 0.637, 2.23, 3000, 6000, 0.263e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-04A": (400, 1.27, 4.46, 3000, 6000, 0.486e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-06A": (600, 1.91, 6.69, 3000, 6000, 0.800e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "SGM7J-08A": (750, 2.39, 8.36, 3000, 6000, 1.59e-4, "Yaskawa Sigma-7 product manual 4.2.2, SGM7J"),
    "1FT7044-5AK7": (None, 2.0, 23.0, 6000, 9000, 5.43e-4, "Siemens 1FT7 Configuration Manual 01/2009 Table 4-8"),
}


@pytest.mark.parametrize("rid", list(REFERENCE))
def test_spot_check_against_published_ratings(rid: str) -> None:
    p, t, tpk, n, nmax, j, _doc = REFERENCE[rid]
    r = next(r for r in AC if r["id"] == rid)
    if p is not None:
        assert num(r["rated_power_W"]) == pytest.approx(p, rel=0.011)
    assert num(r["rated_torque_Nm"]) == pytest.approx(t, rel=0.011)
    assert num(r["peak_torque_Nm"]) == pytest.approx(tpk, rel=0.011)
    assert num(r["rated_speed_rpm"]) == pytest.approx(n, rel=0.011)
    assert num(r["max_speed_rpm"]) == pytest.approx(nmax, rel=0.011)
    assert num(r["rotor_inertia_kgm2"]) == pytest.approx(j, rel=0.011)


def test_1ft7044_carries_the_brake_free_inertia_and_says_so() -> None:
    r = next(r for r in AC if r["id"] == "1FT7044-5AK7")
    assert num(r["rotor_inertia_kgm2"]) == pytest.approx(5.43e-4)  # Siemens Table 4-8, not the 6.3 with brake
    assert "5.43" in r["notes"]


# ---------------------------------------------------------------------------------- the built database


def test_database_holds_every_shipped_row_in_si(use_data_dir: Path) -> None:
    m = catalog.motors()
    # the vendor-sourced family files (motors_<vendor>_<family>.csv) add their rows to the AC servos
    family = sum(len(load(f.filename)) for f in SHIPPED_FILES
                 if f.table.name == "motor" and f.filename not in ("motors_ac_servo.csv", "motors_small_dc.csv"))
    assert family >= 4
    assert len(m) == 297 + 298 + family
    assert len(catalog.motors(kind="ac_servo")) == 297 + family
    assert len(catalog.gearboxes(kind="servo_gearbox")) == 713 + 68 + sum(map(len, TRACED_GB.values()))
    assert len(catalog.gearboxes(kind="small_gearhead")) == 300
    # data/drives_servo.csv (65 rows) plus the vendor-sourced drive family files (drives_<vendor>_<family>.csv)
    assert len(catalog.drives()) == 65 + family_drive_rows()
    row = catalog.get("HG-KR43")
    assert row["rated_speed_rad_s"] == pytest.approx(3000 * RPM)
    assert row["max_speed_rad_s"] == pytest.approx(6000 * RPM)
    assert row["rotor_inertia_kgm2"] == pytest.approx(0.371e-4)
    assert row["flange_m"] == pytest.approx(0.060)
    assert row["origin"] == "builtin"
    assert row["source"].startswith("urchacha/gearbox-configurator@a616618")


def test_database_converts_gearbox_angles_and_stiffness(use_data_dir: Path) -> None:
    g = catalog.get("GPB042-L1-i3")
    arcmin = math.pi / (180 * 60)
    assert g["backlash_rad"] == pytest.approx(5 * arcmin)
    assert g["torsional_stiffness_Nm_per_rad"] == pytest.approx(3 / arcmin)
    assert g["rated_input_speed_rad_s"] == pytest.approx(5000 * RPM)
    assert g["type"] == "planetary"
    assert g["model"] == "GPB042-L1"
    assert g["right_angle"] == 0
    assert catalog.get("GPBR090-L2-i200")["right_angle"] == 1


def test_derived_values_are_flagged_in_the_database(use_data_dir: Path) -> None:
    ac = catalog.motors(kind="ac_servo")
    assert int(ac.approx_rated.sum()) == 24
    assert set(ac.vendor[ac.approx_rated]) == {"FANUC"}
    small = catalog.get("ECXZ06M1VF44N1IL1D659A")
    assert small["derived"] == ["stall_torque", "rated_torque", "rated_speed"]
    no_nominal = catalog.get("G40_KV210")  # T-motor: no I_nom, so no nominal values to derive
    assert no_nominal["derived"] == ["stall_torque"]
    assert no_nominal["rated_torque_Nm"] is None


def test_data_version_is_documented() -> None:
    sources = resources.files("drivetrain.catalog").joinpath("data", "SOURCES.md").read_text(encoding="utf-8")
    assert catalog.DATA_VERSION in sources
    for commit in ("a616618b206f66391d37f0485a3f89cb9b93a427", "215caccec6e05a58fdcdce14956d658853bf5128"):
        assert commit in sources


# ---------------------------------------------------------------------------------- gearbox spot checks

# Values as printed on the page each row cites (source_url), checked cell by cell:
# (row id, column, printed value, page).
_AG2250 = "https://infosys.beckhoff.com/content/1033/ag2250_ba/"
_AG2400 = "https://infosys.beckhoff.com/content/1033/ag2400_ba/"
_AG3400 = "https://infosys.beckhoff.com/content/1033/ag3400_ba/"
GEARBOX_SPOT = [
    # Beckhoff AG2250, "PLE080 technical data", Mechanical data, 1-stage
    ("AG2250-PLE080-i4", "rated_output_torque_Nm", 115, _AG2250 + "8411886091.html"),
    ("AG2250-PLE080-i4", "max_output_torque_Nm", 184, _AG2250 + "8411886091.html"),
    ("AG2250-PLE080-i7", "emergency_stop_torque_Nm", 178, _AG2250 + "8411886091.html"),
    ("AG2250-PLE080-i4", "rated_input_speed_rpm", 3900, _AG2250 + "8411886091.html"),
    ("AG2250-PLE080-i4", "max_input_speed_rpm", 7000, _AG2250 + "8411886091.html"),
    ("AG2250-PLE080-i4", "max_radial_load_N", 1600, _AG2250 + "8411886091.html"),
    ("AG2250-PLE160-i8", "rated_input_speed_rpm", 2200, _AG2250 + "8412002827.html"),
    ("AG2250-PLE060-i5", "max_output_torque_Nm", 64, _AG2250 + "8411826955.html"),
    # Beckhoff AG2400, "TP010 MF", Mechanical data, 1-stage
    ("AG2400-TP010-MF-i5", "rated_output_torque_Nm", 81, _AG2400 + "8995369483.html"),
    ("AG2400-TP010-MF-i8", "max_output_torque_Nm", 126, _AG2400 + "8995369483.html"),
    ("AG2400-TP010-MF-i7", "emergency_stop_torque_Nm", 251, _AG2400 + "8995369483.html"),
    ("AG2400-TP010-MF-i4", "rated_input_speed_rpm", 2600, _AG2400 + "8995369483.html"),
    ("AG2400-TP010-MF-i4", "max_input_speed_rpm", 7500, _AG2400 + "8995369483.html"),
    ("AG2400-TP010-MF-i4", "inertia_input_kgm2", 2.32e-4, _AG2400 + "8995369483.html"),  # 24 mm hub
    ("AG2400-TP010-MF-i4", "input_bore_max_mm", 24, _AG2400 + "8995369483.html"),
    ("AG2400-TP500-MF-i5", "max_output_torque_Nm", 7200, _AG2400 + "8996075403.html"),
    ("AG2400-TP050-MF-i10", "torsional_stiffness_Nm_per_arcmin", 123, _AG2400 + "8995561355.html"),
    # Beckhoff AG3400, "NPT025 MF", Mechanical data, 1-stage
    ("AG3400-NPT025-MF-i5", "rated_output_torque_Nm", 50, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i5", "max_output_torque_Nm", 100, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i5", "emergency_stop_torque_Nm", 190, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i10", "rated_input_speed_rpm", 3900, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i10", "max_input_speed_rpm", 7000, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i3", "input_bore_min_mm", 14, _AG3400 + "9187803147.html"),
    ("AG3400-NPT025-MF-i3", "max_axial_load_N", 1900, _AG3400 + "9187803147.html"),
    ("AG3400-NPT005-MF-i4", "rated_output_torque_Nm", 5.1, _AG3400 + "9187662731.html"),
    # G+ drawing sheets (GIGA Precision), specification table and title block
    ("GPB042-L1-i5", "rated_output_torque_Nm", 22, "GPB042-L1-(8-30-45-M3).PDF"),
    ("GPB042-L1-i5", "input_bore_max_mm", 8, "GPB042-L1-(8-30-45-M3).PDF"),
    ("GPB042-L1-i5", "input_pilot_mm", 30, "GPB042-L1-(8-30-45-M3).PDF"),
    ("GPB060-L1-i5", "input_bore_min_mm", 8, "GPB060-L1-(8-38.1-47.14-M4).PDF"),
    ("GPB060-L1-i5", "input_bore_max_mm", 14, "GPB060-L1-(14-50-70-M4).PDF"),
    ("GPB180-L2-i20", "rated_input_speed_rpm", 2000, "GPB180-L2-(42-114.3-200-M12).PDF"),
    ("GPB180-L2-i20", "max_input_speed_rpm", 4000, "GPB180-L2-(42-114.3-200-M12).PDF"),
    ("GPD255-L2-i25", "rated_output_torque_Nm", 1700, "GPD255-L2-(42-114.3-200-M12).PDF"),
    ("GPD255-L2-i25", "emergency_stop_torque_Nm", 5100, "GPD255-L2-(42-114.3-200-M12).PDF"),  # 3 x rated
    ("GPDR090-L2-i50", "rated_output_torque_Nm", 160, "GPDR090-L2-(19-70-90-M5).PDF"),
]
SERVO_ROWS = {r["id"]: r for rows in SERVO_GEARBOXES.values() for r in rows}


@pytest.mark.parametrize(("rid", "column", "printed", "page"), GEARBOX_SPOT)
def test_gearbox_values_match_the_page_they_cite(rid: str, column: str, printed: float, page: str) -> None:
    r = SERVO_ROWS[rid]
    assert num(r[column]) == pytest.approx(printed, rel=1e-9)
    assert page in r["source_url"]


def test_at_least_five_spot_checks_per_new_family() -> None:
    per_family = collections.Counter(rid.split("-")[0] for rid, *_ in GEARBOX_SPOT)
    assert min(per_family["AG2250"], per_family["AG2400"], per_family["AG3400"]) >= 5


def test_gplus_rows_stay_flagged_with_the_reason_and_have_no_invented_t2b() -> None:
    assert {r["verified"] for r in PLANETARY} == {"no"}
    assert not [r["id"] for r in PLANETARY if r["max_output_torque_Nm"]]  # T2B is printed nowhere we found
    with_drawing = [r for r in PLANETARY if r["source_url"]]
    assert len(with_drawing) == 527
    assert all(r["input_bore_min_mm"] and r["input_adapters"] for r in with_drawing)
    assert all("no vendor document found" in r["notes"] for r in PLANETARY if not r["source_url"])


def test_beckhoff_rows_are_verified_and_carry_the_acceleration_torque() -> None:
    rows = [r for rows in BECKHOFF.values() for r in rows]
    assert {r["verified"] for r in rows} == {"yes"}
    assert all(r["max_output_torque_Nm"] and r["rated_input_speed_rpm"] and r["max_input_speed_rpm"] for r in rows)
    # PLE040's emergency-stop row has 5 cells for 6 ratios: left empty rather than guessed
    assert {r["id"] for r in rows if not r["emergency_stop_torque_Nm"]} == {
        f"AG2250-PLE040-i{i}" for i in (3, 4, 5, 7, 8, 10)}


def test_database_carries_the_gearbox_ratings_and_fit_data_in_si(use_data_dir: Path) -> None:
    g = catalog.get("AG2400-TP010-MF-i5")
    assert g["max_output_torque_Nm"] == pytest.approx(172)
    assert g["emergency_stop_torque_Nm"] == pytest.approx(250)
    assert g["rated_input_speed_rad_s"] == pytest.approx(2900 * RPM)
    assert g["max_input_speed_rad_s"] == pytest.approx(7500 * RPM)
    assert (g["input_bore_min_m"], g["input_bore_max_m"]) == pytest.approx((0.014, 0.024))
    assert g["verified"] == 1
    assert g["source_url"] == _AG2400 + "8995369483.html"
    assert g["model"] == "AG2400-TP010-MF"
    table = catalog.gearboxes(vendor="beckhoff")
    assert len(table) == 68 + sum(len(v) for k, v in TRACED_GB.items() if k.startswith("beckhoff_"))
    assert bool(table.verified.all())
    gplus = catalog.gearboxes(series="GPB")
    assert not bool(gplus.verified.any())
    assert bool(np.isnan(gplus.max_output_torque).all())
    i = list(gplus.ids).index("GPB042-L1-i5")
    assert gplus.input_bore_max[i] == pytest.approx(0.008)
    assert gplus.input_pilot[i] == pytest.approx(0.030)
