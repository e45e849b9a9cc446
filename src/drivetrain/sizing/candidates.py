"""The evaluated candidates of a catalog selection, compactly: who each is, its worst margin, which
checks fail and which cannot be judged; every check of any of them recomputed on demand."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from drivetrain.catalog import GearboxTable, MotorTable
    from drivetrain.sizing.answer import Candidate, SelectionSummary

Array = NDArray[np.float64]


CHECK_UNITS = {"peak_torque": "N*m", "rms_torque": "N*m", "max_speed": "rpm", "inertia_ratio": "-",
               "mechanical_fit": "mm", "gearbox_peak_torque": "N*m", "gearbox_rated_torque": "N*m",
               "gearbox_emergency_stop_torque": "N*m", "gearbox_max_input_speed": "rpm",
               "gearbox_mean_input_speed": "rpm", "motor_brake": "N*m", "gearbox_radial_load": "N",
               "gearbox_axial_load": "N"}
"""Every check of a candidate with its unit, in the order of the compiled pass's arrays (kernel.py)."""

FIT_BIT = 1 << list(CHECK_UNITS).index("mechanical_fit")
BRAKE_BIT = 1 << list(CHECK_UNITS).index("motor_brake")
KNOWN_FIRST = FIT_BIT | BRAKE_BIT
"""The unknown checks that rank a passing candidate after the known ones: a pair not known to assemble,
a motor whose brake variant's holding torque the catalog lacks."""

MOTOR_CHECKS = ("peak_torque", "rms_torque", "max_speed", "inertia_ratio", "motor_brake")
"""The checks a direct-drive candidate has; the others belong to a gearbox."""


@dataclass(frozen=True)
class Details:
    """Every check of some candidates (index j over the candidates asked for)."""

    required: dict[str, Array]
    available: dict[str, Array]
    margin: dict[str, Array]
    approximate: dict[str, NDArray[np.bool_]]
    rms_torque: Array  # RMS motor torque, rotor included [N m]
    peak_torque: Array  # peak motor torque over the cycle [N m]
    inertia_ratio: Array

    def column(self, j: int) -> Details:
        """The details of the j-th candidate asked for alone (views, each of length 1): what
        ``details([k])`` gives for that candidate, to the bit (the kernel's arithmetic is elementwise)."""
        at = slice(j, j + 1)
        return Details(required={n: v[at] for n, v in self.required.items()},
                       available={n: v[at] for n, v in self.available.items()},
                       margin={n: v[at] for n, v in self.margin.items()},
                       approximate={n: v[at] for n, v in self.approximate.items()},
                       rms_torque=self.rms_torque[at], peak_torque=self.peak_torque[at],
                       inertia_ratio=self.inertia_ratio[at])


@dataclass(frozen=True)
class Candidates:
    """Every evaluated candidate (index k), compact: who it is, its worst margin, which checks fail.

    The full checks of any candidates are recomputed on demand by :meth:`details` (the same
    compiled arithmetic), so a selection over 10^5-10^6 candidates keeps 17 bytes of each.
    """

    motor: NDArray[np.int32]  # index into the motor table
    slot: NDArray[np.int32]  # index into slot_row / slot_group
    worst_margin: Array  # smallest known margin [-], NaN where no margin is known
    failed: NDArray[np.uint16]  # bit c set where check c (CHECK_UNITS order) fails (margin < 0)
    unknown: NDArray[np.uint16]  # bit c set where check c cannot be judged (margin NaN)
    slot_row: NDArray[np.int64]  # gearbox row of each slot, -1 for direct drive
    slot_group: NDArray[np.int64]  # (ratio, efficiency) group of each slot
    group_ratio: Array
    approx_motor: NDArray[np.bool_]  # the motor's envelope is derived from its ratings
    model: tuple[Any, ...]  # the kernel's arrays (kernel.check)
    strict: bool = False  # an unknown check rejects the candidate (motor.select.unknown: fail)

    @cached_property
    def ok(self) -> NDArray[np.bool_]:
        """True where no check fails (and, when strict, none is unknown)."""
        if self.strict:
            return (self.failed == 0) & (self.unknown == 0)
        return self.failed == 0

    @cached_property
    def rejected(self) -> NDArray[np.uint8]:
        """1 where the candidate does not pass (the complement of ``ok``, for the compiled ranking)."""
        return (~self.ok).astype(np.uint8)

    def gearbox(self, ks: NDArray[np.intp] | int) -> Any:
        """Gearbox row of the candidates ``ks``, -1 for direct drive."""
        return self.slot_row[self.slot[ks]]

    def ratio(self, ks: NDArray[np.intp] | int) -> Any:
        """Gear ratio of the candidates ``ks`` [-]."""
        return self.group_ratio[self.slot_group[self.slot[ks]]]

    def of_motors(self, motors: NDArray[np.intp]) -> NDArray[np.intp]:
        """The candidates of these motors (ascending)."""
        hit = np.zeros(len(self.approx_motor), dtype=bool)
        hit[motors] = True
        return np.flatnonzero(hit[self.motor])

    @property
    def brake_needed(self) -> bool:
        """The axis needs a motor holding brake: the ``motor_brake`` check applies (kernel.py, par[9])."""
        return not bool(np.isnan(self.model[-1][9]))

    def check_names(self) -> list[str]:
        """The checks that apply to these candidates: ``motor_brake`` only where the axis needs a brake."""
        return [n for n in CHECK_UNITS if n != "motor_brake" or self.brake_needed]

    def failures(self) -> dict[str, int]:
        """How many candidates fail each check."""
        return {n: int(np.count_nonzero(self.failed & (1 << c))) for c, n in enumerate(CHECK_UNITS)
                if n != "motor_brake" or self.brake_needed}

    def unknowns(self) -> dict[str, int]:
        """How many candidates cannot be judged on each check (a rating or dimension unknown)."""
        return {n: int(np.count_nonzero(self.unknown & (1 << c))) for c, n in enumerate(CHECK_UNITS)
                if n != "motor_brake" or self.brake_needed}

    def details(self, ks: NDArray[np.intp] | list[int]) -> Details:
        """Required, available and margin of every check of the candidates ``ks``."""
        from drivetrain.sizing.kernel import D_INERTIA, D_PEAK, D_RMS, N_CHECKS, N_DETAIL, check

        ks = np.asarray(ks, dtype=np.intp)
        slots = self.slot[ks]
        pick = np.stack([self.motor[ks], self.slot_group[slots], slots]).astype(np.int64)
        out = np.empty((N_DETAIL, len(ks)))
        none = np.empty(0, dtype=np.int32)
        bits = np.empty(0, dtype=np.uint16)
        check(self.model, np.zeros(1, dtype=np.int64), self.slot_row, pick, none, none, np.empty(0), bits, bits, out)
        names = list(CHECK_UNITS)
        approx = self.approx_motor[pick[0]]
        exact = np.zeros(len(ks), dtype=bool)
        return Details(required=dict(zip(names, out[:N_CHECKS], strict=True)),
                       available=dict(zip(names, out[N_CHECKS:2 * N_CHECKS], strict=True)),
                       margin=dict(zip(names, out[2 * N_CHECKS:3 * N_CHECKS], strict=True)),
                       approximate={n: approx if n in ("peak_torque", "rms_torque") else exact for n in names},
                       rms_torque=out[D_RMS], peak_torque=out[D_PEAK], inertia_ratio=out[D_INERTIA])


def column(table: Any, name: str) -> Array:
    """A numeric column of a catalog table, all NaN (unknown) where the table has no such column."""
    value = getattr(table, name, None)
    return np.full(len(table), np.nan) if value is None else np.asarray(value, dtype=float)


def closest(c: Candidates, pool: NDArray[np.intp]) -> int:
    """The candidate of ``pool`` with the largest worst margin (an unknown, NaN, margin counts as the lowest)."""
    w = c.worst_margin[pool]
    return int(pool[np.argmax(np.where(np.isnan(w), -np.inf, w))])


__all__ = ["BRAKE_BIT", "CHECK_UNITS", "FIT_BIT", "KNOWN_FIRST", "MOTOR_CHECKS", "Candidates", "Details", "closest",
           "column"]


@dataclass
class Ranking:
    """The evaluated candidates behind a selection's answer: what ``explain``, the drive rule and the
    candidate's own cycle read (not part of the JSON answer).

    Attributes
    ----------
    candidates : Candidates
        Every evaluated candidate (index k): motor, gearbox slot, worst margin, failed and unknown checks.
    ranked : numpy.ndarray of int
        The passing candidates, best first (the objective, then a pair known to assemble first). Where the
        selection searched only for its first candidate (``listing="selected"``), the candidates it ranked.
    motors : MotorTable
        The catalog motors the candidates index (``candidates.motor``).
    gearboxes : GearboxTable or None
        The catalog gearbox rows the candidates' slots index; None where direct drive alone was evaluated.
    best : int or None
        The selected candidate (after the drive rule), None when no candidate passes.
    shown : list of int
        The listed candidates, in the order of the answer's ``candidates``.
    """

    candidates: Candidates
    ranked: NDArray[np.intp]
    motors: MotorTable
    gearboxes: GearboxTable | None
    best: int | None = None
    shown: list[int] = field(default_factory=list)


@dataclass
class Selection:
    """A catalog selection: the listed candidates and the summary (the ``candidates`` and ``selection``
    blocks of the JSON answer, docs/axis-file.md) and the ranking they were read from.

    Attributes
    ----------
    listed : list of Candidate
        The listed candidates (JSON ``candidates``): each with its checks (required, available, margin).
    summary : SelectionSummary
        The selection's summary (JSON ``selection``): counts, the selected candidate, advice.
    ranking : Ranking
        The evaluated candidates and their order.
    """

    listed: list[Candidate]
    summary: SelectionSummary
    ranking: Ranking
