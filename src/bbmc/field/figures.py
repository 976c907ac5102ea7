"""The figures of `bbmc joints`: each set's histograms with the fitted densities, and rose diagrams of
the dip directions and dips. Axes carry units; the chosen distribution is drawn bold, the other
candidates thin."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from bbmc import units
from bbmc.field import distributions as dist
from bbmc.field.analysis import SetFit
from bbmc.geometry.orientation import fisher_deviation_pdf
from bbmc.plots import COLOURS

STYLE = {"exponential": "tab:blue", "lognormal": "tab:orange", "gamma": "tab:green"}
HIDDEN = {0: "both ends seen", 1: "one end hidden", 2: "both ends hidden"}


def _candidates(ax, grid: np.ndarray, candidates: list[dist.Candidate], chosen: dist.Candidate) -> None:
    for candidate in candidates:
        bold = candidate is chosen
        ax.plot(
            grid,
            candidate.distribution.pdf(grid),
            color=STYLE[candidate.family],
            lw=2.2 if bold else 1.0,
            ls="-" if bold else "--",
            label=f"{candidate.family}{' (chosen)' if bold else ''}, AIC {candidate.aic:.1f}",
        )


def _spacing(ax, fit: SetFit, chosen: dist.Candidate) -> None:
    values = fit.spacings
    ax.hist(values, bins="auto", density=True, color="0.8", edgecolor="0.5", label=f"{values.size} spacings")
    grid = np.linspace(0.0, max(values.max(), fit.censored_tail or 0.0) * 1.05, 300)[1:]
    _candidates(ax, grid, fit.spacing, chosen)
    ax.set(xlabel="spacing normal to the set [m]", ylabel="density [1/m]")
    ax.set_title(f"{fit.survey.name}: spacing (Terzaghi factor {fit.spacing_factor:.3f})", fontsize=9)


def _orientation(ax, fit: SetFit) -> None:
    o = fit.orientation
    if o.from_dip_directions:
        angles = np.degrees(o.deviation)
        ax.hist(angles, bins="auto", density=True, color="0.8", edgecolor="0.5", label=f"{angles.size} poles")
        grid = np.linspace(0.0, max(angles.max() * 1.1, 1.0), 300)
        ax.plot(
            grid,
            fisher_deviation_pdf(grid * units.deg, o.fisher_k) * units.deg,
            color="k",
            lw=2,
            label=f"Fisher, K = {o.fisher_k:.1f}",
        )
        ax.set(xlabel="angle from the mean pole [deg]", ylabel="density [1/deg]")
        title = f"mean {np.degrees(o.dip):.1f}/{np.degrees(o.dip_direction):05.1f}"
    else:
        dips = np.degrees(fit.survey.dip)
        width = max(1.0, np.ceil(np.diff(np.histogram_bin_edges(dips, bins="auto"))[0]))
        bins = np.arange(np.floor(dips.min()) - 0.5, dips.max() + width, width)  # whole degrees per bin
        bins = np.unique(np.minimum(bins, 90.5))
        ax.hist(dips, bins=bins, density=True, color="0.8", edgecolor="0.5", label=f"{dips.size} dips")
        mean, std = np.degrees(o.dip), np.degrees(o.dip_std)
        grid = np.linspace(max(mean - 4 * std, 0.0), min(mean + 4 * std, 90.0), 300)
        density = np.exp(-0.5 * ((grid - mean) / std) ** 2) / (std * np.sqrt(2.0 * np.pi))
        ax.plot(grid, density, color="k", lw=2, label=f"normal, {mean:.1f} ± {std:.1f} deg")
        ax.set(xlabel="dip [deg]", ylabel="density [1/deg]")
        title = f"dip (dip direction {np.degrees(o.dip_direction):05.1f} given)"
    ax.set_title(f"{fit.survey.name}: orientation, {title}", fontsize=9)


def _trace_length(ax, fit: SetFit, chosen: dist.Candidate) -> None:
    lengths, ends = fit.survey.trace_length, fit.survey.censored_ends
    groups = [lengths[ends == k] for k in HIDDEN]
    bins = np.histogram_bin_edges(lengths, bins="auto")
    ax.hist(
        groups,
        bins=bins,
        stacked=True,
        density=True,
        color=["0.75", "0.55", "0.35"],
        edgecolor="0.3",
        label=[f"{HIDDEN[k]} ({g.size})" for k, g in zip(HIDDEN, groups, strict=True)],
    )
    grid = np.linspace(0.0, lengths.max() * 1.1, 300)[1:]
    _candidates(ax, grid, fit.trace_length, chosen)
    biased = grid * chosen.distribution.pdf(grid) / chosen.mean
    ax.plot(
        grid,
        biased,
        color=STYLE[chosen.family],
        lw=1.2,
        ls=":",
        label=f"{chosen.family} as the line meets traces, l f(l)/mean",
    )
    ax.set(xlabel="trace length [m] (seen; fitted curves: the whole traces)", ylabel="density [1/m]")
    ax.set_title(f"{fit.survey.name}: trace length", fontsize=9)


def histograms(fits: list[SetFit], chosen: dict[tuple[str, str], dist.Candidate], dpi: int) -> Figure:
    """One row per set: its normal spacings, orientations and trace lengths with the fitted densities;
    `chosen` maps (set, quantity) to the distribution written for it."""
    fig = Figure(figsize=(15, 3.8 * len(fits)), dpi=dpi, layout="constrained")
    axes = np.atleast_2d(fig.subplots(len(fits), 3))
    for row, fit in zip(axes, fits, strict=True):
        _spacing(row[0], fit, chosen[fit.survey.name, "spacing"])
        _orientation(row[1], fit)
        _trace_length(row[2], fit, chosen[fit.survey.name, "trace_length"])
        for ax in row:
            ax.legend(fontsize=7)
            ax.grid(alpha=0.3)
    return fig


def _petals(ax, angles: np.ndarray, span_deg: float, width_deg: float, share, colour, label) -> float:
    """Petals of `width_deg` over 0 to `span_deg` holding the weights `share` of `angles` [rad]; the
    longest petal's length."""
    edges = np.radians(np.arange(0.0, span_deg + width_deg / 2, width_deg))
    counts, _ = np.histogram(angles, bins=edges, weights=share)
    ax.bar(
        edges[:-1],
        counts,
        width=np.radians(width_deg),
        align="edge",
        color=colour,
        alpha=0.55,
        edgecolor=colour,
        label=label,
    )
    return float(counts.max())


def rose(fits: list[SetFit], trend: float, section_azimuth: float, dpi: int) -> Figure:
    """Rose diagrams, Terzaghi-weighted: dip directions (10 deg petals) with the scanline's trend and the
    section's azimuth, and dips (5 deg petals). A set mapped without dip directions is a dashed ray at
    its given mean dip direction."""
    fig = Figure(figsize=(12, 6), dpi=dpi, layout="constrained")
    directions = fig.add_subplot(1, 2, 1, projection="polar")
    dips = fig.add_subplot(1, 2, 2, projection="polar")
    directions.set_theta_zero_location("N")
    directions.set_theta_direction(-1)
    dips.set_theta_zero_location("E")
    top = 0.0
    for colour, fit in zip(COLOURS, fits, strict=False):
        share = fit.weights / fit.weights.sum() * fit.count
        if fit.survey.dip_direction is not None:
            label = f"{fit.survey.name} ({fit.count})"
            top = max(top, _petals(directions, fit.survey.dip_direction, 360.0, 10.0, share, colour, label))
        _petals(dips, fit.survey.dip, 90.0, 5.0, share, colour, fit.survey.name)
    top = top or 1.0
    for fit, colour in zip(fits, COLOURS, strict=False):
        if fit.survey.dip_direction is None:
            direction = fit.orientation.dip_direction
            directions.plot(
                [direction, direction],
                [0, top],
                color=colour,
                ls="--",
                lw=2,
                label=f"{fit.survey.name} ({fit.count}, mean dip direction given)",
            )
    for angle, label, style in ((trend, "scanline trend", "r-"), (section_azimuth, "section azimuth", "g--")):
        directions.plot([angle, angle], [0, top], style, lw=1.5, label=label)
        directions.plot([angle + np.pi, angle + np.pi], [0, top], style, lw=1.5)
    directions.set_title("dip directions (Terzaghi-weighted counts)", fontsize=10)
    directions.legend(fontsize=7, loc="upper left", bbox_to_anchor=(-0.15, 1.12))
    dips.set_thetamin(0)
    dips.set_thetamax(90)
    dips.set_title("dips [deg from horizontal] (Terzaghi-weighted counts)", fontsize=10)
    dips.legend(fontsize=7, loc="lower right")
    return fig
