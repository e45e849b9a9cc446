"""Seeded fuzzing of the classes of issue 30: files that are not files, deep and huge YAML, keys given
twice, ratio chains that overflow, study sizes and seeds, and the length of error messages.

Each class draws a fixed number of cases from a fixed seed, so a run is bounded and repeatable. Every
outcome is a result or an ``InputError`` with a short, printable message: never another exception.
"""

from __future__ import annotations

import os
import random
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain.axis.model import MAX_TOTAL_RATIO, parse_axis
from drivetrain.axis.yaml_text import MAX_DEPTH, parse_yaml
from drivetrain.errors import InputError, InputErrors

ROOT = Path(__file__).resolve().parents[2]
AXIS = ROOT / "tests" / "axes" / "yaskawa_es_30w.yaml"
SEED = 30


def _short(err: InputError, limit: int = 20_000) -> None:
    text = str(err)
    assert len(text) < limit, len(text)
    text.encode("utf-8")


# ---------------------------------------------------------------------------------- files that are not files


def _path_cases(tmp_path: Path) -> list[tuple[str, str]]:
    """(path, words of the refusal) for every kind of path that is no input file."""
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    link = tmp_path / "link.yaml"
    link.symlink_to("/dev/zero")
    big = tmp_path / "big.yaml"
    big.write_bytes(b"a: 1\n" * 250_000)
    folder = tmp_path / "folder.yaml"
    folder.mkdir()
    return [("/dev/zero", "is a device"), ("/dev/null", "is a device"), ("/dev/urandom", "is a device"),
            (str(fifo), "FIFO"), (str(link), "is a device"), (str(big), "too large"), (str(folder), "directory"),
            ("a\x00b.yaml", "NUL byte"), ("x" * 5000, "longer than"), (str(tmp_path / "none.yaml"), "no such file"),
            ("", "is empty|directory")]


def test_fuzz_every_reader_refuses_every_path_that_is_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.axis.model import load_axis
    from drivetrain.catalog import db
    from drivetrain.catalog.importer import import_file
    from drivetrain.machine.model import load_machine
    from drivetrain.study import load_study

    monkeypatch.setenv(db.ENV_DATA_DIR, str(tmp_path / "data"))
    readers = [load_axis, load_machine, load_study, lambda p: import_file(p, "motor")]
    rng = random.Random(SEED)
    cases = _path_cases(tmp_path)
    for _ in range(40):
        path, words = rng.choice(cases)
        reader = rng.choice(readers)
        with pytest.raises(InputError) as err:
            reader(path)
        assert any(w in err.value.rule for w in words.split("|")), (path[:40], err.value)
        _short(err.value, 600)


def test_fuzz_a_study_base_and_a_machine_include_that_are_no_files(tmp_path: Path) -> None:
    from drivetrain.machine.model import parse_machine
    from drivetrain.study import parse_study

    rng = random.Random(SEED)
    cases = _path_cases(tmp_path)
    for _ in range(20):
        path, words = rng.choice(cases)
        if not path:
            continue
        text = yaml.safe_dump({"study": 1, "base": path, "parameters": {"mechanism.lead": [5]}})
        with pytest.raises(InputError) as err:
            parse_study(text)
        assert err.value.field == "base" and any(w in err.value.rule for w in words.split("|"))
        machine = {"version": 1, "cycle_time": 1, "supply": {"voltage": 400}, "axes": [{"include": path}]}
        with pytest.raises(InputError) as err:
            parse_machine(machine)
        assert err.value.field == "axes[0].include" and any(w in err.value.rule for w in words.split("|"))


# ---------------------------------------------------------------------------------- deep and huge YAML


def _nested(rng: random.Random, block: int, flow: int) -> str:
    """A document of ``block`` block mappings holding ``flow`` flow collections, one inside the other."""
    inner = rng.choice(["1", "x", "'q'"])
    for _ in range(flow):
        inner = rng.choice(["[{}]", "{{k: {}}}", "[1, {}]", "{{a: 1, b: {}}}"]).format(inner)
    if block == 0:
        return inner
    lines = ["  " * i + f"k{i}:" for i in range(block - 1)]
    return "\n".join([*lines, "  " * (block - 1) + f"k{block - 1}: {inner}"]) + "\n"


def test_fuzz_nesting_in_block_and_flow_style() -> None:
    rng = random.Random(SEED)
    for _ in range(60):
        depth = rng.choice([rng.randint(1, MAX_DEPTH), rng.randint(MAX_DEPTH + 1, 3 * MAX_DEPTH),
                            rng.randint(1000, 30_000)])
        block = rng.randint(0, min(depth, 2 * MAX_DEPTH))
        text = _nested(rng, block, depth - block)
        try:
            data = parse_yaml(text)
        except InputError as exc:
            assert exc.field == "file" and "nested too deeply" in exc.rule and depth > MAX_DEPTH, (depth, exc)
            _short(exc, 300)
            continue
        assert depth <= MAX_DEPTH and data == yaml.safe_load(text)


def test_fuzz_sizes_near_the_value_bound(monkeypatch: pytest.MonkeyPatch) -> None:
    """Flat and nested lists and mappings around the value bound (lowered to 3000 to stay quick; the
    bound itself is test_hostile_files.py's)."""
    from drivetrain.axis import yaml_text as model

    bound = 3000
    monkeypatch.setattr(model, "MAX_NODES", bound)
    rng = random.Random(SEED)
    for _ in range(40):
        n = rng.choice([bound // 2, bound - 5, bound + 5, 2 * bound])
        shape = rng.choice(["list", "map", "nested"])
        if shape == "list":
            text, values = "[" + ",".join(["1"] * n) + "]", n + 1
        elif shape == "map":
            text, values = "{" + ",".join(f"k{i}: 1" for i in range(n // 2)) + "}", 2 * (n // 2) + 1
        else:
            text, values = "[" + ",".join(["[1, 2, 3]"] * (n // 4)) + "]", 4 * (n // 4) + 1
        try:
            parse_yaml(text)
        except InputError as exc:
            assert values > bound and "alias" not in exc.rule and f"more than {bound} values" in exc.rule
            continue
        assert values <= bound


# ---------------------------------------------------------------------------------- keys given twice


def test_fuzz_duplicate_keys_in_block_and_flow_mappings() -> None:
    rng = random.Random(SEED)
    for _ in range(80):
        keys = [rng.choice(["mass", "lead", "a", "1", "'mass'", '"lead"', "x y"]) for _ in range(rng.randint(1, 6))]
        flow = rng.random() < 0.5
        body = ("{" + ", ".join(f"{k}: {i}" for i, k in enumerate(keys)) + "}" if flow
                else "\n".join(f"  {k}: {i}" for i, k in enumerate(keys)))
        text = f"outer:{' ' if flow else chr(10)}{body}\n"
        names = [k.strip("'\"") for k in keys]
        twice = len(set(names)) < len(names)
        try:
            data = parse_yaml(text)
        except InputError as exc:
            assert twice and "given twice" in exc.rule and exc.field.startswith("outer.")
            assert exc.field.removeprefix("outer.") in names
            continue
        assert not twice and len(data["outer"]) == len(names)


# ---------------------------------------------------------------------------------- overflow


def test_fuzz_ratio_chains_end_in_a_result_or_a_field_error() -> None:
    import drivetrain

    base = yaml.safe_load(AXIS.read_text(encoding="utf-8"))
    rng = random.Random(SEED)
    for _ in range(25):
        ratios = [10 ** rng.uniform(-15, 15) for _ in range(rng.randint(1, 12))]
        axis = {**base, "transmission": [{"type": "gearbox", "ratio": r} for r in ratios]}
        product = 1.0
        inside = True
        for r in ratios:
            product *= r
            inside = inside and 1 / MAX_TOTAL_RATIO <= product <= MAX_TOTAL_RATIO
        try:
            result = drivetrain.size(parse_axis(axis))
        except InputError as exc:
            _short(exc, 400)
            assert exc.field.startswith(("transmission[", "mechanism", "motor", "profile")), exc
            continue
        assert inside
        result.to_dict()


# ---------------------------------------------------------------------------------- studies


def test_fuzz_study_sizes_and_seeds_are_checked_before_allocating() -> None:
    from drivetrain.study import parse_study
    from drivetrain.study.spec import MAX_PARAMETER_VALUES, MAX_SEED, MAX_STUDY_VARIANTS

    rng = random.Random(SEED)
    numbers: list[Any] = [1, 2, 10, 10**6, 10**6 + 1, 10**9, 10**18, 2**64, -1, 0, 1e18, 1e-12, 1e-300, 1e300]
    for _ in range(40):
        k = rng.randint(1, 3)
        params: dict[str, Any] = {}
        for path in ["mechanism.load.friction_torque", "profile[0].time", "profile[0].accel"][:k]:
            kind = rng.choice(["num", "step", "dist"])
            if kind == "num":
                params[path] = {"start": 0.01, "stop": 0.02, "num": rng.choice(numbers)}
            elif kind == "step":
                params[path] = {"start": 0.01, "stop": rng.choice([0.02, 1e300]), "step": rng.choice(numbers)}
            else:
                params[path] = {"distribution": "uniform", "low": 0.01, "high": 0.02}
        design = "grid" if all("num" in p or "step" in p for p in params.values()) else rng.choice(
            ["random", "lhs", "sobol", "saltelli", "morris"])
        body = {"study": 1, "base": str(AXIS), "parameters": params, "design": design,
                "seed": rng.choice([0, 1, MAX_SEED, MAX_SEED + 1, 2**64, -1])}
        if design != "grid":
            body["samples"] = rng.choice(numbers)
        try:
            study = parse_study(yaml.safe_dump(body), yes=rng.random() < 0.5)
        except InputError as exc:
            _short(exc, 500)
            continue
        assert 0 <= study.spec.seed <= MAX_SEED
        assert all(len(p.values or ()) <= MAX_PARAMETER_VALUES for p in study.parameters)
        assert study.n_variants() <= MAX_STUDY_VARIANTS


# ---------------------------------------------------------------------------------- message length


def test_fuzz_messages_listing_user_items_stay_short(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.catalog import db
    from drivetrain.catalog.importer import import_file
    from drivetrain.machine.model import parse_machine

    monkeypatch.setenv(db.ENV_DATA_DIR, str(tmp_path / "data"))
    base = yaml.safe_load(AXIS.read_text(encoding="utf-8"))
    rng = random.Random(SEED)
    for case in range(16):
        n = rng.choice([3, 50, 190, 201, 5000, 30_000])
        width = rng.choice([1, 20, 2000])
        headers = ["id", "vendor"] + [f"u{i}{'x' * width}" for i in range(n)]
        path = tmp_path / f"h{case}.csv"
        path.write_text(",".join(headers) + "\n" + ",".join(["A", "B"] + ["1"] * n) + "\n", encoding="utf-8")
        with pytest.raises(InputError) as err:
            import_file(path, "motor")
        _short(err.value, 30_000)
        if isinstance(err.value, InputErrors):
            assert len(str(err.value).splitlines()) <= 21
        name = "n" * rng.choice([1, 1000, 100_000])
        machine = {"version": 1, "cycle_time": 2, "supply": {"voltage": 400},
                   "axes": [{"name": f"{name}{i}", "axis": base} for i in range(rng.randint(1, 8))],
                   "buses": [{"axes": [f"{name}-missing"]}]}
        with pytest.raises(InputError) as err:
            parse_machine(machine)
        _short(err.value, 1000)
