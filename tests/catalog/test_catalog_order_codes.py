"""Open positions of shipped order codes (data/order_codes.csv, SOURCES.md "Order-code positions"): every
placeholder ``x`` of a shipped id has a row naming its source, and no row points elsewhere."""

from __future__ import annotations

import pytest

from drivetrain.catalog import db, side_tables
from drivetrain.catalog.schema import ROW_TABLES


def test_every_placeholder_of_a_shipped_id_has_a_position_row() -> None:
    positions = side_tables.order_code_positions()
    with db.reader() as rd:
        ids = {str(r["id"]) for spec in ROW_TABLES for r in rd.rows(spec) if r.get("origin", "builtin") == "builtin"}
    open_ids = {i for i in ids if "x" in i}
    assert open_ids == {"6SL312x-xTE21-0AAx"}  # the S120 Motor Module the 1FT7044 table recommends
    for rid in open_ids:
        assert [p["position"] for p in positions[rid]] == [k + 1 for k, ch in enumerate(rid) if ch == "x"]
    assert set(positions) <= ids
    for p in positions["6SL312x-xTE21-0AAx"]:
        assert "Table 4-8" in p["source"] and p["meaning"] == "not read" and p["note"]
        assert p["options"] == ""  # the vendor's key was not read: nothing invented


def test_the_omron_rows_naming_two_models_list_both_letters() -> None:
    """``R88M-K05030H/T``: the shipped row describes the H and the T model; the order sheet chooses one."""
    positions = side_tables.order_code_positions()
    with db.reader() as rd:
        ids = {str(r["id"]) for spec in ROW_TABLES for r in rd.rows(spec) if r.get("origin", "builtin") == "builtin"}
    both = {i for i in ids if i.endswith("H/T")}
    assert len(both) == 14 and both <= set(positions)
    for rid in both:
        [p] = positions[rid]
        assert p["position"] == len(rid) - 2 and p["printed_as"] == "H/T" and p["options"] == "H; T"
        assert "omron-g5" in p["source"] and "p. 3-55" in p["source"]
    assert not any(i.endswith("T/T") and i in positions for i in ids)  # not explained by the page: left out


def test_a_row_pointing_at_a_fixed_character_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    text = side_tables.shipped_text("order_codes.csv").replace("0AAx,18,", "0AAx,17,", 1)
    monkeypatch.setattr(side_tables, "shipped_text", lambda name: text)
    with pytest.raises(RuntimeError, match="position 17"):
        side_tables.order_code_positions()
