r"""Rolling-contact fatigue life: bearings (ISO 281), linear guides, and the cycle's mean load.

Every function works in SI: forces [N], speeds [rad/s] or [m/s], distances [m], times [s];
a life in revolutions is a plain count. Catalogs quote L10 in 10^6 revolutions, km and hours;
the conversions are here, once.

Sources (each function names the one it follows):
- ISO 281:2007, as restated by SKF, "Basic rating life" (skf.com, bearings principles,
  "Selecting bearing size / Using life equations / Basic rating life"): L10 = (C/P)^p
  [10^6 revolutions], p = 3 for ball bearings, 10/3 for roller bearings;
  L10h = 10^6 L10 / (60 n) [h] with n in r/min.
- NSK, "Calculation of Equivalent Loads": P = X Fr + Y Fa, X and Y from the bearing tables.
- THK General Catalog, LM Guide "Calculating the Nominal Life" (thk.com, Cross-Roller Guide /
  Linear Bushing / LM Guide selection pages): nominal life defined for 50 km (balls) and
  100 km (rollers); L10 = (fH fT fC / fW x C / PC)^3 x 50 [km] for balls,
  (...)^(10/3) x 100 [km] for rollers; ISO 14728-1 conversion C50 = 1.26 C100 (balls),
  1.23 C100 (rollers); static safety factor fS = fH fT fC C0 / PC (THK Flat Roller,
  "Static Safety Factor fS"), guideline lower limits 1 to 1.3 without and 2 to 3 with vibration
  or impact in general industrial machinery.
- IKO linear motion rolling guides, "Load Rating and Life" (catalog p. III-5): L = 50 (C/P)^3
  [10^3 m] for ball guides, L = 100 (C/P)^(10/3) for roller ways; Lh = 10^6 L / (2 S n1 60).
- Schneeberger MINIRAIL, "17.2 Calculation of Service Life L in Accordance with the DIN ISO
  Standard": L = a (C_eff / P)^3 x 10^5 m (100 km basis), L_h = L / (2 s n 60).
- Cubic mean load over a varying cycle (the ISO 281 equivalent load for a load that varies
  with the travel; Steinmeyer, "Calculation of the equivalent Load"; Schaeffler monorail
  guidance "Equivalent load"): F_m = (sum |F_i|^p s_i / sum s_i)^(1/p), the weights s_i being
  the distance (or revolutions) travelled under F_i.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError

Array = NDArray[np.float64]
Rolling = Literal["ball", "roller"]

LIFE_EXPONENT: dict[str, float] = {"ball": 3.0, "roller": 10.0 / 3.0}
"""ISO 281 life exponent p: 3 for ball contact, 10/3 for line (roller) contact."""

GUIDE_RATING_DISTANCE: dict[str, float] = {"THK ball": 50e3, "THK roller": 100e3, "IKO ball": 50e3,
                                           "IKO roller": 100e3, "Schneeberger": 100e3}
"""Distance [m] on which a vendor defines a guide's basic dynamic load rating C, as read.

THK: 50 km for ball guides, 100 km for roller guides ("Calculating the Nominal Life"); IKO:
50 x 10^3 m for ball guides, 100 x 10^3 m for roller ways (Table 2.1); Schneeberger (DIN ISO):
10^5 m. Other vendors (HIWIN, Bosch Rexroth, ...) state their basis next to C in their catalog:
pass it as ``rating_distance``. Compare ratings only on the same basis (:func:`convert_guide_rating`).
"""


def life_exponent(kind: str) -> float:
    """The life exponent p for ``kind`` 'ball' (3) or 'roller' (10/3) (ISO 281)."""
    try:
        return LIFE_EXPONENT[kind]
    except KeyError:
        raise InputError("rolling", "must be one of 'ball', 'roller'", kind) from None


def _positive(value: float, name: str, unit: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value)) or value <= 0.0:
        raise InputError(name, f"must be > 0 {unit}", value)
    return float(value)


def _factor(value: float, name: str) -> float:
    return _positive(value, name, "")


def basic_rating_life(dynamic_rating: float, equivalent_load: ArrayLike, kind: str = "ball") -> Array:
    r"""Basic rating life L10 in revolutions (ISO 281:2007).

    .. math:: L_{10} = \left(\frac{C}{P}\right)^p \cdot 10^6

    ``dynamic_rating`` C [N], ``equivalent_load`` P [N] (scalar or array, > 0),
    ``kind`` 'ball' (p = 3) or 'roller' (p = 10/3). Source: ISO 281:2007 as given by SKF,
    "Basic rating life". A 6208 under 3.2 kN with C = 22.4 kN (the course example in
    ``tests/physics/test_mechanism_limits.py``): 343 x 10^6 revolutions.

    >>> round(float(basic_rating_life(22.4e3, 3.2e3)) / 1e6, 1)
    343.0
    """
    c = _positive(dynamic_rating, "C", "N")
    p = np.asarray(equivalent_load, dtype=float)
    if not np.all(np.isfinite(p)) or np.any(p <= 0.0):
        raise InputError("P", "must be > 0 N", equivalent_load)
    return np.asarray((c / p) ** life_exponent(kind) * 1e6, dtype=float)


def life_hours(revolutions: ArrayLike, speed: float) -> Array:
    r"""Life in operating hours at a constant speed: L_h = L / (n 3600) [h].

    ``revolutions`` [-], ``speed`` [rad/s] (> 0). The catalog form L10h = 10^6 L10 / (60 n)
    with n in r/min (SKF, "Basic rating life in hours") is the same equation.

    >>> round(float(life_hours(343e6, 650 * 2 * math.pi / 60)))
    8795
    """
    w = _positive(speed, "speed", "rad/s")
    return np.asarray(np.asarray(revolutions, dtype=float) / (w / (2.0 * math.pi)) / 3600.0, dtype=float)


def equivalent_dynamic_load(radial: ArrayLike, axial: ArrayLike, x: float = 1.0, y: float = 0.0,
                            e: float | None = None) -> Array:
    r"""Equivalent dynamic bearing load P = X Fr + Y Fa [N], vectorised.

    ``radial`` Fr and ``axial`` Fa [N] (magnitudes are used); X, Y from the bearing table
    for Fa/Fr > e. With ``e`` given, P = Fr wherever Fa/Fr <= e (the tables' first column,
    X = 1, Y = 0). Source: NSK, "Calculation of Equivalent Loads"; ISO 281:2007 sec. 6.
    Roloff/Matek worked example (6209, Fr = 5 kN, Fa = 2 kN, X = 0.56, Y = 1.5): 5.8 kN.

    >>> float(equivalent_dynamic_load(5e3, 2e3, 0.56, 1.5))
    5800.0
    """
    fr = np.abs(np.asarray(radial, dtype=float))
    fa = np.abs(np.asarray(axial, dtype=float))
    if x < 0.0 or y < 0.0 or not (math.isfinite(x) and math.isfinite(y)):
        raise InputError("X, Y", "must be finite and >= 0", (x, y))
    p = x * fr + y * fa
    if e is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(fr > 0.0, fa / np.where(fr > 0.0, fr, 1.0), np.inf)
        p = np.where(ratio <= e, fr, p)
    return np.asarray(p, dtype=float)


def static_safety_factor(static_rating: float, static_load: ArrayLike) -> Array:
    r"""Static safety factor s0 = C0 / P0 [-] (ISO 76; SKF "static safety factor s0").

    ``static_rating`` C0 [N], ``static_load`` P0 [N] (the largest load at standstill or in
    slow motion, shocks included). A zero load gives infinity.
    """
    c0 = _positive(static_rating, "C0", "N")
    p0 = np.abs(np.asarray(static_load, dtype=float))
    with np.errstate(divide="ignore"):
        return np.asarray(np.where(p0 > 0.0, c0 / np.where(p0 > 0.0, p0, 1.0), np.inf), dtype=float)


def cubic_mean_load(load: ArrayLike, weights: ArrayLike, exponent: float = 3.0) -> float:
    r"""Mean load with the same fatigue effect as a varying one [N].

    .. math:: F_m = \left(\frac{\sum_i |F_i|^p\, s_i}{\sum_i s_i}\right)^{1/p}

    ``load`` F_i [N] and ``weights`` s_i >= 0 of the same shape: the distance [m] (or the
    revolutions) travelled under each load, e.g. |v_i| dt_i from a sampled cycle. ``exponent``
    p = 3 for balls (10/3 for rollers). Samples at standstill carry no weight: loads held while
    stopped do not consume fatigue life (they count for the static safety factor instead).
    Sources: ISO 281 equivalent load for a variable load; Steinmeyer, "Calculation of the
    equivalent Load" (ball screws); Schaeffler, monorail guidance "Equivalent load".

    >>> round(cubic_mean_load([100.0, 200.0], [1.0, 1.0]), 2)
    165.1
    """
    f = np.abs(np.asarray(load, dtype=float))
    w = np.abs(np.asarray(weights, dtype=float))
    if f.shape != w.shape:
        raise InputError("weights", f"must have the shape of the load {f.shape}", w.shape)
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(w))):
        raise InputError("load", "must be finite", "nan or inf")
    total = float(np.sum(w))
    if total <= 0.0:
        raise InputError("weights", "the cycle must travel some distance for a mean load", total)
    p = _positive(exponent, "exponent", "")
    scale = float(np.max(f))
    if scale == 0.0:
        return 0.0
    # Scaled by the largest load so that |F|^p neither overflows nor underflows.
    return scale * float((np.sum((f / scale) ** p * w) / total) ** (1.0 / p))


def cubic_mean_loads(load: ArrayLike, weights: ArrayLike, exponent: float = 3.0) -> Array:
    """:func:`cubic_mean_load` of each row (last axis) of ``load`` with the same row of ``weights``
    (arrays of one shape, any leading dimensions): the same formula and the same arithmetic, row by
    row, so each value equals that of :func:`cubic_mean_load` of its row. For many cycles at once
    (a design-space study). InputError as there if any row fails its rule.
    """
    f = np.abs(np.asarray(load, dtype=float))
    w = np.abs(np.asarray(weights, dtype=float))
    if f.shape != w.shape or f.ndim < 1:
        raise InputError("weights", f"must have the shape of the load {f.shape}", w.shape)
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(w))):
        raise InputError("load", "must be finite", "nan or inf")
    total = np.sum(w, axis=-1)
    if np.any(total <= 0.0):
        raise InputError("weights", "the cycle must travel some distance for a mean load", float(np.min(total)))
    p = _positive(exponent, "exponent", "")
    scale = np.max(f, axis=-1)
    safe = np.where(scale == 0.0, 1.0, scale)
    inner = np.sum((f / safe[..., None]) ** p * w, axis=-1) / total
    # the root row by row, as a scalar power: numpy's array power can differ from it in the last bit
    mean = np.array([float(m) ** (1.0 / p) for m in inner.ravel()]).reshape(inner.shape)
    return np.asarray(np.where(scale == 0.0, 0.0, scale * mean), dtype=float)


def travel_weights(speed: ArrayLike, dt: ArrayLike) -> Array:
    """Distance (or angle) travelled in each sample |v| dt [m or rad]: the weights of :func:`cubic_mean_load`."""
    return np.asarray(np.abs(np.asarray(speed, dtype=float)) * np.asarray(dt, dtype=float), dtype=float)


def convert_guide_rating(rating: float, from_distance: float, to_distance: float, kind: str = "ball") -> float:
    r"""A guide's dynamic load rating re-stated on another rating distance [N].

    .. math:: C_2 = C_1 \left(\frac{L_1}{L_2}\right)^{1/p}

    ISO 14728-1 (THK, "ISO-regulated basic dynamic load rating conversion formula"):
    C_50 = 1.26 C_100 for balls, 1.23 C_100 for rollers.

    >>> round(convert_guide_rating(1000.0, 100e3, 50e3), 2)
    1259.92
    """
    c = _positive(rating, "C", "N")
    l1 = _positive(from_distance, "from_distance", "m")
    l2 = _positive(to_distance, "to_distance", "m")
    return c * (l1 / l2) ** (1.0 / life_exponent(kind))


def guide_life(dynamic_rating: float, load: ArrayLike, rating_distance: float = 50e3, kind: str = "ball",
               f_h: float = 1.0, f_t: float = 1.0, f_c: float = 1.0, f_w: float = 1.0) -> Array:
    r"""Nominal life L10 of a linear guide (carriage/block) as a travel distance [m].

    .. math:: L_{10} = \left(\frac{f_H f_T f_C}{f_W}\,\frac{C}{P_C}\right)^p L_{rated}

    ``dynamic_rating`` C [N] on the distance ``rating_distance`` [m] (50e3 for THK and IKO
    ball guides, 100e3 for THK roller guides and Schneeberger; the basis printed next to C in
    the vendor's catalog, see :data:`GUIDE_RATING_DISTANCE`); ``load`` P_C [N] per carriage
    (the cubic mean over the cycle for life); ``kind`` 'ball' (p = 3) or 'roller' (p = 10/3);
    hardness f_H, temperature f_T, contact f_C factors <= 1 and load factor f_W >= 1 (Bosch
    Rexroth linear-module calculation fundamentals: f_W 1.0-1.2 without impact below 0.25 m/s,
    1.2-1.5 slight impact up to 1 m/s, 1.5-2.0 moderate up to 2 m/s, 2.0-3.5 strong impact
    above). Sources: THK General Catalog, LM Guide "Calculating the Nominal Life"; IKO catalog
    p. III-5, Table 2.1; Schneeberger MINIRAIL, 17.2.1.

    >>> float(guide_life(10e3, 5e3))  # (10/5)^3 x 50 km
    400000.0
    """
    c = _positive(dynamic_rating, "C", "N")
    dist = _positive(rating_distance, "rating_distance", "m")
    fh, ft, fc, fw = (_factor(f_h, "f_h"), _factor(f_t, "f_t"), _factor(f_c, "f_c"), _factor(f_w, "f_w"))
    p = np.abs(np.asarray(load, dtype=float))
    if not np.all(np.isfinite(p)) or np.any(p <= 0.0):
        raise InputError("P_C", "must be > 0 N", load)
    return np.asarray((fh * ft * fc / fw * c / p) ** life_exponent(kind) * dist, dtype=float)


def guide_static_safety_factor(static_rating: float, load: ArrayLike, f_h: float = 1.0, f_t: float = 1.0,
                               f_c: float = 1.0) -> Array:
    r"""Static safety factor of a linear guide f_S = f_H f_T f_C C_0 / P_C [-].

    ``static_rating`` C0 [N] (or a static moment rating [N m] with a moment ``load``), ``load``
    P_C [N] the largest load at standstill or under shock. THK guideline lower limits: 1-1.3
    without vibration or impact, 2-3 with (general machinery); machine tools 1-1.5 and 2.5-7.
    Source: THK General Catalog, "Static Safety Factor fS".
    """
    factors = _factor(f_h, "f_h") * _factor(f_t, "f_t") * _factor(f_c, "f_c")
    return np.asarray(factors * static_safety_factor(static_rating, load), dtype=float)


def guide_equivalent_load(force: ArrayLike, moments: dict[str, ArrayLike] | None = None,
                          moment_factors: dict[str, float] | None = None) -> Array:
    r"""Load on one carriage from a force and moments, as one equivalent force [N].

    .. math:: P = |F| + \sum_j K_j |M_j|

    ``force`` [N] normal to the rail; ``moments`` {name: M_j [N m]} (pitch, roll, yaw) with
    ``moment_factors`` {name: K_j [1/m]}, the equivalent factors each vendor tabulates per
    model and carriage count (THK LM Guide, "equivalent factor"; a single carriage takes moments
    through K, a pair of carriages mostly as a force couple). A moment without a factor is an
    error: the factor is the vendor's number, never a guess.
    """
    p = np.abs(np.asarray(force, dtype=float))
    for name, m in (moments or {}).items():
        factors = moment_factors or {}
        if name not in factors:
            raise InputError(f"moment_factors.{name}", "is required for a moment on the carriage (vendor table)",
                             has_value=False)
        k = factors[name]
        if not math.isfinite(k) or k < 0.0:
            raise InputError(f"moment_factors.{name}", "must be >= 0 1/m", k)
        p = p + k * np.abs(np.asarray(m, dtype=float))
    return np.asarray(p, dtype=float)


def life_time(life: ArrayLike, travel_per_cycle: float, cycle_time: float) -> Array:
    r"""Operating time to reach a life [s], repeating a cycle.

    .. math:: t = \frac{L}{s_{cycle}}\, t_{cycle}

    ``life`` in the unit of ``travel_per_cycle`` (metres for a guide, revolutions for a
    bearing or screw), ``cycle_time`` [s] including dwells. For a reciprocating stroke l_s at
    n_1 cycles per minute this is THK's / IKO's L_h = 10^6 L / (2 l_s n_1 60) with L in km
    and l_s in mm.
    """
    s = _positive(travel_per_cycle, "travel_per_cycle", "")
    t = _positive(cycle_time, "cycle_time", "s")
    return np.asarray(np.asarray(life, dtype=float) / s * t, dtype=float)
