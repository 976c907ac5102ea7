"""Figures of a block run: the blocks before and after (their edges by label: joint sets, bridges,
cuts), and the monitored histories; of a factor of safety: its mechanism and its trials. The loads
beyond gravity are drawn where a scene has them: the phreatic surface as a blue line (level beyond its
end points, as the engine extends it) and the pseudo-static seismic load as an arrow above the blocks,
labelled with its k_h; bolts and anchors as lines coloured by their axial load (kN per bolt; ruptured
ones dotted)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.patheffects import withStroke

from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.dem.monitors import UNITS
from bbmc.dem.support_report import per_bolt_kN, support_lines
from bbmc.fos.result import StrengthReductionResult, Trial, bracket_decimals
from bbmc.rockmass.figure import edge_style, set_colours

SUFFIXES = sorted({unit for unit, _ in UNITS.values()}, key=len, reverse=True)


WATER_COLOUR = "tab:blue"
SEISMIC_COLOUR = "tab:purple"
SEISMIC_BAND = 0.14  # room above the blocks for the seismic arrow, a fraction of the scene's extent


def _outlines(model: Model, world: np.ndarray) -> list[np.ndarray]:
    return [world[a:b] for a, b in zip(model.vertex_start[:-1], model.vertex_start[1:], strict=True)]


def shaped_figure(points: np.ndarray, dpi: int) -> Figure:
    """A figure whose width follows the shape of the scene's `points` [m] (0.6 to 2 times as wide as
    high), 5 inches high, with room for a colour bar."""
    spread = np.ptp(points, axis=0)
    wide = min(max(spread[0] / max(spread[1], 1e-12), 0.6), 2.0)
    return Figure(figsize=(2.0 + 4.5 * wide, 5.0), dpi=dpi, layout="constrained")


def _frame(ax: Axes, model: Model, points: np.ndarray) -> None:
    """Axes limits around `points` [m], with a band above them for the seismic arrow if there is one."""
    low, high = points.min(axis=0), points.max(axis=0)
    extent = float(np.ptp(points, axis=0).max())
    pad = 0.05 * extent
    band = SEISMIC_BAND * extent if model.scene.seismic is not None else 0.0
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad + band)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def draw_loads(ax: Axes, model: Model, points: np.ndarray) -> None:
    """The phreatic surface across the axes (a blue line, in the legend) and the seismic load (an arrow
    in the band `_frame` leaves above `points`, labelled with k_h), where the scene has them."""
    if model.water_unit_weight > 0.0:
        surface = model.water_surface
        left, right = ax.get_xlim()
        inside = surface[(surface[:, 0] > left) & (surface[:, 0] < right), 0]
        x = np.concatenate([[left], inside, [right]])
        ax.plot(
            x,
            np.interp(x, surface[:, 0], surface[:, 1]),
            color=WATER_COLOUR,
            lw=1.8,
            zorder=4,
            label=f"phreatic surface (water {model.water_unit_weight / 1e3:.3g} kN/m³)",
        )
    seismic = model.scene.seismic
    if seismic is not None:
        extent = float(np.ptp(points, axis=0).max())
        sign = -1.0 if seismic.towards == "-x" else 1.0
        left, right = ax.get_xlim()
        y = points[:, 1].max() + (0.05 + 0.5 * SEISMIC_BAND) * extent
        length, margin = 0.15 * extent, 0.03 * (right - left)
        head = (left + margin, y) if sign < 0 else (right - margin, y)  # the label beside its tail
        tail = (head[0] - sign * length, y)
        ax.annotate(
            "",
            xy=head,
            xytext=tail,
            arrowprops={"arrowstyle": "-|>", "color": SEISMIC_COLOUR, "lw": 2.0, "mutation_scale": 15},
        )
        ax.annotate(
            f"  seismic k_h = {seismic.horizontal_coefficient:g} (towards {seismic.towards})  ",
            xy=tail,
            ha="left" if sign < 0 else "right",
            va="center",
            color=SEISMIC_COLOUR,
            fontsize="small",
        )


def draw_support(ax: Axes, model: Model, blocks: np.ndarray, support: np.ndarray, when: str = "") -> None:
    """The support elements at the blocks' positions, coloured by axial load (`when`: when it was read,
    as the colour bar's label says), with a colour bar up to the largest capacity."""
    lines, axial = support_lines(model.support, blocks, support)
    broken = support[:, L.BROKEN] > 0
    top = max(float(np.max(per_bolt_kN(model.support, support[:, L.CAP_AXIAL]), initial=0.0)), 1e-9)
    drawn = LineCollection(
        lines,
        array=axial,
        cmap="plasma",
        norm=Normalize(0.0, top),
        linewidths=2.5,
        path_effects=[withStroke(linewidth=4.5, foreground="k")],  # seen on any block colour
        linestyles=np.where(broken, ":", "-").tolist(),
    )
    ax.add_collection(drawn)
    ax.figure.colorbar(drawn, ax=ax, shrink=0.7, label=f"bolt load{when} [kN/bolt]; top: largest capacity")


def draw_edges(ax: Axes, model: Model, initial: np.ndarray, world: np.ndarray) -> None:
    """Every labelled edge at `world` by what it is (`edge_style`: each joint set's joints solid in a
    colour of their own and its rock bridges dashed in a dark shade of it; cuts dotted grey; the tension
    crack red), each kind in the legend. An edge two blocks share (where they start, `initial`) is
    drawn once, so that dashes meet."""
    labels = [model.label_names[k] for k in model.edge_label]
    colours = set_colours(model.label_names)
    segments: dict[str, list[np.ndarray]] = {}
    seen = set()
    for i, j in enumerate(model.vertex_next):
        key = tuple(sorted(map(tuple, np.round(initial[[i, j]], 6))))
        if labels[i] and key not in seen:
            seen.add(key)
            segments.setdefault(labels[i], []).append(world[[i, j]])
    for label in sorted(segments, key=lambda label: (label.startswith("bridge"), label)):
        ax.add_collection(LineCollection(segments[label], zorder=2.5, **edge_style(label, colours)))


def scene_figure(
    model: Model,
    initial: np.ndarray,
    final: np.ndarray,
    dof: np.ndarray,
    dpi: int,
    support: tuple[np.ndarray, np.ndarray] | None = None,
) -> Figure:
    """Block outlines at the start (dashed) and the end (solid); blocks with every degree of freedom
    fixed or prescribed are shaded; the labelled edges by what they are, joint set, bridge or cut, as
    `draw_edges` draws them; the water and seismic loads as `draw_loads` draws them; with `support`
    (the blocks' rows and the support's at the end), the bolts as `draw_support` draws them."""
    both = np.vstack([initial, final])
    fig = shaped_figure(both, dpi)
    ax = fig.subplots()
    held = np.all(dof == L.PRESCRIBED, axis=1)
    colours = np.where(held, "0.8", "white")
    ax.add_collection(
        PolyCollection(
            _outlines(model, final),
            facecolors=colours,
            edgecolors="k",
            linewidths=0.6,
            label="end of run (shaded: fixed)",
        )
    )
    ax.add_collection(
        PolyCollection(
            _outlines(model, initial),
            facecolors="none",
            edgecolors="0.45",
            linewidths=0.6,
            linestyles="--",
            label="start",
        )
    )
    draw_edges(ax, model, initial, final)
    _frame(ax, model, both)
    draw_loads(ax, model, both)
    if support is not None and len(model.support.names):
        draw_support(ax, model, *support)
    ax.set_title(f"{model.scene.name or 'scene'}: {len(model.block_names)} blocks")
    fig.legend(loc="outside lower center", ncols=3, fontsize="small")
    return fig


RATIO_UNIT = UNITS["unbalanced_force_ratio"][0]  # the unit of no other quantity: marks the ratio's column


def history_panel(ax: Axes, history: pd.DataFrame, column: str, target_ratio: float | None = None) -> None:
    """One monitored quantity against time (its column named <monitor>_<unit>); the unbalanced-force
    ratio on a log axis (its positive values), with `target_ratio`, the run's stop, as a labelled line."""
    unit = next((u for u in SUFFIXES if column.endswith("_" + u)), "")
    name = column.removesuffix("_" + unit)
    values = history[column]
    if unit == RATIO_UNIT:
        ax.set_yscale("log")
        values = values.where(values > 0)
        if target_ratio is not None:
            ax.axhline(target_ratio, color="tab:red", ls="--", lw=1.2, label=f"stop target {target_ratio:g}")
    ax.plot(history["time_s"], values, "-", color="tab:blue", label=name)
    ax.set_ylabel(f"{name} [{unit.replace('_per_', '/').replace('m_s', 'm/s')}]")
    ax.legend(loc="best", fontsize="small")
    ax.grid(alpha=0.3, which="both" if unit == RATIO_UNIT else "major")


def history_figure(history: pd.DataFrame, dpi: int, target_ratio: float | None = None) -> Figure:
    """Each monitored quantity against time, one panel each (`history_panel`; `target_ratio`: the
    scene's solver.stop.unbalanced_force_ratio); the step of each record is in history.csv."""
    columns = [c for c in history.columns if c not in ("step", "time_s")]
    fig = Figure(figsize=(8, 1.0 + 2.2 * max(len(columns), 1)), dpi=dpi, layout="constrained")
    axes = np.atleast_1d(fig.subplots(max(len(columns), 1), 1, sharex=True, squeeze=False)[:, 0])
    for ax, column in zip(axes, columns, strict=False):
        history_panel(ax, history, column, target_ratio)
    axes[-1].set_xlabel("time [s]")
    return fig


COLOUR_QUANTILE = 0.95  # mechanism.png: the colour scale's top, at most this quantile of the free area...
OUTLIER_RATIO = 2.0  # ... where the largest displacement is more than this many times that quantile
ARROW_SHARE = 0.15  # mechanism.png: the longest arrow, at most this fraction of the scene's extent
SHORTEST_ARROW = 0.05  # mechanism.png: arrows shorter than this fraction of the longest are left out


def colour_top(moved: np.ndarray, area: np.ndarray) -> float:
    """The top of the colour scale for the blocks' displacements `moved` (any unit): the largest, unless
    it is more than `OUTLIER_RATIO` times the displacement below which `COLOUR_QUANTILE` of the blocks'
    `area` lies, then that displacement; so one sliver that moves far does not set the scale."""
    order = np.argsort(moved)
    share = np.cumsum(area[order]) / max(float(np.sum(area)), 1e-300)
    quantile = float(moved[order][min(np.searchsorted(share, COLOUR_QUANTILE), len(order) - 1)])
    largest = float(moved.max(initial=0.0))
    return quantile if largest > OUTLIER_RATIO * quantile else largest


def _nice_length(largest: float) -> float:
    """The largest 1, 2 or 5 x 10^k not above `largest` (> 0): the scale arrow's length."""
    power = 10.0 ** math.floor(math.log10(largest))
    return max(step * power for step in (1.0, 2.0, 5.0) if step * power <= largest * (1 + 1e-12))


def _fitting_scale(centre: np.ndarray, shift: np.ndarray, low: np.ndarray, high: np.ndarray) -> float:
    """The largest length per unit of `shift` with which every arrow from `centre` ends within the box
    [low, high] (x and y)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        limit = np.where(shift > 0, high - centre, low - centre) / shift
    return float(np.min(limit[np.isfinite(limit)], initial=np.inf))


def _key_on_left(model: Model, points: np.ndarray) -> bool:
    """Whether the scale arrow goes in the upper left corner: the side away from the seismic arrow's
    label (on the side the load points to), else the side where the blocks are lower."""
    seismic = model.scene.seismic
    if seismic is not None:
        return seismic.towards == "+x"
    x = points[:, 0]
    middle = 0.5 * (x.min() + x.max())
    return bool(points[x <= middle, 1].max() <= points[x >= middle, 1].max())


def _draw_arrows(
    ax: Axes, model: Model, centre: np.ndarray, shift_mm: np.ndarray, points: np.ndarray
) -> None:
    """Each centroid's displacement [mm] as an arrow from it, in its measured direction (`angles="xy"`
    on equal axes) and to one length scale: the longest `ARROW_SHARE` of the scene's extent, or shorter
    so that every arrow ends inside the axes (those under `SHORTEST_ARROW` of it left out); and a scale
    arrow labelled in mm in an upper corner (`_key_on_left`)."""
    length = np.hypot(*shift_mm.T)
    largest = float(length.max(initial=0.0))
    if largest <= 0.0:
        return
    shown = length >= SHORTEST_ARROW * largest
    (left, right), (bottom, top) = ax.get_xlim(), ax.get_ylim()
    reach = ARROW_SHARE * float(np.ptp(points, axis=0).max()) / largest
    inside = _fitting_scale(centre[shown], shift_mm[shown], np.array([left, bottom]), np.array([right, top]))
    per_mm = min(reach, 0.98 * inside)  # [m of the figure per mm of displacement]
    arrows = ax.quiver(
        *centre[shown].T,
        *shift_mm[shown].T,
        angles="xy",
        scale_units="xy",
        scale=1.0 / per_mm,
        units="inches",
        width=0.025,
        color="white",
        edgecolor="k",
        linewidth=0.6,
        zorder=3,
    )
    key = _nice_length(largest)
    half = 0.5 * key * per_mm / (right - left)  # half the scale arrow, a fraction of the axes' width
    ax.quiverkey(
        arrows,
        0.03 + half if _key_on_left(model, points) else 0.97 - half,
        0.95,
        key,
        f"{key:g} mm",
        labelpos="S",
        coordinates="axes",
        fontproperties={"size": "small"},
    )


def _shade_blocks(ax: Axes, model: Model, start: list[np.ndarray], moved: np.ndarray) -> None:
    """The blocks shaded by `moved` [mm] up to `colour_top` of the free blocks (beyond it red, the colour
    bar's arrow, its label giving their range); the fixed ones grey."""
    held = np.all(model.dof == L.PRESCRIBED, axis=1)
    free = moved[~held]
    top = colour_top(free, model.blocks[~held, L.SIZE] ** 2) if len(free) else 0.0
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85", over="tab:red")
    cells = PolyCollection(
        start,
        array=np.where(held, np.nan, moved),
        cmap=cmap,
        norm=Normalize(0.0, max(top, 1e-9)),
        edgecolors="k",
        linewidths=0.5,
    )
    ax.add_collection(cells)
    largest = float(free.max(initial=0.0))
    red = f"red: {top:.3g} to {largest:.3g} mm (beyond {COLOUR_QUANTILE:.0%} of the free area)\n"
    ax.figure.colorbar(
        cells,
        ax=ax,
        shrink=0.8,
        extend="max" if largest > top else "neither",
        label="largest displacement of the block [mm]\n" + (red if largest > top else "") + "grey: fixed",
    )


def mechanism_figure(result: StrengthReductionResult, dpi: int | None = None) -> Figure:
    """mechanism.png: the failure mechanism of a strength reduction. Every block where the trials
    start, shaded by how far it has moved (its farthest vertex) at the end of the lowest unstable trial,
    with its centroid's displacement as an arrow to the scale of a labelled scale arrow
    (`_draw_arrows`). The colour scale ends at the largest displacement, or, where that is more than
    twice the displacement below which 95 % of the free blocks' area lies, at the latter
    (`colour_top`), so that one sliver does not set it: the blocks beyond it are red, the colour bar's
    label giving their range. The title gives the FS (`fos_title`); the water and seismic loads as
    `draw_loads` draws them; the bolts at the blocks' start, coloured by their load in the last stable
    trial (`draw_support`). `dpi`: the scene's figure_dpi unless given."""
    model = result.model
    points = result.start_world
    fig = shaped_figure(points, dpi or model.scene.figure_dpi)
    ax = fig.subplots()
    start = _outlines(model, result.start_world)
    if result.mechanism_world is None:
        moved = np.zeros(len(start))
    else:
        end = _outlines(model, result.mechanism_world)
        moved = np.array([np.max(np.hypot(*(e - s).T)) for s, e in zip(start, end, strict=True)]) * 1e3
    _shade_blocks(ax, model, start, moved)
    _frame(ax, model, points)
    if result.mechanism_blocks is not None:
        free = ~np.all(model.dof == L.PRESCRIBED, axis=1)
        shift = result.moved(result.mechanism_blocks)[free, :2] * 1e3
        _draw_arrows(ax, model, result.start_blocks[free][:, [L.X, L.Y]], shift, points)
    draw_loads(ax, model, points)
    if len(model.support.names):
        draw_support(ax, model, model.blocks, result.support_state, ", last stable trial")
    if ax.get_legend_handles_labels()[0]:
        fig.legend(loc="outside lower center", fontsize="small")
    name = model.scene.name or "scene"
    shown = (
        "arrows: centroid displacements (scaled)" if result.mechanism_world is not None else "no mechanism"
    )
    ax.set_title(f"{name}: {fos_title(result)}\n{shown}", fontsize=9)
    return fig


def fos_title(result: StrengthReductionResult) -> str:
    """The factor of safety (`factor_of_safety_text`) and the trial the mechanism comes from, to the
    same decimals: "FS = 1.113, lowest failing trial F = 1.117"; beyond the searched range, the bound
    it lies beyond."""
    fs, failing = result.factor_of_safety_text, result.bracket[1]
    if result.bracketed:
        return f"FS = {fs}, lowest failing trial F = {failing:.{bracket_decimals(result.bracket)}f}"
    if math.isinf(failing):
        return f"FS {fs}: no trial failed"
    return f"FS {fs}: every trial failed, the lowest at F = {failing:.4g}"


def bracketing_figure(result: StrengthReductionResult, dpi: int | None = None) -> Figure:
    """bracketing.png: each trial's F in the order run, stable or unstable, and the factor of safety
    found (`factor_of_safety_text`). `dpi`: the scene's figure_dpi unless given."""
    start = "unreduced" if result.start == "unreduced" else "elastic (no equilibrium unreduced)"
    return trials_figure(
        result.trials,
        result.factor_of_safety,
        result.factor_of_safety_text,
        result.bracketed,
        f"bracketing and bisection; trials start from the {start} equilibrium",
        dpi or result.model.scene.figure_dpi,
    )


def trials_figure(
    trials: Sequence[Trial], factor: float, text: str, bracketed: bool, title: str, dpi: int
) -> Figure:
    """Each strength-reduction trial's F in the order run, stable or unstable, and the factor of safety
    `factor` found (printed as `text`), for a 2D or a 3D search."""
    fig = Figure(figsize=(7, 4), dpi=dpi)
    ax = fig.subplots()
    order = np.arange(1, len(trials) + 1)
    factors = np.array([t.factor for t in trials])
    stable = np.array([t.verdict == "stable" for t in trials], dtype=bool)
    ax.plot(order, factors, "-", color="0.6", zorder=1)
    ax.plot(order[stable], factors[stable], "o", color="tab:green", label="stable (holds)")
    ax.plot(order[~stable], factors[~stable], "x", color="tab:red", ms=8, mew=2, label="unstable (fails)")
    label = f"FS = {text}" if bracketed else f"FS {text}: beyond the searched range"
    ax.axhline(factor, color="k", ls="--", lw=1, label=label)
    ax.set_xlabel("trial")
    ax.set_ylabel("strength reduction factor F")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def bridges_figure(model: Model, final: np.ndarray, bridges: pd.DataFrame, dpi: int) -> Figure:
    """The blocks at the end of the run and each rock bridge (a contact whose law breaks into a joint)
    at its middle: intact, broken in part, or broken through, with how it broke (`bridges.csv`)."""
    fig = Figure(figsize=(8, 6), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    ax.add_collection(
        PolyCollection(_outlines(model, final), facecolors="none", edgecolors="0.5", linewidths=0.5)
    )
    intact = bridges["shares_broken"] == 0
    through = bridges["broken_through_by_step"] >= 0
    part = ~intact & ~through
    tension = bridges["in_tension"] > bridges["in_shear"]
    styles = [
        (intact, "o", "0.3", "intact"),
        (part, "o", "tab:orange", "broken in part"),
        (through & ~tension, "x", "tab:red", "broken through, in shear"),
        (through & tension, "+", "tab:purple", "broken through, in tension"),
    ]
    for mask, marker, colour, label in styles:
        ax.plot(
            bridges["x_m"][mask],
            bridges["y_m"][mask],
            marker,
            color=colour,
            ms=6,
            ls="none",
            label=f"{label} ({int(mask.sum())})",
        )
    _frame(ax, model, final)
    ax.set_title(f"{model.scene.name or 'scene'}: rock bridges at the end of the run")
    fig.legend(loc="outside lower center", ncols=2, fontsize="small")
    return fig
