"""Every answer can go on a purchase order or says exactly what is still open (issue: an answer you can
order): the four purchase axes of tests/axes and every shipped example, through ``drivetrain.size`` and the
CLI. The answer is ``pass`` with every catalog part complete, ``pass with unknowns`` with each unknown
naming what decides it and each incomplete part specified on the sheet, or ``fail`` with its reason; the
verdict and the order sheet agree; voltages, brakes and order codes are consistent."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import drivetrain
from drivetrain import cli
from drivetrain.sizing.order_spec import code_choices
from drivetrain.sizing.verdict import sheet_parts, unknown_fails

ROOT = Path(__file__).resolve().parents[2]
AXES = sorted((ROOT / "tests" / "axes").glob("purchase_*.yaml")) + sorted((ROOT / "examples").glob("*.yaml"))
IDS = [f"{p.parent.name}/{p.stem}" for p in AXES]

CATALOG_PARTS = frozenset({"motor", "drive"})
"""Parts a passing answer must order from the catalog; the others (a braking resistor, brake, coupling,
screw, guide, an axis gearbox the file describes) the catalog does not carry and are specifications."""


@cache
def sized(path: Path) -> Any:
    return drivetrain.size(path)


@cache
def answer(path: Path) -> dict[str, Any]:
    return sized(path).to_dict()


def _braked_or_held(result: Any) -> bool:
    """Whether the motor must hold the load at rest: a dwell on the brake, or a static torque at standstill,
    unless the transmission has its own brake element."""
    if any(st.kind == "brake" for st in result.axis.transmission):
        return False
    braked = bool(np.asarray(result.duty.samples.braked, dtype=bool).any())
    return braked or abs(float(result.metrics.holding_torque_Nm or 0.0)) > 1e-9


@pytest.mark.parametrize("path", AXES, ids=IDS)
def test_the_answer_is_one_of_three_outcomes_and_the_sheet_agrees(path: Path) -> None:
    result, d = sized(path), answer(path)
    status, unknowns, rows = d["verdict"]["status"], d["verdict"]["unknowns"], d["order"]["rows"]
    assert status in ("pass", "pass with unknowns", "fail")
    assert result.status == status
    for r in rows:  # a row is what it says it is
        assert (r["kind"], r["status"]) in (("catalog", "complete"), ("catalog", "incomplete"),
                                            ("specification", "specification"))
        if r["status"] != "complete":
            assert r["spec"] or r["open_points"], r
        if r["status"] == "incomplete":
            assert r["open_points"], r
    if status == "pass":
        assert not unknowns
        for r in rows:
            assert r["status"] != "incomplete", r
            if r["part"] in CATALOG_PARTS:
                assert r["status"] == "complete", r
    elif status == "pass with unknowns":
        assert unknowns
        for u in unknowns:
            assert u["check"] and u["part"] and len(u["decide"]) > 10, u
    else:
        assert result.verdict_line().startswith("FAIL: ") and len(result.verdict_line()) > len("FAIL: ") + 5
    # a part unknown in the verdict is not complete on the sheet
    for u in unknowns:
        concerned = [r for r in rows if r["part"] in sheet_parts(u["part"])]
        assert not concerned or any(r["status"] != "complete" for r in concerned), (u, concerned)
    # and a catalog part that cannot be ordered as written is an unknown of the verdict (or the answer fails)
    if status != "fail":
        named = {p for u in unknowns for p in sheet_parts(u["part"])}
        for r in rows:
            if r["status"] == "incomplete":
                assert r["part"] in named, (r["part"], r["open_points"], unknowns)


@pytest.mark.parametrize("path", AXES, ids=IDS)
def test_no_placeholder_code_and_no_motor_both_passing_and_rejected(path: Path) -> None:
    result, d = sized(path), answer(path)
    for r in d["order"]["rows"]:
        if r["order_code"] is not None:
            assert not code_choices(r["order_code"]), r["order_code"]
            assert "x" not in r["order_code"].replace("X", "") or any(
                c.islower() and c != "x" for c in r["order_code"]), r["order_code"]
    passing = {c.motor for c in result.candidates if c.ok}
    rejected = {c.motor for c in result.candidates if not c.ok}
    assert not passing & rejected


@pytest.mark.parametrize("path", AXES, ids=IDS)
def test_voltage_classes_agree_with_the_supply(path: Path) -> None:
    d = answer(path)
    rows = {r["part"]: r for r in d["order"]["rows"]}
    supply = rows["drive"]["spec"].get("supply_voltage_V")
    if supply is None or rows["drive"]["spec"].get("voltage_basis"):
        return  # no stated supply: the motor's class is the supply
    for part in ("motor", "drive"):
        cls = rows[part]["spec"].get("voltage_class_V")
        if cls is None:
            continue
        if supply >= 380.0:
            assert cls >= 380.0, (part, cls, supply)
        if supply <= 240.0:
            assert cls <= 240.0, (part, cls, supply)


@pytest.mark.parametrize("path", AXES, ids=IDS)
def test_an_axis_holding_on_a_brake_asks_the_motor_row_for_one(path: Path) -> None:
    result, d = sized(path), answer(path)
    if not _braked_or_held(result):
        return
    motor = next(r for r in d["order"]["rows"] if r["part"] == "motor")
    assert motor["spec"].get("holding_brake") == "required" or motor["spec"].get("brake_variant"), motor


def test_the_purchase_axes_that_hold_a_load_need_a_brake() -> None:
    """The vertical Z axis and the hoist hold their load: the test above must bite on them."""
    for name in ("purchase_z_axis", "purchase_hoist"):
        assert _braked_or_held(sized(ROOT / "tests" / "axes" / f"{name}.yaml")), name


@pytest.mark.parametrize("path", AXES, ids=IDS)
def test_the_cli_says_the_same(path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    result, d = sized(path), answer(path)
    code = cli.main(["size", str(path), "--json"])
    got = json.loads(capsys.readouterr().out)
    assert got["verdict"] == json.loads(json.dumps(d["verdict"]))
    assert [(r["part"], r["status"], r["order_code"]) for r in got["order"]["rows"]] == [
        (r["part"], r["status"], r["order_code"]) for r in d["order"]["rows"]]
    checks = any(u["check"] != "order_code" for u in d["verdict"]["unknowns"])
    expected = 1 if d["verdict"]["status"] == "fail" else 0
    assert code == expected
    if unknown_fails(result.axis) and checks:
        assert d["verdict"]["status"] == "fail"
    code = cli.main(["size", str(path)])
    out = capsys.readouterr().out.rstrip("\n").splitlines()
    assert code == expected
    assert out[-1] == result.verdict_line()
    assert "order sheet (" in "\n".join(out)


def test_a_passing_candidate_with_an_unknown_drive_says_so(capsys: pytest.CaptureFixture[str]) -> None:
    """The candidate table's result column agrees with the verdict: the belt axis's best motor passes with its
    drive unknown (no torque constant in the catalog), so its row reads ``yes, unknown: drive``."""
    path = ROOT / "examples" / "belt.yaml"
    result = sized(path)
    best = result.candidates[0]
    assert best.ok and best.drive.status == "unknown"
    assert any(u.part == "drive" for u in result.unknowns)
    cli.main(["size", str(path)])
    lines = capsys.readouterr().out.splitlines()
    row = next(ln for ln in lines if f" {best.motor} " in ln and ln.lstrip("│┃ ").startswith("1 "))
    assert "yes, unknown: drive" in row
    judged = [c for c in result.candidates if c.ok and not c.unknown
              and getattr(c.drive, "status", None) not in ("unknown", "none")]
    for c in judged:  # a row judged in full still says a plain yes
        line = next(ln for ln in lines if f" {c.motor} " in ln)
        assert "unknown" not in line.split("│")[-3], line


def test_the_cli_order_sheet_honours_units(capsys: pytest.CaptureFixture[str]) -> None:
    """``--units imperial`` prints the sheet's torques and lengths as the other tables do (lbf*in, in); SI is
    the report's text unchanged."""
    from drivetrain.cli.order import spec_text_in
    from drivetrain.cli.quantities import TableUnits
    from drivetrain.report.order import spec_text

    path = ROOT / "examples" / "ball_screw.yaml"
    motor = next(r for r in answer(path)["order"]["rows"] if r["part"] == "motor")
    assert spec_text_in(motor["spec"], TableUnits("si")) == spec_text(motor["spec"])
    cli.main(["size", str(path), "--units", "imperial"])
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("  motor: "))
    rated = motor["spec"]["rated_torque_Nm"] / 0.112984829  # N*m per lbf*in (NIST SP 811, B.9)
    flange = motor["spec"]["flange_mm"] / 25.4
    assert f"rated torque {rated:.4g} lbf*in" in line and f"flange {flange:.4g} in" in line
    assert "N*m" not in line and " mm" not in line
    cli.main(["size", str(path)])
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("  motor: "))
    assert line == f"  motor: {spec_text(motor['spec'])}"


@cache
def machine() -> Any:
    return drivetrain.size_machine(ROOT / "examples" / "machine" / "pick_and_place.yaml")


def test_the_web_machine_table_shows_the_order_sheet_rows() -> None:
    """Each motor's motor, drive and gearbox cells are its order-sheet rows as the machine BOM lists them:
    the order code, else the row's name, status and open points (never an old per-axis BOM item)."""
    from drivetrain.machine.result import axis_bom_rows
    from drivetrain.web.routes_machine import axis_rows

    result = machine()
    rows = axis_rows(result)
    k = 0
    for ma in result.machine.axes:
        for res in result.axes[ma.name].results:
            sheet = {r["part"]: r for r in res.to_dict()["order"]["rows"]}
            bom = axis_bom_rows(ma.name, [res])
            for part in ("motor", "drive"):
                r = sheet[part]
                cell = rows[k][part]
                assert cell == (r["order_code"] or next(b["note"] for b in bom if b["kind"] == part)), (cell, r)
                if r["order_code"] is None:
                    assert r["name"] in cell and r["status"] in cell
            k += 1
    assert k == len(rows)


def test_the_machine_bus_table_prints_the_resistor_window(capsys: pytest.CaptureFixture[str]) -> None:
    """The bus needs a resistor and its drives state no switch-on voltage: the window's maximum is the sheet's
    U_bus^2 / P_peak (a safe bound), and the missing minimum is said, never ``- .. - ohm``."""
    from drivetrain.cli.analyses import bus_window

    bus = machine().to_dict()["buses"][0]
    assert bus["resistor_needed"] and bus["resistor_max_ohm"] is None
    r_max = bus["dc_bus_voltage_V"] ** 2 / bus["resistor_peak_power_W"]  # physics.regen: R_max = U^2 / P_peak
    assert bus_window(bus) == f"no drive minimum given .. {r_max:.4g} ohm (max at U_bus)"
    assert cli.main(["machine", "size", str(ROOT / "examples" / "machine" / "pick_and_place.yaml")]) in (0, 1)
    out = capsys.readouterr().out
    assert "- .. -" not in out and f"{r_max:.4g} ohm" in out
