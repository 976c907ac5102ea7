"""What a study reports from its samples: summary.csv's rows (counts, invalid samples, truncations),
the lines on stderr about samples without an FS, and the tables and figures of a sampled study of FS
(P_f, convergence, sensitivities, the geometry's share). A grid study reports FS against its
parameters instead (`bbmc.sweep.parameters`)."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from bbmc.io import StageResult
from bbmc.sweep import design, figures, shares, statistics
from bbmc.sweep.config import Config
from bbmc.sweep.kinematic_model import kinematics_summary
from bbmc.sweep.models import ERROR, FS
from bbmc.sweep.outcomes import COUNTS, Outcomes, first_errors
from bbmc.sweep.ranges import Range
from bbmc.sweep.wedge_model import wedge_summary

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


@dataclass(frozen=True)
class Inputs:
    """The sampled inputs: (path, distribution) as the design samples them, the range of each path's
    key, and the truncated ones."""

    variables: list[design.Variable]
    ranges: dict[str, Range]
    truncated: dict[str, design.Truncated]


def unit_of(path: str) -> str:
    """The unit a key's name ends with (friction_deg: deg; tan_friction: 1)."""
    key = path.rsplit(".", 1)[-1]
    return next((unit for unit in UNIT_SUFFIXES if key.endswith(f"_{unit}")), "1")


def summary_rows(values: dict[str, float]) -> pd.DataFrame:
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
    """summary.csv of a scene_run study: the counts, the monitor's mean and spread, displacement stops;
    of a kinematics study: the counts, each mode's probability and its standard error."""
    valid = ~outcomes.excluded
    if config.base.kind == "kinematics":
        return summary_rows(
            {**outcomes.counts(), **kinematics_summary(config.base.model_dump(), samples, valid)}
        )
    values = samples.loc[valid, config.base.monitor].astype(float)
    stopped = samples.loc[valid, "stopped_by_displacement"].astype(float)
    return summary_rows(
        {
            **outcomes.counts(),
            f"mean_{config.base.monitor}": float(values.mean()),
            f"std_{config.base.monitor}": float(values.std()),
            "stopped_by_displacement": float(stopped.mean()),
        }
    )


def report_exclusions(
    table: pd.DataFrame,
    inputs: Inputs,
    messages: pd.Series,
    outcomes: Outcomes,
    say: Callable[[str], None],
    over: str = "P_f is",
) -> None:
    """One line each for the samples with impossible inputs, the invalid ones and the failed runs, if
    any; and one if more than `UNCOUNTED_WARNING` of the samples have no FS (`over`: what is counted
    over the others only)."""
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
            f"error; summary.csv, invalid_sample* rows); the first: {first_errors(messages[invalid], 1)[0]}"
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
            f"{100 * UNCOUNTED_WARNING:.0f} %) have no FS ({outcomes.text()}): {over} over the "
            f"{n - uncounted} others only"
        )


def no_valid_sample_text(messages: pd.Series, outcomes: Outcomes, store: Path) -> str:
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
    wedge = config.base.kind == "wedge"  # its reasons counted, not listed sample by sample
    invalid = wedge_summary(samples, outcomes) if wedge else invalid_rows(samples, outcomes, inputs)
    try:
        stats = statistics.failure_statistics(fs, outcomes.failed, outcomes.impossible, outcomes.invalid)
    except ValueError as error:  # fewer than two valid samples: nothing to summarise but the counts
        say(f"no statistics: {error}")
        summary = pd.concat([summary_rows(outcomes.counts()), invalid], ignore_index=True)
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
        "summary": pd.concat(
            [summary_rows(stats), invalid, truncation_rows(inputs.truncated)], ignore_index=True
        ),
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
