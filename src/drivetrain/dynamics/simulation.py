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

The run itself is here; the reference is ``reference``, the result ``simulation_result``, and the packing
of the kernels' arguments ``kernel_io``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import ServoLoop, check_stable
from drivetrain.dynamics.kernel_io import (
    MAX_SIMULATION_BYTES,
    check_step,
    default_step,
    diverged,
    estimate_bytes,
    initial_state,
    kernel_module,
    loop_filters,
    loop_periods,
    max_steps,
    parameters,
    plant_arrays,
    result,
    spring_table,
    thread_count,
)
from drivetrain.dynamics.reference import Reference
from drivetrain.dynamics.simulation_result import SimulationResult
from drivetrain.errors import InputError

__all__ = ["simulate", "simulate_linear_exact", "simulate_open_loop", "sweep"]

FloatArray = NDArray[np.float64]


STEP_TOLERANCE = 0.02
"""The automatic step's convergence test: relative agreement of settling times and largest errors."""
MAX_REFINEMENT = 32
"""The automatic step is refined at most to ``default_step`` / this."""


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

    step [s] (default: chosen by a convergence test, ``converged_step`` below), duration [s]
    (default: the reference's end), load_torque [N m at the motor shaft] on the last inertia
    (gravity, process force), ``record_every`` keeps one sample in so many steps (of the
    ``default_step``'s grid when the step is automatic), settle_tolerance [rad] for settling times
    (an in-position window; default 0.1 % of the largest move, at least 10 encoder counts),
    speed_limit [rad/s] beyond which the run counts as diverged (default 100 x the reference's peak
    speed, at least 1e4). The loop is checked for linear stability first (``check_stable``;
    InputError with a clear message); a run that still diverges raises ``SimulationDivergedError``
    instead of returning NaN.

    Automatic step: semi-implicit Euler is first order in h for the figures read here (Hairer,
    Lubich, Wanner, *Geometric Numerical Integration*, 2nd ed. (2006), sec. II.1, Theorem 1.1 with
    order 1; sec. VI.3 for the scheme), so a figure F(h) = F* + C h + O(h^2) and
    |F(h) - F(h/2)| estimates the error of F(h/2) (Richardson's estimate; Hairer, Norsett, Wanner,
    *Solving Ordinary Differential Equations I*, 2nd ed. (1993), sec. II.4, "Richardson
    extrapolation"). The run starts at ``default_step`` (step x omega_max <= 0.2, well inside the
    stability bound 2) and halves the step until two successive runs agree (``_agree``): every
    settling time within ``STEP_TOLERANCE`` or one position-loop sample, whichever is larger (both
    "never settles" also agree), and the largest following and load errors within
    ``STEP_TOLERANCE`` or ``STEP_TOLERANCE`` x the settling window. The finer run is returned;
    ``result.step`` is its step and ``result.step_converged`` says whether the test passed (False:
    ``MAX_REFINEMENT`` or the memory limit was reached first; the figures are the finest run's).
    Refined runs record on the first run's grid, so their memory grows only by the reference.
    Measured on the shipped examples: bench/RESULTS.md, "Simulation step".
    """
    if check_stability and chain.n >= 1:
        check_stable(chain, loop)
    if step is not None:
        res = _simulate_at(chain, loop, reference, float(step), duration, load_torque, record_every,
                           settle_tolerance, speed_limit)
        res.step, res.step_converged = float(step), None
        return res
    h0 = default_step(chain, loop)
    coarse = _simulate_at(chain, loop, reference, h0, duration, load_torque, record_every, settle_tolerance,
                          speed_limit)
    tol = coarse.settle_tolerance
    coarse.step, coarse.step_converged = h0, False
    k = 2
    while k <= MAX_REFINEMENT:
        t_end = float(reference.time[-1]) if duration is None else float(duration)
        if round(t_end / (h0 / k)) > max_steps(chain.n, record_every * k):
            break  # the finer run would not fit in memory: keep the finest that did, not converged
        fine = _simulate_at(chain, loop, reference, h0 / k, duration, load_torque, record_every * k, tol,
                            speed_limit)
        fine.step, fine.step_converged = h0 / k, _agree(coarse, fine, loop)
        if fine.step_converged:
            return fine
        coarse, k = fine, 2 * k
    return coarse


def _agree(coarse: SimulationResult, fine: SimulationResult, loop: ServoLoop) -> bool:
    """The figures of two runs at h and h/2 agree (``simulate``'s automatic step)."""
    a, b = np.asarray(coarse.settling_time, dtype=float), np.asarray(fine.settling_time, dtype=float)
    if a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
        return False
    both = ~np.isnan(b)
    if np.any(np.abs(a[both] - b[both]) > np.maximum(STEP_TOLERANCE * b[both], loop.position_sample_time)):
        return False
    floor = STEP_TOLERANCE * fine.settle_tolerance
    return all(abs(x - y) <= max(STEP_TOLERANCE * abs(y), floor)
               for x, y in ((coarse.max_following_error, fine.max_following_error),
                            (coarse.max_load_error, fine.max_load_error)))


def _simulate_at(chain: Chain, loop: ServoLoop, reference: Reference, h: float, duration: float | None,
                 load_torque: float, record_every: int, settle_tolerance: float | None,
                 speed_limit: float | None) -> SimulationResult:
    """One closed-loop run at step ``h`` [s] (``simulate``'s arguments)."""
    check_step(chain, h)
    n_cur, n_vel, n_pos = loop_periods(loop, h)
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
    alpha_c, nb, lp_alpha = loop_filters(loop, h, n_cur, n_vel)
    theta, omega = initial_state(chain, float(r_pos[0]), load_torque)
    t_m0 = float(load_torque)
    limit = speed_limit if speed_limit is not None else max(1e4, 100.0 * float(np.max(np.abs(r_vel))))
    tol = settle_tolerance
    if tol is None:
        at_rest = np.nonzero(r_vel == 0.0)[0]
        moves = (np.abs(np.diff(r_pos[at_rest])) if at_rest.size > 1
                 else np.array([float(np.ptp(r_pos))]))
        tol = max(1e-3 * float(np.max(moves)) if moves.size else 1e-3, 10.0 * loop.encoder_resolution, 1e-9)
    rec, metrics = _run(chain, h, n_steps, record_every, load_torque, 0, loop, alpha_c, nb, lp_alpha,
                        (n_cur, n_vel, n_pos), r_pos, r_vel, r_acc, np.zeros(1), theta, omega, t_m0, t_m0, limit)
    return result(chain, loop, h, record_every, rec, metrics, r_pos, r_vel, tol)


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
    check_step(chain, h)
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
    out = result(chain, dummy, h, record_every, rec, metrics, zeros, zeros, 1e-9)
    out.time = out.time + t_in[0]
    out.loop = None
    return out


def _run(chain: Chain, h: float, n_steps: int, rec_every: int, load_torque: float, mode: int, loop: ServoLoop | None,
         alpha_c: float, nb: FloatArray, lp_alpha: float, periods: tuple[int, int, int], r_pos: FloatArray,
         r_vel: FloatArray, r_acc: FloatArray, u_ext: FloatArray, theta: FloatArray, omega: FloatArray, t_m0: float,
         integ0: float, limit: float) -> tuple[FloatArray, FloatArray]:
    """One run of the kernel; returns the recorded samples (rows as in ``_kernel``) and the metrics."""
    kern = kernel_module()
    n = chain.n
    plant, fmeth, spring = plant_arrays(chain, kern)
    par, ipar = parameters(kern, h, n_steps, rec_every, mode, loop, float(load_torque), alpha_c, nb, lp_alpha,
                            periods, float(t_m0), float(integ0), float(limit))
    # one block for every recorded series: one allocation (large ones get huge pages), rows contiguous
    rec = np.empty((3 * n + 2, n_steps // rec_every + 1))
    metrics = np.zeros(kern.N_METRICS_BASE + max(n - 1, 1))
    run = kern.run_two if n == 2 else kern.run_chain
    tab_x, tab_k = spring_table(chain)
    status, k, j = run(plant, fmeth, spring, tab_x, tab_k, par, ipar, r_pos, r_vel, r_acc, u_ext,
                       np.ascontiguousarray(theta, dtype=float), np.ascontiguousarray(omega, dtype=float), rec, metrics)
    if status != 0:
        raise diverged(chain, h, int(k), int(j), limit, loop)
    return rec, metrics


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
    check_step(chain.with_(stiffness=k_sets.max(axis=0)), h)
    n_cur, n_vel, n_pos = loop_periods(loop, h)
    t_end = float(reference.time[-1]) if duration is None else float(duration)
    n_steps = round(t_end / h)
    t = np.arange(n_steps + 1) * h
    r_pos, r_vel, r_acc = (np.ascontiguousarray(a, dtype=float) for a in reference.resample(t))
    alpha_c, nb, lp_alpha = loop_filters(loop, h, n_cur, n_vel)
    theta, omega = initial_state(chain, float(r_pos[0]), load_torque)
    limit = speed_limit if speed_limit is not None else max(1e4, 100.0 * float(np.max(np.abs(r_vel))))
    kern = kernel_module()
    n = chain.n
    plant, fmeth, spring = plant_arrays(chain, kern)
    # metrics only: the kernel records a single sample (record_every beyond the run)
    par, ipar = parameters(kern, h, n_steps, n_steps + 1, 0, loop, float(load_torque), alpha_c, nb, lp_alpha,
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
    # a swept stiffness replaces the chain's position table (the swept values hold along the move)
    tab_x, tab_k = spring_table(chain) if stiffness is None else (np.zeros(0), np.zeros(0))

    def run_range(lo: int, hi: int) -> None:
        rec = np.empty((3 * n + 2, 1))
        for s in range(lo, hi):
            st, _, _ = run(plant, fmeth, springs[s], tab_x, tab_k, pars[s], ipar, r_pos, r_vel, r_acc, u_none,
                           theta.copy(), omega.copy(), rec, metrics[s])
            status[s] = st != 0

    # the kernel releases the GIL: plain threads run the simulations on all cores, in small chunks
    # so that runs stopped early by divergence do not leave a core idle
    workers = max(1, min(thread_count(), s_count))
    chunk = max(1, s_count // (8 * workers))
    bounds = [(lo, min(lo + chunk, s_count)) for lo in range(0, s_count, chunk)]
    if workers == 1:
        for lo, hi in bounds:
            run_range(lo, hi)
    else:
        from concurrent.futures import ThreadPoolExecutor  # only here: its import costs 20 ms

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
