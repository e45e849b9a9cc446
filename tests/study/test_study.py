"""Studies from the CLI and from Python: grid, Monte Carlo, optimisation, validation, resume, report.

Small designs, run in this process (``workers=0``); the Dask paths are in test_study_dask.py.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
import yaml

import drivetrain
from drivetrain.cli import main
from drivetrain.errors import InputError
from drivetrain.study import load_study, parse_study, sweep
from drivetrain.study.runner import partial_path, read_parquet, run

EXAMPLES = Path(__file__).parents[2] / "examples"
BASE = EXAMPLES / "ball_screw.yaml"


def _study(tmp_path: Path, body: dict[str, Any], name: str = "s.yaml") -> Path:
    data = {"study": 1, "base": str(BASE), **body}
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return p


GRID = {"name": "small grid",
        "parameters": {"mechanism.load.mass": {"start": "10 kg", "stop": "30 kg", "num": 3},
                       "mechanism.lead": {"values": [5, 10], "unit": "mm"},
                       "profile[0].time": {"values": ["0.4 s", "0.8 s"]}},
        "design": "grid"}


# ---------------------------------------------------------------------------------------------
# validation: InputError naming the field, CLI exit 2, before any work


BAD = [
    ({"parameters": {"mechanism.leed": [5, 10]}}, "parameters.mechanism.leed"),
    ({"parameters": {"mechanism.lead": {"values": [5, 10], "unit": "kg"}}}, "parameters.mechanism.lead"),
    ({"parameters": {"mechanism.lead": {"start": "10 mm", "stop": "5 mm", "step": "1 mm"}}},
     "parameters.mechanism.lead.stop"),
    ({"parameters": {"mechanism.lead": {"values": []}}}, "parameters.mechanism.lead.values"),
    ({"parameters": {"mechanism.lead": {"start": "5 mm", "stop": "10 mm"}}}, "parameters.mechanism.lead"),
    ({"parameters": {"mechanism.load.mass": {"distribution": "normal", "mean": "5 kg", "std": "1 kg"}}},
     "parameters.mechanism.load.mass.distribution"),
    ({"parameters": {"mechanism.load.mass": {"distribution": "normal", "mean": "5 kg", "std": "1 m"}},
      "design": "lhs", "samples": 10}, "parameters.mechanism.load.mass.std"),
    ({"parameters": {"profile[7].time": ["1 s"]}}, "parameters.profile[7].time"),
    ({"parameters": {"mechanism.load.mass": {"start": 1, "stop": 2, "num": 1001, "unit": "kg"},
                     "mechanism.lead": {"start": 1, "stop": 2, "num": 1001, "unit": "mm"}}}, "design"),
    ({"parameters": {"mechanism.lead": [5]}, "design": "lhs"}, "samples"),
    ({"parameters": {"mechanism.lead": ["5 mm"]}, "record": ["selection.nonsense"]}, "record[0]"),
    ({"parameters": {"mechanism.lead": ["5 mm"]}, "design": "factorial"}, "design"),
    ({"parameters": {}}, "parameters"),
]


@pytest.mark.parametrize(("body", "field"), BAD)
def test_bad_study_names_the_field(tmp_path: Path, body: dict[str, Any], field: str,
                                   capsys: pytest.CaptureFixture[str]) -> None:
    p = _study(tmp_path, body)
    out = tmp_path / "out.parquet"
    assert main(["sweep", str(p), "-o", str(out), "--workers", "0", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {field}"), err
    assert "Traceback" not in err
    assert not out.exists() and not partial_path(out).exists()


def test_wrong_version_and_missing_base(tmp_path: Path) -> None:
    p = tmp_path / "v.yaml"
    p.write_text(f"study: 2\nbase: {BASE}\nparameters: {{mechanism.lead: [5 mm]}}\n", encoding="utf-8")
    with pytest.raises(InputError) as exc:
        load_study(p)
    assert exc.value.field == "study"
    with pytest.raises(InputError) as exc:
        parse_study("study: 1\nbase: nowhere.yaml\nparameters: {mechanism.lead: [5 mm]}\n", base_dir=tmp_path)
    assert exc.value.field == "base"


def test_many_variants_allowed_with_yes(tmp_path: Path) -> None:
    body = {"parameters": {"mechanism.load.mass": {"start": 1, "stop": 2, "num": 1001, "unit": "kg"},
                           "mechanism.lead": {"start": 1, "stop": 2, "num": 1001, "unit": "mm"}}}
    assert load_study(_study(tmp_path, body), yes=True).n_variants() == 1001 * 1001


# ---------------------------------------------------------------------------------------------
# grid


def test_grid_from_cli(tmp_path: Path) -> None:
    p = _study(tmp_path, GRID)
    out = tmp_path / "res" / "grid.parquet"
    assert main(["sweep", str(p), "-o", str(out), "--workers", "0", "--quiet", "--report",
                 str(tmp_path / "grid.html")]) == 0
    df, meta = read_parquet(out)
    assert len(df) == 12
    assert list(df["variant"]) == list(range(12))
    # first parameter outermost, values in the study's units
    assert list(df["mechanism.load.mass"][:4]) == [10.0] * 4
    assert list(df["mechanism.lead"][:4]) == [5.0, 5.0, 10.0, 10.0]
    assert meta["units"] == {"mechanism.load.mass": "kg", "mechanism.lead": "mm", "profile[0].time": "s"}
    assert meta["study_file"] == p.read_text(encoding="utf-8")
    assert meta["drivetrain_version"] == drivetrain.__version__
    from drivetrain.catalog.schema import DATA_VERSION

    assert meta["catalog_data_version"] == DATA_VERSION
    csv = pd.read_csv(out.with_suffix(".csv"))
    assert list(csv.columns) == list(df.columns)
    assert json.loads(out.with_suffix(".meta.json").read_text())["design"] == "grid"
    html = (tmp_path / "grid.html").read_text(encoding="utf-8")
    for section in ("study-pass_rate", "study-motor_map", "study-pareto", "study-failures"):
        assert section in html
    assert "<script src=" not in html and "Plotly.newPlot" in html  # self-contained


def test_grid_rows_are_the_variants_sizing(tmp_path: Path) -> None:
    """A row holds what drivetrain.size gives for that variant (the parameters written in SI)."""
    res = sweep(_study(tmp_path, GRID), workers=0)
    row = res.table.iloc[7]
    data = yaml.safe_load(BASE.read_text(encoding="utf-8"))
    data["mechanism"]["load"]["mass"] = f"{row['mechanism.load.mass']} kg"
    data["mechanism"]["lead"] = f"{row['mechanism.lead']} mm"
    data["profile"][0]["time"] = f"{row['profile[0].time']} s"
    ref = drivetrain.size(data).to_dict()
    sel = ref["selection"]["selected"]
    assert row["motor"] == sel["motor"]
    assert (row["gearbox"] if isinstance(row["gearbox"], str) else None) == sel["gearbox"]
    margins = {c["name"]: c["margin"] for c in sel["checks"]}
    assert row["margin_rms_torque"] == pytest.approx(margins["rms_torque"], rel=1e-9)
    assert row["load_rms_torque_Nm"] == pytest.approx(ref["rms_torque_Nm"], rel=1e-9)
    assert bool(row["ok"])


def test_variant_errors_are_rows(tmp_path: Path) -> None:
    """Values that make a variant impossible (accel longer than the move) give a row with its error."""
    body = {"parameters": {"profile[0].time": {"values": [0.05, 0.5], "unit": "s"}}}
    df = sweep(_study(tmp_path, body), workers=0).table
    assert not df["ok"][0] and "profile[0]" in df["error"][0]
    assert df["ok"][1] and df["error"][1] == ""


def test_record_dotted_keys_use_size_when_needed(tmp_path: Path) -> None:
    body = {"parameters": {"mechanism.load.mass": {"values": [10, 20], "unit": "kg"}},
            "record": ["motor", "selection.passing", "selection.selected.vendor", "max_speed_rpm"]}
    df = sweep(_study(tmp_path, body), workers=0).table
    assert (df["selection.passing"] > 0).all()
    assert df["selection.selected.vendor"].notna().all()
    assert (df["max_speed_rpm"] > 0).all()


# ---------------------------------------------------------------------------------------------
# Monte Carlo


MC = {"name": "mc",
      "parameters": {"mechanism.load.mass": {"distribution": "triangular", "low": "20 kg", "mode": "25 kg",
                                             "high": "60 kg"},
                     "mechanism.efficiency": {"distribution": "uniform", "low": 0.7, "high": 0.95},
                     "mechanism.load.thrust": {"distribution": "normal", "mean": "0 N", "std": "40 N"}},
      "seed": 5}


@pytest.mark.parametrize("design", ["random", "lhs", "sobol"])
def test_monte_carlo_designs(tmp_path: Path, design: str) -> None:
    res = sweep(_study(tmp_path, {**MC, "design": design, "samples": 16}), workers=0)
    df = res.table
    assert len(df) == 16
    m = df["mechanism.load.mass"]
    assert ((m >= 20) & (m <= 60)).all()
    assert df["mechanism.efficiency"].between(0.7, 0.95).all()
    again = sweep(_study(tmp_path, {**MC, "design": design, "samples": 16}, "t.yaml"), workers=0).table
    assert np.array_equal(again["mechanism.load.mass"], m)  # seeded


def test_monte_carlo_sensitivity_report(tmp_path: Path) -> None:
    """Saltelli design: Sobol indices rank the mass above the thrust for the worst margin; the
    report carries the ranking and the probability that each check fails."""
    from drivetrain.study.report import check_failures, sensitivity

    body = {**MC, "design": "saltelli", "samples": 16}
    res = sweep(_study(tmp_path, body), workers=0, report=tmp_path / "mc.html")
    assert len(res.table) == 16 * 5
    sens = sensitivity(res.study, res.table, "worst_margin")
    assert sens is not None and sens["method"].startswith("Sobol")
    ranked = [r["parameter"] for r in sens["rows"]]
    assert ranked.index("mechanism.load.mass") < ranked.index("mechanism.load.thrust")
    fails = check_failures(res.table)
    assert 0.0 <= fails["any check"] <= 1.0
    html = (tmp_path / "mc.html").read_text(encoding="utf-8")
    assert "Sensitivity ranking" in html and "study-sensitivity" in html


def test_morris(tmp_path: Path) -> None:
    from drivetrain.study.report import sensitivity

    res = sweep(_study(tmp_path, {**MC, "design": "morris", "samples": 4}), workers=0)
    assert len(res.table) == 4 * 4
    sens = sensitivity(res.study, res.table, "rms_torque_Nm")
    assert sens is not None and sens["rank_by"] == "mu_star"


# ---------------------------------------------------------------------------------------------
# optimisation


OPT = {"name": "opt",
       "parameters": {"mechanism.lead": {"values": [5, 10, 20], "unit": "mm"},
                      "profile[0].accel": {"start": "0.05 s", "stop": "0.2 s"}},
       "seed": 1}


def test_optimize_optuna_python(tmp_path: Path) -> None:
    res = sweep(_study(tmp_path, {**OPT, "optimize": {"objective": "motor_size", "trials": 12}}))
    assert res.best is not None
    df = res.table
    assert len(df) == 12
    passing = df[df["ok"].astype(bool)]
    assert res.best["value"] == passing["rated_power_W"].min()
    # the best variant's full sizing selects the motor of that row
    assert res.best["result"]["selection"]["selected"]["rated_power_W"] == res.best["value"]
    assert res.best["result"]["ok"]


def test_optimize_differential_evolution_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = _study(tmp_path, {**OPT, "optimize": {"objective": "energy", "method": "differential_evolution",
                                              "trials": 32}})
    out = tmp_path / "opt.parquet"
    assert main(["sweep", str(p), "-o", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "best: energy_per_cycle_J" in err
    df, meta = read_parquet(out)
    assert meta["best"]["objective"] == "energy_per_cycle_J"
    assert meta["best"]["value"] == pytest.approx(df[df["ok"].astype(bool)]["energy_per_cycle_J"].min())


def test_optimize_rejects_distributions(tmp_path: Path) -> None:
    body = {"parameters": {"mechanism.load.mass": {"distribution": "uniform", "low": "1 kg", "high": "2 kg"}},
            "optimize": {}}
    with pytest.raises(InputError) as exc:
        load_study(_study(tmp_path, body))
    assert exc.value.field == "parameters.mechanism.load.mass.distribution"


# ---------------------------------------------------------------------------------------------
# interrupted and resumed


def test_resume_after_interrupt(tmp_path: Path) -> None:
    study = load_study(_study(tmp_path, GRID))
    out = tmp_path / "r.parquet"

    def stop(n: int) -> None:
        if n >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run(study, out=out, workers=0, batch=2, on_rows=stop)
    part, _ = read_parquet(partial_path(out))
    assert len(part) == 4 and not out.exists()
    seen: list[int] = []
    df = run(study, out=out, workers=0, batch=2, resume=True, on_rows=seen.append)
    assert seen[0] == 6  # the 4 kept rows + the first new batch: nothing recomputed
    assert not partial_path(out).exists()
    whole = run(study, workers=0)
    assert list(df["variant"]) == list(range(12))
    cols = [c for c in whole.columns if c != "error"]
    pd.testing.assert_frame_equal(df[cols], whole[cols], check_dtype=False)


def test_resume_refuses_another_study(tmp_path: Path) -> None:
    out = tmp_path / "r.parquet"
    study = load_study(_study(tmp_path, GRID))
    with pytest.raises(KeyboardInterrupt):
        run(study, out=out, workers=0, batch=2, on_rows=lambda n: (_ for _ in ()).throw(KeyboardInterrupt()))
    other = load_study(_study(tmp_path, {**GRID, "name": "other"}, "o.yaml"))
    with pytest.raises(InputError) as exc:
        run(other, out=out, workers=0, resume=True)
    assert exc.value.field == "--resume"


def test_examples_validate() -> None:
    files = [f for f in sorted((EXAMPLES / "studies").glob("*.yaml"))
             if yaml.safe_load(f.read_text(encoding="utf-8")).get("study")]
    assert {f.stem for f in files} >= {"grid", "montecarlo", "optimize"}
    for f in files:
        s = load_study(f)
        assert s.spec.optimize is not None or s.n_variants() > 0
        assert not math.isnan(float(len(s.parameters)))


def test_documented_study_validates(tmp_path: Path) -> None:
    """The study file of docs/studies.md is accepted as written (its base pointed at the example)."""
    import re

    text = (Path(__file__).parents[2] / "docs" / "studies.md").read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"^```yaml\n(.*?)^```", text, re.MULTILINE | re.DOTALL) if "study: 1" in b]
    assert blocks
    for block in blocks:
        body = block.replace("base: ../ball_screw.yaml", f"base: {BASE}")
        s = parse_study(body, base_dir=tmp_path)
        assert s.n_variants() == 8 * 4 * 4
    opt = [b for b in re.findall(r"^```yaml\n(.*?)^```", text, re.MULTILINE | re.DOTALL) if "optimize:" in b]
    spec = yaml.safe_load(opt[0])["optimize"]
    s = parse_study(yaml.safe_dump({"study": 1, "base": str(BASE), "parameters": OPT["parameters"],
                                    "optimize": spec}), base_dir=tmp_path)
    assert s.spec.optimize is not None and s.spec.optimize.trials == 200


def test_remembered_units_read_as_pint_reads_them(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A study file's quantities read through the remembered unit factors (no pint registry) give the
    same units, SI factors and values as pint's own reading."""
    from drivetrain.study import spec as study_spec

    body = {"parameters": {"mechanism.lead": {"values": ["5 mm", "10 mm", "0.02 m"]},
                           "mechanism.load.mass": {"values": ["5 kg", "7.5 kg"], "unit": "g"},
                           "profile[0].time": {"start": "300 ms", "stop": "1 s", "num": 3}}, "design": "grid"}
    p = _study(tmp_path, body)
    drivetrain.size(BASE)  # the base file's units (mm, kg, s, ...) are remembered
    fast = load_study(p).parameters
    monkeypatch.setattr(study_spec, "_cached_unit", lambda unit: None)
    slow = load_study(p).parameters
    assert [(a.unit, a.si, a.values) for a in fast] == [(b.unit, b.si, b.values) for b in slow]
    assert fast[0].unit == "mm" and fast[0].values == (5.0, 10.0, 20.0)


def test_study_quantity_text_that_computes_is_refused(tmp_path: Path) -> None:
    """Quantity text goes through the units grammar before pint (which would evaluate 9**9**9)."""
    p = _study(tmp_path, {"parameters": {"mechanism.lead": {"values": ["9**9**9 mm"], "unit": "mm"}}})
    with pytest.raises(InputError) as exc:
        load_study(p)
    assert exc.value.field == "parameters.mechanism.lead.values[0]"
