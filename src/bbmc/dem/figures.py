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
