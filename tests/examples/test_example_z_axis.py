"""examples/z_axis.yaml: a vertical axis whose catalog selection answers motor + drive (issue #13's
done-when) from the shipped data, end to end: the CLI table, the JSON, the report and the web payload.

``unknown: fail`` makes the selection pass over the smaller motors whose drive cannot be checked, and
say so. On the file's 400 V supply the 200 V and 100 V class motors are passed over by the
voltage-class check (docs/checks.md, "Voltage class"), and the answer is the 400 V Siemens chain: the
one whose every electrical check the catalog can judge from vendor pages, the Siemens 1FT7044-5AK7
(Kt, currents, R, L, Ke, thermal data from the S120 1FT7 configuration manual 01/2009, Table 4-8,
p. 90) with the S120 Motor Module that table recommends (9 A / 18 A). The same axis restricted to
Siemens (``SIEMENS``) answers it too, and the tests of the full electrical answer use that variant.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from drivetrain import cli
from drivetrain.sizing.pipeline import size

EXAMPLE = Path(__file__).parents[2] / "examples" / "z_axis.yaml"
SIEMENS_TEXT = EXAMPLE.read_text(encoding="utf-8").replace(
    "select: {unknown: fail, gearbox: none}", "select: {unknown: fail, gearbox: none, vendor: siemens}")
assert "vendor: siemens" in SIEMENS_TEXT


@pytest.fixture(scope="module")
def siemens(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("z") / "z_siemens.yaml"
    path.write_text(SIEMENS_TEXT, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def result(siemens: Path):  # type: ignore[no-untyped-def]
    return size(siemens)


def test_the_shipped_example_answers_a_400_v_chain_on_its_400_v_supply() -> None:
    """The file states a 400 V supply: every 200 V (and 100 V) class motor is passed over for its voltage class,
    with the reason, and motors of unknown class too (``unknown: fail``); the answer is the 400 V Siemens chain."""
    r = size(EXAMPLE)
    assert r.ok
    sel = r.selection.selected
    assert sel.motor == "1FT7044-5AK7" and sel.drive.status == "ok"
    assert sel.voltage_class["status"] == "pass" and sel.voltage_class["required"] == 400.0
    over = {p.motor: p.reason for p in r.selection.drive_passed_over}
    assert over["SGM7J-04A"].startswith("voltage_class: a 200 V class motor on a 400 V supply")
    assert over["SGMP-03B"].startswith("voltage_class: a 100 V class motor on a 400 V supply")
    assert "voltage class is not known" in over["APM-FC04A"]


def test_a_200_v_motor_named_on_a_400_v_supply_is_passed_over_by_its_class(tmp_path: Path) -> None:
    """The issue's case: supply_voltage 400 V selected SGM7G-03A (a 200 V motor) and offered 200 V SGD7S drives."""
    text = EXAMPLE.read_text(encoding="utf-8").replace(
        "select: {unknown: fail, gearbox: none}", "select: {unknown: fail, gearbox: none, vendor: yaskawa}")
    path = tmp_path / "z_yaskawa.yaml"
    path.write_text(text, encoding="utf-8")
    r = size(path)
    assert not r.ok  # every shipped Yaskawa servo is a 100 V or 200 V class motor
    assert all(p.reason.startswith("voltage_class:") for p in r.selection.drive_passed_over)
    assert r.selection.drive_advice is not None


def test_the_answer_is_a_motor_and_its_drive_with_every_electrical_check(result) -> None:  # type: ignore[no-untyped-def]
    assert result.ok
    sel = result.selection.selected
    assert sel.motor == "1FT7044-5AK7"
    d = sel.drive
    assert d.status == "ok" and d.id == "6SL312x-xTE21-0AAx" and d.basis == "vendor pairing table"
    assert d.continuous_current_A == 9.0 and d.peak_current_A == 18.0
    assert {c["name"] for c in d.checks} == {"drive_rms_current", "drive_peak_current"}
    e = sel.electrical
    assert e["supply_voltage_V"] == 400.0 and e["dc_bus_voltage_V"] == pytest.approx(400.0 * math.sqrt(2))
    assert e["envelope_source"] == "electrical"  # Ke, R, L at the machine's 400 V supply
    assert 0 < e["rms_current_A"] < e["peak_current_A"] < 18.0
    assert e["rms_current_A"] == pytest.approx(d.motor_rms_current_A)
    assert 0 < e["winding_temperature_rise_K"] < e["winding_allowed_rise_K"]
    names = {c["name"] for c in e["checks"]}
    assert {"motor_rms_current", "motor_peak_current", "peak_torque_at_supply_voltage",
            "winding_temperature_rise"} <= names
    rg = sel.regen
    # the load is lowered every cycle: energy flows back, and none of it is created
    assert 0 < rg.energy_per_cycle_J <= rg.shaft_energy_per_cycle_J
    assert rg.resistor_energy_per_cycle_J == pytest.approx(rg.energy_per_cycle_J - rg.capacitor_absorbed_J)
    assert rg.resistor_peak_power_W > rg.resistor_average_power_W > 0


def test_the_motors_passed_over_are_named_with_the_reason(result) -> None:  # type: ignore[no-untyped-def]
    sel = result.selection
    over = sel.drive_passed_over
    assert sel.drive_passed_over_count >= len(over) > 0
    assert all(p.drive_status in ("unknown", "none") and p.reason for p in over)
    assert sel.next_smaller.failed.startswith("drive: ")


def test_table_json_and_exit_code(siemens: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["size", str(siemens)]) == 0
    text = capsys.readouterr().out
    for words in ("selected: 1FT7044-5AK7", "passed over for its drive", "supply 400 V", "envelope: electrical",
                  "drive 6SL312x-xTE21-0AAx: OK", "braking resistor", "winding temperature rise"):
        assert words in text
    assert cli.main(["size", str(siemens), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["selection"]["selected"]["drive"]["status"] == "ok"


def test_report_has_the_drive_the_regen_plot_and_the_supply_plane(result, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    from drivetrain.report import write_report
    from drivetrain.report.model import build_report

    m = build_report(result)
    labels = [row[0].text for row in m.electrical.rows]
    assert "Drive" in labels and "Braking resistor: energy per cycle" in labels
    assert any("DC bus" in t.name for p in m.speed_torque.panels for t in p.traces)
    write_report(result, tmp_path / "z.html")
    html = (tmp_path / "z.html").read_text(encoding="utf-8")
    assert "Drive and regeneration" in html and "6SL312x-xTE21-0AAx" in html


def test_web_payload_carries_the_drive() -> None:
    import yaml

    from drivetrain.web.payload import size_payload

    p = size_payload(yaml.safe_load(SIEMENS_TEXT))
    assert p["electrical"]["drive"]["id"] == "6SL312x-xTE21-0AAx"
    assert p["electrical"]["electrical"]["envelope_source"] == "electrical"


def test_a_motors_own_electrical_data_with_select_is_refused(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    text = EXAMPLE.read_text(encoding="utf-8").replace("  supply_voltage: 400 V", "  kt: 0.9 N*m/A")
    path = tmp_path / "bad.yaml"
    path.write_text(text, encoding="utf-8")
    assert cli.main(["size", str(path)]) == 2
    err = capsys.readouterr().err
    assert "motor" in err and "kt cannot go with select" in err and "Traceback" not in err


def test_without_the_supply_the_envelope_is_the_derived_one(tmp_path: Path) -> None:
    text = SIEMENS_TEXT.replace("  supply_voltage: 400 V\n", "")
    path = tmp_path / "z.yaml"
    path.write_text(text, encoding="utf-8")
    e = size(path).selection.selected.electrical
    # the 1FT7 rows print no voltage class; the catalog gives them the SINAMICS S120 400 V class (the series
    # rule of catalog.voltage_class), so without a supply the motor's class sets the bus and the envelope
    assert e["supply_voltage_V"] == 400.0 and e["envelope_source"] == "electrical"


def test_rms_torque_is_judged_on_the_motors_own_continuous_curve(result) -> None:  # type: ignore[no-untyped-def]
    # 1FT7044-5AK7: the printed stall torque M_0 = 5 N m (Table 4-8, 100 K) now reaches the envelope; before,
    # the row had none and the 2 N m rated torque at 6000 rpm stood for the continuous torque at every speed
    sel = result.selection.selected
    rms = next(c for c in sel.checks if c.name == "rms_torque")
    mean_rpm = result.to_dict()["mean_speed_rpm"]
    t0, tn, nn = 5.0, 2.0, 6000.0  # continuous envelope: T_0 falling linearly to T_N at n_N (sizing.envelope)
    assert rms.available == pytest.approx(t0 - (t0 - tn) * mean_rpm / nn)
    assert rms.available == pytest.approx(4.25) and rms.ok
    assert "voltage" in sel.derived and "stall_torque" not in sel.derived
