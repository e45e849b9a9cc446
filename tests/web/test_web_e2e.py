"""End to end: Debian's Chromium (through Playwright) drives `drivetrain serve` on loopback.

Builds the shipped ball screw example through the form, sees the selection and the checks,
changes the mass and sees the result follow, saves, reloads and finds the project, downloads
the YAML (which sizes the same) and the report, and imports a bad CSV to see its row errors.
Set DRIVETRAIN_WEB_SCREENSHOTS=docs to write docs/web-editor.png and docs/web-catalog.png.
"""

from __future__ import annotations

import copy
import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.sizing.pipeline import size

pytestmark = pytest.mark.browser

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--no-first-run"]
ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "ball_screw.yaml"
TIMEOUT_MS = 30_000

BAD_CSV = """id,vendor,series,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2
E2E-1,E2E Motors,X,1.3,4.5,3000,6000,3.7e-5
E2E-2,E2E Motors,X,-1,4.5,3000,6000,3.7e-5
E2E-3,E2E Motors,X,1.3,plenty,3000,6000,3.7e-5
"""


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    if not Path(CHROMIUM).exists():
        pytest.skip("Debian chromium is not installed (make browser)")
    pytest.importorskip("playwright.sync_api")
    data = tmp_path_factory.mktemp("web-e2e")
    env = {**os.environ, "DRIVETRAIN_DATA_DIR": str(data), "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "drivetrain.cli", "serve", "--port", "0", "--data-dir", str(data)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        m = re.search(r"http://127\.0\.0\.1:\d+/", line)
        assert m, line + (proc.stderr.read() if proc.stderr else "")
        yield m.group(0), data
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=10)


@pytest.fixture(scope="module")
def browser(server: tuple[str, Path]) -> Iterator[Any]:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


@pytest.fixture
def page(browser: Any, server: tuple[str, Path]) -> Iterator[Any]:
    context = browser.new_context(viewport={"width": 1440, "height": 900}, accept_downloads=True)
    pg = context.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors: list[str] = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.goto(server[0])
    pg.wait_for_selector("body[data-ready='1']")
    yield pg
    context.close()
    assert not errors, errors


def wait_until(page: Any, js: str, arg: Any = None, timeout_s: float = TIMEOUT_MS / 1000) -> Any:
    """Poll a JS function until it returns something truthy (the page's CSP forbids wait_for_function's eval)."""
    deadline = time.monotonic() + timeout_s
    while True:
        value = page.evaluate(js, arg)
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {js} ({arg!r})")
        page.wait_for_timeout(50)


def wait_sized(page: Any) -> None:
    """Until the result shown answers the axis as it stands: an edit marks the page "pending" in the same
    event (app.js scheduleSize), so "idle" can only mean that the last edit's sizing has answered (an
    answer to an earlier edit is dropped by its sequence number); no wait on the clock."""
    wait_until(page, "() => document.body.dataset.sizing === 'idle'")


def yaml_pane(page: Any) -> dict[str, Any]:
    data = parse_yaml(page.input_value("#yaml-text"))
    assert isinstance(data, dict)
    return data


def metric(page: Any, label: str) -> str:
    return str(page.locator(".metrics-table tr", has_text=label).locator("td").inner_text())


def sig4(x: float) -> float:
    return float(f"{x:.4g}")


def screenshot(page: Any, name: str) -> None:
    folder = os.environ.get("DRIVETRAIN_WEB_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        page.evaluate("() => document.querySelectorAll('.form-pane, .results, .catalog-table-wrap')"
                      ".forEach(e => { e.scrollTop = 0; e.scrollLeft = 0; })")
        page.evaluate("() => document.activeElement && document.activeElement.blur()")
        page.wait_for_timeout(200)
        page.screenshot(path=str(Path(folder) / name))


def set_field(page: Any, path: str, value: Any) -> None:
    """Type or choose ``value`` in the input of the field at ``path`` (opening a "More" section if needed)."""
    selector = "#f-" + re.sub(r"[^A-Za-z0-9]+", "-", path)
    page.wait_for_selector(selector, state="attached")
    page.eval_on_selector(selector, "e => { for (let d = e.closest('details'); d; "
                                    "d = d.parentElement.closest('details')) d.open = true; }")
    tag = page.eval_on_selector(selector, "e => e.tagName")
    if tag == "SELECT":
        page.select_option(selector, str(value))
    else:
        page.fill(selector, str(value))


def set_leaves(page: Any, prefix: str, mapping: dict[str, Any]) -> None:
    for key, value in mapping.items():
        path = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            switch_on(page, path)
            set_leaves(page, path, value)
        else:
            set_field(page, path, value)


def switch_on(page: Any, path: str) -> None:
    """Tick the toggle of an optional section (``mechanism.screw``, ``guide``) if it has one and is off."""
    toggle = "#f-" + re.sub(r"[^A-Za-z0-9]+", "-", path) + "-on"
    if page.locator(toggle).count() and not page.is_checked(toggle):
        page.check(toggle)


def form_enterable(axis: dict[str, Any]) -> dict[str, Any]:
    """The axis without what the form leaves to the YAML pane (mapping fields: a guide's moment factors)."""
    out = copy.deepcopy(axis)
    if isinstance(out.get("guide"), dict):
        out["guide"].pop("moment_factors", None)
    return out


def build_through_the_form(page: Any, axis: dict[str, Any]) -> None:
    """Enter an axis file field by field, as a user would (every key must have an input)."""
    unsupported = set(axis) - {"axis", "gravity", "efficiency_model", "extra_inertia", "mechanism", "transmission",
                               "profile", "motor", "guide"}
    assert not unsupported, f"the e2e builder does not enter {unsupported}"
    for key in ("axis", "gravity", "efficiency_model", "extra_inertia"):
        if key in axis:
            set_field(page, key, axis[key])
    mechanism = dict(axis["mechanism"])
    set_field(page, "mechanism.type", mechanism.pop("type"))
    set_leaves(page, "mechanism", mechanism)
    for k, element in enumerate(axis.get("transmission", [])):
        element = dict(element)
        page.select_option("#f-transmission-add-type", element.pop("type"))
        page.click("text=Add element")
        set_leaves(page, f"transmission[{k}]", element)
    for k, step in enumerate(axis.get("profile", [])):
        step = dict(step)
        page.click("text=Add dwell" if "dwell" in step else "text=Add move")
        if "shape" in step:  # first: the jerk fraction appears for s-curves
            set_field(page, f"profile[{k}].shape", step.pop("shape"))
        set_leaves(page, f"profile[{k}]", step)
    if "guide" in axis:
        switch_on(page, "guide")
        set_leaves(page, "guide", axis["guide"])
    motor = axis.get("motor")
    if motor is not None:
        page.check("#f-motor-on")
        motor = dict(motor)
        if "select" in motor:
            page.check("#f-motor-select-on")
            set_leaves(page, "motor.select", motor.pop("select"))
        set_leaves(page, "motor", motor)


def test_build_size_save_reload_and_download(page: Any, server: tuple[str, Path], tmp_path: Path) -> None:
    example = form_enterable(parse_yaml(EXAMPLE.read_text(encoding="utf-8")))
    build_through_the_form(page, example)
    assert yaml_pane(page) == example, "the form did not build the example axis"
    wait_sized(page)

    expected = size(example)
    banner = page.locator("#result-banner")
    if expected.selection is not None and expected.selection.selected is not None:
        selected = expected.selection.selected.motor
        assert f"Selected motor: {selected}" in banner.inner_text()
        assert page.locator(".candidates-table tbody tr").count() == len(expected.candidates)
        checks = expected.selection.selected.checks
    else:
        assert expected.motor is not None
        assert expected.motor.name in banner.inner_text()
        checks = expected.motor.checks
    assert page.locator(".checks-table tbody tr").count() == len(checks)
    assert page.locator(".checks-table").inner_text().count("ok") >= sum(1 for c in checks if c.ok)
    assert float(metric(page, "RMS torque").split()[0]) == sig4(expected.metrics.rms_torque_Nm)
    assert page.locator("#plot-plane .main-svg").count() >= 1
    screenshot(page, "web-editor.png")

    if expected.candidates:  # compare two candidates side by side
        boxes = page.locator(".candidates-table tbody input[type=checkbox]")
        boxes.nth(0).check()
        boxes.nth(1).check()
        compare = page.locator(".compare-table")
        compare.wait_for()
        heads = compare.locator("thead th").all_inner_texts()
        assert heads[1].startswith(expected.candidates[0].motor)
        assert heads[2].startswith(expected.candidates[1].motor)
        wait_until(page, "() => [...document.querySelectorAll('#plot-plane .legendtext')]"
                         ".some(t => t.textContent.includes('cycle') && !t.textContent.includes('|n|'))")
        page.click("text=Clear comparison")

    set_field(page, "mechanism.load.mass", "40 kg")
    wait_sized(page)
    heavier = {**example, "mechanism": {**example["mechanism"], "load": {**example["mechanism"]["load"],
                                                                          "mass": "40 kg"}}}
    rms = size(heavier).metrics.rms_torque_Nm
    assert rms > expected.metrics.rms_torque_Nm
    wait_until(page, "t => document.querySelector('.metrics-table').innerText.includes(t)", f"{sig4(rms):g}")
    assert float(metric(page, "RMS torque").split()[0]) == sig4(rms)

    set_field(page, "mechanism.load.mass", "-3 kg")
    wait_sized(page)
    mass = page.locator("#f-mechanism-load-mass")
    assert mass.get_attribute("aria-invalid") == "true"
    message = page.locator(".field[data-field='mechanism.load.mass'] .field-error").inner_text()
    assert "must be > 0 kg, got -3 kg" in message
    assert "1 problem" in banner.inner_text()
    set_field(page, "mechanism.load.mass", "40 kg")
    wait_sized(page)
    assert mass.get_attribute("aria-invalid") is None

    page.fill("#project-name", "Z lift web")
    page.click("#save-project")
    wait_until(page, "() => document.querySelector('#save-state').innerText.includes('saved, version 1')")
    page.reload()
    page.wait_for_selector("body[data-ready='1']")
    project = page.locator(".project-list button", has_text="Z lift web")
    assert project.count() == 1
    project.click()
    wait_until(page, "() => document.querySelector('#f-mechanism-load-mass')?.value === '40 kg'")
    wait_sized(page)
    assert float(metric(page, "RMS torque").split()[0]) == sig4(rms)

    with page.expect_download() as download:
        page.click("#download-yaml")
    path = tmp_path / download.value.suggested_filename
    download.value.save_as(path)
    assert path.name == "Z_lift.yaml"
    downloaded = parse_yaml(path.read_text(encoding="utf-8"))
    assert downloaded == heavier
    again = size(downloaded)
    assert again.metrics.rms_torque_Nm == pytest.approx(rms, rel=1e-12)
    assert [c.motor for c in again.candidates] == [c.motor for c in size(heavier).candidates]

    for fmt, check in (("html", lambda b: b"<html" in b[:2000].lower()), ("pdf", lambda b: b.startswith(b"%PDF"))):
        with page.expect_download(timeout=120_000) as download:
            page.click(f"#report-{fmt}")
        report = tmp_path / download.value.suggested_filename
        download.value.save_as(report)
        assert report.suffix == f".{fmt}" and check(report.read_bytes()), report
    # the server deletes a report's temp file in a background task after the response: the download
    # can complete first, so give the task a moment before calling a file left over
    deadline = time.monotonic() + 10.0
    while list((server[1] / "tmp").glob("*")) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not list((server[1] / "tmp").glob("*")), "report temp files left in the data folder"


def test_catalog_browse_envelope_and_bad_csv(page: Any) -> None:
    page.click("#tab-catalog")
    page.wait_for_selector(".catalog-table tbody tr")
    page.click("button.sort:has-text('T peak')")
    page.wait_for_selector("th[aria-sort='ascending'] button.sort:has-text('T peak')")
    first = page.locator(".catalog-table tbody tr").first.locator("th").inner_text()
    page.locator(".catalog-table tbody tr").first.locator("th button").click()
    page.wait_for_selector("#plot-envelope .main-svg")
    wait_until(page, "t => document.querySelector('#catalog-detail h3')?.innerText === t", first)
    page.click("#cat-gearboxes")
    page.wait_for_selector("button.sort:has-text('ratio')")
    page.fill("#flt-rmin", "5")
    page.fill("#flt-rmax", "5")
    wait_until(page, """() => {
        const cells = [...document.querySelectorAll('.catalog-table tbody tr td:nth-child(4)')];
        return cells.length > 0 && cells.every(c => c.innerText === '5');
    }""")
    page.click("#cat-motors")
    page.wait_for_selector(".catalog-table tbody tr")

    page.set_input_files("#import-file", files=[{"name": "bad.csv", "mimeType": "text/csv",
                                                  "buffer": BAD_CSV.encode()}])
    page.click("#import-submit")
    rows = page.locator(".import-errors tbody tr")
    rows.first.wait_for()
    assert rows.count() == 2
    assert rows.nth(0).locator("th").inner_text() == "3" and "rated_torque_Nm" in rows.nth(0).inner_text()
    assert rows.nth(1).locator("th").inner_text() == "4" and "peak_torque_Nm" in rows.nth(1).inner_text()
    assert "not imported" in page.locator("#import-result").inner_text()
    page.fill("#flt-q", "E2E-")
    page.wait_for_selector("#cat-page:has-text('nothing matches')")
    page.fill("#flt-q", "")
    page.wait_for_selector(".catalog-table tbody tr")
    page.locator(".catalog-table tbody tr").nth(3).locator("th button").click()
    page.wait_for_selector("#plot-envelope .main-svg")
    screenshot(page, "web-catalog.png")


def test_every_control_has_a_label_and_buttons_are_buttons(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    unlabeled = page.evaluate("""() => [...document.querySelectorAll('input, select, textarea')]
        .filter(e => e.type !== 'hidden' && !e.hidden && !e.closest('[hidden]'))
        .filter(e => !(e.labels && e.labels.length) && !e.getAttribute('aria-label')
                     && !e.getAttribute('aria-labelledby'))
        .map(e => e.outerHTML.slice(0, 120))""")
    assert unlabeled == []
    clickable_divs = page.evaluate("""() => [...document.querySelectorAll('div[onclick], span[onclick], a:not([href])')]
        .map(e => e.outerHTML.slice(0, 80))""")
    assert clickable_divs == []
    page.keyboard.press("Tab")
    assert page.evaluate("document.activeElement.className") == "skip"
    page.focus("#project-name")
    page.keyboard.press("Tab")
    assert page.evaluate("document.activeElement.id") == "save-project"


@pytest.fixture(scope="module", autouse=True)
def _chromium_present() -> None:
    if shutil.which("chromium") is None and not Path(CHROMIUM).exists():
        pytest.skip("Debian chromium is not installed (make browser)")


def test_yaml_pane_and_form_stay_in_sync(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    text = page.input_value("#yaml-text")
    assert "mass: 25 kg" in text
    page.fill("#yaml-text", text.replace("mass: 25 kg", "mass: 31 kg"))
    wait_until(page, "() => document.querySelector('#f-mechanism-load-mass')?.value === '31 kg'")
    page.fill("#yaml-text", text.replace("mass: 25 kg", "mass: [oops"))
    wait_until(page, "() => !document.querySelector('#yaml-error').hidden")
    assert "not valid YAML" in page.inner_text("#yaml-error")
    page.fill("#f-mechanism-lead", "5 mm")
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('lead: 5 mm')")
    assert page.locator("#yaml-error").is_hidden()


# ---------------------------------------------------------------------------------- the editor, as a new user tries it


def test_a_new_axis_shows_no_error_before_the_first_edit(page: Any) -> None:
    wait_sized(page)
    assert page.locator("#axis-form .field-error").count() == 0
    assert page.locator("#error-summary").is_hidden()
    assert "Fill in the mechanism" in page.inner_text("#result-banner")
    set_field(page, "mechanism.load.mass", "10 kg")  # the first edit: what is still missing is shown
    wait_sized(page)
    assert page.locator(".field[data-field='mechanism.lead'] .field-error").inner_text().endswith("is required")


def test_ticking_motor_starts_a_catalog_selection_without_an_error(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    page.uncheck("#f-motor-on")
    wait_sized(page)
    assert "motor" not in yaml_pane(page)
    page.check("#f-motor-on")
    wait_sized(page)
    assert yaml_pane(page)["motor"] == {"select": {}}
    assert page.is_checked("#f-motor-select-on"), "select from the catalog is the first choice"
    assert page.locator("#axis-form .field-error").count() == 0
    assert page.locator("#error-summary").is_hidden()
    assert "Selected motor:" in page.inner_text("#result-banner")

    page.check("#f-motor-given-on")  # a given motor: no error before the user types anything
    wait_sized(page)
    assert "select" not in yaml_pane(page)["motor"]
    assert page.locator("#axis-form .field-error").count() == 0
    assert page.locator("#error-summary").is_hidden()
    assert "Fill in the motor" in page.inner_text("#result-banner")
    set_field(page, "motor.inertia", "0.3 kg*cm^2")  # the first edit: what is still missing is named
    wait_sized(page)
    assert "rated_torque" in page.inner_text("fieldset[data-path='motor']")
    assert "problem" in page.inner_text("#result-banner")
    page.check("#f-motor-select-on")
    wait_sized(page)
    assert yaml_pane(page)["motor"] == {"inertia": "0.3 kg*cm^2", "select": {}}
    assert page.locator("#axis-form .field-error").count() == 0


def test_changing_the_mechanism_type_keeps_what_applies_and_says_what_it_cleared(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    before = yaml_pane(page)["mechanism"]
    set_field(page, "mechanism.type", "lead_screw")  # the same model: everything applies
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('lead_screw')")
    assert yaml_pane(page)["mechanism"] == {**before, "type": "lead_screw"}
    assert page.input_value("#f-mechanism-lead") == "10 mm"
    assert page.input_value("#f-mechanism-length") == "800 mm"
    assert page.locator(".type-notice").count() == 0

    set_field(page, "mechanism.type", "rack_pinion")  # a screw's diameter is not a pinion's
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('rack_pinion')")
    after = yaml_pane(page)["mechanism"]
    assert after == {"type": "rack_pinion", "efficiency": 0.9, "incline": "90 deg", "load": before["load"]}
    assert page.input_value("#f-mechanism-diameter") == ""
    notice = page.inner_text(".type-notice")
    for name in ("lead", "diameter", "length", "material"):
        assert name in notice.split("cleared")[1].split("kept")[0], notice
    assert "load" in notice.split("kept")[1]
    set_field(page, "mechanism.diameter", "40 mm")  # the user's next edit there retires the notice
    assert page.locator(".type-notice").count() == 0
    wait_sized(page)
    assert "Selected motor:" in page.inner_text("#result-banner")

    set_field(page, "mechanism.type", "rotary")  # a rotary load is another model: the linear load goes
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('rotary')")
    assert "load" not in yaml_pane(page)["mechanism"]
    assert "load" in page.inner_text(".type-notice").split("cleared")[1].split("kept")[0]


def test_every_profile_option_has_a_field(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    kinds = page.eval_on_selector("#f-profile-0--kind", "s => [...s.options].map(o => o.value)")
    assert set(kinds) == {"move", "speed", "optimal", "cam", "dwell"}
    page.select_option("#f-profile-0--kind", "optimal")
    wait_until(page, "() => document.querySelector('#f-profile-0-max-speed') !== null")
    set_field(page, "profile[0].max_speed", "0.5 m/s")
    set_field(page, "profile[0].max_accel", "5 m/s^2")
    set_field(page, "profile[0].max_jerk", "200 m/s^3")
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('max_jerk')")
    assert yaml_pane(page)["profile"][0] == {"move": "200 mm", "max_speed": "0.5 m/s", "max_accel": "5 m/s^2",
                                              "max_jerk": "200 m/s^3"}
    assert page.locator("input.other").count() == 0, "no option is left to an 'Other keys' box"
    wait_sized(page)
    assert "problem" not in page.inner_text("#result-banner")
    expected = size(yaml_pane(page))
    wait_until(page, "t => document.querySelector('.metrics-table').innerText.includes(t)",
               f"{sig4(expected.metrics.rms_torque_Nm):g}")

    page.select_option("#f-profile-0--kind", "cam")
    wait_until(page, "() => document.querySelector('#f-profile-0-law') !== null")
    set_field(page, "profile[0].law", "modified_sine")
    set_field(page, "profile[0].time", "0.5 s")
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('modified_sine')")
    assert yaml_pane(page)["profile"][0] == {"move": "200 mm", "time": "0.5 s", "law": "modified_sine"}

    page.select_option("#f-profile-0--kind", "speed")
    wait_until(page, "() => document.querySelector('#f-profile-0-speed') !== null")
    set_field(page, "profile[0].speed", "24 m/min")
    set_field(page, "profile[0].accel", "0.1 s")
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('24 m/min')")
    assert yaml_pane(page)["profile"][0] == {"speed": "24 m/min", "time": "0.5 s", "accel": "0.1 s"}
    page.select_option("#f-profile-0--kind", "move")
    set_field(page, "profile[0].move", "200 mm")
    set_field(page, "profile[0].shape", "s_curve")
    page.wait_for_selector("#f-profile-0-jerk")
    wait_sized(page)
    assert "problem" not in page.inner_text("#result-banner")


def test_unit_hints_show_the_unit_the_user_writes(page: Any) -> None:
    page.select_option("#example-select", "rotary")
    wait_sized(page)
    unit = "() => document.querySelector(\"[data-field='mechanism.incline'] .unit\")?.innerText"
    set_field(page, "mechanism.incline", "30 deg")
    wait_until(page, f"() => ({unit})() === '[deg]'")
    set_field(page, "mechanism.incline", "0.5")  # a bare number is read in SI
    wait_until(page, f"() => ({unit})() === '[rad]'")
    set_field(page, "mechanism.incline", "")  # empty: the unit a user is likely to type
    wait_until(page, f"() => ({unit})() === '[deg]'")
    shown = page.evaluate("() => [...document.querySelectorAll('.field .unit')].map(u => u.innerText)")
    assert "[rad]" not in shown and "[rad/s]" not in shown, shown


def test_the_catalog_opens_on_industrial_servos_in_engineering_numbers(page: Any) -> None:
    page.click("#tab-catalog")
    page.wait_for_selector(".catalog-table tbody tr")
    assert page.input_value("#flt-kind") == "ac_servo"
    text = page.inner_text(".catalog-table tbody")
    assert not re.search(r"\d\.\d+e[-+]?\d", text), "no scientific notation"
    shown = page.evaluate("""() => [...document.querySelectorAll('.catalog-table tbody tr')].map(r =>
        [...r.querySelectorAll('td')].map(c => c.innerText))""")
    inertia = [float(r[7]) for r in shown if r[7] not in ("–", "")]
    assert inertia and all(0.001 <= v < 1e6 for v in inertia), inertia  # kg·cm², plain numbers
    assert page.evaluate("() => import('/static/results.js').then(m => [m.fmt(1.2e-5), m.fmt(0.54), m.fmt(1.27), "
                         "m.fmt(2.4e7), m.fmt(999999.9)])") == ["12e-6", "0.54", "1.27", "24e6", "1e6"]
    slashed = page.locator(".catalog-table tbody th button", has_text="/").first  # FANUC's "beta 0.2/5000is"
    name = slashed.inner_text()
    slashed.click()
    wait_until(page, "t => document.querySelector('#catalog-detail h3')?.innerText === t", name)
    assert name in page.inner_text("#plot-envelope")


def test_candidate_columns_fit_or_scroll_with_the_motor_in_view(page: Any) -> None:
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    page.wait_for_selector(".candidates-table")
    geometry = page.evaluate("""() => {
        const wrap = document.querySelector('.candidates-wrap'), results = document.querySelector('.results');
        const first = document.querySelector('.candidates-table tbody th');
        const r = results.getBoundingClientRect(), w = wrap.getBoundingClientRect();
        return {fits: wrap.scrollWidth <= wrap.clientWidth, overflow: getComputedStyle(wrap).overflowX,
                sticky: getComputedStyle(first).position, wrapRight: w.right, resultsRight: r.right,
                first: first.innerText};
    }""")
    assert geometry["wrapRight"] <= geometry["resultsRight"] + 0.5, geometry  # nothing cut by the pane
    assert geometry["fits"] or (geometry["overflow"] in ("auto", "scroll") and geometry["sticky"] == "sticky"), geometry
    page.evaluate("() => { document.querySelector('.candidates-wrap').scrollLeft = 10000; }")
    visible = page.evaluate("""() => {
        const wrap = document.querySelector('.candidates-wrap').getBoundingClientRect();
        const first = document.querySelector('.candidates-table tbody th').getBoundingClientRect();
        const last = document.querySelector('.candidates-table thead th:last-child').getBoundingClientRect();
        return {first: first.left >= wrap.left - 0.5 && first.right <= wrap.right + 0.5,
                last: last.right <= wrap.right + 1.0}  // scrollWidth is whole pixels;
    }""")
    assert visible == {"first": True, "last": True}, visible


def test_mechanism_checks_and_modes_show_in_the_results(page: Any) -> None:
    # The 3 m belt gantry: its belt checks, the servo-bandwidth check and f1 across the stroke.
    page.select_option("#example-select", "belt_gantry_3m")
    wait_sized(page)
    wait_until(page, "() => !document.querySelector('#mechanism').hidden")
    table = page.locator(".mechanism-table")
    text = table.inner_text()
    expected = size(ROOT / "examples" / "belt_gantry_3m.yaml").mechanism_checks
    assert table.locator("tbody tr").count() == len(expected) + 1  # and the servo-bandwidth check
    assert "belt tension" in text and "servo bandwidth" in text
    assert "weakest link: timing_belt belt" in page.inner_text(".modes-summary")
    assert page.locator("#plot-modes .main-svg").count() >= 1
    # An axis without stiffness data hides the section.
    page.select_option("#example-select", "rotary")
    wait_sized(page)
    wait_until(page, "() => document.querySelector('#mechanism').hidden")
    assert page.locator("#plot-modes").is_hidden()


def test_the_dynamics_show_in_the_results(page: Any) -> None:
    """The belt axis with requirements: the candidates judged (web/static/dynamics.js) under the mechanism,
    the static pick labelled "passed over for how it moves", and folded apart in the banner."""
    page.select_option("#example-select", "belt_dynamic")
    wait_sized(page)
    wait_until(page, "() => document.querySelector('.dynamics-table') !== null")
    first = size(ROOT / "examples" / "belt_dynamic.yaml").selection.dynamics["passed_over"][0]["motor"]
    table = page.inner_text(".dynamics-table")
    assert first in table and "passed over for how it moves" in table and "answer" in table
    assert "static pick passed over for how it moves" in page.inner_text("#result-banner")
    assert "ends up with an inertia ratio" in page.inner_text(".dynamics-inertia")


def test_history_restores_and_delete_asks_twice(page: Any) -> None:
    """Restoring a version adds one; a project is deleted on the second click within 4 s, one click only arms."""
    page.fill("#project-name", "to be deleted")
    page.click("#save-project")
    wait_until(page, "() => document.querySelector('#save-state').innerText.includes('saved, version 1')")
    # the project list is fetched again after the save: on a loaded machine it can lag the save state
    wait_until(page, "() => [...document.querySelectorAll('.project-list button')]"
                     ".some(b => b.innerText.includes('to be deleted'))")
    listed = page.locator(".project-list button", has_text="to be deleted")
    assert listed.count() == 1
    set_field(page, "axis", "second version")  # a second version, then back to the first
    wait_until(page, "() => document.querySelector('#yaml-text').value.includes('second version')")
    page.click("#save-project")
    wait_until(page, "() => document.querySelectorAll('#version-list li').length === 2")
    page.click("#history summary")
    page.click("#version-list button[aria-label='Restore version 1']")
    wait_until(page, "() => document.querySelectorAll('#version-list li').length === 3")
    assert page.locator("#version-list button[aria-label='Restore version 3']").count() == 0  # the current one
    button = page.locator("#delete-project")
    button.click()
    assert button.inner_text() == "Really delete?"
    wait_until(page, "() => document.querySelector('#delete-project').innerText === 'Delete'", timeout_s=6)
    assert listed.count() == 1, "one click deleted the project"
    button.click()
    button.click()
    wait_until(page, "() => ![...document.querySelectorAll('.project-list button')]"
                     ".some(b => b.innerText.includes('to be deleted'))")
    assert button.inner_text() == "Delete"
