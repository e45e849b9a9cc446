"""The report route: the HTML or PDF report of an axis's sizing, as a download."""

from __future__ import annotations

from typing import Any, Literal

from fastapi import FastAPI, Request
from fastapi.responses import FileResponse, Response
from starlette.background import BackgroundTask

from drivetrain.web.common import ApiError, Context, axis_body, axis_from, report_module, safe_filename
from drivetrain.web.payload import engine


def report_job(axis: dict[str, Any], path: str, units: str) -> None:
    """Size the axis and write its report to ``path`` (HTML or PDF by its suffix); run in a worker process."""
    from drivetrain.dynamics.mechanism_modes import size  # the pipeline with its modes stage, as every face
    from drivetrain.report import write_report

    write_report(engine(size, axis), path, units=units)


def register(app: FastAPI, ctx: Context) -> None:
    """Add the report route to ``app``: the report is written in one of the app's worker processes
    (``ctx.isolated``), killed at the request's time limit like a sizing."""
    isolated, temp_path = ctx.isolated, ctx.temp_path

    @app.post("/api/report", tags=["sizing"], response_class=Response,
              responses={200: {"content": {"text/html": {"schema": {"type": "string"}},
                                           "application/pdf": {"schema": {"type": "string", "format": "binary"}}}}},
              openapi_extra={"requestBody": axis_body("the axis to report on")})
    async def report(request: Request, format: Literal["html", "pdf"] = "html",
                     units: Literal["si", "imperial", "as-given"] = "si") -> Response:
        """The HTML or PDF report of the axis's sizing, as a download."""
        module = report_module()
        if module is None:
            raise ApiError(503, "the report is not available in this installation (drivetrain.report is missing)")
        axis = await axis_from(request)
        suffix = f".{format}"
        path = temp_path(suffix)
        try:
            await isolated(report_job, axis, str(path), units)
        except BaseException:
            path.unlink(missing_ok=True)
            raise
        name = axis.get("axis") if isinstance(axis.get("axis"), str) else "axis"
        media = "text/html; charset=utf-8" if format == "html" else "application/pdf"
        return FileResponse(path, media_type=media, filename=safe_filename(str(name), f"-report{suffix}"),
                            background=BackgroundTask(path.unlink, missing_ok=True))
