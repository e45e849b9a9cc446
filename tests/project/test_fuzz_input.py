"""Seeded fuzzing of the axis file and the catalog import (issue 20).

A fixed-seed mutator replaces values, keys and text of known-good inputs with the hostile cases
of the issue (power towers, huge and long numbers, lone surrogates, control and bidi characters,
deep nesting, wrong types) and random edits. Every outcome must be a result or an ``InputError``
with a printable message: never another exception. The run is bounded by a fixed number of cases.
"""

from __future__ import annotations

import copy
import json
import random
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain.axis.model import parse_axis
from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
AXES = [ROOT / "tests" / "axes" / "yaskawa_es_30w.yaml", ROOT / "tests" / "axes" / "lecture_two_inertias.yaml"]

HOSTILE: list[Any] = [
    "9**9**9 mm", "2**1024 mm", "9**9**9", "1e400 mm", "1" * 500, "1" * 5000 + " mm", 10**400, -(10**300),
    1e308, -1e308, float("inf"), float("nan"), "nan", "inf N*m", "\ud800", "10 mm\ud800", "\x00", "A\x00B",
    "\u202eABC", "", " ", "''", "two", True, None, [], {}, [[[[]]]], {"a": {"b": {"c": 1}}}, "m^99", "(((((m)))))",
    "10 mm)", "__import__('os').system('true')", "1/0 mm", "0 mm", "-1 kg", "1e-300 m", "3000 rpm", "0.5 kg*cm^2",
    "x" * 100_000, 0, -1, 1, 2**63, 1.0e300, "1.0e+300", "10 N*m/arcmin", "%", "10 %", "°", "µm", "1 1/s",
]
"""The issue's cases, and the everyday values next to them."""


def _leaves(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out: list[tuple[Any, ...]] = [path]
    if isinstance(node, dict):
        for k, v in node.items():
            out.extend(_leaves(v, (*path, k)))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out.extend(_leaves(v, (*path, i)))
    return out


def _mutate(data: Any, rng: random.Random) -> Any:
    """One structural mutation of a copy of ``data``."""
    data = copy.deepcopy(data)
    path = rng.choice(_leaves(data)[1:])
    parent = data
    for key in path[:-1]:
        parent = parent[key]
    key = path[-1]
    action = rng.random()
    if action < 0.6:
        parent[key] = copy.deepcopy(rng.choice(HOSTILE))
    elif action < 0.7 and isinstance(parent, dict):
        del parent[key]
    elif action < 0.8 and isinstance(parent, dict):
        parent[rng.choice(["", "\ud800", "x" * 1000, "type", "1", "unknown"])] = parent.pop(key)
    elif action < 0.9:
        value: Any = parent[key]
        for _ in range(rng.randint(1, 150)):
            value = [value] if rng.random() < 0.5 else {"k": value}
        parent[key] = value
    else:
        parent[key] = str(parent[key]) + rng.choice(["**9**9", "^99", "\x00", "\ud800", ")", "e999"])
    return data


def _text_mutate(text: str, rng: random.Random) -> str:
    """One edit of the text: a span replaced by a hostile fragment."""
    i = rng.randrange(len(text))
    j = min(len(text), i + rng.randint(0, 12))
    fragment = rng.choice(["[" * 200, "{" * 200, "&a", "*a", "!!python/object:os.system", "\t", ": :", "- ",
                           "9**9**9", "1" * 450, "\\ud800", '"', "'", "\x00", "\u202e", "\n  ", "#", "? "])
    return text[:i] + fragment + text[j:]


def _check(exc: InputError) -> None:
    message = str(exc)
    message.encode("utf-8")  # printable: no lone surrogate reaches the terminal
    assert message


def _size_or_error(data: Any) -> None:
    from drivetrain.sizing.pipeline import size

    try:
        axis = parse_axis(data)
        size(axis, points_per_phase=5)
    except InputError as exc:
        _check(exc)


@pytest.mark.parametrize("axis_file", AXES, ids=lambda p: p.stem)
def test_axis_file_structural_fuzz(axis_file: Path) -> None:
    base = yaml.safe_load(axis_file.read_text(encoding="utf-8"))
    rng = random.Random(20)
    for _ in range(150):
        data = _mutate(base, rng)
        if rng.random() < 0.3:
            data = _mutate(data, rng)
        try:
            text = yaml.safe_dump(data, allow_unicode=True)
        except (yaml.YAMLError, RecursionError):
            continue  # the dumper cannot write this shape; nothing a user can send
        try:
            parsed = parse_yaml(text)
        except InputError as exc:
            _check(exc)
            continue
        _size_or_error(parsed)


@pytest.mark.parametrize("axis_file", AXES, ids=lambda p: p.stem)
def test_axis_file_text_fuzz(axis_file: Path) -> None:
    text = axis_file.read_text(encoding="utf-8")
    rng = random.Random(2020)
    for _ in range(150):
        mutated = _text_mutate(text, rng)
        try:
            parsed = parse_yaml(mutated)
        except InputError as exc:
            _check(exc)
            continue
        _size_or_error(parsed)


def test_dynamics_block_fuzz() -> None:
    from drivetrain.dynamics.axis_model import model, servo_loop
    from drivetrain.dynamics.control import check_stable

    base = yaml.safe_load(AXES[1].read_text(encoding="utf-8"))
    base["dynamics"] = {"loop": {"velocity_bandwidth": "50 Hz", "notch": True, "velocity_kp": 0.5},
                        "friction": {"coulomb": "0.1 N*m"}, "cycles": 1, "load_torque": "0 N*m"}
    rng = random.Random(7)
    for _ in range(120):
        data = _mutate({"dynamics": base["dynamics"]}, rng)
        try:
            axis = parse_axis({**base, **data})
            dyn = model(axis)
            check_stable(dyn.chain, servo_loop(dyn.chain, axis.spec.dynamics or {}))
        except InputError as exc:
            _check(exc)


HEADER = "id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
ROWS = "".join(f"F-{i},ACME,1,3,3000,6000,1e-4,ACME datasheet p. 1\n" for i in range(3))
JSON_DOC = {"table": "motor", "rows": [
    {"id": f"FJ-{i}", "vendor": "A", "rated_torque [N*m]": 1, "peak_torque [N*m]": 3, "rated_speed [rpm]": 3000,
     "max_speed [rpm]": 6000, "rotor_inertia [kg*cm^2]": 1, "source": "A datasheet p. 1",
     "curve": [{"speed [rpm]": 0, "peak_torque [N*m]": 3}]} for i in range(2)]}


@pytest.fixture
def data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    from drivetrain.catalog import db

    directory = tmp_path / "data"
    directory.mkdir()
    monkeypatch.setenv(db.ENV_DATA_DIR, str(directory))
    return directory


def _import_or_error(path: Path) -> None:
    from drivetrain.catalog.importer import import_file

    try:
        import_file(path)
    except InputError as exc:
        _check(exc)


def test_catalog_csv_fuzz(tmp_path: Path, data_dir: Path) -> None:
    rng = random.Random(5)
    cells = [line.split(",") for line in (HEADER + ROWS).splitlines()]
    for n in range(100):
        table = copy.deepcopy(cells)
        for _ in range(rng.randint(1, 3)):
            r, c = rng.randrange(len(table)), rng.randrange(len(table[0]))
            value = rng.choice(HOSTILE)
            table[r][c] = value if isinstance(value, str) else json.dumps(value) if value is not None else ""
        text = "\n".join(",".join(f'"{v}"' if "," in v or "\n" in v else v for v in row) for row in table) + "\n"
        if rng.random() < 0.3:
            text = _text_mutate(text, rng)
        path = tmp_path / f"f{n}.csv"
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        _import_or_error(path)


def test_catalog_json_fuzz(tmp_path: Path, data_dir: Path) -> None:
    rng = random.Random(6)
    for n in range(100):
        doc = _mutate(JSON_DOC, rng)
        try:
            text = json.dumps(doc)
        except (ValueError, RecursionError):
            continue
        if rng.random() < 0.3:
            text = _text_mutate(text, rng)
        path = tmp_path / f"f{n}.json"
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        _import_or_error(path)
