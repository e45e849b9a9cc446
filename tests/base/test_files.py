"""Every file drivetrain writes is written whole or not at all (drivetrain.files)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from drivetrain.errors import InputError
from drivetrain.files import USER_FILE_MODE, atomic_target, write_atomic


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_text("old")

    def fail(tmp: Path) -> None:
        tmp.write_text("half")
        raise RuntimeError("renderer failed")

    with pytest.raises(RuntimeError):
        write_atomic(target, fail, "--csv")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_a_users_file_gets_the_permissions_of_a_new_file(tmp_path: Path) -> None:
    target = write_atomic(tmp_path / "sub" / "r.txt", lambda tmp: tmp.write_text("x"), "--report")
    assert target.read_text() == "x"
    assert target.stat().st_mode & 0o777 == USER_FILE_MODE & ~_umask()


def test_a_cache_entry_keeps_its_prefix_and_stays_private(tmp_path: Path) -> None:
    seen: list[str] = []
    with atomic_target(tmp_path / "k.pickle", durable=False, prefix=".yaml-", suffix=".pickle") as tmp:
        seen.append(tmp.name)
        tmp.write_bytes(b"1")
    assert seen[0].startswith(".yaml-") and seen[0].endswith(".pickle")
    assert (tmp_path / "k.pickle").stat().st_mode & 0o777 == 0o600


def test_a_file_system_error_names_the_field_or_reaches_the_caller(tmp_path: Path) -> None:
    blocker = tmp_path / "plain-file"
    blocker.write_text("")
    with pytest.raises(InputError, match=r"--aas: cannot be written: .* is a file, not a directory"):
        write_atomic(blocker / "a.json", lambda tmp: tmp.write_text("{}"), "--aas")
    with pytest.raises(OSError):  # a cache gets the error itself, and ignores it
        write_atomic(blocker / "a.json", lambda tmp: tmp.write_text("{}"), durable=False, prefix=".c-")


def test_a_directory_in_the_way_is_refused_before_writing(tmp_path: Path) -> None:
    called: list[Path] = []
    with pytest.raises(InputError, match="--csv: is a directory"):
        write_atomic(tmp_path, called.append, "--csv")
    assert not called
