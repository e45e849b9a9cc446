"""The dynamic model of an axis file: its compliant chain, its servo loop and its reference.

``model(axis)`` builds the N-mass chain at the motor shaft, either from the explicit
``dynamics: {chain: [...]}`` of the axis file or from the stiffness, damping and backlash of
its transmission elements (``model_from_stages``), with the motor the axis names or selects
(a selected catalog gearbox enters with its catalog stiffness and backlash). ``simulate_axis``
runs the closed-loop simulation on the axis's own duty-cycle profile, with the mechanism's own
spring following the load where the axis file gives its stiffness data (``with_mechanism_spring``).

The ``dynamics:`` block (all optional)::

    dynamics:
      chain: [{inertia: ...}, {stiffness: ..., damping: ..., backlash: ...}, {inertia: ...}]
      motor_inertia: 1.2 kg*cm^2        # overrides the motor's rotor inertia
      loop: {velocity_bandwidth: 80 Hz, notch: true, current_bandwidth: 2000 Hz,
             torque_limit: 4 N*m, encoder_counts: 1048576, lowpass: 1500 Hz}
            # or given gains: {velocity_kp: 0.05 (N m s/rad), velocity_ti: 0.01 (s), position_kv: 60 (1/s)}
      friction: {coulomb: 0.1 N*m, static: 0.15 N*m, viscous: 1e-4 N*m*s/rad,
                 stribeck_speed: 0.05 rad/s, method: exponential}   # at the load, motor shaft
      load_torque: 0.3 N*m              # constant torque at the motor shaft (default: gravity)
      cycles: 1                         # profile repetitions to simulate
      step: 100 us
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.errors import InputError
from drivetrain.physics.stage import Stage
from drivetrain.units import parse

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.dynamics.chain import Chain
    from drivetrain.dynamics.control import ServoLoop
    from drivetrain.dynamics.mechanism_stiffness import MechanismStiffness
    from drivetrain.dynamics.simulation_result import SimulationResult
    from drivetrain.sizing.result import SizingResult

_KEYS = {"chain", "motor_inertia", "loop", "friction", "load_torque", "cycles", "step", "excitation_orders"}
_LOOP_KEYS = {"velocity_bandwidth", "notch", "current_bandwidth", "torque_limit", "encoder_counts", "lowpass",
              "fraction_of_anti_resonance", "velocity_kp", "velocity_ti", "position_kv"}
MAX_GAIN = 1e12
"""Largest loop gain accepted in SI (N m s/rad, s, 1/s): real drives are below 1e4."""
_FRICTION_KEYS = {"coulomb", "static", "viscous", "stribeck_speed", "method"}


@dataclass(frozen=True)
class AxisDynamics:
    """The chain, the motor it assumes, and the stages after any selected catalog gearbox."""

    chain: Chain
    motor: str
    motor_inertia: float
    stages: tuple[Stage, ...]


def _block(axis: Axis) -> dict[str, Any]:
    raw = axis.spec.dynamics or {}
    unknown = set(raw) - _KEYS
    if unknown:
        raise InputError(f"dynamics.{sorted(unknown)[0]}", f"unknown key; valid: {', '.join(sorted(_KEYS))}",
                         has_value=False)
    _check_values(raw)
    return raw


_LOOP_QUANTITIES = {"velocity_bandwidth": "frequency", "current_bandwidth": "frequency", "lowpass": "frequency",
                    "torque_limit": "torque", "fraction_of_anti_resonance": "dimensionless"}
_FRICTION_QUANTITIES = {"coulomb": "torque", "static": "torque", "viscous": "torsional_damping",
                        "stribeck_speed": "angular_speed"}


def _check_values(raw: dict[str, Any]) -> None:
    """Every value of the block checked for its form, also those the command at hand does not use
    (``modes`` does not read the loop, yet a bad loop value is an error there too)."""
    cycles = raw.get("cycles", 1)
    if isinstance(cycles, bool) or not isinstance(cycles, int) or not 1 <= cycles <= 100:
        raise InputError("dynamics.cycles", "must be a whole number between 1 and 100", cycles)
    if "step" in raw:
        parse(raw["step"], "time", "dynamics.step", allow_zero=False)
    if "load_torque" in raw:
        parse(raw["load_torque"], "torque", "dynamics.load_torque")
    for key, known, quantities in (("loop", _LOOP_KEYS, _LOOP_QUANTITIES),
                                   ("friction", _FRICTION_KEYS, _FRICTION_QUANTITIES)):
        spec = raw.get(key)
        if spec is None:
            continue
        if not isinstance(spec, dict):
            raise InputError(f"dynamics.{key}", "must be a mapping", spec)
        unknown = set(spec) - known
        if unknown:
            raise InputError(f"dynamics.{key}.{sorted(unknown, key=str)[0]}",
                             f"unknown key; valid: {', '.join(sorted(known))}", has_value=False)
        if key == "loop":
            _check_loop_values(spec)
        for name, quantity in quantities.items():
            if name in spec:
                value = parse(spec[name], quantity, f"dynamics.{key}.{name}")
                if value < 0 or (key == "loop" and value == 0):
                    raise InputError(f"dynamics.{key}.{name}", "must be > 0" if key == "loop" else "must be >= 0",
                                     spec[name])


def _motor(axis: Axis, sized: SizingResult | None = None) -> tuple[str, float, tuple[Stage, ...]]:
    """Motor name and inertia, and the stages with a selected catalog gearbox in front.

    ``sized``: the axis's sizing result when the caller has it (its selection is used instead of
    sizing the axis again).
    """
    if axis.motor is not None:
        return axis.motor.name, axis.motor.inertia, axis.stages
    if axis.spec.motor is not None and axis.spec.motor.select is not None:
        from drivetrain import catalog
        from drivetrain.sizing.pipeline import size

        res = sized if sized is not None else size(axis)
        chosen = res.selection.selected if res.selection is not None else None
        if chosen is None:
            raise InputError("motor.select", "no catalog motor passes, so there is no motor to simulate; "
                             + str((res.selection.advice if res.selection is not None else None) or ""),
                             has_value=False)
        m = catalog.get(chosen.motor)
        stages = stages_with_gearbox(axis, catalog.get(chosen.gearbox) if chosen.gearbox else None)
        return chosen.motor, float(m["rotor_inertia_kgm2"]), stages
    raise InputError("motor", "dynamics need a motor: name one or select one from the catalog", has_value=False)


def stages_with_gearbox(axis: Axis, gearbox: dict[str, Any] | None) -> tuple[Stage, ...]:
    """The axis's stages with a catalog gearbox row (``catalog.get``) in front of them (None: as they are).

    The row's output stiffness K_out enters at its input as K_out / i^2 and its backlash at the
    input as backlash x i (``model_from_stages`` takes both at the stage's input); a row without
    stiffness is rigid, backlash included."""
    if gearbox is None:
        return axis.stages
    i = float(gearbox["ratio"])
    k_out = gearbox.get("torsional_stiffness_Nm_per_rad")
    return (Stage(name=str(gearbox["id"]), kind="gearbox", ratio=i, inertia_in=gearbox.get("inertia_input_kgm2") or 0.0,
                  efficiency=gearbox.get("efficiency") or 1.0, back_efficiency=gearbox.get("efficiency") or 1.0,
                  stiffness=None if not k_out else float(k_out) / i**2,
                  backlash=(gearbox.get("backlash_rad") or 0.0) * i if k_out else 0.0), *axis.stages)


def model(axis: Axis, sized: SizingResult | None = None) -> AxisDynamics:
    """The compliant chain of ``axis`` at the motor shaft (``sized``: its sizing result, if at hand)."""
    from drivetrain.dynamics.chain import chain_from_spec, model_from_stages

    block = _block(axis)
    if "chain" in block:
        if not isinstance(block["chain"], list):
            raise InputError("dynamics.chain", "must be a list of inertia and spring entries", block["chain"])
        chain = chain_from_spec(block["chain"])
        return AxisDynamics(chain, "chain", float(chain.inertia[0]), axis.stages)
    name, j_m, stages = _motor(axis, sized)
    if "motor_inertia" in block:
        j_m = parse(block["motor_inertia"], "inertia", "dynamics.motor_inertia", allow_zero=False)
    chain = model_from_stages(j_m, stages, 0.0)
    return AxisDynamics(chain, name, j_m, stages)


def load_friction(axis: Axis, stages: tuple[Stage, ...], block: dict[str, Any]) -> tuple[Any, float]:
    """Load friction (Coulomb, breakaway) and constant load torque at the motor shaft, from the axis."""
    from drivetrain.dynamics.friction import Friction

    mech = axis.mechanism
    ratio = math.prod(s.ratio for s in stages)
    one = np.ones(1)
    # External torque at standstill and just moving, both directions: gravity G, Coulomb C, breakaway S.
    plus = float(mech.external_torque(np.zeros(1), 1e-9 * one, one, None, axis.gravity)[0]) * mech.stage.ratio
    minus = float(mech.external_torque(np.zeros(1), -1e-9 * one, -one, None, axis.gravity)[0]) * mech.stage.ratio
    start = float(mech.external_torque(np.zeros(1), np.zeros(1), one, None, axis.gravity)[0]) * mech.stage.ratio
    gravity = 0.5 * (plus + minus) / ratio
    coulomb = 0.5 * (plus - minus) / ratio
    static = max(start / ratio - gravity, coulomb)
    spec = block.get("friction") or {}
    if not isinstance(spec, dict):
        raise InputError("dynamics.friction", "must be a mapping", spec)
    unknown = set(spec) - _FRICTION_KEYS
    if unknown:
        raise InputError(f"dynamics.friction.{sorted(unknown)[0]}",
                         f"unknown key; valid: {', '.join(sorted(_FRICTION_KEYS))}", has_value=False)
    f = "dynamics.friction"
    coulomb = parse(spec.get("coulomb", coulomb), "torque", f"{f}.coulomb")
    static = parse(spec.get("static", max(static, coulomb)), "torque", f"{f}.static")
    viscous = parse(spec.get("viscous", 0.0), "torsional_damping", f"{f}.viscous")
    stribeck = parse(spec.get("stribeck_speed", 0.01), "angular_speed", f"{f}.stribeck_speed", allow_zero=False)
    method = spec.get("method", "exponential")
    if method not in ("exponential", "tanh"):
        raise InputError(f"{f}.method", "must be exponential or tanh", method)
    if coulomb < 0 or static < coulomb or viscous < 0:
        raise InputError(f, "needs coulomb >= 0, static >= coulomb and viscous >= 0",
                         f"coulomb={coulomb:g}, static={static:g}")
    friction = None
    if coulomb > 0 or viscous > 0:
        friction = Friction(coulomb=coulomb, static=static, viscous=viscous, stribeck_speed=stribeck, method=method)
    load_torque = parse(block.get("load_torque", gravity), "torque", "dynamics.load_torque")
    return friction, load_torque


def _check_loop_values(spec: dict[str, Any]) -> None:
    f = "dynamics.loop"
    for k in ("velocity_kp", "velocity_ti", "position_kv"):
        if k not in spec:
            continue
        v = spec[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(v):
            raise InputError(f"{f}.{k}", "must be a number in SI units", v)
        if not (k == "velocity_ti" and math.isinf(v)) and abs(v) > MAX_GAIN:  # ti: .inf, no integral action
            raise InputError(f"{f}.{k}", f"magnitude is absurd (> {MAX_GAIN:g} in SI)", v)
        if v < 0 or (v == 0 and k != "position_kv"):
            raise InputError(f"{f}.{k}", "must be >= 0" if k == "position_kv" else "must be > 0", v)
    counts = spec.get("encoder_counts", 1)
    if not isinstance(counts, int) or isinstance(counts, bool) or counts <= 0:
        raise InputError(f"{f}.encoder_counts", "must be a positive whole number of counts per revolution", counts)
    if not isinstance(spec.get("notch", False), bool):
        raise InputError(f"{f}.notch", "must be true or false", spec.get("notch"))


def servo_loop(chain: Chain, block: dict[str, Any]) -> ServoLoop:
    """Gains tuned from the requested bandwidth (or the highest the tuning rule allows)."""
    from drivetrain.dynamics.control import tune

    spec = block.get("loop") or {}
    if not isinstance(spec, dict):
        raise InputError("dynamics.loop", "must be a mapping", spec)
    unknown = set(spec) - _LOOP_KEYS
    if unknown:
        raise InputError(f"dynamics.loop.{sorted(unknown)[0]}", f"unknown key; valid: {', '.join(sorted(_LOOP_KEYS))}",
                         has_value=False)
    f = "dynamics.loop"
    kwargs: dict[str, Any] = {}
    for key, arg, quantity in (("velocity_bandwidth", "velocity_bandwidth_hz", "frequency"),
                               ("current_bandwidth", "current_bandwidth_hz", "frequency"),
                               ("torque_limit", "torque_limit", "torque"), ("lowpass", "lowpass_hz", "frequency"),
                               ("fraction_of_anti_resonance", "fraction_of_anti_resonance", "dimensionless")):
        if key in spec:
            value = parse(spec[key], quantity, f"{f}.{key}", allow_zero=False)
            if value <= 0.0:
                raise InputError(f"{f}.{key}", "must be > 0", spec[key])
            kwargs[arg] = value
    if "encoder_counts" in spec:
        counts = spec["encoder_counts"]
        if not isinstance(counts, int) or isinstance(counts, bool) or counts <= 0:
            raise InputError(f"{f}.encoder_counts", "must be a positive whole number of counts per revolution",
                             counts)
        kwargs["encoder_resolution"] = 2.0 * math.pi / counts
    notch = spec.get("notch", False)
    if not isinstance(notch, bool):
        raise InputError(f"{f}.notch", "must be true or false", notch)
    loop = tune(chain, notch=notch and chain.n >= 2, **kwargs)
    given = {k: spec[k] for k in ("velocity_kp", "velocity_ti", "position_kv") if k in spec}
    if given:
        # Gains given by the user replace the tuned ones (each must be a number in SI).
        for k, v in given.items():
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise InputError(f"{f}.{k}", "must be a number in SI units", v)
            if not math.isinf(v) and abs(v) > MAX_GAIN:  # velocity_ti: .inf means no integral action
                raise InputError(f"{f}.{k}", f"magnitude is absurd (> {MAX_GAIN:g} in SI)", v)
        loop = loop.with_(**{k: float(v) for k, v in given.items()}, notes=("gains as given",))
    return loop


TABLE_POINTS = 201
"""Positions across the stroke at which the mechanism's stiffness is tabulated for ``simulate``."""


def with_mechanism_spring(axis: Axis, dyn: AxisDynamics, start: float = 0.0,
                          stiffness: MechanismStiffness | None = None) -> AxisDynamics:
    """``dyn`` with the mechanism's own spring, following the load along the stroke.

    Where the axis file gives the mechanism's stiffness data (``mechanism.screw``/``nut``,
    ``belt``, ``rack``; ``axis_stiffness.mechanism_stiffness_of``), the mechanism stage gets its
    torsional stiffness k_x(x) r^2 at the load position ``start`` [m], and the chain's
    ``spring_table`` carries the stiffness at the motor shaft, k_x(x) r^2 / i^2 (i the ratio of
    the stages before the mechanism), against the load's angle at the motor shaft, x times the
    total ratio: ``simulate`` then updates the spring as the load moves. Unchanged otherwise
    (no data, or an explicit ``dynamics.chain``). ``stiffness``: the mechanism's stiffness across
    the stroke when the caller has it (else computed here at ``TABLE_POINTS`` positions).
    """
    from dataclasses import replace

    from drivetrain.dynamics.axis_stiffness import mechanism_stiffness_of
    from drivetrain.dynamics.chain import model_from_stages

    if "chain" in _block(axis) or not dyn.stages:
        return dyn
    stiff = stiffness if stiffness is not None else mechanism_stiffness_of(axis, TABLE_POINTS)
    if stiff is None:
        return dyn
    head, mech = dyn.stages[:-1], dyn.stages[-1]
    r_head = math.prod(s.ratio for s in head)
    ratio = math.prod(s.ratio for s in dyn.stages)
    k_input = np.asarray(stiff.torsional, dtype=float)
    k0 = float(np.interp(start, stiff.position, k_input))
    chain = model_from_stages(dyn.motor_inertia, (*head, replace(mech, stiffness=k0)), 0.0)
    angle = np.asarray(stiff.position, dtype=float) * ratio
    order = np.argsort(angle)
    chain = chain.with_(spring_table=(angle[order], k_input[order] / r_head**2))
    return AxisDynamics(chain, dyn.motor, dyn.motor_inertia, dyn.stages)


def simulate_axis(axis: Axis, *, cycles: int | None = None, step: float | None = None,
                  velocity_bandwidth_hz: float | None = None) -> SimulationResult:
    """Closed-loop simulation of the axis following its own duty-cycle profile.

    The mechanism's spring follows the load's position (``with_mechanism_spring``) where the
    axis file gives its stiffness data; the loop is tuned on the chain at the start position.
    """
    from drivetrain.axis.requirements import settling_window
    from drivetrain.dynamics.kernel_io import MAX_SIMULATION_BYTES, default_step, estimate_bytes, max_steps
    from drivetrain.dynamics.reference import Reference
    from drivetrain.dynamics.simulation import simulate

    block = _block(axis)
    dyn = model(axis)
    if axis.spec.profile:
        x_start = float(np.asarray(axis.cycle().evaluate(np.array([0.0])).x, dtype=float)[0])
        dyn = with_mechanism_spring(axis, dyn, x_start)
    if velocity_bandwidth_hz is not None:
        block = {**block, "loop": {**(block.get("loop") or {}), "velocity_bandwidth": velocity_bandwidth_hz}}
    loop = servo_loop(dyn.chain, block)
    friction, load_torque = load_friction(axis, dyn.stages, block)
    chain = dyn.chain
    if friction is not None:
        frictions = list(chain.friction) if chain.friction else [None] * chain.n
        frictions[-1] = friction
        chain = chain.with_(friction=tuple(frictions))
    given_cycles = block.get("cycles", 1) if cycles is None else cycles
    if isinstance(given_cycles, bool) or not isinstance(given_cycles, int) or not 1 <= given_cycles <= 100:
        raise InputError("dynamics.cycles", "must be a whole number between 1 and 100", given_cycles)
    n = given_cycles
    cycle = axis.cycle()
    h = step if step is not None else (parse(block["step"], "time", "dynamics.step", allow_zero=False)
                                       if "step" in block else default_step(chain, loop))
    per_cycle = cycle.period / h
    fit = max_steps(chain.n)
    if n * per_cycle > fit:
        need = estimate_bytes(chain.n, round(n * per_cycle)) / 1e9
        if per_cycle <= fit:
            raise InputError("dynamics.cycles", f"{n} cycles of {cycle.period:g} s are {n * per_cycle:.3g} steps of "
                             f"{h:g} s (about {need:.1f} GB); at most {int(fit // per_cycle)} cycles fit in "
                             f"{MAX_SIMULATION_BYTES / 1e9:g} GB", n)
        raise InputError("profile", f"one cycle of {cycle.period:g} s is {per_cycle:.3g} steps of {h:g} s (about "
                         f"{need:.1f} GB); the simulation holds at most {fit * h:.4g} s at this step: simulate a "
                         "shorter profile", has_value=False)
    # A uniform grid over n periods (the reference must be strictly increasing in time).
    t = np.linspace(0.0, n * cycle.period, int(min(200_000, max(2_000, 4_000 * n))) + 1)
    kin = cycle.evaluate(np.mod(t, cycle.period) if n > 1 else t)
    x = np.asarray(kin.x, dtype=float)
    if n > 1:
        x = x + np.floor(t / cycle.period) * float(cycle.evaluate(np.array([cycle.period])).x[0])
    ratio = math.prod(s.ratio for s in dyn.stages)
    ref = Reference.from_load(t, x, kin.v, kin.a, ratio)
    # settling is judged at the load against its window (requirements.settling.window or the default)
    window = settling_window(axis.spec.requirements, axis.mechanism.motion) * ratio
    try:
        # the automatic step is simulate's own: refined until settling and errors converge
        automatic = step is None and "step" not in block
        return simulate(chain, loop, ref, load_torque=load_torque, step=None if automatic else h,
                        settle_tolerance=window)
    except InputError as exc:
        # The step is the user's dynamics.step (or the automatic one): name the key of the file.
        if "step" in block and step is None and exc.field == "simulation.step":
            raise InputError("dynamics.step", exc.rule, block["step"]) from None
        if "step" in block and step is None and exc.field.endswith("_sample_time"):
            times = ", ".join(f"{t * 1e6:g} us" for t in (loop.current_sample_time, loop.velocity_sample_time,
                                                          loop.position_sample_time))
            raise InputError("dynamics.step", f"must divide the loop's sample times ({times})",
                             block["step"]) from None
        raise
