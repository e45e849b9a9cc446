r"""Linear models of the torsional chain: state space, transfer functions, modes, resonance.

Equations of motion of the N-mass chain (lecture, two-mass example, as ERRATA derives it:
J_m w_m' = T_m - B_m w_m - K(th_m - th_y), J_y w_y' = K(th_m - th_y) - B_y w_y - T_y):

.. math:: M \ddot\theta + C \dot\theta + K \theta = e_0 T_m - e_{n-1} T_L

State x = [theta_0 .. theta_{n-1}, omega_0 .. omega_{n-1}] [rad, rad/s]; inputs u = [T_m, T_L]
[N m] (motor torque on the first inertia, load torque disturbance on the last, entering with
-1/J_last); outputs y = x (every angle and speed).

.. math:: A = \begin{bmatrix} 0 & I \\ -M^{-1}K & -M^{-1}C \end{bmatrix},\quad
          B = \begin{bmatrix} 0 & 0 \\ M^{-1}e_0 & -M^{-1}e_{n-1} \end{bmatrix},\quad C = I,\ D = 0

Objects are python-control ``StateSpace``/``TransferFunction`` when python-control is installed
(``as_control=None``), plain numpy otherwise (``StateSpaceMatrices``, ``TransferFunctionData``).
Backlash, friction and lossy gears are nonlinear: the linear model takes the springs in contact
and the viscous parts of the friction only.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]

INPUTS: tuple[str, ...] = ("motor_torque", "load_torque")
OUTPUTS: tuple[str, ...] = ("motor_position", "motor_speed", "load_position", "load_speed")


@dataclass(frozen=True)
class StateSpaceMatrices:
    """Plain state-space model x' = A x + B u, y = C x + D u (SI), with signal names."""

    A: FloatArray
    B: FloatArray
    C: FloatArray
    D: FloatArray
    states: tuple[str, ...] = ()
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()

    def to_control(self) -> Any:
        """The same model as a python-control ``StateSpace`` (needs python-control)."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, states=list(self.states) or None,
                          inputs=list(self.inputs) or None, outputs=list(self.outputs) or None)


@dataclass(frozen=True)
class TransferFunctionData:
    """A SISO transfer function num(s)/den(s), coefficients highest power first."""

    num: FloatArray
    den: FloatArray

    def __call__(self, s: ArrayLike) -> NDArray[np.complex128]:
        z = np.asarray(s, dtype=complex)
        return np.asarray(np.polyval(self.num, z) / np.polyval(self.den, z), dtype=complex)

    def to_control(self) -> Any:
        """The same transfer function as a python-control ``TransferFunction``."""
        import control

        return control.tf(self.num, self.den)


def _control_available() -> bool:
    try:
        import control  # noqa: F401
    except ImportError:  # pragma: no cover - depends on the environment
        return False
    return True


def state_space_matrices(chain: Chain) -> StateSpaceMatrices:
    """A, B, C, D of the chain (see the module docstring) [SI]."""
    n = chain.n
    minv = 1.0 / chain.inertia
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -minv[:, None] * chain.stiffness_matrix()
    a[n:, n:] = -minv[:, None] * chain.damping_matrix()
    b = np.zeros((2 * n, 2))
    b[n, 0] = minv[0]
    b[2 * n - 1, 1] = -minv[-1]
    c = np.eye(2 * n)
    d = np.zeros((2 * n, 2))
    states = tuple(f"theta_{nm}" for nm in chain.names) + tuple(f"omega_{nm}" for nm in chain.names)
    return StateSpaceMatrices(a, b, c, d, states, INPUTS, states)


def state_space(chain: Chain, *, as_control: bool | None = None) -> Any:
    """The chain's state-space model: python-control ``StateSpace`` when available (or
    ``as_control=True``), else ``StateSpaceMatrices``."""
    m = state_space_matrices(chain)
    if as_control or (as_control is None and _control_available()):
        return m.to_control()
    return m


def _io_index(chain: Chain, input: str, output: str) -> tuple[int, int]:
    if input not in INPUTS:
        raise InputError("input", f"must be one of {', '.join(INPUTS)}", input)
    if output not in OUTPUTS:
        raise InputError("output", f"must be one of {', '.join(OUTPUTS)}", output)
    n = chain.n
    row = {"motor_position": 0, "motor_speed": n, "load_position": n - 1, "load_speed": 2 * n - 1}[output]
    return INPUTS.index(input), row


def transfer_function_data(chain: Chain, input: str = "motor_torque", output: str = "motor_speed") -> (
        TransferFunctionData):
    """SISO transfer function from ``input`` to ``output`` as polynomials (numpy only).

    Common roots at s = 0 (the free rigid-body mode seen from a speed output) are cancelled.
    """
    from scipy.signal import ss2tf

    j, i = _io_index(chain, input, output)
    m = state_space_matrices(chain)
    num, den = ss2tf(m.A, m.B, m.C[i : i + 1], m.D[i : i + 1], input=j)
    num = np.trim_zeros(np.where(np.abs(num[0]) < 1e-12 * np.max(np.abs(num[0]) + 1e-300), 0.0, num[0]), "f")
    den = np.asarray(den, dtype=float)
    scale_n = np.max(np.abs(num)) if num.size else 1.0
    scale_d = np.max(np.abs(den))
    while num.size > 1 and den.size > 1 and abs(num[-1]) <= 1e-12 * scale_n and abs(den[-1]) <= 1e-12 * scale_d:
        num, den = num[:-1], den[:-1]
    lead = den[0]
    return TransferFunctionData(np.asarray(num / lead, dtype=float), np.asarray(den / lead, dtype=float))


def transfer_function(chain: Chain, input: str = "motor_torque", output: str = "motor_speed", *,
                      as_control: bool | None = None) -> Any:
    """Transfer function ``input`` -> ``output``: python-control ``TransferFunction`` when available,
    else ``TransferFunctionData``. Inputs: motor_torque, load_torque [N m]; outputs:
    motor_position, motor_speed, load_position, load_speed [rad, rad/s at the motor shaft]."""
    tf = transfer_function_data(chain, input, output)
    if as_control or (as_control is None and _control_available()):
        return tf.to_control()
    return tf


def motor_speed_tf(chain: Chain, *, as_control: bool | None = None) -> Any:
    """Motor torque [N m] -> motor speed [rad/s]."""
    return transfer_function(chain, "motor_torque", "motor_speed", as_control=as_control)


def load_position_tf(chain: Chain, *, as_control: bool | None = None) -> Any:
    """Motor torque [N m] -> load position [rad at the motor shaft]."""
    return transfer_function(chain, "motor_torque", "load_position", as_control=as_control)


def disturbance_tf(chain: Chain, *, as_control: bool | None = None) -> Any:
    """Load torque disturbance [N m] -> load position [rad at the motor shaft]."""
    return transfer_function(chain, "load_torque", "load_position", as_control=as_control)


def frequency_response(chain: Chain, freq_hz: ArrayLike, input: str = "motor_torque",
                       output: str = "motor_speed") -> NDArray[np.complex128]:
    """G(j 2 pi f) = C (j w I - A)^-1 B evaluated directly (no polynomials) [SI per N m].

    The chain's equations M theta'' + C theta' + K theta = tau are a tridiagonal system per
    frequency: (K - w^2 M + j w C) Theta = T, solved for every frequency at once by the Thomas
    algorithm (forward elimination and back substitution along the chain, each step an array over the
    frequencies; Golub, Van Loan, *Matrix Computations*, 4th ed. (2013), §4.3.6, algorithm 4.3.6);
    a speed is j w Theta. The same answer as the state-space solve (``_frequency_response_ss``, kept
    for the tests), at O(n F) instead of O((2n)^3 F).
    """
    j, i = _io_index(chain, input, output)
    f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
    n = chain.n
    w = 2.0 * math.pi * f
    stiff, damp = chain.stiffness_matrix(), chain.damping_matrix()
    inertia = np.asarray(chain.inertia, dtype=float)
    diag = stiff.diagonal()[None, :] - (w * w)[:, None] * inertia[None, :] + 1j * w[:, None] * damp.diagonal()[None, :]
    off = (np.diagonal(stiff, 1)[None, :] + 1j * w[:, None] * np.diagonal(damp, 1)[None, :]) if n > 1 else None
    rhs = np.zeros((f.size, n), dtype=complex)
    rhs[:, 0 if j == 0 else n - 1] = 1.0 if j == 0 else -1.0  # motor torque on the first, load torque on the last
    with np.errstate(divide="ignore", invalid="ignore"):
        cp = np.zeros((f.size, max(n - 1, 0)), dtype=complex)
        dp = np.empty((f.size, n), dtype=complex)
        piv = diag[:, 0]
        dp[:, 0] = rhs[:, 0] / piv
        for k in range(1, n):  # along the chain's few inertias; each step is an array over the frequencies
            assert off is not None
            cp[:, k - 1] = off[:, k - 1] / piv
            piv = diag[:, k] - off[:, k - 1] * cp[:, k - 1]
            dp[:, k] = (rhs[:, k] - off[:, k - 1] * dp[:, k - 1]) / piv
        x = dp[:, n - 1]
        for k in range(n - 2, -1, -1):
            if k < i % n:
                break
            x = dp[:, k] - cp[:, k] * x
    theta = x
    return np.asarray(theta * (1j * w) if i >= n else theta, dtype=complex)


def _frequency_response_ss(chain: Chain, freq_hz: ArrayLike, input: str = "motor_torque",
                           output: str = "motor_speed") -> NDArray[np.complex128]:
    """``frequency_response`` by the state-space solve (j w I - A)^-1 B over the frequencies (the check
    of the tridiagonal solve)."""
    j, i = _io_index(chain, input, output)
    m = state_space_matrices(chain)
    f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
    n = m.A.shape[0]
    # one batched solve over the frequencies: (F, n, n) systems (j w I - A) x = B_j
    mats = (2j * math.pi * f)[:, None, None] * np.eye(n) - m.A
    rhs = np.broadcast_to(m.B[:, j].astype(complex), (f.size, n))[..., None]
    return np.asarray(np.linalg.solve(mats, rhs)[:, i, 0], dtype=complex)


def modes(chain: Chain) -> tuple[FloatArray, FloatArray]:
    r"""Undamped natural frequencies [Hz] and mode shapes, rigid-body mode left out.

    Generalised eigenproblem K v = omega^2 M v, ascending. Mode shapes are the columns of the
    returned (n, n-1) array, scaled to a largest entry of +1.
    Source: Rao, *Mechanical Vibrations*, 5th ed. (2011), sec. 6.10 (eigenvalue problem).
    """
    if chain.n < 2:
        return np.zeros(0), np.zeros((chain.n, 0))
    w2, v = _eigh_diagonal_mass(chain.stiffness_matrix(), np.asarray(chain.inertia, dtype=float))
    w2, v = w2[1:], v[:, 1:]  # a free chain has exactly one rigid-body mode (omega = 0)
    freqs = np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * math.pi)
    for k in range(v.shape[1]):
        col = v[:, k]
        v[:, k] = col / col[np.argmax(np.abs(col))]
    return freqs, v


def _eigh_diagonal_mass(k: FloatArray, m: FloatArray) -> tuple[FloatArray, FloatArray]:
    """K v = w^2 M v for a diagonal M (lumped inertias): symmetric form M^-1/2 K M^-1/2, numpy's eigh.

    Same eigenvalues and M-orthonormal eigenvectors as scipy.linalg.eigh(K, M), without importing
    scipy.linalg (a third of a second) on the way to a first simulation.
    """
    s = 1.0 / np.sqrt(m)
    w2, u = np.linalg.eigh(k * s[:, None] * s[None, :])
    return w2, u * s[:, None]


def natural_frequencies(chain: Chain) -> FloatArray:
    """Undamped natural frequencies [Hz], ascending, the rigid-body mode left out."""
    return modes(chain)[0]


def anti_resonance_frequencies(chain: Chain) -> FloatArray:
    """Anti-resonances of motor torque -> motor speed [Hz]: the chain's natural frequencies with
    the motor held still (K and M without the motor's row and column), ascending."""
    if chain.n < 2:
        return np.zeros(0)
    w2, _ = _eigh_diagonal_mass(chain.stiffness_matrix()[1:, 1:], np.asarray(chain.inertia, dtype=float)[1:])
    return np.asarray(np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * math.pi), dtype=float)


def two_mass_resonance(j_motor: float, j_load: float, stiffness: float) -> tuple[float, float]:
    r"""Resonance and anti-resonance of the two-mass system [Hz, Hz].

    .. math:: f_r = \frac{1}{2\pi}\sqrt{\frac{K (J_1 + J_2)}{J_1 J_2}}, \qquad
              f_{ar} = \frac{1}{2\pi}\sqrt{\frac{K}{J_{load}}}

    J [kg m^2], K [N m/rad]. Source: lecture, "Mechanical Vibration in Drive Trains" (Resonant
    Frequency = sqrt(K_SHAFT (1/J_M + 1/J_LOAD)); example 0.5 and 0.4 kg m^2 on 60e3 N m/rad gives
    82.7 Hz); the anti-resonance is the zero of motor torque -> motor speed (Ellis, 4th ed.,
    "Compliance and Resonance").

    >>> round(two_mass_resonance(0.5, 0.4, 60e3)[0], 1)
    82.7
    """
    for name, v in (("j_motor", j_motor), ("j_load", j_load), ("stiffness", stiffness)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(name, "must be > 0", v)
    f_r = math.sqrt(stiffness * (j_motor + j_load) / (j_motor * j_load)) / (2.0 * math.pi)
    f_ar = math.sqrt(stiffness / j_load) / (2.0 * math.pi)
    return f_r, f_ar


@dataclass(frozen=True)
class TwoMass:
    """Two-mass reduction of a chain: motor, load, equivalent spring, and its two frequencies."""

    j_motor: float
    j_load: float
    stiffness: float
    resonance_hz: float
    anti_resonance_hz: float


def two_mass_reduction(chain: Chain) -> TwoMass:
    """Reduce a chain to the two-mass form the lecture uses [SI].

    J_motor = J_0, J_load = the rest; the equivalent stiffness is chosen so the two-mass
    resonance equals the chain's first natural frequency, K = w1^2 J_m J_L / (J_m + J_L). For a
    two-mass chain this is exact; the anti-resonance reported is the chain's first anti-resonance
    (first zero of motor torque -> motor speed), which equals sqrt(K/J_L)/(2 pi) for two masses.
    """
    if chain.n < 2:
        raise InputError(chain.path, "needs at least two inertias and a spring for a resonance", chain.n)
    jm = float(chain.inertia[0])
    jl = float(chain.inertia[1:].sum())
    f1 = float(natural_frequencies(chain)[0])
    w1 = 2.0 * math.pi * f1
    k = w1 * w1 * jm * jl / (jm + jl)
    far = float(anti_resonance_frequencies(chain)[0])
    return TwoMass(jm, jl, k, f1, far)


# --- the lecture's mass-spring-damper ---------------------------------------------------------

def mass_spring_damper(mass: float, damping: float, stiffness: float) -> StateSpaceMatrices:
    r"""State space of m x'' + B x' + k x = F (lecture, "Example: Mass-Spring-Damper").

    x = [position, speed] [m, m/s], u = F [N], y = position [m]; mass [kg], damping [N s/m],
    stiffness [N/m].
    """
    if not (mass > 0 and math.isfinite(mass)):
        raise InputError("mass", "must be > 0 kg", mass)
    if not (damping >= 0 and math.isfinite(damping)):
        raise InputError("damping", "must be >= 0 N*s/m", damping)
    if not (stiffness >= 0 and math.isfinite(stiffness)):
        raise InputError("stiffness", "must be >= 0 N/m", stiffness)
    a = np.array([[0.0, 1.0], [-stiffness / mass, -damping / mass]])
    b = np.array([[0.0], [1.0 / mass]])
    return StateSpaceMatrices(a, b, np.array([[1.0, 0.0]]), np.zeros((1, 1)), ("x", "v"), ("F",), ("x",))


def mass_spring_damper_tf(mass: float, damping: float, stiffness: float) -> TransferFunctionData:
    r"""X(s)/F(s) = 1 / (m s^2 + B s + k) [m/N]; under a unit step force X(s) = 1/(s(m s^2 + B s + k))
    (lecture, "Example: Mass-Spring-Damper")."""
    mass_spring_damper(mass, damping, stiffness)  # validates
    return TransferFunctionData(np.array([1.0]), np.array([mass, damping, stiffness]))


def mass_spring_damper_final_value(stiffness: float, force: float = 1.0) -> float:
    r"""Final position under a step force F [m]: x_inf = lim_{s->0} s X(s) = F / k (lecture)."""
    if not (stiffness > 0 and math.isfinite(stiffness)):
        raise InputError("stiffness", "must be > 0 N/m for a final value to exist", stiffness)
    return force / stiffness


def second_order_step(mass: float, damping: float, stiffness: float, t: ArrayLike, force: float = 1.0) -> (
        FloatArray):
    r"""Closed-form step response x(t) of m x'' + B x' + k x = F u(t) from rest [m].

    With w_n = sqrt(k/m), zeta = B / (2 sqrt(k m)): for zeta < 1,
    x = (F/k)[1 - e^{-zeta w_n t}(cos w_d t + zeta/sqrt(1-zeta^2) sin w_d t)], w_d = w_n sqrt(1-zeta^2);
    zeta = 1: x = (F/k)[1 - (1 + w_n t) e^{-w_n t}]; zeta > 1: the two real exponentials.
    Source: Ogata, *Modern Control Engineering*, 5th ed. (2010), sec. 5-3.
    """
    mass_spring_damper(mass, damping, stiffness)
    tt = np.asarray(t, dtype=float)
    wn = math.sqrt(stiffness / mass)
    zeta = damping / (2.0 * math.sqrt(stiffness * mass))
    xs = force / stiffness
    if zeta < 1.0 - 1e-9:
        wd = wn * math.sqrt(1.0 - zeta * zeta)
        return np.asarray(xs * (1.0 - np.exp(-zeta * wn * tt) * (np.cos(wd * tt) + zeta / math.sqrt(1 - zeta**2)
                                                                     * np.sin(wd * tt))), dtype=float)
    if zeta <= 1.0 + 1e-9:
        return np.asarray(xs * (1.0 - (1.0 + wn * tt) * np.exp(-wn * tt)), dtype=float)
    r = math.sqrt(zeta * zeta - 1.0)
    s1, s2 = -wn * (zeta - r), -wn * (zeta + r)
    return np.asarray(xs * (1.0 + (s2 * np.exp(s1 * tt) - s1 * np.exp(s2 * tt)) / (s1 - s2)), dtype=float)


# --- discretisation ---------------------------------------------------------------------------

def discretize_zoh(a: ArrayLike, b: ArrayLike, sample_time: float) -> tuple[FloatArray, FloatArray]:
    r"""Zero-order-hold discretisation: Phi = e^{A T}, Gamma = int_0^T e^{A s} ds B.

    Both from one matrix exponential of the augmented matrix
    exp([[A, B], [0, 0]] T) = [[Phi, Gamma], [0, I]] (Van Loan 1978; Franklin, Powell, Workman,
    *Digital Control of Dynamic Systems*, 3rd ed., sec. 4.3.3). x[k+1] = Phi x[k] + Gamma u[k].
    """
    from scipy.linalg import expm

    am = np.atleast_2d(np.asarray(a, dtype=float))
    bm = np.asarray(b, dtype=float)
    if bm.ndim == 1:
        bm = bm[:, None]
    if not (sample_time > 0 and math.isfinite(sample_time)):
        raise InputError("sample_time", "must be > 0 s", sample_time)
    n, m = am.shape[0], bm.shape[1]
    aug = np.zeros((n + m, n + m))
    aug[:n, :n] = am
    aug[:n, n:] = bm
    e = expm(aug * sample_time)
    return e[:n, :n], e[:n, n:]


def discrete_model(chain: Chain, sample_time: float) -> tuple[FloatArray, FloatArray]:
    """(Phi, Gamma) of the chain by zero-order hold at ``sample_time`` [s]."""
    m = state_space_matrices(chain)
    return discretize_zoh(m.A, m.B, sample_time)


# --- critical speeds --------------------------------------------------------------------------

@dataclass(frozen=True)
class CriticalSpeed:
    """A speed where an excitation order crosses a natural frequency."""

    excitation: str
    order: float
    mode: int
    frequency_hz: float
    speed_rad_s: float

    @property
    def speed_rpm(self) -> float:
        """The critical speed [rpm]."""
        return self.speed_rad_s * 60.0 / (2.0 * math.pi)


def excitation_orders(*, unbalance: bool = True, torque_ripple: Sequence[float] = (),
                      gear_teeth: Sequence[tuple[int, float]] = ()) -> dict[str, float]:
    """Excitation orders per motor revolution [events/rev].

    ``unbalance``: order 1. ``torque_ripple``: the motor's ripple orders (e.g. 6, 12 for a
    three-phase drive, or the cogging order = lcm(slots, poles)). ``gear_teeth``: (teeth z,
    ratio from the motor to that gear's shaft): the mesh order at the motor shaft is z / ratio.
    Lecture, "Mechanical Vibration in Drive Trains" (unbalance, torque ripple, harmonic torques).
    """
    out: dict[str, float] = {}
    if unbalance:
        out["unbalance (1x)"] = 1.0
    for o in torque_ripple:
        out[f"torque ripple ({o:g}x)"] = float(o)
    for z, ratio in gear_teeth:
        out[f"gear mesh ({z} teeth)"] = float(z) / float(ratio)
    return out


def critical_speeds(natural_frequencies_hz: ArrayLike, speed_min: float, speed_max: float,
                    orders: Mapping[str, float]) -> list[CriticalSpeed]:
    r"""Speeds within [speed_min, speed_max] [rad/s] where an excitation order crosses a natural
    frequency: order * Omega / (2 pi) = f_n  =>  Omega = 2 pi f_n / order (a Campbell diagram's
    intersections). Lecture, "Critical Speed and Torsional Dynamics": "the speed at which a
    system's natural frequency coincides with the frequency of an external force". Sorted by speed.
    """
    freqs = np.atleast_1d(np.asarray(natural_frequencies_hz, dtype=float))
    lo, hi = sorted((abs(speed_min), abs(speed_max)))
    out: list[CriticalSpeed] = []
    for label, order in orders.items():
        if not (order > 0 and math.isfinite(order)):
            raise InputError(f"orders.{label}", "must be > 0 per revolution", order)
        for mode, f in enumerate(freqs):
            speed = 2.0 * math.pi * f / order
            if lo <= speed <= hi:
                out.append(CriticalSpeed(label, float(order), mode + 1, float(f), speed))
    return sorted(out, key=lambda c: c.speed_rad_s)


def campbell_diagram(natural_frequencies_hz: ArrayLike, speed_max: float, orders: Mapping[str, float],
                     points: int = 50) -> dict[str, FloatArray]:
    """Data for a Campbell diagram: ``speed_rad_s`` and, per excitation, its frequency line [Hz];
    plus ``natural_frequencies_hz`` (horizontal lines)."""
    speed = np.linspace(0.0, abs(speed_max), points)
    out: dict[str, FloatArray] = {"speed_rad_s": speed,
                                  "natural_frequencies_hz": np.atleast_1d(np.asarray(natural_frequencies_hz))}
    for label, order in orders.items():
        out[label] = order * speed / (2.0 * math.pi)
    return out
