"""The motor the report is about: the axis's own motor, or the catalog selection's choice.

A sizing names a motor in the axis file (``SizingResult.motor``), or selects one from the
catalog (``SizingResult.selection.selected``, possibly behind a catalog gearbox), or gives
only the demand. The report plots and tabulates one motor: :func:`focus_of` finds it, reads its
ratings (from the catalog for a selection) and takes the cycle at its shaft through the selected
gearbox from the selection (``selection.candidate_cycle``, as its checks saw it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from drivetrain.axis.model import MotorData
    from drivetrain.sizing.answer import Candidate
    from drivetrain.sizing.result import SizingResult

Array = NDArray[np.float64]


@dataclass(frozen=True)
class GearboxInfo:
    """A catalog gearbox put in front of the axis by the selection (SI)."""

    id: str
    ratio: float
    efficiency: float
    inertia: float
    kind: str = "planetary"
    vendor: str = ""
    rated_output_torque: float | None = None
    source: str = ""


@dataclass(frozen=True)
class Focus:
    """The report's motor, its checks and the cycle at its shaft (SI arrays over samples).

    ``origin`` says where it came from; ``passed`` whether every check passed. ``torque_load`` is
    the torque at the motor shaft without the rotor (through the catalog gearbox if any),
    ``torque`` the motor's torque with it; ``load_inertia`` everything but the rotor at its shaft.
    """

    origin: Literal["axis", "selection"]
    label: str
    motor: MotorData
    gearbox: GearboxInfo | None
    checks: list[dict[str, Any]]  # as the JSON has them: the report reads them as the axis's own checks
    passed: bool
    omega: Array
    alpha: Array
    torque_load: Array
    torque: Array
    load_inertia: float
    metrics: dict[str, Any]
    candidate: Candidate | None = None

    @property
    def inertia_ratio(self) -> float:
        """J_L / J_M at the motor shaft [-]."""
        return self.load_inertia / self.motor.inertia


def candidate_label(c: Candidate) -> str:
    """'HG-KR23' or 'SGM7J-02A + GPB042-L1-i5'."""
    text = c.motor
    if c.gearbox:
        text += f" + {c.gearbox}"
    return text


def shaft_metrics(result: SizingResult, omega: Array, torque: Array) -> dict[str, Any]:
    """Peak, RMS, speeds, power, regenerated energy and per-phase torques of a motor-shaft cycle (SI keys)."""
    from drivetrain.physics.averages import rms, signed_extreme
    from drivetrain.units import to_rpm

    duty = result.duty
    w = duty.weights
    power = torque * omega
    k = int(np.argmax(np.abs(torque)))
    phase = np.asarray(duty.samples.phase)
    segments = []
    for i, ph in enumerate(duty.cycle.phases):
        mask = phase == i
        segments.append({"kind": ph.kind, "move": ph.move, "t0_s": float(ph.t0), "t1_s": float(ph.t1),
                         "torque_Nm": signed_extreme(torque[mask]),
                         "speed_rpm": float(to_rpm(np.max(np.abs(omega[mask])))) if mask.any() else 0.0})
    first = next((ph.move for ph in duty.cycle.phases if ph.kind != "dwell"), None)
    per = {"accel": 0.0, "run": 0.0, "decel": 0.0}
    for i, ph in enumerate(duty.cycle.phases):
        if ph.move == first and ph.kind in per:
            per[ph.kind] = signed_extreme(torque[phase == i])
    holding = np.asarray(duty.samples.holding, dtype=bool)
    return {
        "peak_torque_Nm": float(abs(torque[k])),
        "peak_torque_speed_rpm": float(to_rpm(abs(omega[k]))),
        "rms_torque_Nm": rms(torque, w, duty.period),
        "max_speed_rpm": float(to_rpm(np.max(np.abs(omega)))),
        "mean_speed_rpm": float(to_rpm(np.sum(w * np.abs(omega)) / duty.period)),
        "accel_torque_Nm": per["accel"], "run_torque_Nm": per["run"], "decel_torque_Nm": per["decel"],
        "holding_torque_Nm": signed_extreme(torque[holding]),
        "peak_power_W": float(np.max(np.abs(power))),
        "average_power_W": float(np.sum(w * power) / duty.period),
        "regen_energy_J": float(-np.sum(w * np.minimum(power, 0.0))),
        "segments": segments,
    }


def _from_axis(result: SizingResult) -> Focus | None:
    motor = result.axis.motor
    block = result.motor
    if motor is None or block is None:
        return None
    duty = result.duty
    torque = duty.motor_torque(motor.inertia)
    metrics = shaft_metrics(result, duty.omega, torque)
    # the block's figures as the JSON keys them (their unit in the name)
    figures = block.to_dict().items()
    metrics.update({k: v for k, v in figures if k.endswith(("_Nm", "_W", "_J", "_s")) and v is not None})
    return Focus("axis", motor.name, motor, None, [c.to_dict() for c in block.checks], block.ok,
                 duty.omega, duty.alpha, duty.torque, torque, duty.load_inertia, metrics)


def _gearbox(record: dict[str, Any], ratio: float) -> GearboxInfo:
    def num(key: str, default: float) -> float:
        v = record.get(key)
        return default if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)

    rated = record.get("rated_output_torque_Nm")
    return GearboxInfo(id=str(record.get("id")), ratio=num("ratio", ratio), efficiency=num("efficiency", 1.0),
                       inertia=num("inertia_input_kgm2", 0.0), kind=str(record.get("type") or "planetary"),
                       vendor=str(record.get("vendor") or ""),
                       rated_output_torque=None if rated is None else float(rated),
                       source=str(record.get("source") or ""))


def _from_selection(result: SizingResult) -> Focus | None:
    sel = result.selection
    cand = sel.selected if sel is not None and sel.selected is not None else (
        result.candidates[0] if result.candidates else None)
    if cand is None or not cand.motor:
        return None
    ranking = result.ranking
    if ranking is None:
        return None
    from drivetrain import catalog
    from drivetrain.axis.model import motor_from_catalog_row
    from drivetrain.errors import InputError
    from drivetrain.sizing.selection import candidate_cycle

    try:
        motor = motor_from_catalog_row(catalog.get(cand.motor))
        gb = _gearbox(catalog.get(cand.gearbox), float(cand.ratio or 1.0)) if cand.gearbox else None
    except InputError:
        return None
    # the candidate's own cycle as the selection checked it (the selected one, else the first listed)
    k = ranking.best if ranking.best is not None else ranking.shown[0]
    cycle, rotor = candidate_cycle(result.axis, result.duty, ranking, k)
    omega, alpha, load, j_l = cycle.omega, cycle.alpha, cycle.torque, cycle.load_inertia
    torque = cycle.motor_torque(rotor)
    metrics = shaft_metrics(result, omega, torque)
    metrics["rms_torque_Nm"], metrics["peak_torque_Nm"] = cand.rms_torque_Nm, cand.peak_torque_Nm
    # a selection whose motor no orderable drive feeds (drive_select) has not passed
    passed = cand.ok and (sel is None or sel.drive_advice is None)
    return Focus("selection", candidate_label(cand), motor, gb, [c.to_dict() for c in cand.checks], passed,
                 omega, alpha, load, torque, j_l, metrics, cand)


def focus_of(result: SizingResult) -> Focus | None:
    """The motor the report shows: the axis's motor, else the selected (or closest) catalog candidate."""
    return _from_axis(result) or _from_selection(result)
