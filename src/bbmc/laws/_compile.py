"""Turn one scalar njit law into a numpy ufunc without writing it twice.

Each law is written once, with `math` on float scalars, and compiled by `numba.njit` for the kernels.
`numpy_law` compiles the *same source* again as a broadcasting ufunc for numpy callers. The ufunc gets
its own function object (same code, different name) so that numba's on-disk cache keeps the njit and
the ufunc builds apart: two `cache=True` compilations of one function object share a cache index, and
loading one as the other crashes the interpreter (seen with numba 0.68).
"""

import types

import numba
import numpy as np


def numpy_law(kernel: numba.core.registry.CPUDispatcher) -> numba.np.ufunc.dufunc.DUFunc | np.vectorize:
    """Return a lazily compiled, broadcasting ufunc that runs `kernel`'s source element by element.

    With NUMBA_DISABLE_JIT=1 (for debugging and coverage) `njit` returns the plain function, which is
    then its own source, broadcast by `numpy.vectorize` (numba 0.68's `vectorize` compiles even then,
    and cannot type the plain functions a law calls).
    """
    source = getattr(kernel, "py_func", kernel)
    if numba.config.DISABLE_JIT:
        return np.vectorize(source, otypes=[float])
    twin = types.FunctionType(
        source.__code__,
        source.__globals__,
        source.__name__ + "_ufunc",
        source.__defaults__,
        source.__closure__,
    )
    twin.__qualname__ = source.__qualname__ + "_ufunc"
    twin.__doc__ = source.__doc__
    twin.__module__ = source.__module__
    return numba.vectorize(cache=True)(twin)
