"""The rows of an order sheet, read from an answer's blocks and the catalog rows of the parts it names
(``sizing.order.order_sheet`` puts them in order; docs/order-sheet.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.sizing.order_spec import (
    BRAKE_SERVICE_FACTOR,
    ZERO_TORQUE,
    OrderRow,
    brake_holding_torque,
    choice_text,
    code_choices,
    peak_duration,
    required_rating,
    resistor_spec,
)

if TYPE_CHECKING:
    from drivetrain.sizing.answer import Candidate, MotorAnswer
    from drivetrain.sizing.axis_blocks import MechanismCheck
    from drivetrain.sizing.electrical import DriveAnswer, Regen
    from drivetrain.sizing.result import SizingResult


@dataclass
class _Ctx:
    """What the rows read: the answer, the motor (given or selected) with its catalog row and blocks."""

    result: SizingResult
    motor_id: str | None = None
    motor_row: dict[str, Any] | None = None
    motor: MotorAnswer | Candidate | None = None
    checks: list[dict[str, Any]] = field(default_factory=list)  # the motor's checks as the JSON rows
    drive: DriveAnswer | None = None
    regen: Regen | None = None
    elec: dict[str, Any] = field(default_factory=dict)
    gearbox_id: str | None = None
    gearbox_checks: list[dict[str, Any]] = field(default_factory=list)
    ratio: float = 1.0
    rows: dict[str, dict[str, Any] | None] = field(default_factory=dict)

    def catalog(self, cid: str | None) -> dict[str, Any] | None:
        """The catalog row of ``cid`` (``_catalog``), read once per sheet."""
        if cid and cid not in self.rows:
            self.rows[cid] = _catalog(cid)
        return self.rows.get(cid) if cid else None


def _catalog(cid: str | None) -> dict[str, Any] | None:
    """The catalog row of ``cid`` through the catalog API, None where the catalog has none."""
    if not cid:
        return None
    from drivetrain import catalog
    from drivetrain.errors import InputError

    try:
        return catalog.get(str(cid))
    except (InputError, KeyError, LookupError):
        return None


def context(result: SizingResult) -> _Ctx:
    c = _Ctx(result=result)
    axis = result.axis
    if axis.motor is not None:
        spec = axis.spec.motor
        c.motor_id = spec.id if spec is not None and spec.id else None
        c.motor, c.drive, c.regen = result.motor, result.drive, result.regen
        c.elec = {} if result.motor is None else dict(result.motor.electrical)
    elif result.selection is not None and result.selection.selected is not None and result.ranking is not None \
            and result.ranking.best is not None:
        pick = c.motor = result.selection.selected
        c.motor_id, c.drive, c.regen, c.elec = pick.motor, pick.drive, pick.regen, dict(pick.electrical or {})
        if pick.gearbox:
            c.gearbox_id, c.ratio = pick.gearbox, float(pick.ratio or 1.0)
            c.gearbox_checks = [ch.to_dict() for ch in pick.checks if ch.name.startswith("gearbox_")]
    c.checks = [] if c.motor is None else [ch.to_dict() for ch in c.motor.checks]
    c.motor_row = c.catalog(c.motor_id)
    return c


def _source(row: dict[str, Any]) -> str | None:
    """A catalog row's source: document, section, page (and address) where traced, else its source text."""
    if row.get("source_document"):
        parts = [row["source_document"], row.get("source_section"), f"p. {row['source_page']}"
                 if row.get("source_page") else None, row.get("source_url")]
        return ", ".join(str(p) for p in parts if p)
    return row.get("source") or None


def _catalog_fields(row: dict[str, Any] | None) -> dict[str, Any]:
    if row is None:
        return {"source": "axis file", "unverified": None, "unverified_reason": None}
    unverified = bool(row.get("unverified")) and str(row.get("unverified")) not in ("0", "False")
    return {"vendor": row.get("vendor"), "source": _source(row), "unverified": unverified,
            "unverified_reason": (row.get("unverified_reason") or None) if unverified else None}


def _checks_open(checks: list[dict[str, Any]], what: str = "") -> list[str]:
    """A failing or unjudged check as an open point (never a pass)."""
    out = []
    for ch in checks:
        status = ch.get("status") or ("pass" if ch.get("ok") else "fail")
        stage = f" [{ch['stage']}]" if ch.get("stage") else ""
        if status == "fail":
            out.append(f"{what}{ch['name']}{stage} fails: required {_g(ch.get('required'))} {ch.get('unit', '')}, "
                       f"available {_g(ch.get('available'))} {ch.get('unit', '')}")
        elif status == "unknown":
            out.append(f"{what}{ch['name']}{stage} not judged" + (f": {ch['note']}" if ch.get("note") else ""))
    return out


def _choose_open(choose: list[dict[str, Any]]) -> list[str]:
    """The code positions still to choose as one open point (none where there are none)."""
    if not choose:
        return []
    return [f"code position(s) {', '.join(str(ch['position']) for ch in choose)} to choose before ordering "
            "(the 'x' of the catalog id; their meaning and options are in the vendor's ordering data, not in the "
            "catalog)" if all(ch["options"] is None for ch in choose) else
            "code position(s) to choose: " + "; ".join(choice_text(ch) for ch in choose)]


def _g(x: Any) -> str:
    return "n/a" if x is None else (f"{x:.4g}" if isinstance(x, (int, float)) else str(x))


def _rpm(w: float) -> float:
    return w * 60.0 / (2.0 * math.pi)


def _mm(row: dict[str, Any] | None, key: str) -> float | None:
    v = None if row is None else row.get(key)
    return None if v is None else float(v) * 1e3


def _named_row(part: str, name: str, code: str, vendor: str | None, spec: dict[str, Any],
               open_points: list[str]) -> OrderRow:
    """A part the axis file gives by its own ratings under a name: the name is taken as its order code, to be
    confirmed (it is no catalog row), so the row is never complete."""
    choose = code_choices(code)
    return OrderRow(part, "catalog", "incomplete", name, vendor=vendor, order_code=None if choose else code,
                    catalog_id=None, source="axis file (not a catalog row)", unverified=True,
                    unverified_reason="named in the axis file with its own ratings, not read from a catalog row",
                    spec=spec, choose=choose, element=part,
                    open_points=[f"confirm that '{code}' is the vendor's order code (the axis file gives this part "
                                 "by its ratings)", *_choose_open(choose), *open_points])


def _brake_need(c: _Ctx) -> tuple[bool, float | None]:
    """Whether the motor must hold the load on a brake (a dwell ``holding: brake``, or a static torque at
    standstill: gravity, springs), and the static torque at the motor shaft [N m] (None where every dwell is
    braked and the answer has no static torque). An axis with its own brake element holds on that."""
    axis = c.result.axis
    if any(st.kind == "brake" for st in axis.transmission):
        return False, None
    duty = c.result.duty
    braked = np.asarray(duty.samples.braked, dtype=bool)
    hold = abs(float(c.result.metrics.holding_torque_Nm or 0.0))
    if hold <= ZERO_TORQUE:
        # a dwell the motor holds with no torque: nothing pushes at rest, any holding torque does; where every
        # dwell is braked the static torque is not in the answer (None)
        t = np.asarray(duty.t)
        held_by_motor = False
        for seg in c.result.metrics.segments:
            inside = (t > seg["t0_s"]) & (t < seg["t1_s"])
            held_by_motor |= seg["kind"] == "dwell" and bool(inside.any()) and not bool(braked[inside].any())
        return bool(braked.any()), (0.0 if braked.any() and held_by_motor else None)
    # a selected catalog gearbox reduces it; its efficiency is not credited (a safe upper bound)
    return True, hold / c.ratio


def motor_row(c: _Ctx) -> OrderRow:
    result, axis = c.result, c.result.axis
    need, static = _brake_need(c)
    required = None if static is None else brake_holding_torque(static)
    brake_checks = [ch for ch in c.checks if "brake" in ch["name"]]
    if brake_checks and brake_checks[0].get("required") is not None:
        required = float(brake_checks[0]["required"])  # the answer's own brake check rules
    brake_spec: dict[str, Any] = {}
    brake_open: list[str] = []
    if need:
        brake_spec["holding_brake"] = "required"
        if required is not None:
            brake_spec["brake_holding_torque_min_Nm"] = required
        else:
            brake_open.append("holding brake needed (a dwell holds on the brake): its holding torque needs the "
                              "static load torque at the motor, not in the answer (every dwell is braked)")
    if c.motor is None and axis.motor is None:
        m = result.metrics
        spec = {"rms_torque_Nm": m.rms_torque_Nm, "peak_torque_Nm": m.peak_torque_Nm,
                "max_speed_rpm": m.max_speed_rpm, "load_inertia_kgm2": m.load_inertia_kgm2, **brake_spec}
        return OrderRow("motor", "specification", "specification", "servo motor (no catalog motor passes)",
                        spec=spec, element="motor", open_points=["no catalog motor passes: the demand at the axis "
                                                                 "input (rotor excluded) is the specification",
                                                                 *brake_open])
    row = c.motor_row
    if row is None:  # a motor given by its parameters
        mo = axis.motor
        assert mo is not None
        spec = {"rated_torque_Nm": mo.rated_torque, "peak_torque_Nm": mo.peak_torque,
                "max_speed_rpm": _rpm(mo.max_speed), "rotor_inertia_kgm2": mo.inertia,
                "rms_torque_required_Nm": None if c.motor is None else c.motor.rms_torque_Nm,
                "peak_torque_required_Nm": None if c.motor is None else c.motor.peak_torque_Nm, **brake_spec}
        return _named_row("motor", f"servo motor {mo.name} (as the axis file gives it)", mo.name, None, spec, [
            *brake_open, *_checks_open([ch for ch in c.checks if ch.get("status") != "pass"])])
    code = str(c.motor_id)
    spec = {"voltage_class_V": row.get("voltage_V"), "rated_torque_Nm": row.get("rated_torque_Nm"),
            "peak_torque_Nm": row.get("peak_torque_Nm"), "flange_mm": _mm(row, "flange_m"),
            "shaft_diameter_mm": _mm(row, "shaft_diameter_m"), **brake_spec}
    # the motor's own checks that fail or could not be judged (the gearbox's go to its row)
    open_points = [*brake_open, *_checks_open([ch for ch in c.checks if not ch["name"].startswith("gearbox_")])]
    if row.get("voltage_V") is None:
        open_points.append("voltage class not in the catalog: confirm the motor's winding voltage with the vendor")
    has_brake = str(row.get("brake")) in ("1", "True", "yes")
    if need and not has_brake:
        variant, holding = row.get("brake_code"), row.get("brake_holding_torque_Nm")
        if variant:
            code = str(variant)
            spec["brake_variant"] = code
            spec["brake_holding_torque_Nm"] = holding
            if holding is None:
                open_points.append(f"brake variant {code}: its holding torque is not in the catalog; it must hold at "
                                   f"least {_g(required)} N*m")
            elif required is not None and float(holding) < required:
                open_points.append(f"brake variant {code} holds {_g(holding)} N*m, less than the {_g(required)} N*m "
                                   "needed")
        else:
            torque = ("(its holding torque: above)" if required is None else
                      f"with a holding torque of at least {_g(required)} N*m" + (
                          "" if static is None else
                          f" ({_g(static)} N*m static x {BRAKE_SERVICE_FACTOR:g}, Machine Design 2007)"))
            open_points.append(f"holding-brake variant of {c.motor_id}: the catalog has no brake order code; order the "
                               f"vendor's brake variant {torque}")
            code = ""
    choose = code_choices(code) if code else []
    open_points += _choose_open(choose)
    status = "complete" if not open_points and code else "incomplete"
    name = f"servo motor {row.get('series') or ''} {c.motor_id}".replace("  ", " ")
    return OrderRow("motor", "catalog", status, name,
                    order_code=code if code and not choose else None, catalog_id=c.motor_id, spec=spec,
                    choose=choose, open_points=open_points, element="motor", **_catalog_fields(row))


def _motor_trace(c: _Ctx) -> tuple[float, float, float] | None:
    """(RMS torque [N m], peak torque [N m], peak duration [s]) of the given or selected motor over the cycle,
    with its rotor (``SizingResult.motor_cycle``); None without a motor."""
    own = c.result.motor_cycle()
    if own is None:
        return None
    cycle, rotor, _ = own
    torque = cycle.motor_torque(rotor)
    rms = float(np.sqrt(np.sum(cycle.weights * torque**2) / cycle.period))
    return rms, float(np.max(np.abs(torque))), peak_duration(cycle.t, torque, rms, cycle.period)


def _supply(c: _Ctx) -> tuple[float | None, float | None, str]:
    """(supply [V] line-to-line rms, DC bus [V], basis): the answer's, the axis file's, else the motor's class."""
    from drivetrain.physics.motor_electrical import dc_bus_voltage

    supply, bus = c.elec.get("supply_voltage_V"), c.elec.get("dc_bus_voltage_V")
    spec = c.result.axis.spec.motor
    if supply is None and spec is not None and spec.supply_voltage is not None:
        supply = spec.supply_voltage
    if bus is None and spec is not None and spec.dc_bus_voltage is not None:
        bus = spec.dc_bus_voltage
    basis = "the answer's supply"
    if supply is None and bus is None and c.motor_row is not None and c.motor_row.get("voltage_V") is not None:
        supply, basis = float(c.motor_row["voltage_V"]), "the motor's voltage class"
    if bus is None and supply is not None:
        bus = float(dc_bus_voltage(supply))
    return supply, bus, basis


def drive_row(c: _Ctx) -> OrderRow:
    d = c.drive
    axis = c.result.axis
    did = (d.id if d is not None else None) or (axis.drive.name if axis.drive is not None else None)
    checked = did is not None and ((d is not None and d.ok is not None) or axis.drive is not None)
    if checked:
        row = c.catalog(did)
        code = str(did)
        spec = {"continuous_current_A": None if d is None else d.continuous_current_A,
                "peak_current_A": None if d is None else d.peak_current_A,
                "voltage_class_V": None if row is None else row.get("voltage_V"), "motor": c.motor_id}
        choose = code_choices(code)
        open_points = _choose_open(choose)
        checks = [] if d is None else list(d.checks or ())
        open_points += _checks_open(checks)
        if row is None and axis.drive is not None:
            return _named_row("drive", f"servo drive {did} (as the axis file gives it)", code, axis.drive.vendor,
                              spec, _checks_open(checks))
        return OrderRow("drive", "catalog", "incomplete" if open_points else "complete",
                        f"servo drive {'' if row is None else (row.get('series') or '')} {did}".replace("  ", " "),
                        order_code=None if choose else code, catalog_id=code, spec=spec, choose=choose,
                        open_points=open_points, element="drive", **_catalog_fields(row))
    return _drive_spec(c, d)


def _drive_spec(c: _Ctx, d: DriveAnswer | None) -> OrderRow:
    """A drive for the motor as a specification: continuous and peak output current with the peak's duration,
    supply and DC bus, the motor; in torque terms where the motor's k_T is not known."""
    spec: dict[str, Any] = {"motor": c.motor_id or (c.result.axis.motor.name if c.result.axis.motor else None)}
    open_points: list[str] = []
    trace = _motor_trace(c)
    kt = c.elec.get("torque_constant_NmA")
    if trace is None:
        open_points.append("no motor passes: choose the motor first")
    elif kt:
        spec["continuous_current_A"] = c.elec.get("rms_current_A") or trace[0] / kt
        spec["peak_current_A"] = c.elec.get("peak_current_A") or trace[1] / kt
        spec["peak_duration_s"] = trace[2]
        spec["torque_constant_NmA"] = kt
    else:
        spec.update({"continuous_torque_Nm": trace[0], "peak_torque_Nm": trace[1], "peak_duration_s": trace[2]})
        open_points.append(f"output currents = these torques / the motor's k_T [N*m/A], not known for "
                           f"{spec['motor']}: take k_T from the motor's data sheet")
    supply, bus, basis = _supply(c)
    spec["supply_voltage_V"], spec["dc_bus_voltage_V"] = supply, bus
    if supply is None and bus is None:
        open_points.append("supply voltage not given (motor.supply_voltage) and the motor's voltage class unknown")
    elif basis != "the answer's supply":
        spec["voltage_basis"] = basis
    if c.regen is not None and c.regen.resistor_needed:
        spec["braking_chopper"] = "for an external braking resistor (row braking_resistor)"
    if d is not None and d.candidates:
        spec["vendor_pairing"] = list(d.candidates)
        open_points.append(f"the vendor pairs {', '.join(d.candidates)} with this motor; the catalog has no "
                           "currents to check them against this specification")
    if d is not None and d.reason:
        open_points.append(str(d.reason))
    return OrderRow("drive", "specification", "specification", f"servo drive for {spec['motor'] or 'the motor'}",
                    spec=spec, open_points=open_points, element="drive")


def _gearbox_demand(c: _Ctx, k: int) -> dict[str, float]:
    """What stage ``k`` (a gearbox of the transmission) must rate: T2B, T2N, T2NOT [N m] at its output,
    n1 max and mean [rpm] at its input, with the axis's margins and shock factor (``checks.gearbox_ratings``:
    the same rule as ``result.gearbox_rating_checks``)."""
    from drivetrain.duty.cycle import gearbox_split_at_motor_peak
    from drivetrain.physics.averages import cubic_mean
    from drivetrain.sizing.checks import gearbox_ratings, running_torque, shock_factor

    axis, duty = c.result.axis, c.result.duty
    st = axis.transmission[k]
    margins = axis.spec.motor.margins if axis.spec.motor is not None else None
    tm, sm = (margins.torque, margins.speed) if margins is not None else (1.0, 1.0)
    shock = shock_factor(duty.period, margins.gearbox_shock_factor if margins is not None else None)
    t_out, w_in = duty.stage_torque[k], np.abs(duty.stage_omega[k]) * st.ratio
    estop = math.nan
    motor = axis.motor if axis.motor is not None else c.result._selected_motor()
    first = next(j for j, s in enumerate(axis.transmission) if s.kind == "gearbox")
    if motor is not None and k == first:
        estop = gearbox_split_at_motor_peak(axis, duty, motor.inertia, motor.peak_torque,
                                            running_torque(duty.external))["gearbox_output_torque_at_motor_peak_Nm"]
    nan = math.nan
    got = gearbox_ratings(float(np.max(np.abs(t_out))), cubic_mean(t_out, duty.stage_omega[k], duty.weights),
                          float(np.max(w_in)), float(np.sum(duty.weights * w_in) / duty.period), estop,
                          t2b=nan, t2n=nan, t2not=nan, n1max=nan, n1n=nan, torque_margin=tm, speed_margin=sm,
                          shock=1.0 if math.isnan(shock) else shock)
    req = {name: float(got[name][0]) for name in got}
    out = {"T2B_min_Nm": req["gearbox_peak_torque"], "T2N_min_Nm": req["gearbox_rated_torque"],
            "T2NOT_min_Nm": req["gearbox_emergency_stop_torque"],
            "n1_max_min_rpm": _rpm(req["gearbox_max_input_speed"]),
            "n1_mean_min_rpm": _rpm(req["gearbox_mean_input_speed"])}
    if math.isnan(shock):  # above 1000 cycles/h T2B needs the vendor's shock factor: stated, not assumed
        out["T2B_shock_factor"] = math.nan
    return {k: v for k, v in out.items() if k == "T2B_shock_factor" or math.isfinite(v)}


_CHECK_KEYS = {"gearbox_peak_torque": "T2B_min_Nm", "gearbox_rated_torque": "T2N_min_Nm",
               "gearbox_emergency_stop_torque": "T2NOT_min_Nm", "gearbox_max_input_speed": "n1_max_min_rpm",
               "gearbox_mean_input_speed": "n1_mean_min_rpm"}


def _required_of(checks: list[dict[str, Any]]) -> dict[str, Any]:
    """The required values of the answer's gearbox checks (rpm already), by sheet key; radial and axial
    output loads where the answer checks them."""
    out: dict[str, Any] = {}
    for ch in checks:
        key = _CHECK_KEYS.get(ch["name"])
        if key is None and ("radial" in ch["name"] or "axial" in ch["name"]):
            key = f"{ch['name']}_{ch.get('unit', '')}".replace("*", "")
        if key is not None and ch.get("required") is not None and math.isfinite(float(ch["required"])):
            out[key] = float(ch["required"])
    return out


def _adapter(c: _Ctx, gear: dict[str, Any] | None) -> tuple[str | None, list[str]]:
    """The motor adapter in words (the motor's shaft, pilot, flange, bolt circle) and its open points."""
    row = c.motor_row
    dims = {"shaft": _mm(row, "shaft_diameter_m"), "pilot": _mm(row, "pilot_diameter_m"),
            "flange": _mm(row, "flange_m"), "bolt circle": _mm(row, "bolt_circle_m")}
    if c.motor is None and c.result.axis.motor is None:
        return None, ["motor adapter: for the motor still to choose"]
    if c.motor_id is None or all(v is None for v in dims.values()):
        return None, ["motor adapter: the motor's shaft and flange dimensions are not known (not in the catalog)"]
    text = f"for {c.motor_id}: " + ", ".join(f"{k} {v:.4g} mm" for k, v in dims.items() if v is not None)
    open_points = [f"motor adapter: the motor's {k} is not in the catalog" for k, v in dims.items() if v is None]
    bore = _mm(gear, "input_bore_max_m")
    if bore is not None and dims["shaft"] is not None and dims["shaft"] > bore + 1e-9:
        open_points.append(f"motor adapter: the motor's {dims['shaft']:.4g} mm shaft exceeds the gearbox's largest "
                           f"input bore {bore:.4g} mm")
    return text, open_points


def gearbox_rows(c: _Ctx) -> list[OrderRow]:
    """The selected catalog gearbox, and every gearbox of the axis's transmission."""
    rows: list[OrderRow] = []
    if c.gearbox_id is not None:
        rows.append(_gearbox_catalog_row(c, c.gearbox_id, c.ratio, c.gearbox_checks, "selection"))
    axis = c.result.axis
    checks = c.result.gearbox_checks.checks if c.result.gearbox_checks is not None else ()
    specs: list[Any] = list(axis.spec.transmission)  # each read by its type
    for k, (spec, st) in enumerate(zip(specs, axis.transmission, strict=False)):
        if getattr(spec, "type", None) != "gearbox":
            continue
        own = [ch.to_dict() for ch in checks if ch.stage == st.name]  # read with the catalog gearbox's checks
        element = f"transmission[{k}]"
        if getattr(spec, "catalog", None):
            rows.append(_gearbox_catalog_row(c, str(spec.catalog), st.ratio, own, element))
            continue
        need = _gearbox_demand(c, k)
        need.update(_required_of(own))
        open_points = []
        if "T2B_shock_factor" in need:
            need.pop("T2B_shock_factor")
            open_points.append(f"{3600.0 / c.result.duty.period:.0f} cycles/h exceed the 1000/h T2B holds for: the "
                               "T2B above is without the vendor's shock factor (motor.margins.gearbox_shock_factor)")
        if "T2NOT_min_Nm" not in need:
            open_points.append("T2NOT needs the motor's peak torque (no motor chosen)")
        sp: dict[str, Any] = {"type": f"{getattr(spec, 'kind', '')} gearbox", "ratio": st.ratio, **need}
        if getattr(spec, "backlash", None):
            sp["backlash_max_arcmin"] = float(spec.backlash) * 60.0 * 180.0 / math.pi
        if getattr(spec, "stiffness", None):
            sp["torsional_stiffness_min_Nm_per_arcmin"] = float(spec.stiffness) * math.pi / (180.0 * 60.0)
        if k == 0 or all(s.kind == "coupling" for s in axis.transmission[:k]):
            text, adapter_open = _adapter(c, None)
            if text:
                sp["motor_adapter"] = text
            open_points += adapter_open
        open_points.append("output radial and axial loads not known to the answer: give the vendor the output "
                           "element's forces and distance")
        rows.append(OrderRow("gearbox", "specification", "specification",
                             f"{getattr(spec, 'kind', '')} gearbox i = {st.ratio:.4g}", spec=sp,
                             open_points=open_points, element=element))
    return rows


def _gearbox_catalog_row(c: _Ctx, gid: str, ratio: float, checks: list[dict[str, Any]], element: str) -> OrderRow:
    row = c.catalog(gid)
    spec: dict[str, Any] = {"ratio": ratio, **_required_of(checks)}
    text, open_points = _adapter(c, row)
    if text:
        spec["motor_adapter"] = text
    choose = code_choices(gid)
    open_points = _choose_open(choose) + open_points
    open_points += _checks_open(checks)
    if row is None:
        open_points.append(f"{gid} is not in the catalog")
    return OrderRow("gearbox", "catalog", "incomplete" if open_points else "complete",
                    f"gearbox {gid} (i = {ratio:.4g})" + (" with motor adapter" if text else ""),
                    order_code=None if choose else gid, catalog_id=gid, spec=spec, choose=choose,
                    open_points=open_points, element=element, **_catalog_fields(row))


def resistor_row(c: _Ctx) -> OrderRow | None:
    """The braking resistor as a specification, where the cycle sends energy to one and the drive's built-in
    resistor is not known to take it: the resistance window, energy per event, peak and average power and the
    standard values inside the window."""
    rg = c.regen
    if rg is None or not rg.resistor_needed or rg.builtin_resistor_sufficient is True:
        return None
    drive = c.catalog(c.drive.id) if c.drive is not None and c.drive.ok is not None else None
    given = c.result.axis.drive
    r_min = rg.resistor_min_ohm
    if r_min is None:
        r_min = (drive or {}).get("min_resistance_ohm") or (given.min_resistance if given is not None else None)
    events = [e.resistor_J for e in rg.events]
    u_on = (drive or {}).get("regen_on_voltage_V") or (given.regen_on_voltage if given is not None else None)
    spec, open_points = resistor_spec(float(rg.resistor_peak_power_W), float(rg.resistor_average_power_W),
                                      float(rg.resistor_energy_per_cycle_J), max(events) if events else None,
                                      r_min, rg.resistor_max_ohm, u_on, _supply(c)[1])
    return OrderRow("braking_resistor", "specification", "specification", "braking resistor", spec=spec,
                    open_points=open_points, element="drive")


def transmission_part_rows(c: _Ctx) -> list[OrderRow]:
    """The couplings and brakes of the transmission as specifications."""
    axis, duty = c.result.axis, c.result.duty
    rows = []
    specs: list[Any] = list(axis.spec.transmission)  # each read by its type
    for k, (spec, st) in enumerate(zip(specs, axis.transmission, strict=False)):
        element = f"transmission[{k}]"
        peak = float(np.max(np.abs(duty.stage_torque[k])))
        speed = _rpm(float(np.max(np.abs(duty.stage_omega[k]))))
        if st.kind == "coupling":
            sp: dict[str, Any] = {"peak_torque_min_Nm": peak, "max_speed_min_rpm": speed}
            if k == 0 and _mm(c.motor_row, "shaft_diameter_m") is not None:
                sp["motor_side_bore_mm"] = _mm(c.motor_row, "shaft_diameter_m")
            if getattr(spec, "stiffness", None):
                sp["torsional_stiffness_min_Nm_per_rad"] = float(spec.stiffness)
            if getattr(spec, "backlash", None):
                sp["backlash_max_arcmin"] = float(spec.backlash) * 60.0 * 180.0 / math.pi
            rows.append(OrderRow("coupling", "specification", "specification", "shaft coupling", spec=sp,
                                 element=element, open_points=["load-side bore: the driven shaft's diameter"]))
        elif st.kind == "brake":
            check = c.result.brake_check
            static = None if check is None else check.required
            sp = {"static_torque_Nm": static, "holding_torque_min_Nm":
                  None if static is None else brake_holding_torque(float(static)),
                  "holding_torque_given_Nm": getattr(spec, "holding_torque", None)}
            rows.append(OrderRow("brake", "specification", "specification", "holding brake", spec=sp, element=element,
                                 open_points=[] if static is not None else
                                 ["static torque at the brake not judged: give transmission holding_torque and a "
                                  "dwell with holding: brake"]))
    return rows


def _check_named(c: _Ctx, name: str) -> MechanismCheck | None:
    return next((ch for ch in c.result.mechanism_checks if ch.name == name), None)


def _rating_from_life(check: MechanismCheck | None, rating: float | None, exponent: float) -> float | None:
    """The dynamic rating [N] that meets the life check's required life (``required_rating``)."""
    if check is None or rating is None or check.available in (None, 0.0) or check.required is None:
        return None
    life = float(check.available)
    return None if not math.isfinite(life) else required_rating(float(rating), float(check.required), life, exponent)


def _rating_from_safety(check: MechanismCheck | None, rating: float | None) -> float | None:
    """The static rating [N] that meets the static-safety check: C0 f_s,req / f_s (f_s = C0 / P0, ISO 76)."""
    if check is None or rating is None or not check.available or check.required is None:
        return None
    return float(rating) * float(check.required) / float(check.available)


def mechanism_rows(c: _Ctx) -> list[OrderRow]:
    """The screw and nut of a screw axis and the linear guide, as specifications."""
    axis = c.result.axis
    rows = []
    mech: Any = axis.spec.mechanism  # a screw's keys, read once its type says so
    if getattr(mech, "type", None) in ("ball_screw", "lead_screw"):
        limits, nut = getattr(mech, "screw", None), getattr(mech, "nut", None)
        v = np.asarray(c.result.duty.samples.v, dtype=float)
        sp: dict[str, Any] = {"type": mech.type.replace("_", " "), "lead_mm": mech.lead * 1e3,
                              "diameter_mm": None if mech.diameter is None else mech.diameter * 1e3,
                              "length_mm": None if mech.length is None else mech.length * 1e3,
                              "max_speed_rpm": float(np.max(np.abs(v))) / mech.lead * 60.0}
        guide = c.result.guide
        if guide is not None:
            sp["axial_load_peak_N"] = guide.actuator_peak_force_N
        if limits is not None:
            sp["root_diameter_mm"] = limits.root_diameter * 1e3
            sp["mounting"] = limits.mounting
        crit, buck = _check_named(c, "screw_critical_speed"), _check_named(c, "screw_buckling")
        # without the checks the screw must still turn at its peak speed and take the peak axial force
        sp["critical_speed_min_rpm"] = crit.required if crit is not None else sp["max_speed_rpm"]
        sp["buckling_load_min_N"] = buck.required if buck is not None else sp.get("axial_load_peak_N")
        if nut is not None:
            sp["nut_dynamic_rating_min_N"] = _rating_from_life(_check_named(c, "nut_life"), nut.C_a, 3.0)
            sp["nut_static_rating_min_N"] = _rating_from_safety(_check_named(c, "nut_static_safety"), nut.C_0a)
        open_points = _checks_open([ch.to_dict() for ch in c.result.mechanism_checks
                                    if ch.name.startswith(("screw_", "nut_"))])
        if limits is None:
            open_points.append("critical speed and buckling not judged: give mechanism.screw (root_diameter, "
                               "mounting)")
        if sp.get("axial_load_peak_N") is None:
            open_points.append("peak axial load not in the answer (it comes with a guide block): the vendor needs it")
        if nut is None:
            open_points.append("nut life not judged: give mechanism.nut (C_a)")
        rows.append(OrderRow("screw", "specification", "specification", f"{sp['type']} with nut",
                             spec={k: val for k, val in sp.items() if val is not None}, open_points=open_points,
                             element="mechanism"))
    g = axis.spec.guide
    if g is not None:
        exponent = 3.0 if g.rolling == "ball" else 10.0 / 3.0
        gb = c.result.guide
        sp = {"carriages": g.carriages, "orientation": g.orientation, "rolling": g.rolling,
              "dynamic_rating_min_N": _rating_from_life(_check_named(c, "guide_life"), g.dynamic_rating, exponent),
              "static_rating_min_N": _rating_from_safety(_check_named(c, "guide_static_safety"), g.static_rating),
              "required_life_h": g.required_life / 3600.0}
        peaks = (gb.peak_normal_N, gb.peak_pitch_Nm, gb.peak_roll_Nm, gb.peak_yaw_Nm) if gb is not None else (None,) * 4
        sp.update(zip(("peak_normal_load_N", "peak_pitch_moment_Nm", "peak_roll_moment_Nm", "peak_yaw_moment_Nm"),
                      peaks, strict=True))
        own = [ch for ch in c.result.mechanism_checks if ch.name.startswith("guide_")]
        open_points = _checks_open([ch.to_dict() for ch in own] + [ch.to_dict() for ch in (gb.checks if gb else ())])
        if g.dynamic_rating is None:
            open_points.append("guide life not judged: give guide.dynamic_rating (C) and static_rating (C0)")
        rows.append(OrderRow("guide", "specification", "specification", f"linear guide, {g.carriages} carriage(s)",
                             spec={k: val for k, val in sp.items() if val is not None}, open_points=open_points,
                             element="guide"))
    return rows
