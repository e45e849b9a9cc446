"""Electrical limits of the DC bus (issue: an answer you can order): a capacitor maximum or a chopper
switch-on voltage below the nominal bus is refused at its field; a built-in resistor below the drive's
minimum resistance is never sufficient."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from drivetrain import cli
from drivetrain.axis.model import parse_axis
from drivetrain.errors import InputError
from drivetrain.machine.model import parse_machine
from drivetrain.physics.regen import builtin_resistor_sufficient, capacitor_energy

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "examples" / "machine" / "pick_and_place.yaml"

AXIS: dict[str, Any] = {
    "axis": "lift",
    "mechanism": {"type": "hoist", "diameter": "100 mm", "load": {"mass": "20 kg"}},
    "profile": [{"move": "0.3 m", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"},
                {"move": "-0.3 m", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}],
    "motor": {"rated_torque": "5 N*m", "peak_torque": "15 N*m", "max_speed": "3000 rpm",
              "inertia": "5 kg*cm^2", "kt": "1 N*m/A", "supply_voltage": "400 V"},
    "drive": {"continuous_current": "10 A", "peak_current": "30 A", "bus_capacitance": "1000 uF",
              "bus_max_voltage": "800 V", "regen_on_voltage": "760 V"},
}


def _axis(**drive: Any) -> dict[str, Any]:
    data = copy.deepcopy(AXIS)
    data["drive"].update(drive)
    return data


def test_a_consistent_bus_is_accepted() -> None:
    axis = parse_axis(_axis())
    assert axis.drive is not None and axis.drive.bus_max_voltage == pytest.approx(800.0)


@pytest.mark.parametrize("key", ["bus_max_voltage", "regen_on_voltage"])
def test_a_bus_limit_below_the_nominal_bus_is_refused_at_its_field(key: str) -> None:
    # 400 V mains: nominal bus sqrt(2) x 400 = 565.7 V; 500 V is below it
    with pytest.raises(InputError) as err:
        parse_axis(_axis(**{key: "500 V"}))
    assert err.value.field == f"drive.{key}"
    assert "565.7 V" in err.value.rule and "nominal DC bus" in err.value.rule


def test_the_drive_s_own_bus_wins_over_the_motor_s_supply() -> None:
    # the drive states a 230 V supply (325 V bus): a 400 V capacitor limit is then consistent
    parse_axis(_axis(supply_voltage="230 V", bus_max_voltage="400 V", regen_on_voltage="380 V"))
    with pytest.raises(InputError, match=r"drive\.bus_max_voltage"):
        parse_axis(_axis(dc_bus_voltage="600 V", bus_max_voltage="590 V", regen_on_voltage="620 V"))


def test_the_cli_exits_2_naming_the_field(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "axis.yaml"
    path.write_text(yaml.safe_dump(_axis(bus_max_voltage="500 V")))
    assert cli.main(["size", str(path)]) == 2
    err = capsys.readouterr().err
    assert "drive.bus_max_voltage" in err and "Traceback" not in err


def test_capacitors_never_absorb_negative_energy_once_the_field_is_checked() -> None:
    """Why the refusal: C/2 (U_max^2 - U_nom^2) is negative for U_max below the bus it idles at."""
    assert float(capacitor_energy(1e-3, 500.0, 565.7)) < 0.0


def _machine() -> dict[str, Any]:
    return yaml.safe_load(MACHINE.read_text())


@pytest.mark.parametrize("key", ["bus_max_voltage", "regen_on_voltage"])
def test_a_machine_bus_group_below_the_mains_bus_is_refused(key: str) -> None:
    data = _machine()
    data["buses"][0][key] = "500 V"
    with pytest.raises(InputError) as err:
        parse_machine(data, base=MACHINE.parent)
    assert err.value.field == f"buses[0].{key}"


def test_a_machine_axis_drive_without_its_own_supply_is_checked_against_the_mains() -> None:
    data = _machine()
    z = next(a for a in data["axes"] if a["name"] == "Z")
    del z["axis"]["drive"]["supply_voltage"]
    z["axis"]["motor"] = {"rated_torque": 5, "peak_torque": 15, "max_speed": "3000 rpm", "inertia": 5e-4}
    z["axis"]["drive"]["bus_max_voltage"] = "500 V"
    with pytest.raises(InputError) as err:
        parse_machine(data, base=MACHINE.parent)
    assert err.value.field == "axes[2].axis.drive.bus_max_voltage"


def test_a_builtin_resistor_below_the_drive_minimum_is_not_sufficient() -> None:
    # 10 ohm built-in resistor, drive minimum 20 ohm: small powers, the window's upper bound is far away
    args = (5.0, 50.0, 30.0, 10.0, 760.0)
    assert bool(builtin_resistor_sufficient(*args))  # no minimum stated: no lower bound
    assert not bool(builtin_resistor_sufficient(*args, 20.0))
    assert bool(builtin_resistor_sufficient(*args, 10.0))  # at the minimum: inside the window
    assert bool(builtin_resistor_sufficient(*args, math.nan))
    mins = np.array([5.0, 10.0, 20.0])
    assert builtin_resistor_sufficient(5.0, 50.0, 30.0, 10.0, 760.0, mins).tolist() == [True, True, False]


def test_a_sized_axis_with_its_builtin_resistor_below_the_minimum_says_not_sufficient() -> None:
    import drivetrain

    data = _axis(min_resistance="20 ohm", builtin_resistor={"resistance": "10 ohm", "average_power": "500 W"})
    answer = drivetrain.size(parse_axis(data)).to_dict()
    assert answer["regen"]["builtin_resistor_sufficient"] is False
    data["drive"]["min_resistance"] = "5 ohm"
    assert drivetrain.size(parse_axis(data)).to_dict()["regen"]["builtin_resistor_sufficient"] is True
