"""The compiled hull (sizing/hull.py) gives the plain-float chain's vertices (demand.chain), and
a demand built with it equals one built without it."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.sizing import motor_fit
from drivetrain.sizing.demand import chain
from drivetrain.sizing.hull import chains

# small integer grids make repeats, shared alphas and collinear runs common; floats make the rest
coord = st.one_of(st.integers(-4, 4).map(float), st.floats(-1e3, 1e3, allow_nan=False, allow_subnormal=False))
bins = st.lists(st.lists(st.tuples(coord, coord), min_size=0, max_size=40), min_size=1, max_size=6)


def _sorted_unique(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    return sorted(set(points))


@settings(max_examples=300, deadline=None)
@given(bins)
def test_compiled_chains_equal_the_python_chain(groups: list[list[tuple[float, float]]]) -> None:
    per_bin = [_sorted_unique(g) for g in groups]
    per_bin = [b for b in per_bin if b] or [[(0.0, 0.0)]]
    a = np.array([p[0] for b in per_bin for p in b])
    t = np.array([p[1] for b in per_bin for p in b])
    stops = np.cumsum([len(b) for b in per_bin])
    starts = stops - np.array([len(b) for b in per_bin])
    va, vt, counts = chains(a, t, starts, stops)
    end = 0
    for b, n in zip(per_bin, counts.tolist(), strict=True):
        want = chain([p[0] for p in b], [p[1] for p in b])
        got = list(zip(va[end:end + n].tolist(), vt[end:end + n].tolist(), strict=True))
        assert got == want
        end += n
    assert end == len(va)


def test_collinear_runs_keep_their_ends() -> None:
    a = np.linspace(0.0, 1.0, 1000)
    va, vt, counts = chains(a, 3.0 * a + 1.0, np.array([0]), np.array([1000]))
    assert counts.tolist() == [2]
    assert list(zip(va.tolist(), vt.tolist(), strict=True)) == [(0.0, 1.0), (1.0, 4.0)]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_demand_with_the_compiled_hull_equals_the_plain_one(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(seed)
    n = 5000
    t = np.linspace(0.0, 1.0, n)
    omega = 100.0 * np.sin(2 * np.pi * t) + rng.normal(0.0, 1.0, n)
    alpha = np.round(200.0 * np.cos(2 * np.pi * t), 1)  # repeated accelerations, as phases give
    torque = 0.5 + 1e-3 * alpha + 0.01 * omega + rng.normal(0.0, 0.05, n)
    weights = np.full(n, 1.0 / n)
    plain = motor_fit.demand(omega, alpha, torque, weights, 1.0, 1e-3)
    monkeypatch.setattr(motor_fit, "_COMPILED_FROM", 0)
    compiled = motor_fit.demand(omega, alpha, torque, weights, 1.0, 1e-3)
    for name in ("hull_speed", "hull_torque", "hull_alpha", "all_torque", "all_alpha"):
        np.testing.assert_array_equal(getattr(compiled, name), getattr(plain, name), err_msg=name)
