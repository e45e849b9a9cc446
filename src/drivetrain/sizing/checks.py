"""Checks of a motor (and gearbox) against a duty cycle, vectorised over candidate motors.

Each check has a required and an available value, a margin (available / required - 1: how
much is spare, negative = by how much it fails) and ok. Required values carry the user's
margins (``motor.margins``). The motor's speed-torque envelope comes from ``envelope``; where
it was derived from ratings rather than a datasheet curve the check is marked approximate.
"""

from __future__ import annotations

import math
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
        """JSON form (docs/conventions.md, The JSON result: name, required, available, margin, ok)."""
        return asdict(self)


def margin_of(required: Array | float, available: Array | float) -> Array:
    """available / required - 1 [-]; +inf when nothing is required."""
    req = np.asarray(required, dtype=float)
    avail = np.asarray(available, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(req > 0.0, avail / np.where(req > 0.0, req, 1.0) - 1.0, np.inf)
    return np.asarray(out, dtype=float)


def combine_margins(*margins: Array) -> Array:
    """One margin from several sub-margins: the smallest known shortfall if any is negative, else NaN
    where any is unknown, else the smallest [-]."""
    stack = np.stack([np.asarray(m, dtype=float) for m in np.broadcast_arrays(*margins)])
    gap = np.any(np.isnan(stack), axis=0)
    low = np.min(np.where(np.isnan(stack), np.inf, stack), axis=0)
    return np.asarray(np.where((low < 0.0) | ~gap, low, np.nan), dtype=float)


def mechanical_fit(shaft: Array, flange: Array, pilot: Array, bore_max: Array, bore_min: Array,
                   input_flange: Array, input_pilot: Array, tolerance: float = 0.5e-3) -> Array:
    """Margin of a motor's assembly onto a gearbox input [-] (NaN: cannot be judged), arrays of lengths [m].

    The motor shaft must go into the input's clamping hub: ``shaft <= bore_max`` (margin
    bore_max / shaft - 1) and, where the catalog gives the smallest bore the vendor's bushings
    reach, ``shaft >= bore_min`` (shaft / bore_min - 1). Where the catalog names the motor flange
    and pilot the input adapter is made for, the motor's must equal them within ``tolerance``
    (mismatch margin -|motor / adapter - 1|). A known shortfall fails the pair; otherwise a
    missing dimension (the shaft, the bore, or the motor's flange or pilot where the adapter's is
    given) leaves the fit unknown (NaN), never silently accepted. Sources: WITTENSTEIN
    engineering glossary, "Clamping hub" and "Bushing" (a bushing adapts a motor shaft smaller than
    the clamping hub; http://wittenstein-us.com/tech-support/engineering-glossary/); Beckhoff
    AG2400 (WITTENSTEIN TP+) data pages, "depending on the clamping hub diameter and selected
    adapter plate" (https://infosys.beckhoff.com/content/1033/ag2400_ba/8995369483.html).

    >>> round(float(mechanical_fit(0.022, 0.13, 0.11, 0.014, np.nan, np.nan, np.nan)), 6)  # 22 mm into 14 mm
    -0.363636
    >>> bool(np.isnan(mechanical_fit(0.014, np.nan, np.nan, np.nan, np.nan, np.nan, np.nan)))  # bore unknown
    True
    """
    shaft, flange, pilot = (np.asarray(x, dtype=float) for x in (shaft, flange, pilot))
    bore_max, bore_min, input_flange, input_pilot = (np.asarray(x, dtype=float)
                                                     for x in (bore_max, bore_min, input_flange, input_pilot))
    with np.errstate(divide="ignore", invalid="ignore"):
        m1 = bore_max / shaft - 1.0
        m2 = np.where(np.isnan(shaft), np.nan, np.where(np.isnan(bore_min), np.inf, shaft / bore_min - 1.0))

        def equal(motor: Array, adapter: Array) -> Array:
            mismatch = np.where(np.abs(motor - adapter) <= tolerance, np.inf, -np.abs(motor / adapter - 1.0))
            return np.where(np.isnan(adapter), np.inf, np.where(np.isnan(motor), np.nan, mismatch))

        return combine_margins(m1, m2, equal(flange, input_flange), equal(pilot, input_pilot))


CYCLIC_LIMIT_PER_HOUR = 1000.0
"""Cycles per hour up to which a gearbox's T2B holds without a shock factor (WITTENSTEIN: "T2B ...
< 1000/h cycles; for > 1000/h cycles, the impact factor must be taken into account")."""

GEARBOX_CHECKS = ("gearbox_peak_torque", "gearbox_rated_torque", "gearbox_emergency_stop_torque",
                  "gearbox_max_input_speed", "gearbox_mean_input_speed")
"""The gearbox rating checks, in the order of the selection's check arrays."""


def shock_factor(period: float, given: float | None) -> float:
    """The factor on the cycle's peak output torque for the T2B check [-]: 1 up to 1000 cycles/h,
    above that the vendor's shock factor fs the user read from the vendor's chart (``given``), NaN
    when it is needed and not given (the T2B check is then unknown). ``period`` [s] is one cycle.

    >>> shock_factor(4.0, None), shock_factor(2.0, 1.4)
    (1.0, 1.4)
    """
    if 3600.0 / period <= CYCLIC_LIMIT_PER_HOUR:
        return 1.0
    return math.nan if given is None else float(given)


def gearbox_ratings(out_peak: Array | float, out_cubic: Array | float, in_peak_speed: Array | float,
                    in_mean_speed: Array | float, estop_torque: Array | float, *, t2b: Array | float,
                    t2n: Array | float, t2not: Array | float, n1max: Array | float, n1n: Array | float,
                    torque_margin: float = 1.0, speed_margin: float = 1.0,
                    shock: float = 1.0) -> dict[str, tuple[Array, Array, Array]]:
    """Every rating of a gearbox against the cycle: name -> (required, available, margin) arrays.

    Torques [N m] at the output, speeds [rad/s] at the input; a rating NaN is unknown (margin NaN).

    * ``gearbox_peak_torque``: the cycle's peak output torque x shock factor x torque margin
      <= T2B, the max acceleration torque in cyclic operation (the torque at the output is what
      the load side needs, so the rotor's and the gearbox's own acceleration torque, the
      lecture's k-split, never passes it);
    * ``gearbox_rated_torque``: the speed-weighted cubic-mean output torque x torque margin <= T2N;
    * ``gearbox_emergency_stop_torque``: the torque that passes when the motor gives its peak
      (``estop_torque``: lecture's split (1 - k)(T_M - T_L) + T_L times i eta) <= T2NOT, the
      emergency-stop torque allowed about 1000 times in the gearbox's life; never the cyclic peak;
    * ``gearbox_max_input_speed``: the cycle's peak input speed x speed margin <= n1max;
    * ``gearbox_mean_input_speed``: the time-mean input speed <= n1N, the thermal nominal speed.

    Sources: WITTENSTEIN engineering glossary (T2B: limiting in cyclic operation, at most 1000
    cycles/h without the impact factor); Beckhoff AG2400 TP+ data (T2B "maximum 1000 cycles per
    hour", T2Em.stop "possible 1000 times during the service life", n1N nominal and n1Max maximum
    input speed; https://infosys.beckhoff.com/content/1033/ag2400_ba/8995369483.html); cubic mean:
    drivetrain.physics.averages.cubic_mean.
    """
    def rated(required: Array | float, available: Array | float) -> tuple[Array, Array, Array]:
        req, av = np.broadcast_arrays(np.asarray(required, dtype=float), np.asarray(available, dtype=float))
        mar = np.where(np.isnan(av), np.nan, margin_of(req, av))  # an unknown rating: unknown, whatever is required
        return np.asarray(req, dtype=float), np.asarray(av, dtype=float), np.asarray(mar, dtype=float)

    peak = np.asarray(out_peak, dtype=float) * torque_margin * (1.0 if math.isnan(shock) else shock)
    out = {
        "gearbox_peak_torque": rated(peak, t2b),
        "gearbox_rated_torque": rated(np.asarray(out_cubic, dtype=float) * torque_margin, t2n),
        "gearbox_emergency_stop_torque": rated(estop_torque, t2not),
        "gearbox_max_input_speed": rated(np.asarray(in_peak_speed, dtype=float) * speed_margin, n1max),
        "gearbox_mean_input_speed": rated(in_mean_speed, n1n),
    }
    if math.isnan(shock):
        req, av, _ = out["gearbox_peak_torque"]
        out["gearbox_peak_torque"] = (req, av, np.full_like(req, np.nan))
    return out


def running_torque(external: NDArray[np.float64]) -> float:
    """The load's running torque: the median of |T_ext| over the samples [N m] (0 for no samples).

    ``np.median``'s value (the middle sample, or the mean of the two middle ones), computed without
    it: its NaN check imports ``numpy.ma``, a tenth of a sizing's start-up.
    """
    n = external.size
    if n == 0:
        return 0.0
    s = np.sort(np.abs(external.ravel()))
    if np.isnan(s[-1]):
        return math.nan
    mid = n // 2
    return float(s[mid]) if n % 2 else float((s[mid - 1] + s[mid]) / 2.0)

