"""How well motors fit a duty cycle, vectorised over candidate motors.

The per-sample work is done once per duty cycle; the per-motor work uses closed forms in the
rotor inertia J_M, so thousands of motors cost little more than one:

* RMS: T_m = T + J_M alpha, so sum w T_m^2 = S_TT + 2 J_M S_Ta + J_M^2 S_aa (exact).
* Peak against the intermittent envelope: per speed bin, max_k |T_k + J_M alpha_k| is the
  support function of the points (alpha_k, T_k), so only their convex-hull vertices matter.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from drivetrain.sizing.checks import Check, margin_of
from drivetrain.sizing.demand import Demand, binned_points, chain
from drivetrain.sizing.envelope import Curve, continuous_torque, intermittent_torque, motor_envelopes

Array = NDArray[np.float64]


def demand(omega: Array, alpha: Array, torque: Array, weights: Array, period: float, load_inertia: float,
           bins: int = 64) -> Demand:
    """Reduce samples to a Demand: speed bins and the convex hull of (alpha, T) in each."""
    if len(omega) > _COMPILED_FROM:
        from drivetrain.sizing.hull import fast_demand  # the same bins, vertices and padding, one numpy pass

        return fast_demand(omega, alpha, torque, weights, period, load_inertia, bins)
    a_s, t_s, starts, stops, speeds = binned_points(omega, alpha, torque, bins)
    # points of each bin are sorted by (alpha, T): the monotone chain needs no further sort
    a_l, t_l = a_s.tolist(), t_s.tolist()
    verts = [chain(a_l[s:e], t_l[s:e]) for s, e in zip(starts.tolist(), stops.tolist(), strict=True)]
    width = max(len(v) for v in verts)
    ha = np.array([[p[0] for p in v] + [v[-1][0]] * (width - len(v)) for v in verts])
    ht = np.array([[p[1] for p in v] + [v[-1][1]] * (width - len(v)) for v in verts])
    # (padding repeats the last vertex: a repeated vertex changes no maximum)
    every = sorted({p for v in verts for p in v})
    hull_all = chain([p[0] for p in every], [p[1] for p in every])
    all_a, all_t = np.array([p[0] for p in hull_all]), np.array([p[1] for p in hull_all])
    return Demand(omega=omega, alpha=alpha, torque=torque, weights=weights, period=period,
                  load_inertia=load_inertia, hull_speed=np.asarray(speeds, dtype=float), hull_torque=ht, hull_alpha=ha,
                  all_torque=all_t, all_alpha=all_a)


def _support(torque: Array, alpha: Array, j: Array) -> Array:
    """max over vertices v of |T_v + J alpha_v| for each J [N m] (vertices along the last axis)."""
    out = np.abs(torque[..., 0] + j * alpha[..., 0])
    for v in range(1, torque.shape[-1]):
        np.maximum(out, np.abs(torque[..., v] + j * alpha[..., v]), out=out)
    return out


def scaled(d: Demand, ratio: float) -> Demand:
    """The demand behind an ideal ratio i: speeds and accelerations x i, torques / i, inertia / i^2.

    A lossy stage of efficiency eta scales the same way once its losses are applied at i = 1
    (T_in = Q(T_out / i) = Q(T_out) / i), and a linear map keeps the convex-hull vertices, so
    the hull needs no recomputation.
    """
    return Demand(omega=d.omega * ratio, alpha=d.alpha * ratio, torque=d.torque / ratio, weights=d.weights,
                  period=d.period, load_inertia=d.load_inertia / ratio**2, hull_speed=d.hull_speed * ratio,
                  hull_torque=d.hull_torque / ratio, hull_alpha=d.hull_alpha * ratio,
                  all_torque=d.all_torque / ratio, all_alpha=d.all_alpha * ratio)


_COMPILED_FROM = 20_000
"""Samples above which the hulls are computed by ``hull.fast_demand`` (every bin in one numpy pass, same
vertices): below, the plain-float chain per bin costs less."""

@dataclass(frozen=True)
class MotorArrays:
    """Candidate motors as arrays (SI), one entry per candidate."""

    inertia: Array
    rated_torque: Array
    peak_torque: Array
    rated_speed: Array
    max_speed: Array
    stall_torque: Array  # NaN where unknown
    approximate: NDArray[np.bool_]
    curves: tuple[Curve | None, ...] | None = None  # datasheet speed-torque points, where known


@dataclass(frozen=True)
class Fit:
    """Per-candidate check results (arrays over candidates)."""

    names: tuple[str, ...]
    required: dict[str, Array]
    available: dict[str, Array]
    margin: dict[str, Array]
    units: dict[str, str]
    approximate: dict[str, NDArray[np.bool_]]
    peak_torque: Array
    rms_torque: Array
    inertia_ratio: Array

    @property
    def ok(self) -> NDArray[np.bool_]:
        """True where every check passes."""
        out = np.ones_like(self.peak_torque, dtype=bool)
        for name in self.names:
            out &= self.margin[name] >= 0.0
        return out

    def checks(self, k: int) -> list[Check]:
        """Check objects of candidate ``k``."""
        return [Check(n, float(self.required[n][k]), float(self.available[n][k]), self.units[n],
                      bool(self.margin[n][k] >= 0.0), float(self.margin[n][k]), bool(self.approximate[n][k]))
                for n in self.names]

    def first_failure(self, k: int) -> str:
        """The failing check with the worst margin, as a sentence ('' if all pass)."""
        bad = [(float(self.margin[n][k]), n) for n in self.names if self.margin[n][k] < 0.0]
        if not bad:
            return ""
        # a motor that cannot reach the cycle's speed is rejected for that, first
        m, n = min(bad, key=lambda b: (b[1] != "max_speed", b[0], b[1]))
        return (f"{n}: required {self.required[n][k]:.4g} {self.units[n]} > available "
                f"{self.available[n][k]:.4g} {self.units[n]} ({m * 100:.1f} %)")


def fit_motors(d: Demand, motors: MotorArrays, *, torque_margin: float = 1.0, rms_margin: float = 1.0,
               speed_margin: float = 1.0, inertia_ratio_limit: float = 5.0,
               speed_limit: Array | None = None, extra_inertia: Array | None = None,
               index: NDArray[np.intp] | None = None) -> Fit:
    """Check every candidate motor against the demand (arrays over M candidates).

    Checks: ``peak_torque`` (|T + J_M alpha| x margin against the intermittent envelope at
    the speed where it occurs), ``rms_torque`` (RMS x margin against the continuous torque at
    the mean speed; lecture, Torque Effective Value), ``max_speed`` (x margin against the
    motor's max speed, and ``speed_limit`` such as a gearbox's max input speed), and
    ``inertia_ratio`` (J_L / J_M against the user's limit; the lecture recommends below 5:1).
    ``extra_inertia`` (per candidate, e.g. a catalog gearbox's input inertia [kg m^2]) turns with
    the motor shaft and counts on the load side of the inertia ratio. With ``index``, ``motors``
    holds each motor once and candidate k is motor ``index[k]``: envelopes are then computed
    once per motor, not once per candidate.
    """
    idx = np.arange(len(motors.inertia)) if index is None else index
    # Envelopes per distinct motor, gathered per candidate.
    approx_motor = motors.approximate
    if motors.curves is not None and any(c is not None for c in motors.curves):
        # Datasheet curves where a motor has them; the derived envelope for the others.
        _, peak_env = motor_envelopes(motors.rated_torque, motors.peak_torque, motors.rated_speed, motors.max_speed,
                                      d.hull_speed, motors.stall_torque, motors.curves)
        cont_env, _ = motor_envelopes(motors.rated_torque, motors.peak_torque, motors.rated_speed, motors.max_speed,
                                      np.array([d.mean_speed]), motors.stall_torque, motors.curves)
        env_motor, cont_motor = peak_env.torque, cont_env.torque[:, 0]
        approx_motor = np.asarray(peak_env.approximate, dtype=bool) | np.asarray(cont_env.approximate, dtype=bool)
    else:
        env_motor = intermittent_torque(motors.peak_torque, motors.rated_torque, motors.rated_speed,
                                        motors.max_speed, d.hull_speed, motors.stall_torque).torque
        cont_motor = continuous_torque(motors.rated_torque, motors.rated_speed, motors.max_speed,
                                       np.array([d.mean_speed]), motors.stall_torque).torque[:, 0]
    env_int, cont = env_motor[idx], cont_motor[idx]
    j_m = motors.inertia[idx]
    extra = np.zeros_like(j_m) if extra_inertia is None else extra_inertia
    j = j_m + extra
    # Peak over the whole cycle: max over the global hull's vertices of |T + J alpha|.
    peak_all = _support(d.all_torque, d.all_alpha, j)
    # Peak against the envelope, per speed bin. A motor slower than the cycle's top bin has no
    # torque there: its peak check is not judged (NaN) and its max_speed check fails.
    top = d.hull_speed[-1]
    slow = motors.max_speed[idx] < top
    full = np.flatnonzero(~slow)  # an unknown (NaN) max speed is judged at every bin
    short = np.flatnonzero(slow)
    peak_req = np.empty(len(j))
    peak_av = np.empty(len(j))
    peak_m = np.empty(len(j))
    if short.size:
        # not judged on torque where the motor cannot go: its max_speed check fails instead
        peak_req[short] = _support(d.hull_torque[-1], d.hull_alpha[-1], j[short]) * torque_margin
        peak_av[short] = np.nan
        peak_m[short] = np.nan
    if full.size:
        # (a loop over the few hull vertices: numpy reduces a short last axis slowly)
        jf = j[full]
        vals = np.abs(d.hull_torque[None, :, 0] + jf[:, None] * d.hull_alpha[None, :, 0])
        for v in range(1, d.hull_torque.shape[1]):
            np.maximum(vals, np.abs(d.hull_torque[None, :, v] + jf[:, None] * d.hull_alpha[None, :, v]), out=vals)
        req_bins = vals * torque_margin
        env_f = env_int[full]
        m = margin_of(req_bins, env_f)
        worst = np.argmin(m, axis=1)
        rows = np.arange(len(full))
        peak_req[full], peak_av[full], peak_m[full] = req_bins[rows, worst], env_f[rows, worst], m[rows, worst]
    # RMS in closed form.
    w = d.weights
    s_tt = float(np.sum(w * d.torque**2))
    s_ta = float(np.sum(w * d.torque * d.alpha))
    s_aa = float(np.sum(w * d.alpha**2))
    rms_t = np.sqrt(np.maximum(s_tt + 2.0 * j * s_ta + j**2 * s_aa, 0.0) / d.period)
    rms_req = rms_t * rms_margin
    speed_req = np.full_like(j, d.max_speed * speed_margin)
    max_speed = motors.max_speed[idx]
    speed_av = max_speed if speed_limit is None else np.minimum(max_speed, speed_limit)
    ratio = (d.load_inertia + extra) / j_m
    approx = approx_motor[idx]
    names = ("peak_torque", "rms_torque", "max_speed", "inertia_ratio")
    return Fit(
        names=names,
        required={"peak_torque": peak_req, "rms_torque": rms_req, "max_speed": speed_req * 60 / (2 * np.pi),
                  "inertia_ratio": ratio},
        available={"peak_torque": peak_av, "rms_torque": cont, "max_speed": speed_av * 60 / (2 * np.pi),
                   "inertia_ratio": np.full_like(j, inertia_ratio_limit)},
        margin={"peak_torque": peak_m, "rms_torque": margin_of(rms_req, cont),
                "max_speed": margin_of(speed_req, speed_av), "inertia_ratio": margin_of(ratio, inertia_ratio_limit)},
        units={"peak_torque": "N*m", "rms_torque": "N*m", "max_speed": "rpm", "inertia_ratio": "-"},
        approximate={"peak_torque": approx, "rms_torque": approx, "max_speed": np.zeros_like(approx),
                     "inertia_ratio": np.zeros_like(approx)},
        peak_torque=peak_all, rms_torque=rms_t, inertia_ratio=ratio,
    )
