"""Fuzz the JSON API from its own OpenAPI schema (schemathesis): no 5xx, no hang, every 4xx has a message.

Each operation gets a bounded number of generated cases (about 9 000 requests in all, most of
them axes for the sizing routes), with schemathesis' default checks (status codes, content types
and bodies conform to the schema) plus ours. The cases are the same on every run; set
DRIVETRAIN_FUZZ_RANDOM=1 to explore new ones.
"""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

schemathesis = pytest.importorskip("schemathesis")
pytest.importorskip("fastapi")

from hypothesis import HealthCheck, settings  # noqa: E402

from drivetrain.web.app import LOOPBACK_HOSTS, create_app  # noqa: E402

MAX_EXAMPLES = 60
"""Generated cases per operation in the fuzzing phase (schemathesis adds its coverage cases)."""
SLOWEST_S = 30.0
"""A response slower than this fails the run (nothing may hang): past the server's own 20 s limit,
which stops a sizing (503, a failure here too); the client waits that long, so a request is never
cut short by the client (which would stop its sizing worker and leave a cold one)."""


def _app_in_a_temp_folder() -> tuple[Any, Path]:
    """The app on a fresh data folder; the environment is left as it was (see the fixture below)."""
    folder = Path(tempfile.mkdtemp(prefix="drivetrain-web-fuzz-"))
    before = os.environ.get("DRIVETRAIN_DATA_DIR")
    try:
        app = create_app(folder, allowed_hosts=(*LOOPBACK_HOSTS, "testserver"))
    finally:
        if before is None:
            os.environ.pop("DRIVETRAIN_DATA_DIR", None)
        else:
            os.environ["DRIVETRAIN_DATA_DIR"] = before
    return app, folder


APP, DATA_DIR = _app_in_a_temp_folder()
atexit.register(shutil.rmtree, DATA_DIR, ignore_errors=True)  # also where xdist collects without running
# The report route validates its body exactly like /api/size (fuzzed fully there); its coverage
# phase would render thousands of reports, so it gets the fuzzing phase only.
CONFIG = schemathesis.config.SchemathesisConfig.from_dict(
    {"operations": [{"include-path": "/api/report", "phases": {"coverage": {"enabled": False}}}]})
schema = schemathesis.openapi.from_asgi("/openapi.json", APP, config=CONFIG)


CALLS: dict[str, int] = {}


@pytest.fixture(scope="module", autouse=True)
def _data_dir() -> Iterator[None]:
    """The catalog reads $DRIVETRAIN_DATA_DIR: point it at the app's folder while these tests run."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRIVETRAIN_DATA_DIR", str(DATA_DIR))
        # the sizing processes warm up before the first timed request
        assert APP.state.sizing_workers().wait_ready(120.0), "the sizing workers did not start"
        yield
    shutil.rmtree(DATA_DIR, ignore_errors=True)
    total = sum(CALLS.values())
    print(f"\nfuzzed {len(CALLS)} operations with {total} requests")


def every_error_has_a_message(ctx: Any, response: Any, case: Any) -> bool | None:
    """4xx and 5xx answers are JSON objects with a non-empty 'detail' string."""
    if response.status_code < 400:
        return None
    body = response.json()
    assert isinstance(body, dict), f"error answer is not a JSON object: {response.text[:200]}"
    detail = body.get("detail")
    assert isinstance(detail, str) and detail.strip(), f"error answer without a message: {response.text[:200]}"
    return None


@schema.parametrize()
@settings(max_examples=MAX_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck),
          derandomize=not os.environ.get("DRIVETRAIN_FUZZ_RANDOM"))
def test_api_from_its_own_schema(case: Any) -> None:
    t0 = time.perf_counter()
    CALLS[case.operation.label] = CALLS.get(case.operation.label, 0) + 1
    response = case.call(headers={"x-drivetrain-token": APP.state.token}, timeout=SLOWEST_S)  # token: as the page
    elapsed = time.perf_counter() - t0
    where = f"{case.method} {case.formatted_path}"
    assert response.status_code < 500, f"{where}: {response.status_code} {response.text[:300]}"
    assert elapsed < SLOWEST_S, f"{where} took {elapsed:.1f} s"
    every_error_has_a_message(None, response, case)
    if response.status_code == 422 and "cannot be computed" in response.json()["detail"]:
        warnings.warn(f"engine input bug: {case.method} {case.formatted_path}: {response.json()['detail']}",
                      stacklevel=1)
    # Schema-valid is not always valid: a quantity is a number or any text with units, and the
    # engine checks the units, the bounds of quantities given as text and rules across fields.
    if response.status_code == 413:
        return  # the body limit (1 MB and a little), a deliberate answer schemathesis does not expect
    excluded = [schemathesis.checks.positive_data_acceptance]
    if case.media_type == "multipart/form-data":
        # a "file" part generated as a number or an object still arrives as file content
        excluded.append(schemathesis.checks.negative_data_rejection)
    case.validate_response(response, excluded_checks=excluded)
