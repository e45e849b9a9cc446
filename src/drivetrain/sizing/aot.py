"""Build the selection kernel (``sizing/kernel.py``) ahead of time, so that a sizing never imports
numba: ``python -m drivetrain.sizing.aot`` (``make setup`` runs it after install).

A representative selection (the shipped catalog, a small ball-screw cycle) runs first under numba,
so that every kernel holds the argument types the selection passes it; those functions are then
compiled by numba's ``pycc`` with the options of their ``njit`` (error model, fast-math flags) into
one extension module in ``jit.aot_dir()``, named by ``jit.aot_name`` (a hash of the kernel's
source, numpy's version and the interpreter), and moved there atomically. ``jit.njit`` loads it
when ``kernel.py`` is imported.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

from drivetrain import jit

MODULE = "drivetrain.sizing.kernel"
AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "profile": [{"move": "200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"},
                {"move": "-200 mm", "time": "0.5 s", "accel": "0.1 s"}, {"dwell": "0.3 s"}],
    "motor": {"select": {"objective": "smallest"}},
}


def built_path() -> Path | None:
    """The build for the current kernel source, if it exists."""
    import importlib.machinery

    name = jit.aot_name(MODULE)
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = jit.aot_dir() / f"{name}{suffix}"
        if path.exists():
            return path
    return None


def build(force: bool = False) -> Path:
    """Build the kernel module ahead of time (unless a build for its current source exists)."""
    existing = built_path()
    if existing is not None and not force:
        return existing
    from drivetrain.axis.model import parse_axis
    from drivetrain.sizing import kernel
    from drivetrain.sizing.result import size

    size(parse_axis(AXIS))  # under numba: the dispatchers learn the argument types
    kernels = {name: getattr(kernel, name) for name in jit.OPTIONS[MODULE]}
    dispatchers = {name: (k.jit if isinstance(k, jit.Kernel) else k) for name, k in kernels.items()}
    options = [jit.OPTIONS[MODULE][name] for name, d in dispatchers.items() if d.nopython_signatures]
    if any(o != options[0] for o in options):
        raise RuntimeError(f"the kernels of {MODULE} differ in their options: one build needs one set")
    name = jit.aot_name(MODULE)
    with tempfile.TemporaryDirectory(prefix="drivetrain-aot-") as tmp:
        out = _compile(name, dispatchers, options[0], Path(tmp))
        jit.aot_dir().mkdir(parents=True, exist_ok=True)
        target = jit.aot_dir() / out.name
        staged = jit.aot_dir() / f".{out.name}.{os.getpid()}"
        shutil.copyfile(out, staged)
        os.replace(staged, target)
    for old in jit.aot_dir().glob(f"_aot_{MODULE.rsplit('.', 1)[-1]}_*"):
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
        path = build(force="--force" in sys.argv[1:])
    except Exception as exc:  # the build is an optimisation: numba's njit still serves without it
        print(f"drivetrain: ahead-of-time build of the selection kernel failed ({exc}); "
              "sizing uses numba's compiled cache instead", file=sys.stderr)
        return 0
    print(f"selection kernel built ahead of time: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
