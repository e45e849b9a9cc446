r"""How one candidate drive train will move its axis: the tuned loop's bandwidth and margins, and the
simulated following error per move and settling time per stop, judged against ``requirements:``.

For a candidate (its motor's rotor inertia and peak torque, the axis's stages with the candidate's
gearbox in front), ``candidate_response``:

1. builds the compliant chain at the motor shaft with the mechanism's spring at its weakest position
   over the stroke (``axis_stiffness.mechanism_stiffness_of``; rigid where the axis gives no data);
2. tunes the cascaded loop by ``control.tune`` (the highest velocity bandwidth the rule allows:
   current-loop bandwidth / 4, 20 deg of loop-delay phase, half the first anti-resonance; a notch
   on the first resonance where allowed);
3. computes the velocity loop's -3 dB bandwidth and its phase and gain margins
   (``control.analyse_loop``);
4. simulates one cycle of the axis's own profile through the nonlinear kernel (torque limit at the
   motor's peak, backlash, load friction, gravity; the mechanism's spring following the load) and
   measures, at the load, the largest position error during each move and the time from each stop
   until the error stays inside the settling window. A small part between two springs whose mode lies
   far above the loop (a belt's drive pulley between the gearbox and the belt) is lumped into its
   neighbours for this run only (``reduction``: its step would otherwise be set by that mode); the
   answer says so (``lumped``), and steps 1-3 keep the full chain.

Data the model lacks (the mechanism's or a gearbox's stiffness) is taken as rigid. A stiffer chain
never settles slower, so a candidate that fails with a rigid part fails for certain, and one that
passes with it is ``unknown``, naming what to give.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from drivetrain.dynamics.reference import Reference

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.axis.requirements import Requirements
    from drivetrain.dynamics.mechanism_stiffness import MechanismStiffness
    from drivetrain.physics.stage import Stage

FloatArray = NDArray[np.float64]
Samples = tuple[FloatArray, FloatArray, FloatArray, FloatArray]

SRC_SETTLING = ("closed-loop simulation of the candidate's chain (docs/checks.md, 'Dynamic selection'); "
                "tuning rule: Ellis, Control System Design Guide, 4th ed. (2012), ch. Compliance and Resonance")
SRC_MARGINS = ("Franklin, Powell, Emami-Naeini, Feedback Control of Dynamic Systems, 7th ed. (2015), §6.4; "
               "Ellis, Control System Design Guide, 4th ed. (2012), ch. 3")
REFERENCE_POINTS = 4000
"""Samples of the reference per cycle (resampled onto the simulation step by the kernel)."""


@dataclass(frozen=True)
class Response:
    """The dynamic answer for one candidate.

    Attributes:
        motor, gearbox: the candidate (gearbox None: the axis's own transmission).
        velocity_bandwidth_hz: the tuned velocity loop's -3 dB bandwidth [Hz].
        bandwidth_limit: what set the tuned bandwidth (the tuning rule's note).
        phase_margin_deg, gain_margin_db: velocity-loop margins [deg], [dB].
        resonance_hz, anti_resonance_hz: first resonance and anti-resonance of the chain at the
            weakest position [Hz] (NaN: rigid chain).
        notch: a notch was placed on the first resonance.
        weakest_position: load position of the lowest first mode [m] (NaN: no mechanism data).
        following_error: per move, the largest load position error [m or rad at the load].
        settling_time: per stop, time until the load stays inside the window [s] (NaN: never
            before the next move or the cycle's end).
        window: the settling window at the load [m or rad].
        rigid: parts taken rigid for want of data, each with what to give.
        stable: the tuned closed loop is stable (False: nothing was simulated; every check fails).
        simulated: the profile was simulated (False: a linear check, stability_margin or
            velocity_bandwidth, already fails the candidate; settling and following error are then
            not judged, and say so).
        checks: the dynamic checks (name, required, available, unit, margin, ok, status, note, source).
        lumped: the parts the simulation lumped into their neighbours, each with why (``reduction``;
            the linear figures are the full chain's).
    """

    motor: str
    gearbox: str | None
    velocity_bandwidth_hz: float
    bandwidth_limit: str
    phase_margin_deg: float
    gain_margin_db: float
    resonance_hz: float
    anti_resonance_hz: float
    notch: bool
    weakest_position: float
    following_error: FloatArray
    settling_time: FloatArray
    window: float
    rigid: tuple[str, ...]
    stable: bool = True
    simulated: bool = True
    checks: list[dict[str, Any]] = field(default_factory=list)
    lumped: tuple[str, ...] = ()

    @property
    def status(self) -> str:
        """"pass", "unknown" (every judged check passed, some rest on rigid assumptions) or "fail"."""
        states = {c["status"] for c in self.checks}
        return "fail" if "fail" in states else "unknown" if "unknown" in states else "pass"

    @property
    def worst_settling(self) -> float:
        """The longest settling time over the stops [s] (inf when a stop never settles or nothing was
        simulated)."""
        s = self.settling_time
        if not self.simulated:
            return math.inf
        return math.inf if s.size and np.isnan(s).any() else float(np.max(s)) if s.size else 0.0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, keys with units (m or rad at the load as the axis moves)."""
        return {
            "motor": self.motor, "gearbox": self.gearbox, "status": self.status,
            "velocity_bandwidth_Hz": self.velocity_bandwidth_hz, "bandwidth_limit": self.bandwidth_limit,
            "phase_margin_deg": self.phase_margin_deg, "gain_margin_dB": self.gain_margin_db,
            "resonance_Hz": _none(self.resonance_hz), "anti_resonance_Hz": _none(self.anti_resonance_hz),
            "notch": self.notch, "stable": self.stable, "simulated": self.simulated,
            "weakest_position_m": _none(self.weakest_position),
            "following_error_per_move": [float(v) for v in self.following_error],
            "settling_time_per_stop_s": [_none(float(v)) for v in self.settling_time],
            "settling_window": self.window, "rigid_for_want_of_data": list(self.rigid),
            "simulation_lumped": list(self.lumped),
            "checks": [dict(c) for c in self.checks],
        }


def _none(x: float) -> float | None:
    return None if math.isnan(x) else x


def first_reason(resp: Response) -> str:
    """One line: the first failing (else unknown) dynamic check's note, with its name ("passes" if none)."""
    for state in ("fail", "unknown"):
        for c in resp.checks:
            if c["status"] == state:
                return f"{c['name']}: {c['note']}"
    return "passes"


def weakest_stiffness(stiff: MechanismStiffness | None) -> tuple[float | None, float]:
    """The mechanism's smallest torsional stiffness over the stroke [N m/rad at its input] and where [m]."""
    if stiff is None:
        return None, math.nan
    k = np.asarray(stiff.torsional, dtype=float)
    i = int(np.argmin(k))
    return float(k[i]), float(stiff.position[i])


def candidate_response(axis: Axis, motor: str, motor_inertia: float, torque_limit: float,
                       stages: tuple[Stage, ...], req: Requirements, *, gearbox: str | None = None,
                       stiffness: MechanismStiffness | None = None, rigid: tuple[str, ...] = (),
                       samples: Samples | None = None) -> Response:
    """The dynamic answer of one candidate (module docstring).

    ``motor_inertia`` [kg m^2], ``torque_limit`` the motor's peak torque [N m]; ``stages`` from the
    motor outward with the mechanism last (``axis_model.stages_with_gearbox``); ``stiffness`` the
    mechanism's stiffness across the stroke (None: rigid); ``rigid`` names parts already known to be
    taken rigid for want of data (a catalog gearbox without stiffness), with what to give;
    ``samples`` the axis's load profile sampled by ``profile_samples`` (shared between candidates).

    The linear checks come first: where stability_margin or velocity_bandwidth fails, the candidate
    fails whatever its simulation would show, so it is not simulated (nor is the compiled kernel
    loaded for it).
    """
    from drivetrain.dynamics.chain import model_from_stages
    from drivetrain.dynamics.control import analyse_loop, tune
    from drivetrain.dynamics.linear import anti_resonance_frequencies, natural_frequencies

    head, mech = stages[:-1], stages[-1]
    k_weak, x_weak = weakest_stiffness(stiffness)
    missing = list(rigid)
    if k_weak is None and axis.mechanism.motion == "linear":
        missing.append(f"the {axis.mechanism.type} (give its stiffness: mechanism.screw/nut, belt or rack data)")
    weak = model_from_stages(motor_inertia, (*head, mech) if k_weak is None else
                             (*head, replace(mech, stiffness=k_weak)), 0.0)
    loop = tune(weak, None, current_bandwidth_hz=req.current_bandwidth, velocity_sample_time=req.loop_delay,
                current_sample_time=req.loop_delay / 2.0, position_sample_time=2.0 * req.loop_delay,
                notch=req.notch and weak.n >= 2, torque_limit=torque_limit,
                encoder_resolution=2.0 * math.pi / req.encoder_counts)
    if not req.feedforward:
        loop = loop.with_(velocity_ff=0.0, acceleration_ff=0.0)
    analysis = analyse_loop(weak, loop)
    f_r = float(natural_frequencies(weak)[0]) if weak.n >= 2 else math.nan
    f_ar = float(anti_resonance_frequencies(weak)[0]) if weak.n >= 2 else math.nan

    # what set the bandwidth: the rule's limit, or the step down for a stable loop (not the notch's note)
    note = next((n for n in reversed(loop.notes) if "bandwidth" in n or "lowered" in n), "")
    base = Response(motor=motor, gearbox=gearbox, velocity_bandwidth_hz=float(analysis.velocity_bandwidth_hz),
                    bandwidth_limit=note, phase_margin_deg=float(analysis.velocity_margins.phase_margin_deg),
                    gain_margin_db=float(analysis.velocity_margins.gain_margin_db), resonance_hz=f_r,
                    anti_resonance_hz=f_ar, notch=loop.notch is not None, weakest_position=x_weak,
                    following_error=np.zeros(0), settling_time=np.zeros(0), window=req.settling_window,
                    rigid=tuple(missing))
    if not analysis.stable:
        # no gain set of the rule holds the resonance: nothing to simulate; every check fails with why
        pole = analysis.poles[int(np.argmax(analysis.poles.real))]
        why = (f"no stable tuning: a closed-loop pole at {abs(pole.imag) / (2 * math.pi):.1f} Hz grows even at "
               f"{analysis.velocity_bandwidth_hz:.1f} Hz of bandwidth" + ("" if req.notch else "; allow a notch"))
        unstable = replace(base, bandwidth_limit=why, stable=False, simulated=False,
                           following_error=np.array([math.inf]), settling_time=np.array([math.nan]))
        return replace(unstable, checks=dynamic_checks(unstable, req))
    linear = replace(base, simulated=False)
    linear = replace(linear, checks=dynamic_checks(linear, req))
    if linear.status == "fail":
        return linear

    # The simulation: the chain with the mechanism's spring following the load over one cycle.
    from drivetrain.dynamics.axis_model import AxisDynamics, load_friction, with_mechanism_spring
    from drivetrain.dynamics.reduction import reduce_for_simulation, reduced_step
    from drivetrain.dynamics.simulation import default_step, simulate

    dyn = AxisDynamics(model_from_stages(motor_inertia, stages, 0.0), motor, motor_inertia, stages)
    t, x, v, a = profile_samples(axis) if samples is None else samples
    dyn = with_mechanism_spring(axis, dyn, float(x[0]), stiffness)
    friction, load_torque = load_friction(axis, stages, axis.spec.dynamics or {})
    chain = dyn.chain
    if friction is not None:
        frictions = list(chain.friction) if chain.friction else [None] * chain.n
        frictions[-1] = friction
        chain = chain.with_(friction=tuple(frictions))
    ratio = math.prod(s.ratio for s in stages)
    ref = Reference.from_load(t, x, v, a, ratio)
    # a part whose mode the loop does not act on is lumped (``reduction``); the linear checks above
    # judged the full chain
    sim_chain, lumped = reduce_for_simulation(chain, float(analysis.velocity_bandwidth_hz), req.current_bandwidth)
    step = reduced_step(chain, sim_chain, loop) if lumped else default_step(chain, loop)
    sim = simulate(sim_chain, loop, reference_on_grid(ref, step), load_torque=load_torque, step=step,
                   settle_tolerance=req.settling_window * ratio, check_stability=False)  # judged above
    follow = _per_move_error(sim.states["reference_speed"], sim.load_error) / ratio
    resp = replace(base, following_error=follow, settling_time=np.asarray(sim.settling_time, dtype=float),
                   lumped=lumped)
    return replace(resp, checks=dynamic_checks(resp, req))


_GRIDS: dict[tuple[bytes, float, int], Reference] = {}
"""The last few references resampled onto a simulation's grid (``reference_on_grid``)."""
GRIDS_KEPT = 4
_GRIDS_LOCK = threading.Lock()


def reference_on_grid(ref: Reference, step: float) -> Reference:
    """``ref`` resampled onto the instants a simulation at ``step`` [s] steps through (those of
    ``simulation.simulate``: k x step, k = 0 .. round(end / step)), kept for the next candidate or
    study variant with the same profile, ratio and step (the candidates of one gearbox share all
    three, a study's variants often do). ``simulate`` then takes the samples as they are
    (``Reference.resample`` at its own instants): the same numbers as resampling each time."""
    import hashlib

    n = round(float(ref.time[-1]) / step)
    digest = hashlib.blake2b(digest_size=16)
    for arr in (ref.time, ref.position, ref.speed, ref.acceleration):
        digest.update(np.ascontiguousarray(arr, dtype=float).tobytes())
    key = (digest.digest(), float(step), n)
    with _GRIDS_LOCK:  # the web app sizes in threads
        hit = _GRIDS.pop(key, None)
    if hit is None:
        t = np.arange(n + 1, dtype=np.float64) * step
        hit = Reference(np.asarray(t, dtype=np.float64), *ref.resample(t))
    with _GRIDS_LOCK:
        _GRIDS[key] = hit  # the most recent last; the oldest dropped
        while len(_GRIDS) > GRIDS_KEPT:
            del _GRIDS[next(iter(_GRIDS))]
    return hit


def profile_samples(axis: Axis) -> Samples:
    """One cycle of the axis's load profile at ``REFERENCE_POINTS`` + 1 instants: time [s], position,
    speed, acceleration [m, m/s, m/s^2 or rad, rad/s, rad/s^2 at the load]; the same for every
    candidate, so computed once per selection."""
    cycle = axis.cycle()
    t = np.linspace(0.0, cycle.period, REFERENCE_POINTS + 1)
    kin = cycle.evaluate(t)
    return (t, np.asarray(kin.x, dtype=float), np.asarray(kin.v, dtype=float), np.asarray(kin.a, dtype=float))


def _per_move_error(ref_speed: FloatArray, load_error: FloatArray) -> FloatArray:
    """The largest |load error| [rad at the motor] during each move (a run of nonzero reference speed;
    a loop over the few moves, each reduced as an array)."""
    v = np.abs(np.asarray(ref_speed, dtype=float))
    if v.size == 0:
        return np.zeros(0)
    moving = (v > 1e-12 * max(1.0, float(v.max()))).astype(np.int8)
    edges = np.diff(np.concatenate([[0], moving, [0]]))
    err = np.abs(np.asarray(load_error, dtype=float))
    return np.array([float(err[a:b].max()) for a, b in zip(np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0],
                                                           strict=True)])


def dynamic_checks(resp: Response, req: Requirements) -> list[dict[str, Any]]:
    """The checks of ``resp`` against ``req``: settling_time, following_error, velocity_bandwidth
    (where stated) and stability_margin, shaped like the other checks; ``unknown`` where a judged
    pass rests on a part taken rigid for want of data, or where the profile was not simulated
    because a linear check already fails the candidate (the note says which)."""
    unit = "m" if req.motion == "linear" else "rad"
    why = resp.bandwidth_limit
    checks: list[dict[str, Any]] = []
    linear = _linear_checks(resp, req)

    def add(name: str, required: float, available: float, unit: str, margin: float, note: str) -> None:
        checks.append(_check(resp, name, required, available, unit, margin, note, SRC_SETTLING))

    if resp.stable and not resp.simulated:
        decided = [c["name"] for c in linear if c["status"] == "fail"]
        skip = ("not simulated: the candidate already fails " + ", ".join(decided) if decided
                else "not simulated: the linear checks are judged first")
        for name, required, u in (("settling_time", req.settling_time, "s"),
                                  ("following_error", req.following_error, unit)):
            if required is not None:
                checks.append({"name": name, "required": required, "available": None, "unit": u, "margin": None,
                               "ok": None, "status": "unknown", "approximate": False,
                               "note": f"{skip} (a simulation of the profile would decide it)",
                               "source": SRC_SETTLING})
        return checks + linear
    if req.settling_time is not None:
        worst = resp.worst_settling if resp.stable else math.inf
        margin = req.settling_time / worst - 1.0 if worst > 0 else math.inf
        text = ("never settles inside the window before the next move" if math.isinf(worst)
                else f"settles in {worst * 1e3:.1f} ms")
        cmp = "<=" if margin >= 0 else ">"
        add("settling_time", req.settling_time, worst, "s", margin,
            f"{text} {cmp} {req.settling_time * 1e3:g} ms into {_window(resp.window, req.motion)}: {why}")
    if req.following_error is not None:
        worst_e = float(np.max(resp.following_error)) if resp.following_error.size else 0.0
        margin = req.following_error / worst_e - 1.0 if worst_e > 0 else math.inf
        add("following_error", req.following_error, worst_e, unit, margin,
            f"largest load position error during a move {_window(worst_e, req.motion)} "
            f"({'<=' if margin >= 0 else '>'} {_window(req.following_error, req.motion)}): {why}")
    return checks + linear


def _check(resp: Response, name: str, required: float, available: float, unit: str, margin: float, note: str,
           source: str) -> dict[str, Any]:
    """One dynamic check: fail below margin 0; a pass resting on a part taken rigid is unknown."""
    ok = bool(margin >= 0.0)
    status = "fail" if not ok else ("unknown" if resp.rigid else "pass")
    rigid_note = ("; rigid for want of data: " + "; ".join(resp.rigid)) if resp.rigid else ""
    return {"name": name, "required": required, "available": available, "unit": unit, "margin": margin,
            "ok": None if status == "unknown" else ok, "status": status, "approximate": False,
            "note": note + ("" if status == "fail" else rigid_note), "source": source}


def _linear_checks(resp: Response, req: Requirements) -> list[dict[str, Any]]:
    """velocity_bandwidth (where stated) and stability_margin: decided by the tuned linear loop alone."""
    why = resp.bandwidth_limit
    checks: list[dict[str, Any]] = []
    if req.velocity_bandwidth is not None:
        margin = resp.velocity_bandwidth_hz / req.velocity_bandwidth - 1.0
        checks.append(_check(resp, "velocity_bandwidth", req.velocity_bandwidth, resp.velocity_bandwidth_hz, "Hz",
                             margin, f"tuned velocity loop reaches {resp.velocity_bandwidth_hz:.1f} Hz: {why}",
                             SRC_SETTLING))
    pm = resp.phase_margin_deg / req.phase_margin_deg - 1.0
    gm = resp.gain_margin_db / req.gain_margin_db - 1.0 if math.isfinite(resp.gain_margin_db) else math.inf
    text = (f"velocity loop phase margin {resp.phase_margin_deg:.1f} deg (>= {req.phase_margin_deg:g}), gain margin "
            f"{resp.gain_margin_db:.1f} dB (>= {req.gain_margin_db:g})")
    if not resp.stable:
        pm, gm, text = -1.0, -1.0, why
    checks.append(_check(resp, "stability_margin", req.phase_margin_deg, resp.phase_margin_deg, "deg", min(pm, gm),
                         text, SRC_MARGINS))
    return checks


def _window(x: float, motion: str) -> str:
    if motion == "linear":
        return f"{x * 1e6:.3g} um" if x < 1e-3 else f"{x * 1e3:.3g} mm"
    return f"{math.degrees(x) * 60:.3g} arcmin"
