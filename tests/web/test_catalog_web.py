"""The web catalog browser's management routes: a web import records the uploaded file's name and
time, the rows filter (shipped / yours), edit (PATCH), remove (DELETE) and the history."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("httpx")

from fastapi.testclient import TestClient

from drivetrain.web.app import create_app
from tests.conftest import family_motor_rows

BASE = "http://127.0.0.1"
CSV = (
    "id,vendor,series,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],"
    "rotor_inertia [kg*cm^2]\n"
    "WEBM-1,Webco,W,1.3,4.5,3000,6000,0.37\n"
)


@pytest.fixture()
def client(tmp_path: Path) -> Iterator[TestClient]:
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(tmp_path))
        mp.setenv("DRIVETRAIN_CATALOG", "")
        app = create_app(tmp_path)
        # the page's token, as the page sends it on form bodies (drivetrain.web.app.Guard)
        with TestClient(app, base_url=BASE, headers={"x-drivetrain-token": app.state.token}) as c:
            # imports run in the app's worker processes: let them warm up first (on a loaded machine that
            # alone can take most of a request's time limit)
            assert app.state.sizing_workers().wait_ready(120.0), "the worker processes did not start"
            yield c


def upload(client: TestClient, text: str, name: str = "team motors.csv", replace: bool = False) -> dict[str, object]:
    data = {"replace": "true"} if replace else {}
    r = client.post("/api/catalog/import", files={"file": (name, text.encode(), "text/csv")}, data=data)
    assert r.status_code == 200, r.text
    body: dict[str, object] = r.json()
    return body


def test_web_import_source_is_the_uploaded_file_and_time(client: TestClient) -> None:
    upload(client, CSV)
    item = client.get("/api/catalog/items/WEBM-1").json()
    assert re.fullmatch(r"uploaded file team_motors\.csv at \d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC", item["source"]), \
        item["source"]
    assert "tmp" not in item["source"]
    mine = client.get("/api/catalog/motors", params={"origin": "user"}).json()
    assert [i["id"] for i in mine["items"]] == ["WEBM-1"]
    shipped = client.get("/api/catalog/motors", params={"origin": "builtin", "limit": 1}).json()
    assert shipped["total"] == 595 + family_motor_rows() and shipped["items"][0]["unverified"] in (True, False)
    assert client.get("/api/catalog/gearboxes", params={"origin": "user"}).json()["total"] == 0


def test_web_replace_edit_remove_and_history(client: TestClient) -> None:
    upload(client, CSV)
    r = client.post("/api/catalog/import", files={"file": ("m.csv", CSV.replace("1.3,", "1.4,").encode(), "text/csv")})
    assert r.status_code == 422 and "--replace" in r.text
    upload(client, CSV.replace("1.3,", "1.4,"), replace=True)
    assert client.get("/api/catalog/items/WEBM-1").json()["rated_torque_Nm"] == 1.4

    r = client.patch("/api/catalog/items/WEBM-1", json={"rotor_inertia [kg*cm^2]": 0.5, "notes": "checked"})
    assert r.status_code == 200, r.text
    assert r.json()["rotor_inertia_kgm2"] == pytest.approx(0.5e-4) and r.json()["notes"] == "checked"
    r = client.patch("/api/catalog/items/WEBM-1", json={"peak_torque": 0.1})
    assert r.status_code == 422 and "must be >= rated_torque" in r.text
    r = client.patch("/api/catalog/items/WEBM-1", json=[1, 2])
    assert r.status_code == 422 and "JSON object" in r.text
    r = client.patch("/api/catalog/items/HG-KR43", json={"rated_torque": 1})
    assert r.status_code == 422 and "shipped catalog" in r.text

    r = client.delete("/api/catalog/items/HG-KR43")
    assert r.status_code == 422 and "shipped catalog" in r.text
    r = client.delete("/api/catalog/items/WEBM-1")
    assert r.status_code == 200 and r.json()["removed"] == 1
    assert client.get("/api/catalog/items/WEBM-1").status_code == 404

    history = client.get("/api/catalog/history", params={"id": "WEBM-1"}).json()["entries"]
    assert [e["action"] for e in history] == ["import", "replace", "edit", "remove"]
    assert history[1]["old_values"]["rated_torque_Nm"] == 1.3
    assert history[2]["source"] == "web catalog edit" and history[3]["source"] == "web catalog"
