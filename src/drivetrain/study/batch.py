"""The batched sizing path of a study: many variants of one axis against one loaded catalog.

A variant is sized by the sizing pipeline itself (``sizing.pipeline.size_many``: the same stages,
checks, ``ok`` and answer keys as ``drivetrain.size``), with ``listing="selected"``: the selection
finds the selected (or, when nothing passes, the closest) candidate smallest first
(``sizing.search``) instead of ranking and listing the whole catalog. A worker process keeps one
:class:`Engine`, whose pipeline ``Context`` keeps the catalog tables, the sampled kinematics of equal
profiles and the drive rule's catalog reads for all its batches. A batch's variants are sized in one
``size_many`` call: their mechanism checks as arrays over the variants, the first hulls of variants
of equal motion in one compiled pass.

The drive blocks of the selected candidate (a drive for the selected motor, its currents, regen) are
computed only for an engine made with ``drives`` (a study that records one of their keys); the drive
rule (the selected motor has an orderable drive) holds either way.

``tests/study/test_study_batch.py`` asserts, on a fixed sample and on 60 random variants, that the
selected (or closest) motor and gearbox and every check's required, available and margin equal
those of ``drivetrain.size``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.errors import InputError
from drivetrain.sizing.pipeline import Context, size, size_many

if TYPE_CHECKING:
    from drivetrain.axis.model import Axis
    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.sizing.result import SizingResult


def motoring_energy(duty: DutyCycle, rotor_inertia: float) -> float:
    """Energy the motor delivers per cycle [J]: the integral of max(T omega, 0) dt, rotor included
    (``selection._energy``'s measure, regenerated energy not credited)."""
    p = duty.motor_torque(rotor_inertia) * duty.omega
    return float(np.sum(duty.weights * np.maximum(p, 0.0)))


def answer(r: SizingResult) -> dict[str, Any]:
    """``r.to_dict()`` with ``ok`` and ``energy_per_cycle_J`` (the selected candidate's, none when
    nothing passes)."""
    from drivetrain.sizing.selection import candidate_cycle

    out = r.to_dict()
    out["ok"] = r.ok
    if r.axis.motor is not None:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, r.axis.motor.inertia)
    elif r.ranking is not None and r.ranking.best is not None:
        cycle, j = candidate_cycle(r.axis, r.duty, r.ranking)
        out["energy_per_cycle_J"] = motoring_energy(cycle, j)
    elif r.selection is not None:
        out["energy_per_cycle_J"] = math.nan
    else:
        out["energy_per_cycle_J"] = motoring_energy(r.duty, 0.0)
    return out


class Engine:
    """Sizes many variants against the catalog loaded once; a worker process keeps one engine."""

    def __init__(self, points_per_phase: int = 64, drives: bool = False) -> None:
        self.points = points_per_phase
        self.drives = drives  # the drive blocks of the selected candidate (its drive, currents, regen)
        self.context = Context(points_per_phase)

    def size(self, axis: Axis) -> dict[str, Any]:
        """A variant's result: ``answer`` of the pipeline's with ``listing="selected"`` (its
        ``selection`` block holds the keys of ``search.select_first``; the selected candidate's
        ``drive``, ``electrical`` and ``regen`` only where the engine was made with ``drives``)."""
        return answer(size(axis, self.points, listing="selected", drives=self.drives, context=self.context))

    def size_many(self, axes: list[Axis]) -> list[dict[str, Any] | InputError]:
        """:meth:`size` of each axis (or the InputError it raises), sized together in one
        ``size_many`` of the pipeline."""
        results = size_many(axes, self.points, listing="selected", drives=self.drives, context=self.context,
                            errors="return")
        return [r if isinstance(r, InputError) else answer(r) for r in results]


def full_result(axis: Axis, points_per_phase: int = 64) -> dict[str, Any]:
    """``answer(drivetrain.size(axis))``: the whole listing, for results that record keys the batched
    path does not compute."""
    return answer(size(axis, points_per_phase))


__all__ = ["Engine", "answer", "full_result", "motoring_energy"]
