"""In Debian's Chromium (Playwright): a page served from another loopback port cannot write to the
app (a form POST and a no-cors fetch() of a multipart catalog import, fetch() of JSON or with a
token header, which need a preflight), while the app's own page still imports; a sizing's
warnings show above the checks. (A text body to /api/size and the rest: tests/web/test_web_hostile.py.)
"""

from __future__ import annotations

import http.server
import json
import threading
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.web.test_web_e2e import ARGS, CHROMIUM, TIMEOUT_MS, browser, page, server, wait_sized, wait_until  # noqa: F401

pytestmark = pytest.mark.browser

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "ball_screw.yaml"
CSV = ("id,vendor,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2,source\n"
       "{id},ACME,1.3,4.5,3000,6000,3.7e-5,ACME datasheet p. 1\n")

ATTACKER_PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>another site</title></head><body>
<form id="form" method="post" enctype="multipart/form-data" target="sink">
  <input type="file" name="file" id="file">
</form>
<iframe name="sink" title="sink"></iframe>
</body></html>"""


@pytest.fixture(scope="module")
def attacker() -> Iterator[str]:
    """A page on another loopback port (the same host as the app, another origin)."""

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            body = ATTACKER_PAGE.encode()
            self.send_response(200)
            self.send_header("content-type", "text/html; charset=utf-8")
            self.send_header("content-length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: Any) -> None:
            pass

    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    finally:
        httpd.shutdown()
        httpd.server_close()


def motors_matching(base: str, text: str) -> int:
    with urllib.request.urlopen(f"{base}api/catalog/motors?q={text}", timeout=30) as r:
        return int(json.load(r)["total"])


def test_another_port_cannot_write(browser: Any, server: tuple[str, Path], attacker: str) -> None:  # noqa: F811
    base = server[0]
    assert base.split(":")[2] != attacker.split(":")[2]
    context = browser.new_context()
    pg = context.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    try:
        pg.goto(attacker)
        # 1. a plain form POST of a multipart catalog import (no preflight for forms)
        pg.eval_on_selector("#form", "(f, url) => { f.action = url; }", f"{base}api/catalog/import")
        pg.set_input_files("#file", files=[{"name": "evil.csv", "mimeType": "text/csv",
                                            "buffer": CSV.format(id="EVIL-FORM").encode()}])
        with pg.expect_response(lambda r: "/api/catalog/import" in r.url) as answer:
            pg.eval_on_selector("#form", "f => f.submit()")
        assert answer.value.status == 403
        assert motors_matching(base, "EVIL-FORM") == 0
        # 2. fetch() without CORS: the request reaches the server, the browser withholds the answer
        #    (Cross-Origin-Resource-Policy), so the server's state shows the refusal
        failed = pg.evaluate("""async ([url, csv]) => {
            const data = new FormData();
            data.append("file", new Blob([csv], { type: "text/csv" }), "evil.csv");
            try { await fetch(url, { method: "POST", mode: "no-cors", body: data }); } catch (e) { return "failed"; }
            return "opaque";
        }""", [f"{base}api/catalog/import", CSV.format(id="EVIL-FETCH")])
        assert failed in ("failed", "opaque")
        assert motors_matching(base, "EVIL-FETCH") == 0
        # 3. fetch() of JSON, or with a guessed token: the browser asks first, and the server never allows it
        outcome = pg.evaluate("""async ([url, token]) => {
            const out = [];
            for (const headers of [{ "content-type": "application/json" }, { "x-drivetrain-token": token }]) {
                try {
                    const r = await fetch(url, { method: "POST", headers, body: "{}" });
                    out.push(`read ${r.status}`);
                } catch (e) {
                    out.push("blocked");
                }
            }
            return out;
        }""", [f"{base}api/projects", "guess"])
        assert outcome == ["blocked", "blocked"]
    finally:
        context.close()
    assert motors_matching(base, "EVIL-") == 0


def test_the_app_page_still_imports(page: Any, server: tuple[str, Path]) -> None:  # noqa: F811
    page.click("#tab-catalog")
    page.wait_for_selector(".catalog-table tbody tr")
    page.set_input_files("#import-file", files=[{"name": "own.csv", "mimeType": "text/csv",
                                                  "buffer": CSV.format(id="OWN-PAGE-1").encode()}])
    page.click("#import-submit")
    page.wait_for_selector("#import-result .ok-text")
    assert "OWN-PAGE-1" in page.inner_text("#import-result") or "1" in page.inner_text("#import-result")
    assert motors_matching(server[0], "OWN-PAGE-1") == 1


def test_result_warnings_show_above_the_checks(page: Any) -> None:  # noqa: F811
    # The lead-screw example: the ball-screw example's screw limits would (rightly) refuse a 200 m
    # stroke as an input error before any warning.
    page.select_option("#example-select", "lead_screw")
    wait_sized(page)
    assert page.locator("#result-warnings").is_hidden()
    text = (EXAMPLE.parent / "lead_screw.yaml").read_text(encoding="utf-8")
    slipped = text.replace("- {move: 50 mm,", "- {move: 50,", 1)  # a distance in mm written bare: 50 m
    assert slipped != text
    page.fill("#yaml-text", slipped)
    wait_until(page, "() => !document.getElementById('result-warnings').hidden")
    wait_sized(page)
    banner = page.locator("#result-warnings")
    assert banner.get_attribute("role") == "alert"
    items = banner.locator("li")
    assert items.count() >= 1
    assert "check the units of the profile" in items.first.inner_text()
    # the warnings are part of the result the page got
    page.fill("#yaml-text", text)
    wait_until(page, "() => document.getElementById('result-warnings').hidden")
