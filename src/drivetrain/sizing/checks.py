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


MAX_ADAPTERS = 4
"""Drawn motor adapters kept per gearbox row (the shipped G+ rows draw at most 4)."""


def adapter_arrays(adapters: Any) -> Array:
    """The drawn input adapters of gearbox rows (catalog ``input_adapters``: ``bore/pilot/bolt circle/screw``
    in mm, separated by spaces; ``sq`` before the third number: a square hole pattern of that side)
    as an array (rows, MAX_ADAPTERS, 3): bore, pilot and bolt-circle diameter [m], NaN where a row
    draws fewer (or none). The four holes of a square pattern of side s lie on a circle of diameter
    s sqrt(2), so a square pattern compares with a motor's bolt circle as that circle (NEMA 23:
    47.14 mm square, 66.67 mm circle). Source of the format: catalog/data/SOURCES.md, "G+ drawing
    sheets".

    >>> adapter_arrays(["14/50/70/M4 8/38.1/sq47.14/M4"])[0, :2].round(5).tolist()
    [[0.014, 0.05, 0.07], [0.008, 0.0381, 0.06667]]
    """
    texts = [str(t) for t in adapters]
    out = np.full((len(texts), MAX_ADAPTERS, 3), np.nan)
    for r, text in enumerate(texts):
        for a, item in enumerate(text.split()[:MAX_ADAPTERS]):
            parts = item.split("/")
            if len(parts) < 3:
                continue
            third = parts[2]
            circle = float(third[2:]) * math.sqrt(2.0) if third.startswith("sq") else float(third)
            out[r, a] = (float(parts[0]) * 1e-3, float(parts[1]) * 1e-3, circle * 1e-3)
    return out


def _equal(motor: Array, adapter: Array, tolerance: float) -> Array:
    """A motor dimension against the adapter's: +inf within ``tolerance``, else -|motor / adapter - 1|;
    NaN where either is unknown."""
    mismatch = np.where(np.abs(motor - adapter) <= tolerance, np.inf, -np.abs(motor / adapter - 1.0))
    return np.asarray(np.where(np.isnan(adapter) | np.isnan(motor), np.nan, mismatch), dtype=float)


def adapter_margin(shaft: Array | float, pilot: Array | float, bolt_circle: Array | float, adapters: Array,
                   tolerance: float = 0.5e-3) -> Array:
    """Margin of a motor onto the best of a gearbox's drawn adapters [-] (``adapters`` (..., A, 3): bore,
    pilot, bolt circle [m], NaN-padded): for each adapter the shaft into its bore (bore / shaft - 1),
    the pilot and the bolt circle equal within ``tolerance``; the motor fits when one adapter fits.
    The largest known margin where one passes; else NaN where an adapter cannot be judged (it might
    fit); else the largest (least negative) shortfall; NaN where no adapter is drawn."""
    sh, pi, bc = (np.asarray(x, dtype=float)[..., None] for x in (shaft, pilot, bolt_circle))
    with np.errstate(divide="ignore", invalid="ignore"):
        each = combine_margins(np.where(np.isnan(adapters[..., 0]), np.nan, adapters[..., 0] / sh - 1.0),
                               _equal(pi, adapters[..., 1], tolerance), _equal(bc, adapters[..., 2], tolerance))
    drawn = ~np.isnan(adapters[..., 1])
    each = np.where(drawn, each, -np.inf)  # an adapter not drawn fits nothing
    best = np.max(np.where(np.isnan(each), -np.inf, each), axis=-1)
    gap = np.any(drawn & np.isnan(each), axis=-1)
    return np.asarray(np.where(best >= 0.0, best, np.where(gap | ~np.any(drawn, axis=-1), np.nan, best)),
                      dtype=float)


def mechanical_fit(shaft: Array, flange: Array, pilot: Array, bore_max: Array, bore_min: Array,
                   input_flange: Array, input_pilot: Array, tolerance: float = 0.5e-3,
                   bolt_circle: Array | float = np.nan, adapters: Array | None = None) -> Array:
    """Margin of a motor's assembly onto a gearbox input [-] (NaN: cannot be judged), arrays of lengths [m].

    The motor shaft must go into the input's clamping hub: ``shaft <= bore_max`` (margin
    bore_max / shaft - 1) and, where the catalog gives the smallest bore the vendor's bushings
    reach, ``shaft >= bore_min`` (shaft / bore_min - 1). The motor's flange must match the input
    adapter: where the catalog draws the adapters (``adapters``, :func:`adapter_arrays`), one of
    them must take the motor's shaft, pilot and bolt circle (:func:`adapter_margin`); otherwise the
    adapter's pilot (``input_pilot``) and square flange (``input_flange``) must equal the motor's
    within ``tolerance`` (mismatch margin -|motor / adapter - 1|), and with neither given the
    adapter is not known: the fit is unknown, never taken as the motor's own. A known shortfall
    fails the pair; otherwise a missing dimension (the shaft, the bore, a motor dimension the
    adapter names, the adapter's bolt pattern) leaves the fit unknown (NaN), never silently
    accepted. Sources: WITTENSTEIN engineering glossary, "Clamping hub" and "Bushing" (a bushing
    adapts a motor shaft smaller than the clamping hub;
    http://wittenstein-us.com/tech-support/engineering-glossary/); Beckhoff AG2400 (WITTENSTEIN
    TP+) data pages, "depending on the clamping hub diameter and selected adapter plate"
    (https://infosys.beckhoff.com/content/1033/ag2400_ba/8995369483.html); the drawn adapters of
    the G+ sheets (catalog/data/SOURCES.md).

    >>> round(float(mechanical_fit(0.022, 0.13, 0.11, 0.014, np.nan, np.nan, np.nan)), 6)  # 22 mm into 14 mm
    -0.363636
    >>> bool(np.isnan(mechanical_fit(0.014, np.nan, np.nan, np.nan, np.nan, np.nan, np.nan)))  # bore unknown
    True
    >>> bool(np.isnan(mechanical_fit(0.014, 0.06, 0.05, 0.014, np.nan, np.nan, np.nan)))  # adapter unknown
    True
    """
    shaft, flange, pilot, bc = (np.asarray(x, dtype=float) for x in (shaft, flange, pilot, bolt_circle))
    bore_max, bore_min, input_flange, input_pilot = (np.asarray(x, dtype=float)
                                                     for x in (bore_max, bore_min, input_flange, input_pilot))
    if adapters is None:
        adapters = np.full((*np.broadcast_shapes(bore_max.shape, input_pilot.shape), MAX_ADAPTERS, 3), np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        m1 = bore_max / shaft - 1.0
        m2 = np.where(np.isnan(shaft), np.nan, np.where(np.isnan(bore_min), np.inf, shaft / bore_min - 1.0))
        drawn = np.any(~np.isnan(adapters[..., 1]), axis=-1)
        # no drawn adapter: the adapter's square flange (it names the adapter plate) and pilot where named;
        # the pilot alone does not give the bolt pattern: it can fail the pair, not pass it
        pilot_m = np.where(np.isnan(input_pilot), np.inf, _equal(pilot, input_pilot, tolerance))
        own = np.where(np.isnan(input_flange), np.where(pilot_m < 0.0, pilot_m, np.nan),
                       combine_margins(_equal(flange, input_flange, tolerance), pilot_m))
        m3 = np.where(drawn, adapter_margin(shaft, pilot, bc, adapters, tolerance), own)
        return combine_margins(m1, m2, m3)


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

