"""The JSON models of the web API (request and response bodies), for validation and the OpenAPI schema."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, Field

from drivetrain.errors import InputError

MAX_TEXT_BYTES = 1_000_000
"""Largest axis text in a request [characters] (the axis-file limit)."""

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
    kind: Literal["axis", "machine"] = Field(default="axis", description="an axis file or a machine file")


class ProjectDetail(ProjectOut):
    yaml: str = Field(description="the axis as YAML text, as saved")
    axis: dict[str, Any] | None = Field(description="an axis project: the YAML parsed (null when it does not parse)")
    machine: dict[str, Any] | None = Field(default=None, description="a machine project: the YAML parsed (null when "
                                           "it does not parse)")
    yaml_error: ErrorOut | None = None


class ProjectCreate(BaseModel):
    name: Text = Field(min_length=1, max_length=200)
    yaml: Text = Field(max_length=MAX_TEXT_BYTES, description="the axis (or machine) file text")
    kind: Literal["axis", "machine"] = Field(default="axis", description="an axis project or a machine project")


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
    drive_vendors: list[str] = []
    drive_voltages: list[float] = []


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


ERRORS: dict[int | str, dict[str, Any]] = {
    code: {"model": ErrorOut, "description": text}
    for code, text in ((400, "bad request"), (403, "refused: another origin or host"),
                       (404, "not found"), (409, "conflict"), (413, "body too large"),
                       (422, "invalid input, naming the field"), (500, "server error"),
                       (503, "not available or too busy"))
}


YAML_FILE: dict[int | str, dict[str, Any]] = {
    200: {"description": "an axis file (YAML; a mapping of axis keys)",
          "content": {"application/yaml": {"schema": {"type": "object"}}}},
}
