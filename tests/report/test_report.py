"""The sizing report: HTML rendered in headless Chromium, PDF rasterised and read back, units, escaping, files.

Browser tests drive Debian's /usr/bin/chromium through Playwright's Python API (never
``playwright install``); they skip only when that browser is absent (``make browser`` installs it).
PDF tests use poppler's pdftoppm and pdftotext, installed with it.
"""

from __future__ import annotations

import copy
import html
import os
import re
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import drivetrain
from drivetrain.errors import InputError
from drivetrain.report import render_html, render_pdf, repr_html, write_report
from drivetrain.report.checks import CHECK_NAMES
from drivetrain.report.display import display_units, fmt_number, pretty_unit
from drivetrain.report.formulas import FORMULAS, docstring_of

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _verdict(check: Any) -> str:
    """The result cell of a check (a ``CheckRow`` or a given motor's ``Check``): its status (a check the catalog
    cannot judge reads UNKNOWN)."""
    status = getattr(check, "status", None) or ("pass" if check.ok else "fail")
    return {"pass": "PASS", "fail": "FAIL"}.get(status, status.upper())
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]
HAS_CHROMIUM = Path(CHROMIUM).exists()
HAS_POPPLER = shutil.which("pdftoppm") is not None and shutil.which("pdftotext") is not None
EVIL = "<script>alert(1)</script>"

needs_chromium = pytest.mark.skipif(not HAS_CHROMIUM, reason=f"{CHROMIUM} not installed (make browser)")
needs_poppler = pytest.mark.skipif(not HAS_POPPLER, reason="poppler-utils not installed (make browser)")

HG_KR43 = {"name": "HG-KR43", "inertia": "0.371 kg*cm^2", "rated_torque": "1.3 N*m", "peak_torque": "4.5 N*m",
           "rated_speed": "3000 rpm", "max_speed": "6000 rpm", "margins": {"torque": 1.2, "inertia_ratio": 10}}


def _raw(name: str = "ball_screw") -> dict[str, Any]:
    data = yaml.safe_load((EXAMPLES / f"{name}.yaml").read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


@pytest.fixture(scope="module")
def ball() -> drivetrain.sizing.result.SizingResult:
    """The shipped ball screw example: a catalog selection."""
    return drivetrain.size(EXAMPLES / "ball_screw.yaml")


@pytest.fixture(scope="module")
def weak() -> drivetrain.sizing.result.SizingResult:
    """The ball screw with a given motor that passes some checks and fails others, and a hostile name."""
    raw = _raw()
    raw["axis"] = EVIL
    raw["motor"] = {**HG_KR43, "name": "weak <b>motor</b>", "peak_torque": "1.5 N*m", "rated_torque": "0.4 N*m"}
    return drivetrain.size(raw)


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if not HAS_CHROMIUM:
        pytest.skip(f"{CHROMIUM} not installed (make browser)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            yield b
        finally:
            b.close()


def _open(browser: Any, path: Path) -> tuple[Any, dict[str, list[str]]]:
    """Open a report offline: any request that is not file:// is refused and recorded."""
    seen: dict[str, list[str]] = {"network": [], "errors": [], "dialogs": []}
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.on("pageerror", lambda exc: seen["errors"].append(str(exc)))
    page.on("console", lambda msg: seen["errors"].append(msg.text) if msg.type == "error" else None)

    def on_dialog(dialog: Any) -> None:
        seen["dialogs"].append(dialog.message)
        dialog.dismiss()

    page.on("dialog", on_dialog)

    def route(r: Any) -> None:
        if r.request.url.startswith("file:"):
            r.continue_()
        else:
            seen["network"].append(r.request.url)
            r.abort()

    page.route("**/*", route)
    page.goto(path.resolve().as_uri())
    page.wait_for_function("document.querySelectorAll('.dt-plot .main-svg').length >= "
                           "document.querySelectorAll('.dt-plot').length", timeout=20_000)
    return page, seen


def _check_rows(page: Any) -> dict[str, str]:
    rows = page.eval_on_selector_all(
        "#dt-table-checks tbody tr",
        "rows => rows.map(r => Array.from(r.cells).map(c => c.innerText.trim()))")
    return {r[0]: r[-1] for r in rows}


# --------------------------------------------------------------------------- HTML in Chromium


@pytest.mark.browser
def test_html_report_in_chromium_shows_numbers_checks_and_plots(ball: Any, browser: Any, tmp_path: Path) -> None:
    path = write_report(ball, tmp_path / "ball.html")
    page, seen = _open(browser, path)
    try:
        text = page.inner_text("body")
        selected = ball.selection.selected
        assert selected.motor in text
        # Key numbers, formatted independently of the report code (4 significant digits).
        for value in (selected.peak_torque_Nm, selected.rms_torque_Nm, ball.metrics.peak_torque_Nm,
                      ball.metrics.rms_torque_Nm):
            assert f"{value:.4g}" in text, value
        assert "PASS" in page.inner_text("#dt-verdict")
        # Every check of the selected motor, with its own verdict.
        rows = _check_rows(page)
        assert len(rows) == len(selected.checks)
        for check in selected.checks:
            assert rows[CHECK_NAMES[check.name]] == _verdict(check)
        # Every plot drew: plotly's SVG with non-empty line paths, and the phase bands where there are phases.
        plots = page.eval_on_selector_all(".dt-plot", """divs => divs.map(d => ({
            key: d.dataset.plot,
            svg: d.querySelectorAll('.main-svg').length,
            lines: Array.from(d.querySelectorAll('.main-svg .trace path.js-line'))
                        .filter(p => (p.getAttribute('d') || '').length > 20).length,
            bands: d.querySelectorAll('.shapelayer path').length}))""")
        # modes: f1 across the stroke of the HIWIN screw (one line: the example states no bandwidth to draw).
        assert {p["key"] for p in plots} == {"motion", "motor", "speed_torque", "regen", "modes"}
        for p in plots:
            assert p["svg"] >= 1 and p["lines"] >= (1 if p["key"] == "modes" else 2), p
        assert all(p["bands"] >= len(ball.duty.cycle.phases) for p in plots if p["key"] in ("motion", "motor"))
        assert page.locator("svg.dt-diagram .dt-block").count() == len(ball.axis.stages) + 2
        assert seen == {"network": [], "errors": [], "dialogs": []}
    finally:
        page.close()


@pytest.mark.browser
def test_html_report_escapes_user_strings_in_the_browser(weak: Any, browser: Any, tmp_path: Path) -> None:
    path = write_report(weak, tmp_path / "weak.html")
    page, seen = _open(browser, path)
    try:
        assert page.inner_text("#dt-axis-name") == EVIL  # shown as text, not run
        assert seen["dialogs"] == [] and seen["errors"] == []
        assert "FAIL" in page.inner_text("#dt-verdict")
        rows = _check_rows(page)
        for check in weak.motor.checks:
            assert rows[CHECK_NAMES[check.name]] == _verdict(check)
        assert {"PASS", "FAIL"} <= set(rows.values())
        assert page.locator("#dt-axis-name b, .dt-report b:text('motor')").count() == 0
    finally:
        page.close()


def test_html_escapes_every_user_string(weak: Any) -> None:
    text = render_html(weak)
    body = text[: text.index('<script type="text/javascript">')]
    assert EVIL not in text
    assert html.escape(EVIL) in body
    assert "weak <b>motor</b>" not in text and "weak &lt;b&gt;motor&lt;/b&gt;" in body
    assert "<script" not in body  # the only scripts are plotly.js and the plot calls
    assert text.count("<script") == 2


def test_html_is_self_contained(ball: Any) -> None:
    text = render_html(ball)
    bundle = re.search(r'<script type="text/javascript">/\*\*?.*?</script>', text, re.S)
    outside = text.replace(bundle.group(0), "") if bundle else text
    assert bundle is not None and len(bundle.group(0)) > 3_000_000  # plotly.js embedded from the package
    assert not re.search(r"<(script|link|img|iframe)[^>]*(src|href)\s*=", outside)
    assert "http" not in outside.replace("http://www.w3.org/2000/svg", "")
    assert "Plotly.newPlot" in outside


# --------------------------------------------------------------------------- PDF


@needs_poppler
def test_pdf_report_pages_are_drawn_and_carry_the_numbers(ball: Any, tmp_path: Path) -> None:
    from PIL import Image

    path = render_pdf(ball, tmp_path / "ball.pdf")
    assert path.read_bytes().startswith(b"%PDF")
    subprocess.run(["pdftoppm", "-r", "30", "-png", str(path), str(tmp_path / "page")], check=True, timeout=60)
    pages = sorted(tmp_path.glob("page*.png"))
    assert len(pages) >= 5
    for page in pages:
        gray = np.asarray(Image.open(page).convert("L"), dtype=float)
        inked = float(np.mean(gray < 200))
        assert gray.var() > 50.0 and inked > 0.01, (page.name, gray.var(), inked)
    text = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True,
                          timeout=60).stdout
    selected = ball.selection.selected
    assert selected.motor in text and "Z lift" in text
    for value in (selected.peak_torque_Nm, selected.rms_torque_Nm, ball.metrics.peak_torque_Nm):
        assert f"{value:.4g}" in text, value
    lines = text.splitlines()
    for check in selected.checks:
        name = CHECK_NAMES[check.name].split(" J_L")[0]
        verdict = _verdict(check)
        assert any(name in line and verdict in line for line in lines), name
    assert f"page {len(pages)} of {len(pages)}" in text


SECTION_HEADING = re.compile(r"^(\d+ (The axis|Motion profile|Motor shaft: speed and torque|Speed-torque plane|"
                             r"Mechanism: checks and modes|Selection and ratio|Inputs|Formulas and sources)|Notes)$")


def _page_texts(path: Path) -> list[str]:
    info = subprocess.run(["pdfinfo", str(path)], capture_output=True, text=True, check=True, timeout=60).stdout
    m = re.search(r"^Pages:\s+(\d+)", info, re.M)
    assert m, info
    return [subprocess.run(["pdftotext", "-layout", "-f", str(k), "-l", str(k), str(path), "-"], capture_output=True,
                           text=True, check=True, timeout=60).stdout for k in range(1, int(m.group(1)) + 1)]


@needs_poppler
@pytest.mark.skipif(shutil.which("pdfinfo") is None, reason="poppler-utils not installed (make browser)")
# ball_screw and rotary once left section headings at page bottoms; the gantry has the mechanism section
@pytest.mark.parametrize("example", ["ball_screw", "rotary", "belt_gantry_3m"])
def test_pdf_section_headings_are_never_the_last_text_on_a_page(example: str, ball: Any, tmp_path: Path) -> None:
    result = ball if example == "ball_screw" else drivetrain.size(EXAMPLES / f"{example}.yaml")
    pages = _page_texts(render_pdf(result, tmp_path / f"{example}.pdf"))
    headings_seen = 0
    for k, text in enumerate(pages, start=1):
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        body = [line for line in lines if f"page {k} of {len(pages)}" not in line]  # the running footer
        headings_seen += sum(1 for line in body if SECTION_HEADING.match(line))
        assert body, f"page {k} is empty"
        assert not SECTION_HEADING.match(body[-1]), f"page {k} ends with the heading {body[-1]!r}"
    assert headings_seen >= 7, headings_seen  # the headings are found at all (the pattern matches them)


# --------------------------------------------------------------------------- units


def test_imperial_units_switch_every_torque_and_inertia(ball: Any) -> None:
    si = render_html(ball, "si")
    imp = render_html(ball, "imperial")
    imp_body = imp[: imp.index("<script")]
    peak = ball.selection.selected.peak_torque_Nm
    assert f"{peak * 8.850745791327187:.4g} lbf·in" in imp_body
    assert f"{peak:.4g} N·m" in si
    kpis = re.search(r'<section class="dt-kpis".*?</section>', imp_body, re.S)
    assert kpis is not None and "N·m" not in kpis.group(0) and "kg·cm²" not in kpis.group(0)
    assert "lb·in²" in kpis.group(0)
    assert "lbf·in" in imp_body and ">imperial" in imp_body.replace("<dd>", ">")


def test_as_given_units_follow_the_axis_file() -> None:
    raw = _raw()
    raw["motor"] = {"name": "imperial motor", "inertia": "5.25e-5 oz*in*s^2", "rated_torque": "11.5 lbf*in",
                    "peak_torque": "39.8 lbf*in", "rated_speed": "3000 rpm", "max_speed": "6000 rpm"}
    raw["profile"][0]["move"] = "7.874 in"
    raw["transmission"][0]["inertia"] = "2.832e-5 oz*in*s^2"  # the file's first inertia sets the unit
    result = drivetrain.size(raw)
    du = display_units("as-given", result.axis.raw)
    assert du.unit("torque") == "lbf*in" and du.unit("inertia") == "oz*in*s^2" and du.unit("length") == "in"
    body = render_html(result, "as-given")
    body = body[: body.index("<script")]
    assert f"{result.motor.peak_torque_Nm * 8.850745791327187:.4g} lbf·in" in body
    assert "oz·in·s²" in body and "7.874 in" in body


def test_display_formatting() -> None:
    assert [fmt_number(v) for v in (1.02733, 3428.57, 12345.6, 0.0, -0.00001234, float("nan"))] == [
        "1.027", "3429", "12346", "0", "-1.234×10⁻⁵", "—"]
    assert pretty_unit("kg*cm^2") == "kg·cm²" and pretty_unit("N*m") == "N·m"
    du = display_units("imperial")
    assert du.fmt(1.0, "torque") == "8.851 lbf·in"
    assert du.fmt(1e-4, "inertia") == "0.3417 lb·in²"
    assert display_units("si").fmt(104.71975511965977, "angular_speed") == "1000 rpm"


def test_bad_units_and_suffix_are_input_errors(ball: Any, tmp_path: Path) -> None:
    with pytest.raises(InputError, match="units"):
        write_report(ball, tmp_path / "r.html", units="furlongs")
    with pytest.raises(InputError, match=r"\.html or \.pdf"):
        write_report(ball, tmp_path / "r.docx")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- files


def test_reports_are_written_atomically(ball: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import drivetrain.report as report
    from drivetrain.report import pdf

    target = tmp_path / "out.html"
    target.write_text("previous report", encoding="utf-8")

    def broken_replace(src: Any, dst: Any) -> None:
        raise OSError("disk full")

    with monkeypatch.context() as m:
        m.setattr(report.os, "replace", broken_replace)
        with pytest.raises(InputError, match="--report: cannot be written"):
            write_report(ball, target)
    assert target.read_text(encoding="utf-8") == "previous report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.html"]

    pdf_target = tmp_path / "out.pdf"
    pdf_target.write_bytes(b"previous pdf")

    def half_written(self: Any, path: Path, model: Any) -> None:
        path.write_bytes(b"%PDF-1.4 half")
        raise RuntimeError("renderer crashed")

    with monkeypatch.context() as m:
        m.setattr(pdf._Doc, "finish", half_written)
        with pytest.raises(RuntimeError, match="crashed"):
            write_report(ball, pdf_target)
    assert pdf_target.read_bytes() == b"previous pdf"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.html", "out.pdf"]

    written = write_report(ball, target)
    assert written == target and target.read_text(encoding="utf-8").rstrip().endswith("</html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.html", "out.pdf"]
    assert oct(target.stat().st_mode & 0o777) == oct(0o644 & ~_umask())


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# --------------------------------------------------------------------------- content


def test_notebook_view_is_static_and_complete(weak: Any) -> None:
    text = repr_html(weak)
    assert "<script" not in text and text.count("<svg") >= 4  # diagram + three plots
    assert html.escape(EVIL) in text and EVIL not in text
    assert f"{weak.motor.peak_torque_Nm:.4g}" in text


def test_report_without_a_motor_states_the_demand() -> None:
    raw = copy.deepcopy(_raw())
    del raw["motor"]
    result = drivetrain.size(raw)
    text = render_html(result)
    body = text[: text.index("<script")]
    assert "no motor given" in body and "no catalog used" in body
    assert f"{result.metrics.peak_torque_Nm:.4g} N·m" in body


def test_axis_checks_join_the_motor_checks_and_the_verdict() -> None:
    raw = _raw()
    raw["motor"] = HG_KR43
    raw["guide"] = {"l_y": "50 mm", "l_z": "80 mm", "rated_force": "5000 N", "rated_pitch_moment": "1 N*m"}
    raw["transmission"].append({"type": "brake", "inertia": "0.1 kg*cm^2", "holding_torque": "5 N*m"})
    result = drivetrain.size(raw)
    text = render_html(result)
    body = html.unescape(re.sub(r"<[^>]+>", "|", text[: text.index("<script")]))
    verdict = body[body.index("FAIL"): body.index("Peak torque")]
    assert "guide pitch moment" in verdict and "Guide pitch moment: required" in verdict
    assert "brake" not in verdict.lower()  # the brake holds: not a failure
    rows = re.findall(r"\|(Guide [a-z]+ [a-z]+|Brake holding torque)\|.*?\|(PASS|FAIL)\|", body)
    assert dict(rows) == {"Guide normal force": "PASS", "Guide pitch moment": "FAIL", "Brake holding torque": "PASS"}


def test_every_formula_cites_the_docstring_of_its_implementation() -> None:
    for f in FORMULAS.values():
        doc = " ".join(docstring_of(f.ref).split())
        assert f.cite in doc, (f.key, f.ref)


def test_formulas_listed_match_the_axis(ball: Any, weak: Any) -> None:
    from drivetrain.report.model import build_report

    keys = {f.key for f in build_report(ball).formulas}
    assert {"ball_screw", "four_quadrant", "rms", "check_peak", "min_rms_ratio"} <= keys
    assert "hoist" not in keys and "belt" not in keys
    weak_keys = {f.key for f in build_report(weak).formulas}
    assert {"accel_times", "powers", "optimal_ratio"} <= weak_keys and "min_rms_ratio" not in weak_keys


# --------------------------------------------------------------------------- mechanism section


@pytest.fixture(scope="module")
def gantry() -> drivetrain.sizing.result.SizingResult:
    return drivetrain.size(EXAMPLES / "belt_gantry_3m.yaml")


def test_html_mechanism_section_has_the_checks_and_f1_across_the_stroke(gantry: Any) -> None:
    from drivetrain.dynamics.mechanism_modes import modes_of_result

    page = render_html(gantry)
    section = re.search(r'<section id="dt-mechanism">.*?</section>', page, re.S)
    assert section is not None
    body = section.group(0)
    rows = re.search(r'id="dt-table-mechanism-checks".*?<tbody>(.*?)</tbody>', body, re.S)
    assert rows is not None and rows.group(1).count("<tr>") == len(gantry.mechanism_checks)
    assert "Belt tension" in body and "Gates Mectrol" in body
    modes = modes_of_result(gantry)
    assert modes is not None
    assert f"{modes.f1_min_Hz:.4g} Hz" in body
    assert "Servo bandwidth (f1)" in body and "weakest link: timing_belt belt" in body
    assert 'data-plot="modes"' in body
    # the plot carries f1 at every position of the table
    assert page.count('"name":"first natural frequency f1"') == 1


def test_no_mechanism_section_without_mechanism_data() -> None:
    raw = yaml.safe_load((EXAMPLES / "ball_screw.yaml").read_text(encoding="utf-8"))
    for key in ("screw", "nut"):
        raw["mechanism"].pop(key)
    raw.pop("guide")
    raw["motor"] = {"name": "given", "inertia": "2 kg*cm^2", "rated_torque": "1.3 N*m", "peak_torque": "3.8 N*m",
                    "max_speed": "5000 rpm"}
    # a screw without its block is still bounded from its nominal diameter (the section says what decides it)
    html = render_html(drivetrain.size(raw))
    assert 'id="dt-mechanism"' in html and "mechanism.screw.root_diameter" in html
    rotary = yaml.safe_load((EXAMPLES / "rotary.yaml").read_text(encoding="utf-8"))
    rotary["motor"] = raw["motor"]
    assert 'id="dt-mechanism"' not in render_html(drivetrain.size(rotary))


@needs_poppler
def test_pdf_has_the_mechanism_section(gantry: Any, tmp_path: Path) -> None:
    pages = _page_texts(render_pdf(gantry, tmp_path / "gantry.pdf"))
    text = "\n".join(pages)
    assert "Mechanism: checks and modes" in text
    assert "Checks of the mechanism" in text and "First mode across the stroke" in text
    assert "bandwidth (f1)" in text
