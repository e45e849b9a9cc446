"""End to end, the machine view: Debian's Chromium (through Playwright) drives `drivetrain serve` on loopback.

Creates a machine project from the shipped examples/machine/pick_and_place.yaml, sizes it and sees
the machine table, the bus plot, the bus figures and the bill of materials (the package's own
numbers), a bad offset gets its error at that field, the project survives save and reload with
its history, the report and AAS downloads work, and an axis project joins a machine by reference.
Set DRIVETRAIN_WEB_SCREENSHOTS=docs to write docs/web-machine.png.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from drivetrain.machine.result import size_machine
from tests.web.test_web_e2e import browser, page, screenshot, server, wait_until  # noqa: F401 (fixtures)

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "machine" / "pick_and_place.yaml"


def wait_machine(pg: Any) -> None:
    """Until the machine sizing asked for has answered."""
    wait_until(pg, "() => document.body.dataset.machine === 'idle'", timeout_s=90)


def size_now(pg: Any) -> None:
    pg.evaluate("() => { document.body.dataset.machine = 'asked'; }")
    pg.click("#m-size")
    wait_machine(pg)


def bus_value(pg: Any, label: str) -> str:
    return str(pg.locator(".bus-table tr", has_text=label).first.locator("td").first.inner_text())


def sig4(x: float) -> str:
    return f"{float(f'{x:.4g}'):g}"


def test_machine_project_from_the_example(page: Any, server: tuple[str, Path], tmp_path: Path) -> None:  # noqa: F811
    page.click("#tab-machine")
    page.wait_for_selector("#m-example-select option[value='pick_and_place']", state="attached")
    page.select_option("#m-example-select", "pick_and_place")
    wait_until(page, "() => document.querySelectorAll('.machine-axes-table tbody tr[data-owner]').length === 4")
    assert "pick-and-place" in page.input_value("#m-yaml")
    assert "include:" not in page.input_value("#m-yaml")  # the example's axis files come inline
    page.fill("#m-name", "Pick and place")
    page.click("#m-save")
    wait_until(page, "() => document.getElementById('m-save-state').textContent === 'saved, version 1'")

    size_now(page)
    expected = size_machine(EXAMPLE, phasing_samples=200).to_dict()
    m = expected["machine"]
    assert "every axis passes" in page.inner_text("#m-banner")
    rows = page.locator(".machine-table tbody tr")
    assert rows.count() == 5  # X, Y's two motors, Z, R
    assert "1FT7044-5AK7" in rows.nth(0).inner_text() and "SINAMICS S120 Motor Module 9 A" in rows.nth(0).inner_text()
    assert "50 %" in rows.nth(1).inner_text() and "planetary gearbox i = 7" in rows.nth(1).inner_text()
    wait_until(page, "() => !!document.querySelector('#plot-bus .main-svg')")
    assert page.locator("#plot-bus .scatterlayer .trace").count() == 5  # four axes and the bus
    assert bus_value(page, "bus peak power") == f"{sig4(m['bus_peak_power_W'])} W"
    assert bus_value(page, "braking resistor energy per cycle") == f"{sig4(m['resistor_energy_per_cycle_J'])} J"
    assert bus_value(page, "supply peak line current") == f"{sig4(m['supply_peak_current_A'])} A"
    bom = page.locator(".bom-table tbody tr")
    assert bom.count() == len(expected["bill_of_materials"])
    motor_rows = bom.filter(has_text="1FT7044-5AK7")  # four as they are, the Z axis's as its brake variant
    assert sum(int(motor_rows.nth(k).locator("td").nth(2).inner_text()) for k in range(motor_rows.count())) == 5
    assert "to choose" in bom.filter(has_text="braking resistor").inner_text()
    screenshot(page, "web-machine.png")
    # each axis's result: the link opens its checks
    page.locator(".machine-table tbody tr").nth(3).locator("button.link").click()
    assert page.locator("#m-axis-Z-1").get_attribute("open") is not None
    assert page.locator("#m-axis-Z-1 .checks-table").is_visible()

    # a bad field: its error at that field (the API's 422 names axes[0].offset)
    page.fill("[data-field='axes[0].offset']", "-1 s")
    page.keyboard.press("Tab")
    assert "offset: -1 s" in page.input_value("#m-yaml")
    size_now(page)
    offset = page.locator("[data-field='axes[0].offset']")
    assert offset.get_attribute("aria-invalid") == "true"
    assert "must be >= 0" in page.locator("[data-field='axes[0].offset'] + .inline-error").inner_text()
    assert "cannot be sized" in page.inner_text("#m-banner")
    page.fill("[data-field='axes[0].offset']", "0.1 s")
    page.keyboard.press("Tab")
    page.click("#m-save")
    wait_until(page, "() => document.getElementById('m-save-state').textContent === 'saved, version 2'")

    # save and reload keep it, with its history
    page.reload()
    page.wait_for_selector("body[data-ready='1']")
    assert page.locator("#view-machine").is_visible()
    wait_until(page, "() => document.getElementById('m-name').value === 'Pick and place'")
    assert page.input_value("[data-field='axes[0].offset']") == "0.1 s"
    assert page.locator(".machine-axes-table tbody tr[data-owner]").count() == 4
    page.click("#m-history summary")
    wait_until(page, "() => document.querySelectorAll('#m-version-list li').length === 2")
    assert page.locator("#m-project-list .project").count() == 1
    page.click("#tab-editor")
    assert page.locator("#project-list .project").count() == 0  # machine projects stay out of the axis list

    # downloads: the machine report (HTML) and the AAS submodel
    page.click("#tab-machine")
    with page.expect_download(timeout=120_000) as info:
        page.click("#m-report-html")
    html_path = tmp_path / "m.html"
    info.value.save_as(html_path)
    assert info.value.suggested_filename == "pick-and-place-report.html"
    text = html_path.read_text(encoding="utf-8")
    assert "DC bus over the machine cycle" in text and "Bill of materials" in text
    with page.expect_download(timeout=60_000) as info:
        page.click("#m-aas")
    aas_path = tmp_path / "m.aas.json"
    info.value.save_as(aas_path)
    assert json.loads(aas_path.read_text())["submodels"][0]["idShort"] == "PowerDriveTrainSizing"


def test_an_axis_project_joins_a_machine(page: Any, server: tuple[str, Path]) -> None:  # noqa: F811
    x_belt = (ROOT / "examples" / "machine" / "x_belt.yaml").read_text(encoding="utf-8")
    r = page.request.post(f"{server[0]}api/projects", data={"name": "X belt axis", "yaml": x_belt})
    assert r.status == 201, r.text()
    pid = r.json()["id"]
    page.click("#tab-machine")
    page.click("#m-new")
    page.fill("#m-f-cycle", "1.6 s")
    page.keyboard.press("Tab")
    wait_until(page, "(id) => !!document.querySelector(`#m-add-select option[value='${id}']`)", str(pid))
    page.select_option("#m-add-select", str(pid))
    page.click("#m-add")
    page.select_option("#m-add-select", str(pid))
    page.click("#m-add")
    assert page.locator(".machine-axes-table tbody tr[data-owner]").count() == 2
    assert f"project: {pid}" in page.input_value("#m-yaml")
    page.select_option("[data-field='axes[1].start']", "after")
    assert "after: X belt axis" in page.input_value("#m-yaml")
    size_now(page)
    assert page.locator(".machine-table tbody tr").count() == 2
    assert "X belt axis 2" in page.inner_text(".machine-table")
    # remove one: the other's after: goes back to an offset
    page.click("button[aria-label='Remove axis X belt axis']")
    assert page.locator(".machine-axes-table tbody tr[data-owner]").count() == 1
    assert "after:" not in page.input_value("#m-yaml")
    size_now(page)
    assert page.locator(".machine-table tbody tr").count() == 1
    # the link to the axis project opens it in the axis editor
    page.click(".machine-table button:has-text('open project')")
    wait_until(page, "() => document.getElementById('project-name').value === 'X belt axis'")
    assert page.locator("#view-editor").is_visible()
