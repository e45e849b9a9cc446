"""Bad axis files: one clear message naming the field path; the CLI exits 2 without a traceback."""

import subprocess
import sys
from pathlib import Path

import pytest

from drivetrain.axis.model import parse_axis
from drivetrain.axis.yaml_text import parse_yaml, read_yaml
from drivetrain.errors import InputError

GOOD_MECH = {"type": "ball_screw", "lead": "10 mm", "load": {"mass": "25 kg"}}


def _err(data: dict) -> InputError:
    with pytest.raises(InputError) as info:
        parse_axis(data)
    return info.value


@pytest.mark.parametrize(
    ("mech", "field", "words"),
    [
        ({**GOOD_MECH, "load": {"mass": "-3 kg"}}, "mechanism.load.mass", "must be > 0 kg, got -3 kg"),
        ({**GOOD_MECH, "load": {"mass": 0}}, "mechanism.load.mass", "must be > 0"),
        ({**GOOD_MECH, "lead": "0 mm"}, "mechanism.lead", "must be > 0 m"),
        ({**GOOD_MECH, "lead": "10 kg"}, "mechanism.lead", "wrong dimension"),
        ({**GOOD_MECH, "diameter": "-20 mm"}, "mechanism.diameter", "must be > 0"),
        ({**GOOD_MECH, "efficiency": 0}, "mechanism.efficiency", "must be > 0"),
        ({**GOOD_MECH, "efficiency": 1.5}, "mechanism.efficiency", "must be <= 1"),
        ({**GOOD_MECH, "back_efficiency": -1.5}, "mechanism.back_efficiency", "must be >= -1"),
        ({**GOOD_MECH, "lead": "nan mm"}, "mechanism.lead", "finite"),
        ({**GOOD_MECH, "lead": "1e20 m"}, "mechanism.lead", "absurd"),
        ({**GOOD_MECH, "type": "screw"}, "mechanism.type", "valid: 'ball_screw'"),
        ({**GOOD_MECH, "lenght": "1 m"}, "mechanism.lenght", "unknown key"),
        ({"type": "ball_screw", "load": {"mass": 1}}, "mechanism.lead", "is required"),
    ],
)
def test_mechanism_errors_name_the_field(mech: dict, field: str, words: str) -> None:
    err = _err({"mechanism": mech})
    assert err.field == field
    assert words in str(err)


def test_back_efficiency_may_be_negative() -> None:
    axis = parse_axis({"mechanism": {**GOOD_MECH, "back_efficiency": -0.3}})
    assert axis.mechanism.stage.self_locking


@pytest.mark.parametrize(
    ("trans", "field", "words"),
    [
        ({"type": "gearbox", "ratio": 0}, "transmission[0].ratio", "must be > 0"),
        ({"type": "gearbox", "ratio": -2}, "transmission[0].ratio", "must be > 0"),
        ({"type": "gearbx", "ratio": 2}, "transmission[0].type", "valid: 'gearbox'"),
        ({"type": "gearbox"}, "transmission[0]", "give ratio"),
        ({"type": "belt", "drive_diameter": "30 mm"}, "transmission[0]", "driven_diameter"),
    ],
)
def test_transmission_errors_name_the_field(trans: dict, field: str, words: str) -> None:
    err = _err({"mechanism": GOOD_MECH, "transmission": [trans]})
    assert err.field == field
    assert words in str(err)


def test_not_a_mapping() -> None:
    with pytest.raises(InputError, match="mapping"):
        parse_axis(["mechanism"])


def test_malformed_yaml_says_where() -> None:
    with pytest.raises(InputError, match="at line 3"):
        parse_yaml("axis: x\nmechanism: [unclosed\n")


def test_alias_bomb_is_refused_fast() -> None:
    lines = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for k in range(1, 9):
        prev = chr(ord("a") + k - 1)
        cur = chr(ord("a") + k)
        lines.append(f"{cur}: &{cur} [{', '.join(['*' + prev] * 9)}]")
    with pytest.raises(InputError, match="alias"):
        parse_yaml("\n".join(lines))


def test_huge_file_is_refused(tmp_path: Path) -> None:
    big = tmp_path / "big.yaml"
    with big.open("w") as f:
        f.write("axis: x\n")
        f.write("# " + "x" * 2_000_000 + "\n")
    with pytest.raises(InputError, match="too large"):
        read_yaml(big)


def test_missing_file() -> None:
    with pytest.raises(InputError, match="cannot be read"):
        read_yaml("/nonexistent/axis.yaml")


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "drivetrain.cli", *args], capture_output=True, text=True,
                          timeout=120)


def test_cli_exits_2_without_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("mechanism: {type: ball_screw, lead: 10 mm, load: {mass: -3 kg}}\nprofile: []\n")
    proc = _cli("size", str(bad))
    assert proc.returncode == 2
    assert "mechanism.load.mass: must be > 0 kg, got -3 kg" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_cli_malformed_yaml_exits_2(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("mechanism: {type: ball_screw\n")
    proc = _cli("size", str(bad))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and "YAML" in proc.stderr


def test_absurdly_small_positive_size_is_an_input_error() -> None:
    err = _err({"mechanism": {"type": "belt", "diameter": 5e-324, "load": {"mass": 1}}})
    assert err.field == "mechanism.diameter" and "absurd" in str(err)
