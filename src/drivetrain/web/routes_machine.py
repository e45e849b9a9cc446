"""The machine route: size a machine project (its axes inline) over its DC buses, as JSON."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import FastAPI, Query, Request
from fastapi.responses import Response

from drivetrain.errors import InputError
from drivetrain.web.common import Context, check_unicode
from drivetrain.web.payload import encode, engine

MAX_WEB_AXES = 8
"""Axes of a machine the web app sizes in one request (each is a full sizing)."""


async def machine_from(request: Request) -> dict[str, Any]:
    """The request's JSON body as a machine mapping (422 naming the problem otherwise)."""
    import json

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


def register(app: FastAPI, ctx: Context) -> None:
    """Add the machine route to ``app``."""
    blocking = ctx.blocking

    @app.post("/api/machine/size", tags=["machine"], response_class=Response,
              responses={200: {"content": {"application/json": {"schema": {"type": "object"}}}}},
              openapi_extra={"requestBody": {"required": True, "description": "the machine file as JSON, its axes "
                                             "inline (docs/machine.md)", "content": {"application/json": {
                                                 "schema": {"type": "object"}}}}})
    async def size_machine_route(
        request: Request,
        samples: Annotated[int, Query(ge=1, le=2000, description="random-phasing samples for free axes")] = 200,
        seed: Annotated[int, Query(ge=0, le=2**32 - 1, description="seed of the random phasing")] = 0,
    ) -> Response:
        """Size a machine: every axis, the DC bus(es) over the machine cycle, phasing, bill of materials."""
        data = await machine_from(request)

        def run() -> bytes:
            from drivetrain.machine.model import parse_machine
            from drivetrain.machine.result import size_machine

            machine = parse_machine(data, allow_include=False, max_axes=MAX_WEB_AXES)
            result = size_machine(machine, phasing_samples=samples, seed=seed)
            return encode({**result.to_dict(), "series": result.series()})

        body = await blocking(lambda: engine(run))
        return Response(body, media_type="application/json")
