"""The web app's JSON API through FastAPI's TestClient: sizing, errors naming the field, projects
with their history, YAML round trips, the catalog, reports, and the safety limits."""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import quote

import numpy as np
import pytest
import yaml

pytest.importorskip("fastapi")
pytest.importorskip("httpx")

from fastapi.testclient import TestClient

from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.sizing.pipeline import size
from drivetrain.web import app as web_app
from drivetrain.web.app import create_app
from drivetrain.web.common import ResultCache
from drivetrain.web.payload import WEB_POINTS_PER_PHASE, plain

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "ball_screw.yaml"
BASE = "http://127.0.0.1"


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    path = tmp_path_factory.mktemp("web-api")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(path))
        yield path


@pytest.fixture(scope="module")
def client(data_dir: Path) -> Iterator[TestClient]:
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(data_dir))
        app = create_app(data_dir)
        with TestClient(app, base_url=BASE, headers={"x-drivetrain-token": app.state.token}) as c:
            # the worker processes (sizing, parsing, reports, imports) warm up before the first request:
            # on a loaded machine their start alone can take most of a request's time limit
            assert app.state.sizing_workers().wait_ready(120.0), "the sizing workers did not start"
            yield c


def example_axis() -> dict[str, Any]:
    data = parse_yaml(EXAMPLE.read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


def key_numbers(result: dict[str, Any]) -> dict[str, Any]:
    return {k: result[k] for k in ("cycle_time_s", "load_inertia_kgm2", "peak_torque_Nm", "rms_torque_Nm",
                                   "max_speed_rpm", "regen_energy_J")}


def choice(result: dict[str, Any]) -> list[tuple[Any, ...]]:
    """The motor verdict or the ranked candidates, exactly."""
    if "motor" in result:
        return [(result["motor"]["name"], result["motor"]["ok"])]
    return [(c["motor"], c.get("gearbox"), c["ok"]) for c in result.get("candidates", [])]


def same_sizing(a: dict[str, Any], b: dict[str, Any]) -> None:
    assert key_numbers(a) == pytest.approx(key_numbers(b), rel=1e-12)
    assert choice(a) == choice(b)


def assert_error(response: Any, status: int) -> dict[str, Any]:
    assert response.status_code == status, response.text
    body = response.json()
    assert isinstance(body["detail"], str) and body["detail"].strip(), body
    return body  # type: ignore[no-any-return]


# ---------------------------------------------------------------------------------- sizing


def test_size_example_matches_the_engine(client: TestClient) -> None:
    axis = example_axis()
    r = client.post("/api/size", json=axis)
    assert r.status_code == 200, r.text
    body = r.json()
    expected = json.loads(json.dumps(plain(size(axis, WEB_POINTS_PER_PHASE).to_dict())))
    same_sizing(body["result"], expected)
    assert body["motion"] == "linear"
    n = len(body["series"]["t_s"])
    assert n > 10 and all(len(v) == n for v in body["series"].values())
    if "candidates" in body["result"]:
        selected = body["result"]["selection"]["selected"]["motor"]
        assert body["selected"]["motor"] == selected
        assert body["envelopes"] and body["envelopes"][0]["name"] == selected
        assert "torque_motor_Nm" in body["selected"]["series"]


# direct drive (ball_screw; roll: its catalog gearboxes are not known to take its motors, so direct ranks first);
# a selection with a gearbox
@pytest.mark.parametrize("name", ["ball_screw", "roll", "belt_gantry"])
def test_selected_cycle_is_the_cycle_of_the_candidate_sized_again(client: TestClient, name: str) -> None:
    """The selected candidate's cycle on /api/size (the axis's cycle behind its gearbox, from the
    selection) is the cycle of the axis sized again with that motor and gearbox given (relative 1e-9)."""
    axis = parse_yaml((EXAMPLE.parent / f"{name}.yaml").read_text(encoding="utf-8"))
    r = client.post("/api/size", json=axis)
    assert r.status_code == 200, r.text
    sel = r.json()["selected"]
    assert sel is not None and (sel["gearbox"] is not None) == (name == "belt_gantry")
    params = {"motor": sel["motor"], **({"gearbox": sel["gearbox"]} if sel["gearbox"] else {})}
    again = client.post("/api/size/candidate", params=params, json=axis)
    assert again.status_code == 200, again.text
    for key in ("t_s", "omega_motor_rad_s", "torque_motor_Nm"):
        np.testing.assert_allclose(sel["series"][key], again.json()["series"][key], rtol=1e-9, atol=1e-12)
    assert sel["motor_result"]["rms_torque_Nm"] == pytest.approx(again.json()["motor_result"]["rms_torque_Nm"],
                                                                 rel=1e-9)
    assert {**sel["envelope"], "rank": None} == again.json()["envelope"]


def test_bad_mass_answers_422_naming_the_field(client: TestClient) -> None:
    axis = example_axis()
    axis["mechanism"]["load"]["mass"] = "-3 kg"
    body = assert_error(client.post("/api/size", json=axis), 422)
    assert body["field"] == "mechanism.load.mass"
    assert body["detail"] == "mechanism.load.mass: must be > 0 kg, got -3 kg"
    assert body["errors"] == [{"field": "mechanism.load.mass", "message": body["detail"]}]


@pytest.mark.parametrize(("mutate", "field"), [
    (lambda a: a["mechanism"].update(lead="ten mm"), "mechanism.lead"),
    (lambda a: a["mechanism"].update(type="pogo_stick"), "mechanism.type"),
    (lambda a: a["profile"][1].update(dwell="-1 s"), "profile[1].dwell"),
    (lambda a: a["transmission"][0].update(inertia="3 kg"), "transmission[0].inertia"),
    (lambda a: a.update(colour="red"), "colour"),
])
def test_errors_name_their_field_like_the_cli(client: TestClient, mutate: Any, field: str) -> None:
    axis = example_axis()
    mutate(axis)
    body = assert_error(client.post("/api/size", json=axis), 422)
    assert body["field"] == field
    assert body["detail"].startswith(field + ":")


@pytest.mark.parametrize("content", [b"", b"[1, 2]", b"{not json", b'"text"'])
def test_a_body_that_is_not_an_axis_object_is_422(client: TestClient, content: bytes) -> None:
    body = assert_error(client.post("/api/size", content=content, headers={"content-type": "application/json"}), 422)
    assert body["field"] == "body"


def test_size_candidate_fixes_motor_and_gearbox(client: TestClient) -> None:
    axis = example_axis()
    r = client.post("/api/size/candidate", params={"motor": "HG-KR43"}, json=axis)
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["motor"] == "HG-KR43" and body["gearbox"] is None and body["ratio"] == 1.0
    assert body["motor_result"]["name"] == "HG-KR43" and body["motor_result"]["checks"]
    gearboxes = client.get("/api/catalog/gearboxes", params={"limit": 1}).json()["items"]
    g = gearboxes[0]
    r = client.post("/api/size/candidate", params={"motor": "HG-KR43", "gearbox": g["id"]}, json=axis)
    assert r.status_code == 200, r.text
    assert r.json()["ratio"] == pytest.approx(g["ratio"])
    assert_error(client.post("/api/size/candidate", params={"motor": "NO-SUCH-MOTOR"}, json=axis), 422)


# ---------------------------------------------------------------------------------- projects


def test_projects_crud_and_version_history(client: TestClient) -> None:
    text1 = EXAMPLE.read_text(encoding="utf-8")
    r = client.post("/api/projects", json={"name": "  Z lift  ", "yaml": text1})
    assert r.status_code == 201, r.text
    p = r.json()
    pid = p["id"]
    assert p["name"] == "Z lift" and p["version"] == 1 and p["yaml"] == text1 and p["axis"]["axis"] == "Z lift"
    assert any(q["id"] == pid for q in client.get("/api/projects").json())

    text2 = text1.replace("mass: 25 kg", "mass: 30 kg")
    r = client.put(f"/api/projects/{pid}", json={"yaml": text2, "base_version": 1})
    assert r.status_code == 200 and r.json()["version"] == 2
    assert client.put(f"/api/projects/{pid}", json={"yaml": text2}).json()["version"] == 2  # unchanged: no version
    body = assert_error(client.put(f"/api/projects/{pid}", json={"yaml": text1, "base_version": 1}), 409)
    assert "version 2" in body["detail"]

    assert client.patch(f"/api/projects/{pid}", json={"name": "Z lift, heavier"}).json()["name"] == "Z lift, heavier"
    assert_error(client.patch(f"/api/projects/{pid}", json={"name": ""}), 422)
    dup = client.post(f"/api/projects/{pid}/duplicate", json={})
    assert dup.status_code == 201 and dup.json()["name"] == "Z lift, heavier (copy)"
    assert client.get(f"/api/projects/{dup.json()['id']}").json()["yaml"] == text2

    versions = client.get(f"/api/projects/{pid}/versions").json()
    assert [v["version"] for v in versions] == [2, 1]
    assert client.get(f"/api/projects/{pid}/versions/1").json()["yaml"] == text1

    r = client.post(f"/api/projects/{pid}/undo")  # undo = restore version 1 as version 3
    assert r.status_code == 200 and r.json()["version"] == 3 and r.json()["yaml"] == text1
    assert client.get(f"/api/projects/{pid}/versions").json()[0]["restored_from"] == 1
    assert_error(client.post(f"/api/projects/{pid}/undo"), 409)  # nothing before version 1
    r = client.post(f"/api/projects/{pid}/versions/2/restore")
    assert r.json()["version"] == 4 and r.json()["yaml"] == text2

    assert client.delete(f"/api/projects/{pid}").status_code == 204
    assert_error(client.get(f"/api/projects/{pid}"), 404)
    assert_error(client.get(f"/api/projects/{pid}/versions"), 404)
    assert_error(client.delete(f"/api/projects/{pid}"), 404)
    assert_error(client.get("/api/projects/0"), 422)


def test_a_draft_that_does_not_size_can_be_saved_but_not_text_that_is_not_yaml(client: TestClient) -> None:
    r = client.post("/api/projects", json={"name": "draft", "yaml": "axis: half done\nmechanism: {type: belt}\n"})
    assert r.status_code == 201 and r.json()["yaml_error"] is None
    body = assert_error(client.post("/api/projects", json={"name": "broken", "yaml": "a: [1, 2"}), 422)
    assert body["field"] == "yaml" and "not valid YAML" in body["detail"]
    assert_error(client.post("/api/projects", json={"name": "list", "yaml": "- 1\n- 2\n"}), 422)


# ---------------------------------------------------------------------------------- YAML files


def test_yaml_upload_and_download_round_trip_to_the_same_sizing(client: TestClient) -> None:
    text = EXAMPLE.read_text(encoding="utf-8")
    r = client.post("/api/yaml/upload", files={"file": ("ball_screw.yaml", text.encode(), "application/yaml")})
    assert r.status_code == 200, r.text
    axis = r.json()["axis"]
    first = client.post("/api/size", json=axis).json()["result"]

    r = client.post("/api/yaml/dump", json=axis)
    assert r.status_code == 200
    assert r.headers["content-disposition"] == 'attachment; filename="Z_lift.yaml"'
    again = parse_yaml(r.text)
    assert again == axis
    second = client.post("/api/size", json=again).json()["result"]
    same_sizing(second, first)

    pid = client.post("/api/projects", json={"name": "round trip", "yaml": r.text}).json()["id"]
    download = client.get(f"/api/projects/{pid}/yaml")
    assert download.status_code == 200 and download.text == r.text
    third = client.post("/api/size", json=yaml.safe_load(download.text)).json()["result"]
    same_sizing(third, first)


def test_yaml_uploads_use_the_cli_limits(client: TestClient) -> None:
    bomb = "a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1]\n" + "".join(
        f"{chr(98 + k)}: &{chr(98 + k)} [*{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, "
        f"*{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}]\n" for k in range(8))
    body = assert_error(client.post("/api/yaml/upload", files={"file": ("bomb.yaml", bomb.encode())}), 422)
    assert body["field"] == "file"
    body = assert_error(client.post("/api/yaml/parse", json={"yaml": "!!python/object:os.system {}"}), 422)
    assert body["field"] == "yaml"
    body = assert_error(client.post("/api/yaml/upload", files={"file": ("x.yaml", b"\xff\xfe\x00")}), 422)
    assert "UTF-8" in body["detail"]


# ---------------------------------------------------------------------------------- safety


def test_text_that_is_not_unicode_is_refused_not_crashed_on(client: TestClient) -> None:
    body = assert_error(client.post("/api/yaml/parse", json={"yaml": 'axis: "\\ud800"'}), 422)
    assert body["field"] == "yaml.axis"
    raw = b'{"axis": "\\ud800x", "mechanism": {"type": "rotary"}}'  # a JSON escape of a lone surrogate
    body = assert_error(client.post("/api/size", content=raw, headers={"content-type": "application/json"}), 422)
    assert body["field"] == "axis" and "Unicode" in body["detail"]
    assert_error(client.post("/api/projects", content=b'{"name": "\\udc00", "yaml": "a: 1"}',
                             headers={"content-type": "application/json"}), 422)
    r = client.post("/api/yaml/upload", files={"file": ("u.yaml", b'axis: "\\udc80"')})
    assert assert_error(r, 422)["field"] == "file.axis"


def test_host_and_origin_are_checked(client: TestClient) -> None:
    body = assert_error(client.get("/api/health", headers={"host": "attacker.example"}), 403)
    assert body["field"] == "host"
    assert client.get("/api/health", headers={"host": "localhost:8000"}).status_code == 200
    body = assert_error(client.post("/api/projects", json={"name": "x", "yaml": "a: 1"},
                                    headers={"origin": "https://attacker.example"}), 403)
    assert body["field"] == "origin"
    ok = client.post("/api/yaml/parse", json={"yaml": "a: 1"}, headers={"origin": "http://127.0.0.1"})
    assert ok.status_code == 200
    body = assert_error(client.post("/api/yaml/parse", json={"yaml": "a: 1"},
                                    headers={"origin": "http://127.0.0.1:8000"}), 403)  # another port
    assert body["field"] == "origin"


def test_request_bodies_are_limited(client: TestClient) -> None:
    big = {"yaml": "x: " + "a" * 1_100_000}
    body = assert_error(client.post("/api/yaml/parse", json=big), 413)
    assert "too large" in body["detail"]


def test_no_request_path_reaches_the_file_system(client: TestClient) -> None:
    assert client.get("/").headers["content-type"].startswith("text/html")
    assert "default-src 'self'" in client.get("/").headers["content-security-policy"]
    assert client.get("/static/app.js").status_code == 200
    assert client.get("/static/vendor/plotly.min.js").status_code == 200
    for path in ("/static/../app.py", "/static/%2e%2e/app.py", "/static/..%2fapp.py", "/static//etc/passwd",
                 "/static/%2fetc%2fpasswd", "/api/examples/..%2f..%2fpyproject"):
        r = client.get(path)
        assert r.status_code == 404, path
        assert "FastAPI" not in r.text and "def create_app" not in r.text


def slow(axis: dict[str, Any]) -> dict[str, Any]:
    """A sizing that takes 2 s (module level: the app runs it in a worker process)."""
    time.sleep(2.0)
    return {}


def test_a_slow_request_is_stopped_with_a_message(data_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DRIVETRAIN_DATA_DIR", str(data_dir))
    monkeypatch.setattr(web_app, "size_payload", slow)
    with TestClient(create_app(data_dir, timeout=0.3), base_url=BASE) as c:
        t0 = time.perf_counter()
        body = assert_error(c.post("/api/size", json=example_axis()), 503)
        assert time.perf_counter() - t0 < 1.5
        assert "longer than 0.3 s" in body["detail"]


def test_every_error_answer_is_json_with_a_message(client: TestClient) -> None:
    assert_error(client.get("/api/nothing-here"), 404)
    assert_error(client.delete("/api/size"), 405)
    assert_error(client.get("/api/catalog/motors", params={"limit": 0}), 422)
    assert_error(client.get("/api/catalog/motors", params={"sort": "colour"}), 422)
    assert_error(client.get("/api/examples/nope"), 404)


def test_openapi_describes_the_axis_schema(client: TestClient) -> None:
    schema = client.get("/openapi.json").json()
    body = schema["paths"]["/api/size"]["post"]["requestBody"]["content"]["application/json"]["schema"]
    assert body == {"$ref": "#/components/schemas/AxisSpec"}
    comps = schema["components"]["schemas"]
    assert "ScrewSpec" in comps and "AxisSpec" in comps
    lead = comps["ScrewSpec"]["properties"]["lead"]
    assert lead["x-quantity"] == "length" and {"type": "string", "maxLength": 200} in lead["anyOf"]
    assert comps["ErrorOut"]["required"] == ["detail"]


def test_form_description_covers_every_mechanism_and_transmission(client: TestClient) -> None:
    from drivetrain.axis.mechanisms import MECHANISM_TYPES
    from drivetrain.axis.transmission import TRANSMISSION_TYPES

    desc = client.get("/api/form").json()
    fields = {f["name"]: f for f in desc["axis"]["fields"]}
    assert set(fields["mechanism"]["variants"]) == set(MECHANISM_TYPES)
    assert set(fields["transmission"]["item"]["variants"]) == set(TRANSMISSION_TYPES)
    assert fields["profile"]["kind"] == "profile"
    screw = {f["name"]: f for f in fields["mechanism"]["variants"]["ball_screw"]["fields"]}
    assert screw["lead"]["kind"] == "quantity" and screw["lead"]["unit"] == "m" and screw["lead"]["required"]



def test_form_description_gives_every_profile_key_a_field(client: TestClient) -> None:
    from drivetrain.motion.profiles import VALID_KEYS, parse_profile

    profile = client.get("/api/form").json()["profile"]
    columns = {c["key"]: c for c in profile["columns"]}
    assert set(columns) | {"dwell"} == set(VALID_KEYS)
    kinds = {k["kind"]: k["keys"] for k in profile["kinds"]}
    assert set().union(*kinds.values()) == set(VALID_KEYS)
    assert columns["law"]["options"][1:] == ["cycloidal", "modified_sine", "modified_trapezoid", "poly345"]
    values = {"move": "200 mm", "speed": "0.4 m/s", "time": "0.5 s", "accel": "0.1 s", "decel": "0.1 s",
              "shape": "trapezoid", "max_speed": "1 m/s", "max_accel": "10 m/s^2", "max_jerk": "500 m/s^3",
              "law": "cycloidal", "thrust": "5 N", "dwell": "0.2 s", "holding": "brake"}
    for kind, keys in kinds.items():  # each kind's keys (bar the s-curve's jerk options) make a step the engine takes
        step = {k: values[k] for k in keys if k in values}
        cycle = parse_profile([step], "linear")
        assert cycle.period > 0, kind


# ---------------------------------------------------------------------------------- catalog


def test_catalog_filter_sort_and_envelope(client: TestClient) -> None:
    page = client.get("/api/catalog/motors", params={"sort": "peak_torque", "order": "desc", "limit": 5}).json()
    peaks = [m["peak_torque_Nm"] for m in page["items"]]
    assert len(peaks) == 5 and peaks == sorted(peaks, reverse=True) and page["total"] > 5
    facets = client.get("/api/catalog/facets").json()
    vendor = facets["motor_vendors"][0]
    only = client.get("/api/catalog/motors", params={"vendor": vendor, "limit": 500}).json()
    assert only["items"] and all(vendor.lower() in m["vendor"].lower() for m in only["items"])
    assert_error(client.get("/api/catalog/motors", params={"vendor": "No Such Vendor"}), 422)
    gb = client.get("/api/catalog/gearboxes", params={"ratio_min": 5, "ratio_max": 10, "limit": 500}).json()
    assert gb["items"] and all(5 <= g["ratio"] <= 10 for g in gb["items"])
    motor = page["items"][0]["id"]
    env = client.get(f"/api/catalog/motors/{motor}/envelope").json()
    assert env["name"] == motor and len(env["speed_rad_s"]) == len(env["peak_Nm"]) > 10
    assert max(t for t in env["peak_Nm"] if t is not None) == pytest.approx(page["items"][0]["peak_torque_Nm"])
    assert client.get(f"/api/catalog/items/{motor}").json()["id"] == motor
    assert_error(client.get("/api/catalog/items/NO-SUCH-ID"), 404)
    assert_error(client.get("/api/catalog/motors/NO-SUCH-ID/envelope"), 404)


GOOD_CSV = """id,vendor,series,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2
WEB-M1,Webtest,W,1.3,4.5,3000,6000,3.7e-5
"""
BAD_CSV = """id,vendor,series,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgm2
WEB-B1,Webtest,W,1.3,4.5,3000,6000,3.7e-5
WEB-B2,Webtest,W,-1,4.5,3000,6000,3.7e-5
WEB-B3,Webtest,W,1.3,lots,3000,6000,3.7e-5
"""


def test_catalog_ids_with_a_slash_are_found(client: TestClient) -> None:
    page = client.get("/api/catalog/motors", params={"q": "/", "limit": 5}).json()
    slashed = [m["id"] for m in page["items"] if "/" in m["id"]]
    assert slashed, "the shipped catalog has ids with a slash (FANUC)"
    for motor_id in slashed:
        quoted = quote(motor_id, safe="")
        item = client.get(f"/api/catalog/items/{quoted}")
        assert item.status_code == 200 and item.json()["id"] == motor_id, item.text
        envelope = client.get(f"/api/catalog/motors/{quoted}/envelope")
        assert envelope.status_code == 200 and envelope.json()["name"] == motor_id, envelope.text
    missing = assert_error(client.get("/api/catalog/items/no%2Fsuch"), 404)
    assert missing["field"] == "item_id"
    assert assert_error(client.get("/api/catalog/motors/no%2Fsuch/envelope"), 404)["field"] == "motor_id"


def test_catalog_import_reports_every_bad_row_and_writes_nothing(client: TestClient, data_dir: Path) -> None:
    key_before = ResultCache(data_dir).key("size", {"a": 1})
    body = assert_error(client.post("/api/catalog/import", files={"file": ("mine.csv", BAD_CSV.encode(), "text/csv")}),
                        422)
    fields = [e["field"] for e in body["errors"]]
    assert fields == ["mine.csv:3:rated_torque_Nm", "mine.csv:4:peak_torque_Nm"]
    assert str(data_dir / "tmp") not in body["detail"]
    assert client.get("/api/catalog/motors", params={"q": "WEB-B"}).json()["total"] == 0
    r = client.post("/api/catalog/import", files={"file": ("mine.csv", GOOD_CSV.encode(), "text/csv")})
    assert r.status_code == 200, r.text
    assert r.json()["rows"] == 1 and r.json()["ids"] == ["WEB-M1"]
    assert "mine.csv" in r.json()["message"] and str(data_dir / "tmp") not in r.json()["message"]
    found = client.get("/api/catalog/motors", params={"q": "WEB-M1"}).json()
    assert ResultCache(data_dir).key("size", {"a": 1}) != key_before, "an import must invalidate sizings"
    assert found["total"] == 1 and found["items"][0]["origin"] == "user"
    assert not list((data_dir / "tmp").glob("*")), "temporary upload left behind"


# ---------------------------------------------------------------------------------- report


@pytest.mark.parametrize("fmt", ["html", "pdf"])
def test_report_download(client: TestClient, data_dir: Path, fmt: str) -> None:
    health = client.get("/api/health").json()
    r = client.post("/api/report", params={"format": fmt}, json=example_axis())
    if not health["report"]:
        body = assert_error(r, 503)
        assert "not available" in body["detail"]
        return
    if fmt == "pdf" and r.status_code == 422 and "browser" in r.text.lower():
        pytest.skip(f"no PDF writer here: {r.json()['detail']}")
    assert r.status_code == 200, r.text[:500]
    assert r.headers["content-disposition"].startswith('attachment; filename="Z_lift-report.')
    if fmt == "html":
        assert r.headers["content-type"].startswith("text/html") and "<html" in r.text.lower()
    else:
        assert r.content.startswith(b"%PDF")
    assert not list((data_dir / "tmp").glob("*")), "temporary report left behind"
