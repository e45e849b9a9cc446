"""Plausibility rules of catalog rows, mirroring the shipped data's own checks (check_catalog.py,
data/SOURCES.md): a kg*cm^2 figure read as kg*m^2, a rated power that disagrees with torque x speed.

Each rule yields (field, rule); a rule fires only when the values it needs are given and positive.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from typing import Any

from drivetrain import units

Rule = Callable[[Mapping[str, Any], str], Iterator[tuple[str, str]]]


def _pos(v: Mapping[str, Any], *names: str) -> bool:
    return all(isinstance(v.get(n), (int, float)) and v[n] > 0 for n in names)


def motor_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "rated_torque", "peak_torque") and v["peak_torque"] < v["rated_torque"]:
        yield "peak_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if _pos(v, "rated_torque", "stall_torque") and v["stall_torque"] < v["rated_torque"] * (1 - 1e-6):
        yield "stall_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if _pos(v, "rotor_inertia", "rated_torque") and not 1e-6 < v["rotor_inertia"] / v["rated_torque"] < 1e-2:
        # catalogue range is ~1e-5..1e-3 s^2; a kg*cm^2 figure read as kg*m^2 lands far above
        yield (
            "rotor_inertia",
            (
                f"rotor_inertia / rated_torque = {v['rotor_inertia'] / v['rated_torque']:.2e} s^2 "
                "is outside the plausible 1e-6..1e-2 s^2 (unit slip? write the unit in the "
                "header, e.g. rotor_inertia [kg*cm^2])"
            ),
        )
    if _pos(v, "rotor_inertia", "rotor_inertia_brake") and v["rotor_inertia_brake"] < v["rotor_inertia"]:
        yield "rotor_inertia_brake", "must be >= rotor_inertia (the brake adds inertia)"
    if kind == "ac_servo":
        yield from _ac_servo_rules(v)
    elif kind == "small_dc":
        yield from _small_dc_rules(v)


def _ac_servo_rules(v: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    if _pos(v, "rated_speed", "max_speed") and v["max_speed"] < v["rated_speed"]:
        yield "max_speed", f"must be >= rated_speed ({units.to_rpm(v['rated_speed']):.6g} rpm)"
    if _pos(v, "rotor_inertia") and not 1e-8 < v["rotor_inertia"] < 1.0:
        yield "rotor_inertia", "is outside the plausible 1e-8..1 kg*m^2 for an AC servo (unit slip?)"
    if _pos(v, "rated_power", "rated_torque", "rated_speed"):
        mech = v["rated_torque"] * v["rated_speed"]
        dev = (mech - v["rated_power"]) / v["rated_power"]
        if abs(dev) > 0.15:
            yield (
                "rated_power",
                (
                    f"disagrees with rated_torque x rated_speed = {mech:.4g} W by {dev:+.0%} "
                    "(more than 15 %: check the units of torque, speed and power)"
                ),
            )
    if _pos(v, "mass") and not 0.05 < v["mass"] < 500:
        yield "mass", "is outside the plausible 0.05..500 kg for an AC servo"


def _small_dc_rules(v: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    if _pos(v, "voltage", "torque_constant", "winding_resistance", "no_load_speed"):
        inl = v.get("no_load_current") or 0.0
        ideal = (v["voltage"] - v["winding_resistance"] * inl) / v["torque_constant"]
        if abs(ideal - v["no_load_speed"]) / v["no_load_speed"] > 0.10:
            yield (
                "no_load_speed",
                (
                    f"disagrees by more than 10 % with (V - R*I_nl)/k_t = "
                    f"{units.to_rpm(ideal):.6g} rpm (check the units of k_t, R and speed)"
                ),
            )
    if _pos(v, "rated_torque", "stall_torque") and not v["rated_torque"] < v["stall_torque"]:
        yield "rated_torque", f"must be < stall_torque ({v['stall_torque']:.6g} N*m)"
    if _pos(v, "rated_speed", "no_load_speed") and not v["rated_speed"] < v["no_load_speed"]:
        yield "rated_speed", f"must be < no_load_speed ({units.to_rpm(v['no_load_speed']):.6g} rpm)"


def gearbox_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "efficiency") and v["efficiency"] > 1:
        yield "efficiency", "must be in (0, 1] (write 95 % or 0.95)"
    rated = v.get("rated_output_torque")
    for name in ("max_output_torque", "emergency_stop_torque"):
        if _pos(v, "rated_output_torque", name) and v[name] < rated:
            yield name, f"must be >= rated_output_torque ({rated:.6g} N*m)"
    if _pos(v, "max_output_torque", "emergency_stop_torque") and v["emergency_stop_torque"] < v["max_output_torque"]:
        yield "emergency_stop_torque", f"must be >= max_output_torque ({v['max_output_torque']:.6g} N*m)"
    if _pos(v, "input_bore_min", "input_bore_max") and v["input_bore_min"] > v["input_bore_max"]:
        yield "input_bore_min", f"must be <= input_bore_max ({v['input_bore_max'] * 1e3:.6g} mm)"
    if _pos(v, "max_input_speed", "rated_input_speed") and v["max_input_speed"] < v["rated_input_speed"]:
        yield (
            "max_input_speed",
            f"must be >= rated_input_speed ({units.to_rpm(v['rated_input_speed']):.6g} rpm)",
        )
    if v.get("direction") is not None and v["direction"] not in (1, -1):
        yield "direction", "must be 1 (output turns like the input) or -1"
    if kind == "servo_gearbox":
        if _pos(v, "inertia_input") and not v["inertia_input"] < 0.1:
            yield "inertia_input", "is outside the plausible 0..0.1 kg*m^2 (unit slip?)"
        elif _pos(v, "inertia_input", "rated_output_torque") and not 1e-8 < v["inertia_input"] / rated < 1e-3:
            yield (
                "inertia_input",
                (
                    f"inertia_input / rated_output_torque = {v['inertia_input'] / rated:.2e} s^2 "
                    "is outside the plausible 1e-8..1e-3 s^2 (unit slip?)"
                ),
            )
        if v.get("stages") is not None and v["stages"] not in (1, 2, 3):
            yield "stages", "must be 1, 2 or 3"


def drive_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if _pos(v, "continuous_current", "peak_current") and v["peak_current"] < v["continuous_current"]:
        yield "peak_current", f"must be >= continuous_current ({v['continuous_current']:.6g} A)"


def curve_rules(v: Mapping[str, Any], kind: str) -> Iterator[tuple[str, str]]:
    if v.get("continuous_torque") is None and v.get("peak_torque") is None:
        yield "continuous_torque", "a curve point needs continuous_torque, peak_torque or both"
    if _pos(v, "continuous_torque", "peak_torque") and v["peak_torque"] < v["continuous_torque"]:
        yield "peak_torque", f"must be >= continuous_torque ({v['continuous_torque']:.6g} N*m)"


RULES: dict[str, Rule] = {
    "motor": motor_rules,
    "gearbox": gearbox_rules,
    "drive": drive_rules,
    "curve": curve_rules,
}
