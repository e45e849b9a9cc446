"""What a time simulation returns: the recorded series at the motor shaft and the figures of merit
(following and load error, settling, overshoot, vibration, torques, energy), with ``to_dict``,
``to_pandas`` and ``plot``; and the chain's mechanical energy used to check the integrator.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.control import ServoLoop

FloatArray = NDArray[np.float64]


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
        step: the integration step [s].
        step_converged: the automatic step passed ``simulate``'s convergence test (False: it was
            refined as far as allowed without passing; None: the step was given).
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
        self.step = math.nan
        self.step_converged: bool | None = None
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
            "step_s": self.step,
            "step_converged": self.step_converged,
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
