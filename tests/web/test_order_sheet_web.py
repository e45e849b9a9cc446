"""The order sheet on the web page (web/static/order.js): the rows of the JSON ``order`` block, the pattern id
with its positions to choose, and the result column not widened by the sheet at 1,440 px.

Debian's Chromium through the harness of test_web_e2e.py; every wait polls a condition of the page.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.web.test_web_e2e import (  # noqa: F401 (fixtures)
    browser,
    page,
    server,
    wait_sized,
    wait_until,
)

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]


def test_the_page_shows_the_order_sheet_of_the_answer(page: Any) -> None:  # noqa: F811
    from drivetrain.dynamics.mechanism_modes import size
    from drivetrain.sizing.order import order_sheet

    page.select_option("#example-select", "z_axis")
    wait_sized(page)
    wait_until(page, "() => document.querySelectorAll('#order-sheet table.order-table tbody tr').length > 0")
    shown = page.evaluate("""() => {
        const rows = [...document.querySelectorAll('#order-sheet table.order-table tbody tr')]
          .map(tr => [...tr.children].map(c => c.textContent));
        const res = document.querySelector('.results');
        const table = document.querySelector('#order-sheet table.order-table').getBoundingClientRect();
        return {rows, text: document.querySelector('#order-sheet').innerText,
                sideways: res.scrollWidth > res.clientWidth, right: table.right,
                column: res.getBoundingClientRect().right};
    }""")
    order = order_sheet(size(ROOT / "examples" / "z_axis.yaml")).to_dict()
    assert [r[:2] for r in shown["rows"]] == [[r["part"].replace("_", " "), r["status"]] for r in order["rows"]]
    from drivetrain.report.order import code_cell

    assert [r[4] for r in shown["rows"]] == [code_cell(r) for r in order["rows"]]  # the id with positions to choose
    for point in order["open_points"]:
        assert point.split(": ", 1)[1] in shown["text"]
    assert not shown["sideways"] and shown["right"] <= shown["column"] + 0.5
