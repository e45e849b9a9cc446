"""Routes of the catalog: filter and sort motors, gearboxes and drives, one item, a motor's envelope, and
importing, editing and removing the user's own rows with their history; with the table queries behind them.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from fastapi import FastAPI, File, Form, Query, Request, UploadFile
from fastapi import Path as PathParam

from drivetrain.catalog.importer import MAX_IMPORT_BYTES
from drivetrain.errors import InputError, InputErrors
from drivetrain.web.common import MAX_ERROR_ITEMS, ApiError, Context, bounded, need_catalog, safe_filename
from drivetrain.web.models import CatalogPage, EnvelopeOut, FacetsOut, ImportOut
from drivetrain.web.payload import engine, motor_envelope, plain

MAX_UPLOAD_BYTES = MAX_IMPORT_BYTES
"""Largest catalog import [bytes]: the import's own limit (``catalog.importer.MAX_IMPORT_BYTES``, 20 MB),
the one docs/limits.md states; the request body may be larger by its multipart wrapping
(``app.UPLOAD_BODY_BYTES``)."""
_CATALOG_ID = Annotated[str, PathParam(min_length=1, max_length=200, description="catalog id")]
"""A catalog id in a path: it may hold a slash (FANUC's "beta 0.2/5000is"), so the routes take the
rest of the path (``{...:path}``) and the page sends it percent-encoded."""


MotorSort = Literal["id", "vendor", "series", "rated_power", "rated_torque", "peak_torque", "rated_speed",
                    "max_speed", "rotor_inertia", "mass", "flange", "voltage"]
Origin = Literal["all", "builtin", "user"]
GearboxSort = Literal["id", "vendor", "series", "ratio", "stages", "rated_output_torque", "max_output_torque",
                      "efficiency", "max_input_speed", "inertia_input", "backlash", "mass"]
DriveSort = Literal["id", "vendor", "series", "continuous_current", "peak_current", "voltage", "rated_power",
                    "motor_series"]


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


def drives_page(vendor: str | None, voltage: str | None, q: str | None, sort: str, order: str, offset: int,
                limit: int, origin: str = "all") -> dict[str, Any]:
    """Drives (currents, voltage class, the motor series each runs, source), filtered and sorted."""
    from drivetrain import catalog

    table = engine(lambda: catalog.drives(vendor=vendor or None, voltage=voltage or None))
    mask = _text_mask(table, q)
    if q:  # a drive is also found by the motor series it runs
        mask |= np.char.find(np.char.lower(table.motor_series.astype(str)), q.strip().lower()) >= 0
    return _page(table, mask & _origin_mask(table, origin), sort, order, offset, limit)


def facets() -> dict[str, Any]:
    from drivetrain import catalog

    m, g, d = catalog.motors(), catalog.gearboxes(), catalog.drives()
    volts = sorted({float(v) for v in m.voltage if math.isfinite(v)})
    return {"motor_vendors": sorted(set(m.vendor.tolist())), "motor_kinds": sorted(set(m.kind.tolist())),
            "gearbox_vendors": sorted(set(g.vendor.tolist())), "gearbox_series": sorted(set(g.series.tolist()) - {""}),
            "gearbox_kinds": sorted(set(g.kind.tolist())), "motor_voltages": volts,
            "drive_vendors": sorted(set(d.vendor.tolist())),
            "drive_voltages": sorted({float(v) for v in d.voltage if math.isfinite(v)})}



def utc_now() -> str:
    """The time of an upload, as recorded in the rows' source."""
    import datetime as dt

    return dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC")


def rename_import_error(exc: InputError, tmp: str, shown: str) -> InputError:
    errors = exc.errors if isinstance(exc, InputErrors) else [exc]
    if len(errors) > MAX_ERROR_ITEMS + 1:  # only the first ones are answered: rename no more
        exc = bounded(exc)
        errors = exc.errors if isinstance(exc, InputErrors) else [exc]
    renamed = [InputError(e.field.replace(tmp, shown), e.rule.replace(tmp, shown), e.value, has_value=e.has_value)
               for e in errors]
    return renamed[0] if len(renamed) == 1 else InputErrors(renamed)


def import_job(path: str, kind: str | None, directory: Path, replace: bool, source: str) -> dict[str, Any]:
    """Import the file at ``path`` into the user catalog; run in a worker process (killed, and its
    transaction rolled back by SQLite, when the request runs past its time limit)."""
    from drivetrain import catalog

    rep = catalog.import_file(Path(path), kind, directory=directory, replace=replace, source=source)
    return {"table": rep.table, "rows": rep.rows, "curve_points": rep.curve_points, "ids": list(rep.ids),
            "message": str(rep)}


def register(app: FastAPI, ctx: Context) -> None:
    """Add the catalog routes to ``app``."""
    blocking, isolated, temp_path, directory = ctx.blocking, ctx.isolated, ctx.temp_path, ctx.directory

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

    @app.get("/api/catalog/drives", response_model=CatalogPage, tags=["catalog"])
    async def catalog_drives(
        vendor: Annotated[str | None, Query(max_length=100)] = None,
        voltage: Annotated[str | None, Query(max_length=40, description="voltage class, e.g. 400 V")] = None,
        q: Annotated[str | None, Query(max_length=100, description="text in the id, model or (motor) series")] = None,
        sort: DriveSort = "continuous_current",
        order: Literal["asc", "desc"] = "asc",
        offset: Annotated[int, Query(ge=0, le=1_000_000)] = 0,
        limit: Annotated[int, Query(ge=1, le=500)] = 50,
        origin: Annotated[Origin, Query(description="shipped rows (builtin), yours (user) or all")] = "all",
    ) -> dict[str, Any]:
        """Servo drives of the shipped and user catalogs (currents, voltage class, motor series, source)."""
        need_catalog()
        return await blocking(drives_page, vendor, voltage, q, sort, order, offset, limit, origin)

    @app.get("/api/catalog/items/{item_id:path}", tags=["catalog"])
    async def catalog_item(item_id: _CATALOG_ID) -> dict[str, Any]:
        """One motor, gearbox or drive with its source and notes."""
        need_catalog()
        from drivetrain import catalog

        try:
            record: dict[str, Any] = plain(await blocking(catalog.get, item_id))
        except InputError as exc:
            raise ApiError(404, str(exc).replace("id:", "item_id:", 1), "item_id") from None
        return record

    @app.get("/api/catalog/motors/{motor_id:path}/envelope", response_model=EnvelopeOut, tags=["catalog"])
    async def catalog_envelope(motor_id: _CATALOG_ID) -> dict[str, Any]:
        """A motor's continuous and peak speed-torque envelope (from its curve, or derived from ratings)."""
        need_catalog()
        try:
            return await blocking(motor_envelope, motor_id)
        except InputError as exc:
            raise ApiError(404, str(exc).replace("ids:", "motor_id:", 1), "motor_id") from None

    @app.post("/api/catalog/import", response_model=ImportOut, tags=["catalog"])
    async def catalog_import(
        file: Annotated[UploadFile, File(description="a CSV or JSON file of motors, gearboxes, drives or curves")],
        kind: Annotated[Literal["motor", "gearbox", "drive", "curve"] | None, Form()] = None,
        replace: Annotated[bool, Form(description="update rows of your catalog with the same id")] = False,
    ) -> dict[str, Any]:
        """Import your own catalog rows: all rows are checked first; every bad cell is reported (422).

        Rows that name no source record the uploaded file's name and the time of the upload (UTC)."""
        need_catalog()
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
            del data
            try:
                uploaded = f"uploaded file {shown + suffix} at {utc_now()}"
                rep = await isolated(import_job, str(path), kind, directory, replace, uploaded)
            except InputError as exc:
                raise rename_import_error(exc, str(path), shown + suffix) from None
        finally:
            path.unlink(missing_ok=True)
        rep["message"] = str(rep["message"]).replace(str(path), shown + suffix)
        return rep

    @app.delete("/api/catalog/items/{item_id:path}", tags=["catalog"])
    async def catalog_remove(item_id: _CATALOG_ID) -> dict[str, Any]:
        """Remove one row of your catalog (a motor with its curve points); shipped rows cannot be removed."""
        need_catalog()
        from drivetrain.catalog import manage

        count = await blocking(lambda: manage.remove([item_id], directory=directory, source="web catalog"))
        return {"removed": count, "id": item_id, "message": f"removed {item_id} from your catalog"}

    @app.patch("/api/catalog/items/{item_id:path}", tags=["catalog"])
    async def catalog_edit(item_id: _CATALOG_ID, request: Request) -> dict[str, Any]:
        """Change fields of one row of your catalog: a JSON object of field (or ``name [unit]``) to value;
        null clears a field. The row is validated as an import is; the answer is the row as stored."""
        need_catalog()
        import json

        from drivetrain import catalog

        try:
            changes = json.loads(await request.body() or b"null")
        except ValueError:
            raise InputError("body", "must be a JSON object of field: value", has_value=False) from None
        if not isinstance(changes, dict):
            raise InputError("body", "must be a JSON object of field: value", has_value=False)
        record: dict[str, Any] = plain(await blocking(
            lambda: catalog.update(item_id, changes, directory=directory, source="web catalog edit")))
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
