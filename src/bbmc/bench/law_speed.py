"""The joint laws' speed, as `make bench`'s `laws` section measures it: each law of `bbmc.laws`
evaluated three ways on the same inputs, its numpy ufunc, its njit kernel in a compiled loop (as the
engine calls it) and its plain Python source, so the table says what compiling one scalar law for both
numba and numpy buys.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numba
import numpy as np
import pandas as pd

from bbmc import laws, units
from bbmc.laws import stiffness, strength


@numba.njit(cache=True)
def _kernel_loop(law, values, out, *params):
    for i in range(values.size):
        out[i] = law(values[i], *params)


def _cases() -> list[tuple[str, numba.core.registry.CPUDispatcher, Callable, tuple[float, ...]]]:
    deg, mpa = units.deg, units.MPa
    bb = (2.13, 3.31 * mpa, 32 * deg, 70 * deg)
    return [
        ("peak_shear_strength (eq 9)", strength.peak_shear_strength, laws.peak_shear_strength, bb),
        (
            "equivalent_friction_angle (eq 14)",
            strength.equivalent_friction_angle,
            laws.equivalent_friction_angle,
            (*bb, 0.016),
        ),
        (
            "corrected_shear_stiffness (eq 16)",
            stiffness.corrected_shear_stiffness,
            laws.corrected_shear_stiffness,
            (0.9e9, 0.13 * mpa, 0.14 * mpa, 0.312, 0.7188),
        ),
        ("normal_stiffness (eq 8)", stiffness.normal_stiffness, laws.normal_stiffness, (7715.0, 0.3434)),
    ]


def _best_seconds(action: Callable[[], object], repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        best = min(best, time.perf_counter() - start)
    return best


def law_speed_table(array_size: int, python_loop_size: int, repeats: int) -> pd.DataFrame:
    """Time every law three ways on the same inputs (after a warm-up call compiles them): evaluations
    per second of its numpy ufunc and of its njit kernel in a compiled loop over `array_size` values,
    and of its plain Python source over `python_loop_size` of them; the best of `repeats` runs."""
    rows = []
    values = np.geomspace(1.0, 1e8, array_size)
    small = values[:: max(1, values.size // python_loop_size)][:python_loop_size]
    out = np.empty_like(values)
    for name, kernel, ufunc, params in _cases():
        ufunc(values[:10], *params)
        _kernel_loop(kernel, values[:10], out[:10], *params)
        source = kernel.py_func
        t_ufunc = _best_seconds(lambda u=ufunc, p=params: u(values, *p), repeats)
        t_kernel = _best_seconds(lambda k=kernel, p=params: _kernel_loop(k, values, out, *p), repeats)
        t_python = _best_seconds(lambda s=source, p=params: [s(v, *p) for v in small], repeats)
        rate = {
            "ufunc": values.size / t_ufunc,
            "njit": values.size / t_kernel,
            "python": small.size / t_python,
        }
        rows.append(
            {
                "law": name,
                "ufunc_evals_per_s": rate["ufunc"],
                "njit_kernel_evals_per_s": rate["njit"],
                "python_evals_per_s": rate["python"],
                "njit_over_python": rate["njit"] / rate["python"],
                "ufunc_over_python": rate["ufunc"] / rate["python"],
                "njit_over_ufunc": rate["njit"] / rate["ufunc"],
                "array_size": values.size,
                "python_loop_size": small.size,
            }
        )
    return pd.DataFrame(rows)
