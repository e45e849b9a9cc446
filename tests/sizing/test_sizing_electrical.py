"""The electrical half wired into sizing: JSON keys, checks, blocks, and bad input naming the field."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from drivetrain import cli
from drivetrain.cli import commands
from drivetrain.errors import InputError
from drivetrain.physics import motor_electrical, regen
from drivetrain.sizing.pipeline import size

RPM = 2 * math.pi / 60

Z_LIFT: dict[str, Any] = {
    "axis": "Z lift",
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "600 mm",
                  "efficiency": 0.9, "incline": "90 deg", "load": {"mass": "40 kg"}},
    "profile": [{"move": "300 mm", "time": "0.6 s", "accel": "0.15 s"}, {"dwell": "0.3 s"},
                {"move": "-300 mm", "time": "0.6 s", "accel": "0.15 s"}, {"dwell": "0.3 s"}],
    "motor": {"id": "1FT7044-5AK7", "rated_rise": "100 K"},
    "drive": {"id": "test drive", "vendor": "test", "continuous_current": "9 A", "peak_current": "18 A",
              "peak_time": "0.25 s", "supply_voltage": "400 V", "bus_capacitance": "110 uF",
              "bus_max_voltage": "720 V", "regen_on_voltage": "700 V", "min_resistance": "40 ohm"},
    "environment": {"ambient": "45 degC", "altitude": "1500 m"},
}


def axis(**changes: Any) -> dict[str, Any]:
    data = copy.deepcopy(Z_LIFT)
    for path, value in changes.items():
        node = data
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[k]
        if value is None:
            node.pop(keys[-1], None)
        else:
            node[keys[-1]] = value
    return data


def test_electrical_keys_of_a_catalog_motor_with_a_drive() -> None:
    result = size(axis())
    out = result.to_dict()
    m = out["motor"]
    assert m["envelope_source"] == "electrical"
    assert m["supply_voltage_V"] == 400.0
    assert m["dc_bus_voltage_V"] == pytest.approx(400.0 * math.sqrt(2))
    assert m["torque_constant_NmA"] == 0.88  # the shipped Siemens row
    names = {c["name"] for c in m["checks"]}
    assert {"motor_rms_current", "motor_peak_current", "peak_torque_at_supply_voltage",
            "winding_temperature_rise"} <= names
    # the current is the torque over Kt(T), Kt falling from the rated (2 N m) to the peak point (23 N m, 30 A)
    t_m = result.duty.motor_torque(result.axis.motor.inertia)
    sat = motor_electrical.Saturation(np.array(2.0), np.array(23.0), np.array(30.0))
    peak = float(np.max(np.abs(t_m)))
    assert peak > 2.0
    assert m["peak_current_A"] == pytest.approx(float(motor_electrical.current_from_torque(peak, 0.88, sat)),
                                                rel=1e-12)
    assert m["peak_current_A"] > peak / 0.88
    # derating: Kollmorgen rule at 45 degC, 1500 m
    assert m["derating_factor"] == pytest.approx(0.95 * 0.94)
    assert m["winding_allowed_rise_K"] == pytest.approx(100.0 * (0.95 * 0.94) ** 2)
    assert 0.0 < m["winding_mean_rise_K"] <= m["winding_temperature_rise_K"]
    assert out["drive"]["id"] == "test drive"
    assert out["drive"]["ok"] is True
    assert {c["name"] for c in out["drive"]["checks"]} == {"drive_rms_current", "drive_peak_current", "drive_i2t"}
    rg = out["regen"]
    assert rg["shaft_energy_per_cycle_J"] == pytest.approx(m["regen_energy_J"], rel=1e-12)
    assert rg["energy_per_cycle_J"] < rg["shaft_energy_per_cycle_J"]
    e_c = float(regen.capacitor_energy(110e-6, 720.0, 400.0 * math.sqrt(2)))
    assert rg["capacitor_energy_per_event_J"] == pytest.approx(e_c)
    assert rg["capacitor_absorbed_J"] + rg["resistor_energy_per_cycle_J"] == pytest.approx(rg["energy_per_cycle_J"])
    assert rg["resistor_average_power_W"] == pytest.approx(rg["resistor_energy_per_cycle_J"] / 1.8)
    assert rg["resistor_min_ohm"] == 40.0
    assert rg["resistor_max_ohm"] == pytest.approx(700.0**2 / rg["resistor_peak_power_W"])
    assert rg["builtin_resistor_sufficient"] is None
    assert len(rg["events"]) == 2
    assert result.ok
    json.dumps(commands.jsonable(out))


def test_continuous_current_falls_from_stall_to_rated_with_the_mean_speed() -> None:
    """1FT7044-5AK7: I_0 5.7 A, I_N 2.5 A at 6000 rpm; the Z lift's mean speed is 2000 rpm."""
    out = size(axis(environment=None)).to_dict()
    m = out["motor"]
    assert out["mean_speed_rpm"] == pytest.approx(2000.0, rel=1e-9)
    assert m["continuous_current_A"] == pytest.approx(5.7 + (2.5 - 5.7) * 2000.0 / 6000.0, rel=1e-9)
    check = next(c for c in m["checks"] if c["name"] == "motor_rms_current")
    assert check["available"] == pytest.approx(m["continuous_current_A"], rel=1e-12)  # 40 degC, sea level: no derating


def test_the_supply_curve_is_the_voltage_limited_curve() -> None:
    m = size(axis()).to_dict()["motor"]
    curve = m["supply_curve"]
    ke = motor_electrical.ke_si(57.0, "ll_rms")
    sat = motor_electrical.Saturation(np.array(2.0), np.array(23.0), np.array(30.0))
    expect = motor_electrical.torque_speed_curve(np.array(curve["speed_rad_s"]), 0.88, ke, 0.61, 0.0042, 3,
                                                 400.0 * math.sqrt(2), 5.7, 18.0, sat)
    np.testing.assert_allclose(curve["peak_torque_Nm"], np.minimum(expect.peak[0], 23.0), rtol=1e-12)
    assert curve["peak_torque_Nm"][-1] == 0.0  # beyond the no-load speed


def test_without_electrical_data_nothing_is_added() -> None:
    out = size(axis(motor={"id": "1FT7042-5AF7"}, drive=None, environment=None)).to_dict()
    assert out["motor"]["envelope_source"] == "derived"
    assert "rms_current_A" not in out["motor"]
    assert "drive" not in out and "regen" not in out


def test_a_motor_with_only_kt_gets_currents_but_no_voltage_envelope() -> None:
    out = size(axis(motor={"id": "SGM7J-04A"}, drive=None)).to_dict()
    m = out["motor"]
    assert m["envelope_source"] == "derived"
    assert m["rms_current_A"] > 0
    assert m["winding_temperature_rise_K"] is None  # no rated rise known
    assert out["regen"]["energy_per_cycle_J"] == pytest.approx(out["regen"]["shaft_energy_per_cycle_J"])


def test_a_weak_drive_fails_and_says_why() -> None:
    result = size(axis(drive__continuous_current="1 A", drive__peak_current="2 A"))
    out = result.to_dict()
    assert out["drive"]["ok"] is False
    failing = {c["name"] for c in out["drive"]["checks"] if not c["ok"]}
    assert {"drive_rms_current", "drive_peak_current", "drive_i2t"} <= failing
    assert not result.ok


def test_a_low_bus_voltage_fails_the_torque_at_speed() -> None:
    """On a 48 V bus the 1FT7044-5AK7 (57 V/krpm) cannot reach 4000 rpm: the at-speed check fails."""
    out = size(axis(drive__supply_voltage=None, drive__dc_bus_voltage="48 V")).to_dict()
    check = next(c for c in out["motor"]["checks"] if c["name"] == "peak_torque_at_supply_voltage")
    assert check["ok"] is False
    assert check["available"] == 0.0
    assert out["motor"]["ok"] is False
    assert "peak_torque_at_supply_voltage" in out["motor"]["failed"]


def test_cli_prints_the_electrical_lines(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import yaml

    path = tmp_path / "z.yaml"
    path.write_text(yaml.safe_dump(axis()), encoding="utf-8")
    assert cli.main(["size", str(path)]) == 0
    text = capsys.readouterr().out
    assert "envelope: electrical" in text
    assert "motor current: RMS" in text
    assert "winding temperature rise" in text
    assert "drive test drive: OK" in text
    assert "braking resistor" in text


BAD = [
    ({"drive__peak_current": "5 A"}, "drive"),
    ({"drive__continuous_current": "9 kg"}, "drive.continuous_current"),
    ({"drive__colour": "red"}, "drive.colour"),
    ({"motor": {"inertia": "5e-4 kg*m^2", "rated_torque": "2 N*m", "peak_torque": "6 N*m",
                "max_speed": "3000 rpm"}}, "motor.kt"),
    ({"motor__ke": 57}, "motor"),
    ({"motor__ke_basis": "rms"}, "motor.ke_basis"),
    ({"motor__resistance": "-1 ohm"}, "motor.resistance"),
    ({"motor__pole_pairs": 0}, "motor.pole_pairs"),
    ({"environment__altitude": "20 km"}, "environment.altitude"),
    ({"environment__ambient": "70 degC"}, "environment.ambient"),
    ({"environment__derating": "siemens_1ft7"}, "environment.altitude"),
    ({"motor__insulation_class": "Z"}, "motor.insulation_class"),
]


@pytest.mark.parametrize(("changes", "field"), BAD, ids=[f for _, f in BAD])
def test_bad_electrical_input_names_the_field(changes: dict[str, Any], field: str, tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    import yaml

    with pytest.raises(InputError) as err:
        size(axis(**changes))
    assert err.value.field == field or err.value.field.startswith(field + ".")
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(axis(**changes)), encoding="utf-8")
    assert cli.main(["size", str(path)]) == 2
    assert f"error: {field}" in capsys.readouterr().err


def test_a_drive_without_a_motor_is_refused() -> None:
    data = axis()
    del data["motor"]
    with pytest.raises(InputError, match="drive"):
        size(data)


def test_a_drive_with_a_selection_is_checked_for_every_candidate() -> None:
    data = axis(motor={"select": {"vendor": "siemens", "flange": "96 mm", "gearbox": "none"}})
    r = size(data)
    assert r.candidates and all(c.drive.basis == "given in the axis file" for c in r.candidates)
