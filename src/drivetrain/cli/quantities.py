"""Quantities in the CLI tables, in the unit system of ``--units`` (si, imperial, as-given).

One conversion for every face: the report's (``drivetrain.report.display``, whose table is
``drivetrain.units.SI_UNITS`` / ``IMPERIAL_UNITS``). With ``si`` the tables print as they always have
(N*m, kg*cm^2, mm, N/um); in every system a shaft's speed stays rpm, power W, energy J and time s.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

CONVERTED = frozenset({"torque", "inertia", "length", "speed", "acceleration", "jerk", "mass", "force",
                       "linear_stiffness"})
"""Quantities whose display unit differs between the systems (the others are the same in all)."""

_SCALED_UNITS = {"mm": ("length", 1e-3)}
"""Check units that are not SI: the quantity and the SI value of one unit (a shaft diameter in mm)."""


class TableUnits:
    """Formats SI values for the tables in the chosen system."""

    def __init__(self, choice: str = "si", raw: Mapping[str, Any] | None = None) -> None:
        from drivetrain.report.display import DisplayUnits, display_units

        self.system = choice
        self._du: DisplayUnits | None = None if choice == "si" else display_units(choice, raw)

    def unit(self, quantity: str, si_unit: str) -> str:
        """The unit ``quantity`` is printed in: ``si_unit`` in SI (as the tables always wrote it)."""
        if self._du is None or quantity not in CONVERTED:
            return si_unit
        return self._du.unit(quantity)

    def num(self, value: float, quantity: str, si_scale: float = 1.0, spec: str = ".4g") -> str:
        """The number alone: in SI ``value * si_scale`` (the scale of the table's SI unit), else converted."""
        if self._du is None or quantity not in CONVERTED:
            return f"{value * si_scale:{spec}}"
        return f"{self._du.to(value, quantity):{spec}}"

    def q(self, value: float | None, quantity: str, si_unit: str, si_scale: float = 1.0, spec: str = ".4g") -> str:
        """An SI ``value`` of ``quantity`` with its unit ("1.234 N*m", or "10.92 lbf*in" in imperial)."""
        if value is None:
            return "n/a"
        return f"{self.num(value, quantity, si_scale, spec)} {self.unit(quantity, si_unit)}"

    def converts(self, unit: str) -> bool:
        """Whether a check's values in ``unit`` print differently from SI in this system."""
        return self._du is not None and _check_quantity(unit)[0] in CONVERTED

    def check(self, value: float | None, unit: str) -> str:
        """A check's required or available value, given in the check's own ``unit``."""
        if value is None:
            return "n/a"
        if not self.converts(unit):
            return f"{value:.4g} {unit}"
        quantity, si_per_unit = _check_quantity(unit)
        return self.q(value * si_per_unit, quantity, unit)


def _check_quantity(unit: str) -> tuple[str, float]:
    """(quantity, SI value of one ``unit``) of a check's unit; ("", 1) when it names no known quantity."""
    from drivetrain.report.checks import CHECK_QUANTITY

    return _SCALED_UNITS.get(unit, (CHECK_QUANTITY.get(unit, ""), 1.0))
