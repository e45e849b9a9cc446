"""The order sheet (drivetrain.sizing.order): one row per part of every shipped example, codes that can be
ordered as written, the drive and braking-resistor specifications by hand, the --bom file, the machine BOM,
and the same rows in the JSON, the CLI and the report."""

from __future__ import annotations

import csv
import io
import json
import math
from collections import Counter
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from drivetrain import cli
from drivetrain.sizing.order import (
    BOM_COLUMNS,
    E12,
    PARTS,
    code_choices,
    nearest_standard,
    order_sheet,
    peak_duration,
    required_rating,
    standard_values,
)
from drivetrain.sizing.order_spec import resistor_spec

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.yaml"))
MACHINE = ROOT / "examples" / "machine" / "pick_and_place.yaml"


@cache
def sized(name: str) -> Any:
    """The example's answer as ``drivetrain size`` gives it (the pipeline with its modes stage)."""
    from drivetrain.dynamics.mechanism_modes import size

    return size(ROOT / "examples" / name)


def _expected_parts(result: Any) -> Counter[str]:
    """The parts the axis has, counted from the answer's blocks and the axis file."""
    axis = result.axis
    parts: Counter[str] = Counter({"motor": 1, "drive": 1})
    pick = result.selection.selected if result.axis.motor is None and result.selection is not None else None
    parts["gearbox"] = sum(st.kind == "gearbox" for st in axis.transmission) + bool(pick and pick.gearbox)
    parts["coupling"] = sum(st.kind == "coupling" for st in axis.transmission)
    parts["brake"] = sum(st.kind == "brake" for st in axis.transmission)
    parts["screw"] = int(axis.spec.mechanism.type in ("ball_screw", "lead_screw"))
    parts["guide"] = int(axis.spec.guide is not None)
    regen = pick.regen if pick is not None else result.regen
    parts["braking_resistor"] = int(bool(regen is not None and regen.resistor_needed
                                         and regen.builtin_resistor_sufficient is not True))
    return +parts


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_has_a_row_per_part_and_no_pattern_as_order_code(path: Path) -> None:
    result = sized(path.name)
    sheet = order_sheet(result)
    assert Counter(r.part for r in sheet.rows) == _expected_parts(result)
    assert [r.part for r in sheet.rows] == sorted((r.part for r in sheet.rows), key=PARTS.index)
    for row in sheet.rows:
        assert row.kind in ("catalog", "specification")
        if row.order_code is not None:
            assert not code_choices(row.order_code), f"{row.part}: {row.order_code} has positions to choose"
            assert row.kind == "catalog" and (row.vendor or row.source == "axis file (not a catalog row)")
        if row.source == "axis file (not a catalog row)":  # a name the file gives: never complete
            assert row.status == "incomplete" and row.unverified and row.open_points
        if row.kind == "specification":
            assert row.status == "specification" and row.order_code is None and row.spec
        if row.status == "complete":  # orderable as written, nothing open
            assert row.order_code and not row.open_points and not row.choose
        if row.choose:
            assert row.order_code is None and row.status == "incomplete"
    # a part's unknown is never a pass: the sheet is complete only when every row is
    assert sheet.complete == all(r.status == "complete" for r in sheet.rows)
    d = sheet.to_dict()
    assert d["open_points"] == [f"{r.part}: {p}" for r in sheet.rows for p in r.open_points]
    assert d["complete_rows"] + d["incomplete_rows"] + d["specification_rows"] == len(sheet.rows)


def test_a_pattern_id_is_never_an_order_code_its_positions_are_listed() -> None:
    """The S120 Motor Module's catalog id has lost characters written 'x' (its catalog notes): the row
    lists positions 7, 9 and 18 to choose and is incomplete (examples/z_axis.yaml selects 1FT7044-5AK7 and
    its recommended drive); where the catalog comes to hold the full code, the row orders it as written."""
    from drivetrain import catalog

    assert [c["position"] for c in code_choices("6SL312x-xTE21-0AAx")] == [7, 9, 18]
    assert code_choices("AG2400-TP004-MF-i4") == [] and code_choices("MQMF022L1") == []
    assert [c["position"] for c in code_choices("SGM7J-□□A")] == [7, 8]
    drive = next(r for r in order_sheet(sized("z_axis.yaml")).rows if r.part == "drive")
    assert drive.kind == "catalog" and drive.catalog_id in catalog.drive_pairs()["1FT7044-5AK7"]
    positions = [c["position"] for c in code_choices(drive.catalog_id)]
    if positions:  # the catalog's id as read (through the catalog API): a pattern is listed, never ordered
        assert drive.order_code is None and drive.status == "incomplete"
        assert [c["position"] for c in drive.choose] == positions
        assert any(", ".join(map(str, positions)) in p for p in drive.open_points)
    else:  # a complete vendor code: ordered as written
        assert drive.order_code == drive.catalog_id and not drive.choose


def test_a_motor_without_drive_currents_gets_a_drive_specification_in_torque_terms() -> None:
    """examples/belt.yaml selects MQMF022L1 (no k_T in the catalog): the drive row is a specification with the
    motor's RMS and peak torque over the cycle, the peak's duration (the 1/3 s acceleration of the trapezoid
    1.2 m in 1 s) and the supply of the motor's 200 V class; the currents need the motor's k_T."""
    result = sized("belt.yaml")
    pick = result.selection.selected
    assert pick.motor == "MQMF022L1" and pick.drive.status == "unknown"
    drive = next(r for r in order_sheet(result).rows if r.part == "drive")
    assert drive.kind == "specification" and drive.spec["motor"] == "MQMF022L1"
    cycle, rotor, _ = result.motor_cycle()
    torque = cycle.motor_torque(rotor)
    rms = math.sqrt(float(np.sum(cycle.weights * torque**2)) / cycle.period)
    assert drive.spec["continuous_torque_Nm"] == pytest.approx(rms, rel=1e-12)
    assert drive.spec["continuous_torque_Nm"] == pytest.approx(pick.rms_torque_Nm, rel=1e-9)
    assert drive.spec["peak_torque_Nm"] == pytest.approx(pick.peak_torque_Nm, rel=1e-9)
    assert drive.spec["peak_duration_s"] == pytest.approx(1.0 / 3.0, rel=1e-9)  # t_a = 1 s / 3 (trapezoid)
    assert drive.spec["supply_voltage_V"] == 200.0
    assert drive.spec["dc_bus_voltage_V"] == pytest.approx(200.0 * math.sqrt(2.0), rel=1e-12)
    assert "continuous_current_A" not in drive.spec
    assert any("k_T" in p for p in drive.open_points)


def test_a_drive_with_currents_is_a_catalog_row() -> None:
    """examples/belt_gantry.yaml: SGM7G-09A with SGD7S-7R6A (currents from a third-party transcription: unverified)."""
    drive = next(r for r in order_sheet(sized("belt_gantry.yaml")).rows if r.part == "drive")
    assert (drive.kind, drive.order_code, drive.vendor) == ("catalog", "SGD7S-7R6A", "Yaskawa")
    assert drive.unverified is True and drive.unverified_reason


def test_a_held_load_asks_for_the_brake_variant_with_its_holding_torque() -> None:
    """The hoist holds its load: the motor row asks for the brake variant holding what the selection's
    `motor_brake` check requires (the static torque at the motor through the gearbox in the holding direction
    x 1.5, Machine Design 2007); where the catalog has no brake order code the row is incomplete, without an
    order code, and says the holding torque to order; where it has one, that code is the one to order."""
    result = sized("hoist.yaml")
    motor = next(r for r in order_sheet(result).rows if r.part == "motor")
    need = result.selection.selected.check("motor_brake").required
    assert motor.spec["holding_brake"] == "required"
    assert motor.spec["brake_holding_torque_min_Nm"] == pytest.approx(need, rel=1e-12)
    from drivetrain import catalog

    assert motor.catalog_id == result.selection.selected.motor
    variant = catalog.get(motor.catalog_id).get("brake_code")
    if variant is None:  # the catalog names no brake variant: no code to order, the holding torque to ask for
        assert motor.status == "incomplete" and motor.order_code is None
        assert any(f"{motor.spec['brake_holding_torque_min_Nm']:.4g} N*m" in p for p in motor.open_points)
    else:  # the brake variant's own code is the one to order
        assert motor.spec["brake_variant"] == variant and motor.order_code in (variant, None)


def test_standard_values_and_the_resistance_window_by_hand() -> None:
    """E12 (IEC 60063): 1.0 1.2 1.5 1.8 2.2 2.7 3.3 3.9 4.7 5.6 6.8 8.2 per decade."""
    assert E12 == (1.0, 1.2, 1.5, 1.8, 2.2, 2.7, 3.3, 3.9, 4.7, 5.6, 6.8, 8.2)
    assert standard_values(20.0, 50.0) == [22.0, 27.0, 33.0, 39.0, 47.0]
    assert standard_values(100.0, 120.0) == [100.0, 120.0]  # the bounds are inside
    assert nearest_standard(20.0, 50.0) == [47.0, 22.0]
    assert nearest_standard(0.0, 50.0) == [47.0]  # no drive minimum: the largest only
    assert nearest_standard(23.0, 26.0) == []
    # switch-on voltage 400 V, peak 800 W: R_max = 400^2 / 800 = 200 ohm; drive minimum 30 ohm
    spec, open_points = resistor_spec(800.0, 50.0, 120.0, 70.0, 30.0, None, 400.0, 565.0)
    assert spec["resistance_min_ohm"] == 30.0 and spec["resistance_max_ohm"] == pytest.approx(200.0)
    assert spec["standard_values_ohm"] == [180.0, 33.0]
    assert (spec["energy_per_event_J"], spec["peak_power_W"], spec["average_power_W"]) == (70.0, 800.0, 50.0)
    assert not any("switch-on" in p for p in open_points)
    # no switch-on voltage: the bound at the nominal bus 565.685 V (below U_on, so safe): 320000 / 800 = 400 ohm
    spec, open_points = resistor_spec(800.0, 50.0, 120.0, 70.0, 30.0, None, None, 400.0 * math.sqrt(2.0))
    assert spec["resistance_max_ohm"] == pytest.approx(400.0)
    assert spec["standard_values_ohm"] == [390.0, 33.0]
    assert any("switch-on voltage not known" in p for p in open_points)
    # a drive minimum above the maximum: no resistor takes the peak, said so, no value offered
    spec, open_points = resistor_spec(800.0, 50.0, 120.0, 70.0, 500.0, None, 400.0, None)
    assert "standard_values_ohm" not in spec and any("empty window" in p for p in open_points)


def test_the_belt_axis_resistor_row_by_hand() -> None:
    """examples/belt.yaml: 200 V class, bus 282.84 V, resistor peak 132.78 W: R_max = 282.84^2 / 132.78 =
    602.5 ohm, largest E12 value below it 560 ohm; the energy per event is the larger of the two braking events."""
    result = sized("belt.yaml")
    regen = result.selection.selected.regen
    row = next(r for r in order_sheet(result).rows if r.part == "braking_resistor")
    p = regen.resistor_peak_power_W
    assert row.spec["resistance_max_ohm"] == pytest.approx(2.0 * 200.0**2 / p, rel=1e-12)
    assert row.spec["resistance_max_ohm"] == pytest.approx(602.5, abs=0.05)
    assert row.spec["standard_values_ohm"] == [560.0]
    assert row.spec["energy_per_event_J"] == max(e.resistor_J for e in regen.events)
    assert row.spec["average_power_W"] == regen.resistor_average_power_W
    assert row.spec["resistance_min_ohm"] is None and any("minimum resistance" in p for p in row.open_points)


def test_peak_duration_and_required_rating_by_hand() -> None:
    t = np.array([0.0, 1.0, 2.0, 3.0])
    # samples stand for [0, 0.5], [0.5, 1.5], [1.5, 2.5], [2.5, 4]: the first two are above 1
    assert peak_duration(t, np.array([2.0, -2.0, 0.0, 0.0]), 1.0, 4.0) == pytest.approx(1.5)
    # a run at the end continues at the start of the next cycle: 1.5 s + 0.5 s
    assert peak_duration(t, np.array([2.0, 0.0, 0.0, 2.0]), 1.0, 4.0) == pytest.approx(2.0)
    assert peak_duration(t, np.zeros(4), 1.0, 4.0) == 0.0
    assert peak_duration(t, np.full(4, 3.0), 1.0, 4.0) == 4.0
    # L10 = (C / P)^3: eight times the life needs twice the rating
    assert required_rating(10_000.0, 8_000.0, 1_000.0, 3.0) == pytest.approx(20_000.0)


def test_bom_file_holds_the_json_rows(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "belt_bom.csv"
    cli.main(["size", str(ROOT / "examples" / "belt.yaml"), "--bom", str(path), "--json"])
    order = json.loads(capsys.readouterr().out)["order"]
    rows = list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))
    assert tuple(rows[0].keys()) == BOM_COLUMNS
    assert [(r["part"], r["kind"], r["status"], r["order_code"]) for r in rows] == [
        (o["part"], o["kind"], o["status"], o["order_code"] or "") for o in order["rows"]]
    assert {r["axis"] for r in rows} == {"belt gantry X"}
    motor, drive = rows[0], rows[1]
    assert (motor["vendor"], motor["order_code"], motor["unverified"]) == ("Panasonic", "MQMF022L1", "yes")
    assert "continuous_torque_Nm=" in drive["specification"] and "k_T" in drive["open_points"]
    resistor = next(r for r in rows if r["part"] == "braking_resistor")
    assert "standard_values_ohm=560" in resistor["specification"]
    assert cli.main(["size", str(ROOT / "examples" / "belt.yaml"), "--bom", str(tmp_path / "b.txt")]) == 2
    assert "--bom: must end in .csv" in capsys.readouterr().err


def test_a_failed_bom_write_leaves_no_partial_file(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """The write stops half-way (a full disk): the file a user had stays as it was and no temporary is left."""
    path = tmp_path / "bom.csv"
    path.write_text("the user's own file\n", encoding="utf-8")
    real = Path.write_text

    def half_then_fail(self: Path, data: str, *args: Any, **kwargs: Any) -> int:
        real(self, data[: len(data) // 2], *args, **kwargs)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Path, "write_text", half_then_fail)
    code = cli.main(["size", str(ROOT / "examples" / "belt.yaml"), "--bom", str(path)])
    monkeypatch.undo()
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --bom:") and "Traceback" not in err
    assert path.read_text(encoding="utf-8") == "the user's own file\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bom.csv"]


def test_the_machine_bom_is_the_axes_order_rows() -> None:
    """examples/machine: every row of the machine BOM but the bus's own (supply module, bus resistor) is an
    order-sheet row of an axis's motor, merged by order code (or identical specification)."""
    from drivetrain.machine.result import size_machine

    res = size_machine(MACHINE, phasing_samples=5)
    out = res.to_dict()
    expected: Counter[tuple[str, str]] = Counter()
    for a in res.machine.axes:
        for r in res.axes[a.name].results:
            for row in order_sheet(r).rows:
                if row.part != "braking_resistor":  # sized per DC bus in a machine
                    expected[(row.part, row.order_code or f"{row.name} {sorted(row.spec.items())}")] += row.quantity
    bus_names = {b.name for b in res.machine.buses}
    got: Counter[tuple[str, str]] = Counter()
    for r in out["bill_of_materials"]:
        if set(r["used_by"]) <= bus_names:
            continue
        got[(r["kind"], r["order_code"] or f"{r['name']} {sorted(r['spec'].items())}")] += r["quantity"]
    assert got == expected
    resistor = next(r for r in out["bill_of_materials"] if r["kind"] == "braking_resistor")
    bus = out["buses"][0]
    assert resistor["spec"]["resistance_max_ohm"] == pytest.approx(
        bus["dc_bus_voltage_V"] ** 2 / bus["resistor_peak_power_W"], rel=1e-12)
    assert "- .. -" not in resistor["note"] and "E12: 120 ohm" in resistor["note"]


def _cli_table(text: str, title: str) -> list[list[str]]:
    """The body rows of the CLI table whose title starts with ``title`` (cells stripped)."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith(title))
    rows = []
    for line in lines[start + 1:]:
        if line.startswith("└"):
            break
        if line.startswith("│"):
            rows.append([c.strip() for c in line.strip("│").split("│")])
    return rows


def test_the_cli_prints_the_json_rows(capsys: pytest.CaptureFixture[str]) -> None:
    axis = str(ROOT / "examples" / "z_axis.yaml")
    cli.main(["size", axis, "--json"])
    order = json.loads(capsys.readouterr().out)["order"]
    cli.main(["size", axis])
    text = capsys.readouterr().out
    rows = _cli_table(text, "order sheet (")
    expected = []
    for r in order["rows"]:
        code = r["order_code"] or (f"{r['catalog_id']} (choose position "
                                   f"{', '.join(str(c['position']) for c in r['choose'])})" if r["choose"] else
                                   (f"{r['catalog_id']} (not as written)" if r["catalog_id"] else "specification"))
        expected.append([r["part"].replace("_", " "), r["status"], str(r["quantity"]), r["vendor"] or "-",
                         code + (" †" if r["unverified"] else ""), r["name"]])
    assert rows == expected
    for point in order["open_points"]:
        assert f"open: {point.split(': ', 1)[1]}" in text


def test_the_report_holds_the_order_sheet() -> None:
    from drivetrain.report.html import render_html

    result = sized("belt.yaml")
    html = render_html(result)
    order = order_sheet(result).to_dict()
    assert 'id="dt-order"' in html and "Order sheet (1 complete, 0 incomplete, 4 specification(s)" in html
    assert "MQMF022L1 †" in html and html.count(">specification<") >= order["specification_rows"]
    for r in order["rows"]:
        for point in r["open_points"]:
            assert point.replace("'", "&#x27;")[:60] in html


def test_a_brake_whose_dwells_are_all_braked_still_gets_its_holding_torque() -> None:
    """Every dwell of the vertical Z axis held on the brake: the motor never holds at rest (the answer's holding
    torque is 0 N m), yet the selection's `motor_brake` check works out the static torque over the stroke, and the
    motor row asks for that, never for 0 N m."""
    import yaml

    from drivetrain.sizing.pipeline import size

    data = yaml.safe_load((ROOT / "examples" / "z_axis.yaml").read_text(encoding="utf-8"))
    data.pop("transmission")  # the example's own brake on the screw: here the motor's must hold
    data["motor"]["select"]["unknown"] = "flag"  # no 400 V motor's brake holding torque is in the catalog
    for step in data["profile"]:
        if "dwell" in step:
            step["holding"] = "brake"
    result = size(data)
    assert result.metrics.holding_torque_Nm == 0.0
    motor = next(r for r in order_sheet(result).rows if r.part == "motor")
    need = result.selection.selected.check("motor_brake").required
    assert motor.spec["holding_brake"] == "required" and need > 0.0
    assert motor.spec["brake_holding_torque_min_Nm"] == pytest.approx(need, rel=1e-12)
