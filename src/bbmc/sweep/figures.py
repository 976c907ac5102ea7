"""Figures of a probabilistic sweep: the tornado of rank correlations, the distribution of FS, and
P_f and mean FS against the number of samples.

Drawn from the sweep's results only (FS per sample, `statistics.failure_statistics`,
`statistics.spearman`, `statistics.convergence`).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.ticker import FixedLocator, FuncFormatter, MaxNLocator, NullLocator
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


TAIL_QUANTILE = 0.995  # where a long upper tail of FS is cut off the distribution figure
TAIL_STRETCH = 3.0  # a tail counts as long where the largest FS lies this many times further off


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


def probability_text(p: float) -> str:
    """A probability to 3 significant digits, 0 and 1 exactly ("0", "3.69e-05", "0.252", "1")."""
    return f"{p:.3g}" if 0.0 < p < 1.0 else f"{p:.0f}"


def _beta_from_pf(stats: dict) -> str:
    """beta = -Phi^-1(P_f), or its 95 % lower bound where P_f = 0 makes it infinite."""
    beta = stats["reliability_index_pf"]
    if beta == math.inf:
        return f"$\\beta_{{P_f}}$ $\\geq$ {stats['reliability_index_pf_lower_bound']:.2f}"
    return f"$\\beta_{{P_f}}$ = {_beta(beta)}"


def counts_text(stats: dict) -> str:
    """How many samples have an FS, and why the others have none."""
    return (
        f"{stats['valid_samples']} valid of {stats['samples']} samples ({stats['invalid_samples']} invalid, "
        f"{stats['failed_runs']} failed runs, {stats['impossible_samples']} impossible inputs)"
    )


def whole_sample_ticks(first: int, last: int) -> list[int]:
    """Ticks for a log axis of sample counts from `first` to `last`: whole samples only, at 1, 2 and 5
    per decade (over more than two decades, 1 alone) where at least three fall in the range, else at
    most 6 whole numbers evenly spread (one study of one count: that count)."""
    steps = (1, 2, 5) if last <= 100 * first else (1,)
    ticks = [m * 10**k for k in range(len(str(last))) for m in steps if first <= m * 10**k <= last]
    if len(ticks) >= 3:
        return ticks
    spread = MaxNLocator(nbins=5, integer=True).tick_values(first, last)
    return sorted({int(t) for t in spread if first <= t <= last} | {first, last})


def drawn_range(values: np.ndarray) -> float:
    """The largest FS the figure's axes reach: the largest value, or where a long tail would squeeze the
    distribution into a corner (a largest value more than TAIL_STRETCH times as far from the least as
    the TAIL_QUANTILE is), that quantile; `values` sorted."""
    low, high = float(values[0]), float(values[-1])
    quantile = float(np.quantile(values, TAIL_QUANTILE))
    return quantile if high - low > TAIL_STRETCH * max(quantile - low, 1e-12) else high


def distribution_figure(fs: ArrayLike, stats: dict, dpi: int) -> Figure:
    """(a) Histogram of FS over the valid samples, failing samples (FS < 1) shaded; (b) empirical CDF
    of FS, whose height at FS = 1 is P_f. FS = 1 is marked on both; P_f with its Clopper-Pearson 95 %
    interval (3 significant digits: a P_f of 0 shows its upper bound), the reliability indices and,
    if given in `stats` (fs_at_mean_inputs), the FS at the mean inputs are in the title. A long upper
    tail (`drawn_range`) is left off both axes and counted in the histogram's legend."""
    fs = np.asarray(fs, dtype=float).ravel()
    values = np.sort(fs[np.isfinite(fs)])
    fig = Figure(figsize=(11, 4.5), dpi=dpi, layout="constrained")
    ax_h, ax_c = fig.subplots(1, 2)
    top = drawn_range(values)
    drawn = values[values <= top]
    edges = _edges_through_one(drawn)
    ax_h.hist(drawn[drawn >= 1.0], bins=edges, color=POSITIVE, alpha=0.8, label="FS $\\geq$ 1 (stable)")
    ax_h.hist(drawn[drawn < 1.0], bins=edges, color=NEGATIVE, alpha=0.8, label="FS < 1 (fails)")
    if drawn.size < values.size:
        beyond = values.size - drawn.size
        ax_h.plot(
            [], [], " ", label=f"not drawn: {beyond:,} samples with FS > {top:.3g} (up to {values[-1]:.3g})"
        )
    ax_h.set(xlabel="factor of safety FS (-)", ylabel="number of samples", title="(a) histogram of FS")
    ax_h.yaxis.set_major_locator(MaxNLocator(integer=True))  # whole samples
    ax_h.set_ylim(top=ax_h.get_ylim()[1] * 1.35)  # headroom: the legend above the tallest bar
    ecdf = np.arange(1, values.size + 1) / values.size
    ax_c.step(values, ecdf, where="post", color="k", label="empirical CDF")
    if drawn.size < values.size:
        ax_c.set_xlim(edges[0], edges[-1])
    p_f = stats["probability_of_failure"]
    ax_c.axhline(p_f, color=NEGATIVE, linestyle=":", linewidth=1.0, label=f"$P_f$ = {probability_text(p_f)}")
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
    at_mean = stats.get("fs_at_mean_inputs", math.nan)
    fig.suptitle(
        f"$P_f$ = {probability_text(p_f)} (95 % CI {probability_text(stats['pf_ci_low'])}"
        f"–{probability_text(stats['pf_ci_high'])}),  {_beta_from_pf(stats)},  "
        f"$\\beta_{{normal}}$ = {_beta(stats['reliability_index_normal'])},  "
        f"$\\beta_{{lognormal}}$ = {_beta(stats['reliability_index_lognormal'])}\n"
        + (f"FS at the mean inputs = {at_mean:.3f};  " if math.isfinite(at_mean) else "")
        + f"mean FS = {stats['mean_fs']:.3f}, std = {stats['std_fs']:.3f};  {counts_text(stats)}",
        fontsize=10,
    )
    return fig


def convergence_figure(table: pd.DataFrame, stats: dict, dpi: int) -> Figure:
    """(a) P_f over the first n samples with its Clopper-Pearson 95 % band, (b) mean FS with its 95 %
    band (mean -+ 1.96 sigma / sqrt(n)), both against n on a log axis with ticks at whole samples
    (`statistics.convergence`); the whole study's value dotted on each; the title says how many samples
    have an FS (`counts_text`: `stats` is `statistics.failure_statistics`')."""
    n = table["samples"].to_numpy(dtype=float)
    ticks = whole_sample_ticks(int(n[0]), int(n[-1]))
    fig = Figure(figsize=(11, 4.2), dpi=dpi, layout="constrained")
    ax_p, ax_m = fig.subplots(1, 2)
    panels = (
        (ax_p, "probability_of_failure", "pf_ci", "$P_f$ (-)", "(a) probability of failure", NEGATIVE),
        (ax_m, "mean_fs", "mean_fs_ci", "mean FS (-)", "(b) mean factor of safety", POSITIVE),
    )
    for ax, column, band, ylabel, title, colour in panels:
        value = table[column].to_numpy(dtype=float)
        ax.fill_between(n, table[f"{band}_low"], table[f"{band}_high"], color=colour, alpha=0.2,
                        linewidth=0, label="95 % interval")  # fmt: skip
        ax.plot(n, value, color=colour, marker="o", markersize=3, label="over the first n samples")
        ax.axhline(value[-1], color="k", linestyle=":", linewidth=1.0, label=f"all {int(n[-1])} samples")
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_minor_locator(NullLocator())
        ax.xaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
        ax.set(xlabel="number of samples n (-)", ylabel=ylabel, title=title)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8, loc="upper right")
    ax_p.set_ylim(bottom=0.0)
    last = table.iloc[-1]
    fig.suptitle(
        f"Convergence: $P_f$ = {probability_text(last['probability_of_failure'])} (95 % CI "
        f"{probability_text(last['pf_ci_low'])}–{probability_text(last['pf_ci_high'])}), "
        f"mean FS = {last['mean_fs']:.3f} at n = {int(n[-1])}; {counts_text(stats)}",
        fontsize=10,
    )
    return fig
