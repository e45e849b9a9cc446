"""The compiled kernels' one way in to numba: ``njit``, or the ahead-of-time build of a module.

Ahead of time. A module listed in ``AOT_MODULES`` may have a build of its kernels made with numba's
``pycc`` by ``python -m drivetrain.sizing.aot`` (``make setup`` runs it): a plain extension module
in the cache folder, named by a hash of the module's source and the builder's, numpy's version, the
interpreter and the CPU (it is built for the host's), so a changed kernel never meets an old build.
Where that build exists, ``njit`` returns a ``Kernel`` that calls it, and the process never imports
numba (importing numba and loading its cached kernel cost more than a whole sizing). Arguments of a
type the build was not made for, or no build at all, go to numba's ``njit`` as before, compiled on
first use.

numba without its BLAS probe. Importing ``numba.np.arraymath`` (which numba does on the first
compile or cache load) runs ``_check_blas``: it imports ``scipy.linalg.cython_blas`` and with it
``scipy.linalg``, ``numpy.f2py`` and ``numpy.testing`` (about 0.2 s of CPU), only to decide
whether the inner product of ``np.convolve``/``np.correlate`` inside compiled code calls BLAS or a
plain loop. No kernel here calls either, nor any linear algebra, so the probe is told "no BLAS"
while that module is imported: the flag it sets affects only those two functions (which then use
the loop); ``np.dot`` and ``np.linalg`` inside compiled code still find BLAS themselves.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

from drivetrain.unit_cache import cache_dir

AOT_MODULES = ("drivetrain.sizing.kernel", "drivetrain.sizing.hull")
"""Modules whose kernels may be built ahead of time (their functions call no other module's kernels)."""

building = False
"""Set by the builder (``sizing/aot.py``): its process compiles from numba's ``njit``, never from a build."""

BUILDER = "drivetrain.sizing.aot"
"""The module that makes the builds (its source is part of a build's name)."""

OPTIONS: dict[str, dict[str, dict[str, Any]]] = {}
"""module -> function name -> the options given to ``njit`` (read by the ahead-of-time build)."""

_loaded: dict[str, ModuleType | None] = {}


def numba_njit(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """numba's ``njit`` (numba imported on first use, without its BLAS probe)."""
    _import_arraymath_without_blas_probe()
    import numba

    return numba.njit(**options)


def _import_arraymath_without_blas_probe() -> None:
    if "numba.np.arraymath" in sys.modules:
        return
    import numba.np.linalg as linalg

    probe = linalg.ensure_blas

    def no_blas() -> None:
        raise ImportError("BLAS probe skipped (drivetrain.jit)")

    linalg.ensure_blas = no_blas
    try:
        import numba.np.arraymath  # noqa: F401
    finally:
        linalg.ensure_blas = probe


def aot_dir() -> Path:
    """The folder of the ahead-of-time builds."""
    return cache_dir() / "aot"


def aot_name(module: str) -> str:
    """Extension-module name of the build of ``module`` for its current source, numpy and interpreter."""
    import numpy as np

    digest = hashlib.sha256()
    for source in (module, BUILDER):  # the kernel's source and the way it is built
        spec = importlib.util.find_spec(source)
        if spec is None or spec.origin is None:
            raise ImportError(source)
        digest.update(Path(spec.origin).read_bytes())
    digest.update(f"{np.__version__}|{sys.version}|{sys.platform}|{_cpu()}".encode())
    return f"_aot_{module.rsplit('.', 1)[-1]}_{digest.hexdigest()[:16]}"


def _cpu() -> str:
    """The CPU and its features (a build for the host's CPU must not run on another)."""
    import platform

    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as fh:
            head = [line.strip() for line in fh if line.startswith(("model name", "flags", "Features"))][:2]
    except OSError:
        head = []
    # (not platform.processor(): on Linux it runs ``uname -p`` in a subprocess)
    return "|".join([platform.machine(), *head])


def aot_module(module: str) -> ModuleType | None:
    """The ahead-of-time build of ``module``, or None where there is none (or it does not load)."""
    if building:
        return None
    if module not in _loaded:
        _loaded[module] = None
        if module in AOT_MODULES:
            name = aot_name(module)
            for suffix in importlib.machinery.EXTENSION_SUFFIXES:
                path = aot_dir() / f"{name}{suffix}"
                if path.exists():
                    try:
                        loader = importlib.machinery.ExtensionFileLoader(name, str(path))
                        spec = importlib.util.spec_from_file_location(name, path, loader=loader)
                        if spec is not None:
                            mod = importlib.util.module_from_spec(spec)
                            loader.exec_module(mod)
                            _loaded[module] = mod
                    except (ImportError, OSError):
                        pass
                    break
    return _loaded[module]


class Kernel:
    """A kernel of a module built ahead of time: the build's function, numba's for any other types."""

    def __init__(self, fn: Callable[..., Any], options: dict[str, Any], built: Callable[..., Any] | None) -> None:
        self.py_func = fn
        self._options = options
        self._built = built
        self._jit: Any = None
        self.__name__ = fn.__name__
        self.__doc__ = fn.__doc__

    @property
    def jit(self) -> Any:
        """numba's dispatcher of the same function (compiled or loaded on first use)."""
        if self._jit is None:
            self._jit = numba_njit(**self._options)(self.py_func)
        return self._jit

    def __call__(self, *args: Any) -> Any:
        if self._built is not None:
            try:
                return self._built(*args)
            except TypeError:
                pass  # argument types the build was not made for
        return self.jit(*args)


def njit(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """numba's ``njit`` with ``options``; for a module built ahead of time, a ``Kernel`` of its build."""

    def decorate(fn: Callable[..., Any]) -> Any:
        OPTIONS.setdefault(fn.__module__, {})[fn.__name__] = options
        if fn.__module__ in AOT_MODULES:
            built = aot_module(fn.__module__)
            if built is not None:
                return Kernel(fn, options, getattr(built, fn.__name__, None))
        return numba_njit(**options)(fn)

    return decorate
