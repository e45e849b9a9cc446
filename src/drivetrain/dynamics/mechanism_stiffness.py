r"""Stiffness of the mechanism itself across the stroke: screw drive, timing belt, rack and pinion, conveyor.

A linear mechanism's compliance changes with the carriage position: a screw shaft is softer the
farther the nut is from its thrust bearing, a belt's spans lengthen and shorten as the carriage
moves. Every function here is vectorised over carriage positions and returns SI: axial stiffness
[N/m] at the carriage, torsional stiffness [N m/rad] at the mechanism's input shaft.

Sources:
- THK General Catalog, Ball Screw, "Axial Rigidity of the Feed Screw System" (Studying the
  Rigidity): 1/K = 1/K_S + 1/K_N + 1/K_B + 1/K_H; screw shaft K_S = A E / L for a shaft fixed
  at one end (fixed-free, fixed-supported; L from the fixed bearing to the nut),
  K_S = A E L / (a b) for both ends fixed (nut at a from one bearing, b = L - a), smallest at
  mid-span, 4 A E / L; A = pi d_1^2 / 4 (root diameter), E = 206 GPa. The same formulas in the
  Utah "ME EN 7960 Precision Machine Design, Ball Screw Calculations" notes (source THK).
- Timing belt as a spring: each free span is c_spec / L (c_spec [N], the belt's specific
  stiffness for its width: force per unit strain), the two paths from the drive pulley to the
  carriage in parallel; lowest where the two lengths are equal (BRECO linear-drive formula
  collection; Parker Compax3 manual, "Toothed belt drive as two mass system": D = D_1 + D_2,
  D_i = D_spec / l_i, stiffness changes with the position of the moved mass).
- Rack and pinion mesh: mesh stiffness per unit face width c_gamma (ISO 6336-1, the mean
  mesh stiffness c_gamma-alpha; solid steel spur gear pairs of standard basic rack are about
  20 N/(mm um)), k = c_gamma b.
- Torsional stiffness at the input shaft: k_theta = k_x r^2 with r the lever arm [m/rad]
  (lead / 2 pi for a screw, the pitch radius of a pulley or pinion): a twist d(phi) moves the
  carriage r d(phi) against k_x (energy equivalence; docs/conventions.md, Linear mechanisms).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError
from drivetrain.physics.belt_rack import linear_belt_spans

Array = NDArray[np.float64]

STEEL_YOUNGS_MODULUS = 206e9
"""[Pa] THK's screw-shaft Young's modulus."""

MESH_STIFFNESS_STEEL = 20e9
"""[N/m per m of face width] = 20 N/(mm um): ISO 6336-1 mean mesh stiffness c_gamma-alpha of
solid steel spur gear pairs with a standard basic rack (use the vendor's value when given)."""

SCREW_MOUNTINGS = ("fixed_free", "fixed_supported", "supported_supported", "fixed_fixed")


def _positive(value: float, name: str, unit: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value)) or value <= 0.0:
        raise InputError(name, f"must be > 0 {unit}", value)
    return float(value)


def _stiffness_array(value: ArrayLike, name: str) -> Array:
    a = np.asarray(value, dtype=float)
    if np.any(np.isnan(a)) or np.any(a <= 0.0):
        raise InputError(name, "must be > 0 N/m (inf for rigid)", value)
    return a


def series(*stiffnesses: ArrayLike) -> Array:
    r"""Springs in series, element-wise over positions: 1/k = sum 1/k_i [unit of the inputs].

    Arrays broadcast together; ``inf`` is a rigid element. The result is never larger than the
    smallest element (the weakest link; lecture, "High Stiffness").

    >>> series([2.0, 4.0], 4.0).tolist()
    [1.3333333333333333, 2.0]
    """
    if not stiffnesses:
        raise ValueError("series needs at least one stiffness")
    compliance: Array = np.zeros(())
    for n, k in enumerate(stiffnesses):
        compliance = compliance + 1.0 / _stiffness_array(k, f"stiffness[{n}]")
    with np.errstate(divide="ignore"):
        return np.asarray(1.0 / compliance, dtype=float)


def screw_shaft_stiffness(root_diameter: float, nut_position: ArrayLike, bearing_span: float,
                          mounting: str = "fixed_supported",
                          youngs_modulus: float = STEEL_YOUNGS_MODULUS) -> Array:
    r"""Axial stiffness of a screw shaft between its thrust bearing(s) and the nut [N/m].

    .. math::
        K_S = \frac{A E}{x} \ \text{(one end fixed)}, \qquad
        K_S = \frac{A E L}{x (L - x)} \ \text{(fixed-fixed)}, \qquad A = \frac{\pi d_1^2}{4}

    ``root_diameter`` d_1 [m]; ``nut_position`` x [m] from the fixed (thrust) bearing, array
    over the stroke, 0 < x <= L (fixed-fixed: 0 < x < L); ``bearing_span`` L [m] between the
    supports (or to the free end); ``mounting``: ``fixed_free``, ``fixed_supported`` and
    ``supported_supported`` carry the thrust at one end (A E / x); ``fixed_fixed`` at both,
    the two shaft lengths in parallel (A E L / (x (L - x)), 4 A E / L at mid-span).
    Source: THK, "Axial Rigidity of the Feed Screw System".

    >>> round(float(screw_shaft_stiffness(0.02, 0.5, 1.0, "fixed_fixed")) / float(
    ...     screw_shaft_stiffness(0.02, 1.0, 1.0, "fixed_supported")), 6)
    4.0
    """
    d = _positive(root_diameter, "root_diameter", "m")
    span = _positive(bearing_span, "bearing_span", "m")
    e = _positive(youngs_modulus, "youngs_modulus", "Pa")
    x = np.asarray(nut_position, dtype=float)
    if mounting not in SCREW_MOUNTINGS:
        raise InputError("mounting", f"must be one of {', '.join(repr(m) for m in SCREW_MOUNTINGS)}", mounting)
    if not np.all(np.isfinite(x)) or np.any(x <= 0.0) or np.any(x > span) or (
            mounting == "fixed_fixed" and np.any(x >= span)):
        raise InputError("nut_position", f"must lie between the bearings, in (0, {span:g}) m", nut_position)
    area_e = math.pi * d**2 / 4.0 * e
    if mounting == "fixed_fixed":
        return np.asarray(area_e * span / (x * (span - x)), dtype=float)
    return np.asarray(area_e / x, dtype=float)


def screw_drive_stiffness(root_diameter: float, nut_position: ArrayLike, bearing_span: float,
                          mounting: str = "fixed_supported", nut_stiffness: float = math.inf,
                          bearing_stiffness: float = math.inf, housing_stiffness: float = math.inf,
                          youngs_modulus: float = STEEL_YOUNGS_MODULUS) -> dict[str, Array]:
    r"""Axial stiffness of a ball-screw feed system over the stroke [N/m], part by part.

    .. math:: \frac{1}{K} = \frac{1}{K_S(x)} + \frac{1}{K_N} + \frac{1}{K_B} + \frac{1}{K_H}

    Shaft (:func:`screw_shaft_stiffness`), nut K_N (catalog value, at the preload), support
    bearing K_B (the thrust bearing set; both sets in parallel for fixed-fixed: pass their sum),
    nut and bearing housings K_H; [N/m], ``inf`` where unknown or rigid. Returns
    {"shaft", "nut", "support bearing", "housing", "total"}, each shaped like ``nut_position``.
    Source: THK, "Axial Rigidity of the Feed Screw System".
    """
    shaft = screw_shaft_stiffness(root_diameter, nut_position, bearing_span, mounting, youngs_modulus)
    parts = {"shaft": shaft,
             "nut": np.full_like(shaft, _stiffness_array(nut_stiffness, "nut_stiffness")),
             "support bearing": np.full_like(shaft, _stiffness_array(bearing_stiffness, "bearing_stiffness")),
             "housing": np.full_like(shaft, _stiffness_array(housing_stiffness, "housing_stiffness"))}
    parts["total"] = series(*parts.values())
    return parts


BELT_STRAIN_AT_ALLOWABLE = 0.004
"""Strain of a steel-cord polyurethane belt at its allowable tensile load (0.4 %): the ELATECH
tables give C_spez = F_Tzul / 0.004 for every width (AT5, ATL5, AT20, pp. 14-20), and the
Parker Compax3 manual computes D_spez from F_max and 0.004 the same way."""


def belt_specific_stiffness_from_tension(allowable_tension: float,
                                         strain: float = BELT_STRAIN_AT_ALLOWABLE) -> float:
    r"""Specific stiffness c_spec [N] of a belt from its allowable tensile load and the strain there.

    .. math:: c_{spec} = \frac{F_{adm}}{\varepsilon_{adm}}

    ``allowable_tension`` F_adm [N] (ELATECH F_Tzul, BRECOflex F_adm) for the belt's width,
    ``strain`` at that load (0.004 for ELATECH steel-cord belts). Use the catalog's own c_spec
    where it is printed. ELATECH ATL5, 50 mm: F_Tzul = 5060 N, C_spez = 1 265 000 N:

    >>> belt_specific_stiffness_from_tension(5060.0)
    1265000.0
    """
    return _positive(allowable_tension, "belt.permissible_tension", "N") / _positive(strain, "strain", "")


def belt_drive_stiffness(specific_stiffness: float, span_pull: ArrayLike, span_other: ArrayLike) -> Array:
    r"""Axial stiffness of a pretensioned belt at the carriage: both paths in parallel [N/m].

    .. math:: k = c_{spec}\left(\frac{1}{L_1} + \frac{1}{L_2}\right)

    ``specific_stiffness`` c_spec [N] of the belt (force per unit strain, for its width),
    ``span_pull`` L_1 and ``span_other`` L_2 [m] (arrays over positions,
    :func:`drivetrain.physics.belt_rack.linear_belt_spans`). Valid while the pretension keeps
    both spans taut. Sources: BRECO linear-drive formula collection; Parker Compax3
    "Toothed belt drive as two mass system".

    >>> float(belt_drive_stiffness(1e6, 0.5, 0.5))
    4000000.0
    """
    c = _positive(specific_stiffness, "belt.specific_stiffness", "N")
    l1 = np.asarray(span_pull, dtype=float)
    l2 = np.asarray(span_other, dtype=float)
    if np.any(l1 < 0.0) or np.any(l2 < 0.0) or not (np.all(np.isfinite(l1)) and np.all(np.isfinite(l2))):
        raise InputError("span", "lengths must be finite and >= 0 m", (span_pull, span_other))
    with np.errstate(divide="ignore", over="ignore"):
        return np.asarray(c / l1 + c / l2, dtype=float)


def linear_belt_stiffness(specific_stiffness: float, position: ArrayLike, centre_distance: float,
                          layout: str = "loop", clamp_offset: float = 0.0) -> Array:
    """Axial stiffness of a linear belt axis (or conveyor) at each carriage position [N/m].

    :func:`linear_belt_spans` (``loop``: clamped carriage, drive pulley and idler; ``omega``:
    belt fixed at the frame ends) then :func:`belt_drive_stiffness`.
    """
    l1, l2 = linear_belt_spans(position, centre_distance, layout, clamp_offset)
    return belt_drive_stiffness(specific_stiffness, l1, l2)


def conveyor_stiffness(specific_stiffness: float, position: ArrayLike, centre_distance: float) -> Array:
    """Axial stiffness of a conveyor belt at the load [N/m]: the load rides on a closed loop.

    The carry side from the drive pulley to the load and the path round the tail pulley back to
    the drive pulley act in parallel: the ``loop`` layout of :func:`linear_belt_stiffness`, with
    ``position`` the load's distance from the drive pulley.
    """
    return linear_belt_stiffness(specific_stiffness, position, centre_distance, "loop")


def rack_mesh_stiffness(face_width: float, mesh_stiffness_per_width: float = MESH_STIFFNESS_STEEL,
                        pressure_angle: float = math.radians(20.0)) -> float:
    r"""Stiffness of a rack-and-pinion mesh along the rack [N/m].

    .. math:: k_x = c_\gamma\, b \cos^2\alpha

    ``face_width`` b [m], ``mesh_stiffness_per_width`` c_gamma [N/m per m] along the line of
    action (ISO 6336-1, :data:`MESH_STIFFNESS_STEEL`), ``pressure_angle`` alpha [rad]: the
    tooth spring acts along the line of action, so a travel x along the rack compresses it by
    x cos(alpha) and its force has the component cos(alpha) along the rack. Independent of the
    carriage position; the rack mounting and the pinion shaft add in series.
    """
    b = _positive(face_width, "rack.face_width", "m")
    c = _positive(mesh_stiffness_per_width, "rack.mesh_stiffness", "N/m^2")
    if not (0.0 <= pressure_angle < math.pi / 2.0):
        raise InputError("pressure_angle", "must lie in [0, 90) deg", pressure_angle)
    return c * b * math.cos(pressure_angle) ** 2


def torsional_at_input(axial_stiffness: ArrayLike, lever: float) -> Array:
    r"""Axial stiffness at the carriage seen as torsional stiffness at the input shaft [N m/rad].

    .. math:: k_\theta = k_x r^2

    ``axial_stiffness`` k_x [N/m] (array over positions), ``lever`` r [m/rad]: lead / (2 pi)
    for a screw, the pitch radius of a pulley or pinion.

    >>> torsional_at_input(4e6, 0.02).item()
    1600.0
    """
    r = _positive(lever, "lever", "m/rad")
    return np.asarray(np.asarray(axial_stiffness, dtype=float) * r**2, dtype=float)


@dataclass(frozen=True)
class MechanismStiffness:
    """A mechanism's stiffness across the stroke (SI).

    ``position`` [m] carriage positions; ``parts`` {name: axial stiffness [N/m] per position}
    in series, ``lever`` r [m/rad]. ``axial`` and ``torsional`` are the series totals at the
    carriage [N/m] and at the mechanism's input shaft [N m/rad].
    """

    position: Array
    parts: Mapping[str, Array]
    lever: float
    axial: Array = field(init=False)
    torsional: Array = field(init=False)

    def __post_init__(self) -> None:
        if not self.parts:
            raise ValueError("MechanismStiffness needs at least one part")
        total = series(*self.parts.values())
        object.__setattr__(self, "axial", np.broadcast_to(total, np.shape(self.position)).astype(float))
        object.__setattr__(self, "torsional", torsional_at_input(self.axial, self.lever))

    @property
    def worst_index(self) -> int:
        """Index of the position with the lowest stiffness."""
        return int(np.argmin(self.axial))

    def weakest_link(self, index: int | None = None) -> str:
        """Name of the most compliant part at a position (default: the softest position)."""
        i = self.worst_index if index is None else index
        return min(self.parts, key=lambda name: float(np.broadcast_to(self.parts[name], self.axial.shape)[i]))
