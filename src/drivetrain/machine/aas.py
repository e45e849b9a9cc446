"""Export a sizing result as an IDTA 02021 "Sizing of Power Drive Trains" submodel (AAS JSON, metamodel V3.0).

Structure and semantic ids follow the submodel template IDTA 02021-1-0 ("Sizing of Power Drive
Trains", Industrial Digital Twin Association, 2023; semantic ids under
``https://admin-shell.io/idta/PowerDriveTrainSizing/``): ``SizingProjectInformation``,
``SizingResult`` with an ``OverallSystem`` entity, one ``MainComponent`` entity per motor, drive
and gearbox, ``OtherComponents`` (braking resistors, supply modules) and ``Messages``. The
serialisation is the AAS JSON of IDTA 01001-3-0 (Part 1: metamodel); the file validates
against its published JSON schema (tests/data/aas/aas.json, admin-shell-io/aas-specs).

Values are SI numbers (xs:double); each numeric property names its unit in its description,
because the template types them as plain numbers.
"""

from __future__ import annotations

import datetime as _dt
import math
import re
from typing import Any

from drivetrain.version import __version__

SMT = "https://admin-shell.io/idta/PowerDriveTrainSizing"
IRDI = {"ManufacturerName": "0173-1#02-AAO677#002", "ManufacturerArticleNumber": "0173-1#02-AAO676#003",
        "ManufacturerOrderCode": "0173-1#02-AAO227#002"}
TOOL = f"drivetrain {__version__}"


def _sem(name: str) -> dict[str, Any]:
    value = IRDI.get(name) or f"{SMT}/{name}/1/0"
    return {"type": "ExternalReference", "keys": [{"type": "GlobalReference", "value": value}]}


def id_short(text: str) -> str:
    """A valid idShort from any text: letters, digits, underscores; starts with a letter.

    >>> id_short("Y gantry (2 motors)")
    'Y_gantry_2_motors'
    """
    s = re.sub(r"[^A-Za-z0-9_]+", "_", text).strip("_")
    if not s or not s[0].isalpha():
        s = f"A{s}" if s else "A1"
    return s[:128]


def prop(name: str, value: Any, unit: str | None = None, value_type: str | None = None) -> dict[str, Any]:
    """An AAS Property (string, double, integer or boolean)."""
    if value_type is None:
        if isinstance(value, bool):
            value_type = "xs:boolean"
        elif isinstance(value, int):
            value_type = "xs:int"
        elif isinstance(value, float):
            value_type = "xs:double"
        else:
            value_type = "xs:string"
    text = ("true" if value else "false") if isinstance(value, bool) else (
        repr(float(value)) if value_type == "xs:double" else str(value))
    out: dict[str, Any] = {"modelType": "Property", "idShort": name, "semanticId": _sem(name),
                           "valueType": value_type, "value": text}
    if unit:
        out["description"] = [{"language": "en", "text": f"unit: {unit}"}]
    return out


def mlp(name: str, text: str) -> dict[str, Any]:
    return {"modelType": "MultiLanguageProperty", "idShort": name, "semanticId": _sem(name),
            "value": [{"language": "en", "text": text or "-"}]}


def smc(name: str, elements: list[dict[str, Any]], semantic: str | None = None) -> dict[str, Any]:
    """A SubmodelElementCollection (an empty one carries no ``value``: AAS JSON lists have at least one item)."""
    out: dict[str, Any] = {"modelType": "SubmodelElementCollection", "idShort": name,
                           "semanticId": _sem(semantic or name)}
    if elements:
        out["value"] = elements
    return out


def entity(name: str, semantic: str, statements: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {"modelType": "Entity", "idShort": name, "semanticId": _sem(semantic),
                           "entityType": "CoManagedEntity"}
    if statements:
        out["statements"] = statements
    return out


def _num(items: list[dict[str, Any]], name: str, value: Any, unit: str) -> None:
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
        items.append(prop(name, float(value), unit))


def _component(kind: str, k: int, vendor: str | None, code: str, figures: list[tuple[str, Any, str]],
               quantity: int | None = None, other: bool = False) -> dict[str, Any]:
    st: list[dict[str, Any]] = []
    if not other:
        st.append(prop("MainComponentType", kind))
    st += [prop("ManufacturerName", vendor or "not stated"), prop("ManufacturerArticleNumber", code),
           prop("ManufacturerOrderCode", code)]
    if quantity is not None:
        st.append(prop("QuantityOfParts", int(quantity), value_type="xs:int"))
    for name, value, unit in figures:
        _num(st, name, value, unit)
    sem = "OtherComponent" if other else "MainComponent"
    return entity(f"{'OtherComponent' if other else 'MainComponent'}{k:02d}", sem, st)


def _project(name: str, axis_ref: str | None, created: str) -> dict[str, Any]:
    items = [prop("ClientName", "not stated"), prop("SizingProjectName", name), prop("SizingToolName", TOOL),
             prop("DateCreated", created, value_type="xs:dateTime"),
             prop("DateChanged", created, value_type="xs:dateTime")]
    if axis_ref:
        items.append(prop("SizingProjectAxisReference", axis_ref))
    return smc("SizingProjectInformation", items)


def _messages(texts: list[tuple[str, str]]) -> dict[str, Any]:
    msgs = [smc(f"Message{k + 1:02d}", [prop("CriticalityOfMessage", level), mlp("MessageText", text)], "Message")
            for k, (level, text) in enumerate(texts)]
    return smc("Messages", msgs)


def _axis_components(d: dict[str, Any], start: int, quantity: int = 1) -> list[dict[str, Any]]:
    """Main components of one axis result dict (SizingResult.to_dict()): motor, drive, gearbox."""
    out: list[dict[str, Any]] = []
    k = start
    m = d.get("motor")
    sel = (d.get("selection") or {}).get("selected")
    if m is not None:
        peak_avail = next((c["available"] for c in m.get("checks", []) if c["name"] == "peak_torque"), None)
        figs = [("MaxTorqueUtilization", m.get("peak_torque_Nm"), "N*m"),
                ("RmsOfMotorTorque", m.get("rms_torque_Nm"), "N*m"),
                ("MassInertiaRatio", m.get("inertia_ratio"), "-"),
                ("MaxCurrentUtilization", m.get("peak_current_A"), "A"),
                ("MaxThermalUtilization", m.get("winding_temperature_rise_K"), "K (winding rise)")]
        if peak_avail:
            figs.append(("MaxTorqueUtilizationPercentage", 100.0 * m["peak_torque_Nm"] / peak_avail, "%"))
        vendor = str(m.get("source", "")).split(" ")[0] if m.get("source") != "axis file" else None
        out.append(_component("Motor", k, vendor, str(m.get("name")), figs, quantity))
        k += 1
    elif sel:
        out.append(_component("Motor", k, sel.get("vendor"), str(sel["motor"]),
                              [("MaxTorqueUtilization", sel.get("peak_torque_Nm"), "N*m"),
                               ("RmsOfMotorTorque", sel.get("rms_torque_Nm"), "N*m"),
                               ("MassInertiaRatio", sel.get("inertia_ratio"), "-")], quantity))
        k += 1
        if sel.get("gearbox"):
            out.append(_component("Gearbox", k, None, str(sel["gearbox"]), [], quantity))
            k += 1
    drv = d.get("drive")
    if drv is not None:
        rg = d.get("regen") or {}
        out.append(_component("Drive", k, drv.get("vendor"), str(drv.get("id")), [
            ("ContinuousCurrent", drv.get("continuous_current_A"), "A"),
            ("MaxCurrentUtilization", (m or {}).get("peak_current_A"), "A"),
            ("AverageRegenerativePowerDcLink", rg.get("energy_per_cycle_J", 0.0) / d["cycle_time_s"]
             if "cycle_time_s" in d and rg else None, "W"),
            ("MaxRegenerativePowerDcLink", rg.get("resistor_peak_power_W"), "W")], quantity))
        k += 1
    return out


def _environment(submodel: dict[str, Any], name: str) -> dict[str, Any]:
    aas_id = f"urn:drivetrain:aas:{id_short(name)}"
    return {
        "assetAdministrationShells": [{
            "modelType": "AssetAdministrationShell", "id": aas_id, "idShort": id_short(name),
            "assetInformation": {"assetKind": "Instance", "globalAssetId": f"urn:drivetrain:asset:{id_short(name)}"},
            "submodels": [{"type": "ModelReference", "keys": [{"type": "Submodel", "value": submodel["id"]}]}],
        }],
        "submodels": [submodel],
    }


def _submodel(name: str, elements: list[dict[str, Any]]) -> dict[str, Any]:
    return {"modelType": "Submodel", "id": f"urn:drivetrain:submodel:PowerDriveTrainSizing:{id_short(name)}",
            "idShort": "PowerDriveTrainSizing", "kind": "Instance",
            "semanticId": {"type": "ExternalReference",
                           "keys": [{"type": "GlobalReference", "value": f"{SMT}/1/0"}]},
            "submodelElements": elements}


def _now(created: str | None) -> str:
    return created or _dt.datetime.now(_dt.UTC).replace(microsecond=0).strftime("%Y-%m-%dT%H:%M:%SZ")


def axis_aas(result: dict[str, Any], created: str | None = None) -> dict[str, Any]:
    """The AAS environment (JSON) of one axis's sizing result (``SizingResult.to_dict()``)."""
    name = str(result.get("axis", "axis"))
    when = _now(created)
    overall: list[dict[str, Any]] = []
    m = result.get("motor") or {}
    _num(overall, "ExternalMomentOfInertia", result.get("load_inertia_kgm2"), "kg*m^2")
    _num(overall, "InternalMomentOfIntertia", m.get("inertia_kgm2"), "kg*m^2")
    _num(overall, "MassInertiaRatio", m.get("inertia_ratio"), "-")
    msgs = [("Warning", w) for w in result.get("warnings", [])]
    if m and not m.get("ok", True):
        msgs.append(("Error", f"motor fails: {m.get('failed')}"))
    res = [entity("OverallSystem", "OverallSystem", overall), *_axis_components(result, 1), _messages(msgs)]
    sm = _submodel(name, [_project(name, name, when), smc("SizingResult", res)])
    return _environment(sm, name)


def machine_aas(result: dict[str, Any], created: str | None = None) -> dict[str, Any]:
    """The AAS environment (JSON) of a machine's sizing result (``MachineResult.to_dict()``)."""
    mach = result["machine"]
    name = str(mach["name"])
    when = _now(created)
    overall: list[dict[str, Any]] = []
    _num(overall, "EnergyConsumtionPerCycle", mach.get("supply_continuous_power_W", 0.0) * mach["cycle_time_s"], "J")
    main: list[dict[str, Any]] = []
    for a in result["axes"]:
        results = [a["result"]] if "result" in a else a["results"]
        for r in results:
            main.extend(_axis_components({**r, "cycle_time_s": a["cycle_s"]}, len(main) + 1))
    others: list[dict[str, Any]] = []
    for row in result["bill_of_materials"]:
        if row["kind"] in ("braking_resistor", "supply_module") and row["order_code"] is not None:
            bus: dict[str, Any] = next((b for b in result["buses"] if b["name"] in row["used_by"]), {})
            figs = ([("EnergyConsumtionPerCycle", bus.get("resistor_energy_per_cycle_J"), "J (dissipated)")]
                    if row["kind"] == "braking_resistor" else [])
            others.append(_component(row["kind"], len(others) + 1, row.get("vendor"), str(row["order_code"]), figs,
                                     row["quantity"], other=True))
    msgs = [("Information", f"bus {b['name']}: peak {b['bus_peak_power_W']:.4g} W, RMS {b['bus_rms_power_W']:.4g} W, "
                            f"resistor {b['resistor_energy_per_cycle_J']:.4g} J per cycle") for b in result["buses"]]
    msgs += [("Error", f"axis {a['name']} fails") for a in result["axes"] if not a["ok"]]
    res = [entity("OverallSystem", "OverallSystem", overall), *main, *others, _messages(msgs)]
    sm = _submodel(name, [_project(name, None, when), smc("SizingResult", res)])
    return _environment(sm, name)
