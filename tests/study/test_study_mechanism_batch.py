"""The mechanism checks of a study's batch, computed together, equal those of each axis alone.

``mechanism_checks.prepare_many`` computes the screw, nut and guide checks of many axes as arrays
over the axes; ``mechanism_checks`` of a prepared axis returns them. Each entry (name, required,
available, margin, ok, note) must equal, to the bit, what ``mechanism_checks`` computes for that
axis alone, and ``Engine.size_many`` must give each axis the answer of ``Engine.size`` and of
``drivetrain.size`` (tests/study/test_study_batch.py holds the sample-agreement tests of the engine).
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.errors import InputError
from drivetrain.physics import rolling_life
from drivetrain.sizing.mechanism_checks import mechanism_checks, prepare_many
from drivetrain.study.batch import Engine, full_result
from tests.study.test_study_batch import ball_screw_variant

EXAMPLES = Path(__file__).parents[2] / "examples"


def _variant(mass: float, lead: float, time: float, **changes: Any) -> dict[str, Any]:
    v = ball_screw_variant(mass, lead, time)
    for path, value in changes.items():
        node = v
        *head, last = path.split("__")
        for key in head:
            node = node.setdefault(key, {})
        node[last] = value
    return v


def _mixed() -> list[dict[str, Any]]:
    """Variants over the benchmark grid's ranges and several groups: other guide orientations,
    a preloaded nut, a moment without its factor, another stroke, no nut, no screw ratings."""
    rng = np.random.default_rng(5)
    out = []
    for k in range(48):
        mass, lead, time = float(rng.uniform(5.0, 40.0)), float(rng.uniform(0.004, 0.024)), float(rng.uniform(0.3, 1.0))
        changes: dict[str, Any] = {}
        if k % 6 == 1:
            changes["guide__orientation"] = "horizontal"
            changes["guide__l_x"] = "20 mm"
        if k % 6 == 2:
            changes["guide__orientation"] = "wall"
            changes["guide__l_y"] = "15 mm"  # a yaw moment without a moment factor: said in the note
        if k % 6 == 3:
            changes["mechanism__nut__preload"] = "400 N"
        if k % 6 == 4:
            changes["profile"] = [{"move": "150 mm", "time": time, "accel": 0.1}, {"dwell": 0.3},
                                  {"move": "-150 mm", "time": 0.5, "accel": 0.1}, {"dwell": 0.2}]
        out.append(_variant(mass, lead, time, **changes))
    no_nut = _variant(20.0, 0.01, 0.5)
    del no_nut["mechanism"]["nut"]
    no_screw = _variant(20.0, 0.01, 0.5)
    del no_screw["mechanism"]["screw"]
    return [*out, no_nut, no_screw]


@pytest.mark.parametrize("slice_", [256, 7])
def test_prepared_checks_equal_each_axis_alone(slice_: int, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("drivetrain.sizing.mechanism_checks.PREPARE_SLICE", slice_)
    axes = [parse_axis(d) for d in _mixed()]
    duties = [duty_cycle(a, 64) for a in axes]
    alone = [mechanism_checks(a, d) for a, d in zip(axes, duties, strict=True)]
    together = prepare_many(list(zip(axes, duties, strict=True)))
    assert all(checks is not None for checks in together)
    assert together == alone  # every entry to the bit, notes included
    names = {c.name for checks in alone for c in checks}
    assert {"screw_buckling", "screw_dn_speed", "nut_life", "nut_static_safety", "guide_life",
            "guide_static_safety"} <= names
    assert any("moments without moment_factors" in c.note for checks in alone for c in checks)


def test_prepared_checks_are_returned_not_kept_on_the_duty_cycle() -> None:
    a, b = parse_axis(_variant(10.0, 0.01, 0.5)), parse_axis(_variant(35.0, 0.01, 0.5))
    da = duty_cycle(a, 32)
    fresh = duty_cycle(a, 32)
    assert prepare_many([(a, da)]) == [mechanism_checks(a, fresh)]
    assert set(vars(da)) == set(vars(fresh))  # nothing stashed on the duty cycle
    assert mechanism_checks(b, da) != mechanism_checks(a, da)  # computed for b
    assert mechanism_checks(b, da) == mechanism_checks(b, fresh)


def test_a_group_that_would_raise_is_left_to_each_axis() -> None:
    """A group whose numbers break a rule is not prepared: each axis raises its own InputError."""
    bad = _variant(20.0, 0.01, 0.5, mechanism__screw__home_position="790 mm")  # nut beyond the screw
    good = _variant(20.0, 0.01, 0.5)
    axes = [parse_axis(bad), parse_axis(good)]
    duties = [duty_cycle(a, 32) for a in axes]
    got = prepare_many(list(zip(axes, duties, strict=True)))
    assert got[0] is None and got[1] is not None
    with pytest.raises(InputError, match="home_position"):
        mechanism_checks(axes[0], duties[0])


def test_size_many_equals_size_axis_by_axis() -> None:
    data = [*_mixed()[:12], _variant(4000.0, 0.002, 0.21)]
    impossible = _variant(20.0, 0.01, 0.5)
    impossible["profile"][0]["accel"] = "0.4 s"  # accel + decel longer than the move: bad input
    axes = [parse_axis(d) for d in [*data, impossible]]
    got = Engine().size_many(axes)
    assert isinstance(got[-1], InputError)
    with pytest.raises(InputError) as alone:
        Engine().size(axes[-1])
    assert str(got[-1]) == str(alone.value)
    engine = Engine()
    for axis, fast in zip(axes[:-1], got[:-1], strict=True):
        assert not isinstance(fast, InputError)
        assert fast == engine.size(axis)
        ref = full_result(axis)
        assert fast["mechanism_checks"] == ref["mechanism_checks"]
        assert fast["ok"] == ref["ok"]
        sel = ref["selection"].get("selected") or ref["candidates"][0]
        mine = fast["selection"].get("selected") or fast["candidates"][0]
        assert (mine["motor"], mine["gearbox"]) == (sel["motor"], sel["gearbox"])


@settings(max_examples=60, deadline=None)
@given(shape=st.tuples(st.integers(1, 6), st.integers(1, 40)), data=st.data(),
       exponent=st.sampled_from([3.0, 10.0 / 3.0]))
def test_cubic_mean_loads_equal_cubic_mean_load_row_by_row(shape: tuple[int, int], data: st.DataObject,
                                                            exponent: float) -> None:
    loads = data.draw(hnp.arrays(float, shape, elements=st.floats(-1e5, 1e5)))
    weights = data.draw(hnp.arrays(float, shape, elements=st.floats(1e-6, 10.0)))
    rows = rolling_life.cubic_mean_loads(loads, weights, exponent)
    for k in range(shape[0]):
        assert rows[k] == rolling_life.cubic_mean_load(loads[k], weights[k], exponent)


def test_cubic_mean_loads_refuse_what_cubic_mean_load_refuses() -> None:
    with pytest.raises(InputError, match="weights"):
        rolling_life.cubic_mean_loads(np.ones((2, 3)), np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]))
    with pytest.raises(InputError, match="finite"):
        rolling_life.cubic_mean_loads(np.array([[1.0, np.nan]]), np.ones((1, 2)))
    assert rolling_life.cubic_mean_loads(np.zeros((1, 3)), np.ones((1, 3)))[0] == 0.0


@pytest.mark.parametrize(("n", "size", "workers"),
                         [(10_000, 200, 2), (1000, 200, 4), (7, 3, 2), (0, 5, 1), (450, 100, 1)])
def test_tasks_cover_every_variant_once_in_order(n: int, size: int, workers: int) -> None:
    from drivetrain.study.runner import _tasks

    items = [(k, (float(k),)) for k in range(n)]
    tasks = list(_tasks(items, size, workers))
    assert [it for t in tasks for it in t] == items
    assert all(0 < len(t) <= size for t in tasks)
    if n >= 2 * workers * size:
        assert sum(len(t) == max(1, size // 4) for t in tasks) >= 2 * workers * 4 - 1  # the short tail


def _one_motion() -> list[dict[str, Any]]:
    """Variants of one lead and move time (the load masses of one motion), some with other margins
    or gearbox options, and two of another motion."""
    out = [_variant(m, 0.01, 0.5) for m in (5.0, 12.0, 25.0, 40.0, 400.0, 4000.0)]
    out += [_variant(20.0, 0.01, 0.5, motor__select__gearbox="only"),
            _variant(20.0, 0.01, 0.5, motor__margins__torque=1.6),
            _variant(20.0, 0.01, 0.5, motor__select__objective="energy"),
            _variant(8.0, 0.016, 0.4), _variant(30.0, 0.016, 0.4)]
    return out


def test_hulls_of_one_motion_equal_each_variant_alone() -> None:
    """The hulls ``size_many`` computes for the variants of one motion together equal, array for
    array, those of each variant alone (``fast_demands``), the load inertia its own."""
    from drivetrain.sizing.hull import fast_demands
    from drivetrain.sizing.search import prepare_hulls
    from drivetrain.sizing.selection import lossy_torque

    engine = Engine()
    axes = [parse_axis(d) for d in _one_motion()]
    pairs = [(a, engine.context.duty(a)) for a in axes]
    checked = 0
    for (axis, duty), prepared in zip(pairs, prepare_hulls(engine.context.tables, pairs), strict=True):
        for eff, dem in ({} if prepared is None else prepared.demands).items():
            [alone] = fast_demands(duty.omega, duty.alpha, [lossy_torque(axis, duty, eff)], duty.weights, duty.period,
                                   duty.load_inertia)
            for name in ("omega", "alpha", "torque", "weights", "hull_speed", "hull_torque", "hull_alpha",
                         "all_torque", "all_alpha"):
                assert np.array_equal(getattr(dem, name), getattr(alone, name)), name
            assert (dem.period, dem.load_inertia) == (alone.period, alone.load_inertia)
            checked += 1
    assert checked >= 8


def test_size_many_of_one_motion_equals_size() -> None:
    axes = [parse_axis(d) for d in _one_motion()]
    got = Engine().size_many(axes)
    engine = Engine()
    for axis, fast in zip(axes, got, strict=True):
        assert fast == engine.size(axis)
        ref = full_result(axis)
        assert fast["ok"] == ref["ok"]
        sel = ref["selection"].get("selected") or ref["candidates"][0]
        mine = fast["selection"].get("selected") or fast["candidates"][0]
        assert (mine["motor"], mine["gearbox"]) == (sel["motor"], sel["gearbox"])
        for a, b in zip(mine["checks"], sel["checks"], strict=True):
            assert a["name"] == b["name"]
            assert a["margin"] == b["margin"] or a["margin"] == pytest.approx(b["margin"], rel=1e-12)


def test_variants_of_one_motion_go_together() -> None:
    from drivetrain.study import load_study
    from drivetrain.study.runner import _by_motion

    study_file = EXAMPLES / "studies" / "grid.yaml"
    study = load_study(study_file)
    items = list(enumerate(study.variants()))
    grouped = _by_motion(items, study.parameters)
    assert sorted(grouped) == items
    motion = [tuple(v for p, v in zip(study.parameters, values, strict=True) if p.path != "mechanism.load.mass")
              for _, values in grouped]
    changes = sum(a != b for a, b in itertools.pairwise(motion))
    assert changes == len(set(motion)) - 1  # each motion's variants in one run
