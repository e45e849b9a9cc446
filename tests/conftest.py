"""Shared test setup: the catalog database and the caches live in temporary folders, never the user's."""

import os
from pathlib import Path

import pytest


@pytest.fixture(autouse=True, scope="session")
def _data_dir(tmp_path_factory: pytest.TempPathFactory) -> None:
    os.environ.pop("DRIVETRAIN_CATALOG", None)  # a shared user catalog of the machine is never touched
    if "DRIVETRAIN_TEST_KEEP_DATA_DIR" not in os.environ:
        os.environ["DRIVETRAIN_DATA_DIR"] = str(Path(tmp_path_factory.mktemp("drivetrain-data")))
    os.environ["DRIVETRAIN_CACHE_DIR"] = str(Path(tmp_path_factory.mktemp("drivetrain-cache")))
