"""The parts of an order sheet: a row (``OrderRow``) and the formulas its specifications use (standard
resistor values, the peak's duration, ratings for a life, a brake's holding torque); ``sizing.order``
builds the sheet (docs/order-sheet.md).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

PARTS = ("motor", "drive", "gearbox", "braking_resistor", "brake", "coupling", "screw", "guide")
"""The parts an order sheet lists, in its order."""

E12 = (1.0, 1.2, 1.5, 1.8, 2.2, 2.7, 3.3, 3.9, 4.7, 5.6, 6.8, 8.2)
"""The E12 series of preferred values (IEC 60063:2015, "Preferred number series for resistors and
capacitors", Table 1: E12 column; the same values IEC 60062 marks on resistors)."""

BRAKE_SERVICE_FACTOR = 1.5
"""Holding-brake torque over the static load torque at the brake's shaft [-]: T_H = T_static K with
K = 1.5 to 3 for wear, usually 1.5 (Machine Design, "Mechatronics Q & A: Hold It Steady", 21 Nov 2007,
items 1 and 2)."""

PLACEHOLDER = re.compile(r"[x\u25a1\u25a0*?#]")
"""A position of a vendor code still to be chosen: a lower-case ``x`` (Siemens writes its order-number
options so), or ``□``, ``■``, ``*``, ``?``, ``#``."""

ZERO_TORQUE = 1e-9
"""[N m] a static torque at most this is the round-off of zero: no brake needed."""


@dataclass(frozen=True)
class OrderRow:
    """One part of the axis on the order sheet.

    Attributes
    ----------
    part : str
        What the row orders: one of ``PARTS``.
    kind : str
        ``"catalog"`` (a vendor's part: vendor, order code, source) or ``"specification"`` (what the part
        must do, for any vendor).
    status : str
        ``"complete"`` (a catalog part orderable as written, nothing open), ``"incomplete"`` (a catalog part
        with code positions to choose or open points) or ``"specification"``.
    name : str
        The part in words (one line).
    quantity : int
        Pieces per axis (per motor of a gantry share).
    vendor : str or None
        The catalog row's vendor.
    order_code : str or None
        The code to order as written; None where it has positions still to choose (``choose``) or where
        the row is a specification.
    catalog_id : str or None
        The catalog id the row comes from (it may be a pattern, e.g. ``6SL312x-xTE21-0AAx``).
    source : str or None
        Where the catalog row's values come from (document, section, page; or repository and commit).
    unverified : bool or None
        True where the catalog row is not traced to a vendor document (a transcription, a derived value);
        None for a specification.
    unverified_reason : str or None
        Why it is unverified.
    spec : dict
        What the part must do or is, keys carrying their unit (``continuous_current_A``, ``T2B_Nm``, ...).
    choose : list of dict
        Code positions the buyer must choose: ``position`` (1-based character of the code), ``meaning``
        and ``options`` (None where the catalog states none).
    open_points : list of str
        What is still to be decided or checked before the part can be ordered.
    element : str or None
        The axis element the row belongs to (``transmission[0]``, ``mechanism``, ``guide``).
    """

    part: str
    kind: str
    status: str
    name: str
    quantity: int = 1
    vendor: str | None = None
    order_code: str | None = None
    catalog_id: str | None = None
    source: str | None = None
    unverified: bool | None = None
    unverified_reason: str | None = None
    spec: dict[str, Any] = field(default_factory=dict)
    choose: list[dict[str, Any]] = field(default_factory=list)
    open_points: list[str] = field(default_factory=list)
    element: str | None = None

    @property
    def complete(self) -> bool:
        """A catalog part orderable as written with nothing open."""
        return self.status == "complete"

    def to_dict(self) -> dict[str, Any]:
        """The row in the JSON ``order`` block (docs/axis-file.md)."""
        return {"part": self.part, "kind": self.kind, "status": self.status, "name": self.name,
                "quantity": self.quantity, "vendor": self.vendor, "order_code": self.order_code,
                "catalog_id": self.catalog_id, "source": self.source, "unverified": self.unverified,
                "unverified_reason": self.unverified_reason, "element": self.element, "spec": dict(self.spec),
                "choose": [dict(c) for c in self.choose], "open_points": list(self.open_points)}


def standard_values(low: float, high: float, series: tuple[float, ...] = E12) -> list[float]:
    """Every value of a preferred-number series in ``[low, high]`` [ohm], ascending.

    Source: IEC 60063:2015, Table 1 (E12: 1.0, 1.2, ..., 8.2 per decade); a value is a series member times
    a power of ten.

    >>> standard_values(20.0, 50.0)
    [22.0, 27.0, 33.0, 39.0, 47.0]
    """
    if not (math.isfinite(low) and math.isfinite(high)) or high < low or high <= 0.0:
        return []
    lo = max(low, 1e-3)
    decades = np.arange(math.floor(math.log10(lo)), math.floor(math.log10(high)) + 1)
    values = np.round(np.outer(10.0 ** decades, series).ravel(), 12)
    tol = 1e-9 * high
    return [float(v) for v in values if low - tol <= v <= high + tol]


def nearest_standard(low: float, high: float, series: tuple[float, ...] = E12) -> list[float]:
    """The standard values to order for a resistance window ``[low, high]`` [ohm]: the largest series value
    at most ``high`` (it takes the peak power at the switch-on voltage with the least chopper current) and
    the smallest at least ``low`` (the most the cycle allows), where they lie in the window; ``low`` 0 when
    the drive states no minimum (then only the largest is given: the smallest needs the drive's minimum).
    Empty when no series value lies in the window.

    Source: IEC 60063:2015, Table 1; the window from ``physics.regen.resistance_window``.

    >>> nearest_standard(20.0, 50.0)
    [47.0, 22.0]
    """
    inside = standard_values(low, high, series)
    if not inside:
        return []
    return [inside[-1]] if len(inside) == 1 or low <= 0.0 else [inside[-1], inside[0]]


def peak_duration(t: np.ndarray, value: np.ndarray, threshold: float, period: float) -> float:
    """The longest time [s] ``|value|`` stays above ``threshold`` in one periodic cycle.

    ``t`` [s] the sample times (ascending, phases may repeat a boundary time), ``value`` the motor torque
    [N m] or current [A] at them, ``threshold`` in the same unit (the continuous RMS value), ``period`` [s].
    Each sample stands for the time from the midpoint before it to the midpoint after it; a run that
    reaches the cycle's end continues at its start (the cycle repeats). A drive's peak current is rated
    for a time (Beckhoff AX5000, "tmax Max. time for Ipeak"; Copley I2T): this is the time the cycle
    asks of it.
    """
    t = np.asarray(t, dtype=float)
    above = np.abs(np.asarray(value, dtype=float)) > threshold
    if t.size == 0 or not above.any():
        return 0.0
    if above.all():
        return float(period)
    mid = np.concatenate(([t[0]], 0.5 * (t[1:] + t[:-1]), [t[0] + period]))
    dt = np.diff(mid)  # the time each sample stands for; the last carries the wrap to the next cycle
    edges = np.diff(np.concatenate(([0], above.astype(np.int8), [0])))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    csum = np.concatenate(([0.0], np.cumsum(dt)))
    runs = csum[stops] - csum[starts]
    if above[0] and above[-1] and len(runs) > 1:  # the last run continues into the first
        runs = np.concatenate(([runs[0] + runs[-1]], runs[1:-1]))
    return float(runs.max())


def required_rating(rating: float, required_life: float, life: float, exponent: float) -> float:
    """The dynamic load rating [N] that gives ``required_life`` where ``rating`` gives ``life``:
    C_req = C (L_req / L)^(1/p), p = 3 for balls, 10/3 for rollers.

    Source: ISO 281 / ISO 14728-1, L10 = (C / P)^p; THK LM Guide, "Calculating the Nominal Life".

    >>> round(required_rating(10000.0, 8000.0, 1000.0, 3.0))
    20000
    """
    return rating * (required_life / life) ** (1.0 / exponent)


def brake_holding_torque(static_torque: float, factor: float = BRAKE_SERVICE_FACTOR) -> float:
    """The holding torque [N m] a brake must have for a static torque [N m] at its shaft: T_H = K T.

    Source: Machine Design, "Mechatronics Q & A: Hold It Steady" (21 Nov 2007): T_H = (T / GR) K with a
    service factor K of 1.5 to 3 (``BRAKE_SERVICE_FACTOR``)."""
    return abs(static_torque) * factor


def code_choices(code: str, known: dict[int, dict[str, Any]] | None = None) -> list[dict[str, Any]]:
    """The positions of ``code`` still to be chosen (``PLACEHOLDER``), 1-based, with their meaning and
    options where ``known`` (by position) states them."""
    known = known or {}
    out = []
    for m in PLACEHOLDER.finditer(code):
        if _is_placeholder(code, m.start()):
            said = known.get(m.start() + 1, {})
            out.append({"position": m.start() + 1, "meaning": said.get("meaning", "not stated in the catalog"),
                        "options": said.get("options")})
    return out


def _is_placeholder(code: str, k: int) -> bool:
    """A lower-case ``x`` counts only in a code written otherwise without lower-case letters (``6SL312x``),
    so ``i`` ratios and lower-case words stay codes; the other marks always count."""
    if code[k] != "x":
        return True
    return not any(c.islower() and c != "x" for c in code)


def choice_text(c: dict[str, Any]) -> str:
    """A code position to choose in words: its position, meaning and options."""
    opts = f" ({', '.join(c['options'])})" if c.get("options") else " (options not in the catalog)"
    return f"position {c['position']}: {c['meaning']}{opts}"


def resistor_spec(peak_power: float, average_power: float, energy_per_cycle: float, energy_per_event: float | None,
                  r_min: float | None, r_max: float | None, u_on: float | None,
                  bus: float | None) -> tuple[dict[str, Any], list[str]]:
    """A braking resistor's specification and open points: peak and average power [W], energy per cycle and per
    event [J], the resistance window [ohm] (``physics.regen.resistance_window``: the drive's minimum, and
    U_on^2 / P_peak at the switch-on voltage ``u_on`` [V], else at the nominal DC ``bus`` [V], a safe lower
    bound since U_on lies above the bus) and the E12 values in it (``nearest_standard``)."""
    from drivetrain.physics.regen import resistor_max_resistance

    spec: dict[str, Any] = {"energy_per_event_J": energy_per_event, "energy_per_cycle_J": energy_per_cycle,
                            "peak_power_W": peak_power, "average_power_W": average_power}
    open_points: list[str] = []
    if energy_per_event is None:
        open_points.append("energy per braking event not known here: the resistor's pulse rating must take at "
                           "least the largest event (at most the energy per cycle)")
    basis = "U_on^2 / P_peak at the drive's switch-on voltage"
    if r_max is None and u_on is not None:
        r_max = float(resistor_max_resistance(u_on, peak_power))
    if r_max is None:
        if bus is not None:
            r_max = float(resistor_max_resistance(bus, peak_power))
            basis = (f"U_bus^2 / P_peak at the nominal DC bus {bus:.4g} V: the drive's switch-on voltage is not "
                     "known and lies above the bus, so this bound is safe")
            open_points.append("switch-on voltage not known: the maximum is taken at the nominal DC bus (a safe, "
                               "lower bound); the drive's manual gives the exact window")
        else:
            open_points.append("maximum resistance needs the drive's switch-on voltage or the DC bus voltage")
    spec["resistance_min_ohm"], spec["resistance_max_ohm"] = r_min, r_max
    spec["resistance_max_basis"] = basis
    if r_min is None:
        open_points.append("the drive's minimum resistance is not known: check the chosen value against the "
                           "drive's manual")
    if r_max is not None:
        lo = 0.0 if r_min is None else float(r_min)
        if lo > r_max:
            open_points.append(f"empty window: the drive's minimum {lo:.4g} ohm exceeds {r_max:.4g} ohm, no resistor "
                               "on this drive takes the peak power")
        else:
            spec["standard_values_ohm"] = nearest_standard(lo, r_max)
            spec["standard_series"] = "E12 (IEC 60063:2015)"
    return spec, open_points
