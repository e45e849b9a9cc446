"""The typed blocks of the axis's own checks in the answer (``SizingResult.guide``, ``slip_check``,
``mechanism_checks``, ``brake_check``, ``gearbox_checks``) and of its modes (``SizingResult.modes``): each a
dataclass whose fields carry their units, its ``to_dict()`` the object of the JSON that docs/axis-file.md
documents (the keys in their order, an optional key only where the JSON has it).

* :class:`AxisChecks`: what the axis-checks stage of the pipeline finds (``sizing.pipeline.axis_checks``);

* :class:`RatingCheck`: one rating against what the cycle needs: ``slip_check``, ``brake_check`` and each of
  the guide's rating checks;
* :class:`GuideReport`: ``guide``, the forces and moments on the carriage (:func:`guide_report`);
* :class:`MechanismCheck`: each entry of ``mechanism_checks`` (``sizing.mechanism_checks``);
* :class:`GearboxCheck`, :class:`GearboxChecks`: ``gearbox_checks`` (``result.gearbox_rating_checks``);
* :class:`Modes`, :class:`ModeAtPosition`, :class:`BandwidthCheck`: ``modes``
  (``dynamics.mechanism_modes.modes_across_stroke``).

Every check block answers ``unknown`` (it could not be judged) and ``failed`` by the same rule the verdict
applies to any check of the JSON (``sizing.verdict``): its ``status`` where it has one, else its ``ok``
(None, or a margin that is not a number: unknown).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.physics.guides import carriage_moments, rms_force

Array = NDArray[np.float64]


def _unknown(status: str | None, ok: bool | None, margin: float | None) -> bool:
    if status is not None:
        return status == "unknown"
    return ok is None or (margin is not None and math.isnan(margin))


def _failed(status: str | None, ok: bool | None) -> bool:
    return status in ("fail", "fails") if status is not None else ok is False


class Judged:
    """What the verdict reads of a check block (docs/checks.md, "The verdict"): a check is unknown where its
    ``status`` says so, or, without a status, where ``ok`` is undecided or the margin is not a number; it fails
    where its status says so, else where ``ok`` is False. A block without a ``status`` field has None."""

    ok: bool | None
    margin: float | None

    @property
    def unknown(self) -> bool:
        """Whether the check could not be judged."""
        return _unknown(getattr(self, "status", None), self.ok, self.margin)

    @property
    def failed(self) -> bool:
        """Whether the check fails."""
        return _failed(getattr(self, "status", None), self.ok)


@dataclass(frozen=True)
class RatingCheck(Judged):
    """A rating of the axis against what the cycle needs of it: the load's slip on its carrier
    (``slip_check``), the brake's holding torque (``brake_check``) and each rating check of the guide
    (``guide.checks``).

    Attributes
    ----------
    name : str
        The check: ``slip_limit``, ``brake_holding_torque``, ``guide_normal``, ``guide_pitch``,
        ``guide_roll`` or ``guide_yaw``.
    required : float
        What the cycle needs, in :attr:`unit` [unit].
    available : float
        What the rating allows, in :attr:`unit` [unit].
    unit : str
        The unit of both (``"m/s^2"``, ``"N*m"``, ``"N"``, ``"Nm"``).
    margin : float
        available / required - 1 [-]; +inf where nothing is required.
    ok : bool
        Whether the rating holds (margin >= 0).
    approximate : bool
        Whether a figure is approximate (always False for these checks).
    note : str or None
        What the figures mean where they need a word (left out of the JSON where None).
    """

    name: str
    required: float
    available: float
    unit: str
    margin: float
    ok: bool
    approximate: bool = False
    note: str | None = None


    def to_dict(self) -> dict[str, Any]:
        """The check's object of the JSON: name, required, available, unit, margin, ok, approximate (and note)."""
        out: dict[str, Any] = {"name": self.name, "required": self.required, "available": self.available,
                               "unit": self.unit, "margin": self.margin, "ok": self.ok, "approximate": self.approximate}
        if self.note is not None:
            out["note"] = self.note
        return out


@dataclass(frozen=True)
class GuideReport:
    """The ``guide`` block: the forces and moments on the carriage of a linear axis over the cycle, and the
    guide's ratings checked against their peaks (:func:`guide_report`).

    Attributes
    ----------
    actuator_rms_force_N : float
        RMS over the cycle of the actuator force, moving mass times acceleration plus the load's whole
        external force along the travel [N].
    actuator_peak_force_N : float
        The actuator force's peak magnitude [N].
    peak_thrust_N : float
        Peak magnitude of F_x = m a + F_applied, the force along the travel the carriage moments use [N].
    peak_normal_N : float
        Peak normal force on the carriage [N].
    peak_pitch_Nm : float
        Peak pitch moment on the carriage [N m].
    peak_roll_Nm : float
        Peak roll moment on the carriage [N m].
    peak_yaw_Nm : float
        Peak yaw moment on the carriage [N m].
    checks : tuple of RatingCheck
        One check per rating the guide states (``guide_normal``, ``guide_pitch``, ``guide_roll``, ``guide_yaw``).
    ok : bool
        Whether every rating check passes (True without one).
    """

    actuator_rms_force_N: float
    actuator_peak_force_N: float
    peak_thrust_N: float
    peak_normal_N: float
    peak_pitch_Nm: float
    peak_roll_Nm: float
    peak_yaw_Nm: float
    checks: tuple[RatingCheck, ...]
    ok: bool

    def to_dict(self) -> dict[str, Any]:
        """The ``guide`` object of the JSON: the forces and moments, ``checks`` and ``ok``, in that order."""
        return {"actuator_rms_force_N": self.actuator_rms_force_N, "actuator_peak_force_N": self.actuator_peak_force_N,
                "peak_thrust_N": self.peak_thrust_N, "peak_normal_N": self.peak_normal_N,
                "peak_pitch_Nm": self.peak_pitch_Nm, "peak_roll_Nm": self.peak_roll_Nm, "peak_yaw_Nm": self.peak_yaw_Nm,
                "checks": [c.to_dict() for c in self.checks], "ok": self.ok}


@dataclass(frozen=True)
class MechanismCheck(Judged):
    """One entry of ``mechanism_checks``: a limit of the screw, nut, guide life, belt or rack against what the
    cycle needs of it (``sizing.mechanism_checks``; docs/checks.md lists the formulas and their sources).

    Attributes
    ----------
    name : str
        The check (``screw_buckling``, ``screw_tensile_compressive``, ``screw_critical_speed``, ``screw_dn_speed``,
        ``nut_life``, ``nut_static_safety``, ``guide_life``, ``guide_static_safety``, ``belt_slack_side``,
        ``belt_tension``, ``rack_feed_force``, ``belt_stiffness``).
    required : float or None
        What the cycle needs, in :attr:`unit` [unit]; None where nothing is required (``belt_stiffness``).
    available : float or None
        What the part allows, in :attr:`unit` [unit]; for a check bounded from the nominal diameter the bound;
        None where it is not known.
    margin : float or None
        available / required - 1 [-] (+inf where nothing is required); None where not known.
    ok : bool
        Whether the check passes; True for a check that is unknown (its ``status`` says so).
    unit : str
        The unit of required and available (``"N"``, ``"rpm"``, ``"h"``, ``"-"``).
    source : str
        The public document the formula comes from.
    approximate : bool
        Whether a figure is approximate (always False for these checks).
    note : str
        The figures behind the check, or what would decide it ("" where none).
    status : str or None
        ``"unknown"`` (the check cannot be judged from what is given) or ``"fail"`` (a bound already fails it);
        None for a check judged from the part's own ratings (its ``ok`` says). In the JSON an unknown's status
        follows ``ok``, a failing bound's comes last, a judged check has none.
    """

    name: str
    required: float | None
    available: float | None
    margin: float | None
    ok: bool
    unit: str
    source: str
    approximate: bool = False
    note: str = ""
    status: str | None = None


    def to_dict(self) -> dict[str, Any]:
        """The entry of the JSON's ``mechanism_checks`` list."""
        out: dict[str, Any] = {"name": self.name, "required": self.required, "available": self.available,
                               "margin": self.margin, "ok": self.ok}
        if self.status == "unknown":
            out["status"] = self.status
        out.update({"unit": self.unit, "source": self.source, "approximate": self.approximate, "note": self.note})
        if self.status is not None and self.status != "unknown":
            out["status"] = self.status
        return out


@dataclass(frozen=True)
class GearboxCheck(Judged):
    """One rating of a gearbox of ``transmission:`` against the cycle (``result.gearbox_rating_checks``).

    Attributes
    ----------
    name : str
        The check: ``gearbox_peak_torque`` (T2B), ``gearbox_rated_torque`` (T2N),
        ``gearbox_emergency_stop_torque`` (T2NOT), ``gearbox_max_input_speed`` (n1max) or
        ``gearbox_mean_input_speed`` (n1N).
    stage : str
        The name of the gearbox's stage in ``transmission:``.
    required : float
        What the cycle needs [N m or rpm, :attr:`unit`]; NaN where it cannot be computed (T2NOT without a motor).
    available : float or None
        The gearbox's rating [N m or rpm, :attr:`unit`]; None where not given.
    unit : str
        ``"N*m"`` or ``"rpm"``.
    margin : float or None
        available / required - 1 [-]; None where not known.
    status : str
        ``"pass"``, ``"fail"`` or ``"unknown"``.
    ok : bool
        Whether the check passes; an unknown one passes unless the selection is strict (``unknown: fail``).
    approximate : bool
        Whether a figure is approximate (always False).
    note : str or None
        Why an unknown check is unknown and what would decide it; None (not in the JSON) for a judged one.
    """

    name: str
    stage: str
    required: float
    available: float | None
    unit: str
    margin: float | None
    status: str
    ok: bool
    approximate: bool = False
    note: str | None = None


    def to_dict(self) -> dict[str, Any]:
        """The check's object of the JSON's ``gearbox_checks.checks``."""
        out: dict[str, Any] = {"name": self.name, "stage": self.stage, "required": self.required,
                               "available": self.available, "unit": self.unit, "margin": self.margin,
                               "status": self.status, "ok": self.ok, "approximate": self.approximate}
        if self.note is not None:
            out["note"] = self.note
        return out


@dataclass(frozen=True)
class GearboxChecks:
    """The ``gearbox_checks`` block: every rating of the rated gearboxes of ``transmission:``.

    Attributes
    ----------
    checks : tuple of GearboxCheck
        Five checks per gearbox, in the order of ``sizing.checks.GEARBOX_CHECKS``.
    ok : bool
        Whether every check passes.
    unknown : tuple of str
        The checks that could not be judged, as ``"stage: check"``.
    """

    checks: tuple[GearboxCheck, ...]
    ok: bool
    unknown: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        """The ``gearbox_checks`` object of the JSON: ``checks``, ``ok``, ``unknown``."""
        return {"checks": [c.to_dict() for c in self.checks], "ok": self.ok, "unknown": list(self.unknown)}


@dataclass(frozen=True)
class BandwidthCheck(Judged):
    """The modes' ``servo_bandwidth`` check: the lowest first mode against k times the velocity bandwidth the
    axis asks for (``dynamics.mechanism_modes.servo_bandwidth_check``). Reported, not part of the verdict.

    Attributes
    ----------
    name : str
        ``"servo_bandwidth"``.
    available : float
        The lowest first mode over the stroke, f1 [Hz].
    unit : str
        ``"Hz"``.
    source : str
        The public document the rule comes from.
    approximate : bool
        Whether a figure is approximate (always False).
    required : float
        k f_v [Hz]; NaN where the axis states no velocity bandwidth.
    margin : float
        available / required - 1 [-]; NaN where unknown.
    ok : bool or None
        Whether f1 >= k f_v; None where unknown.
    status : str
        ``"pass"``, ``"fail"`` or ``"unknown"``.
    note : str
        The rule with its figures, or what would decide it.
    """

    name: str
    available: float
    unit: str
    source: str
    approximate: bool
    required: float
    margin: float
    ok: bool | None
    status: str
    note: str


    def to_dict(self) -> dict[str, Any]:
        """The check's object of the JSON's ``modes.checks``."""
        return {"name": self.name, "available": self.available, "unit": self.unit, "source": self.source,
                "approximate": self.approximate, "required": self.required, "margin": self.margin, "ok": self.ok,
                "status": self.status, "note": self.note}


@dataclass(frozen=True)
class ModeAtPosition:
    """The first mode at one position of the stroke (an entry of ``modes.f1_by_position``).

    Attributes
    ----------
    position_m : float
        The position of the load along the stroke [m].
    f1_Hz : float
        The first natural frequency of the chain there [Hz].
    axial_stiffness_N_per_m : float
        The mechanism's axial stiffness there [N/m].
    """

    position_m: float
    f1_Hz: float
    axial_stiffness_N_per_m: float

    def to_dict(self) -> dict[str, Any]:
        """The entry of the JSON's ``modes.f1_by_position``."""
        return {"position_m": self.position_m, "f1_Hz": self.f1_Hz,
                "axial_stiffness_N_per_m": self.axial_stiffness_N_per_m}


@dataclass(frozen=True)
class Modes:
    """The ``modes`` block: the first natural frequency of the axis's chain across the stroke and the
    servo-bandwidth check (``dynamics.mechanism_modes``); reported, not part of the verdict.

    Attributes
    ----------
    f1_min_Hz : float
        The lowest first mode over the stroke [Hz].
    worst_position_m : float
        Where along the stroke it is lowest [m].
    weakest_link : str
        The softest spring of the chain there, seen at the motor.
    springs_at_motor_Nm_per_rad : dict of str to float
        Each compliant stage's torsional stiffness reflected to the motor shaft at the worst position
        [N m/rad], by its name.
    natural_frequencies_at_worst_Hz : tuple of float
        The chain's natural frequencies at the worst position [Hz].
    f1_by_position : tuple of ModeAtPosition
        The first mode at each position computed.
    velocity_bandwidth_Hz : float or None
        The velocity-loop bandwidth the axis asks for [Hz]; None where it states none.
    bandwidth_source : str
        Where that bandwidth comes from (``"dynamics.loop.velocity_bandwidth"`` or ``"not stated"``).
    max_velocity_bandwidth_Hz : float
        The highest velocity bandwidth the mechanism allows, f1 / k [Hz].
    checks : tuple of BandwidthCheck
        The ``servo_bandwidth`` check.
    motor : str or None
        The motor the chain assumes (the given or selected one); None (not in the JSON) for ``drivetrain modes``.
    """

    f1_min_Hz: float
    worst_position_m: float
    weakest_link: str
    springs_at_motor_Nm_per_rad: dict[str, float]
    natural_frequencies_at_worst_Hz: tuple[float, ...]
    f1_by_position: tuple[ModeAtPosition, ...]
    velocity_bandwidth_Hz: float | None
    bandwidth_source: str
    max_velocity_bandwidth_Hz: float
    checks: tuple[BandwidthCheck, ...]
    motor: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The ``modes`` object of the JSON."""
        out: dict[str, Any] = {
            "f1_min_Hz": self.f1_min_Hz, "worst_position_m": self.worst_position_m, "weakest_link": self.weakest_link,
            "springs_at_motor_Nm_per_rad": dict(self.springs_at_motor_Nm_per_rad),
            "natural_frequencies_at_worst_Hz": list(self.natural_frequencies_at_worst_Hz),
            "f1_by_position": [p.to_dict() for p in self.f1_by_position],
            "velocity_bandwidth_Hz": self.velocity_bandwidth_Hz, "bandwidth_source": self.bandwidth_source,
            "max_velocity_bandwidth_Hz": self.max_velocity_bandwidth_Hz,
            "checks": [c.to_dict() for c in self.checks]}
        if self.motor is not None:
            out["motor"] = self.motor
        return out


@dataclass(frozen=True)
class AxisChecks:
    """What the axis-checks stage finds (``sizing.pipeline.axis_checks``): the axis's own checks, before a motor.

    Attributes
    ----------
    warnings : tuple of str
        What is implausible in the axis file (``duty.sanity.sanity_warnings``), in words.
    guide : GuideReport or None
        The carriage's forces, moments and rating checks, for a linear axis with ``guide:``.
    slip_check : RatingCheck or None
        The load's slip on its carrier, for a mechanism with a slip limit.
    mechanism_checks : tuple of MechanismCheck
        The limits of the screw, nut, guide life, belt and rack the axis file has ratings for (may be empty).
    brake_check : RatingCheck or None
        A brake stage's holding torque against the braked dwells.
    """

    warnings: tuple[str, ...] = ()
    guide: GuideReport | None = None
    slip_check: RatingCheck | None = None
    mechanism_checks: tuple[MechanismCheck, ...] = ()
    brake_check: RatingCheck | None = None


AxisCheck = RatingCheck | MechanismCheck | GearboxCheck
"""A check of the axis's own blocks (``own_checks``)."""


def own_checks(result: Any, keys: tuple[str, ...] = ("slip_check", "guide", "brake_check", "mechanism_checks",
                                                     "gearbox_checks")) -> list[tuple[str, AxisCheck]]:
    """The checks of the axis's own blocks of an answer (a ``SizingResult``, or ``AxisChecks``: the attributes of
    ``keys`` it has, in that order), each with the name of its block."""
    out: list[tuple[str, AxisCheck]] = []
    for key in keys:
        block = getattr(result, key, None)
        if isinstance(block, RatingCheck):
            out.append((key, block))
        elif isinstance(block, (GuideReport, GearboxChecks)):
            out += [(key, c) for c in block.checks]
        elif isinstance(block, (list, tuple)):
            out += [(key, c) for c in block]
    return out


def guide_report(axis: Any, duty: Any) -> GuideReport:
    """Forces and moments on the carriage of a linear axis, checked against the guide's ratings.

    The actuator force is the lecture's F_actuator = (W_L / g) a + F_applied + F_friction (+ F_gravity
    on a slope or vertical): the moving mass times the acceleration plus the load's whole external
    force along the travel (process force by its thrust_mode, friction mu W_L, gravity, springs).
    Its RMS over the cycle is F_T,RMS (``physics.guides.rms_force``). The carriage moments
    (``physics.guides.carriage_moments``) use F_x = m a + F_applied. Forces [N], moments [N m].
    """
    from drivetrain.physics.loads import process_thrust

    spec = axis.spec.guide
    load = axis.mechanism.load
    s = duty.samples
    a = np.asarray(s.a, dtype=float)
    direction = np.asarray(s.direction, dtype=float)
    thrust = np.asarray(s.thrust, dtype=float)
    f_given = np.where(np.isnan(thrust), load.thrust, thrust)
    f_proc = process_thrust(f_given, direction, load.thrust_mode)
    f_x = load.mass * a + f_proc
    weight = load.mass * axis.gravity
    mom = carriage_moments(f_x, weight, spec.l_x, spec.l_y, spec.l_z, spec.d_p, spec.d_r, spec.orientation)
    breakaway = getattr(s, "breakaway", None)
    f_actuator = load.moving_mass * a + load.force(np.asarray(s.x, dtype=float), np.asarray(s.v, dtype=float),
                                                   direction, f_given, axis.gravity, breakaway)
    peaks: dict[str, float] = {}
    checks = []
    for key, rating in (("normal_N", spec.rated_force), ("pitch_Nm", spec.rated_pitch_moment),
                        ("roll_Nm", spec.rated_roll_moment), ("yaw_Nm", spec.rated_yaw_moment)):
        peak = float(np.max(np.abs(mom[key])))
        peaks[key] = peak
        if rating is not None:
            margin = rating / peak - 1.0 if peak > 0 else math.inf
            checks.append(RatingCheck(f"guide_{key.split('_')[0]}", peak, rating, key.split("_")[1], margin,
                                      margin >= 0.0))
    return GuideReport(actuator_rms_force_N=rms_force(f_actuator, duty.weights, duty.period),
                       actuator_peak_force_N=float(np.max(np.abs(f_actuator))),
                       peak_thrust_N=float(np.max(np.abs(f_x))), peak_normal_N=peaks["normal_N"],
                       peak_pitch_Nm=peaks["pitch_Nm"], peak_roll_Nm=peaks["roll_Nm"], peak_yaw_Nm=peaks["yaw_Nm"],
                       checks=tuple(checks), ok=all(c.ok for c in checks))


def slip_check(accel: Array, limit: float, incline: float, g: float) -> RatingCheck:
    """The load must not slip on its carrier [m/s^2].

    Lecture, inclined plane: m a_max < mu_0 m g cos(alpha), the limit ``limit`` = mu_0 g cos(alpha).
    On an incline the weight's component adds to the force friction must supply when the load
    accelerates up the slope and subtracts going down: a_up < mu_0 g cos(alpha) - g sin(alpha),
    a_down < mu_0 g cos(alpha) + g sin(alpha) (positive travel is up the slope). Both are checked;
    the worse one is reported.
    """
    a = np.asarray(accel, dtype=float)
    up_need, down_need = float(max(np.max(a), 0.0)), float(max(-np.min(a), 0.0))
    up_limit = limit - g * math.sin(incline)
    down_limit = limit + g * math.sin(incline)
    cases = [(up_limit / up_need - 1.0 if up_need > 0 else math.inf, up_need, up_limit),
             (down_limit / down_need - 1.0 if down_need > 0 else math.inf, down_need, down_limit)]
    if min(up_limit, down_limit) <= 0.0:
        # mu_0 < tan(alpha): the load slides down the slope even at rest, whatever the profile.
        need, avail = (up_need, up_limit) if up_limit <= 0.0 else (down_need, down_limit)
        return RatingCheck("slip_limit", need, avail, "m/s^2", -1.0, False,
                           note="the load slides on its carrier at rest: the friction coefficient is below "
                                "tan(incline)")
    margin, need, avail = min(cases)
    note = "the profile never accelerates the load: nothing can slip (the margin is unbounded)" if need == 0.0 else None
    return RatingCheck("slip_limit", need, avail, "m/s^2", margin, margin >= 0.0, note=note)


__all__ = ["AxisCheck", "AxisChecks", "BandwidthCheck", "GearboxCheck", "GearboxChecks", "GuideReport", "Judged",
           "MechanismCheck", "ModeAtPosition", "Modes", "RatingCheck", "guide_report", "own_checks", "slip_check"]
