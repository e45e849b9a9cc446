"""The typed blocks of a motor's answer: a catalog selection's listed candidate (``Candidate``, its
checks ``CheckRow``), the selection's summary (``SelectionSummary``, with ``OptimalRatio`` and the
motors ``PassedOver`` for their drive) and a given motor's block (``MotorAnswer``).

Each is a dataclass whose fields are the JSON's keys (docs/axis-file.md), in the JSON's order;
``to_dict()`` gives the JSON block, with a key whose field is None left out where the answer leaves
it out (each class says which), so ``SizingResult.to_dict()`` and ``--json`` read as they did when
these blocks were dicts.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drivetrain.sizing.checks import Check
    from drivetrain.sizing.electrical import DriveAnswer, Regen


@dataclass
class CheckRow:
    """One check of a listed candidate (docs/checks.md): ``required`` must not exceed ``available``.

    Attributes
    ----------
    name : str
        The check (``candidates.CHECK_UNITS``: ``peak_torque``, ``rms_torque``, ``max_speed``, ...).
    required : float
        What the cycle needs, margins included, in ``unit`` [N*m, rpm, -, mm or N].
    available : float or None
        What the motor or gearbox offers, in ``unit`` [N*m, rpm, -, mm or N]; None where unknown or not judged.
    unit : str
        The unit of ``required`` and ``available``.
    margin : float or None
        available / required - 1 [-]; None where it cannot be judged (or is infinite).
    ok : bool
        The check does not reject the candidate (it passes, or is unknown under ``unknown: flag``).
    status : str
        ``pass``, ``fail``, ``unknown`` (a rating or dimension the catalog lacks) or ``not_judged``
        (a torque at a speed the motor cannot reach).
    approximate : bool
        The motor's envelope behind it was derived from ratings, not read from a datasheet curve.
    note : str or None
        Why an ``unknown`` or ``not_judged`` check cannot be judged, and what would decide it; None (left
        out of the JSON) otherwise.
    """

    name: str
    required: float
    available: float | None
    unit: str
    margin: float | None
    ok: bool
    status: str
    approximate: bool
    note: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON row: the fields in order, ``note`` only where there is one."""
        out: dict[str, Any] = {"name": self.name, "required": self.required, "available": self.available,
                               "unit": self.unit, "margin": self.margin, "ok": self.ok, "status": self.status,
                               "approximate": self.approximate}
        if self.note is not None:
            out["note"] = self.note
        return out


@dataclass
class BrakeVariant:
    """A candidate motor's brake variant, where the axis needs a holding brake (``motor_brake.brake_variant``).

    Attributes
    ----------
    order_code : str or None
        The brake variant's order code; None where the catalog lacks it.
    holding_torque_Nm : float or None
        The brake's holding torque [N m]; None where the catalog lacks it.
    rotor_inertia_kgm2 : float or None
        The with-brake rotor inertia [kg m^2]; None where the catalog lacks it (the plain rotor's is used).
    note : str or None
        What the catalog lacks of the variant, to ask the vendor; None (left out of the JSON) when it has all.
    """

    order_code: str | None
    holding_torque_Nm: float | None
    rotor_inertia_kgm2: float | None
    note: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON block: the fields in order, ``note`` only where there is one."""
        out: dict[str, Any] = {"order_code": self.order_code, "holding_torque_Nm": self.holding_torque_Nm,
                               "rotor_inertia_kgm2": self.rotor_inertia_kgm2}
        if self.note is not None:
            out["note"] = self.note
        return out


@dataclass
class Candidate:
    """A catalog candidate as the answer lists it (JSON ``candidates`` and ``selection.selected``): a motor in
    one configuration, direct or behind one catalog gearbox, with every check.

    Attributes
    ----------
    rank : int or None
        Its place among the passing motors (1 the selected); None for a failing one.
    motor : str
        The catalog motor id.
    vendor : str
        The motor's vendor.
    series : str
        The motor's series.
    rated_power_W : float
        The motor's rated power [W] (NaN where the catalog lacks it).
    flange_mm : float or None
        The motor's flange size [mm]; None where unknown.
    shaft_diameter_mm : float or None
        The motor's shaft diameter [mm]; None where unknown.
    gearbox : str or None
        The catalog gearbox id; None for direct drive.
    gearbox_vendor : str or None
        The gearbox's vendor; None for direct drive.
    ratio : float
        The catalog gearbox's ratio [-] (1 for direct drive).
    inertia_ratio : float
        Load inertia at the motor shaft over the rotor's [-].
    rms_torque_Nm : float
        The motor's RMS torque over the cycle, rotor included [N m].
    peak_torque_Nm : float
        The motor's peak torque over the cycle, rotor included [N m].
    ok : bool
        No check rejects it.
    status : str
        ``ok`` (every check passes), ``unknown`` (none fails, ``unknown`` cannot be judged) or ``fails``.
    unknown : list of str
        The checks that cannot be judged.
    failed : str
        The first of ``failures`` ('' when it passes).
    failures : list of str
        One sentence per failing check, a motor too slow for the cycle first.
    approximate_envelope : bool
        The motor's speed-torque envelope is derived from its ratings.
    rated_torque_derived : bool
        The motor's rated torque was derived, not read.
    derived : dict or None
        The motor's catalog values computed rather than read, each with its formula; None (left out)
        where every value was read.
    unverified : bool
        The motor's or gearbox's catalog row is not traced to a vendor document.
    unverified_reason : str or None
        Why, per part; None when traced.
    checks : list of CheckRow
        Every check that applies to it, in ``candidates.CHECK_UNITS`` order.
    brake : BrakeVariant or None
        The motor's brake variant (order code, holding torque, with-brake rotor inertia) where the axis
        needs a holding brake (``motor_brake.brake_variant``); None (left out) otherwise.
    drive : DriveAnswer or None
        Its drive (``drive_select.attach_drives``); None (left out) where drives were not attached.
    voltage_class : dict or None
        The motor's voltage class against the stated supply (``voltage_class.voltage_class_check``); None
        (left out) where no supply is stated.
    electrical : dict or None
        The selected candidate's electrical figures with its drive (currents [A], envelope source, winding
        rise [K], their checks: ``drive_select.selected_electrical``); None (left out) for the others.
    regen : Regen or None
        The selected candidate's regeneration block; in the JSON wherever ``electrical`` is (null where
        not known).
    """

    rank: int | None
    motor: str
    vendor: str
    series: str
    rated_power_W: float
    flange_mm: float | None
    shaft_diameter_mm: float | None
    gearbox: str | None
    gearbox_vendor: str | None
    ratio: float
    inertia_ratio: float
    rms_torque_Nm: float
    peak_torque_Nm: float
    ok: bool
    status: str
    unknown: list[str]
    failed: str
    failures: list[str]
    approximate_envelope: bool
    rated_torque_derived: bool
    derived: dict[str, str] | None
    unverified: bool
    unverified_reason: str | None
    checks: list[CheckRow]
    brake: BrakeVariant | None = None
    drive: DriveAnswer | None = None
    voltage_class: dict[str, Any] | None = None
    electrical: dict[str, Any] | None = None
    regen: Regen | None = None

    def check(self, name: str) -> CheckRow | None:
        """The check of this name, None where it does not apply."""
        return next((ch for ch in self.checks if ch.name == name), None)

    def to_dict(self) -> dict[str, Any]:
        """The JSON block (docs/axis-file.md, "Selection"): the fields in order, each optional one only
        where the answer has it."""
        out: dict[str, Any] = {
            "rank": self.rank, "motor": self.motor, "vendor": self.vendor, "series": self.series,
            "rated_power_W": self.rated_power_W, "flange_mm": self.flange_mm,
            "shaft_diameter_mm": self.shaft_diameter_mm, "gearbox": self.gearbox,
            "gearbox_vendor": self.gearbox_vendor, "ratio": self.ratio, "inertia_ratio": self.inertia_ratio,
            "rms_torque_Nm": self.rms_torque_Nm, "peak_torque_Nm": self.peak_torque_Nm, "ok": self.ok,
            "status": self.status, "unknown": list(self.unknown), "failed": self.failed,
            "failures": list(self.failures), "approximate_envelope": self.approximate_envelope,
            "rated_torque_derived": self.rated_torque_derived}
        if self.derived is not None:
            out["derived"] = self.derived
        out.update({"unverified": self.unverified, "unverified_reason": self.unverified_reason,
                    "checks": [ch.to_dict() for ch in self.checks]})
        if self.brake is not None:
            out["brake"] = self.brake.to_dict()
        if self.drive is not None:
            out["drive"] = self.drive.to_dict()
        if self.voltage_class is not None:
            out["voltage_class"] = self.voltage_class
        if self.electrical is not None:
            out["electrical"] = self.electrical
            out["regen"] = None if self.regen is None else self.regen.to_dict()
        return out


@dataclass
class OptimalRatio:
    """The best ratio for the selected motor (``selection.optimal_ratio``).

    Attributes
    ----------
    motor : str
        The catalog motor id.
    inertia_match_ratio : float
        sqrt(J_L / J_M): the ratio that matches the load's inertia to the rotor's [-].
    min_rms_ratio : float
        The ratio that minimises the motor's RMS torque behind an ideal gearbox [-].
    min_rms_torque_Nm : float
        That least RMS torque [N m].
    max_ratio_for_speed : float
        The largest ratio at which the motor reaches the cycle's top speed [-].
    nearest_catalog_ratio : float or None
        The catalog gearbox ratio nearest to ``min_rms_ratio`` [-]; None without catalog gearboxes.
    """

    motor: str
    inertia_match_ratio: float
    min_rms_ratio: float
    min_rms_torque_Nm: float
    max_ratio_for_speed: float
    nearest_catalog_ratio: float | None

    def to_dict(self) -> dict[str, Any]:
        """The JSON block: the fields in order."""
        return {"motor": self.motor, "inertia_match_ratio": self.inertia_match_ratio,
                "min_rms_ratio": self.min_rms_ratio, "min_rms_torque_Nm": self.min_rms_torque_Nm,
                "max_ratio_for_speed": self.max_ratio_for_speed, "nearest_catalog_ratio": self.nearest_catalog_ratio}


@dataclass
class PassedOver:
    """A passing motor the drive rule (or the dynamic rule) passed over (``drive_select.orderable``).

    Attributes
    ----------
    motor : str
        The catalog motor id.
    drive_status : str
        Its drive's status (``fails``, ``unknown``, ``none``, ...), ``voltage_class fail`` or ``dynamics``.
    reason : str
        Why it is not the answer, in one sentence.
    """

    motor: str
    drive_status: str
    reason: str

    def to_dict(self) -> dict[str, Any]:
        """The JSON entry: the fields in order."""
        return {"motor": self.motor, "drive_status": self.drive_status, "reason": self.reason}


_SEARCH_HEAD = ("objective", "motors", "gearbox_rows", "unknown_policy", "cycles_per_hour", "evaluated", "passing",
                "passing_motors", "failures_by_check", "unknown_by_check")
_RANKED_HEAD = ("objective", "evaluated", "motors", "gearbox_rows", "passing", "passing_motors", "listing",
                "unknown_policy", "failures_by_check", "unknown_by_check", "cycles_per_hour")


@dataclass
class SelectionSummary:
    """A catalog selection's summary (JSON ``selection``, docs/axis-file.md): counts, the selected candidate,
    the next smaller motor, advice. A field that is None is left out of the JSON (``next_smaller`` is in it,
    null or not, wherever ``optimal_ratio`` is).

    Attributes
    ----------
    objective : str
        The ranking's objective (``motor.select.objective``).
    motors : int
        Catalog motors searched.
    gearbox_rows : int
        Catalog gearbox rows searched (0: direct drive alone).
    unknown_policy : str
        ``motor.select.unknown``: ``flag`` or ``fail``.
    cycles_per_hour : float
        Cycles per hour [1/h].
    evaluated : int or None
        Candidates evaluated (motor x configuration); None where the smallest-first search did not
        evaluate them all.
    passing : int or None
        Candidates that pass; None as ``evaluated``.
    passing_motors : int or None
        Motors with a passing configuration; None as ``evaluated``.
    listing : str or None
        ``best_per_motor`` or ``all_pairs``; None for the smallest-first search's answer (its keys then
        come in the search's order: objective, motors, gearbox_rows, unknown_policy, cycles_per_hour,
        the counts).
    failures_by_check : dict or None
        Candidates failing each check (a count per check name); None as ``evaluated``.
    unknown_by_check : dict or None
        Candidates that cannot be judged on each check; None as ``evaluated``.
    selected : Candidate or None
        The selected candidate; None when nothing passes.
    next_smaller : Candidate or None
        The next smaller motor than the selected one in its best configuration, and why it fails.
    optimal_ratio : OptimalRatio or None
        The best ratio for the selected motor.
    pareto_front : list of str or None
        Passing configurations not dominated on size, margin and inertia ratio (at most 50).
    unverified : str or None
        How many passing configurations have checks the catalog cannot judge.
    advice : str or None
        What to relax when nothing passes.
    drive_passed_over : list of PassedOver or None
        The first 20 passing motors passed over for their drive (or the dynamic rule).
    drive_passed_over_count : int or None
        How many were passed over.
    drive_advice : str or None
        Why no passing motor tried has an orderable drive (the answer fails).
    dynamics : dict or None
        The dynamic selection's answer (``dynamics.dynamic_selection``) where the axis has ``requirements:``.
    transmission_gearbox : str or None
        The axis's own gearbox(es) the motors go onto, where the selection searched no catalog gearbox.
    """

    objective: str
    motors: int
    gearbox_rows: int
    unknown_policy: str
    cycles_per_hour: float
    evaluated: int | None = None
    passing: int | None = None
    passing_motors: int | None = None
    listing: str | None = None
    failures_by_check: dict[str, int] | None = None
    unknown_by_check: dict[str, int] | None = None
    selected: Candidate | None = None
    next_smaller: Candidate | None = None
    optimal_ratio: OptimalRatio | None = None
    pareto_front: list[str] | None = None
    unverified: str | None = None
    advice: str | None = None
    drive_passed_over: list[PassedOver] | None = None
    drive_passed_over_count: int | None = None
    drive_advice: str | None = None
    dynamics: dict[str, Any] | None = None
    transmission_gearbox: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON block: the counts in the order the selection (or the search) gives them, then the
        answer's keys present."""
        out: dict[str, Any] = {}
        for name in (_SEARCH_HEAD if self.listing is None else _RANKED_HEAD):
            value = getattr(self, name)
            if value is not None:
                out[name] = value
        if self.selected is not None:
            out["selected"] = self.selected.to_dict()
        if self.optimal_ratio is not None:
            out["next_smaller"] = None if self.next_smaller is None else self.next_smaller.to_dict()
            out["optimal_ratio"] = self.optimal_ratio.to_dict()
        tail: dict[str, Any] = {
            "pareto_front": self.pareto_front, "unverified": self.unverified, "advice": self.advice,
            "drive_passed_over": None if self.drive_passed_over is None else [p.to_dict()
                                                                              for p in self.drive_passed_over],
            "drive_passed_over_count": self.drive_passed_over_count, "drive_advice": self.drive_advice,
            "dynamics": self.dynamics, "transmission_gearbox": self.transmission_gearbox}
        out.update({k: v for k, v in tail.items() if v is not None})
        return out


@dataclass
class MotorAnswer:
    """A given motor's block (JSON ``motor``, docs/axis-file.md): the demand with its rotor, the lecture's
    figures and every check (``result.motor_result``).

    Attributes
    ----------
    name : str
        The motor's name (its catalog id where it has one).
    source : str
        Where its data came from (``catalog`` or the axis file).
    unverified : bool
        Its catalog row is not traced to a vendor document.
    unverified_reason : str or None
        Why; None when traced.
    inertia_kgm2 : float
        Its rotor inertia [kg m^2].
    inertia_ratio : float
        Load inertia at the motor shaft over the rotor's [-].
    peak_torque_Nm : float
        Peak motor torque over the cycle, rotor included [N m].
    rms_torque_Nm : float
        RMS motor torque, rotor included [N m].
    accel_torque_Nm : float
        Largest motor torque while accelerating [N m].
    run_torque_Nm : float
        Motor torque at constant speed [N m].
    decel_torque_Nm : float
        Motor torque while decelerating [N m].
    holding_torque_Nm : float
        Largest motor torque at standstill [N m].
    peak_power_W : float
        Peak mechanical power at the shaft [W].
    regen_energy_J : float
        Energy returned by the load per cycle [J].
    min_accel_time_s : float
        Shortest time to the cycle's top speed at the motor's peak torque [s].
    min_decel_time_s : float
        Shortest time from the top speed to standstill [s].
    operation_power_W : float
        Running torque x top speed [W].
    acceleration_power_W : float or None
        Power to accelerate the load in the first move's ramp [W]; None without one.
    gearbox_torque_split_k : float or None
        The lecture's split k = J_M / (J_M + J_LR) for the first gearbox [-]; None (left out, with the next
        two) without a gearbox.
    gearbox_output_torque_at_motor_peak_Nm : float or None
        The gearbox's output torque at the motor's peak [N m].
    gearbox_output_peak_torque_Nm : float or None
        The gearbox's largest output torque over the cycle [N m].
    electrical : dict
        The electrical half's figures (``sizing.electrical.ElectricalAnswer.motor``: supply and bus voltage
        [V], currents [A], envelope source, winding rise [K], ``supply_curve``), each key in the JSON beside
        the others.
    ok : bool
        Every check passes.
    failed : str
        The first failing check as a sentence ('' when all pass).
    checks : list of Check
        Every check (``sizing.checks.Check``), the mechanical ones then the electrical ones.
    segments : list of dict
        Every accel, run, decel and dwell with its span [s], largest torque [N m] and top speed.
    """

    name: str
    source: str
    unverified: bool
    unverified_reason: str | None
    inertia_kgm2: float
    inertia_ratio: float
    peak_torque_Nm: float
    rms_torque_Nm: float
    accel_torque_Nm: float
    run_torque_Nm: float
    decel_torque_Nm: float
    holding_torque_Nm: float
    peak_power_W: float
    regen_energy_J: float
    min_accel_time_s: float
    min_decel_time_s: float
    operation_power_W: float
    acceleration_power_W: float | None
    gearbox_torque_split_k: float | None
    gearbox_output_torque_at_motor_peak_Nm: float | None
    gearbox_output_peak_torque_Nm: float | None
    electrical: dict[str, Any]
    ok: bool
    failed: str
    checks: list[Check]
    segments: list[dict[str, Any]] = field(default_factory=list)

    def check(self, name: str) -> Check | None:
        """The check of this name, None where the motor has none."""
        return next((ch for ch in self.checks if ch.name == name), None)

    def to_dict(self) -> dict[str, Any]:
        """The JSON block: the fields in order, the gearbox split only with a gearbox, the electrical keys
        in its place."""
        out: dict[str, Any] = {
            "name": self.name, "source": self.source, "unverified": self.unverified,
            "unverified_reason": self.unverified_reason, "inertia_kgm2": self.inertia_kgm2,
            "inertia_ratio": self.inertia_ratio, "peak_torque_Nm": self.peak_torque_Nm,
            "rms_torque_Nm": self.rms_torque_Nm, "accel_torque_Nm": self.accel_torque_Nm,
            "run_torque_Nm": self.run_torque_Nm, "decel_torque_Nm": self.decel_torque_Nm,
            "holding_torque_Nm": self.holding_torque_Nm, "peak_power_W": self.peak_power_W,
            "regen_energy_J": self.regen_energy_J, "min_accel_time_s": self.min_accel_time_s,
            "min_decel_time_s": self.min_decel_time_s, "operation_power_W": self.operation_power_W,
            "acceleration_power_W": self.acceleration_power_W}
        if self.gearbox_torque_split_k is not None:
            out.update({"gearbox_torque_split_k": self.gearbox_torque_split_k,
                        "gearbox_output_torque_at_motor_peak_Nm": self.gearbox_output_torque_at_motor_peak_Nm,
                        "gearbox_output_peak_torque_Nm": self.gearbox_output_peak_torque_Nm})
        out.update(self.electrical)
        out.update({"ok": self.ok, "failed": self.failed, "checks": [c.to_dict() for c in self.checks],
                    "segments": self.segments})
        return out


__all__ = ["BrakeVariant", "Candidate", "CheckRow", "MotorAnswer", "OptimalRatio", "PassedOver", "SelectionSummary"]
