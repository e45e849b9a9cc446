"""Invariants of the machine-cycle grid and the shared bus (hypothesis)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.physics import dc_bus, regen

floats = st.floats(min_value=-1000.0, max_value=1000.0, allow_nan=False)


@st.composite
def axis_trace(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """An axis's power over its own cycle: piecewise linear with jumps (repeated times)."""
    n = draw(st.integers(min_value=2, max_value=12))
    steps = np.array(draw(st.lists(st.floats(min_value=0.01, max_value=0.5), min_size=n - 1, max_size=n - 1)))
    t = np.concatenate([[0.0], np.cumsum(steps)])
    jumps = draw(st.lists(st.integers(min_value=1, max_value=n - 2), max_size=3, unique=True)) if n > 2 else []
    for k in sorted(jumps, reverse=True):
        t = np.insert(t, k, t[k])
    p = np.array(draw(st.lists(floats, min_size=t.size, max_size=t.size)))
    return t, p


@settings(max_examples=60, deadline=None)
@given(axis_trace(), st.floats(min_value=0.0, max_value=1.0), st.floats(min_value=0.0, max_value=3.0),
       st.integers(min_value=1, max_value=50))
def test_the_grid_integrates_an_axis_exactly(trace: tuple[np.ndarray, np.ndarray], frac: float, extra: float,
                                             uniform: int) -> None:
    """On the machine grid, an axis's energy is its own cycle's energy plus its rest at the last value."""
    t, p = trace
    cycle = float(t[-1]) + extra
    offset = frac * cycle
    g, right, w = dc_bus.periodic_grid([t + offset], cycle, uniform)
    q = dc_bus.periodic_resample(t, p, g, offset, cycle, right)
    own = float(np.sum(regen.trapezoid_weights(t) * p)) + (cycle - float(t[-1])) * float(p[-1])
    assert np.isclose(float(np.sum(w * q)), own, rtol=1e-9, atol=1e-6 * (1.0 + np.abs(p).max() * cycle))
    assert np.isclose(float(w.sum()), cycle)
    # every sample of the axis is on the grid: its extremes are kept
    assert np.isclose(q.max(), max(p.max(), p[-1])) and np.isclose(q.min(), min(p.min(), p[-1]))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(floats, min_size=5, max_size=5), min_size=1, max_size=4))
def test_shared_energy_is_bounded_by_braking_and_motoring(rows: list[list[float]]) -> None:
    p = np.array(rows)
    w = np.full(p.shape[1], 0.1)
    shared = dc_bus.shared_energy(p, w)
    braking = float(np.sum(w * np.maximum(-p, 0.0)))
    motoring = float(np.sum(w * np.maximum(p, 0.0)))
    assert -1e-9 <= shared <= min(braking, motoring) + 1e-9
    # what the bus still receives is the braking less what was shared
    assert np.isclose(float(np.sum(w * np.maximum(-p.sum(axis=0), 0.0))), braking - shared, atol=1e-9)
    if p.shape[0] == 1:
        assert shared == 0.0
