"""The request time limit: 20 s by default, raised by ``serve --timeout`` or ``$DRIVETRAIN_REQUEST_TIMEOUT``."""

import subprocess
import sys

import pytest

from drivetrain.errors import InputError
from drivetrain.web.app import REPORT_TIMEOUT_S, REQUEST_TIMEOUT_S, time_limits


def test_default_and_given(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DRIVETRAIN_REQUEST_TIMEOUT", raising=False)
    assert time_limits() == (REQUEST_TIMEOUT_S, REPORT_TIMEOUT_S) == (20.0, 120.0)
    assert time_limits(0.3) == (0.3, 120.0)
    monkeypatch.setenv("DRIVETRAIN_REQUEST_TIMEOUT", "300")
    assert time_limits() == (300.0, 300.0)  # a report never gets less than a request
    assert time_limits(5.0) == (5.0, 120.0)  # the caller's own wins


@pytest.mark.parametrize("text", ["soon", "-1", "0", "1e9", "nan"])
def test_bad_environment_names_the_variable(monkeypatch: pytest.MonkeyPatch, text: str) -> None:
    monkeypatch.setenv("DRIVETRAIN_REQUEST_TIMEOUT", text)
    with pytest.raises(InputError, match="DRIVETRAIN_REQUEST_TIMEOUT"):
        time_limits()


def test_serve_refuses_a_bad_timeout() -> None:
    r = subprocess.run([sys.executable, "-m", "drivetrain.cli", "serve", "--timeout", "-5"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert "--timeout" in r.stderr and "Traceback" not in r.stderr
