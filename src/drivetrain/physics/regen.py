r"""Regeneration: the energy a braking axis returns to the drive's DC bus, and the braking resistor.

Energy path of one deceleration or lowering event (power signs: positive = motoring):

* shaft power :math:`p_m = T\omega` [W] at the motor shaft, rotor included. The duty cycle's
  torque already carries the four-quadrant losses of every mechanism and transmission stage
  (docs/conventions.md: a load driving back passes :math:`T_{out}\eta_{back}/i`), so those losses are
  already out of :math:`p_m` and are not taken off twice;
* winding copper loss :math:`p_{Cu} = 3 I^2 R_{ph}` [W], I the phase rms current, R_ph the
  per-phase resistance of the star equivalent (:mod:`drivetrain.physics.motor_electrical`);
* electrical power at the motor terminals :math:`p_e = p_m + p_{Cu}`; where
  :math:`p_e < 0` the motor feeds the bus with :math:`-p_e`. Inverter losses are left out
  (they would only lower the regenerated energy: the answer errs on the resistor's safe side);
* an *event* is a run of consecutive samples with :math:`p_e < 0` (found from the sign,
  vectorised); its bus energy :math:`E = \sum w_k (-p_{e,k})` with the cycle's quadrature
  weights (the same sum as the duty cycle's ``regen_energy_J``, so both agree to rounding);
* the bus capacitors take up to :math:`E_C = \tfrac12 C (U_{max}^2 - U_{nom}^2)` per event
  (or the drive's published absorbable energy); the bus is assumed back at U_nom when each
  event starts (the motoring between events draws it down). The rest goes to the braking
  resistor: :math:`E_R = \max(0, E - E_C)`, at the event's power once the capacitors are full.

Sources: Delta ASDA-B2 user manual (Revision May 2018), chapter 2 "Installation", selection of
the regenerative resistor, pp. 2-13 to 2-15 (energy method, E_o = J n^2 / 182, and the
external-load example);
TECO JSDAP manual p. 5-73 (E_R = E_M - (E_L + E_C)); Servotronix CDHD2 manual (E_BUS =
1/2 C (V_M^2 - V_NOM^2)); Omron 1S manual §4-4 (winding loss lowers the regenerated energy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

DELTA_ROTOR_ENERGY_DIVISOR = 182.0
"""Delta's rounded 1 / (0.5 (2 pi / 60)^2) = 182.38 [rpm^2 s^2 / rad^2]: E_o = J n^2 / 182."""


def kinetic_energy(inertia: ArrayLike, omega: ArrayLike) -> FloatArray:
    r"""Rotational kinetic energy [J]: :math:`E = \tfrac12 J \omega^2` (J [kg m^2], omega [rad/s])."""
    return np.asarray(0.5 * np.asarray(inertia, dtype=float) * np.asarray(omega, dtype=float) ** 2)


def rotor_energy_delta(inertia: ArrayLike, speed_rpm: ArrayLike) -> FloatArray:
    r"""Delta's rotor energy from speed n [rpm] to stop [J]: :math:`E_o = J n^2 / 182`.

    J [kg m^2]. The exact kinetic energy is J n^2 / 182.38; Delta rounds the divisor.

    Source: Delta ASDA-B2 user manual (May 2018), chapter 2, p. 2-13, table "Regenerative power
    from empty load 3000 r/min to stop": ECMA-C△0604, J = 0.277e-4 kg m^2 -> 1.37 J.

    >>> round(float(rotor_energy_delta(0.277e-4, 3000.0)), 2)
    1.37
    """
    return np.asarray(np.asarray(inertia, dtype=float) * np.asarray(speed_rpm, dtype=float) ** 2
                      / DELTA_ROTOR_ENERGY_DIVISOR)


def capacitor_energy(capacitance: ArrayLike, u_max: ArrayLike, u_nom: ArrayLike) -> FloatArray:
    r"""Energy [J] the DC-bus capacitors absorb from U_nom up to U_max: :math:`\tfrac12 C (U_{max}^2 - U_{nom}^2)`.

    C [F], voltages [V]. Source: Servotronix CDHD2 manual, regeneration: E_BUS =
    1/2 C (V_M^2 - V_NOM^2), V_NOM = sqrt(2) V_mains.

    >>> round(float(capacitor_energy(1e-3, 390.0, 311.0)), 2)
    27.69
    """
    c = np.asarray(capacitance, dtype=float)
    return np.asarray(0.5 * c * (np.asarray(u_max, dtype=float) ** 2 - np.asarray(u_nom, dtype=float) ** 2))


def copper_loss(current: ArrayLike, r_phase: ArrayLike) -> FloatArray:
    r"""Winding copper loss [W] of a three-phase motor: :math:`P_{Cu} = 3 I^2 R_{ph}`.

    I phase rms current [A], R_ph per-phase (star) resistance [ohm] (a line-to-line value
    halves first: :func:`drivetrain.physics.motor_electrical.phase_value`).

    Derivation: Joule loss of three phases carrying rms current I.
    """
    i = np.asarray(current, dtype=float)
    return np.asarray(3.0 * i**2 * np.asarray(r_phase, dtype=float))


def resistor_max_resistance(u_on: ArrayLike, peak_power: ArrayLike) -> FloatArray:
    r"""Largest braking resistance [ohm] taking the peak power at the switch-on voltage: :math:`U_{on}^2/P_{peak}`.

    Derivation: P = U^2 / R of the resistor across the bus when the brake chopper conducts.
    +inf when no power must be absorbed.
    """
    p = np.asarray(peak_power, dtype=float)
    with np.errstate(divide="ignore"):
        return np.asarray(np.where(p > 0, np.asarray(u_on, dtype=float) ** 2 / np.where(p > 0, p, 1.0), np.inf))


def resistor_rating(average_power: ArrayLike, utilisation: ArrayLike) -> FloatArray:
    r"""Resistor nameplate power [W] for an average regenerative power: :math:`P_{avg}/u`.

    ``utilisation`` u: the vendor's share of the nameplate a resistor may dissipate on
    average (Delta: 0.5, "rated at 50 % of the capacity"; TECO JSDG2S: 0.2).

    Source: Delta ASDA-A user manual, §6-6-3, built-in resistor table footnote *1; the ASDA-B2
    example (2 x (0.7 x 1.27) x (3000 x 2 pi / 60) = 560 W).

    >>> round(float(resistor_rating(0.7 * 1.27 * 3000 * 2 * np.pi / 60, 0.5)))
    559
    """
    return np.asarray(np.asarray(average_power, dtype=float) / np.asarray(utilisation, dtype=float))


@dataclass(frozen=True)
class RegenEvents:
    """Regenerative events of one cycle, each a run of samples feeding the bus (arrays over events, SI)."""

    start: IntArray
    """first sample index of each event"""
    stop: IntArray
    """one past the last sample index"""
    t_start: FloatArray
    """[s]"""
    t_stop: FloatArray
    """[s]"""
    shaft_energy: FloatArray
    """[J] mechanical energy returned at the shaft during the event, sum w max(-p_m, 0)"""
    copper_energy: FloatArray
    """[J] copper loss during the event"""
    bus_energy: FloatArray
    """[J] energy into the DC bus, sum w (-p_e)"""
    capacitor_energy: FloatArray
    """[J] part taken by the bus capacitors"""
    resistor_energy: FloatArray
    """[J] part the braking resistor must dissipate"""
    resistor_peak_power: FloatArray
    """[W] largest bus power while the capacitors are full (0 if they never fill)"""
    peak_power: FloatArray
    """[W] largest bus power of the event"""


@dataclass(frozen=True)
class Regen:
    """Regeneration over one cycle: events and cycle totals (SI)."""

    events: RegenEvents
    period: float
    bus_power: FloatArray
    """[W] per sample, positive into the bus: max(-p_e, 0)"""
    shaft_energy: float
    """[J] mechanical energy returned at the shaft per cycle, sum w max(-p_m, 0) over every sample
    (the duty cycle's ``regen_energy_J`` when p_m is its power); it includes braking that the
    copper loss eats up entirely, which belongs to no event"""

    @property
    def energy(self) -> float:
        """Energy into the bus per cycle [J]."""
        return float(self.events.bus_energy.sum())

    @property
    def capacitor_absorbed(self) -> float:
        """Energy the capacitors take per cycle [J]."""
        return float(self.events.capacitor_energy.sum())

    @property
    def resistor_energy(self) -> float:
        """Energy the braking resistor dissipates per cycle [J]."""
        return float(self.events.resistor_energy.sum())

    @property
    def resistor_peak_power(self) -> float:
        """Largest power the resistor must take [W]."""
        return float(self.events.resistor_peak_power.max(initial=0.0))

    @property
    def resistor_average_power(self) -> float:
        """Resistor energy per cycle / cycle time [W]."""
        return self.resistor_energy / self.period

    @property
    def peak_power(self) -> float:
        """Largest power into the bus [W]."""
        return float(self.events.peak_power.max(initial=0.0))


def trapezoid_weights(t: ArrayLike) -> FloatArray:
    """Trapezoidal quadrature weights [s] of samples at times ``t`` [s] (sum = t[-1] - t[0])."""
    tt = np.asarray(t, dtype=float)
    h = np.diff(tt)
    w = np.zeros_like(tt)
    w[:-1] += h / 2.0
    w[1:] += h / 2.0
    return w


def regen_cycle(
    t: ArrayLike,
    shaft_power: ArrayLike,
    copper_power: ArrayLike | float = 0.0,
    capacitor_energy: float = 0.0,
    weights: ArrayLike | None = None,
    period: float | None = None,
) -> Regen:
    r"""Split one cycle's regeneration into events and send each to the capacitors, then the resistor.

    Args:
        t: sample times [s], ascending (repeated times at phase joints allowed).
        shaft_power: :math:`p_m = T\omega` [W] per sample, rotor included (negative = braking).
        copper_power: :math:`3 I^2 R_{ph}` [W] per sample (:func:`copper_loss`), or 0.
        capacitor_energy: :math:`E_C` [J] the bus absorbs per event (:func:`capacitor_energy`
            or the drive's published value).
        weights: quadrature weights [s] (the duty cycle's); trapezoidal from ``t`` if None.
        period: cycle time [s]; t[-1] - t[0] if None.

    Returns:
        :class:`Regen` with the events and the cycle totals.

    Events are runs of samples with :math:`p_e = p_m + p_{Cu} < 0`, labelled with one cumulative
    sum; per-event sums use ``np.add.reduceat`` (no loop over samples). The resistor's share of
    an event is what remains once the running event energy exceeds E_C.

    Source: module docstring (Delta ASDA-B2 pp. 2-13 to 2-15; TECO JSDAP p. 5-73; Servotronix CDHD2).
    """
    tt = np.asarray(t, dtype=float)
    p_m = np.asarray(shaft_power, dtype=float)
    p_cu = np.broadcast_to(np.asarray(copper_power, dtype=float), p_m.shape)
    w = trapezoid_weights(tt) if weights is None else np.asarray(weights, dtype=float)
    per = float(tt[-1] - tt[0]) if period is None else float(period)
    p_e = p_m + p_cu
    bus = np.maximum(-p_e, 0.0)
    neg = p_e < 0.0
    edges = np.diff(neg.astype(np.int8), prepend=0, append=0)
    start = np.flatnonzero(edges == 1).astype(np.int64)
    stop = np.flatnonzero(edges == -1).astype(np.int64)
    if start.size == 0:
        z = np.zeros(0)
        zi = np.zeros(0, dtype=np.int64)
        return Regen(RegenEvents(zi, zi, z, z, z, z, z, z, z, z, z), per, bus, _returned(w, p_m))
    e_bus_k = w * bus
    e_bus = np.add.reduceat(e_bus_k, start)
    e_shaft = np.add.reduceat(w * np.maximum(-p_m, 0.0) * neg, start)
    e_cu = np.add.reduceat(w * p_cu * neg, start)
    # running energy within each event: global cumulative sum minus its value before the event
    cum = np.cumsum(e_bus_k)
    before = np.where(start > 0, cum[np.maximum(start - 1, 0)], 0.0)
    label = np.cumsum(edges[:-1] == 1) - 1  # event index of each sample (valid where neg)
    running = cum - before[np.clip(label, 0, None)]
    full = neg & (running > capacitor_energy)
    e_cap = np.minimum(e_bus, capacitor_energy)
    e_res = np.maximum(e_bus - capacitor_energy, 0.0)
    peak_res = np.where(e_res > 0.0, _resistor_peak(tt, bus, neg, label, start, capacitor_energy,
                                                    np.maximum.reduceat(np.where(full, bus, 0.0), start)), 0.0)
    peak = np.maximum.reduceat(bus, start)
    events = RegenEvents(start, stop, tt[start], tt[stop - 1], e_shaft, e_cu, e_bus, e_cap, e_res, peak_res, peak)
    return Regen(events, per, bus, _returned(w, p_m))


def _resistor_peak(t: FloatArray, bus: FloatArray, neg: NDArray[np.bool_], label: NDArray[np.int64],
                   start: NDArray[np.int64], e_c: float, sampled: FloatArray) -> FloatArray:
    r"""Largest bus power [W] of each event from the instant its capacitors are full.

    The fill instant :math:`t^*` solves :math:`\int_{t_0}^{t^*} p_{bus}\,dt = E_C` with the bus
    power linear between samples (the trapezoid integral, aligned in time; exact for the linear
    power of a constant-torque ramp). Within its sample interval :math:`[t_k, t_{k+1}]`, with
    :math:`h = t_{k+1} - t_k`, :math:`b_0, b_1` the bus powers and :math:`c = E_C - E(t_k)`:

    .. math:: b_0\tau + \frac{b_1 - b_0}{2h}\tau^2 = c, \quad
              \tau = \frac{2c}{b_0 + \sqrt{b_0^2 + 2 (b_1 - b_0) c / h}}, \quad
              p^* = b_0 + (b_1 - b_0)\,\tau / h

    and the peak is :math:`\max(p^*, \max_{t_k > t^*} p_{bus})`. Taking the first sample past
    the fill instant instead (a sample-based peak) depends on where the samples fall: during a
    braking ramp the power falls, so a coarser sampling reads a lower power than the one at
    :math:`t^*`. An event whose trapezoid integral never exceeds E_C (it does only under the
    caller's weights) keeps the sample-based peak ``sampled``.

    Sources: the order capacitors first, resistor after (E_R = E_M - (E_L + E_C)) is TECO JSDAP
    manual p. 5-73 and Servotronix CDHD2 (module docstring); the root is the quadratic's
    cancellation-free form, Press et al., *Numerical Recipes*, 3rd ed., §5.6, eqs. 5.6.4-5.6.5.
    """
    n = t.size
    c_trap = np.concatenate(([0.0], np.cumsum(0.5 * (bus[:-1] + bus[1:]) * np.diff(t))))
    base = np.where(start > 0, c_trap[np.maximum(start - 1, 0)], 0.0)
    running = c_trap - base[np.clip(label, 0, None)]
    after = neg & (running > e_c)
    k = np.minimum.reduceat(np.where(after, np.arange(n), n), start)
    found = (k < n) & (k > 0)
    k1 = np.where(found, k, 1)
    k0 = k1 - 1
    b0, b1 = bus[k0], bus[k1]
    h = t[k1] - t[k0]
    c = np.clip(e_c - running[k0] * (k0 >= start), 0.0, None)
    h_safe = np.where(h > 0.0, h, 1.0)
    disc = np.sqrt(np.maximum(b0**2 + 2.0 * (b1 - b0) * c / h_safe, 0.0))
    den = b0 + disc
    with np.errstate(over="ignore"):  # a subnormal den gives tau = inf, clipped to the interval's end below
        tau = np.where(den > 0.0, 2.0 * c / np.where(den > 0.0, den, 1.0), 0.0)
    p_star = np.clip(b0 + (b1 - b0) * np.clip(tau / h_safe, 0.0, 1.0), np.minimum(b0, b1), np.maximum(b0, b1))
    later = np.maximum.reduceat(np.where(after, bus, 0.0), start)
    return np.where(found & (h > 0.0), np.maximum(p_star, later), sampled)


def _returned(w: FloatArray, p_m: FloatArray) -> float:
    return float(np.sum(w * np.maximum(-p_m, 0.0)))


def resistance_window(
    peak_power: ArrayLike, u_on: ArrayLike, drive_min_resistance: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    r"""Braking-resistance window [ohm]: :math:`R_{min,drive} \le R \le U_{on}^2 / P_{peak}`.

    The lower bound protects the drive's brake transistor (vendor minimum); the upper bound
    lets the resistor take the peak regenerative power at the chopper's switch-on voltage.
    An empty window (min > max) means no resistor on this drive can take the peak.

    Source: Delta ASDA-A user manual §6-6-3 ("Min. Allowable Resistance"); TECO JSDG2S manual
    §5-6-7 (minimum resistance); P = U^2 / R.
    """
    return np.asarray(drive_min_resistance, dtype=float), resistor_max_resistance(u_on, peak_power)


def builtin_resistor_sufficient(
    average_power: ArrayLike,
    peak_power: ArrayLike,
    builtin_average_power: ArrayLike,
    builtin_resistance: ArrayLike,
    u_on: ArrayLike,
    drive_min_resistance: ArrayLike = np.nan,
) -> NDArray[np.bool_]:
    r"""Whether the drive's built-in resistor takes the cycle: average and peak power, and the
    drive's minimum resistance.

    .. math:: P_{avg} \le P_{avg,builtin} \quad\text{and}\quad
              R_{min,drive} \le R_{builtin} \le U_{on}^2 / P_{peak}

    ``builtin_average_power`` is the vendor's "processable" average regenerative power of the
    built-in resistor [W] (Delta ASDA-A: 50 % of its rating; TECO JSDG2S: 20 %). NaN data
    (no built-in resistor, or unknown) gives False; a NaN ``drive_min_resistance`` (not stated)
    sets no lower bound. A resistor below the drive's minimum overloads its brake transistor
    whatever the cycle, the same window as ``resistance_window``.

    Source: Delta ASDA-A §6-6-3 ("when the regenerative power exceeds the processing capacity
    of the servo drive, install an external regenerative resistor"); TECO JSDG2S §5-6-7.
    """
    avg = np.asarray(average_power, dtype=float)
    ok_avg = avg <= np.asarray(builtin_average_power, dtype=float)
    r_builtin = np.asarray(builtin_resistance, dtype=float)
    ok_peak = r_builtin <= resistor_max_resistance(u_on, peak_power)
    r_min = np.asarray(drive_min_resistance, dtype=float)
    ok_min = np.isnan(r_min) | (r_builtin >= r_min)
    return np.asarray(ok_avg & ok_peak & ok_min)
