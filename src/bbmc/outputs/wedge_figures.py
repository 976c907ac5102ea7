"""Figures of a wedge: the wedge in 3D with the slope around it and the forces on it, and its planes on
the stereonet. (A wedge study's FS histogram is `bbmc sweep`'s fs_distribution.png, with P_f over the
wedges that form; its summary.csv adds P_f over every sample, as Swedge separates them.)

* `wedge_figure`: matplotlib's 3D axes (mplot3d), chosen over pyvista because the figure is a static
  PNG written headless beside the CSVs like every other bbmc figure, needs no OpenGL or extra package
  (pyvista is not a dependency), and a wedge has at most five faces, where mplot3d's painter's
  algorithm (no depth buffer) draws convex faces correctly. ParaView, on the VTK file of
  `bbmc.outputs.wedge_vtk`, is the interactive view. The wedge's faces are shaded by face, the slope face
  and the upper surface drawn as translucent patches around it, the line of intersection dashed, and the
  forces as arrows from the centroid, to one scale (the largest as long as 0.6 of the line of
  intersection), their sizes in the legend. Axes east, north, up [m], equal aspect.
* `wedge_net_figure`: the great circles of planes 1 and 2, the face and the upper surface, the line of
  intersection as a point and the friction cones for lines (`bbmc.outputs.stereonet`).
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from numpy.typing import ArrayLike, NDArray

from bbmc.geometry.orientation import trend_and_plunge
from bbmc.kinematics.face import Face
from bbmc.outputs.stereonet import plot_friction_cone, plot_planes, plot_points
from bbmc.outputs.stereonet_figures import NetDrawing, face_text, net_figure, plot_face
from bbmc.outputs.wedge_vtk import FACE_NAMES, one_wedge, wedge_faces
from bbmc.slope.wedge.analysis import WedgeAnalysis, WedgeOrientations
from bbmc.slope.wedge.geometry import WedgeGeometry
from bbmc.slope.wedge.mechanics import MODE_DESCRIPTIONS, SlidingMode
from bbmc.slope.wedge.support import Bolt

KN = 1.0e3  # N per kN, for the legend
FACE_COLOURS = {1: "tab:orange", 2: "tab:green", 3: "0.8", 4: "khaki", 5: "tab:cyan"}
FACE_ALPHAS = {1: 0.85, 2: 0.85, 3: 0.3, 4: 0.3, 5: 0.85}  # the free faces see-through: joints show
ARROW_SHARE = 0.6  # the longest force arrow, this fraction of the line of intersection's length
RESULTANT = "F"  # the active resultant's symbol: drawn broad and pale, under the forces it sums
SHORTEST_ARROW = 0.08  # arrows shorter than this fraction of the longest are drawn this long, and say so
SURROUND = 0.35  # the face and upper surface patches reach this fraction of the wedge's size beyond it
PLANE_COLOURS = ("tab:orange", "tab:green")
PLANE_NAMES = ("plane 1", "plane 2")  # the joint planes' names in the legends by default
UPPER_COLOUR = "saddlebrown"
LINE_COLOUR = "crimson"
ELEVATION = 20.0  # the camera above the horizontal [deg]


def _unit(v: NDArray) -> NDArray:
    return v / np.linalg.norm(v)


def _slope_patches(g: WedgeGeometry, size: float) -> tuple[NDArray, NDArray]:
    """Quadrilaterals (4, 3) of the slope face (toe line at z = 0 to the crest) and of the upper surface
    (crest back into the slope), reaching `size` beyond the wedge on each side."""
    face, upper = g.normal_face, g.normal_upper
    strike = _unit(np.cross(face, [0.0, 0.0, 1.0]))  # horizontal, in the face
    crest = _unit(g.crest_2 - g.crest_1)  # the crest line (face ∩ upper surface)
    along = g.vertices @ strike
    ends = (along.min() - size, along.max() + size)
    toe = [e * strike for e in ends]
    top = [g.crest_1 + (e - g.crest_1 @ strike) / (crest @ strike) * crest for e in ends]
    back = _unit(np.cross(upper, crest))
    back = back if back @ face < 0.0 else -back  # into the slope
    depth = (g.vertices - g.crest_1) @ back
    far = [p + (depth.max() + size) * back for p in top]
    return np.array([toe[0], toe[1], top[1], top[0]]), np.array([top[0], top[1], far[1], far[0]])


def wedge_forces(
    analysis: WedgeAnalysis, bolts: Sequence[Bolt], index: tuple[int, ...]
) -> list[tuple[str, str, NDArray, str]]:
    """The forces the 3D figure draws on the wedge at `index`: (symbol, name, vector [N], colour), the
    zero ones left out; the `bolts` drawn one by one, the rest of the support as "other" forces."""
    loads, g = analysis.loads, analysis.geometry

    def at(value: ArrayLike) -> NDArray:
        return np.asarray(value, dtype=float)[index]

    weight = at(loads.weight)
    active_bolts = sum((np.asarray(b.vector, float) for b in bolts if b.form == "active"), np.zeros(3))
    passive_bolts = sum((np.asarray(b.vector, float) for b in bolts if b.form == "passive"), np.zeros(3))
    drawn = [
        ("W", "weight", np.array([0.0, 0.0, -weight]), "k"),
        ("U1", "water on plane 1", at(loads.water_1) * at(g.normal_1), "tab:blue"),
        ("U2", "water on plane 2", at(loads.water_2) * at(g.normal_2), "deepskyblue"),
        ("kW", "seismic", at(loads.seismic), "tab:purple"),
        ("A", "other active forces", at(loads.forces) - active_bolts, "tab:brown"),
        ("P", "other passive forces", at(loads.passive) - passive_bolts, "olive"),
    ]
    if g.has_crack:
        drawn.insert(3, ("V", "water in the crack", at(loads.water_crack) * at(g.normal_crack), "navy"))
    drawn += [
        (
            f"B{k + 1}",
            f"bolt {k + 1} ({b.form}, {float(b.count):g} × {float(b.force) / KN:,.4g} kN)",
            np.asarray(b.vector, float),
            "magenta",
        )
        for k, b in enumerate(bolts)
    ]
    drawn.append((RESULTANT, "active resultant", at(loads.active), "red"))
    scale = max(weight, 1.0)
    return [force for force in drawn if np.linalg.norm(force[2]) > 1e-9 * scale]


def _draw_forces(
    ax: Axes, g: WedgeGeometry, forces: list[tuple[str, str, NDArray, str]]
) -> tuple[list[Line2D], NDArray]:
    """Arrows from the centroid, the longest ARROW_SHARE of the line of intersection, none shorter than
    SHORTEST_ARROW of it (lengthened, and its legend entry says so); legend handles and the tips (k, 3)."""
    largest = max(np.linalg.norm(v) for _, _, v, _ in forces)
    scale = ARROW_SHARE * float(np.linalg.norm(g.top)) / largest
    handles, tips = [], []
    for symbol, name, vector, colour in forces:
        size = np.linalg.norm(vector)
        lengthened = size < SHORTEST_ARROW * largest
        shaft = scale * vector * (SHORTEST_ARROW * largest / size if lengthened else 1.0)
        tips.append(g.centroid + shaft)
        resultant = symbol == RESULTANT
        style = {"color": colour, "linewidth": 5.0 if resultant else 2.0, "alpha": 0.5 if resultant else 1.0}
        where = g.centroid + (1.2 if resultant else 1.08) * shaft  # F's label clear of a force along it
        ax.text(*where, symbol, color=colour, fontsize=9, fontweight="bold", zorder=5)
        ax.quiver(*g.centroid, *shaft, **style, arrow_length_ratio=0.15, zorder=3 if resultant else 4)
        label = f"{name} {symbol} = {size / KN:,.0f} kN" + (" (arrow lengthened)" if lengthened else "")
        handles.append(Line2D([], [], **style, label=label))
    return handles, np.array(tips)


def _view_azimuth(g: WedgeGeometry, elevation: float) -> float:
    """The camera's azimuth [deg, from east anticlockwise]: out of the slope, within 60 deg of the face's
    normal, where the view sees the face and both joint planes most squarely (the largest of the least
    |cos| between the view and their normals, on a 1 deg grid)."""
    centre = np.arctan2(g.normal_face[1], g.normal_face[0])
    azimuth = centre + np.radians(np.arange(-60.0, 61.0))
    up = np.radians(elevation)
    view = np.stack(
        [np.cos(up) * np.cos(azimuth), np.cos(up) * np.sin(azimuth), np.full_like(azimuth, np.sin(up))], -1
    )
    seen = np.abs(view @ np.stack([g.normal_1, g.normal_2, g.normal_face]).T).min(axis=1)
    return float(np.degrees(azimuth[np.argmax(seen)]))


def wedge_figure(
    analysis: WedgeAnalysis,
    bolts: Sequence[Bolt] = (),
    index: tuple[int, ...] = (),
    title: str = "Wedge",
    dpi: int = 150,
    names: tuple[str, str] = PLANE_NAMES,
) -> Figure:
    """The wedge at `index` of `analysis` (its full geometry, not the essentials) in 3D (module
    docstring), with the `bolts` the analysis included drawn one by one, its joint planes called
    `names` in the legend; the title names the mode and FS. Raises WedgeNotFormedError where the wedge
    does not form."""
    if not isinstance(analysis.geometry, WedgeGeometry):
        raise ValueError("analysis: the 3D figure needs the full geometry (essentials_only=False)")
    g = one_wedge(analysis.geometry, index)
    points, faces = wedge_faces(g)
    face_names = FACE_NAMES | dict(enumerate(names, start=1))
    size = float(np.ptp(points, axis=0).max())
    fig = Figure(figsize=(11.0, 7.5), dpi=dpi)
    ax = fig.add_axes((0.08, 0.06, 0.56, 0.86), projection="3d")  # room for a z label on the left
    ax.computed_zorder = False  # drawn in zorder: the slope, the wedge (its faces sorted by depth), forces
    face_patch, upper_patch = _slope_patches(g, SURROUND * size)
    surround = Poly3DCollection(
        [face_patch, upper_patch], facecolors=["0.7", UPPER_COLOUR], alpha=0.18, zorder=1
    )
    surround.set_edgecolor("0.4")
    ax.add_collection3d(surround)
    polygons = [points[list(p)] for p in faces.values()]
    colours = [matplotlib.colors.to_rgba(FACE_COLOURS[k], FACE_ALPHAS[k]) for k in faces]
    wedge = Poly3DCollection(polygons, facecolors=colours, edgecolors="k", linewidths=1.0, zorder=2)
    ax.add_collection3d(wedge)
    end = g.crack_foot if g.has_crack else g.top  # the line's length within the wedge
    ax.plot(*np.stack([np.zeros(3), end]).T, color=LINE_COLOUR, linestyle="--", linewidth=1.8, zorder=3)
    handles = [
        Patch(facecolor=FACE_COLOURS[k], alpha=FACE_ALPHAS[k], edgecolor="k", label=f"wedge: {face_names[k]}")
        for k in faces
    ]
    handles += [
        Patch(facecolor="0.7", alpha=0.4, edgecolor="0.4", label="slope face (around the wedge)"),
        Patch(facecolor=UPPER_COLOUR, alpha=0.3, edgecolor="0.4", label="upper slope surface"),
        Line2D([], [], color=LINE_COLOUR, linestyle="--", label="line of intersection"),
    ]
    arrows, tips = _draw_forces(ax, g, wedge_forces(analysis, bolts, index))
    handles += arrows
    corners = np.vstack([points, face_patch, upper_patch, tips])
    low, high = corners.min(axis=0), corners.max(axis=0)
    ax.set(xlim=(low[0], high[0]), ylim=(low[1], high[1]), zlim=(low[2], high[2]))
    ax.set_aspect("equal")
    ax.set_box_aspect(None, zoom=1.15)
    ax.view_init(elev=ELEVATION, azim=_view_azimuth(g, ELEVATION))
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.zaxis.set_rotate_label(False)  # else the label turns with the view, upside down on the left
    ax.set_zlabel("up [m]", rotation=90)
    fig.legend(handles=handles, loc="center left", bbox_to_anchor=(0.66, 0.5), fontsize=8, frameon=False)
    solution = analysis.solution
    mode = MODE_DESCRIPTIONS[SlidingMode(int(np.asarray(solution.mode)[index]))]
    fs = float(np.asarray(solution.factor_of_safety)[index])
    fig.suptitle(f"{title}: {mode}, FS = {fs:.3f}", fontsize=12)
    fig.text(
        0.01,
        0.01,
        f"weight {float(np.asarray(analysis.loads.weight)[index]) / KN:,.0f} kN, "
        f"volume {float(g.volume):,.0f} m³, H = {float(g.height_h):.1f} m (H1 = {float(g.height_h1):.1f} m); "
        "arrows from the centroid, to one scale",
        fontsize=8,
    )
    return fig


def _plane_text(dip: float, direction: float) -> str:
    return f"{np.degrees(dip):.0f}/{np.degrees(direction) % 360.0:03.0f}"


def wedge_net(
    ax: Axes,
    orientations: WedgeOrientations,
    line: ArrayLike,
    friction_angles: dict[str, float],
    names: tuple[str, str] = PLANE_NAMES,
) -> NetDrawing:
    """On a net from `net_axes`: planes 1 and 2, the face and the upper surface as great circles (each
    angle a scalar [rad]), the line of intersection `line` (3,) (downward unit) as a point, and for
    each named friction angle [rad] the friction cone for lines (lines inside it plunge more steeply)."""
    o = orientations
    for k, (dip, direction) in enumerate(((o.dip_1, o.dip_direction_1), (o.dip_2, o.dip_direction_2))):
        plot_planes(
            ax,
            dip,
            direction,
            color=PLANE_COLOURS[k],
            linewidth=1.6,
            label=f"{names[k]} {_plane_text(dip, direction)}",
        )
    plot_face(ax, Face(float(o.face_dip), float(o.face_dip_direction)))
    plot_planes(
        ax,
        o.upper_dip,
        o.upper_dip_direction,
        color=UPPER_COLOUR,
        linewidth=1.4,
        linestyle="--",
        label=f"upper surface {_plane_text(o.upper_dip, o.upper_dip_direction)}",
    )
    line = np.asarray(line, dtype=float)
    trend, plunge = (float(np.degrees(angle)) for angle in trend_and_plunge(line))
    plot_points(
        ax,
        line[None],
        marker="^",
        markersize=8,
        color=LINE_COLOUR,
        markeredgecolor="k",
        zorder=6,
        label=f"line of intersection {plunge:.1f}/{trend:03.0f} (plunge/trend)",
    )
    styles = ("-", ":", "-.")
    for k, (name, phi) in enumerate(friction_angles.items()):
        plot_friction_cone(
            ax, phi, "lines", edgecolor="tab:blue", linewidth=1.3, linestyle=styles[k % 3], zorder=2
        )
        ax.plot(
            [],
            [],
            color="tab:blue",
            linestyle=styles[k % 3],
            label=f"friction cone, {name}: φ = {np.degrees(phi):.0f}°",
        )
    face = Face(float(o.face_dip), float(o.face_dip_direction))
    notes = [
        f"Wedge: planes as dip/dip direction [°], face {face_text(face)}; friction cones for lines: "
        "a line of intersection inside a cone plunges more steeply than that φ"
    ]
    return NetDrawing(None, "", [], notes)


def wedge_net_figure(
    analysis: WedgeAnalysis,
    orientations: WedgeOrientations,
    friction_angles: dict[str, float],
    index: tuple[int, ...] = (),
    projection: str = "equal_area",
    dpi: int = 150,
    names: tuple[str, str] = PLANE_NAMES,
) -> Figure:
    """The wedge at `index`'s planes, face, upper surface, line of intersection and friction cones on a
    net (`wedge_net`), as a figure (`stereonet_figures.net_figure`)."""
    picked = WedgeOrientations(
        *(
            float(np.broadcast_to(a, np.shape(analysis.factor_of_safety))[index])
            for a in orientations.angles()
        )
    )
    line = np.asarray(analysis.geometry.line)[index]
    return net_figure(
        "Wedge planes", lambda ax: wedge_net(ax, picked, line, friction_angles, names), projection, dpi
    )
