"""The sampled cycle with its breakaway copies (motion/cycle.py): every column equals numpy's
``np.insert`` of a copy of each move's first sample (the construction it replaces), on random
profiles (hypothesis)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.motion import cycle as cycle_module
from drivetrain.motion.cams import CAM_LAWS, evaluate_pieces
from drivetrain.motion.profiles import parse_profile

move = st.builds(lambda d, t, f: {"move": f"{d} mm", "time": f"{t} s", "accel": f"{t * f} s"},
                 st.sampled_from([-300, -50, 20, 200]), st.floats(0.1, 2.0), st.floats(0.05, 0.5))
dwell = st.builds(lambda t: {"dwell": f"{t} s"}, st.floats(0.01, 1.0))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(move, dwell), min_size=1, max_size=8).filter(lambda p: any("move" in s for s in p)),
       st.integers(3, 40))
def test_copies_equal_numpys_insert(profile: list[dict[str, str]], points: int) -> None:
    got = parse_profile(profile, "linear").sample(points)
    copy_at = np.flatnonzero(got.breakaway)
    assert copy_at.size >= 1
    plain = np.delete(np.arange(got.t.size), copy_at)
    starts = copy_at - np.arange(copy_at.size)  # index of each copied sample among the plain ones
    for name in ("t", "x", "v", "a", "j", "direction", "step", "phase", "segment", "holding", "braked", "thrust",
                 "weights", "breakaway"):
        col = getattr(got, name)
        base = col[plain]
        value = {"weights": np.zeros(starts.size), "breakaway": np.ones(starts.size, dtype=bool)}.get(name,
                                                                                                       base[starts])
        np.testing.assert_array_equal(col, np.insert(base, starts, value), err_msg=name)
    assert not got.breakaway[plain].any() and (got.weights[plain] > 0).all()


law = st.builds(lambda d, t, name: {"move": f"{d} mm", "time": f"{t} s", "law": name},
                st.sampled_from([-120, 35, 400]), st.floats(0.05, 2.0), st.sampled_from(CAM_LAWS))
s_curve = st.builds(lambda d, t, f: {"move": f"{d} mm", "time": f"{t} s", "shape": "s_curve", "jerk_fraction": f},
                    st.sampled_from([-80, 10, 250]), st.floats(0.05, 2.0), st.floats(0.0, 1.0))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(move, dwell, law, s_curve), min_size=1, max_size=6), st.integers(3, 60))
def test_in_place_sampling_equals_the_grid(profile: list[dict[str, str]], points: int) -> None:
    """Many points per segment are written segment by segment in place (cycle.DIRECT_POINTS): every
    column is the same, float for float, as the one-grid construction of fewer points."""
    cycle = parse_profile(profile, "linear")
    grid = cycle.sample(points)
    original = cycle_module.DIRECT_POINTS
    try:
        cycle_module.DIRECT_POINTS = 3
        direct = cycle.sample(points)
    finally:
        cycle_module.DIRECT_POINTS = original
    for name in ("t", "x", "v", "a", "j", "direction", "step", "phase", "segment", "holding", "braked", "thrust",
                 "weights", "breakaway"):
        a, b = getattr(grid, name), getattr(direct, name)
        assert a.dtype == b.dtype, name
        np.testing.assert_array_equal(a, b, err_msg=name)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(move, dwell, law, s_curve), min_size=1, max_size=6), st.integers(3, 60), st.booleans())
def test_columns_equal_the_full_grid(profile: list[dict[str, str]], points: int, in_place: bool) -> None:
    """Every column (those computed on first use included) equals the construction it replaces: all four
    kinematic columns of the full-degree polynomials on one grid, then np.insert of the breakaway copies."""
    cycle = parse_profile(profile, "linear")
    original = cycle_module.DIRECT_POINTS
    try:
        cycle_module.DIRECT_POINTS = 3 if in_place else original
        got = cycle.sample(points)
    finally:
        cycle_module.DIRECT_POINTS = original
    n = max(3, points | 1)
    tab = cycle._table
    frac = np.linspace(0.0, 1.0, n)
    t = tab.t0[:, None] + (tab.t1 - tab.t0)[:, None] * frac[None, :]
    t[:, -1] = tab.t1
    simpson = np.ones(n)
    simpson[1:-1:2], simpson[2:-1:2] = 4.0, 2.0
    weights = ((tab.t1 - tab.t0)[:, None] / (3.0 * (n - 1))) * simpson[None, :]
    x, v, a, j = evaluate_pieces(tab.coeffs[:, None, :], tab.amp[:, None], tab.omega[:, None], tab.phase[:, None],
                                 tab.span[:, None] * frac[None, :])
    copy_at = np.flatnonzero(got.breakaway)
    starts = copy_at - np.arange(copy_at.size)
    for name, grid in {"t": t, "x": x, "v": v, "a": a, "j": j, "weights": weights}.items():
        base = grid.ravel()
        want = np.insert(base, starts, 0.0 if name == "weights" else base[starts])
        np.testing.assert_array_equal(getattr(got, name), want, err_msg=name)
