"""Cam displacement laws for indexing moves, in normalised form.

A law maps normalised time ``u = t / T`` in [0, 1] to normalised displacement ``s(u)`` in
[0, 1], rest to rest: ``s(0) = 0``, ``s(1) = 1`` and ``s' = s'' = 0`` at both ends. A move of
distance ``h`` [m or rad] in time ``T`` [s] follows ``x(t) = h s(t / T)``, so its peaks are
``v = C_v h / T``, ``a = C_a h / T^2`` and ``j = C_j h / T^3`` with the law's coefficients.

Each law is built from its acceleration, as the cam texts define it, and integrated exactly:
every piece is a polynomial plus at most one sinusoid, ``s(w) = sum q_k w^k + A sin(W w + P)``
in the piece's local coordinate ``w = u - u0``. Pieces are split at ``u = 1/2`` so that the
first half (acceleration) and the second half (deceleration) never share a piece.

Source: R. L. Norton, *Cam Design and Manufacturing Handbook*, 2nd ed., Industrial Press
(2009), ch. 3 "Double-dwell cam design" (cycloidal, modified trapezoid, modified sine, 3-4-5
polynomial), with the peak coefficients of its table 3-2: cycloidal C_v = 2, C_a = 6.2832,
C_j = 39.48; modified trapezoid 2.0, 4.8881, 61.43; modified sine 1.7596, 5.5280, 69.47;
3-4-5 polynomial 1.8750, 5.7735, 60.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

CAM_LAWS: tuple[str, ...] = ("cycloidal", "modified_sine", "modified_trapezoid", "poly345")
"""Valid ``law:`` names of an indexing move."""

DEGREE = 5
"""Highest power of the position polynomial of any piece (the 3-4-5 law)."""


class CamPiece(NamedTuple):
    """One piece of a normalised law on [u0, u1]: ``s(w) = sum(poly[k] w^k) + amp sin(omega w + phase)``.

    ``w = u - u0`` is the local normalised time; ``poly`` has DEGREE + 1 ascending coefficients.
    """

    u0: float
    u1: float
    poly: tuple[float, ...]
    amp: float
    omega: float
    phase: float


class _Accel(NamedTuple):
    """Normalised acceleration on [u0, u1] as the texts write it, in global u:
    ``s''(u) = poly(u) + b sin(omega u + phase)`` (scaled afterwards so that s(1) = 1)."""

    u0: float
    u1: float
    poly: tuple[float, ...]
    b: float = 0.0
    omega: float = 0.0
    phase: float = 0.0


@dataclass(frozen=True)
class CamLaw:
    """A normalised rest-to-rest displacement law with its peak coefficients.

    ``c_v``, ``c_a``, ``c_j`` [-] are the largest magnitudes of s', s'' and s''' over [0, 1].
    """

    name: str
    pieces: tuple[CamPiece, ...]
    c_v: float
    c_a: float
    c_j: float

    def evaluate(self, u: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Normalised s, s', s'', s''' at ``u`` in [0, 1] (right limits at piece boundaries)."""
        uu = np.asarray(u, dtype=float)
        starts = np.array([p.u0 for p in self.pieces])
        idx = np.clip(np.searchsorted(starts, uu, side="right") - 1, 0, len(self.pieces) - 1)
        poly = np.array([p.poly for p in self.pieces])[idx]
        amp = np.array([p.amp for p in self.pieces])[idx]
        omega = np.array([p.omega for p in self.pieces])[idx]
        phase = np.array([p.phase for p in self.pieces])[idx]
        return evaluate_pieces(poly, amp, omega, phase, uu - starts[idx])


def evaluate_pieces(
    poly: FloatArray, amp: FloatArray, omega: FloatArray, phase: FloatArray, w: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Value and first three derivatives of ``sum(poly[..., k] w^k) + amp sin(omega w + phase)``.

    ``poly`` has shape ``w.shape + (n,)``; the other arrays have the shape of ``w``. Horner's
    scheme per derivative; the loop runs over the polynomial degree, never over samples.
    """
    return evaluate_derivatives(derivatives(poly), amp, omega, phase, w)


def derivatives(poly: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Coefficients of ``poly`` (ascending, last axis) and of its first three derivatives.

    Trailing coefficients that are zero in every piece (a trapezoid's degree is 2 of DEGREE's 5) are
    dropped: Horner's scheme from the highest non-zero one gives the same floats in fewer passes.
    """
    used = np.flatnonzero(np.any(poly != 0.0, axis=tuple(range(poly.ndim - 1)))) if poly.size else np.zeros(0, int)
    keep = int(used[-1]) + 1 if used.size else 1
    c = poly[..., :keep]
    out = [c]
    for _ in range(3):
        c = c[..., 1:] * np.arange(1, c.shape[-1], dtype=float)
        out.append(c)
    return out[0], out[1], out[2], out[3]


def evaluate_derivatives(
    derivs: tuple[FloatArray, FloatArray, FloatArray, FloatArray], amp: FloatArray, omega: FloatArray,
    phase: FloatArray, w: FloatArray,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`evaluate_pieces` with the coefficients of :func:`derivatives` already computed."""
    x, v, a, j = (_horner(c, w) for c in derivs)
    if not np.any(amp):  # polynomial pieces only (every profile but a cam's sine): no sine term to add
        return x, v, a, j
    arg = omega * w + phase
    sin, cos = np.sin(arg), np.cos(arg)
    return x + amp * sin, v + amp * omega * cos, a - amp * omega**2 * sin, j - amp * omega**3 * cos


def horner_into(coef: FloatArray, w: FloatArray, out: FloatArray) -> None:
    """out[:] = sum(coef[k] w^k) for one piece (``coef`` 1-D, ascending), by the operations of ``_horner``."""
    if coef.shape[-1] == 0:
        out[...] = 0.0
        return
    out[...] = coef[-1]
    for col in range(coef.shape[-1] - 2, -1, -1):
        out *= w
        out += coef[col:col + 1]


def _horner(coef: FloatArray, w: FloatArray) -> FloatArray:
    """sum(coef[..., k] w^k) by Horner's scheme."""
    shape = np.broadcast(w, coef[..., 0] if coef.shape[-1] else coef.sum(axis=-1)).shape
    if coef.shape[-1] == 0:  # the derivative of a constant
        return np.zeros(shape)
    acc = np.empty(shape)
    acc[...] = coef[..., -1]
    for col in range(coef.shape[-1] - 2, -1, -1):
        acc *= w
        acc += coef[..., col]
    return acc


def _integrate(accel: list[_Accel]) -> list[CamPiece]:
    """Integrate acceleration pieces twice from rest at u = 0, with s and s' continuous."""
    from numpy.polynomial import Polynomial  # only where a cam law is built (4 ms of imports otherwise)

    s0 = v0 = 0.0
    pieces: list[CamPiece] = []
    for p in accel:
        # Shift the polynomial to local w = u - u0, then integrate from w = 0.
        local = Polynomial(p.poly)(Polynomial([p.u0, 1.0]))
        phase = p.omega * p.u0 + p.phase
        pos = local.integ(2)
        amp = 0.0
        if p.b != 0.0:
            # s'' = b sin(W w + P)  =>  s = -b/W^2 sin(W w + P) + (b/W) cos(P) w + b/W^2 sin(P)
            amp = -p.b / p.omega**2
            pos = pos + Polynomial([-amp * math.sin(phase), -amp * p.omega * math.cos(phase)])
        pos = pos + Polynomial([s0, v0])
        coef = np.zeros(DEGREE + 1)
        coef[: len(pos.coef)] = pos.coef
        pieces.append(CamPiece(p.u0, p.u1, tuple(float(c) for c in coef), amp, p.omega, phase))
        width = np.array([p.u1 - p.u0])
        s, v, _, _ = evaluate_pieces(
            coef[None, :], np.array([amp]), np.array([p.omega]), np.array([phase]), width
        )
        s0, v0 = float(s[0]), float(v[0])
    return pieces


def _normalise(pieces: list[CamPiece]) -> list[CamPiece]:
    """Scale so that s(1) = 1 (the texts' amplitudes are this scale, e.g. C_a = 4.8881)."""
    last = pieces[-1]
    s_end, _, _, _ = evaluate_pieces(
        np.array([last.poly]), np.array([last.amp]), np.array([last.omega]), np.array([last.phase]),
        np.array([last.u1 - last.u0]),
    )
    scale = 1.0 / float(s_end[0])
    return [p._replace(poly=tuple(c * scale for c in p.poly), amp=p.amp * scale) for p in pieces]


_HALF_PI = 0.5 * math.pi
_FOUR_PI = 4.0 * math.pi


def _accel_definitions(name: str) -> list[_Accel]:
    """Acceleration of each law (Norton, Cam Design and Manufacturing Handbook, ch. 3), split at 1/2.

    cos(x) is written sin(x + pi/2) so that every piece has one sinusoid form.
    """
    if name == "cycloidal":
        # s'' = 2 pi sin(2 pi u)
        return [_Accel(0.0, 0.5, (0.0,), 1.0, 2 * math.pi), _Accel(0.5, 1.0, (0.0,), 1.0, 2 * math.pi)]
    if name == "modified_trapezoid":
        # sine quarter-waves of period 1/4 joined by constant-acceleration flats, breaks at eighths.
        return [
            _Accel(0.0, 0.125, (0.0,), 1.0, _FOUR_PI),
            _Accel(0.125, 0.375, (1.0,)),
            _Accel(0.375, 0.5, (0.0,), 1.0, _FOUR_PI, -1.5 * math.pi + _HALF_PI),
            _Accel(0.5, 0.625, (0.0,), 1.0, _FOUR_PI, -1.5 * math.pi + _HALF_PI),
            _Accel(0.625, 0.875, (-1.0,)),
            _Accel(0.875, 1.0, (0.0,), -1.0, _FOUR_PI, -3.5 * math.pi + _HALF_PI),
        ]
    if name == "modified_sine":
        # quarter-waves of period 1/4 at the ends, a half-wave of period 3/2 in the middle.
        mid_omega = _FOUR_PI / 3.0
        mid_phase = -mid_omega * 0.125 + _HALF_PI
        return [
            _Accel(0.0, 0.125, (0.0,), 1.0, _FOUR_PI),
            _Accel(0.125, 0.5, (0.0,), 1.0, mid_omega, mid_phase),
            _Accel(0.5, 0.875, (0.0,), 1.0, mid_omega, mid_phase),
            _Accel(0.875, 1.0, (0.0,), -1.0, _FOUR_PI, -3.5 * math.pi + _HALF_PI),
        ]
    if name == "poly345":
        # s = 10 u^3 - 15 u^4 + 6 u^5  =>  s'' = 60 u - 180 u^2 + 120 u^3
        acc = (0.0, 60.0, -180.0, 120.0)
        return [_Accel(0.0, 0.5, acc), _Accel(0.5, 1.0, acc)]
    raise KeyError(name)


# Where each law's |s''| and |s'''| peak (u), from the definitions above; |s'| peaks at u = 1/2.
_PEAK_ACCEL_AT = {
    "cycloidal": 0.25,
    "modified_trapezoid": 0.125,
    "modified_sine": 0.125,
    "poly345": (3.0 - math.sqrt(3.0)) / 6.0,
}


@cache
def cam_law(name: str) -> CamLaw:
    """The normalised law ``name`` (one of CAM_LAWS), built once and cached.

    Raises KeyError for an unknown name (the profile parser turns that into an InputError).
    """
    pieces = _normalise(_integrate(_accel_definitions(name)))
    law = CamLaw(name, tuple(pieces), 0.0, 0.0, 0.0)
    _, v, _, _ = law.evaluate(np.array([0.5]))
    _, _, a, _ = law.evaluate(np.array([_PEAK_ACCEL_AT[name]]))
    _, _, _, j = law.evaluate(np.array([0.0]))  # every law's jerk peaks at the start
    return CamLaw(name, tuple(pieces), abs(float(v[0])), abs(float(a[0])), abs(float(j[0])))
