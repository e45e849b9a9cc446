"""What the page draws from a sizing, apart from the HTTP layer: pure functions from an axis
mapping (or a ``SizingResult``) to the JSON the page needs (the result, the sampled cycle, speed-
torque envelopes, the selected or a fixed catalog candidate), and its compact encoding.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from drivetrain.errors import InputError

if TYPE_CHECKING:
    from drivetrain.sizing.answer import Candidate

log = logging.getLogger("drivetrain.web")

T = TypeVar("T")

ENVELOPE_POINTS = 61
MAX_ENVELOPES = 6


def plain(obj: Any) -> Any:
    """JSON-ready copy: numpy scalars and arrays become Python numbers and lists, NaN and inf None."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind == "f" and obj.ndim == 1 and bool(np.all(np.isfinite(obj))):
            return obj.tolist()  # the common case, without a Python call per number
        return plain(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if obj is None or isinstance(obj, str):
        return obj
    return str(obj)



def _engine_errors() -> tuple[type[BaseException], ...]:
    import tokenize

    return (ArithmeticError, tokenize.TokenError)


def engine(fn: Callable[..., T], *args: Any) -> T:
    """Call the engine; an arithmetic failure on input it let through becomes a 422, not a crash.

    A stopgap: the engine should reject such input with a field name (e.g. a diameter so small
    that its radius underflows, or unit text pint cannot tokenize); the server log keeps the
    traceback.
    """
    try:
        return fn(*args)
    except InputError:
        raise
    except _engine_errors() as exc:
        log.warning("the engine failed on input it should have rejected", exc_info=True)
        raise InputError("", f"these values cannot be computed ({type(exc).__name__}: {exc}); a value is "
                         "outside the range the engine handles", has_value=False) from None



def _motor_envelope(name: str, rated: float, peak: float, rated_speed: float, max_speed: float,
                    stall: float | None, curve: Any = None, rank: int | None = None) -> dict[str, Any]:
    return _envelopes([name], np.array([rated]), np.array([peak]), np.array([rated_speed]), np.array([max_speed]),
                      np.array([np.nan if stall is None else stall]), [curve], [rank])[0]


def _envelopes(names: list[str], rated: np.ndarray, peak: np.ndarray, rated_speed: np.ndarray,
               max_speed: np.ndarray, stall: np.ndarray, curves: list[Any],
               ranks: list[int | None]) -> list[dict[str, Any]]:
    """Continuous and peak envelopes of motors for the page, from 0 to each one's max speed (one call)."""
    from drivetrain.sizing.envelope import motor_envelopes

    top = np.where(np.isfinite(max_speed) & (max_speed > 0), max_speed, rated_speed)
    omega = np.linspace(0.0, 1.0, ENVELOPE_POINTS)[None, :] * top[:, None]
    cont, pk = motor_envelopes(rated, peak, rated_speed, max_speed, omega, stall,
                               curves=curves if any(c is not None for c in curves) else None)
    approx = np.asarray(cont.approximate) | np.asarray(pk.approximate)
    approx = np.broadcast_to(approx, (len(names),))
    return [{"name": name, "rank": rank, "speed_rad_s": plain(omega[i]), "continuous_Nm": plain(cont.torque[i]),
             "peak_Nm": plain(pk.torque[i]), "approximate": bool(approx[i])}
            for i, (name, rank) in enumerate(zip(names, ranks, strict=True))]


def _candidate_envelopes(candidates: list[Candidate], notes: list[str]) -> list[dict[str, Any]]:
    ids: list[str] = []
    for c in candidates:
        if c.motor not in ids:
            ids.append(c.motor)
        if len(ids) >= MAX_ENVELOPES:
            break
    if not ids:
        return []
    try:
        from drivetrain import catalog

        table = catalog.motors(ids=ids)
    except (ImportError, InputError) as exc:
        notes.append(f"candidate envelopes unavailable: {exc}")
        return []
    at = {str(mid): i for i, mid in enumerate(table.ids)}
    idx = np.array([at[mid] for mid in ids])
    ranks = [next((k + 1 for k, c in enumerate(candidates) if c.motor == mid), None) for mid in ids]
    return _envelopes(ids, table.rated_torque[idx], table.peak_torque[idx], table.rated_speed[idx],
                      table.max_speed[idx], table.stall_torque[idx], [table.curves[i] for i in idx], ranks)


WEB_POINTS_PER_PHASE = 17
"""Samples per profile segment for the page: its plots need far fewer than a report, and RMS
and energy stay exact (Simpson per segment, segment ends always sampled)."""


def candidate_axis(axis: dict[str, Any], motor_id: str, gearbox_id: str | None) -> dict[str, Any]:
    """The axis with a catalog candidate fixed: the motor by id, the gearbox as the first stage.

    Data wiring only: the gearbox's ratio, input inertia and efficiency are copied from its
    catalog row (efficiency 1 where the catalog gives none, as the selection does).
    """
    from drivetrain import catalog

    out = dict(axis)
    given: dict[str, Any] = axis["motor"] if isinstance(axis.get("motor"), dict) else {}
    motor: dict[str, Any] = {"id": motor_id}
    if isinstance(given.get("margins"), dict):
        motor["margins"] = given["margins"]
    out["motor"] = motor
    if gearbox_id:
        try:
            row = catalog.get(gearbox_id)
        except InputError as exc:
            raise InputError("gearbox", exc.rule, exc.value, has_value=exc.has_value) from None
        if row.get("table") != "gearbox":
            raise InputError("gearbox", "is not a gearbox of the catalog", gearbox_id)
        stage: dict[str, Any] = {"type": "gearbox", "ratio": row["ratio"],
                                 "inertia": row.get("inertia_input_kgm2") or 0.0,
                                 "efficiency": row.get("efficiency") or 1.0, "catalog": gearbox_id}
        transmission: list[Any] = axis["transmission"] if isinstance(axis.get("transmission"), list) else []
        out["transmission"] = [stage, *transmission]
    return out


def candidate_payload(axis: dict[str, Any], motor_id: str, gearbox_id: str | None) -> dict[str, Any]:
    """Size the axis with one candidate fixed: its motor-shaft cycle, checks and envelope."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.sizing.pipeline import size

    fixed = candidate_axis(axis, motor_id, gearbox_id)
    try:
        parsed = engine(parse_axis, fixed)
    except InputError as exc:
        if exc.field.startswith("motor.id"):
            raise InputError("motor", exc.rule, exc.value, has_value=exc.has_value) from None
        raise
    result = engine(size, parsed, WEB_POINTS_PER_PHASE)
    cols = result.series()
    series = {k: np.asarray(cols[k], dtype=float) for k in ("t_s", "omega_motor_rad_s", "torque_motor_Nm")
              if k in cols}
    return {"motor": motor_id, "gearbox": gearbox_id, "ratio": float(parsed.transmission[0].ratio) if gearbox_id
            else 1.0, "series": series, "motor_result": {} if result.motor is None else result.motor.to_dict(),
            "envelope": motor_envelope(motor_id)}


def selected_payload(parsed: Any, result: Any, envelopes: list[dict[str, Any]]) -> dict[str, Any]:
    """The selected candidate of a sizing: its own cycle (the axis's cycle behind its gearbox, as the
    selection checked it), the selection's figures for it and its envelope."""
    from drivetrain.sizing.selection import candidate_cycle

    best: Candidate = result.selection.selected
    cycle, rotor = candidate_cycle(parsed, result.duty, result.ranking)
    series = {"t_s": cycle.t, "omega_motor_rad_s": cycle.omega, "torque_motor_Nm": cycle.motor_torque(rotor)}
    figures = {"rms_torque_Nm": best.rms_torque_Nm, "peak_torque_Nm": best.peak_torque_Nm,
               "inertia_ratio": best.inertia_ratio, "checks": [c.to_dict() for c in best.checks]}
    envelope = next((e for e in envelopes if e["name"] == best.motor), None) or motor_envelope(best.motor)
    return {"motor": best.motor, "gearbox": best.gearbox, "ratio": best.ratio, "series": series,
            "motor_result": figures, "envelope": envelope}


def size_payload(axis: dict[str, Any]) -> dict[str, Any]:
    """Size an axis mapping and collect what the page draws: the result, the sampled cycle, envelopes."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.dynamics.mechanism_modes import size  # the pipeline with its modes stage

    t0 = time.perf_counter()
    parsed = engine(parse_axis, axis)
    result = engine(size, parsed, WEB_POINTS_PER_PHASE)  # the pipeline with its modes stage
    notes: list[str] = []
    series = {k: np.asarray(v, dtype=float) for k, v in result.series().items()}
    envelopes: list[dict[str, Any]] = []
    motor = parsed.motor
    if motor is not None:
        envelopes.append(_motor_envelope(motor.name, motor.rated_torque, motor.peak_torque, motor.rated_speed,
                                         motor.max_speed, motor.stall_torque))
    selected = None
    if result.candidates:
        envelopes.extend(_candidate_envelopes(result.candidates, notes))
        if result.ranking is not None and result.ranking.best is not None:
            selected = selected_payload(parsed, result, envelopes)
    return {"result": result.to_dict(), "motion": parsed.mechanism.motion, "series": series,
            "envelopes": envelopes, "selected": selected, "notes": notes,
            "modes": None if result.modes is None else dict(plain(result.modes.to_dict())),
            "electrical": electrical_payload(result), "elapsed_ms": (time.perf_counter() - t0) * 1e3}


def electrical_payload(result: Any) -> dict[str, Any] | None:
    """The results panel's drive, electrical figures and regen block: the given motor's or the selected one's.

    ``drive`` (id, status, checks), ``electrical`` (envelope source, currents, winding temperature
    and their checks; the T-n curve left out) and ``regen`` (energy into the bus, braking resistor),
    each None when the sizing has none.
    """
    if result.motor is not None:
        m = result.motor
        # the motor's JSON block as the panel reads it, less its checks but the electrical ones
        electrical = {k: v for k, v in m.to_dict().items() if k not in ("checks", "supply_curve")}
        electrical["checks"] = [c.to_dict() for c in m.checks if c.name.startswith(
            ("motor_rms_current", "motor_peak_current", "peak_torque_at_supply", "winding_"))]
        out = {"drive": result.drive, "electrical": electrical, "regen": result.regen}
    else:
        sel = result.selection.selected if result.selection is not None else None
        if sel is None:
            return None
        elec = {k: v for k, v in (sel.electrical or {}).items() if k != "curve"}
        out = {"drive": sel.drive, "electrical": elec or None, "regen": sel.regen}
    if out["drive"] is not None:
        out["drive"] = out["drive"].to_dict()
    if out["regen"] is not None:  # the panel shows the figures, not the events
        out["regen"] = out["regen"].to_dict(events=False)
    return out if any(v for v in out.values()) else None


def encode(payload: dict[str, Any]) -> bytes:
    """Compact JSON of a sizing payload: numpy arrays and scalars as numbers, NaN and infinity as null.

    orjson writes numpy arrays natively (no Python call per number), which is most of a payload.
    """
    import orjson

    return orjson.dumps(payload, default=_json_default, option=orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS)


def _json_default(obj: Any) -> Any:
    """What orjson does not write itself: strided numpy arrays and other numpy values; anything else as text."""
    if isinstance(obj, (np.ndarray, np.generic)):
        return obj.tolist()
    return str(obj)



def motor_envelope(motor_id: str) -> dict[str, Any]:
    """A catalog motor's continuous and peak envelope for the page."""
    from drivetrain import catalog

    table = catalog.motors(ids=[motor_id])  # an unknown id: InputError naming ``ids``
    stall = float(table.stall_torque[0])
    return _motor_envelope(motor_id, float(table.rated_torque[0]), float(table.peak_torque[0]),
                           float(table.rated_speed[0]), float(table.max_speed[0]),
                           stall if math.isfinite(stall) else None, table.curves[0])

