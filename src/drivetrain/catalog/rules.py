"""Plausibility rules of catalog rows, mirroring the shipped data's own checks (check_catalog.py,
data/SOURCES.md): a kg*cm^2 figure read as kg*m^2, a rated power that disagrees with torque x speed.

Each rule yields (field, rule); a rule fires only when the values it needs are given and positive.
"""

from __future__ import annotations

import itertools
import math
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


# ---------------------------------------------------------------------------------- consistency
# The rules of ``catalog check`` that a single row can be judged on (catalog.check adds the ones that
# need other rows: drive pairings and voltage classes); ``catalog import`` refuses a row that breaks
# one. Each yields (rule id, field, what is wrong); docs/catalog.md, "Consistency check", lists them.

KT_RATED_BAND = (0.95, 1.25)
"""Allowed K_t x I / T at the rated and at the stall point. Vendors print K_t at 20 degC (Yaskawa) or hot
(Siemens, 100 K) and the torques with a hot winding, so K_t x I exceeds T by up to about 15 % in the
shipped vendor tables (Yaskawa SGM7: 1.04 to 1.14, Mitsubishi HC: up to 1.22); 5 % below 1 is rounding."""
KT_PEAK_BAND = (0.95, 1.5)
"""Allowed K_t x I_max / T_max: iron saturation makes the peak torque fall short of K_t x I_max (1.34 in
the shipped tables: Mitsubishi HC103R), never exceed it beyond rounding."""
KT_KE_BAND = (0.85, 1.05)
"""Allowed K_t / (sqrt(3) k_E,LL,rms): the printed hot K_t lies a few per cent below the ideal cold value
(Siemens 1FT7044-5AK7: 0.933, catalog.derive)."""
MASS_PER_FLANGE3 = (1252.0, 16841.0)
"""[kg/m^3] band of motor mass / flange^3: half the smallest and twice the largest value of the shipped
traced rows that give both (2,503 SGM7G-09A to 8,421 SGM7A-70A, 20 rows); catches a unit slip (g, lb)."""
INERTIA_PER_FLANGE5 = (4.7, 411.0)
"""[kg/m^3] band of rotor inertia / flange^5: a quarter of the smallest and four times the largest value
of the shipped traced rows (18.9 SGM7A-30A to 102.9 SGM7J-06A, 20 rows; flat and long motors of one
flange differ by about four); catches kg*cm^2 read as kg*m^2 (a factor 10^4)."""


Finding = tuple[str, str, str]


def _ratio_rule(v: Mapping[str, Any], rule: str, torque: str, current: str, band: tuple[float, float]
                ) -> Iterator[Finding]:
    derived = set(str(v.get("derived") or "").split(","))
    if not _pos(v, "torque_constant", torque, current) or derived & {"torque_constant", torque}:
        return  # a value computed from the other two agrees by construction
    ratio = v["torque_constant"] * v[current] / v[torque]
    if not band[0] <= ratio <= band[1]:
        yield (rule, torque, f"torque_constant x {current} / {torque} = {ratio:.3g} is outside {band[0]:g}.."
                             f"{band[1]:g} (check the units and the rms/peak basis of k_T and the current)")


def motor_consistency(v: Mapping[str, Any], kind: str) -> Iterator[Finding]:
    """Consistency rules of one motor row (field names as keys, SI)."""
    if _pos(v, "rated_torque", "peak_torque") and v["peak_torque"] < v["rated_torque"]:
        yield "rated_le_peak", "peak_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if kind != "ac_servo":
        return
    if _pos(v, "rated_torque", "stall_torque") and v["stall_torque"] < v["rated_torque"] * (1 - 1e-6):
        yield "rated_le_stall", "stall_torque", f"must be >= rated_torque ({v['rated_torque']:.6g} N*m)"
    if _pos(v, "rated_speed", "max_speed") and v["max_speed"] < v["rated_speed"]:
        yield "rated_speed_le_max", "max_speed", f"must be >= rated_speed ({units.to_rpm(v['rated_speed']):.6g} rpm)"
    yield from _ratio_rule(v, "kt_rated_current", "rated_torque", "rated_current", KT_RATED_BAND)
    yield from _ratio_rule(v, "kt_stall_current", "stall_torque", "stall_current", KT_RATED_BAND)
    yield from _ratio_rule(v, "kt_peak_current", "peak_torque", "peak_current", KT_PEAK_BAND)
    derived = set(str(v.get("derived") or "").split(","))
    if _pos(v, "torque_constant", "back_emf") and "torque_constant" not in derived:
        from drivetrain.catalog.derive import kt_from_back_emf

        basis = str(v.get("back_emf_basis") or "ll_rms")
        ideal = kt_from_back_emf(v["back_emf"], basis)
        ratio = v["torque_constant"] / ideal
        if not KT_KE_BAND[0] <= ratio <= KT_KE_BAND[1]:
            yield ("kt_ke", "torque_constant",
                   f"torque_constant / (sqrt(3) k_E,LL,rms) = {ratio:.3g} with back_emf on basis {basis} is outside "
                   f"{KT_KE_BAND[0]:g}..{KT_KE_BAND[1]:g} (check the back-EMF basis: line-to-line or phase, rms or "
                   "peak)")
    f = float(v.get("flange") or math.nan)
    if _pos(v, "flange", "mass") and not MASS_PER_FLANGE3[0] <= v["mass"] / f**3 <= MASS_PER_FLANGE3[1]:
        yield ("mass_for_flange", "mass", f"mass / flange^3 = {v['mass'] / f**3:.4g} kg/m^3 is outside the "
                                          f"{MASS_PER_FLANGE3[0]:g}..{MASS_PER_FLANGE3[1]:g} of the traced rows")
    if _pos(v, "flange", "rotor_inertia") and not (
            INERTIA_PER_FLANGE5[0] <= v["rotor_inertia"] / f**5 <= INERTIA_PER_FLANGE5[1]):
        yield ("inertia_for_flange", "rotor_inertia",
               f"rotor_inertia / flange^5 = {v['rotor_inertia'] / f**5:.4g} kg/m^3 is outside the "
               f"{INERTIA_PER_FLANGE5[0]:g}..{INERTIA_PER_FLANGE5[1]:g} of the traced rows (unit slip?)")
    sizes = [(n, v[n]) for n in ("shaft_diameter", "pilot_diameter", "flange") if _pos(v, n)]
    for (a, x), (b, y) in itertools.pairwise(sizes):
        if not x < y:
            yield "shaft_pilot_flange", a, f"must be < {b} ({y * 1e3:.6g} mm): shaft < pilot < flange"


def gearbox_consistency(v: Mapping[str, Any], kind: str) -> Iterator[Finding]:
    """T2N <= T2B <= T2NOT and n1N <= n1max of one gearbox row."""
    order = [(n, v[n]) for n in ("rated_output_torque", "max_output_torque", "emergency_stop_torque") if _pos(v, n)]
    for (a, x), (b, y) in itertools.pairwise(order):
        if y < x:
            yield "torque_order", b, f"must be >= {a} ({x:.6g} N*m): T2N <= T2B <= T2NOT"
    if _pos(v, "max_input_speed", "rated_input_speed") and v["max_input_speed"] < v["rated_input_speed"]:
        yield ("input_speed_order", "max_input_speed",
               f"must be >= rated_input_speed ({units.to_rpm(v['rated_input_speed']):.6g} rpm): n1N <= n1max")


def drive_consistency(v: Mapping[str, Any], kind: str) -> Iterator[Finding]:
    if _pos(v, "continuous_current", "peak_current") and v["peak_current"] < v["continuous_current"]:
        yield "continuous_le_peak", "peak_current", f"must be >= continuous_current ({v['continuous_current']:.6g} A)"


def curve_consistency(v: Mapping[str, Any], kind: str) -> Iterator[Finding]:
    if _pos(v, "continuous_torque", "peak_torque") and v["peak_torque"] < v["continuous_torque"]:
        yield "continuous_le_peak", "peak_torque", f"must be >= continuous_torque ({v['continuous_torque']:.6g} N*m)"


CONSISTENCY: dict[str, Callable[[Mapping[str, Any], str], Iterator[Finding]]] = {
    "motor": motor_consistency,
    "gearbox": gearbox_consistency,
    "drive": drive_consistency,
    "curve": curve_consistency,
}
