"""The mechanism's own checks over the duty cycle: screw limits and nut life, guide life, belt tension, rack force.

``mechanism_checks(axis, duty)`` returns the ``mechanism_checks`` list of the sizing result, each
entry a ``sizing.axis_blocks.MechanismCheck`` (name, required, available, margin, ok, unit, its
``source`` and note; its ``to_dict()`` the entry of the JSON). A check runs only where the axis file
gives the ratings it needs (docs/axis-file.md, "Mechanism limits"); the formulas live in ``drivetrain.physics``
(screw_limits, rolling_life, belt_rack) with their sources, and docs/checks.md lists them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.axis.model import Axis
from drivetrain.duty.cycle import DutyCycle
from drivetrain.errors import InputError
from drivetrain.physics import belt_rack, rolling_life, screw_limits
from drivetrain.physics.guides import carriage_moments
from drivetrain.physics.mechanisms.base import LinearLoad
from drivetrain.sizing.axis_blocks import MechanismCheck

Array = NDArray[np.float64]
RPM = 60.0 / (2.0 * math.pi)
"""[rpm per rad/s]: speed checks print in rpm like the motor's max_speed check."""

SRC_THK_AXIAL = "THK General Catalog, Ball Screw, Permissible Axial Load, A15-30 eq. (5), (6)"
SRC_THK_SPEED = "THK General Catalog, Ball Screw, Permissible Rotational Speed, A15-32 eq. (7)-(17)"
SRC_NUT_LIFE = "MiSUMi 2025 Technical Data p. 1678; THK Studying the Service Life; Steinmeyer equivalent load"
SRC_GUIDE = "THK LM Guide Calculating the Nominal Life and Static Safety Factor; ISO 14728-1"
SRC_BELT = "Gates Mectrol Timing Belt Theory 3.1-3.3; ELATECH catalog p. 54 (F_Tmax = F_TV + F_U)"
SRC_RACK = "Shigley ch. 13 mesh forces; vendor permissible feed force with application factor K_A"


def _check(name: str, required: float, available: float, unit: str, source: str, note: str = "",
           status: str | None = None) -> MechanismCheck:
    margin = available / required - 1.0 if required > 0.0 else math.inf
    return MechanismCheck(name, float(required), float(available), float(margin), bool(margin >= 0.0), unit, source,
                          note=note, status=status)


def _unjudged(name: str, required: float, bound: float | None, unit: str, source: str, note: str) -> MechanismCheck:
    """A check that cannot be judged from what is given: ``bound`` [unit] is an upper bound on what is
    available (None: none). Required above the bound fails with it; otherwise it is unknown (margin None)."""
    if bound is not None and required > bound:
        return _check(name, required, bound, unit, source, note, status="fail")
    return MechanismCheck(name, float(required), None, None, True, unit, source, note=note, status="unknown")


def screw_bounds(span: float | None, diameter: float | None, stroke: float, mounting: str = "fixed_supported",
                 ) -> tuple[float | None, float | None, float | None, str]:
    """Upper bounds on a screw's permissible compressive load [N], tensile/compressive load [N] and
    critical speed [rad/s] without ``mechanism.screw``: the root (thread minor) diameter d_1 is at most
    the nominal ``diameter`` [m], and each limit grows with d_1 (buckling with d_1^4, the load at the
    permissible stress with d_1^2, the critical speed with d_1: physics/screw_limits.py, THK A15-30 and
    A15-32), so the nominal diameter bounds them all from above. Lengths [m]: the critical speed over the
    ``span`` (the screw's length, THK's l_b); the buckling length is at least what the nut's travel over
    the ``stroke`` forces (``buckling_length``): the stroke (fixed-free, fixed-supported), (span +
    stroke) / 2 (fixed-fixed), the span (supported-supported). None where a length or the diameter is
    missing; the last item says what is missing ("" when nothing)."""
    missing = [f for f, v in (("mechanism.diameter", diameter), ("mechanism.length", span)) if v is None]
    if diameter is None:
        return None, None, None, " and ".join(missing)
    tensile = screw_limits.permissible_tensile_compressive_load(diameter)
    if span is None:
        return None, tensile, None, " and ".join(missing)
    crit = float(screw_limits.critical_speed(diameter, span, mounting))
    shortest = {"fixed_free": stroke, "fixed_supported": stroke, "fixed_fixed": (span + stroke) / 2.0,
                "supported_supported": span}[mounting]
    buck = float(screw_limits.buckling_load(diameter, min(shortest, span), mounting)) if shortest > 0.0 else None
    return buck, tensile, crit, ""


def _screw_bound_rows(spec: Any, duty: DutyCycle, f_peak: Array, w_peak: Array,
                      out: list[list[MechanismCheck]]) -> None:
    """The screw checks of axes without ``mechanism.screw``, bounded from the nominal diameter (screw_bounds)."""
    lo, hi = _stroke(duty)
    mounting = "fixed_supported"  # ScrewLimitsSpec's default: no block, no stated mounting
    buck, tensile, crit, missing = screw_bounds(getattr(spec, "length", None), getattr(spec, "diameter", None),
                                                hi - lo, mounting)
    d = getattr(spec, "diameter", None)
    basis = (f"upper bound: root diameter taken as the nominal {d * 1e3:g} mm, {mounting} (the default)"
             if d is not None else "")
    give = "give mechanism.screw.root_diameter (and its mounting) to judge it"
    if missing:
        give = f"give {missing} and mechanism.screw.root_diameter to judge it"
    for k, row in enumerate(out):
        for name, req, bound, unit, src in (
                ("screw_buckling", float(f_peak[k]), buck, "N", SRC_THK_AXIAL),
                ("screw_tensile_compressive", float(f_peak[k]), tensile, "N", SRC_THK_AXIAL),
                ("screw_critical_speed", float(w_peak[k]) * RPM, None if crit is None else crit * RPM, "rpm",
                 SRC_THK_SPEED)):
            fails = bound is not None and req > bound
            note = (f"{basis}: {bound:.4g} {unit}, below what is required whatever the root diameter"
                    if fails and bound is not None else
                    f"{basis + f': at most {bound:.4g} {unit}; ' if bound is not None else ''}{give}")
            row.append(_unjudged(name, req, bound, unit, src, note))


def belt_stiffness_note(axis: Axis) -> MechanismCheck | None:
    """For a belt axis whose belt stiffness is not given: an unknown ``belt_stiffness`` entry saying that
    the modes treat the belt as rigid and what to give (dynamics/axis_stiffness.py needs
    ``mechanism.belt.specific_stiffness``, or ``permissible_tension``, and ``centre_distance``)."""
    spec = axis.spec.mechanism
    if getattr(spec, "type", None) not in ("belt", "timing_belt", "conveyor"):
        return None
    belt = getattr(spec, "belt", None)
    gaps = []
    if belt is None or (belt.specific_stiffness is None and belt.permissible_tension is None):
        gaps.append("mechanism.belt.specific_stiffness (or permissible_tension)")
    if belt is None or belt.centre_distance is None:
        gaps.append("mechanism.belt.centre_distance")
    if not gaps:
        return None
    return MechanismCheck("belt_stiffness", None, None, None, True, "N", SRC_BELT, status="unknown",
                          note=f"the modes treat the belt as rigid: give {' and '.join(gaps)} to include its stiffness")


def output_loads(axis: Axis, duty: DutyCycle) -> tuple[float, float]:
    """The largest radial and axial load the axis puts on the shaft that drives its mechanism [N]: what a
    catalog gearbox's output carries when it drives the mechanism directly (its F2r / F2a checks,
    kernel.py). NaN where it is not modelled.

    * belt, timing belt, conveyor: the drive pulley's shaft load, sqrt(T_t^2 + T_s^2 - 2 T_t T_s cos(wrap))
      over the cycle (``belt_rack.pulley_shaft_load``), with the tensions of ``_belt_checks`` (the stated
      pretension, default the largest pull; all pull on one span where the belt's geometry is not given);
      no axial load;
    * rack and pinion: the pinion's sqrt(F_t^2 + F_r^2) radial and F_t tan(beta) axial
      (``belt_rack.pinion_shaft_load``, Shigley ch. 13);
    * ball and lead screw: none on the drive shaft (the screw's thrust is carried by its fixed bearing);
    * a first transmission stage that is a coupling: none (a flexible coupling carries no shaft load);
      any other first stage, and the other mechanisms (rotary, roll, hoist, chain, custom): NaN.
    """
    kind = getattr(axis.spec.mechanism, "type", "")
    first = axis.transmission[0].kind if axis.transmission else None
    if first == "coupling" or (kind in ("ball_screw", "lead_screw") and first is None):
        return 0.0, 0.0
    if first is not None or kind not in ("belt", "timing_belt", "conveyor", "rack_pinion"):
        return math.nan, math.nan
    force = axial_force(axis, duty)
    if kind == "rack_pinion":
        rack = getattr(axis.spec.mechanism, "rack", None)
        alpha, beta = (rack.pressure_angle, rack.helix_angle) if rack is not None else (math.radians(20.0), 0.0)
        radial, axial = belt_rack.pinion_shaft_load(np.abs(force), alpha, beta)
        return float(np.max(radial)), float(np.max(np.abs(axial)))
    belt = getattr(axis.spec.mechanism, "belt", None)
    pull = np.abs(force)
    lp, lo = np.zeros_like(pull), np.ones_like(pull)  # all pull on one span: the largest shaft load
    if belt is not None and belt.centre_distance is not None:
        try:
            lp, lo = belt_rack.linear_belt_spans(belt_positions(axis, duty), belt.centre_distance, belt.layout,
                                                 belt.clamp_offset)
            lp, lo = np.where(force >= 0.0, lo, lp), np.where(force >= 0.0, lp, lo)
        except InputError:
            return math.nan, math.nan
    pre = belt.pretension if belt is not None and belt.pretension is not None else float(pull.max())
    tight, slack = belt_rack.linear_belt_tensions(pull, pre, lp, lo)
    wrap = belt.wrap_angle if belt is not None else math.pi
    return float(np.max(belt_rack.pulley_shaft_load(tight, slack, wrap))), 0.0


def axial_force(axis: Axis, duty: DutyCycle) -> Array:
    """Force the mechanism transmits to the load along its travel over the cycle [N]: F_ext + M a."""
    load = axis.mechanism.load
    if not isinstance(load, LinearLoad):
        raise TypeError("axial_force needs a linear mechanism")
    s = duty.samples
    x, v, a = (np.asarray(s.x, dtype=float), np.asarray(s.v, dtype=float), np.asarray(s.a, dtype=float))
    direction = np.asarray(s.direction, dtype=float)
    thrust = np.asarray(s.thrust, dtype=float)
    thrust = np.where(np.isnan(thrust), load.thrust, thrust)
    thrust = np.where(direction == 0.0, 0.0, thrust)
    f = load.force(x, v, direction, thrust, axis.gravity) + load.moving_mass * a
    return np.asarray(np.where(np.asarray(s.braked, dtype=bool), load.force(x, 0 * v, 0 * v, 0 * v, axis.gravity), f),
                      dtype=float)


def _stroke(duty: DutyCycle) -> tuple[float, float]:
    x = np.asarray(duty.samples.x, dtype=float)
    return float(x.min()), float(x.max())


def nut_travel_positions(axis: Axis, duty: DutyCycle, points: int = 41) -> tuple[Array, float]:
    """Nut positions [m] from the fixed bearing across the stroke, and the bearing span [m]."""
    spec = axis.spec.mechanism
    limits = getattr(spec, "screw", None)
    if limits is None:
        raise InputError("mechanism.screw", "is required for nut positions", has_value=False)
    span = limits.unsupported_length or getattr(spec, "length", None)
    if span is None:
        raise InputError("mechanism.screw.unsupported_length", "is required when mechanism.length is not given",
                         has_value=False)
    lo, hi = _stroke(duty)
    pos = limits.home_position + np.linspace(lo, hi, points)
    if pos.min() < 0.0 or pos.max() > span:
        raise InputError("mechanism.screw.home_position",
                         f"puts the nut outside the screw over the stroke ({pos.min():.4g} to {pos.max():.4g} m "
                         f"from the fixed bearing, span {span:g} m)", limits.home_position)
    return np.clip(pos, 1e-6 * span, span * (1 - 1e-9) if limits.mounting == "fixed_fixed" else span), float(span)


def belt_positions(axis: Axis, duty: DutyCycle) -> Array:
    """Carriage positions from the drive pulley over the cycle's samples [m] (``mechanism.belt``)."""
    belt = getattr(axis.spec.mechanism, "belt", None)
    if belt is None:
        raise InputError("mechanism.belt", "is required for carriage positions", has_value=False)
    return np.asarray(belt.home_position + np.asarray(duty.samples.x, dtype=float), dtype=float)


def _belt_checks(axis: Axis, duty: DutyCycle, force: Array) -> list[MechanismCheck]:
    belt = getattr(axis.spec.mechanism, "belt", None)
    if belt is None:
        return []
    pull = np.abs(force)
    if belt.centre_distance is not None:
        try:
            lp, lo = belt_rack.linear_belt_spans(belt_positions(axis, duty), belt.centre_distance, belt.layout,
                                                 belt.clamp_offset)
        except InputError as exc:
            raise InputError("mechanism.belt.home_position", f"the carriage leaves the belt over the stroke "
                             f"({exc.rule})", belt.home_position) from None
        # A force towards +x (away from the drive pulley) is pulled through the path round the idler
        # (loop) or the far span (omega); a force towards the pulley through the direct span.
        lp, lo = np.where(force >= 0.0, lo, lp), np.where(force >= 0.0, lp, lo)
    else:
        lp, lo = np.zeros_like(pull), np.ones_like(pull)  # worst case: all pull on one span
    need = belt_rack.minimum_pretension(pull, lp, lo)
    pre = belt.pretension if belt.pretension is not None else float(pull.max())
    tight, slack = belt_rack.linear_belt_tensions(pull, pre, lp, lo)
    out = [_check("belt_slack_side", need, pre, "N", SRC_BELT, "pretension needed to keep the slack span taut")]
    permissible = belt.permissible_tension
    if permissible is not None:
        out.append(_check("belt_tension", float(tight.max()), permissible, "N", SRC_BELT,
                          f"pretension {pre:.4g} N" + ("" if belt.pretension is not None else " (default: peak pull)")))
    shaft = belt_rack.pulley_shaft_load(tight, slack, belt.wrap_angle)
    out[-1] = replace(out[-1], note=out[-1].note + f"; peak pulley shaft load {float(shaft.max()):.4g} N")
    return out


def _rack_checks(axis: Axis, duty: DutyCycle, force: Array) -> list[MechanismCheck]:
    rack = getattr(axis.spec.mechanism, "rack", None)
    if rack is None or rack.permissible_force is None:
        return []
    ft = np.abs(force)
    radial, _ = belt_rack.pinion_shaft_load(ft, rack.pressure_angle, rack.helix_angle)
    c = _check("rack_feed_force", rack.application_factor * float(ft.max()), rack.permissible_force, "N", SRC_RACK,
               f"K_A = {rack.application_factor:g}; peak radial load on the pinion shaft {float(radial.max()):.4g} N")
    return [c]


def mechanism_checks(axis: Axis, duty: DutyCycle) -> list[MechanismCheck]:
    """Every mechanism check the axis file has ratings for (empty if none, or for a rotary mechanism).

    :func:`prepare_many` gives the same entries for many axes, computed together.
    """
    if axis.mechanism.motion != "linear":
        return []
    force = axial_force(axis, duty)
    belt = belt_stiffness_note(axis)
    return [*_checks_of_group([(axis, duty, force)])[0], *_belt_checks(axis, duty, force),
            *_rack_checks(axis, duty, force), *([belt] if belt is not None else [])]


# ---------------------------------------------------------------------------------------------
# the screw, nut and guide checks as arrays over axes: one axis (mechanism_checks) or many (a study)

PREPARE_SLICE = 256
"""Axes computed together at most (their arrays of samples stay a few MB)."""


def prepare_many(pairs: Sequence[tuple[Axis, DutyCycle]]) -> list[list[MechanismCheck] | None]:
    """The mechanism checks of many (axis, duty cycle) pairs, computed together: for each pair its
    :func:`mechanism_checks`, or None where it was not computed here (then :func:`mechanism_checks`
    of that pair computes it, or raises its InputError).

    The axes are taken in groups that differ only in what the checks read per axis (the load's
    mass and forces, the screw lead, the motion's speeds and sample weights) and share the rest
    (screw, nut and guide ratings, the stroke, the number of samples, no belt or rack). Each
    group's sample-wise work (peak speeds and forces, equivalent loads, cubic means) runs as arrays
    over its axes; :func:`mechanism_checks` of one axis is the same computation for a group of one,
    and ``tests/study/test_study_mechanism_batch.py`` asserts the entries equal, to the bit. A group whose
    numbers would raise an InputError (or any axis outside these cases) is left to
    :func:`mechanism_checks`, which raises it for its own axis.
    """
    groups: list[tuple[tuple[Any, ...], list[tuple[int, Axis, DutyCycle, Array]]]] = []
    out: list[list[MechanismCheck] | None] = [None] * len(pairs)
    for index, (axis, duty) in enumerate(pairs):
        spec = axis.spec.mechanism
        if (axis.mechanism.motion != "linear" or not isinstance(axis.mechanism.load, LinearLoad)
                or getattr(spec, "belt", None) is not None or getattr(spec, "rack", None) is not None):
            continue
        try:
            force = axial_force(axis, duty)
            key = (getattr(spec, "screw", None), getattr(spec, "nut", None), getattr(spec, "length", None),
                   getattr(spec, "diameter", None), axis.spec.guide, _stroke(duty), force.shape)
        except InputError:
            continue
        for known, members in groups:
            if known == key:
                members.append((index, axis, duty, force))
                break
        else:
            groups.append((key, [(index, axis, duty, force)]))
    for _, group in groups:
        for start in range(0, len(group), PREPARE_SLICE):
            members = group[start:start + PREPARE_SLICE]
            try:
                lists = _checks_of_group([(a, d, f) for _, a, d, f in members])
            except InputError:
                continue
            for (index, axis, _, _), checks in zip(members, lists, strict=True):
                belt = belt_stiffness_note(axis)
                out[index] = checks if belt is None else [*checks, belt]
    return out


def _checks_of_group(members: list[tuple[Axis, DutyCycle, Array]]) -> list[list[MechanismCheck]]:
    """The screw, nut and guide checks of axes that share their ratings and stroke (prepare_many)."""
    first, first_duty, _ = members[0]
    spec = first.spec.mechanism
    limits = getattr(spec, "screw", None)
    nut = getattr(spec, "nut", None)
    force = np.stack([f for _, _, f in members])
    lever = np.array([a.mechanism.lever for a, _, _ in members])
    v = np.stack([np.asarray(d.samples.v, dtype=float) for _, d, _ in members])
    weights = np.stack([d.weights for _, d, _ in members])
    omega = v / lever[:, None]
    w_peak = np.max(np.abs(omega), axis=1)
    f_peak = np.max(np.abs(force), axis=1)
    out: list[list[MechanismCheck]] = [[] for _ in members]
    if limits is not None:  # the ratings and the stroke are the group's: the first axis's checks hold for all
        pos, span = nut_travel_positions(first, first_duty)
        d1 = limits.root_diameter
        buck = float(screw_limits.buckling_load(d1, screw_limits.buckling_length(pos, span, limits.mounting),
                                                limits.mounting, limits.youngs_modulus).min())
        tensile = screw_limits.permissible_tensile_compressive_load(d1)
        crit = float(screw_limits.critical_speed(d1, span, limits.mounting, limits.youngs_modulus))
        dn = None
        if limits.dn_limit is not None:
            dcirc = limits.ball_circle_diameter or getattr(spec, "diameter", None)
            if dcirc is None:
                raise InputError("mechanism.screw.ball_circle_diameter", "is required for the DN check "
                                 "(or give mechanism.diameter)", has_value=False)
            dn = (screw_limits.dn_speed_limit(dcirc, limits.dn_limit) * RPM, dcirc)
        for k, row in enumerate(out):
            row.append(_check("screw_buckling", f_peak[k], buck, "N", SRC_THK_AXIAL,
                              "largest axial load taken as compressive; worst nut position over the stroke"))
            row.append(_check("screw_tensile_compressive", f_peak[k], tensile, "N", SRC_THK_AXIAL))
            row.append(_check("screw_critical_speed", w_peak[k] * RPM, crit * RPM, "rpm", SRC_THK_SPEED,
                              f"unsupported length {span:g} m, {limits.mounting}"))
            if dn is not None:
                row.append(_check("screw_dn_speed", w_peak[k] * RPM, dn[0], "rpm", SRC_THK_SPEED,
                                  f"DN {limits.dn_limit:g} mm/min at D = {dn[1] * 1e3:g} mm"))
    elif getattr(spec, "type", None) in ("ball_screw", "lead_screw"):
        _screw_bound_rows(spec, first_duty, f_peak, w_peak, out)
    if nut is not None:
        _nut_checks(members, nut, force, omega, weights, out)
    if first.spec.guide is not None and first.spec.guide.dynamic_rating is not None:
        _guide_rows(members, force, v, weights, out)
    return out


def _nut_checks(members: list[tuple[Axis, DutyCycle, Array]], nut: Any, force: Array, omega: Array, weights: Array,
                out: list[list[MechanismCheck]]) -> None:
    """nut_life and nut_static_safety of a group (screw_limits.nut_life row by row: its formulas, from the
    cubic-mean load of each row)."""
    try:
        c = screw_limits._positive(nut.C_a, "nut.C_a", "N")
        fw = screw_limits._positive(nut.load_factor, "load_factor", "")
        leads = [screw_limits._positive(getattr(a.spec.mechanism, "lead", a.mechanism.lever * 2 * math.pi), "lead",
                                        "m") for a, _, _ in members]
        if not np.all(np.isfinite(weights)) or np.any(weights < 0.0):
            raise InputError("dt", "must be >= 0 s", float(np.min(weights)))
        revs = np.abs(omega) * weights / (2.0 * math.pi)
        loaded = screw_limits.preloaded_nut_load(force, nut.preload)
        f_m = rolling_life.cubic_mean_loads(loaded, revs)
    except InputError as exc:
        raise exc.at("mechanism.nut") from None
    revs_cycle = np.sum(revs, axis=1)
    cycle_time = np.sum(weights, axis=1)
    f_static = np.max(loaded, axis=1)
    for k, h in enumerate(leads):
        life = screw_limits.nut_life_from_mean(c, float(f_m[k]), float(revs_cycle[k]), float(cycle_time[k]), h, fw)
        out[k].append(_check("nut_life", nut.required_life / 3600.0, life.hours, "h", SRC_NUT_LIFE,
                             f"F_m = {life.equivalent_load:.4g} N, L10 = {life.revolutions:.4g} rev = "
                             f"{life.km:.4g} km"))
        if nut.C_0a is not None:
            fs = nut.C_0a / float(f_static[k]) if f_static[k] > 0 else math.inf
            out[k].append(_check("nut_static_safety", nut.static_safety, fs, "-",
                                 SRC_THK_AXIAL + "; ISO 76 s0 = C0 / P0"))


def _guide_rows(members: list[tuple[Axis, DutyCycle, Array]], force: Array, v: Array, weights: Array,
                out: list[list[MechanismCheck]]) -> None:
    """guide_life and guide_static_safety of a group, row by row."""
    g = members[0][0].spec.guide
    assert g is not None and g.dynamic_rating is not None
    loads = [a.mechanism.load for a, _, _ in members]
    assert all(isinstance(load, LinearLoad) for load in loads)  # a linear mechanism's load
    weight = np.array([[load.mass * a.gravity] for load, (a, _, _) in zip(loads, members, strict=True)])  # type: ignore[union-attr]
    mom = carriage_moments(force, weight, g.l_x, g.l_y, g.l_z, g.d_p, g.d_r, g.orientation)  # type: ignore[arg-type]
    moments = {k.split("_")[0]: mom[k] for k in ("pitch_Nm", "roll_Nm", "yaw_Nm")}
    factors: dict[str, float] = {str(k): float(v) for k, v in (g.moment_factors or {}).items()}
    used: dict[str, ArrayLike] = {name: m for name, m in moments.items() if name in factors}
    unused = np.zeros(len(members), dtype=bool)
    for name, m in moments.items():
        if name not in factors:
            unused |= np.any(np.abs(m) > 0, axis=1)
    p = rolling_life.guide_equivalent_load(mom["normal_N"] / g.carriages, used, factors)
    travel = rolling_life.travel_weights(v, weights)
    loaded = np.max(p, axis=1) > 0.0
    p_m = np.zeros(len(members))
    if np.any(loaded):
        p_m[loaded] = rolling_life.cubic_mean_loads(p[loaded], travel[loaded], rolling_life.life_exponent(g.rolling))
    travel_cycle = np.sum(travel, axis=1)
    fs = None
    if g.static_rating is not None:
        fs = np.min(rolling_life.guide_static_safety_factor(g.static_rating, np.maximum(p, 1e-300)), axis=1)
    for k, (_, duty, _) in enumerate(members):
        if not loaded[k]:
            out[k].append(_check("guide_life", g.required_life / 3600.0, math.inf, "h", SRC_GUIDE,
                                 "no load on the carriages"))
            continue
        note = "moments without moment_factors are not in the carriage load" if unused[k] else ""
        life_m = float(rolling_life.guide_life(g.dynamic_rating, max(float(p_m[k]), 1e-12), g.rating_distance,
                                               g.rolling, f_w=g.load_factor))
        hours = float(rolling_life.life_time(life_m, float(travel_cycle[k]), duty.period)) / 3600.0
        out[k].append(_check("guide_life", g.required_life / 3600.0, hours, "h", SRC_GUIDE,
                             f"P_m = {float(p_m[k]):.4g} N per carriage, L10 = {life_m / 1e3:.4g} km"
                             + (f"; {note}" if note else "")))
        if fs is not None:
            out[k].append(_check("guide_static_safety", g.static_safety, float(fs[k]), "-", SRC_GUIDE))
