"""The verdict in three outcomes, the same everywhere: ``SizingResult.status`` (pass, pass with unknowns,
fail) with its typed ``unknowns``, the JSON ``verdict`` block, the CLI's last line and exit code, the
report's banner, the web page's banner, and ``machine size`` (the worst axis)."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest
import yaml

from drivetrain import cli
from drivetrain.axis.model import load_axis
from drivetrain.sizing.pipeline import size
from drivetrain.sizing.verdict import Unknown

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
RESULTS_JS = ROOT / "src" / "drivetrain" / "web" / "static" / "results.js"
OUTCOMES = ("pass", "pass with unknowns", "fail")


def belt_with_partial_gearbox(unknown: str) -> dict[str, Any]:
    """belt.yaml with its transmission gearbox rated for T2B alone (T2N, n1max ... not given) and the
    selection's unknown policy."""
    raw = load_axis(EXAMPLES / "belt.yaml").raw
    stage = {**raw["transmission"][0], "max_torque": "40 N*m"}
    motor = {**raw["motor"], "select": {**raw["motor"]["select"], "unknown": unknown}}
    return {**raw, "transmission": [stage], "motor": motor}


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_every_example_states_one_of_three_outcomes_consistently(name: str) -> None:
    res = size(EXAMPLES / name)
    assert res.status in OUTCOMES
    assert res.ok == (res.status != "fail")
    assert (res.status == "pass") == (res.ok and not res.unknowns)
    block = res.to_dict()["verdict"]
    assert block == {"status": res.status, "unknowns": [u.to_dict() for u in res.unknowns]}
    for u in res.unknowns:
        assert isinstance(u, Unknown) and u.check and u.part and u.decide


def test_an_unknown_drive_is_a_pass_with_unknowns_that_names_it() -> None:
    """belt.yaml selects MQMF022L1, whose catalog row has no torque constant: its drive cannot be checked."""
    res = size(EXAMPLES / "belt.yaml")
    assert res.status == "pass with unknowns" and res.ok
    drive = [u for u in res.unknowns if u.part == "drive"]
    assert drive and drive[0].check == "drive" and "torque constant" in drive[0].decide
    assert res.verdict_line().startswith("PASS WITH UNKNOWNS: drive (the catalog has no torque constant")


def test_the_t2b_shock_factor_case_is_an_unknown_of_the_gearbox() -> None:
    """roll.yaml runs 2400 cycles/h: T2B holds for 1000/h, so without a shock factor it is not judged (a catalog
    gearbox asked for: the whole catalog answers it direct)."""
    d = yaml.safe_load((EXAMPLES / "roll.yaml").read_text(encoding="utf-8"))
    d["motor"]["select"]["gearbox"] = "only"
    res = size(d)
    assert res.status == "pass with unknowns"
    t2b = [u for u in res.unknowns if u.check == "gearbox_peak_torque"]
    assert t2b and t2b[0].part == "gearbox" and "gearbox_shock_factor" in t2b[0].decide


def test_an_unknown_gearbox_rating_fails_only_under_unknown_fail() -> None:
    flag = size(belt_with_partial_gearbox("flag"))
    assert flag.status == "pass with unknowns" and flag.ok
    stage = [u for u in flag.unknowns if u.part.startswith("gearbox stage")]
    assert {u.check for u in stage} >= {"gearbox_rated_torque", "gearbox_max_input_speed"}
    assert all("not given" in u.decide for u in stage if u.check != "gearbox_peak_torque")
    t2b = next(u for u in stage if u.check == "gearbox_peak_torque")  # 1286 cycles/h: T2B needs the shock factor
    assert "gearbox_shock_factor" in t2b.decide and t2b.part == "gearbox stage (gearbox planetary 5:1)"
    strict = size(belt_with_partial_gearbox("fail"))
    assert strict.status == "fail" and not strict.ok
    assert strict.verdict_line().startswith("FAIL")


def level_ball_screw() -> dict[str, Any]:
    """examples/ball_screw.yaml laid level with no brake dwell: every check judged and passed, and its motor
    (no brake needed) and drive orderable as written: a plain pass."""
    d = yaml.safe_load((EXAMPLES / "ball_screw.yaml").read_text(encoding="utf-8"))
    d["mechanism"]["incline"] = "0 deg"
    d["profile"][3] = {"dwell": "0.3 s"}
    d["guide"]["orientation"] = "horizontal"
    return d


def test_the_cli_prints_the_verdict_last_and_exits_by_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    level = tmp_path / "level_screw.yaml"
    level.write_text(yaml.safe_dump(level_ball_screw()), encoding="utf-8")
    assert cli.main(["size", str(level)]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "PASS"
    # every check of ball_screw passes, but its motor's brake variant has no order code: not a plain pass
    assert cli.main(["size", str(EXAMPLES / "ball_screw.yaml")]) == 0
    last = capsys.readouterr().out.splitlines()[-1]
    assert last.startswith("PASS WITH UNKNOWNS: ") and "order_code (holding-brake variant of HG-KR23" in last
    assert cli.main(["size", str(EXAMPLES / "belt.yaml")]) == 0
    assert capsys.readouterr().out.splitlines()[-1].startswith("PASS WITH UNKNOWNS: drive (")
    assert cli.main(["size", str(EXAMPLES / "conveyor.yaml")]) == 1
    assert capsys.readouterr().out.splitlines()[-1].startswith("FAIL: mechanism: slip_limit")
    for policy, code in (("flag", 0), ("fail", 1)):
        path = tmp_path / f"belt_{policy}.yaml"
        path.write_text(yaml.safe_dump(belt_with_partial_gearbox(policy)), encoding="utf-8")
        assert cli.main(["size", str(path)]) == code
        last = capsys.readouterr().out.splitlines()[-1]
        assert last.startswith("PASS WITH UNKNOWNS" if code == 0 else "FAIL")
        assert cli.main(["size", str(path), "--json"]) == code
        out = json.loads(capsys.readouterr().out)
        assert out["verdict"]["status"] == ("pass with unknowns" if code == 0 else "fail")


def test_the_report_of_an_unknown_drive_says_pass_with_unknowns_and_lists_it(tmp_path: Path) -> None:
    """The report's banner used to say "PASS, passes every check" with the drive unknown."""
    from drivetrain.report import write_report

    res = size(EXAMPLES / "belt.yaml")
    write_report(res, tmp_path / "belt.html")
    html = (tmp_path / "belt.html").read_text(encoding="utf-8")
    banner = html[html.index('id="dt-verdict"'):]
    banner = banner[:banner.index("</section>")]
    assert "PASS WITH UNKNOWNS" in banner and "pass with unknowns" in banner
    assert "passes every check" not in banner
    assert "the catalog has no torque constant for MQMF022L1" in banner
    assert 'class="dt-verdict dt-unknowns"' in html


def test_a_passing_report_keeps_its_pass_banner(tmp_path: Path) -> None:
    from drivetrain.report import write_report

    write_report(size(level_ball_screw()), tmp_path / "y.html")
    html = (tmp_path / "y.html").read_text(encoding="utf-8")
    banner = html[html.index('id="dt-verdict"'):]
    assert 'class="dt-verdict dt-pass"' in html and "PASS WITH UNKNOWNS" not in banner[:banner.index("</section>")]
    write_report(size(EXAMPLES / "belt.yaml"), tmp_path / "b.html")
    html = (tmp_path / "b.html").read_text(encoding="utf-8")
    assert "PASS WITH UNKNOWNS: drive" in html  # a listed candidate whose drive cannot be checked says so


def machine(axis: dict[str, Any]) -> dict[str, Any]:
    return {"version": 1, "machine": "line", "cycle_time": "3 s", "supply": {"voltage": "400 V", "phases": 3},
            "axes": [{"name": "X", "axis": axis}]}


def test_machine_verdict_is_the_worst_axis_and_sets_the_exit_code(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    from drivetrain.machine.result import size_machine

    unknown = size_machine(machine(load_axis(EXAMPLES / "belt.yaml").raw))
    assert unknown.status == "pass with unknowns" and unknown.ok
    d = unknown.to_dict()
    assert d["verdict"]["status"] == "pass with unknowns"
    assert d["verdict"]["unknowns"][0]["axis"] == "X" and d["verdict"]["unknowns"][0]["check"] == "drive"
    failing = size_machine(machine(belt_with_partial_gearbox("fail")))
    assert failing.status == "fail" and not failing.ok
    for m, code, head in ((machine(load_axis(EXAMPLES / "belt.yaml").raw), 0, "PASS WITH UNKNOWNS"),
                          (machine(belt_with_partial_gearbox("fail")), 1, "FAIL")):
        path = tmp_path / "m.yaml"
        path.write_text(yaml.safe_dump(m), encoding="utf-8")
        assert cli.main(["machine", "size", str(path)]) == code
        assert capsys.readouterr().out.splitlines()[-1].startswith(head)
        assert cli.main(["machine", "size", str(path), "--json"]) == code
        capsys.readouterr()


def run_results_js(body: str, script: Path = RESULTS_JS) -> str:
    """Run ``body`` in node with ``@RESULTS@`` standing for the imported ``script`` (results.js) and a minimal
    document (skip when node is absent); its stdout."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    module = f"await import({json.dumps(script.as_uri())})"
    dom = """
      globalThis.Node = class {};
      const mk = (t) => ({ tag: t, children: [], attrs: {}, cls: new Set(),
        setAttribute(k, v) { this.attrs[k] = v; }, append(...c) { this.children.push(...c); },
        set textContent(v) { this.text = v; this.children = []; },
        get textContent() {
          return (this.text ?? "") + this.children.map((c) => typeof c === "string" ? c : c.textContent).join(""); },
        replaceChildren(...c) { this.children = c; this.text = undefined; }, addEventListener() {},
        set className(v) { this.cls = new Set(v.split(" ")); },
        get classList() { const s = this.cls; return { add: (c) => s.add(c) }; } });
      globalThis.document = { createElement: mk, createTextNode: (t) => t };
    """
    out = subprocess.run([node, "--input-type=module", "-e", dom + body.replace("@RESULTS@", module)],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_the_web_banner_shows_the_three_outcomes_from_the_json() -> None:
    """results.js reads the answer's ``verdict`` block: the class and the line under the banner."""
    pytest.importorskip("fastapi")
    from drivetrain.web.payload import encode, size_payload

    result = json.loads(encode(size_payload(load_axis(EXAMPLES / "belt.yaml").raw)))["result"]
    out = run_results_js(f"""
      const R = @RESULTS@;
      const result = {json.dumps(result)};
      const show = (r) => {{ const n = document.createElement("div"); R.renderBanner(n, r);
                            return [[...n.cls].join(" "), n.textContent]; }};
      const passing = {{ ...result, verdict: {{ status: "pass", unknowns: [] }} }};
      const failing = {{ ...result, verdict: {{ status: "fail", unknowns: result.verdict.unknowns }} }};
      console.log(JSON.stringify([show(result), show(passing), show(failing), R.verdict(failing).ok]));
    """)
    (cls_u, text_u), (cls_p, text_p), (cls_f, text_f), failing_ok = json.loads(out)
    assert "warn" in cls_u and "PASS WITH UNKNOWNS" in text_u and "torque constant for MQMF022L1" in text_u
    assert "good" in cls_p and text_p.endswith("PASS")
    assert "bad" in cls_f and "FAIL" in text_f and failing_ok is False


def test_the_web_api_answer_carries_the_verdict_block() -> None:
    """The JSON the page reads (/api/size) holds the verdict as the engine states it."""
    pytest.importorskip("fastapi")
    from drivetrain.web.payload import WEB_POINTS_PER_PHASE, encode, size_payload

    axis = load_axis(EXAMPLES / "belt.yaml").raw
    body = json.loads(encode(size_payload(axis)))  # the bytes /api/size answers with
    expected = size(axis, WEB_POINTS_PER_PHASE)
    assert body["result"]["verdict"]["status"] == expected.status == "pass with unknowns"
    assert [u["check"] for u in body["result"]["verdict"]["unknowns"]] == [u.check for u in expected.unknowns]


def test_the_demand_table_says_which_shaft_each_number_is_at(capsys: pytest.CaptureFixture[str]) -> None:
    """The gantry selects a motor behind a catalog gearbox: the table is the demand at the axis input (the
    gearbox output), and the selected motor's own figures at its shaft turn i times faster."""
    import re

    res = size(EXAMPLES / "belt_gantry.yaml")
    pick = res.selection.selected
    assert pick.gearbox and pick.ratio > 1
    cli.main(["size", str(EXAMPLES / "belt_gantry.yaml")])
    out = capsys.readouterr().out
    assert "demand at the motor shaft" not in out
    assert f"demand at the axis input (rotor excluded); at the shaft of {pick.motor} behind {pick.gearbox}" in out
    axis_speed = float(re.search(r"│ max / mean speed\s+│\s+([\d.]+) /", out).group(1))  # type: ignore[union-attr]
    motor_row = re.search(r"│ motor shaft \(i = ([\d.]+)\): max / mean speed\s+│\s+([\d.]+) /", out)
    assert motor_row is not None and float(motor_row.group(1)) == pytest.approx(pick.ratio)
    assert float(motor_row.group(2)) == pytest.approx(axis_speed * pick.ratio, abs=pick.ratio)
    peak = re.search(r"│ motor shaft \(i = [\d.]+\): peak / RMS torque, rotor included\s+│\s+([\d.]+) /", out)
    torques = res.torques()
    assert peak is not None and float(peak.group(1)) == pytest.approx(torques.loc["peak_torque_Nm", "motor"], rel=1e-3)


def test_a_direct_selection_adds_no_motor_shaft_rows(capsys: pytest.CaptureFixture[str]) -> None:
    cli.main(["size", str(EXAMPLES / "belt.yaml")])  # on the axis's own gearbox: the axis input is the motor shaft
    out = capsys.readouterr().out
    assert "demand at the axis input (rotor excluded)\n" in out and "│ motor shaft (i =" not in out


def test_the_web_machine_banner_states_the_worst_axis() -> None:
    """machine_results.js reads the machine's ``verdict`` block: the banner's class and its last line."""
    from drivetrain.machine.result import size_machine
    from drivetrain.web.payload import encode

    p = json.loads(encode(size_machine(machine(load_axis(EXAMPLES / "belt.yaml").raw)).to_dict()))
    out = run_results_js(f"""
      const MR = @RESULTS@;
      const p = {json.dumps(p)};
      const v = MR.machineVerdict(p);
      const failing = MR.machineVerdict({{ ...p, verdict: {{ status: "fail", unknowns: [] }} }});
      console.log(JSON.stringify([v.cls, v.line.textContent, failing.cls, failing.line.textContent,
                                  MR.axisOutcome(p.axes[0].result, null)]));
    """, RESULTS_JS.with_name("machine_results.js"))
    cls, text, fail_cls, fail_text, axis = json.loads(out)
    assert cls == "warn" and text.startswith("PASS WITH UNKNOWNS") and "X: drive (drive)" in text
    assert fail_cls == "bad" and fail_text == "FAIL" and axis == "pass with unknowns"
