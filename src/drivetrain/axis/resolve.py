"""Catalog references in an axis file, resolved where the file is read.

The formulas (drivetrain.physics) never see the database: a ``transmission: [{type: gearbox,
catalog: ID}]`` entry becomes a gearbox spec carrying the row's datasheet values, and a
``motor: {id: ...}`` becomes MotorData, here.
"""

from __future__ import annotations

from typing import Any

from drivetrain.axis.transmission import GearboxSpec, TransmissionSpec
from drivetrain.errors import InputError


def catalog_gearbox_row(catalog_id: str, field: str) -> dict[str, Any]:
    """The catalog record of a gearbox id, or an InputError at ``field``."""
    from drivetrain import catalog

    try:
        row = catalog.get(catalog_id)
    except InputError as exc:
        raise InputError(field, exc.rule, catalog_id) from None
    if row.get("table") != "gearbox":
        raise InputError(field, "is not a gearbox in the catalog", catalog_id)
    return row


def resolve_gearbox(spec: GearboxSpec, index: int) -> GearboxSpec:
    """A ``catalog: ID`` gearbox with ratio, efficiency, input inertia, torsional stiffness,
    backlash and ratings from its catalog row (datasheet values with their source) unless given in
    the file."""
    if spec.catalog is None:
        return spec
    row = catalog_gearbox_row(str(spec.catalog), f"transmission[{index}].catalog")
    filled = {
        "ratio": spec.ratio if spec.ratio is not None else float(row["ratio"]),
        "efficiency": spec.efficiency if spec.efficiency is not None else row.get("efficiency"),
        "inertia": spec.inertia or (row.get("inertia_input_kgm2") or 0.0),
        "stiffness": row.get("torsional_stiffness_Nm_per_rad") if spec.stiffness is None else spec.stiffness,
        "backlash": spec.backlash or (row.get("backlash_rad") or 0.0),
        # ratings, checked by drivetrain.sizing.checks.gearbox_ratings (None where the row lacks them)
        "rated_torque": spec.rated_torque if spec.rated_torque is not None else row.get("rated_output_torque_Nm"),
        "max_torque": spec.max_torque if spec.max_torque is not None else row.get("max_output_torque_Nm"),
        "emergency_stop_torque": spec.emergency_stop_torque if spec.emergency_stop_torque is not None
        else row.get("emergency_stop_torque_Nm"),
        "max_input_speed": spec.max_input_speed if spec.max_input_speed is not None
        else row.get("max_input_speed_rad_s"),
        "rated_input_speed": spec.rated_input_speed if spec.rated_input_speed is not None
        else row.get("rated_input_speed_rad_s"),
    }
    return spec.model_copy(update={k: v for k, v in filled.items() if v is not None})


def resolve_transmission(specs: list[TransmissionSpec]) -> list[TransmissionSpec]:
    """Every catalog reference of the transmission list resolved (others unchanged)."""
    return [resolve_gearbox(t, k) if isinstance(t, GearboxSpec) else t for k, t in enumerate(specs)]
