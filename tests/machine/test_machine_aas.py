"""The IDTA 02021 "Sizing of Power Drive Trains" export validates against the published AAS V3.0 JSON schema."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from drivetrain import cli
from drivetrain.machine.aas import SMT, axis_aas, id_short, machine_aas

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "tests" / "data" / "aas" / "aas.json").read_text(encoding="utf-8"))
VALIDATOR = jsonschema.Draft201909Validator(SCHEMA)


def _errors(env: dict[str, Any]) -> list[str]:
    return [f"{list(e.absolute_path)}: {e.message[:200]}" for e in VALIDATOR.iter_errors(env)]


def _elements(env: dict[str, Any]) -> dict[str, Any]:
    return {e["idShort"]: e for e in env["submodels"][0]["submodelElements"]}


def test_axis_export_validates(tmp_path: Path) -> None:
    out = tmp_path / "axis.aas.json"
    assert cli.main(["size", str(ROOT / "examples" / "machine" / "x_belt.yaml"), "--aas", str(out), "--json"]) == 0
    env = json.loads(out.read_text(encoding="utf-8"))
    assert _errors(env) == []
    sm = env["submodels"][0]
    assert sm["semanticId"]["keys"][0]["value"] == f"{SMT}/1/0"
    result = {e["idShort"]: e for e in _elements(env)["SizingResult"]["value"]}
    motor = {s["idShort"]: s["value"] for s in result["MainComponent01"]["statements"]}
    assert motor["MainComponentType"] == "Motor"
    assert motor["ManufacturerOrderCode"] == "1FT7044-5AK7"
    drive = {s["idShort"]: s["value"] for s in result["MainComponent02"]["statements"]}
    assert drive["MainComponentType"] == "Drive" and float(drive["ContinuousCurrent"]) == 9.0


def test_machine_export_validates(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "machine.aas.json"
    path = ROOT / "examples" / "machine" / "pick_and_place.yaml"
    assert cli.main(["machine", "size", str(path), "--samples", "5", "--aas", str(out), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    env = json.loads(out.read_text(encoding="utf-8"))
    assert _errors(env) == []
    comps = [e for e in _elements(env)["SizingResult"]["value"] if e["idShort"].startswith("MainComponent")]
    kinds = [next(s["value"] for s in c["statements"] if s["idShort"] == "MainComponentType") for c in comps]
    assert kinds.count("Motor") == 5 and kinds.count("Drive") == 5  # X, Y (two), Z, R
    others = [e for e in _elements(env)["SizingResult"]["value"] if e["idShort"].startswith("OtherComponent")]
    assert others == []  # no resistor named in the example: the BOM says what to choose instead
    assert env == machine_aas(result, created=env["submodels"][0]["submodelElements"][0]["value"][3]["value"])


def test_a_broken_export_fails_the_schema() -> None:
    env = axis_aas({"axis": "a", "motor": None}, created="2026-01-01T00:00:00Z")
    assert _errors(env) == []
    bad = copy.deepcopy(env)
    bad["submodels"][0]["idShort"] = "1 not an idShort"
    assert _errors(bad)
    bad = copy.deepcopy(env)
    bad["submodels"][0]["submodelElements"][0]["value"][0]["valueType"] = "xs:float64"
    assert _errors(bad)


def test_id_short_is_always_valid() -> None:
    for text in ("Y gantry (2 motors)", "3 axis", "", "__", "ä-ö"):
        assert VALIDATOR.is_valid({"submodels": [{"modelType": "Submodel", "id": "urn:x", "idShort": id_short(text)}]})


def test_named_resistors_and_supply_modules_are_other_components() -> None:
    from drivetrain.machine.result import size_machine
    from tests.machine.test_machine import TWO

    data = copy.deepcopy(TWO)
    data["buses"] = [{"name": "bus", "axes": ["Z", "X"], "supply_module": {"id": "SM-1", "vendor": "v"},
                      "resistors": [{"id": "BR-1", "vendor": "v", "resistance": "100 ohm", "quantity": 2}]}]
    out = json.loads(json.dumps(size_machine(data, phasing_samples=1).to_dict()))
    env = machine_aas(out, created="2026-01-01T00:00:00Z")
    assert _errors(env) == []
    others = [e for e in _elements(env)["SizingResult"]["value"] if e["idShort"].startswith("OtherComponent")]
    codes = {next(s["value"] for s in o["statements"] if s["idShort"] == "ManufacturerOrderCode"): o for o in others}
    assert set(codes) == {"SM-1", "BR-1"}
    qty = next(s["value"] for s in codes["BR-1"]["statements"] if s["idShort"] == "QuantityOfParts")
    assert qty == "2"
