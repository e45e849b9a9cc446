"""Axis files that name catalog parts: a motor by id, a gearbox by catalog row."""

import math

import pytest

from drivetrain import catalog
from drivetrain.axis.model import parse_axis
from drivetrain.errors import InputError

MECH = {"type": "ball_screw", "lead": "10 mm", "load": {"mass": 20}}


def test_gearbox_from_the_catalog_brings_its_datasheet_values() -> None:
    row = catalog.get("GPB042-L1-i5")
    axis = parse_axis({"mechanism": MECH, "transmission": [{"type": "gearbox", "catalog": "GPB042-L1-i5"}]})
    st = axis.transmission[0]
    assert st.ratio == row["ratio"] == 5
    assert st.efficiency == row["efficiency"]
    assert st.inertia_in == row["inertia_input_kgm2"]
    # catalog stiffness is at the output: K / i^2 at the input; backlash x i
    assert st.stiffness == pytest.approx(row["torsional_stiffness_Nm_per_rad"] / 25)
    assert st.backlash == pytest.approx(row["backlash_rad"] * 5)
    assert row["backlash_rad"] == pytest.approx(5 * math.pi / (180 * 60))  # 5 arcmin, class P2


def test_unknown_catalog_gearbox_names_the_field() -> None:
    with pytest.raises(InputError) as err:
        parse_axis({"mechanism": MECH, "transmission": [{"type": "gearbox", "catalog": "GPB042-L1-i55"}]})
    assert err.value.field == "transmission[0].catalog"


def test_motor_by_id_with_an_override() -> None:
    axis = parse_axis({"mechanism": MECH, "motor": {"id": "HG-KR43", "inertia": "0.42 kg*cm^2"}})
    assert axis.motor is not None
    assert axis.motor.rated_torque == 1.3 and axis.motor.inertia == pytest.approx(0.42e-4)


def test_unknown_motor_id_suggests_close_ones() -> None:
    with pytest.raises(InputError) as err:
        parse_axis({"mechanism": MECH, "motor": {"id": "HG-KR44"}})
    assert err.value.field == "motor.id" and "HG-KR43" in str(err.value)
