"""Sizing: the duty cycle of an axis, checked against a given motor or a catalog selection.

``size(axis)`` is the orchestrator behind ``drivetrain size``: profile -> duty cycle ->
metrics -> motor checks -> ``SizingResult`` (JSON of design.md, tables, plots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain import __version__
from drivetrain.axis.model import Axis, MotorData, load_axis, parse_axis
from drivetrain.duty.cycle import (
    DutyCycle,
    acceleration_power,
    duty_cycle,
    load_metrics,
    minimum_accel_time,
    minimum_decel_time,
    operation_power,
)
from drivetrain.sizing.checks import Check
from drivetrain.sizing.motor_fit import MotorArrays, demand, fit_motors

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure


@dataclass
class SizingResult:
    """What the motor must deliver over the cycle, and how a motor (or candidates) fits.

    ``metrics`` is the load's demand at the motor shaft (rotor excluded); ``motor`` the same
    with the rotor and the checks of a given motor; ``candidates`` a catalog selection.
    """

    axis: Axis
    duty: DutyCycle
    metrics: dict[str, Any]
    motor: dict[str, Any] | None = None
    candidates: list[dict[str, Any]] = field(default_factory=list)
    selection: dict[str, Any] | None = None
    extras: dict[str, Any] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """True when the axis's own checks (slip, guide, brake, mechanism, drive) and the given motor or a
        candidate pass."""
        own = [self.extras[k]["ok"] for k in ("slip_check", "guide", "brake_check", "drive") if k in self.extras]
        own += [c["ok"] for c in self.extras.get("mechanism_checks", [])]
        if not all(own):
            return False
        if self.motor is not None:
            return bool(self.motor["ok"])
        if self.selection is not None:
            return bool(self.selection.get("passing", 0))
        return True

    def to_dict(self) -> dict[str, Any]:
        """The JSON result of design.md (keys carry their unit)."""
        from drivetrain.catalog import DATA_VERSION

        out: dict[str, Any] = {"axis": self.axis.name, "drivetrain_version": __version__,
                               "catalog_version": DATA_VERSION, "efficiency_model": self.axis.efficiency_model}
        out.update(self.metrics)
        out.update(self.extras)
        if self.motor is not None:
            out["motor"] = self.motor
        if self.selection is not None:
            out["selection"] = {k: v for k, v in self.selection.items() if not k.startswith("_")}
        if self.candidates:
            out["candidates"] = self.candidates
        return out

    def _repr_html_(self) -> str:
        """Jupyter display: the report's content with static plots.

        The report is a face above the result: it is looked up by name here, never imported, so
        the result does not depend on it (docs/architecture.md)."""
        import importlib

        return str(importlib.import_module("drivetrain.report").repr_html(self))

    def explain(self, model: str) -> str:
        """Why a catalog motor was accepted or rejected (needs a catalog selection)."""
        from drivetrain.errors import InputError
        from drivetrain.sizing.selection import explain

        if self.selection is None:
            raise InputError("--explain", "needs a catalog selection (motor: {select: ...})", model)
        return explain(self.selection, model)

    def series(self) -> dict[str, np.ndarray]:
        """The sampled cycle as columns (SI): time, load motion, motor-shaft speed and torque."""
        s = self.duty.samples
        cols = {"t_s": self.duty.t, "x": np.asarray(s.x), "v": np.asarray(s.v), "a": np.asarray(s.a),
                "omega_motor_rad_s": self.duty.omega, "alpha_motor_rad_s2": self.duty.alpha,
                "torque_load_Nm": self.duty.torque}
        if self.axis.motor is not None:
            cols["torque_motor_Nm"] = self.duty.motor_torque(self.axis.motor.inertia)
        return cols

    def to_pandas(self) -> pd.DataFrame:
        """The sampled cycle as a pandas DataFrame (pandas imported on demand)."""
        import pandas as pd

        return pd.DataFrame(self.series())

    def plot(self) -> Figure:
        """Matplotlib figure: load position and speed, motor-shaft torque over the cycle."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        cols = self.series()
        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
        linear = self.axis.mechanism.motion == "linear"
        axes[0].plot(cols["t_s"], cols["x"] * (1e3 if linear else 180 / math.pi))
        axes[0].set_ylabel("position [mm]" if linear else "position [deg]")
        axes[1].plot(cols["t_s"], cols["omega_motor_rad_s"] * 60 / (2 * math.pi))
        axes[1].set_ylabel("motor speed [rpm]")
        axes[2].plot(cols["t_s"], cols["torque_load_Nm"], label="load at motor shaft")
        if "torque_motor_Nm" in cols:
            axes[2].plot(cols["t_s"], cols["torque_motor_Nm"], label="motor (with rotor)")
        axes[2].set_ylabel("torque [N m]")
        axes[2].set_xlabel("time [s]")
        axes[2].legend()
        fig.suptitle(self.axis.name)
        fig.tight_layout()
        return fig


def ratio_for_inertia_ratio(load_inertia: float, motor_inertia: float, limit: float) -> float:
    """Smallest ratio that brings J_L / J_M down to ``limit``: i = sqrt(J_L / (limit J_M)) [-].

    ``load_inertia`` [kg m^2] at the gearbox output, ``motor_inertia`` [kg m^2]. Reflection
    J_L / i^2 (lecture, gear system-motor connections); machinemfg.com servo sizing, case one.
    """
    return math.sqrt(load_inertia / (limit * motor_inertia))


def optimal_ratio_pure_inertia(load_inertia: float, motor_inertia: float) -> float:
    """Ratio that maximises load acceleration for a purely inertial load: i = sqrt(J_L / J_M) [-].

    From alpha_L = T i / (J_M i^2 + J_L), maximal where d/di = 0, i.e. J_L / i^2 = J_M: the
    lecture's 1:1 ideal inertia match.
    """
    return math.sqrt(load_inertia / motor_inertia)


def motor_arrays(motors: list[MotorData]) -> MotorArrays:
    """Stack MotorData into arrays for ``fit_motors``."""
    return MotorArrays(
        inertia=np.array([m.inertia for m in motors]),
        rated_torque=np.array([m.rated_torque for m in motors]),
        peak_torque=np.array([m.peak_torque for m in motors]),
        rated_speed=np.array([m.rated_speed for m in motors]),
        max_speed=np.array([m.max_speed for m in motors]),
        stall_torque=np.array([np.nan if m.stall_torque is None else m.stall_torque for m in motors]),
        approximate=np.array([m.approximate_envelope for m in motors]),
    )


def motor_result(axis: Axis, duty: DutyCycle, motor: MotorData) -> dict[str, Any]:
    """The ``motor`` block of the JSON: demand with the rotor, lecture figures and checks."""
    margins = axis.spec.motor.margins if axis.spec.motor is not None else None
    d = demand(duty.omega, duty.alpha, duty.torque, duty.weights, duty.period, duty.load_inertia)
    fit = fit_motors(
        d, motor_arrays([motor]),
        torque_margin=margins.torque if margins else 1.0,
        rms_margin=(margins.rms_torque or margins.torque) if margins else 1.0,
        speed_margin=margins.speed if margins else 1.0,
        inertia_ratio_limit=margins.inertia_ratio if margins else 5.0,
    )
    t_m = duty.motor_torque(motor.inertia)
    with_rotor = load_metrics(duty, t_m)
    run = abs(with_rotor["run_torque_Nm"])
    n = d.max_speed
    first = _first_move_ramp_times(duty)
    checks: list[Check] = fit.checks(0)
    gearbox = _gearbox_split(axis, motor, duty, run)
    from drivetrain.sizing.electrical import electrical_answer

    elec = electrical_answer(axis, duty, motor, margins)
    checks = checks + elec.checks
    ok = bool(fit.ok[0]) and all(c.ok for c in elec.checks)
    failed = fit.first_failure(0) or next((f"{c.name}: required {c.required:.4g} {c.unit} > available "
                                           f"{c.available:.4g} {c.unit} ({c.margin * 100:.1f} %)"
                                           for c in elec.checks if not c.ok), "")
    extra: dict[str, Any] = dict(elec.motor)
    if elec.curve is not None:
        extra["supply_curve"] = elec.curve
    if elec.drive is not None:
        extra["_drive"] = elec.drive
    if elec.regen is not None:
        extra["_regen"] = elec.regen
    return {
        "name": motor.name,
        "source": motor.source,
        "unverified": bool(motor.unverified_reason),
        "unverified_reason": motor.unverified_reason or None,
        "inertia_kgm2": motor.inertia,
        "inertia_ratio": duty.load_inertia / motor.inertia,
        "peak_torque_Nm": with_rotor["peak_torque_Nm"],
        "rms_torque_Nm": with_rotor["rms_torque_Nm"],
        "accel_torque_Nm": with_rotor["accel_torque_Nm"],
        "run_torque_Nm": with_rotor["run_torque_Nm"],
        "decel_torque_Nm": with_rotor["decel_torque_Nm"],
        "holding_torque_Nm": with_rotor["holding_torque_Nm"],
        "peak_power_W": with_rotor["peak_power_W"],
        "regen_energy_J": with_rotor["regen_energy_J"],
        "min_accel_time_s": minimum_accel_time(n, motor.inertia, duty.load_inertia, motor.peak_torque, run),
        "min_decel_time_s": minimum_decel_time(n, motor.inertia, duty.load_inertia, motor.peak_torque, run),
        "operation_power_W": operation_power(n, run),
        "acceleration_power_W": acceleration_power(n, duty.load_inertia, first) if first > 0 else None,
        **gearbox,
        **extra,
        "ok": ok,
        "failed": failed,
        "checks": [c.to_dict() for c in checks],
        "segments": with_rotor["segments"],
    }


def _gearbox_split(axis: Axis, motor: MotorData, duty: DutyCycle, run_torque: float) -> dict[str, Any]:
    """The lecture's gearbox torque split for the first gearbox from the motor, if any
    (``duty.cycle.gearbox_split_at_motor_peak``)."""
    from drivetrain.duty.cycle import gearbox_split_at_motor_peak

    return gearbox_split_at_motor_peak(axis, duty, motor.inertia, motor.peak_torque, run_torque)


def _brake_check(axis: Axis, duty: DutyCycle) -> dict[str, Any] | None:
    """A brake's holding torque against the torque it must hold in braked dwells [N m].

    The brake holds what the load side applies at its shaft at standstill (gravity, springs):
    the output torque of the brake's stage in every dwell marked ``holding: brake``.
    """
    braked = np.asarray(duty.samples.braked, dtype=bool)
    for k, st in enumerate(axis.transmission):
        if st.kind != "brake" or st.holding_torque is None:
            continue
        need = float(np.max(np.abs(duty.stage_torque[k][braked]))) if braked.any() else 0.0
        margin = st.holding_torque / need - 1.0 if need > 0 else math.inf
        return {"name": "brake_holding_torque", "required": need, "available": st.holding_torque, "unit": "N*m",
                "margin": margin, "ok": margin >= 0.0, "approximate": False}
    return None


def _first_move_ramp_times(duty: DutyCycle) -> float:
    """Duration of the first move's acceleration phase [s] (0 if none)."""
    for ph in duty.cycle.phases:
        if ph.kind == "accel":
            return float(ph.t1 - ph.t0)
    return 0.0


def size(axis: Axis | dict[str, Any] | str | Path, points_per_phase: int = 64) -> SizingResult:
    """Size an axis: its duty cycle at the motor shaft, the given motor's checks or a selection."""
    if isinstance(axis, (str, Path)):
        axis = load_axis(axis)
    elif isinstance(axis, dict):
        axis = parse_axis(axis)
    duty = duty_cycle(axis, points_per_phase)
    metrics = load_metrics(duty)
    result = SizingResult(axis=axis, duty=duty, metrics=metrics)
    from drivetrain.duty.sanity import sanity_warnings

    result.extras["warnings"] = sanity_warnings(axis, duty)
    if axis.spec.guide is not None and axis.mechanism.motion == "linear":
        from drivetrain.physics.guides import guide_report

        result.extras["guide"] = guide_report(axis, duty)
    if axis.mechanism.slip_limit is not None:
        from drivetrain.physics.guides import slip_check

        incline = getattr(axis.mechanism.load, "incline", 0.0)
        result.extras["slip_check"] = slip_check(np.asarray(duty.samples.a), axis.mechanism.slip_limit, incline,
                                                 axis.gravity)
    from drivetrain.sizing.mechanism_checks import mechanism_checks

    checks = mechanism_checks(axis, duty)
    if checks:
        result.extras["mechanism_checks"] = checks
    brake = _brake_check(axis, duty)
    if brake is not None:
        result.extras["brake_check"] = brake
    if axis.motor is not None:
        result.motor = motor_result(axis, duty, axis.motor)
        for key in ("drive", "regen"):  # the electrical half's blocks sit beside the motor's
            block = result.motor.pop(f"_{key}", None)
            if block is not None:
                result.extras[key] = block
    elif axis.drive is not None:
        from drivetrain.errors import InputError

        raise InputError("drive", "a given drive needs a given motor (motor: {id: ...} or its parameters); "
                         "catalog selection with drives is not available yet", has_value=False)
    elif axis.spec.motor is not None and axis.spec.motor.select is not None:
        from drivetrain.sizing.selection import select

        chosen = select(axis, duty, axis.spec.motor.select, axis.spec.motor.margins)
        result.candidates = chosen["candidates"]
        result.selection = chosen["selection"]
    return result
