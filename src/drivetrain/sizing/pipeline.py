"""The sizing pipeline: one orchestrator, ``size_many``, from axis files to ``SizingResult``s.

Every face sizes through it: ``drivetrain.size`` and ``drivetrain size`` (which add the modes stage
from the dynamics layer), the report, the web app, a machine's axes and gantry shares, and a study's
batches. ``size(axis) = size_many([axis])[0]``. Its stages, in order, each a public function a caller
may start from (e.g. :func:`size_duty` from a duty cycle the caller has):

========================  ===============================================================================
stage                     function
========================  ===============================================================================
read                      :func:`read_axis`: a path, mapping or ``Axis`` to an ``Axis``
duty cycle                :meth:`Context.duty`: the motor-shaft duty cycle (``duty.cycle``); the sampled
                          kinematics shared between axes of equal profile
axis checks               :func:`axis_checks`: warnings, guide, slip, mechanism limits (screw, nut, belt,
                          rack; many axes at once by ``mechanism_checks.prepare_many``), brake
selection                 a given motor: ``result.motor_result`` (its checks and electrical half); a catalog
                          selection: :func:`select_motor` (``selection.select``, every candidate ranked;
                          or ``search.select_first``, the first candidate found smallest first)
drives                    :func:`drive_rule` (the selected motor must have an orderable drive,
                          ``drive_select.orderable``, of the supply's voltage class, and, with
                          ``requirements:``, pass the dynamic rule ``dynamic_selection.Judge``) and
                          ``drive_select.attach_drives`` (a drive per listed candidate; the selected
                          one's currents, winding, regen)
mechanism                 ``result.gearbox_rating_checks``: every rated gearbox of the axis with the
                          given or selected motor
modes                     :func:`attach_modes`: f1 across the stroke, by a function the caller passes
                          (the dynamics layer's ``mechanism_modes.modes_of_result``: sizing may not
                          import it)
verdict                   ``result.verdict`` (``SizingResult.ok``)
========================  ===============================================================================

What the stages keep between the axes of one call (catalog tables, sampled kinematics, the drive
rule's catalog reads) lives in a :class:`Context` the caller may pass and keep (a study's worker
keeps one): nothing is kept on other objects or in module state.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, overload

import numpy as np

from drivetrain.axis.model import Axis, load_axis, parse_axis
from drivetrain.duty.cycle import DutyCycle, demand_of, duty_from_samples
from drivetrain.errors import InputError
from drivetrain.sizing.drive_select import DriveMemo
from drivetrain.sizing.result import SizingResult, brake_check, gearbox_rating_checks, motor_result, selected_motor

if TYPE_CHECKING:
    from drivetrain.motion.cycle import Cycle, Samples
    from drivetrain.sizing.axis_blocks import AxisChecks, MechanismCheck, Modes
    from drivetrain.sizing.candidates import Selection
    from drivetrain.sizing.search import Prepared, Tables

AxisInput = Axis | dict[str, Any] | str | Path
ModesStage = Callable[[SizingResult], "Modes | None"]
Listing = Literal["ranked", "selected"]


@dataclass
class Context:
    """What the pipeline keeps between the axes it sizes: one per ``size_many`` call unless the caller
    passes its own (a study's worker keeps one for all its batches).

    Attributes
    ----------
    points_per_phase : int
        Samples per profile phase of the duty cycle.
    tables : dict
        The catalog tables of each selection spec the search met (``search.Tables``).
    kinematics : dict
        The sampled load motion (``Cycle``, ``Samples``) of each profile met, by its text.
    drives : DriveMemo
        The drive rule's catalog reads (drive rows, motor-series prefixes, each motor's prospect).
    """

    points_per_phase: int = 64
    tables: dict[str, Tables] = field(default_factory=dict)
    kinematics: dict[str, tuple[Cycle, Samples]] = field(default_factory=dict)
    drives: DriveMemo = field(default_factory=DriveMemo)

    def duty(self, axis: Axis) -> DutyCycle:
        """The duty-cycle stage: the axis's motor-shaft duty cycle (``duty.cycle.duty_cycle``), its
        profile's sampled kinematics shared with the axes of equal profile met before."""
        key = repr((axis.spec.profile, axis.mechanism.motion, self.points_per_phase))
        hit = self.kinematics.get(key)
        if hit is None:
            cycle = axis.cycle()
            hit = (cycle, cycle.sample(self.points_per_phase))
            if len(self.kinematics) > 4096:
                self.kinematics.clear()
            self.kinematics[key] = hit
        return duty_from_samples(axis, hit[0], hit[1])


def read_axis(axis: AxisInput) -> Axis:
    """The read stage: an axis file's path, its mapping, or an ``Axis`` as it is."""
    if isinstance(axis, (str, Path)):
        return load_axis(axis)
    if isinstance(axis, dict):
        return parse_axis(axis)
    return axis


def axis_checks(axis: Axis, duty: DutyCycle, mechanism: list[MechanismCheck] | None = None) -> AxisChecks:
    """The axis-checks stage: the answer's ``warnings``, ``guide``, ``slip_check``, ``mechanism_checks``
    and ``brake_check`` (those that apply). ``mechanism``: the axis's mechanism checks where the caller
    computed them (``mechanism_checks.prepare_many``)."""
    from drivetrain.duty.sanity import sanity_warnings
    from drivetrain.sizing.axis_blocks import AxisChecks, guide_report, slip_check

    warnings = tuple(sanity_warnings(axis, duty))
    guide = slip = None
    if axis.spec.guide is not None and axis.mechanism.motion == "linear":
        guide = guide_report(axis, duty)
    if axis.mechanism.slip_limit is not None:
        incline = getattr(axis.mechanism.load, "incline", 0.0)
        slip = slip_check(np.asarray(duty.samples.a), axis.mechanism.slip_limit, incline, axis.gravity)
    if mechanism is None:
        from drivetrain.sizing.mechanism_checks import mechanism_checks

        mechanism = mechanism_checks(axis, duty)
    return AxisChecks(warnings, guide, slip, tuple(mechanism), brake_check(axis, duty))


def select_motor(axis: Axis, duty: DutyCycle, *, all_pairs: bool = False, listing: Listing = "ranked",
                 context: Context | None = None, prepared: Prepared | None = None) -> Selection:
    """The selection stage of a ``motor: {select: ...}`` axis: every candidate ranked and the best of each
    motor listed (``listing="ranked"``, ``selection.select``; ``all_pairs`` lists every passing pair), or
    only the first candidate, found smallest first (``listing="selected"``, ``search.select_first``:
    the same selected candidate and figures, without the whole listing, counts or advice)."""
    from drivetrain.sizing.selection import select

    assert axis.spec.motor is not None and axis.spec.motor.select is not None
    spec, margins = axis.spec.motor.select, axis.spec.motor.margins
    if listing == "ranked" or all_pairs:
        return select(axis, duty, spec, margins, all_pairs=all_pairs)
    from drivetrain.sizing.search import select_first

    return select_first((context or Context()).tables, axis, duty, spec, margins, prepared)


def drive_rule(axis: Axis, duty: DutyCycle, chosen: Selection, *, listing: Listing = "ranked",
               context: Context | None = None, prepared: Prepared | None = None) -> Selection:
    """The drive rule of the drives stage: the selected motor is the best-ranked passing one whose drive
    can be ordered (``drive_select.orderable``); a search's answer is ranked in full first where the
    first candidate's drive decides. ``prepared``: the search's (``select_motor``), whose hulls a
    ranking of the whole catalog reuses."""
    from drivetrain.sizing.drive_select import orderable
    from drivetrain.sizing.selection import select

    assert axis.spec.motor is not None and axis.spec.motor.select is not None
    spec, margins = axis.spec.motor.select, axis.spec.motor.margins
    reselect = None if listing == "ranked" else (lambda: select(axis, duty, spec, margins))
    judge = None
    judged_first = False
    memo = (context or Context()).drives
    if axis.requirements is not None:
        # the dynamic rule (docs/checks.md, "Dynamic selection") lives in the dynamics layer, above this
        # one: looked up by name, as the report is (docs/architecture.md)
        import importlib

        fastest = spec.objective == "fastest_settling"
        # the stroke from the duty cycle at hand where it is sampled as duty_cycle samples it (64 per phase)
        sampled = duty if context is not None and context.points_per_phase == 64 else None
        judge = importlib.import_module("drivetrain.dynamics.dynamic_selection").Judge(
            axis, objective="fastest_settling" if fastest else "first_passing", duty=sampled)
        if fastest:  # judge the top candidates (refusing all) on a copy, then walk again to the fastest
            import copy

            chosen = reselect() if reselect is not None else chosen
            reselect = None
            probe = copy.copy(chosen)
            probe.summary, probe.ranking = copy.copy(chosen.summary), copy.copy(chosen.ranking)
            judge.collect = True
            orderable(axis, duty, probe, None, memo, judge)
            judge.settle_on_fastest()
        elif reselect is not None:
            # a search's answer: its orderable pick is judged first; only when it is passed over is the whole
            # ranking needed for the walk (the same walk, in the same order, meeting that pick first)
            searched = chosen
            chosen = orderable(axis, duty, chosen, reselect, memo)
            reselect = reselect if chosen is searched else None  # else the drive rule ranked in full already
            best = chosen.ranking.best
            if best is not None and chosen.summary.drive_advice is None:
                c, gb = chosen.ranking.candidates, chosen.ranking.gearboxes
                g = int(c.gearbox(best))
                judged_first = judge.first(str(chosen.ranking.motors.ids[int(c.motor[best])]),
                                           str(gb.ids[g]) if g >= 0 and gb is not None else None)
            if not judged_first and reselect is not None:
                # passed over: the whole ranking for the walk, without the listing's rows (only the answer's
                # rows are built, by the walk); the judge keeps its set-up and the static pick's answer
                from drivetrain.sizing.search import select_first

                chosen, reselect = select_first((context or Context()).tables, axis, duty, spec, margins, prepared,
                                                whole=True), None
    if not judged_first:
        chosen = orderable(axis, duty, chosen, reselect, memo, judge)
    if judge is not None:
        dyn = chosen.summary.dynamics = judge.to_dict()
        if axis.requirements is not None and axis.requirements.settling_ratio and chosen.ranking.best is not None:
            from drivetrain.sizing.selection import candidate_cycle

            ratio = judge.settling_ratio(candidate_cycle(axis, duty, chosen.ranking)[0])
            if ratio is not None:
                dyn["settling_optimal_ratio"] = ratio
        return _count_dynamics(chosen, judge)
    return chosen


def _count_dynamics(chosen: Selection, judge: Any) -> Selection:
    """The dynamic checks count with the static ones in ``failures_by_check`` and ``unknown_by_check`` (of
    the candidates judged: ``dynamic_selection.failure_counts``); ``dynamics.answer_inertia_ratio`` is the
    inertia ratio the dynamic pick ends up with."""
    import importlib

    summary = chosen.summary
    dyn = summary.dynamics
    assert dyn is not None
    fails, unknown = importlib.import_module("drivetrain.dynamics.dynamic_selection").failure_counts(dyn)
    if summary.failures_by_check is not None:
        summary.failures_by_check = {**summary.failures_by_check, **fails}
    if summary.unknown_by_check is not None:
        summary.unknown_by_check = {**summary.unknown_by_check, **unknown}
    pick = summary.selected
    if dyn.get("chosen") and pick is not None and pick.motor == dyn["chosen"]["motor"]:
        # the inertia ratio is a consequence: the one the dynamic pick ends up with (docs/checks.md)
        dyn["answer_inertia_ratio"] = pick.inertia_ratio
    return chosen


def attach_modes(result: SizingResult, modes: ModesStage) -> SizingResult:
    """The modes stage: ``result.modes = modes(result)`` (f1 across the stroke with the given or
    selected motor; None where the mechanism has no stiffness data or there is no motor)."""
    result.modes = modes(result)
    return result


def size_duty(axis: Axis, duty: DutyCycle, *, all_pairs: bool = False, listing: Listing = "ranked",
              drives: bool = True, context: Context | None = None, mechanism: list[MechanismCheck] | None = None,
              prepared: Prepared | None = None, own_checks: SizingResult | None = None,
              load_share: float | None = None, modes: ModesStage | None = None) -> SizingResult:
    """The pipeline from a duty cycle the caller has: axis checks, selection, drives, mechanism, modes.

    ``drives=False`` leaves out the drive blocks of a selection's candidates (``attach_drives``:
    the ``drive``, ``electrical`` and ``regen`` of its candidates), which changes no other key; the drive
    rule holds either way. ``own_checks``: an answer whose own checks (axis checks and gearbox ratings) are
    kept as they are, and ``load_share`` the fraction of its load this one carries (a gantry share keeps its
    whole axis's checks). ``mechanism``, ``prepared``: what ``size_many`` computed for many axes together.
    """
    context = context or Context()
    kept = axis_checks(axis, duty, mechanism) if own_checks is None else own_checks
    result = SizingResult(axis=axis, duty=duty, metrics=demand_of(duty), warnings=list(kept.warnings),
                          guide=kept.guide, slip_check=kept.slip_check, mechanism_checks=list(kept.mechanism_checks),
                          brake_check=kept.brake_check, load_share=load_share)
    gear = None if own_checks is None else own_checks.gearbox_checks
    if axis.motor is not None:
        result.motor, beside = motor_result(axis, duty, axis.motor)
        result.drive, result.regen = beside.get("drive"), beside.get("regen")  # the electrical half's
        if own_checks is None:
            gear = gearbox_rating_checks(axis, duty, axis.motor)
    elif axis.spec.motor is not None and axis.spec.motor.select is not None:
        from drivetrain.sizing.drive_select import attach_drives

        chosen = select_motor(axis, duty, all_pairs=all_pairs, listing=listing, context=context, prepared=prepared)
        chosen = drive_rule(axis, duty, chosen, listing=listing, context=context, prepared=prepared)
        if drives:
            attach_drives(axis, duty, chosen, axis.spec.motor.margins, context.drives)
        result.candidates, result.selection, result.ranking = chosen.listed, chosen.summary, chosen.ranking
        if own_checks is None:
            strict = axis.spec.motor.select.unknown == "fail"
            gear = gearbox_rating_checks(axis, duty, selected_motor(chosen.ranking), strict)
        own = [st.name for st in axis.transmission if st.kind == "gearbox"]
        if own and not result.selection.gearbox_rows:
            # the motors go direct onto the axis's own gearbox: say so, not "direct drive, ratio 1"
            result.selection.transmission_gearbox = ", ".join(own)
    elif axis.drive is not None:
        raise InputError("drive", "a given drive needs a motor: give motor: {id: ...}, its parameters, "
                         "or motor: {select: ...}", has_value=False)
    elif own_checks is None:
        gear = gearbox_rating_checks(axis, duty, None)
    result.gearbox_checks = gear
    if modes is not None:
        attach_modes(result, modes)
    return result


@overload
def size_many(axes: Sequence[AxisInput], points_per_phase: int = ..., all_pairs: bool = ..., *,
              listing: Listing = ..., drives: bool = ..., modes: ModesStage | None = ...,
              context: Context | None = ..., errors: Literal["raise"] = ...) -> list[SizingResult]: ...


@overload
def size_many(axes: Sequence[AxisInput], points_per_phase: int = ..., all_pairs: bool = ..., *,
              listing: Listing = ..., drives: bool = ..., modes: ModesStage | None = ...,
              context: Context | None = ..., errors: Literal["return"]) -> list[SizingResult | InputError]: ...


def size_many(axes: Sequence[AxisInput], points_per_phase: int = 64, all_pairs: bool = False, *,
              listing: Listing = "ranked", drives: bool = True, modes: ModesStage | None = None,
              context: Context | None = None,
              errors: Literal["raise", "return"] = "raise") -> list[SizingResult] | list[SizingResult | InputError]:
    """Size axes (paths, mappings or ``Axis``): each one's answer, as it gets alone.

    ``all_pairs`` lists every passing motor-gearbox pair of a selection (``drivetrain size --all``);
    ``listing="selected"`` finds only a selection's selected candidate (``search.select_first``), as a
    study records it; ``drives=False`` leaves out the drive blocks of a selection's candidates;
    ``modes`` is the modes stage (``drivetrain.size`` passes the dynamics layer's). Many axes share
    work: their mechanism checks as arrays over the axes (``mechanism_checks.prepare_many``) and, for
    ``listing="selected"``, the first hulls of the axes of equal motion (``search.prepare_hulls``).
    ``errors="return"`` puts an axis's InputError in its place instead of raising it.
    """
    if context is None:
        context = Context(points_per_phase)
    elif context.points_per_phase != points_per_phase:
        raise ValueError("the context samples another number of points per phase")
    read: list[tuple[Axis, DutyCycle] | InputError] = []
    for a in axes:
        try:
            axis = read_axis(a)
            read.append((axis, context.duty(axis)))
        except InputError as exc:
            if errors == "raise":
                raise
            read.append(exc)
    pairs = [x for x in read if not isinstance(x, InputError)]
    mechanism: list[list[MechanismCheck] | None] = [None] * len(pairs)
    prepared: list[Prepared | None] = [None] * len(pairs)
    if len(pairs) > 1:
        from drivetrain.sizing.mechanism_checks import prepare_many

        mechanism = prepare_many(pairs)
    if listing == "selected" and not all_pairs:
        from drivetrain.sizing.search import prepare_hulls

        prepared = prepare_hulls(context.tables, pairs)
    out: list[SizingResult | InputError] = []
    index = 0
    for x in read:
        if isinstance(x, InputError):
            out.append(x)
            continue
        axis, duty = x
        try:
            out.append(size_duty(axis, duty, all_pairs=all_pairs, listing=listing, drives=drives, context=context,
                                 mechanism=mechanism[index], prepared=prepared[index], modes=modes))
        except InputError as exc:
            if errors == "raise":
                raise
            out.append(exc)
        index += 1
    return out


def size(axis: AxisInput, points_per_phase: int = 64, all_pairs: bool = False, *, listing: Listing = "ranked",
         drives: bool = True, modes: ModesStage | None = None, context: Context | None = None) -> SizingResult:
    """``size_many([axis], ...)[0]``: one axis's answer (see :func:`size_many`)."""
    return size_many([axis], points_per_phase, all_pairs, listing=listing, drives=drives, modes=modes,
                     context=context)[0]


__all__ = [
    "Context",
    "attach_modes",
    "axis_checks",
    "drive_rule",
    "read_axis",
    "select_motor",
    "size",
    "size_duty",
    "size_many",
]
