"""Build the compiled kernels ahead of time, so that a sizing never imports numba:
``python -m drivetrain.sizing.aot`` (``make setup`` runs it after install). The modules are
``jit.AOT_MODULES``: the selection kernel (``sizing/kernel.py``) and the hull (``sizing/hull.py``).

Each module's own functions are compiled, from the same source as their ``njit`` (there is no
second copy): a representative run under numba first (a selection on the shipped catalog with a
small ball-screw cycle; hulls of a few bins) gives every kernel the argument types the callers
pass it; those functions are then compiled by numba's ``pycc`` with the options of their ``njit``
(error model, fast-math flags, GIL release) into one extension module per source module in
``jit.aot_dir()``, named by ``jit.aot_name`` (a hash of the module's source and this builder's,
numpy's version, the interpreter and the CPU), and moved there atomically. ``jit.njit`` loads it
when the module is imported; ``tests/test_aot.py`` asserts the build and numba's njit give the
same results to the bit.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

from drivetrain import jit

AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "profile": [{"move": "200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"},
                {"move": "-200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}],
    "motor": {"select": {"objective": "smallest"}},
}


def built_path(module: str) -> Path | None:
    """The build of ``module`` for its current source, if it exists."""
    import importlib.machinery

    name = jit.aot_name(module)
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = jit.aot_dir() / f"{name}{suffix}"
        if path.exists():
            return path
    return None


def _representative_runs() -> None:
    """Run every kernel under numba with the argument types its callers pass."""
    import numpy as np

    from drivetrain.axis.model import parse_axis
    from drivetrain.duty.cycle import duty_cycle
    from drivetrain.sizing import hull
    from drivetrain.sizing.pipeline import size

    axis = parse_axis(AXIS)
    size(axis)  # the selection kernel (evaluate, closest failing, details)
    duty = duty_cycle(axis)
    hull.fast_demand(duty.omega, duty.alpha, duty.torque, duty.weights, duty.period, duty.load_inertia)
    hull.chains(np.zeros(3), np.arange(3.0), np.array([0]), np.array([3]))


def build(force: bool = False) -> list[Path]:
    """Build every module of ``jit.AOT_MODULES`` ahead of time (unless a build of its current source exists)."""
    import importlib

    todo = [m for m in jit.AOT_MODULES if force or built_path(m) is None]
    if todo:
        if any(m in sys.modules for m in todo):
            raise RuntimeError("build in a fresh process: python -m drivetrain.sizing.aot")
        jit.building = True  # compile from njit here, even where an older build of the same name exists
        _representative_runs()
        for module in todo:
            _build_module(module, importlib.import_module(module))
    return [p for p in (built_path(m) for m in jit.AOT_MODULES) if p is not None]


def _build_module(module: str, mod: Any) -> Path:
    dispatchers = {name: getattr(mod, name) for name in jit.OPTIONS[module]}
    options = [jit.OPTIONS[module][name] for name, d in dispatchers.items() if d.nopython_signatures]
    if not options or any(o != options[0] for o in options):
        raise RuntimeError(f"the kernels of {module} differ in their options or never ran: one build needs one set")
    name = jit.aot_name(module)
    with tempfile.TemporaryDirectory(prefix="drivetrain-aot-") as tmp:
        out = _compile(name, dispatchers, options[0], Path(tmp))
        jit.aot_dir().mkdir(parents=True, exist_ok=True)
        target = jit.aot_dir() / out.name
        staged = jit.aot_dir() / f".{out.name}.{os.getpid()}"
        shutil.copyfile(out, staged)
        os.replace(staged, target)
    for old in jit.aot_dir().glob(f"_aot_{module.rsplit('.', 1)[-1]}_*"):
        if not old.name.startswith(name):
            old.unlink(missing_ok=True)
    return target


def _compile(name: str, dispatchers: dict[str, Any], options: dict[str, Any], out_dir: Path) -> Path:
    import numba.pycc.compiler as pycc_compiler
    from numba.core.cpu import FastMathOptions
    from numba.pycc import CC

    base = pycc_compiler.Flags

    class Flags(base):  # type: ignore[misc, valid-type]
        """pycc's flags with the kernel's own error model and fast-math flags."""

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self.error_model = options.get("error_model", "python")
            self.fastmath = FastMathOptions(options.get("fastmath", False))
            self.release_gil = bool(options.get("nogil", False))  # the web app sizes in threads

    cc = CC(name)
    cc.output_dir = str(out_dir)
    cc.verbose = False
    cc.target_cpu = "host"  # built where it runs (jit.aot_name holds the CPU's features)
    for fname, d in dispatchers.items():
        if d.nopython_signatures:
            cc.export(fname, d.nopython_signatures[0])(d.py_func)
    setattr(pycc_compiler, "Flags", Flags)  # noqa: B010 (pycc builds its flags inside; no other way in)
    try:
        cc.compile()
    finally:
        setattr(pycc_compiler, "Flags", base)  # noqa: B010
    (out,) = [p for p in out_dir.iterdir() if p.name.startswith(name)]
    return out


def main() -> int:
    try:
        paths = build(force="--force" in sys.argv[1:])
    except Exception as exc:  # the build is an optimisation: numba's njit still serves without it
        print(f"drivetrain: ahead-of-time build of the compiled kernels failed ({exc}); "
              "sizing uses numba's compiled cache instead", file=sys.stderr)
        return 0
    for path in paths:
        print(f"built ahead of time: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
