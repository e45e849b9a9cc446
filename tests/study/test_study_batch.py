"""The batched path of a study gives, variant by variant, what ``drivetrain.size`` gives.

A sample of variants of examples/ball_screw.yaml (load, lead, move time, margins, objectives,
gearbox options, a given motor, variants where nothing passes) is sized both ways: the selected
motor and gearbox, every check's required/available/margin and the RMS and peak torques must be
equal (the same arithmetic, so to rounding of the last bit at most).
"""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import drivetrain
from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing.hull import fast_demand
from drivetrain.sizing.motor_fit import demand
from drivetrain.study.batch import Engine, full_result
from drivetrain.study.record import row_from

EXAMPLES = Path(__file__).parents[2] / "examples"
BASE = yaml.safe_load((EXAMPLES / "ball_screw.yaml").read_text(encoding="utf-8"))


def ball_screw_variant(mass: float, lead: float, time: float) -> dict[str, Any]:
    """examples/ball_screw.yaml with another load mass, screw lead and first move time (a fresh copy)."""
    v = copy.deepcopy(BASE)
    v["mechanism"]["load"]["mass"] = mass
    v["mechanism"]["lead"] = lead
    v["profile"][0]["time"] = time
    return v


def _variant(mass: float, lead: float, time: float, **motor: Any) -> dict[str, Any]:
    v = ball_screw_variant(mass, lead, time)
    for k, val in motor.items():
        if k in ("objective", "gearbox", "max_inertia_ratio", "unknown"):
            v["motor"]["select"][k] = val
        else:
            v["motor"]["margins"][k] = val
    return v


def _same_candidate(fast: dict[str, Any], ref: dict[str, Any]) -> None:
    assert fast["motor"] == ref["motor"]
    assert fast["gearbox"] == ref["gearbox"]
    assert fast["ratio"] == ref["ratio"]
    assert fast["ok"] == ref["ok"]
    for key in ("rms_torque_Nm", "peak_torque_Nm", "inertia_ratio"):
        assert fast[key] == pytest.approx(ref[key], rel=1e-12)
    assert [c["name"] for c in fast["checks"]] == [c["name"] for c in ref["checks"]]
    for a, b in zip(fast["checks"], ref["checks"], strict=True):
        assert a["ok"] == b["ok"]
        for key in ("required", "available", "margin"):
            if a[key] is None or b[key] is None:
                assert a[key] == b[key]
            else:
                assert a[key] == pytest.approx(b[key], rel=1e-12, abs=1e-15)


SAMPLE = [
    _variant(5.0, 0.005, 0.3),
    _variant(25.0, 0.010, 0.5),
    _variant(40.0, 0.020, 1.0),
    _variant(12.0, 0.016, 0.4, objective="energy"),
    _variant(30.0, 0.005, 0.6, objective="rms_utilisation"),
    _variant(18.0, 0.012, 0.7, objective="inertia_match"),
    _variant(25.0, 0.010, 0.5, gearbox="only"),
    _variant(25.0, 0.010, 0.5, gearbox="none"),
    _variant(20.0, 0.008, 0.5, torque=1.5, inertia_ratio=3),
    _variant(25.0, 0.010, 0.5, unknown="fail"),  # a check that cannot be judged rejects the pair
    _variant(12.0, 0.016, 0.4, objective="energy", unknown="fail"),
    _variant(4000.0, 0.002, 0.21),  # nothing passes: the closest candidate
    _variant(4000.0, 0.002, 0.21, gearbox="none"),  # ... direct drive only
    _variant(4000.0, 0.002, 0.21, gearbox="only"),  # ... behind a gearbox only
    _variant(4000.0, 0.002, 0.21, unknown="fail"),  # ... an unknown check rejects too
]


@pytest.fixture(scope="module")
def engine() -> Engine:
    return Engine()


@pytest.mark.parametrize("k", range(len(SAMPLE)))
def test_selected_candidate_equals_size(engine: Engine, k: int) -> None:
    axis = parse_axis(SAMPLE[k])
    fast = engine.size(axis)
    ref = drivetrain.size(axis)
    d = ref.to_dict()
    assert fast["ok"] == ref.ok
    if ref.selection is not None and ref.selection.passing:
        _same_candidate(fast["selection"]["selected"], d["selection"]["selected"])
    else:
        assert "selected" not in fast["selection"]
        _same_candidate(fast["candidates"][0], d["candidates"][0])
        if "failures_by_check" in fast["selection"]:  # counted only where every candidate was evaluated
            assert fast["selection"]["failures_by_check"] == d["selection"]["failures_by_check"]
    for key in ("rms_torque_Nm", "peak_torque_Nm", "regen_energy_J", "max_speed_rpm"):
        assert fast[key] == d[key]


@pytest.mark.parametrize("k", range(len(SAMPLE)))
def test_keys_mean_what_size_says(engine: Engine, k: int) -> None:
    """Every key of the batched answer is a key of ``size().to_dict()`` with the same value (the
    selection's counts only where the batched search evaluated every candidate)."""
    axis = parse_axis(SAMPLE[k])
    fast, ref = engine.size(axis), full_result(axis)
    assert set(fast) == set(ref)
    assert set(fast["selection"]) <= set(ref["selection"])
    for key, value in fast["selection"].items():
        if key != "selected":
            assert value == ref["selection"][key], key
    for key in ("ok", "guide", "slip_check", "brake_check", "mechanism_checks", "gearbox_checks", "warnings"):
        assert fast.get(key) == ref.get(key), key


def test_nothing_passing_is_in_the_sample(engine: Engine) -> None:
    assert not any(engine.size(parse_axis(v))["ok"] for v in SAMPLE[-4:])


def test_given_motor_equals_size(engine: Engine) -> None:
    v = copy.deepcopy(BASE)
    v["motor"] = {"id": "SGM7J-04A", "margins": {"torque": 1.2}}
    axis = parse_axis(v)
    fast = engine.size(axis)
    ref = drivetrain.size(axis).to_dict()
    assert fast["motor"]["checks"] == ref["motor"]["checks"]
    assert fast["motor"]["rms_torque_Nm"] == ref["motor"]["rms_torque_Nm"]


def test_rows_of_both_paths_agree(engine: Engine) -> None:
    """The table row is the same whether a variant ran batched or through size().to_dict()."""
    record = ["motor", "gearbox", "margins", "rms", "peak", "energy", "checks"]
    for data in SAMPLE[:4]:
        axis = parse_axis(data)
        a, b = row_from(engine.size(axis), record), row_from(full_result(axis), record)
        assert a.keys() == b.keys()
        for key in a:
            if isinstance(a[key], float) and math.isnan(a[key]):
                assert math.isnan(b[key]), key
            elif not isinstance(a[key], float):
                assert a[key] == b[key], key
            else:
                assert a[key] == pytest.approx(b[key], rel=1e-12), key


def test_shared_kinematics_equal_fresh(engine: Engine) -> None:
    """Two axes with the same profile share sampled kinematics; the duty cycle equals a fresh one."""
    a, b = parse_axis(_variant(10.0, 0.01, 0.5)), parse_axis(_variant(33.0, 0.01, 0.5))
    engine.context.duty(a)
    shared = engine.context.duty(b)
    fresh = duty_cycle(b, engine.points)
    assert np.array_equal(shared.torque, fresh.torque)
    assert np.array_equal(shared.omega, fresh.omega)


@settings(max_examples=30, deadline=None)
@given(mass=st.floats(1.0, 200.0), lead=st.floats(0.002, 0.05), time=st.floats(0.25, 2.0),
       eff=st.sampled_from([1.0, 0.97, 0.9, 0.7]))
def test_compiled_hull_equals_demand(mass: float, lead: float, time: float, eff: float) -> None:
    """The compiled hull gives the same vertices (and padding) as motor_fit.demand."""
    from drivetrain.physics.stage import Stage

    axis = parse_axis(_variant(mass, lead, time))
    duty = duty_cycle(axis, 16)
    lossy = duty.behind(Stage("g", "gearbox", efficiency=eff, back_efficiency=eff), axis.efficiency_model)
    args = (duty.omega, duty.alpha, lossy.torque, duty.weights, duty.period, duty.load_inertia)
    a, b = fast_demand(*args), demand(*args)
    for key in ("hull_speed", "hull_torque", "hull_alpha", "all_torque", "all_alpha"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key


@settings(max_examples=20, deadline=None)
@given(mass=st.floats(1.0, 200.0), lead=st.floats(0.002, 0.05), time=st.floats(0.25, 2.0))
def test_batched_hulls_equal_demand(mass: float, lead: float, time: float) -> None:
    """Several efficiencies in one pass give each efficiency's motor_fit.demand."""
    from drivetrain.physics.stage import Stage
    from drivetrain.sizing.hull import fast_demands

    axis = parse_axis(_variant(mass, lead, time))
    duty = duty_cycle(axis, 16)
    torques = [duty.behind(Stage("g", "gearbox", efficiency=e, back_efficiency=e), axis.efficiency_model).torque
               for e in (1.0, 0.97, 0.9, 0.7)]
    got = fast_demands(duty.omega, duty.alpha, torques, duty.weights, duty.period, duty.load_inertia)
    for t, a in zip(torques, got, strict=True):
        b = demand(duty.omega, duty.alpha, t, duty.weights, duty.period, duty.load_inertia)
        for key in ("hull_speed", "hull_torque", "hull_alpha", "all_torque", "all_alpha"):
            assert np.array_equal(getattr(a, key), getattr(b, key)), key


def _random_variants(n: int, seed: int) -> list[dict[str, Any]]:
    """Variants over the benchmark grid's ranges (load 5-40 kg, lead 4-24 mm, move time 0.3-1 s), a
    quarter heavier, faster or both, some with other margins or gearbox options."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        motor: dict[str, Any] = {}
        if k % 5 == 1:
            motor["torque"] = float(rng.uniform(1.0, 2.0))
        if k % 7 == 2:
            motor["inertia_ratio"] = float(rng.uniform(2.0, 30.0))
        if k % 11 == 3:
            motor["gearbox"] = str(rng.choice(["only", "none"]))
        if k % 13 == 4:
            motor["unknown"] = "fail"
        mass, lead, time = float(rng.uniform(5.0, 40.0)), float(rng.uniform(0.004, 0.024)), float(rng.uniform(0.3, 1.0))
        if k % 4 == 0:  # heavy, fast or both: often nothing passes
            mass, lead, time = float(rng.uniform(5.0, 2000.0)), float(rng.uniform(0.002, 0.005)), float(
                rng.uniform(0.2, 0.4))
        out.append(_variant(mass, lead, time, **motor))
    return out


@pytest.mark.parametrize("data", _random_variants(60, 15))
def test_random_variants_equal_size(engine: Engine, data: dict[str, Any]) -> None:
    """60 random variants: the batched path's selected (or, when nothing passes, closest) candidate,
    its every check and the axis's own results equal those of drivetrain.size."""
    axis = parse_axis(data)
    fast, ref = engine.size(axis), full_result(axis)
    assert fast["ok"] == ref["ok"]
    if "selected" in ref["selection"]:
        _same_candidate(fast["selection"]["selected"], ref["selection"]["selected"])
    else:
        assert "selected" not in fast["selection"]
        _same_candidate(fast["candidates"][0], ref["candidates"][0])
    for key in ("rms_torque_Nm", "peak_torque_Nm", "mechanism_checks", "gearbox_checks", "brake_check"):
        assert fast.get(key) == ref.get(key), key
    assert fast["energy_per_cycle_J"] == pytest.approx(ref["energy_per_cycle_J"], rel=1e-12, nan_ok=True)


@settings(max_examples=25, deadline=None)
@given(mass=st.floats(1.0, 400.0), lead=st.floats(0.002, 0.05), time=st.floats(0.2, 2.0),
       torque=st.floats(1.0, 2.5), limit=st.floats(1.0, 50.0))
def test_search_bounds_hold_for_every_candidate(mass: float, lead: float, time: float, torque: float,
                                                limit: float) -> None:
    """What the search leaves out fails, and no candidate's worst margin is above its bound: checked
    against every candidate of the catalog (selection.evaluate)."""
    from drivetrain.sizing.search import load_tables, search_bounds
    from drivetrain.sizing.selection import evaluate

    axis = parse_axis(_variant(mass, lead, time, torque=torque, inertia_ratio=limit))
    spec, margins = axis.spec.motor.select, axis.spec.motor.margins
    duty = duty_cycle(axis, 16)
    tb = load_tables(axis, spec)
    c = evaluate(axis, duty, tb.motors, tb.gb, margins, allow_direct=tb.allow_direct)
    b = search_bounds(tb, duty, margins, spec)
    rows = c.gearbox(np.arange(len(c.motor)))
    group = c.slot_group[c.slot]
    kept = b.feasible[group, c.motor] & np.where(rows >= 0, b.row_ok[np.maximum(rows, 0)], True)
    assert not np.any(c.ok & ~kept)
    bound = np.minimum(b.pair_bound[group, c.motor], np.where(rows >= 0, b.row_bound[np.maximum(rows, 0)], np.inf))
    known = ~np.isnan(c.worst_margin)
    assert np.all(c.worst_margin[known] <= bound[known])


def test_drives_left_out_change_nothing_else() -> None:
    """size(drives=False) is size() without the drive post-pass's blocks."""
    from drivetrain.sizing.pipeline import size

    data = _variant(25.0, 0.010, 0.5)
    a, b = size(data).to_dict(), size(data, drives=False).to_dict()
    post = ("drive", "electrical", "regen")
    assert any(k in a["selection"]["selected"] for k in post)
    assert not any(k in b["selection"]["selected"] for k in post)
    for d in (a, b):
        d.pop("order")  # the order sheet reads the drive blocks
        for cand in [d["selection"]["selected"], *d["candidates"]]:
            for k in post:
                cand.pop(k, None)
    assert a == b


def test_a_recorded_drive_key_runs_the_drive_post_pass(tmp_path: Path) -> None:
    """A study that records a key of the drive post-pass gets it from the batched path with drives."""
    from drivetrain.study import load_study
    from drivetrain.study.runner import make_plan, run_batch

    study_file = tmp_path / "s.yaml"
    study_file.write_text(yaml.safe_dump({
        "study": 1, "base": str(EXAMPLES / "ball_screw.yaml"),
        "parameters": {"mechanism.load.mass": ["10 kg", "30 kg"]},
        "record": ["motor", "selection.selected.drive.id", "selection.selected.electrical.rms_current_A"]}))
    study = load_study(study_file)
    plan = make_plan(study)
    assert plan.drives and not plan.full
    rows = run_batch(plan, list(enumerate(study.variants())))
    for row, values in zip(rows, study.variants(), strict=True):
        ref = row_from(full_result(parse_axis(plan.axis_dict(values))), list(plan.record))
        assert row["selection.selected.drive.id"] == ref["selection.selected.drive.id"]
        assert row["selection.selected.electrical.rms_current_A"] == ref["selection.selected.electrical.rms_current_A"]
        assert row["motor"] == ref["motor"]


def test_a_variant_value_of_bad_text_is_refused_in_its_row() -> None:
    """The run path checks the base file's text once and each variant's new values (a lone
    surrogate is refused in the variant's row, naming the parameter's path), as parse_axis would."""
    from drivetrain.study.runner import Plan, run_batch
    from drivetrain.study.spec import Parameter

    par = Parameter(path="axis", tokens=("axis",), unit=None, si=1.0, values=("fine name", "bad \ud800 name"))
    plan = Plan(base=BASE, parameters=(par,), record=("ok",), points=64, full=False)
    rows = run_batch(plan, [(0, ("fine name",)), (1, ("bad \ud800 name",))])
    assert rows[0]["error"] == "" and rows[0]["ok"] == drivetrain.size(BASE).ok
    assert rows[1]["ok"] is False
    assert "axis" in rows[1]["error"] and "Unicode" in rows[1]["error"]


BELT_DYNAMIC = yaml.safe_load((EXAMPLES / "belt_dynamic.yaml").read_text(encoding="utf-8"))


@pytest.mark.parametrize("mass", [6.0, 9.0, 12.0, 15.0, 20.0])
def test_requirements_variants_equal_size(engine: Engine, mass: float) -> None:
    """examples/belt_dynamic.yaml over load masses where its static pick passes its dynamic requirements
    and where it fails them (the search's pick passed over: the walk down the whole ranking): the study's
    answer is ``drivetrain.size``'s on the selected motor, gearbox, every margin, the next smaller motor,
    the optimal ratio and the whole dynamics block."""
    v = copy.deepcopy(BELT_DYNAMIC)
    v["mechanism"]["load"]["mass"] = mass
    axis = parse_axis(v)
    ref = drivetrain.size(axis)
    fast, d = engine.size(axis), ref.to_dict()
    assert fast["ok"] == ref.ok
    _same_candidate(fast["selection"]["selected"], d["selection"]["selected"])
    assert fast["selection"]["dynamics"] == d["selection"]["dynamics"]
    assert fast["selection"].get("drive_passed_over") == d["selection"].get("drive_passed_over")
    passed = fast["selection"]["dynamics"]["passed_over"]
    if passed:  # the walk's answer: its neighbours as size's
        for key in ("next_smaller", "optimal_ratio"):
            assert fast["selection"].get(key) == d["selection"].get(key)
