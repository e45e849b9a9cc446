r"""Limits and life of a ball or lead screw: buckling, critical speed, DN value, nut life.

SI throughout: lengths [m], forces [N], speeds [rad/s], E [Pa], density [kg/m^3]. Catalogs
write the same formulas with mm, N/mm^2 and min^-1 and fold the constants into one factor
(THK's eta_2 d_1^4 / l_a^2 x 10^4 and lambda_2 d_1 / l_b^2 x 10^7); here the physical form is
kept, with the mounting factors eta_1, lambda_1 and the catalogs' safety factors (0.5 on
buckling, 0.8 on the critical speed). ``tests/physics/test_mechanism_limits.py`` checks that this
form reproduces THK's folded factors and MiSUMi's worked examples.

Sources:
- THK General Catalog, Ball Screw, "Permissible Axial Load" (A15-30, catalog 514E): buckling
  P_1 = eta_1 pi^2 E I / l_a^2 x 0.5 = eta_2 d_1^4 / l_a^2 x 10^4 [N]; fixed-free eta_1 = 0.25
  (eta_2 = 1.3), fixed-supported 2 (10), fixed-fixed 4 (20); E = 2.06e5 N/mm^2,
  I = pi d_1^4 / 64 with the thread minor (root) diameter d_1; permissible tensile/compressive
  load P_2 = sigma pi d_1^2 / 4 = 116 d_1^2 with sigma = 147 MPa.
- THK, "Permissible Rotational Speed" (A15-32, catalog 513-1E): critical speed
  N_1 = 60 lambda_1^2 / (2 pi l_b^2) sqrt(E 10^3 I / (gamma A)) x 0.8 = lambda_2 d_1 / l_b^2 x 10^7
  [min^-1], gamma = 7.85e-6 kg/mm^3; fixed-free lambda_1 = 1.875 (lambda_2 = 3.4),
  supported-supported 3.142 (9.7), fixed-supported 3.927 (15.1), fixed-fixed 4.73 (21.9). The
  permissible speed is also limited by the DN value N_2 = DN / D (D = ball centre-to-centre
  diameter [mm]), DN per model in THK's table.
- THK, "Method for Mounting the Ball Screw Shaft": fixed-fixed: take the smaller buckling load
  and critical speed of the two lengths on either side of the nut; fixed-free and
  fixed-supported: the length from the nut to the fixed (thrust) bearing.
- MiSUMi, Economy Series catalog 2025 (Thailand), Technical Data "Selection of Ball Screws"
  pp. 1676-1678: the same formulas with worked examples (allowable axial load 3630 N, allowable
  rotational speed 3024 min^-1, life 24824 h), which are this module's validation.
- Nut life: L = (C_a / (f_w F_m))^3 x 10^6 revolutions (MiSUMi p. 1678; THK "Studying the
  Service Life"), F_m the cubic mean of the axial load over the travel (Steinmeyer,
  "Calculation of the equivalent Load").
- Preloaded (double or offset) nuts: each half carries the preload until the external load
  reaches 2^(3/2) F_pr = 2.83 F_pr, where the other half unloads (Steinmeyer, "Equivalent Load:
  Considering the preload with double nuts"); with Hertzian ball contact (deflection
  proportional to F^(2/3)) the loaded half carries F_pr (1 + F / (2.83 F_pr))^(3/2) below that
  and F above it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError
from drivetrain.physics.rolling_life import cubic_mean_load

Array = NDArray[np.float64]

STEEL_YOUNGS_MODULUS = 206e9
"""[Pa] THK's value for screw shafts (2.06e5 N/mm^2)."""
STEEL_DENSITY = 7850.0
"""[kg/m^3] THK's screw-shaft density (7.85e-6 kg/mm^3)."""
PERMISSIBLE_STRESS = 147e6
"""[Pa] THK's permissible tensile/compressive stress of the screw shaft (eq. 6)."""
BUCKLING_SAFETY = 0.5
"""Safety factor THK and MiSUMi apply to the Euler buckling load."""
CRITICAL_SPEED_SAFETY = 0.8
"""Safety factor THK and MiSUMi apply to the critical (whirling) speed."""
PRELOAD_RELEASE = 2.0**1.5
"""External load / preload at which one half of a preloaded nut unloads (2.83, Steinmeyer)."""

MOUNTINGS = ("fixed_free", "supported_supported", "fixed_supported", "fixed_fixed")

BUCKLING_FACTOR: dict[str, float] = {"fixed_free": 0.25, "supported_supported": 1.0, "fixed_supported": 2.0,
                                     "fixed_fixed": 4.0}
"""eta_1 of the Euler load eta_1 pi^2 E I / l^2: THK A15-30 (fixed-free 0.25, fixed-supported 2,
fixed-fixed 4); supported-supported is Euler's pin-ended column, 1."""

CRITICAL_SPEED_FACTOR: dict[str, float] = {"fixed_free": 1.875, "supported_supported": 3.142,
                                           "fixed_supported": 3.927, "fixed_fixed": 4.73}
"""lambda_1 of the first bending mode (THK A15-32; the roots of the beam equation)."""


def _mounting(mounting: str, field: str = "mounting") -> str:
    if mounting not in MOUNTINGS:
        raise InputError(field, f"must be one of {', '.join(repr(m) for m in MOUNTINGS)}", mounting)
    return mounting


def _positive(value: float, name: str, unit: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value)) or value <= 0.0:
        raise InputError(name, f"must be > 0 {unit}", value)
    return float(value)


def _lengths(length: ArrayLike, name: str = "length") -> Array:
    a = np.asarray(length, dtype=float)
    if not np.all(np.isfinite(a)) or np.any(a <= 0.0):
        raise InputError(name, "must be > 0 m", length)
    return a


def buckling_load(root_diameter: float, length: ArrayLike, mounting: str = "fixed_supported",
                  youngs_modulus: float = STEEL_YOUNGS_MODULUS, safety: float = BUCKLING_SAFETY) -> Array:
    r"""Permissible compressive axial load of a screw shaft against buckling [N].

    .. math:: P_1 = s\,\frac{\eta_1 \pi^2 E I}{l^2}, \qquad I = \frac{\pi d_1^4}{64}

    ``root_diameter`` d_1 [m] (thread minor diameter), ``length`` l [m] between the nut and
    the fixed bearing (array: one per nut position, see :func:`buckling_length`),
    ``mounting`` one of :data:`MOUNTINGS`, ``youngs_modulus`` E [Pa], ``safety`` s (0.5,
    THK/MiSUMi). Source: THK A15-30 eq. (5); MiSUMi 2025 p. 1676. MiSUMi's example
    (d_1 = 12.5 mm, 820 mm, fixed-supported) publishes 3630 N with the rounded factor m = 10:

    >>> round(float(buckling_load(12.5e-3, 0.82, "fixed_supported")))
    3624
    """
    d = _positive(root_diameter, "root_diameter", "m")
    e = _positive(youngs_modulus, "youngs_modulus", "Pa")
    s = _positive(safety, "safety", "")
    eta = BUCKLING_FACTOR[_mounting(mounting)]
    inertia = math.pi * d**4 / 64.0
    return np.asarray(s * eta * math.pi**2 * e * inertia / _lengths(length) ** 2, dtype=float)


def permissible_tensile_compressive_load(root_diameter: float, stress: float = PERMISSIBLE_STRESS) -> float:
    r"""Axial load the screw shaft carries at its permissible stress [N]: P_2 = sigma pi d_1^2 / 4.

    ``root_diameter`` d_1 [m], ``stress`` [Pa] (147 MPa, THK A15-30 eq. (6): 116 d_1^2 [N] with
    d_1 in mm).

    >>> round(permissible_tensile_compressive_load(10e-3))
    11545
    """
    d = _positive(root_diameter, "root_diameter", "m")
    return _positive(stress, "stress", "Pa") * math.pi * d**2 / 4.0


def critical_speed(root_diameter: float, length: ArrayLike, mounting: str = "fixed_supported",
                   youngs_modulus: float = STEEL_YOUNGS_MODULUS, density: float = STEEL_DENSITY,
                   safety: float = CRITICAL_SPEED_SAFETY) -> Array:
    r"""Permissible rotational speed of a screw shaft from its first whirling mode [rad/s].

    .. math:: \omega_1 = s\,\frac{\lambda_1^2}{l^2}\sqrt{\frac{E I}{\rho A}}
              = s\,\frac{\lambda_1^2 d_1}{4 l^2}\sqrt{\frac{E}{\rho}}

    (the first bending natural frequency of a uniform shaft; in rev/min, THK's
    60 lambda_1^2 / (2 pi l^2) sqrt(E I / (gamma A)) x 0.8). ``root_diameter`` d_1 [m],
    ``length`` l [m] between the supports (fixed-free: the free length), ``mounting`` one of
    :data:`MOUNTINGS`, E [Pa], ``density`` [kg/m^3], ``safety`` s = 0.8 (THK, MiSUMi).
    Source: THK A15-32 eq. (7); MiSUMi 2025 p. 1677 (d_1 = 12.5 mm, 790 mm, fixed-supported:
    3024 min^-1 with the rounded factor 15.1):

    >>> round(float(critical_speed(12.5e-3, 0.79)) * 60 / (2 * math.pi))
    3022
    """
    d = _positive(root_diameter, "root_diameter", "m")
    e = _positive(youngs_modulus, "youngs_modulus", "Pa")
    rho = _positive(density, "density", "kg/m^3")
    s = _positive(safety, "safety", "")
    lam = CRITICAL_SPEED_FACTOR[_mounting(mounting)]
    return np.asarray(s * lam**2 * d / (4.0 * _lengths(length) ** 2) * math.sqrt(e / rho), dtype=float)


def buckling_length(nut_position: ArrayLike, bearing_span: float, mounting: str) -> Array:
    """Length of shaft in compression between the nut and its fixed end, per nut position [m].

    ``nut_position`` x [m] measured from the fixed (thrust) bearing, 0 < x <= ``bearing_span``
    (the distance between the two supports, or to the free end). Fixed-free and fixed-supported:
    x (THK uses the length to the fixed bearing). Fixed-fixed: the longer of x and span - x (THK:
    "use the smaller" buckling load of the two). Supported-supported: the span.
    """
    span = _positive(bearing_span, "bearing_span", "m")
    x = np.asarray(nut_position, dtype=float)
    if not np.all(np.isfinite(x)) or np.any(x <= 0.0) or np.any(x > span):
        raise InputError("nut_position", f"must lie in (0, {span:g}] m from the fixed bearing", nut_position)
    m = _mounting(mounting)
    if m == "fixed_fixed":
        return np.asarray(np.maximum(x, span - x), dtype=float)
    if m == "supported_supported":
        return np.full_like(x, span)
    return np.asarray(x, dtype=float)


def dn_value(ball_circle_diameter: float, speed: ArrayLike) -> Array:
    r"""DN value of a ball screw, in the catalogs' unit [mm min^-1]: D [mm] x n [min^-1].

    ``ball_circle_diameter`` D [m] (ball centre-to-centre diameter), ``speed`` [rad/s].
    Kept in the vendor unit so that it compares directly with the catalog limit (THK A15-32
    table: N_2 = DN / D, the DN given per model).
    """
    d = _positive(ball_circle_diameter, "ball_circle_diameter", "m")
    return np.asarray(d * 1e3 * np.abs(np.asarray(speed, dtype=float)) * 60.0 / (2.0 * math.pi), dtype=float)


def dn_speed_limit(ball_circle_diameter: float, dn_limit: float) -> float:
    r"""Permissible speed from the DN value [rad/s]: N_2 = DN / D with D in mm, N in min^-1.

    ``ball_circle_diameter`` D [m], ``dn_limit`` the catalog's DN [mm min^-1] (THK A15-32,
    eqs. (8)-(17); e.g. N_2 = 210,000 / D for models SBK3636 to SBK5050, eq. (8-1)).

    >>> round(dn_speed_limit(0.02, 100000) * 60 / (2 * math.pi))
    5000
    """
    d = _positive(ball_circle_diameter, "ball_circle_diameter", "m")
    dn = _positive(dn_limit, "dn_limit", "mm/min")
    return dn / (d * 1e3) * 2.0 * math.pi / 60.0


def preloaded_nut_load(axial_load: ArrayLike, preload: float) -> Array:
    r"""Load on the more loaded half of a preloaded nut [N].

    .. math:: F^* = F_{pr}\left(1 + \frac{|F|}{2^{3/2} F_{pr}}\right)^{3/2} \quad (|F| < 2^{3/2} F_{pr}),
              \qquad F^* = |F| \text{ above}

    ``axial_load`` F [N] (array over the cycle), ``preload`` F_pr [N] >= 0 (0: a nut without
    preload, F* = |F|). Source: Steinmeyer, "Equivalent Load: Considering the preload with
    double nuts" (release at 2.83 F_pr); the 3/2 power follows from Hertzian point contact.

    >>> float(preloaded_nut_load(0.0, 100.0))
    100.0
    """
    f = np.abs(np.asarray(axial_load, dtype=float))
    if not math.isfinite(preload) or preload < 0.0:
        raise InputError("nut.preload", "must be >= 0 N", preload)
    if preload == 0.0:
        return np.asarray(f, dtype=float)
    inside = preload * (1.0 + f / (PRELOAD_RELEASE * preload)) ** 1.5
    return np.asarray(np.where(f < PRELOAD_RELEASE * preload, inside, f), dtype=float)


@dataclass(frozen=True)
class ScrewLife:
    """Nominal (L10) life of a ball-screw nut over a repeated cycle (SI).

    ``equivalent_load`` F_m [N] (cubic mean, preload included, before the load factor);
    ``revolutions`` L10 [-]; ``distance`` [m] of nut travel; ``time`` [s] of operation at the
    cycle's duty (dwells included); ``mean_speed`` [rad/s] over the cycle.
    """

    equivalent_load: float
    revolutions: float
    distance: float
    time: float
    mean_speed: float

    @property
    def hours(self) -> float:
        """Life in operating hours [h]."""
        return self.time / 3600.0

    @property
    def km(self) -> float:
        """Life as nut travel [km]."""
        return self.distance / 1e3


def nut_life(dynamic_rating: float, axial_load: ArrayLike, speed: ArrayLike, dt: ArrayLike, lead: float,
             preload: float = 0.0, load_factor: float = 1.0) -> ScrewLife:
    r"""L10 life of a ball-screw nut from the axial load and speed sampled over one cycle.

    .. math:: F_m = \left(\frac{\sum |F^*_i|^3 |n_i| \Delta t_i}{\sum |n_i| \Delta t_i}\right)^{1/3},
              \qquad L_{10} = \left(\frac{C_a}{f_w F_m}\right)^3 10^6

    ``dynamic_rating`` C_a [N]; ``axial_load`` F_i [N], ``speed`` screw speed [rad/s] and
    ``dt`` sample durations [s] (arrays of one shape, covering one whole cycle with its dwells);
    ``lead`` [m/rev]; ``preload`` F_pr [N] of a preloaded nut (:func:`preloaded_nut_load`);
    ``load_factor`` f_w >= 1 (MiSUMi: 1.0-1.2 impactless, 1.2-1.5 normal, 1.5-2.0 with impact).
    The life in time is L10 divided by the revolutions per cycle times the cycle time.
    Sources: MiSUMi 2025 p. 1678 (L_h = 10^6 / (60 N_m) (C / (P_m f_w))^3); THK "Studying the
    Service Life"; Steinmeyer (equivalent load, preload).
    """
    c = _positive(dynamic_rating, "nut.C_a", "N")
    h = _positive(lead, "lead", "m")
    fw = _positive(load_factor, "load_factor", "")
    f = np.asarray(axial_load, dtype=float)
    w = np.asarray(speed, dtype=float)
    t = np.asarray(dt, dtype=float)
    if not (f.shape == w.shape == t.shape):
        raise InputError("speed", "axial_load, speed and dt must have one shape", (f.shape, w.shape, t.shape))
    if not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise InputError("dt", "must be >= 0 s", dt)
    revs = np.abs(w) * t / (2.0 * math.pi)
    f_m = cubic_mean_load(preloaded_nut_load(f, preload), revs)
    return nut_life_from_mean(c, f_m, float(np.sum(revs)), float(np.sum(t)), h, fw)


def nut_life_from_mean(dynamic_rating: float, equivalent_load: float, revs_per_cycle: float, cycle_time: float,
                       lead: float, load_factor: float = 1.0) -> ScrewLife:
    """:func:`nut_life` from its cycle's cubic-mean load F_m [N] (preload included), the screw
    revolutions per cycle [-] and the cycle time [s] (dwells included); ``lead`` [m/rev], C_a
    [N] and f_w as there (already checked by the caller). The same formulas and sources as
    :func:`nut_life`, which ends here.
    """
    life_revs = (dynamic_rating / (load_factor * equivalent_load)) ** 3 * 1e6
    return ScrewLife(equivalent_load=equivalent_load, revolutions=life_revs, distance=life_revs * lead,
                     time=life_revs / revs_per_cycle * cycle_time,
                     mean_speed=revs_per_cycle * 2.0 * math.pi / cycle_time)
