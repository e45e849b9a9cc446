"""The web API's machine route: a machine with inline axes sized as JSON; includes refused."""

from __future__ import annotations

import copy
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
from fastapi.testclient import TestClient

from drivetrain.web.app import create_app
from test_machine import TWO, X_AXIS


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    path = tmp_path_factory.mktemp("web-machine")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(path))
        with TestClient(create_app(path), base_url="http://127.0.0.1") as c:
            yield c


def test_a_machine_is_sized(client: TestClient) -> None:
    r = client.post("/api/machine/size?samples=3", json=TWO)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["machine"]["name"] == "two axes"
    assert out["machine"]["resistor_energy_per_cycle_J"] > 0
    assert [a["name"] for a in out["axes"]] == ["Z", "X"]
    assert len(out["series"]["t_s"]) == len(out["series"]["bus:bus"]) > 100


def test_includes_are_refused(client: TestClient, tmp_path: Path) -> None:
    data = copy.deepcopy(TWO)
    data["axes"][1] = {"include": str(tmp_path / "x.yaml")}
    r = client.post("/api/machine/size", json=data)
    assert r.status_code == 422
    assert "axes[1].include" in r.text


@pytest.mark.parametrize(("body", "field"), [
    ([1, 2], "body"),
    ({"version": 1, "cycle_time": "1 s", "supply": {"voltage": "400 V"},
      "axes": [{"axis": X_AXIS}] * 9}, "axes"),
    ({**TWO, "supply": {"voltage": "9 kV"}}, "supply.voltage"),
])
def test_bad_machines_get_422_naming_the_field(client: TestClient, body: object, field: str) -> None:
    r = client.post("/api/machine/size", json=body)
    assert r.status_code == 422
    assert field in r.text
