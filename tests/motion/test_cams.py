"""Cam laws for indexing: end conditions, continuity and the published peak coefficients.

Reference values: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3,
table of peak velocity, acceleration and jerk factors for double-dwell laws.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drivetrain.motion.cams import CAM_LAWS, cam_law, evaluate_pieces
from drivetrain.motion.profiles import parse_profile

# law: (C_v, C_a, C_j, relative tolerance of the published figures)
PUBLISHED = {
    "cycloidal": (2.0, 2.0 * math.pi, 4.0 * math.pi**2, 1e-12),
    "poly345": (1.875, 5.7735, 60.0, 1e-4),
    "modified_trapezoid": (2.0, 4.888, 61.43, 1e-3),
    "modified_sine": (1.76, 5.528, 69.47, 1e-3),
}
U = np.linspace(0.0, 1.0, 400_001)


@pytest.mark.parametrize("name", CAM_LAWS)
def test_rest_to_rest(name: str) -> None:
    s, v, a, _ = cam_law(name).evaluate(np.array([0.0, 1.0]))
    assert s[0] == 0.0 and s[1] == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(v, 0.0, atol=1e-14)
    np.testing.assert_allclose(a, 0.0, atol=1e-13)


@pytest.mark.parametrize("name", CAM_LAWS)
def test_published_peak_coefficients(name: str) -> None:
    law = cam_law(name)
    c_v, c_a, c_j, tol = PUBLISHED[name]
    assert law.c_v == pytest.approx(c_v, rel=tol)
    assert law.c_a == pytest.approx(c_a, rel=tol)
    assert law.c_j == pytest.approx(c_j, rel=max(tol, 1e-4))
    # the stated peaks are the true maxima over the whole rise
    _, v, a, j = law.evaluate(U)
    assert np.abs(v).max() == pytest.approx(law.c_v, rel=1e-9)
    assert np.abs(a).max() == pytest.approx(law.c_a, rel=1e-9)
    assert np.abs(j).max() == pytest.approx(law.c_j, rel=1e-9)


def test_norton_first_segment_formulas() -> None:
    """Norton writes the first eighth as s = 0.43990085 u - 0.0350062 sin(4 pi u) (modified sine)
    and s = 0.38898448 u - 0.0309544 sin(4 pi u) (modified trapezoid)."""
    u = np.linspace(0.0, 0.125, 101)
    for name, c1, c2 in (("modified_sine", 0.43990085, 0.0350062), ("modified_trapezoid", 0.38898448, 0.0309544)):
        s, _, _, _ = cam_law(name).evaluate(u)
        np.testing.assert_allclose(s, c1 * u - c2 * np.sin(4 * np.pi * u), rtol=0, atol=2e-8)
    s, _, _, _ = cam_law("poly345").evaluate(U[::1000])
    u3 = U[::1000]
    np.testing.assert_allclose(s, 10 * u3**3 - 15 * u3**4 + 6 * u3**5, rtol=0, atol=1e-14)


@pytest.mark.parametrize("name", CAM_LAWS)
def test_continuous_up_to_acceleration_and_symmetric(name: str) -> None:
    law = cam_law(name)
    for left, right in zip(law.pieces[:-1], law.pieces[1:], strict=True):
        end = evaluate_pieces(
            np.array([left.poly]), np.array([left.amp]), np.array([left.omega]), np.array([left.phase]),
            np.array([left.u1 - left.u0]),
        )
        start = law.evaluate(np.array([right.u0]))
        for k in range(3):
            assert end[k][0] == pytest.approx(start[k][0], abs=1e-13)
    s, v, a, _ = law.evaluate(U)
    np.testing.assert_allclose(s + s[::-1], 1.0, atol=1e-14)  # odd symmetry about the midpoint
    assert np.all(np.diff(s) >= -1e-15) and np.all(v >= -1e-14)
    assert np.all(a[U < 0.5] >= -1e-13) and np.all(a[U > 0.5] <= 1e-13)  # accel first half, decel second


def test_unknown_law() -> None:
    with pytest.raises(KeyError):
        cam_law("harmonic")


@pytest.mark.parametrize("name", CAM_LAWS)
def test_cam_move_in_a_rotary_profile(name: str) -> None:
    cycle = parse_profile([{"dwell": 0.2}, {"move": "-90 deg", "time": "0.4 s", "law": name}], "rotary")
    step = cycle.steps[1]
    h, t = math.pi / 2, 0.4
    law = cam_law(name)
    assert step.peak_speed == pytest.approx(law.c_v * h / t)
    assert step.peak_accel == pytest.approx(law.c_a * h / t**2)
    assert step.peak_jerk == pytest.approx(law.c_j * h / t**3)
    assert [(p.kind, p.t0, p.t1) for p in cycle.phases[1:]] == [
        ("accel", 0.2, pytest.approx(0.4)), ("decel", pytest.approx(0.4), pytest.approx(0.6))
    ]
    s = cycle.sample(65)
    assert s.x[-1] == pytest.approx(-h, rel=1e-14)
    assert np.abs(s.v).max() == pytest.approx(step.peak_speed, rel=1e-6)
    assert np.abs(s.v).max() <= step.peak_speed * (1 + 1e-12)
    assert np.all(s.direction[s.step == 1] == -1)
    # local scaling is exact: x(t) = x0 + h s((t - t0) / T)
    k = cycle.evaluate(np.linspace(0.2, 0.6, 101))
    s_n, _, a_n, _ = law.evaluate(np.linspace(0.0, 1.0, 101))
    np.testing.assert_allclose(k.x, -h * s_n, rtol=0, atol=1e-13)
    np.testing.assert_allclose(k.a, -h * a_n / t**2, rtol=0, atol=1e-10 * step.peak_accel)
