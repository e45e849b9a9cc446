"""Checks of a motor (and gearbox) against a duty cycle, vectorised over candidate motors.

Each check has a required and an available value, a margin (available / required - 1: how
much is spare, negative = by how much it fails) and ok. Required values carry the user's
margins (``motor.margins``). The motor's speed-torque envelope comes from ``envelope``; where
it was derived from ratings rather than a datasheet curve the check is marked approximate.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Check:
    """One check: ``required`` must not exceed ``available`` (both in ``unit``)."""

    name: str
    required: float
    available: float
    unit: str
    ok: bool
    margin: float
    approximate: bool = False
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON form (design.md: name, required, available, margin, ok)."""
        return asdict(self)


def margin_of(required: Array | float, available: Array | float) -> Array:
    """available / required - 1 [-]; +inf when nothing is required."""
    req = np.asarray(required, dtype=float)
    avail = np.asarray(available, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(req > 0.0, avail / np.where(req > 0.0, req, 1.0) - 1.0, np.inf)
    return np.asarray(out, dtype=float)


def to_checks(name: str, unit: str, required: Array, available: Array, margin: Array, approximate: bool = False,
              note: str = "") -> list[Check]:
    """Per-candidate Check objects from arrays."""
    return [Check(name, float(r), float(a), unit, bool(m >= 0.0), float(m), approximate, note)
            for r, a, m in zip(np.atleast_1d(required), np.atleast_1d(available), np.atleast_1d(margin),
                               strict=True)]
