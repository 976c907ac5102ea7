"""Figures of a probabilistic sweep: the tornado of rank correlations and the distribution of FS.

Drawn from the sweep's results only (FS per sample, `statistics.failure_statistics`, `statistics.spearman`).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from bbmc import plots  # noqa: F401  (selects the Agg backend before any figure is drawn)

POSITIVE, NEGATIVE = "tab:blue", "tab:red"


def tornado_figure(spearman: pd.Series, dpi: int) -> Figure:
    """Horizontal bars of Spearman's rho between each input and FS, largest |rho| on top, signed: an
    input whose increase raises FS points right (blue), one that lowers it points left (red)."""
    order = spearman.iloc[np.argsort(np.abs(spearman.to_numpy()), kind="stable")]  # smallest first: bottom
    names = [str(name) for name in order.index]
    values = order.to_numpy(dtype=float)
    label_width = max((len(name) for name in names), default=10)
    fig = Figure(figsize=(4.5 + 0.075 * label_width, 1.2 + 0.4 * len(names)), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    y = np.arange(len(names))
    ax.barh(y, values, color=[POSITIVE if v >= 0 else NEGATIVE for v in values], edgecolor="k", linewidth=0.4)
    for position, value in zip(y, values, strict=True):
        ax.text(
            value + (0.03 if value >= 0 else -0.03),
            position,
            f"{value:+.2f}",
            va="center",
            ha="left" if value >= 0 else "right",
            fontsize=8,
        )
    ax.axvline(0.0, color="k", linewidth=0.8)
    ax.set_yticks(y, names, fontsize=8)
    ax.set_xlim(-1.15, 1.15)
    ax.set_ylim(-0.6, len(names) - 0.4)
    ax.set_xlabel("Spearman rank correlation with FS, $\\rho_s$ (-)")
    ax.set_title("Sensitivity of FS to the inputs (tornado)")
    ax.grid(axis="x", alpha=0.3)
    return fig


def _edges_through_one(values: np.ndarray) -> np.ndarray:
    """Histogram bins of numpy's "auto" width (at most 80 over the range), with FS = 1 on an edge so
    no bin mixes failing and stable samples."""
    low, high = float(values[0]), float(values[-1])
    if high - low <= 1e-9 * max(1.0, abs(high)):  # one value (to rounding): one bin around it
        return np.array([low - 0.05, low + 0.05])
    width = max(np.diff(np.histogram_bin_edges(values, bins="auto"))[0], (high - low) / 80.0)
    first = 1.0 + math.floor((low - 1.0) / width) * width
    count = math.ceil((high - first) / width) + 1
    return first + width * np.arange(count + 1)


def _beta(value: float) -> str:
    return f"{value:+.2f}" if math.isfinite(value) else ("+inf" if value > 0 else "-inf")


def distribution_figure(fs: ArrayLike, stats: dict, dpi: int) -> Figure:
    """(a) Histogram of FS over the valid samples, failing samples (FS < 1) shaded; (b) empirical CDF
    of FS, whose height at FS = 1 is P_f. FS = 1 is marked on both; P_f with its Wilson 95 % interval
    and both reliability indices are in the title."""
    fs = np.asarray(fs, dtype=float).ravel()
    values = np.sort(fs[np.isfinite(fs)])
    fig = Figure(figsize=(11, 4.5), dpi=dpi, layout="constrained")
    ax_h, ax_c = fig.subplots(1, 2)
    edges = _edges_through_one(values)
    ax_h.hist(values[values >= 1.0], bins=edges, color=POSITIVE, alpha=0.8, label="FS $\\geq$ 1 (stable)")
    ax_h.hist(values[values < 1.0], bins=edges, color=NEGATIVE, alpha=0.8, label="FS < 1 (fails)")
    ax_h.set(xlabel="factor of safety FS (-)", ylabel="number of samples", title="(a) histogram of FS")
    ecdf = np.arange(1, values.size + 1) / values.size
    ax_c.step(values, ecdf, where="post", color="k", label="empirical CDF")
    p_f = stats["probability_of_failure"]
    ax_c.axhline(p_f, color=NEGATIVE, linestyle=":", linewidth=1.0, label=f"$P_f$ = {p_f:.3g}")
    ax_c.set(
        xlabel="factor of safety FS (-)",
        ylabel="cumulative probability P(FS $\\leq$ x) (-)",
        ylim=(0.0, 1.02),
        title="(b) cumulative distribution of FS",
    )
    for ax in (ax_h, ax_c):
        ax.axvline(1.0, color="k", linestyle="--", linewidth=1.2, label="FS = 1")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left" if ax is ax_h else "lower right")
    fig.suptitle(
        f"$P_f$ = {p_f:.4f} (95 % CI {stats['pf_ci_low']:.4f}-{stats['pf_ci_high']:.4f}),  "
        f"$\\beta_{{normal}}$ = {_beta(stats['reliability_index_normal'])},  "
        f"$\\beta_{{lognormal}}$ = {_beta(stats['reliability_index_lognormal'])}\n"
        f"mean FS = {stats['mean_fs']:.3f}, std = {stats['std_fs']:.3f};  "
        f"{values.size} valid of {stats['samples']} samples ({stats['failed_runs']} failed runs)",
        fontsize=10,
    )
    return fig
