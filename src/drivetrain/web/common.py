"""What every route module shares: error answers, the axis body of a request, YAML in and out,
the cache of encoded sizings, and ``Context`` (the store, the data folder and the work pools of
one app, handed to each module's ``register``).
"""

from __future__ import annotations

import re
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, TypeVar

from fastapi import Request
from fastapi.responses import JSONResponse

from drivetrain.errors import InputError, InputErrors
from drivetrain.motion.profiles import MAX_PROFILE_STEPS
from drivetrain.web.models import check_unicode
from drivetrain.web.store import Store

T = TypeVar("T")


class Runner(Protocol):
    """Runs a blocking call off the event loop and awaits its result."""

    async def __call__(self, fn: Callable[..., T], *args: Any) -> T: ...


@dataclass(frozen=True)
class Context:
    """One app's state the routes need: its project store, sizing cache, data folder and runners.

    ``isolated`` runs a sizing in one of the app's worker processes (``drivetrain.web.workers``),
    which the request's time limit stops: its function and arguments must pickle;
    ``blocking`` runs other heavy work (reports, imports) on the app's bounded work pool;
    ``light`` runs quick file and database calls on AnyIO's threads; ``temp_path`` makes a
    temporary file inside the data folder (the caller removes it); ``size_payload`` is the
    sizing behind ``/api/size`` (``drivetrain.web.payload.size_payload``, as ``create_app``
    finds it in ``drivetrain.web.app`` when the app is built); ``machine_payload`` the one
    behind ``/api/machine/size`` (``routes_machine.machine_size_payload``, found the same way).
    """

    store: Store
    cache: ResultCache
    directory: Path
    blocking: Runner
    light: Runner
    isolated: Runner
    temp_path: Callable[[str], Path]
    size_payload: Callable[[dict[str, Any]], dict[str, Any]]
    machine_payload: Callable[..., dict[str, Any]]


class SafeJSONResponse(JSONResponse):
    """JSON with non-ASCII escaped: any text (even a lone surrogate echoed in a message) can be sent."""

    def render(self, content: Any) -> bytes:
        import json

        return json.dumps(content, ensure_ascii=True, allow_nan=False, separators=(",", ":")).encode("ascii")


class ApiError(Exception):
    """An error answer with a status, a message and the field at fault."""

    def __init__(self, status: int, detail: str, field: str | None = None) -> None:
        super().__init__(detail)
        self.status, self.detail, self.field = status, detail, field



MAX_ERROR_ITEMS = 20
"""Errors listed in one error answer; the rest are counted in a last item (a catalog import of a
header with tens of thousands of unknown columns would otherwise answer tens of MB)."""
MAX_MESSAGE_CHARS = 1000
"""Characters of one error message (or field name) in an answer; the rest are cut and counted."""


def clip(text: str, limit: int = MAX_MESSAGE_CHARS) -> str:
    """``text`` cut to at most ``limit`` characters, ending in how many were left out."""
    if len(text) <= limit:
        return text
    keep = limit - 40  # room for the note
    return f"{text[:keep]}... ({len(text) - keep} more characters)"


def _counted(err: InputError) -> int:
    """The number of errors a count item of ``bounded`` stands for (0: ``err`` is not one)."""
    m = re.fullmatch(r"and (\d+) more errors \(the first \d+ are listed\)", err.rule) if not err.field else None
    return int(m.group(1)) if m else 0


def bounded(err: InputError) -> InputError:
    """``err`` with at most MAX_ERROR_ITEMS errors (the first ones, then one counting the rest), each
    field and rule cut to MAX_MESSAGE_CHARS; the same object when it is within both bounds. Bounding
    again (a worker bounds what it sends, the answer what it lists) keeps the count."""
    errors = err.errors if isinstance(err, InputErrors) else [err]
    more = _counted(errors[-1]) if len(errors) > 1 else 0
    if more:
        errors = errors[:-1]
    if len(errors) <= MAX_ERROR_ITEMS and all(len(e.field) <= MAX_MESSAGE_CHARS and len(e.rule) <= MAX_MESSAGE_CHARS
                                              for e in errors):
        return err
    kept = [InputError(clip(e.field), clip(e.rule), e.value, has_value=e.has_value) for e in errors[:MAX_ERROR_ITEMS]]
    more += len(errors) - len(kept)
    if more:
        kept.append(InputError("", f"and {more} more errors (the first {len(kept)} are listed)", has_value=False))
    return kept[0] if len(kept) == 1 else InputErrors(kept)


def error_body(err: InputError) -> dict[str, Any]:
    """The JSON of a 422 for an InputError (or several), bounded (``bounded``)."""
    err = bounded(err)
    errors = err.errors if isinstance(err, InputErrors) else [err]
    items = [{"field": e.field or None, "message": e.message} for e in errors]
    return {"detail": "\n".join(str(i["message"]) for i in items), "field": err.field or None, "errors": items}


def json_error(status: int, detail: str, field: str | None = None, headers: dict[str, str] | None = None,
                errors: list[dict[str, Any]] | None = None) -> JSONResponse:
    """An error answer: ``detail`` and each listed error's message cut to MAX_MESSAGE_CHARS, at most
    MAX_ERROR_ITEMS errors listed (then one counting the rest)."""
    detail = clip(detail or "error")
    field = None if field is None else clip(field)
    listed = errors if errors is not None else [{"field": field, "message": detail}]
    items = [{**e, "message": clip(str(e.get("message", "")))} for e in listed[:MAX_ERROR_ITEMS]]
    if len(listed) > MAX_ERROR_ITEMS:
        items.append({"field": None, "message": f"and {len(listed) - MAX_ERROR_ITEMS} more errors (the first "
                                                f"{MAX_ERROR_ITEMS} are listed)"})
    body = {"detail": detail, "field": field, "errors": items}
    return SafeJSONResponse(body, status_code=status, headers=headers)


def safe_filename(name: str, suffix: str) -> str:
    """A download name made of [A-Za-z0-9._-] only, from a user-given axis name."""
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("._")[:80] or "axis"
    return f"{stem}{suffix}"


def attachment(filename: str) -> dict[str, str]:
    return {"Content-Disposition": f'attachment; filename="{filename}"'}


def report_module() -> Any | None:
    try:
        import drivetrain.report as report
    except ImportError:
        return None
    return report if hasattr(report, "write_report") else None


def catalog_available() -> bool:
    try:
        import drivetrain.catalog  # noqa: F401
    except ImportError:
        return False
    return True


def dump_yaml(axis: dict[str, Any]) -> str:
    """The axis as YAML text in the axis file's key order, short mappings on one line."""
    import yaml

    class _Dumper(yaml.SafeDumper):
        pass

    def represent_dict(dumper: yaml.SafeDumper, data: dict[str, Any]) -> yaml.Node:
        flat = all(not isinstance(v, (dict, list)) for v in data.values())
        return dumper.represent_mapping("tag:yaml.org,2002:map", data.items(), flow_style=flat and len(data) <= 8)

    _Dumper.add_representer(dict, represent_dict)
    text: str = yaml.dump(axis, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=110,
                          default_flow_style=False)
    return text


def _yaml_mapping(text: str, field: str, keys: str) -> dict[str, Any]:
    """YAML text to a mapping through the CLI's safe loader and limits; ``keys`` names what it should hold."""
    from drivetrain.axis.yaml_text import parse_yaml

    try:
        data = parse_yaml(text)
    except InputError as exc:
        raise InputError(field, exc.rule, exc.value, has_value=exc.has_value) from None
    if not isinstance(data, dict):
        raise InputError(field, f"must be a mapping of {keys}", type(data).__name__)
    check_unicode(data, field)
    return {str(k): v for k, v in data.items()}


def parse_axis_text(text: str, field: str = "yaml") -> dict[str, Any]:
    """Axis YAML text to a mapping through the CLI's safe loader and limits."""
    return _yaml_mapping(text, field, "axis keys (axis, mechanism, transmission, profile, motor)")


def parse_machine_text(text: str, field: str = "yaml") -> dict[str, Any]:
    """Machine YAML text to a mapping through the CLI's safe loader and limits (its keys checked when sized)."""
    return _yaml_mapping(text, field, "machine keys (version, machine, cycle_time, supply, axes, buses)")


def parse_text(kind: str, text: str, field: str = "yaml") -> dict[str, Any]:
    """The web's one parse of YAML text from a request (an axis or a machine file): the CLI's parser
    with its bounds (``drivetrain.axis.yaml_text.parse_yaml``). Routes run it in a worker process
    (``Context.isolated``), so a parse that runs past the request's time limit is killed with it."""
    return parse_machine_text(text, field) if kind == "machine" else parse_axis_text(text, field)


class ResultCache:
    """The last sizings, keyed by the axis and the catalog files' state (an import invalidates them).

    Sizing is a pure function of the axis and the catalog, and the page re-sends the same axis
    often (undo, switching back a value, comparing candidates), so the encoded answers are kept.
    """

    def __init__(self, directory: Path, size: int = 64) -> None:
        from collections import OrderedDict

        self.directory, self.size = directory, size
        self.data: OrderedDict[str, bytes] = OrderedDict()
        self.lock = threading.Lock()

    def key(self, kind: str, axis: dict[str, Any], *extra: Any) -> str:
        import hashlib
        import json

        stamp = []
        paths = [self.directory / n for n in ("catalog.sqlite", "user.sqlite", "user.sqlite-wal")]
        try:  # a shared user catalog ($DRIVETRAIN_CATALOG) lives elsewhere
            from drivetrain.catalog.db import user_db_path
        except ImportError:
            pass
        else:
            paths.append(user_db_path(self.directory))
        for path in paths:
            try:
                st = path.stat()
                stamp.append((str(path), st.st_mtime_ns, st.st_size))
            except OSError:
                stamp.append((str(path), 0, 0))
        text = json.dumps([kind, axis, extra, stamp], sort_keys=True, separators=(",", ":"), default=str)
        return hashlib.sha256(text.encode()).hexdigest()

    def get(self, key: str) -> bytes | None:
        with self.lock:
            value = self.data.get(key)
            if value is not None:
                self.data.move_to_end(key)
            return value

    def put(self, key: str, value: bytes) -> None:
        with self.lock:
            self.data[key] = value
            self.data.move_to_end(key)
            while len(self.data) > self.size:
                self.data.popitem(last=False)



def axis_body(description: str, complete: bool = True) -> dict[str, Any]:
    schema = ({"$ref": "#/components/schemas/AxisSpec"} if complete else
              {"type": "object", "description": "the axis as a JSON object; a draft need not be complete"})
    return {"required": True, "description": description, "content": {"application/json": {"schema": schema}}}


async def axis_from(request: Request) -> dict[str, Any]:
    """The request's JSON body as an axis mapping (422 naming the problem otherwise).

    A profile longer than the axis file allows is refused here, before any work is queued.
    """
    import json

    raw = await request.body()
    if not raw.strip():
        raise InputError("body", "must be the axis as a JSON object (axis, mechanism, transmission, profile, motor)",
                         has_value=False)
    try:
        data = json.loads(raw)
    except (ValueError, RecursionError) as exc:
        raise InputError("body", f"is not valid JSON ({str(exc)[:120]})", has_value=False) from None
    if not isinstance(data, dict):
        raise InputError("body", "must be a JSON object with the axis keys (axis, mechanism, transmission, profile, "
                         "motor)", type(data).__name__)
    check_unicode(data, "")
    profile = data.get("profile")
    if isinstance(profile, list) and len(profile) > MAX_PROFILE_STEPS:
        raise InputError("profile", f"has {len(profile)} moves and dwells; at most {MAX_PROFILE_STEPS} are accepted "
                         "(a cycle that long is better split into the axis's typical cycles)", has_value=False)
    return data



def need_catalog() -> None:
    """Refuse (503) when this installation has no catalog."""
    if not catalog_available():
        raise ApiError(503, "the catalog is not available in this installation (drivetrain.catalog is missing)")
