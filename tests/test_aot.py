"""The selection kernel built ahead of time (sizing/aot.py, jit.py) from the same source as numba's
njit kernel: identical pass/fail and margins on the whole shipped catalog, loaded without numba,
never a build of another source."""

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
EXAMPLES = ("ball_screw", "belt", "hoist", "rack_pinion", "rotary")

COMPARE = textwrap.dedent("""
    import json, sys
    import numpy as np
    from drivetrain import catalog, jit
    from drivetrain.axis.model import Margins, load_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing import kernel, selection
    from drivetrain.sizing.pipeline import size
    out = {"kernel": type(kernel.check).__name__, "numba_after_size": None, "examples": {}}
    size(load_axis(sys.argv[1] + "/ball_screw.yaml"))
    out["numba_after_size"] = "numba" in sys.modules
    built = jit.aot_module("drivetrain.sizing.kernel")
    ways = {"aot": built.check, "njit": kernel.check.jit}  # each called directly: no fallback between them
    m, gb = catalog.motors(), catalog.gearboxes()  # the whole shipped catalog, every gearbox kind
    for name in sys.argv[2:]:
        ax = load_axis(f"{sys.argv[1]}/{name}.yaml")
        duty = duty_cycle(ax)
        got = {}
        for way, fn in ways.items():
            kernel.check = fn
            c = selection.evaluate(ax, duty, m, gb, Margins())
            arrays = [c.motor, c.slot, c.worst_margin, c.failed, c.unknown]
            for lo in range(0, len(c.motor), 100_000):
                d = c.details(np.arange(lo, min(lo + 100_000, len(c.motor))))
                arrays += [*d.required.values(), *d.available.values(), *d.margin.values()]
            got[way] = arrays
        out["examples"][name] = {
            "candidates": int(len(got["aot"][0])),
            "identical": all(np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
                             for a, b in zip(got["aot"], got["njit"], strict=True)),
        }
    print(json.dumps(out))
""")


@pytest.fixture(scope="module")
def built_cache(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    cache = tmp_path_factory.mktemp("aot-cache")
    env = {**os.environ, "DRIVETRAIN_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-m", "drivetrain.sizing.aot"], env=env, capture_output=True, text=True,
                          check=True)
    assert done.stdout.count("built ahead of time") == len(jit.AOT_MODULES), done.stderr
    return env


def test_the_build_passes_and_fails_what_numba_does(built_cache: dict[str, str]) -> None:
    """Every candidate of the whole shipped catalog (every motor x every gearbox row and direct), on
    each example axis: the same pass/fail and unknown bits, worst margin and every check's required,
    available and margin, to the bit, from the build and from numba's njit of the same source."""
    run = subprocess.run([sys.executable, "-c", COMPARE, str(ROOT / "examples"), *EXAMPLES], env=built_cache,
                         capture_output=True, text=True, check=True)
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["kernel"] == "Kernel"
    assert out["numba_after_size"] is False
    assert set(out["examples"]) == set(EXAMPLES)
    for name, got in out["examples"].items():
        assert got["candidates"] > 500_000, name
        assert got["identical"], name


HULL = textwrap.dedent("""
    import json, sys
    import numpy as np
    from drivetrain import jit
    from drivetrain.sizing import hull, motor_fit
    from drivetrain.axis.model import parse_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing.aot import AXIS
    out = {"kernel": type(hull._hulls).__name__}
    axis = parse_axis(AXIS)
    duty = duty_cycle(axis, 4000)  # more samples than motor_fit._COMPILED_FROM: the compiled hull
    rng = np.random.default_rng(7)
    torque = duty.torque + rng.normal(0.0, 0.01, duty.torque.size)
    args = (duty.omega, duty.alpha, torque, duty.weights, duty.period, duty.load_inertia)
    built = motor_fit.demand(*args)
    out["numba_after_hull"] = "numba" in sys.modules
    hull._hulls = hull._hulls.jit  # numba's njit of the same source, same arguments
    ref = motor_fit.demand(*args)
    out["points"] = int(duty.torque.size)
    out["identical"] = all(np.array_equal(getattr(built, k), getattr(ref, k))
                           for k in ("hull_speed", "hull_torque", "hull_alpha", "all_torque", "all_alpha"))
    print(json.dumps(out))
""")


def test_the_hull_build_gives_numbas_vertices(built_cache: dict[str, str]) -> None:
    run = subprocess.run([sys.executable, "-c", HULL], env=built_cache, capture_output=True, text=True, check=True)
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["kernel"] == "Kernel"
    assert out["numba_after_hull"] is False
    assert out["points"] > 20_000
    assert out["identical"]


OWN_PROCESS = textwrap.dedent("""
    import json, sys
    from drivetrain.cli import main
    sys.argv = ["drivetrain", "size", sys.argv[1], "--json"]
    code = main()
    from pydantic.plugin._loader import get_plugins
    import gc, os
    threads = len(os.listdir("/proc/self/task")) if os.path.isdir("/proc/self/task") else None
    print(json.dumps({"code": code, "plugins": list(get_plugins()), "threads": threads,
                      "collector": [gc.isenabled(), gc.get_freeze_count()], "modules": sorted(
        m for m in sys.modules if m in ("importlib.metadata", "email", "numpy.ma", "numba", "yaml"))}))
""")


def test_a_drivetrain_process_loads_no_plugin_machinery_or_masked_arrays(built_cache: dict[str, str]) -> None:
    """A ``drivetrain size`` process with the kernels built: pydantic's plugin loader (importlib.metadata,
    email) is not imported with discovery off, nor numpy.ma (by np.unique), nor the YAML library for a
    file read before (axis/yaml_cache.py; numba, absent here, would import it for its own configuration);
    numpy's OpenBLAS starts no thread; the garbage collector is on, the start-up imports' objects frozen
    (cli._import_for_sizing); the answer is main(argv)'s in a program whose pydantic looks for plugins,
    whose OpenBLAS runs its threads and whose collector ran throughout."""
    env = {k: v for k, v in built_cache.items()
           if k not in ("PYDANTIC_DISABLE_PLUGINS", "OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")}
    axis = str(ROOT / "examples" / "ball_screw.yaml")
    for _ in range(2):  # the first run remembers the unit factors and the file's data
        run = subprocess.run([sys.executable, "-c", OWN_PROCESS, axis], env=env, capture_output=True, text=True,
                             check=True).stdout
    out = json.loads(run.splitlines()[-1])
    assert out["code"] in (0, 1) and out["plugins"] == [] and out["modules"] == []
    assert out["threads"] in (1, None)  # OpenBLAS started no thread of its own
    assert out["collector"][0] and out["collector"][1] > 10_000  # on again, the imports' objects frozen
    called = subprocess.run([sys.executable, "-c", "import sys; from drivetrain.cli import main; "
                             "main(['size', sys.argv[1], '--json'])", axis],
                            env=env, capture_output=True, text=True, check=True).stdout
    assert json.loads("\n".join(run.splitlines()[:-1])) == json.loads(called)


def test_a_thread_count_the_user_set_is_kept(built_cache: dict[str, str]) -> None:
    env = {**{k: v for k, v in built_cache.items() if k != "OPENBLAS_NUM_THREADS"}, "OMP_NUM_THREADS": "2"}
    probe = ("import os, sys; from drivetrain.cli import main; sys.argv = ['drivetrain', '--version']; main(); "
             "import numpy; print(os.environ.get('OPENBLAS_NUM_THREADS'), len(os.listdir('/proc/self/task')), "
             "os.cpu_count())")
    if not Path("/proc/self/task").is_dir():
        pytest.skip("no /proc: the thread count cannot be read")
    out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True).stdout
    setting, threads, cpus = out.split()[-3:]
    assert setting == "None" and int(threads) == min(2, int(cpus))  # OpenBLAS: at most one thread per CPU


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
