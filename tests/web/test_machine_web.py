"""The web API's machine route: a machine with inline axes sized as JSON; includes refused."""

from __future__ import annotations

import copy
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
from fastapi.testclient import TestClient

from drivetrain.web.app import create_app
from tests.machine.test_machine import TWO, X_AXIS, Z_AXIS


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    path = tmp_path_factory.mktemp("web-machine")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(path))
        app = create_app(path)
        with TestClient(app, base_url="http://127.0.0.1") as c:
            # machine sizing runs in the app's worker processes: let them warm up first (on a loaded machine
            # that alone can take most of a request's time limit)
            assert app.state.sizing_workers().wait_ready(120.0), "the worker processes did not start"
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


def axis_project(client: TestClient, name: str, axis: dict[str, object]) -> int:
    import yaml

    r = client.post("/api/projects", json={"name": name, "yaml": yaml.safe_dump(axis)})
    assert r.status_code == 201, r.text
    return int(r.json()["id"])


def test_a_machine_project_is_saved_with_history_and_listed_apart(client: TestClient) -> None:
    import yaml

    r = client.post("/api/projects", json={"name": "two axes", "yaml": yaml.safe_dump(TWO), "kind": "machine"})
    assert r.status_code == 201, r.text
    p = r.json()
    assert p["kind"] == "machine" and p["axis"] is None and p["machine"]["machine"] == "two axes"
    changed = {**TWO, "cycle_time": "3 s"}
    r = client.put(f"/api/projects/{p['id']}", json={"yaml": yaml.safe_dump(changed), "base_version": 1})
    assert r.status_code == 200 and r.json()["version"] == 2 and r.json()["machine"]["cycle_time"] == "3 s"
    assert [v["version"] for v in client.get(f"/api/projects/{p['id']}/versions").json()] == [2, 1]
    undone = client.post(f"/api/projects/{p['id']}/undo").json()
    assert undone["kind"] == "machine" and undone["machine"]["cycle_time"] == "2 s"
    assert p["id"] in [q["id"] for q in client.get("/api/projects?kind=machine").json()]
    assert p["id"] not in [q["id"] for q in client.get("/api/projects?kind=axis").json()]
    # a machine project's text must be a mapping; a draft with bad values is kept (sizing judges it)
    r = client.put(f"/api/projects/{p['id']}", json={"yaml": "- just a list"})
    assert r.status_code == 422 and r.json()["field"] == "yaml"
    assert client.post("/api/projects", json={"name": "q", "yaml": "a: 1", "kind": "gearbox"}).status_code == 422


def test_axes_may_name_saved_axis_projects(client: TestClient) -> None:
    """The same machine, its axes inline or naming saved axis projects, sizes to the same figures."""
    z_id, x_id = axis_project(client, "Z hoist", Z_AXIS), axis_project(client, "X table", X_AXIS)
    inline = client.post("/api/machine/size?samples=3", json=TWO).json()
    by_ref = copy.deepcopy(TWO)
    by_ref["axes"] = [{"project": z_id}, {"project": x_id, "project_version": 1, "offset": "0.25 s"}]
    r = client.post("/api/machine/size?samples=3", json=by_ref)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["machine"] == {**inline["machine"], "drivetrain_version": out["machine"]["drivetrain_version"]}
    assert out["links"] == {"Z": {"project": z_id, "name": "Z hoist", "version": 1},
                            "X": {"project": x_id, "name": "X table", "version": 1}}
    assert out["table"] == inline["table"]
    assert [(r["axis"], r["motor"], r["ok"]) for r in out["table"]] == [(a["name"], f"motor {a['name']}", a["ok"])
                                                                       for a in inline["axes"]]
    assert all(r["min_margin"] is not None and r["limit"] for r in out["table"])


@pytest.mark.parametrize(("axis", "field"), [
    ({"project": 10_000}, "axes[0].project"),
    ({"project": "one"}, "axes[0].project"),
    ({"project": 1, "project_version": 99}, "axes[0].project_version"),
    ({"project_version": 1}, "axes[0].project_version"),
    ({"project": 1, "axis": X_AXIS}, "axes[0].project"),
])
def test_bad_project_references_name_their_field(client: TestClient, axis: dict[str, object], field: str) -> None:
    axis_project(client, "some axis", X_AXIS)
    r = client.post("/api/machine/size", json={**TWO, "axes": [axis], "buses": []})
    assert r.status_code == 422, r.text
    assert r.json()["field"] == field


def test_a_machine_project_is_not_an_axis(client: TestClient) -> None:
    import yaml

    mid = client.post("/api/projects", json={"name": "m", "yaml": yaml.safe_dump(TWO), "kind": "machine"}).json()["id"]
    r = client.post("/api/machine/size", json={**TWO, "axes": [{"project": mid}], "buses": []})
    assert r.status_code == 422 and "machine project" in r.json()["detail"]


def test_machine_report_and_aas_downloads(client: TestClient) -> None:
    r = client.post("/api/report/machine?format=html&samples=2", json=TWO)
    assert r.status_code == 200, r.text
    assert r.headers["content-disposition"] == 'attachment; filename="two_axes-report.html"'
    assert "DC bus over the machine cycle" in r.text and "Bill of materials" in r.text
    r = client.post("/api/report/machine?format=pdf&samples=2", json=TWO)
    assert r.status_code == 200 and r.content.startswith(b"%PDF")
    r = client.post("/api/machine/aas?samples=2", json=TWO)
    assert r.status_code == 200 and r.headers["content-disposition"].endswith('two_axes.aas.json"')
    assert r.json()["submodels"][0]["idShort"] == "PowerDriveTrainSizing"
    r = client.post("/api/report/machine", json={**TWO, "cycle_time": "1 s"})
    assert r.status_code == 422 and r.json()["field"] == "cycle_time"


def test_shipped_machine_examples_come_with_their_axes_inline(client: TestClient) -> None:
    assert client.get("/api/machine/examples").json() == ["pick_and_place"]
    ex = client.get("/api/machine/examples/pick_and_place").json()
    assert all("include" not in a and "axis" in a for a in ex["machine"]["axes"])
    assert client.post("/api/machine/parse", json={"yaml": ex["yaml"]}).json()["machine"] == ex["machine"]
    assert client.get("/api/machine/examples/nope").status_code == 404
    r = client.post("/api/machine/parse", json={"yaml": "[1, 2]"})
    assert r.status_code == 422 and r.json()["field"] == "yaml"
