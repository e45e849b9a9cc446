"""The report's tables of one sizing result (inertia, profile steps, demand, phases, motor data,
candidates, ratios, inputs), its headline figures and its subtitle.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.report.blocks import Cell, KeyFigure, Table
from drivetrain.report.checks import CHECK_NAMES, failure_sentence, speed_si
from drivetrain.report.diagram import MECHANISM_NAMES, is_load_part
from drivetrain.report.display import (
    DisplayUnits,
    fmt_number,
    fmt_percent,
    leaves,
    pretty_powers,
    pretty_unit,
    quantity_of,
    snapped_metrics,
)
from drivetrain.report.focus import Focus
from drivetrain.units import quantity_of_key

if TYPE_CHECKING:
    from drivetrain.sizing.answer import CheckRow
    from drivetrain.sizing.result import SizingResult

MAX_CANDIDATE_ROWS = 25


def _extra_values(result: SizingResult, du: DisplayUnits) -> list[tuple[str, str]]:
    """The guide's peak forces and moments and a gantry share's load share, labelled and in display units."""
    rows: list[tuple[str, str]] = []

    def add(label: str, key: str, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            if isinstance(value, str):
                rows.append((f"{label}{key.replace('_', ' ')}", value))
            return
        named = quantity_of_key(key)
        if named is not None:
            rows.append((f"{label}{named[0].replace('_', ' ')}", du.fmt(float(value), named[1])))
            return
        rows.append((f"{label}{key.replace('_', ' ')}", fmt_number(float(value))))

    if result.guide is not None:  # its forces and moments; its checks are the checks table's
        for sub, v in result.guide.to_dict().items():
            add("guide: ", sub, v)
    if result.load_share is not None:
        add("", "load_share", result.load_share)
    return rows


def key_figures(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> list[KeyFigure]:
    m = result.metrics.to_dict()
    src = focus.metrics if focus is not None else m
    where = f"{focus.motor.name}, with rotor" if focus is not None else "at motor shaft, rotor excluded"
    figs = [
        KeyFigure("Peak torque", du.fmt(src["peak_torque_Nm"], "torque"), where),
        KeyFigure("RMS torque", du.fmt(src["rms_torque_Nm"], "torque"), where),
        KeyFigure("Max motor speed", du.fmt(speed_si(src["max_speed_rpm"]), "angular_speed"),
                  f"mean {du.fmt(speed_si(src['mean_speed_rpm']), 'angular_speed')}"),
        KeyFigure("Load inertia", du.fmt(focus.load_inertia if focus is not None else m["load_inertia_kgm2"],
                                         "inertia"), "at motor shaft"),
    ]
    if focus is not None:
        figs.append(KeyFigure("Inertia ratio", f"{fmt_number(focus.inertia_ratio, 3)} : 1", "J_L / J_M"))
    figs += [
        KeyFigure("Peak power", du.fmt(src["peak_power_W"], "power"), "mechanical, motor shaft"),
        KeyFigure("Regenerated energy", du.fmt(src["regen_energy_J"] + 0.0, "energy"), "per cycle"),
        KeyFigure("Cycle time", du.fmt(m["cycle_time_s"], "time"), _plural(_moves(result), "move")),
    ]
    return figs


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _moves(result: SizingResult) -> int:
    return sum(1 for s in result.duty.cycle.steps if s.kind == "move")


def inertia_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table:
    axis = result.axis
    j = "inertia"
    total = focus.load_inertia if focus is not None else result.duty.load_inertia
    rows: list[list[Cell]] = []

    def row(element: str, part: str, at_input: float, factor: float, ratio_text: str) -> None:
        at_motor = at_input * factor
        share = at_motor / total if total > 0 else 0.0
        rows.append([Cell(element), Cell(part), Cell(du.fmt(at_input, j)), Cell(ratio_text),
                     Cell(du.fmt(at_motor, j)), Cell(f"{share * 100:.1f} %")])

    up = 1.0
    if focus is not None and focus.gearbox is not None:
        row(f"gearbox {focus.gearbox.id} (catalog)", "input inertia", focus.gearbox.inertia, 1.0, "1")
        up = focus.gearbox.ratio
    for st in axis.transmission:
        if st.inertia_in:
            row(st.name, "own, outside its losses", st.inertia_in, 1.0 / up**2, fmt_number(up))
        if st.inertia_inside:
            row(st.name, "driven side, inside its losses", st.inertia_inside, 1.0 / up**2, fmt_number(up))
        if not st.inertia:
            row(st.name, "—", 0.0, 1.0 / up**2, fmt_number(up))
        up *= st.ratio
    mech = axis.mechanism
    name = MECHANISM_NAMES.get(mech.type, mech.type)
    parts = mech.inertia_parts or {"mechanism": mech.stage.inertia}
    for part, value in parts.items():
        row("load" if is_load_part(part) else name, pretty_powers(part), value, 1.0 / up**2, fmt_number(up))
    rest = mech.stage.inertia - sum(parts.values())
    if abs(rest) > 1e-12 * max(1.0, mech.stage.inertia):
        row(name, "other", rest, 1.0 / up**2, fmt_number(up))
    if axis.spec.extra_inertia:
        row("extra inertia", "at motor shaft", axis.spec.extra_inertia, 1.0, "1")
    rows.append([Cell("Total load inertia at the motor shaft", "strong"), Cell(""), Cell(""), Cell(""),
                 Cell(du.fmt(total, j), "strong"), Cell("100 %", "strong")])
    if focus is not None:
        rows.append([Cell(f"Motor rotor J_M ({focus.motor.name})"), Cell(""), Cell(""), Cell(""),
                     Cell(du.fmt(focus.motor.inertia, j)),
                     Cell(f"J_L/J_M = {fmt_number(focus.inertia_ratio, 3)}", "strong")])
    note = ("Each part's inertia at its own input, divided by the square of the ratio between it and the motor "
            "(J / i²). A linear mechanism's ratio is the motor angle per load travel, 1 / lever arm [rad/m].")
    return Table("inertia", "Reflected inertia per element",
                 ["element", "part", "J at its input", "ratio to motor", "J at motor shaft", "share"], rows,
                 "llrrrr", note, [0.2, 0.27, 0.15, 0.12, 0.15, 0.11])


def steps_table(result: SizingResult, du: DisplayUnits) -> Table:
    linear = result.axis.mechanism.motion == "linear"
    qd, qv, qa, qj = ("length", "speed", "acceleration", "jerk") if linear else (
        "angle", "angular_speed", "angular_acceleration", "angular_jerk")
    rows = []
    for s in result.duty.cycle.steps:
        if s.kind == "dwell":
            rows.append([Cell(str(s.index + 1)), Cell("dwell"), Cell(f"holding: {s.holding or 'motor'}"),
                         Cell("—"), Cell(du.fmt(s.duration, "time")), Cell("—"), Cell("—"), Cell("—"), Cell("—")])
            continue
        ramps = f"{fmt_number(s.t_accel)} / {fmt_number(s.t_decel)} s"
        accel = du.num(s.peak_accel, qa)
        if not math.isclose(s.peak_accel, s.peak_decel):
            accel += f" / {du.num(s.peak_decel, qa)}"
        rows.append([Cell(str(s.index + 1)), Cell("move"), Cell(s.shape.replace("_", " ")),
                     Cell(du.fmt(s.distance * s.direction if s.distance > 0 else s.distance, qd)),
                     Cell(du.fmt(s.duration, "time")), Cell(ramps), Cell(du.fmt(s.peak_speed, qv)),
                     Cell(f"{accel} {du.label(qa)}"), Cell(du.fmt(s.peak_jerk, qj) if s.peak_jerk else "—")])
    return Table("steps", "Profile steps (load side)",
                 ["step", "kind", "shape", "distance", "time", "accel / decel", "peak speed", "peak accel",
                  "peak jerk"], rows, "lllrrrrrr", "A trapezoid's jerk is impulsive at its corners (shown as —).",
                 [0.06, 0.08, 0.14, 0.12, 0.09, 0.13, 0.12, 0.14, 0.12])


def demand_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table:
    m = snapped_metrics(result.metrics.to_dict())
    mo = snapped_metrics(focus.metrics) if focus is not None else None
    rows: list[list[Cell]] = []

    def row(label: str, key: str, q: str, signed: bool = False) -> None:
        load = du.fmt(m[key], q, signed=signed) if m.get(key) is not None else "—"
        motor = du.fmt(mo[key], q, signed=signed) if mo is not None and mo.get(key) is not None else "—"
        rows.append([Cell(label), Cell(load), Cell(motor)] if mo is not None else [Cell(label), Cell(load)])

    def speed_row(label: str, key: str) -> None:
        load = du.fmt(speed_si(m[key]), "angular_speed")
        motor = du.fmt(speed_si(mo[key]), "angular_speed") if mo is not None and mo.get(key) is not None else "—"
        rows.append([Cell(label), Cell(load), Cell(motor)] if mo is not None else [Cell(label), Cell(load)])

    row("Peak torque |T|", "peak_torque_Nm", "torque")
    row("RMS torque (whole cycle)", "rms_torque_Nm", "torque")
    row("Acceleration torque, move 1", "accel_torque_Nm", "torque", True)
    row("Run torque, move 1", "run_torque_Nm", "torque", True)
    row("Deceleration torque, move 1", "decel_torque_Nm", "torque", True)
    row("Holding torque (dwell, not braked)", "holding_torque_Nm", "torque", True)
    speed_row("Maximum speed", "max_speed_rpm")
    speed_row("Mean speed |n|", "mean_speed_rpm")
    speed_row("Speed at peak torque", "peak_torque_speed_rpm")
    row("Peak power |T ω|", "peak_power_W", "power")
    row("Average power", "average_power_W", "power")
    row("Regenerated energy per cycle", "regen_energy_J", "energy")
    extra: list[tuple[str, str, str]] = [
        ("Load inertia at the shaft J_L", du.fmt(m["load_inertia_kgm2"], "inertia"),
         du.fmt(focus.load_inertia, "inertia") if focus is not None else ""),
        ("Cycle time t_c", du.fmt(m["cycle_time_s"], "time"), ""),
    ]
    if focus is not None:
        extra.append(("Inertia ratio J_L / J_M", "", fmt_number(focus.inertia_ratio, 3)))
        for label, key, q in (("Shortest accel time t_am at n_max", "min_accel_time_s", "time"),
                              ("Shortest decel time t_dm at n_max", "min_decel_time_s", "time"),
                              ("Load operation power P_o", "operation_power_W", "power"),
                              ("Load acceleration power P_a", "acceleration_power_W", "power")):
            if focus.metrics.get(key) is not None:
                extra.append((label, "", du.fmt(focus.metrics[key], q)))
    slip = result.axis.mechanism.slip_limit
    if slip is not None and result.slip_check is None:
        a_max = float(np.max(np.abs(result.duty.samples.a)))
        extra.append(("Slip limit of the load a_max", f"{du.fmt(slip, 'acceleration')} (profile "
                      f"{du.fmt(a_max, 'acceleration')}{': SLIPS' if a_max > slip else ''})", ""))
    extra += [(label, value, "") for label, value in _extra_values(result, du)]
    for label, load, motor in extra:
        rows.append([Cell(label), Cell(load), Cell(motor)] if mo is not None else [Cell(label), Cell(load)])
    if focus is not None:
        via = f" via {focus.gearbox.id}" if focus.gearbox is not None else ""
        cols = ["quantity", "axis input, no motor", f"motor {focus.motor.name}{via}, with rotor"]
    else:
        cols = ["quantity", "at the motor shaft, no motor"]
    return Table("demand", "Demand at the motor shaft", cols, rows, "lrr" if mo is not None else "lr",
                 "Signed values: positive in the direction of positive motion. Peak and RMS are magnitudes; RMS "
                 "over the whole repeating cycle, dwells included (braked dwells carry no torque).",
                 [0.4, 0.27, 0.33] if mo is not None else [0.6, 0.4])


def segments_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table:
    seg = result.metrics.segments
    mseg = focus.metrics.get("segments", []) if focus is not None else []
    rows = []
    for k, s in enumerate(seg):
        move = "—" if s.get("move") is None else str(int(s["move"]) + 1)
        row = [Cell(str(k + 1)), Cell(move), Cell(s["kind"]), Cell(fmt_number(s["t0_s"])), Cell(fmt_number(s["t1_s"])),
               Cell(fmt_number(s["t1_s"] - s["t0_s"])), Cell(du.fmt(speed_si(s["speed_rpm"]), "angular_speed")),
               Cell(du.fmt(s["torque_Nm"], "torque", signed=True))]
        if focus is not None:
            row.append(Cell(du.fmt(speed_si(mseg[k]["speed_rpm"]), "angular_speed") if k < len(mseg) else "—"))
            row.append(Cell(du.fmt(mseg[k]["torque_Nm"], "torque", signed=True) if k < len(mseg) else "—"))
        rows.append(row)
    cols = ["#", "move", "phase", "t0 [s]", "t1 [s]", "duration [s]", "top speed", "torque, no motor"]
    widths = [0.05, 0.07, 0.09, 0.08, 0.08, 0.1, 0.13, 0.14]
    if focus is not None:
        cols += ["motor speed", "motor torque"]
        widths += [0.12, 0.14]
    return Table("segments", "Torque per move and phase", cols, rows, "lll" + "r" * (len(cols) - 3),
                 "Each phase's largest-magnitude torque at the motor shaft, with its sign, and its top speed.",
                 widths)


def motor_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table | None:
    if focus is None:
        return None
    motor = focus.motor
    rows = [
        [Cell("Motor"), Cell(motor.name)],
        [Cell("Source"), Cell(motor.source)],
        *([[Cell("Catalog data"), Cell(f"unverified: {motor.unverified_reason}", "warn")]]
          if motor.unverified_reason else []),
        [Cell("Rotor inertia J_M"), Cell(du.fmt(motor.inertia, "inertia"))],
        [Cell("Rated torque T_N"), Cell(du.fmt(motor.rated_torque, "torque"))],
        [Cell("Stall torque T_0"), Cell(du.fmt(motor.stall_torque, "torque") if motor.stall_torque else
                                         "not given (T_0 = T_N)")],
        [Cell("Peak torque T_max"), Cell(du.fmt(motor.peak_torque, "torque"))],
        [Cell("Rated speed n_N"), Cell(du.fmt(motor.rated_speed, "angular_speed"))],
        [Cell("Maximum speed n_max"), Cell(du.fmt(motor.max_speed, "angular_speed"))],
        [Cell("Speed-torque envelope"), Cell("derived from the ratings (approximate)"
                                             + ("; the catalog also has curve points" if not
                                                motor.approximate_envelope else ""), "warn")],
        *_derived_rows(motor.name),
    ]
    gb = focus.gearbox
    if gb is not None:
        rows += [
            [Cell("Gearbox"), Cell(f"{gb.id} ({gb.vendor})" if gb.vendor else gb.id)],
            [Cell("Gearbox ratio, efficiency"),
             Cell(f"i = {fmt_number(gb.ratio)}, η = {fmt_number(gb.efficiency, 3)}")],
            [Cell("Gearbox input inertia"), Cell(du.fmt(gb.inertia, "inertia"))],
            [Cell("Gearbox rated output torque"), Cell(du.fmt(gb.rated_output_torque, "torque"))],
            [Cell("Gearbox source"), Cell(gb.source)],
        ]
    return Table("motor_data", "Motor data" + (" and gearbox data" if gb is not None else ""), ["", ""], rows, "ll",
                 "", [0.3, 0.7])


def _derived_rows(motor_id: str) -> list[list[Cell]]:
    """The catalog values of the motor computed rather than read, each with its formula (catalog.derive)."""
    from drivetrain import catalog
    from drivetrain.catalog.derive import formulas

    row = catalog.motor_row(motor_id)
    derived = formulas(row) if row is not None else {}
    return [[Cell(f"Derived: {name}"), Cell(text, "warn")] for name, text in derived.items()]


def _margin_cell(checks: dict[str, CheckRow], name: str) -> Cell:
    ch = checks.get(name)
    if ch is None:
        return Cell("—")
    return Cell(fmt_percent(ch.margin), "pass" if ch.ok else "fail")


def candidates_table(result: SizingResult, du: DisplayUnits) -> Table | None:
    if not result.candidates:
        return None
    rows = []
    for c in result.candidates[:MAX_CANDIDATE_ROWS]:
        checks = {ch.name: ch for ch in c.checks}
        failed = [ch for ch in c.checks if ch.status == "fail"]
        if c.ok:  # the three outcomes of the answer's verdict (docs/checks.md, "The verdict")
            gaps = list(c.unknown)
            drive = c.drive
            if drive is not None and drive.status in ("unknown", "none"):
                gaps.append("drive")
            verdict = Cell(f"PASS WITH UNKNOWNS: {', '.join(gaps)}", "warn") if gaps else Cell("PASS", "pass")
        elif failed:
            worst = min(failed, key=lambda ch: (ch.name != "max_speed", ch.margin or 0.0))
            verdict = Cell(failure_sentence(worst.to_dict(), du), "fail")
        else:
            verdict = Cell(c.failed or "FAIL", "fail")
        rows.append([Cell(str(c.rank) if c.rank is not None else "—"), Cell(c.motor), Cell(c.gearbox or "—"),
                     Cell(fmt_number(c.ratio)), Cell(fmt_number(c.inertia_ratio, 3)),
                     _margin_cell(checks, "peak_torque"), _margin_cell(checks, "rms_torque"),
                     _margin_cell(checks, "max_speed"), verdict])
    note = ("Passing candidates in rank order (the best configuration of each motor), then the closest rejected "
            "ones with the reason each failed.")
    if len(result.candidates) > MAX_CANDIDATE_ROWS:
        note += f" The first {MAX_CANDIDATE_ROWS} of {len(result.candidates)} shown."
    sel = result.selection
    fails = None if sel is None else sel.failures_by_check
    if sel is not None and fails is not None and sel.evaluated is not None:
        parts = [f"{CHECK_NAMES.get(k, k)} {v}" for k, v in fails.items() if isinstance(v, int) and v]
        note += (f" Of {sel.evaluated} configurations evaluated, rejections by check (a configuration may fail "
                 f"several): {', '.join(parts)}.")
        unknown = sel.unknown_by_check
        if unknown is not None:
            gaps = [f"{CHECK_NAMES.get(k, k)} {v}" for k, v in unknown.items() if isinstance(v, int) and v]
            if gaps:
                note += (f" Not judged for lack of catalog data (policy: {sel.unknown_policy}): "
                         f"{', '.join(gaps)}.")
    return Table("candidates", "Ranked candidates", ["#", "motor", "gearbox", "ratio", "J_L/J_M", "peak margin",
                                                     "RMS margin", "speed margin", "result / reason"], rows,
                 "lllrrrrrl", note, [0.045, 0.13, 0.12, 0.065, 0.08, 0.105, 0.105, 0.105, 0.245])


def ratios_table(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> Table | None:
    from drivetrain.sizing.result import optimal_ratio_pure_inertia, ratio_for_inertia_ratio

    rows: list[list[Cell]] = []
    axis = result.axis
    opt = result.selection.optimal_ratio if result.selection is not None else None
    if opt is not None:
        who = opt.motor
        items = (("inertia_match_ratio", "Inertia-matching ratio √(J_L / J_M)",
                  f"an added reduction that makes J_L / i² = J_M for {who} (purely inertial load)"),
                 ("min_rms_ratio", "Ratio of least RMS torque",
                  "the added reduction that minimises the motor's RMS torque over this cycle"
                  + f" ({du.fmt(opt.min_rms_torque_Nm, 'torque')})"),
                 ("max_ratio_for_speed", "Largest ratio within the motor's max speed", "a larger ratio overspeeds it"),
                 ("nearest_catalog_ratio", "Nearest catalog gearbox ratio", "to the ratio of least RMS torque"))
        for key, label, meaning in items:
            value = getattr(opt, key)
            if isinstance(value, (int, float)):
                rows.append([Cell(label), Cell(fmt_number(float(value), 3), "strong" if key == "min_rms_ratio" else ""),
                             Cell(meaning, "muted")])
    elif focus is not None:
        j_l, j_m = focus.load_inertia, focus.motor.inertia
        limit = axis.spec.motor.margins.inertia_ratio if axis.spec.motor is not None else 5.0
        rows.append([Cell("Inertia-matching ratio √(J_L / J_M)"),
                     Cell(fmt_number(optimal_ratio_pure_inertia(j_l, j_m), 3), "strong"),
                     Cell("an added reduction at the motor that makes J_L / i² = J_M (purely inertial load: "
                          "fastest acceleration)", "muted")])
        i_lim = ratio_for_inertia_ratio(j_l, j_m, limit)
        rows.append([Cell(f"Reduction for J_L / J_M = {fmt_number(limit, 3)}"), Cell(fmt_number(i_lim, 3)),
                     Cell("already within the limit" if i_lim <= 1.0 else "smallest added reduction that meets "
                          "the limit", "muted")])
    if not rows:
        return None
    total = axis.total_ratio
    present = (f"{du.fmt(2 * math.pi / total, 'length')} per motor rev" if axis.mechanism.motion == "linear"
               else f"i = {fmt_number(total)}")
    meaning = "load travel per revolution of the axis input" if axis.mechanism.motion == "linear" else \
        "axis input to load"
    if focus is not None and focus.gearbox is not None:
        meaning += f", before the selected gearbox (i = {fmt_number(focus.gearbox.ratio)})"
    rows.insert(0, [Cell("Present transmission"), Cell(present), Cell(meaning, "muted")])
    return Table("ratios", "Transmission ratio", ["", "value", "meaning"], rows, "lrl", "", [0.34, 0.2, 0.46])


def inputs_table(result: SizingResult) -> Table:
    from drivetrain.errors import InputError
    from drivetrain.units import QUANTITIES, parse

    rows = []
    for path, value in leaves(result.axis.raw):
        if isinstance(value, bool):
            given = "true" if value else "false"
        elif value is None:
            given = "—"
        else:
            given = str(value)
        si = given
        if isinstance(value, str):
            key = path.rsplit(".", 1)[-1].split("[", 1)[0]
            q = quantity_of(value, key)
            if q is not None:
                try:
                    v = parse(value, q, path)
                    unit = QUANTITIES[q][0]
                    si = fmt_number(v, 6) + (f" {pretty_unit(unit)}" if unit else "")
                except InputError:
                    si = "—"
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            si = fmt_number(float(value), 6)
        rows.append([Cell(path), Cell(given), Cell(si)])
    return Table("inputs", "Inputs: the axis file as given, and in SI", ["key", "as given", "SI"], rows, "lll",
                 "A bare number in the axis file is SI. Angles in SI are radians, speeds rad/s.", [0.42, 0.29, 0.29])


def subtitle(result: SizingResult, focus: Focus | None) -> str:
    axis = result.axis
    mech = axis.mechanism
    parts = [MECHANISM_NAMES.get(mech.type, mech.type)]
    incline = getattr(mech.load, "incline", 0.0)
    if mech.motion == "linear" and incline:
        parts[0] += ", vertical" if math.isclose(incline, math.pi / 2) else f", {math.degrees(incline):.3g}° incline"
    n = len(axis.transmission)
    geared = [st.name for st in axis.transmission if st.kind == "gearbox"]
    picked = focus.candidate.gearbox if focus is not None and focus.candidate else None
    if picked:
        parts.append(f"gearbox {picked} (i = {fmt_number(float(focus.candidate.ratio or 1.0))})"
                     if focus is not None and focus.candidate else f"gearbox {picked}")
    if geared:
        parts.append(", ".join(geared))
    elif n:
        parts.append(f"{n} transmission element{'s' if n != 1 else ''}")
    elif not picked:
        parts.append("direct drive")
    parts.append(f"{_plural(_moves(result), 'move')} in a {fmt_number(result.duty.period)} s cycle")
    if focus is not None:
        parts.append(("selected " if focus.origin == "selection" else "motor ") + focus.label)
    return " · ".join(parts)
