"""`bbmc bench`: what speed costs in accuracy on the paper's scenes, what the engine leaves out, how it
grows, and the joint laws' throughput; everything measured side by side in one run (results/bench/).

tradeoff.csv / tradeoff_readings.csv / recommended.csv / tradeoff.png: each solver knob varied alone on
the paper's scenes against a converged reference (`bbmc.bench.tradeoff`).
economy.csv: the gain of each piece of work the engine leaves out, and that it changes no number
(`bbmc.bench.economy`).
scaling.csv / scaling.png: time per step and peak memory on generated jointed slopes of growing size
(`bbmc.bench.scaling`).
engine_cost.csv: time per step of this engine against an earlier commit's on the scaling slope and the
shear box, in alternating fresh processes (`bbmc.bench.engine_cost`).
fos_cost.csv: trials, steps and wall time of each factor of safety the verification runs, and how far
it moves with one solver setting changed at a time (`bbmc.bench.fos_cost`).
mobilized_cost.csv: the full Barton-Bandis law's cost per sub-contact update against the peak-only
law's, and its error against update interval and stress-change trigger (`bbmc.bench.mobilized_cost`).
sweep_cost.csv: sweep samples per second (limit equilibrium) and per minute (DEM), the speed-up on 2
processes and on a 2-worker dask LocalCluster, and the overhead per task (`bbmc.bench.sweep_cost`).

laws.csv: for each law, evaluations per second as a numpy ufunc over an array, inside an njit kernel
loop, and as the plain Python source in a Python loop (its calls to other laws still run compiled, so
the python column flatters plain Python for the composite laws), plus the ratios between them.

Wall-clock numbers depend on the machine and its load; the ratios, measured in the same run, are what
to compare across machines.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Annotated, Literal

import numba
import numpy as np
import pandas as pd
from pydantic import Field

from bbmc import laws, units
from bbmc.bench import tradeoff as to
from bbmc.bench.economy import economy_table
from bbmc.bench.engine_cost import engine_cost_table
from bbmc.bench.fos_cost import fos_cost_table
from bbmc.bench.mobilized_cost import mobilized_cost_table
from bbmc.bench.paper_scenes import ShearScene, SlopeScene
from bbmc.bench.scaling import scaling_figure, scaling_table
from bbmc.bench.sweep_cost import sweep_cost_table
from bbmc.config import InputFile, Section
from bbmc.io import StageResult
from bbmc.laws import stiffness, strength

NAME = "bench"


Fraction = Annotated[float, Field(gt=0, le=1)]
Interval = Annotated[int, Field(ge=1, le=100_000)]
SubContacts = Annotated[int, Field(ge=1, le=64)]
Repeats = Annotated[int, Field(ge=1, le=100)]


class KnobValues(Section):
    """The values each knob takes, one knob at a time (the others at the scene's own settings)."""

    update_interval_steps: list[Interval] = Field(min_length=1)
    safety_factor: list[Fraction] = Field(min_length=1)
    sub_contacts_per_edge: list[SubContacts] = Field(min_length=1)
    damping: list[Annotated[float, Field(ge=0, lt=1)]] = Field(min_length=1)
    density_scaling: list[Annotated[float, Field(ge=1, le=10_000)]] = Field(min_length=1)
    law_update_stress_change: list[Annotated[float, Field(gt=0, le=10)]] = Field(min_length=1)


class Accurate(Section):
    """The accurate end of the knobs: the reference, or the overrides of its check."""

    update_interval_steps: Interval | None = None
    safety_factor: Fraction | None = None
    sub_contacts_per_edge: SubContacts | None = None


class Tradeoff(Section):
    scenes: list[Literal["shear", "slope_barton_bandis", "slope_constant"]] = Field(min_length=1)
    knobs: KnobValues
    reference: Accurate
    reference_check: Accurate
    target_error: Annotated[float, Field(gt=0, lt=1)]
    repeats: Repeats
    figure_error_floor: Annotated[float, Field(gt=0, lt=1)] = 1e-7


class Economies(Section):
    repeats: Repeats


class Scaling(Section):
    block_counts: list[Annotated[int, Field(ge=10, le=1_000_000)]] = Field(min_length=2)
    steps: Annotated[int, Field(ge=10, le=1_000_000)]
    repeats: Repeats
    memory_limit_GB: Annotated[float, Field(gt=0)]


class EngineCost(Section):
    """The engine against an earlier commit's, side by side (`bbmc.bench.engine_cost`)."""

    commit: Annotated[str, Field(min_length=4, max_length=40, pattern=r"^[0-9a-fA-F]+$")]
    block_counts: list[Annotated[int, Field(ge=10, le=1_000_000)]] = Field(min_length=1)
    steps: Annotated[int, Field(ge=10, le=1_000_000)]
    repeats: Repeats


class Laws(Section):
    array_size: int = Field(ge=1_000, le=100_000_000)
    python_loop_size: int = Field(ge=100, le=10_000_000)
    repeats: Repeats


class FosCost(Section):
    """Each variant is one change laid over every verification scene (`bbmc.bench.fos_cost`)."""

    variants: dict[str, dict] = Field(min_length=1)


class MobilizedCost(Section):
    """The full B-B law's cost per law update against the peak-only law's, and its update schedules'
    trade on a shear box (`bbmc.bench.mobilized_cost`)."""

    sub_contacts: int = Field(ge=1000, le=10_000_000)
    repeats: Repeats
    update_intervals: list[Annotated[int, Field(ge=1)]] = Field(min_length=1)
    stress_changes: list[Annotated[float, Field(gt=0)]] = Field(default_factory=list)


class SweepCost(Section):
    """Sweep throughput, speed-up on 2 processes and on a LocalCluster, task overhead
    (`bbmc.bench.sweep_cost`)."""

    le_samples: int = Field(ge=1000, le=100_000_000)
    dem_samples: int = Field(ge=2, le=10_000)
    repeats: Repeats


class Config(Section):
    shear_config: InputFile  # the paper's scenes, exactly as bbmc shear and bbmc slope build them
    slope_config: InputFile
    tradeoff: Tradeoff
    economy: Economies
    scaling: Scaling
    engine_cost: EngineCost
    fos: FosCost
    mobilized: MobilizedCost
    sweep: SweepCost
    laws: Laws
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120


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


def law_table(config: Laws) -> pd.DataFrame:
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
    return pd.DataFrame(rows)


def paper_scenes(config: Config) -> list:
    """The scenes the tradeoff and the economies run, in the config's order."""
    made = {
        "shear": lambda: ShearScene(config.shear_config),
        "slope_barton_bandis": lambda: SlopeScene(config.slope_config, "barton_bandis"),
        "slope_constant": lambda: SlopeScene(config.slope_config, "constant"),
    }
    return [made[name]() for name in config.tradeoff.scenes]


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """The trade, the economies, the scaling study and the laws' throughput."""
    t = config.tradeoff
    scenes = paper_scenes(config)
    values = t.knobs.model_dump()
    reference, check = (a.model_dump(exclude_none=True) for a in (t.reference, t.reference_check))
    parts = [to.scene_tradeoff(s, values, reference, check, t.repeats, progress) for s in scenes]
    trade = pd.concat([p[0] for p in parts], ignore_index=True)
    economies = economy_table(scenes, config.economy.repeats, progress)
    s = config.scaling
    growth = scaling_table(
        s.block_counts, s.steps, s.repeats, s.memory_limit_GB * 1e9, config.slope_config, progress=progress
    )
    e = config.engine_cost
    cost = engine_cost_table(
        e.commit, e.block_counts, e.steps, e.repeats, config.slope_config, config.shear_config, progress
    )
    fos = fos_cost_table(config.slope_config, config.fos.variants, progress)
    m = config.mobilized
    mobilized = mobilized_cost_table(
        m.sub_contacts, m.repeats, m.update_intervals, m.stress_changes, progress
    )
    w = config.sweep
    sweep = sweep_cost_table(w.le_samples, w.dem_samples, w.repeats, config.slope_config, progress)
    progress("joint laws' throughput")
    return StageResult(
        tables={
            "tradeoff": trade,
            "tradeoff_readings": pd.concat([p[1] for p in parts], ignore_index=True),
            "recommended": to.recommended(trade, t.target_error),
            "economy": economies,
            "scaling": growth,
            "engine_cost": cost,
            "fos_cost": fos,
            "mobilized_cost": mobilized,
            "sweep_cost": sweep,
            "laws": law_table(config.laws),
        },
        figures={
            "tradeoff": to.tradeoff_figure(trade, t.figure_error_floor, config.figure_dpi),
            "scaling": scaling_figure(growth, config.figure_dpi),
        },
    )
