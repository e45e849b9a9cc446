"""drivetrain: size and analyse servo axes.

Describe a load, the mechanism that moves it, the transmission and the motion; drivetrain
computes what the motor must deliver, checks motors and gearboxes with every margin, and
analyses the axis's dynamics. Heavy modules load on first use, so ``import drivetrain`` is fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from drivetrain.version import __version__

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.machine.result import MachineResult
    from drivetrain.sizing.result import SizingResult


def load_axis(path: str) -> Axis:
    """Read and validate an axis file into an SI ``Axis``."""
    from drivetrain.axis.model import load_axis as _load

    return _load(path)


def size_many(axes: Any, points_per_phase: int = 64, all_pairs: bool = False, **kwargs: Any) -> list[SizingResult]:
    """Size axes (each an ``Axis``, a mapping of the axis file, or a path to one): the sizing pipeline
    (``sizing.pipeline.size_many``) with its modes stage, f1 across the stroke
    (``dynamics.mechanism_modes.size_many``); each answer is the one the axis gets alone."""
    from drivetrain.dynamics.mechanism_modes import size_many as _size_many

    return _size_many(axes, points_per_phase, all_pairs, **kwargs)


def size(axis: Any, points_per_phase: int = 64, all_pairs: bool = False, **kwargs: Any) -> SizingResult:
    """Size an axis (an ``Axis``, a mapping of the axis file, or a path to one): ``size_many([axis])[0]``,
    the answer of ``drivetrain size`` (``to_dict()`` is its ``--json``)."""
    return size_many([axis], points_per_phase, all_pairs, **kwargs)[0]


def simulate(axis: Any, **kwargs: Any) -> Any:
    """Closed-loop simulation of an axis on its own profile (``dynamics.axis_model.simulate_axis``)."""
    from drivetrain.axis.model import Axis, parse_axis
    from drivetrain.axis.model import load_axis as _load
    from drivetrain.dynamics.axis_model import simulate_axis

    if not isinstance(axis, Axis):
        axis = parse_axis(axis) if isinstance(axis, dict) else _load(axis)
    return simulate_axis(axis, **kwargs)


def sweep(study: Any, **kwargs: Any) -> Any:
    """Run a design-space study file (``drivetrain.study.sweep``: grid, Monte Carlo or optimisation)."""
    from drivetrain.study import sweep as _sweep

    return _sweep(study, **kwargs)


def size_machine(machine: Any, **kwargs: Any) -> MachineResult:
    """Size a machine (a path to a machine file, its mapping, or a ``Machine``): axes, DC bus, BOM."""
    from drivetrain.machine.result import size_machine as _size_machine

    return _size_machine(machine, **kwargs)


__all__ = ["__version__", "load_axis", "simulate", "size", "size_machine", "size_many", "sweep"]
