"""The catalog's drives in the web app: GET /api/catalog/drives lists them (currents, voltage class, the
motor series each runs, source), filtered and sorted as the motors are, and the facets name their vendors
and voltage classes (issue 31, "The web app")."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("httpx")

from fastapi.testclient import TestClient

from drivetrain import catalog
from drivetrain.web.app import create_app

BASE = "http://127.0.0.1"
DRIVE_CSV = ("id,vendor,series,continuous_current [A],peak_current [A],voltage [V],motor_series,source\n"
             "WEBD-1,Webco,WD,2.5,7.5,230,WM,team test bench 2026\n")


@pytest.fixture()
def client(tmp_path: Path) -> Iterator[TestClient]:
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(tmp_path))
        mp.setenv("DRIVETRAIN_CATALOG", "")
        app = create_app(tmp_path)
        with TestClient(app, base_url=BASE, headers={"x-drivetrain-token": app.state.token}) as c:
            yield c


def test_the_drives_route_lists_every_shipped_drive_with_its_currents_voltage_series_and_source(
        client: TestClient) -> None:
    table = catalog.drives()
    page = client.get("/api/catalog/drives", params={"limit": 500}).json()
    assert page["total"] == len(table) > 0
    ids = {item["id"] for item in page["items"]}
    assert ids == set(table.ids.tolist())
    for item in page["items"]:
        for key in ("continuous_current_A", "peak_current_A", "voltage_V", "motor_series", "source", "vendor"):
            assert key in item
        assert item["source"]  # every shipped row names where it was read
    currents = [i["continuous_current_A"] for i in page["items"]]
    known = [c for c in currents if c is not None]
    assert known == sorted(known)  # sorted by continuous current, the unknown last
    assert all(c is not None for c in currents[:len(known)])


def test_the_drives_route_filters_by_vendor_voltage_and_motor_series(client: TestClient) -> None:
    vendor = sorted(set(catalog.drives().vendor.tolist()))[0]
    page = client.get("/api/catalog/drives", params={"vendor": vendor, "limit": 500}).json()
    assert page["total"] > 0 and {i["vendor"] for i in page["items"]} == {vendor}
    facets = client.get("/api/catalog/facets").json()
    assert vendor in facets["drive_vendors"]
    volts = facets["drive_voltages"]
    assert volts and all(math.isfinite(v) for v in volts)
    page = client.get("/api/catalog/drives", params={"voltage": f"{volts[0]:g} V", "limit": 500}).json()
    assert page["total"] > 0 and all(abs(i["voltage_V"] - volts[0]) <= 0.1 * volts[0] for i in page["items"])
    series = next(s for s in catalog.drives().motor_series.tolist() if s)
    page = client.get("/api/catalog/drives", params={"q": series.lower(), "limit": 500}).json()
    assert page["total"] > 0 and all(series.lower() in (i["motor_series"] + i["id"] + i["series"]).lower()
                                     for i in page["items"])
    r = client.get("/api/catalog/drives", params={"sort": "power_factor"})
    assert r.status_code == 422


def test_an_imported_drive_is_listed_as_yours(client: TestClient) -> None:
    r = client.post("/api/catalog/import", files={"file": ("drives.csv", DRIVE_CSV.encode(), "text/csv")},
                    data={"kind": "drive"})
    assert r.status_code == 200, r.text
    mine = client.get("/api/catalog/drives", params={"origin": "user"}).json()
    assert mine["total"] == 1
    row = mine["items"][0]
    assert (row["id"], row["continuous_current_A"], row["peak_current_A"], row["voltage_V"], row["motor_series"]) == (
        "WEBD-1", 2.5, 7.5, 230.0, "WM")
    assert "Webco" in client.get("/api/catalog/facets").json()["drive_vendors"]
