"""The sizing report: one self-contained HTML file or a PDF, and the notebook view of a result.

    from drivetrain import size
    from drivetrain.report import write_report
    result = size("examples/ball_screw.yaml")
    write_report(result, "z_lift.html")                    # interactive, works offline
    write_report(result, "z_lift.pdf", units="imperial")   # A4 pages

Contents: title block and verdict; key figures and every check with its margin; the axis as a
diagram with ratios, efficiencies and inertias; the load's motion profile; the motor shaft's
speed and torque with the phases shaded, RMS and peak; the speed-torque plane with the motor's
envelopes; tables of reflected inertia, per-move torques, candidates and ratios; the inputs as
given and in SI; the formulas used with their sources; versions of software and catalog data.

Units follow ``units``: ``si`` (N·m, rpm, kg·cm², mm), ``imperial`` (lbf·in, rpm, lb·in², in)
or ``as-given`` (the units the axis file used, SI otherwise). Files are written atomically: a
temporary sibling is renamed over the target only once complete. plotly and matplotlib are
imported on first use, so ``import drivetrain`` stays fast.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from drivetrain.errors import InputError

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

__all__ = ["REPORT_SUFFIXES", "check_target", "render_html", "render_pdf", "repr_html", "write_atomic", "write_report"]

REPORT_SUFFIXES: dict[str, str] = {".html": "html", ".htm": "html", ".pdf": "pdf"}
"""File suffixes ``write_report`` understands, and the format each writes."""


def _check_units(units: str) -> str:
    from drivetrain.units import UNIT_CHOICES

    if units not in UNIT_CHOICES:
        raise InputError("--units", f"must be one of {', '.join(UNIT_CHOICES)}", units)
    return units


STALE_TEMP_AGE_S = 3600.0
"""A temporary sibling of a target older than this [s] whose writer is gone is removed."""


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


def _os_error(exc: OSError, field: str, path: Path) -> InputError:
    import errno

    why = {errno.ENOSPC: "the disk is full", errno.EDQUOT: "the disk quota is exceeded",
           errno.EFBIG: "the file-size limit is exceeded", errno.EACCES: "permission denied",
           errno.EPERM: "permission denied", errno.EROFS: "the file system is read-only",
           errno.EISDIR: "it is a directory", errno.ENOTDIR: "a parent is not a directory"}.get(
        exc.errno or 0, exc.strerror or type(exc).__name__)
    return InputError(field, f"cannot be written ({why})", str(path))


@contextlib.contextmanager
def _atomic_target(path: Path, field: str = "--report") -> Iterator[Path]:
    """A temporary file next to ``path``; renamed over it when the block succeeds, removed if not.

    The temporary name is unique and carries the writer's process id, so stale ones (left by a
    killed writer) are recognised and removed by the next write to the same target. Errors of the
    file system (read-only, full disk, file-size limit, a directory in the way) are ``InputError``
    naming ``field``.
    """
    import tempfile

    check_target(path, field)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale(path)
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=".tmp", dir=path.parent)
        os.close(fd)
    except OSError as exc:
        raise _os_error(exc, field, path) from None
    tmp = Path(name)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise _os_error(exc, field, path) from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


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


def write_atomic(path: str | os.PathLike[str], write: Callable[[Path], None], field: str) -> Path:
    """Write a file through ``write(temporary sibling)`` and rename it over ``path``; see ``_atomic_target``."""
    target = Path(path)
    with _atomic_target(target, field) as tmp:
        write(tmp)
    return target


def _write_atomic(path: Path, write: Callable[[Path], None]) -> Path:
    return write_atomic(path, write, "--report")


def render_html(result: SizingResult, units: str = "si") -> str:
    """The report as one HTML document (plotly.js embedded, no network needed)."""
    from drivetrain.report.html import render_html as _render

    return _render(result, _check_units(units))


def repr_html(result: SizingResult, units: str = "si") -> str:
    """The report as an HTML fragment for Jupyter: same content, static SVG plots, no script."""
    from drivetrain.report.html import repr_html as _repr

    return _repr(result, _check_units(units))


def render_pdf(result: SizingResult, path: str | os.PathLike[str], units: str = "si") -> Path:
    """Write the report as a PDF (A4) to ``path``, atomically; returns the path."""
    from drivetrain.report.model import build_report
    from drivetrain.report.pdf import write_pdf

    model = build_report(result, _check_units(units))
    target = Path(path)
    return _write_atomic(target, lambda tmp: write_pdf(model, tmp))


def write_report(result: SizingResult, path: str | os.PathLike[str], units: str = "si") -> Path:
    """Write an HTML (``.html``) or PDF (``.pdf``) report of ``result`` to ``path``; returns the path.

    Raises ``InputError`` for another suffix or an unknown ``units``. An existing file at
    ``path`` is replaced only by a complete report; if rendering fails it is left untouched.
    """
    target = Path(path)
    kind = REPORT_SUFFIXES.get(target.suffix.lower())
    if kind is None:
        raise InputError("--report", "must end in .html or .pdf", str(path))
    _check_units(units)
    check_target(target, "--report")
    if kind == "pdf":
        return render_pdf(result, target, units)
    data = render_html(result, units).encode("utf-8")

    def write(tmp: Path) -> None:
        tmp.write_bytes(data)

    return _write_atomic(target, write)
