"""The data of YAML files read before (axis/yaml_cache.py): the same data, types and shared values as
the loader gives; a refused text is refused each time; a damaged entry is read again from the text."""

from __future__ import annotations

import datetime
import pickle
from pathlib import Path

import pytest

from drivetrain.axis import yaml_cache
from drivetrain.axis.yaml_text import parse_yaml, read_yaml
from drivetrain.errors import InputError

ROOT = Path(__file__).resolve().parents[2]

TEXT = """\
name: typed
when: 2026-11-24
at: 2026-11-24 19:40:00
1: one
nan: .nan
big: 123456789012345678901234567890
neg_zero: -0.0
flags: [yes, no, ~, true]
base: &b {mass: 25 kg, friction: 0.05}
copy: *b
set: !!set {a, b}
bytes: !!binary aGVsbG8=
"""


@pytest.fixture(autouse=True)
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("DRIVETRAIN_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache" / "yaml"


def _same(a: object, b: object) -> None:
    assert type(a) is type(b)
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b)
        for k in a:
            _same(a[k], b[k])
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _same(x, y)
    elif isinstance(a, float) and a != a:
        assert b != b
    elif isinstance(a, (set, frozenset)):  # equal sets may list their items in another order (string hashes)
        assert a == b
    else:
        assert a == b and repr(a) == repr(b)


@pytest.mark.parametrize("name", [*sorted(p.name for p in (ROOT / "examples").glob("*.yaml")), "typed"])
def test_a_file_read_again_gives_the_loaders_data(tmp_path: Path, cache: Path, name: str) -> None:
    path = ROOT / "examples" / name if name != "typed" else tmp_path / "typed.yaml"
    if name == "typed":
        path.write_text(TEXT, encoding="utf-8")
    first = read_yaml(path)
    assert len(list(cache.glob("*.pickle"))) == 1
    again = read_yaml(path)
    assert again is not first
    _same(parse_yaml(path.read_text(encoding="utf-8")), again)
    if name == "typed":
        assert isinstance(again["when"], datetime.date) and again["set"] == {"a", "b"}
        assert again["copy"] is again["base"]  # the alias shares its value, as the loader's data does


def test_a_refused_text_is_refused_each_time(tmp_path: Path, cache: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("a: [1, 2\n", encoding="utf-8")
    for _ in range(2):
        with pytest.raises(InputError, match="not valid YAML"):
            read_yaml(path)
    assert not cache.exists() or not list(cache.glob("*.pickle"))


def test_a_damaged_entry_is_read_from_the_text(tmp_path: Path, cache: Path) -> None:
    path = tmp_path / "a.yaml"
    path.write_text("a: 1\nb: [x, y]\n", encoding="utf-8")
    read_yaml(path)
    (entry,) = cache.glob("*.pickle")
    for content in (b"", b"garbage", entry.read_bytes()[:10]):
        entry.write_bytes(content)
        assert read_yaml(path) == {"a": 1, "b": ["x", "y"]}


def test_another_text_is_another_entry(tmp_path: Path, cache: Path) -> None:
    path = tmp_path / "a.yaml"
    for k in range(3):
        path.write_text(f"a: {k}\n", encoding="utf-8")
        assert read_yaml(path) == {"a": k}
    assert len(list(cache.glob("*.pickle"))) == 3
    assert yaml_cache.get("a: 7\n") == (False, None)


def test_an_entry_naming_a_class_that_moved_is_read_from_the_text(tmp_path: Path, cache: Path) -> None:
    """An entry written by another version that names a class by a module path that no longer exists (the
    axis file's models moved from physics/ to axis/) is not an answer: the text is read again."""
    path = tmp_path / "a.yaml"
    path.write_text("mechanism: {type: belt}\n", encoding="utf-8")
    read_yaml(path)
    (entry,) = cache.glob("*.pickle")
    key = entry.stem.encode()
    stale = b"(V" + key + b"\ncdrivetrain.physics.mechanisms.belt\nBeltSpec\nt."  # (key, BeltSpec), protocol 0
    with pytest.raises(ModuleNotFoundError):
        pickle.loads(stale)
    entry.write_bytes(stale)
    assert read_yaml(path) == {"mechanism": {"type": "belt"}}
