r"""Nonlinear time simulation of the chain under the cascaded servo loop.

The plant is the N-mass chain at the motor shaft (``Chain``) with, per spring, Modelica
``ElastoBacklash`` (no torque inside the gap, no pulling in contact, continuous torque at contact:
tau = tau_c + min(tau_c, tau_d) while positive) and an optional ``LossyGear`` at its load end
(efficiency by power direction, stuck at zero speed, self-locking when back_efficiency <= 0); per
inertia, viscous damping and ``Friction`` (exponential Stribeck with exact stick like Modelica
``BearingFriction``, or the smooth tanh form); a constant load torque (gravity, process force) on
the last inertia. The cascaded controller of ``control.ServoLoop`` runs each loop at its own
sample time, with torque limit and encoder quantisation.

Integrator (default and only): semi-implicit (symplectic) Euler at a fixed step h,
omega_{k+1} = omega_k + h a(theta_k, omega_k), theta_{k+1} = theta_k + h omega_{k+1} (Hairer,
Lubich, Wanner, *Geometric Numerical Integration*, 2nd ed. (2006), sec. I.1.2 and IX.8): for a
lossless linear chain it conserves a modified energy exactly, so the energy error does not drift;
it oscillates with a relative amplitude of at most about h omega_max / 2 (omega_max the highest
natural frequency [rad/s]), and the scheme is stable for h omega_max < 2. ``tests`` bound both.
The step must divide every loop's sample time.

The kernels (``_kernel.run_two`` for the two-mass chain, ``_kernel.run_chain`` for any other) are
compiled with numba (``@njit(cache=True)``) on first use, one specialisation each, so the first run
in a fresh environment compiles only the kernel it needs and later runs load it from the cache;
numba is imported only then, never by ``import drivetrain``. ``sweep`` runs the same kernel with
metrics only (no per-step recording), spread over the cores by threads (the kernel releases the GIL).
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import ServoLoop, check_stable
from drivetrain.dynamics.filters import lowpass_coefficient
from drivetrain.dynamics.friction import METHOD_CODE
from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class SimulationDivergedError(InputError):
    """A simulation blew up; the message names the time, the inertia and the likely cause."""


@dataclass(frozen=True)
class Reference:
    """Motion reference at the motor shaft: time [s], position [rad], speed [rad/s], accel [rad/s^2]."""

    time: FloatArray
    position: FloatArray
    speed: FloatArray
    acceleration: FloatArray

    @staticmethod
    def from_arrays(time: ArrayLike, position: ArrayLike, speed: ArrayLike | None = None,
                    acceleration: ArrayLike | None = None) -> Reference:
        """Build from arrays (speed and acceleration by finite differences when not given)."""
        t = np.asarray(time, dtype=float).reshape(-1)
        x = np.asarray(position, dtype=float).reshape(-1)
        if t.size < 2 or x.size != t.size:
            raise InputError("reference", "needs time and position arrays of the same length >= 2",
                             f"{t.size} and {x.size}")
        if not np.all(np.isfinite(t)) or not np.all(np.isfinite(x)) or np.any(np.diff(t) <= 0):
            raise InputError("reference.time", "must be finite and strictly increasing", has_value=False)
        v = np.gradient(x, t) if speed is None else np.asarray(speed, dtype=float).reshape(-1)
        a = np.gradient(v, t) if acceleration is None else np.asarray(acceleration, dtype=float).reshape(-1)
        for name, arr in (("speed", v), ("acceleration", a)):
            if arr.size != t.size or not np.all(np.isfinite(arr)):
                raise InputError(f"reference.{name}", "must be finite and as long as the time array", arr.size)
        return Reference(t, x, v, a)

    @staticmethod
    def from_load(time: ArrayLike, position: ArrayLike, speed: ArrayLike, acceleration: ArrayLike,
                  ratio: float) -> Reference:
        """From a load-side profile [m or rad] through the chain's ratio (motor rad per load unit)."""
        return Reference.from_arrays(time, np.asarray(position) * ratio, np.asarray(speed) * ratio,
                                     np.asarray(acceleration) * ratio)

    def resample(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, speed, acceleration at times ``t`` (linear interpolation, held at the ends)."""
        tt = np.asarray(t, dtype=float)
        return (np.interp(tt, self.time, self.position), np.interp(tt, self.time, self.speed),
                np.interp(tt, self.time, self.acceleration))


def move_reference(distance: float, speed: float, accel: float, dwell: float = 0.0, *, repeat: int = 1,
                   back_and_forth: bool = True, step: float = 1e-4) -> Reference:
    """Trapezoidal (or triangular) point-to-point moves at the motor shaft, each followed by a dwell.

    distance [rad], peak speed [rad/s], acceleration [rad/s^2], dwell [s]. With ``back_and_forth``
    the moves alternate direction. A helper for tests and benchmarks; the axis's own duty-cycle
    profile is passed as arrays through ``Reference.from_arrays``.
    """
    for name, v in (("distance", abs(distance)), ("speed", speed), ("accel", accel)):
        if not (v > 0 and math.isfinite(v)):
            raise InputError(name, "must be > 0", v)
    d = abs(distance)
    ta = speed / accel
    if accel * ta * ta > d:  # triangular
        ta = math.sqrt(d / accel)
        speed = accel * ta
    tc = (d - accel * ta * ta) / speed
    t_move = 2 * ta + tc
    t_one = t_move + dwell
    t = np.arange(0.0, repeat * t_one + step / 2, step)
    x = np.zeros_like(t)
    vel = np.zeros_like(t)
    acc_all = np.zeros_like(t)
    start = 0.0
    for r in range(repeat):
        sgn = -1.0 if (back_and_forth and r % 2 == 1) else 1.0
        tau = t - r * t_one
        inside = (tau >= 0) & (tau < t_one + (step / 2 if r == repeat - 1 else 0.0))
        tt = tau[inside]
        ph1 = tt < ta
        ph2 = (tt >= ta) & (tt < ta + tc)
        ph3 = (tt >= ta + tc) & (tt < t_move)
        ph4 = tt >= t_move
        xs = np.empty_like(tt)
        vs = np.zeros_like(tt)
        acc = np.zeros_like(tt)
        xs[ph1] = 0.5 * accel * tt[ph1] ** 2
        vs[ph1] = accel * tt[ph1]
        acc[ph1] = accel
        xs[ph2] = 0.5 * accel * ta**2 + speed * (tt[ph2] - ta)
        vs[ph2] = speed
        td = t_move - tt[ph3]
        xs[ph3] = d - 0.5 * accel * td**2
        vs[ph3] = accel * td
        acc[ph3] = -accel
        xs[ph4] = d
        x[inside] = start + sgn * xs
        vel[inside] = sgn * vs
        acc_all[inside] = sgn * acc
        start += sgn * d
    return Reference(t, x, vel, acc_all)


def chain_energy(chain: Chain, theta: ArrayLike, omega: ArrayLike) -> FloatArray:
    r"""Mechanical energy of the chain [J]: sum (1/2) J w^2 + sum (1/2) K (twist beyond the gap)^2.

    ``theta``, ``omega``: (samples, n) or (n,) arrays [rad, rad/s].
    """
    th = np.atleast_2d(np.asarray(theta, dtype=float))
    w = np.atleast_2d(np.asarray(omega, dtype=float))
    e = 0.5 * np.sum(chain.inertia * w * w, axis=1)
    if chain.n > 1:
        rel = th[:, :-1] - th[:, 1:]
        b2 = 0.5 * chain.backlash
        beyond = np.sign(rel) * np.clip(np.abs(rel) - b2, 0.0, None)
        e = e + 0.5 * np.sum(chain.stiffness * beyond * beyond, axis=1)
    return np.asarray(e, dtype=float)


class SimulationResult:
    """Time series and figures of merit of one simulation (SI, angles at the motor shaft).

    Attributes:
        time: [s] recorded instants.
        states: dict of arrays: ``theta_<name>`` [rad], ``omega_<name>`` [rad/s] per inertia,
            ``reference_position`` [rad], ``reference_speed`` [rad/s], ``torque`` and
            ``torque_command`` [N m], ``shaft_torque_<k>`` [N m], ``following_error`` [rad],
            ``load_error`` [rad].
        following_error: reference - measured (encoder) motor position [rad], as the drive shows it.
        load_error: reference - load position [rad at the motor shaft].
        torque: motor torque [N m].
        shaft_torque: (samples, springs) torque in each spring [N m].
        settling_time: per stop of the reference, the time from the stop until |load_error| stays
            within ``settle_tolerance`` [s] (NaN: not settled before the next move or the end).
        overshoot: per stop, the largest excursion of the load past the target in the direction
            of the move [rad] (0 when it never passes).
        load_vibration_amplitude: the largest, over the stops, half peak-to-peak of the load error
            in the dwell after a stop [rad].
        peak_shaft_torque: per spring, max |shaft torque| [N m]; compare with the rigid sizing peak.
        energy: mechanical work the motor did on the chain, integral of T w_m dt [J].
        chain, loop: the models simulated.
    """

    def __init__(self, time: FloatArray, states: dict[str, FloatArray], chain: Chain, loop: ServoLoop | None,
                 settle_tolerance: float, metrics: FloatArray) -> None:
        self.time = time
        self.states = states
        self.chain = chain
        self.loop = loop
        self.settle_tolerance = settle_tolerance
        self.following_error = states["following_error"]
        self.load_error = states["load_error"]
        self.torque = states["torque"]
        m = chain.n - 1
        self.shaft_torque = (np.column_stack([states[f"shaft_torque_{k}"] for k in range(m)]) if m
                             else np.zeros((time.size, 0)))
        self.peak_shaft_torque = metrics[7:7 + m].copy()
        self.energy = float(metrics[2])
        self.peak_torque = float(metrics[3])
        total = float(time[-1] - time[0]) if time.size > 1 else 0.0
        self.rms_torque = math.sqrt(float(metrics[4]) / total) if total > 0 else abs(float(self.torque[0]))
        self.max_following_error = float(metrics[0])
        self.max_load_error = float(metrics[1])
        self.settling_time, self.overshoot, amplitude = self._stops()
        self.load_vibration_amplitude = float(np.max(amplitude)) if amplitude.size else 0.0

    def _stops(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        v = self.states["reference_speed"]
        x = self.states["reference_position"]
        moving = np.abs(v) > 1e-12 * max(1.0, float(np.max(np.abs(v))))
        # smooth over isolated zero-speed samples inside a move (a speed reversal)
        starts = np.nonzero(moving[1:] & ~moving[:-1])[0] + 1
        stops = np.nonzero(~moving[1:] & moving[:-1])[0] + 1
        settle, over, amp = [], [], []
        t = self.time
        load_pos = x - self.load_error
        for s in stops:
            nxt = starts[starts > s]
            end = int(nxt[0]) if nxt.size else t.size
            if end - s < 2:
                continue
            prev = starts[starts < s]
            begin = int(prev[-1]) - 1 if prev.size else 0
            direction = float(np.sign(x[s] - x[max(begin, 0)])) or 1.0
            err = self.load_error[s:end]
            outside = np.nonzero(np.abs(err) > self.settle_tolerance)[0]
            if outside.size == 0:
                settle.append(0.0)
            elif outside[-1] == err.size - 1:
                settle.append(math.nan)
            else:
                settle.append(float(t[s + outside[-1] + 1] - t[s]))
            over.append(max(0.0, float(np.max((load_pos[s:end] - x[s]) * direction))))
            amp.append(0.5 * float(np.max(err) - np.min(err)))
        return np.array(settle), np.array(over), np.array(amp)

    def to_dict(self, *, series: bool = False) -> dict[str, Any]:
        """JSON-ready: figures of merit (keys carry units); with ``series`` also every time series."""
        out: dict[str, Any] = {
            "duration_s": float(self.time[-1] - self.time[0]),
            "max_following_error_rad": self.max_following_error,
            "max_load_error_rad": self.max_load_error,
            "settling_time_s": [None if math.isnan(v) else float(v) for v in self.settling_time],
            "overshoot_rad": [float(v) for v in self.overshoot],
            "load_vibration_amplitude_rad": self.load_vibration_amplitude,
            "peak_torque_Nm": self.peak_torque,
            "rms_torque_Nm": self.rms_torque,
            "peak_shaft_torque_Nm": [float(v) for v in self.peak_shaft_torque],
            "energy_J": self.energy,
            "settle_tolerance_rad": self.settle_tolerance,
        }
        if series:
            out["series"] = {"time_s": self.time.tolist(), **{k: v.tolist() for k, v in self.states.items()}}
        return out

    def to_pandas(self) -> Any:
        """The time series as a pandas DataFrame indexed by time [s] (pandas imported here)."""
        import pandas as pd

        return pd.DataFrame(self.states, index=pd.Index(self.time, name="time_s"))

    def plot(self) -> Any:
        """Speeds, following error, torques: a matplotlib Figure (matplotlib imported here)."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 7))
        axes[0].plot(self.time, self.states["reference_speed"], "k--", label="reference")
        for name in self.chain.names:
            axes[0].plot(self.time, self.states[f"omega_{name}"], label=name)
        axes[0].set_ylabel("speed [rad/s]")
        axes[0].legend()
        axes[1].plot(self.time, self.following_error, label="following error (encoder)")
        axes[1].plot(self.time, self.load_error, label="load error")
        axes[1].set_ylabel("error [rad]")
        axes[1].legend()
        axes[2].plot(self.time, self.torque, label="motor torque")
        for k in range(self.shaft_torque.shape[1]):
            axes[2].plot(self.time, self.shaft_torque[:, k], label=f"shaft torque {k}")
        axes[2].set_ylabel("torque [N m]")
        axes[2].set_xlabel("time [s]")
        axes[2].legend()
        for ax in axes:
            ax.grid(True)
        return fig


# --- preparation -----------------------------------------------------------------------------

def _plant_arrays(chain: Chain, kern: Any) -> tuple[FloatArray, IntArray, FloatArray]:
    """The chain packed as the kernels take it: ``plant`` (rows per inertia), ``fmeth``, ``spring``."""
    n = chain.n
    m = n - 1
    plant = np.zeros((kern.N_PLANT, n))
    plant[kern.JM] = chain.inertia
    plant[kern.BG] = chain.ground_damping
    plant[kern.WS] = 1.0
    plant[kern.FEXP] = 2.0
    fmeth = np.full(n, -1, dtype=np.int64)
    for j, fr in enumerate(chain.friction):
        if fr is None:
            continue
        plant[kern.FC, j] = fr.coulomb
        plant[kern.FS, j] = fr.breakaway
        plant[kern.FV, j] = fr.viscous
        plant[kern.WS, j] = fr.stribeck_speed
        plant[kern.FEXP, j] = fr.exponent
        fmeth[j] = METHOD_CODE[fr.method]
    spring = np.zeros((kern.N_SPRING, max(m, 1)))
    spring[kern.ETA] = 1.0
    spring[kern.ETAB] = 1.0
    if m:
        spring[kern.KK, :m] = chain.stiffness
        spring[kern.DD, :m] = chain.damping
        spring[kern.GAP, :m] = chain.backlash
        spring[kern.ETA, :m] = chain.efficiency
        spring[kern.ETAB, :m] = chain.back_efficiency
    return plant, fmeth, spring


def _parameters(kern: Any, h: float, n_steps: int, rec: int, mode: int, loop: ServoLoop | None, load_torque: float,
                alpha_c: float, nb: FloatArray, lp_alpha: float, periods: tuple[int, int, int], t_m0: float,
                integ0: float, limit: float) -> tuple[FloatArray, IntArray]:
    """The scalar inputs packed as the kernels take them (``par`` floats, ``ipar`` integers)."""
    lp = loop if loop is not None else ServoLoop(velocity_kp=1.0, velocity_ti=math.inf, position_kv=0.0)
    par = np.zeros(kern.N_PAR)
    par[kern.P_H] = h
    par[kern.P_TLOAD] = load_torque
    par[kern.P_KP] = lp.velocity_kp
    par[kern.P_KI] = 0.0 if math.isinf(lp.velocity_ti) else lp.velocity_kp / lp.velocity_ti
    par[kern.P_KV] = lp.position_kv
    par[kern.P_KFFV] = lp.velocity_ff
    par[kern.P_KFFA] = lp.acceleration_ff
    par[kern.P_ALPHA] = alpha_c
    par[kern.P_NB0:kern.P_NB4 + 1] = nb
    par[kern.P_LP] = lp_alpha
    par[kern.P_TLIM] = lp.torque_limit
    par[kern.P_Q] = lp.encoder_resolution
    par[kern.P_TM0] = t_m0
    par[kern.P_INTEG0] = integ0
    par[kern.P_VLIM] = limit
    ipar = np.zeros(kern.N_IPAR, dtype=np.int64)
    ipar[kern.I_STEPS] = n_steps
    ipar[kern.I_REC] = rec
    ipar[kern.I_MODE] = mode
    ipar[kern.I_NOTCH] = lp.notch is not None
    ipar[kern.I_LP] = lp.lowpass_hz is not None
    ipar[kern.I_CUR], ipar[kern.I_VEL], ipar[kern.I_POS] = periods
    return par, ipar


def _loop_filters(loop: ServoLoop, h: float, n_cur: int, n_vel: int) -> tuple[float, FloatArray, float]:
    """Current-loop smoothing factor per current sample, notch biquad, low-pass factor."""
    alpha_c = 1.0 - math.exp(-2.0 * math.pi * loop.current_bandwidth_hz * n_cur * h)
    nb = loop.notch.discrete(n_vel * h) if loop.notch is not None else np.zeros(5)
    lp_alpha = lowpass_coefficient(loop.lowpass_hz, n_vel * h) if loop.lowpass_hz is not None else 0.0
    return alpha_c, np.asarray(nb, dtype=float), lp_alpha


def _omega_max(chain: Chain) -> float:
    from drivetrain.dynamics.linear import natural_frequencies

    f = natural_frequencies(chain)
    return 2.0 * math.pi * float(f[-1]) if f.size else 0.0


def _check_step(chain: Chain, step: float) -> None:
    if not (step > 0 and math.isfinite(step)):
        raise InputError("simulation.step", "must be > 0 s", step)
    wmax = _omega_max(chain)
    if step * wmax >= 1.0:
        raise InputError(
            "simulation.step",
            f"is too large for the stiffest mode ({wmax / (2 * math.pi):.1f} Hz): semi-implicit Euler needs "
            f"step * omega_max < 2 and this tool asks < 1 for accuracy; use a step below {1.0 / wmax:.3g} s",
            step)


def _periods(loop: ServoLoop, step: float) -> tuple[int, int, int]:
    out = []
    for name in ("current_sample_time", "velocity_sample_time", "position_sample_time"):
        t = getattr(loop, name)
        k = round(t / step)
        if k < 1 or abs(k * step - t) > 1e-9 * t + 1e-15:
            raise InputError(f"dynamics.control.{name}", f"must be a whole multiple of the simulation step "
                             f"{step:g} s", t)
        out.append(int(k))
    return out[0], out[1], out[2]


MAX_SIMULATION_BYTES = 1_500_000_000
"""Memory a simulation may take [bytes]: the reference and every recorded series live in memory."""


def estimate_bytes(inertias: int, steps: int, record_every: int = 1) -> int:
    """Memory of a run [bytes]: time and reference (4 series) per step, 3 n + 2 recorded series per
    recorded sample, and half as much again for the result's copies (measured: about 100 bytes per
    step for one inertia)."""
    return int(1.5 * 8 * steps * (4 + (3 * inertias + 2) / record_every))


def max_steps(inertias: int, record_every: int = 1) -> int:
    """The most steps that fit in ``MAX_SIMULATION_BYTES``."""
    return int(MAX_SIMULATION_BYTES / (1.5 * 8 * (4 + (3 * inertias + 2) / record_every)))


def default_step(chain: Chain, loop: ServoLoop) -> float:
    """The largest step that divides the current-loop period and keeps step * omega_max <= 0.2 [s]."""
    wmax = _omega_max(chain)
    t_c = loop.current_sample_time
    h = t_c
    if wmax > 0:
        h = t_c / math.ceil(t_c * wmax / 0.2)
    return h


def _initial_state(chain: Chain, position: float, load_torque: float) -> tuple[FloatArray, FloatArray]:
    """Static equilibrium under the load torque: every spring carries it (twist T/K + half the gap)."""
    n = chain.n
    theta = np.full(n, position, dtype=float)
    if load_torque != 0.0 and n > 1:
        twist = load_torque / chain.stiffness + np.sign(load_torque) * 0.5 * chain.backlash
        theta[1:] = position - np.cumsum(twist)
    return theta, np.zeros(n)


def _diverged(chain: Chain, step: float, k: int, j: int, speed_limit: float, loop: ServoLoop | None) -> (
        SimulationDivergedError):
    t = k * step
    cause = ("the closed loop is unstable or on the edge (gains too high for the resonance, "
             "too little phase margin, or a torque limit with integrator windup)" if loop is not None
             else "the applied torque is unbounded for this inertia")
    return SimulationDivergedError(
        "simulation",
        f"diverged at t = {t:.6g} s: the speed of inertia {j} ({chain.names[j]}) exceeded {speed_limit:.3g} rad/s; "
        f"likely cause: {cause}. Step h = {step:g} s, h * omega_max = {step * _omega_max(chain):.3g}",
        has_value=False)


def _kernel_module() -> Any:
    from drivetrain.dynamics import _kernel

    return _kernel


def _thread_count() -> int:
    """Threads for ``sweep``: numba's thread count (``NUMBA_NUM_THREADS``, default all cores)."""
    from numba import config

    return int(getattr(config, "NUMBA_NUM_THREADS", os.cpu_count() or 1))


# --- public entry points ---------------------------------------------------------------------

def simulate(
    chain: Chain,
    loop: ServoLoop,
    reference: Reference,
    *,
    step: float | None = None,
    duration: float | None = None,
    load_torque: float = 0.0,
    record_every: int = 1,
    settle_tolerance: float | None = None,
    speed_limit: float | None = None,
    check_stability: bool = True,
) -> SimulationResult:
    """Closed-loop nonlinear simulation of ``chain`` under ``loop`` following ``reference``.

    step [s] (default ``default_step``), duration [s] (default: the reference's end), load_torque
    [N m at the motor shaft] on the last inertia (gravity, process force), ``record_every`` keeps
    one sample in so many steps, settle_tolerance [rad] for settling times (an in-position
    window; default 0.1 % of the largest move, at least 10 encoder counts), speed_limit [rad/s]
    beyond which the run counts as diverged (default 100 x the reference's peak speed, at least
    1e4). The loop is checked for
    linear stability first (``check_stable``; InputError with a clear message); a run that still
    diverges raises ``SimulationDivergedError`` instead of returning NaN.
    """
    if check_stability and chain.n >= 1:
        check_stable(chain, loop)
    h = default_step(chain, loop) if step is None else float(step)
    _check_step(chain, h)
    n_cur, n_vel, n_pos = _periods(loop, h)
    t_end = float(reference.time[-1]) if duration is None else float(duration)
    if not (t_end > 0 and math.isfinite(t_end)):
        raise InputError("simulation.duration", "must be > 0 s", duration)
    if record_every < 1:
        raise InputError("simulation.record_every", "must be >= 1", record_every)
    n_steps = round(t_end / h)
    fit = max_steps(chain.n, record_every)
    if n_steps > fit:
        raise InputError("simulation.duration", f"is {n_steps} steps of {h:g} s (about "
                         f"{estimate_bytes(chain.n, n_steps, record_every) / 1e9:.1f} GB); at most {fit} steps "
                         f"({fit * h:.4g} s) fit in {MAX_SIMULATION_BYTES / 1e9:g} GB", t_end)
    t = np.arange(n_steps + 1) * h
    r_pos, r_vel, r_acc = (np.ascontiguousarray(a, dtype=float) for a in reference.resample(t))
    alpha_c, nb, lp_alpha = _loop_filters(loop, h, n_cur, n_vel)
    theta, omega = _initial_state(chain, float(r_pos[0]), load_torque)
    t_m0 = float(load_torque)
    limit = speed_limit if speed_limit is not None else max(1e4, 100.0 * float(np.max(np.abs(r_vel))))
    at_rest = np.nonzero(r_vel == 0.0)[0]
    moves = (np.abs(np.diff(r_pos[at_rest])) if at_rest.size > 1
             else np.array([float(np.ptp(r_pos))]))
    tol = settle_tolerance
    if tol is None:
        tol = max(1e-3 * float(np.max(moves)) if moves.size else 1e-3, 10.0 * loop.encoder_resolution, 1e-9)
    rec, metrics = _run(chain, h, n_steps, record_every, load_torque, 0, loop, alpha_c, nb, lp_alpha,
                        (n_cur, n_vel, n_pos), r_pos, r_vel, r_acc, np.zeros(1), theta, omega, t_m0, t_m0, limit)
    return _result(chain, loop, h, record_every, rec, metrics, r_pos, r_vel, tol)


def simulate_open_loop(
    chain: Chain,
    time: ArrayLike,
    motor_torque: ArrayLike,
    *,
    step: float | None = None,
    load_torque: float = 0.0,
    theta0: ArrayLike | None = None,
    omega0: ArrayLike | None = None,
    record_every: int = 1,
    speed_limit: float = 1e6,
) -> SimulationResult:
    """The plant alone driven by a motor torque [N m] given at ``time`` [s] (held between samples
    when ``step`` is None, the step being the sample spacing; otherwise interpolated). Initial
    angles/speeds [rad, rad/s] default to rest."""
    t_in = np.asarray(time, dtype=float).reshape(-1)
    u_in = np.asarray(motor_torque, dtype=float).reshape(-1)
    if t_in.size < 2 or u_in.size != t_in.size:
        raise InputError("motor_torque", "needs as many samples as time (>= 2)", u_in.size)
    h = float(t_in[1] - t_in[0]) if step is None else float(step)
    if step is None and not np.allclose(np.diff(t_in), h, rtol=1e-6, atol=0.0):
        raise InputError("time", "must be equally spaced when no step is given", has_value=False)
    _check_step(chain, h)
    n_steps = round((t_in[-1] - t_in[0]) / h)
    t = t_in[0] + np.arange(n_steps + 1) * h
    u = u_in[: n_steps + 1].copy() if step is None else np.interp(t, t_in, u_in)
    th = np.zeros(chain.n) if theta0 is None else np.array(theta0, dtype=float).reshape(-1)
    w = np.zeros(chain.n) if omega0 is None else np.array(omega0, dtype=float).reshape(-1)
    if th.size != chain.n or w.size != chain.n:
        raise InputError("theta0", f"needs {chain.n} entries", th.size)
    zeros = np.zeros(n_steps + 1)
    dummy = ServoLoop(velocity_kp=1.0, velocity_ti=math.inf, position_kv=0.0)
    rec, metrics = _run(chain, h, n_steps, record_every, load_torque, 1, None, 0.0, np.zeros(5), 0.0, (1, 1, 1),
                        zeros, zeros, zeros, np.ascontiguousarray(u, dtype=float), th, w, 0.0, 0.0, speed_limit)
    out = _result(chain, dummy, h, record_every, rec, metrics, zeros, zeros, 1e-9)
    out.time = out.time + t_in[0]
    out.loop = None
    return out


def _run(chain: Chain, h: float, n_steps: int, rec_every: int, load_torque: float, mode: int, loop: ServoLoop | None,
         alpha_c: float, nb: FloatArray, lp_alpha: float, periods: tuple[int, int, int], r_pos: FloatArray,
         r_vel: FloatArray, r_acc: FloatArray, u_ext: FloatArray, theta: FloatArray, omega: FloatArray, t_m0: float,
         integ0: float, limit: float) -> tuple[FloatArray, FloatArray]:
    """One run of the kernel; returns the recorded samples (rows as in ``_kernel``) and the metrics."""
    kern = _kernel_module()
    n = chain.n
    plant, fmeth, spring = _plant_arrays(chain, kern)
    par, ipar = _parameters(kern, h, n_steps, rec_every, mode, loop, float(load_torque), alpha_c, nb, lp_alpha,
                            periods, float(t_m0), float(integ0), float(limit))
    # one block for every recorded series: one allocation (large ones get huge pages), rows contiguous
    rec = np.empty((3 * n + 2, n_steps // rec_every + 1))
    metrics = np.zeros(kern.N_METRICS_BASE + max(n - 1, 1))
    run = kern.run_two if n == 2 else kern.run_chain
    status, k, j = run(plant, fmeth, spring, par, ipar, r_pos, r_vel, r_acc, u_ext,
                       np.ascontiguousarray(theta, dtype=float), np.ascontiguousarray(omega, dtype=float), rec, metrics)
    if status != 0:
        raise _diverged(chain, h, int(k), int(j), limit, loop)
    return rec, metrics


def _result(chain: Chain, loop: ServoLoop, h: float, rec_every: int, rec: FloatArray, metrics: FloatArray,
            r_pos: FloatArray, r_vel: FloatArray, tol: float) -> SimulationResult:
    n = chain.n
    n_rec = rec.shape[1]
    time = np.arange(n_rec, dtype=float) * (h * rec_every)
    if rec_every == 1:
        ref_pos, ref_vel = r_pos[:n_rec], r_vel[:n_rec]
    else:
        idx = np.arange(n_rec) * rec_every
        ref_pos, ref_vel = r_pos[idx], r_vel[idx]
    states: dict[str, FloatArray] = {}
    for j, name in enumerate(chain.names):
        states[f"theta_{name}"] = rec[j]
    for j, name in enumerate(chain.names):
        states[f"omega_{name}"] = rec[n + j]
    states["reference_position"] = ref_pos
    states["reference_speed"] = ref_vel
    states["torque"] = rec[3 * n - 1]
    states["torque_command"] = rec[3 * n]
    for k in range(n - 1):
        states[f"shaft_torque_{k}"] = rec[2 * n + k]
    states["following_error"] = rec[3 * n + 1]
    states["load_error"] = ref_pos - rec[n - 1]
    return SimulationResult(time, states, chain, loop, tol, metrics)


def simulate_linear_exact(chain: Chain, time: ArrayLike, motor_torque: ArrayLike, load_torque: ArrayLike | float = 0.0,
                          x0: ArrayLike | None = None) -> FloatArray:
    r"""Exact (zero-order-hold) stepping of the linear chain: x[k+1] = Phi x[k] + Gamma u[k].

    ``time`` equally spaced [s]; torques [N m] held over each step. Returns the state history
    (samples, 2n): angles then speeds. Phi, Gamma from ``linear.discretize_zoh``; exact for a
    piecewise-constant input, so a lossless chain keeps its energy to round-off.
    """
    from drivetrain.dynamics.linear import discrete_model

    t = np.asarray(time, dtype=float).reshape(-1)
    h = float(t[1] - t[0])
    if not np.allclose(np.diff(t), h, rtol=1e-9, atol=1e-15):
        raise InputError("time", "must be equally spaced for exact stepping", has_value=False)
    phi, gamma = discrete_model(chain, h)
    u = np.column_stack([np.broadcast_to(np.asarray(motor_torque, dtype=float), t.shape),
                         np.broadcast_to(np.asarray(load_torque, dtype=float), t.shape)])
    x = np.zeros((t.size, 2 * chain.n))
    x[0] = 0.0 if x0 is None else np.asarray(x0, dtype=float)
    gu = u @ gamma.T
    for k in range(t.size - 1):
        x[k + 1] = phi @ x[k] + gu[k]
    return x


def sweep(
    chain: Chain,
    loop: ServoLoop,
    reference: Reference,
    *,
    stiffness: ArrayLike | None = None,
    velocity_kp: ArrayLike | None = None,
    velocity_ti: ArrayLike | None = None,
    position_kv: ArrayLike | None = None,
    step: float | None = None,
    duration: float | None = None,
    load_torque: float = 0.0,
    speed_limit: float | None = None,
) -> dict[str, FloatArray]:
    """Many closed-loop runs in parallel over the CPU cores, keeping only metrics.

    Each of ``stiffness`` ((S, n-1) or (S,) for one spring) [N m/rad], ``velocity_kp`` [N m s/rad],
    ``velocity_ti`` [s], ``position_kv`` [1/s] is either None (the chain's / loop's value) or S
    values. Returns arrays of length S: ``max_following_error_rad``, ``max_load_error_rad``,
    ``energy_J``, ``peak_torque_Nm``, ``rms_torque_Nm``, ``final_load_error_rad``,
    ``peak_shaft_torque_Nm`` (S, n-1) and ``diverged`` (bool). No stability pre-check is done;
    diverged runs are flagged, not raised. Each run is the compiled kernel of ``simulate`` (the same
    specialisation, so nothing more is compiled) with no per-step recording; the runs are spread
    over ``NUMBA_NUM_THREADS`` threads (the kernel releases the GIL).
    """
    m = chain.n - 1
    sizes = [np.size(a) if a is not None else 0 for a in (velocity_kp, velocity_ti, position_kv)]
    if stiffness is not None:
        k_arr = np.asarray(stiffness, dtype=float)
        k_sets = k_arr.reshape(-1, 1) if k_arr.ndim == 1 else k_arr
        sizes.append(k_sets.shape[0])
    s_count = max([*sizes, 1])
    k_sets = (np.tile(chain.stiffness, (s_count, 1)) if stiffness is None
              else np.ascontiguousarray(np.broadcast_to(k_sets, (s_count, m)), dtype=float))
    if np.any(~np.isfinite(k_sets)) or np.any(k_sets <= 0):
        raise InputError("sweep.stiffness", "must all be > 0 N*m/rad", has_value=False)

    def col(v: ArrayLike | None, default: float, name: str) -> FloatArray:
        a = np.full(s_count, default) if v is None else np.broadcast_to(np.asarray(v, dtype=float), (s_count,))
        if np.any(~(a > 0)):
            raise InputError(f"sweep.{name}", "must all be > 0", has_value=False)
        return np.asarray(a, dtype=float)

    kp = col(velocity_kp, loop.velocity_kp, "velocity_kp")
    ti = col(velocity_ti, loop.velocity_ti, "velocity_ti")
    kv = col(position_kv, max(loop.position_kv, 1e-300), "position_kv")
    gains = np.ascontiguousarray(np.column_stack([kp, np.where(np.isinf(ti), 0.0, kp / ti), kv]))
    h = default_step(chain.with_(stiffness=k_sets.max(axis=0)), loop) if step is None else float(step)
    _check_step(chain.with_(stiffness=k_sets.max(axis=0)), h)
    n_cur, n_vel, n_pos = _periods(loop, h)
    t_end = float(reference.time[-1]) if duration is None else float(duration)
    n_steps = round(t_end / h)
    t = np.arange(n_steps + 1) * h
    r_pos, r_vel, r_acc = (np.ascontiguousarray(a, dtype=float) for a in reference.resample(t))
    alpha_c, nb, lp_alpha = _loop_filters(loop, h, n_cur, n_vel)
    theta, omega = _initial_state(chain, float(r_pos[0]), load_torque)
    limit = speed_limit if speed_limit is not None else max(1e4, 100.0 * float(np.max(np.abs(r_vel))))
    kern = _kernel_module()
    n = chain.n
    plant, fmeth, spring = _plant_arrays(chain, kern)
    # metrics only: the kernel records a single sample (record_every beyond the run)
    par, ipar = _parameters(kern, h, n_steps, n_steps + 1, 0, loop, float(load_torque), alpha_c, nb, lp_alpha,
                            (n_cur, n_vel, n_pos), float(load_torque), float(load_torque), float(limit))
    pars = np.tile(par, (s_count, 1))
    pars[:, kern.P_KP] = gains[:, 0]
    pars[:, kern.P_KI] = gains[:, 1]
    pars[:, kern.P_KV] = gains[:, 2]
    springs = np.repeat(spring[None], s_count, axis=0)
    springs[:, kern.KK, :m] = k_sets
    metrics = np.zeros((s_count, kern.N_METRICS_BASE + max(m, 1)))
    status = np.zeros(s_count, dtype=bool)
    run = kern.run_two if n == 2 else kern.run_chain
    u_none = np.zeros(1)

    def run_range(lo: int, hi: int) -> None:
        rec = np.empty((3 * n + 2, 1))
        for s in range(lo, hi):
            st, _, _ = run(plant, fmeth, springs[s], pars[s], ipar, r_pos, r_vel, r_acc, u_none, theta.copy(),
                           omega.copy(), rec, metrics[s])
            status[s] = st != 0

    # the kernel releases the GIL: plain threads run the simulations on all cores, in small chunks
    # so that runs stopped early by divergence do not leave a core idle
    workers = max(1, min(_thread_count(), s_count))
    chunk = max(1, s_count // (8 * workers))
    bounds = [(lo, min(lo + chunk, s_count)) for lo in range(0, s_count, chunk)]
    if workers == 1:
        for lo, hi in bounds:
            run_range(lo, hi)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            for fut in [pool.submit(run_range, lo, hi) for lo, hi in bounds]:
                fut.result()
    return {
        "max_following_error_rad": metrics[:, 0].copy(),
        "max_load_error_rad": metrics[:, 1].copy(),
        "energy_J": metrics[:, 2].copy(),
        "peak_torque_Nm": metrics[:, 3].copy(),
        "rms_torque_Nm": np.sqrt(metrics[:, 4] / max(t_end, 1e-300)),
        "final_load_error_rad": metrics[:, 5].copy(),
        "peak_shaft_torque_Nm": metrics[:, 7:7 + m].copy(),
        "diverged": status,
    }
