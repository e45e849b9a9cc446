r"""Forces in timing-belt and rack-and-pinion drives: belt pull and span tensions, tooth forces, shaft loads.

SI throughout: forces [N], torques [N m], lengths [m], angles [rad]; arrays over the cycle's
samples and over carriage positions broadcast together.

Sources:
- Gates Mectrol, "Timing Belt Theory" (sec. 3.1 torque, effective tension, tight and slack
  side tension; 3.2 shaft forces; 3.3 belt pre-tension): effective tension T_e = T / r =
  T_t - T_s; the slack side must stay in tension; the shaft force is the vector sum of the two
  span tensions on the pulley.
- BRECOflex, "Timing Belt Drive Definitions & Formulas" (peripheral force F_U, admissible
  tensile load F_adm, pre-tension F_V, shaft force F_W) and the BRECO linear-drive formula
  collection: a linear drive's spring rate depends on the span lengths L_1, L_2 on either side
  of the carriage and is lowest where L_1 = L_2.
- Spur and helical gear mesh forces (the rack is a gear of infinite radius): tangential
  F_t = T / r, radial F_r = F_t tan(alpha_n) / cos(beta), axial F_a = F_t tan(beta)
  (Shigley's Mechanical Engineering Design, ch. 13, force analysis of spur and helical gearing).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError

Array = NDArray[np.float64]


def _positive(value: float, name: str, unit: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value)) or value <= 0.0:
        raise InputError(name, f"must be > 0 {unit}", value)
    return float(value)


def effective_pull(torque: ArrayLike, pitch_radius: float) -> Array:
    r"""Effective pull (tangential force) of a belt pulley or pinion [N]: F = T / r.

    ``torque`` at the pulley or pinion [N m] (array over the cycle), ``pitch_radius`` r [m]
    (belt pitch line, or pinion pitch circle). Gates Mectrol "Timing Belt Theory" 3.1
    (effective tension T_e); BRECOflex peripheral force F_U.

    >>> float(effective_pull(10.0, 0.025))
    400.0
    """
    r = _positive(pitch_radius, "pitch_radius", "m")
    return np.asarray(np.asarray(torque, dtype=float) / r, dtype=float)


def linear_belt_spans(position: ArrayLike, centre_distance: float, layout: str = "loop",
                      clamp_offset: float = 0.0) -> tuple[Array, Array]:
    r"""Free lengths of the two belt paths from the drive pulley to the carriage [m].

    ``position`` x [m] of the carriage's belt clamp from the drive pulley's tangent point,
    0 <= x <= ``centre_distance`` L; ``layout``:

    - ``loop``: belt clamped to the carriage, driven round a drive pulley and an idler
      (the usual belt axis and a conveyor carrying its load): direct span x, the other path
      round the idler (L - x) + L. The pair is equal (the drive is softest) at the idler end.
    - ``omega``: belt fixed at both frame ends, the drive pulley riding on the carriage
      (omega drive), or a belt fixed at the ends and driven from the middle: spans x and L - x,
      softest at mid-stroke.

    ``clamp_offset`` [m] adds the belt length inside the clamp and round the pulleys that also
    stretches (default 0). Span lengths follow the geometry of the BRECO linear-drive formula
    collection (spring rate from L_1 and L_2; minimum where L_1 = L_2).
    """
    length = _positive(centre_distance, "centre_distance", "m")
    x = np.asarray(position, dtype=float)
    if not np.all(np.isfinite(x)) or np.any(x < 0.0) or np.any(x > length):
        raise InputError("position", f"must lie in [0, {length:g}] m", position)
    if not math.isfinite(clamp_offset) or clamp_offset < 0.0:
        raise InputError("clamp_offset", "must be >= 0 m", clamp_offset)
    if layout == "loop":
        return x + clamp_offset, (2.0 * length - x) + clamp_offset
    if layout == "omega":
        return x + clamp_offset, (length - x) + clamp_offset
    raise InputError("layout", "must be one of 'loop', 'omega'", layout)


def linear_belt_tensions(pull: ArrayLike, pretension: float, span_pull: ArrayLike,
                         span_other: ArrayLike) -> tuple[Array, Array]:
    r"""Tight- and slack-side tensions of a pretensioned linear belt drive [N].

    .. math:: T_t = T_i + T_e \frac{L_o}{L_p + L_o}, \qquad T_s = T_i - T_e \frac{L_p}{L_p + L_o}

    The pulley pulls the carriage by ``pull`` T_e [N] through span ``span_pull`` L_p [m]; the
    other path ``span_other`` L_o [m] slackens. Both spans have the same stiffness per unit
    length (c / L), so they share the pull by stiffness: the stretch delta of the carriage
    relative to the pulley gives dT_p = c delta / L_p, dT_o = -c delta / L_o, and
    T_e = dT_p - dT_o. ``pretension`` T_i [N] (installation tension, Gates Mectrol 3.3;
    BRECOflex F_V). With equal spans this is T_i +- T_e / 2. A negative slack tension means
    the belt goes slack: the pretension is too low (:func:`minimum_pretension`).
    """
    te = np.abs(np.asarray(pull, dtype=float))
    if not math.isfinite(pretension) or pretension < 0.0:
        raise InputError("pretension", "must be >= 0 N", pretension)
    lp = np.asarray(span_pull, dtype=float)
    lo = np.asarray(span_other, dtype=float)
    if np.any(lp < 0.0) or np.any(lo < 0.0) or np.any(lp + lo <= 0.0):
        raise InputError("span", "lengths must be >= 0 m with a positive sum", (span_pull, span_other))
    total = lp + lo
    return (np.asarray(pretension + te * lo / total, dtype=float),
            np.asarray(pretension - te * lp / total, dtype=float))


def minimum_pretension(pull: ArrayLike, span_pull: ArrayLike, span_other: ArrayLike) -> float:
    r"""Smallest pretension that keeps the slack side taut over the cycle [N].

    max over samples of T_e L_p / (L_p + L_o) (:func:`linear_belt_tensions` with T_s = 0).
    At the worst position (L_p >> L_o) it approaches the largest effective pull, the usual
    rule for linear belt drives (Gates Mectrol "Timing Belt Theory" 3.3: slack-side tension
    must not fall to zero).
    """
    te = np.abs(np.asarray(pull, dtype=float))
    lp = np.asarray(span_pull, dtype=float)
    lo = np.asarray(span_other, dtype=float)
    return float(np.max(te * lp / (lp + lo)))


def pulley_shaft_load(tight: ArrayLike, slack: ArrayLike, wrap_angle: float = math.pi) -> Array:
    r"""Radial load on the pulley shaft from the two span tensions [N].

    .. math:: F_W = \sqrt{T_t^2 + T_s^2 - 2 T_t T_s \cos\beta}

    ``tight``, ``slack`` [N] (a slack tension below zero is taken as 0: a slack belt pushes
    nothing), ``wrap_angle`` beta [rad] of the belt on the pulley (pi: the two spans parallel,
    F_W = T_t + T_s). Gates Mectrol "Timing Belt Theory" 3.2 (shaft forces); BRECOflex F_W.

    >>> float(pulley_shaft_load(300.0, 100.0))
    400.0
    """
    if not (0.0 <= wrap_angle <= 2.0 * math.pi):
        raise InputError("wrap_angle", "must lie in [0, 2 pi] rad", wrap_angle)
    tt = np.maximum(np.asarray(tight, dtype=float), 0.0)
    ts = np.maximum(np.asarray(slack, dtype=float), 0.0)
    return np.asarray(np.sqrt(np.maximum(tt**2 + ts**2 - 2.0 * tt * ts * math.cos(wrap_angle), 0.0)), dtype=float)


def belt_tension_margin(tight: ArrayLike, permissible: float) -> float:
    r"""Margin of the largest tight-side tension against the belt's permissible tension [-].

    margin = F_adm / max(T_t) - 1 (>= 0 passes). ``permissible`` F_adm [N], the belt vendor's
    admissible tensile load for the belt width (BRECOflex F_adm).
    """
    adm = _positive(permissible, "belt.permissible_tension", "N")
    peak = float(np.max(np.asarray(tight, dtype=float)))
    return math.inf if peak <= 0.0 else adm / peak - 1.0


def gear_mesh_forces(tangential: ArrayLike, pressure_angle: float = math.radians(20.0),
                     helix_angle: float = 0.0) -> tuple[Array, Array, Array]:
    r"""Tangential, radial (separating) and axial forces of a pinion on its rack [N].

    .. math:: F_r = F_t \frac{\tan\alpha_n}{\cos\beta}, \qquad F_a = F_t \tan\beta

    ``tangential`` F_t [N] (the rack's feed force, :func:`effective_pull`),
    ``pressure_angle`` alpha_n [rad] (normal, 20 deg standard), ``helix_angle`` beta [rad]
    (0 for straight teeth). Shigley's Mechanical Engineering Design, ch. 13, force analysis of
    spur and helical gearing.

    >>> [round(float(v), 1) for v in gear_mesh_forces(1000.0)]
    [1000.0, 364.0, 0.0]
    """
    if not (0.0 < pressure_angle < math.pi / 2.0):
        raise InputError("pressure_angle", "must lie in (0, 90) deg", pressure_angle)
    if not (0.0 <= abs(helix_angle) < math.pi / 2.0):
        raise InputError("helix_angle", "must lie in [0, 90) deg", helix_angle)
    ft = np.abs(np.asarray(tangential, dtype=float))
    return (np.asarray(ft, dtype=float), np.asarray(ft * math.tan(pressure_angle) / math.cos(helix_angle), dtype=float),
            np.asarray(ft * math.tan(abs(helix_angle)), dtype=float))


def pinion_shaft_load(tangential: ArrayLike, pressure_angle: float = math.radians(20.0),
                      helix_angle: float = 0.0) -> tuple[Array, Array]:
    r"""Radial and axial load on the pinion (gearbox output or motor) shaft from the mesh [N].

    Radial: sqrt(F_t^2 + F_r^2) (tangential and separating forces are perpendicular);
    axial: F_a. Compare with the gearbox's or motor's permissible F_2r, F_2a at the pinion's
    distance from the flange (the catalog's values).
    """
    ft, fr, fa = gear_mesh_forces(tangential, pressure_angle, helix_angle)
    return np.asarray(np.hypot(ft, fr), dtype=float), fa


def rack_force_margin(tangential: ArrayLike, permissible: float, application_factor: float = 1.0) -> float:
    r"""Margin of the rack's largest feed force against its permissible tangential force [-].

    margin = F_perm / (K_A max|F_t|) - 1 (>= 0 passes). ``permissible`` F_perm [N] the rack and
    pinion vendor's permissible feed (tangential) force for the pinion and rack pair,
    ``application_factor`` K_A >= 1 for shocks (ISO 6336-1 application factor).
    """
    perm = _positive(permissible, "rack.permissible_force", "N")
    ka = _positive(application_factor, "rack.application_factor", "")
    if ka < 1.0:
        raise InputError("rack.application_factor", "must be >= 1", application_factor)
    peak = float(np.max(np.abs(np.asarray(tangential, dtype=float))))
    return math.inf if peak <= 0.0 else perm / (ka * peak) - 1.0
