r"""Electrical model of a permanent-magnet synchronous (AC servo) motor for sizing.

Conventions (every function below follows them):

* Currents are **phase rms** values [A], as vendors print them ("A rms"). The q-axis current
  amplitude of the amplitude-invariant Park transform is :math:`i_q = \sqrt2\,I`.
* The back-EMF constant is carried inside as ``ke`` = phase-peak volts per mechanical rad/s
  [V s/rad], so the phase back-EMF amplitude is :math:`\hat e = k_e \omega` and the permanent
  magnet flux linkage is :math:`\psi = k_e / p` (p pole pairs). :func:`ke_si` converts the
  datasheet forms (line-to-line or phase, rms or peak, V per 1000 rpm).
* Resistance and inductance are **per phase** of the equivalent star [ohm, H];
  :func:`phase_value` converts a line-to-line (terminal-to-terminal) value, R_ph = R_LL / 2.
* Torque constant :math:`K_t` [N m / A rms]. For a sinusoidal PMSM,
  :math:`T = \tfrac32 p \psi i_q = \tfrac{3}{\sqrt2} k_e I` and
  :math:`K_t = \sqrt3\,K_{e,LL,rms}` with :math:`K_{e,LL,rms}` in V s/rad, i.e.
  :math:`K_t\,[\mathrm{N\,m/A_{rms}}] = 0.01654\,K_e\,[\mathrm{V_{rms,LL}}/\mathrm{krpm}]`
  (:func:`kt_from_ke`; Novanta, "What Motor Torque Constant to Use for Drive Type - Theory
  and Application", sinusoidal torque constant; MathWorks Motor Control Blockset
  ``mcb.getPMSMParameters``, whose BLY171D record has Ke = 3.8 V_pk,LL/krpm and
  FluxPM = 0.0052 Wb for p = 4, the same relation). A datasheet Kt is usually the hot value
  (Siemens 1FT7 k_T at 100 K rise) and a little below sqrt(3) Ke (magnets weaken with heat):
  torque is therefore computed from the datasheet Kt and voltage from Ke.
* Voltage limit: the inverter gives at most :math:`\hat v_{max} = m V_{DC}/\sqrt3` phase peak
  (space-vector modulation, linear range m <= 1; MathWorks ``mcb.getMotorBaseSpeed``:
  v_max = v_dc / sqrt(3)). :func:`dc_bus_voltage` gives the bus of a diode rectifier,
  :math:`\sqrt2 U_{LL}` (Servotronix CDHD2 manual, regeneration: V_NOM = sqrt(2) V_mains).

Steady-state dq model with i_d = 0 (surface PMSM, no field weakening: the catalog has no data
on the drives' field-weakening range), Lq = Ld = L:

.. math::
    v_d = -\omega_e L i_q, \qquad v_q = R i_q + \omega_e \psi, \qquad
    v_d^2 + v_q^2 \le \hat v_{max}^2, \qquad \omega_e = p\,\omega

Per-motor parameters are scalars or 1-D arrays (M,); ``omega`` is (S,) shared or (M, S);
curve functions return (M, S). Speeds are magnitudes [rad/s].
"""

from __future__ import annotations

from typing import Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

SQRT2: Final = float(np.sqrt(2.0))
SQRT3: Final = float(np.sqrt(3.0))
KRPM: Final = 1000.0 * 2.0 * np.pi / 60.0
"""[rad/s] one thousand revolutions per minute."""

KE_BASES: Final = ("ll_rms", "ll_peak", "phase_rms", "phase_peak")
"""How a datasheet states Ke: line-to-line or phase (line-to-neutral), rms or peak."""


def _col(value: ArrayLike) -> FloatArray:
    return np.asarray(value, dtype=float).reshape(-1, 1)


def _speeds(omega: ArrayLike) -> FloatArray:
    w = np.abs(np.asarray(omega, dtype=float))
    return w.reshape(1, -1) if w.ndim <= 1 else w


# ------------------------------------------------------------------------------- constants


def ke_si(value: ArrayLike, basis: str, per_krpm: bool = True) -> FloatArray:
    r"""Back-EMF constant as phase-peak volts per mechanical rad/s [V s/rad].

    .. math::
        k_e = K_e \cdot c_{basis} / (1000 \cdot 2\pi/60), \quad
        c = \{ll\_rms: \sqrt2/\sqrt3,\ ll\_peak: 1/\sqrt3,\ phase\_rms: \sqrt2,\ phase\_peak: 1\}

    Args:
        value: K_e as printed [V per 1000 rpm] (or [V s/rad] with ``per_krpm`` False).
        basis: one of :data:`KE_BASES`.
        per_krpm: True when ``value`` is per 1000 rpm.

    Source: sinusoidal three-phase quantities: line-to-line amplitude = sqrt(3) x phase
    amplitude, rms = amplitude / sqrt(2). Check: MathWorks Motor Control Blockset, BLY171D record,
    Ke = 3.8 V_pk,LL/krpm, p = 4 gives psi = 0.0052 Wb as the blockset prints (FluxPM).

    >>> round(float(ke_si(3.8, "ll_peak")) / 4, 5)
    0.00524
    """
    factors = {"ll_rms": SQRT2 / SQRT3, "ll_peak": 1.0 / SQRT3, "phase_rms": SQRT2, "phase_peak": 1.0}
    if basis not in factors:
        raise ValueError(f"basis must be one of {KE_BASES}, got {basis!r}")
    scale = 1.0 / KRPM if per_krpm else 1.0
    return np.asarray(value, dtype=float) * factors[basis] * scale


def ke_line_rms(ke: ArrayLike) -> FloatArray:
    """Line-to-line rms back-EMF constant [V s/rad] from the phase-peak ``ke`` [V s/rad] (x sqrt(3)/sqrt(2))."""
    return np.asarray(ke, dtype=float) * SQRT3 / SQRT2


def kt_from_ke(ke: ArrayLike) -> FloatArray:
    r"""Ideal torque constant [N m / A rms] of a sinusoidal PMSM from the phase-peak ``ke`` [V s/rad].

    .. math:: K_t = \tfrac{3}{\sqrt2} k_e = \sqrt3\,K_{e,LL,rms}

    Source: T = 3/2 p psi i_q with i_q = sqrt(2) I and k_e = p psi (power balance
    T omega = 3 E_rms I); Novanta, "What Motor Torque Constant to Use for Drive Type"
    (sinusoidal torque constant). Siemens 1FT7044-5AK7: k_E = 57 V/krpm gives 0.943 N m/A
    against the printed hot k_T = 0.88 (Configuration Manual 01/2009, Table 4-8, p. 90).

    >>> round(float(kt_from_ke(ke_si(57.0, "ll_rms"))), 3)
    0.943
    """
    return 3.0 / SQRT2 * np.asarray(ke, dtype=float)


def phase_value(value: ArrayLike, basis: str) -> FloatArray:
    """Per-phase (star-equivalent) resistance [ohm] or inductance [H] from a datasheet value.

    ``basis``: ``"phase"`` (as printed) or ``"line_to_line"`` (terminal to terminal: twice the
    phase value in star, so R_ph = R_LL / 2; the same holds for the synchronous inductance of
    a balanced machine measured between two terminals).

    Derivation: series connection of two star phases between two terminals.
    """
    if basis == "phase":
        return np.asarray(value, dtype=float)
    if basis == "line_to_line":
        return np.asarray(value, dtype=float) / 2.0
    raise ValueError(f"basis must be 'phase' or 'line_to_line', got {basis!r}")


def dc_bus_voltage(supply_voltage: ArrayLike) -> FloatArray:
    r"""DC-bus voltage [V] of a diode-rectified three-phase (or single-phase) supply: :math:`\sqrt2 U`.

    ``supply_voltage``: line-to-line rms [V]. Source: Servotronix CDHD2 manual, regeneration
    section: V_NOM = sqrt(2) V_mains (the no-load peak of the rectified mains).

    >>> round(float(dc_bus_voltage(400.0)), 1)
    565.7
    """
    return SQRT2 * np.asarray(supply_voltage, dtype=float)


def max_phase_voltage(dc_bus: ArrayLike, modulation: float = 1.0) -> FloatArray:
    r"""Largest phase-voltage amplitude [V] the inverter gives: :math:`m V_{DC}/\sqrt3`.

    Source: space-vector PWM, linear range (m <= 1); MathWorks Motor Control Blockset,
    ``mcb.getMotorBaseSpeed``: v_max = v_dc / sqrt(3).
    """
    return modulation * np.asarray(dc_bus, dtype=float) / SQRT3


# ------------------------------------------------------------------------- current <-> torque


class Saturation(NamedTuple):
    """Where the datasheet gives it: Kt falls linearly from the rated point to the peak point."""

    rated_torque: FloatArray
    peak_torque: FloatArray
    peak_current: FloatArray


def _kt_line(
    kt: ArrayLike, sat: Saturation | None
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    k = np.asarray(kt, dtype=float)
    if sat is None:
        nan = np.full_like(k, np.nan)
        return k, nan, nan, nan, np.zeros_like(k, dtype=bool)
    t_n = np.asarray(sat.rated_torque, dtype=float)
    t_p = np.asarray(sat.peak_torque, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        k_p = t_p / np.asarray(sat.peak_current, dtype=float)
        beta = (k_p - k) / (t_p - t_n)
    has = np.isfinite(beta) & (t_p > t_n) & (k_p > 0)
    return k, t_n, t_p, np.where(has, beta, 0.0), has


def current_from_torque(torque: ArrayLike, kt: ArrayLike, saturation: Saturation | None = None) -> FloatArray:
    r"""Phase current [A rms] for a torque [N m]: :math:`I = T / K_t(T)`, sign of the torque kept.

    .. math::
        K_t(T) = \begin{cases} K_t & |T| \le T_N \\
        K_t + (K_{t,max} - K_t)\frac{|T| - T_N}{T_{max} - T_N} & T_N < |T| \le T_{max} \\
        K_{t,max} & |T| > T_{max} \end{cases}, \qquad K_{t,max} = T_{max}/I_{max}

    Without ``saturation`` (or where one of its values is NaN) :math:`I = T/K_t`. At
    :math:`T_{max}` the current is exactly the datasheet :math:`I_{max}`.

    Args:
        torque: motor torque [N m], any shape broadcasting with the parameters.
        kt: datasheet torque constant [N m / A rms].
        saturation: rated torque T_N, peak torque T_max [N m] and the current at peak torque
            I_max [A rms], as the datasheet prints them.

    Source: I = T/Kt (definition of the torque constant, Siemens 1FT7 Configuration Manual
    Appendix A.1: k_T = M_0 / I_0); the linear Kt drop between the rated and the peak point is
    the simplest curve through both datasheet points (Yaskawa Sigma-7 tables: Kt I_max / T_max
    is 1.03-1.23, i.e. Kt falls at peak current). Between the printed points it is an
    interpolation, not a vendor curve.

    Siemens 1FT7044-5AK7: 23 N m at 30 A (k_T 0.88):

    >>> s = Saturation(np.array(2.0), np.array(23.0), np.array(30.0))
    >>> round(float(current_from_torque(23.0, 0.88, s)), 6)
    30.0
    """
    t = np.asarray(torque, dtype=float)
    k, t_n, t_p, beta, has = _kt_line(kt, saturation)
    mag = np.abs(t)
    over = has & (mag > t_n)
    k_eff = np.where(over, k + beta * (np.minimum(mag, np.where(has, t_p, 0.0)) - np.where(has, t_n, 0.0)), k)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(t / k_eff, dtype=float)


def torque_from_current(current: ArrayLike, kt: ArrayLike, saturation: Saturation | None = None) -> FloatArray:
    r"""Torque [N m] at a phase current [A rms]: the inverse of :func:`current_from_torque`.

    With :math:`K_t(T) = \alpha + \beta T` between the rated and the peak point,
    :math:`I = T/(\alpha + \beta T)` gives :math:`T = \alpha I / (1 - \beta I)`.

    Source: as :func:`current_from_torque`.

    >>> s = Saturation(np.array(2.0), np.array(23.0), np.array(30.0))
    >>> round(float(torque_from_current(30.0, 0.88, s)), 6)
    23.0
    """
    i = np.asarray(current, dtype=float)
    k, t_n, t_p, beta, has = _kt_line(kt, saturation)
    mag = np.abs(i)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        i_n = np.where(has, t_n / k, np.inf)
        i_p = np.where(has, t_p / (k + beta * (t_p - t_n)), np.inf)
        alpha = k - beta * t_n
        mid = alpha * mag / (1.0 - beta * mag)
        high = mag * np.where(has, t_p / i_p, k)
    out = np.where(mag <= i_n, k * mag, np.where(mag <= i_p, mid, high))
    return np.asarray(np.sign(i) * out, dtype=float)


def torque_constant(kt: float | None, ke: float | None) -> float | None:
    """The torque constant K_t [N m / A rms] a current is computed with: the datasheet ``kt`` where
    given, else the ideal one from the phase-peak ``ke`` [V s/rad] (:func:`kt_from_ke`); None when
    neither is known (no current can then be computed).

    >>> torque_constant(0.88, 0.5), round(torque_constant(None, 0.5), 4), torque_constant(None, None)
    (0.88, 1.0607, None)
    """
    if kt is not None:
        return kt
    return None if ke is None else float(kt_from_ke(ke))


def saturation(rated_torque: float, peak_torque: float, peak_current: float | None) -> Saturation | None:
    """The datasheet's rated torque, peak torque [N m] and current at peak torque [A rms] as a
    ``Saturation``, or None where the current at peak torque is not given (K_t then constant)."""
    if peak_current is None:
        return None
    return Saturation(np.array(rated_torque), np.array(peak_torque), np.array(peak_current))


def phase_current(torque: ArrayLike, kt: float, sat: Saturation | None = None) -> FloatArray:
    """Magnitude of the phase current [A rms] over a torque series [N m]: :math:`|I| = |T / K_t(T)|`.

    ``kt`` [N m / A rms] (see :func:`torque_constant`), falling between the datasheet's rated and
    peak points where ``sat`` (see :func:`saturation`) is given. Source: as :func:`current_from_torque`.

    Siemens 1FT7044-5AK7: 23 N m at 30 A (k_T 0.88, rated 2 N m):

    >>> [round(float(i), 6) for i in phase_current(np.array([-23.0, 1.76]), 0.88, saturation(2.0, 23.0, 30.0))]
    [30.0, 2.0]
    """
    return np.abs(current_from_torque(torque, kt, sat))


# ---------------------------------------------------------------------------- voltage limit


def voltage_limited_current(
    omega: ArrayLike,
    ke: ArrayLike,
    r_phase: ArrayLike,
    l_phase: ArrayLike,
    pole_pairs: ArrayLike,
    v_max: ArrayLike,
    generating: bool = False,
) -> FloatArray:
    r"""Largest q-axis current [A rms] the voltage allows at speed ``omega`` (i_d = 0), shape (M, S).

    Solves :math:`(\omega_e L i)^2 + (s R i + \omega_e \psi)^2 = \hat v_{max}^2` for the
    current amplitude i >= 0, s = +1 motoring, s = -1 generating (braking: the resistive drop
    opposes the EMF):

    .. math::
        i = \frac{-s R \omega_e\psi + \sqrt{\hat v^2 (R^2 + \omega_e^2L^2) - \omega_e^4 L^2 \psi^2}}
                 {R^2 + \omega_e^2 L^2}, \qquad I = i/\sqrt2

    0 where no positive root exists (above the no-load speed when motoring); +inf at standstill
    without resistance.

    Args:
        omega: mechanical speed [rad/s], (S,) or (M, S).
        ke: phase-peak back-EMF constant [V s/rad] (:func:`ke_si`), per motor.
        r_phase: phase resistance [ohm]. l_phase: phase (synchronous) inductance [H].
        pole_pairs: p [-]. v_max: phase-voltage amplitude limit [V] (:func:`max_phase_voltage`).
        generating: the braking quadrant.

    Source: steady-state dq voltage equations of a surface PMSM (MathWorks Motor Control
    Blockset, ``mcb.getMotorBaseSpeed``, "actual" voltage equations), with i_d = 0.
    """
    w = _speeds(omega)
    ke_, r, ll, p, v = (_col(x) for x in (ke, r_phase, l_phase, pole_pairs, v_max))
    s = -1.0 if generating else 1.0
    we = p * w
    psi = ke_ / p
    a = r**2 + (we * ll) ** 2
    disc = v**2 * a - we**4 * ll**2 * psi**2
    with np.errstate(divide="ignore", invalid="ignore"):
        root = (-s * r * we * psi + np.sqrt(np.maximum(disc, 0.0))) / a
    root = np.where(disc < 0.0, 0.0, np.maximum(root, 0.0))
    root = np.where(a == 0.0, np.inf, root)
    return np.asarray(root / SQRT2, dtype=float)


class TorqueSpeed(NamedTuple):
    """Voltage- and current-limited torque [N m] at speed, (M, S): continuous and peak."""

    continuous: FloatArray
    peak: FloatArray


def torque_speed_curve(
    omega: ArrayLike,
    kt: ArrayLike,
    ke: ArrayLike,
    r_phase: ArrayLike,
    l_phase: ArrayLike,
    pole_pairs: ArrayLike,
    dc_bus: ArrayLike,
    continuous_current: ArrayLike,
    peak_current: ArrayLike,
    saturation: Saturation | None = None,
    modulation: float = 1.0,
    generating: bool = False,
) -> TorqueSpeed:
    r"""Torque–speed curves [N m] of M motors at the supply's bus voltage, shape (M, S).

    .. math::
        T_{c}(\omega) = T\big(\min(I_{c}, I_v(\omega))\big), \qquad
        T_{p}(\omega) = T\big(\min(I_{p}, I_v(\omega))\big)

    with :math:`I_v` of :func:`voltage_limited_current` at
    :math:`\hat v_{max} = m V_{DC}/\sqrt3`, and T(I) of :func:`torque_from_current` (datasheet
    Kt with its saturation).

    Args:
        omega: speeds [rad/s]. kt: [N m / A rms]. ke: phase-peak [V s/rad]. r_phase [ohm],
            l_phase [H], pole_pairs [-]: per motor.
        dc_bus: DC-bus voltage [V] (:func:`dc_bus_voltage` of the supply, or the drive's).
        continuous_current, peak_current: current limits [A rms] (the smaller of the motor's and
            the drive's continuous and peak currents).
        saturation: the datasheet peak point for Kt (:class:`Saturation`).
        modulation: m <= 1 (linear SVPWM range). generating: braking quadrant.

    The continuous curve is the current-limited one; it leaves out the speed-dependent iron
    losses that make a vendor's S1 curve droop with speed (no data for them in the catalog).

    Source: :func:`voltage_limited_current` (MathWorks ``mcb.getMotorBaseSpeed`` dq model)
    and :func:`torque_from_current`.
    """
    v = max_phase_voltage(dc_bus, modulation)
    i_v = voltage_limited_current(omega, ke, r_phase, l_phase, pole_pairs, v, generating)
    kt_c = _col(kt)
    sat = None
    if saturation is not None:
        sat = Saturation(*(_col(x) for x in saturation))
    i_c = np.minimum(_col(continuous_current), i_v)
    i_p = np.minimum(_col(peak_current), i_v)
    return TorqueSpeed(torque_from_current(i_c, kt_c, sat), torque_from_current(i_p, kt_c, sat))


def base_speed(
    ke: ArrayLike,
    r_phase: ArrayLike,
    l_phase: ArrayLike,
    pole_pairs: ArrayLike,
    dc_bus: ArrayLike,
    current: ArrayLike,
    method: str = "dq",
    modulation: float = 1.0,
) -> FloatArray:
    r"""Mechanical speed [rad/s] at which the voltage limit is reached at ``current`` [A rms], i_d = 0.

    ``method="dq"``: the steady-state dq equations solved exactly,
    :math:`(\omega_e L i_q)^2 + (R i_q + \omega_e\psi)^2 = \hat v_{max}^2`.

    ``method="resistive_drop"``: MathWorks' approximate equations, the resistive drop taken off
    the voltage arithmetically: :math:`\omega_e = (\hat v_{max} - R i_q)/\sqrt{(L i_q)^2 + \psi^2}`.

    Source: MathWorks Motor Control Blockset, ``mcb.getMotorBaseSpeed`` (approximate and actual
    voltage equations); i_q = sqrt(2) I.
    """
    ke_, r, ll, p = (np.asarray(x, dtype=float) for x in (ke, r_phase, l_phase, pole_pairs))
    v = max_phase_voltage(dc_bus, modulation)
    iq = SQRT2 * np.asarray(current, dtype=float)
    psi = ke_ / p
    if method == "resistive_drop":
        we = (v - r * iq) / np.sqrt((ll * iq) ** 2 + psi**2)
    elif method == "dq":
        a = (ll * iq) ** 2 + psi**2
        b = 2.0 * r * iq * psi
        c = (r * iq) ** 2 - v**2
        we = (-b + np.sqrt(b**2 - 4.0 * a * c)) / (2.0 * a)
    else:
        raise ValueError(f"method must be 'dq' or 'resistive_drop', got {method!r}")
    return np.asarray(np.maximum(we, 0.0) / p, dtype=float)


def no_load_speed(ke: ArrayLike, dc_bus: ArrayLike, modulation: float = 1.0) -> FloatArray:
    r"""Speed [rad/s] where the back-EMF amplitude reaches the voltage limit: :math:`\hat v_{max}/k_e`.

    Source: v_q = omega_e psi at zero current (the dq equations of :func:`voltage_limited_current`).
    """
    return np.asarray(max_phase_voltage(dc_bus, modulation) / np.asarray(ke, dtype=float), dtype=float)


def terminal_voltage(
    omega: ArrayLike, current: ArrayLike, ke: ArrayLike, r_phase: ArrayLike, l_phase: ArrayLike, pole_pairs: ArrayLike
) -> FloatArray:
    r"""Phase-voltage amplitude [V] the motor needs at speed ``omega`` [rad/s] and current [A rms], i_d = 0.

    .. math:: \hat v = \sqrt{(\omega_e L i_q)^2 + (R i_q + \omega_e \psi)^2}, \quad i_q = \sqrt2 I

    A negative current is braking. Source: steady-state dq equations (as above).
    """
    w = np.asarray(omega, dtype=float)
    p = np.asarray(pole_pairs, dtype=float)
    iq = SQRT2 * np.asarray(current, dtype=float)
    we = p * w
    psi = np.asarray(ke, dtype=float) / p
    return np.asarray(np.hypot(we * np.asarray(l_phase, dtype=float) * iq,
                               np.asarray(r_phase, dtype=float) * iq + we * psi), dtype=float)
