r"""The settling-optimal ratio: for the selected motor, the transmission ratio that settles the axis
fastest into its stated window, beside the selection's "optimal ratio" (min RMS torque, inertia match).

The ratio varied is an ideal reduction i in front of the candidate's drive train (its catalog gearbox,
the axis's transmission and mechanism): the total ratio times i. Behind it the motor sees the load's
inertia and the chain's springs divided by i^2 and the reference times i (Ellis, *Control System
Design Guide*, 4th ed. (2012), ch. "Compliance and Resonance": the reflected inertia ratio sets the
anti-resonance and with it the bandwidth the loop can hold). A change of the axis's gearbox ratio, of a
screw's lead (1 / i) or of a drive pulley's diameter (1 / i) is that change to first order (the
mechanism's own inertia and stiffness at its input then change a little differently).

The scan is coarse: ``points`` ratios log-spaced between the ratio where the motor's peak or RMS torque
no longer covers the cycle and the one where it reaches its maximum speed (both found for all ratios at
once as arrays: ratios x samples), each judged by ``response.candidate_response`` (its own tuned loop,
and a simulation of the profile where the linear checks pass). The answer is the ratio with the
shortest worst settling time among those whose dynamic checks do not fail.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.axis.requirements import Requirements
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.dynamics.response import Response, Samples

SCAN_POINTS = 9
"""Ratios judged by the coarse scan."""
SCAN_SPAN = 4.0
"""The scan runs from 1/4 to 4 times the candidate's own total ratio, inside the torque and speed limits."""


def feasible_factors(cycle: DutyCycle, rotor_inertia: float, peak_torque: float, rated_torque: float,
                     max_speed: float, factors: np.ndarray) -> np.ndarray:
    """Which reduction factors i keep the motor inside its peak torque, RMS torque and max speed [bool].

    Behind an ideal reduction i the motor torque is T / i + J_M alpha i (T [N m], alpha [rad/s^2] the
    candidate's cycle at its motor shaft, rotor excluded) and its speed omega i; evaluated for every
    factor and sample at once (a (factors, samples) array). Source: ``selection.optimal_ratio`` (the
    same torque model; lecture, Torque Effective Value).
    """
    i = np.asarray(factors, dtype=float)[:, None]
    torque = np.asarray(cycle.torque, dtype=float)[None, :] / i + rotor_inertia * np.asarray(cycle.alpha)[None, :] * i
    w = np.asarray(cycle.weights, dtype=float)[None, :]
    rms = np.sqrt(np.sum(w * torque**2, axis=1) / cycle.period)
    peak = np.max(np.abs(torque), axis=1)
    speed = np.max(np.abs(np.asarray(cycle.omega, dtype=float))) * i[:, 0]
    ok = peak <= peak_torque
    if math.isfinite(rated_torque) and rated_torque > 0:
        ok &= rms <= rated_torque
    if math.isfinite(max_speed) and max_speed > 0:
        ok &= speed <= max_speed
    return np.asarray(ok, dtype=bool)


def _label(axis: Axis, gearbox_ratio: float | None, factor: float) -> tuple[str, str]:
    """Which ratio the factor changes, and its new value, in words."""
    own = [s for s in axis.transmission if s.kind == "gearbox"]
    if gearbox_ratio is not None:
        return "gearbox ratio", f"gearbox ratio {gearbox_ratio:.3g} -> {gearbox_ratio * factor:.3g}"
    if own:
        return "gearbox ratio", f"{own[0].name} ratio {own[0].ratio:.3g} -> {own[0].ratio * factor:.3g}"
    mech = axis.mechanism
    lead = getattr(mech, "lead", None)
    if isinstance(lead, float) and lead > 0:
        return "lead", f"lead {lead * 1e3:.3g} mm -> {lead / factor * 1e3:.3g} mm"
    diameter = getattr(mech, "diameter", None)
    if isinstance(diameter, float) and diameter > 0:
        return "pulley diameter", f"drive diameter {diameter * 1e3:.3g} mm -> {diameter / factor * 1e3:.3g} mm"
    return "ratio", f"a reduction of {factor:.3g} in front of the axis"


def settling_optimal_ratio(axis: Axis, req: Requirements, motor_id: str, gearbox_id: str | None,
                           cycle: DutyCycle, *, stiffness: Any, samples: Samples,
                           current: Response | None = None, points: int = SCAN_POINTS) -> dict[str, Any]:
    """The settling-optimal ratio of the selected candidate (module docstring), JSON-ready.

    ``cycle``: the candidate's own duty cycle at its motor shaft (``selection.candidate_cycle``);
    ``current``: its dynamic answer at its own ratio (judged again when None).
    """
    from drivetrain import catalog
    from drivetrain.dynamics.axis_model import stages_with_gearbox
    from drivetrain.dynamics.response import candidate_response
    from drivetrain.physics.stage import Stage

    m = catalog.get(motor_id)
    g = catalog.get(gearbox_id) if gearbox_id else None
    j_m, t_pk = float(m["rotor_inertia_kgm2"]), float(m["peak_torque_Nm"])
    t_n = float(m.get("rated_torque_Nm") or math.nan)
    n_max = float(m.get("max_speed_rad_s") or math.nan)
    stages = stages_with_gearbox(axis, g)
    rigid: tuple[str, ...] = ()
    if g is not None and not g.get("torsional_stiffness_Nm_per_rad"):
        rigid = (f"gearbox {gearbox_id} (the catalog has no torsional stiffness: give it, and its backlash)",)
    factors = np.geomspace(1.0 / SCAN_SPAN, SCAN_SPAN, 4 * points + 1)
    ok = feasible_factors(cycle, j_m, t_pk, t_n, n_max, factors)
    out: dict[str, Any] = {"motor": motor_id, "gearbox": gearbox_id, "ratio": None, "scanned": 0}
    if not ok.any():
        out["reason"] = "no ratio within 1/4 to 4 times its own keeps the motor inside its torque and speed"
        return out
    lo, hi = float(factors[ok].min()), float(factors[ok].max())
    scan = np.unique(np.concatenate([np.geomspace(lo, hi, points), [1.0] if lo <= 1.0 <= hi else []]))

    def judged(i: float) -> Response:
        front = Stage(name="settling ratio", kind="gearbox", ratio=float(i))
        return candidate_response(axis, motor_id, j_m, t_pk, (front, *stages), req, gearbox=gearbox_id,
                                  stiffness=stiffness, rigid=rigid, samples=samples)

    answers = [current if (current is not None and i == 1.0) else judged(float(i)) for i in scan]
    settle = np.array([r.worst_settling if r.status != "fail" or _only_settling_fails(r) else math.inf
                       for r in answers])
    own = answers[int(np.argmin(np.abs(np.log(scan))))] if current is None else current
    out.update({"scanned": int(scan.size), "range": [float(scan[0]), float(scan[-1])],
                "current_settling_time_s": _finite(own.worst_settling)})
    if not np.isfinite(settle).any():
        out["reason"] = (f"no ratio of the {scan.size} scanned settles into the window with the margins asked "
                         f"(the best-ranked reason: {_first_fail(answers)})")
        return out
    # the fastest; on a tie (settling resolved to the simulation's step) the one nearest the candidate's own
    tied = np.flatnonzero(settle <= float(np.min(settle)) + 1e-9)
    k = int(tied[np.argmin(np.abs(np.log(scan[tied])))])
    stage, label = _label(axis, float(g["ratio"]) if g is not None else None, float(scan[k]))
    best = answers[k]
    meets = req.settling_time is None or best.worst_settling <= req.settling_time
    out.update({"ratio": float(scan[k]), "stage": stage, "label": label,
                "settling_time_s": _finite(best.worst_settling), "meets_settling_time": meets,
                "velocity_bandwidth_Hz": best.velocity_bandwidth_hz, "phase_margin_deg": best.phase_margin_deg,
                "per_ratio": [{"factor": float(i), "settling_time_s": _finite(float(s))}
                              for i, s in zip(scan, settle, strict=True)]})
    return out


def _only_settling_fails(r: Response) -> bool:
    """A ratio whose only failing check is the settling time still ranks by it (the scan looks for the
    fastest, the requirement says whether it is fast enough)."""
    return all(c["status"] != "fail" or c["name"] == "settling_time" for c in r.checks)


def _first_fail(answers: list[Response]) -> str:
    from drivetrain.dynamics.response import first_reason

    return first_reason(answers[0]) if answers else "none"


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None
