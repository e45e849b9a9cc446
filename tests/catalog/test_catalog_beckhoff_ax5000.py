"""Beckhoff AX5206 (drives_beckhoff_ax5000.csv), read from Beckhoff's AX5000 function documentation (data/SOURCES.md,
"Beckhoff AX5000"): the values the page marks fixed, per channel, traced."""

from __future__ import annotations

import csv
import io
from importlib import resources

import pytest

from drivetrain import catalog
from drivetrain.axis.electrical import drive_from_catalog_row
from drivetrain.errors import InputError


def rows() -> list[dict[str, str]]:
    text = resources.files("drivetrain.catalog").joinpath("data", "drives_beckhoff_ax5000.csv").read_text("utf-8")
    return list(csv.DictReader(io.StringIO(text)))


def test_ax5206_channel_ratings_as_printed() -> None:
    # "Taking AX5206 as an example": P-0-0091 Channel rated current 6.0 A (fixed), P-0-0090 Channel peak current
    # 13.0 A (fixed), tmax Max. time for Ipeak 7.0 s (fixed); S-0-0112 Amplifier rated current 12.0 A (both channels)
    (r,) = rows()
    assert r["id"] == "AX5206" and r["vendor"] == "Beckhoff Automation" and r["verified"] == "yes"
    assert (float(r["continuous_current_A"]), float(r["peak_current_A"]), float(r["peak_time [s]"])) == (6.0, 13.0, 7.0)
    assert r["source_url"] == "https://infosys.beckhoff.com/content/1033/ax5000_function_doku_hw2/3679013131.html"
    assert "12.0 A" in r["source"] and "sum of both channels" in r["notes"]
    assert r["voltage_V"] == ""  # not on the page: not guessed


def test_ax5206_is_a_traced_drive_with_an_i2t_limit_in_the_database() -> None:
    row = catalog.get("AX5206")
    assert not row["unverified"] and row["peak_time_s"] == 7.0
    assert "infosys.beckhoff.com" in row["sources"]["ratings"]
    d = drive_from_catalog_row(row)
    assert (d.continuous_current, d.peak_current, d.peak_time) == (6.0, 13.0, 7.0)
    # no Beckhoff motor is shipped (AM8000 searched for and not found): the vendor rule offers it to none
    with pytest.raises(InputError, match="no motor vendor matches"):
        catalog.motors(vendor="Beckhoff Automation")
