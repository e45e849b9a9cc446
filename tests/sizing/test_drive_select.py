"""Selection returns motor + drive: the drive post-pass (drivetrain.sizing.drive_select), catalog drives
by id, and the selected candidate's electrical and regen blocks in the table, JSON and report."""

from __future__ import annotations

import copy
import itertools
import json
import math
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from drivetrain import catalog, cli
from drivetrain.axis.electrical import DriveSpec, drive_data, electrical_from_catalog_row, shipped_electrical
from drivetrain.errors import InputError
from drivetrain.sizing.pipeline import size

Z_AXIS: dict[str, Any] = yaml.safe_load(textwrap.dedent("""\
    axis: Z lift
    efficiency_model: four_quadrant
    mechanism:
      type: ball_screw
      lead: 10 mm
      diameter: 20 mm
      length: 800 mm
      material: steel
      efficiency: 0.9
      incline: 90 deg
      load: {mass: 25 kg, counterweight: 0 kg, friction: 0.05, thrust: 0 N}
      screw: {root_diameter: 17.32 mm}  # HIWIN R20-10K3-FSC (examples/ball_screw.yaml): judged under unknown: fail
    profile:
      - {move: 200 mm, time: 0.5 s, accel: 0.1 s}
      - {dwell: 0.3 s}
      - {move: -200 mm, time: 0.5 s, accel: 0.1 s}
      - {dwell: 0.3 s, holding: brake}
    motor:
      select: {vendor: siemens, flange: 96 mm, gearbox: none}
    """))
PAIRED_MOTOR = "1FT7044-5AK7"
PAIRED_DRIVE = "6SL312x-xTE21-0AAx"


def axis(**changes: Any) -> dict[str, Any]:
    d = copy.deepcopy(Z_AXIS)
    d.update(changes)
    return d


# ---------------------------------------------------------------------------------- shipped data


@pytest.fixture(scope="module")
def siemens() -> Any:
    return size(axis())


def test_pairing_table_names_the_drive_and_its_current_checks_pass(siemens: Any) -> None:
    cand = next(c for c in siemens.candidates if c.motor == PAIRED_MOTOR)
    d = cand.drive
    assert d.basis == "vendor pairing table" and list(d.candidates) == [PAIRED_DRIVE]
    # Siemens 1FT7 configuration manual Table 4-8 p. 90: the recommended Motor Module, 9 A / 18 A
    assert d.id == PAIRED_DRIVE and d.continuous_current_A == 9.0 and d.peak_current_A == 18.0
    assert d.status == "ok" and d.ok is True
    checks = {c["name"]: c for c in d.checks}
    assert checks["drive_rms_current"]["required"] == pytest.approx(d.motor_rms_current_A)
    # I = T / Kt below the rated torque, more above it (saturation): never less than T_rms / Kt
    kt = 0.88  # Table 4-8, k_T
    assert d.motor_rms_current_A >= cand.rms_torque_Nm / kt * (1 - 1e-9)
    assert d.motor_rms_current_A <= cand.rms_torque_Nm / kt * 1.2


def test_motor_without_torque_constant_leaves_the_drive_unknown_and_says_why(siemens: Any) -> None:
    for cand in siemens.candidates:
        if cand.motor == PAIRED_MOTOR:
            continue
        d = cand.drive
        assert d.status == "unknown" and d.ok is None
        assert "torque constant" in d.reason and cand.motor in d.reason


def test_drives_without_current_ratings_answer_unknown() -> None:
    """TECO JSMA-P motors have their currents and k_T; the JSDG2S drives of the catalog only their regen data."""
    r = size(axis(motor={"select": {"vendor": "teco", "gearbox": "none"}}))
    assert r.candidates, "the TECO JSMA-P motors are candidates"
    for cand in r.candidates:
        assert catalog.get(cand.motor)["torque_constant_Nm_per_A"] is not None
        d = cand.drive
        assert d.status == "unknown" and "current ratings" in d.reason
        assert d.motor_rms_current_A > 0 and d.candidates
        assert all(x.startswith("JSDG2S-") for x in d.candidates)


def test_sigma_7_motors_get_their_paired_servopack_with_its_currents_checked() -> None:
    """Every Sigma-7 candidate with currents is offered the SGD7S its pairing row names (drives_pairing.csv, the
    hdauto-chatbot transcription) and gets the drive's current checks, flagged as third-party."""
    r = size(axis(motor={"select": {"vendor": "yaskawa", "gearbox": "none"}}))
    pairs = catalog.drive_pairs()
    sigma7 = [c for c in r.candidates if catalog.get(c.motor)["series"].startswith("SGM7")
              and catalog.get(c.motor)["torque_constant_Nm_per_A"] is not None]
    assert sigma7, "the Sigma-7 motors with currents are among the candidates"
    for cand in sigma7:
        d = cand.drive
        assert d.basis == "vendor pairing table" and list(d.candidates) == pairs[cand.motor]
        assert d.status in ("ok", "fails") and d.id in pairs[cand.motor]
        assert {c["name"] for c in d.checks} >= {"drive_rms_current", "drive_peak_current"}
        assert d.unverified is True and "hdauto-chatbot" in d.unverified_reason
        if d.status == "ok":
            assert d.motor_rms_current_A <= d.continuous_current_A
            assert d.motor_peak_current_A <= d.peak_current_A


def test_shipped_electrical_merge_matches_the_table_reader() -> None:
    row = catalog.get(PAIRED_MOTOR)
    a, b = electrical_from_catalog_row(row), shipped_electrical(PAIRED_MOTOR)
    for key in ("kt", "ke", "resistance", "inductance", "pole_pairs", "rated_current", "stall_current",
                "peak_current", "thermal_time_constant", "rated_rise"):
        assert getattr(a, key) == pytest.approx(getattr(b, key)), key
    # Table 4-8 prints I_0 at 60 K and 100 K: the stall current read is the 100 K one
    assert a.rated_rise == 100.0 and a.stall_current == 5.7


def test_a_catalog_drive_by_id_is_checked_like_a_given_motor() -> None:
    r = size(axis(motor={"id": PAIRED_MOTOR}, drive={"id": PAIRED_DRIVE}))
    d = r.drive
    assert d.id == PAIRED_DRIVE and d.continuous_current_A == 9.0 and d.ok is True
    assert r.motor.electrical["winding_temperature_rise_K"] is not None


def test_a_catalog_drive_without_currents_is_an_input_error_naming_the_field(tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(InputError) as exc:
        drive_data(DriveSpec(id="MR-J4-60B4"))
    assert exc.value.field == "drive.continuous_current"
    path = tmp_path / "z.yaml"
    path.write_text(yaml.safe_dump(axis(motor={"id": PAIRED_MOTOR}, drive={"id": "MR-J4-60B4"})), encoding="utf-8")
    assert cli.main(["size", str(path)]) == 2
    assert "drive.continuous_current" in capsys.readouterr().err
    # values given beside the id complete it (MR-J4-_B manual 11 (b) p. 11-13: 12 J capacitor charging; 400 V class)
    d = drive_data(DriveSpec(id="MR-J4-60B4", continuous_current="1.5 A", peak_current="4.5 A"))
    assert d.absorbable_energy == pytest.approx(12.0) and d.supply_voltage == 400.0


def test_unknown_drive_id_without_currents_is_an_input_error() -> None:
    with pytest.raises(InputError) as exc:
        drive_data(DriveSpec(id="NO-SUCH-DRIVE"))
    assert exc.value.field == "drive.id"


# ---------------------------------------------------------------------------------- a user catalog

USER_MOTORS = """\
id,vendor,series,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],rotor_inertia [kg*cm^2],\
rated_power [W],voltage [V],torque_constant [N*m/A],back_emf [V*s],winding_resistance [ohm],\
winding_inductance [mH],pole_count,rated_current [A],stall_current [A],peak_current [A],\
thermal_time_constant [s],rated_winding_rise [K],source
TC-04,Testco,T,1.27,4.46,3000,6000,0.486,400,200,0.544,0.36,1.9,4.5,10,2.5,2.6,9.3,1200,100,test fixture
"""
USER_DRIVES = """\
id,vendor,continuous_current [A],peak_current [A],peak_time [s],voltage [V],absorbable_energy [J],\
min_resistance [ohm],regen_on_voltage [V],builtin_braking_resistor,braking_resistor [ohm],\
braking_resistor_average_power [W],source
TD-S,Testco,0.3,0.9,3,200,10,40,390,yes,50,12,test fixture
TD-M,Testco,1.6,4.8,3,200,10,40,390,yes,50,12,test fixture
TD-L,Testco,5,15,3,200,20,30,390,yes,40,30,test fixture
TD-400,Testco,1.6,4.8,3,400,10,40,780,yes,50,12,test fixture
"""


def import_catalog(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, motors: str, drives: str = USER_DRIVES) -> None:
    """A user catalog in a fresh data folder with these motor and drive rows."""
    from drivetrain.catalog import db

    monkeypatch.setenv(db.ENV_DATA_DIR, str(tmp_path / "data"))
    for name, text in (("m.csv", motors), ("d.csv", drives)):
        (tmp_path / name).write_text(text, encoding="utf-8")
        catalog.import_file(tmp_path / name)


@pytest.fixture()
def user_catalog(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import_catalog(tmp_path, monkeypatch, USER_MOTORS)


def test_selection_answers_motor_drive_resistor_and_winding_temperature(user_catalog: None) -> None:
    r = size(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}))
    sel = r.selection.selected
    assert sel.motor == "TC-04"
    d = sel.drive
    # the smallest passing drive of the vendor at 200 V: TD-S is too small, TD-400 is another voltage
    assert d.status == "ok" and d.id == "TD-M" and d.basis == "vendor and supply voltage"
    assert "TD-400" not in d.candidates and d.candidates[0] == "TD-S"
    assert {c["name"] for c in d.checks} >= {"drive_rms_current", "drive_peak_current", "drive_i2t"}
    elec = sel.electrical
    assert elec["envelope_source"] == "electrical" and elec["supply_voltage_V"] == 200.0
    assert elec["winding_temperature_rise_K"] is not None and 0 < elec["winding_temperature_rise_K"] < 100
    assert elec["rms_current_A"] == pytest.approx(d.motor_rms_current_A)
    rg = sel.regen
    assert rg.capacitor_basis == "published" and rg.resistor_min_ohm == 40.0
    assert rg.energy_per_cycle_J <= rg.shaft_energy_per_cycle_J + 1e-9
    assert isinstance(rg.builtin_resistor_sufficient, bool)
    # every listed candidate carries a drive block
    assert all(c.drive is not None for c in r.candidates)


def test_selection_drive_in_json_and_table(user_catalog: None, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "z.yaml"
    path.write_text(yaml.safe_dump(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}})),
                    encoding="utf-8")
    assert cli.main(["size", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["selection"]["selected"]["drive"]["id"] == "TD-M"
    assert out["candidates"][0]["drive"]["id"] == "TD-M"
    assert out["selection"]["selected"]["regen"]["resistor_peak_power_W"] >= 0
    assert cli.main(["size", str(path)]) == 0
    text = capsys.readouterr().out
    assert "TD-M" in text and "winding temperature rise" in text and "braking resistor" in text


def test_given_drive_is_checked_for_every_candidate(user_catalog: None) -> None:
    r = size(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}, drive={"id": "TD-S"}))
    d = r.selection.selected.drive
    assert d.id == "TD-S" and d.basis == "given in the axis file"
    assert d.status == "fails" and not all(c["ok"] for c in d.checks)


def test_drive_pick_is_monotone_in_load(user_catalog: None) -> None:
    """A heavier load never gets a smaller drive (property over a few masses)."""
    sizes = []
    for mass in (5, 15, 25, 35):
        a = axis(motor={"select": {"vendor": "testco", "gearbox": "none", "max_inertia_ratio": 100}})
        a["mechanism"]["load"]["mass"] = f"{mass} kg"
        pick = size(a).selection.selected
        d = None if pick is None else pick.drive
        if d and d.status == "ok":
            sizes.append(d.continuous_current_A)
    assert sizes and all(b >= a for a, b in itertools.pairwise(sizes))
    assert not math.isnan(float(np.sum(sizes)))


def test_report_shows_the_drive_regen_plot_and_supply_curve(user_catalog: None, tmp_path: Path) -> None:
    from drivetrain.report import write_report
    from drivetrain.report.model import build_report

    r = size(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}))
    m = build_report(r)
    assert m.regen is not None and m.electrical is not None
    names = [t.name for p in m.regen.panels for t in p.traces]
    assert "to the braking resistor (cumulative)" in names
    # the plot's resistor energy ends at the regen block's figure (same model, same cycle)
    res = next(t for p in m.regen.panels for t in p.traces if t.name.startswith("to the braking resistor"))
    assert float(res.y[-1]) == pytest.approx(r.selection.selected.regen.resistor_energy_per_cycle_J,
                                             rel=1e-6, abs=1e-9)
    assert any("DC bus" in t.name for p in m.speed_torque.panels for t in p.traces)
    labels = [row[0].text for row in m.electrical.rows]
    assert "Drive" in labels and "Braking resistor: energy per cycle" in labels
    write_report(r, tmp_path / "r.html")
    write_report(r, tmp_path / "r.pdf")
    html = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "Drive and regeneration" in html and "TD-M" in html
    assert (tmp_path / "r.pdf").stat().st_size > 10_000


def test_web_payload_carries_drive_electrical_and_regen(user_catalog: None) -> None:
    from drivetrain.web.payload import encode, size_payload

    p = size_payload(axis(motor={"select": {"vendor": "testco", "gearbox": "none"}}))
    e = p["electrical"]
    assert e["drive"]["id"] == "TD-M" and e["electrical"]["winding_temperature_rise_K"] is not None
    assert "events" not in e["regen"] and "curve" not in e["electrical"]
    assert p["result"]["candidates"][0]["drive"]["id"] == "TD-M"
    assert json.loads(encode(p))["electrical"]["regen"]["resistor_energy_per_cycle_J"] >= 0
    given = size_payload(axis(motor={"id": PAIRED_MOTOR}, drive={"id": PAIRED_DRIVE}))
    assert given["electrical"]["drive"]["id"] == PAIRED_DRIVE


RESULTS_JS = Path(__file__).resolve().parents[2] / "src/drivetrain/web/static/results.js"


def run_results_js(body: str) -> str:
    """Run ``body`` in node with ``@RESULTS@`` standing for the imported results.js (skip when node is absent);
    its stdout."""
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    module = f"await import({json.dumps(RESULTS_JS.as_uri())})"
    script = "globalThis.Node = class {};\n" + body.replace("@RESULTS@", module)
    out = subprocess.run([node, "--input-type=module", "-e", script], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_results_panel_renders_the_electrical_block() -> None:
    """results.js: the drive, winding and regen rows appear (node, when available)."""
    out = run_results_js("""
      globalThis.document = { createElement: (t) => ({ tag: t, children: [], attrs: {},
        setAttribute(k, v) { this.attrs[k] = v; }, append(...c) { this.children.push(...c); },
        appendChild(c) { this.children.push(c); return c; }, set textContent(v) { this.text = v; },
        get textContent() {
          return this.text ?? this.children.map((c) => typeof c === "string" ? c : c.textContent).join(""); },
        replaceChildren(...c) { this.children = c; }, addEventListener() {}, classList: { add() {} } }),
        createTextNode: (t) => t };
      const R = @RESULTS@;
      const parts = R.electricalParts({ drive: { id: "TD-M", status: "ok", basis: "vendor", checks: [] },
        electrical: { envelope_source: "electrical", rms_current_A: 1, peak_current_A: 2, checks: [],
                       winding_temperature_rise_K: 12 },
        regen: { energy_per_cycle_J: 5, capacitor_absorbed_J: 1, resistor_energy_per_cycle_J: 4,
                 resistor_peak_power_W: 100, resistor_average_power_W: 2, builtin_resistor_sufficient: true } });
      console.log(JSON.stringify(parts.length), parts[0].textContent);
    """)
    assert out.startswith("1") and "TD-M" in out and "braking resistor" in out


def test_a_vendor_without_drives_answers_none() -> None:
    r = size(axis(motor={"select": {"vendor": "panasonic", "gearbox": "none"}}))
    for cand in r.candidates:
        d = cand.drive
        assert d.status in ("none", "unknown") and d.ok is None and list(d.candidates) == []


# ------------------------------------------------------------- the selected motor needs an orderable drive

# TC-02 passes every mechanical check but draws ~50 A at its peak (k_T 0.06 N m/A): no Testco drive feeds it.
# TC-08 is larger (ranked after it) and runs on TD-M. TC-NK (another vendor) has no torque constant.
WALK_MOTORS = USER_MOTORS.split("TC-04")[0] + """\
TC-02,Testco,T,1.27,4.46,3000,6000,0.486,400,200,0.06,0.04,0.02,0.05,10,21,22,80,1200,100,test fixture
TC-08,Testco,T,2.4,7.1,3000,6000,0.9,750,200,0.6,0.4,1.2,3.0,10,4,4.2,12,1500,100,test fixture
TC-NK,Unco,U,1.27,4.46,3000,6000,0.486,400,200,,,,,,,,,,,test fixture
"""


@pytest.fixture()
def walk_catalog(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import_catalog(tmp_path, monkeypatch, WALK_MOTORS)


def test_a_motor_no_drive_can_feed_is_passed_over_for_the_next(walk_catalog: None) -> None:
    r = size(axis(motor={"select": {"vendor": "testco", "gearbox": "none", "max_inertia_ratio": 100}}))
    ranked = [c.motor for c in r.candidates if c.rank is not None]
    assert ranked[0] == "TC-02"  # the smallest passes mechanically ...
    assert r.candidates[0].drive.status == "fails"  # ... but the largest Testco drive cannot feed it
    sel = r.selection
    assert sel.selected.motor == "TC-08" and sel.selected.drive.status == "ok"
    assert sel.selected.drive.id == "TD-M"  # k_T 0.6: about 1 A rms, 4 A peak
    assert [p.motor for p in sel.drive_passed_over] == ["TC-02"]
    why = sel.drive_passed_over[0].reason
    assert "TD-L" in why and "drive_peak_current" in why
    # the next smaller motor is the one passed over, with the drive as its reason
    assert sel.next_smaller.motor == "TC-02" and sel.next_smaller.failed.startswith("drive: ")
    assert sel.optimal_ratio.motor == "TC-08"
    assert r.ok


def test_unknown_fail_passes_over_a_motor_whose_drive_cannot_be_checked(walk_catalog: None) -> None:
    both = {"vendor": ["testco", "unco"], "gearbox": "none", "max_inertia_ratio": 100}
    flag = size(axis(motor={"select": both}))
    # unknown: fail would also reject every motor on its brake (the fixture catalog has no brake data, and
    # the Z axis needs one): the load counterbalanced and held by the motor, the drives alone decide
    balanced = axis(motor={"select": {**both, "unknown": "fail"}})
    balanced["mechanism"] = {**balanced["mechanism"], "load": {**balanced["mechanism"]["load"],
                                                             "counterweight": "25 kg"}}
    balanced["profile"] = [{k: v for k, v in p.items() if k != "holding"} for p in balanced["profile"]]
    strict = size(balanced)
    # flag: TC-NK (as small as TC-02) is an answer, its drive marked unknown; TC-02's drive fails either way
    assert flag.selection.selected.motor == "TC-NK" and flag.selection.selected.drive.status == "unknown"
    assert flag.ok
    assert strict.selection.selected.motor == "TC-08" and strict.selection.selected.drive.status == "ok"
    over = {p.motor: p.drive_status for p in strict.selection.drive_passed_over}
    assert over == {"TC-NK": "unknown", "TC-02": "fails"} and strict.ok


def test_no_orderable_drive_fails_the_answer_and_says_why(walk_catalog: None, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    a = axis(motor={"select": {"vendor": "testco", "gearbox": "none", "max_inertia_ratio": 100}}, drive={"id": "TD-S"})
    r = size(a)
    assert not r.ok and "none of the" in r.selection.drive_advice
    assert r.selection.selected.drive.status == "fails"  # the best-ranked, with the checks that fail
    path = tmp_path / "z.yaml"
    path.write_text(yaml.safe_dump(a), encoding="utf-8")
    assert cli.main(["size", str(path)]) == 1
    assert "not orderable" in capsys.readouterr().out
    from drivetrain.report import write_report

    write_report(r, tmp_path / "r.html")
    html = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "No passing motor has a drive that can be ordered" in html and "Not orderable" in html


def test_results_verdict_fails_a_selection_without_an_orderable_drive() -> None:
    """results.js: the banner's verdict follows selection.drive_advice (node, when available)."""
    out = run_results_js("""
      const R = @RESULTS@;
      const sel = { selected: { motor: "TC-02", checks: [] }, passing: 2, evaluated: 3 };
      const ok = R.verdict({ selection: sel });
      const bad = R.verdict({ selection: { ...sel, drive_advice: "none of the 2 ..." } });
      console.log(JSON.stringify([ok.ok, bad.ok, bad.failed]));
    """)
    assert json.loads(out) == [True, False, "not orderable: none of the 2 ..."]


def test_each_gantry_share_obeys_the_drive_rule(walk_catalog: None) -> None:
    """A gantry's motors are each sized for their share through the sizing pipeline: the share's selected
    motor has an orderable drive, as ``size`` of the whole axis does (TC-02, the smallest, draws more
    current than any Testco drive gives for its share)."""
    from drivetrain.machine.result import size_machine

    select = {"select": {"vendor": "testco", "gearbox": "none", "max_inertia_ratio": 100}}
    heavy = axis(motor=select)
    heavy["mechanism"]["load"]["mass"] = "50 kg"  # each motor carries 25 kg, the load of the tests above
    gantry = {"name": "Y", "motors": 2, "split": ["50 %", "50 %"], "axis": heavy}
    m = size_machine({"version": 1, "machine": "gantry", "cycle_time": "2 s",
                      "supply": {"voltage": "200 V", "phases": 3}, "axes": [gantry]})
    shares = m.axes["Y"].results
    assert len(shares) == 2
    for share in shares:
        assert share.selection is not None
        assert next(c.motor for c in share.candidates if c.rank is not None) == "TC-02"
        assert share.selection.selected.motor == "TC-08"
        assert share.selection.selected.drive.status == "ok"
        assert [p.motor for p in share.selection.drive_passed_over] == ["TC-02"]
        assert share.ok


# ---------------------------------------------------------------------------------- by vendor pairing


class _Cycle:
    """A motor-shaft cycle of given torques (equal weights): what the pairing rule reads of a DutyCycle."""

    def __init__(self, torque: list[float]) -> None:
        self._t = np.asarray(torque, dtype=float)
        self.weights = np.full(self._t.size, 1.0)
        self.period = float(self._t.size)

    def motor_torque(self, inertia: float) -> np.ndarray:
        return self._t


def test_roll_example_answers_its_motor_with_the_paired_drive_by_pairing() -> None:
    """examples/roll.yaml from the Mitsubishi motors selects an HG-KR, which has no torque constant: the MR-J4
    amplifier the pairing table names for it (drives_pairing.csv, a third-party transcription) is judged by
    the pairing, and flagged. (The whole catalog now answers a direct drive whose currents are known.)"""
    d0 = yaml.safe_load((Path(__file__).parents[2] / "examples" / "roll.yaml").read_text(encoding="utf-8"))
    d0["motor"]["select"] = {"objective": "smallest", "vendor": "Mitsubishi Electric"}
    r = size(d0)
    pick = r.selection.selected
    motor = pick.motor
    assert motor.startswith("HG-KR")
    d = pick.drive
    assert catalog.get(motor)["torque_constant_Nm_per_A"] is None
    assert d.status == "ok" and d.ok is True and d.judged_by == "vendor pairing"
    assert d.id.startswith("MR-J4-") and list(d.candidates) == catalog.drive_pairs()[motor]
    assert d.unverified is True and "hdauto-chatbot" in d.unverified_reason
    checks = {c["name"]: c for c in d.checks}
    row = catalog.get(motor)
    assert checks["drive_continuous_by_pairing"]["available"] == pytest.approx(row["rated_torque_Nm"])
    assert checks["drive_peak_by_pairing"]["available"] == pytest.approx(row["peak_torque_Nm"])
    assert all(c["ok"] for c in d.checks)


def test_pairing_covers_only_the_motor_ratings() -> None:
    """Within the rated (RMS) and peak torque the paired drive passes; beyond either the pairing says nothing."""
    from drivetrain.sizing.drive_select import pick_drive

    rated, peak = 0.16, 0.56  # HG-KR053 (motors_ac_servo.csv)
    light = _Cycle([0.1, -0.1, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0])  # RMS 0.117 N m, peak 0.3 N m
    within, _ = pick_drive(light, 0.0, "HG-KR053", "Mitsubishi Electric", 200.0, rated, peak)  # type: ignore[arg-type]
    assert within.status == "ok" and within.judged_by == "vendor pairing" and within.id == "MR-J4-10B"
    hot, drive = pick_drive(_Cycle([0.2, -0.2, 0.2, 0.2]), 0.0, "HG-KR053", "Mitsubishi Electric", 200.0,  # type: ignore[arg-type]
                            rated, peak)
    assert hot.status == "unknown" and hot.ok is None and "beyond what the pairing states" in hot.reason
    assert {c["name"]: c["ok"] for c in hot.checks} == {"drive_continuous_by_pairing": False,
                                                          "drive_peak_by_pairing": True}
    assert drive is not None and drive.name == "MR-J4-10B"
    over, _ = pick_drive(_Cycle([0.1, 0.6, 0.0, 0.0]), 0.0, "HG-KR053", "Mitsubishi Electric", 200.0,  # type: ignore[arg-type]
                         rated, peak)
    assert over.status == "unknown"


def test_a_vendor_pairing_is_not_flagged_and_no_pairing_stays_unknown(monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.sizing.drive_select import pick_drive

    sources = dict(catalog.drive_pair_sources())
    sources[("HG-KR053", "MR-J4-10B")] = {"source": "vendor table", "source_url": "", "verified": True}
    monkeypatch.setattr(catalog, "drive_pair_sources", lambda: sources)
    block, _ = pick_drive(_Cycle([0.1, 0.0]), 0.0, "HG-KR053", "Mitsubishi Electric", 200.0, 0.16, 0.56)  # type: ignore[arg-type]
    assert block.status == "ok" and block.unverified is False
    # without a pairing entry the MR-J4 drives are offered by vendor and voltage: no torque constant, unknown
    monkeypatch.setattr(catalog, "drive_pairs", lambda: {})
    block, _ = pick_drive(_Cycle([0.1, 0.0]), 0.0, "HG-KR053", "Mitsubishi Electric", 200.0, 0.16, 0.56)  # type: ignore[arg-type]
    assert block.status == "unknown" and block.judged_by is None and "torque constant" in block.reason


def test_shipped_pairings_say_whether_they_are_the_vendors() -> None:
    sources = catalog.drive_pair_sources()
    assert sources[("1FT7044-5AK7", "6SL312x-xTE21-0AAx")]["verified"] is True
    third = [k for k, v in sources.items() if not v["verified"]]
    assert len(third) == 72 and all("hdauto-chatbot" in sources[k]["source"] for k in third)
    assert {k for k in sources} == {(m, d) for m, ds in catalog.drive_pairs().items() for d in ds}
