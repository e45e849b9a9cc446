"""Files written whole or not at all: every file drivetrain writes goes through ``atomic_target``.

A file is written to a unique temporary sibling and renamed over the target only once complete, so a
reader never sees half of it and an existing file is replaced only by a whole new one. A user's file
(a report, a CSV, an export: ``durable=True``) is flushed to disk before the rename and gets the
permissions of an ordinary new file; a cache entry (``durable=False``) is not flushed, as it can
always be made again. With ``field`` a file-system error (read-only, full disk, file-size limit, a
directory in the way) becomes an ``InputError`` naming that field; without, the ``OSError`` goes to
the caller (a cache ignores it).

``tempfile`` is imported only when writing: its imports cost 3-5 ms of every start.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterator
from pathlib import Path

from drivetrain.errors import InputError

__all__ = ["STALE_TEMP_AGE_S", "atomic_target", "check_target", "os_error", "write_atomic"]

STALE_TEMP_AGE_S = 3600.0
"""A temporary sibling of a target older than this [s] whose writer is gone is removed."""

USER_FILE_MODE = 0o644
"""Permissions of a user's file before the umask (a temporary file is created private, 0o600)."""


def check_target(path: str | os.PathLike[str], field: str) -> Path:
    """``path`` as a Path if a file can be written there, else ``InputError`` naming ``field``.

    Checked before the work that produces the file: the target must not be a directory, and no
    existing ancestor may be a file. Permission and space problems show when writing.
    """
    target = Path(path)
    if str(path) == "" or target.name in ("", ".", ".."):
        raise InputError(field, "must name a file", str(path))
    if target.is_dir():
        raise InputError(field, "is a directory; give a file name", str(path))
    parent = target.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if parent.exists() and not parent.is_dir():
        raise InputError(field, f"cannot be written: {parent} is a file, not a directory", str(path))
    return target


def os_error(exc: OSError, field: str, path: Path) -> InputError:
    """The ``InputError`` naming ``field`` for a file-system error while writing ``path``, in words."""
    import errno

    why = {errno.ENOSPC: "the disk is full", errno.EDQUOT: "the disk quota is exceeded",
           errno.EFBIG: "the file-size limit is exceeded", errno.EACCES: "permission denied",
           errno.EPERM: "permission denied", errno.EROFS: "the file system is read-only",
           errno.EISDIR: "it is a directory", errno.ENOTDIR: "a parent is not a directory"}.get(
        exc.errno or 0, exc.strerror or type(exc).__name__)
    return InputError(field, f"cannot be written ({why})", str(path))


@contextlib.contextmanager
def atomic_target(path: str | os.PathLike[str], *, field: str | None = None, durable: bool = True,
                  prefix: str | None = None, suffix: str = ".tmp") -> Iterator[Path]:
    """A new empty temporary file next to ``path``; renamed over it when the block succeeds, removed if not.

    Without ``prefix`` the temporary name is ``.NAME.PID.XXXXXXXX.tmp``: it carries the writer's process
    id, so stale ones (left by a killed writer) are recognised and removed by the next write to the
    same target. A cache passes its own ``prefix`` (and prunes its folder itself). ``durable``: fsync
    before the rename and the permissions of a new file (``USER_FILE_MODE`` less the umask).
    ``field``: file-system errors become ``InputError`` naming it (and the target is checked first).
    """
    import tempfile

    target = Path(path)
    if field is not None:
        check_target(target, field)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        if prefix is None:
            _remove_stale(target)
        fd, name = tempfile.mkstemp(prefix=prefix if prefix is not None else f".{target.name}.{os.getpid()}.",
                                    suffix=suffix, dir=target.parent)
        os.close(fd)
    except OSError as exc:
        if field is None:
            raise
        raise os_error(exc, field, target) from None
    tmp = Path(name)
    try:
        yield tmp
        if durable:
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
            os.chmod(tmp, USER_FILE_MODE & ~_umask())
        os.replace(tmp, target)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if field is None:
            raise
        raise os_error(exc, field, target) from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_atomic(path: str | os.PathLike[str], write: Callable[[Path], object], field: str | None = None, *,
                 durable: bool = True, prefix: str | None = None, suffix: str = ".tmp") -> Path:
    """Write a file through ``write(temporary sibling)`` and rename it over ``path``; see ``atomic_target``."""
    target = Path(path)
    with atomic_target(target, field=field, durable=durable, prefix=prefix, suffix=suffix) as tmp:
        write(tmp)
    return target


def _remove_stale(path: Path) -> None:
    """Remove temporary siblings of ``path`` whose writer process no longer runs."""
    import glob
    import re
    import time

    pattern = re.compile(rf"\.{re.escape(path.name)}\.(?:(\d+)\.)?[A-Za-z0-9_]+\.tmp")
    now = time.time()
    for sibling in path.parent.glob(f".{glob.escape(path.name)}.*.tmp"):
        m = pattern.fullmatch(sibling.name)
        if m is None:
            continue
        with contextlib.suppress(OSError):
            pid = int(m.group(1)) if m.group(1) is not None else None
            writer_gone = pid is not None and pid != os.getpid() and not _alive(pid)
            if writer_gone or now - sibling.stat().st_mtime > STALE_TEMP_AGE_S:
                sibling.unlink()


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True  # another user's process (or not a pid): leave its file alone
    return True


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
