"""SI factors of units, remembered on disk between runs, so a run that reads only known units never
builds pint's registry (building it costs more than a whole sizing).

``units._unit_factor`` asks here first and records what pint answers. The file is keyed by the
bytes of ``units.py`` and by pint's installed copy (path and modification time): a change to
either starts a new file, so a remembered factor is always the one pint would give now. A file
that cannot be read, or holds anything but pairs of finite floats, is ignored; one that cannot
be written leaves the run as it was (pint answers, as without the cache).

The folder is ``$DRIVETRAIN_CACHE_DIR``, else the platform's user cache folder.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import math
import os
import sys
import threading
from pathlib import Path

from drivetrain.files import write_atomic

ENV_CACHE_DIR = "DRIVETRAIN_CACHE_DIR"

_factors: dict[str, tuple[float, float]] | None = None
_path: Path | None = None
_lock = threading.Lock()  # the web app parses in threads


def cache_dir() -> Path:
    """The folder for caches: $DRIVETRAIN_CACHE_DIR, else the platform's user cache folder."""
    env = os.environ.get(ENV_CACHE_DIR)
    if env:
        return Path(env).expanduser()
    home = Path.home()
    if sys.platform == "win32":
        return Path(os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local") / "drivetrain" / "Cache"
    if sys.platform == "darwin":
        return home / "Library" / "Caches" / "drivetrain"
    return Path(os.environ.get("XDG_CACHE_HOME") or home / ".cache") / "drivetrain"


def _file() -> Path | None:
    """This installation's file, or None when pint is not installed."""
    global _path
    if _path is None:
        spec = importlib.util.find_spec("pint")
        if spec is None or spec.origin is None:
            return None
        digest = hashlib.sha256()
        digest.update(Path(__file__).with_name("units.py").read_bytes())
        digest.update(spec.origin.encode())
        digest.update(str(os.stat(spec.origin).st_mtime_ns).encode())
        _path = cache_dir() / f"units-{digest.hexdigest()[:16]}.json"
    return _path


def _key(unit: str, quantity: str) -> str:
    return f"{quantity}|{unit}"


def _load() -> dict[str, tuple[float, float]]:
    global _factors
    if _factors is None:
        _factors = {}
        path = _file()
        try:
            raw = json.loads(path.read_text(encoding="utf-8")) if path is not None else {}
        except (OSError, ValueError):
            raw = {}
        if isinstance(raw, dict):
            for key, pair in raw.items():
                if (isinstance(key, str) and isinstance(pair, list) and len(pair) == 2
                        and all(isinstance(v, float) and math.isfinite(v) for v in pair)):
                    _factors[key] = (pair[0], pair[1])
    return _factors


def get(unit: str, quantity: str) -> tuple[float, float] | None:
    """The remembered (SI value of 1 ``unit``, SI value of 0 ``unit``), or None."""
    return _load().get(_key(unit, quantity))


def put(unit: str, quantity: str, factors: tuple[float, float]) -> None:
    """Remember ``factors`` of ``unit`` read as ``quantity`` (written at once, atomically)."""
    if not all(math.isfinite(v) for v in factors):
        return
    with _lock:
        table = _load()
        table[_key(unit, quantity)] = (float(factors[0]), float(factors[1]))
        content = json.dumps({k: list(v) for k, v in table.items()})
        path = _file()
        if path is None:
            return
        with contextlib.suppress(OSError):
            write_atomic(path, lambda tmp: tmp.write_text(content, encoding="utf-8"), durable=False,
                         prefix=".units-", suffix=".json")
