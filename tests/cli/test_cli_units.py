"""``--units`` in the CLI tables: imperial converts every torque, inertia, length and force the tables print,
through the report's one unit table; SI (the default) prints as it always has.

Conversion factors checked by hand against exact definitions (NIST SP 811 (2008), appendix B.8):
1 in = 0.0254 m, 1 lb = 0.45359237 kg, 1 lbf = 4.4482216152605 N, so
1 lbf*in = 0.11298482902761668 N*m and 1 lb*in^2 = 2.926396534292e-4 kg*m^2 = 2.926396534292 kg*cm^2.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from drivetrain import cli
from drivetrain.study.cli import objective_text
from tests.sizing.test_sizing_electrical import Z_LIFT as ELECTRICAL_Z_LIFT

ROOT = Path(__file__).resolve().parents[2]
BALL = ROOT / "examples" / "ball_screw.yaml"
GANTRY = ROOT / "examples" / "belt_gantry_3m.yaml"
LBF_IN = 4.4482216152605 * 0.0254  # [N*m] one pound-force inch
LB_IN2_KGCM2 = 0.45359237 * 2.54**2  # [kg*cm^2] one pound inch squared
IN = 0.0254  # [m]
LBF_PER_IN = 4.4482216152605 / 0.0254  # [N/m] one pound-force per inch

# A given catalog motor with electrical data and a drive, so the check and electrical blocks print: the
# electrical tests' Z lift at the default environment.
Z_LIFT = {k: v for k, v in ELECTRICAL_Z_LIFT.items() if k != "environment"}


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    code = cli.main(list(args))
    return code, capsys.readouterr().out


def number(text: str, label: str, unit: str) -> float:
    """The number printed before ``unit`` on the table row starting with ``label``."""
    row = next(line for line in text.splitlines() if label in line)
    m = re.search(r"(-?[\d.]+(?:e[-+]?\d+)?) " + re.escape(unit), row)
    assert m is not None, f"no value in {unit} on the row {row!r}"
    return float(m.group(1))


def test_size_imperial_converts_the_demand_table(capsys: pytest.CaptureFixture[str]) -> None:
    code_si, si = run(capsys, "size", str(BALL))
    code_imp, imp = run(capsys, "size", str(BALL), "--units", "imperial")
    assert code_si == code_imp
    rms_si = number(si, "RMS torque", "N*m")
    rms_imp = number(imp, "RMS torque", "lbf*in")
    # by hand: 0.4646 N*m / 0.112985 N*m per lbf*in = 4.112 lbf*in
    assert rms_si == pytest.approx(0.4646, abs=5e-5)
    assert rms_imp == pytest.approx(4.112, abs=5e-4)
    assert rms_imp == pytest.approx(rms_si / LBF_IN, rel=2e-4)  # both printed to 4 digits
    j_si = number(si, "│ load inertia ", "kg*cm^2")
    j_imp = number(imp, "│ load inertia ", "lb*in^2")
    assert j_imp == pytest.approx(j_si / LB_IN2_KGCM2, rel=5e-4)
    assert number(imp, "holding torque", "lbf*in") == pytest.approx(number(si, "holding torque", "N*m") / LBF_IN,
                                                                    rel=5e-4)
    flange = re.search(r"HG-KR23 .*?(\d+(?:\.\d+)?) in ", imp)
    assert flange is not None and float(flange.group(1)) == pytest.approx(60 / 25.4, abs=0.005)  # a 60 mm flange
    demand = imp.split("candidates:")[0]
    assert "N*m" not in demand and "kg*cm^2" not in demand
    # what is the same in both systems stays: shaft speed, power, energy
    assert number(imp, "max / mean speed", "rpm") == number(si, "max / mean speed", "rpm")
    assert number(imp, "regenerated energy", "J") == number(si, "regenerated energy", "J")
    # the failing checks of the next smaller motor are rebuilt in the system's units (which motor that is depends
    # on the catalog: a torque failure, where it has one, prints lbf*in; test_failure_sentence_... pins the sentence)
    nxt = imp.split("next smaller motor", 1)[1].split("optimal ratio", 1)[0]
    assert "N*m" not in nxt
    assert all("lbf*in" in line for line in nxt.splitlines() if "torque: required" in line)


def test_failure_sentence_is_rebuilt_in_imperial_units() -> None:
    """A failing torque check (the SI sentence of drivetrain.sizing.reasons) is printed in lbf*in, by hand:
    0.5723 N*m / 0.112985 = 5.065 lbf*in, 0.48 N*m / 0.112985 = 4.248 lbf*in; the margin stays as it is."""
    from drivetrain.cli.quantities import TableUnits
    from drivetrain.cli.sizing import _failure
    from drivetrain.sizing.answer import CheckRow

    ch = CheckRow(name="rms_torque", required=0.5723, available=0.48, unit="N*m", margin=0.48 / 0.5723 - 1, ok=False,
                  status="fail", approximate=False)
    line = _failure("rms_torque: required 0.5723 N*m > available 0.48 N*m (-16.1 %)", {"rms_torque": ch},
                    TableUnits("imperial"))
    found = re.search(r"rms_torque: required ([\d.]+) lbf\*in > available ([\d.]+) lbf\*in \(-16.1 %\)", line)
    assert found is not None, line
    assert float(found.group(1)) == pytest.approx(0.5723 / LBF_IN, rel=5e-4)
    assert float(found.group(2)) == pytest.approx(0.48 / LBF_IN, rel=5e-4)


def test_si_is_the_default_and_prints_as_before(capsys: pytest.CaptureFixture[str]) -> None:
    _, default = run(capsys, "size", str(BALL))
    _, si = run(capsys, "size", str(BALL), "--units", "si")
    assert default == si
    assert "lbf" not in default and "lb*in" not in default and not re.search(r"\d in\b", default)
    assert re.search(r"RMS torque\s+│\s+0\.4646 N\*m", default)
    assert re.search(r"│ load inertia\s+│\s+1\.82 kg\*cm\^2", default)


def test_given_motor_checks_and_electrical_in_imperial(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "z.yaml"
    path.write_text(yaml.safe_dump(Z_LIFT), encoding="utf-8")
    code_si, si = run(capsys, "size", str(path))
    code_imp, imp = run(capsys, "size", str(path), "--units", "imperial")
    assert code_si == code_imp == 0
    peak_si = number(si, "peak_torque", "N*m")
    assert number(imp, "peak_torque", "lbf*in") == pytest.approx(peak_si / LBF_IN, rel=5e-4)
    kt = re.search(r"Kt ([\d.]+) N\*m/A", si)
    kt_imp = re.search(r"Kt ([\d.]+) lbf\*in/A", imp)
    assert kt is not None and kt_imp is not None
    assert float(kt_imp.group(1)) == pytest.approx(float(kt.group(1)) / LBF_IN, rel=5e-4)
    # currents and speeds are the same in both systems
    assert re.search(r"motor current: RMS [\d.]+ A", imp)
    assert number(imp, "max_speed", "rpm") == number(si, "max_speed", "rpm")


def test_modes_imperial_positions_in_inches_stiffness_in_lbf_per_in(capsys: pytest.CaptureFixture[str]) -> None:
    _, si = run(capsys, "modes", str(GANTRY))
    _, imp = run(capsys, "modes", str(GANTRY), "--units", "imperial")
    worst_mm = float(re.search(r"at position (\d+) mm", si).group(1))  # type: ignore[union-attr]
    worst_in = float(re.search(r"at position ([\d.]+) in", imp).group(1))  # type: ignore[union-attr]
    assert worst_in == pytest.approx(worst_mm / 25.4, rel=5e-3)
    first_si = re.search(r"│\s+0 mm\s+│\s+[\d.]+ Hz\s+│\s+([\d.]+) N/um", si)
    first_imp = re.search(r"│\s+0 in\s+│\s+[\d.]+ Hz\s+│\s+([\d,]+) lbf/in", imp)
    assert first_si is not None and first_imp is not None
    k_si = float(first_si.group(1)) * 1e6  # [N/m]
    assert float(first_imp.group(1).replace(",", "")) == pytest.approx(k_si / LBF_PER_IN, rel=1e-2)  # 3 digits each
    # frequencies do not change with the unit system
    assert re.findall(r"[\d.]+ Hz", si) == re.findall(r"[\d.]+ Hz", imp)


def test_sweep_summary_objective_in_imperial() -> None:
    assert objective_text("rms_torque_Nm", 1.0, "imperial") == f"rms_torque = {1.0 / LBF_IN:.6g} lbf*in"
    assert objective_text("rms_torque_Nm", 1.0) == "rms_torque_Nm = 1"
    assert objective_text("rated_power_W", 200.0, "imperial") == "rated_power_W = 200"  # W stays
    assert objective_text("worst_margin", 0.25, "imperial") == "worst_margin = 0.25"


def test_one_unit_table() -> None:
    from drivetrain import units
    from drivetrain.report import display

    assert display.display_units("si").units == units.SI_UNITS
    assert display.display_units("imperial").units == units.IMPERIAL_UNITS
    assert display.display_units("imperial").to(1.0, "torque") == pytest.approx(1 / LBF_IN, rel=1e-12)
    assert display.display_units("imperial").to(1.0, "length") == pytest.approx(1 / IN, rel=1e-12)
