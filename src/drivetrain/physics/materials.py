"""Material properties: densities, shear moduli, friction coefficients.

Sources: densities of iron and aluminium from the lecture's load pages ("rho = 7.87e3 [kg/m^3]:
Iron, rho = 2.70e3: Aluminum"); the steel density varies by vendor guide (7.8e3 FANUC and
Mitsubishi, 7.87e3 Yaskawa, 7.9e3 Siemens: their selection guides, docs/references.md), so steel is 7.85e3, the
common engineering value, and every example test sets its source's own figure. Shear moduli:
the lecture gives G = 11e6 lb/in^2 for stainless steel (Resonant Frequency page); others are
handbook values (Roark's Formulas for Stress and Strain, 8th ed., Table 2.1 typical values).
Friction coefficients: the lecture's table "Coefficient of Friction for Various Materials"
(from Marks' Standard Handbook for Mechanical Engineers, 1967).
"""

from __future__ import annotations

from dataclasses import dataclass

from drivetrain.errors import InputError

PSI = 6894.757293168361  # [Pa per lbf/in^2]

DENSITY: dict[str, float] = {
    "steel": 7.85e3,
    "iron": 7.87e3,  # lecture, load pages
    "stainless_steel": 7.9e3,
    "cast_iron": 7.2e3,
    "aluminium": 2.70e3,  # lecture, load pages
    "aluminum": 2.70e3,
    "brass": 8.5e3,
    "bronze": 8.8e3,
    "copper": 8.96e3,
    "titanium": 4.5e3,
    "nylon": 1.15e3,
    "acetal": 1.41e3,
    "glass": 2.5e3,
    "oak": 0.75e3,
    "rubber": 1.2e3,
}
"""Densities [kg/m^3]."""

SHEAR_MODULUS: dict[str, float] = {
    "steel": 79.3e9,
    "stainless_steel": 11e6 * PSI,  # lecture: G = 11e6 lb/in^2 for stainless steel
    "iron": 79.3e9,
    "cast_iron": 41e9,
    "aluminium": 26e9,
    "aluminum": 26e9,
    "brass": 37e9,
    "bronze": 44e9,
    "copper": 44e9,
    "titanium": 44e9,
}
"""Shear moduli G [Pa]."""


@dataclass(frozen=True)
class FrictionPair:
    """Static (sticktion) and sliding coefficients of a material pair [-]."""

    static: float
    sliding: float | None


FRICTION: dict[str, FrictionPair] = {
    "steel_steel": FrictionPair(0.78, 0.42),
    "aluminium_steel": FrictionPair(0.61, 0.47),
    "aluminum_steel": FrictionPair(0.61, 0.47),
    "glass_glass": FrictionPair(0.94, 0.40),
    "oak_oak": FrictionPair(0.62, 0.48),
    "rubber_pavement": FrictionPair(0.9, 0.85),
    "tyre_road": FrictionPair(0.90, 0.85),
    "diamond_diamond": FrictionPair(0.2, None),
    "teflon_teflon": FrictionPair(0.04, None),
}
"""The lecture's friction table (Marks' Handbook, 1967): static and sliding coefficients."""

ROLLING_FRICTION_RANGE = (0.002, 0.04)
"""Typical rolling-friction coefficients mu' (lecture, Friction): 0.002 to 0.04."""


def density(material: str, field: str = "material") -> float:
    """Density of a named material [kg/m^3]; InputError listing valid names if unknown."""
    key = material.strip().lower().replace(" ", "_").replace("-", "_")
    if key not in DENSITY:
        raise InputError(field, f"unknown material; valid: {', '.join(sorted(DENSITY))}", material)
    return DENSITY[key]


def shear_modulus(material: str, field: str = "material") -> float:
    """Shear modulus G of a named material [Pa]; InputError listing valid names if unknown."""
    key = material.strip().lower().replace(" ", "_").replace("-", "_")
    if key not in SHEAR_MODULUS:
        raise InputError(field, f"no shear modulus for this material; valid: {', '.join(sorted(SHEAR_MODULUS))}",
                         material)
    return SHEAR_MODULUS[key]
