"""Machine projects: the shared DC bus against a hand calculation, gantry split, phasing, bad machine files."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import drivetrain
from drivetrain import cli
from drivetrain.errors import InputError
from drivetrain.machine.model import parse_machine
from drivetrain.machine.result import size_machine
from drivetrain.physics import dc_bus

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "machine" / "pick_and_place.yaml"
G = 9.80665
M_Z = 20.0  # [kg] hoist load
R_Z = 0.1  # [m] drum radius
J_M = 1e-4  # [kg m^2] each motor's rotor
J_X = 0.1  # [kg m^2] the rotary table
MOTOR = {"rated_torque": 100, "peak_torque": 300, "max_speed": "6000 rpm", "inertia": J_M}

# Z lowers 20 kg by 0.5 m in 1 s (0.25 s ramps) and rests 1 s; X swings a 0.1 kg m^2 table 180 deg in
# 0.5 s (triangle) and back, starting 0.25 s into the cycle: its acceleration falls in Z's constant-speed
# lowering, its first braking too, its return move while Z rests. No losses (efficiency 1), no copper loss.
Z_AXIS: dict[str, Any] = {
    "axis": "Z", "mechanism": {"type": "hoist", "diameter": "200 mm", "inertia": 0, "efficiency": 1.0,
                               "load": {"mass": f"{M_Z} kg"}},
    "profile": [{"move": "-0.5 m", "time": "1 s", "accel": "0.25 s"}, {"dwell": "1 s"}],
    "motor": {"name": "motor Z", **MOTOR}}
X_AXIS: dict[str, Any] = {
    "axis": "X", "mechanism": {"type": "rotary", "inertia": J_X},
    "profile": [{"move": "180 deg", "time": "0.5 s", "shape": "triangle"}, {"dwell": "0.5 s"},
                {"move": "-180 deg", "time": "0.5 s", "shape": "triangle"}, {"dwell": "0.5 s"}],
    "motor": {"name": "motor X", **MOTOR}}
TWO: dict[str, Any] = {"version": 1, "machine": "two axes", "cycle_time": "2 s", "supply": {"voltage": "400 V"},
                       "axes": [{"axis": Z_AXIS}, {"axis": X_AXIS, "offset": "0.25 s"}],
                       "buses": [{"name": "bus", "axes": ["Z", "X"]}]}


def machine(**changes: Any) -> dict[str, Any]:
    data = copy.deepcopy(TWO)
    data.update(changes)
    return data


def test_two_axes_one_lowering_while_the_other_accelerates_match_the_hand_calculation() -> None:
    """Hand calculation (SI):

    Z: v0 = 0.5 m / 0.75 s = 0.6667 m/s, a0 = v0 / 0.25 s = 2.667 m/s^2. Lowering at constant speed
    feeds the bus m g v0 = 20 * 9.80665 * 0.6667 = 130.76 W; over the whole move it returns the
    potential energy m g s = 98.07 J (its kinetic energy, rotor included, comes back in the ramps),
    and at the start of its braking ramp it feeds (m g + m_eff a0) v0, m_eff = m + J_M / r^2.
    X: omega = 2 pi / 0.5 s = 12.566 rad/s peak, alpha = 50.27 rad/s^2, J = J_X + J_M = 0.1001 kg m^2;
    accelerating it draws at most J alpha omega = 63.23 W < 130.76 W, so all its kinetic energy
    1/2 J omega^2 = 7.904 J comes from Z's braking on the shared bus (regen_shared_J), and the bus
    never draws power during Z's move. Its braking (0.5 to 0.75 s) adds to Z's lowering: the bus
    receives up to 130.76 + 63.23 = 193.98 W. No capacitors: the resistor takes everything the bus
    receives, m g s (Z, less X's acceleration, plus X's first braking) + X's second braking
    = 98.07 + 7.904 J. The supply delivers only X's return acceleration: peak 63.23 W.
    """
    out = size_machine(TWO).to_dict()
    m = out["machine"]
    v0, a0 = 0.5 / 0.75, (0.5 / 0.75) / 0.25
    w = 2 * math.pi / 0.5
    alpha = w / 0.25
    j = J_X + J_M
    e_x = 0.5 * j * w**2
    p_x = j * alpha * w
    p_run = M_Z * G * v0
    assert m["regen_shared_J"] == pytest.approx(e_x, rel=1e-6)
    assert m["resistor_energy_per_cycle_J"] == pytest.approx(M_Z * G * 0.5 + e_x, rel=1e-6)
    assert m["resistor_average_power_W"] == pytest.approx((M_Z * G * 0.5 + e_x) / 2.0, rel=1e-6)
    assert m["resistor_peak_power_W"] == pytest.approx(p_run + p_x, rel=1e-6)
    assert m["bus_peak_power_W"] == pytest.approx(p_x, rel=1e-6)
    assert m["supply_peak_power_W"] == pytest.approx(p_x, rel=1e-6)
    assert m["supply_peak_current_A"] == pytest.approx(p_x / (math.sqrt(3) * 400.0), rel=1e-6)
    assert m["supply_continuous_power_W"] == pytest.approx(e_x / 2.0, rel=1e-6)  # X's return, averaged over 2 s
    # Z's own figures: the braking ramp's first instant
    z = next(a for a in out["axes"] if a["name"] == "Z")
    m_eff = M_Z + J_M / R_Z**2
    assert -min(size_machine(TWO).axes["Z"].power) == pytest.approx((M_Z * G + m_eff * a0) * v0, rel=1e-6)
    assert z["regen_energy_J"] == pytest.approx(M_Z * G * 0.5, rel=1e-6)
    assert z["power_basis"] == "shaft"
    assert any("copper loss left out" in n for n in z["notes"])


def test_capacitors_take_each_braking_event_first() -> None:
    """10 J per event on the bus: Z's lowering (one event, 98.07 J) gives 88.07 J to the resistor, X's
    return braking (7.904 J, its own event while Z rests) is absorbed whole."""
    out = size_machine(machine(buses=[{"name": "bus", "axes": ["Z", "X"], "absorbable_energy": "10 J"}])).to_dict()
    m = out["machine"]
    e_x = 0.5 * (J_X + J_M) * (2 * math.pi / 0.5) ** 2
    assert m["capacitor_energy_per_event_J"] == 10.0
    assert m["capacitor_absorbed_J"] == pytest.approx(10.0 + e_x, rel=1e-6)
    assert m["resistor_energy_per_cycle_J"] == pytest.approx(M_Z * G * 0.5 - 10.0, rel=1e-6)


def test_separate_buses_share_nothing() -> None:
    out = size_machine(machine(buses=[])).to_dict()
    assert {b["name"] for b in out["buses"]} == {"Z", "X"}
    assert all(not b["declared"] for b in out["buses"])
    assert out["machine"]["regen_shared_J"] == 0.0
    e_x = 0.5 * (J_X + J_M) * (2 * math.pi / 0.5) ** 2
    # every joule braked goes to a resistor: Z's 98.07 J and both of X's brakings
    assert out["machine"]["resistor_energy_per_cycle_J"] == pytest.approx(M_Z * G * 0.5 + 2 * e_x, rel=1e-6)


def test_resistors_in_parallel_share_by_conductance() -> None:
    bus = {"name": "bus", "axes": ["Z", "X"], "regen_on_voltage": "760 V", "min_resistance": "20 ohm",
           "resistors": [{"id": "R1", "resistance": "100 ohm", "continuous_power": "100 W"},
                         {"id": "R2", "resistance": "100 ohm", "continuous_power": "20 W"}]}
    b = size_machine(machine(buses=[bus])).to_dict()["buses"][0]
    assert b["resistor_equivalent_ohm"] == pytest.approx(50.0)
    assert b["resistor_max_ohm"] == pytest.approx(760.0**2 / b["resistor_peak_power_W"])
    assert [r["share"] for r in b["resistors"]] == [0.5, 0.5]
    assert b["resistors"][0]["ok"] and not b["resistors"][1]["ok"]  # 26.5 W average each
    assert b["resistors_ok"] is False and b["ok"] is False


def test_gantry_split_sizes_each_motor_for_its_share() -> None:
    axis = copy.deepcopy(X_AXIS)
    data = machine(axes=[{"axis": axis, "motors": 2, "split": ["60 %", "40 %"]}], buses=None)
    res = size_machine(data)
    ap = res.axes["X"]
    full = drivetrain.size(axis)
    assert [r.load_share for r in ap.results] == [0.6, 0.4]
    for r, s in zip(ap.results, (0.6, 0.4), strict=True):
        np.testing.assert_allclose(r.duty.torque, s * full.duty.torque, rtol=1e-12)
        assert r.duty.load_inertia == pytest.approx(s * full.duty.load_inertia)
        # each motor: its share of the load plus its own rotor
        t_m = r.duty.motor_torque(J_M)
        assert r.motor.peak_torque_Nm == pytest.approx(float(np.max(np.abs(t_m))), rel=1e-9)
    # the two motors together: the whole load and both rotors
    p_full = full.duty.torque * full.duty.omega + 2 * J_M * full.duty.alpha * full.duty.omega
    np.testing.assert_allclose(ap.power, p_full, rtol=1e-9, atol=1e-9)
    out = res.to_dict()
    bom = {(r["kind"], r["order_code"]): r["quantity"] for r in out["bill_of_materials"]}
    assert bom[("motor", "motor X")] == 2
    assert out["axes"][0]["load_shares"] == [0.6, 0.4]


def test_gantry_split_by_stiffness() -> None:
    m = parse_machine(machine(axes=[{"axis": X_AXIS, "motors": 2, "split": "stiffness",
                                     "stiffness": ["200 N/um", "100 N/um"]}], buses=None))
    assert m.axes[0].shares == pytest.approx((2 / 3, 1 / 3))
    assert m.axes[0].split_basis == "stiffness"


def test_after_starts_an_axis_when_the_other_ends_its_last_move() -> None:
    data = machine(axes=[{"axis": Z_AXIS, "offset": "0.1 s"}, {"axis": X_AXIS, "after": "Z", "delay": "0.05 s"}],
                   buses=None)
    res = size_machine(data)
    assert res.offsets["X"] == pytest.approx(0.1 + 1.0 + 0.05)  # Z's move ends 1 s into its cycle


def test_random_phasing_is_reproducible_with_its_seed() -> None:
    data = machine(axes=[{"axis": Z_AXIS}, {"axis": X_AXIS, "offset": "free"}])
    a = size_machine(data, phasing_samples=40, seed=7).to_dict()["phasing"]
    b = size_machine(data, phasing_samples=40, seed=7).to_dict()["phasing"]
    c = size_machine(data, phasing_samples=40, seed=8).to_dict()["phasing"]
    assert a == b
    assert a["random"] != c["random"]
    assert a["free_axes"] == ["X"]
    r = a["random"]["resistor_peak_power_W"]
    assert r["p50"] <= r["p95"] <= r["p100"]
    # in phase = the free axis at offset 0, the stated evaluation
    stated = size_machine(data, phasing_samples=1).to_dict()["machine"]
    assert a["in_phase"]["bus_peak_power_W"] == pytest.approx(stated["bus_peak_power_W"])
    # worst phasing takes the largest of stated, in phase and the random maximum
    worst = size_machine(data, phasing_samples=40, seed=7).to_dict()["machine"]["worst_phasing"]
    assert worst["resistor_peak_power_W"] == pytest.approx(max(r["p100"], a["in_phase"]["resistor_peak_power_W"]))


def test_shared_energy_and_line_current_formulas() -> None:
    p = np.array([[100.0, -50.0, 0.0], [-30.0, 80.0, -10.0]])
    assert dc_bus.shared_energy(p, [1.0, 1.0, 1.0]) == pytest.approx(30.0 + 50.0)
    assert float(dc_bus.line_current(400.0, 230.0, phases=1, power_factor=0.8)) == pytest.approx(400 / (230 * 0.8))


@pytest.mark.parametrize(("change", "field"), [
    ({"axes": [{"axis": Z_AXIS}, {"axis": X_AXIS, "after": "Y"}]}, "axes[1].after"),
    ({"cycle_time": "1.5 s"}, "cycle_time"),
    ({"axes": [{"include": "no_such_axis.yaml"}]}, "axes[0].include"),
    ({"supply": {"voltage": "-400 V"}}, "supply.voltage"),
    ({"supply": {"voltage": "400 kV"}}, "supply.voltage"),
    ({"supply": {"voltage": "400 m"}}, "supply.voltage"),
    ({"version": 2}, "version"),
    ({"buses": [{"axes": ["Z", "Q"]}]}, "buses[0].axes[1]"),
    ({"axes": [{"axis": Z_AXIS, "motors": 2, "split": ["70 %", "40 %"]}], "buses": None}, "axes[0].split"),
    ({"axes": [{"axis": Z_AXIS, "after": "X2"}, {"axis": X_AXIS, "name": "X2", "after": "Z"}], "buses": None},
     "axes[0].after"),
])
def test_bad_machine_files_exit_2_naming_the_field(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                   change: dict[str, Any], field: str) -> None:
    data = machine(**change)
    if data.get("buses") is None:
        data.pop("buses")
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    with pytest.raises(InputError) as err:
        size_machine(path)
    assert err.value.field == field
    assert cli.main(["machine", "size", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f"error: {field}:")
    assert "Traceback" not in captured.err


def test_example_machine_runs_from_the_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    aas = tmp_path / "m.aas.json"
    assert cli.main(["machine", "size", str(EXAMPLE), "--json", "--samples", "20", "--aas", str(aas)]) == 0
    out = json.loads(capsys.readouterr().out)
    m = out["machine"]
    for key in ("bus_peak_power_W", "bus_rms_power_W", "regen_shared_J", "resistor_energy_per_cycle_J",
                "resistor_peak_power_W", "resistor_average_power_W", "resistor_min_ohm", "resistor_max_ohm",
                "supply_peak_power_W", "supply_continuous_power_W", "supply_peak_current_A"):
        assert key in m
    assert m["ok"] is True
    assert [a["name"] for a in out["axes"]] == ["X", "Y", "Z", "R"]
    y = out["axes"][1]
    assert y["motors"] == 2 and len(y["results"]) == 2 and y["load_shares"] == [0.5, 0.5]
    assert all(a["power_basis"] == "electrical" for a in out["axes"])
    bom = {(r["kind"], r["order_code"]): r["quantity"] for r in out["bill_of_materials"]}
    assert bom[("motor", "1FT7044-5AK7")] == 4  # X, two on Y, R; Z holds on a brake: its variant is still to choose
    assert sum(r["quantity"] for r in out["bill_of_materials"]
               if r["kind"] == "motor" and r["catalog_id"] == "1FT7044-5AK7") == 5
    assert bom[("drive", "SINAMICS S120 Motor Module 9 A")] == 5
    assert bom[("braking_resistor", None)] == 1  # none named: the row says what to choose
    assert out["phasing"]["free_axes"] == ["R"]
    assert json.loads(aas.read_text())["submodels"][0]["idShort"] == "PowerDriveTrainSizing"
    # the example's bus energy balance: what the axes brake is shared, absorbed or burnt
    assert m["regen_shared_J"] + m["capacitor_absorbed_J"] + m["resistor_energy_per_cycle_J"] == pytest.approx(
        m["regen_into_bus_J"], rel=1e-9)


def test_machine_report_html_and_pdf(tmp_path: Path) -> None:
    from drivetrain.report.machine import write_machine_report

    res = size_machine(TWO, phasing_samples=5)
    html_path = write_machine_report(res, tmp_path / "m.html")
    text = html_path.read_text(encoding="utf-8")
    assert "DC bus over the machine cycle" in text and "Bill of materials" in text and "motor Z" in text
    assert "<script src=" not in text  # self-contained
    pdf = write_machine_report(res, tmp_path / "m.pdf")
    assert pdf.read_bytes().startswith(b"%PDF")
    with pytest.raises(InputError):
        write_machine_report(res, tmp_path / "m.txt")


def test_size_machine_is_exported_lazily() -> None:
    assert "size_machine" in drivetrain.__all__
    assert drivetrain.size_machine(TWO, phasing_samples=1).machine.name == "two axes"


def test_the_documented_machine_file_is_valid(tmp_path: Path) -> None:
    import re

    text = (ROOT / "docs" / "machine.md").read_text(encoding="utf-8")
    block = re.search(r"^```yaml\n(.*?)^```", text, re.MULTILINE | re.DOTALL)
    assert block is not None
    (tmp_path / "m.yaml").write_text(block.group(1), encoding="utf-8")
    (tmp_path / "x_axis.yaml").write_text(yaml.safe_dump(X_AXIS), encoding="utf-8")
    out = size_machine(tmp_path / "m.yaml", phasing_samples=1).to_dict()
    b = out["buses"][0]
    assert b["capacitor_energy_per_event_J"] == 10.0
    assert b["resistor_equivalent_ohm"] == pytest.approx(50.0)
    # the axis names no drive: the order sheet's drive specification is its row
    assert {r["kind"] for r in out["bill_of_materials"]} == {"motor", "drive", "braking_resistor"}


def test_one_axis_on_its_bus_reproduces_the_axis_regen_block() -> None:
    """The machine's bus path (periodic grid, trapezoid) and the axis's own regen block (its samples,
    Simpson weights) are two computations of the same energy flow: they agree to 1e-4."""
    example = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))
    z = copy.deepcopy(example["axes"][2]["axis"])
    z["drive"]["absorbable_energy"] = "5 J"
    out = size_machine({"version": 1, "cycle_time": "0.7 s", "supply": {"voltage": "400 V"}, "axes": [{"axis": z}]},
                       phasing_samples=1).to_dict()
    rg, m = out["axes"][0]["result"]["regen"], out["machine"]
    assert rg["resistor_energy_per_cycle_J"] > 0 and rg["capacitor_absorbed_J"] == m["capacitor_absorbed_J"] == 10.0
    assert m["regen_into_bus_J"] == pytest.approx(rg["energy_per_cycle_J"], rel=1e-4)
    for key in ("resistor_energy_per_cycle_J", "resistor_average_power_W"):
        assert m[key] == pytest.approx(rg[key], rel=1e-4)
    # The resistor's peak is the bus power at the instant the capacitors are full, found on the power
    # linear between samples (physics.regen): the same instant on the axis's samples and the bus grid.
    assert m["resistor_peak_power_W"] == pytest.approx(rg["resistor_peak_power_W"], rel=1e-6)
