"""The duty cycle: speed, torque and power at the motor shaft over the whole repeating cycle.

Data flow (docs/conventions.md): profile samples of the load -> mechanism external load -> each stage
from the load side to the motor side with the four-quadrant rule -> motor-shaft torque (rotor
excluded) -> metrics. With a motor, its rotor adds J_M alpha.

Metric definitions follow the lecture's selection pages (Yaskawa): T_rms = sqrt(sum T_k^2 t_k
/ t_c) over the whole cycle (dwells included: ERRATA, holding torque counts unless braked),
t_am = 2 pi N_M (J_M + J_L) / (60 (T_PM - T_L)), t_dm = ... / (60 (T_PM + T_L)),
P_o = 2 pi N_M T_L / 60, P_a = (2 pi N_M / 60)^2 J_L / t_a.
Integrals use the profile's quadrature weights (Simpson per phase, both ends of every phase),
so RMS and energies of piecewise-polynomial torques are exact to rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.physics.acceleration import acceleration_power, operation_power
from drivetrain.physics.averages import rms, signed_extreme
from drivetrain.physics.mechanisms.base import LinearLoad
from drivetrain.physics.stage import Stage, chain_inertia, torque_in
from drivetrain.physics.torque_split import gearbox_peak_torque, gearbox_torque_split
from drivetrain.units import to_rpm

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.motion.cycle import Cycle, Samples
    from drivetrain.physics.efficiency import EfficiencyModel

Array = NDArray[np.float64]


@dataclass(frozen=True)
class DutyCycle:
    """Motor-shaft quantities over one cycle, rotor excluded (SI arrays over samples).

    ``torque`` [N m] is what the load side demands at the motor shaft; ``external`` [N m] its
    external-load part (gravity, friction, thrust, springs) without inertia; ``omega`` [rad/s]
    and ``alpha`` [rad/s^2] the motor-shaft speed and acceleration; ``weights`` [s] the
    quadrature weights (sum = period); ``braked`` where a brake holds the load (no motor torque).
    ``stage_torque`` holds the output torque of every stage [N m], motor side first.
    """

    samples: Samples
    cycle: Cycle
    omega: Array
    alpha: Array
    torque: Array
    external: Array
    braked: NDArray[np.bool_]
    stage_torque: tuple[Array, ...]
    stage_omega: tuple[Array, ...]
    load_inertia: float
    period: float

    @property
    def t(self) -> Array:
        """Sample times [s]."""
        return np.asarray(self.samples.t, dtype=float)

    @property
    def weights(self) -> Array:
        """Quadrature weights [s]; sum(weights * f) integrates f over one period."""
        return np.asarray(self.samples.weights, dtype=float)

    def motor_torque(self, rotor_inertia: float | Array) -> Array:
        """Motor torque with the rotor [N m]: T + J_M alpha (zero where braked).

        ``rotor_inertia`` may be an array over candidates (shape (M,)): the result is (M, N).
        """
        j = np.asarray(rotor_inertia, dtype=float)
        t = self.torque + j[..., None] * self.alpha if j.ndim else self.torque + float(j) * self.alpha
        return np.where(self.braked, 0.0, t)

    def behind(self, stage: Stage, model: EfficiencyModel) -> DutyCycle:
        """The cycle one stage nearer the motor: what a motor sees through ``stage`` added at its shaft.

        The same stage-by-stage propagation as :func:`duty_from_samples` (four-quadrant rule,
        stage.torque_in), applied to this cycle's motor-shaft torque; the stage's inertia joins the
        load inertia (lecture: J_total = J_m + J_L / N^2). This is how the catalog selection puts a
        gearbox in front of the axis, so a selected candidate's cycle is this one behind its gearbox.
        """
        i = stage.ratio
        omega, alpha = self.omega * i, self.alpha * i
        direction = np.asarray(self.samples.direction, dtype=float)
        t_in, ext_in = torque_in(stage, self.torque, self.external, omega, alpha, direction, model)
        return DutyCycle(
            samples=self.samples, cycle=self.cycle, omega=omega, alpha=alpha,
            torque=np.where(self.braked, 0.0, t_in), external=np.where(self.braked, 0.0, ext_in), braked=self.braked,
            stage_torque=(self.torque, *self.stage_torque), stage_omega=(self.omega, *self.stage_omega),
            load_inertia=chain_inertia([stage], self.load_inertia), period=self.period,
        )


def duty_cycle(axis: Axis, points_per_phase: int = 64) -> DutyCycle:
    """Compute the motor-shaft duty cycle of ``axis`` over its profile."""
    cycle = axis.cycle()
    samples = cycle.sample(points_per_phase)
    return duty_from_samples(axis, cycle, samples)


def duty_from_samples(axis: Axis, cycle: Cycle, samples: Samples) -> DutyCycle:
    """Propagate the load's demand through the mechanism and the transmission to the motor shaft.

    Vectorised over samples; a Python loop runs only over the few stages.
    """
    x = np.asarray(samples.x, dtype=float)
    v = np.asarray(samples.v, dtype=float)
    a = np.asarray(samples.a, dtype=float)
    direction = np.asarray(samples.direction, dtype=float)
    thrust_override = np.asarray(samples.thrust, dtype=float)
    mech = axis.mechanism
    default_thrust = mech.load.thrust if isinstance(mech.load, LinearLoad) else mech.load.torque
    # The thrust as written, move by move; the load applies its thrust_mode (against the motion, or
    # signed) and nothing in a dwell, which holds gravity and springs only (physics.loads.process_thrust).
    thrust = np.where(np.isnan(thrust_override), default_thrust, thrust_override)
    breakaway = getattr(samples, "breakaway", None)
    if breakaway is None:
        breakaway = np.zeros(v.shape, dtype=bool)

    stage = mech.stage
    t_ext_in = mech.external_torque(x, v, direction, thrust, axis.gravity, breakaway)
    # The mechanism's "output" torque is the load force F (or load torque): F / i = F r.
    t_out = t_ext_in * stage.ratio
    ext_out = t_out
    omega = v * stage.ratio
    alpha = a * stage.ratio
    model = axis.efficiency_model
    torques: list[Array] = []
    omegas: list[Array] = []
    for st in reversed(axis.stages):
        if st is not stage:
            omega = omega * st.ratio
            alpha = alpha * st.ratio
        torques.append(t_out)
        omegas.append(omega / st.ratio)
        t_out, ext_out = torque_in(st, t_out, ext_out, omega, alpha, direction, model)
    if axis.spec.extra_inertia:
        t_out = t_out + axis.spec.extra_inertia * alpha
    braked = np.asarray(samples.braked, dtype=bool)
    if braked.any():  # a brake holds the load: no motor torque there
        t_out, ext_out = np.where(braked, 0.0, t_out), np.where(braked, 0.0, ext_out)
    return DutyCycle(
        samples=samples, cycle=cycle, omega=omega, alpha=alpha, torque=t_out,
        external=ext_out, braked=braked,
        stage_torque=tuple(reversed(torques)), stage_omega=tuple(reversed(omegas)),
        load_inertia=axis.load_inertia, period=float(cycle.period),
    )


def steady_state_torque(axis: Axis, load_speed: float) -> float:
    """Motor-shaft torque (rotor excluded) at a constant load speed [N m]: the run torque T_L.

    ``load_speed`` [m/s or rad/s], signed. Uses the same stage-by-stage propagation as the
    duty cycle (lecture, Load Torque formulas of the selection pages).
    """
    s = _Const(load_speed)
    duty = duty_from_samples(axis, _ConstCycle(), s)  # type: ignore[arg-type]
    return float(duty.torque[0])


class _Const:
    """A one-sample stand-in for profile samples at constant speed."""

    def __init__(self, v: float) -> None:
        self.t = np.zeros(1)
        self.x = np.zeros(1)
        self.v = np.array([v])
        self.a = np.zeros(1)
        self.direction = np.array([np.sign(v)])
        self.thrust = np.array([np.nan])
        self.braked = np.zeros(1, dtype=bool)
        self.breakaway = np.zeros(1, dtype=bool)
        self.holding = np.zeros(1, dtype=bool)
        self.weights = np.ones(1)
        self.phase = np.zeros(1, dtype=int)


class _ConstCycle:
    period = 1.0
    phases: tuple[()] = ()


def gearbox_split_at_motor_peak(axis: Axis, duty: DutyCycle, motor_inertia: float, motor_peak_torque: float,
                                run_torque: float) -> dict[str, Any]:
    """The lecture's gearbox torque split for the first gearbox from the motor, if any.

    Lecture, Dynamic Loading and Gearbox Sizing: k = J_M / (J_M + J_LR); at the motor's peak only
    T_GR = (1 - k)(T_M - T_L) + T_L passes the gearbox (motor side), so the gearbox need not be sized
    to the motor's peak. Everything that turns before the gearbox's gear mesh is on the motor's side of
    the split, reflected to the motor shaft: the rotor, ``extra_inertia`` (it turns with the rotor),
    every element before the gearbox and the gearbox's own input inertia (J / i^2 through the stages in
    front of it). At the gearbox output the torque is T_GR times the ratio and efficiency of every
    stage up to and including the gearbox. Torques [N m], inertias [kg m^2] at the motor shaft.
    """
    for k, st in enumerate(axis.transmission):
        if st.kind != "gearbox":
            continue
        j_before = axis.spec.extra_inertia + chain_inertia(list(axis.transmission[: k + 1]))
        j_motor_side = motor_inertia + j_before
        j_lr = duty.load_inertia - j_before
        t_gr = gearbox_peak_torque(motor_peak_torque, j_motor_side, j_lr, run_torque)
        through = math.prod(s.ratio * s.efficiency for s in axis.transmission[: k + 1])
        return {"gearbox_torque_split_k": gearbox_torque_split(j_motor_side, j_lr),
                "gearbox_output_torque_at_motor_peak_Nm": t_gr * through,
                "gearbox_output_peak_torque_Nm": float(np.max(np.abs(duty.stage_torque[k])))}
    return {}


def phase_table(duty: DutyCycle, torque: Array) -> list[dict[str, Any]]:
    """Every accel, run, decel and dwell in order, with its span, largest torque (signed) and top speed.

    One pass over the samples (linear in their number): the samples are grouped by phase with a
    stable sort (already in order: the cycle is sampled in time), each group's extremes by reduceat.
    """
    phases = duty.cycle.phases
    phase_idx = np.asarray(duty.samples.phase)
    order = np.argsort(phase_idx, kind="stable") if np.any(np.diff(phase_idx) < 0) else None
    idx = phase_idx if order is None else phase_idx[order]
    t = np.asarray(torque, dtype=float) if order is None else np.asarray(torque, dtype=float)[order]
    w = np.abs(np.asarray(duty.omega, dtype=float)) if order is None else np.abs(np.asarray(duty.omega)[order])
    starts = np.searchsorted(idx, np.arange(len(phases)), side="left")
    ends = np.searchsorted(idx, np.arange(len(phases)), side="right")
    has = ends > starts
    extreme = np.zeros(len(phases))
    top_w = np.zeros(len(phases))
    if t.size and has.any():
        at = starts[has]
        mag = np.abs(t)
        top_w[has] = np.maximum.reduceat(w, at)
        biggest = np.zeros(len(phases))
        biggest[has] = np.maximum.reduceat(mag, at)
        # the value of largest magnitude with its sign, the first such sample (as signed_extreme)
        hits = np.flatnonzero(mag == biggest[idx])
        groups, first = np.unique(idx[hits], return_index=True)
        extreme[groups] = t[hits[first]]
    rows: list[dict[str, Any]] = []
    for k, ph in enumerate(phases):
        rows.append({
            "kind": ph.kind, "move": ph.move, "step": ph.step, "t0_s": float(ph.t0),
            "t1_s": float(ph.t1), "torque_Nm": float(extreme[k]) if has[k] else 0.0,
            "speed_rpm": float(to_rpm(top_w[k])) if has[k] else 0.0,
        })
    return rows


def first_move_torques(duty: DutyCycle, torque: Array) -> dict[str, float]:
    """Signed accel, run and decel torques of the first move, and the holding torque [N m]."""
    phase_idx = np.asarray(duty.samples.phase)
    out = {"accel": 0.0, "run": 0.0, "decel": 0.0}
    first = next((ph.move for ph in duty.cycle.phases if ph.kind != "dwell"), None)
    for k, ph in enumerate(duty.cycle.phases):
        if ph.move == first and ph.kind in out:
            mask = phase_idx == k
            out[ph.kind] = signed_extreme(torque[mask])
    holding = np.asarray(duty.samples.holding, dtype=bool)
    out["holding"] = signed_extreme(torque[holding])
    return out


@dataclass
class Demand:
    """What the load demands of the motor over the cycle, at the motor shaft: ``SizingResult.metrics``, the
    rotor excluded (:func:`demand_of`; with a torque that includes a rotor, that motor's own figures). Its
    :meth:`to_dict` is the demand's keys at the top of the JSON (docs/axis-file.md).

    Attributes
    ----------
    cycle_time_s : float
        The cycle's period [s].
    load_inertia_kgm2 : float
        The load's inertia reflected to the motor shaft, every stage included [kg m^2].
    peak_torque_Nm : float
        The largest torque magnitude over the cycle [N m].
    peak_torque_speed_rpm : float
        The speed at that peak [rpm].
    rms_torque_Nm : float
        The RMS torque over the cycle [N m].
    max_speed_rpm : float
        The largest speed magnitude [rpm].
    mean_speed_rpm : float
        The time-weighted mean speed magnitude [rpm].
    accel_torque_Nm : float
        The signed torque of largest magnitude in the first move's acceleration [N m].
    run_torque_Nm : float
        The same in the first move's constant-speed run [N m].
    decel_torque_Nm : float
        The same in the first move's deceleration [N m].
    holding_torque_Nm : float
        The same in the dwells the motor holds [N m].
    peak_power_W : float
        The largest shaft power magnitude [W].
    average_power_W : float
        The mean shaft power over the cycle [W].
    regen_energy_J : float
        The energy the shaft returns per cycle [J].
    operation_power_W : float
        The lecture's operation power at top speed and run torque [W].
    acceleration_power_W : float or None
        The lecture's acceleration power over the first acceleration ramp [W]; None without one.
    segments : list of dict
        Every accel, run, decel and dwell in order (:func:`phase_table`): its span [s], largest signed
        torque [N m] and top speed [rpm].
    """

    cycle_time_s: float
    load_inertia_kgm2: float
    peak_torque_Nm: float
    peak_torque_speed_rpm: float
    rms_torque_Nm: float
    max_speed_rpm: float
    mean_speed_rpm: float
    accel_torque_Nm: float
    run_torque_Nm: float
    decel_torque_Nm: float
    holding_torque_Nm: float
    peak_power_W: float
    average_power_W: float
    regen_energy_J: float
    operation_power_W: float
    acceleration_power_W: float | None
    segments: list[dict[str, Any]]

    def to_dict(self) -> dict[str, Any]:
        """The demand's keys of the JSON, in the order of the fields."""
        return {f: getattr(self, f) for f in _DEMAND_KEYS}


_DEMAND_KEYS = tuple(Demand.__dataclass_fields__)


def demand_of(duty: DutyCycle, torque: Array | None = None) -> Demand:
    """The load's demand at the motor shaft (rotor excluded unless ``torque`` includes it)."""
    t = duty.torque if torque is None else torque
    w = duty.weights
    power = t * duty.omega
    k_peak = int(np.argmax(np.abs(t)))
    per = first_move_torques(duty, t)
    top = float(np.max(np.abs(duty.omega)))
    ramp = next((ph.t1 - ph.t0 for ph in duty.cycle.phases if ph.kind == "accel"), 0.0)
    return Demand(
        cycle_time_s=duty.period,
        load_inertia_kgm2=duty.load_inertia,
        peak_torque_Nm=float(abs(t[k_peak])),
        peak_torque_speed_rpm=float(to_rpm(abs(duty.omega[k_peak]))),
        rms_torque_Nm=rms(t, w, duty.period),
        max_speed_rpm=float(to_rpm(np.max(np.abs(duty.omega)))),
        mean_speed_rpm=float(to_rpm(np.sum(w * np.abs(duty.omega)) / duty.period)),
        accel_torque_Nm=per["accel"],
        run_torque_Nm=per["run"],
        decel_torque_Nm=per["decel"],
        holding_torque_Nm=per["holding"],
        peak_power_W=float(np.max(np.abs(power))),
        average_power_W=float(np.sum(w * power) / duty.period),
        regen_energy_J=float(-np.sum(w * np.minimum(power, 0.0))),
        operation_power_W=operation_power(top, abs(per["run"])),
        acceleration_power_W=acceleration_power(top, duty.load_inertia, ramp) if ramp > 0 else None,
        segments=phase_table(duty, t),
    )


def load_metrics(duty: DutyCycle, torque: Array | None = None) -> dict[str, Any]:
    """:func:`demand_of` as the JSON's keys (the ``motor`` block's figures with its rotor)."""
    return demand_of(duty, torque).to_dict()
