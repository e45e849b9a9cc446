"""The selection that knows how the axis will move (docs/checks.md, "Dynamic selection"): with a
``requirements:`` block the walk simulates each candidate it would answer and passes over those whose
tuned loop does not meet the requirements, with the reason; without the block nothing changes."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain import cli
from drivetrain.sizing.pipeline import size

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "belt_dynamic.yaml"
DATA: dict[str, Any] = yaml.safe_load(EXAMPLE.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def dynamic() -> Any:
    return size(EXAMPLE)


@pytest.fixture(scope="module")
def static() -> Any:
    data = copy.deepcopy(DATA)
    del data["requirements"]
    return size(data)


def test_the_static_pick_is_passed_over_for_how_it_moves(dynamic: Any, static: Any) -> None:
    """The smallest motor passes torque, speed and inertia ratio, but its tuned loop on the belt has too
    little phase margin for the 45 deg asked: the next one, with more rotor inertia, is the answer."""
    pick, first = dynamic.selection.selected, static.selection.selected
    assert pick.motor != first.motor
    over = {p.motor: p for p in dynamic.selection.drive_passed_over}
    assert over[first.motor].drive_status == "dynamics"
    assert over[first.motor].reason.startswith("stability_margin: velocity loop phase margin")
    dyn = dynamic.selection.dynamics
    assert dyn["chosen"]["motor"] == pick.motor and dyn["chosen"]["status"] == "pass"
    judged = {c["motor"]: c for c in dyn["candidates"]}
    assert judged[first.motor]["phase_margin_deg"] < 45.0 <= judged[pick.motor]["phase_margin_deg"]
    assert dyn["requirements"]["phase_margin_deg"] == pytest.approx(45.0)
    assert dynamic.ok
    # its simulation lumped the drive pulley (the gearbox's output lump), whose 1.3-1.8 kHz mode lies far
    # above the loop; the pick not simulated has nothing lumped
    lumped = judged[pick.motor]["simulation_lumped"]
    assert len(lumped) == 1 and lumped[0].startswith("gearbox planetary 5:1 lumped into its neighbours")
    assert judged[first.motor]["simulation_lumped"] == []


def test_the_cli_names_the_static_pick_and_why(capsys: pytest.CaptureFixture[str], static: Any) -> None:
    assert cli.main(["size", str(EXAMPLE)]) == 0
    out = capsys.readouterr().out
    assert f"passed over for how it moves: {static.selection.selected.motor}: stability_margin" in out
    assert "dynamics of " in out and "settling_time pass" in out
    assert cli.main(["size", str(EXAMPLE), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["selection"]["dynamics"]["judged"] >= 2


def test_requirements_no_candidate_meets_fail_the_answer(tmp_path: Path) -> None:
    data = copy.deepcopy(DATA)
    data["requirements"]["settling"] = {"window": "1 um", "time": "1 ms"}
    data["requirements"]["candidates"] = 3
    r = size(data)
    assert not r.ok and "dynamic requirements" in r.selection.drive_advice
    assert r.selection.dynamics["judged"] == 3 and r.selection.dynamics["chosen"] is None


def test_without_requirements_the_answer_has_no_dynamics_block(static: Any) -> None:
    assert static.selection.dynamics is None


def test_linear_checks_decide_before_the_simulation(dynamic: Any) -> None:
    """The static pick fails its phase margin, a linear check: it is not simulated, and its settling is
    unknown with why, never a made-up figure; the answer is simulated."""
    judged = {c["motor"]: c for c in dynamic.selection.dynamics["candidates"]}
    over = dynamic.selection.dynamics["passed_over"][0]
    first = judged[over["motor"]]
    assert first["simulated"] is False and first["settling_time_per_stop_s"] == []
    settle = next(c for c in first["checks"] if c["name"] == "settling_time")
    assert settle["status"] == "unknown" and "already fails stability_margin" in settle["note"]
    assert dynamic.selection.dynamics["chosen"]["simulated"] is True
    assert dynamic.selection.dynamics["stopped_early"] is True


def test_the_walk_stops_once_the_candidates_are_judged() -> None:
    data = copy.deepcopy(DATA)
    data["requirements"].update({"candidates": 4, "stability": {"phase_margin": "80 deg"}})
    r = size(data)
    assert r.selection.dynamics["judged"] == 4 and r.selection.drive_passed_over_count == 4
    assert "none of the 4 passing motors tried" in r.selection.drive_advice


def _fastest(window: str) -> Any:
    data = copy.deepcopy(DATA)
    data["motor"]["select"]["objective"] = "fastest_settling"
    data["requirements"].update({"candidates": 6, "settling": {"window": window, "time": "50 ms"},
                                 "stability": {"phase_margin": "30 deg"}})
    return size(data)


def test_fastest_settling_answers_the_candidate_that_settles_fastest() -> None:
    """Among the first 6 static passes (all meeting a 30 deg margin and 50 ms into 20 um), the answer is
    the one with the shortest worst settling time; the ones ranked before it are passed over with both
    times."""
    r = _fastest("20 um")
    dyn = r.selection.dynamics
    assert dyn["objective"] == "fastest_settling" and dyn["judged"] == 6
    worst = {c["motor"]: max(c["settling_time_per_stop_s"]) for c in dyn["candidates"] if c["status"] == "pass"}
    assert len(worst) >= 2
    best = min(worst, key=lambda m: worst[m])
    assert r.selection.selected.motor == best == dyn["chosen"]["motor"]
    order = [c["motor"] for c in dyn["candidates"]]
    before = order[: order.index(best)]
    assert [p.motor for p in r.selection.drive_passed_over] == before
    for p in r.selection.drive_passed_over:
        assert p.reason.startswith("fastest_settling: settles in") and f"{best} in" in p.reason
    assert r.ok


def test_fastest_settling_needs_requirements() -> None:
    from drivetrain.axis.model import parse_axis
    from drivetrain.errors import InputError

    data = copy.deepcopy(DATA)
    del data["requirements"]
    data["motor"]["select"]["objective"] = "fastest_settling"
    with pytest.raises(InputError) as err:
        parse_axis(data)
    assert err.value.field == "motor.select.objective"


def test_the_report_shows_the_dynamics_and_the_pick_passed_over(dynamic: Any, static: Any) -> None:
    """report/dynamics.py: each judged candidate with settling, following error, bandwidth, margins,
    resonance and anti-resonance; the static pick 'passed over for how it moves' with why; the
    inertia ratio the answer ends up with."""
    from drivetrain.report.html import render_html
    from drivetrain.report.model import build_report

    model = build_report(dynamic)
    judged, over = model.dynamics
    first, pick = static.selection.selected.motor, dynamic.selection.selected.motor
    rows = {r[0].text: [c.text for c in r] for r in judged.rows}
    assert rows[first][-1] == "passed over for how it moves" and rows[first][2] == "not simulated"
    assert rows[pick][-1] == "answer" and rows[pick][2].endswith(" ms") and rows[pick][3].endswith(" um")
    assert " deg / " in rows[pick][5] and rows[pick][5].endswith(" dB")  # phase and gain margin
    assert rows[pick][6].count(" Hz") == 2  # first resonance, anti-resonance
    assert f"{pick} ends up with an inertia ratio J_L/J_M of" in judged.note and "still applies" in judged.note
    assert dynamic.selection.dynamics["answer_inertia_ratio"] == dynamic.selection.selected.inertia_ratio
    assert [r[0].text for r in over.rows] == [first] and over.rows[0][3].text.startswith("stability_margin:")
    page = render_html(dynamic)
    assert "How it moves: the dynamic checks" in page and "Static picks passed over for how it moves" in page
    assert build_report(static).dynamics == []


def test_the_web_panel_shows_the_dynamics(dynamic: Any) -> None:
    """web/static/dynamics.js (through results.js): the candidates judged and the static pick labelled
    'passed over for how it moves' (node, when available)."""
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    module = (ROOT / "src/drivetrain/web/static/dynamics.js").as_uri()
    result = json.dumps(dynamic.to_dict()).replace("NaN", "null")
    script = """
      globalThis.Node = class {};
      globalThis.document = { createElement: (t) => ({ tag: t, children: [], attrs: {},
        setAttribute(k, v) { this.attrs[k] = v; }, append(...c) { this.children.push(...c); },
        set textContent(v) { this.text = v; },
        get textContent() {
          return this.text ?? this.children.map((c) => typeof c === "string" ? c : c.textContent).join("|"); },
        replaceChildren(...c) { this.children = c; } }) };
      const D = await import(@MODULE@);
      const result = @RESULT@;
      console.log(D.dynamicsPanel(result).textContent);
      console.log("FOLD " + D.passedOverForMotion(result.selection).textContent);
    """.replace("@MODULE@", json.dumps(module)).replace("@RESULT@", result)
    out = subprocess.run([node, "--input-type=module", "-e", script], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    first = dynamic.selection.dynamics["passed_over"][0]["motor"]
    pick = dynamic.selection.selected.motor
    assert "How it moves: the dynamic checks" in out.stdout and "passed over for how it moves" in out.stdout
    assert f"{first}|–|not simulated|not simulated|" in out.stdout and f"{pick}|–|" in out.stdout
    assert "|answer" in out.stdout and "ends up with an inertia ratio" in out.stdout
    assert "FOLD 1 static pick passed over for how it moves" in out.stdout and "stability_margin" in out.stdout


def test_the_dynamic_checks_count_and_explain(dynamic: Any, static: Any,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """failures_by_check counts the dynamic checks of the candidates judged; --explain MODEL lists them."""
    sel = dynamic.selection
    assert sel.failures_by_check["stability_margin"] == 1 and sel.failures_by_check["settling_time"] == 0
    assert sel.unknown_by_check["settling_time"] == 0  # not simulated is not a gap in the data
    assert "stability_margin" not in static.selection.failures_by_check
    first = static.selection.selected.motor
    assert cli.main(["size", str(EXAMPLE), "--explain", first]) == 0
    out = capsys.readouterr().out
    assert "dynamics (its best configuration): passed over for how it moves: stability_margin" in out
    assert "FAIL stability_margin: required 45, available 40.7" in out
    assert "??   settling_time: required 0.02, available n/a s (n/a): not simulated" in out
    assert "dynamics (its best configuration): the answer" in dynamic.explain(sel.selected.motor)


def test_the_settling_optimal_ratio_is_the_fastest_of_the_scan() -> None:
    """requirements.settling_ratio: a coarse scan of ideal reductions in front of the answer's drive train,
    inside its torque and speed; the answer is the fastest to settle; factor 1 is the answer as selected."""
    data = copy.deepcopy(DATA)
    data["requirements"].update({"settling_ratio": True, "settling": {"window": "20 um", "time": "20 ms"}})
    r = size(data)
    dyn = r.selection.dynamics
    opt = dyn["settling_optimal_ratio"]
    assert opt["motor"] == r.selection.selected.motor == dyn["chosen"]["motor"]
    scan = {round(p["factor"], 9): p["settling_time_s"] for p in opt["per_ratio"]}
    times = [t for t in scan.values() if t is not None]
    assert opt["settling_time_s"] == min(times) and opt["scanned"] == len(scan) >= 5
    assert scan[1.0] == pytest.approx(max(dyn["chosen"]["settling_time_per_stop_s"]))
    assert opt["current_settling_time_s"] == scan[1.0]
    # no factor beyond the motor's max speed: today's optimal ratio line names that limit
    assert opt["range"][1] <= r.selection.optimal_ratio.max_ratio_for_speed
    assert opt["stage"] == "gearbox ratio" and "ratio 5 ->" in opt["label"]
    assert opt["settling_time_s"] < opt["current_settling_time_s"]  # a longer ratio settles this belt faster
    assert "settling_optimal_ratio" not in size(EXAMPLE).selection.dynamics  # only when asked


def test_feasible_factors_follow_the_torque_and_speed_limits() -> None:
    import numpy as np

    from drivetrain.duty.cycle import DutyCycle
    from drivetrain.dynamics.settling_ratio import feasible_factors

    class Cycle:  # T = 1 N m constant, alpha = 0, omega up to 100 rad/s
        torque, alpha, omega, weights, period = np.ones(3), np.zeros(3), np.array([0.0, 100.0, 50.0]), np.ones(3), 3.0

    cyc: DutyCycle = Cycle()  # type: ignore[assignment]
    ok = feasible_factors(cyc, 1e-4, peak_torque=2.0, rated_torque=1.0, max_speed=300.0,
                          factors=np.array([0.4, 0.5, 1.0, 2.0, 3.0, 3.5]))
    # peak 1/i <= 2 -> i >= 0.5; RMS 1/i <= 1 -> i >= 1; speed 100 i <= 300 -> i <= 3
    assert ok.tolist() == [False, False, True, True, True, False]


def test_requirements_as_a_study_parameter(tmp_path: Path) -> None:
    """A study sweeps requirements.settling.window like any axis-file key: each variant is the selection
    with that requirement, and the dynamics group is recorded by default (the selected candidate's
    settling time, margins, how many were judged and passed over). 20 ms into 20 um: MQMF042L1 settles in
    7.4 ms; 5 ms into 20 um it does not, and another motor (or none) is the answer."""
    from drivetrain.study import sweep

    study = tmp_path / "req.yaml"
    study.write_text(yaml.safe_dump({
        "study": 1, "base": str(EXAMPLE), "design": "grid",
        "parameters": {"requirements.settling.time": {"values": [5, 20], "unit": "ms"},
                       "requirements.settling.window": {"values": [20, 100], "unit": "um"}}}), encoding="utf-8")
    table = sweep(study, workers=0).table
    assert {"dynamics_settling_time_s", "dynamics_phase_margin_deg", "dynamics_judged",
            "dynamics_passed_over"} <= set(table.columns)
    for _, row in table.iterrows():
        data = copy.deepcopy(DATA)
        data["requirements"]["settling"] = {"time": f"{row['requirements.settling.time']} ms",
                                            "window": f"{row['requirements.settling.window']} um"}
        ref = size(data)
        dyn = ref.selection.dynamics
        assert bool(row["ok"]) == ref.ok and row["dynamics_judged"] == dyn["judged"]
        if row["ok"]:
            assert row["motor"] == ref.selection.selected.motor
            assert row["dynamics_settling_time_s"] <= row["requirements.settling.time"] * 1e-3
    strict = table[(table["requirements.settling.time"] == 5) & (table["requirements.settling.window"] == 20)]
    loose = table[(table["requirements.settling.time"] == 20) & (table["requirements.settling.window"] == 20)]
    assert loose["motor"].iloc[0] == "MQMF042L1" and loose["dynamics_settling_time_s"].iloc[0] > 5e-3
    assert strict["motor"].iloc[0] != "MQMF042L1" or not strict["ok"].iloc[0]


def test_a_study_without_requirements_records_no_dynamics(tmp_path: Path) -> None:
    from drivetrain.study import parse_study

    body = {"study": 1, "base": str(ROOT / "examples" / "belt.yaml"), "parameters": {"mechanism.load.mass": [5, 10]}}
    assert "dynamics" not in parse_study(yaml.safe_dump(body)).spec.record
    body["parameters"] = {"requirements.settling.time": {"values": [5, 10], "unit": "ms"}}
    assert parse_study(yaml.safe_dump(body)).spec.record[-1] == "dynamics"


@pytest.mark.parametrize("margin, objective", [("30 deg", "smallest"), ("45 deg", "smallest"), ("80 deg", "smallest"),
                                               ("30 deg", "fastest_settling")])
def test_a_search_answers_as_the_whole_ranking_does(margin: str, objective: str) -> None:
    """listing="selected" (a study's search, its pick judged first, the whole ranking only when it is
    passed over) answers the same motor, the same dynamic choice and the same judged candidates as the
    ranked listing's walk."""
    data = copy.deepcopy(DATA)
    data["motor"]["select"]["objective"] = objective
    data["requirements"].update({"candidates": 4, "stability": {"phase_margin": margin},
                                 "settling": {"window": "20 um", "time": "20 ms"}})
    ranked, searched = size(data), size(data, listing="selected")
    assert searched.ok == ranked.ok
    assert searched.selection.selected.motor == ranked.selection.selected.motor
    a, b = ranked.selection.dynamics, searched.selection.dynamics
    assert (a["chosen"] or {}).get("motor") == (b["chosen"] or {}).get("motor")
    assert [c["motor"] for c in a["candidates"]] == [c["motor"] for c in b["candidates"]]
    assert [p["motor"] for p in a["passed_over"]] == [p["motor"] for p in b["passed_over"]]
