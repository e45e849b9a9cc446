"""The electrical half of sizing a given motor: currents, the envelope at the supply voltage, the
drive's current checks, regeneration and the braking resistor, and the winding temperature.

Everything here is a thin orchestration of the formula modules in ``drivetrain.physics``
(``motor_electrical``, ``drive_overload``, ``regen``, ``motor_thermal``), which carry the
equations and their sources. Inputs come from the axis file (``drivetrain.axis.electrical``);
what is missing is reported as missing (None), never guessed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from drivetrain.errors import InputError
from drivetrain.physics import drive_overload, motor_electrical, motor_thermal, regen
from drivetrain.sizing.checks import Check, margin_of

if TYPE_CHECKING:
    from drivetrain.axis.electrical import DriveData, MotorElectrical
    from drivetrain.axis.model import Axis, Margins, MotorData
    from drivetrain.duty.cycle import DutyCycle

Array = np.ndarray


@dataclass(frozen=True)
class RegenEvent:
    """One regeneration event of the cycle: an interval in which the motor sends power into the DC bus.

    Attributes
    ----------
    t0_s : float
        Start of the event [s] from the start of the cycle.
    t1_s : float
        End of the event [s].
    energy_J : float
        Energy the event sends into the DC bus [J], after the copper loss.
    resistor_J : float
        Of it, the energy the braking resistor must take [J] (what the bus capacitors cannot absorb).
    """

    t0_s: float
    t1_s: float
    energy_J: float
    resistor_J: float

    def to_dict(self) -> dict[str, float]:
        """The event in the JSON of docs/axis-file.md (``regen.events[]``), keys in field order."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class Regen:
    """The regeneration block of the motor with its drive: the energy the cycle sends into the DC bus, what
    the bus capacitors absorb and what is left for a braking resistor (``physics.regen.regen_cycle``).

    The given motor's sits in ``SizingResult.regen``, the selected candidate's in
    ``SizingResult.selection.selected.regen``; :meth:`to_dict` is the ``regen`` object of the JSON
    (docs/axis-file.md), its keys the fields in this order.

    Attributes
    ----------
    shaft_energy_per_cycle_J : float
        Mechanical energy the motor shaft returns per cycle [J] (the integral of the negative T * omega).
    copper_loss_in_events_J : float
        Copper loss in the motor's windings during the regeneration events [J] (0 where R or K_t is not known).
    energy_per_cycle_J : float
        Energy into the DC bus per cycle [J]: the shaft's minus the copper loss, over the events.
    capacitor_energy_per_event_J : float
        Energy the drive's bus capacitors can absorb in one event [J] (0 without the drive's data).
    capacitor_basis : str
        Where that energy comes from: ``"published"`` (the drive's absorbable energy), ``"capacitance"``
        (1/2 C (U_max^2 - U_bus^2)) or ``"none"``.
    capacitor_absorbed_J : float
        Energy the bus capacitors absorb per cycle [J].
    resistor_energy_per_cycle_J : float
        Energy the braking resistor must take per cycle [J].
    resistor_peak_power_W : float
        Peak power into the braking resistor [W].
    resistor_average_power_W : float
        Average power into the braking resistor over the cycle [W].
    resistor_min_ohm : float or None
        The drive's minimum braking resistance [ohm]; None where the drive does not state it.
    resistor_max_ohm : float or None
        The largest resistance that still takes the peak power at the drive's regeneration-on voltage
        [ohm] (U_on^2 / P_peak); None where that voltage is not known or no power goes to a resistor.
    resistor_needed : bool
        Whether the cycle sends energy to a braking resistor at all.
    builtin_resistor_sufficient : bool or None
        Whether the drive's built-in resistor takes the peak and average power; None where not known.
    events : tuple of RegenEvent
        The regeneration events of the cycle, in time order.
    """

    shaft_energy_per_cycle_J: float
    copper_loss_in_events_J: float
    energy_per_cycle_J: float
    capacitor_energy_per_event_J: float
    capacitor_basis: str
    capacitor_absorbed_J: float
    resistor_energy_per_cycle_J: float
    resistor_peak_power_W: float
    resistor_average_power_W: float
    resistor_min_ohm: float | None
    resistor_max_ohm: float | None
    resistor_needed: bool
    builtin_resistor_sufficient: bool | None
    events: tuple[RegenEvent, ...] = ()

    def to_dict(self, events: bool = True) -> dict[str, Any]:
        """The ``regen`` object of the JSON (docs/axis-file.md): the fields in order, ``events`` as a list
        of their dicts; without ``events`` where ``events`` is False (the web page's panel)."""
        out: dict[str, Any] = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "events"}
        if events:
            out["events"] = [e.to_dict() for e in self.events]
        return out


DriveLayout = Literal["given motor", "currents", "not checked", "pairing"]
"""How a drive block was built, which fixes its JSON keys and their order (``DriveAnswer.to_dict``)."""

_DRIVE_KEYS: dict[str, tuple[str, ...]] = {
    "given motor": ("id", "vendor", "continuous_current_A", "peak_current_A", "i2t_setpoint_A2s", "i2t_peak_A2s",
                    "ok", "checks"),
    "currents": ("basis", "candidates", "motor_rms_current_A", "motor_peak_current_A", "id", "vendor",
                 "continuous_current_A", "peak_current_A", "i2t_setpoint_A2s", "i2t_peak_A2s", "ok", "checks",
                 "status", "supply_voltage_V", "peak_time_s", "unverified", "unverified_reason"),
    "not checked": ("basis", "candidates", "status", "id", "ok", "checks", "reason", "motor_rms_current_A",
                    "motor_peak_current_A"),
    "pairing": ("basis", "candidates", "motor_rms_current_A", "motor_peak_current_A", "id", "vendor", "judged_by",
                "pairing_source", "checks", "continuous_current_A", "peak_current_A", "status", "ok", "reason",
                "supply_voltage_V", "peak_time_s", "unverified", "unverified_reason"),
}
"""The keys of each layout's JSON, in the order of docs/axis-file.md's examples (as they were before the block
was typed: the JSON is unchanged)."""

_DRIVE_LEFT_OUT_WHEN_NONE = frozenset({"motor_rms_current_A", "motor_peak_current_A", "continuous_current_A",
                                       "peak_current_A", "i2t_setpoint_A2s", "i2t_peak_A2s", "checks",
                                       "unverified_reason"})
"""Keys the JSON leaves out where they are not known (the others are ``null`` then); ``unverified`` is left out
unless true."""


@dataclass(frozen=True)
class DriveAnswer:
    """The drive block: the drive of a given motor (``drive:`` in the axis file, checked by its currents), or the
    drive a catalog candidate may be ordered with (``drive_select.pick_drive``; docs/checks.md, "Drive selection").

    A given motor's sits in ``SizingResult.drive``; a catalog selection's in each listed candidate's
    ``drive`` and in ``selection.selected.drive``. :meth:`to_dict` is the ``drive`` object of the JSON
    (docs/axis-file.md, "Result keys of the electrical half" and "Drives in a selection").

    Attributes
    ----------
    layout : str
        How the block was built, which fixes its JSON keys and their order: ``"given motor"`` (a given motor's
        drive), ``"currents"`` (a catalog candidate's drive checked by its currents), ``"not checked"`` (its
        drive cannot be checked, or the given drive cannot run the motor: ``status`` and ``reason`` say why),
        ``"pairing"`` (judged by the vendor's pairing). Not itself in the JSON.
    basis : str or None
        Where the drives considered come from (``"vendor pairing table"``, ``"vendor and supply voltage"``,
        ``"given in the axis file"``, ...); None for a given motor's drive.
    candidates : tuple of str or None
        The drive ids considered; None for a given motor's drive.
    motor_rms_current_A : float or None
        The motor's RMS current over the candidate's own cycle [A rms]; None without a torque constant.
    motor_peak_current_A : float or None
        The motor's peak current over that cycle [A rms]; None without a torque constant.
    id : str or None
        The drive named (None when none can be named).
    vendor : str or None
        Its vendor.
    judged_by : str or None
        ``"vendor pairing"`` where the pairing judged the drive, else None.
    pairing_source : str or None
        The source of that pairing (``catalog.drive_pair_sources``), where judged by it.
    continuous_current_A : float or None
        The drive's continuous output current [A rms]; None where not known.
    peak_current_A : float or None
        The drive's peak output current [A rms]; None where not known.
    i2t_setpoint_A2s : float or None
        The set point of the drive's I^2 t accumulator [A^2 s], where the vendor states how long the peak lasts.
    i2t_peak_A2s : float or None
        The accumulator's highest value over the periodic cycle [A^2 s], with the set point.
    ok : bool or None
        Whether the drive passes its checks; None where it cannot be judged.
    checks : tuple of dict or None
        The drive's checks (``drive_rms_current``, ``drive_peak_current``, ``drive_i2t``, or the pairing's
        ``drive_continuous_by_pairing``, ``drive_peak_by_pairing``): each with its name, required and available
        value, unit, margin and ok; None where the drive was not checked.
    status : str or None
        ``"ok"``, ``"fails"``, ``"unknown"`` or ``"none"`` (docs/axis-file.md); None for a given motor's drive
        (its ``ok`` says) and, before its current is known, for a candidate's drive that can be checked.
    reason : str or None
        Why the status is ``unknown``, ``none`` or (a given drive that cannot run the motor) ``fails``; or how
        the pairing judged the drive.
    supply_voltage_V : float or None
        The drive's supply voltage [V] (AC line to line, rms), where the catalog states it.
    peak_time_s : float or None
        How long the drive may deliver its peak current [s], where the vendor states it.
    unverified : bool
        Whether the drive's ratings (or its pairing) are a third-party transcription (data/SOURCES.md, "Drives").
    unverified_reason : str or None
        Why, where unverified.
    """

    layout: DriveLayout
    basis: str | None = None
    candidates: tuple[str, ...] | None = None
    motor_rms_current_A: float | None = None
    motor_peak_current_A: float | None = None
    id: str | None = None
    vendor: str | None = None
    judged_by: str | None = None
    pairing_source: str | None = None
    continuous_current_A: float | None = None
    peak_current_A: float | None = None
    i2t_setpoint_A2s: float | None = None
    i2t_peak_A2s: float | None = None
    ok: bool | None = None
    checks: tuple[dict[str, Any], ...] | None = None
    status: str | None = None
    reason: str | None = None
    supply_voltage_V: float | None = None
    peak_time_s: float | None = None
    unverified: bool = False
    unverified_reason: str | None = None

    @property
    def outcome(self) -> str:
        """``status``, or for a given motor's drive (which has none) ``"ok"`` or ``"fails"`` by ``ok``."""
        return self.status or ("ok" if self.ok else "fails")

    def to_dict(self) -> dict[str, Any]:
        """The ``drive`` object of the JSON (docs/axis-file.md): the keys of :attr:`layout` in their order, those
        not known left out where the JSON leaves them out (``_DRIVE_LEFT_OUT_WHEN_NONE``)."""
        out: dict[str, Any] = {}
        for key in _DRIVE_KEYS[self.layout]:
            value = getattr(self, key)
            if (value is None and key in _DRIVE_LEFT_OUT_WHEN_NONE) or (key == "unverified" and not value):
                continue
            out[key] = list(value) if isinstance(value, tuple) else value
        return out


@dataclass
class ElectricalAnswer:
    """What the electrical half adds to a given motor's result."""

    motor: dict[str, Any] = field(default_factory=dict)
    """keys joining the ``motor`` block (supply_voltage_V, envelope_source, rms_current_A, ...)"""
    checks: list[Check] = field(default_factory=list)
    """checks joining the motor's checks"""
    drive: DriveAnswer | None = None
    regen: Regen | None = None
    curve: dict[str, Any] | None = None
    """the T-n curve at the supply voltage (speeds, continuous and peak torque), for reports"""


def _check(name: str, required: float, available: float, unit: str, note: str = "") -> Check:
    m = float(margin_of(required, available))
    return Check(name, float(required), float(available), unit, bool(m >= 0.0), m, False, note)


def dc_bus(elec: MotorElectrical | None, drive: DriveData | None) -> tuple[float | None, float | None]:
    """(AC supply [V] line-to-line rms or None, DC bus [V] or None): the drive's first, then the motor's keys."""
    for src in (drive, elec):
        if src is None:
            continue
        if src.dc_bus_voltage is not None:
            return src.supply_voltage, src.dc_bus_voltage
        if src.supply_voltage is not None:
            return src.supply_voltage, float(motor_electrical.dc_bus_voltage(src.supply_voltage))
    return None, None


def continuous_current_at(elec: MotorElectrical, speed: float, rated_speed: float) -> float | None:
    """Continuous current [A rms] at ``speed`` [rad/s]: I_0 at standstill falling linearly to I_N at rated speed.

    The same shape as the derived continuous torque envelope (docs/checks.md, "The derived
    envelope"): the stall current I_0 at standstill, the rated current I_N at the rated speed
    and beyond; one of them alone is used as it is.
    """
    i0, i_n = elec.stall_current, elec.rated_current
    if i0 is None or i_n is None:
        return i0 if i0 is not None else i_n
    frac = min(max(speed / rated_speed, 0.0), 1.0) if rated_speed > 0 else 1.0
    return i0 + (i_n - i0) * frac


def electrical_answer(axis: Axis, duty: DutyCycle, motor: MotorData, margins: Margins | None) -> ElectricalAnswer:
    """The electrical figures, checks, drive block and regen block of a given motor on ``axis``.

    Empty when the axis file gives neither electrical motor data nor a drive. A drive without the
    motor's torque constant (kt or ke) is an input error naming ``motor.kt``.
    """
    elec = axis.electrical
    drive = axis.drive
    env = axis.environment
    out = ElectricalAnswer()
    has_elec = elec is not None and elec.any
    envelope_source = "derived" if motor.approximate_envelope else "datasheet"
    if not has_elec and drive is None:
        out.motor = {"envelope_source": envelope_source}
        return out
    assert elec is not None or drive is not None
    kt = None if elec is None else motor_electrical.torque_constant(elec.kt, elec.ke)
    if kt is None:
        raise InputError("motor.kt", "the current checks need the motor's torque constant (give kt, or ke)",
                         has_value=False)
    assert elec is not None
    torque_margin = margins.torque if margins is not None else 1.0
    t_m = duty.motor_torque(motor.inertia)
    w = duty.omega
    sat = motor_electrical.saturation(motor.rated_torque, motor.peak_torque, elec.peak_current)
    current = motor_electrical.phase_current(t_m, kt, sat)
    i_rms = float(drive_overload.rms_current(current, duty.weights, duty.period))
    i_peak = float(current.max()) if current.size else 0.0
    supply, bus = dc_bus(elec, drive)
    derate = 1.0 if env.derating == "none" else float(motor_thermal.derating(env.ambient, env.altitude, env.derating))
    out.motor = {
        "supply_voltage_V": supply,
        "dc_bus_voltage_V": bus,
        "torque_constant_NmA": kt,
        "rms_current_A": i_rms,
        "peak_current_A": i_peak,
        "derating_factor": derate,
        "ambient_degC": env.ambient,
        "altitude_m": env.altitude,
        "electrical_sources": list(elec.sources),
    }
    # motor current checks
    mean_speed = float(np.sum(duty.weights * np.abs(w)) / duty.period)
    i_cont = continuous_current_at(elec, mean_speed, motor.rated_speed)
    out.motor["continuous_current_A"] = i_cont
    if i_cont is not None:
        out.checks.append(_check("motor_rms_current", i_rms, i_cont * derate, "A",
                                 f"continuous current at the mean speed x derating {derate:.3g} ({env.derating})"))
    if elec.peak_current is not None:
        out.checks.append(_check("motor_peak_current", i_peak, elec.peak_current, "A"))
    # envelope at the supply voltage
    if elec.has_voltage_model and bus is not None:
        envelope_source = "electrical"
        out.checks.append(_voltage_check(t_m, w, kt, elec, drive, bus, sat, torque_margin, motor.peak_torque, out))
    out.motor["envelope_source"] = envelope_source
    # winding temperature
    out.motor.update(_thermal(duty, current, elec, derate, out))
    if drive is not None:
        out.drive = _drive_block(drive, duty, current, i_rms, i_peak)
    out.regen = _regen_block(duty, t_m, current, elec, drive, bus)
    return out


def _voltage_check(t_m: Array, w: Array, kt: float, elec: MotorElectrical, drive: DriveData | None, bus: float,
                   sat: motor_electrical.Saturation | None, torque_margin: float, motor_peak: float,
                   out: ElectricalAnswer) -> Check:
    """Every sample's torque (x margin) against the voltage- and current-limited curve at its speed."""
    assert elec.ke is not None and elec.resistance is not None and elec.inductance is not None
    assert elec.pole_pairs is not None
    peaks = [x for x in (elec.peak_current, None if drive is None else drive.peak_current) if x is not None]
    conts = [x for x in (elec.continuous_current, None if drive is None else drive.continuous_current) if x is not None]
    i_p = min(peaks) if peaks else math.inf
    i_c = min(conts) if conts else i_p
    generating = t_m * w < 0.0
    args = (kt, elec.ke, elec.resistance, elec.inductance, elec.pole_pairs, bus, i_c, i_p)
    mot = motor_electrical.torque_speed_curve(np.abs(w), *args, saturation=sat).peak[0]
    gen = motor_electrical.torque_speed_curve(np.abs(w), *args, saturation=sat, generating=True).peak[0]
    # the datasheet peak torque stays a limit of its own (the curve knows only the current limits)
    available = np.minimum(np.where(generating, gen, mot), motor_peak)
    required = np.abs(t_m) * torque_margin
    with np.errstate(divide="ignore", invalid="ignore"):
        margins = np.where(required > 0, available / np.where(required > 0, required, 1.0) - 1.0, np.inf)
    k = int(np.argmin(margins))
    w_max = float(np.max(np.abs(w))) if w.size else 0.0
    speeds = np.linspace(0.0, max(w_max, float(motor_electrical.no_load_speed(elec.ke, bus))) * 1.05, 101)
    curve = motor_electrical.torque_speed_curve(speeds, *args, saturation=sat)
    out.curve = {"speed_rad_s": speeds.tolist(),
                 "continuous_torque_Nm": np.minimum(curve.continuous[0], motor_peak).tolist(),
                 "peak_torque_Nm": np.minimum(curve.peak[0], motor_peak).tolist(), "dc_bus_voltage_V": bus}
    out.motor["no_load_speed_rpm"] = float(motor_electrical.no_load_speed(elec.ke, bus)) * 60.0 / (2.0 * math.pi)
    return _check("peak_torque_at_supply_voltage", float(required[k]), float(available[k]), "N*m",
                  f"at {abs(float(w[k])) * 60.0 / (2.0 * math.pi):.0f} rpm, {bus:.0f} V DC bus")


def _thermal(duty: DutyCycle, current: Array, elec: MotorElectrical, derate: float,
             out: ElectricalAnswer) -> dict[str, Any]:
    """Winding rise: periodic solution when R, tau, rated rise and I_0 are known; RMS rule without tau."""
    keys: dict[str, Any] = {"winding_temperature_rise_K": None}
    i0, rise_n, r = elec.continuous_current, elec.rated_rise, elec.resistance
    if i0 is None or rise_n is None:
        return keys
    allowed = rise_n * derate**2
    i_rms = float(drive_overload.rms_current(current, duty.weights, duty.period))
    mean = float(motor_thermal.steady_rise(i_rms, i0, rise_n))
    peak = mean
    if r is not None and elec.thermal_time_constant is not None:
        r_th = float(motor_thermal.thermal_resistance(rise_n, i0, r))
        per = motor_thermal.periodic_rise(duty.t, np.asarray(regen.copper_loss(current, r)), r_th,
                                          elec.thermal_time_constant)
        mean, peak = float(per.mean), float(per.peak)
        keys["winding_time_to_95_percent_s"] = float(per.time_to_95)
    keys.update({"winding_temperature_rise_K": peak, "winding_mean_rise_K": mean,
                 "winding_allowed_rise_K": allowed})
    out.checks.append(_check("winding_temperature_rise", peak, allowed, "K",
                             f"rated rise {rise_n:g} K x derating^2"))
    return keys


def _drive_block(drive: DriveData, duty: DutyCycle, current: Array, i_rms: float, i_peak: float) -> DriveAnswer:
    """The drive's current checks over the cycle (RMS, peak and, with a stated peak time, the I^2 t accumulator)."""
    checks = [_check("drive_rms_current", i_rms, drive.continuous_current, "A"),
              _check("drive_peak_current", i_peak, drive.peak_current, "A")]
    setpoint = i2t_peak = None
    if drive.peak_time is not None:
        setpoint = float(drive_overload.i2t_setpoint(drive.peak_current, drive.continuous_current, drive.peak_time))
        per = drive_overload.i2t_periodic(duty.t, current, drive.continuous_current, setpoint)
        i2t_peak = float(per.peak)
        checks.append(_check("drive_i2t", i2t_peak, setpoint, "A^2*s",
                             "Copley I2T accumulator, periodic steady state"))
    return DriveAnswer("given motor", id=drive.name, vendor=drive.vendor,
                       continuous_current_A=drive.continuous_current, peak_current_A=drive.peak_current,
                       i2t_setpoint_A2s=setpoint, i2t_peak_A2s=i2t_peak, ok=all(c.ok for c in checks),
                       checks=tuple(c.to_dict() for c in checks))


def _regen_block(duty: DutyCycle, t_m: Array, current: Array, elec: MotorElectrical, drive: DriveData | None,
                 bus: float | None) -> Regen:
    """The regeneration block of the motor's cycle with its drive (``physics.regen.regen_cycle``)."""
    p_cu = regen.copper_loss(current, elec.resistance) if elec.resistance is not None else np.zeros_like(current)
    e_c, basis = 0.0, "none"
    if drive is not None and drive.absorbable_energy is not None:
        e_c, basis = drive.absorbable_energy, "published"
    elif drive is not None and None not in (drive.bus_capacitance, drive.bus_max_voltage) and bus is not None:
        assert drive.bus_capacitance is not None and drive.bus_max_voltage is not None
        e_c, basis = float(regen.capacitor_energy(drive.bus_capacitance, drive.bus_max_voltage, bus)), "capacitance"
    r = regen.regen_cycle(duty.t, t_m * duty.omega, p_cu, e_c, weights=duty.weights, period=duty.period)
    r_min = None if drive is None else drive.min_resistance
    r_max = None
    if drive is not None and drive.regen_on_voltage is not None:
        r_max = float(regen.resistor_max_resistance(drive.regen_on_voltage, r.resistor_peak_power))
    builtin = None
    if (drive is not None and drive.builtin_average_power is not None and drive.builtin_resistance is not None
            and drive.regen_on_voltage is not None):
        builtin = bool(regen.builtin_resistor_sufficient(r.resistor_average_power, r.resistor_peak_power,
                                                         drive.builtin_average_power, drive.builtin_resistance,
                                                         drive.regen_on_voltage,
                                                         math.nan if r_min is None else r_min))
    return Regen(
        shaft_energy_per_cycle_J=r.shaft_energy,
        copper_loss_in_events_J=float(r.events.copper_energy.sum()),
        energy_per_cycle_J=r.energy,
        capacitor_energy_per_event_J=e_c,
        capacitor_basis=basis,
        capacitor_absorbed_J=r.capacitor_absorbed,
        resistor_energy_per_cycle_J=r.resistor_energy,
        resistor_peak_power_W=r.resistor_peak_power,
        resistor_average_power_W=r.resistor_average_power,
        resistor_min_ohm=r_min,
        resistor_max_ohm=None if r_max is None or math.isinf(r_max) else r_max,
        resistor_needed=r.resistor_energy > 0.0,
        builtin_resistor_sufficient=builtin,
        events=tuple(RegenEvent(float(a), float(b), float(e), float(q))
                     for a, b, e, q in zip(r.events.t_start, r.events.t_stop, r.events.bus_energy,
                                           r.events.resistor_energy, strict=True)),
    )
