"""The motor holding brake in the catalog selection (docs/checks.md, "Motor holding brake")."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from drivetrain import catalog
from drivetrain.axis.model import Margins, load_axis, parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.physics.brake import BRAKE_SAFETY_FACTOR, held_torque
from drivetrain.sizing import selection
from drivetrain.sizing.motor_brake import holding_need
from drivetrain.sizing.pipeline import size

ROOT = Path(__file__).resolve().parents[2]


def _vertical(mass: float = 20.0, **select: Any) -> dict[str, Any]:
    """A vertical ball-screw axis (10 mm lead, screw eta 0.9 both ways), selected direct from the HC motors."""
    return {"axis": "z", "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.5 m",
                                       "incline": "90 deg", "efficiency": 0.9, "load": {"mass": f"{mass} kg"}},
            "profile": [{"move": "100 mm", "time": "0.5 s"}, {"dwell": "0.5 s"}, {"move": "-100 mm", "time": "0.5 s"},
                        {"dwell": "0.5 s"}],
            "motor": {"select": {"vendor": "Mitsubishi Electric", "gearbox": "none", **select}}}


def test_held_torque_works_the_load_back_through_every_stage() -> None:
    """F / i x eta' per stage (the load drives back); a self-locking stage holds it alone."""
    lead = 0.01
    f = 20.0 * 9.80665
    assert held_torque(f, [(2 * math.pi / lead, 0.9)]) == pytest.approx(f * lead / (2 * math.pi) * 0.9)
    assert held_torque(f, [(2 * math.pi / lead, 0.9), (3.0, 0.95)]) == pytest.approx(
        f * lead / (2 * math.pi) * 0.9 / 3.0 * 0.95)
    assert held_torque(f, [(2 * math.pi / lead, -0.2)]) == 0.0
    assert Margins().brake == BRAKE_SAFETY_FACTOR == 1.5


def test_a_vertical_axis_needs_a_brake_a_horizontal_one_does_not() -> None:
    ax = parse_axis(_vertical())
    need = holding_need(ax, duty_cycle(ax))
    assert need.needed and need.torque == pytest.approx(20.0 * 9.80665 * 0.01 / (2 * math.pi) * 0.9, rel=1e-9)
    flat = _vertical()
    flat["mechanism"]["incline"] = "0 deg"
    ax = parse_axis(flat)
    assert not holding_need(ax, duty_cycle(ax)).needed
    flat["profile"][1]["holding"] = "brake"
    ax = parse_axis(flat)
    need = holding_need(ax, duty_cycle(ax))
    assert need.needed and need.torque == 0.0 and "holding: brake" in need.why


def test_every_candidate_of_a_vertical_axis_is_checked_on_its_brake() -> None:
    """Required = static torque at the motor x 1.5; available = the brake variant's holding torque;
    unknown where the catalog lacks it, never a pass; the with-brake inertia in the duty cycle."""
    ax = parse_axis(_vertical())
    duty = duty_cycle(ax)
    spec = ax.spec.motor.select
    sel = selection.select(ax, duty, spec, ax.spec.motor.margins)
    need = 20.0 * 9.80665 * 0.01 / (2 * math.pi) * 0.9 * 1.5
    c = sel.ranking.candidates
    motors = sel.ranking.motors
    d = c.details(np.arange(len(c.motor)))
    held = motors.brake_holding_torque[c.motor]
    assert np.allclose(d.required["motor_brake"], need, rtol=1e-12)
    known = ~np.isnan(held)
    assert known.any() and (~known).any()
    assert np.array_equal(np.isnan(d.margin["motor_brake"]), ~known)  # unknown, never a pass
    assert np.allclose(d.available["motor_brake"][known], held[known])
    assert "motor_brake" in sel.summary.unknown_by_check
    # the listed candidates say so, with the variant's order code
    first = sel.listed[0]
    names = [ch.name for ch in first.checks]
    assert "motor_brake" in names and first.brake is not None


def test_the_brake_variants_rotor_inertia_is_in_its_duty_cycle() -> None:
    """Yaskawa SGM7J rows give the with-brake inertia (motor_brakes.csv): the candidates use it, in the
    RMS torque and the inertia ratio; a motor without it keeps its own."""
    ax = parse_axis(_vertical(vendor="Yaskawa"))
    sel = selection.select(ax, duty_cycle(ax), ax.spec.motor.select, ax.spec.motor.margins)
    motors = sel.ranking.motors
    cat = catalog.motors(vendor="Yaskawa")
    assert list(motors.ids) == list(cat.ids)
    j_b = cat.rotor_inertia_brake
    assert (~np.isnan(j_b)).any() and np.isnan(j_b).any()
    assert np.array_equal(motors.rotor_inertia, np.where(np.isnan(j_b), cat.rotor_inertia, j_b))
    c = sel.ranking.candidates
    k = int(np.flatnonzero(motors.ids[c.motor] == "SGM7J-02A")[0])
    assert sel.ranking.candidates.details([k]).inertia_ratio[0] == pytest.approx(
        ax.load_inertia / float(j_b[list(cat.ids).index("SGM7J-02A")]), rel=1e-12)
    listed = next(x for x in sel.listed if x.motor.startswith("SGM7J")) if any(
        x.motor.startswith("SGM7J") for x in sel.listed) else None
    if listed is not None:
        assert listed.brake is not None and listed.brake.rotor_inertia_kgm2 is not None


def test_a_brake_too_weak_for_the_load_fails_the_candidate_with_the_reason() -> None:
    """HC52's brake holds 8.3 N*m (motor_brakes.csv): a 600 kg load on a 10 mm lead needs
    600 g 0.01 / 2 pi x 0.9 x 1.5 = 12.6 N*m at the brake."""
    ax = parse_axis(_vertical(600.0))
    duty = duty_cycle(ax)
    sel = selection.select(ax, duty, ax.spec.motor.select, ax.spec.motor.margins)
    c, motors = sel.ranking.candidates, sel.ranking.motors
    k = int(np.flatnonzero(motors.ids[c.motor] == "HC52")[0])
    d = c.details([k])
    assert d.available["motor_brake"][0] == pytest.approx(8.3)
    assert d.required["motor_brake"][0] == pytest.approx(600 * 9.80665 * 0.01 / (2 * math.pi) * 0.9 * 1.5)
    assert d.margin["motor_brake"][0] < 0.0
    assert c.failed[k] & (1 << list(selection.CHECK_UNITS).index("motor_brake"))


def test_the_hoist_selects_a_brake_variant_and_says_what_its_brake_must_hold() -> None:
    """examples/hoist.yaml holds a dwell on the brake and a 50 kg unbalance: its selection checks the
    brake (required 50 g 0.1 x 0.95 (hoist) / 15 x 0.98 (the helical default) x 1.5) and never passes an
    unknown brake as a pass."""
    result = size(load_axis(ROOT / "examples" / "hoist.yaml"))
    sel = result.selection.selected
    brake = sel.check("motor_brake")
    assert brake is not None
    assert brake.required == pytest.approx(50 * 9.80665 * 0.1 * 0.95 / 15 * 0.98 * 1.5, rel=1e-6)
    assert brake.status in ("pass", "unknown")
    if brake.status == "unknown":
        assert "motor_brake" in sel.unknown and sel.status == "unknown" and "holding torque" in str(brake.note)
    assert sel.brake is not None


def test_a_horizontal_axis_has_no_brake_check() -> None:
    """Nothing to hold: no motor_brake check, no count of it, the plain rotor inertia."""
    flat = _vertical()
    flat["mechanism"]["incline"] = "0 deg"
    ax = parse_axis(flat)
    sel = selection.select(ax, duty_cycle(ax), ax.spec.motor.select, ax.spec.motor.margins)
    assert "motor_brake" not in sel.summary.failures_by_check
    assert all(ch.name != "motor_brake" for ch in sel.listed[0].checks) and sel.listed[0].brake is None
    cat = catalog.motors(vendor="Mitsubishi Electric")
    assert np.array_equal(sel.ranking.motors.rotor_inertia, cat.rotor_inertia)


def test_an_axis_with_its_own_brake_needs_no_motor_brake() -> None:
    """A `brake` element in transmission: holds the load (brake_check judges it): the motor is not its brake
    variant and has no motor_brake check."""
    d = _vertical()
    d["transmission"] = [{"type": "brake", "holding_torque": "2 N*m"}]
    ax = parse_axis(d)
    assert not holding_need(ax, duty_cycle(ax)).needed
    res = size(ax)
    assert all(ch.name != "motor_brake" for ch in res.selection.selected.checks)
    assert res.brake_check.ok
