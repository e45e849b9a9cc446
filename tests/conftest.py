"""Shared test setup: the catalog database and the caches live in temporary folders, never the user's."""

import os
from pathlib import Path

import pytest


@pytest.fixture(autouse=True, scope="session")
def _data_dir(tmp_path_factory: pytest.TempPathFactory) -> None:
    os.environ.pop("DRIVETRAIN_CATALOG", None)  # a shared user catalog of the machine is never touched
    # pytest-xdist's workers inherit COLUMNS=80 and LINES=24: the CLI would fit its tables to them, as on an
    # 80-column terminal; tests see a pipe unless they set COLUMNS themselves (monkeypatch)
    os.environ.pop("COLUMNS", None)
    os.environ.pop("LINES", None)
    if "DRIVETRAIN_TEST_KEEP_DATA_DIR" not in os.environ:
        os.environ["DRIVETRAIN_DATA_DIR"] = str(Path(tmp_path_factory.mktemp("drivetrain-data")))
    # a request's time limit (20 s) is the server's defence against a runaway sizing, not a property the tests
    # check, except those that pass their own: on a machine whose cores are busy a first sizing in a fresh
    # worker process can take longer, and its 503 would fail a test for the load, not for the code
    os.environ["DRIVETRAIN_REQUEST_TIMEOUT"] = "600"
    os.environ["DRIVETRAIN_CACHE_DIR"] = str(Path(tmp_path_factory.mktemp("drivetrain-cache")))


def family_motor_rows() -> int:
    """Rows of the vendor-sourced motor family files (``motors_<vendor>_<family>.csv``), counted from the files.

    The shipped AC servos are the 297 configurator rows plus these; tests that count shipped motors add it.
    """
    import csv
    import io

    from drivetrain.catalog.db import shipped_text
    from drivetrain.catalog.schema import MOTOR, SHIPPED_FILES

    base = ("motors_ac_servo.csv", "motors_small_dc.csv")
    files = [f.filename for f in SHIPPED_FILES if f.table is MOTOR and f.filename not in base]
    return sum(len(list(csv.DictReader(io.StringIO(shipped_text(name))))) for name in files)


def family_drive_rows() -> int:
    """Rows of the vendor-sourced drive family files (``drives_<vendor>_<family>.csv``), counted from the files.

    The shipped drives are the 65 rows of drives_servo.csv plus these; tests that count shipped drives add it.
    """
    import csv
    import io

    from drivetrain.catalog.db import shipped_text
    from drivetrain.catalog.schema import DRIVE, SHIPPED_FILES

    base = ("drives.csv", "drives_servo.csv")
    files = [f.filename for f in SHIPPED_FILES if f.table is DRIVE and f.filename not in base]
    return sum(len(list(csv.DictReader(io.StringIO(shipped_text(name))))) for name in files)


def family_gearbox_rows(vendor_prefix: str = "") -> int:
    """Rows of the servo gearbox family files (``gearboxes_<vendor>_<family>.csv``, schema.TRACED_GEARBOX_FAMILIES),
    counted from the files; ``vendor_prefix`` keeps only the families whose name starts with it ("beckhoff_").

    The shipped servo gearboxes are the 713 G+ and 68 Beckhoff rows plus these; tests that count them add it.
    """
    import csv
    import io

    from drivetrain.catalog.db import shipped_text
    from drivetrain.catalog.schema import TRACED_GEARBOX_FAMILIES

    files = [f"gearboxes_{family}.csv" for family in TRACED_GEARBOX_FAMILIES if family.startswith(vendor_prefix)]
    return sum(len(list(csv.DictReader(io.StringIO(shipped_text(name))))) for name in files)
