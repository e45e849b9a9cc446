"""The scalar path of ``time_optimal_parameters`` (one move as floats) gives the array path's values."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain.motion.moves import time_optimal_parameters


@settings(max_examples=500, deadline=None)
@given(st.floats(-1e3, 1e3, allow_nan=False), st.floats(1e-3, 1e3), st.floats(1e-3, 1e4),
       st.one_of(st.just(math.inf), st.floats(1e-3, 1e6)))
def test_scalar_path_equals_the_array_path(d: float, vmax: float, amax: float, jmax: float) -> None:
    scalar = time_optimal_parameters(d, vmax, amax, jmax)
    array = time_optimal_parameters(np.array([d]), np.array([vmax]), np.array([amax]), np.array([jmax]))
    for name, s_val, a_val in zip(scalar._fields, scalar, array, strict=True):
        assert np.array_equal(np.asarray(s_val), a_val[0], equal_nan=True), name


def test_limits_outside_the_scalar_path_still_answer() -> None:
    """A zero limit or an infinite distance goes the array way (numpy's inf/nan rules), as before."""
    for args in [(1.0, 0.0, 1.0, 1.0), (math.inf, 1.0, 1.0, 1.0), (1.0, 1.0, 1.0, 0.0), (0, 1, 2, 3)]:
        got = time_optimal_parameters(*args)
        want = time_optimal_parameters(*(np.array([float(a)]) for a in args))
        for g, w in zip(got, want, strict=True):
            assert np.array_equal(np.asarray(g).ravel(), w, equal_nan=True)
