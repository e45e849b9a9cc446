"""Hostile and extreme input (issue 20): no hang, no traceback, no unbounded memory.

Every case gets one message naming the field, the value and the rule (``InputError``); through
the command line that is exit status 2 and no traceback.
"""

from __future__ import annotations

import errno
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.cli import main
from drivetrain.errors import InputError, InputErrors, format_value
from drivetrain.units import parse

ROOT = Path(__file__).resolve().parents[2]
AXIS = ROOT / "tests" / "axes" / "yaskawa_es_30w.yaml"  # a given motor: sizing is quick
TWO_INERTIAS = ROOT / "tests" / "axes" / "lecture_two_inertias.yaml"


def axis_data() -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load(AXIS.read_text(encoding="utf-8"))
    return data


def write_axis(tmp_path: Path, data: dict[str, Any] | str, name: str = "axis.yaml") -> Path:
    path = tmp_path / name
    text = data if isinstance(data, str) else yaml.safe_dump(data, allow_unicode=True)
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    return path


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    code = main(args)
    return code, capsys.readouterr().err


# ---------------------------------------------------------------------------------- 1. units grammar

ACCEPTED = [
    ("10 mm", "length", 0.010),
    ("0.5 kg*cm^2", "inertia", 0.5e-4),
    ("3000 rpm", "angular_speed", 3000 * 2 * math.pi / 60),
    ("30 m/min", "speed", 0.5),
    ("4.5 lb*in^2", "inertia", 4.5 * 0.45359237 * 0.0254**2),
    ("1 oz*in*s^2", "inertia", 0.45359237 / 16 * 9.80665 * 0.0254),
    ("oz*in*s^2", "inertia", 0.45359237 / 16 * 9.80665 * 0.0254),
    ("3 N*m/arcmin", "torsional_stiffness", 3 * 180 * 60 / math.pi),
    ("1e-3 m", "length", 1e-3),
    ("3000 1/min", "angular_speed", 3000 * 2 * math.pi / 60),
    ("2 N m", "torque", 2.0),
    ("5 kg*m/s**2", "force", 5.0),
    ("1 kg/(m*s^2)", "pressure", 1.0),
    ("-5 mm", "length", -0.005),
]


@pytest.mark.parametrize(("text", "quantity", "expected"), ACCEPTED)
def test_every_unit_form_in_use_still_parses(text: str, quantity: str, expected: float) -> None:
    assert parse(text, quantity, "f") == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("9**9**9 mm", "cannot be raised to a power"),
        ("2**1024 mm", "cannot be raised to a power"),
        ("10 mm^99", "larger than 12"),
        ("10 (mm^9)^9", "larger than 12"),
        ("10 ((((mm))))", "levels of parentheses"),
        ("10 * 2 mm", "expected a unit"),
        ("10 2 mm", "expected a unit"),
        ("10 mm^^2", "small number"),
        ("10 mm^1e9", "small number"),
        ("__import__('os') mm", "unexpected"),
        ("1" * 41 + " mm", "more than 40 digits"),
        ("10 " + "m*" * 60 + "m", "too long"),
    ],
)
def test_quantity_text_that_computes_is_refused(text: str, words: str) -> None:
    with pytest.raises(InputError) as err:
        parse(text, "length", "mechanism.lead")
    assert err.value.field == "mechanism.lead"
    assert words in str(err.value)


def test_grammar_refuses_before_pint_sees_the_text(monkeypatch: pytest.MonkeyPatch) -> None:
    import pint

    def boom(*_: Any, **__: Any) -> None:
        raise AssertionError("pint must not parse this")

    from drivetrain.units import check_grammar

    monkeypatch.setattr(pint.UnitRegistry, "Quantity", property(boom))
    with pytest.raises(InputError):
        check_grammar("9**9**9**9 mm")


def test_axis_file_with_a_power_tower_is_a_field_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data = axis_data()
    data["mechanism"]["load"]["friction_torque"] = "9**9**9 N*m"
    code, err = run_cli(["size", str(write_axis(tmp_path, data))], capsys)
    assert code == 2
    assert err.startswith("error: mechanism.load.friction_torque: is not a quantity")


# ---------------------------------------------------------------------------------- YAML


def test_deep_yaml_is_refused_before_the_parser_recurses(tmp_path: Path) -> None:
    text = AXIS.read_text(encoding="utf-8") + "extra: " + "[" * 600 + "]" * 600 + "\n"
    with pytest.raises(InputError) as err:
        parse_yaml(text)
    assert err.value.field == "file" and "nested too deeply" in err.value.rule
    mapping = "axis: x\n" + "".join("  " * i + f"k{i}:\n" for i in range(600)) + "  " * 600 + "v: 1\n"
    with pytest.raises(InputError, match="nested too deeply"):
        parse_yaml(mapping)


@pytest.mark.parametrize(
    ("value", "field", "words"),
    [
        ("1" + "0" * 390, "mechanism.load.friction_torque", "absurd"),
        ("1" * 5000, "mechanism.load.friction_torque", "more than 400 digits"),
        ("1" + "0" * 450, "mechanism.load.friction_torque", "more than 400 digits"),
        ('"0.035 N*m\\ud800"', "mechanism.load.friction_torque", "lone surrogate"),
        ("'2**1024 N*m'", "mechanism.load.friction_torque", "cannot be raised to a power"),
    ],
)
def test_extreme_scalars_name_their_field(value: str, field: str, words: str) -> None:
    text = AXIS.read_text(encoding="utf-8").replace("0.035 N*m", value)
    with pytest.raises(InputError) as err:
        parse_axis(parse_yaml(text))
    assert err.value.field == field
    assert words in str(err.value)
    str(err.value).encode("utf-8")  # the message itself prints


def test_lone_surrogate_in_a_name_and_empty_key(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = AXIS.read_text(encoding="utf-8").replace("axis: Yaskawa Sigma-S 30 W example", 'axis: "\\ud800"')
    code, err = run_cli(["size", str(write_axis(tmp_path, text))], capsys)
    assert code == 2 and "axis: is not valid Unicode" in err and "\\ud800" in err
    with pytest.raises(InputError) as info:
        parse_axis(parse_yaml(AXIS.read_text(encoding="utf-8") + "'': 1\n"))
    assert info.value.field == "''" and "unknown key" in info.value.rule


def test_error_values_print_escaped() -> None:
    assert format_value("A\x00B") == "'A\\x00B'"
    assert format_value("\u202eABC") == "'\\u202eABC'"
    assert format_value(10**5000).startswith("an integer of about 5000 digits")
    assert str(InputError("k\x00", "bad", "x")) == "k\\x00: bad, got x"


# ---------------------------------------------------------------------------------- dynamics


@pytest.mark.parametrize(
    ("dynamics", "field", "words"),
    [
        ({"cycles": "two"}, "dynamics.cycles", "whole number"),
        ({"cycles": 1.5}, "dynamics.cycles", "whole number"),
        ({"loop": {"velocity_kp": 1.0e300}}, "dynamics.loop.velocity_kp", "absurd"),
        ({"loop": {"velocity_kp": "x"}}, "dynamics.loop.velocity_kp", "number"),
        ({"loop": {"current_bandwidth": -1}}, "dynamics.loop.current_bandwidth", "must be > 0"),
        ({"loop": {"notch": "yes"}}, "dynamics.loop.notch", "true or false"),
        ({"friction": {"coulomb": -1}}, "dynamics.friction.coulomb", ">= 0"),
        ({"step": "abc"}, "dynamics.step", "not a quantity"),
    ],
)
@pytest.mark.parametrize("command", ["simulate", "modes"])
def test_dynamics_values_are_checked_by_every_command(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dynamics: dict[str, Any], field: str, words: str,
    command: str,
) -> None:
    data = yaml.safe_load(TWO_INERTIAS.read_text(encoding="utf-8"))
    data["dynamics"] = {**(data.get("dynamics") or {}), **dynamics}
    code, err = run_cli([command, str(write_axis(tmp_path, data))], capsys)
    assert code == 2, err
    assert err.startswith(f"error: {field}:") and words in err


@pytest.mark.parametrize(("step", "words"), [("1e-4 s", "must divide the loop's sample times"),
                                             ("0.1 s", "too large")])
def test_simulation_step_errors_name_the_key_of_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], step: str, words: str
) -> None:
    data = yaml.safe_load(TWO_INERTIAS.read_text(encoding="utf-8"))
    data["dynamics"]["step"] = step
    code, err = run_cli(["simulate", str(write_axis(tmp_path, data))], capsys)
    assert code == 2 and err.startswith("error: dynamics.step:") and words in err


def test_unstable_tuned_loop_names_what_the_user_can_change() -> None:
    from drivetrain.dynamics import two_mass_chain
    from drivetrain.dynamics.control import check_stable, tune

    chain = two_mass_chain(1e-4, 5e-4, 500.0, damping=0.002)
    loop = tune(chain)
    tuned_too_high = loop.with_(velocity_kp=30 * loop.velocity_kp)
    with pytest.raises(InputError) as err:
        check_stable(chain, tuned_too_high)
    assert err.value.field == "dynamics.loop"
    assert "velocity_bandwidth" in err.value.rule and "velocity_kp" not in err.value.rule
    given = loop.with_(velocity_kp=30 * loop.velocity_kp, notes=("gains as given",))
    with pytest.raises(InputError) as err:
        check_stable(chain, given)
    assert "lower velocity_kp" in err.value.rule


# ---------------------------------------------------------------------------------- 2. simulation bound


def test_simulation_too_long_for_memory_is_refused_naming_cycles(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = AXIS.read_text(encoding="utf-8").replace("time: 1.0 s", "time: 60.0 s") + "dynamics: {cycles: 100}\n"
    code, err = run_cli(["simulate", str(write_axis(tmp_path, text))], capsys)
    assert code == 2
    assert err.startswith("error: dynamics.cycles: 100 cycles of 60.5 s") and "at most 14 cycles fit" in err


def test_simulation_of_one_huge_cycle_is_refused_naming_the_profile(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = AXIS.read_text(encoding="utf-8").replace("time: 1.0 s", "time: 100000 s")
    code, err = run_cli(["simulate", str(write_axis(tmp_path, text))], capsys)
    assert code == 2
    assert err.startswith("error: profile: one cycle of 100000 s") and "shorter profile" in err


def test_simulate_api_refuses_a_duration_past_the_memory_bound() -> None:
    from drivetrain.dynamics import two_mass_chain
    from drivetrain.dynamics.control import tune
    from drivetrain.dynamics.kernel_io import MAX_SIMULATION_BYTES, estimate_bytes, max_steps
    from drivetrain.dynamics.reference import move_reference
    from drivetrain.dynamics.simulation import simulate

    chain = two_mass_chain(1e-4, 5e-4, 500.0)
    ref = move_reference(1.0, 10.0, 100.0)
    with pytest.raises(InputError) as err:
        simulate(chain, tune(chain), ref, duration=1e5)
    assert err.value.field == "simulation.duration" and "fit in" in err.value.rule
    fit = max_steps(chain.n)
    assert estimate_bytes(chain.n, fit) <= MAX_SIMULATION_BYTES < estimate_bytes(chain.n, fit + 10)


# ---------------------------------------------------------------------------------- 3. samples, 4. phase table


def test_points_past_the_sample_bound_name_the_option(capsys: pytest.CaptureFixture[str]) -> None:
    code, err = run_cli(["size", str(ROOT / "examples" / "ball_screw.yaml"), "--points", "100000"], capsys)
    assert code == 2
    assert err.startswith("error: --points:") and "at most 41665 points per phase fit" in err


def test_sample_bound_in_the_api() -> None:
    from drivetrain.motion.cycle import MAX_SAMPLES

    cycle = load_axis(ROOT / "examples" / "ball_screw.yaml").cycle()
    with pytest.raises(InputError) as err:
        cycle.sample(MAX_SAMPLES)
    assert err.value.field == "points_per_phase"
    fit = int(err.value.rule.split("at most ")[1].split()[0])
    assert cycle.sample(fit).t.size <= MAX_SAMPLES


def test_profile_length_is_capped() -> None:
    from drivetrain.motion.profiles import MAX_PROFILE_STEPS

    data = axis_data()
    data["profile"] = [{"move": "1 rev", "time": "0.1 s"}, {"dwell": "0.1 s"}] * (MAX_PROFILE_STEPS // 2) + [
        {"dwell": "0.1 s"}]
    with pytest.raises(InputError) as err:
        parse_axis(data).cycle()
    assert err.value.field == "profile" and f"at most {MAX_PROFILE_STEPS}" in err.value.rule


def _phase_table_by_masks(duty: Any, torque: np.ndarray) -> list[dict[str, Any]]:
    """The definition: one mask per phase (quadratic, the reference for the linear pass)."""
    from drivetrain.physics.averages import signed_extreme
    from drivetrain.units import to_rpm

    idx = np.asarray(duty.samples.phase)
    rows = []
    for k, ph in enumerate(duty.cycle.phases):
        mask = idx == k
        rows.append({"kind": ph.kind, "move": ph.move, "step": ph.step, "t0_s": float(ph.t0), "t1_s": float(ph.t1),
                     "torque_Nm": signed_extreme(torque[mask]),
                     "speed_rpm": float(to_rpm(np.max(np.abs(duty.omega[mask])))) if mask.any() else 0.0})
    return rows


@pytest.mark.parametrize("example", sorted((ROOT / "examples").glob("*.yaml")), ids=lambda p: p.stem)
def test_phase_table_matches_its_definition(example: Path) -> None:
    from drivetrain.duty.cycle import duty_cycle, phase_table

    duty = duty_cycle(load_axis(example), 17)
    for torque in (duty.torque, -duty.torque, np.round(duty.torque, 1), np.zeros_like(duty.torque)):
        assert phase_table(duty, torque) == _phase_table_by_masks(duty, torque)


def test_phase_table_builds_no_mask_per_phase(monkeypatch: pytest.MonkeyPatch) -> None:
    """A long profile: the table must not compare the whole sample array once per phase."""
    from drivetrain.duty import cycle as cycle_mod

    data = axis_data()
    data["profile"] = [{"move": "1 rev", "time": "0.1 s"}, {"dwell": "0.05 s"}] * 400
    duty = cycle_mod.duty_cycle(parse_axis(data), 5)
    calls = 0

    class Counting(np.ndarray):
        def __eq__(self, other: object) -> Any:  # type: ignore[override]
            nonlocal calls
            calls += 1
            return np.asarray(self).__eq__(other)

    real_asarray = np.asarray

    def counting_asarray(a: Any, *args: Any, **kwargs: Any) -> Any:
        out = real_asarray(a, *args, **kwargs)
        return out.view(Counting) if out.dtype.kind in "iu" else out

    monkeypatch.setattr(np, "asarray", counting_asarray)
    rows = cycle_mod.phase_table(duty, duty.torque)
    monkeypatch.undo()
    assert len(rows) == len(duty.cycle.phases) == 1600
    assert calls <= 2


# ---------------------------------------------------------------------------------- catalog import

HEADER = "id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
ROW = "{id},ACME,1,3,3000,6000,1e-4,ACME datasheet p. 1\n"
JSON_ROW = {"id": "J1", "vendor": "A", "rated_torque_Nm": 1, "peak_torque_Nm": 3, "rated_speed_rpm": 3000,
            "max_speed_rpm": 6000, "rotor_inertia_kgm2": 1e-4, "source": "A datasheet p. 1"}


@pytest.fixture
def user_catalog(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    from drivetrain.catalog import db

    directory = tmp_path / "data"
    directory.mkdir()
    monkeypatch.setenv(db.ENV_DATA_DIR, str(directory))
    return directory


def _import(tmp_path: Path, name: str, text: str) -> InputError:
    from drivetrain.catalog.importer import import_file

    path = tmp_path / name
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    with pytest.raises(InputError) as err:
        import_file(path, "motor" if name.endswith(".csv") else None)
    return err.value


def _rules(err: InputError) -> str:
    errs = err.errors if isinstance(err, InputErrors) else [err]
    return " | ".join(f"{e.field}: {e.rule}" for e in errs)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ('{"table": []}', "table: must be one of"),
        ('{"table": {"a": 1}, "rows": []}', "table: must be one of"),
        ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
        ('{"rows": [' + "[" * 30 + "]" * 30 + "]}", "nested too deeply"),
        (json.dumps([JSON_ROW]).replace('"rated_torque_Nm": 1', '"rated_torque_Nm": 1' + "0" * 400),
         "more than 400 digits"),
        (json.dumps([JSON_ROW]).replace('"rated_torque_Nm": 1', '"rated_torque_Nm": 1' + "0" * 5000),
         "more than 400 digits"),
        (json.dumps([JSON_ROW]).replace('"rated_torque_Nm": 1', '"rated_torque_Nm": 1' + "0" * 309),
         "finite"),
        (json.dumps([JSON_ROW]).replace('"J1"', '"J\\ud800"'), "id: is not valid Unicode"),
        (json.dumps([JSON_ROW]).replace('"vendor"', '"v\\udc00"'), "not valid Unicode"),
    ],
)
def test_broken_json_catalog_files(tmp_path: Path, user_catalog: Path, text: str, words: str) -> None:
    err = _import(tmp_path, "m.json", text)
    assert words in _rules(err)
    str(err).encode("utf-8")


@pytest.mark.parametrize(
    ("row_id", "words"),
    [
        ("hg-kr053", "differs only by letter case from HG-KR053 in the shipped catalog"),
        ("\u202eABC", "U+202E"),
        ("A\x00B", "U+0000"),
        ("A" * 100_000, "is too long"),
    ],
)
def test_hostile_ids(tmp_path: Path, user_catalog: Path, row_id: str, words: str) -> None:
    err = _import(tmp_path, "m.csv", HEADER + ROW.format(id=row_id))
    assert ":2:id" in _rules(err) and words in _rules(err)


def test_ids_differing_by_case_within_one_file(tmp_path: Path, user_catalog: Path) -> None:
    err = _import(tmp_path, "m.csv", HEADER + ROW.format(id="abc-1") + ROW.format(id="ABC-1"))
    assert ":3:id: differs only by letter case from abc-1 in this file" in _rules(err)


def test_duplicated_csv_column(tmp_path: Path, user_catalog: Path) -> None:
    text = HEADER.replace("source", "rated_torque_Nm") + ROW.format(id="D1").replace("ACME datasheet p. 1", "2")
    err = _import(tmp_path, "m.csv", text)
    assert ":1:rated_torque_Nm: column is given twice" in _rules(err)


def test_unit_expression_in_a_catalog_cell(tmp_path: Path, user_catalog: Path) -> None:
    err = _import(tmp_path, "m.csv", HEADER + ROW.format(id="U1").replace(",1,3,", ",9**9**9 N*m,3,"))
    assert ":2:rated_torque_Nm: is not a quantity" in _rules(err)


def test_rows_per_file_and_in_the_user_catalog_are_bounded(
    tmp_path: Path, user_catalog: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from drivetrain.catalog import importer

    monkeypatch.setattr(importer, "MAX_IMPORT_ROWS", 5)
    err = _import(tmp_path, "m.csv", HEADER + "".join(ROW.format(id=f"R{i}") for i in range(6)))
    assert "has 6 rows and curve points; an import takes at most 5" in _rules(err)
    err = _import(tmp_path, "m.json", json.dumps([{**JSON_ROW, "id": f"J{i}"} for i in range(6)]))
    assert "has 6 rows and curve points; an import takes at most 5" in _rules(err)
    monkeypatch.setattr(importer, "MAX_USER_ROWS", 7)
    path = tmp_path / "ok.csv"
    path.write_text(HEADER + "".join(ROW.format(id=f"R{i}") for i in range(5)), encoding="utf-8")
    assert importer.import_file(path).rows == 5
    err = _import(tmp_path, "more.csv", HEADER + "".join(ROW.format(id=f"S{i}") for i in range(3)))
    assert "at most 7" in _rules(err)


def test_export_escapes_formula_cells_and_reimports_them(tmp_path: Path, user_catalog: Path) -> None:
    from drivetrain.catalog import importer
    from drivetrain.catalog.reading import escape_cell, unescape_cell

    assert escape_cell(-1.5) == -1.5 and escape_cell("-x") == "'-x" and escape_cell("ACME") == "ACME"
    for cell in ("=1+1", "+1", "-2", "@SUM(A1)", "\tx"):
        assert unescape_cell(escape_cell(cell)) == cell
    path = tmp_path / "evil.csv"
    path.write_text(HEADER + ROW.format(id="EVIL-1").replace("ACME", '=HYPERLINK("http://x")'), encoding="utf-8")
    importer.import_file(path)
    out = tmp_path / "out.csv"
    importer.export(out, "motor", origin="user")
    lines = out.read_text(encoding="utf-8").splitlines()
    assert any(",'=HYPERLINK(" in line or ",\"'=HYPERLINK(" in line for line in lines)
    assert not any(",=" in line or ',"=' in line for line in lines)
    from drivetrain.catalog.reading import read_csv

    raw = read_csv(out.read_text(encoding="utf-8"), "out.csv")
    assert raw.rows[0].cells["vendor"] == '=HYPERLINK("http://x")'


# ---------------------------------------------------------------------------------- output files


@pytest.mark.parametrize(
    ("option", "make", "words"),
    [
        ("--csv", "dir", "is a directory"),
        ("--report", "dir.html", "is a directory"),
        ("--csv", "file/x.csv", "is a file, not a directory"),
        ("--report", "file/x.html", "is a file, not a directory"),
    ],
)
def test_output_targets_that_cannot_be_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], option: str, make: str, words: str
) -> None:
    (tmp_path / "dir").mkdir()
    (tmp_path / "dir.html").mkdir()
    (tmp_path / "file").write_text("x", encoding="utf-8")
    code, err = run_cli(["size", str(AXIS), option, str(tmp_path / make)], capsys)
    assert code == 2 and err.startswith(f"error: {option}:") and words in err


def test_plot_target_checks(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, err = run_cli(["simulate", str(TWO_INERTIAS), "--plot", str(tmp_path)], capsys)
    assert code == 2 and "error: --plot: is a directory" in err
    code, err = run_cli(["simulate", str(TWO_INERTIAS), "--plot", str(tmp_path / "fig.tmp")], capsys)
    assert code == 2 and "error: --plot: must end in .png, .svg, .pdf" in err


@pytest.mark.parametrize(
    ("code_no", "words"),
    [(errno.ENOSPC, "the disk is full"), (errno.EFBIG, "file-size limit"), (errno.EROFS, "read-only"),
     (errno.EACCES, "permission denied")],
)
@pytest.mark.parametrize("option", ["--csv", "--report"])
def test_file_system_errors_while_writing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, code_no: int, words: str,
    option: str,
) -> None:
    real_replace = os.replace

    def failing_replace(src: Any, dst: Any) -> None:
        if str(dst).startswith(str(tmp_path)):
            raise OSError(code_no, os.strerror(code_no))
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", failing_replace)
    target = tmp_path / ("out.csv" if option == "--csv" else "out.html")
    code, err = run_cli(["size", str(AXIS), option, str(target)], capsys)
    assert code == 2 and err.startswith(f"error: {option}: cannot be written (") and words in err
    assert list(tmp_path.iterdir()) == []  # no temporary left behind


def test_no_directory_for_the_temporary(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import tempfile

    def read_only(*_: Any, **__: Any) -> Any:
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkstemp", read_only)
    code, err = run_cli(["size", str(AXIS), "--csv", str(tmp_path / "x.csv")], capsys)
    assert code == 2 and "error: --csv: cannot be written (the file system is read-only)" in err


def test_stale_temporaries_of_a_killed_writer_are_removed(tmp_path: Path) -> None:
    from drivetrain.files import STALE_TEMP_AGE_S, write_atomic

    target = tmp_path / "r.pdf"
    dead = tmp_path / ".r.pdf.999999999.abc123_x.tmp"  # no such process id
    old = tmp_path / ".r.pdf.abcd1234.tmp"  # the old naming, long abandoned
    fresh = tmp_path / ".r.pdf.zz9y8x7w.tmp"  # old naming, recent: a writer may still be at work
    other = tmp_path / ".other.pdf.999999999.abc.tmp"
    for p in (dead, old, fresh, other):
        p.write_bytes(b"half")
    os.utime(old, (0, 0))
    assert STALE_TEMP_AGE_S < 1e9
    write_atomic(target, lambda tmp: tmp.write_bytes(b"%PDF"), "--report")
    assert target.read_bytes() == b"%PDF"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["r.pdf", fresh.name, other.name])


def test_temporary_names_are_unique(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.files import write_atomic

    seen: list[str] = []
    write_atomic(tmp_path / "a.csv", lambda tmp: seen.append(tmp.name) or tmp.write_text("1"), "--csv")
    write_atomic(tmp_path / "a.csv", lambda tmp: seen.append(tmp.name) or tmp.write_text("2"), "--csv")
    assert seen[0] != seen[1] and f".{os.getpid()}." in seen[0]


# ---------------------------------------------------------------------------------- slip check


def test_a_profile_that_only_dwells_explains_its_slip_margin() -> None:
    from drivetrain.sizing.axis_blocks import slip_check

    out = slip_check(np.zeros(5), 2.9, math.radians(5), 9.80665)
    assert out.ok and math.isinf(out.margin) and "never accelerates" in (out.note or "")
    steep = slip_check(np.zeros(5), 0.3 * 9.80665 * math.cos(math.radians(30)), math.radians(30), 9.80665)
    assert not steep.ok and steep.margin == -1.0 and "slides" in (steep.note or "")


def test_dwell_only_conveyor_sizes_without_nan(tmp_path: Path) -> None:
    from drivetrain.sizing.pipeline import size

    data = yaml.safe_load((ROOT / "examples" / "conveyor.yaml").read_text(encoding="utf-8"))
    data["profile"] = [{"dwell": "1 s"}]
    data["motor"] = {"name": "m", "inertia": "1 kg*cm^2", "rated_torque": "2 N*m", "peak_torque": "6 N*m",
                     "max_speed": "3000 rpm"}
    result = size(parse_axis(data))
    slip = result.slip_check
    assert slip.ok and "never accelerates" in (slip.note or "")
    assert not any(isinstance(v, float) and math.isnan(v) for v in slip.to_dict().values())

