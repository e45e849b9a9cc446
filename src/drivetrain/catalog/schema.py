"""The catalog's tables: every field with its quantity, SI database column and display unit.

This module is the one place that says what a motor, gearbox, drive or speed-torque curve
point is made of. The database schema, the importer, the exporter and the array tables are all
generated from these lists, so a field added here appears everywhere at once.

Naming: a field's ``name`` is what users write in a CSV/JSON header (``rotor_inertia``,
optionally with a unit: ``rotor_inertia [kg*cm^2]``); its ``column`` is the SQLite column and
the key of ``catalog.get()`` dicts, in SI with the unit in the name (``rotor_inertia_kgm2``).
"""

from __future__ import annotations

from dataclasses import dataclass

DATA_VERSION = "2026.11-6"
"""Version of the shipped data files; the cached database is rebuilt when it changes."""

SCHEMA_VERSION = 5
"""Version of the SQLite layout; older user databases listed in db._UPGRADABLE gain the new columns in
place, any other version is refused."""

# Non-numeric field types; every other ``quantity`` is a units.QUANTITIES key or in EXTRA_QUANTITIES.
TEXT = "text"
INTEGER = "integer"
FLAG = "flag"
DECIBEL = "decibel"

# Quantities units.py does not know: name -> (SI unit for pint, description).
EXTRA_QUANTITIES: dict[str, tuple[str, str]] = {
    "torque_constant": ("N*m/A", "torque constant (N*m/A)"),
    "resistance": ("ohm", "resistance (ohm)"),
    "inductance": ("H", "inductance (H)"),
    "capacitance": ("F", "capacitance (F)"),
    "thermal_resistance": ("K/W", "thermal resistance (K/W)"),
}


@dataclass(frozen=True)
class Field:
    """One field of a catalog table.

    name: header name in import files and the Python attribute name.
    quantity: a units.QUANTITIES key, an EXTRA_QUANTITIES key, or TEXT / INTEGER / FLAG / DECIBEL.
    column: SQLite column and dict key, SI with the unit in the name.
    unit: unit used in export headers and tables (a human catalogue unit, e.g. rpm, kg*cm^2).
    positive: a given value must be > 0 (``False``: >= 0 allowed, or a sign is meaningful).
    """

    name: str
    quantity: str
    column: str
    unit: str = ""
    positive: bool = True

    @property
    def numeric(self) -> bool:
        return self.quantity not in (TEXT, FLAG)


def _text(name: str) -> Field:
    return Field(name, TEXT, name)


_COMMON_HEAD = (_text("id"), _text("kind"), _text("vendor"), _text("series"), _text("model"))
_COMMON_TAIL = (_text("source"), _text("notes"))
# The vendor document a row's numbers were read from (data/SOURCES.md).
_DOCUMENT = (_text("source_document"), _text("source_section"), _text("source_page"), _text("source_url"))
# Why a row is not traced to a vendor document (shown with its ``unverified`` flag in every answer).
_TRACE = (Field("verified", FLAG, "verified"), _text("unverified_reason"))
# Where one group of a motor's fields was read when it differs from the row's document.
_GROUP_SOURCES = (_text("ratings_source"), _text("mechanical_source"), _text("electrical_source"))

MOTOR_FIELDS: tuple[Field, ...] = (
    *_COMMON_HEAD,
    _text("type"),
    Field("rated_power", "power", "rated_power_W", "W"),
    Field("rated_torque", "torque", "rated_torque_Nm", "N*m"),
    Field("stall_torque", "torque", "stall_torque_Nm", "N*m"),
    Field("peak_torque", "torque", "peak_torque_Nm", "N*m"),
    Field("rated_speed", "angular_speed", "rated_speed_rad_s", "rpm"),
    Field("max_speed", "angular_speed", "max_speed_rad_s", "rpm"),
    Field("rotor_inertia", "inertia", "rotor_inertia_kgm2", "kg*cm^2"),
    Field("rotor_inertia_brake", "inertia", "rotor_inertia_brake_kgm2", "kg*cm^2"),
    Field("brake", FLAG, "brake"),
    Field("mass", "mass", "mass_kg", "kg"),
    Field("flange", "length", "flange_m", "mm"),
    Field("shaft_diameter", "length", "shaft_diameter_m", "mm"),
    Field("pilot_diameter", "length", "pilot_diameter_m", "mm"),
    Field("bolt_circle", "length", "bolt_circle_m", "mm"),
    Field("voltage", "voltage", "voltage_V", "V"),
    Field("torque_constant", "torque_constant", "torque_constant_Nm_per_A", "N*m/A"),
    Field("winding_resistance", "resistance", "winding_resistance_ohm", "ohm"),
    Field("winding_inductance", "inductance", "winding_inductance_H", "mH"),
    Field("rated_current", "current", "rated_current_A", "A"),
    Field("no_load_current", "current", "no_load_current_A", "A", positive=False),
    Field("no_load_speed", "angular_speed", "no_load_speed_rad_s", "rpm"),
    Field("max_continuous_speed", "angular_speed", "max_continuous_speed_rad_s", "rpm"),
    Field("rth_winding_housing", "thermal_resistance", "rth_winding_housing_K_per_W", "K/W"),
    Field("rth_housing_ambient", "thermal_resistance", "rth_housing_ambient_K_per_W", "K/W"),
    # electrical columns (data/motors_ac_servo_electrical.csv, merged by id into the motors they describe)
    Field("peak_current", "current", "peak_current_A", "A"),
    Field("stall_current", "current", "stall_current_A", "A"),
    Field("back_emf", "back_emf_constant", "back_emf_Vs_per_rad", "V*s"),
    _text("back_emf_basis"),
    _text("resistance_basis"),
    Field("pole_count", INTEGER, "pole_count"),
    Field("thermal_time_constant", "time", "thermal_time_constant_s", "s"),
    Field("rated_winding_rise", "temperature_difference", "rated_winding_rise_K", "K"),
    # the holding-brake variant (data/SOURCES.md "Brake variants"): the brake's holding (static friction) torque,
    # the brake variant's order code and where both were read; its inertia is rotor_inertia_brake (with-brake total)
    Field("brake_holding_torque", "torque", "brake_holding_torque_Nm", "N*m"),
    _text("brake_code"),
    _text("brake_source"),
    _text("rated_torque_basis"),
    _text("derived"),
    # the formula of each derived field ("field = formula", joined by voltage_class.SEPARATOR)
    _text("derivation"),
    *_COMMON_TAIL,
    *_DOCUMENT,
    *_TRACE,
    *_GROUP_SOURCES,
)

GEARBOX_FIELDS: tuple[Field, ...] = (
    *_COMMON_HEAD,
    _text("type"),
    Field("ratio", "dimensionless", "ratio"),
    Field("stages", INTEGER, "stages"),
    Field("rated_output_torque", "torque", "rated_output_torque_Nm", "N*m"),
    Field("max_output_torque", "torque", "max_output_torque_Nm", "N*m"),
    Field("emergency_stop_torque", "torque", "emergency_stop_torque_Nm", "N*m"),
    Field("efficiency", "dimensionless", "efficiency"),
    Field("max_input_speed", "angular_speed", "max_input_speed_rad_s", "rpm"),
    Field("rated_input_speed", "angular_speed", "rated_input_speed_rad_s", "rpm"),
    Field("inertia_input", "inertia", "inertia_input_kgm2", "kg*cm^2"),
    Field("backlash", "angle", "backlash_rad", "arcmin", positive=False),
    Field("torsional_stiffness", "torsional_stiffness", "torsional_stiffness_Nm_per_rad", "N*m/arcmin"),
    Field("max_radial_load", "force", "max_radial_load_N", "N"),
    Field("max_axial_load", "force", "max_axial_load_N", "N"),
    Field("max_tilting_moment", "torque", "max_tilting_moment_Nm", "N*m"),
    Field("mass", "mass", "mass_kg", "kg"),
    Field("noise", DECIBEL, "noise_dB", "dB"),
    Field("input_bore_max", "length", "input_bore_max_m", "mm"),
    Field("input_bore_min", "length", "input_bore_min_m", "mm"),
    Field("input_flange", "length", "input_flange_m", "mm"),
    Field("input_pilot", "length", "input_pilot_m", "mm"),
    _text("input_adapters"),
    Field("direction", INTEGER, "direction", positive=False),
    Field("right_angle", FLAG, "right_angle"),
    Field("verified", FLAG, "verified"),
    *_COMMON_TAIL,
    *_DOCUMENT,
    _text("unverified_reason"),
)

DRIVE_FIELDS: tuple[Field, ...] = (
    *_COMMON_HEAD,
    Field("continuous_current", "current", "continuous_current_A", "A"),
    Field("peak_current", "current", "peak_current_A", "A"),
    Field("voltage", "voltage", "voltage_V", "V"),
    Field("rated_power", "power", "rated_power_W", "W"),
    Field("dc_bus_capacitance", "capacitance", "dc_bus_capacitance_F", "uF"),
    Field("braking_resistor", "resistance", "braking_resistor_ohm", "ohm"),
    Field("braking_resistor_power", "power", "braking_resistor_power_W", "W"),
    # the electrical half of sizing (docs/checks.md, "Drive" and "Regeneration")
    Field("peak_time", "time", "peak_time_s", "s"),
    Field("dc_bus_voltage", "voltage", "dc_bus_voltage_V", "V"),
    Field("bus_max_voltage", "voltage", "bus_max_voltage_V", "V"),
    Field("regen_on_voltage", "voltage", "regen_on_voltage_V", "V"),
    Field("absorbable_energy", "energy", "absorbable_energy_J", "J", positive=False),
    Field("builtin_braking_resistor", FLAG, "builtin_braking_resistor"),
    Field("braking_resistor_average_power", "power", "braking_resistor_average_power_W", "W"),
    Field("min_resistance", "resistance", "min_resistance_ohm", "ohm"),
    # the motor series the drive runs (prefixes of the motors' ``series``, space- or comma-separated; empty:
    # not stated, the drive is offered to every motor of its vendor and voltage; docs/checks.md "Drive selection")
    _text("motor_series"),
    # fields computed rather than read (the voltage class from the vendor's model-code rule) and how
    _text("derived"),
    _text("derivation"),
    # where the output currents were read when not in the row's document (data/SOURCES.md "Drives")
    _text("ratings_source"),
    *_COMMON_TAIL,
    *_DOCUMENT,
    *_TRACE,
)

CURVE_FIELDS: tuple[Field, ...] = (
    _text("motor_id"),
    Field("speed", "angular_speed", "speed_rad_s", "rpm", positive=False),
    Field("continuous_torque", "torque", "continuous_torque_Nm", "N*m", positive=False),
    Field("peak_torque", "torque", "peak_torque_Nm", "N*m", positive=False),
    _text("source"),
)


@dataclass(frozen=True)
class TableSpec:
    """A catalog table: its fields, SQL name, kinds (with the default) and required fields per kind."""

    name: str
    sql: str
    fields: tuple[Field, ...]
    kinds: tuple[str, ...]
    required: dict[str, tuple[str, ...]]
    aliases: dict[str, str]

    @property
    def default_kind(self) -> str:
        return self.kinds[0] if self.kinds else ""

    def field(self, name: str) -> Field:
        return next(f for f in self.fields if f.name == name)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f.name for f in self.fields)


MOTOR = TableSpec(
    name="motor",
    sql="motors",
    fields=MOTOR_FIELDS,
    kinds=("ac_servo", "small_dc"),
    required={
        "ac_servo": (
            "id",
            "vendor",
            "rated_torque",
            "peak_torque",
            "rated_speed",
            "max_speed",
            "rotor_inertia",
        ),
        # what MGDB-style data always carries (check_catalog.py's small-motor rules)
        "small_dc": (
            "id",
            "vendor",
            "voltage",
            "torque_constant",
            "winding_resistance",
            "no_load_speed",
            "rotor_inertia",
        ),
    },
    aliases={
        "voltage_class": "voltage",
        "nominal_voltage": "voltage",
        "nominal_torque": "rated_torque",
        "nominal_speed": "rated_speed",
        "nominal_current": "rated_current",
        "terminal_resistance": "winding_resistance",
        "terminal_inductance": "winding_inductance",
        "max_intermittent_torque": "peak_torque",
        "max_intermittent_speed": "max_speed",
        "max_continuous_power": "rated_power",
    },
)

GEARBOX = TableSpec(
    name="gearbox",
    sql="gearboxes",
    fields=GEARBOX_FIELDS,
    kinds=("servo_gearbox", "small_gearhead"),
    required={
        "servo_gearbox": ("id", "vendor", "ratio", "efficiency", "rated_output_torque"),
        "small_gearhead": ("id", "vendor", "ratio", "efficiency", "rated_output_torque", "max_output_torque"),
    },
    aliases={
        "max_continuous_torque": "rated_output_torque",
        "max_intermittent_torque": "max_output_torque",
        "input_inertia": "inertia_input",
    },
)

DRIVE = TableSpec(
    name="drive",
    sql="drives",
    fields=DRIVE_FIELDS,
    kinds=("servo_drive",),
    # a drive documented only by its regen data is kept: its current checks are answered as unknown
    required={"servo_drive": ("id", "vendor")},
    aliases={},
)

CURVE = TableSpec(
    name="curve",
    sql="motor_curves",
    fields=CURVE_FIELDS,
    kinds=(),
    required={"": ("motor_id", "speed")},
    aliases={},
)

TABLES: dict[str, TableSpec] = {t.name: t for t in (MOTOR, GEARBOX, DRIVE, CURVE)}
ROW_TABLES: tuple[TableSpec, ...] = (MOTOR, GEARBOX, DRIVE)
"""Tables whose rows have an id (unique across all of them and across both databases)."""


@dataclass(frozen=True)
class ShippedFile:
    """A data file inside the package and how its rows enter the database."""

    filename: str
    table: TableSpec
    kind: str
    constants: tuple[tuple[str, str], ...] = ()
    derived: tuple[str, ...] = ()
    model_pattern: str = ""  # regex whose first group, applied to the id, is the model name
    unverified: str = ""  # why the file's rows are not traced to a vendor document (rows not marked verified)


_CONFIGURATOR = (
    "values from a third-party configurator's data file (urchacha/gearbox-configurator, data/SOURCES.md), "
    "not read from a vendor document"
)
_MGDB = "values from the MGDB compilation (ekrimsk/MGDB, data/SOURCES.md), not read from a vendor document"

TRACED_MOTOR_FAMILIES: tuple[str, ...] = (
    "teco_jsma", "mitsubishi_hg_kn", "yaskawa_sigma2", "mitsubishi_hc_meldas",
    "rexroth_mhp", "yaskawa_sgm7d",
    "yaskawa_sgmp",
)
"""Servo motor families shipped as ``motors_<vendor>_<family>.csv``, each read from one vendor document."""

TRACED_DRIVE_FAMILIES: tuple[str, ...] = ("beckhoff_ax5000",)
"""Servo drive families shipped as ``drives_<vendor>_<family>.csv`` (the columns of drives_servo.csv),
each read from one vendor document."""

TRACED_GEARBOX_FAMILIES: tuple[str, ...] = ("beckhoff_ag3400ma",)
"""Servo gearbox families shipped as ``gearboxes_<vendor>_<family>.csv`` (the columns of the Beckhoff
files), each read from one vendor document; ids are model-ratio, as the other gearbox files."""

SHIPPED_FILES: tuple[ShippedFile, ...] = (
    # data/SOURCES.md: the id is the vendor's model code
    ShippedFile("motors_ac_servo.csv", MOTOR, "ac_servo", model_pattern=r"^(.*)$", unverified=_CONFIGURATOR),
    # data/SOURCES.md: MGDB stall torque, nominal torque and nominal speed are derived columns
    ShippedFile(
        "motors_small_dc.csv",
        MOTOR,
        "small_dc",
        derived=("stall_torque", "rated_torque", "rated_speed"),
        unverified=_MGDB,
    ),
    # data/SOURCES.md: every row of this file is a precision planetary gearbox
    # ids are model-stage-ratio (GPB042-L1-i3): the model is the id without the ratio
    ShippedFile(
        "gearboxes_planetary.csv",
        GEARBOX,
        "servo_gearbox",
        constants=(("type", "planetary"),),
        model_pattern=r"^(.*)-i[0-9.]+$",
        unverified=_CONFIGURATOR,
    ),
    # data/SOURCES.md: Beckhoff planetary gear units, every row read from Beckhoff's technical-data pages
    *(
        ShippedFile(
            f"gearboxes_{family}.csv",
            GEARBOX,
            "servo_gearbox",
            constants=(("type", "planetary"),),
            model_pattern=r"^(.*)-i[0-9.]+$",
        )
        for family in ("beckhoff_ag2250", "beckhoff_ag2400", "beckhoff_ag3400")
    ),
    # data/SOURCES.md: further servo gearbox families; each file has a `type` column (planetary, ...)
    *(
        ShippedFile(f"gearboxes_{family}.csv", GEARBOX, "servo_gearbox", model_pattern=r"^(.*)-i[0-9.]+$")
        for family in TRACED_GEARBOX_FAMILIES
    ),
    ShippedFile("gearboxes_small.csv", GEARBOX, "small_gearhead", unverified=_MGDB),
    # data/SOURCES.md, "Servo motors read from vendor documents": one file per vendor family, every row
    # read from the vendor table named in its row (traced: verified = yes)
    *(
        ShippedFile(f"motors_{family}.csv", MOTOR, "ac_servo", model_pattern=r"^(.*)$")
        for family in TRACED_MOTOR_FAMILIES
    ),
    ShippedFile("drives.csv", DRIVE, "servo_drive"),
    # data/SOURCES.md, "Drives": every number read from the vendor document named in its row
    ShippedFile("drives_servo.csv", DRIVE, "servo_drive"),
    *(ShippedFile(f"drives_{family}.csv", DRIVE, "servo_drive") for family in TRACED_DRIVE_FAMILIES),
)
ELECTRICAL_FILE = "motors_ac_servo_electrical.csv"
"""Motor electrical data by motor id, merged into the motors rows when the shipped database is built."""
PAIRING_FILE = "drives_pairing.csv"
"""The vendors' motor-drive pairing tables: motor_id, drive_id, source, source_url."""
BRAKES_FILE = "motor_brakes.csv"
"""Holding-brake variants of shipped motors, by id: with-brake inertia (kg*m^2, the with-brake total), holding torque
(N*m), the brake variant's order code and the source; merged into the motor rows when the shipped database is built
(data/SOURCES.md, "Brake variants")."""
ORDER_CODES_FILE = "order_codes.csv"
"""The open positions of shipped order codes (an ``x`` the buyer must choose), by id: position (1-based character
index), what the vendor's key says it means and its options where read, and the source (data/SOURCES.md,
"Order-code positions"). Read by ``side_tables.order_code_positions``, not built into the database."""
REJECTS_FILE = "rejects.csv"
MOTOR_DOCUMENTS_FILE = "motor_documents.csv"
"""Vendor documents of shipped motors, by id: the document, section, page, URL, ``verified`` and the
source of each field group; it fills those fields of the motor rows (data/SOURCES.md)."""
DOCUMENT_FIELDS = (
    "source_document", "source_section", "source_page", "source_url", "verified", "ratings_source",
    "mechanical_source", "electrical_source",
)

FIELD_GROUPS: dict[str, tuple[str, ...]] = {
    "ratings": (
        "rated_power", "rated_torque", "stall_torque", "peak_torque", "rated_speed", "max_speed",
        "max_continuous_speed", "no_load_speed", "rated_output_torque", "max_output_torque",
        "emergency_stop_torque", "efficiency", "max_input_speed", "rated_input_speed", "max_radial_load",
        "max_axial_load", "max_tilting_moment", "continuous_current", "peak_current",
    ),
    "mechanical": (
        "rotor_inertia", "brake", "mass", "flange", "shaft_diameter", "pilot_diameter",
        "bolt_circle", "ratio", "stages", "inertia_input", "backlash", "torsional_stiffness", "noise",
        "input_bore_max", "input_bore_min", "input_flange", "input_pilot", "input_adapters", "direction",
        "right_angle",
    ),
    "electrical": (
        "voltage", "torque_constant", "winding_resistance", "winding_inductance", "rated_current",
        "no_load_current", "rth_winding_housing", "rth_housing_ambient", "dc_bus_capacitance",
        "braking_resistor", "braking_resistor_power",
    ),
    "brake": ("rotor_inertia_brake", "brake_holding_torque", "brake_code"),
}
"""The field groups ``catalog show`` gives a source for (the curve is a fourth, sourced per point)."""

HISTORY_COLUMNS = ("at", "action", "table_name", "id", "source", "old_values", "new_values")
"""The user database's change log: every import, replace, edit and removal of a user row."""


def sql_type(field: Field) -> str:
    if field.quantity == TEXT:
        return "TEXT"
    if field.quantity in (INTEGER, FLAG):
        return "INTEGER"
    return "REAL"


def ddl() -> list[str]:
    """CREATE statements for one database (the shipped one and the user one share them)."""
    statements = ["CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)"]
    for spec in ROW_TABLES:
        cols = ",\n  ".join(
            f"{f.column} {sql_type(f)}"
            + (" PRIMARY KEY" if f.name == "id" else "")
            + (" NOT NULL" if f.name in ("kind", "vendor", "source") else "")
            for f in spec.fields
        )
        kinds = ", ".join(f"'{k}'" for k in spec.kinds)
        statements.append(f"CREATE TABLE {spec.sql} (\n  {cols},\n  CHECK (kind IN ({kinds}))\n)")
    cols = ",\n  ".join(f"{f.column} {sql_type(f)}" for f in CURVE.fields)
    statements.append(f"CREATE TABLE {CURVE.sql} (\n  {cols},\n  PRIMARY KEY (motor_id, speed_rad_s)\n)")
    statements.append(
        "CREATE TABLE drive_pairs (motor_id TEXT, drive_id TEXT, source TEXT, source_url TEXT, verified TEXT)"
    )
    statements.append(f"CREATE TABLE history ({', '.join(c + ' TEXT' for c in HISTORY_COLUMNS)})")
    statements.append(
        "CREATE TABLE rejects (target_file TEXT, id TEXT, vendor TEXT, reason TEXT, source TEXT, source_values TEXT)"
    )
    return statements


_DERIVED_RATINGS = {"rated_torque": "rated torque", "rated_speed": "rated speed"}


def trace(row: dict[str, object]) -> tuple[bool, str]:
    """Whether a row (a database dict keyed by column) is unverified, and why.

    A row is unverified when it is marked ``verified = no`` (its values are not traced to a vendor
    document; ``unverified_reason`` says why) or when a rating it is sized on was derived rather than
    read (``derived`` names rated_torque or rated_speed: e.g. P / omega).
    """
    reasons: list[str] = []
    if row.get("verified") == 0:
        reasons.append(str(row.get("unverified_reason") or "not traced to a vendor document"))
    derived = [d for d in str(row.get("derived") or "").split(",") if d in _DERIVED_RATINGS]
    if derived:
        basis = row.get("rated_torque_basis")
        how = f" ({basis})" if basis and basis != "source" else ""
        reasons.append(" and ".join(_DERIVED_RATINGS[d] for d in derived) + f" derived, not read{how}")
    return bool(reasons), "; ".join(reasons)
