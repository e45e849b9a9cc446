"""The selection that knows how the axis will move: walk the static passes best first and keep the
first that also passes its dynamic checks (``response.candidate_response``), or, for the objective
``fastest_settling``, the one that settles fastest among those judged (``Judge``, the rule the
pipeline's drive stage runs in the selection's walk).

The walk calls it with each static pass as (motor id, catalog gearbox id or None); the answer says
which was chosen, every candidate judged with its checks, and the static picks passed over with why.
Candidates whose dynamic answer is ``unknown`` (a part taken rigid for want of data) are accepted
under ``select.unknown: flag`` and passed over under ``fail``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.axis.requirements import Requirements
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.dynamics.response import Response, Samples


_PROFILES: dict[str, Samples] = {}
"""The load profiles sampled (``response.profile_samples``), by repr of the axis's profile and motion."""


@dataclass
class DynamicSelection:
    """The dynamic walk's answer.

    Attributes:
        chosen: index into the ranked list of the candidate chosen (None: none judged passes).
        responses: every candidate judged, in ranked order (up to ``requirements.candidates``).
        passed_over: the static picks before the chosen one, each {motor, gearbox, status, reason}.
        judged: how many candidates were simulated; stopped_early: the walk stopped at the first pass.
        objective: "first_passing" or "fastest_settling".
    """

    chosen: int | None
    responses: list[Response] = field(default_factory=list)
    passed_over: list[dict[str, Any]] = field(default_factory=list)
    judged: int = 0
    stopped_early: bool = False
    objective: str = "first_passing"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (the ``dynamics`` block of a selection)."""
        return {"objective": self.objective, "judged": self.judged, "stopped_early": self.stopped_early,
                "chosen": None if self.chosen is None else self.responses[self.chosen].to_dict(),
                "passed_over": list(self.passed_over),
                "candidates": [r.to_dict() for r in self.responses]}


def reason(resp: Response) -> str:
    """One line: the first failing (else unknown) dynamic check's note, with its name."""
    from drivetrain.dynamics.response import first_reason

    return first_reason(resp)


def _judged(axis: Axis, req: Requirements, motor_id: str, gearbox_id: str | None, stiffness: Any,
            samples: Samples | None) -> Response:
    """One candidate's dynamic answer (``response.candidate_response``) from its catalog rows."""
    from drivetrain import catalog
    from drivetrain.dynamics.axis_model import stages_with_gearbox
    from drivetrain.dynamics.response import candidate_response

    m = catalog.get(motor_id)
    g = catalog.get(gearbox_id) if gearbox_id else None
    rigid: tuple[str, ...] = ()
    if g is not None and not g.get("torsional_stiffness_Nm_per_rad"):
        rigid = (f"gearbox {gearbox_id} (the catalog has no torsional stiffness: give it, and its backlash)",)
    return candidate_response(axis, motor_id, float(m["rotor_inertia_kgm2"]), float(m["peak_torque_Nm"]),
                              stages_with_gearbox(axis, g), req, gearbox=gearbox_id, stiffness=stiffness,
                              rigid=rigid, samples=samples)


def _passed_over(resp: Response, why: str | None = None) -> dict[str, Any]:
    return {"motor": resp.motor, "gearbox": resp.gearbox, "status": resp.status, "reason": why or reason(resp)}


def _slower(resp: Response, out: DynamicSelection, accept_unknown: bool) -> str | None:
    """Why a candidate that meets the requirements was passed over by ``fastest_settling``."""
    ok = resp.status == "pass" or (accept_unknown and resp.status == "unknown")
    if not ok or out.chosen is None or out.objective != "fastest_settling":
        return None
    best = out.responses[out.chosen]
    return (f"fastest_settling: settles in {resp.worst_settling * 1e3:.1f} ms, {best.motor} in "
            f"{best.worst_settling * 1e3:.1f} ms")


class Judge:
    """The dynamic rule of the selection's walk (``drive_select.orderable``): called with each candidate
    the walk would answer, best first, it simulates the candidate (``candidate_response``) and accepts
    it when its dynamic checks pass (or are unknown, under ``select.unknown: flag``). At most
    ``requirements.candidates`` are simulated; past them a candidate is refused as not judged and the
    walk stops (``exhausted``). What it judged is the answer's ``selection.dynamics`` block (``to_dict``).

    For the objective ``fastest_settling`` the rule runs in two passes (``pipeline.drive_rule``): in
    the first (``collect=True``) it judges and refuses every candidate, up to
    ``requirements.candidates``; ``settle_on_fastest`` then keeps the one that meets the requirements
    and settles fastest; in the second pass, with the answers kept (nothing simulated again), it
    accepts that one only and refuses the ones before it with why.
    """

    def __init__(self, axis: Axis, *, objective: str = "first_passing", duty: DutyCycle | None = None) -> None:
        """``duty``: the axis's duty cycle at ``duty_cycle``'s default sampling, where the caller has it
        (the mechanism's stroke is read from it instead of sampling the cycle again)."""
        from drivetrain.dynamics.axis_model import TABLE_POINTS
        from drivetrain.dynamics.axis_stiffness import mechanism_stiffness_of
        from drivetrain.dynamics.response import profile_samples

        if axis.requirements is None:
            raise ValueError("the dynamic rule needs an axis with requirements")
        self.axis = axis
        self.req = axis.requirements
        spec = axis.spec.motor.select if axis.spec.motor is not None else None
        self.accept_unknown = spec is None or spec.unknown == "flag"
        self.stiffness = mechanism_stiffness_of(axis, TABLE_POINTS, duty)
        # the load profile, sampled once for every candidate and kept for the next axis of the same profile
        # (a study's variants of load, ratio or requirements): the cycle is its profile's and motion's alone
        key = repr((axis.spec.profile, axis.mechanism.motion))
        samples = _PROFILES.get(key)
        if samples is None:
            samples = profile_samples(axis)
            for a in samples:
                a.setflags(write=False)  # shared: read only
            if len(_PROFILES) >= 64:
                _PROFILES.clear()
            _PROFILES[key] = samples
        self.samples = samples
        self.answer = DynamicSelection(chosen=None, objective=objective)
        self.collect = False
        self._seen: dict[tuple[str, str | None], Response] = {}
        self._fastest: tuple[str, str | None] | None = None
        self._replay = False
        self._replayed = 0

    @property
    def exhausted(self) -> bool:
        """``requirements.candidates`` candidates were judged (in the second pass of fastest_settling:
        every judged one was met again): the walk may stop."""
        if self._replay:
            return self._replayed >= len(self._seen)
        return self.answer.judged >= self.req.candidates

    def _ok(self, resp: Response) -> bool:
        return resp.status == "pass" or (self.accept_unknown and resp.status == "unknown")

    def __call__(self, motor_id: str, gearbox_id: str | None) -> tuple[bool, str]:
        out = self.answer
        key = (motor_id, gearbox_id)
        if self._replay:  # the second pass of fastest_settling: the answers are kept
            resp = self._seen.get(key)
            self._replayed += resp is not None
            if resp is None:
                return False, "dynamics: not judged (the fastest-settling pass judged the candidates before it)"
            if key == self._fastest:
                return True, reason(resp)
            why = _slower(resp, out, self.accept_unknown) or reason(resp)
            out.passed_over.append(_passed_over(resp, why))
            return False, why
        if self.exhausted:
            return False, (f"dynamics: not judged (requirements.candidates = {self.req.candidates} candidates "
                           "simulated before it)")
        resp = self._seen.get(key)  # judged ahead by ``first``
        if resp is None:
            resp = _judged(self.axis, self.req, motor_id, gearbox_id, self.stiffness, self.samples)
            self._seen[key] = resp
        out.responses.append(resp)
        out.judged += 1
        ok = self._ok(resp)
        if self.collect:
            return False, "fastest_settling: judged, the fastest is chosen after the first pass"
        if ok:
            out.chosen = len(out.responses) - 1
            out.stopped_early = not self.exhausted
        else:
            out.passed_over.append(_passed_over(resp))
        return ok, reason(resp)

    def first(self, motor_id: str, gearbox_id: str | None) -> bool:
        """Judge the static answer ahead of the walk (a search's answer, whose whole ranking the walk
        would need first): True when it passes, and it is then the dynamic answer, judged alone (the
        walk that would have met it first is not needed); False leaves it for the walk to count."""
        key = (motor_id, gearbox_id)
        resp = _judged(self.axis, self.req, motor_id, gearbox_id, self.stiffness, self.samples)
        self._seen[key] = resp
        if not self._ok(resp):
            return False
        out = self.answer
        out.responses.append(resp)
        out.judged, out.chosen, out.stopped_early = 1, 0, self.req.candidates > 1
        return True

    def settle_on_fastest(self) -> bool:
        """After the collecting pass: keep the candidate that meets the requirements and settles fastest
        (the first in ranked order on a tie); False when none does."""
        out = self.answer
        ok = [k for k, r in enumerate(out.responses) if self._ok(r)]
        self.collect, self._replay = False, True
        out.passed_over = []
        if not ok:
            return False
        best = min(ok, key=lambda k: out.responses[k].worst_settling)
        out.chosen = best
        self._fastest = (out.responses[best].motor, out.responses[best].gearbox)
        return True

    def settling_ratio(self, cycle: DutyCycle) -> dict[str, Any] | None:
        """The chosen candidate's settling-optimal ratio (``settling_ratio.settling_optimal_ratio``), where
        ``requirements.settling_ratio`` asks for it; ``cycle`` its duty cycle at its motor shaft."""
        out = self.answer
        if not self.req.settling_ratio or out.chosen is None:
            return None
        from drivetrain.dynamics.settling_ratio import settling_optimal_ratio

        pick = out.responses[out.chosen]
        return settling_optimal_ratio(self.axis, self.req, pick.motor, pick.gearbox, cycle, stiffness=self.stiffness,
                                      samples=self.samples, current=pick)

    def to_dict(self) -> dict[str, Any]:
        """The ``selection.dynamics`` block: the requirements in SI and every candidate judged."""
        from dataclasses import asdict

        return {"requirements": asdict(self.req), **self.answer.to_dict()}


def failure_counts(dyn: dict[str, Any]) -> tuple[dict[str, int], dict[str, int]]:
    """Of the candidates judged (the ``selection.dynamics`` block): how many each dynamic check fails, and
    how many it cannot judge for want of data (a part taken rigid; a check left unsimulated because a
    linear one already fails is neither)."""
    fails: dict[str, int] = {}
    unknown: dict[str, int] = {}
    for c in dyn.get("candidates", []):
        for ch in c["checks"]:
            fails.setdefault(ch["name"], 0)
            unknown.setdefault(ch["name"], 0)
            if ch["status"] == "fail":
                fails[ch["name"]] = fails.get(ch["name"], 0) + 1
            elif ch["status"] == "unknown" and not ch["note"].startswith("not simulated"):
                unknown[ch["name"]] = unknown.get(ch["name"], 0) + 1
    return fails, unknown


def explain_dynamics(dyn: dict[str, Any], model: str) -> str:
    """The lines ``--explain MODEL`` adds for a motor the selection judged dynamically ("" if it was not):
    each dynamic check with required, available, margin and why, and whether it was passed over."""
    judged = [c for c in dyn.get("candidates", []) if str(c["motor"]).lower() == model.lower()]
    if not judged:
        return ""
    chosen = dyn.get("chosen") or {}
    over = {(p["motor"], p.get("gearbox")): p["reason"] for p in dyn.get("passed_over", [])}
    mark = {"pass": "ok  ", "fail": "FAIL", "unknown": "??  "}
    lines = []
    for c in judged:
        key = (c["motor"], c.get("gearbox"))
        role = ("the answer" if key == (chosen.get("motor"), chosen.get("gearbox")) else
                f"passed over for how it moves: {over[key]}" if key in over else c["status"])
        lines.append(f"  dynamics ({c.get('gearbox') or 'its best configuration'}): {role}")
        for ch in c["checks"]:
            avail = "n/a" if ch["available"] is None else f"{ch['available']:.4g}"
            margin = "n/a" if ch["margin"] is None else (
                "inf" if math.isinf(ch["margin"]) else f"{ch['margin'] * 100:+.1f} %")
            lines.append(f"  {mark[ch['status']]} {ch['name']}: required {ch['required']:.4g}, available {avail} "
                         f"{ch['unit']} ({margin}): {ch['note']}")
    return "\n" + "\n".join(lines)
