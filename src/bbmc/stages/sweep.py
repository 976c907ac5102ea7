"""`bbmc sweep`: a probabilistic analysis or parameter study of a limit-equilibrium model or a block
scene (`bbmc.sweep`), on local processes or a dask.distributed cluster.

Writes into <results>/sweep/<name>/: samples.csv (each sample's inputs and outputs, its error if its
run failed), summary.csv (`quantity,value,unit`: mean and standard deviation of FS, probability of
failure with its 95 % interval, reliability indices, failed runs), sensitivity.csv (Spearman rank
correlation of each input with FS; Sobol indices for a saltelli design), fs_distribution.png,
tornado.png and provenance.json. The finished batches stay in <results>/sweep/<name>.progress/<study>/
(one folder per distinct study), so that running the same command again runs only what is missing.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.config import ConfigError, read_yaml
from bbmc.io import StageResult
from bbmc.slope import safety
from bbmc.slope.config import load_paper_slope
from bbmc.sweep import design, figures, statistics
from bbmc.sweep.config import Config, Planar, Toppling
from bbmc.sweep.models import ERROR, FS, PlanarModel, SceneModel, TopplingModel, get_path
from bbmc.sweep.runner import Model, run_batches

NAME = "sweep"
__all__ = ["NAME", "Config", "run"]


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


def check_paths(config: Config, config_path: Path, tree: dict | None) -> None:
    """Every varying path exists in the base: ConfigError naming the entry otherwise."""
    tree = config.base.model_dump() if tree is None else tree
    entries = [("variables", v.path) for v in config.variables] + [("grid", a.path) for a in config.grid]
    for k, (section, path) in enumerate(entries):
        index = k if section == "variables" else k - len(config.variables)
        try:
            value = get_path(tree, path)
        except KeyError as missing:
            raise ConfigError(
                f"{config_path}: key '{section}.{index}.path': '{path}' is not in the base (no {missing})"
            ) from None
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{config_path}: key '{section}.{index}.path': '{path}' is not a number")


def design_of(config: Config, config_path: Path) -> tuple[pd.DataFrame, dict | None]:
    """Every sample's inputs, made up front from the seed, and SALib's problem for a saltelli design."""
    s = config.sampling
    if s.method == "grid":
        return design.grid_table([(a.path, a.values) for a in config.grid]), None
    try:
        variables = [(v.path, design.marginal(v.distribution, **v.parameters())) for v in config.variables]
        if s.method == "saltelli":
            return design.saltelli_table(variables, s.samples, s.seed)
        corr = config.correlation
        correlation = (*corr.between, corr.rho) if corr else None
        return design.sample_table(variables, s.samples, s.method, s.seed, correlation), None
    except ValueError as error:
        raise ConfigError(f"{config_path}: key 'variables': {error}") from None


def study_key(config: Config, tree: dict | None) -> str:
    """A digest of everything that decides the samples' results (config and base scene), naming the
    folder of finished batches: a changed study never reuses another's batches."""
    text = json.dumps(config.model_dump(mode="json"), sort_keys=True)
    if tree is not None:
        text += json.dumps(tree, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _rows(values: dict[str, float]) -> pd.DataFrame:
    return pd.DataFrame([(k, v, "1") for k, v in values.items()], columns=["quantity", "value", "unit"])


def run_summary(config: Config, samples: pd.DataFrame, errors: np.ndarray) -> pd.DataFrame:
    """summary.csv of a scene_run study: the monitor's mean and spread, failed runs, displacement stops."""
    values = samples[config.base.monitor]
    stopped = samples["stopped_by_displacement"].astype(float)
    return _rows(
        {
            "samples": len(samples),
            "failed_runs": int(errors.sum()),
            f"mean_{config.base.monitor}": float(values.mean()),
            f"std_{config.base.monitor}": float(values.std()),
            "stopped_by_displacement": float(stopped.mean()),
        }
    )


def run(
    config: Config,
    config_path: Path,
    progress_root: Path,
    scheduler: str | None = None,
    workers: int | None = None,
    say: Callable[[str], None] = lambda _: None,
) -> StageResult:
    """Design, run (resuming from `progress_root`), summarise and draw the study."""
    tree = None if isinstance(config.base, Planar | Toppling) else _scene_tree(config)  # read once
    check_paths(config, config_path, tree)
    table, problem = design_of(config, config_path)
    store = progress_root / f"{config.name}.progress" / study_key(config, tree)
    samples = run_batches(model_of(config, tree), table, store, config.batch_size, scheduler, workers, say)
    errors = samples[ERROR].fillna("").astype(str).str.len().to_numpy() > 0
    if config.base.kind == "scene_run":
        return StageResult(
            tables={"samples": samples.reset_index(), "summary": run_summary(config, samples, errors)}
        )
    fs = samples[FS].to_numpy(dtype=float)
    try:
        stats = statistics.failure_statistics(fs, errors)
    except ValueError as error:  # fewer than two runs succeeded: nothing to summarise but the count
        say(f"no statistics: {error}")
        summary = _rows({"samples": len(samples), "failed_runs": int(errors.sum())})
        return StageResult(tables={"samples": samples.reset_index(), "summary": summary})
    ranks = statistics.spearman(samples[list(table.columns)], fs)
    sensitivity = ranks.rename("spearman_rho").to_frame()
    if problem is not None:
        sensitivity = sensitivity.join(statistics.sobol_indices(problem, fs, config.sampling.seed))
    return StageResult(
        tables={
            "samples": samples.reset_index(),
            "summary": _rows(stats),
            "sensitivity": sensitivity.rename_axis("input").reset_index(),
        },
        figures={
            "fs_distribution": figures.distribution_figure(fs, stats, config.figure_dpi),
            "tornado": figures.tornado_figure(ranks, config.figure_dpi),
        },
    )
