"""The answer of a sizing, ``SizingResult``, and the blocks of it that the pipeline's stages build
(``sizing.pipeline``): a given motor's checks, the gearbox ratings, the brake, the verdict.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.axis.model import Axis, MotorData
from drivetrain.duty.cycle import Demand, DutyCycle, load_metrics
from drivetrain.physics.acceleration import acceleration_power, minimum_accel_time, minimum_decel_time, operation_power
from drivetrain.sizing.answer import Candidate, MotorAnswer, SelectionSummary
from drivetrain.sizing.axis_blocks import (
    GearboxCheck,
    GearboxChecks,
    GuideReport,
    MechanismCheck,
    Modes,
    RatingCheck,
)
from drivetrain.sizing.checks import Check, running_torque
from drivetrain.sizing.electrical import DriveAnswer, Regen
from drivetrain.sizing.motor_fit import MotorArrays, demand, fit_motors
from drivetrain.sizing.verdict import Status, Unknown, collect_unknowns, failures, unknown_fails
from drivetrain.version import __version__

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

    from drivetrain.sizing.candidates import Ranking


@dataclass
class SizingResult:
    """What the motor must deliver over the cycle, and how a motor (or candidates) fits: the answer of
    the sizing pipeline (``sizing.pipeline.size_many``), one per axis.

    Attributes
    ----------
    axis : Axis
        The axis sized (SI).
    duty : DutyCycle
        The duty cycle at the motor shaft (sampled load motion, motor-shaft speed [rad/s],
        acceleration [rad/s^2] and load torque [N m] through every stage, rotor excluded).
    metrics : Demand
        The load's demand at the motor shaft, rotor excluded (``duty.cycle.Demand``): RMS, peak,
        accel/run/decel torque [N m], speeds [rpm], load inertia [kg m^2], power [W], energy [J] (fields carry
        their unit).
    motor : MotorAnswer or None
        A given motor: the demand with its rotor, the figures of the lecture and every check
        (required, available, margin). None for a catalog selection or no motor.
    candidates : list of Candidate
        A catalog selection's listed candidates, each with its checks (empty without a selection).
    selection : SelectionSummary or None
        A catalog selection's summary: counts, the ``selected`` candidate, next smaller motor, advice.
    warnings : list of str
        What is implausible in the axis file, in words (empty when nothing is).
    guide : GuideReport or None
        The carriage's forces [N], moments [N m] and the guide's rating checks (``sizing.axis_blocks``), for a
        linear axis with ``guide:``.
    slip_check : RatingCheck or None
        The load's slip on its carrier [m/s^2], for a mechanism with a slip limit.
    mechanism_checks : list of MechanismCheck
        The limits of the screw, nut, guide life, belt and rack the axis file has ratings for (empty if none).
    brake_check : RatingCheck or None
        A brake stage's holding torque against the braked dwells [N m].
    drive : DriveAnswer or None
        A given motor's drive (``sizing.electrical.DriveAnswer``); a catalog selection's are in
        ``selection.selected.drive`` and each listed candidate's ``drive``.
    regen : Regen or None
        A given motor's regeneration block (``sizing.electrical.Regen``); the selected candidate's is
        ``selection.selected.regen``.
    gearbox_checks : GearboxChecks or None
        The ratings of the rated gearboxes of ``transmission:`` with the given or selected motor.
    load_share : float or None
        A gantry share's fraction of the load [-] (``machine.axes.size_share``); None for a whole axis.
    ranking : Ranking or None
        The evaluated candidates behind ``candidates`` and ``selection`` (not part of the JSON).
    modes : Modes or None
        f1 across the stroke and the servo-bandwidth check (``sizing.axis_blocks.Modes``), where the modes
        stage ran and the mechanism has stiffness data; reported, not part of ``ok``.
    """

    axis: Axis
    duty: DutyCycle
    metrics: Demand
    motor: MotorAnswer | None = None
    candidates: list[Candidate] = field(default_factory=list)
    selection: SelectionSummary | None = None
    warnings: list[str] = field(default_factory=list)
    guide: GuideReport | None = None
    slip_check: RatingCheck | None = None
    mechanism_checks: list[MechanismCheck] = field(default_factory=list)
    brake_check: RatingCheck | None = None
    drive: DriveAnswer | None = None
    regen: Regen | None = None
    gearbox_checks: GearboxChecks | None = None
    load_share: float | None = None
    ranking: Ranking | None = None
    modes: Modes | None = None

    @property
    def ok(self) -> bool:
        """Whether the answer stands: ``status != "fail"`` (kept for compatibility; :attr:`status` says more).
        The order sheet's open points never fail an answer, so it is not built here."""
        if not verdict(self):
            return False
        return not (unknown_fails(self.axis) and collect_unknowns(self, sheet=False))

    @property
    def status(self) -> Status:
        """The verdict in three outcomes (docs/checks.md, "The verdict"): ``"pass"`` (every check judged and
        passed), ``"pass with unknowns"`` (every judged check passed, :attr:`unknowns` could not be judged)
        or ``"fail"`` (a check fails; or, under ``motor.select.unknown: fail``, a check cannot be judged)."""
        return self._verdict()[0]

    def _verdict(self, sheet: Any = True) -> tuple[Status, list[Unknown]]:
        """:attr:`status` and :attr:`unknowns` from one collection (``sheet``: the order sheet where the caller
        built it)."""
        unknowns = collect_unknowns(self, sheet)
        if not verdict(self):
            return "fail", unknowns
        if not unknowns:
            return "pass", unknowns
        # an order-sheet open point (check "order_code") is no check: unknown: fail does not fail on it
        checks = any(u.check != "order_code" for u in unknowns)
        return ("fail" if unknown_fails(self.axis) and checks else "pass with unknowns"), unknowns

    @property
    def unknowns(self) -> list[Unknown]:
        """Every check of the answer that could not be judged, with the part it concerns and what would
        decide it (:func:`collect_unknowns`)."""
        return collect_unknowns(self)

    def verdict_line(self) -> str:
        """The verdict in one line, as the CLI prints it last: ``PASS``, ``PASS WITH UNKNOWNS: check (why),
        ...`` or ``FAIL: ...`` (what fails, then what could not be judged)."""
        status, unknowns = self._verdict()
        unknown = [f"{u.check} ({u.decide})" for u in unknowns]
        if status == "pass":
            return "PASS"
        if status == "pass with unknowns":
            return "PASS WITH UNKNOWNS: " + ", ".join(unknown)
        failing = failures(self)
        if not failing and unknown:  # unknown: fail
            failing = [f"not judged under motor.select.unknown: fail: {', '.join(unknown)}"]
        elif unknown:
            failing.append(f"not judged: {', '.join(unknown)}")
        return "FAIL: " + "; ".join(failing)

    def to_dict(self) -> dict[str, Any]:
        """The JSON result of docs/axis-file.md (keys carry their unit), from the fields in this order:
        the axis, versions, ``metrics``, the axis's own blocks (:meth:`own_blocks`), ``motor``, ``selection``,
        ``candidates``, ``modes``, the
        order sheet (``order``: ``sizing.order.order_sheet``) and last the ``verdict`` (:attr:`status` and
        :attr:`unknowns`)."""
        from drivetrain.catalog import DATA_VERSION

        out: dict[str, Any] = {"axis": self.axis.name, "drivetrain_version": __version__,
                               "catalog_version": DATA_VERSION, "efficiency_model": self.axis.efficiency_model}
        out.update(self.metrics.to_dict())
        out.update(self.own_blocks())
        if self.motor is not None:
            out["motor"] = self.motor.to_dict()
        if self.selection is not None:
            out["selection"] = self.selection.to_dict()
        if self.candidates:
            out["candidates"] = [c.to_dict() for c in self.candidates]
        if self.modes is not None:
            out["modes"] = self.modes.to_dict()
        import importlib  # the order sheet reads the result: looked up by name, so no circle of files

        sheet = importlib.import_module("drivetrain.sizing.order").order_sheet(self)
        out["order"] = sheet.to_dict()
        status, unknowns = self._verdict(sheet)  # the sheet built once, for the order block and the verdict
        out["verdict"] = {"status": status, "unknowns": [u.to_dict() for u in unknowns]}
        return out

    def own_blocks(self) -> dict[str, Any]:
        """The JSON of the axis's own blocks and a given motor's drive, in the answer's order: ``warnings``,
        ``guide``, ``slip_check``, ``mechanism_checks``, ``brake_check``, ``drive``, ``regen``,
        ``gearbox_checks``; a gantry share (which keeps its whole axis's checks) puts its ``load_share`` after
        them and its drive's blocks last. A block that does not apply is left out."""
        out: dict[str, Any] = {"warnings": list(self.warnings)}
        for key in ("guide", "slip_check"):
            block = getattr(self, key)
            if block is not None:
                out[key] = block.to_dict()
        if self.mechanism_checks:
            out["mechanism_checks"] = [c.to_dict() for c in self.mechanism_checks]
        if self.brake_check is not None:
            out["brake_check"] = self.brake_check.to_dict()
        drive = {k: b.to_dict() for k, b in (("drive", self.drive), ("regen", self.regen)) if b is not None}
        if self.load_share is None:
            out.update(drive)
        if self.gearbox_checks is not None:
            out["gearbox_checks"] = self.gearbox_checks.to_dict()
        if self.load_share is not None:
            out["load_share"] = self.load_share
            out.update(drive)
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

        if self.selection is None or self.ranking is None:
            raise InputError("--explain", "needs a catalog selection (motor: {select: ...})", model)
        text = explain(self.selection, self.ranking, model)
        if self.selection.dynamics:  # the dynamic checks: the dynamics layer's, looked up by name
            import importlib

            text += importlib.import_module("drivetrain.dynamics.dynamic_selection").explain_dynamics(
                self.selection.dynamics, model)
        return text

    def series(self) -> dict[str, np.ndarray]:
        """The sampled cycle as columns (SI): time, load motion, motor-shaft speed and torque."""
        s = self.duty.samples
        cols = {"t_s": self.duty.t, "x": np.asarray(s.x), "v": np.asarray(s.v), "a": np.asarray(s.a),
                "omega_motor_rad_s": self.duty.omega, "alpha_motor_rad_s2": self.duty.alpha,
                "torque_load_Nm": self.duty.torque}
        if self.axis.motor is not None:
            cols["torque_motor_Nm"] = self.duty.motor_torque(self.axis.motor.inertia)
        return cols

    def motor_cycle(self) -> tuple[DutyCycle, float, str] | None:
        """The motor's own cycle: the given motor's (the axis's duty cycle), or the selected candidate's
        (the axis's cycle behind its catalog gearbox, as the selection checked it); with its rotor inertia
        [kg m^2] and its name. None without a given or selected motor."""
        if self.axis.motor is not None:
            return self.duty, self.axis.motor.inertia, self.axis.motor.name
        if self.ranking is not None and self.ranking.best is not None:
            from drivetrain.sizing.selection import candidate_cycle

            cycle, rotor = candidate_cycle(self.axis, self.duty, self.ranking)
            return cycle, rotor, str(self.ranking.motors.ids[self.ranking.candidates.motor[self.ranking.best]])
        return None

    def torques(self) -> pd.DataFrame:
        """The answer as the report's table reads it: the demand at the motor shaft without the rotor
        (``demand``), the given or selected motor's own figures with its rotor inertia (``motor``) and
        what the motor offers (``rating``: peak and rated torque [N m], max speed [rpm], rotor inertia
        [kg m^2]); one row per quantity, its unit in its name."""
        import pandas as pd

        rows = ("peak_torque_Nm", "rms_torque_Nm", "accel_torque_Nm", "run_torque_Nm", "decel_torque_Nm",
                "holding_torque_Nm", "max_speed_rpm", "peak_power_W", "regen_energy_J", "load_inertia_kgm2",
                "rotor_inertia_kgm2")
        demand = {k: getattr(self.metrics, k, None) for k in rows}
        motor: dict[str, Any] = dict.fromkeys(rows)
        rating: dict[str, Any] = dict.fromkeys(rows)
        own = self.motor_cycle()
        name = "motor"
        if own is not None:
            cycle, rotor, name = own
            with_rotor = load_metrics(cycle, cycle.motor_torque(rotor))
            motor.update({k: with_rotor.get(k) for k in rows})
            motor["rotor_inertia_kgm2"] = rotor
            motor["load_inertia_kgm2"] = cycle.load_inertia
            data = self.axis.motor if self.axis.motor is not None else self._selected_motor()
            if data is not None:
                rating.update({"peak_torque_Nm": data.peak_torque, "rms_torque_Nm": data.rated_torque,
                               "max_speed_rpm": data.max_speed * 60.0 / (2.0 * math.pi),
                               "rotor_inertia_kgm2": data.inertia})
        frame = pd.DataFrame({"demand": demand, "motor": motor, "rating": rating}, index=list(rows))
        frame.attrs["motor"] = name
        return frame

    def _selected_motor(self) -> MotorData | None:
        return None if self.ranking is None else selected_motor(self.ranking)

    def to_pandas(self) -> pd.DataFrame:
        """The sampled cycle as a pandas DataFrame (pandas imported on demand), in SI: time ``t_s``; the
        load side (``load_x``, ``load_v``, ``load_a``: the load's position, speed and acceleration, m or
        rad); the demand at the axis input without a rotor (``shaft_speed_rad_s``,
        ``shaft_acceleration_rad_s2``, ``shaft_torque_Nm``); and the motor side of the given or selected
        motor, behind its catalog gearbox where it has one (``motor_speed_rad_s``,
        ``motor_acceleration_rad_s2``, ``motor_torque_Nm`` with its rotor)."""
        import pandas as pd

        s = self.duty.samples
        cols: dict[str, Any] = {"t_s": self.duty.t, "load_x": np.asarray(s.x), "load_v": np.asarray(s.v),
                                "load_a": np.asarray(s.a), "shaft_speed_rad_s": self.duty.omega,
                                "shaft_acceleration_rad_s2": self.duty.alpha, "shaft_torque_Nm": self.duty.torque}
        own = self.motor_cycle()
        if own is not None:
            cycle, rotor, _ = own
            cols.update({"motor_speed_rad_s": cycle.omega, "motor_acceleration_rad_s2": cycle.alpha,
                         "motor_torque_Nm": cycle.motor_torque(rotor)})
        frame = pd.DataFrame(cols)
        frame.attrs["motor"] = None if own is None else own[2]
        return frame

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


TYPED_BLOCKS = (DriveAnswer, Regen)
"""The typed blocks of the answer that are not dataclasses of ``sizing.answer`` or ``sizing.axis_blocks`` (their
JSON: ``to_dict``); a candidate's are written by ``Candidate.to_dict``."""


def plain_block(value: Any) -> Any:
    """A block of the answer as the JSON holds it: a typed block's ``to_dict()``, any other value as it is."""
    return value.to_dict() if isinstance(value, TYPED_BLOCKS) else value


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


def motor_result(axis: Axis, duty: DutyCycle, motor: MotorData) -> tuple[MotorAnswer, dict[str, Any]]:
    """The ``motor`` block of the JSON (demand with the rotor, lecture figures and checks) and the
    electrical half's blocks that sit beside it in the answer (``drive``, ``regen``, where known)."""
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
    beside: dict[str, Any] = {}
    if elec.drive is not None:
        beside["drive"] = elec.drive
    if elec.regen is not None:
        beside["regen"] = elec.regen
    return MotorAnswer(
        name=motor.name,
        source=motor.source,
        unverified=bool(motor.unverified_reason),
        unverified_reason=motor.unverified_reason or None,
        inertia_kgm2=motor.inertia,
        inertia_ratio=duty.load_inertia / motor.inertia,
        peak_torque_Nm=with_rotor["peak_torque_Nm"],
        rms_torque_Nm=with_rotor["rms_torque_Nm"],
        accel_torque_Nm=with_rotor["accel_torque_Nm"],
        run_torque_Nm=with_rotor["run_torque_Nm"],
        decel_torque_Nm=with_rotor["decel_torque_Nm"],
        holding_torque_Nm=with_rotor["holding_torque_Nm"],
        peak_power_W=with_rotor["peak_power_W"],
        regen_energy_J=with_rotor["regen_energy_J"],
        min_accel_time_s=minimum_accel_time(n, motor.inertia, duty.load_inertia, motor.peak_torque, run),
        min_decel_time_s=minimum_decel_time(n, motor.inertia, duty.load_inertia, motor.peak_torque, run),
        operation_power_W=operation_power(n, run),
        acceleration_power_W=acceleration_power(n, duty.load_inertia, first) if first > 0 else None,
        gearbox_torque_split_k=gearbox.get("gearbox_torque_split_k"),
        gearbox_output_torque_at_motor_peak_Nm=gearbox.get("gearbox_output_torque_at_motor_peak_Nm"),
        gearbox_output_peak_torque_Nm=gearbox.get("gearbox_output_peak_torque_Nm"),
        electrical=extra,
        ok=ok,
        failed=failed,
        checks=list(checks),
        segments=with_rotor["segments"],
    ), beside


def _gearbox_split(axis: Axis, motor: MotorData, duty: DutyCycle, run_torque: float) -> dict[str, Any]:
    """The lecture's gearbox torque split for the first gearbox from the motor, if any
    (``duty.cycle.gearbox_split_at_motor_peak``)."""
    from drivetrain.duty.cycle import gearbox_split_at_motor_peak

    return gearbox_split_at_motor_peak(axis, duty, motor.inertia, motor.peak_torque, run_torque)


def gearbox_rating_checks(axis: Axis, duty: DutyCycle, motor: MotorData | None,
                          strict: bool = False) -> GearboxChecks | None:
    """Every rating of each gearbox in ``transmission:`` that has a rating or a catalog id, checked
    by ``checks.gearbox_ratings`` against the gearbox's own output torque and input speed over
    the cycle; the emergency-stop torque needs a motor (given, or the selected one). A rating
    that is not given is reported unknown, not passed; ``strict`` makes an unknown fail.
    """
    from drivetrain.axis.transmission import GearboxSpec
    from drivetrain.duty.cycle import gearbox_split_at_motor_peak
    from drivetrain.physics.averages import cubic_mean
    from drivetrain.physics.torque_split import gearbox_peak_torque
    from drivetrain.sizing.checks import GEARBOX_CHECKS, gearbox_ratings, shock_factor

    margins = axis.spec.motor.margins if axis.spec.motor is not None else None
    tm, sm = (margins.torque, margins.speed) if margins is not None else (1.0, 1.0)
    shock = shock_factor(duty.period, margins.gearbox_shock_factor if margins is not None else None)
    out: list[GearboxCheck] = []
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
            note = None
            if status == "unknown":
                if name == "gearbox_emergency_stop_torque" and motor is None:
                    note = "needs the motor's peak torque: checked on the selected motor"
                elif name == "gearbox_peak_torque" and math.isnan(shock) and not math.isnan(av):
                    note = (f"{3600.0 / duty.period:.0f} cycles/h exceed the 1000/h that T2B holds for: "
                            "set motor.margins.gearbox_shock_factor from the vendor's chart")
                else:
                    note = f"transmission[{k}].{names[name]} not given"
            out.append(GearboxCheck(name, st.name, req * scale, None if math.isnan(av) else av * scale,
                                    "rpm" if rpm else "N*m", mar if math.isfinite(mar) else None, status,
                                    status == "pass" or (status == "unknown" and not strict), note=note))
    if not out:
        return None
    return GearboxChecks(tuple(out), all(c.ok for c in out),
                         tuple(f"{c.stage}: {c.name}" for c in out if c.status == "unknown"))


def _nan(x: float | None) -> float:
    return math.nan if x is None else float(x)


def brake_check(axis: Axis, duty: DutyCycle) -> RatingCheck | None:
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
        return RatingCheck("brake_holding_torque", need, st.holding_torque, "N*m", margin, margin >= 0.0)
    return None


def _first_move_ramp_times(duty: DutyCycle) -> float:
    """Duration of the first move's acceleration phase [s] (0 if none)."""
    for ph in duty.cycle.phases:
        if ph.kind == "accel":
            return float(ph.t1 - ph.t0)
    return 0.0


def verdict(result: SizingResult) -> bool:
    """True when the axis's own checks (slip, guide, brake, gearbox ratings, mechanism, drive) and the
    given motor or the selected candidate pass (the pipeline's last stage; ``SizingResult.ok``)."""
    blocks = (result.slip_check, result.guide, result.brake_check, result.gearbox_checks, result.drive)
    own = [b.ok for b in blocks if b is not None]
    own += [c.ok for c in result.mechanism_checks]
    if not all(own):
        return False
    if result.motor is not None:
        return bool(result.motor.ok)
    if result.selection is not None:
        # the selection's best passing candidate, with a drive that can be ordered (drive_select.orderable)
        return (result.ranking is not None and result.ranking.best is not None
                and result.selection.drive_advice is None)
    return True


def selected_motor(ranking: Ranking) -> MotorData | None:
    """The selected catalog motor as MotorData (for the checks that need its peak torque), if any."""
    if ranking.best is None:
        return None
    motors = ranking.motors
    m = int(ranking.candidates.motor[ranking.best])
    return MotorData(name=str(motors.ids[m]), inertia=float(motors.rotor_inertia[m]),
                     rated_torque=float(motors.rated_torque[m]), peak_torque=float(motors.peak_torque[m]),
                     rated_speed=float(motors.rated_speed[m]), max_speed=float(motors.max_speed[m]))
