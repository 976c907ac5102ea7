"""`bbmc bench`: throughput of the joint laws, measured side by side in one run (results/bench/).

For each law: evaluations per second as a numpy ufunc over an array, inside an njit kernel loop, and as
the plain Python source in a Python loop (its calls to other laws still run compiled, so the
python column flatters plain Python for the composite laws), plus the ratios between them. Wall-clock
numbers depend on the machine and its load; the ratios, measured in the same run, are what to
compare across machines.

engine.csv: the block engine's steps and sub-contact updates per second on generated brick walls of
increasing size, and how its cost per step grows with the number of blocks (`bbmc.dem.benchmark`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Annotated

import numba
import numpy as np
import pandas as pd
from pydantic import Field

from bbmc import laws, units
from bbmc.config import Section
from bbmc.dem.benchmark import engine_table
from bbmc.io import StageResult
from bbmc.laws import stiffness, strength

NAME = "bench"


class EngineBench(Section):
    block_counts: list[Annotated[int, Field(ge=10, le=1_000_000)]] = Field(min_length=1)
    sub_contacts_per_edge: int = Field(ge=1, le=64)
    steps: int = Field(ge=10, le=1_000_000)
    repeats: int = Field(ge=1, le=100)


class Config(Section):
    array_size: int = Field(ge=1_000, le=100_000_000)
    python_loop_size: int = Field(ge=100, le=10_000_000)
    repeats: int = Field(ge=1, le=100)
    engine: EngineBench


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


def run(config: Config) -> StageResult:
    """Time every law three ways on the same inputs (after a warm-up call compiles them)."""
    rows = []
    values = np.geomspace(1.0, 1e8, config.array_size)
    small = values[:: max(1, values.size // config.python_loop_size)][: config.python_loop_size]
    out = np.empty_like(values)
    for name, kernel, ufunc, params in _cases():
        ufunc(values[:10], *params)
        _kernel_loop(kernel, values[:10], out[:10], *params)
        source = kernel.py_func
        t_ufunc = _best_seconds(lambda u=ufunc, p=params: u(values, *p), config.repeats)
        t_kernel = _best_seconds(lambda k=kernel, p=params: _kernel_loop(k, values, out, *p), config.repeats)
        t_python = _best_seconds(lambda s=source, p=params: [s(v, *p) for v in small], config.repeats)
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
    engine = config.engine
    table = engine_table(
        sorted(engine.block_counts), engine.sub_contacts_per_edge, engine.steps, engine.repeats
    )
    return StageResult(tables={"laws": pd.DataFrame(rows), "engine": table})
