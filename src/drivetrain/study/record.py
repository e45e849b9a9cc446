"""One variant's result as one table row: the groups a study records and any dotted key of ``size``.

Groups (``record:`` in the study file):

* ``motor``: the selected motor (``motor``), its rated power (``rated_power_W``); a given motor's name;
* ``gearbox``: the selected catalog gearbox (``gearbox``, empty for direct drive) and ``ratio``;
* ``margins``: ``margin_<check>`` of every check of the selected candidate (or the given motor) and
  ``worst_margin``; when nothing passes, those of the closest candidate (``selection.candidates[0]``);
* ``rms`` / ``peak``: RMS and peak motor torque with the rotor (``rms_torque_Nm``, ``peak_torque_Nm``)
  and the load's own at the motor shaft (``load_rms_torque_Nm``, ``load_peak_torque_Nm``);
* ``energy``: ``energy_per_cycle_J``, what the motor delivers per cycle (regeneration not credited);
* ``checks``: ``ok_<check>`` of every check, the axis's own (slip, guide, brake, the ratings of a
  gearbox given in ``transmission:``, the mechanism's) included;
* ``dynamics`` (by default when the study has ``requirements:``): the dynamic answer of the selected
  candidate (``selection.dynamics.chosen``): ``dynamics_settling_time_s`` (its worst stop; NaN when it
  never settles or none passes), ``dynamics_following_error`` (its worst move, m or rad at the load),
  ``dynamics_velocity_bandwidth_Hz``, ``dynamics_phase_margin_deg``, ``dynamics_gain_margin_dB``, and
  ``dynamics_judged`` (candidates judged) and ``dynamics_passed_over`` (static picks passed over for how
  they move).

Every row has ``variant``, the parameters, ``ok`` (every check passes) and ``error`` (an input error of
that variant, e.g. a lead that makes the profile impossible; empty otherwise).
"""

from __future__ import annotations

import math
from typing import Any

from drivetrain.sizing.candidates import CHECK_UNITS
from drivetrain.study.paths import get_dotted

CHECK_NAMES = tuple(CHECK_UNITS)
"""The checks of a catalog candidate, in the selection's order."""
OWN_CHECKS = ("slip_check", "guide", "brake_check", "gearbox_checks")


def _num(x: Any) -> float:
    return math.nan if x is None else float(x)


def row_from(result: dict[str, Any], record: list[str]) -> dict[str, Any]:
    """The recorded columns of one variant's result (``batch.Engine.size`` or ``SizingResult.to_dict``)."""
    row: dict[str, Any] = {"ok": bool(result.get("ok", False))}
    sel = result.get("selection")
    cand: dict[str, Any] | None = None
    if "motor" in result:
        m = result["motor"]
        cand = {"motor": m.get("name"), "gearbox": None, "ratio": 1.0, "rated_power_W": None,
                "rms_torque_Nm": m.get("rms_torque_Nm"), "peak_torque_Nm": m.get("peak_torque_Nm"),
                "checks": m.get("checks", [])}
    elif sel is not None:
        cand = sel.get("selected") or sel.get("closest")
        if cand is None and result.get("candidates"):
            cand = result["candidates"][0]  # SizingResult.to_dict with nothing passing
    groups = set(record)
    if "motor" in groups:
        row["motor"] = None if cand is None else cand.get("motor")
        row["rated_power_W"] = _num(None if cand is None else cand.get("rated_power_W"))
    if "gearbox" in groups:
        row["gearbox"] = None if cand is None else cand.get("gearbox")
        row["ratio"] = _num(None if cand is None else cand.get("ratio"))
    checks = {} if cand is None else {c["name"]: c for c in cand.get("checks", [])}
    if "margins" in groups:
        margins = [_num(checks[n].get("margin")) if n in checks else math.nan for n in CHECK_NAMES]
        for n, v in zip(CHECK_NAMES, margins, strict=True):
            row[f"margin_{n}"] = v
        known = [v for v in margins if not math.isnan(v)]
        row["worst_margin"] = min(known) if known else math.nan
    if "rms" in groups:
        row["rms_torque_Nm"] = _num(None if cand is None else cand.get("rms_torque_Nm"))
        row["load_rms_torque_Nm"] = _num(result.get("rms_torque_Nm"))
    if "peak" in groups:
        row["peak_torque_Nm"] = _num(None if cand is None else cand.get("peak_torque_Nm"))
        row["load_peak_torque_Nm"] = _num(result.get("peak_torque_Nm"))
    if "energy" in groups:
        row["energy_per_cycle_J"] = _num(result.get("energy_per_cycle_J"))
    if "checks" in groups:
        for n in CHECK_NAMES:
            row[f"ok_{n}"] = bool(checks[n]["ok"]) if n in checks else None
        for own in OWN_CHECKS:
            if own in result:
                row[f"ok_{own}"] = bool(result[own]["ok"])
        if "mechanism_checks" in result:
            row["ok_mechanism_checks"] = all(bool(c["ok"]) for c in result["mechanism_checks"])
    if "dynamics" in groups:
        row.update(dynamics_columns((sel or {}).get("dynamics")))
    for name in record:
        if "." in name or "[" in name or name not in ("motor", "gearbox", "margins", "rms", "peak", "energy",
                                                      "checks", "dynamics"):
            found, value = get_dotted(result, name)
            row[name] = value if found and not isinstance(value, (dict, list)) else (
                None if not found else str(value))
    return row


def dynamics_columns(dyn: dict[str, Any] | None) -> dict[str, Any]:
    """The ``dynamics`` group's columns from ``selection.dynamics`` (NaN where not judged or none passes)."""
    chosen = (dyn or {}).get("chosen") or {}
    stops = chosen.get("settling_time_per_stop_s") or []
    errs = chosen.get("following_error_per_move") or []
    settle = math.nan if not stops or any(v is None for v in stops) else max(stops)
    gm = chosen.get("gain_margin_dB")
    return {"dynamics_settling_time_s": float(settle),
            "dynamics_following_error": float(max(errs)) if errs else math.nan,
            "dynamics_velocity_bandwidth_Hz": _num(chosen.get("velocity_bandwidth_Hz")),
            "dynamics_phase_margin_deg": _num(chosen.get("phase_margin_deg")),
            "dynamics_gain_margin_dB": _num(gm),
            "dynamics_judged": int((dyn or {}).get("judged", 0)),
            "dynamics_passed_over": len((dyn or {}).get("passed_over", []))}


def fast_covers(fast: dict[str, Any], full: dict[str, Any], record: list[str]) -> tuple[bool, list[str]]:
    """(the batched result has every dotted key asked for, the keys the full result lacks too)."""
    from drivetrain.study.spec import GROUPS

    missing_fast = False
    unknown: list[str] = []
    for name in record:
        if name in GROUPS:
            continue
        if not get_dotted(full, name)[0]:
            unknown.append(name)
        elif not get_dotted(fast, name)[0]:
            missing_fast = True
    return not missing_fast, unknown


__all__ = ["CHECK_NAMES", "OWN_CHECKS", "dynamics_columns", "fast_covers", "row_from"]
