"""The web app behind ``drivetrain serve``: a JSON API (FastAPI, described by its OpenAPI schema) and
one page built from plain JS modules in ``static/``.

No physics here: every number comes from ``drivetrain.sizing.result.size``, the catalog and the report.
The API takes the axis as the JSON form of the axis file (``AxisSpec``), so a bad value gets the
CLI's message, naming its field: ``{"detail": "mechanism.load.mass: must be > 0 kg, got -3 kg",
"field": "mechanism.load.mass"}`` with status 422.

Safe by default: the server binds loopback; requests must name a loopback host (no DNS
rebinding) and state-changing requests from another origin are refused; bodies are limited in
size and requests in time; no request path reaches the file system (static files come from the
package, reports and uploads go to temporary files inside the data folder and are removed).
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import re
import tempfile
import threading
import time
from collections.abc import AsyncIterator, Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Annotated, Any, Literal, TypeVar

import anyio
import anyio.to_thread
import numpy as np
from fastapi import FastAPI, File, Form, Query, Request, UploadFile
from fastapi import Path as PathParam
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.utils import get_openapi
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from pydantic import AfterValidator, BaseModel, Field
from starlette.background import BackgroundTask
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from drivetrain import __version__
from drivetrain.errors import InputError, InputErrors
from drivetrain.web.store import ENV_DATA_DIR, StoreError, default_data_dir

log = logging.getLogger("drivetrain.web")

T = TypeVar("T")

MAX_TEXT_BYTES = 1_000_000
"""Largest axis text in a request [characters] (the axis-file limit)."""
MAX_BODY_BYTES = MAX_TEXT_BYTES + 65_536
"""Largest request body [bytes]: an axis file and its JSON wrapping."""
MAX_UPLOAD_BYTES = 5_000_000
"""Largest catalog import [bytes]."""
REQUEST_TIMEOUT_S = 20.0
"""Time limit of one request [s]; a report (PDF through a browser) gets REPORT_TIMEOUT_S."""
REPORT_TIMEOUT_S = 120.0
MAX_PARALLEL_WORK = max(1, min(4, os.cpu_count() or 2))
"""Sizings, reports and imports computed at once (one per core, at most 4): a catalog selection
holds a few hundred MB of arrays while it runs; further requests wait within their time limit."""
ENVELOPE_POINTS = 61
MAX_ENVELOPES = 6
LOOPBACK_HOSTS: tuple[str, ...] = ("127.0.0.1", "localhost", "::1", "[::1]")
STATIC_DIR = Path(__file__).resolve().parent / "static"
_TMP_PREFIX = "web-"
_STALE_TMP_S = 3600.0
_PROJECT_ID = Annotated[int, PathParam(ge=1, le=2**53, description="project id")]
_VERSION = Annotated[int, PathParam(ge=1, le=2**53, description="version number")]
_CATALOG_ID = Annotated[str, PathParam(min_length=1, max_length=200, description="catalog id")]


# ---------------------------------------------------------------------------------- API models


def unicode_text(value: str) -> str:
    """Text that is valid Unicode: a lone surrogate (e.g. from a JSON or YAML escape) is refused."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise ValueError(f"is not valid Unicode text (a lone surrogate at character {exc.start})") from None
    return value


Text = Annotated[str, AfterValidator(unicode_text)]


def check_unicode(data: Any, field: str) -> None:
    """Raise InputError if any key or string in ``data`` is not valid Unicode."""
    stack: list[tuple[Any, str]] = [(data, field)]
    while stack:
        node, path = stack.pop()
        if isinstance(node, str):
            try:
                unicode_text(node)
            except ValueError as exc:
                raise InputError(path, str(exc), has_value=False) from None
        elif isinstance(node, dict):
            for k, v in node.items():
                sub = f"{path}.{k}" if path else str(k)
                stack.append((k, path))
                stack.append((v, sub))
        elif isinstance(node, list):
            stack.extend((v, f"{path}[{i}]") for i, v in enumerate(node))


class ErrorItem(BaseModel):
    field: str | None = Field(description="dotted path of the field at fault, e.g. mechanism.load.mass")
    message: str


class ErrorOut(BaseModel):
    """Every 4xx and 5xx answer: a message, the field at fault (if any), and all errors found."""

    detail: str = Field(description="the message, e.g. 'mechanism.load.mass: must be > 0 kg, got -3 kg'")
    field: str | None = None
    errors: list[ErrorItem] = []


class ProjectOut(BaseModel):
    id: int
    name: str
    created: float = Field(description="seconds since the epoch")
    updated: float = Field(description="seconds since the epoch")
    version: int = Field(description="current version number")


class ProjectDetail(ProjectOut):
    yaml: str = Field(description="the axis as YAML text, as saved")
    axis: dict[str, Any] | None = Field(description="the YAML parsed (null when it does not parse)")
    yaml_error: ErrorOut | None = None


class ProjectCreate(BaseModel):
    name: Text = Field(min_length=1, max_length=200)
    yaml: Text = Field(max_length=MAX_TEXT_BYTES, description="the axis file text")


class ProjectSave(BaseModel):
    yaml: Text = Field(max_length=MAX_TEXT_BYTES, description="the axis file text")
    base_version: int | None = Field(default=None, ge=1, le=2**53,
                                     description="the version this edit started from (refused if stale)")
    note: Text = Field(default="", max_length=200)


class ProjectRename(BaseModel):
    name: Text = Field(min_length=1, max_length=200)


class ProjectDuplicate(BaseModel):
    name: Text | None = Field(default=None, min_length=1, max_length=200)


class VersionOut(BaseModel):
    version: int
    created: float
    restored_from: int | None
    note: str
    bytes: int


class VersionDetail(VersionOut):
    yaml: str


class YamlIn(BaseModel):
    yaml: Text = Field(max_length=MAX_TEXT_BYTES, description="axis file text")


class AxisOut(BaseModel):
    axis: dict[str, Any]
    yaml: str | None = None


class EnvelopeOut(BaseModel):
    name: str
    rank: int | None = None
    speed_rad_s: list[float]
    continuous_Nm: list[float | None]
    peak_Nm: list[float | None]
    approximate: bool


class CandidateOut(BaseModel):
    """One catalog candidate sized as a given motor (and gearbox): its own cycle at its motor shaft."""

    motor: str
    gearbox: str | None
    ratio: float
    series: dict[str, list[float | None]] = Field(description="t_s, omega_motor_rad_s, torque_motor_Nm")
    motor_result: dict[str, Any] = Field(description="/api/size/candidate: the `motor` block of the JSON result "
                                         "for this candidate; /api/size (the selected one): the selection's figures "
                                         "for it (RMS and peak torque, inertia ratio, checks)")
    envelope: EnvelopeOut


class SizeOut(BaseModel):
    result: dict[str, Any] = Field(description="the JSON result of `drivetrain size --json`")
    motion: Literal["linear", "rotary"]
    series: dict[str, list[float | None]] = Field(description="sampled cycle, SI columns")
    envelopes: list[EnvelopeOut] = Field(description="speed-torque envelopes of the motor or candidates")
    selected: CandidateOut | None = Field(default=None, description="the best candidate of a catalog selection")
    notes: list[str] = []
    elapsed_ms: float


class CatalogPage(BaseModel):
    total: int
    offset: int
    limit: int
    items: list[dict[str, Any]]


class FacetsOut(BaseModel):
    motor_vendors: list[str]
    motor_kinds: list[str]
    gearbox_vendors: list[str]
    gearbox_series: list[str]
    gearbox_kinds: list[str]
    motor_voltages: list[float]


class ImportOut(BaseModel):
    table: str
    rows: int
    curve_points: int
    ids: list[str]
    message: str


class HealthOut(BaseModel):
    status: str
    version: str
    report: bool
    catalog: bool


_ERRORS: dict[int | str, dict[str, Any]] = {
    code: {"model": ErrorOut, "description": text}
    for code, text in ((400, "bad request"), (403, "refused: another origin or host"),
                       (404, "not found"), (409, "conflict"), (413, "body too large"),
                       (422, "invalid input, naming the field"), (500, "server error"),
                       (503, "not available or too busy"))
}


_YAML_FILE: dict[int | str, dict[str, Any]] = {
    200: {"description": "an axis file (YAML; a mapping of axis keys)",
          "content": {"application/yaml": {"schema": {"type": "object"}}}},
}

# ---------------------------------------------------------------------------------- helpers


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


def plain(obj: Any) -> Any:
    """JSON-ready copy: numpy scalars and arrays become Python numbers and lists, NaN and inf None."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind == "f" and obj.ndim == 1 and bool(np.all(np.isfinite(obj))):
            return obj.tolist()  # the common case, without a Python call per number
        return plain(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if obj is None or isinstance(obj, str):
        return obj
    return str(obj)


def error_body(err: InputError) -> dict[str, Any]:
    """The JSON of a 422 for an InputError (or several)."""
    errors = err.errors if isinstance(err, InputErrors) else [err]
    items = [{"field": e.field or None, "message": e.message} for e in errors]
    return {"detail": str(err), "field": err.field or None, "errors": items}


def _json_error(status: int, detail: str, field: str | None = None, headers: dict[str, str] | None = None,
                errors: list[dict[str, Any]] | None = None) -> JSONResponse:
    body = {"detail": detail or "error", "field": field,
            "errors": errors if errors is not None else [{"field": field, "message": detail}]}
    return SafeJSONResponse(body, status_code=status, headers=headers)


def safe_filename(name: str, suffix: str) -> str:
    """A download name made of [A-Za-z0-9._-] only, from a user-given axis name."""
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("._")[:80] or "axis"
    return f"{stem}{suffix}"


def _attachment(filename: str) -> dict[str, str]:
    return {"Content-Disposition": f'attachment; filename="{filename}"'}


def _pydantic_field(loc: Sequence[Any]) -> str:
    from drivetrain.fields import format_path

    parts = list(loc)
    if parts and parts[0] in ("body", "query", "path", "header", "cookie"):
        parts = parts[1:]
    clean: list[int | str] = [p if isinstance(p, int) else str(p) for p in parts]
    return format_path(clean)


def _report_module() -> Any | None:
    try:
        import drivetrain.report as report
    except ImportError:
        return None
    return report if hasattr(report, "write_report") else None


def _catalog_available() -> bool:
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


def parse_axis_text(text: str, field: str = "yaml") -> dict[str, Any]:
    """Axis YAML text to a mapping through the CLI's safe loader and limits."""
    from drivetrain.axis.model import parse_yaml

    try:
        data = parse_yaml(text)
    except InputError as exc:
        raise InputError(field, exc.rule, exc.value, has_value=exc.has_value) from None
    if not isinstance(data, dict):
        raise InputError(field, "must be a mapping of axis keys (axis, mechanism, transmission, profile, motor)",
                         type(data).__name__)
    check_unicode(data, field)
    return {str(k): v for k, v in data.items()}


# ---------------------------------------------------------------------------------- sizing


def _engine_errors() -> tuple[type[BaseException], ...]:
    import tokenize

    return (ArithmeticError, tokenize.TokenError)


def engine(fn: Callable[..., T], *args: Any) -> T:
    """Call the engine; an arithmetic failure on input it let through becomes a 422, not a crash.

    A stopgap: the engine should reject such input with a field name (e.g. a diameter so small
    that its radius underflows, or unit text pint cannot tokenize); the server log keeps the
    traceback.
    """
    try:
        return fn(*args)
    except (InputError, ApiError):
        raise
    except _engine_errors() as exc:
        log.warning("the engine failed on input it should have rejected", exc_info=True)
        raise InputError("", f"these values cannot be computed ({type(exc).__name__}: {exc}); a value is "
                         "outside the range the engine handles", has_value=False) from None



def _motor_envelope(name: str, rated: float, peak: float, rated_speed: float, max_speed: float,
                    stall: float | None, curve: Any = None, rank: int | None = None) -> dict[str, Any]:
    return _envelopes([name], np.array([rated]), np.array([peak]), np.array([rated_speed]), np.array([max_speed]),
                      np.array([np.nan if stall is None else stall]), [curve], [rank])[0]


def _envelopes(names: list[str], rated: np.ndarray, peak: np.ndarray, rated_speed: np.ndarray,
               max_speed: np.ndarray, stall: np.ndarray, curves: list[Any],
               ranks: list[int | None]) -> list[dict[str, Any]]:
    """Continuous and peak envelopes of motors for the page, from 0 to each one's max speed (one call)."""
    from drivetrain.sizing.envelope import motor_envelopes

    top = np.where(np.isfinite(max_speed) & (max_speed > 0), max_speed, rated_speed)
    omega = np.linspace(0.0, 1.0, ENVELOPE_POINTS)[None, :] * top[:, None]
    cont, pk = motor_envelopes(rated, peak, rated_speed, max_speed, omega, stall,
                               curves=curves if any(c is not None for c in curves) else None)
    approx = np.asarray(cont.approximate) | np.asarray(pk.approximate)
    approx = np.broadcast_to(approx, (len(names),))
    return [{"name": name, "rank": rank, "speed_rad_s": plain(omega[i]), "continuous_Nm": plain(cont.torque[i]),
             "peak_Nm": plain(pk.torque[i]), "approximate": bool(approx[i])}
            for i, (name, rank) in enumerate(zip(names, ranks, strict=True))]


def _candidate_envelopes(candidates: list[dict[str, Any]], notes: list[str]) -> list[dict[str, Any]]:
    ids: list[str] = []
    for c in candidates:
        mid = c.get("motor_id") or c.get("motor")
        if isinstance(mid, str) and mid not in ids:
            ids.append(mid)
        if len(ids) >= MAX_ENVELOPES:
            break
    if not ids:
        return []
    try:
        from drivetrain import catalog

        table = catalog.motors(ids=ids)
    except (ImportError, InputError) as exc:
        notes.append(f"candidate envelopes unavailable: {exc}")
        return []
    at = {str(mid): i for i, mid in enumerate(table.ids)}
    idx = np.array([at[mid] for mid in ids])
    ranks = [next((k + 1 for k, c in enumerate(candidates) if (c.get("motor_id") or c.get("motor")) == mid), None)
             for mid in ids]
    return _envelopes(ids, table.rated_torque[idx], table.peak_torque[idx], table.rated_speed[idx],
                      table.max_speed[idx], table.stall_torque[idx], [table.curves[i] for i in idx], ranks)


WEB_POINTS_PER_PHASE = 17
"""Samples per profile segment for the page: its plots need far fewer than a report, and RMS
and energy stay exact (Simpson per segment, segment ends always sampled)."""


def candidate_axis(axis: dict[str, Any], motor_id: str, gearbox_id: str | None) -> dict[str, Any]:
    """The axis with a catalog candidate fixed: the motor by id, the gearbox as the first stage.

    Data wiring only: the gearbox's ratio, input inertia and efficiency are copied from its
    catalog row (efficiency 1 where the catalog gives none, as the selection does).
    """
    from drivetrain import catalog

    out = dict(axis)
    given: dict[str, Any] = axis["motor"] if isinstance(axis.get("motor"), dict) else {}
    motor: dict[str, Any] = {"id": motor_id}
    if isinstance(given.get("margins"), dict):
        motor["margins"] = given["margins"]
    out["motor"] = motor
    if gearbox_id:
        try:
            row = catalog.get(gearbox_id)
        except InputError as exc:
            raise InputError("gearbox", exc.rule, exc.value, has_value=exc.has_value) from None
        if row.get("table") != "gearbox":
            raise InputError("gearbox", "is not a gearbox of the catalog", gearbox_id)
        stage: dict[str, Any] = {"type": "gearbox", "ratio": row["ratio"],
                                 "inertia": row.get("inertia_input_kgm2") or 0.0,
                                 "efficiency": row.get("efficiency") or 1.0, "catalog": gearbox_id}
        transmission: list[Any] = axis["transmission"] if isinstance(axis.get("transmission"), list) else []
        out["transmission"] = [stage, *transmission]
    return out


def candidate_payload(axis: dict[str, Any], motor_id: str, gearbox_id: str | None) -> dict[str, Any]:
    """Size the axis with one candidate fixed: its motor-shaft cycle, checks and envelope."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.sizing.result import size

    fixed = candidate_axis(axis, motor_id, gearbox_id)
    try:
        parsed = engine(parse_axis, fixed)
    except InputError as exc:
        if exc.field.startswith("motor.id"):
            raise InputError("motor", exc.rule, exc.value, has_value=exc.has_value) from None
        raise
    result = engine(size, parsed, WEB_POINTS_PER_PHASE)
    cols = result.series()
    series = {k: np.asarray(cols[k], dtype=float) for k in ("t_s", "omega_motor_rad_s", "torque_motor_Nm")
              if k in cols}
    return {"motor": motor_id, "gearbox": gearbox_id, "ratio": float(parsed.transmission[0].ratio) if gearbox_id
            else 1.0, "series": series, "motor_result": result.motor or {},
            "envelope": motor_envelope(motor_id)}


def selected_payload(parsed: Any, result: Any, envelopes: list[dict[str, Any]]) -> dict[str, Any]:
    """The selected candidate of a sizing: its own cycle (the axis's cycle behind its gearbox, as the
    selection checked it), the selection's figures for it and its envelope."""
    from drivetrain.sizing.selection import candidate_cycle

    best = result.selection["selected"]
    cycle, rotor = candidate_cycle(parsed, result.duty, result.selection)
    series = {"t_s": cycle.t, "omega_motor_rad_s": cycle.omega, "torque_motor_Nm": cycle.motor_torque(rotor)}
    figures = {k: best[k] for k in ("rms_torque_Nm", "peak_torque_Nm", "inertia_ratio", "checks")}
    envelope = next((e for e in envelopes if e["name"] == best["motor"]), None) or motor_envelope(best["motor"])
    return {"motor": best["motor"], "gearbox": best["gearbox"], "ratio": best["ratio"], "series": series,
            "motor_result": figures, "envelope": envelope}


def size_payload(axis: dict[str, Any]) -> dict[str, Any]:
    """Size an axis mapping and collect what the page draws: the result, the sampled cycle, envelopes."""
    from drivetrain.axis.model import parse_axis
    from drivetrain.sizing.result import size

    t0 = time.perf_counter()
    parsed = engine(parse_axis, axis)
    result = engine(size, parsed, WEB_POINTS_PER_PHASE)
    notes: list[str] = []
    series = {k: np.asarray(v, dtype=float) for k, v in result.series().items()}
    envelopes: list[dict[str, Any]] = []
    motor = parsed.motor
    if motor is not None:
        envelopes.append(_motor_envelope(motor.name, motor.rated_torque, motor.peak_torque, motor.rated_speed,
                                         motor.max_speed, motor.stall_torque))
    selected = None
    if result.candidates:
        envelopes.extend(_candidate_envelopes(result.candidates, notes))
        if result.selection is not None and "_best" in result.selection:
            selected = selected_payload(parsed, result, envelopes)
    return {"result": result.to_dict(), "motion": parsed.mechanism.motion, "series": series,
            "envelopes": envelopes, "selected": selected, "notes": notes,
            "elapsed_ms": (time.perf_counter() - t0) * 1e3}


def encode(payload: dict[str, Any]) -> bytes:
    """Compact JSON of a sizing payload: numpy arrays and scalars as numbers, NaN and infinity as null.

    orjson writes numpy arrays natively (no Python call per number), which is most of a payload.
    """
    import orjson

    return orjson.dumps(payload, default=_json_default, option=orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS)


def _json_default(obj: Any) -> Any:
    """What orjson does not write itself: strided numpy arrays and other numpy values; anything else as text."""
    if isinstance(obj, (np.ndarray, np.generic)):
        return obj.tolist()
    return str(obj)


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
        if _catalog_available():  # a shared user catalog ($DRIVETRAIN_CATALOG) lives elsewhere
            from drivetrain.catalog.db import user_db_path

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


# ---------------------------------------------------------------------------------- catalog


MotorSort = Literal["id", "vendor", "series", "rated_power", "rated_torque", "peak_torque", "rated_speed",
                    "max_speed", "rotor_inertia", "mass", "flange", "voltage"]
Origin = Literal["all", "builtin", "user"]
GearboxSort = Literal["id", "vendor", "series", "ratio", "stages", "rated_output_torque", "max_output_torque",
                      "efficiency", "max_input_speed", "inertia_input", "backlash", "mass"]


def _order(table: Any, sort: str, descending: bool) -> np.ndarray:
    column = table.ids if sort == "id" else getattr(table, sort)
    values = np.asarray(column)
    if values.dtype.kind == "f":
        key = np.where(np.isnan(values), np.inf, -values if descending else values)
        order: np.ndarray = np.argsort(key, kind="stable")
        return order
    order = np.argsort(np.char.lower(values.astype(str)), kind="stable")
    return order[::-1] if descending else order


def _text_mask(table: Any, q: str | None) -> np.ndarray:
    if not q:
        return np.ones(len(table), dtype=bool)
    needle = q.strip().lower()
    hay = np.char.lower(np.char.add(np.char.add(table.ids.astype(str), " "), table.model.astype(str)))
    hay = np.char.add(np.char.add(hay, " "), np.char.lower(table.series.astype(str)))
    mask: np.ndarray = np.char.find(hay, needle) >= 0
    return mask


def _page(table: Any, mask: np.ndarray, sort: str, order: str, offset: int, limit: int) -> dict[str, Any]:
    sub = table.take(np.flatnonzero(mask))
    idx = _order(sub, sort, order == "desc")
    page = idx[offset:offset + limit]
    items = [plain(sub.row(int(i))) for i in page]
    return {"total": len(sub), "offset": offset, "limit": limit, "items": items}


def _origin_mask(table: Any, origin: str) -> np.ndarray:
    """Rows of the shipped catalog ("builtin"), of yours ("user") or all."""
    mask: np.ndarray = np.ones(len(table), dtype=bool) if origin == "all" else table.origin == origin
    return mask


def motors_page(vendor: str | None, kind: str | None, voltage: str | None, flange: str | None, q: str | None,
                sort: str, order: str, offset: int, limit: int, origin: str = "all") -> dict[str, Any]:
    from drivetrain import catalog

    table = engine(lambda: catalog.motors(vendor=vendor or None, kind=kind or None, voltage=voltage or None,
                                          flange=flange or None))
    return _page(table, _text_mask(table, q) & _origin_mask(table, origin), sort, order, offset, limit)


def gearboxes_page(vendor: str | None, series: str | None, kind: str | None, ratio_min: float | None,
                   ratio_max: float | None, q: str | None, sort: str, order: str, offset: int,
                   limit: int, origin: str = "all") -> dict[str, Any]:
    from drivetrain import catalog

    table = catalog.gearboxes(vendor=vendor or None, series=series or None, kind=kind or None)
    mask = _text_mask(table, q) & _origin_mask(table, origin)
    if ratio_min is not None:
        mask &= table.ratio >= ratio_min
    if ratio_max is not None:
        mask &= table.ratio <= ratio_max
    return _page(table, mask, sort, order, offset, limit)


def facets() -> dict[str, Any]:
    from drivetrain import catalog

    m, g = catalog.motors(), catalog.gearboxes()
    volts = sorted({float(v) for v in m.voltage if math.isfinite(v)})
    return {"motor_vendors": sorted(set(m.vendor.tolist())), "motor_kinds": sorted(set(m.kind.tolist())),
            "gearbox_vendors": sorted(set(g.vendor.tolist())), "gearbox_series": sorted(set(g.series.tolist()) - {""}),
            "gearbox_kinds": sorted(set(g.kind.tolist())), "motor_voltages": volts}


def motor_envelope(motor_id: str) -> dict[str, Any]:
    from drivetrain import catalog

    try:
        table = catalog.motors(ids=[motor_id])
    except InputError as exc:
        raise ApiError(404, str(exc).replace("ids:", "motor_id:", 1), "motor_id") from None
    stall = float(table.stall_torque[0])
    return _motor_envelope(motor_id, float(table.rated_torque[0]), float(table.peak_torque[0]),
                           float(table.rated_speed[0]), float(table.max_speed[0]),
                           stall if math.isfinite(stall) else None, table.curves[0])


# ---------------------------------------------------------------------------------- middleware


class Guard:
    """Pure ASGI middleware: host and origin checks, body size limit, time limit, security headers."""

    HEADERS: tuple[tuple[bytes, bytes], ...] = (
        (b"x-content-type-options", b"nosniff"),
        (b"x-frame-options", b"DENY"),
        (b"referrer-policy", b"no-referrer"),
        (b"cross-origin-resource-policy", b"same-origin"),
        (b"content-security-policy",
         b"default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
         b"connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'; form-action 'self'"),
    )

    def __init__(self, app: ASGIApp, allowed_hosts: Sequence[str] | None, max_body: int, upload_body: int,
                 timeout: float, report_timeout: float) -> None:
        self.app = app
        self.allowed = None if allowed_hosts is None else {h.lower() for h in allowed_hosts}
        self.max_body, self.upload_body = max_body, upload_body
        self.timeout, self.report_timeout = timeout, report_timeout

    @staticmethod
    def _host_of(value: str) -> str:
        value = value.strip().lower()
        if value.startswith("["):
            return value[: value.find("]") + 1] if "]" in value else value
        return value.rsplit(":", 1)[0] if value.count(":") == 1 else value

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        host = self._host_of(headers.get("host", ""))
        if self.allowed is not None and host not in self.allowed:
            await _send_json(send, 403, f"host {host or '(none)'} is not served here; use 127.0.0.1 or localhost",
                             "host")
            return
        origin = headers.get("origin")
        if origin and scope["method"] not in ("GET", "HEAD", "OPTIONS"):
            m = re.match(r"^[a-z][a-z0-9+.-]*://(.+)$", origin.strip().lower())
            same = {host} if self.allowed is None else self.allowed
            if m is None or self._host_of(m.group(1)) not in same:
                await _send_json(send, 403, "requests from another origin are refused", "origin")
                return
        path: str = scope.get("path", "")
        limit = self.upload_body if path.endswith("/import") or path.endswith("/upload") else self.max_body
        length = headers.get("content-length")
        if length is not None:
            if not length.isdigit():
                await _send_json(send, 400, "content-length must be a number", "content-length")
                return
            if int(length) > limit:
                await _send_json(send, 413, f"the request body is too large ({length} bytes; at most {limit})", "body")
                return
        received = 0
        started = False

        async def limited_receive() -> Message:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > limit:
                    raise _BodyTooLarge(limit)
            return message

        async def send_with_headers(message: Message) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                message = dict(message)
                message["headers"] = list(message.get("headers", [])) + list(self.HEADERS)
            await send(message)

        timeout = self.report_timeout if path.startswith("/api/report") else self.timeout
        try:
            with anyio.fail_after(timeout):
                await self.app(scope, limited_receive, send_with_headers)
        except _BodyTooLarge as exc:
            if not started:
                await _send_json(send, 413, f"the request body is too large (at most {exc.limit} bytes)", "body")
        except TimeoutError:
            if not started:
                await _send_json(send, 503, f"the request took longer than {timeout:g} s and was stopped", None,
                                 {"retry-after": "5"})


class _BodyTooLarge(Exception):
    def __init__(self, limit: int) -> None:
        super().__init__(limit)
        self.limit = limit


async def _send_json(send: Send, status: int, detail: str, field: str | None,
                     extra: dict[str, str] | None = None) -> None:
    import json

    body = json.dumps({"detail": detail, "field": field, "errors": [{"field": field, "message": detail}]}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    headers += [(k.encode(), v.encode()) for k, v in (extra or {}).items()]
    headers += list(Guard.HEADERS)
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


# ---------------------------------------------------------------------------------- the app


def create_app(data_dir: Path | None = None, *, allowed_hosts: Sequence[str] | None = LOOPBACK_HOSTS,
               max_body: int = MAX_BODY_BYTES, timeout: float = REQUEST_TIMEOUT_S) -> FastAPI:
    """The FastAPI application.

    ``data_dir`` holds the project database, the user catalog and temporary files (default:
    ``$DRIVETRAIN_DATA_DIR`` or ``~/.local/share/drivetrain``); when given, it is also exported
    as ``$DRIVETRAIN_DATA_DIR`` so the catalog and sizing read the same folder. ``allowed_hosts``
    are the Host names served (None: any, for a deliberate non-loopback bind).
    """
    from drivetrain.web.store import Store

    if data_dir is not None:
        data_dir = Path(data_dir).expanduser().resolve()
        os.environ[ENV_DATA_DIR] = str(data_dir)
    directory = data_dir or default_data_dir()
    store = Store(directory)
    cache = ResultCache(directory)
    tmp_dir = directory / "tmp"
    # Heavy work (sizing, reports, imports) runs on a few long-lived threads: a bounded queue, and
    # the same threads' memory reused rather than a new thread's each time.
    pools: list[ThreadPoolExecutor] = []
    pools_lock = threading.Lock()

    def work_pool() -> ThreadPoolExecutor:
        with pools_lock:
            if not pools:
                pools.append(ThreadPoolExecutor(max_workers=MAX_PARALLEL_WORK, thread_name_prefix="drivetrain-work"))
            return pools[0]

    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        yield
        with pools_lock:  # a later request (a test client restarting the app) makes a new pool
            while pools:
                pools.pop().shutdown(wait=False, cancel_futures=True)

    app = FastAPI(title="drivetrain", version=__version__, responses=_ERRORS, default_response_class=SafeJSONResponse,
                  lifespan=lifespan,
                  description="Size servo axes: the JSON API of `drivetrain serve`. The axis is the JSON form of "
                              "the axis file (docs/axis-file.md); quantities are numbers in SI or text with units.")
    app.state.store = store
    app.state.data_dir = directory
    app.add_middleware(Guard, allowed_hosts=allowed_hosts, max_body=max_body, upload_body=MAX_UPLOAD_BYTES,
                       timeout=timeout, report_timeout=REPORT_TIMEOUT_S)

    async def blocking(fn: Callable[..., T], *args: Any) -> T:
        """Run ``fn`` on the work pool; a request that times out drops its job if it has not started."""
        import asyncio

        future = work_pool().submit(fn, *args)
        try:
            return await asyncio.wrap_future(future)
        except BaseException:
            future.cancel()
            raise

    async def light(fn: Callable[..., T], *args: Any) -> T:
        return await anyio.to_thread.run_sync(fn, *args, abandon_on_cancel=True)

    def temp_path(suffix: str) -> Path:
        tmp_dir.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=_TMP_PREFIX, suffix=suffix, dir=tmp_dir)
        os.close(fd)
        return Path(name)

    def clean_stale() -> None:
        if not tmp_dir.is_dir():
            return
        now = time.time()
        for p in tmp_dir.glob(f"{_TMP_PREFIX}*"):
            try:
                if now - p.stat().st_mtime > _STALE_TMP_S:
                    p.unlink()
            except OSError:
                pass

    clean_stale()

    # ------------------------------------------------------------------ errors

    @app.exception_handler(InputError)
    async def _input_error(request: Request, exc: InputError) -> JSONResponse:
        return SafeJSONResponse(error_body(exc), status_code=422)

    @app.exception_handler(StoreError)
    async def _store_error(request: Request, exc: StoreError) -> JSONResponse:
        detail = f"{exc.field}: {exc.message}" if exc.field and exc.status in (400, 422) else exc.message
        return _json_error(422 if exc.status == 400 else exc.status, detail, exc.field)

    @app.exception_handler(ApiError)
    async def _api_error(request: Request, exc: ApiError) -> JSONResponse:
        return _json_error(exc.status, exc.detail, exc.field)

    @app.exception_handler(RequestValidationError)
    async def _validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
        from drivetrain.errors import format_value

        items: list[dict[str, Any]] = []
        for err in exc.errors():
            field = _pydantic_field(err.get("loc", ()))
            msg = str(err.get("msg", "invalid")).removeprefix("Value error, ")
            if err.get("type") == "missing":
                msg = "is required"
            elif "input" in err and err.get("type") not in ("json_invalid",):
                value = err["input"]
                shown = format_value(value) if isinstance(value, (str, int, float, bool)) else type(value).__name__
                msg = f"{msg}, got {shown}"
            items.append({"field": field or None, "message": f"{field}: {msg}" if field else msg})
        detail = "\n".join(str(i["message"]) for i in items) or "invalid request"
        return _json_error(422, detail, items[0]["field"] if items else None, errors=items)

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        detail = exc.detail if isinstance(exc.detail, str) and exc.detail else "error"
        headers = dict(exc.headers or {})
        if exc.status_code == 405:
            headers["Allow"] = ", ".join(allowed_methods(app, request.url.path))
            detail = f"method {request.method} is not allowed here; use {headers['Allow']}"
        return _json_error(exc.status_code, detail, None, headers=headers)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error in %s %s", request.method, request.url.path)
        return _json_error(500, f"internal error ({type(exc).__name__}); the server log has the details")

    # ------------------------------------------------------------------ page and static files

    @app.get("/", include_in_schema=False)
    async def index() -> FileResponse:
        return FileResponse(STATIC_DIR / "index.html", media_type="text/html; charset=utf-8",
                            headers={"Cache-Control": "no-cache"})

    @app.get("/static/vendor/plotly.min.js", include_in_schema=False)
    async def plotly_js() -> FileResponse:
        import plotly

        path = Path(plotly.__file__).resolve().parent / "package_data" / "plotly.min.js"
        if not path.is_file():
            raise ApiError(503, "plotly.js is not available in the installed plotly package")
        return FileResponse(path, media_type="text/javascript", headers={"Cache-Control": "max-age=86400"})

    app.mount("/static", StaticFiles(directory=STATIC_DIR, follow_symlink=False), name="static")

    # ------------------------------------------------------------------ meta

    @app.get("/api/health", response_model=HealthOut, tags=["meta"])
    async def health() -> dict[str, Any]:
        """Liveness, version, and whether the report and catalog are installed."""
        return {"status": "ok", "version": __version__, "report": _report_module() is not None,
                "catalog": _catalog_available()}

    @app.get("/api/form", tags=["meta"])
    async def form() -> dict[str, Any]:
        """The axis editor's description: every field of every mechanism and transmission type, with units."""
        from drivetrain.web.schema import form_description

        return form_description()

    @app.get("/api/schema/axis", tags=["meta"])
    async def axis_schema() -> dict[str, Any]:
        """JSON schema of the axis file (quantities: a number in SI or text with units)."""
        from drivetrain.web.schema import axis_json_schema

        return axis_json_schema()

    @app.get("/api/examples", tags=["meta"])
    async def examples() -> list[str]:
        """Names of the example axes (one per mechanism)."""
        return sorted(_examples())

    @app.get("/api/examples/{name}", response_model=AxisOut, tags=["meta"])
    async def example(name: Annotated[str, PathParam(max_length=64)]) -> dict[str, Any]:
        """One example axis as YAML text and parsed."""
        found = _examples().get(name)
        if found is None:
            raise ApiError(404, f"name: no example called {name!r}; known: {', '.join(sorted(_examples()))}", "name")
        text = found.read_text(encoding="utf-8")
        return {"axis": parse_axis_text(text), "yaml": text}

    # ------------------------------------------------------------------ sizing and axis files

    @app.post("/api/size", response_model=SizeOut, tags=["sizing"],
              openapi_extra={"requestBody": _axis_body("the axis to size")})
    async def size_axis(request: Request) -> Response:
        """Size an axis (the JSON form of the axis file): the result, the sampled cycle and envelopes."""
        axis = await _axis_from(request)
        key = cache.key("size", axis)
        body = cache.get(key)
        if body is None:
            body = await blocking(lambda: encode(size_payload(axis)))
            cache.put(key, body)
        return Response(body, media_type="application/json")

    @app.post("/api/size/candidate", response_model=CandidateOut, tags=["sizing"],
              openapi_extra={"requestBody": _axis_body("the axis; its motor section is replaced by the candidate")})
    async def size_candidate(
        request: Request,
        motor: Annotated[str, Query(min_length=1, max_length=200, description="catalog motor id")],
        gearbox: Annotated[str | None, Query(max_length=200, description="catalog gearbox id (none: direct)")] = None,
    ) -> Response:
        """Size the axis with one catalog candidate fixed (to compare candidates in the speed-torque plane)."""
        need_catalog()
        axis = await _axis_from(request)
        key = cache.key("candidate", axis, motor, gearbox)
        body = cache.get(key)
        if body is None:
            body = await blocking(lambda: encode(candidate_payload(axis, motor, gearbox or None)))
            cache.put(key, body)
        return Response(body, media_type="application/json")

    @app.post("/api/yaml/parse", response_model=AxisOut, tags=["axis file"])
    async def yaml_parse(body: YamlIn) -> dict[str, Any]:
        """Axis YAML text to its JSON form (safe loader, same limits as the CLI)."""
        return {"axis": await light(parse_axis_text, body.yaml), "yaml": None}

    @app.post("/api/yaml/dump", tags=["axis file"], response_class=Response, responses=_YAML_FILE,
              openapi_extra={"requestBody": _axis_body("the axis to write as YAML", complete=False)})
    async def yaml_dump(request: Request) -> Response:
        """The axis as a YAML file to download."""
        axis = await _axis_from(request)
        name = axis.get("axis") if isinstance(axis.get("axis"), str) else "axis"
        return Response(dump_yaml(axis), media_type="application/yaml; charset=utf-8",
                        headers=_attachment(safe_filename(str(name), ".yaml")))

    @app.post("/api/yaml/upload", response_model=AxisOut, tags=["axis file"])
    async def yaml_upload(file: Annotated[UploadFile, File(description="an axis YAML file")]) -> dict[str, Any]:
        """Read an uploaded axis file (safe loader, same limits as the CLI)."""
        from drivetrain.axis.model import MAX_FILE_BYTES

        data = await file.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            raise InputError("file", f"is too large (an axis file is at most {MAX_FILE_BYTES} bytes)",
                             has_value=False)
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError("file", f"is not UTF-8 text (byte {exc.start})", has_value=False) from None
        return {"axis": await light(parse_axis_text, text, "file"), "yaml": text}

    @app.post("/api/report", tags=["sizing"], response_class=Response,
              responses={200: {"content": {"text/html": {"schema": {"type": "string"}},
                                           "application/pdf": {"schema": {"type": "string", "format": "binary"}}}}},
              openapi_extra={"requestBody": _axis_body("the axis to report on")})
    async def report(request: Request, format: Literal["html", "pdf"] = "html",
                     units: Literal["si", "imperial", "as-given"] = "si") -> Response:
        """The HTML or PDF report of the axis's sizing, as a download."""
        module = _report_module()
        if module is None:
            raise ApiError(503, "the report is not available in this installation (drivetrain.report is missing)")
        axis = await _axis_from(request)
        suffix = f".{format}"
        path = temp_path(suffix)

        def write() -> None:
            from drivetrain.sizing.result import size

            module.write_report(engine(size, axis), str(path), units=units)

        try:
            await blocking(write)
        except BaseException:
            path.unlink(missing_ok=True)
            raise
        name = axis.get("axis") if isinstance(axis.get("axis"), str) else "axis"
        media = "text/html; charset=utf-8" if format == "html" else "application/pdf"
        return FileResponse(path, media_type=media, filename=safe_filename(str(name), f"-report{suffix}"),
                            background=BackgroundTask(path.unlink, missing_ok=True))

    # ------------------------------------------------------------------ projects

    def detail(info: Any, text: str, axis: dict[str, Any] | None = None) -> dict[str, Any]:
        out = info.to_dict()
        out["yaml"] = text
        if axis is not None:
            out["axis"], out["yaml_error"] = axis, None
            return out
        try:
            out["axis"], out["yaml_error"] = parse_axis_text(text), None
        except InputError as exc:
            out["axis"], out["yaml_error"] = None, error_body(exc)
        return out

    @app.get("/api/projects", response_model=list[ProjectOut], tags=["projects"])
    async def list_projects() -> list[dict[str, Any]]:
        """Every project, most recently saved first."""
        return [p.to_dict() for p in await light(store.projects)]

    @app.post("/api/projects", response_model=ProjectDetail, status_code=201, tags=["projects"])
    async def create_project(body: ProjectCreate) -> dict[str, Any]:
        """A new project (version 1). The text must be YAML; it may still fail sizing (a draft)."""
        axis = await light(parse_axis_text, body.yaml)
        info = await light(store.create, body.name, body.yaml)
        return detail(info, body.yaml, axis)

    @app.get("/api/projects/{project_id}", response_model=ProjectDetail, tags=["projects"])
    async def get_project(project_id: _PROJECT_ID) -> dict[str, Any]:
        """A project with its current text."""
        info, head = await light(store.head, project_id)
        return detail(info, head.text)

    @app.put("/api/projects/{project_id}", response_model=ProjectDetail, tags=["projects"])
    async def save_project(project_id: _PROJECT_ID, body: ProjectSave) -> dict[str, Any]:
        """Save the text as the next version (one transaction; refused if base_version is stale)."""
        axis = await light(parse_axis_text, body.yaml)
        info = await light(store.save, project_id, body.yaml, body.base_version, body.note)
        return detail(info, body.yaml, axis)

    @app.patch("/api/projects/{project_id}", response_model=ProjectOut, tags=["projects"])
    async def rename_project(project_id: _PROJECT_ID, body: ProjectRename) -> dict[str, Any]:
        """Rename a project."""
        return (await light(store.rename, project_id, body.name)).to_dict()

    @app.delete("/api/projects/{project_id}", status_code=204, response_class=Response, tags=["projects"])
    async def delete_project(project_id: _PROJECT_ID) -> Response:
        """Delete a project and its history."""
        await light(store.delete, project_id)
        return Response(status_code=204)

    @app.post("/api/projects/{project_id}/duplicate", response_model=ProjectOut, status_code=201, tags=["projects"])
    async def duplicate_project(project_id: _PROJECT_ID, body: ProjectDuplicate) -> dict[str, Any]:
        """A copy of the project's current version as a new project."""
        return (await light(store.duplicate, project_id, body.name)).to_dict()

    @app.get("/api/projects/{project_id}/versions", response_model=list[VersionOut], tags=["projects"])
    async def list_versions(project_id: _PROJECT_ID) -> list[dict[str, Any]]:
        """The project's saved versions, newest first."""
        return [v.info() for v in await light(store.versions, project_id)]

    @app.get("/api/projects/{project_id}/versions/{version}", response_model=VersionDetail, tags=["projects"])
    async def get_version(project_id: _PROJECT_ID, version: _VERSION) -> dict[str, Any]:
        """One saved version with its text."""
        v = await light(store.version, project_id, version)
        return {**v.info(), "yaml": v.text}

    @app.post("/api/projects/{project_id}/versions/{version}/restore", response_model=ProjectDetail,
              tags=["projects"])
    async def restore_version(project_id: _PROJECT_ID, version: _VERSION) -> dict[str, Any]:
        """Save an earlier version again as the newest one."""
        info = await light(store.restore, project_id, version)
        _, head = await light(store.head, project_id)
        return detail(info, head.text)

    @app.post("/api/projects/{project_id}/undo", response_model=ProjectDetail, tags=["projects"])
    async def undo_project(project_id: _PROJECT_ID) -> dict[str, Any]:
        """Undo the last save: the version before it becomes the newest (409 when there is none)."""
        info = await light(store.undo, project_id)
        _, head = await light(store.head, project_id)
        return detail(info, head.text)

    @app.get("/api/projects/{project_id}/yaml", tags=["projects"], response_class=Response, responses=_YAML_FILE)
    async def project_yaml(project_id: _PROJECT_ID) -> Response:
        """The project's current axis file, as a download."""
        info, head = await light(store.head, project_id)
        return Response(head.text, media_type="application/yaml; charset=utf-8",
                        headers=_attachment(safe_filename(info.name, ".yaml")))

    # ------------------------------------------------------------------ catalog

    def need_catalog() -> None:
        if not _catalog_available():
            raise ApiError(503, "the catalog is not available in this installation (drivetrain.catalog is missing)")

    @app.get("/api/catalog/facets", response_model=FacetsOut, tags=["catalog"])
    async def catalog_facets() -> dict[str, Any]:
        """Vendors, kinds, series and voltages present, for the filters."""
        need_catalog()
        return await blocking(facets)

    @app.get("/api/catalog/motors", response_model=CatalogPage, tags=["catalog"])
    async def catalog_motors(
        vendor: Annotated[str | None, Query(max_length=100)] = None,
        kind: Annotated[str | None, Query(max_length=40)] = None,
        voltage: Annotated[str | None, Query(max_length=40, description="e.g. 400 V")] = None,
        flange: Annotated[str | None, Query(max_length=40, description="e.g. 80 mm")] = None,
        q: Annotated[str | None, Query(max_length=100, description="text in the id, model or series")] = None,
        sort: MotorSort = "rated_torque",
        order: Literal["asc", "desc"] = "asc",
        offset: Annotated[int, Query(ge=0, le=1_000_000)] = 0,
        limit: Annotated[int, Query(ge=1, le=500)] = 50,
        origin: Annotated[Origin, Query(description="shipped rows (builtin), yours (user) or all")] = "all",
    ) -> dict[str, Any]:
        """Motors of the shipped and user catalogs (SI, units in the keys), filtered and sorted."""
        need_catalog()
        return await blocking(motors_page, vendor, kind, voltage, flange, q, sort, order, offset, limit, origin)

    @app.get("/api/catalog/gearboxes", response_model=CatalogPage, tags=["catalog"])
    async def catalog_gearboxes(
        vendor: Annotated[str | None, Query(max_length=100)] = None,
        series: Annotated[str | None, Query(max_length=100)] = None,
        kind: Annotated[str | None, Query(max_length=40)] = None,
        ratio_min: Annotated[float | None, Query(ge=0, le=1e6)] = None,
        ratio_max: Annotated[float | None, Query(ge=0, le=1e6)] = None,
        q: Annotated[str | None, Query(max_length=100)] = None,
        sort: GearboxSort = "ratio",
        order: Literal["asc", "desc"] = "asc",
        offset: Annotated[int, Query(ge=0, le=1_000_000)] = 0,
        limit: Annotated[int, Query(ge=1, le=500)] = 50,
        origin: Annotated[Origin, Query(description="shipped rows (builtin), yours (user) or all")] = "all",
    ) -> dict[str, Any]:
        """Gearboxes (one row per model and ratio), filtered and sorted."""
        need_catalog()
        return await blocking(gearboxes_page, vendor, series, kind, ratio_min, ratio_max, q, sort, order, offset,
                              limit, origin)

    @app.get("/api/catalog/items/{item_id}", tags=["catalog"])
    async def catalog_item(item_id: _CATALOG_ID) -> dict[str, Any]:
        """One motor, gearbox or drive with its source and notes."""
        need_catalog()
        from drivetrain import catalog

        try:
            record: dict[str, Any] = plain(await blocking(catalog.get, item_id))
        except InputError as exc:
            raise ApiError(404, str(exc).replace("id:", "item_id:", 1), "item_id") from None
        return record

    @app.get("/api/catalog/motors/{motor_id}/envelope", response_model=EnvelopeOut, tags=["catalog"])
    async def catalog_envelope(motor_id: _CATALOG_ID) -> dict[str, Any]:
        """A motor's continuous and peak speed-torque envelope (from its curve, or derived from ratings)."""
        need_catalog()
        return await blocking(motor_envelope, motor_id)

    @app.post("/api/catalog/import", response_model=ImportOut, tags=["catalog"])
    async def catalog_import(
        file: Annotated[UploadFile, File(description="a CSV or JSON file of motors, gearboxes, drives or curves")],
        kind: Annotated[Literal["motor", "gearbox", "drive", "curve"] | None, Form()] = None,
        replace: Annotated[bool, Form(description="update rows of your catalog with the same id")] = False,
    ) -> dict[str, Any]:
        """Import your own catalog rows: all rows are checked first; every bad cell is reported (422).

        Rows that name no source record the uploaded file's name and the time of the upload (UTC)."""
        need_catalog()
        from drivetrain import catalog

        shown = safe_filename(Path(file.filename or "upload.csv").stem, "")
        suffix = Path(file.filename or "").suffix.lower()
        if suffix not in (".csv", ".json"):
            suffix = ".csv"
        data = await file.read(MAX_UPLOAD_BYTES + 1)
        if len(data) > MAX_UPLOAD_BYTES:
            raise InputError("file", f"is too large (at most {MAX_UPLOAD_BYTES} bytes)", has_value=False)
        path = temp_path(suffix)
        try:
            path.write_bytes(data)
            try:
                uploaded = f"uploaded file {shown + suffix} at {_utc_now()}"
                rep = await blocking(lambda: catalog.import_file(path, kind, directory=directory, replace=replace,
                                                                 source=uploaded))
            except InputError as exc:
                raise _rename_import_error(exc, str(path), shown + suffix) from None
        finally:
            path.unlink(missing_ok=True)
        message = str(rep).replace(str(path), shown + suffix)
        return {"table": rep.table, "rows": rep.rows, "curve_points": rep.curve_points, "ids": list(rep.ids),
                "message": message}

    @app.delete("/api/catalog/items/{item_id}", tags=["catalog"])
    async def catalog_remove(item_id: _CATALOG_ID) -> dict[str, Any]:
        """Remove one row of your catalog (a motor with its curve points); shipped rows cannot be removed."""
        need_catalog()
        from drivetrain.catalog import manage

        count = await blocking(lambda: manage.remove([item_id], directory=directory, source="web catalog"))
        return {"removed": count, "id": item_id, "message": f"removed {item_id} from your catalog"}

    @app.patch("/api/catalog/items/{item_id}", tags=["catalog"])
    async def catalog_edit(item_id: _CATALOG_ID, request: Request) -> dict[str, Any]:
        """Change fields of one row of your catalog: a JSON object of field (or ``name [unit]``) to value;
        null clears a field. The row is validated as an import is; the answer is the row as stored."""
        need_catalog()
        import json

        from drivetrain.catalog import manage

        try:
            changes = json.loads(await request.body() or b"null")
        except ValueError:
            raise InputError("body", "must be a JSON object of field: value", has_value=False) from None
        if not isinstance(changes, dict):
            raise InputError("body", "must be a JSON object of field: value", has_value=False)
        record: dict[str, Any] = plain(await blocking(
            lambda: manage.update(item_id, changes, directory=directory, source="web catalog edit")))
        return record

    @app.get("/api/catalog/history", tags=["catalog"])
    async def catalog_history(
        item_id: Annotated[str | None, Query(alias="id", max_length=200, description="only this id")] = None,
    ) -> dict[str, Any]:
        """The changes to your catalog, oldest first: imports, replacements, edits and removals."""
        need_catalog()
        from drivetrain.catalog import manage

        entries = await blocking(lambda: manage.history(item_id, directory=directory))
        return {"entries": plain(entries)}

    # ------------------------------------------------------------------ OpenAPI with the axis schema

    def openapi() -> dict[str, Any]:
        if app.openapi_schema:
            return app.openapi_schema
        from drivetrain.web.schema import openapi_components

        schema = get_openapi(title=app.title, version=app.version, description=app.description, routes=app.routes)
        axis, defs = openapi_components()
        components = schema.setdefault("components", {}).setdefault("schemas", {})
        components.update(defs)
        components["AxisSpec"] = axis
        app.openapi_schema = schema
        return schema

    app.openapi = openapi  # type: ignore[method-assign]
    return app


def allowed_methods(app: FastAPI, path: str) -> list[str]:
    """Every method some route serves at ``path`` (routes are per method; Starlette names only one)."""
    from starlette.routing import Route

    methods: set[str] = set()
    for route in app.routes:
        if isinstance(route, Route) and route.path_regex.match(path) and route.methods:
            methods |= set(route.methods)
    return sorted(methods)


def _utc_now() -> str:
    import datetime as dt

    return dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC")


def _rename_import_error(exc: InputError, tmp: str, shown: str) -> InputError:
    errors = exc.errors if isinstance(exc, InputErrors) else [exc]
    renamed = [InputError(e.field.replace(tmp, shown), e.rule.replace(tmp, shown), e.value, has_value=e.has_value)
               for e in errors]
    return renamed[0] if len(renamed) == 1 else InputErrors(renamed)


def _axis_body(description: str, complete: bool = True) -> dict[str, Any]:
    schema = ({"$ref": "#/components/schemas/AxisSpec"} if complete else
              {"type": "object", "description": "the axis as a JSON object; a draft need not be complete"})
    return {"required": True, "description": description, "content": {"application/json": {"schema": schema}}}


async def _axis_from(request: Request) -> dict[str, Any]:
    """The request's JSON body as an axis mapping (422 naming the problem otherwise)."""
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
    return data


def _examples() -> dict[str, Path]:
    """Example axes shipped next to the package in a source checkout (examples/*.yaml)."""
    import drivetrain

    root = Path(drivetrain.__file__).resolve().parents[2] / "examples"
    if not root.is_dir():
        return {}
    return {p.stem: p for p in sorted(root.glob("*.yaml")) if p.is_file()}

