r"""Filters on the torque command: the notch (biquad) and the first-order low-pass.

Notch (second-order "biquad", as servo drives implement it):

.. math:: N(s) = \frac{s^2 + 2 d \zeta \omega_n s + \omega_n^2}{s^2 + 2 \zeta \omega_n s + \omega_n^2}

with centre omega_n = 2 pi f_n [rad/s], depth d = |N(j omega_n)| (0 < d < 1) and the -3 dB width
approximately 2 zeta f_n [Hz] for a deep notch. Discretised by the bilinear transform with the
frequency prewarped to the centre, so the discrete notch sits exactly at f_n (Franklin, Powell,
Workman, *Digital Control of Dynamic Systems*, 3rd ed., sec. 6.3.2). Lecture, "Mechanical
Vibration in Drive Trains": "The center frequency of the notch filter can be programmed to cancel
or minimize the gain at the resonant frequency."
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError


@dataclass(frozen=True)
class Notch:
    """A notch filter: centre [Hz], -3 dB width [Hz], depth (gain at the centre, 0..1)."""

    center_hz: float
    width_hz: float
    depth: float = 0.1

    def __post_init__(self) -> None:
        if not (math.isfinite(self.center_hz) and self.center_hz > 0.0):
            raise InputError("notch.center", "must be > 0 Hz", self.center_hz)
        if not (math.isfinite(self.width_hz) and self.width_hz > 0.0):
            raise InputError("notch.width", "must be > 0 Hz", self.width_hz)
        if not (math.isfinite(self.depth) and 0.0 <= self.depth < 1.0):
            raise InputError("notch.depth", "must be in [0, 1) (gain at the centre)", self.depth)

    @property
    def zeta(self) -> float:
        """Damping of the denominator, zeta = width / (2 f_n) [-]."""
        return self.width_hz / (2.0 * self.center_hz)

    @property
    def depth_db(self) -> float:
        """Depth in decibels (negative) [dB]."""
        return 20.0 * math.log10(self.depth) if self.depth > 0 else -math.inf

    def continuous(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(num, den) polynomial coefficients in s, highest power first."""
        w = 2.0 * math.pi * self.center_hz
        z = self.zeta
        return np.array([1.0, 2.0 * self.depth * z * w, w * w]), np.array([1.0, 2.0 * z * w, w * w])

    def response(self, freq_hz: ArrayLike) -> NDArray[np.complex128]:
        """Continuous frequency response N(j 2 pi f) [-]."""
        s = 2j * math.pi * np.asarray(freq_hz, dtype=float)
        num, den = self.continuous()
        return np.asarray(np.polyval(num, s) / np.polyval(den, s), dtype=complex)

    def discrete(self, sample_time: float) -> NDArray[np.float64]:
        """Biquad coefficients [b0, b1, b2, a1, a2] (a0 = 1) by prewarped Tustin at ``sample_time`` [s].

        y[k] = b0 u[k] + b1 u[k-1] + b2 u[k-2] - a1 y[k-1] - a2 y[k-2].
        """
        w = 2.0 * math.pi * self.center_hz
        if self.center_hz >= 0.5 / sample_time:
            raise InputError("notch.center", f"must be below the Nyquist frequency {0.5 / sample_time:g} Hz",
                             self.center_hz)
        c = w / math.tan(w * sample_time / 2.0)  # prewarped bilinear constant
        z = self.zeta
        d = self.depth
        n0, n1, n2 = c * c + 2 * d * z * w * c + w * w, 2 * (w * w - c * c), c * c - 2 * d * z * w * c + w * w
        m0, m1, m2 = c * c + 2 * z * w * c + w * w, 2 * (w * w - c * c), c * c - 2 * z * w * c + w * w
        return np.array([n0 / m0, n1 / m0, n2 / m0, m1 / m0, m2 / m0])


def notch_phase_lag_deg(notch: Notch, freq_hz: float) -> float:
    """Phase lag the notch adds at ``freq_hz`` [deg] (positive = lag)."""
    return -math.degrees(float(np.angle(notch.response(freq_hz))))


def propose_notch(
    resonance_hz: float,
    anti_resonance_hz: float,
    loop_bandwidth_hz: float,
    max_phase_lag_deg: float = 10.0,
) -> Notch:
    r"""Propose a notch for a two-mass resonance: centre, width and depth [Hz, Hz, -].

    Rule (documented choice, following Ellis, *Control System Design Guide*, 4th ed. (2012),
    chapter "Compliance and Resonance": notch centred on the resonance, as deep as the resonant
    peak, as wide as the loop's phase margin allows):

    - centre = resonance f_r;
    - depth = min(0.1, (f_ar/f_r)^2): at least 20 dB, and at least the inertia-ratio rise
      (J_m + J_L)/J_m = (f_r/f_ar)^2 that the resonance adds to the motor-side loop gain above f_r;
    - width: the span f_r - f_ar of the resonance/anti-resonance pair (at least 0.2 f_r), narrowed
      until the notch adds no more than ``max_phase_lag_deg`` of phase lag at the loop bandwidth.
    """
    if not (resonance_hz > 0 and math.isfinite(resonance_hz)):
        raise InputError("resonance", "must be > 0 Hz", resonance_hz)
    if not (0 < anti_resonance_hz < resonance_hz):
        raise InputError("anti_resonance", f"must be > 0 and below the resonance {resonance_hz:g} Hz",
                         anti_resonance_hz)
    if not (loop_bandwidth_hz > 0 and math.isfinite(loop_bandwidth_hz)):
        raise InputError("loop_bandwidth", "must be > 0 Hz", loop_bandwidth_hz)
    depth = min(0.1, (anti_resonance_hz / resonance_hz) ** 2)
    width = max(resonance_hz - anti_resonance_hz, 0.2 * resonance_hz)
    width = min(width, 1.9 * resonance_hz)
    if loop_bandwidth_hz < resonance_hz and notch_phase_lag_deg(
        Notch(resonance_hz, width, depth), loop_bandwidth_hz
    ) > max_phase_lag_deg:
        lo, hi = 1e-4 * resonance_hz, width
        for _ in range(60):
            mid = math.sqrt(lo * hi)
            if notch_phase_lag_deg(Notch(resonance_hz, mid, depth), loop_bandwidth_hz) > max_phase_lag_deg:
                hi = mid
            else:
                lo = mid
        width = lo
    return Notch(resonance_hz, width, depth)


def lowpass_coefficient(cutoff_hz: float, sample_time: float) -> float:
    r"""Discrete first-order low-pass gain alpha = 1 - exp(-2 pi f_c T) [-] (exact ZOH discretisation).

    y[k+1] = y[k] + alpha (u[k] - y[k]). Franklin, Powell, Workman, 3rd ed., sec. 6.3 (ZOH equivalent).
    """
    if not (cutoff_hz > 0 and math.isfinite(cutoff_hz)):
        raise InputError("lowpass", "must be > 0 Hz", cutoff_hz)
    return 1.0 - math.exp(-2.0 * math.pi * cutoff_hz * sample_time)


def lowpass_response(cutoff_hz: float, freq_hz: ArrayLike) -> NDArray[np.complex128]:
    """Continuous first-order low-pass 1 / (1 + s / (2 pi f_c)) at ``freq_hz`` [-]."""
    f = np.asarray(freq_hz, dtype=float)
    return np.asarray(1.0 / (1.0 + 1j * f / cutoff_hz), dtype=complex)
