r"""Stiffness of drive-train elements, combined and reflected to the motor shaft.

Every function returns SI: torsional stiffness [N m/rad], axial stiffness [N/m], torsional
damping [N m s/rad]. Catalog units are converted here, once (N m/arcmin -> N m/rad).

Sources:
- Lecture, "Mechanical Vibration in Drive Trains": K_SHAFT = pi D^4 G / (32 L); the torsional
  natural frequency example (0.5 and 0.4 kg m^2 on 60e3 N m/rad: 82.7 Hz).
- Timoshenko & Gere, *Mechanics of Materials*, 4th ed. (1997), sec. 3.3-3.4 (torsion of solid and
  hollow circular shafts: K = G I_p / L, I_p = pi (D^4 - d^4) / 32).
- THK General Catalog, Ball Screw, "Axial Rigidity of the Feed Screw System" (K_s = A E / L for a
  screw fixed at one end, K_s = A E L / (a b) for both ends fixed, the nut and support bearing
  rigidities in series with it).
- Belt manufacturers' linear-drive design guides (e.g. Gates/Mulco, BRECOflex "specific
  stiffness" c_sp [N]): axial belt stiffness k = c_sp / L of a span of length L.
- Energy equivalence (lecture, "Energy Equivalence Principle"): a spring of stiffness K behind a
  ratio i (input speed / output speed) is seen at the input as K / i^2; viscous damping as B / i^2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

ARCMIN = math.pi / (180.0 * 60.0)
"""[rad] one minute of arc."""


def _positive(value: float, name: str, unit: str) -> float:
    from drivetrain.errors import InputError

    if not (isinstance(value, (int, float)) and math.isfinite(value)) or value <= 0.0:
        raise InputError(name, f"must be > 0 {unit}", value)
    return float(value)


def torsional_stiffness_shaft(diameter: float, length: float, shear_modulus: float) -> float:
    r"""Torsional stiffness of a solid round shaft [N m/rad].

    .. math:: K = \frac{\pi D^4 G}{32 L}

    diameter D [m], length L [m], shear modulus G [Pa] (from the materials table).
    Source: lecture, "Mechanical Vibration in Drive Trains" (K_SHAFT); Timoshenko & Gere, 4th ed.,
    sec. 3.3. MathWorks' servomechanism example (d = 20 mm, L = 1 m, G = 81.5 GPa) publishes
    kT = 1280.2 N m/rad:

    >>> round(torsional_stiffness_shaft(0.02, 1.0, 81.5e9), 1)
    1280.2
    """
    d = _positive(diameter, "diameter", "m")
    length_ = _positive(length, "length", "m")
    g = _positive(shear_modulus, "shear_modulus", "Pa")
    return math.pi * d**4 * g / (32.0 * length_)


def torsional_stiffness_hollow_shaft(
    outer_diameter: float, inner_diameter: float, length: float, shear_modulus: float
) -> float:
    r"""Torsional stiffness of a hollow round shaft (tube) [N m/rad].

    .. math:: K = \frac{\pi (D_o^4 - D_i^4) G}{32 L}

    outer and inner diameters [m], length [m], shear modulus [Pa].
    Source: Timoshenko & Gere, *Mechanics of Materials*, 4th ed., sec. 3.4 (hollow shafts).

    >>> round(torsional_stiffness_hollow_shaft(0.02, 0.0, 1.0, 81.5e9), 1)
    1280.2
    """
    from drivetrain.errors import InputError

    do = _positive(outer_diameter, "outer_diameter", "m")
    if not math.isfinite(inner_diameter) or inner_diameter < 0.0 or inner_diameter >= do:
        raise InputError("inner_diameter", "must be >= 0 m and smaller than the outer diameter", inner_diameter)
    length_ = _positive(length, "length", "m")
    g = _positive(shear_modulus, "shear_modulus", "Pa")
    return math.pi * (do**4 - inner_diameter**4) * g / (32.0 * length_)


def stiffness_series(stiffnesses: Iterable[float]) -> float:
    r"""Springs in series (the same torque through each) [same unit as the inputs].

    .. math:: \frac{1}{K} = \sum_i \frac{1}{K_i}

    An infinite entry (a rigid element) contributes nothing. The weakest link dominates
    (lecture, "High Stiffness": "a single element with inadequate stiffness can compromise the
    integrity of the entire system").

    >>> stiffness_series([2.0, 2.0])
    1.0
    """
    compliance = 0.0
    n = 0
    for k in stiffnesses:
        n += 1
        if math.isinf(k) and k > 0:
            continue
        compliance += 1.0 / _positive(k, f"stiffness[{n - 1}]", "N*m/rad")
    if n == 0:
        raise ValueError("stiffness_series needs at least one stiffness")
    return math.inf if compliance == 0.0 else 1.0 / compliance


def stiffness_parallel(stiffnesses: Iterable[float]) -> float:
    r"""Springs in parallel (the same deflection across each) [same unit as the inputs].

    .. math:: K = \sum_i K_i

    >>> stiffness_parallel([1.0, 2.0])
    3.0
    """
    total = 0.0
    for n, k in enumerate(stiffnesses):
        if not math.isfinite(k) and not (math.isinf(k) and k > 0):
            raise ValueError(f"stiffness[{n}] is not a number: {k}")
        if k < 0.0:
            from drivetrain.errors import InputError

            raise InputError(f"stiffness[{n}]", "must be >= 0", k)
        total += k
    return total


def torsional_stiffness_from_arcmin(stiffness_per_arcmin: float) -> float:
    r"""Gearbox torsional stiffness from a catalog value in N m/arcmin to [N m/rad].

    .. math:: K\,[\mathrm{N\,m/rad}] = K\,[\mathrm{N\,m/arcmin}] \cdot \frac{180 \cdot 60}{\pi}

    Planetary and harmonic gearbox catalogs (e.g. Neugart, Wittenstein alpha, Harmonic Drive)
    give the torsional rigidity at the output flange in N m/arcmin; reflect it to the gearbox
    input with :func:`reflect_stiffness`.

    >>> round(torsional_stiffness_from_arcmin(1.0), 2)
    3437.75
    """
    return _positive(stiffness_per_arcmin, "stiffness", "N*m/arcmin") / ARCMIN


def arcmin_to_rad(angle_arcmin: float) -> float:
    """[rad] from [arcmin] (catalog backlash): angle * pi / (180 * 60)."""
    return angle_arcmin * ARCMIN


def belt_axial_stiffness(specific_stiffness: float, span_length: float) -> float:
    r"""Axial stiffness of one free belt span [N/m].

    .. math:: k = \frac{c_{sp}}{L}

    specific stiffness c_sp [N] (belt catalog value per unit strain, for the belt's width),
    span length L [m]. Source: timing-belt linear-drive design guides (Gates/Mulco, BRECOflex:
    "specific stiffness c_spec"; k = c_spec / L).

    >>> belt_axial_stiffness(1.0e6, 0.5)
    2000000.0
    """
    c = _positive(specific_stiffness, "specific_stiffness", "N")
    return c / _positive(span_length, "span_length", "m")


def belt_linear_drive_axial_stiffness(specific_stiffness: float, span_a: float, span_b: float) -> float:
    r"""Axial stiffness of a pretensioned linear belt drive with the carriage between two spans [N/m].

    .. math:: k = c_{sp} \left(\frac{1}{L_a} + \frac{1}{L_b}\right)

    Both spans act in parallel while the pretension keeps the slack side taut (the same design
    guides as :func:`belt_axial_stiffness`); lowest with the carriage in the middle.
    """
    return belt_axial_stiffness(specific_stiffness, span_a) + belt_axial_stiffness(specific_stiffness, span_b)


def torsional_from_linear_radius(axial_stiffness: float, radius: float) -> float:
    r"""Axial stiffness acting at a radius, seen as torsional stiffness at the pulley [N m/rad].

    .. math:: K = k r^2

    axial stiffness k [N/m], pulley (or pinion) pitch radius r [m]: a twist d(phi) stretches the
    span by r d(phi), giving a force k r d(phi) and a torque k r^2 d(phi).

    >>> torsional_from_linear_radius(2.0e6, 0.02)
    800.0
    """
    k = _positive(axial_stiffness, "axial_stiffness", "N/m")
    return k * _positive(radius, "radius", "m") ** 2


def belt_torsional_stiffness(specific_stiffness: float, span_length: float, pulley_radius: float) -> float:
    r"""Torsional stiffness of one belt span at its drive pulley [N m/rad]: K = (c_sp / L) r^2."""
    return torsional_from_linear_radius(belt_axial_stiffness(specific_stiffness, span_length), pulley_radius)


def screw_shaft_axial_stiffness(
    root_diameter: float,
    length: float,
    youngs_modulus: float = 206e9,
    mounting: str = "fixed_free",
    nut_position: float | None = None,
) -> float:
    r"""Axial stiffness of a ball screw shaft [N/m].

    .. math::
        K_s = \frac{A E}{L} \quad \text{(fixed - free/supported, L from the fixed bearing to the nut)}

        K_s = \frac{A E L}{a\,(L - a)} \quad \text{(fixed - fixed, nut at a; } 4 A E / L
        \text{ at mid-stroke, the minimum)}

    with A = pi d_r^2 / 4 the root-diameter section [m^2], E Young's modulus [Pa] (steel
    206 GPa, the THK value), L [m]. ``mounting`` is ``fixed_free`` or ``fixed_fixed``;
    ``nut_position`` a [m] from one end (default mid-stroke, the lowest stiffness).
    Source: THK General Catalog, Ball Screw, "Axial Rigidity of the Feed Screw System".
    """
    from drivetrain.errors import InputError

    dr = _positive(root_diameter, "root_diameter", "m")
    length_ = _positive(length, "length", "m")
    e = _positive(youngs_modulus, "youngs_modulus", "Pa")
    area = math.pi * dr**2 / 4.0
    if mounting == "fixed_free":
        return area * e / length_
    if mounting == "fixed_fixed":
        a = length_ / 2.0 if nut_position is None else float(nut_position)
        if not 0.0 < a < length_:
            raise InputError("nut_position", "must lie strictly between the two bearings", nut_position)
        return area * e * length_ / (a * (length_ - a))
    raise InputError("mounting", "must be one of 'fixed_free', 'fixed_fixed'", mounting)


def ball_screw_axial_stiffness(
    shaft_stiffness: float, nut_stiffness: float = math.inf, bearing_stiffness: float = math.inf
) -> float:
    r"""Axial stiffness of the feed-screw system: shaft, nut and support bearing in series [N/m].

    .. math:: \frac{1}{K} = \frac{1}{K_s} + \frac{1}{K_N} + \frac{1}{K_B}

    Source: THK General Catalog, "Axial Rigidity of the Feed Screw System" (the nut mounting
    bracket and bearing housing rigidities, when known, add in series the same way).
    """
    return stiffness_series([shaft_stiffness, nut_stiffness, bearing_stiffness])


def torsional_from_axial_lead(axial_stiffness: float, lead: float) -> float:
    r"""Axial stiffness of a screw system seen as torsional stiffness at the screw [N m/rad].

    .. math:: K = k_{ax} \left(\frac{h}{2\pi}\right)^2

    axial stiffness [N/m], lead h [m/rev]: the screw turns 2 pi rad per lead of travel, so its
    lever arm is h / (2 pi) (docs/conventions.md, "Linear mechanisms").

    >>> round(torsional_from_axial_lead(1e9, 0.01), 1)
    2533.0
    """
    k = _positive(axial_stiffness, "axial_stiffness", "N/m")
    h = _positive(lead, "lead", "m")
    return k * (h / (2.0 * math.pi)) ** 2


def reflect_stiffness(stiffness: float, ratio: float) -> float:
    r"""Stiffness behind a ratio i seen at its input [N m/rad]: K / i^2.

    For a linear mechanism ``stiffness`` is axial [N/m] and ``ratio`` is [rad/m].
    Source: lecture, "Energy Equivalence Principle" ((1/2) K' phi_in^2 = (1/2) K phi_out^2).

    >>> reflect_stiffness(400.0, 2.0)
    100.0
    """
    return stiffness / ratio**2


def reflect_damping(damping: float, ratio: float) -> float:
    r"""Viscous damping behind a ratio i seen at its input [N m s/rad]: B / i^2 (power equivalence)."""
    return damping / ratio**2
