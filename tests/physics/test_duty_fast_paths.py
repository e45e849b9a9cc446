"""The duty cycle's shorter paths give the answers of the formulas they replace (hypothesis).

``torque_in`` computes the sign of motion once for the stage's Coulomb friction and its quadrant and
skips terms whose coefficient is zero; ``speed_sign`` takes the sign after choosing; ``evaluate_pieces``
runs Horner's scheme from the highest non-zero coefficient. Each is compared with the formula written
out in full (the previous construction), on random stages, speeds and polynomials.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from drivetrain.motion.cams import DEGREE, evaluate_pieces
from drivetrain.physics.efficiency import speed_sign
from drivetrain.physics.loads import coulomb_friction
from drivetrain.physics.stage import Stage, torque_in

N = 40
values = arrays(np.float64, N, elements=st.one_of(st.just(0.0), st.floats(-50.0, 50.0)))
directions = arrays(np.float64, N, elements=st.sampled_from([-1.0, 0.0, 1.0]))
maybe_zero = st.one_of(st.just(0.0), st.floats(1e-6, 2.0))
stages = st.builds(Stage, name=st.just("s"), kind=st.just("gearbox"), ratio=st.floats(0.1, 50.0),
                   inertia_in=maybe_zero, inertia_inside=maybe_zero, efficiency=st.floats(0.3, 1.0),
                   back_efficiency=st.one_of(st.just(0.0), st.floats(0.1, 1.0)), friction_torque_in=maybe_zero)


def _reference(stage: Stage, t_out: np.ndarray, ext_out: np.ndarray, omega: np.ndarray, alpha: np.ndarray,
               direction: np.ndarray, model: str) -> tuple[np.ndarray, np.ndarray]:
    """torque_in as written before: every term computed, the sign of motion twice."""
    i = stage.ratio
    coulomb = stage.friction_torque_in * np.sign(np.where(omega != 0.0, omega, direction))
    if model == "load_torque_only":
        ext = ext_out / (i * stage.efficiency) + coulomb
        return (t_out - ext_out) / i + stage.inertia * alpha + ext, ext
    bracket = stage.inertia_inside * alpha + t_out / i
    s = np.where(omega != 0.0, np.sign(omega), np.sign(direction))
    out = np.where(bracket * s > 0.0, bracket / stage.efficiency, bracket * stage.back_efficiency)
    held = np.zeros_like(bracket) if stage.back_efficiency <= 0.0 else bracket / stage.efficiency
    out = np.where(s == 0.0, held, out)
    return stage.inertia_in * alpha + out + coulomb, ext_out / i


@settings(max_examples=200, deadline=None)
@given(stages, values, values, values, values, directions, st.sampled_from(["four_quadrant", "load_torque_only"]))
def test_torque_in_equals_the_full_formula(stage: Stage, t_out: np.ndarray, ext_out: np.ndarray, omega: np.ndarray,
                                           alpha: np.ndarray, direction: np.ndarray, model: str) -> None:
    got = torque_in(stage, t_out, ext_out, omega, alpha, direction, model)  # type: ignore[arg-type]
    want = _reference(stage, t_out, ext_out, omega, alpha, direction, model)
    for g, w in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, w)  # equal floats (a zero may differ only in its sign)


@given(values, directions)
def test_speed_sign_equals_the_choice_of_signs(omega: np.ndarray, direction: np.ndarray) -> None:
    np.testing.assert_array_equal(speed_sign(omega, direction),
                                  np.where(omega != 0.0, np.sign(omega), np.sign(direction)))


def _horner_full(coef: np.ndarray, w: np.ndarray) -> np.ndarray:
    acc = np.empty(np.broadcast_shapes(w.shape, coef.shape[:-1]))
    acc[...] = coef[..., -1]
    for col in range(coef.shape[-1] - 2, -1, -1):
        acc *= w
        acc += coef[..., col]
    return acc


@settings(max_examples=200, deadline=None)
@given(st.integers(0, DEGREE), st.integers(1, 6), st.data())
def test_trimmed_horner_equals_the_full_degree(degree: int, pieces: int, data: st.DataObject) -> None:
    coef = np.zeros((pieces, DEGREE + 1))
    coef[:, : degree + 1] = data.draw(arrays(np.float64, (pieces, degree + 1), elements=st.floats(-1e3, 1e3)))
    w = data.draw(arrays(np.float64, (pieces, 7), elements=st.floats(0.0, 5.0)))
    zeros = np.zeros((pieces, 1))
    got = evaluate_pieces(coef[:, None, :], zeros, zeros, zeros, w)
    derivs = [coef[:, None, :]]
    for _ in range(3):
        c = derivs[-1]
        derivs.append(c[..., 1:] * np.arange(1, c.shape[-1], dtype=float))
    for g, c in zip(got, derivs, strict=True):
        np.testing.assert_array_equal(g, _horner_full(c, w))


@given(values, directions, st.one_of(st.none(), arrays(np.bool_, N)), st.floats(0.0, 1.0), st.floats(0.0, 1.0),
       st.floats(0.0, 1e4))
def test_coulomb_friction_equals_the_full_formula(v: np.ndarray, direction: np.ndarray, breakaway: np.ndarray | None,
                                                  mu: float, mu_static: float, normal: float) -> None:
    d = np.sign(direction)
    sliding = np.where(v != 0.0, np.sign(v), d) * mu * normal
    start = (v == 0.0) if breakaway is None else breakaway
    want = np.where(start, d * mu_static * normal, sliding)
    np.testing.assert_array_equal(coulomb_friction(normal, mu, mu_static, v, direction, breakaway), want)
