"""The shipped side tables merged into the motor rows when the catalog is built: the electrical data
(data/SOURCES.md, "Motor electrical data"), the holding-brake variants ("Brake variants") and the vendor
documents of re-sourced rows; and the reading of every shipped data file.
"""

from __future__ import annotations

import math
from typing import Any

from drivetrain.catalog.derive import DERIVED_KT
from drivetrain.catalog.schema import (
    BRAKES_FILE,
    DOCUMENT_FIELDS,
    ELECTRICAL_FILE,
    MOTOR_DOCUMENTS_FILE,
    ORDER_CODES_FILE,
)


def shipped_text(filename: str) -> str:
    """Text of a file shipped in drivetrain/catalog/data (read through importlib.resources, imported here: a
    warm sizing reads none, and its import brings tempfile and shutil)."""
    from importlib import resources

    return resources.files("drivetrain.catalog").joinpath("data", filename).read_text(encoding="utf-8")


_BRAKE_COLUMNS = {"rotor_inertia_brake_kgm2": "rotor_inertia_brake", "brake_holding_torque_Nm": "brake_holding_torque",
                  "brake_code": "brake_code", "brake_source": "brake_source"}


def motor_brakes() -> dict[str, dict[str, str]]:
    """The holding-brake variants of shipped motors by id (BRAKES_FILE; data/SOURCES.md, "Brake variants")."""
    import csv
    import io

    reader = csv.DictReader(io.StringIO(shipped_text(BRAKES_FILE)))
    if reader.fieldnames is None or set(reader.fieldnames) != {"id", *_BRAKE_COLUMNS, *BRAKE_ONLY_COLUMNS}:
        raise RuntimeError(f"{BRAKES_FILE}: columns must be id and "
                           f"{', '.join([*_BRAKE_COLUMNS, *BRAKE_ONLY_COLUMNS])}")
    out: dict[str, dict[str, str]] = {}
    for r in reader:
        if r["id"] in out or not r["brake_source"].strip():
            raise RuntimeError(f"{BRAKES_FILE}: {r['id']}: listed twice or without brake_source")
        for column in BRAKE_ONLY_COLUMNS:
            text = (r.get(column) or "").strip()
            if text and not float(text) > 0.0:
                raise RuntimeError(f"{BRAKES_FILE}: {r['id']}: {column} {text} must be > 0")
        out[r["id"]] = {k: v.strip() for k, v in r.items() if k != "id" and v and v.strip()}
    return out


BRAKE_ONLY_COLUMNS = ("mass_brake_kg",)
"""Columns of BRAKES_FILE read from it directly and not merged into the motor rows (the motors table has no
field for them): the with-brake motor mass [kg] as the vendor prints it."""


def merge_brake(values: dict[str, Any], brake: dict[str, str]) -> None:
    """Add a motor's brake variant (BRAKES_FILE, SI columns) to its row; a value its own file already has must agree."""
    for column, name in _BRAKE_COLUMNS.items():
        if column not in brake:
            continue
        value: Any = brake[column] if name in ("brake_code", "brake_source") else float(brake[column])
        have = values.get(name)
        if have is not None and (have != value if isinstance(value, str) else not math.isclose(have, value,
                                                                                               rel_tol=1e-9)):
            raise RuntimeError(f"{BRAKES_FILE}: {values.get('id')}: {name} {value} differs from its file's {have}")
        values[name] = value


_ORDER_CODE_COLUMNS = ("id", "position", "printed_as", "meaning", "options", "source", "note")


def order_code_positions() -> dict[str, list[dict[str, Any]]]:
    """The open positions of shipped order codes by id (ORDER_CODES_FILE; data/SOURCES.md, "Order-code
    positions"): each ``position`` (1-based character index into the id, where ``printed_as`` must start: an
    ``x`` the buyer chooses, or the alternatives the row names, e.g. ``H/T``),
    ``meaning`` and ``options`` (``options`` empty where the vendor's key was not read: the buyer chooses from
    the vendor's catalogue), ``source`` and ``note``; positions in order."""
    import csv
    import io

    reader = csv.DictReader(io.StringIO(shipped_text(ORDER_CODES_FILE)))
    if reader.fieldnames is None or tuple(reader.fieldnames) != _ORDER_CODE_COLUMNS:
        raise RuntimeError(f"{ORDER_CODES_FILE}: columns must be {', '.join(_ORDER_CODE_COLUMNS)}")
    out: dict[str, list[dict[str, Any]]] = {}
    for r in reader:
        pos, printed = int(r["position"]), r["printed_as"]
        if not (printed and pos >= 1 and r["id"][pos - 1:pos - 1 + len(printed)] == printed) or not r["source"].strip():
            raise RuntimeError(f"{ORDER_CODES_FILE}: {r['id']}: position {pos} does not hold {r['printed_as']!r}, "
                               "or the row has no source")
        out.setdefault(r["id"], []).append({**{k: v.strip() for k, v in r.items() if k != "id"}, "position": pos})
    for rows in out.values():
        rows.sort(key=lambda p: p["position"])
    return out


def motor_documents() -> dict[str, dict[str, Any]]:
    """The vendor documents of shipped motors by id (MOTOR_DOCUMENTS_FILE), ``verified`` as 1/0."""
    import csv
    import io

    out: dict[str, dict[str, Any]] = {}
    reader = csv.DictReader(io.StringIO(shipped_text(MOTOR_DOCUMENTS_FILE)))
    if reader.fieldnames is None or set(reader.fieldnames) != {"id", *DOCUMENT_FIELDS}:
        raise RuntimeError(f"{MOTOR_DOCUMENTS_FILE}: columns must be id and {', '.join(DOCUMENT_FIELDS)}")
    for r in reader:
        values: dict[str, Any] = {k: v.strip() for k, v in r.items() if k != "id" and v and v.strip()}
        if values.get("verified") not in ("yes", "no"):
            raise RuntimeError(f"{MOTOR_DOCUMENTS_FILE}: {r['id']}: verified must be yes or no")
        values["verified"] = int(values["verified"] == "yes")
        out[r["id"]] = values
    return out


# electrical table column -> (motor field, factor to SI); back-EMF V/1000 rpm -> V s/rad (its basis kept as text);
# the stall torque is the one printed beside the stall current (Siemens 1FT7 M_0 at 100 K, Table 4-8)
_ELECTRICAL_COLUMNS: dict[str, tuple[str, float]] = {
    "rated_current_A": ("rated_current", 1.0), "peak_current_A": ("peak_current", 1.0),
    "stall_current_A": ("stall_current", 1.0), "stall_torque_Nm": ("stall_torque", 1.0),
    "torque_constant_Nm_per_A": ("torque_constant", 1.0),
    "back_emf_V_per_krpm": ("back_emf", 60.0 / (2.0 * math.pi * 1000.0)),
    "winding_resistance_ohm": ("winding_resistance", 1.0),
    "winding_inductance_H": ("winding_inductance", 1.0),
    "thermal_time_constant_s": ("thermal_time_constant", 1.0),
}


def _electrical_rows() -> dict[str, dict[str, str]]:
    import csv
    import io

    return {r["id"]: r for r in csv.DictReader(io.StringIO(shipped_text(ELECTRICAL_FILE)))}


def merge_electrical(values: dict[str, Any]) -> None:
    """Add the shipped electrical table's values (data/SOURCES.md, "Motor electrical data") to a motor row.

    Only empty fields are filled; the electrical table's source is kept in ``electrical_source``.
    """
    row = _electrical_rows_cached().get(str(values.get("id")))
    if row is None:
        return
    for column, (name, factor) in _ELECTRICAL_COLUMNS.items():
        text = row.get(column, "").strip()
        if text and values.get(name) is None:
            values[name] = float(text) * factor
    if row.get("pole_count", "").strip() and values.get("pole_count") is None:
        values["pole_count"] = int(float(row["pole_count"]))
    # The table prints I_0 at a 60 K and at a 100 K winding rise (Siemens 1FT7, Table 4-8): the stall
    # current read is the 100 K one, so the rated rise that goes with it is 100 K.
    if row.get("stall_current_60K_A", "").strip() and values.get("stall_current") is not None:
        values.setdefault("rated_winding_rise", 100.0)
    if values.get("back_emf") is not None:
        values["back_emf_basis"] = "ll_rms"
    if row.get("resistance_basis"):
        values["resistance_basis"] = row["resistance_basis"]
    source = f"{row.get('source', '')} <{row.get('source_url', '')}>"
    # k_T not printed but rated torque and rated current are (same table): stored as k_T = T_N / I_N,
    # flagged as derived (data/SOURCES.md, "Derived torque constants")
    if row.get("torque_constant_basis", "").startswith("derived") and values.get("torque_constant") is not None:
        names = [n for n in str(values.get("derived") or "").split(",") if n]
        values["derived"] = ",".join(dict.fromkeys([*names, "torque_constant"]))
        source += f"; k_T {DERIVED_KT}"
    values["electrical_source"] = source


_ELECTRICAL_CACHE: dict[str, dict[str, dict[str, str]]] = {}


def _electrical_rows_cached() -> dict[str, dict[str, str]]:
    if "rows" not in _ELECTRICAL_CACHE:
        _ELECTRICAL_CACHE["rows"] = _electrical_rows()
    return _ELECTRICAL_CACHE["rows"]
