"""The formulas a sizing uses, each with its source, so a reviewer can follow every number by hand.

Every entry names the function (or module) of drivetrain that implements it in ``ref`` and a
phrase of that docstring in ``cite``: the citation printed in the report is the one the code
carries (``tests/report/test_report.py`` checks that each ``cite`` is in the docstring of its ``ref``).

Equations use a small markup shared by the HTML and the PDF: ``X_{abc}`` or ``X_a`` is a
subscript; everything else (Greek letters, ², √, Σ) is plain Unicode.
"""

from __future__ import annotations

import html
import importlib
import inspect
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult


@dataclass(frozen=True)
class Formula:
    """One formula: its equations (markup), what the symbols mean, its source and implementation."""

    key: str
    title: str
    equations: tuple[str, ...]
    symbols: str
    source: str
    ref: str
    cite: str


_SUB = re.compile(r"_(\{[^{}]*\}|[A-Za-z0-9])")


def markup_html(text: str) -> str:
    """Escaped HTML of a markup equation, subscripts as ``<sub>``."""
    escaped = html.escape(text, quote=False)
    return _SUB.sub(lambda m: f"<sub>{m.group(1).strip('{}')}</sub>", escaped)


def markup_mathtext(text: str) -> str:
    """A matplotlib text string of a markup equation, subscripts as mathtext ``$_{...}$``."""
    escaped = text.replace("$", r"\$")
    return _SUB.sub(lambda m: "$_{\\mathregular{" + m.group(1).strip("{}") + "}}$", escaped)


def markup_plain(text: str) -> str:
    """The equation as plain text (subscripts keep their underscore, braces dropped)."""
    return _SUB.sub(lambda m: "_" + m.group(1).strip("{}"), text)


def docstring_of(ref: str) -> str:
    """The docstring of a dotted path: a module, or a function or class inside one."""
    parts = ref.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for name in parts[k:]:
            obj = getattr(obj, name)
        return inspect.getdoc(obj) or ""
    raise ImportError(ref)


F = Formula
_ALL: tuple[Formula, ...] = (
    # --- motion profile
    F("profile_trapezoid", "Trapezoidal move and movement amount",
      ("v_{max} = x_f / t_2,   a_{max} = x_f / (t_1 t_2)", "L = V (2 t_s − t_a − t_d) / 2"),
      "x_f distance, t_1 ramp time, t_2 time to the start of the decel ramp; V speed, t_s step time, "
      "t_a, t_d ramp times", "lecture, trapezoidal profile and \"Movement Amount\"",
      "drivetrain.motion.profiles", "movement amount"),
    F("profile_s_curve", "Jerk-limited (s-curve and time-optimal) moves",
      ("a_{max} = v / (t_r (1 − f/2)),   t_j = f t_r / 2",),
      "t_r ramp time, f jerk fraction of the ramp, t_j duration of each jerk piece",
      "L. Biagiotti, C. Melchiorri, Trajectory Planning for Automatic Machines and Robots, Springer 2008, "
      "sec. 3.4 (double S)", "drivetrain.motion.moves.s_curve_peak_accel", "Biagiotti"),
    F("profile_cam", "Cam laws (cycloidal, modified sine, modified trapezoid, 3-4-5 polynomial)",
      ("x(τ) = x_f · s(τ / T),   s from the law's normalised acceleration",),
      "T move time, s(u) normalised displacement of the law", "R. L. Norton, Cam Design and Manufacturing "
      "Handbook, 2nd ed., ch. 3", "drivetrain.motion.cams", "Norton"),
    # --- loads
    F("gravity_friction", "Gravity and dry friction on an incline",
      ("F_G = m g sin α,   F_N = m g cos α,   F_f = μ F_N sign(v)",),
      "m mass (net of a counterweight for gravity), α incline above horizontal, μ sliding (μ_{st} at "
      "breakaway) friction coefficient", "lecture, \"The causes for the motor load\", inclined plane, "
      "\"Friction (dry)\"", "drivetrain.physics.loads", "inclined-plane pages"),
    F("slip_limit", "Slip limit of a load on its carrier",
      ("a_{max} < μ_0 g cos α",), "μ_0 static friction of the load on the belt, α incline",
      "lecture, inclined plane", "drivetrain.physics.loads.slip_limit_acceleration", "Lecture, inclined plane"),
    # --- mechanisms
    F("ball_screw", "Ball screw / lead screw",
      ("T = F P_B / (2π η),   J_W = (M + M_C) (P_B / 2π)²",
       "F = (M − M_C) g sin θ + μ M g cos θ + F_{thrust}",
       "J_B = π ρ L_B D_B⁴ / 32"),
      "P_B lead, η screw efficiency, M load and M_C counterweight mass, θ incline, ρ density, L_B, D_B screw "
      "length and diameter", "lecture, \"Horizontal/Vertical Ball Screw Load\" (Yaskawa selection pages), "
      "ERRATA for the vertical case", "drivetrain.physics.mechanisms.screw", "Horizontal/Vertical Ball Screw Load"),
    F("lead_screw_efficiency", "Lead screw efficiency from its thread",
      ("η = tan λ / tan(λ + φ),   η_{back} = tan(λ − φ) / tan λ",
       "tan λ = l / (π d_m),   tan φ = μ   (η_{back} ≤ 0: self-locking)"),
      "λ lead angle, φ friction angle, l lead, d_m mean diameter",
      "Shigley's Mechanical Engineering Design, power screws",
      "drivetrain.physics.mechanisms.screw.lead_screw_efficiency", "Shigley"),
    F("belt", "Belt axis (timing belt, conveyor)",
      ("T = (μ M g + F) D / (2 η)",
       "J_1 = (m_L + m_{CB} + m_{belt}) r² + J_{IP} (r / r_{IP})² + J_{DnP} (r / r_{DnP})²,   J = J_{DP} + J_1"),
      "D, r drive pulley diameter and radius; J_{DP}, J_{IP}, J_{DnP} drive, idler and driven pulley inertias",
      "lecture, ServoSoft \"belt with idlers\" and \"counterbalanced belt\" pages; Yaskawa timing-belt page",
      "drivetrain.axis.mechanisms.belt", "belt with idlers"),
    F("rack_pinion", "Rack and pinion",
      ("T = (μ M g + F) D / (2 η),   J_W = M (D / 2)²,   J_P = π ρ t D⁴ / 32",),
      "D pinion pitch diameter, t pinion thickness", "lecture, \"Rack & Pinion Load\" (Yaskawa page), ERRATA "
      "for the speed", "drivetrain.axis.mechanisms.rack", "Rack & Pinion Load"),
    F("roll", "Feed roll",
      ("T = (μ P + F) D / (2 η),   J_R = π ρ L D⁴ / 32",),
      "P nip (pressing) force, F web tension, D roll diameter, L roll length", "lecture, \"Roll Load\" "
      "(Yaskawa page)", "drivetrain.axis.mechanisms.roll", "Roll Load"),
    F("rotary", "Rotary table with an unbalanced mass",
      ("J_1 = J_{disc} + J_{load} + M r²", "T = J_1 α + T_{thrust} + M g r sin(φ + β) sin θ"),
      "M unbalanced mass at radius r and angle β, φ table angle, θ inclination of the table axis",
      "lecture, \"Disk Load\" (Yaskawa page) and ServoSoft \"Unbalanced Load\"",
      "drivetrain.axis.mechanisms.rotary", "Unbalanced Load"),
    F("hoist", "Hoist drum with counterweight",
      ("T = (M_1 + M_2) r² dω/dt + (M_1 − M_2) g r",),
      "M_1 load, M_2 counterweight, r drum radius", "lecture, M1/M2 pulley",
      "drivetrain.axis.mechanisms.hoist", "M1/M2 pulley"),
    F("chain", "Chain loop",
      ("J_1 = n_{PR} J_{PR} (r_{DR} / r_{PR})² + m_{Loop} r_{DR}²",
       "T = n_{DR} J_{DR} α + Q (J_1 α + (m_{Loop} g ± F_{thrust}) r_{DR})"),
      "DR drive and PR passive sprockets, Q = 1/η motoring, η braking", "lecture, ServoSoft chain-loop page",
      "drivetrain.physics.mechanisms.chain", "ServoSoft chain-loop page"),
    F("custom", "Custom rotary load", ("T = J α + T_L",), "J inertia, T_L load torque",
      "lecture, equation of motion", "drivetrain.axis.mechanisms.custom.CustomSpec", "T = J alpha + T_L"),
    F("cylinder_inertia", "Inertia of a cylindrical part",
      ("J = π ρ L (D_o⁴ − D_i⁴) / 32 = M (D_o² + D_i²) / 8",),
      "ρ density, L length, D_o, D_i outer and inner diameter", "lecture, solid and hollow cylinder pages "
      "(ERRATA: plus sign in the mass form)", "drivetrain.physics.inertia.cylinder_from_density",
      "roll and ball screw pages"),
    # --- transmission
    F("gear_stage", "Gear stage (gearbox, gear pair)",
      ("T_1 = T_2 / (n η),   J_2' = J_2 / n²",),
      "n ratio input/output, η efficiency (worm 50–80 %, self-locking at high ratio)",
      "lecture, \"Gear system-motor connections\"", "drivetrain.physics.transmission", "Gear system-motor connections"),
    F("belt_stage", "Belt or chain stage", ("i = D_L / D_m = N_{load} / N_{motor}",),
      "D pulley diameters, N teeth; chains about 80 % efficient", "lecture, belt-pulley systems",
      "drivetrain.physics.transmission", "Ratio = D_L / D_m"),
    F("harmonic", "Harmonic drive ratio", ("GR = FS / (CS − FS)",),
      "FS flexspline teeth, CS circular spline teeth (circular spline fixed)", "lecture, harmonic drive",
      "drivetrain.physics.transmission.harmonic_ratio", "GR = FS / (CS - FS)"),
    # --- reflection to the motor shaft
    F("reflect", "Reflected inertia", ("J' = J / i²,   linear load: J = M r²",),
      "i ratio (input/output speed), r lever arm (lead / 2π or pulley radius)",
      "lecture, \"Energy Equivalence Principle\" (gear system-motor connections)",
      "drivetrain.physics.stage.reflect_inertia", "Energy Equivalence Principle"),
    F("chain_inertia", "Load inertia at the motor shaft",
      ("J_L = Σ_k J_k / (i_1 i_2 ⋯ i_{k−1})²",),
      "J_k all inertia of element k at its own input, i the ratios of the elements between it and the motor",
      "lecture, J_total = J_m + J_L / N², applied stage by stage", "drivetrain.physics.stage.chain_inertia",
      "J_total = J_m + J_L / N^2"),
    F("four_quadrant", "Torque through a lossy element (four quadrants)",
      ("T_{in} = J_{in} α + (J_{inside} α + T_{out} / i) / η   when power flows to the load",
       "T_{in} = J_{in} α + (J_{inside} α + T_{out} / i) · η_{back}   when the load drives back"),
      "J_{in} inertia outside the element's losses, J_{inside} inside them; a dwell holds as if motoring "
      "unless the element self-locks (η_{back} ≤ 0)", "lecture, ServoSoft four-quadrant pages; docs/conventions.md",
      "drivetrain.physics.stage.torque_in", "ServoSoft quadrant pages"),
    F("load_torque_only", "Losses on the load torque only (vendor selection guides)",
      ("T_{in} = T_{ext} / (i η) + (J_{inside} α + T_{inertial} / i) + J_{in} α",),
      "only the external load torque passes through the efficiency", "vendor selection guides, e.g. Yaskawa "
      "T_L = (9.8 μ M + F) P_B / (2π R η)", "drivetrain.physics.stage.torque_in", "Yaskawa"),
    # --- duty cycle metrics
    F("motor_torque", "Motor torque with the rotor", ("T_M = T + J_M α",),
      "T load torque at the motor shaft, J_M rotor inertia, α motor acceleration",
      "lecture, equation of motion T = J α + T_L", "drivetrain.duty.cycle", "rotor adds J_M alpha"),
    F("rms", "RMS torque over the cycle", ("T_{rms} = √(Σ T_k² t_k / t_c)",),
      "over the whole cycle t_c, dwells included (holding torque counts unless braked)",
      "lecture, Torque Effective Value (Yaskawa); ERRATA", "drivetrain.physics.averages.rms", "Torque Effective Value"),
    F("power_energy", "Peak power and regenerated energy",
      ("P_{peak} = max |T ω|,   E_{regen} = ∫ max(0, −T ω) dt over one cycle",),
      "mechanical, at the motor shaft, before motor and drive losses; integrals with Simpson weights per phase",
      "docs/conventions.md, The JSON result", "drivetrain.duty.cycle", "quadrature weights"),
    F("accel_times", "Shortest acceleration and deceleration times",
      ("t_{am} = 2π N_M (J_M + J_L) / (60 (T_{PM} − T_L))",
       "t_{dm} = 2π N_M (J_M + J_L) / (60 (T_{PM} + T_L))"),
      "N_M speed [rpm], T_{PM} motor peak torque, T_L run torque", "lecture (Yaskawa selection pages); ERRATA",
      "drivetrain.physics.acceleration.minimum_accel_time", "t_am = 2 pi N_M (J_M + J_L) / (60 (T_PM - T_L))"),
    F("powers", "Load operation and acceleration power",
      ("P_o = 2π N_M T_L / 60,   P_a = (2π N_M / 60)² J_L / t_a",), "t_a acceleration time",
      "lecture, Load Operation Power and Load Acceleration Power", "drivetrain.physics.acceleration.acceleration_power",
      "Load Acceleration Power"),
    # --- checks
    F("check_peak", "Peak torque check",
      ("|T_M(t)| · f_T ≤ T_i(|n(t)|)",),
      "f_T torque margin factor, T_i intermittent envelope at the speed where the torque occurs",
      "drivetrain checks (intermittent envelope at the speed of each sample)", "drivetrain.sizing.motor_fit.fit_motors",
      "intermittent envelope"),
    F("check_rms", "RMS torque check", ("T_{rms} · f_{rms} ≤ T_c(n_{mean}),   n_{mean} = (1/t_c) ∫ |n| dt",),
      "T_c continuous (S1) envelope", "lecture, Torque Effective Value", "drivetrain.sizing.motor_fit.fit_motors",
      "continuous torque at the mean speed"),
    F("check_speed", "Speed check", ("n_{max} · f_n ≤ n_{max,motor}",), "f_n speed margin factor",
      "motor datasheet maximum speed", "drivetrain.sizing.motor_fit.fit_motors", "max speed"),
    F("check_inertia", "Inertia ratio", ("J_L / J_M ≤ limit",),
      "the lecture recommends below 5:1, 1:1 ideal", "lecture, inertia ratio", "drivetrain.sizing.motor_fit.fit_motors",
      "recommends below 5:1"),
    F("gearbox_t2b", "Gearbox ratings: T2B, n1max, n1N, mechanical fit",
      ("max|T_{out}| · f_T · f_s ≤ T_{2B},   n_{1,max} · f_n ≤ n_{1max},   n_{1,mean} ≤ n_{1N},   "
       "d_{shaft} ≤ d_{bore}",),
      "T_out the torque at the gearbox output over the cycle (the rotor's own acceleration torque never passes "
      "it); f_s the vendor's shock factor above 1000 cycles/h; a rating the catalog lacks leaves its check "
      "unknown", "WITTENSTEIN glossary (T2B, clamping hub); Beckhoff AG2400 TP+ data (T2B, n1N, n1Max)",
      "drivetrain.sizing.checks.gearbox_ratings", "WITTENSTEIN"),
    F("gearbox_rated", "Gearbox rated torque check",
      ("T_{av} = ∛(Σ n_i t_i |T_i|³ / Σ n_i t_i),   T_{av} · f_T ≤ T_{rated,out}",),
      "speed-weighted cubic mean of the output torque over the cycle; standstill carries no weight",
      "Harmonic Drive / strain-wave gear selection (average load torque)", "drivetrain.physics.averages.cubic_mean",
      "Harmonic Drive"),
    F("gearbox_peak", "Gearbox emergency-stop torque check",
      ("T_{GR} = (1 − k)(T_M − T_L) + T_L,   k = J_M / (J_M + J_{LR}),   T_{GR} i η ≤ T_{2NOT}",),
      "torque through the gearbox when the motor gives its peak torque T_M (an emergency stop); T_L static load "
      "torque, J_{LR} reflected load inertia; compared with the gearbox's emergency-stop torque, never used as "
      "the cyclic peak",
      "lecture, Dynamic Loading and Gearbox Sizing", "drivetrain.physics.torque_split.gearbox_peak_torque",
      "lecture, gearbox sizing"),
    F("min_rms_ratio", "Ratio of least RMS torque",
      ("T_M(i) = T / i + J_M α i,   i_{opt}^4 = Σ T² Δt / (J_M² Σ α² Δt)",),
      "T, α load torque and acceleration at the gearbox output, through an ideal gearbox of ratio i; the mean "
      "square torque is convex in i², least where its derivative vanishes; clamped to the motor's speed",
      "drivetrain selection (closed-form optimum of the lecture's RMS torque)",
      "drivetrain.sizing.selection.optimal_ratio",
      "the ratio minimising RMS torque"),
    F("guide", "Moments on a linear guide carriage",
      ("M_p = F_x (l_z + d_p),   M_r = F_z l_y,   M_y = F_x l_y",),
      "F_x force along the travel (inertial and process), F_z weight, l offsets of the load's centre of mass, "
      "d_p, d_r guide dimensions; each peak against the guide's rating", "lecture, linear actuators",
      "drivetrain.axis.model.GuideSpec", "M_p = F_x (l_z + d_p)"),
    F("envelope_continuous", "Continuous (S1) envelope, derived from ratings",
      ("T_c = T_0 + (T_N − T_0) ω / ω_N   (ω ≤ ω_N),   T_c = T_N ω_N / ω   (ω_N < ω ≤ ω_{max})",),
      "T_0 stall, T_N rated torque at rated speed ω_N; approximate when no vendor curve is given",
      "approximation of the typical AC servo T-n characteristic (Yaskawa Sigma-7 ratings, Siemens 1FT7 "
      "configuration manual), docs/checks.md", "drivetrain.sizing.envelope.continuous_torque", "Yaskawa Sigma-7"),
    F("envelope_intermittent", "Intermittent envelope, derived from ratings",
      ("T_i = T_{max}   (ω ≤ ω_N),   then linear to T_c(ω_{max}) at ω_{max},   never below T_c",),
      "T_{max} peak torque; approximate when no vendor curve is given",
      "approximation of the typical AC servo T-n characteristic (Yaskawa Sigma-7, Siemens 1FT7)",
      "drivetrain.sizing.envelope.intermittent_torque", "Siemens 1FT7"),
    F("optimal_ratio", "Inertia-matching ratio",
      ("i* = √(J_L / J_M),   i_{limit} = √(J_L / (limit · J_M))",),
      "ratio of an added reduction at the motor that makes J_L / i² equal J_M (purely inertial load: "
      "fastest acceleration), or reaches the inertia-ratio limit",
      "lecture, 1:1 ideal inertia match; machinemfg.com servo sizing, case one",
      "drivetrain.sizing.result.optimal_ratio_pure_inertia", "1:1 ideal inertia match"),
)
FORMULAS: dict[str, Formula] = {f.key: f for f in _ALL}
"""Every formula the report can cite, by key."""

_MECHANISM_FORMULAS: dict[str, tuple[str, ...]] = {
    "ball_screw": ("ball_screw", "cylinder_inertia"),
    "lead_screw": ("ball_screw", "lead_screw_efficiency", "cylinder_inertia"),
    "belt": ("belt",),
    "timing_belt": ("belt",),
    "conveyor": ("belt", "slip_limit"),
    "rack_pinion": ("rack_pinion", "cylinder_inertia"),
    "roll": ("roll", "cylinder_inertia"),
    "rotary": ("rotary", "cylinder_inertia"),
    "hoist": ("hoist",),
    "chain": ("chain",),
    "custom": ("custom",),
}


def formulas_for(result: SizingResult, catalog_gearbox: bool = False) -> list[Formula]:
    """The formulas this sizing used, in the order a reviewer follows the numbers.

    ``catalog_gearbox``: the report's motor sits behind a gearbox the selection chose.
    """
    axis = result.axis
    keys: list[str] = []
    shapes = {s.shape for s in axis.cycle().steps} if axis.spec.profile else set()
    if shapes & {"trapezoid", "triangle"}:
        keys.append("profile_trapezoid")
    if shapes & {"s_curve", "time_optimal"}:
        keys.append("profile_s_curve")
    if shapes - {"trapezoid", "triangle", "s_curve", "time_optimal", "dwell"}:
        keys.append("profile_cam")
    if axis.mechanism.motion == "linear":
        keys.append("gravity_friction")
    keys += _MECHANISM_FORMULAS.get(axis.mechanism.type, ())
    kinds = {s.kind for s in axis.transmission}
    if catalog_gearbox or kinds & {"gearbox", "gear_pair"}:
        keys.append("gear_stage")
    if kinds & {"belt", "chain"}:
        keys.append("belt_stage")
    if any(t.get("flexspline_teeth") for t in axis.raw.get("transmission", []) if isinstance(t, dict)):
        keys.append("harmonic")
    keys += ["reflect", "chain_inertia"]
    keys.append("load_torque_only" if axis.efficiency_model == "load_torque_only" else "four_quadrant")
    motor = axis.motor is not None or bool(result.candidates)
    if motor:
        keys.append("motor_torque")
    keys += ["rms", "power_energy"]
    if motor:
        keys += ["check_peak", "check_rms", "check_speed", "check_inertia", "envelope_continuous",
                 "envelope_intermittent"]
    if catalog_gearbox or any(c.gearbox for c in result.candidates):
        keys += ["gearbox_t2b", "gearbox_rated", "gearbox_peak"]
    if axis.motor is not None:
        keys += ["accel_times", "powers"]
    if motor:
        keys.append("optimal_ratio")
    if result.selection is not None and result.selection.optimal_ratio is not None:
        keys.append("min_rms_ratio")
    if result.slip_check is not None:
        keys.append("slip_limit")
    if result.guide is not None:
        keys.append("guide")
    return [FORMULAS[k] for k in dict.fromkeys(keys)]
