"""A parameter study's report: FS against each grid parameter, with its spread over the realizations.

A grid study (`sampling.method: grid`) sets its parameters by design, so it reports neither a
probability of failure nor rank correlations (a grid's points are not draws of a distribution, and a
seed has no order): it gives, per grid point, the FS of every realization run there
(`fs_against_parameter.csv`, `fs_against_parameter.png`). With `sampling.realizations` the same draws
of the variables (a rock mass's seed) are run at every grid point (`bbmc.sweep.design.
grid_realizations_table`), so the line of one realization across the grid shows the parameter's own
effect on that rock mass, and the band the spread of the joint geometry.

Per grid point, over its valid runs (those with an FS): the least, median, largest and mean FS, the
runs, the valid ones, those without an FS (invalid, failed or impossible: `excluded`) and the valid
ones with FS < 1 (`below_one`). A point whose runs all lack an FS has NaN there.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from bbmc import plots  # noqa: F401  (selects the Agg backend before any figure is drawn)
from bbmc.io import StageResult
from bbmc.sweep.config import Config
from bbmc.sweep.models import FS
from bbmc.sweep.outcomes import Outcomes
from bbmc.sweep.report import Inputs, invalid_rows, summary_rows, truncation_rows, unit_of

COLUMNS = ("runs", "valid", "excluded", "below_one", "fs_min", "fs_median", "fs_max", "fs_mean")
MOST_LINES = 20  # at most this many realizations are drawn as lines of their own
POINT_LINES = 12  # at most this many grid points are printed one line each
COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:olive")


def fs_by_point(samples: pd.DataFrame, axes: list[str], outcomes: Outcomes) -> pd.DataFrame:
    """One row per grid point, in grid order: its parameters' values and `COLUMNS` over its runs."""
    valid = ~outcomes.excluded
    fs = np.where(valid, samples[FS].to_numpy(dtype=float), np.nan)
    frame = samples[axes].assign(fs=fs, valid=valid, excluded=~valid, below_one=valid & (fs < 1.0))
    table = frame.groupby(axes, sort=False).agg(
        runs=("fs", "size"),
        valid=("valid", "sum"),
        excluded=("excluded", "sum"),
        below_one=("below_one", "sum"),
        fs_min=("fs", "min"),
        fs_median=("fs", "median"),
        fs_max=("fs", "max"),
        fs_mean=("fs", "mean"),
    )
    return table.reset_index()


def axis_label(path: str) -> str:
    """A grid path as an axis label: its last key without the unit suffix, and the unit
    ("blocks.0.rock_mass.profile.benches.face_angle_deg" -> "face angle [deg]"); a key without a unit
    suffix gets [-]."""
    key, unit = path.rsplit(".", 1)[-1], unit_of(path)
    name = key[: -len(unit) - 1] if unit != "1" else key
    return f"{name.replace('_', ' ')} [{unit if unit != '1' else '-'}]"


def _point_text(row: pd.Series, axes: list[str]) -> str:
    where = ", ".join(f"{path.rsplit('.', 1)[-1]} {row[path]:g}" for path in axes)
    if row["valid"] == 0:
        return f"{where}: no FS ({int(row['excluded'])} of {int(row['runs'])} runs without one)"
    spread = f" (min {row['fs_min']:.3f}, max {row['fs_max']:.3f})" if row["valid"] > 1 else ""
    excluded = f", {int(row['excluded'])} without an FS" if row["excluded"] else ""
    return f"{where}: FS {row['fs_median']:.3f}{spread} over {int(row['valid'])} runs{excluded}"


def _combinations(table: pd.DataFrame, others: list[str]) -> list[tuple[dict[str, float], pd.DataFrame]]:
    """The grid points of each combination of the other parameters' values, in grid order."""
    if not others:
        return [({}, table)]
    return [
        (dict(zip(others, key if isinstance(key, tuple) else (key,), strict=True)), group)
        for key, group in table.groupby(others, sort=False)
    ]


def _per_realization(samples: pd.DataFrame, fs: np.ndarray, fixed: dict[str, float], n: int) -> np.ndarray:
    """The FS of the runs at the fixed values of the other parameters, as (grid point, realization)."""
    rows = np.ones(len(samples), dtype=bool)
    for path, value in fixed.items():
        rows &= samples[path].to_numpy(dtype=float) == value
    return fs[rows].reshape(-1, n)


def fs_figure(
    table: pd.DataFrame, samples: pd.DataFrame, axes: list[str], realizations: int, fs: np.ndarray, dpi: int
) -> Figure:
    """FS against the first grid parameter (`fs`: each run's FS, NaN without one): per combination of
    the other parameters, the median over the realizations (markers and line), the band from the least
    to the largest FS, and each realization's own line (the same draws at every point; at most
    `MOST_LINES` of them); FS = 1 dashed."""
    x_path = axes[0]
    fig = Figure(figsize=(7.5, 4.8), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    for k, (fixed, group) in enumerate(_combinations(table, axes[1:])):
        colour = COLOURS[k % len(COLOURS)]
        name = ", ".join(f"{path.rsplit('.', 1)[-1]} = {value:g}" for path, value in fixed.items())
        suffix = f" ({name})" if name else ""
        x = group[x_path].to_numpy(dtype=float)
        if realizations > 1:
            band = f"least to largest FS over {realizations} realizations{suffix}"
            ax.fill_between(
                x, group["fs_min"], group["fs_max"], color=colour, alpha=0.18, linewidth=0, label=band
            )
            if realizations <= MOST_LINES:
                for r, line in enumerate(_per_realization(samples, fs, fixed, realizations).T):
                    label = "one realization across the grid" if r == 0 and k == 0 else None
                    ax.plot(x, line, color=colour, alpha=0.45, linewidth=0.8, label=label)
        median = "median FS" if realizations > 1 else "FS"
        ax.plot(x, group["fs_median"], color=colour, marker="o", linewidth=2.0, label=median + suffix)
    ax.axhline(1.0, color="k", linestyle="--", linewidth=1.2, label="FS = 1")
    values = np.unique(table[x_path].to_numpy(dtype=float))
    if len(values) <= POINT_LINES:  # few grid values: a tick at each
        ax.set_xticks(values, [f"{value:g}" for value in values])
    per_point = f", {realizations} realizations per point" if realizations > 1 else ""
    ax.set(
        xlabel=axis_label(x_path),
        ylabel="factor of safety FS [-]",
        title=f"FS against {axis_label(x_path).split(' [')[0]}{per_point}",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return fig


def grid_result(
    config: Config, samples: pd.DataFrame, inputs: Inputs, outcomes: Outcomes, say: Callable[[str], None]
) -> StageResult:
    """The tables and figure of a grid study of FS: samples, summary (the counts, invalid samples,
    truncations), fs_against_parameter (`fs_by_point`) and its chart; one line per grid point (the
    least and largest FS over all of them beyond `POINT_LINES` points)."""
    axes = [axis.path for axis in config.grid]
    table = fs_by_point(samples, axes, outcomes)
    fs = np.where(outcomes.excluded, np.nan, samples[FS].to_numpy(dtype=float))
    realizations = config.sampling.realizations or 1
    if len(table) <= POINT_LINES:
        for _, row in table.iterrows():
            say(_point_text(row, axes))
    else:
        low, high = table["fs_min"].idxmin(), table["fs_max"].idxmax()
        say(
            f"FS from {table.loc[low, 'fs_min']:.3f} ({_point_text(table.loc[low], axes).split(':')[0]}) to "
            f"{table.loc[high, 'fs_max']:.3f} ({_point_text(table.loc[high], axes).split(':')[0]}) over "
            f"{len(table)} grid points (fs_against_parameter.csv)"
        )
    summary = pd.concat(
        [
            summary_rows(outcomes.counts()),
            invalid_rows(samples, outcomes, inputs),
            truncation_rows(inputs.truncated),
        ],
        ignore_index=True,
    )
    return StageResult(
        tables={"samples": samples.reset_index(), "summary": summary, "fs_against_parameter": table},
        figures={
            "fs_against_parameter": fs_figure(table, samples, axes, realizations, fs, config.figure_dpi)
        },
    )
