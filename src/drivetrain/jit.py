"""The compiled kernels' one way in to numba: ``njit``, used by the dynamics simulation
(``dynamics/_kernel.py``) only; numba's own on-disk cache (``cache=True``) keeps them between runs.
The sizing (the selection checks, ``sizing/kernel.py``, and the hulls, ``sizing/hull.py``) is
plain numpy and never imports numba.

numba without its BLAS probe. Importing ``numba.np.arraymath`` (which numba does on the first
compile or cache load) runs ``_check_blas``: it imports ``scipy.linalg.cython_blas`` and with it
``scipy.linalg``, ``numpy.f2py`` and ``numpy.testing`` (about 0.2 s of CPU), only to decide
whether the inner product of ``np.convolve``/``np.correlate`` inside compiled code calls BLAS or a
plain loop. No kernel here calls either, nor any linear algebra, so the probe is told "no BLAS"
while that module is imported: the flag it sets affects only those two functions (which then use
the loop); ``np.dot`` and ``np.linalg`` inside compiled code still find BLAS themselves.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any


def njit(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """numba's ``njit`` with ``options`` (numba imported on first use, without its BLAS probe)."""
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
