"""Routes of the sizing and the axis file: size an axis, size it with one catalog candidate fixed,
YAML text to the axis and back, and an uploaded axis file.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import FastAPI, File, Query, Request, UploadFile
from fastapi.responses import Response

from drivetrain.errors import InputError
from drivetrain.web.common import (
    Context,
    attachment,
    axis_body,
    axis_from,
    dump_yaml,
    need_catalog,
    parse_text,
    safe_filename,
)
from drivetrain.web.models import YAML_FILE, AxisOut, CandidateOut, SizeOut, YamlIn
from drivetrain.web.payload import candidate_payload
from drivetrain.web.workers import encoded


def register(app: FastAPI, ctx: Context) -> None:
    """Add the sizing and axis-file routes to ``app``."""
    cache, isolated, size_payload = ctx.cache, ctx.isolated, ctx.size_payload

    @app.post("/api/size", response_model=SizeOut, tags=["sizing"],
              openapi_extra={"requestBody": axis_body("the axis to size")})
    async def size_axis(request: Request) -> Response:
        """Size an axis (the JSON form of the axis file): the result, the sampled cycle and envelopes.

        The sizing runs in a worker process; at the request's time limit it is stopped (503).
        """
        axis = await axis_from(request)
        key = cache.key("size", axis)
        body = cache.get(key)
        if body is None:
            body = await isolated(encoded, size_payload, axis)
            cache.put(key, body)
        return Response(body, media_type="application/json")

    @app.post("/api/size/candidate", response_model=CandidateOut, tags=["sizing"],
              openapi_extra={"requestBody": axis_body("the axis; its motor section is replaced by the candidate")})
    async def size_candidate(
        request: Request,
        motor: Annotated[str, Query(min_length=1, max_length=200, description="catalog motor id")],
        gearbox: Annotated[str | None, Query(max_length=200, description="catalog gearbox id (none: direct)")] = None,
    ) -> Response:
        """Size the axis with one catalog candidate fixed (to compare candidates in the speed-torque plane)."""
        need_catalog()
        axis = await axis_from(request)
        key = cache.key("candidate", axis, motor, gearbox)
        body = cache.get(key)
        if body is None:
            body = await isolated(encoded, candidate_payload, axis, motor, gearbox or None)
            cache.put(key, body)
        return Response(body, media_type="application/json")

    @app.post("/api/yaml/parse", response_model=AxisOut, tags=["axis file"])
    async def yaml_parse(body: YamlIn) -> dict[str, Any]:
        """Axis YAML text to its JSON form (safe loader, same limits as the CLI)."""
        return {"axis": await isolated(parse_text, "axis", body.yaml), "yaml": None}

    @app.post("/api/yaml/dump", tags=["axis file"], response_class=Response, responses=YAML_FILE,
              openapi_extra={"requestBody": axis_body("the axis to write as YAML", complete=False)})
    async def yaml_dump(request: Request) -> Response:
        """The axis as a YAML file to download."""
        axis = await axis_from(request)
        name = axis.get("axis") if isinstance(axis.get("axis"), str) else "axis"
        return Response(dump_yaml(axis), media_type="application/yaml; charset=utf-8",
                        headers=attachment(safe_filename(str(name), ".yaml")))

    @app.post("/api/yaml/upload", response_model=AxisOut, tags=["axis file"])
    async def yaml_upload(file: Annotated[UploadFile, File(description="an axis YAML file")]) -> dict[str, Any]:
        """Read an uploaded axis file (safe loader, same limits as the CLI)."""
        from drivetrain.axis.yaml_text import MAX_FILE_BYTES

        data = await file.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            raise InputError("file", f"is too large (an axis file is at most {MAX_FILE_BYTES} bytes)",
                             has_value=False)
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError("file", f"is not UTF-8 text (byte {exc.start})", has_value=False) from None
        return {"axis": await isolated(parse_text, "axis", text, "file"), "yaml": text}
