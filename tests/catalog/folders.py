"""A test's own catalog data folder: the shipped database built once per module, copied for each test."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from drivetrain.catalog import db


def fresh_dir(base: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """``base`` made the catalog's data folder (``$DRIVETRAIN_DATA_DIR``) with a copy of the shipped
    database ``built`` (``db.builtin_db``) in it, so a test may change it freely."""
    base.mkdir(parents=True)
    shutil.copy(built, base / db.BUILTIN_NAME)
    monkeypatch.setenv(db.ENV_DATA_DIR, str(base))
    return base
