"""Hostile input, second round (issue 30): the study, machine and catalog paths around the axis file.

One regression test per case the issue names, each ending in an ``InputError`` naming the field or
file (through the command line: exit status 2, one line, no traceback). The seeded fuzz tests of
the same classes are in test_fuzz_files.py.
"""

from __future__ import annotations

import json
import os
import sqlite3
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.axis.yaml_text import MAX_DEPTH, MAX_NODES, parse_yaml
from drivetrain.cli import main
from drivetrain.errors import InputError, InputErrors
from drivetrain.userfile import read_bytes

ROOT = Path(__file__).resolve().parents[2]
AXIS = ROOT / "tests" / "axes" / "yaskawa_es_30w.yaml"  # a given motor: sizing is quick
MACHINE = ROOT / "examples" / "machine" / "pick_and_place.yaml"


def axis_data() -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load(AXIS.read_text(encoding="utf-8"))
    return data


def cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """Exit status and standard error of the command; the error is one line without a traceback."""
    code = main(args)
    err = capsys.readouterr().err
    if code == 2:
        assert err.startswith("error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    return code, err


# ---------------------------------------------------------------------------------- files that are not files


@pytest.mark.parametrize("command", [["size"], ["modes"], ["machine", "size"], ["sweep"]])
def test_a_device_is_refused_at_the_file(command: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    code, err = cli([*command, "/dev/zero"], capsys)
    assert code == 2 and "is a device, not a" in err and "/dev/zero" in err


def test_a_fifo_and_a_directory_are_refused_without_blocking(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)  # nobody writes to it: a blocking open would wait for ever
    code, err = cli(["size", str(fifo)], capsys)
    assert code == 2 and "FIFO" in err
    code, err = cli(["size", str(tmp_path)], capsys)
    assert code == 2 and "is a directory" in err


def test_a_path_with_a_nul_byte(capsys: pytest.CaptureFixture[str]) -> None:
    code, err = cli(["size", "axis\x00.yaml"], capsys)
    assert code == 2 and "NUL byte" in err and "embedded null" not in err


def test_a_file_past_its_size_is_read_no_further(tmp_path: Path) -> None:
    path = tmp_path / "big.yaml"
    path.write_bytes(b"a" * 101)
    with pytest.raises(InputError, match="too large"):
        read_bytes(path, "file", 100)
    assert read_bytes(path, "file", 101) == b"a" * 101
    assert os.stat("/proc/self/maps").st_size == 0  # a file that reports no size: read to the bound only
    with pytest.raises(InputError, match="over 100 bytes"):
        read_bytes("/proc/self/maps", "file", 100)


def test_a_study_whose_base_is_a_device(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    study = tmp_path / "s.yaml"
    study.write_text(yaml.safe_dump({"study": 1, "base": "/dev/zero", "parameters": {"mechanism.lead": [5]}}),
                     encoding="utf-8")
    code, err = cli(["sweep", str(study), "--workers", "0"], capsys)
    assert code == 2 and err.startswith("error: base: is a device")


def test_a_machine_whose_include_is_a_device_or_nul(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data = yaml.safe_load(MACHINE.read_text(encoding="utf-8"))
    for include, words in (("/dev/zero", "is a device"), ("a\x00b.yaml", "NUL byte")):
        data["axes"][0] = {"name": "x", "include": include}
        path = tmp_path / "m.yaml"
        path.write_text(yaml.safe_dump(data), encoding="utf-8")
        code, err = cli(["machine", "size", str(path)], capsys)
        assert code == 2 and err.startswith("error: axes[0].include: ") and words in err


def test_a_catalog_import_of_a_device(capsys: pytest.CaptureFixture[str], user_catalog: Path) -> None:
    code, err = cli(["catalog", "import", "/dev/zero", "--kind", "motor"], capsys)
    assert code == 2 and "is a device" in err


# ---------------------------------------------------------------------------------- deep or huge YAML


@pytest.mark.parametrize("text", [
    "{a: " * 20_000 + "1" + "}" * 20_000,  # the issue's flow mapping
    "[" * 20_000 + "]" * 20_000,
    "a: " + "[{b: " * 10_000 + "1" + "}]" * 10_000,
    "".join("  " * d + "k:\n" for d in range(MAX_DEPTH + 5)) + "  " * (MAX_DEPTH + 5) + "1\n",  # block style
])
def test_deep_yaml_is_refused_at_the_depth_bound(text: str) -> None:
    with pytest.raises(InputError, match=f"nested too deeply \\(over {MAX_DEPTH} levels\\)"):
        parse_yaml(text)


def test_a_large_file_within_the_depth_bound_is_refused_by_its_value_count() -> None:
    """The issue's 1 MB file nested about 100 deep: refused at the value bound, before it is composed."""
    inner = ",".join(["1"] * 150_000)
    text = "{a: " * 95 + "[" + inner + "]" + "}" * 95
    assert len(text) < 1_000_000
    with pytest.raises(InputError) as err:
        parse_yaml(text)
    assert err.value.rule.startswith(f"holds more than {MAX_NODES} values") and "alias" not in err.value.rule


def test_a_flat_list_is_not_called_an_alias_bomb(monkeypatch: pytest.MonkeyPatch) -> None:
    with pytest.raises(InputError) as err:  # the issue's flat, alias-free list (1 MB)
        parse_yaml("[" + ",".join(["1"] * 490_000) + "]")
    assert "alias" not in err.value.rule and f"holds more than {MAX_NODES} values" in err.value.rule
    from drivetrain.axis import yaml_text as model

    monkeypatch.setattr(model, "MAX_NODES", 1000)  # just below the bound, it is read (quick, at a lower bound)
    assert len(parse_yaml("[" + ",".join(["1"] * 999) + "]")) == 999


def test_an_alias_bomb_is_still_named_so() -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 10) + "]" for k in range(1, 9)]
    with pytest.raises(InputError, match="alias"):
        parse_yaml("\n".join(lines))


def test_the_parser_gives_the_data_of_the_safe_loader() -> None:
    for path in sorted((ROOT / "examples").glob("**/*.yaml")):
        text = path.read_text(encoding="utf-8")
        assert parse_yaml(text) == yaml.safe_load(text), path


# ---------------------------------------------------------------------------------- duplicate keys


def test_a_key_given_twice_is_refused_naming_it_and_its_lines(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    text = AXIS.read_text(encoding="utf-8").replace(
        "load: {friction_torque: 0.035 N*m}", "load:\n    friction_torque: 0.035 N*m\n    friction_torque: 3.5 N*m")
    path = tmp_path / "a.yaml"
    path.write_text(text, encoding="utf-8")
    code, err = cli(["size", str(path)], capsys)
    assert code == 2 and err.startswith("error: mechanism.load.friction_torque: is given twice (lines 10 and 11)")


def test_the_issue_mass_given_twice() -> None:
    with pytest.raises(InputError) as err:
        parse_yaml("mechanism:\n  load: {mass: 25 kg, mass: 2500 kg}\n")
    assert err.value.field == "mechanism.load.mass" and "given twice" in err.value.rule


def test_a_merge_key_may_be_overridden() -> None:
    assert parse_yaml("base: &b {x: 1, y: 2}\nc: {<<: *b, y: 3}\n")["c"] == {"x": 1, "y": 3}


def test_an_axis_twice_on_one_bus(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data = yaml.safe_load(MACHINE.read_text(encoding="utf-8"))
    first = data["buses"][0]["axes"][0]
    data["buses"][0]["axes"].append(first)
    for name in ("x_belt.yaml", "y_gantry.yaml", "rotary.yaml"):  # the includes, beside the copy
        (tmp_path / name).write_bytes((MACHINE.parent / name).read_bytes())
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    code, err = cli(["machine", "size", str(path)], capsys)
    k = len(data["buses"][0]["axes"]) - 1
    assert code == 2 and err.startswith(f"error: buses[0].axes[{k}]: lists this axis a second time (first at "
                                        "buses[0].axes[0])")


# ---------------------------------------------------------------------------------- overflow


@pytest.mark.parametrize("command", [["size"], ["machine", "size"]])
def test_a_ratio_chain_that_overflows_is_a_field_error(tmp_path: Path, command: list[str],
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    axis = axis_data()
    axis["transmission"] = [{"type": "gearbox", "ratio": 1e15}] * 11  # 1e165: its square overflows a float
    if command == ["size"]:
        path = tmp_path / "a.yaml"
        path.write_text(yaml.safe_dump(axis), encoding="utf-8")
    else:
        machine = {"version": 1, "cycle_time": "2 s", "supply": {"voltage": "400 V"},
                   "axes": [{"name": "x", "axis": axis}]}
        path = tmp_path / "m.yaml"
        path.write_text(yaml.safe_dump(machine), encoding="utf-8")
    code, err = cli([*command, str(path)], capsys)
    assert code == 2 and "transmission[0]: brings the product of the ratios from the motor to 1e+15" in err


def test_the_ratio_bound_names_the_element_that_passes_it() -> None:
    axis = axis_data()
    axis["transmission"] = [{"type": "gearbox", "ratio": 1e5}] * 3
    with pytest.raises(InputError) as err:
        parse_axis(axis)
    assert err.value.field == "transmission[2]"


# ---------------------------------------------------------------------------------- studies


def _study(tmp_path: Path, body: dict[str, Any]) -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump({"study": 1, "base": str(AXIS), **body}, sort_keys=False), encoding="utf-8")
    return path


@pytest.mark.parametrize(("body", "field", "words"), [
    ({"parameters": {"mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "num": 10**18}}},
     "parameters.mechanism.load.friction_torque.num", "at most 1,000,000"),
    ({"parameters": {"mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "step": 1e-12}}},
     "parameters.mechanism.load.friction_torque.step", "the smallest step that fits is 1e-08"),
    ({"parameters": {"mechanism.load.friction_torque": {"start": 0, "stop": 1e300, "step": 1e-300}}},
     "parameters.mechanism.load.friction_torque.step", "infinitely many"),
    ({"parameters": {f"profile[0].{k}": {"start": 0.1, "stop": 0.9, "num": 900_000}
                     for k in ("time", "accel")} | {"mechanism.load.friction_torque":
                                                     {"start": 0.01, "stop": 0.02, "num": 900_000}}},
     "design", "at most 10,000,000,000, even with --yes"),
    ({"parameters": {"mechanism.load.friction_torque": {"distribution": "uniform", "low": 0.01, "high": 0.02}},
      "design": "random", "samples": 10**9}, "samples", "samples fit with 1 parameter"),
    ({"parameters": {"mechanism.load.friction_torque": [0.01]}, "seed": 2**64}, "seed", "less than or equal"),
    ({"parameters": {"mechanism.load.friction_torque": [0.01]}, "seed": -1}, "seed", "greater than or equal"),
])
def test_study_bounds_are_checked_before_anything_is_allocated(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], body: dict[str, Any], field: str, words: str) -> None:
    code, err = cli(["sweep", str(_study(tmp_path, body)), "--yes", "--workers", "0"], capsys)
    assert code == 2 and err.startswith(f"error: {field}: ") and words in err


def test_the_million_variant_guard_still_needs_yes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    body = {"parameters": {"mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "num": 1001},
                           "profile[0].time": {"start": 0.5, "stop": 1.5, "num": 1001}}}
    code, err = cli(["sweep", str(_study(tmp_path, body)), "--workers", "0"], capsys)
    assert code == 2 and "confirm with --yes" in err


def test_a_billion_variant_study_streams_its_rows_in_bounded_batches(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The issue's 10^9-variant ``--yes`` sweep: the variants are made as they are asked for and the rows
    are written every FLUSH_ROWS rows, so the rows held never exceed a flush; the run is stopped after a
    fixed number of batches and the partial table holds every row sized until then."""
    import pyarrow.parquet as pq

    from drivetrain.study import load_study, stream
    from drivetrain.study.runner import partial_path
    from drivetrain.study.stream import run

    body = {"parameters": {"mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "num": 31_623},
                           "profile[0].time": {"start": 0.5, "stop": 1.5, "num": 31_623}}}
    study = load_study(_study(tmp_path, body), yes=True)
    assert study.n_variants() > 10**9
    monkeypatch.setattr(stream, "FLUSH_ROWS", 30)
    sinks: list[stream.RowSink] = []
    real_sink = stream.RowSink

    def sink(*args: Any, **kwargs: Any) -> stream.RowSink:
        sinks.append(real_sink(*args, **kwargs))
        return sinks[-1]

    monkeypatch.setattr(stream, "RowSink", sink)

    class Enough(Exception):
        pass

    def stop_after_six_batches(rows: int) -> None:
        if rows >= 6 * 20:
            raise Enough

    out = tmp_path / "big.parquet"
    with pytest.raises(Enough):
        run(study, out=out, workers=0, batch=20, on_rows=stop_after_six_batches)
    [s] = sinks
    assert s.rows == 120 and s.flushes == 3 and s.most_buffered < 30 + 20  # a flush and one batch at most
    table = pq.read_table(partial_path(out))
    assert table.num_rows == 120 and table.column("variant").to_pylist() == list(range(120))
    assert set(table.column_names) >= {"variant", "mechanism.load.friction_torque", "profile[0].time", "ok", "error"}
    assert json.loads(table.schema.metadata[b"drivetrain.study"])["variants"] == study.n_variants()


def test_a_streamed_study_runs_to_its_end(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A study above the streaming threshold (lowered for the test) writes the whole table, the same rows as
    an in-memory run."""
    import pyarrow.parquet as pq

    from drivetrain.study import load_study, stream
    from drivetrain.study.stream import run

    body = {"parameters": {"mechanism.load.friction_torque": {"start": 0.01, "stop": 0.02, "num": 5},
                           "profile[0].time": ["0.5 s", "0.8 s", "-1 s"]}}
    study = load_study(_study(tmp_path, body))
    in_memory = run(study, workers=0)
    monkeypatch.setattr(stream, "STREAM_ABOVE", 10)
    monkeypatch.setattr(stream, "FLUSH_ROWS", 4)
    out = tmp_path / "t.parquet"
    df = run(study, out=out, workers=0, batch=3)
    assert len(df) == 0 and df.attrs["drivetrain"]["rows"] == 15
    table = pq.read_table(out).to_pandas()
    assert list(table["variant"]) == list(range(15)) and out.with_suffix(".csv").exists()
    assert list(table["ok"]) == list(in_memory["ok"]) and list(table["error"]) == list(in_memory["error"])
    assert table["worst_margin"].tolist() == pytest.approx(in_memory["worst_margin"].tolist(), nan_ok=True)


# ---------------------------------------------------------------------------------- catalog import


@pytest.fixture
def user_catalog(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    from drivetrain.catalog import db

    directory = tmp_path / "data"
    directory.mkdir()
    monkeypatch.setenv(db.ENV_DATA_DIR, str(directory))
    return directory


HEADER = "id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
ROW = "{id},ACME,1,3,3000,6000,1e-4,ACME datasheet p. 1\n"


def test_a_wide_header_of_unknown_columns_gives_a_short_message(
        tmp_path: Path, user_catalog: Path, capsys: pytest.CaptureFixture[str]) -> None:
    n = 24_000  # the issue's 470 kB header
    path = tmp_path / "wide.csv"
    path.write_text(",".join(["id", "vendor"] + [f"unknowncol{i:07d}" for i in range(n)]) + "\n"
                    + "X1,acme" + ",1" * n + "\n", encoding="utf-8")
    assert path.stat().st_size > 400_000
    code, err = cli(["catalog", "import", str(path), "--kind", "motor"], capsys)
    assert code == 2 and len(err) < 1000 and "has 24,002 columns" in err and "and 23997 more" in err


def test_many_errors_are_counted_not_listed(tmp_path: Path, user_catalog: Path) -> None:
    from drivetrain.catalog.importer import import_file

    path = tmp_path / "m.csv"
    path.write_text(HEADER + "".join(ROW.format(id=f"R{i}").replace(",1,3,", ",x,3,") for i in range(300)),
                    encoding="utf-8")
    with pytest.raises(InputErrors) as err:
        import_file(path, "motor")
    assert len(err.value.errors) == 300
    text = str(err.value)
    assert text.count("\n") == 20 and text.endswith("... and 280 more errors")


def test_long_user_names_are_shortened_in_a_message() -> None:
    with pytest.raises(InputError) as err:
        parse_yaml("a" * 50_000 + ": 1\n" + "a" * 50_000 + ": 2\n")
    assert len(str(err.value)) < 400


def _catalog_bytes(directory: Path) -> bytes:
    return (directory / "user.sqlite").read_bytes()


def _seed_catalog(tmp_path: Path) -> None:
    from drivetrain.catalog.importer import import_file

    first = tmp_path / "first.csv"
    first.write_text(HEADER + ROW.format(id="KEEP-1"), encoding="utf-8")
    import_file(first, "motor")


def test_an_import_onto_a_read_only_catalog(tmp_path: Path, user_catalog: Path, monkeypatch: pytest.MonkeyPatch,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    """A read-only file system, simulated at the SQLite layer (root writes through chmod): the user
    catalog opened read-only, as SQLite opens a file it cannot write."""
    _seed_catalog(tmp_path)
    before = _catalog_bytes(user_catalog)
    real_connect = sqlite3.connect

    def read_only(path: Any, *args: Any, **kwargs: Any) -> sqlite3.Connection:
        if str(path).endswith("user.sqlite"):
            return real_connect(f"file:{path}?mode=ro", *args, uri=True, **kwargs)
        return real_connect(path, *args, **kwargs)

    monkeypatch.setattr(sqlite3, "connect", read_only)
    new = tmp_path / "new.csv"
    new.write_text(HEADER + ROW.format(id="NEW-1"), encoding="utf-8")
    code, err = cli(["catalog", "import", str(new), "--kind", "motor"], capsys)
    monkeypatch.undo()
    assert code == 2 and err.startswith("error: catalog: cannot be written: the file or its folder is read-only")
    assert str(user_catalog / "user.sqlite") in err
    assert _catalog_bytes(user_catalog) == before


def test_an_import_onto_a_full_disk(tmp_path: Path, user_catalog: Path, monkeypatch: pytest.MonkeyPatch,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    """The disk fills in the middle of the transaction (after some rows are written): rolled back,
    exit 2 naming the catalog, the file byte-identical."""
    from drivetrain.catalog import db, manage

    _seed_catalog(tmp_path)
    before = _catalog_bytes(user_catalog)
    real_write = manage.write_import

    def fills_the_disk(conn: sqlite3.Connection, *args: Any, **kwargs: Any) -> Any:
        real_write(conn, *args, **kwargs)  # the rows are in the transaction
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(manage, "write_import", fills_the_disk)
    new = tmp_path / "new.csv"
    new.write_text(HEADER + "".join(ROW.format(id=f"NEW-{i}") for i in range(50)), encoding="utf-8")
    code, err = cli(["catalog", "import", str(new), "--kind", "motor"], capsys)
    assert code == 2 and err.startswith("error: catalog: cannot be written: the disk is full") and "as it was" in err
    assert _catalog_bytes(user_catalog) == before
    with db.reader() as rd:
        assert "NEW-0" not in rd.ids() and "KEEP-1" in rd.ids()


def test_a_failing_commit_is_rolled_back(tmp_path: Path, user_catalog: Path) -> None:
    """A COMMIT that fails (a full disk at the last write) leaves no open transaction behind."""
    from drivetrain.catalog.db import immediate_transaction

    conn = sqlite3.connect(tmp_path / "t.sqlite", isolation_level=None)
    conn.execute("CREATE TABLE t (x)")
    conn.execute("CREATE TABLE p (x PRIMARY KEY)")
    conn.execute("CREATE TABLE c (x REFERENCES p(x) DEFERRABLE INITIALLY DEFERRED)")
    conn.execute("PRAGMA foreign_keys = ON")
    with pytest.raises(sqlite3.IntegrityError), immediate_transaction(conn):
        conn.execute("INSERT INTO t VALUES (1)")
        conn.execute("INSERT INTO c VALUES (2)")  # refused at COMMIT
    assert not conn.in_transaction and conn.execute("SELECT count(*) FROM t").fetchone() == (0,)
    conn.close()


def test_load_axis_reads_through_the_bounded_reader(tmp_path: Path) -> None:
    path = tmp_path / "a.yaml"
    path.write_text(AXIS.read_text(encoding="utf-8"), encoding="utf-8")
    assert load_axis(path).name == "Yaskawa Sigma-S 30 W example"


@pytest.mark.parametrize("python", [False, True], ids=["libyaml events", "PyYAML parser"])
def test_both_parsers_keep_the_bounds(python: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """The bounds hold whichever parser gives the events (PyYAML's own where libyaml is absent)."""
    from drivetrain.axis import yaml_text as model

    def parse(text: str) -> Any:
        return model._parse(text, "<text>", model._loader_class(python=python))

    for text in ("{a: " * 5000 + "1" + "}" * 5000, "[" * 5000 + "]" * 5000):
        with pytest.raises(InputError, match="nested too deeply"):
            parse(text)
    with pytest.raises(InputError, match="given twice"):
        parse("a: {b: 1, b: 2}")
    monkeypatch.setattr(model, "MAX_NODES", 500)
    with pytest.raises(InputError, match="holds more than 500 values"):
        parse("[" + ",".join(["1"] * 600) + "]")
    text = AXIS.read_text(encoding="utf-8")
    assert parse(text) == yaml.safe_load(text)


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_a_catalog_option_naming_a_fifo_or_a_device_is_refused(kind: str, tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    """``--catalog`` naming a FIFO waited for ever and a device was read as zeros: refused at the option."""
    import os

    target = "/dev/zero"
    if kind == "fifo":
        target = str(tmp_path / "fifo")
        os.mkfifo(target)
    code, err = cli(["--catalog", target, "catalog", "list"], capsys)
    assert code == 2 and err.startswith("error: --catalog: must name a regular catalog file")
    assert "Traceback" not in err
