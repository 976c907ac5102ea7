"""Stereonets a reader takes in at a glance: the pole plot of a survey (poles by set with their counts,
Terzaghi-weighted density contours, the set means' great circles and 95 % confidence cones, the slope
face) and the kinematic plot of one failure mode (its critical zones filled from the classification's own
mask function, the face, the friction cone, the daylight envelope, the lateral limits and the poles or
intersections). Each figure names its projection and hemisphere, the number of readings raw and
weighted, the weight cap, the face and the friction angle. The net is `bbmc.outputs.stereonet`'s.

Sets are named "set k + 1" for the label k >= 0 unless the caller names them; label -1 is the random
readings, drawn grey.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from dataclasses import dataclass, field

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.axes import Axes
from matplotlib.contour import QuadContourSet
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from bbmc.geometry.orientation import downward, plane_of_pole, poles
from bbmc.kinematics.face import Face
from bbmc.kinematics.intersections import set_pair_lines
from bbmc.outputs.stereonet import (
    COUNT_CONE,
    DENSITY_UNITS,
    PROJECTION_NAMES,
    Mask,
    daylight_envelope,
    fill_zone,
    friction_cone_angle,
    net_axes,
    plot_cones,
    plot_density,
    plot_friction_cone,
    plot_lateral_limits,
    plot_planes,
    plot_points,
    projection_of,
)
from bbmc.rockmass.figure import SET_COLOURS

RANDOM = -1
RANDOM_COLOUR = "0.55"
FACE_COLOUR = "k"
FRICTION_COLOUR = "tab:blue"
DAYLIGHT_COLOUR = "tab:purple"
LEGEND_WIDTH = 50  # characters of a legend line at 8 pt


@dataclass(frozen=True)
class PoleSurvey:
    """Readings as upward unit poles (n, 3), their set labels (n,) (-1: random) and Terzaghi weights (n,),
    capped at `weight_cap` (None: unweighted). `set_names` maps labels to names."""

    poles: np.ndarray
    labels: np.ndarray
    weights: np.ndarray
    weight_cap: float | None
    set_names: dict[int, str] = field(default_factory=dict)

    @classmethod
    def from_planes(
        cls,
        dip: np.ndarray,
        dip_direction: np.ndarray,
        labels: np.ndarray,
        weights: np.ndarray | None = None,
        weight_cap: float | None = None,
        set_names: dict[int, str] | None = None,
    ) -> PoleSurvey:
        """From planes' `dip` and `dip_direction` [rad]; no `weights`: every reading counts once."""
        normals = poles(dip, dip_direction)
        w = np.ones(len(normals)) if weights is None else np.asarray(weights, dtype=float)
        return cls(normals, np.asarray(labels), w, weight_cap, dict(set_names or {}))

    def name(self, label: int) -> str:
        """The set's name: the caller's, else "set k + 1"; "random" for label -1."""
        return "random" if label == RANDOM else self.set_names.get(int(label), f"set {int(label) + 1}")


@dataclass(frozen=True)
class SetMeans:
    """Set means: labels (k,), mean upward unit poles (k, 3) and 95 % confidence cone half-angles (k,)
    [rad]."""

    labels: np.ndarray
    poles: np.ndarray
    alpha95: np.ndarray


@dataclass(frozen=True)
class Zone:
    """A critical zone: its name, the classification's mask (lower-hemisphere unit vectors (m, 3) -> bool
    (m,)) and its fill colour."""

    name: str
    mask: Mask
    colour: str


@dataclass(frozen=True)
class KinematicMode:
    """A failure mode as drawn: its name, whether its points are poles ("poles") or lines ("lines": dip
    vectors, intersections), its zones, its lateral limits (centre trend, half-width) [rad] or None
    (`curved`: mplstereonet's small circles, which the zones' edges show, not drawn as lines), whether
    its criterion uses the friction cone about the vertical and (for poles) the daylight envelope
    (flexural toppling uses neither: its zone's own edge is its slip limit), and which friction cone:
    that of its own points (None), or "poles" for lines split by their base planes' cone (direct
    toppling: phi from the centre)."""

    name: str
    vectors: str
    zones: tuple[Zone, ...]
    lateral_limits: tuple[float, float] | None = None
    friction_cone: bool = True
    daylight: bool = True
    curved: bool = False
    cone_of: str | None = None


@dataclass(frozen=True)
class NetDrawing:
    """What a plot drew that its figure states: the density contours and their unit (for the colour bar),
    legend entries of what the axes cannot label (the zones' fills) and the notes."""

    density: QuadContourSet | None
    density_unit: str
    handles: list
    notes: list[str]


def _dip_text(dip: float, dip_direction: float) -> str:
    return f"{np.degrees(dip):.0f}/{np.degrees(dip_direction) % 360.0:03.0f}"


def face_text(face: Face) -> str:
    """A face's dip/dip direction in whole degrees, as 60/180."""
    return _dip_text(face.dip, face.dip_direction)


def plot_face(ax: Axes, face: Face, note: str = "") -> None:
    """The face's great circle, labelled "slope face 60/180" and `note`."""
    plot_planes(
        ax,
        face.dip,
        face.dip_direction,
        color=FACE_COLOUR,
        linewidth=2.0,
        label=f"slope face {face_text(face)}{note}",
        zorder=2,
    )


def _colour(label: int) -> str:
    return RANDOM_COLOUR if label == RANDOM else SET_COLOURS[int(label) % len(SET_COLOURS)]


def plot_sets(ax: Axes, survey: PoleSurvey, markersize: float = 4.0) -> None:
    """The poles coloured by set, each set in the legend with its count ("set 1 (n = 84)"), random last."""
    labels = sorted(set(survey.labels.tolist()), key=lambda k: (k == RANDOM, k))
    for label in labels:
        members = survey.labels == label
        plot_points(
            ax,
            survey.poles[members],
            color=_colour(label),
            markersize=markersize,
            markeredgecolor="white" if label != RANDOM else _colour(label),
            markeredgewidth=0.4,
            label=f"{survey.name(label)} (n = {int(members.sum())})",
            zorder=3,
        )


def plot_set_means(ax: Axes, sets: SetMeans, survey: PoleSurvey) -> None:
    """Each set mean's great circle (its plane: dip/dip direction and alpha95 in the legend), its mean
    pole and its 95 % confidence cone (the small circle of half-angle alpha95 about the mean pole)."""
    dips, directions = plane_of_pole(sets.poles)
    for label, pole, alpha, dip, direction in zip(
        sets.labels, sets.poles, sets.alpha95, dips, directions, strict=True
    ):
        colour = _colour(label)
        name = f"{survey.name(label)} mean {_dip_text(np.radians(dip), np.radians(direction))}"
        plot_planes(
            ax,
            np.radians(dip),
            np.radians(direction),
            color=colour,
            linewidth=1.4,
            label=f"{name}, α95 = {np.degrees(alpha):.1f}°",
            zorder=2,
        )
        plot_points(ax, pole[None], marker="s", markersize=6, color=colour, markeredgecolor="k", zorder=5)
        plot_cones(ax, pole[None], np.array([alpha]), edgecolor="k", linewidth=1.0, zorder=5)


def plot_mean_intersections(ax: Axes, sets: SetMeans) -> None:
    """The lines of intersection of every pair of set means, as black triangles."""
    if len(sets.labels) < 2:
        return
    lines = set_pair_lines(sets.poles).lines
    lines = lines[np.all(np.isfinite(lines), axis=1)]
    plot_points(
        ax,
        lines,
        marker="^",
        markersize=6,
        color="k",
        linestyle="none",
        label="intersections of the set means",
        zorder=5,
    )


def _weight_note(survey: PoleSurvey) -> str:
    count = len(survey.poles)
    if survey.weight_cap is None:
        return f"{count} readings, unweighted"
    bias = np.degrees(np.arcsin(1.0 / survey.weight_cap))
    return (
        f"{count} readings; Terzaghi-weighted total {survey.weights.sum():.1f} "
        f"(weights 1/|cos δ| capped at {survey.weight_cap:.2f}, minimum bias angle {bias:.0f}°)"
    )


def pole_plot(
    ax: Axes,
    survey: PoleSurvey,
    sets: SetMeans | None = None,
    face: Face | None = None,
    method: str = "schmidt",
) -> NetDrawing:
    """The pole plot on a net from `net_axes`: weighted density contours, poles by set, set means with
    their cones and intersections, and the face's great circle."""
    density = plot_density(ax, survey.poles, survey.weights, method)
    plot_sets(ax, survey)
    if sets is not None:
        plot_set_means(ax, sets, survey)
        plot_mean_intersections(ax, sets)
    notes = [_weight_note(survey), "Planes as dip/dip direction [°]"]
    what = "weighted readings" if survey.weight_cap is not None else "readings"
    unit = f"% of {what} per 1 % area" if method == "schmidt" else DENSITY_UNITS[method]
    if method == "schmidt":
        notes.append(
            f"Contours: Schmidt count in a cone of 1 % of the hemisphere's area "
            f"({np.degrees(COUNT_CONE):.1f}° half-angle), {unit}"
        )
    if sets is not None:
        notes.append("Set means: great circles, mean poles (squares) and 95 % confidence cones (black)")
    if face is not None:
        plot_face(ax, face)
    return NetDrawing(density, unit, [], notes)


def kinematic_plot(
    ax: Axes,
    mode: KinematicMode,
    face: Face,
    friction_angle: float,
    survey: PoleSurvey | None = None,
    lines: np.ndarray | None = None,
    lines_name: str = "intersections",
    contours: bool = False,
) -> NetDrawing:
    """One mode's kinematic plot on a net from `net_axes`: its zones filled from their masks (the legend
    gives how many of the points lie in each by the same mask, raw and, for a weighted survey,
    weighted), the face, the friction cone and, for poles, the daylight envelope (`plot_references`);
    then the poles by set (`survey`, over their weighted density if `contours`) or the `lines` (n, 3),
    named `lines_name` in the legend (small and translucent when there are many)."""
    points = survey.poles if survey is not None else lines
    handles = []
    for zone in mode.zones:
        fill_zone(ax, zone.mask, zone.colour)
        label = zone.name if points is None else zone.name + ": " + _zone_count(zone, points, mode, survey)
        handles.append(Patch(facecolor=zone.colour, alpha=0.35, edgecolor=zone.colour, label=label))
    notes = [plot_references(ax, mode, face, friction_angle)]
    if survey is not None and contours:
        drawing = pole_plot(ax, survey, method="schmidt")
        return NetDrawing(drawing.density, drawing.density_unit, handles, notes + drawing.notes)
    if survey is not None:
        plot_sets(ax, survey, markersize=3.5)
        notes.append(_weight_note(survey))
    elif lines is not None:
        size, alpha = (3.0, 1.0) if len(lines) <= 300 else (1.5, 0.5)
        label = f"{lines_name} (n = {len(lines)})"
        plot_points(
            ax, lines, color="k", markersize=size, alpha=alpha, markeredgewidth=0, zorder=3, label=label
        )
    return NetDrawing(None, "", handles, notes)


def plot_references(ax: Axes, mode: KinematicMode, face: Face, friction_angle: float) -> str:
    """The face's great circle, the friction cone (`friction_cone_angle`), the daylight envelope on a
    pole plot and the lateral limits, as the mode asks; returns the note naming them."""
    on_lines = " (daylight limit)" if mode.vectors == "lines" and mode.daylight else ""
    plot_face(ax, face, on_lines)
    phi = np.degrees(friction_angle)
    note = f"{mode.name}: face {face_text(face)} (dip/dip direction), friction angle {phi:.0f}°"
    if mode.friction_cone:
        kind = mode.cone_of or mode.vectors
        cone = np.degrees(friction_cone_angle(friction_angle, kind))
        plot_friction_cone(ax, friction_angle, kind, edgecolor=FRICTION_COLOUR, linewidth=1.5, zorder=2)
        whose = "base planes' friction cone" if kind != mode.vectors else "friction cone"
        ax.plot([], [], color=FRICTION_COLOUR, label=f"{whose}, φ = {phi:.0f}° ({cone:.0f}° from the centre)")
    if mode.vectors == "poles" and mode.daylight:
        envelope = daylight_envelope(face.dip, face.dip_direction)
        plot_points(
            ax,
            envelope,
            marker="",
            linestyle="-",
            color=DAYLIGHT_COLOUR,
            linewidth=1.3,
            label="daylight envelope",
        )
    if mode.lateral_limits is not None and mode.curved:
        note += f", lateral limits ±{np.degrees(mode.lateral_limits[1]):.0f}° (curved: the zone's edges)"
    elif mode.lateral_limits is not None:
        trend, half = mode.lateral_limits
        first, _ = plot_lateral_limits(ax, trend, half)
        first.set_label(f"lateral limits ±{np.degrees(half):.0f}°")
        note += f", lateral limits ±{np.degrees(half):.0f}° (straight)"
    return note


def _zone_count(zone: Zone, points: np.ndarray, mode: KinematicMode, survey: PoleSurvey | None) -> str:
    """'k of n poles (p %)', and the weighted share for a weighted survey."""
    inside = np.asarray(zone.mask(downward(points)), dtype=bool)
    text = f"{inside.sum()} of {len(points)} {mode.vectors} ({100.0 * inside.mean():.1f} %"
    if survey is not None and survey.weight_cap is not None:
        text += f"; weighted {100.0 * survey.weights[inside].sum() / survey.weights.sum():.1f} %"
    return text + ")"


def net_figure(
    title: str, draw: Callable[[Axes], NetDrawing], projection: str = "equal_area", dpi: int = 150
) -> Figure:
    """A figure of one net: `draw` on it, the legend to its right, the colour bar of any density below
    it, the title naming the projection and hemisphere, and the drawing's notes at the foot."""
    width, height, side = 10.0, 8.0, 5.4  # inches: the figure and the net's square
    fig = Figure(figsize=(width, height), dpi=dpi)
    ax = net_axes(fig, (0.5 / width, 1.7 / height, side / width, side / height), projection)
    drawing = draw(ax)
    handles, _ = ax.get_legend_handles_labels()
    for handle in drawing.handles + handles:  # the legend's column is 3.6 in wide
        handle.set_label(textwrap.fill(handle.get_label(), LEGEND_WIDTH, subsequent_indent="   "))
    fig.legend(
        handles=drawing.handles + handles,
        loc="upper left",
        bbox_to_anchor=(6.4 / width, 0.9),
        fontsize=8,
        frameon=False,
    )
    if drawing.density is not None:
        bar_axes = fig.add_axes((1.0 / width, 1.2 / height, (side - 1.0) / width, 0.12 / height))
        bar = fig.colorbar(drawing.density, cax=bar_axes, orientation="horizontal")
        bar.set_label(f"pole density, {drawing.density_unit}", fontsize=8)
        bar.ax.tick_params(labelsize=7)
    fig.suptitle(f"{title}: {PROJECTION_NAMES[projection_of(ax)]}, lower hemisphere", fontsize=11, y=0.975)
    fig.text(0.01, 0.01, "\n".join(drawing.notes), fontsize=7.5, va="bottom", ha="left")
    return fig


def pole_figure(
    survey: PoleSurvey,
    sets: SetMeans | None = None,
    face: Face | None = None,
    projection: str = "equal_area",
    method: str = "schmidt",
    dpi: int = 150,
) -> Figure:
    """The pole plot (`pole_plot`) as a figure (`net_figure`)."""
    return net_figure(
        "Poles to planes", lambda ax: pole_plot(ax, survey, sets, face, method), projection, dpi
    )


def kinematic_figure(
    mode: KinematicMode,
    face: Face,
    friction_angle: float,
    survey: PoleSurvey | None = None,
    lines: np.ndarray | None = None,
    lines_name: str = "intersections",
    contours: bool = False,
    projection: str = "equal_area",
    dpi: int = 150,
) -> Figure:
    """One mode's kinematic plot (`kinematic_plot`) as a figure (`net_figure`)."""
    return net_figure(
        f"Kinematic analysis, {mode.name}",
        lambda ax: kinematic_plot(ax, mode, face, friction_angle, survey, lines, lines_name, contours),
        projection,
        dpi,
    )
