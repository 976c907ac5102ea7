"""Figures of a block run: the blocks before and after, and the monitored histories."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.dem.monitors import UNITS
from bbmc.dem.strength_reduction import StrengthReductionResult

SUFFIXES = sorted({unit for unit, _ in UNITS.values()}, key=len, reverse=True)


def _outlines(model: Model, world: np.ndarray) -> list[np.ndarray]:
    return [world[a:b] for a, b in zip(model.vertex_start[:-1], model.vertex_start[1:], strict=True)]


def scene_figure(model: Model, initial: np.ndarray, final: np.ndarray, dof: np.ndarray, dpi: int) -> Figure:
    """Block outlines at the start (dashed) and the end (solid); blocks with every degree of freedom
    fixed or prescribed are shaded."""
    fig = Figure(figsize=(8, 6), dpi=dpi)
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
            edgecolors="tab:blue",
            linewidths=0.6,
            linestyles="--",
            label="start",
        )
    )
    both = np.vstack([initial, final])
    pad = 0.05 * np.ptp(both, axis=0).max()
    ax.set_xlim(both[:, 0].min() - pad, both[:, 0].max() + pad)
    ax.set_ylim(both[:, 1].min() - pad, both[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{model.scene.name or 'scene'}: {len(model.block_names)} blocks")
    ax.legend(loc="best", fontsize="small")
    return fig


def history_figure(history: pd.DataFrame, dpi: int) -> Figure:
    """Each monitored quantity against step, one panel each (columns named <monitor>_<unit>)."""
    columns = [c for c in history.columns if c not in ("step", "time_s")]
    fig = Figure(figsize=(8, 2.2 * max(len(columns), 1)), dpi=dpi)
    axes = np.atleast_1d(fig.subplots(max(len(columns), 1), 1, sharex=True, squeeze=False)[:, 0])
    for ax, column in zip(axes, columns, strict=False):
        unit = next((u for u in SUFFIXES if column.endswith("_" + u)), "")
        name = column.removesuffix("_" + unit)
        ax.plot(history["step"], history[column], "-", color="tab:blue", label=name)
        ax.set_ylabel(f"{name} [{unit.replace('_per_', '/').replace('m_s', 'm/s')}]")
        ax.legend(loc="best", fontsize="small")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("step (one cycle)")
    return fig


def mechanism_figure(model: Model, result: StrengthReductionResult, dpi: int) -> Figure:
    """The failure mechanism: every block where the trials start, shaded by how far it has moved at the
    end of the lowest unstable trial, with its centroid's displacement as an arrow (scaled to be seen)."""
    points = result.start_world
    spread = np.ptp(points, axis=0)
    wide = min(max(spread[0] / max(spread[1], 1e-12), 0.6), 2.0)  # the figure follows the scene's shape
    fig = Figure(figsize=(2.0 + 4.5 * wide, 5.0), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    start = _outlines(model, result.start_world)
    held = np.all(model.dof == L.PRESCRIBED, axis=1)
    if result.mechanism_world is None:
        moved = np.zeros(len(start))
        title = "no unstable trial: no mechanism"
    else:
        end = _outlines(model, result.mechanism_world)
        moved = np.array([np.max(np.hypot(*(e - s).T)) for s, e in zip(start, end, strict=True)]) * 1e3
        title = f"mechanism at F = {result.bracket[1]:.3g} (lowest unstable trial)"
    colours = np.where(held, np.nan, moved)
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85")
    cells = PolyCollection(start, array=colours, cmap=cmap, edgecolors="k", linewidths=0.5)
    cells.set_clim(0.0, max(float(np.nanmax(colours, initial=0.0)), 1e-9))
    ax.add_collection(cells)
    fig.colorbar(cells, ax=ax, shrink=0.8, label="largest displacement of the block [mm] (grey: fixed)")
    if result.mechanism_world is not None:
        centre = np.array([s.mean(axis=0) for s in start])
        shift = np.array([e.mean(axis=0) for e in end]) - centre
        free = ~held & (np.hypot(*shift.T) > 0)
        ax.quiver(*centre[free].T, *shift[free].T, color="tab:red", angles="xy", width=0.004, zorder=3)
    pad = 0.05 * spread.max()
    ax.set_xlim(points[:, 0].min() - pad, points[:, 0].max() + pad)
    ax.set_ylim(points[:, 1].min() - pad, points[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    name = model.scene.name or "scene"
    ax.set_title(f"{name}: {title}\narrows: centroid displacements (scaled)", fontsize=9)
    return fig


def bracketing_figure(result: StrengthReductionResult, dpi: int) -> Figure:
    """Each trial's F in the order run, stable or unstable, and the factor of safety found."""
    fig = Figure(figsize=(7, 4), dpi=dpi)
    ax = fig.subplots()
    order = np.arange(1, len(result.trials) + 1)
    factors = np.array([t.factor for t in result.trials])
    stable = np.array([t.verdict == "stable" for t in result.trials], dtype=bool)
    ax.plot(order, factors, "-", color="0.6", zorder=1)
    ax.plot(order[stable], factors[stable], "o", color="tab:green", label="stable (holds)")
    ax.plot(order[~stable], factors[~stable], "x", color="tab:red", ms=8, mew=2, label="unstable (fails)")
    label = "FS" if result.bracketed else "FS beyond the searched range"
    fs = result.factor_of_safety
    ax.axhline(fs, color="k", ls="--", lw=1, label=f"{label} = {fs:.3f}")
    ax.set_xlabel("trial")
    ax.set_ylabel("strength reduction factor F")
    start = "unreduced" if result.start == "unreduced" else "elastic (no equilibrium unreduced)"
    ax.set_title(f"bracketing and bisection; trials start from the {start} equilibrium", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig
