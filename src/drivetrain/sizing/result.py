"""Sizing: the duty cycle of an axis, checked against a given motor or a catalog selection.

``size(axis)`` is the orchestrator behind ``drivetrain size``: profile -> duty cycle ->
metrics -> motor checks -> ``SizingResult`` (JSON of docs/axis-file.md, tables, plots).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.axis.model import Axis, MotorData, load_axis, parse_axis
from drivetrain.duty.cycle import DutyCycle, duty_cycle, load_metrics
from drivetrain.physics.acceleration import acceleration_power, minimum_accel_time, minimum_decel_time, operation_power
from drivetrain.sizing.checks import Check, running_torque
from drivetrain.sizing.motor_fit import MotorArrays, demand, fit_motors
from drivetrain.version import __version__

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
        """True when the axis's own checks (slip, guide, brake, gearbox ratings, mechanism, drive) and the
        given motor or a candidate pass."""
        own = [self.extras[k]["ok"] for k in ("slip_check", "guide", "brake_check", "gearbox_checks", "drive")
               if k in self.extras]
        own += [c["ok"] for c in self.extras.get("mechanism_checks", [])]
        if not all(own):
            return False
        if self.motor is not None:
            return bool(self.motor["ok"])
        if self.selection is not None:
            # the selection's best passing candidate, with a drive that can be ordered (drive_select._walk)
            return "_best" in self.selection and "drive_advice" not in self.selection
        return True

    def to_dict(self) -> dict[str, Any]:
        """The JSON result of docs/axis-file.md (keys carry their unit)."""
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


def gearbox_rating_checks(axis: Axis, duty: DutyCycle, motor: MotorData | None,
                          strict: bool = False) -> dict[str, Any] | None:
    """Every rating of each gearbox in ``transmission:`` that has a rating or a catalog id, checked
    by ``checks.gearbox_ratings`` against the gearbox's own output torque and input speed over
    the cycle; the emergency-stop torque needs a motor (given, or the selected one). A rating
    that is not given is reported unknown, not passed; ``strict`` makes an unknown fail.
    """
    from drivetrain.duty.cycle import gearbox_split_at_motor_peak
    from drivetrain.physics.averages import cubic_mean
    from drivetrain.physics.torque_split import gearbox_peak_torque
    from drivetrain.physics.transmission import GearboxSpec
    from drivetrain.sizing.checks import GEARBOX_CHECKS, gearbox_ratings, shock_factor

    margins = axis.spec.motor.margins if axis.spec.motor is not None else None
    tm, sm = (margins.torque, margins.speed) if margins is not None else (1.0, 1.0)
    shock = shock_factor(duty.period, margins.gearbox_shock_factor if margins is not None else None)
    out: list[dict[str, Any]] = []
    from drivetrain.axis.resolve import resolve_transmission

    specs = resolve_transmission(axis.spec.transmission)  # a catalog row brings its ratings
    first_gearbox = next((k for k, st in enumerate(axis.transmission) if st.kind == "gearbox"), -1)
    for k, (spec, st) in enumerate(zip(specs, axis.transmission, strict=False)):
        if not isinstance(spec, GearboxSpec):
            continue
        ratings = (spec.rated_torque, spec.max_torque, spec.emergency_stop_torque, spec.max_input_speed,
                   spec.rated_input_speed)
        if spec.catalog is None and all(r is None for r in ratings):
            continue  # a bare ratio: nothing rated to check
        t_out, w_in = duty.stage_torque[k], np.abs(duty.stage_omega[k]) * st.ratio
        estop = math.nan
        if motor is not None:
            run = running_torque(duty.external)
            if k == first_gearbox:  # the lecture's split with everything before the mesh on the motor side
                estop = gearbox_split_at_motor_peak(axis, duty, motor.inertia, motor.peak_torque, run)[
                    "gearbox_output_torque_at_motor_peak_Nm"]
            else:
                j_before = sum(s.inertia for s in axis.transmission[: k + 1])
                estop = gearbox_peak_torque(motor.peak_torque, motor.inertia + j_before,
                                            duty.load_inertia - j_before, run) * st.ratio * st.efficiency
        got = gearbox_ratings(float(np.max(np.abs(t_out))), cubic_mean(t_out, duty.stage_omega[k], duty.weights),
                              float(np.max(w_in)), float(np.sum(duty.weights * w_in) / duty.period), estop,
                              t2b=_nan(spec.max_torque), t2n=_nan(spec.rated_torque),
                              t2not=_nan(spec.emergency_stop_torque), n1max=_nan(spec.max_input_speed),
                              n1n=_nan(spec.rated_input_speed), torque_margin=tm, speed_margin=sm, shock=shock)
        names = {"gearbox_peak_torque": "max_torque", "gearbox_rated_torque": "rated_torque",
                 "gearbox_emergency_stop_torque": "emergency_stop_torque",
                 "gearbox_max_input_speed": "max_input_speed", "gearbox_mean_input_speed": "rated_input_speed"}
        for name in GEARBOX_CHECKS:
            req, av, mar = (float(x) for x in got[name])
            rpm = name.endswith("speed")
            scale = 60.0 / (2.0 * math.pi) if rpm else 1.0
            status = "unknown" if math.isnan(mar) else ("pass" if mar >= 0.0 else "fail")
            check = {"name": name, "stage": st.name, "required": req * scale,
                     "available": None if math.isnan(av) else av * scale, "unit": "rpm" if rpm else "N*m",
                     "margin": mar if math.isfinite(mar) else None, "status": status,
                     "ok": status == "pass" or (status == "unknown" and not strict), "approximate": False}
            if status == "unknown":
                if name == "gearbox_emergency_stop_torque" and motor is None:
                    check["note"] = "needs the motor's peak torque: checked on the selected motor"
                elif name == "gearbox_peak_torque" and math.isnan(shock) and not math.isnan(av):
                    check["note"] = (f"{3600.0 / duty.period:.0f} cycles/h exceed the 1000/h that T2B holds for: "
                                     "set motor.margins.gearbox_shock_factor from the vendor's chart")
                else:
                    check["note"] = f"transmission[{k}].{names[name]} not given"
            out.append(check)
    if not out:
        return None
    return {"checks": out, "ok": all(c["ok"] for c in out),
            "unknown": [f"{c['stage']}: {c['name']}" for c in out if c["status"] == "unknown"]}


def _nan(x: float | None) -> float:
    return math.nan if x is None else float(x)


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


def size(axis: Axis | dict[str, Any] | str | Path, points_per_phase: int = 64,
         all_pairs: bool = False, *, duty: DutyCycle | None = None,
         selector: Callable[..., dict[str, Any]] | None = None, drives: bool = True) -> SizingResult:
    """Size an axis: its duty cycle at the motor shaft, the given motor's checks or a selection.

    A selection lists the best configuration of each motor; ``all_pairs`` lists every passing
    motor-gearbox pair instead (``drivetrain size --all``).

    For callers that size many axes (a study): ``duty`` is the axis's duty cycle when the caller
    has it already; ``selector`` stands in for ``selection.select`` (same arguments; an answer
    with the same keys, of which it may leave out those it did not compute); ``drives=False``
    leaves out the drive post-pass of a selection (the ``drive``, ``electrical`` and ``regen``
    blocks of its candidates), which changes no other key.
    """
    if isinstance(axis, (str, Path)):
        axis = load_axis(axis)
    elif isinstance(axis, dict):
        axis = parse_axis(axis)
    if duty is None:
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
    strict = bool(axis.spec.motor is not None and axis.spec.motor.select is not None
                  and axis.spec.motor.select.unknown == "fail")
    if axis.motor is not None:
        result.motor = motor_result(axis, duty, axis.motor)
        for key in ("drive", "regen"):  # the electrical half's blocks sit beside the motor's
            block = result.motor.pop(f"_{key}", None)
            if block is not None:
                result.extras[key] = block
        gear = gearbox_rating_checks(axis, duty, axis.motor)
    elif axis.spec.motor is not None and axis.spec.motor.select is not None:
        from drivetrain.sizing.drive_select import attach_drives, orderable
        from drivetrain.sizing.selection import select

        spec, margins = axis.spec.motor.select, axis.spec.motor.margins
        chosen = (selector or select)(axis, duty, spec, margins, all_pairs=all_pairs)
        judge = None
        if axis.requirements is not None:
            # the dynamic rule lives in the dynamics layer, above this one: looked up by name
            # (docs/architecture.md), the pattern of the report's lookup
            import importlib

            judge = importlib.import_module("drivetrain.dynamics.dynamic_selection").Judge(axis)
        chosen = orderable(axis, duty, chosen, None if selector is None else  # the whole ranking, if needed
                           lambda: select(axis, duty, spec, margins, all_pairs=all_pairs), judge)
        if judge is not None:
            chosen["selection"]["dynamics"] = judge.to_dict()
        if drives:
            attach_drives(axis, duty, chosen, axis.spec.motor.margins)  # the electrical post-pass
        result.candidates = chosen["candidates"]
        result.selection = chosen["selection"]
        gear = gearbox_rating_checks(axis, duty, _selected_motor(result.selection), strict)
        own = [st.name for st in axis.transmission if st.kind == "gearbox"]
        if own and not result.selection.get("gearbox_rows"):
            # the motors go direct onto the axis's own gearbox: say so, not "direct drive, ratio 1"
            result.selection["transmission_gearbox"] = ", ".join(own)
    elif axis.drive is not None:
        from drivetrain.errors import InputError

        raise InputError("drive", "a given drive needs a motor: give motor: {id: ...}, its parameters, "
                         "or motor: {select: ...}", has_value=False)
    else:
        gear = gearbox_rating_checks(axis, duty, None)
    if gear is not None:
        result.extras["gearbox_checks"] = gear
    return result


def _selected_motor(selection: dict[str, Any]) -> MotorData | None:
    """The selected catalog motor as MotorData (for the checks that need its peak torque), if any."""
    if "_best" not in selection:
        return None
    motors, _ = selection["_tables"]
    m = int(selection["_candidates"].motor[selection["_best"]])
    return MotorData(name=str(motors.ids[m]), inertia=float(motors.rotor_inertia[m]),
                     rated_torque=float(motors.rated_torque[m]), peak_torque=float(motors.peak_torque[m]),
                     rated_speed=float(motors.rated_speed[m]), max_speed=float(motors.max_speed[m]))
