"""A study, as `bbmc sweep` and `bbmc.api.study` run it: a probabilistic analysis or a parameter study of
a limit-equilibrium model or a block scene, on local processes or a dask.distributed cluster.

Everything that can be checked before any work is checked first (exit status 2, one line, nothing
written): the base (a scene file is validated and built as `bbmc run` would), a `scene_run` monitor's
name, every varying path, each distribution's parameters, that it is sampled within the range its key
accepts, and grid values within that range.

Every sample is accounted for: its `outcome` in samples.csv is `valid` (it has an FS, perhaps below 1:
a failure), `invalid` (its own scene is at fault, chiefly its geometry: `bbmc.sweep.models`),
`failed_run` (any other error) or `impossible_input` (not run). P_f is over the valid samples; a study
in which more than `bbmc.sweep.report.UNCOUNTED_WARNING` of the samples have no FS says so in one
line.

Its results, which `bbmc sweep` writes into <results>/sweep/<name>/ and `bbmc.api.study` returns:
samples.csv (each sample's inputs and outputs, its outcome, and its error where it has no output),
summary.csv (`quantity,value,unit`: the counts of valid, invalid, failed and impossible samples, each
invalid sample as a row `invalid_sample.<sample>.<key>` holding its seed (NaN for a study without a
`realization` variable; <key> is the key its error names, the reason: `blocks` for a block that finds
no equilibrium even elastically or blocks that overlap), the truncations; for a sampled study also the
FS at the mean inputs, mean and standard deviation of FS, probability of failure with its 95 %
interval, reliability indices), and provenance.json. A sampled study adds (`bbmc.sweep.report`)
convergence.csv and convergence.png (P_f and mean FS against the number of samples; not for a crossed
design), sensitivity.csv (Spearman rank correlation of each input with FS; Sobol indices for a
saltelli design; a realization's seed, which has no order, is not ranked), fs_distribution.png,
tornado.png, and for a crossed design geometry_share.csv (`bbmc.sweep.shares`). A grid study adds
fs_against_parameter.csv and .png (`bbmc.sweep.parameters`) instead: its points are set, not drawn.
The finished batches stay in <progress root>/<name>.progress/<study>/ (one folder per distinct study),
so that running the same study again runs only what is missing. A study in which no sample gave a
result raises `NoValidSampleError` (exit status 4) and writes nothing.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
from pydantic import BaseModel

from bbmc.config import ConfigError, read_yaml, validate
from bbmc.dem.model import build_model
from bbmc.dem.monitors import column_name
from bbmc.io import StageResult
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.schema import Scene
from bbmc.slope import safety
from bbmc.slope.config import load_paper_slope
from bbmc.sweep import design, figures, parameters
from bbmc.sweep.config import Config, Kinematics, Planar, Toppling, Wedge
from bbmc.sweep.kinematic_model import KinematicsModel
from bbmc.sweep.models import ERROR, FS, OUTCOME, PlanarModel, SceneModel, TopplingModel, get_path
from bbmc.sweep.outcomes import IMPOSSIBLE, Outcomes, one_line
from bbmc.sweep.ranges import Range, impossible_inputs, key_range
from bbmc.sweep.report import (
    Inputs,
    fs_result,
    invalid_rows,
    no_valid_sample_text,
    report_exclusions,
    run_summary,
    truncation_rows,
)
from bbmc.sweep.runner import Model, run_batches, warm_engine
from bbmc.sweep.wedge_model import WedgeModel

if TYPE_CHECKING:
    from distributed import Client

STORE_VERSION = "2"  # in the batches' folder name: raised when the same study's results change


class NoValidSampleError(Exception):
    """No sample of the study gave a result (every run failed or had impossible inputs): the message
    gives the counts and the first distinct errors, a few lines (exit status 4)."""


def _scene_tree(config: Config) -> dict:
    """The base scene: the scene file, or the paper's slope built by `bbmc.slope.safety`."""
    base = config.base
    if base.scene is not None:
        return read_yaml(base.scene)
    return safety.reduction_scene(*load_paper_slope(base.slope_config), base.joint_model)


def model_of(config: Config, tree: dict | None) -> Model:
    """The model each sample runs (`tree`: the base scene, for a scene base)."""
    base = config.base
    if isinstance(base, Planar):
        return PlanarModel(base.model_dump())
    if isinstance(base, Toppling):
        return TopplingModel(base.model_dump())
    if isinstance(base, Kinematics):
        return KinematicsModel(base.model_dump())
    if isinstance(base, Wedge):
        return WedgeModel(base)
    return SceneModel(tree, str(base.scene or base.slope_config), base.kind, base.monitor)


def check_scene(config: Config, config_path: Path, tree: dict) -> None:
    """The base scene validated and built as `bbmc run` does (ConfigError naming the scene and its
    key), and a `scene_run` monitor one of the history's columns (ConfigError naming 'base.monitor')."""
    base = config.base
    source = Path(base.scene or base.slope_config)
    typed = base.scene is not None  # else the paper's slope, built from a config already checked
    model = build_model(validate(tree, Scene, str(source), source.parent, typed=typed), source)
    if base.kind == "scene_run":
        columns = ["step", "time_s", *(column_name(spec) for spec in model.monitors)]
        if base.monitor not in columns:
            close = difflib.get_close_matches(base.monitor, columns, n=1)
            hint = f"did you mean '{close[0]}'?" if close else f"its columns: {', '.join(columns)}"
            raise ConfigError(
                f"{config_path}: key 'base.monitor': '{base.monitor}' is not a column of the scene's "
                f"history.csv ({hint})"
            )


def _entries(config: Config) -> list[tuple[str, str]]:
    """(key of the entry in the study, its path) of every variable and grid axis."""
    return [(f"variables.{k}", v.path) for k, v in enumerate(config.variables)] + [
        (f"grid.{k}", a.path) for k, a in enumerate(config.grid)
    ]


def check_paths(config: Config, config_path: Path, tree: dict | None) -> dict[str, Range]:
    """Every varying path exists in the base and holds a number (ConfigError naming the entry
    otherwise); returns the range each path's key accepts (`bbmc.sweep.ranges`)."""
    schema: type[BaseModel] = Scene if tree is not None else type(config.base)
    tree = config.base.model_dump() if tree is None else tree
    ranges = {}
    for entry, path in _entries(config):
        try:
            value = get_path(tree, path)
        except KeyError as missing:
            raise ConfigError(
                f"{config_path}: key '{entry}.path': '{path}' is not in the base (no {missing})"
            ) from None
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{config_path}: key '{entry}.path': '{path}' is not a number")
        ranges[path] = key_range(schema, tree, path)
    return ranges


def inputs_of(config: Config, config_path: Path, ranges: dict[str, Range]) -> Inputs:
    """Each variable's distribution, truncated to its key's range unless `truncate: false`; grid values
    checked against the range. ConfigError naming the entry for meaningless parameters, a sampled key
    that takes whole numbers, or a distribution with almost none of its probability in the range."""
    for k, axis in enumerate(config.grid):
        outside = [v for v in axis.values if not ranges[axis.path].contains(v)]
        if outside:
            raise ConfigError(
                f"{config_path}: key 'grid.{k}.values': {outside[0]:g} is outside the range "
                f"'{axis.path}' accepts ({ranges[axis.path]})"
            )
    variables, truncated = [], {}
    for k, v in enumerate(config.variables):
        where, accepted = f"{config_path}: key 'variables.{k}", ranges[v.path]
        if v.distribution == "realization":
            if not accepted.integer or accepted.low < 0:
                raise ConfigError(f"{where}.distribution': a realization draws seeds: '{v.path}' is no seed")
            variables.append((v.path, design.marginal("realization")))
            continue
        if accepted.integer:
            raise ConfigError(f"{where}.path': '{v.path}' takes whole numbers: vary it with a grid")
        try:
            dist = design.marginal(v.distribution, **v.parameters())
        except ValueError as error:
            raise ConfigError(f"{where}': {error}") from None
        try:
            cut = design.truncation(dist, accepted.low, accepted.high)
        except ValueError as error:
            raise ConfigError(f"{where}': {error}: '{v.path}' accepts {accepted} only") from None
        if cut is not None and v.truncate:
            truncated[v.path] = cut
            dist = cut
        variables.append((v.path, dist))
    return Inputs(variables, ranges, truncated)


def design_of(config: Config, config_path: Path, inputs: Inputs) -> tuple[pd.DataFrame, dict | None]:
    """Every sample's inputs, made up front from the seed, and SALib's problem for a saltelli design."""
    s = config.sampling
    axes = [(a.path, a.values) for a in config.grid]
    try:
        if s.method == "grid" and s.realizations is not None:
            corr = config.correlation
            correlation = (*corr.between, corr.rho) if corr else None
            return design.grid_realizations_table(
                axes, inputs.variables, s.realizations, s.seed, correlation
            ), None
        if s.method == "grid":
            return design.grid_table(axes), None
        if s.method == "saltelli":
            return design.saltelli_table(inputs.variables, s.samples, s.seed)
        corr = config.correlation
        correlation = (*corr.between, corr.rho) if corr else None
        if s.realizations is not None:
            geometry = {v.path for v in config.variables if v.is_geometry}
            groups = [
                [(p, d) for p, d in inputs.variables if (p in geometry) == side] for side in (True, False)
            ]
            table = design.crossed_table(*groups, s.realizations, s.samples, s.method, s.seed, correlation)
            return table[[path for path, _ in inputs.variables]], None
        return design.sample_table(inputs.variables, s.samples, s.method, s.seed, correlation), None
    except ValueError as error:
        raise ConfigError(f"{config_path}: key 'sampling': {error}") from None


def study_key(config: Config, tree: dict | None) -> str:
    """A digest of everything that decides the samples' results (config, base scene and the version of
    the batches' contents), naming the folder of finished batches: a changed study never reuses
    another's batches."""
    text = STORE_VERSION + json.dumps(config.model_dump(mode="json"), sort_keys=True)
    if tree is not None:
        text += json.dumps(tree, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class _Where:
    """Where a study's batches run (`scheduler`: an address or a `distributed.Client`; else `workers`
    local processes), and its progress: the runner's reports passed on, and lines of its own at the
    last count."""

    def __init__(
        self, scheduler: str | Client | None, workers: int | None, progress: ProgressCallback, total: int
    ) -> None:
        self.scheduler, self.workers, self.progress = scheduler, workers, progress
        self.done, self.total = 0, total

    def report(self, news: Progress) -> None:
        self.done = news.done
        self.progress(news)

    def say(self, text: str) -> None:
        self.progress(Progress(self.done, self.total, "samples", text))

    def batches(self) -> tuple:
        """run_batches' arguments after the batch size."""
        return self.scheduler, self.workers, self.report


def _run_samples(
    model: Model,
    table: pd.DataFrame,
    impossible: pd.Series,
    store: Path,
    config: Config,
    where: _Where,
) -> pd.DataFrame:
    """Every sample with possible inputs run (resuming from `store`), the others kept with their error,
    in sample order."""
    possible = impossible == ""
    ran = (
        run_batches(model, table[possible], store, config.batch_size, *where.batches())
        if possible.any()
        else pd.DataFrame(index=table.index[:0])
    )
    skipped = table[~possible].assign(**{ERROR: impossible[~possible], OUTCOME: IMPOSSIBLE})
    return pd.concat([ran, skipped]).sort_index().rename_axis("sample")


def fs_at_mean_inputs(model: Model, inputs: Inputs, store: Path, where: _Where) -> float:
    """FS with each variable at the mean of the distribution it is sampled from (truncated: the
    truncated mean), the others at the base's values; run like a sample, kept in `store`. NaN, with a
    line on stderr, if the run fails."""
    means = pd.DataFrame(
        [
            {
                path: float(dist.mean())
                for path, dist in inputs.variables
                if not isinstance(dist, design.Realizations)
            }
        ],
        index=pd.RangeIndex(1, name="sample"),
    )
    problem = impossible_inputs(means, inputs.ranges).iloc[0]
    result = (
        means.assign(**{ERROR: problem})
        if problem
        else run_batches(model, means, store / "mean_inputs", 1, where.scheduler, 1)
    )
    error = str(result[ERROR].fillna("").iloc[0])
    if error:
        where.say(f"the FS at the mean inputs could not be found: {one_line(error)}")
        return math.nan
    fs = float(result[FS].iloc[0])
    where.say(f"FS at the mean inputs: {fs:.3f}")
    return fs


def run(
    config: Config,
    config_path: Path,
    progress_root: Path,
    scheduler: str | Client | None = None,
    workers: int | None = None,
    progress: ProgressCallback = ignore,
) -> StageResult:
    """Check, design, run (resuming from `progress_root`), summarise and draw the study. `scheduler`: a
    dask scheduler's address or a `distributed.Client`; else `workers` local processes (default every
    core). `progress` is told each batch done and each line the command prints (unit "samples")."""
    tree = (
        None if isinstance(config.base, Planar | Toppling | Kinematics | Wedge) else _scene_tree(config)
    )  # read once
    if tree is not None:
        check_scene(config, config_path, tree)
    inputs = inputs_of(config, config_path, check_paths(config, config_path, tree))
    table, problem = design_of(config, config_path, inputs)
    where = _Where(scheduler, workers, progress, len(table))
    for path, cut in inputs.truncated.items():
        if cut.probability_cut >= 1e-6:
            where.say(
                f"{path} sampled from its distribution truncated to {inputs.ranges[path]}, which leaves out "
                f"{figures.probability_text(cut.probability_cut)} of its probability (summary.csv)"
            )
    model = model_of(config, tree)
    store = progress_root / f"{config.name}.progress" / study_key(config, tree)
    if tree is not None:  # the block engine: compiled once per machine, not by each worker at once
        warm_engine(scheduler, where.say)
    grid = config.sampling.method == "grid"
    scattered = isinstance(config.base, Wedge) and config.base.scattered  # no one wedge at the mean
    at_mean = None
    if (
        config.base.kind not in ("scene_run", "kinematics")
        and config.variables
        and not grid
        and not scattered
    ):
        at_mean = fs_at_mean_inputs(model, inputs, store, where)
    checks = impossible_inputs(table, inputs.ranges)
    samples = _run_samples(model, table, checks, store, config, where)
    messages = samples[ERROR].fillna("").astype(str)
    outcomes = Outcomes.of(samples)
    if outcomes.excluded.all():
        raise NoValidSampleError(no_valid_sample_text(messages, outcomes, store))
    over = "each grid point's FS is" if grid else "P_f is"
    report_exclusions(table, inputs, messages, outcomes, where.say, over)
    if config.base.kind in ("scene_run", "kinematics"):
        summary = [
            run_summary(config, samples, outcomes),
            invalid_rows(samples, outcomes, inputs),
            truncation_rows(inputs.truncated),
        ]
        return StageResult(
            tables={"samples": samples.reset_index(), "summary": pd.concat(summary, ignore_index=True)}
        )
    if grid:
        return parameters.grid_result(config, samples, inputs, outcomes, where.say)
    return fs_result(config, samples, inputs, outcomes, at_mean, problem, where.say)
