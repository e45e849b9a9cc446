"""Catalog selection: every motor against every ratio, checked by hand on one case per family."""

from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drivetrain import catalog
from drivetrain.axis.model import load_axis, parse_axis
from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.errors import InputError
from drivetrain.physics.stage import Stage, torque_in
from drivetrain.sizing.checks import adapter_arrays
from drivetrain.sizing.pipeline import size

EXAMPLES = Path(__file__).parents[2] / "examples"
FAMILIES = ["ball_screw", "belt", "rack_pinion", "rotary", "hoist", "chain", "conveyor", "roll", "lead_screw",
            "custom"]


def _rotor(cand: dict) -> float:
    """The candidate's rotor inertia: its brake variant's where the axis needs a brake and the catalog gives it."""
    m = catalog.get(cand.motor)
    braked = cand.brake is not None and m["rotor_inertia_brake_kgm2"] is not None
    return m["rotor_inertia_brake_kgm2"] if braked else m["rotor_inertia_kgm2"]


def motor_torque(result, cand: dict) -> tuple[np.ndarray, float]:
    """Motor torque of a candidate computed directly from the duty cycle (no closed forms)."""
    duty = result.duty
    j = _rotor(cand)
    ratio, eff = 1.0, 1.0
    if cand.gearbox:
        g = catalog.get(cand.gearbox)
        ratio, eff, j = g["ratio"], g["efficiency"], j + (g["inertia_input_kgm2"] or 0.0)
    st = Stage("g", "gearbox", ratio=ratio, efficiency=eff, back_efficiency=eff)
    t_in, _ = torque_in(st, duty.torque, duty.external, duty.omega * ratio, duty.alpha * ratio,
                        np.asarray(duty.samples.direction, float), result.axis.efficiency_model)
    return np.where(duty.braked, 0.0, t_in + j * duty.alpha * ratio), j


@pytest.mark.parametrize("family", FAMILIES)
def test_selected_passes_and_next_smaller_fails(family: str) -> None:
    res = size(EXAMPLES / f"{family}.yaml")
    sel = res.selection
    assert sel is not None and sel.passing > 0
    best = sel.selected
    assert best.ok and all(c.ok for c in best.checks)
    # Hand check of the closed forms: RMS and peak of the motor torque, and the inertia ratio.
    t_m, j_total = motor_torque(res, best)
    checks = {c.name: c for c in best.checks}
    rms = float(np.sqrt(np.sum(res.duty.weights * t_m**2) / res.duty.period))
    assert best.rms_torque_Nm == pytest.approx(rms, rel=1e-9)
    assert best.peak_torque_Nm == pytest.approx(float(np.max(np.abs(t_m))), rel=1e-9)
    j_m = _rotor(best)
    ratio = best.ratio
    assert checks["inertia_ratio"].required == pytest.approx(
        (res.duty.load_inertia / ratio**2 + (j_total - j_m)) / j_m, rel=1e-9)
    speed_margin = res.axis.spec.motor.margins.speed
    assert checks["max_speed"].required == pytest.approx(res.metrics.max_speed_rpm * ratio * speed_margin,
                                                            rel=1e-9)
    nxt = sel.next_smaller
    if nxt is not None:
        # (or was passed over for its drive: drive_select.attach_drives)
        # or passes with a fit or brake not known where the selected one's is (ranked after: selection.ranked)
        assert not nxt.ok or nxt.failed.startswith("drive:") or (
            {"motor_brake", "mechanical_fit"} & (set(nxt.unknown) - set(best.unknown)))
        if not nxt.ok:
            name = nxt.failed.split(":")[0]
            assert name in {c.name for c in nxt.checks if not c.ok}
        assert nxt.rated_power_W <= best.rated_power_W
    else:  # nothing smaller exists: the selected motor is the catalog's smallest
        powers = catalog.motors(kind="ac_servo").rated_power
        assert best.rated_power_W == np.nanmin(powers)


def test_next_smaller_motor_can_reach_the_cycle_speed() -> None:
    """The shipped catalog holds low-speed direct-drive motors (Yaskawa SGM7D, 360 r/min max) smaller than the
    ball-screw example's pick: the next smaller motor named is one that reaches the cycle's speed, so its failing
    checks say how tight the pick is (a motor that only fails max_speed would say nothing)."""
    sel = size(EXAMPLES / "ball_screw.yaml").selection
    nxt = sel.next_smaller
    checks = {c.name: c for c in nxt.checks}
    assert checks["max_speed"].status == "pass"
    assert {c.name for c in nxt.checks if c.status == "fail"} & {"rms_torque", "peak_torque", "inertia_ratio"}
    assert nxt.rated_power_W < sel.selected.rated_power_W


def test_every_motor_against_every_ratio() -> None:
    res = size(EXAMPLES / "ball_screw.yaml")
    n_m = len(catalog.motors(kind="ac_servo"))
    n_g = len(catalog.gearboxes(kind="servo_gearbox"))
    assert res.selection.evaluated == n_m * (n_g + 1)


def test_json_candidates_follow_the_design() -> None:
    out = size(EXAMPLES / "ball_screw.yaml").to_dict()
    cand = out["candidates"][0]
    for key in ("motor", "gearbox", "ratio", "inertia_ratio", "ok", "checks"):
        assert key in cand
    assert {"name", "required", "available", "margin", "ok"} <= set(cand["checks"][0])
    assert any(not c["ok"] and c["failed"] for c in out["candidates"])


def test_bad_vendor_names_the_filter_and_lists_vendors() -> None:
    ax = load_axis(EXAMPLES / "ball_screw.yaml").raw
    bad = {**ax, "motor": {"select": {"vendor": "Acme"}}}
    with pytest.raises(InputError) as err:
        size(parse_axis(bad))
    assert err.value.field == "motor.select.vendor"
    assert "Yaskawa" in str(err.value)


def test_empty_result_says_what_to_relax() -> None:
    ax = load_axis(EXAMPLES / "ball_screw.yaml").raw
    heavy = {**ax, "mechanism": {**ax["mechanism"], "load": {"mass": "20000 kg"}},
             "motor": {"select": {"gearbox": "none"}, "margins": {"inertia_ratio": 10}}}
    res = size(parse_axis(heavy))
    assert not res.ok
    advice = res.selection.advice
    assert "no candidate passes" in advice and ("inertia" in advice or "short by" in advice)


def test_explain_a_rejected_motor() -> None:
    res = size(EXAMPLES / "ball_screw.yaml")
    text = res.explain("HG-MR43")
    assert "HG-MR43" in text and "inertia_ratio" in text
    with pytest.raises(InputError):
        res.explain("NOPE-123")


def test_optimal_ratio_of_a_pure_inertia_is_the_inertia_match() -> None:
    """alpha_L = T i / (J_M i^2 + J_L) is largest at i = sqrt(J_L / J_M): minimum RMS for pure inertia."""
    res = size({"mechanism": {"type": "custom", "inertia": 0.05},
                "profile": [{"move": "90 deg", "time": 0.3}, {"dwell": 0.2}],
                "motor": {"select": {"gearbox": "none"}, "margins": {"inertia_ratio": 1000}}})
    opt = res.selection.optimal_ratio
    assert opt.min_rms_ratio == pytest.approx(opt.inertia_match_ratio, rel=1e-3)


def test_datasheet_curve_replaces_the_derived_envelope() -> None:
    """A motor with speed-torque points is checked against them and its checks are not approximate."""
    from drivetrain.catalog.curves import Curve
    from drivetrain.sizing.motor_fit import MotorArrays, demand, fit_motors

    res = size(EXAMPLES / "ball_screw.yaml")
    d = res.duty
    dm = demand(d.omega, d.alpha, d.torque, d.weights, d.period, d.load_inertia)
    one = np.ones(1)
    curve = Curve.from_points([(0.0, 1.0, 3.0), (700.0, 1.0, 3.0)])  # flat 1 N m / 3 N m to 700 rad/s
    base = {"inertia": 4e-5 * one, "rated_torque": 1.3 * one, "peak_torque": 4.5 * one, "rated_speed": 314.16 * one,
            "max_speed": 628.3 * one, "stall_torque": np.full(1, np.nan), "approximate": np.array([True])}
    derived = fit_motors(dm, MotorArrays(**base))
    measured = fit_motors(dm, MotorArrays(**{**base, "approximate": np.array([False])}, curves=(curve,)))
    assert derived.available["rms_torque"][0] == pytest.approx(1.3)
    assert measured.available["rms_torque"][0] == pytest.approx(1.0)
    assert measured.available["peak_torque"][0] == pytest.approx(3.0)
    assert not measured.checks(0)[0].approximate and derived.checks(0)[0].approximate


@pytest.mark.parametrize(("axis_file", "curves"), [
    (EXAMPLES / "ball_screw.yaml", False), (EXAMPLES / "lead_screw.yaml", False),
    (Path(__file__).parents[1] / "axes" / "lecture_two_inertias.yaml", False), (EXAMPLES / "ball_screw.yaml", True),
    (EXAMPLES / "belt_gantry.yaml", False)])
def test_compiled_selection_matches_the_reference_checks(axis_file: Path, curves: bool) -> None:
    """Every candidate of the whole shipped catalog: the compiled pass equals fit_motors (numpy) per
    gearbox group, checks.mechanical_fit and checks.gearbox_ratings per pair, and each candidate's
    worst margin, failure bits and unknown bits agree with its checks (relative tolerance 1e-9: the
    same operations in another order). With ``curves``, every third motor gets speed-torque curve
    points (the datasheet path)."""
    import dataclasses

    from drivetrain.axis.model import Margins
    from drivetrain.catalog.curves import Curve
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.physics.averages import cubic_mean
    from drivetrain.sizing.checks import gearbox_ratings, mechanical_fit, shock_factor
    from drivetrain.sizing.motor_fit import MotorArrays, demand, fit_motors, scaled
    from drivetrain.sizing.selection import CHECK_UNITS, evaluate

    axis = load_axis(axis_file)
    duty = duty_cycle(axis, 17)
    margins = axis.spec.motor.margins if axis.spec.motor else Margins()
    motors, gb = catalog.motors(), catalog.gearboxes(kind="servo_gearbox")
    if curves:  # a curve a little under the derived envelope, falling to zero at the max speed
        rows = [Curve.from_points([(0.0, 0.9 * t, 2.5 * t), (0.5 * w, 0.8 * t, 2.0 * t), (w, 0.0, 0.5 * t)])
                if k % 3 == 0 and np.isfinite(w) else None
                for k, (t, w) in enumerate(zip(motors.rated_torque, motors.max_speed, strict=True))]
        motors = dataclasses.replace(motors, curves=tuple(rows), has_curve=np.array([r is not None for r in rows]))
    c = evaluate(axis, duty, motors, gb, margins)
    assert len(c.motor) == len(motors) * (len(gb) + 1)
    every = np.arange(len(c.motor))
    d = c.details(every)
    arrays = MotorArrays(inertia=motors.rotor_inertia, rated_torque=motors.rated_torque,
                         peak_torque=motors.peak_torque, rated_speed=motors.rated_speed, max_speed=motors.max_speed,
                         stall_torque=motors.stall_torque, approximate=~motors.has_curve, curves=tuple(motors.curves))
    direction = np.asarray(duty.samples.direction, dtype=float)
    rows = c.gearbox(every)
    has_all = rows >= 0
    g_all = np.where(has_all, rows, 0)
    eff = np.where(has_all, np.nan_to_num(gb.efficiency[g_all], nan=1.0), 1.0)
    checked = np.zeros(len(c.motor), dtype=bool)
    slow = np.zeros(len(c.motor), dtype=bool)
    shock = shock_factor(duty.period, margins.gearbox_shock_factor)
    for ratio, e in {(float(r), float(x)) for r, x in zip(c.ratio(every), eff, strict=True)}:
        k = np.flatnonzero((c.ratio(every) == ratio) & (eff == e))
        g = rows[k]
        has = g >= 0
        gi = np.where(has, g, 0)
        stage = Stage("g", "gearbox", ratio=1.0, efficiency=e, back_efficiency=e)
        t_in, _ = torque_in(stage, duty.torque, duty.external, duty.omega, duty.alpha, direction,
                            axis.efficiency_model)
        dm = scaled(demand(duty.omega, duty.alpha, t_in, duty.weights, duty.period, duty.load_inertia), ratio)
        j_g = np.where(has, np.nan_to_num(gb.inertia_input[gi]), 0.0)
        ref = fit_motors(dm, arrays, torque_margin=margins.torque, rms_margin=margins.rms_torque or margins.torque,
                         speed_margin=margins.speed, inertia_ratio_limit=margins.inertia_ratio,
                         extra_inertia=j_g, index=c.motor[k].astype(np.intp))
        for name in ref.names:
            for got, want in ((d.required, ref.required), (d.available, ref.available), (d.margin, ref.margin)):
                np.testing.assert_allclose(got[name][k], want[name], rtol=1e-9, err_msg=f"{name} at ratio {ratio}")
            np.testing.assert_array_equal(d.approximate[name][k], ref.approximate[name])
        np.testing.assert_allclose(d.rms_torque[k], ref.rms_torque, rtol=1e-9)
        np.testing.assert_allclose(d.peak_torque[k], ref.peak_torque, rtol=1e-9)
        slow[k] = motors.max_speed[c.motor[k]] < dm.hull_speed[-1]
        # mechanical fit of each geared pair (checks.mechanical_fit)
        m = c.motor[k]
        fit = mechanical_fit(motors.shaft_diameter[m], motors.flange[m], motors.pilot_diameter[m],
                             gb.input_bore_max[gi], gb.input_bore_min[gi], gb.input_flange[gi], gb.input_pilot[gi],
                             bolt_circle=motors.bolt_circle[m], adapters=adapter_arrays(gb.input_adapters)[gi])
        np.testing.assert_allclose(d.margin["mechanical_fit"][k][has], fit[has], rtol=1e-12)
        # gearbox ratings (checks.gearbox_ratings; the e-stop torque by the lecture's split)
        run_t = float(np.median(np.abs(duty.external)))
        j = motors.rotor_inertia[m] + j_g
        split = j / (j + duty.load_inertia / ratio**2)
        t_pass = ((1 - split) * (motors.peak_torque[m] - run_t / ratio) + run_t / ratio) * ratio * e
        want_gb = gearbox_ratings(np.max(np.abs(duty.torque)), cubic_mean(duty.torque, duty.omega, duty.weights),
                                  dm.max_speed, dm.mean_speed, t_pass, t2b=gb.max_output_torque[gi],
                                  t2n=gb.rated_output_torque[gi], t2not=gb.emergency_stop_torque[gi],
                                  n1max=gb.max_input_speed[gi], n1n=gb.rated_input_speed[gi],
                                  torque_margin=margins.torque, speed_margin=margins.speed, shock=shock)
        rpm = 60 / (2 * np.pi)
        for name, (req, av, mar) in want_gb.items():
            scale = rpm if CHECK_UNITS[name] == "rpm" else 1.0
            np.testing.assert_allclose(d.required[name][k][has], np.broadcast_to(req * scale, k.shape)[has],
                                       rtol=1e-9, err_msg=name)
            np.testing.assert_allclose(d.available[name][k][has], np.broadcast_to(av * scale, k.shape)[has],
                                       rtol=1e-9, err_msg=name)
            np.testing.assert_allclose(d.margin[name][k][has], np.broadcast_to(mar, k.shape)[has], rtol=1e-9,
                                       err_msg=name)
            assert np.all(d.margin[name][k][~has] == np.inf)
        assert np.all(d.margin["mechanical_fit"][k][~has] == np.inf)
        checked[k] = True
    assert checked.all()
    margin = np.stack([d.margin[n] for n in CHECK_UNITS])
    with np.errstate(invalid="ignore"):
        worst = np.where(np.all(np.isnan(margin), axis=0), np.nan, np.nanmin(np.where(np.isnan(margin), np.inf,
                                                                                        margin), axis=0))
    np.testing.assert_array_equal(c.worst_margin, worst)
    bits = sum((margin[b] < 0).astype(np.uint16) << b for b in range(len(CHECK_UNITS)))
    np.testing.assert_array_equal(c.failed, bits)
    gaps = np.isnan(margin)
    gaps[0] &= ~slow  # a motor too slow for the cycle is not judged on torque: its max_speed fails instead
    np.testing.assert_array_equal(c.unknown, sum(gaps[b].astype(np.uint16) << b for b in range(len(CHECK_UNITS))))
    assert np.all(c.failed[slow] & (1 << 2))


@given(st.lists(st.tuples(st.floats(-50, 50), st.floats(-500, 500), st.floats(-5, 5)), min_size=1, max_size=60),
       st.floats(0.0, 1e-2))
@settings(max_examples=200, deadline=None)
def test_demand_hull_gives_the_peak_torque_of_every_sample(points: list, j: float) -> None:
    """The hull vertices of each speed bin give max |T + J alpha| over the samples of that bin, and
    the whole cycle's hull over all samples: the convex hull loses no extreme point."""
    from drivetrain.sizing.motor_fit import demand

    omega, torque, alpha = (np.array(c) for c in zip(*points, strict=True))
    # a few repeated and collinear samples, as constant phases and ramps make
    omega, torque, alpha = (np.concatenate([x, x[:3], x[:1]]) for x in (omega, torque, alpha))
    d = demand(omega, alpha, torque, np.ones_like(omega), float(len(omega)), 0.0, bins=8)
    brute = np.abs(torque + j * alpha)
    assert np.max(np.abs(d.all_torque + j * d.all_alpha)) == pytest.approx(np.max(brute), rel=1e-12, abs=1e-12)
    w = np.abs(omega)
    for b in range(len(d.hull_speed)):
        # a bin holds the speeds above the previous (non-empty) bin's upper edge, up to its own
        in_bin = (w <= d.hull_speed[b]) & (w > (d.hull_speed[b - 1] if b else -1.0))
        got = np.max(np.abs(d.hull_torque[b] + j * d.hull_alpha[b]))
        assert got == pytest.approx(np.max(brute[in_bin]), rel=1e-12, abs=1e-12)


@given(st.lists(st.one_of(st.sampled_from([-0.5, -0.25, 0.0, 0.3, float("nan")]), st.floats(-1, 1)), min_size=1,
                max_size=80), st.integers(1, 12))
@settings(max_examples=300, deadline=None)
def test_closest_failing_equals_a_stable_sort_of_every_failure(worst: list, n: int) -> None:
    """Ranking the closest failures without sorting them all gives what the stable sort gives."""
    from types import SimpleNamespace

    from drivetrain.sizing.selection import closest_failing

    w = np.array(worst)
    ok = w >= 0.0
    c = SimpleNamespace(worst_margin=w, ok=ok, rejected=(~ok).astype(np.uint8))
    failing = np.flatnonzero(~ok)
    want = failing[np.argsort(-w[failing], kind="stable")][:n]
    np.testing.assert_array_equal(closest_failing(c, n), want)  # type: ignore[arg-type]


def test_closed_form_optimal_ratio_is_the_minimum_of_the_sampled_rms() -> None:
    """The closed-form ratio of least RMS torque against a dense scan of the RMS over the real cycle
    (rotor included, lossless gearbox): no scanned ratio does better (relative 1e-9)."""
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing.selection import optimal_ratio

    axis = load_axis(EXAMPLES / "hoist.yaml")
    duty = duty_cycle(axis, 17)
    motors = catalog.motors()
    m = int(np.nanargmin(np.where(np.isfinite(motors.max_speed), np.abs(motors.rotor_inertia - 1e-4), np.nan)))
    opt = optimal_ratio(axis, duty, motors, m, None)
    j = float(motors.rotor_inertia[m])

    def rms(i: float) -> float:
        return float(np.sqrt(np.sum(duty.weights * (duty.torque / i + j * duty.alpha * i) ** 2) / duty.period))

    best = opt.min_rms_ratio
    assert 0.01 <= best <= max(opt.max_ratio_for_speed, 1.0)
    assert rms(best) == pytest.approx(opt.min_rms_torque_Nm, rel=1e-12)
    scan = np.geomspace(0.01, max(opt.max_ratio_for_speed, 1.0), 4000)
    assert rms(best) <= min(rms(float(i)) for i in scan) * (1 + 1e-9)


@pytest.mark.parametrize("objective", ["smallest", "rms_utilisation", "inertia_match", "energy"])
def test_passing_candidates_are_ranked_by_the_objective(objective: str) -> None:
    """The listed passing candidates come in the order of their score, each score recomputed here
    from what the candidate's own entry (or its own cycle) says."""
    from drivetrain.sizing.selection import candidate_cycle

    data = parse_yaml((EXAMPLES / "roll.yaml").read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    data["motor"] = {**data["motor"], "select": {**data["motor"].get("select", {}), "objective": objective,
                                                 "top": 8}}
    res = size(data)
    sel = res.selection
    assert sel is not None and sel.passing >= 3
    ranked = [c for c in res.candidates if c.ok]
    assert [c.rank for c in ranked] == list(range(1, len(ranked) + 1))
    c_all = res.ranking.candidates

    def score(c: dict) -> float:
        check = {ch.name: ch for ch in c.checks}
        if objective == "rms_utilisation":
            return check["rms_torque"].required / check["rms_torque"].available
        if objective == "inertia_match":
            return abs(np.log(c.inertia_ratio))
        if objective == "energy":
            motors, gb = res.ranking.motors, res.ranking.gearboxes
            m = int(np.flatnonzero(np.asarray(motors.ids) == c.motor)[0])
            rows = c_all.of_motors(np.array([m]))
            g = -1 if c.gearbox is None else int(np.flatnonzero(np.asarray(gb.ids) == c.gearbox)[0])
            k = int(rows[np.flatnonzero(c_all.gearbox(rows) == g)[0]])
            cycle, rotor = candidate_cycle(res.axis, res.duty, res.ranking, k)
            power = cycle.motor_torque(rotor) * cycle.omega
            return float(np.sum(cycle.weights * np.maximum(power, 0.0)))
        return c.rated_power_W

    scores = [score(c) for c in ranked]
    assert all(a <= b * (1 + 1e-9) + 1e-12 for a, b in pairwise(scores)), scores
