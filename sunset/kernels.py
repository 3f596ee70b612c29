"""The one switch between the NumPy reference kernels and their Numba twins.

Every hot step of the vector stage and of the coding is written twice. The
NumPy version is the reference: whole-array operations in the manner of the
Cray's vector loops, what the book shows and what the stage module reads as
the paper's algorithm. Its twin, in a ``*_numba`` module beside it, does the
same arithmetic, operation for operation and in the same order, one element
at a time with everything in registers; the tests check that both give
identical bytes.

A stage marks its reference kernel with :func:`twin`; that is the only place
where the choice is made::

    @twin("sunset.vector.heightfield_numba")
    def sea_scan(u, g, zeta0, dzeta, n_pixels, best_u, best_surf) -> int:
        ...  # the NumPy reference

Calling ``sea_scan`` runs the function of the same name in the twin module
when the compiled kernels are on (:func:`enabled`), and the reference
otherwise. The twin modules import their stages, never the other way round,
and are loaded only when first used.

The compiled kernels are on when Numba can be imported and the environment
variable ``SUNSET_COMPILED`` is not ``0``; :func:`use_compiled` switches them
for a block of code (the tests run both paths).
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import os

try:  # pragma: no cover - exercised by whichever environment runs the tests
    import numba as _numba
except ImportError:  # pragma: no cover
    _numba = None

__all__ = ["AVAILABLE", "enabled", "use_compiled", "jit", "twin"]

#: True when Numba is importable (the compiled kernels exist).
AVAILABLE = _numba is not None

_state = {"on": AVAILABLE and os.environ.get("SUNSET_COMPILED", "1") != "0"}


def enabled() -> bool:
    """Whether the renderer uses the compiled kernels now."""
    return _state["on"]


@contextlib.contextmanager
def use_compiled(flag: bool):
    """Use (True) or avoid (False) the compiled kernels inside a ``with`` block.

    Asking for them where Numba is missing leaves the NumPy path on.
    """
    old = _state["on"]
    _state["on"] = bool(flag) and AVAILABLE
    try:
        yield _state["on"]
    finally:
        _state["on"] = old


def jit(fn):
    """Compile with NumPy's float semantics (x/0 gives ±inf or NaN, no exception), cached on disk."""
    if _numba is None:
        return fn
    return _numba.njit(cache=True, nogil=True, error_model="numpy")(fn)


def twin(module: str):
    """Mark a NumPy reference kernel whose Numba twin is the function of the same name in ``module``.

    Returns a decorator. The decorated function dispatches on :func:`enabled`
    at every call; the reference stays reachable as ``.reference`` and the
    twin as ``.compiled()`` (the tests compare the two).
    """
    def decorate(reference):
        name = reference.__name__

        def compiled():
            return getattr(importlib.import_module(module), name)

        @functools.wraps(reference)
        def kernel(*args, **kwargs):
            if _state["on"]:
                return compiled()(*args, **kwargs)
            return reference(*args, **kwargs)

        kernel.reference = reference
        kernel.compiled = compiled
        return kernel
    return decorate
