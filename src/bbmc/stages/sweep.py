"""`bbmc sweep`: a probabilistic analysis or parameter study of a limit-equilibrium model or a block
scene (`bbmc.sweep`), on local processes or a dask.distributed cluster.

Everything that can be checked before any work is checked first (exit status 2, one line, nothing
written): the base (a scene file is validated and built as `bbmc run` would), a `scene_run` monitor's
name, every varying path, each distribution's parameters, that it is sampled within the range its key
accepts, and grid values within that range.

Every sample is accounted for: its `outcome` in samples.csv is `valid` (it has an FS, perhaps below 1:
a failure), `invalid` (its own scene is at fault, chiefly its geometry: `bbmc.sweep.models`),
`failed_run` (any other error) or `impossible_input` (not run). P_f is over the valid samples; a study
in which more than `UNCOUNTED_WARNING` of the samples have no FS says so in one line on stderr.

Writes into <results>/sweep/<name>/: samples.csv (each sample's inputs and outputs, its outcome, and
its error where it has no output), summary.csv (`quantity,value,unit`: the counts of valid, invalid,
failed and impossible samples, each invalid sample as a row `invalid_sample.<sample>.<key>` holding its
seed (NaN for a study without a `realization` variable; <key> is the key its error names, the reason:
`blocks` for a block that finds no equilibrium even elastically or blocks that overlap), the FS at the
mean inputs, mean and standard deviation of FS, probability of failure with its 95 % interval,
reliability indices, the truncations),
convergence.csv and convergence.png (P_f and mean FS against the number of samples; not for a grid or
a crossed design), sensitivity.csv (Spearman rank correlation of each input with FS; Sobol indices for
a saltelli design; a realization's seed, which has no order, is not ranked), fs_distribution.png,
tornado.png, for a crossed design geometry_share.csv (`bbmc.sweep.shares`), and provenance.json. The
finished batches stay in <results>/sweep/<name>.progress/<study>/ (one folder per distinct study), so
that running the same command again runs only what is missing. A study in which no sample gave a
result raises `NoValidSampleError` (exit status 4) and writes nothing.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
from pydantic import BaseModel

from bbmc.config import ConfigError, read_yaml, validate
from bbmc.dem.model import build_model
from bbmc.dem.monitors import column_name
from bbmc.io import StageResult
from bbmc.scene.schema import Scene
from bbmc.slope import safety
from bbmc.slope.config import load_paper_slope
from bbmc.sweep import design, figures, shares, statistics
from bbmc.sweep.config import Config, Planar, Toppling
from bbmc.sweep.models import (
    ERROR,
    FS,
    OUTCOME,
    PlanarModel,
    SceneModel,
    TopplingModel,
    get_path,
)
from bbmc.sweep.outcomes import COUNTS, IMPOSSIBLE, Outcomes, first_errors, one_line
from bbmc.sweep.ranges import Range, impossible_inputs, key_range
from bbmc.sweep.runner import Model, run_batches

NAME = "sweep"
__all__ = ["NAME", "Config", "NoValidSampleError", "run"]

# Unit suffixes of keys (longest first), for the unit column of a truncation's bounds in summary.csv.
UNIT_SUFFIXES = (
    "MPa_per_mm",
    "per_mm",
    "kN_m3",
    "kg_m3",
    "m_s2",
    "m_s",
    "kPa",
    "MPa",
    "deg",
    "kN",
    "mm",
    "m",
)
UNCOUNTED_WARNING = 0.10  # a study with more than this fraction of samples without an FS says so
STORE_VERSION = "2"  # in the batches' folder name: raised when the same study's results change


class NoValidSampleError(Exception):
    """No sample of the study gave a result (every run failed or had impossible inputs): the message
    gives the counts and the first distinct errors, a few lines (exit status 4)."""


@dataclass(frozen=True)
class Inputs:
    """The sampled inputs: (path, distribution) as the design samples them, the range of each path's
    key, and the truncated ones."""

    variables: list[design.Variable]
    ranges: dict[str, Range]
    truncated: dict[str, design.Truncated]


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
    if s.method == "grid":
        return design.grid_table([(a.path, a.values) for a in config.grid]), None
    try:
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


def unit_of(path: str) -> str:
    """The unit a key's name ends with (friction_deg: deg; tan_friction: 1)."""
    key = path.rsplit(".", 1)[-1]
    return next((unit for unit in UNIT_SUFFIXES if key.endswith(f"_{unit}")), "1")


def _rows(values: dict[str, float]) -> pd.DataFrame:
    return pd.DataFrame([(k, v, "1") for k, v in values.items()], columns=["quantity", "value", "unit"])


def truncation_rows(truncated: dict[str, design.Truncated]) -> pd.DataFrame:
    """summary.csv's record of each truncation: truncation.<path>.min and .max (the finite bounds, in
    the key's unit) and truncation.<path>.probability_cut (the part of the distribution left out)."""
    rows = []
    for path, cut in truncated.items():
        for end, bound in (("min", cut.low), ("max", cut.high)):
            if math.isfinite(bound):
                rows.append((f"truncation.{path}.{end}", bound, unit_of(path)))
        rows.append((f"truncation.{path}.probability_cut", cut.probability_cut, "1"))
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def invalid_rows(samples: pd.DataFrame, outcomes: Outcomes, inputs: Inputs) -> pd.DataFrame:
    """summary.csv's row of each invalid sample: `invalid_sample.<sample>.<key>`, <key> the key its
    error names (its reason; "scene" if it names none), the value its realization's seed (NaN in a
    study without a `realization` variable)."""
    seeds = [path for path, dist in inputs.variables if isinstance(dist, design.Realizations)]
    rows = []
    for sample, row in samples[outcomes.invalid].iterrows():
        named = re.search(r"key '([^']+)'", str(row[ERROR]))
        seed = float(row[seeds[0]]) if seeds else math.nan
        rows.append((f"invalid_sample.{sample}.{named.group(1) if named else 'scene'}", seed, "seed"))
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def run_summary(config: Config, samples: pd.DataFrame, outcomes: Outcomes) -> pd.DataFrame:
    """summary.csv of a scene_run study: the counts, the monitor's mean and spread, displacement stops."""
    valid = ~outcomes.excluded
    values = samples.loc[valid, config.base.monitor].astype(float)
    stopped = samples.loc[valid, "stopped_by_displacement"].astype(float)
    return _rows(
        {
            **outcomes.counts(),
            f"mean_{config.base.monitor}": float(values.mean()),
            f"std_{config.base.monitor}": float(values.std()),
            "stopped_by_displacement": float(stopped.mean()),
        }
    )


def _run_samples(
    model: Model,
    table: pd.DataFrame,
    impossible: pd.Series,
    store: Path,
    config: Config,
    scheduler: str | None,
    workers: int | None,
    say: Callable[[str], None],
) -> pd.DataFrame:
    """Every sample with possible inputs run (resuming from `store`), the others kept with their error,
    in sample order."""
    possible = impossible == ""
    ran = (
        run_batches(model, table[possible], store, config.batch_size, scheduler, workers, say)
        if possible.any()
        else pd.DataFrame(index=table.index[:0])
    )
    skipped = table[~possible].assign(**{ERROR: impossible[~possible], OUTCOME: IMPOSSIBLE})
    return pd.concat([ran, skipped]).sort_index().rename_axis("sample")


def fs_at_mean_inputs(
    model: Model, inputs: Inputs, store: Path, scheduler: str | None, say: Callable[[str], None]
) -> float:
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
        else run_batches(model, means, store / "mean_inputs", 1, scheduler, 1)
    )
    error = str(result[ERROR].fillna("").iloc[0])
    if error:
        say(f"the FS at the mean inputs could not be found: {one_line(error)}")
        return math.nan
    fs = float(result[FS].iloc[0])
    say(f"FS at the mean inputs: {fs:.3f}")
    return fs


def _report_exclusions(
    table: pd.DataFrame, inputs: Inputs, messages: pd.Series, outcomes: Outcomes, say: Callable[[str], None]
) -> None:
    """One line each for the samples with impossible inputs, the invalid ones and the failed runs, if
    any; and one if more than `UNCOUNTED_WARNING` of the samples have no FS."""
    n = len(messages)
    impossible, errors = outcomes.impossible, outcomes.failed
    if impossible.any():
        outside = {path: int((~inputs.ranges[path].contains(table[path])).sum()) for path in table.columns}
        detail = ", ".join(f"{path} outside {inputs.ranges[path]}: {k}" for path, k in outside.items() if k)
        say(
            f"{int(impossible.sum())} of {n} samples have impossible inputs ({detail}): not run, counted in "
            "summary.csv (impossible_samples); the statistics are over the valid samples"
        )
    invalid = outcomes.invalid
    if invalid.any():
        say(
            f"{int(invalid.sum())} of {n} samples are invalid, their own scene at fault (samples.csv, column "
            f"error; summary.csv, invalid_sample.*); the first: {first_errors(messages[invalid], 1)[0]}"
        )
    if errors.any():
        say(
            f"{int(errors.sum())} of {n} samples failed to run (samples.csv, column error); the first: "
            f"{first_errors(messages[errors], 1)[0]}"
        )
    uncounted = int(outcomes.excluded.sum())
    if uncounted > UNCOUNTED_WARNING * n:
        say(
            f"warning: {uncounted} of {n} samples ({100 * uncounted / n:.0f} %, more than "
            f"{100 * UNCOUNTED_WARNING:.0f} %) have no FS ({outcomes.text()}): P_f is over the "
            f"{n - uncounted} others only"
        )


def _no_valid_sample(messages: pd.Series, outcomes: Outcomes, store: Path) -> str:
    return "\n".join(
        [
            f"no sample gave a result of {len(messages)}: {outcomes.text()}; the first errors:",
            *(f"  {line}" for line in first_errors(messages)),
            f"every sample's error is in {store}/batch_*.csv",
        ]
    )


def fs_result(
    config: Config,
    samples: pd.DataFrame,
    inputs: Inputs,
    outcomes: Outcomes,
    at_mean: float | None,
    problem: dict | None,
    say: Callable[[str], None],
) -> StageResult:
    """The tables and figures of a study of FS: summary (with the FS at the mean inputs, none for a
    grid, and the truncations), convergence (not for a grid, whose order is not a random one),
    sensitivities, the FS distribution."""
    fs = samples[FS].to_numpy(dtype=float)
    invalid = invalid_rows(samples, outcomes, inputs)
    try:
        stats = statistics.failure_statistics(fs, outcomes.failed, outcomes.impossible, outcomes.invalid)
    except ValueError as error:  # fewer than two valid samples: nothing to summarise but the counts
        say(f"no statistics: {error}")
        summary = pd.concat([_rows(outcomes.counts()), invalid], ignore_index=True)
        return StageResult(tables={"samples": samples.reset_index(), "summary": summary})
    stats = (
        {key: stats[key] for key in COUNTS}
        | ({} if at_mean is None else {"fs_at_mean_inputs": at_mean})
        | {key: value for key, value in stats.items() if key not in COUNTS}
    )
    p_f, low, high = (
        figures.probability_text(stats[key]) for key in ("probability_of_failure", "pf_ci_low", "pf_ci_high")
    )
    say(
        f"P_f = {p_f} (95 % CI {low} to {high}), mean FS {stats['mean_fs']:.3f}"
        + (f", FS at the mean inputs {at_mean:.3f}" if at_mean is not None and math.isfinite(at_mean) else "")
    )
    tables = {
        "samples": samples.reset_index(),
        "summary": pd.concat([_rows(stats), invalid, truncation_rows(inputs.truncated)], ignore_index=True),
    }
    drawn = {"fs_distribution": figures.distribution_figure(fs, stats, config.figure_dpi)}
    if config.sampling.realizations is not None:  # its order is not a random one: no convergence
        tables |= shares.tables(fs, outcomes.excluded, config.sampling, tables["summary"], say)
    elif config.sampling.method != "grid":
        convergence = statistics.convergence(fs, outcomes.excluded, statistics.convergence_counts(len(fs)))
        tables["convergence"] = convergence
        drawn["convergence"] = figures.convergence_figure(convergence, stats, config.figure_dpi)
    seeds = {path for path, dist in inputs.variables if isinstance(dist, design.Realizations)}
    ranked = [path for path in inputs.ranges if path not in seeds]  # a seed has no order: not ranked
    try:
        if not ranked:
            raise ValueError("a seed has no order, and nothing else varies")
        ranks = statistics.spearman(samples[ranked], fs)
    except ValueError as error:  # fewer than 3 valid samples
        say(f"no sensitivities: {error}")
        return StageResult(tables=tables, figures=drawn)
    sensitivity = ranks.rename("spearman_rho").to_frame()
    if problem is not None:
        if outcomes.excluded.any():
            say("no Sobol indices: Saltelli's estimators need every sample, and some gave no FS")
        else:
            sensitivity = sensitivity.join(statistics.sobol_indices(problem, fs, config.sampling.seed))
    tables["sensitivity"] = sensitivity.rename_axis("input").reset_index()
    drawn["tornado"] = figures.tornado_figure(ranks, config.figure_dpi)
    return StageResult(tables=tables, figures=drawn)


def run(
    config: Config,
    config_path: Path,
    progress_root: Path,
    scheduler: str | None = None,
    workers: int | None = None,
    say: Callable[[str], None] = lambda _: None,
) -> StageResult:
    """Check, design, run (resuming from `progress_root`), summarise and draw the study."""
    tree = None if isinstance(config.base, Planar | Toppling) else _scene_tree(config)  # read once
    if tree is not None:
        check_scene(config, config_path, tree)
    inputs = inputs_of(config, config_path, check_paths(config, config_path, tree))
    table, problem = design_of(config, config_path, inputs)
    for path, cut in inputs.truncated.items():
        if cut.probability_cut >= 1e-6:
            say(
                f"{path} sampled from its distribution truncated to {inputs.ranges[path]}, which leaves out "
                f"{figures.probability_text(cut.probability_cut)} of its probability (summary.csv)"
            )
    model = model_of(config, tree)
    store = progress_root / f"{config.name}.progress" / study_key(config, tree)
    at_mean = None
    if config.base.kind != "scene_run" and config.variables:
        at_mean = fs_at_mean_inputs(model, inputs, store, scheduler, say)
    checks = impossible_inputs(table, inputs.ranges)
    samples = _run_samples(model, table, checks, store, config, scheduler, workers, say)
    messages = samples[ERROR].fillna("").astype(str)
    outcomes = Outcomes.of(samples)
    if outcomes.excluded.all():
        raise NoValidSampleError(_no_valid_sample(messages, outcomes, store))
    _report_exclusions(table, inputs, messages, outcomes, say)
    if config.base.kind == "scene_run":
        summary = [
            run_summary(config, samples, outcomes),
            invalid_rows(samples, outcomes, inputs),
            truncation_rows(inputs.truncated),
        ]
        return StageResult(
            tables={"samples": samples.reset_index(), "summary": pd.concat(summary, ignore_index=True)}
        )
    return fs_result(config, samples, inputs, outcomes, at_mean, problem, say)
