"""A motor onto a gearbox: the adapter is compared where the catalog draws or names it, unknown where it
does not; T2B at a cycle rate that needs the shock factor is unknown until it is given (docs/checks.md,
"Mechanical fit" and "Gearbox ratings")."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from drivetrain import catalog
from drivetrain.axis.model import Margins, parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing import selection
from drivetrain.sizing.checks import adapter_arrays, adapter_margin, mechanical_fit
from drivetrain.sizing.pipeline import size

NAN = math.nan


def test_a_gearbox_without_its_adapter_does_not_take_the_motor_by_default() -> None:
    """Shaft into the bore, but neither the drawn adapters nor the adapter's flange are known: unknown."""
    assert np.isnan(mechanical_fit(0.035, 0.18, 0.1143, 0.06, NAN, NAN, NAN, bolt_circle=0.2))
    # the adapter's pilot alone can fail the pair (a mismatch), not pass it
    assert np.isnan(mechanical_fit(0.035, 0.18, 0.1143, 0.06, NAN, NAN, 0.1143, bolt_circle=0.2))
    assert mechanical_fit(0.035, 0.18, 0.1143, 0.06, NAN, NAN, 0.110, bolt_circle=0.2) < 0.0


def test_the_drawn_adapters_decide_the_fit() -> None:
    """One drawn adapter must take the motor's shaft, pilot and bolt circle (a square pattern of side s as
    a circle of s sqrt 2)."""
    ad = adapter_arrays(["14/50/70/M4 19/70/90/M5", "14/73/sq69.6/M5", ""])
    assert ad[1, 0, 2] == pytest.approx(0.0696 * math.sqrt(2.0)) and np.isnan(ad[2]).all()
    # a 60 mm-flange motor (14 mm shaft, 50 mm pilot, 70 mm bolt circle) takes the first adapter
    assert adapter_margin(0.014, 0.05, 0.07, ad[0]) >= 0.0
    # a 130 mm motor (22 mm shaft, 110 mm pilot, 145 mm circle) takes none: fails
    assert adapter_margin(0.022, 0.11, 0.145, ad[0]) < 0.0
    # its bolt circle unknown: cannot be judged
    assert np.isnan(adapter_margin(0.014, 0.05, NAN, ad[0]))
    # a NEMA 34 motor (73 mm pilot, 98.4 mm circle) on the square-pattern adapter
    assert adapter_margin(0.014, 0.073, 0.0984, ad[1]) >= 0.0
    full = mechanical_fit(0.022, 0.13, 0.11, 0.022, NAN, NAN, NAN, bolt_circle=0.145, adapters=ad[0])
    assert full < 0.0


def _table(gearbox: dict[str, Any] | None = None, period: str = "1.5 s", **select: Any) -> dict[str, Any]:
    return {"axis": "table", "mechanism": {"type": "rotary", "load": {"inertia": "0.2 kg*m^2"}},
            "profile": [{"move": "90 deg", "time": "0.5 s"}, {"dwell": period}],
            "transmission": [gearbox] if gearbox else [],
            "motor": {"select": {"gearbox": "only", **select}} if not gearbox else {
                "rated_torque": "3 N*m", "peak_torque": "9 N*m", "rated_speed": "3000 rpm", "max_speed": "6000 rpm",
                "inertia": "3 kg*cm^2"}}


def test_a_catalog_pair_without_the_adapter_is_unknown_and_says_what_to_give() -> None:
    """Beckhoff AG2400 rows give the clamping-hub bore only: every geared candidate's fit is unknown
    (never passed on the bore alone) and the answer names the adapter as what to give."""
    ax = parse_axis(_table(gearbox_series="AG2400 TP"))
    sel = selection.select(ax, duty_cycle(ax), ax.spec.motor.select, ax.spec.motor.margins)
    c = sel.ranking.candidates
    geared = c.gearbox(np.arange(len(c.motor))) >= 0
    bit = 1 << list(selection.CHECK_UNITS).index("mechanical_fit")
    fails = (c.failed & bit) != 0
    assert np.all(((c.unknown & bit) != 0)[geared & ~fails])
    row = next(r for r in sel.listed if r.gearbox is not None and "mechanical_fit" in r.unknown)
    fit = next(ch for ch in row.checks if ch.name == "mechanical_fit")
    assert "motor adapter" in fit.note


def test_a_catalog_pair_with_drawn_adapters_is_judged_on_them() -> None:
    """G+ GPB142 draws one adapter, 35/114.3/200 mm: a 180 mm APM-FF motor (35 mm shaft, 114.3 mm pilot,
    200 mm circle) fits it; a 130 mm one (110 mm pilot) does not, with the reason."""
    motors, gb = catalog.motors(), catalog.gearboxes(series="GPB")
    ad = adapter_arrays(gb.input_adapters)
    r = list(gb.ids).index("GPB142-L1-i5")
    assert gb.input_adapters[r] == "35/114.3/200/M12"
    big = list(motors.ids).index("APM-FF30A")
    assert mechanical_fit(motors.shaft_diameter[big], motors.flange[big], motors.pilot_diameter[big],
                          gb.input_bore_max[r], gb.input_bore_min[r], gb.input_flange[r], gb.input_pilot[r],
                          bolt_circle=motors.bolt_circle[big], adapters=ad[r]) >= 0.0
    ax = parse_axis(_table(gearbox_series="GPB"))
    sel = selection.select(ax, duty_cycle(ax), ax.spec.motor.select, ax.spec.motor.margins)
    c = sel.ranking.candidates
    bit = 1 << list(selection.CHECK_UNITS).index("mechanical_fit")
    pilots = sel.ranking.motors.pilot_diameter[c.motor]
    rows = c.gearbox(np.arange(len(c.motor)))
    on_142 = np.isin(rows, np.flatnonzero(np.char.startswith(sel.ranking.gearboxes.ids.astype(str), "GPB142-L1")))
    wrong = on_142 & (np.abs(pilots - 0.1143) > 0.5e-3)
    assert wrong.any()
    assert np.all((c.failed[wrong] & bit) != 0)
    k = int(np.flatnonzero(wrong)[0])
    from drivetrain.sizing.reasons import candidate_answer

    row = candidate_answer(c, k, sel.ranking.motors, sel.ranking.gearboxes, None)
    assert any("no drawn adapter takes the motor" in f for f in row.failures)


def test_t2b_at_a_cycle_rate_that_needs_the_shock_factor_is_unknown_on_the_catalog_path() -> None:
    """2 s cycles (1800/h) above the 1000/h T2B holds for: without motor.margins.gearbox_shock_factor every
    geared candidate's T2B is unknown (never a pass); with it, judged."""
    ax = parse_axis(_table(period="1.5 s", gearbox_series="AG2400 TP"))
    duty = duty_cycle(ax)
    assert 3600.0 / duty.period > 1000.0
    bit = 1 << list(selection.CHECK_UNITS).index("gearbox_peak_torque")
    sel = selection.select(ax, duty, ax.spec.motor.select, Margins())
    c = sel.ranking.candidates
    geared = c.gearbox(np.arange(len(c.motor))) >= 0
    assert geared.any() and np.all((c.unknown[geared] & bit) != 0) and not np.any(c.failed[geared] & bit)
    judged = selection.select(ax, duty, ax.spec.motor.select, Margins(gearbox_shock_factor=1.3))
    jc = judged.ranking.candidates
    assert not np.any(jc.unknown[jc.gearbox(np.arange(len(jc.motor))) >= 0] & bit)


def test_t2b_at_a_cycle_rate_that_needs_the_shock_factor_is_unknown_on_the_transmission_path() -> None:
    gearbox = {"type": "gearbox", "ratio": 5, "max_torque": "200 N*m", "rated_torque": "100 N*m"}
    res = size(parse_axis(_table(gearbox=gearbox)))
    t2b = next(c for c in res.gearbox_checks.checks if c.name == "gearbox_peak_torque")
    assert t2b.status == "unknown" and t2b.margin is None and "gearbox_shock_factor" in (t2b.note or "")
    slow = size(parse_axis(_table(gearbox=gearbox, period="5 s")))
    t2b = next(c for c in slow.gearbox_checks.checks if c.name == "gearbox_peak_torque")
    assert t2b.status == "pass"


def _gantry(**belt: Any) -> dict[str, Any]:
    mech: dict[str, Any] = {"type": "timing_belt", "diameter": "60 mm", "load": {"mass": "30 kg"}}
    if belt:
        mech["belt"] = belt
    return {"axis": "gantry", "mechanism": mech,
            "profile": [{"move": "1 m", "time": "0.8 s"}, {"dwell": "0.5 s"}],
            "motor": {"select": {"gearbox": "only", "gearbox_series": "GPB"}}}


def test_a_pulley_on_the_gearbox_output_is_checked_against_f2r() -> None:
    """The belt's pull with the default pretension (the largest pull) on one span: the pulley shaft
    carries sqrt(T_t^2 + T_s^2 + 2 T_t T_s) = T_t + T_s at 180 deg wrap; against each row's F2r."""
    from drivetrain.sizing.mechanism_checks import axial_force, output_loads

    ax = parse_axis(_gantry())
    duty = duty_cycle(ax)
    radial, axial = output_loads(ax, duty)
    peak = float(np.max(np.abs(axial_force(ax, duty))))
    assert axial == 0.0 and radial == pytest.approx(3.0 * peak, rel=1e-9)  # tight 2 x pull, slack = pull
    sel = selection.select(ax, duty, ax.spec.motor.select, ax.spec.motor.margins)
    c, gb = sel.ranking.candidates, sel.ranking.gearboxes
    ks = np.arange(len(c.motor))
    d = c.details(ks)
    rows = c.gearbox(ks)
    f2r = gb.max_radial_load[rows]
    known = ~np.isnan(f2r)
    assert known.any()
    np.testing.assert_allclose(d.required["gearbox_radial_load"], radial)
    np.testing.assert_allclose(d.margin["gearbox_radial_load"][known], f2r[known] / radial - 1.0)
    assert np.all(np.isnan(d.margin["gearbox_radial_load"][~known]))
    bit = 1 << list(selection.CHECK_UNITS).index("gearbox_radial_load")
    small = known & (f2r < radial)
    assert np.all((c.failed[small] & bit) != 0)


def test_an_output_load_not_modelled_is_unknown() -> None:
    """A rotary table on the gearbox output: its loads are not modelled, so F2r and F2a cannot be judged."""
    ax = parse_axis(_table(gearbox_series="AG2250 PLE"))
    sel = selection.select(ax, duty_cycle(ax), ax.spec.motor.select, ax.spec.motor.margins)
    row = next(r for r in sel.listed if r.gearbox is not None)
    f2r = next(ch for ch in row.checks if ch.name == "gearbox_radial_load")
    assert f2r.status == "unknown" and "not modelled" in f2r.note
