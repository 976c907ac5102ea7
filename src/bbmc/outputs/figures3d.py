"""The figure of a 3D run: its blocks at the start and at the end in one 3D view, to true scale.

matplotlib's 3D axes (mplot3d), as `bbmc.outputs.wedge_figures` draws a wedge: a static PNG written
headless beside the CSVs, no OpenGL; ParaView on the run's VTK series (`bbmc.outputs.vtk3d`) is the
interactive view. The start is a grey dashed wireframe (every face's outline), the end shaded faces:
held blocks light grey and see-through (a base does not hide what sits on it), moving blocks coloured
by their centroid's displacement |u| [mm] (the colour bar). An arrow from each moving block's centroid
points the way it moved, its length |u| to a scale of its own (the longest ARROW_SHARE times the
smallest moving block's radius), so that the mechanism shows even where the displacements are too
small to see at true scale; the arrows are drawn over the blocks. Axes x (east), y (north), z (up)
[m] with equal scaling, as a dip read off unequal axes would be wrong.

The view: ELEVATION above the horizontal, looking along the horizontal normal of the horizontal
displacement of the block that moved most, so that its path (down a dip, say) lies across the view and
its plunge shows at true angle; if no block moved sideways, matplotlib's default azimuth DEFAULT_AZIMUTH.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib import cm, colors
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

from bbmc.dem3d.layout import RADIUS, X
from bbmc.dem3d.model import Model
from bbmc.dem3d.tables import held_blocks, placed_vertices

ELEVATION = 20.0  # the camera above the horizontal [deg]
DEFAULT_AZIMUTH = -60.0  # matplotlib's default [deg from x, anticlockwise]
HELD_COLOUR = (0.75, 0.75, 0.75, 0.3)
MOVING_ALPHA = 0.9
COLOUR_MAP = "viridis"
ARROW_SHARE = 1.5  # the longest arrow, this many times its block's radius
SHORTEST = 1e-3  # blocks that moved less than this share of the most get no arrow
ARROW_COLOUR = "crimson"


def _faces(model: Model, vertices: np.ndarray, block: int) -> list[np.ndarray]:
    """Block's faces as (k, 3) polygons of `vertices`."""
    faces = range(model.block_face_start[block], model.block_face_start[block + 1])
    return [vertices[model.face_vertices[model.face_start[f] : model.face_start[f + 1]]] for f in faces]


def view_azimuth(moved: np.ndarray) -> float:
    """The camera's azimuth [deg] for displacements `moved` (n, 3) [m] (module docstring)."""
    if not len(moved):
        return DEFAULT_AZIMUTH
    u = moved[np.argmax(np.linalg.norm(moved, axis=1))]
    if np.hypot(u[0], u[1]) == 0.0:
        return DEFAULT_AZIMUTH
    return float(np.degrees(np.arctan2(u[1], u[0]))) - 90.0


def _draw_arrows(ax, model: Model, moved: np.ndarray, size_mm: np.ndarray) -> np.ndarray:
    """An arrow from each moving block's centroid along its displacement (module docstring); returns
    their tips (k, 3) [m]."""
    largest = size_mm.max()
    arrows = np.flatnonzero(size_mm > SHORTEST * largest) if largest > 0.0 else np.zeros(0, dtype=int)
    if not len(arrows):
        return np.zeros((0, 3))
    scale = ARROW_SHARE * model.blocks[arrows, RADIUS].min() / largest  # m per mm of the longest
    tails = model.blocks[arrows, X : X + 3]
    reach = (
        moved[arrows] / np.linalg.norm(moved[arrows], axis=1)[:, None] * (scale * size_mm[arrows])[:, None]
    )
    ax.quiver(*tails.T, *reach.T, color=ARROW_COLOUR, linewidth=1.8, arrow_length_ratio=0.25, zorder=3)
    return tails + reach


def mechanism_figure(
    model: Model,
    start: np.ndarray,
    dpi: int = 150,
    names: Sequence[str] | None = None,
    title: str = "Blocks at the start and the end",
) -> Figure:
    """The blocks at the start (`start`, a copy of model.blocks taken before the run) and now, one 3D
    view (module docstring); the title says which block moved most and how far."""
    held = held_blocks(model)
    before, after = placed_vertices(model, start), model.vertices
    moved = model.blocks[:, X : X + 3] - start[:, X : X + 3]
    size_mm = np.where(held, 0.0, np.linalg.norm(moved, axis=1)) / 1e-3
    norm = colors.Normalize(0.0, float(size_mm.max()) if size_mm.max() > 0.0 else 1.0)
    shade = cm.ScalarMappable(norm=norm, cmap=COLOUR_MAP)
    fig = Figure(figsize=(9.0, 7.0), dpi=dpi)
    ax = fig.add_axes((0.07, 0.04, 0.74, 0.84), projection="3d")  # room for the z label on the left
    outlines, polygons, fills = [], [], []
    for b in range(len(model.blocks)):
        outlines += _faces(model, before, b)
        faces = _faces(model, after, b)
        polygons += faces
        fill = HELD_COLOUR if held[b] else colors.to_rgba(shade.to_rgba(size_mm[b]), MOVING_ALPHA)
        fills += [fill] * len(faces)
    ax.computed_zorder = False  # drawn in zorder: the blocks (their faces sorted by depth), start, arrows
    ax.add_collection3d(
        Poly3DCollection(polygons, facecolors=fills, edgecolors="k", linewidths=0.5, zorder=1)
    )
    ax.add_collection3d(Line3DCollection(outlines, colors="0.45", linestyles="--", linewidths=0.8, zorder=2))
    tips = _draw_arrows(ax, model, moved, size_mm)
    corners = np.vstack([before, after, tips])
    low, high = corners.min(axis=0), corners.max(axis=0)
    ax.set(xlim=(low[0], high[0]), ylim=(low[1], high[1]), zlim=(low[2], high[2]))
    ax.set_aspect("equal")
    ax.set_box_aspect(None, zoom=1.1)
    ax.view_init(elev=ELEVATION, azim=view_azimuth(np.where(held[:, None], 0.0, moved)))
    ax.set_xlabel("x (east) [m]")
    ax.set_ylabel("y (north) [m]")
    ax.zaxis.set_rotate_label(False)  # else the label turns with the view
    ax.set_zlabel("z (up) [m]", rotation=90)
    bar = fig.colorbar(shade, ax=ax, fraction=0.04, pad=0.08, shrink=0.7)
    bar.set_label("displacement of the centroid |u| [mm]")
    handles = [
        Line2D([], [], color="0.45", linestyle="--", label="start"),
        Patch(facecolor=shade.to_rgba(norm.vmax), edgecolor="k", label="end (moving blocks)"),
        Patch(facecolor=HELD_COLOUR, edgecolor="k", label="held"),
        Line2D([], [], color=ARROW_COLOUR, label="way it moved (arrow length to its own scale)"),
    ]
    fig.legend(handles=handles, loc="lower right", fontsize=8, frameon=False)  # clear of the y axis
    most = int(np.argmax(size_mm))
    label = f"block {most}" if names is None else names[most]
    fig.suptitle(f"{title}\n{label} moved most, {size_mm[most]:,.1f} mm (true scale)", fontsize=11)
    return fig
