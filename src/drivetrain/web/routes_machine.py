"""The machine routes: size a machine (its axes inline or naming saved axis projects) over its DC buses,
its report (HTML or PDF) and AAS submodel as downloads, the machine file's YAML, the shipped examples.

A machine posted here is the machine file as JSON (docs/machine.md) with one addition for the web
app: an axis may name a saved axis project, ``{project: 12}`` (its current version) or
``{project: 12, project_version: 3}``, instead of ``axis:``; the server puts that project's axis
inline before the machine package reads the file. ``include:`` is refused (a request must not
name files on the server). No sizing of its own: ``drivetrain.machine`` computes every figure.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

from fastapi import FastAPI, Query, Request
from fastapi import Path as PathParam
from fastapi.responses import FileResponse, Response
from starlette.background import BackgroundTask

from drivetrain.errors import InputError
from drivetrain.web.common import (
    ApiError,
    Context,
    attachment,
    check_unicode,
    dump_yaml,
    parse_axis_text,
    parse_text,
    safe_filename,
)
from drivetrain.web.models import YamlIn
from drivetrain.web.payload import electrical_payload, encode, engine
from drivetrain.web.store import NotFound, Store
from drivetrain.web.workers import encoded

if TYPE_CHECKING:
    from drivetrain.machine.result import MachineResult

MAX_WEB_AXES = 8
"""Axes of a machine the web app sizes in one request (each is a full sizing)."""
PROJECT_KEYS = ("project", "project_version")
_SAMPLES = Annotated[int, Query(ge=1, le=2000, description="random-phasing samples for free axes")]
_SEED = Annotated[int, Query(ge=0, le=2**32 - 1, description="seed of the random phasing")]
_BODY = {"requestBody": {"required": True, "description": "the machine file as JSON, its axes inline or naming saved "
                         "axis projects ({project: ID}) (docs/machine.md)",
                         "content": {"application/json": {"schema": {"type": "object"}}}}}


async def machine_from(request: Request) -> dict[str, Any]:
    """The request's JSON body as a machine mapping (422 naming the problem otherwise)."""
    raw = await request.body()
    try:
        data = json.loads(raw) if raw.strip() else None
    except (ValueError, RecursionError) as exc:
        raise InputError("body", f"is not valid JSON ({str(exc)[:120]})", has_value=False) from None
    if not isinstance(data, dict):
        raise InputError("body", "must be the machine file as a JSON object (version, machine, cycle_time, supply, "
                         "axes, buses)", type(data).__name__ if data is not None else None)
    check_unicode(data, "")
    return data


def _project_id(value: Any, field: str, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 2**53:
        raise InputError(field, f"must be the {what} (a whole number >= 1)", value)
    return value


def resolve_projects(data: dict[str, Any], store: Store) -> tuple[dict[str, Any], dict[int, dict[str, Any]]]:
    """The machine with every ``axes[k].project`` replaced by that saved axis project's axis, inline.

    Returns the new mapping and, per axis index, the project it came from (id, name, version)."""
    axes = data.get("axes")
    if not isinstance(axes, list) or not any(isinstance(a, dict) and "project" in a for a in axes):
        return data, {}
    if len(axes) > MAX_WEB_AXES:  # refuse before reading any project
        raise InputError("axes", f"has more than {MAX_WEB_AXES} axes", len(axes))
    links: dict[int, dict[str, Any]] = {}
    out: list[Any] = []
    for k, a in enumerate(axes):
        if not isinstance(a, dict) or not any(key in a for key in PROJECT_KEYS):
            out.append(a)
            continue
        where = f"axes[{k}].project"
        if "project" not in a:
            raise InputError(f"axes[{k}].project_version", "applies only with project:", a["project_version"])
        pid = _project_id(a["project"], where, "id of a saved axis project")
        if "axis" in a or "include" in a:
            raise InputError(where, "give one of project: (a saved axis project) or axis: (the axis inline)", pid)
        try:
            if "project_version" in a:
                version = _project_id(a["project_version"], f"axes[{k}].project_version", "version of the project")
                info = store.info(pid)
                text = store.version(pid, version).text
            else:
                info, head = store.head(pid)
                version, text = info.version, head.text
        except NotFound as exc:
            field = f"axes[{k}].project_version" if exc.field == "version" else where
            raise InputError(field, f"names no saved project version ({exc.message})", a.get("project_version", pid)
                             if exc.field == "version" else pid) from None
        if info.kind != "axis":
            raise InputError(where, f"names {info.name!r}, a {info.kind} project; an axis project is needed", pid)
        axis = parse_axis_text(text, where)
        out.append({**{key: v for key, v in a.items() if key not in PROJECT_KEYS}, "axis": axis})
        links[k] = {"project": pid, "name": info.name, "version": version}
    return {**data, "axes": out}, links


def axis_rows(result: MachineResult) -> list[dict[str, Any]]:
    """The machine table: one row per motor (a gantry has several) with its motor, drive, gearbox (from the
    order-sheet rows, as the machine's bill of materials: ``machine.result.axis_bom_rows``; a row without an
    order code by its name, status and open points), smallest margin (and its check), pass and its ``status``
    (pass, pass with unknowns, fail), and the axis page's ``electrical`` block (drive, currents, regen)."""
    from drivetrain.machine.result import axis_bom_rows

    rows: list[dict[str, Any]] = []
    for ma in result.machine.axes:
        ap = result.axes[ma.name]
        for k, res in enumerate(ap.results):
            parts = axis_bom_rows(ma.name, [res])  # the order-sheet rows, as the machine BOM lists them
            d = res.to_dict()
            checks = [c for block in (d.get("motor"), d.get("drive"), (d.get("selection") or {}).get("selected"))
                      if isinstance(block, dict) for c in block.get("checks", []) if c.get("margin") is not None]
            worst = min(checks, key=lambda c: c["margin"]) if checks else None

            def part(kind: str, items: list[dict[str, Any]] = parts) -> str | None:
                names = [str(i["order_code"] or i.get("note") or "") for i in items if i["kind"] == kind]
                return "; ".join(n for n in names if n) or None

            failed = (d.get("motor") or {}).get("failed") or ""
            rows.append({"axis": ma.name, "motor_index": k + 1, "motors": ma.motors, "share": ma.shares[k],
                         "motor": part("motor"), "drive": part("drive"), "gearbox": part("gearbox"),
                         "min_margin": None if worst is None else worst["margin"],
                         "limit": None if worst is None else worst["name"], "ok": bool(res.ok),
                         "status": res.status, "failed": failed or None, "electrical": electrical_payload(res)})
    return rows


def machine_payload(result: MachineResult, links: dict[int, dict[str, Any]]) -> dict[str, Any]:
    """What the page draws: the JSON result, the machine cycle's series, the machine table, project links."""
    names = [a.name for a in result.machine.axes]
    return {**result.to_dict(), "series": result.series(), "table": axis_rows(result),
            "links": {names[k]: v for k, v in links.items()}}


def machine_examples() -> dict[str, Path]:
    """Machine files shipped next to the package in a source checkout (examples/machine/*.yaml with axes)."""
    root = Path(__file__).resolve().parents[3] / "examples" / "machine"  # src/drivetrain/web/ -> the checkout
    if not root.is_dir():
        return {}
    out = {}
    for p in sorted(root.glob("*.yaml")):
        if p.is_file() and "\naxes:" in p.read_text(encoding="utf-8"):
            out[p.stem] = p
    return out


def inline_example(path: Path) -> dict[str, Any]:
    """A shipped machine file with each ``include:`` replaced by the included axis file's content."""
    from drivetrain.axis.yaml_text import read_yaml

    data = read_yaml(path)
    if not isinstance(data, dict):
        raise InputError("name", "the example is not a machine file", path.name)
    axes = []
    for a in data.get("axes") or []:
        if isinstance(a, dict) and isinstance(a.get("include"), str):
            included = read_yaml(path.parent / a["include"])
            a = {**{k: v for k, v in a.items() if k != "include"}, "axis": included}
        axes.append(a)
    return {**data, "axes": axes}


def sized_machine(resolved: dict[str, Any], samples: int, seed: int) -> MachineResult:
    """The machine (its axes inline) sized; run in a worker process, like every job below."""
    from drivetrain.machine.model import parse_machine
    from drivetrain.machine.result import size_machine

    def run() -> MachineResult:
        machine = parse_machine(resolved, allow_include=False, max_axes=MAX_WEB_AXES)
        return size_machine(machine, phasing_samples=samples, seed=seed)

    return engine(run)


def machine_size_payload(resolved: dict[str, Any], links: dict[int, dict[str, Any]], samples: int,
                         seed: int) -> dict[str, Any]:
    """What ``/api/machine/size`` answers (``machine_payload`` of the sized machine)."""
    return machine_payload(sized_machine(resolved, samples, seed), links)


def machine_report_job(resolved: dict[str, Any], samples: int, seed: int, path: str) -> str:
    """Write the machine report (HTML or PDF by the suffix of ``path``); returns the machine's name."""
    from drivetrain.report.machine import write_machine_report

    result = sized_machine(resolved, samples, seed)
    write_machine_report(result, Path(path))
    return result.machine.name


def machine_aas_job(resolved: dict[str, Any], samples: int, seed: int) -> tuple[str, str]:
    """The machine's name and its AAS environment as JSON text."""
    from drivetrain.machine.aas import machine_aas

    result = sized_machine(resolved, samples, seed)
    return result.machine.name, json.dumps(machine_aas(json.loads(encode(result.to_dict()))), indent=2)


def register(app: FastAPI, ctx: Context) -> None:
    """Add the machine routes to ``app``.

    Sizing a machine, its report and its AAS run in the app's worker processes (``ctx.isolated``):
    past the request's time limit the worker is killed and the request's place is free again.
    """
    isolated, light, store, temp_path = ctx.isolated, ctx.light, ctx.store, ctx.temp_path

    async def resolved_of(request: Request) -> tuple[dict[str, Any], dict[int, dict[str, Any]]]:
        data = await machine_from(request)
        resolved, links = await light(resolve_projects, data, store)
        return resolved, links

    @app.post("/api/machine/size", tags=["machine"], response_class=Response,
              responses={200: {"content": {"application/json": {"schema": {"type": "object"}}}}},
              openapi_extra=_BODY)
    async def size_machine_route(request: Request, samples: _SAMPLES = 200, seed: _SEED = 0) -> Response:
        """Size a machine: every axis, the DC bus(es) over the machine cycle, phasing, bill of materials.

        Besides the JSON result (``drivetrain machine size --json``): ``series`` (the machine cycle's
        grid and each axis's and bus's power [W]), ``table`` (one row per motor: motor, drive, gearbox,
        smallest margin, pass) and ``links`` (axis name: the saved axis project it came from)."""
        resolved, links = await resolved_of(request)
        body = await isolated(encoded, ctx.machine_payload, resolved, links, samples, seed)
        return Response(body, media_type="application/json")

    @app.post("/api/report/machine", tags=["machine"], response_class=Response,
              responses={200: {"content": {"text/html": {"schema": {"type": "string"}},
                                           "application/pdf": {"schema": {"type": "string", "format": "binary"}}}}},
              openapi_extra=_BODY)
    async def machine_report(request: Request, format: Literal["html", "pdf"] = "html", samples: _SAMPLES = 200,
                             seed: _SEED = 0) -> Response:
        """The machine report (HTML or PDF: the bus over the cycle, the buses, the BOM, each axis's page)."""
        resolved, _ = await resolved_of(request)
        path = temp_path(f".{format}")
        try:
            name = await isolated(machine_report_job, resolved, samples, seed, str(path))
        except BaseException:
            path.unlink(missing_ok=True)
            raise
        media = "text/html; charset=utf-8" if format == "html" else "application/pdf"
        return FileResponse(path, media_type=media, filename=safe_filename(name, f"-report.{format}"),
                            background=BackgroundTask(path.unlink, missing_ok=True))

    @app.post("/api/machine/aas", tags=["machine"], response_class=Response,
              responses={200: {"content": {"application/json": {"schema": {"type": "object"}}}}},
              openapi_extra=_BODY)
    async def machine_aas_route(request: Request, samples: _SAMPLES = 200, seed: _SEED = 0) -> Response:
        """The sizing as an IDTA 02021 "Sizing of Power Drive Trains" AAS environment (JSON), as a download."""
        resolved, _ = await resolved_of(request)
        name, body = await isolated(machine_aas_job, resolved, samples, seed)
        return Response(body, media_type="application/json", headers=attachment(safe_filename(name, ".aas.json")))

    @app.post("/api/machine/parse", tags=["machine"])
    async def parse_machine_yaml(body: YamlIn) -> dict[str, Any]:
        """Machine YAML text to its JSON form (the keys are checked when it is sized)."""
        return {"machine": await isolated(parse_text, "machine", body.yaml)}

    @app.post("/api/machine/yaml", tags=["machine"], response_class=Response,
              openapi_extra={"requestBody": {"required": True, "description": "the machine as JSON",
                                             "content": {"application/json": {"schema": {"type": "object"}}}}})
    async def machine_yaml(request: Request) -> Response:
        """The machine's JSON form as YAML text."""
        data = await machine_from(request)
        return Response(dump_yaml(data), media_type="application/yaml; charset=utf-8")

    @app.get("/api/machine/examples", tags=["machine"])
    async def examples() -> list[str]:
        """Names of the shipped machine examples."""
        return sorted(machine_examples())

    @app.get("/api/machine/examples/{name}", tags=["machine"])
    async def example(name: Annotated[str, PathParam(max_length=64)]) -> dict[str, Any]:
        """A shipped machine example, its included axis files put inline (the web app reads no files by name)."""
        found = machine_examples().get(name)
        if found is None:
            raise ApiError(404, f"name: no machine example called {name!r}; known: "
                           f"{', '.join(sorted(machine_examples()))}", "name")
        data = await light(inline_example, found)
        return {"machine": data, "yaml": dump_yaml(data)}
