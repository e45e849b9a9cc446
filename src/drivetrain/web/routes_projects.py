"""Routes of the saved projects: list, create, save (versioned), rename, delete, duplicate, history,
restore, undo and download.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import FastAPI, Query
from fastapi import Path as PathParam
from fastapi.responses import Response

from drivetrain.errors import InputError
from drivetrain.web.common import (
    Context,
    attachment,
    error_body,
    parse_text,
    safe_filename,
)
from drivetrain.web.models import (
    YAML_FILE,
    ProjectCreate,
    ProjectDetail,
    ProjectDuplicate,
    ProjectOut,
    ProjectRename,
    ProjectSave,
    VersionDetail,
    VersionOut,
)

_PROJECT_ID = Annotated[int, PathParam(ge=1, le=2**53, description="project id")]
_VERSION = Annotated[int, PathParam(ge=1, le=2**53, description="version number")]


def register(app: FastAPI, ctx: Context) -> None:
    """Add the project routes to ``app``.

    A save parses its text with the web's one parser (``common.parse_text``, the command line's
    bounds) on a thread, not in the worker processes: a save must not wait behind sizings and
    reports, and the parser's bounds keep it short."""
    store, light = ctx.store, ctx.light

    def detail(info: Any, text: str, parsed: dict[str, Any] | None = None) -> dict[str, Any]:
        """The project with its text parsed as what it holds: ``axis`` or ``machine`` (the other null)."""
        out = info.to_dict()
        out["yaml"] = text
        key, other = ("machine", "axis") if info.kind == "machine" else ("axis", "machine")
        out[other] = None
        if parsed is not None:
            out[key], out["yaml_error"] = parsed, None
            return out
        try:
            out[key], out["yaml_error"] = parse_text(info.kind, text), None
        except InputError as exc:
            out[key], out["yaml_error"] = None, error_body(exc)
        return out

    @app.get("/api/projects", response_model=list[ProjectOut], tags=["projects"])
    async def list_projects(
        kind: Annotated[Literal["axis", "machine"] | None, Query(description="only projects of this kind")] = None,
    ) -> list[dict[str, Any]]:
        """Every project (of ``kind``, if given), most recently saved first."""
        return [p.to_dict() for p in await light(store.projects, kind)]

    @app.post("/api/projects", response_model=ProjectDetail, status_code=201, tags=["projects"])
    async def create_project(body: ProjectCreate) -> dict[str, Any]:
        """A new axis or machine project (version 1). The text must be YAML; it may still fail sizing (a draft)."""
        parsed = await light(parse_text, body.kind, body.yaml)
        info = await light(lambda: store.create(body.name, body.yaml, kind=body.kind))
        return detail(info, body.yaml, parsed)

    @app.get("/api/projects/{project_id}", response_model=ProjectDetail, tags=["projects"])
    async def get_project(project_id: _PROJECT_ID) -> dict[str, Any]:
        """A project with its current text."""
        info, head = await light(store.head, project_id)
        return detail(info, head.text)

    @app.put("/api/projects/{project_id}", response_model=ProjectDetail, tags=["projects"])
    async def save_project(project_id: _PROJECT_ID, body: ProjectSave) -> dict[str, Any]:
        """Save the text as the next version (one transaction; refused if base_version is stale)."""
        current = await light(store.info, project_id)
        parsed = await light(parse_text, current.kind, body.yaml)
        info = await light(store.save, project_id, body.yaml, body.base_version, body.note)
        return detail(info, body.yaml, parsed)

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

    @app.get("/api/projects/{project_id}/yaml", tags=["projects"], response_class=Response, responses=YAML_FILE)
    async def project_yaml(project_id: _PROJECT_ID) -> Response:
        """The project's current axis (or machine) file, as a download."""
        info, head = await light(store.head, project_id)
        return Response(head.text, media_type="application/yaml; charset=utf-8",
                        headers=attachment(safe_filename(info.name, ".yaml")))
