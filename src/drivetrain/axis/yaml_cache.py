"""The data of YAML files read before, remembered on disk by their text, so that a run on a file it has
read before neither imports the YAML library nor parses the file again (about 15 ms of a ``drivetrain
size``).

``model.read_yaml`` asks here first with the file's text. An entry is keyed by a hash of the text, of
``model.py`` (the limits and the loader) and of this module, and by the installed PyYAML (its path and
modification time): it holds the exact data the safe loader gave for that text (pickled: the same
types, shared values and all), or nothing: a text the loader refused is never stored, so its error is
raised by the loader each time. An entry that cannot be read is ignored; one that cannot be written
leaves the run as it was. Only files are remembered (not the texts the web app parses); the newest
``KEEP`` entries are kept. The folder is ``unit_cache.cache_dir()``/yaml.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import pickle
from pathlib import Path
from typing import Any

from drivetrain.files import atomic_target

KEEP = 64
"""Entries kept (the newest); older ones are removed when one is added."""

_salt: bytes | None = None


def _key(text: str) -> str | None:
    """The entry name of ``text``, or None when PyYAML is not installed as a file."""
    global _salt
    if _salt is None:
        spec = importlib.util.find_spec("yaml")
        if spec is None or spec.origin is None:
            return None
        here = Path(__file__)
        digest = hashlib.sha256()
        for path in (here, here.with_name("model.py")):
            digest.update(path.read_bytes())
        digest.update(f"{spec.origin}|{os.stat(spec.origin).st_mtime_ns}".encode())
        _salt = digest.digest()
    return hashlib.sha256(_salt + text.encode("utf-8", "surrogatepass")).hexdigest()[:32]


def _folder() -> Path:
    from drivetrain.unit_cache import cache_dir

    return cache_dir() / "yaml"


def get(text: str) -> tuple[bool, Any]:
    """(True, the data) remembered for ``text``, else (False, None)."""
    try:
        key = _key(text)
        if key is None:
            return False, None
        raw = (_folder() / f"{key}.pickle").read_bytes()
        stored_key, data = pickle.loads(raw)
    except Exception:  # absent, damaged or foreign: parse the text
        return False, None
    return (True, data) if stored_key == key else (False, None)


def put(text: str, data: Any) -> None:
    """Remember ``data`` as what the safe loader gives for ``text`` (atomically; best effort)."""
    try:
        key = _key(text)
        if key is None:
            return
        folder = _folder()
        with (atomic_target(folder / f"{key}.pickle", durable=False, prefix=".yaml-", suffix=".pickle") as tmp,
              open(tmp, "wb") as fh):
            pickle.dump((key, data), fh, protocol=pickle.HIGHEST_PROTOCOL)
        entries = sorted(folder.glob("*.pickle"), key=lambda p: p.stat().st_mtime_ns, reverse=True)
        for old in entries[KEEP:]:
            old.unlink(missing_ok=True)
    except (OSError, pickle.PicklingError, RecursionError, ValueError):
        pass
