"""Drive-train dynamics: compliant chain models, resonance, the servo loop and a fast simulation.

Modules, one physical idea each:
    stiffness  shaft, belt, ball-screw and gearbox stiffness; series/parallel; reflection K/i^2
    chain      the N-mass chain (``Chain``), from the axis file (``chain_from_spec``) or from the
               drive-train stages (``model_from_stages``)
    linear     state space, transfer functions, modes, two-mass resonance, ZOH, critical speeds
    filters    notch and low-pass on the torque command
    friction   Coulomb + viscous + Stribeck (exponential with stick, or tanh)
    control    the cascaded loop (``ServoLoop``), tuning, Bode data, margins, stability
    simulation the compiled nonlinear simulation (``simulate`` -> ``SimulationResult``)

Importing this package does not import numba, scipy or python-control, nor any submodule: each
loads on first use of one of its names.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drivetrain.dynamics.chain import Chain, chain_from_spec, model_from_stages, two_mass_chain
    from drivetrain.dynamics.control import (
        LoopAnalysis,
        Margins,
        ServoLoop,
        analyse_loop,
        check_stable,
        notch_effect,
        tune,
    )
    from drivetrain.dynamics.filters import Notch, propose_notch
    from drivetrain.dynamics.friction import Friction
    from drivetrain.dynamics.kernel_io import SimulationDivergedError
    from drivetrain.dynamics.linear import (
        CriticalSpeed,
        StateSpaceMatrices,
        TransferFunctionData,
        TwoMass,
        anti_resonance_frequencies,
        campbell_diagram,
        critical_speeds,
        discrete_model,
        discretize_zoh,
        disturbance_tf,
        excitation_orders,
        frequency_response,
        load_position_tf,
        mass_spring_damper,
        modes,
        motor_speed_tf,
        natural_frequencies,
        state_space,
        transfer_function,
        two_mass_reduction,
        two_mass_resonance,
    )
    from drivetrain.dynamics.reference import Reference, move_reference
    from drivetrain.dynamics.simulation import simulate, simulate_open_loop, sweep
    from drivetrain.dynamics.simulation_result import SimulationResult

_LAZY = {  # name -> module: a submodule loads on first use, so `size` (modes only) skips the simulation
    "Chain": "chain",
    "chain_from_spec": "chain",
    "model_from_stages": "chain",
    "two_mass_chain": "chain",
    "LoopAnalysis": "control",
    "Margins": "control",
    "ServoLoop": "control",
    "analyse_loop": "control",
    "check_stable": "control",
    "notch_effect": "control",
    "tune": "control",
    "Notch": "filters",
    "propose_notch": "filters",
    "Friction": "friction",
    "CriticalSpeed": "linear",
    "StateSpaceMatrices": "linear",
    "TransferFunctionData": "linear",
    "TwoMass": "linear",
    "anti_resonance_frequencies": "linear",
    "campbell_diagram": "linear",
    "critical_speeds": "linear",
    "discrete_model": "linear",
    "discretize_zoh": "linear",
    "disturbance_tf": "linear",
    "excitation_orders": "linear",
    "frequency_response": "linear",
    "load_position_tf": "linear",
    "mass_spring_damper": "linear",
    "modes": "linear",
    "motor_speed_tf": "linear",
    "natural_frequencies": "linear",
    "state_space": "linear",
    "transfer_function": "linear",
    "two_mass_reduction": "linear",
    "two_mass_resonance": "linear",
    "Reference": "reference",
    "SimulationDivergedError": "kernel_io",
    "SimulationResult": "simulation_result",
    "move_reference": "reference",
    "simulate": "simulation",
    "simulate_open_loop": "simulation",
    "sweep": "simulation",
}


__all__ = [
    "Chain",
    "CriticalSpeed",
    "Friction",
    "LoopAnalysis",
    "Margins",
    "Notch",
    "Reference",
    "ServoLoop",
    "SimulationDivergedError",
    "SimulationResult",
    "StateSpaceMatrices",
    "TransferFunctionData",
    "TwoMass",
    "analyse_loop",
    "anti_resonance_frequencies",
    "campbell_diagram",
    "chain_from_spec",
    "check_stable",
    "critical_speeds",
    "discrete_model",
    "discretize_zoh",
    "disturbance_tf",
    "excitation_orders",
    "frequency_response",
    "load_position_tf",
    "mass_spring_damper",
    "model_from_stages",
    "modes",
    "modes_summary",
    "motor_speed_tf",
    "move_reference",
    "natural_frequencies",
    "notch_effect",
    "propose_notch",
    "simulate",
    "simulate_open_loop",
    "state_space",
    "sweep",
    "transfer_function",
    "tune",
    "two_mass_chain",
    "two_mass_reduction",
    "two_mass_resonance",
]


def __getattr__(name: str) -> Any:
    """The public names of the submodules, imported on first use (PEP 562)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def model(axis: Any) -> Any:
    """The compliant chain of an axis (``axis_model.model``): chain, motor and stages."""
    from drivetrain.dynamics.axis_model import model as _model

    return _model(axis)


def modes_summary(chain: Chain) -> dict[str, Any]:
    """What ``drivetrain modes AXIS --json`` prints: natural frequencies (ascending, rigid-body
    mode left out) as ``natural_frequencies_Hz``, mode shapes, and the two-mass resonance and
    anti-resonance."""
    from drivetrain.dynamics.linear import modes, two_mass_reduction

    freqs, shapes = modes(chain)
    out: dict[str, Any] = {
        "natural_frequencies_Hz": [float(f) for f in freqs],
        "mode_shapes": [[float(v) for v in shapes[:, k]] for k in range(shapes.shape[1])],
        "inertias_kgm2": [float(j) for j in chain.inertia],
        "names": list(chain.names),
    }
    if chain.n >= 2:
        tm = two_mass_reduction(chain)
        out.update({"resonance_Hz": tm.resonance_hz, "anti_resonance_Hz": tm.anti_resonance_hz,
                    "two_mass": {"j_motor_kgm2": tm.j_motor, "j_load_kgm2": tm.j_load,
                                 "stiffness_Nm_per_rad": tm.stiffness}})
    return out
