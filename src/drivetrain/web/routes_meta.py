"""Routes about the app itself: health, the editor's form description, the axis schema, examples."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

from fastapi import FastAPI
from fastapi import Path as PathParam

from drivetrain.version import __version__
from drivetrain.web.common import ApiError, Context, catalog_available, parse_axis_text, report_module
from drivetrain.web.models import AxisOut, HealthOut


def register(app: FastAPI, ctx: Context) -> None:
    """Add the meta routes to ``app``."""

    @app.get("/api/health", response_model=HealthOut, tags=["meta"])
    async def health() -> dict[str, Any]:
        """Liveness, version, and whether the report and catalog are installed."""
        return {"status": "ok", "version": __version__, "report": report_module() is not None,
                "catalog": catalog_available()}

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



def _examples() -> dict[str, Path]:
    """Example axes shipped next to the package in a source checkout (examples/*.yaml)."""
    root = Path(__file__).resolve().parents[3] / "examples"  # src/drivetrain/web/ -> the checkout
    if not root.is_dir():
        return {}
    return {p.stem: p for p in sorted(root.glob("*.yaml")) if p.is_file()}
