"""Unit factors remembered on disk (unit_cache): the same SI values as pint, per installation."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from drivetrain import unit_cache, units


@pytest.fixture
def fresh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv(unit_cache.ENV_CACHE_DIR, str(tmp_path))
    monkeypatch.setattr(unit_cache, "_factors", None)
    monkeypatch.setattr(unit_cache, "_path", None)
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()
    yield tmp_path
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()


@pytest.mark.parametrize(("text", "quantity", "si"), [("12 mm", "length", 0.012), ("2 kg*cm^2", "inertia", 2e-4),
                                                      ("3000 rpm", "angular_speed", 314.1592653589793),
                                                      ("90 deg", "angle", 1.5707963267948966)])
def test_a_remembered_factor_gives_the_value_pint_gives(fresh: Path, text: str, quantity: str, si: float) -> None:
    first = units.parse(text, quantity, "f")
    (file,) = fresh.glob("units-*.json")
    unit = text.split(" ", 1)[1]
    assert f"{quantity}|{unit}" in json.loads(file.read_text())
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()
    unit_cache._factors = None  # read back from the file
    assert units.parse(text, quantity, "f") == first == pytest.approx(si, rel=1e-12)


def test_the_file_is_what_is_read(fresh: Path) -> None:
    units.parse("1 mm", "length", "f")
    (file,) = fresh.glob("units-*.json")
    file.write_text(json.dumps({"length|mm": [0.5, 0.0]}))
    unit_cache._factors = None
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()
    assert units.parse("2 mm", "length", "f") == 1.0


@pytest.mark.parametrize("content", ["not json", '{"length|mm": [1, "x"]}', '{"length|mm": [NaN, 0.0]}', "[1, 2]"])
def test_a_damaged_file_is_ignored(fresh: Path, content: str) -> None:
    units.parse("1 mm", "length", "f")
    (file,) = fresh.glob("units-*.json")
    file.write_text(content)
    unit_cache._factors = None
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()
    assert units.parse("2 mm", "length", "f") == 0.002


def test_an_unwritable_folder_leaves_parsing_as_it_was(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv(unit_cache.ENV_CACHE_DIR, str(blocker / "sub"))
    monkeypatch.setattr(unit_cache, "_factors", None)
    monkeypatch.setattr(unit_cache, "_path", None)
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()
    assert units.parse("7 mm", "length", "f") == pytest.approx(0.007)
    units._unit_factor.cache_clear()
    units._parse_cached.cache_clear()


def test_a_run_with_remembered_units_never_imports_pint(fresh: Path) -> None:
    code = "import sys; from drivetrain.units import parse; parse('5 mm', 'length', 'f'); print('pint' in sys.modules)"
    env = {"DRIVETRAIN_CACHE_DIR": str(fresh), "PYTHONPATH": str(Path(units.__file__).parents[1])}
    runs = [subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout
            for _ in range(2)]
    assert [r.strip() for r in runs] == ["True", "False"]
