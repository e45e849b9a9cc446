"""The selection kernel built ahead of time (sizing/aot.py, jit.py): the same pass and fail as numba's
compiled kernel on the shipped examples, loaded without numba, never a build of another source."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from drivetrain import jit

ROOT = Path(__file__).resolve().parents[1]

COMPARE = textwrap.dedent("""
    import json, sys
    import numpy as np
    from drivetrain import catalog, jit
    from drivetrain.axis.model import Margins, load_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing import kernel, selection
    from drivetrain.sizing.result import size
    out = {"kernel": type(kernel.check).__name__, "numba_after_size": None, "examples": {}}
    size(load_axis(sys.argv[1] + "/ball_screw.yaml"))
    out["numba_after_size"] = "numba" in sys.modules
    m, gb = catalog.motors(), catalog.gearboxes(kind="servo_gearbox")
    for name in ("ball_screw", "belt", "hoist"):
        ax = load_axis(f"{sys.argv[1]}/{name}.yaml")
        duty = duty_cycle(ax)
        built = selection.evaluate(ax, duty, m, gb, Margins())
        kernel.check._built = None  # numba's kernel, same arguments
        ref = selection.evaluate(ax, duty, m, gb, Margins())
        kernel.check._built = jit.aot_module("drivetrain.sizing.kernel").check
        w, r = built.worst_margin, ref.worst_margin
        out["examples"][name] = {
            "failed": bool(np.array_equal(built.failed, ref.failed)),
            "motor": bool(np.array_equal(built.motor, ref.motor)),
            "nan": bool(np.array_equal(np.isnan(w), np.isnan(r))),
            "max_rel": float(np.nanmax(np.abs(w - r) / np.maximum(np.abs(r), 1.0))),
        }
    print(json.dumps(out))
""")


@pytest.fixture(scope="module")
def built_cache(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    cache = tmp_path_factory.mktemp("aot-cache")
    env = {**os.environ, "DRIVETRAIN_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-m", "drivetrain.sizing.aot"], env=env, capture_output=True, text=True,
                          check=True)
    assert "built ahead of time" in done.stdout, done.stderr
    return env


def test_the_build_passes_and_fails_what_numba_does(built_cache: dict[str, str]) -> None:
    run = subprocess.run([sys.executable, "-c", COMPARE, str(ROOT / "examples")], env=built_cache,
                         capture_output=True, text=True, check=True)
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["kernel"] == "Kernel"
    assert out["numba_after_size"] is False
    for name, got in out["examples"].items():
        assert got["failed"] and got["motor"] and got["nan"], name
        # the same arithmetic; fast-math may contract a multiply-add differently for the host's CPU
        assert got["max_rel"] <= 1e-12, name


def test_a_second_build_reuses_the_first(built_cache: dict[str, str]) -> None:
    files = sorted((Path(built_cache["DRIVETRAIN_CACHE_DIR"]) / "aot").iterdir())
    again = subprocess.run([sys.executable, "-m", "drivetrain.sizing.aot"], env=built_cache, capture_output=True,
                           text=True, check=True)
    assert str(files[0]) in again.stdout
    assert sorted((Path(built_cache["DRIVETRAIN_CACHE_DIR"]) / "aot").iterdir()) == files


def test_a_changed_source_has_another_name(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "aot_probe_mod.py").write_text("X = 1\n")
    first = jit.aot_name("aot_probe_mod")
    (tmp_path / "aot_probe_mod.py").write_text("X = 2\n")
    assert jit.aot_name("aot_probe_mod") != first
    assert jit.aot_module("aot_probe_mod") is None  # not a module that is built ahead of time


def test_argument_types_the_build_was_not_made_for_go_to_numba() -> None:
    def double(x: np.ndarray) -> np.ndarray:
        return x * 2.0

    def built(*args: object) -> object:
        raise TypeError("can't convert")

    k = jit.Kernel(double, {"cache": False}, built)
    np.testing.assert_array_equal(k(np.arange(3.0)), [0.0, 2.0, 4.0])
    assert jit.Kernel(double, {}, lambda x: "built")(np.arange(3.0)) == "built"
