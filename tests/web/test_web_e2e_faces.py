"""The page as people use it (issue 31): laid out for 1,280 to 1,920 px (boxes inside their containers, the
toolbar on one line), no failing request on first load, the drives in the catalog tab, the supply and
environment of a selection in the form, and a short "not orderable" verdict with the list folded.

Debian's Chromium through the harness of test_web_e2e.py; every wait polls a condition of the page.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from drivetrain import catalog
from drivetrain.sizing.pipeline import size
from tests.web.test_web_e2e import (  # noqa: F401 (fixtures)
    TIMEOUT_MS,
    browser,
    page,
    server,
    set_field,
    switch_on,
    wait_sized,
    wait_until,
    yaml_pane,
)

pytestmark = pytest.mark.browser

WIDTHS = (1280, 1440, 1920)
"""The widths the page is laid out for (docs/architecture.md, "The web page")."""

GEOMETRY = """(sel) => {
  const box = (e) => { const b = e.getBoundingClientRect(); return {l: b.left, t: b.top, r: b.right, b: b.bottom}; };
  const shown = (e) => !e.hidden && e.getClientRects().length > 0 && getComputedStyle(e).visibility !== 'hidden';
  const bar = document.querySelector(sel.toolbar);
  const pane = document.querySelector(sel.pane);
  return {
    toolbar: box(bar),
    tools: [...bar.children].filter(shown)
      .filter(e => e.getBoundingClientRect().width > 0 && e.getBoundingClientRect().height > 0)
      .map(e => [e.id || e.tagName, box(e)]),
    pane: box(pane),
    paneScrolls: pane.scrollWidth > pane.clientWidth,
    items: [...document.querySelectorAll(sel.items)].filter(shown).map(box),
    wraps: [...pane.querySelectorAll('.table-wrap')].filter(shown).map(w => [w.scrollWidth, w.clientWidth]),
  };
}"""


def inside(inner: dict[str, float], outer: dict[str, float], slack: float = 0.5) -> bool:
    return (inner["l"] >= outer["l"] - slack and inner["r"] <= outer["r"] + slack
            and inner["t"] >= outer["t"] - slack and inner["b"] <= outer["b"] + slack)


def assert_laid_out(g: dict[str, Any], what: str) -> None:
    """Every tool inside the toolbar and on one line; the items inside the pane; nothing scrolls sideways."""
    bar = g["toolbar"]
    for name, b in g["tools"]:
        assert inside(b, bar), f"{what}: {name} {b} outside the toolbar {bar}"
    tops = [b["t"] for _, b in g["tools"]]
    bottoms = [b["b"] for _, b in g["tools"]]
    assert max(tops) < min(bottoms), f"{what}: the toolbar wraps: {g['tools']}"
    assert g["items"], f"{what}: nothing to measure"
    for b in g["items"]:
        horizontal = {**b, "t": g["pane"]["t"], "b": g["pane"]["t"]}  # the pane scrolls vertically
        assert inside(horizontal, g["pane"]), f"{what}: {b} cut by the pane {g['pane']}"
    assert not g["paneScrolls"], f"{what}: the pane scrolls sideways"
    for scroll, client in g["wraps"]:
        assert scroll <= client, f"{what}: a table is wider than its pane ({scroll} > {client} px)"


@pytest.fixture(params=WIDTHS, ids=[f"{w}px" for w in WIDTHS])
def sized_page(request: pytest.FixtureRequest, browser: Any, server: tuple[str, Path]) -> Iterator[Any]:  # noqa: F811
    context = browser.new_context(viewport={"width": request.param, "height": 900})
    pg = context.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    pg.goto(server[0])
    pg.wait_for_selector("body[data-ready='1']")
    yield pg
    context.close()


def test_the_editor_and_the_machine_view_fit_the_width(sized_page: Any) -> None:
    pg = sized_page
    pg.select_option("#example-select", "ball_screw")
    wait_sized(pg)
    pg.wait_for_selector(".profile-table .row-buttons button")
    g = pg.evaluate(GEOMETRY, {"toolbar": "#view-editor .toolbar", "pane": "#view-editor .form-pane",
                               "items": ".profile-table .row-buttons button"})
    assert_laid_out(g, "axis editor")
    assert len(g["items"]) >= 3 * 4  # up, down and remove of each step

    pg.click("#tab-machine")
    wait_until(pg, "() => document.querySelectorAll('#m-example-select option').length > 1")
    pg.select_option("#m-example-select", "pick_and_place")
    pg.wait_for_selector(".machine-axes-table tbody tr")
    g = pg.evaluate(GEOMETRY, {"toolbar": "#view-machine .toolbar", "pane": "#view-machine .form-pane",
                               "items": ".machine-axes-table tr > :last-child"})
    assert_laid_out(g, "machine axes")


def test_the_first_load_makes_no_failing_request(browser: Any, server: tuple[str, Path]) -> None:  # noqa: F811
    context = browser.new_context(viewport={"width": 1440, "height": 900})
    pg = context.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    failures: list[str] = []
    pg.on("console", lambda m: failures.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
    pg.on("pageerror", lambda e: failures.append(f"page error: {e}"))
    pg.on("response", lambda r: failures.append(f"{r.status} {r.request.method} {r.url}") if r.status >= 400 else None)
    pg.on("requestfailed", lambda r: failures.append(f"failed {r.method} {r.url}: {r.failure}"))
    try:
        pg.goto(server[0])
        pg.wait_for_selector("body[data-ready='1']")
        wait_sized(pg)
        assert "Fill in the mechanism" in pg.inner_text("#result-banner")
        for tab, ready in (("#tab-machine", "#m-example-select option:nth-child(2)"),
                           ("#tab-catalog", ".catalog-table tbody tr")):
            pg.click(tab)
            pg.wait_for_selector(ready, state="attached")
        pg.click("#cat-drives")
        pg.wait_for_selector("button.sort:has-text('I cont.')")
        pg.click("#tab-editor")
        wait_sized(pg)
    finally:
        context.close()
    assert failures == []


def test_the_catalog_tab_lists_drives_beside_motors_and_gearboxes(page: Any) -> None:  # noqa: F811
    drives = catalog.drives()
    page.click("#tab-catalog")
    page.wait_for_selector(".catalog-table tbody tr")
    page.click("#cat-drives")
    page.wait_for_selector("button.sort:has-text('I cont.')")
    wait_until(page, "n => document.querySelector('#cat-page').innerText.endsWith(`of ${n}`)", len(drives))
    heads = page.locator(".catalog-table thead th").all_inner_texts()
    for name in ("id", "vendor", "I cont. [A]", "I peak [A]", "U [V]", "motor series", "source"):
        assert any(h.startswith(name) for h in heads), (name, heads)
    vendor = sorted(set(drives.vendor.tolist()))[-1]
    page.select_option("#flt-vendor", vendor)
    wait_until(page, """v => {
        const cells = [...document.querySelectorAll('.catalog-table tbody tr td:nth-child(2)')];
        return cells.length > 0 && cells.every(c => c.innerText === v);
    }""", vendor)
    first = page.locator(".catalog-table tbody tr").first.locator("th button")
    name = first.inner_text()
    first.click()
    wait_until(page, "t => document.querySelector('#catalog-detail h3')?.innerText === t", name)
    detail = page.inner_text("#catalog-detail")
    assert "continuous / peak current" in detail and "motor series" in detail and "source" in detail
    assert catalog.get(name)["source"][:40] in detail


def test_a_selection_takes_the_supply_and_the_environment_in_the_form(page: Any) -> None:  # noqa: F811
    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    assert page.is_checked("#f-motor-select-on")
    set_field(page, "motor.supply_voltage", "400 V")
    switch_on(page, "environment")
    set_field(page, "environment.ambient", "45 degC")
    set_field(page, "environment.altitude", "1500 m")
    wait_sized(page)
    axis = yaml_pane(page)
    assert axis["motor"]["supply_voltage"] == "400 V"
    assert axis["environment"] == {"ambient": "45 degC", "altitude": "1500 m"}
    assert page.locator("#f-motor-dc-bus-voltage").count() == 1
    expected = size(axis).selection
    assert f"Selected motor: {expected.selected.motor}" in page.inner_text("#result-banner")
    assert f"{expected.passing} of {expected.evaluated}" in page.inner_text("#result-banner")


def test_not_orderable_is_a_short_verdict_with_the_motors_folded(page: Any) -> None:  # noqa: F811
    shown = page.evaluate("""() => import('/static/results.js').then(R => {
        const over = Array.from({length: 20}, (_, k) => ({motor: `M-${k}`, reason: `no drive of vendor V${k} fits`}));
        const sel = {selected: {motor: 'M-0', vendor: 'V0', checks: []}, passing: 25, evaluated: 90,
                     drive_passed_over: over, drive_passed_over_count: 23,
                     drive_advice: 'none of the 23 passing motors tried has a drive that passes its current checks; '
                                   + 'the best-ranked, M-0: no drive of vendor V0 fits'};
        const node = document.createElement('div');
        document.body.append(node);
        R.renderBanner(node, {selection: sel});
        const details = node.querySelector('details');
        const out = {bad: node.classList.contains('bad'), open: details.open,
                     summary: details.querySelector('summary').innerText,
                     items: details.querySelectorAll('li').length, visible: node.innerText};
        node.remove();
        return out;
    })""")
    assert shown["bad"] and not shown["open"]
    assert shown["summary"] == "23 passing motors passed over for their drive"
    assert shown["items"] == 21  # the 20 listed and "... and 3 more"
    assert "M-7" not in shown["visible"]  # folded: the list is not in the visible text
    assert "Not orderable: none of the 23 passing motors tried has a drive" in shown["visible"]


def poll(pg: Any, condition: Any, what: str) -> None:
    """Until ``condition()`` (a Python-side record of the page's events) holds; Playwright delivers the
    events while the page is waited on."""
    deadline = time.monotonic() + TIMEOUT_MS / 1000
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        pg.wait_for_timeout(20)


def test_an_answer_to_an_earlier_edit_is_never_shown(page: Any) -> None:  # noqa: F811
    """An edit back to the axis already shown while the answer to another edit is on its way (held here):
    the page cancels that request, so its answer can never replace the result of the axis as it stands."""
    from tests.web.test_web_e2e import metric, sig4

    page.select_option("#example-select", "ball_screw")
    wait_sized(page)
    set_field(page, "mechanism.load.mass", "30 kg")
    wait_sized(page)
    shown = metric(page, "RMS torque")
    held: list[Any] = []
    failed: list[str] = []
    page.on("requestfailed", lambda r: failed.append(r.url) if r.url.endswith("/api/size") else None)
    page.route("**/api/size", lambda route: held.append(route))
    try:
        set_field(page, "mechanism.load.mass", "40 kg")
        poll(page, lambda: held, "the 40 kg request to leave the page")
        set_field(page, "mechanism.load.mass", "30 kg")  # back to the axis whose result is shown
        wait_sized(page)
        poll(page, lambda: failed, "the page to cancel the request for 40 kg")
    finally:
        page.unroute("**/api/size")
        for route in held:
            with contextlib.suppress(Exception):  # a request the page cancelled cannot be continued
                route.continue_()
    assert yaml_pane(page)["mechanism"]["load"]["mass"] == "30 kg"
    assert page.evaluate("() => document.body.dataset.sizing") == "idle"
    assert metric(page, "RMS torque") == shown
    assert float(shown.split()[0]) == sig4(size(yaml_pane(page)).metrics.rms_torque_Nm)


def test_a_round_off_residue_shows_as_zero_on_the_page(page: Any) -> None:  # noqa: F811
    shown = page.evaluate("""() => import('/static/results.js').then(R => {
        const m = R.snappedMetrics({peak_power_W: 3993, average_power_W: 3.79e-14, peak_torque_Nm: 2,
                                    run_torque_Nm: -1e-15, rms_torque_Nm: 1.0});
        return [R.ZERO_TOLERANCE, m.average_power_W, m.run_torque_Nm, m.rms_torque_Nm];
    })""")
    from drivetrain.report.display import ZERO_TOLERANCE

    assert shown == [ZERO_TOLERANCE, 0, 0, 1.0]
