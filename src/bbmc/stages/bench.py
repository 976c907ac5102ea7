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
bandwidth.csv / bandwidth_limit.csv: the memory bandwidth (a STREAM triad on 1 and every thread), the
bytes one sub-contact update moves and the most updates per second that bandwidth carries
(`bbmc.bench.bandwidth`).
wedge_cost.csv: one deterministic wedge, the combination analysis of 10 joint sets and the probabilistic
wedge samples per second, on one core, beside issue 35's marks (`bbmc.bench.wedge_cost`).
engine3d.csv: the 3D engine's sub-contact updates per second per core beside the 2D engine's, its
2-thread speed-up and bitwise check, a 3D wedge's strength reduction, and that a 2D run imports nothing of
3D (`bbmc.bench.engine3d`).
support_cost.csv: where a scene has no support, this engine's time per step against the last commit
before support elements; and the design search of a scene's `design:` section, its trials and wall
time (`bbmc.bench.support_cost`).

machine.csv: the processor, its cores, the memory, the Python, numpy and numba versions, the run's start
and end (UTC) and each section's wall time (`bbmc.bench.machine`).

laws.csv: for each law, evaluations per second as a numpy ufunc over an array, inside an njit kernel
loop, and as the plain Python source in a Python loop (its calls to other laws still run compiled, so
the python column flatters plain Python for the composite laws), plus the ratios between them.

Every section of the config is optional: a section left out is skipped, with a line saying so, and
`bbmc bench --only scaling,engine_cost` runs only the sections named (its results folder then holds only
theirs). Wall-clock numbers depend on the machine and its load; the ratios, measured in the same run, are
what to compare across machines.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Annotated, Literal

import pandas as pd
from matplotlib.figure import Figure
from pydantic import Field, model_validator

from bbmc.bench import tradeoff as to
from bbmc.bench.bandwidth import bandwidth_table, limit_table, slope_counts
from bbmc.bench.economy import economy_table
from bbmc.bench.engine3d import engine3d_table
from bbmc.bench.engine_cost import engine_cost_table
from bbmc.bench.fos_cost import fos_cost_table
from bbmc.bench.kinematics_cost import kinematics_cost_table
from bbmc.bench.law_speed import law_speed_table
from bbmc.bench.machine import machine_table, now_utc
from bbmc.bench.mobilized_cost import mobilized_cost_table
from bbmc.bench.paper_scenes import ShearScene, SlopeScene
from bbmc.bench.rockmass_cost import bridge_cost, rockmass_cost
from bbmc.bench.scaling import scaling_figure, scaling_table
from bbmc.bench.support_cost import support_cost_table
from bbmc.bench.sweep_cost import sweep_cost_table
from bbmc.bench.wedge_cost import wedge_cost_table
from bbmc.config import ConfigError, InputFile, Section
from bbmc.io import StageResult

NAME = "bench"
SECTIONS = (
    "tradeoff",
    "economy",
    "scaling",
    "engine_cost",
    "fos",
    "mobilized",
    "sweep",
    "laws",
    "rockmass",
    "bandwidth",
    "support",
    "kinematics",
    "wedge",
    "engine3d",
)


Fraction = Annotated[float, Field(gt=0, le=1)]
Interval = Annotated[int, Field(ge=1, le=100_000)]
SubContacts = Annotated[int, Field(ge=1, le=64)]
Repeats = Annotated[int, Field(ge=1, le=100)]
SceneName = Literal["shear", "slope_barton_bandis", "slope_constant"]
EVERY_SCENE: list[SceneName] = ["shear", "slope_barton_bandis", "slope_constant"]


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
    scenes: list[SceneName] = Field(min_length=1)
    knobs: KnobValues
    reference: Accurate
    reference_check: Accurate
    target_error: Annotated[float, Field(gt=0, lt=1)]
    repeats: Repeats
    figure_error_floor: Annotated[float, Field(gt=0, lt=1)] = 1e-7


class Economies(Section):
    repeats: Repeats
    scenes: list[SceneName] = Field(default_factory=lambda: list(EVERY_SCENE), min_length=1)


class Scaling(Section):
    block_counts: list[Annotated[int, Field(ge=10, le=1_000_000)]] = Field(min_length=2)
    steps: Annotated[int, Field(ge=10, le=1_000_000)]
    repeats: Repeats
    memory_limit_GB: Annotated[float, Field(gt=0)]
    # each size on each of these thread counts (the first the reference of the speed-up)
    threads: list[Annotated[int, Field(ge=1, le=1024)]] = Field(default_factory=lambda: [1], min_length=1)


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


class RockMassCost(Section):
    """A rock mass of about 10,000 blocks (`bbmc.bench.rockmass_cost`): its generation time, and the
    engine's cost per step with its bridges and cuts as intact rock against plain joints."""

    spacing_scale: Annotated[float, Field(gt=0)] = 1.0  # 1: about 10,000 blocks
    steps: Annotated[int, Field(ge=10, le=1_000_000)]
    repeats: Repeats


class Bandwidth(Section):
    """The memory bandwidth by a STREAM triad, and the bytes per sub-contact update on the scaling
    section's slope of about `blocks` blocks (`bbmc.bench.bandwidth`)."""

    array_MB: Annotated[float, Field(ge=1, le=10_000)]  # each of the triad's three arrays, 1e6 bytes
    repeats: Repeats
    blocks: Annotated[int, Field(ge=10, le=1_000_000)] = 10_000


class SupportCost(Section):
    """Where a scene has no support: this engine against the last commit before support elements;
    and the design search of a scene with a `design:` section (`bbmc.bench.support_cost`)."""

    commit: Annotated[str, Field(min_length=4, max_length=40, pattern=r"^[0-9a-fA-F]+$")]
    block_counts: list[Annotated[int, Field(ge=10, le=1_000_000)]] = Field(min_length=1)
    steps: Annotated[int, Field(ge=10, le=1_000_000)]
    repeats: Repeats
    design_scene: InputFile


class KinematicsCost(Section):
    """Set finding and kinematic tallies of `readings` readings, the compass at 1 deg for
    `compass_readings`, and Monte Carlo draws per second (`bbmc.bench.kinematics_cost`)."""

    readings: Annotated[int, Field(ge=100, le=10_000_000)] = 100_000
    compass_readings: Annotated[int, Field(ge=10, le=5_000)] = 300
    samples: Annotated[int, Field(ge=1000, le=100_000_000)] = 1_000_000
    repeats: Repeats


class WedgeCost(Section):
    """One deterministic wedge of `wedge_config` (over `calls` calls), the combination analysis of ten
    sets against its slope, and `samples` probabilistic samples of the wedge study `study_config`, in
    `repeats` fresh processes on one thread (`bbmc.bench.wedge_cost`)."""

    wedge_config: InputFile
    study_config: InputFile
    calls: Annotated[int, Field(ge=1, le=1_000_000)] = 1000
    samples: Annotated[int, Field(ge=100, le=10_000_000)] = 1_000_000
    repeats: Repeats


class Engine3dCost(Section):
    """The 3D engine's rate at each of `block_counts` beside the 2D engine's, over `steps` steps, its
    2-thread speed-up at `threads_blocks`, the 3D wedge's strength reduction, in `repeats` alternating
    fresh processes (`bbmc.bench.engine3d`)."""

    block_counts: list[Annotated[int, Field(ge=1, le=1_000_000)]] = Field(min_length=1)
    steps: Annotated[int, Field(ge=1, le=1_000_000)]
    threads_blocks: Annotated[int, Field(ge=1, le=1_000_000)]
    repeats: Repeats


class Config(Section):
    """The paper's scenes and the sections to run (each optional, at least one given)."""

    shear_config: InputFile  # the paper's scenes, exactly as bbmc shear and bbmc slope build them
    slope_config: InputFile
    tradeoff: Tradeoff | None = None
    economy: Economies | None = None
    scaling: Scaling | None = None
    engine_cost: EngineCost | None = None
    fos: FosCost | None = None
    mobilized: MobilizedCost | None = None
    sweep: SweepCost | None = None
    laws: Laws | None = None
    rockmass: RockMassCost | None = None
    bandwidth: Bandwidth | None = None
    support: SupportCost | None = None
    kinematics: KinematicsCost | None = None
    wedge: WedgeCost | None = None
    engine3d: Engine3dCost | None = None
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120

    @model_validator(mode="after")
    def _something_to_run(self) -> Config:
        if all(getattr(self, name) is None for name in SECTIONS):
            raise ValueError(f"no section to run: give at least one of {', '.join(SECTIONS)}")
        return self


class PaperScenes:
    """The paper's scenes by name, each built once and shared by the sections that run it."""

    def __init__(self, config: Config) -> None:
        self.config, self.made = config, {}

    def __call__(self, names: list[SceneName]) -> list:
        c = self.config
        make = {
            "shear": lambda: ShearScene(c.shear_config),
            "slope_barton_bandis": lambda: SlopeScene(c.slope_config, "barton_bandis"),
            "slope_constant": lambda: SlopeScene(c.slope_config, "constant"),
        }
        for name in names:
            if name not in self.made:
                self.made[name] = make[name]()
        return [self.made[name] for name in names]


Part = tuple[dict[str, pd.DataFrame], dict[str, Figure]]


def tradeoff_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    t = config.tradeoff
    values = t.knobs.model_dump()
    reference, check = (a.model_dump(exclude_none=True) for a in (t.reference, t.reference_check))
    parts = [to.scene_tradeoff(s, values, reference, check, t.repeats, progress) for s in scenes(t.scenes)]
    trade = pd.concat([p[0] for p in parts], ignore_index=True)
    tables = {
        "tradeoff": trade,
        "tradeoff_readings": pd.concat([p[1] for p in parts], ignore_index=True),
        "recommended": to.recommended(trade, t.target_error),
    }
    return tables, {"tradeoff": to.tradeoff_figure(trade, t.figure_error_floor, config.figure_dpi)}


def economy_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    e = config.economy
    return {"economy": economy_table(scenes(e.scenes), e.repeats, progress)}, {}


def scaling_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    s = config.scaling
    growth = scaling_table(
        s.block_counts,
        s.steps,
        s.repeats,
        s.memory_limit_GB * 1e9,
        config.slope_config,
        progress=progress,
        threads=s.threads,
    )
    return {"scaling": growth}, {"scaling": scaling_figure(growth, config.figure_dpi)}


def engine_cost_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    e = config.engine_cost
    cost = engine_cost_table(
        e.commit, e.block_counts, e.steps, e.repeats, config.slope_config, config.shear_config, progress
    )
    return {"engine_cost": cost}, {}


def fos_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    return {"fos_cost": fos_cost_table(config.slope_config, config.fos.variants, progress)}, {}


def mobilized_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    m = config.mobilized
    table = mobilized_cost_table(m.sub_contacts, m.repeats, m.update_intervals, m.stress_changes, progress)
    return {"mobilized_cost": table}, {}


def sweep_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    w = config.sweep
    table = sweep_cost_table(w.le_samples, w.dem_samples, w.repeats, config.slope_config, progress)
    return {"sweep_cost": table}, {}


def laws_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    progress("joint laws' throughput")
    laws_config = config.laws
    table = law_speed_table(laws_config.array_size, laws_config.python_loop_size, laws_config.repeats)
    return {"laws": table}, {}


def rockmass_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    settings = config.rockmass
    progress("rock mass: generation and the cost of bridges per step")
    generation = rockmass_cost(settings.repeats, settings.spacing_scale)
    steps = bridge_cost(settings.spacing_scale, settings.steps, settings.repeats)
    plain = steps[1]["seconds_per_step"]
    rows = [
        {"quantity": "blocks", "value": generation["blocks"], "unit": "1"},
        {"quantity": "traces", "value": generation["traces"], "unit": "1"},
        {"quantity": "generation_time", "value": generation["seconds"], "unit": "s"},
        {"quantity": "seconds_per_step_bridges", "value": steps[0]["seconds_per_step"], "unit": "s"},
        {"quantity": "seconds_per_step_plain_joints", "value": plain, "unit": "s"},
        {"quantity": "bridges_over_plain", "value": steps[0]["seconds_per_step"] / plain, "unit": "1"},
    ]
    return {"rockmass_cost": pd.DataFrame(rows)}, {}


def bandwidth_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    b = config.bandwidth
    progress("memory bandwidth: STREAM triad on 1 and every thread; bytes per sub-contact update")
    triad = bandwidth_table(b.array_MB, b.repeats)
    limit = limit_table(triad, slope_counts(b.blocks, config.slope_config))
    return {"bandwidth": triad, "bandwidth_limit": limit}, {}


def support_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    c = config.support
    table = support_cost_table(
        c.commit, c.block_counts, c.steps, c.repeats, config.slope_config, config.shear_config,
        c.design_scene, progress,
    )  # fmt: skip
    return {"support_cost": table}, {}


def kinematics_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    k = config.kinematics
    return {"kinematics_cost": kinematics_cost_table(k.readings, k.compass_readings, k.samples, k.repeats,
                                                     progress)}, {}  # fmt: skip


def wedge_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    w = config.wedge
    table = wedge_cost_table(w.wedge_config, w.study_config, w.calls, w.samples, w.repeats, progress)
    return {"wedge_cost": table}, {}


def engine3d_part(config: Config, scenes: PaperScenes, progress: Callable[[str], None]) -> Part:
    e = config.engine3d
    table = engine3d_table(e.block_counts, e.steps, e.threads_blocks, e.repeats, str(config.slope_config),
                           progress)  # fmt: skip
    return {"engine3d": table}, {}


PARTS = {
    "tradeoff": tradeoff_part,
    "economy": economy_part,
    "scaling": scaling_part,
    "engine_cost": engine_cost_part,
    "fos": fos_part,
    "mobilized": mobilized_part,
    "sweep": sweep_part,
    "laws": laws_part,
    "rockmass": rockmass_part,
    "bandwidth": bandwidth_part,
    "support": support_part,
    "kinematics": kinematics_part,
    "wedge": wedge_part,
    "engine3d": engine3d_part,
}


def selected(config: Config, only: list[str] | None) -> list[str]:
    """The sections to run, in the config's order: those `only` names (every one must be a section the
    config gives: `ConfigError` otherwise), or all the config gives."""
    if only is None:
        return [name for name in SECTIONS if getattr(config, name) is not None]
    unknown = [name for name in only if name not in SECTIONS]
    if unknown:
        raise ConfigError(f"--only: unknown section '{unknown[0]}'; the sections are {', '.join(SECTIONS)}")
    missing = [name for name in only if getattr(config, name) is None]
    if missing:
        raise ConfigError(f"--only: the config has no section '{missing[0]}'")
    return [name for name in SECTIONS if name in only]


def run(
    config: Config, progress: Callable[[str], None] = lambda _: None, only: list[str] | None = None
) -> StageResult:
    """The sections of the config (or those of `only`), in the order of `SECTIONS`."""
    sections = selected(config, only)
    if only is None:
        for name in SECTIONS:
            if name not in sections:
                progress(f"section '{name}' is not in the config: skipped")
    tables, figures, scenes = {}, {}, PaperScenes(config)
    started, seconds = now_utc(), {}
    for name in sections:
        start = time.perf_counter()
        part_tables, part_figures = PARTS[name](config, scenes, progress)
        seconds[name] = time.perf_counter() - start
        tables |= part_tables
        figures |= part_figures
    tables["machine"] = machine_table(started, now_utc(), seconds)
    return StageResult(tables=tables, figures=figures)
