"""The interface of the compiled kernels (``_kernel``): a chain, a servo loop and the run settings packed
into the arrays the kernels take, the step and memory limits checked before a run, and the recorded rows
unpacked into a ``SimulationResult``. The kernel module (and numba) is imported only when a run starts.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import ServoLoop
from drivetrain.dynamics.filters import lowpass_coefficient
from drivetrain.dynamics.friction import METHOD_CODE
from drivetrain.dynamics.simulation_result import SimulationResult
from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class SimulationDivergedError(InputError):
    """A simulation blew up; the message names the time, the inertia and the likely cause."""


def plant_arrays(chain: Chain, kern: Any) -> tuple[FloatArray, IntArray, FloatArray]:
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


def parameters(kern: Any, h: float, n_steps: int, rec: int, mode: int, loop: ServoLoop | None, load_torque: float,
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


def loop_filters(loop: ServoLoop, h: float, n_cur: int, n_vel: int) -> tuple[float, FloatArray, float]:
    """Current-loop smoothing factor per current sample, notch biquad, low-pass factor."""
    alpha_c = 1.0 - math.exp(-2.0 * math.pi * loop.current_bandwidth_hz * n_cur * h)
    nb = loop.notch.discrete(n_vel * h) if loop.notch is not None else np.zeros(5)
    lp_alpha = lowpass_coefficient(loop.lowpass_hz, n_vel * h) if loop.lowpass_hz is not None else 0.0
    return alpha_c, np.asarray(nb, dtype=float), lp_alpha


def spring_table(chain: Chain) -> tuple[FloatArray, FloatArray]:
    """The last spring's (angle, stiffness) table as the kernels take it (empty: constant spring)."""
    if chain.spring_table is None:
        return np.zeros(0), np.zeros(0)
    x, k = chain.spring_table
    return np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(k, dtype=float)


def _omega_max(chain: Chain) -> float:
    """Highest natural frequency [rad/s]; with a ``spring_table``, at the table's stiffest value."""
    from drivetrain.dynamics.linear import natural_frequencies

    if chain.spring_table is not None:
        chain = chain.with_(stiffness=np.r_[chain.stiffness[:-1], float(np.max(chain.spring_table[1]))],
                            spring_table=None)
    f = natural_frequencies(chain)
    return 2.0 * math.pi * float(f[-1]) if f.size else 0.0


def check_step(chain: Chain, step: float) -> None:
    if not (step > 0 and math.isfinite(step)):
        raise InputError("simulation.step", "must be > 0 s", step)
    wmax = _omega_max(chain)
    if step * wmax >= 1.0:
        raise InputError(
            "simulation.step",
            f"is too large for the stiffest mode ({wmax / (2 * math.pi):.1f} Hz): semi-implicit Euler needs "
            f"step * omega_max < 2 and this tool asks < 1 for accuracy; use a step below {1.0 / wmax:.3g} s",
            step)


def loop_periods(loop: ServoLoop, step: float) -> tuple[int, int, int]:
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


def initial_state(chain: Chain, position: float, load_torque: float) -> tuple[FloatArray, FloatArray]:
    """Static equilibrium under the load torque: every spring carries it (twist T/K + half the gap)."""
    n = chain.n
    theta = np.full(n, position, dtype=float)
    if load_torque != 0.0 and n > 1:
        twist = load_torque / chain.stiffness + np.sign(load_torque) * 0.5 * chain.backlash
        theta[1:] = position - np.cumsum(twist)
    return theta, np.zeros(n)


def diverged(chain: Chain, step: float, k: int, j: int, speed_limit: float, loop: ServoLoop | None) -> (
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


def kernel_module() -> Any:
    from drivetrain.dynamics import _kernel

    return _kernel


def thread_count() -> int:
    """Threads for ``sweep``: numba's thread count (``NUMBA_NUM_THREADS``, default all cores)."""
    from numba import config

    return int(getattr(config, "NUMBA_NUM_THREADS", os.cpu_count() or 1))


def result(chain: Chain, loop: ServoLoop, h: float, rec_every: int, rec: FloatArray, metrics: FloatArray,
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
    res = SimulationResult(time, states, chain, loop, tol, metrics)
    res.step = h
    return res
