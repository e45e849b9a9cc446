"""The catalog's tables kept on disk (catalog/table_cache.py): a stored table is the built one, field by
field; a changed catalog, a damaged or foreign file builds it again; its arrays can be written without
touching the file."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from drivetrain import catalog
from drivetrain.catalog import db, table_cache
from tests.catalog.folders import fresh_dir

USER_MOTOR = (
    "id,vendor,series,kind,rated_torque [N*m],peak_torque [N*m],rated_speed [rpm],max_speed [rpm],"
    "rotor_inertia [kg*cm^2],voltage [V],flange [mm],source\n"
    "U-400,Userco,U,ac_servo,1.27,4.46,3000,6000,0.486,400,60,bench measurement 2026-03\n"
)


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return db.builtin_db(tmp_path_factory.mktemp("catalog-db"))


@pytest.fixture(autouse=True)
def folders(tmp_path: Path, built: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    fresh_dir(tmp_path / "data", built, monkeypatch)
    monkeypatch.setenv("DRIVETRAIN_CACHE_DIR", str(tmp_path / "cache"))
    catalog._CACHE.clear()  # a new process
    yield tmp_path / "cache" / "catalog"
    catalog._CACHE.clear()


def _fresh(query: str) -> object:
    catalog._CACHE.clear()
    return catalog.gearboxes(kind="servo_gearbox") if query == "gearbox" else catalog.motors(kind="ac_servo")


def _same(a: object, b: object) -> None:
    assert type(a) is type(b)
    for f in dataclasses.fields(a):  # type: ignore[arg-type]
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert isinstance(y, np.ndarray) and x.dtype == y.dtype, f.name
            np.testing.assert_array_equal(x, y, err_msg=f.name)
        else:
            assert x == y, f.name


@pytest.mark.parametrize("query", ["motor", "gearbox"])
def test_a_stored_table_is_the_built_one(folders: Path, query: str) -> None:
    built = _fresh(query)
    assert len(list(folders.glob("table-*.bin"))) == 1
    stored = _fresh(query)
    assert stored is not built
    assert any(isinstance(getattr(stored, f.name), np.ndarray) and getattr(stored, f.name).base is not None
               for f in dataclasses.fields(stored))  # type: ignore[arg-type]  # read from the file
    _same(built, stored)
    rows = [stored.row(i) for i in range(len(stored))]  # type: ignore[attr-defined]
    assert rows == [built.row(i) for i in range(len(built))]  # type: ignore[attr-defined]


def test_an_import_builds_the_table_again(folders: Path, tmp_path: Path) -> None:
    before = _fresh("motor")
    path = tmp_path / "user.csv"
    path.write_text(USER_MOTOR, encoding="utf-8")
    catalog.import_file(path)
    after = _fresh("motor")
    assert len(after) == len(before) + 1 and after.ids[-1] == "U-400"  # type: ignore[attr-defined]
    catalog.update("U-400", {"rated_torque": 1.3})  # same file size, a write transaction
    updated = _fresh("motor")
    assert updated.rated_torque[-1] == pytest.approx(1.3)  # type: ignore[attr-defined]


def test_a_damaged_or_foreign_file_is_built_again(folders: Path) -> None:
    built = _fresh("gearbox")
    (stored,) = folders.glob("table-*.bin")
    for content in (b"", b"not a table", stored.read_bytes()[:200]):
        stored.write_bytes(content)
        _same(built, _fresh("gearbox"))
    assert stored.read_bytes()[: len(table_cache.MAGIC)] == table_cache.MAGIC  # stored again


def test_writing_to_an_array_leaves_the_file(folders: Path) -> None:
    _fresh("motor")
    stored = _fresh("motor")
    stored.rated_torque[0] = -1.0  # type: ignore[attr-defined]
    assert _fresh("motor").rated_torque[0] > 0  # type: ignore[attr-defined]


def test_no_cache_folder_still_answers(folders: Path, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("x")
    monkeypatch.setenv("DRIVETRAIN_CACHE_DIR", str(blocked))  # a file, not a folder: nothing can be stored
    _same(_fresh("motor"), _fresh("motor"))


def test_old_files_are_pruned(folders: Path) -> None:
    for k in range(table_cache.KEEP + 3):
        catalog._CACHE.clear()
        catalog.motors(vendor=None, kind=None, voltage=None, flange=None if k == 0 else f"{40 + 20 * k} mm")
    assert len(list(folders.glob("table-*.bin"))) == table_cache.KEEP
