"""Figures of a kinematic analysis beyond the stereonet: the compass chart (the percentage of critical
poles or intersections of each mode for faces dipping towards every direction, a pit wall's sectors)
and the face-angle chart (the same against the face's dip, for one wall); and the drawing of each mode
on the stereonet, its zones filled from the classification's own masks
(`bbmc.kinematics.modes.critical_zone_masks`), so a zone drawn and a reading counted cannot differ."""

from __future__ import annotations

import math
from dataclasses import replace

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.figure import Figure

from bbmc.kinematics.compass import FaceSweep
from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.modes import critical_zone_masks
from bbmc.outputs.stereonet_figures import KinematicMode, Zone

# The modes a designer reads first, as the charts and nets show them: (mode, what its percentage counts).
CHART_MODES = (
    ("planar_sliding", "planar sliding (poles)"),
    ("wedge_sliding", "wedge sliding (intersections)"),
    ("flexural_toppling", "flexural toppling (poles)"),
    ("direct_toppling", "direct toppling (intersections)"),
)
COLOURS = {
    "planar_sliding": "tab:red",
    "wedge_sliding": "tab:orange",
    "flexural_toppling": "tab:blue",
    "direct_toppling": "tab:purple",
}


def compass_chart(sweep: FaceSweep, friction_deg: float, dpi: int) -> Figure:
    """% critical of each chart mode (all readings) against the face's dip direction, on a polar chart
    with north up and azimuths clockwise; the face's dip and the friction angle in the title."""
    fig = Figure(figsize=(8.0, 7.0), dpi=dpi)
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    theta = np.append(sweep.dip_direction, sweep.dip_direction[0] + 2.0 * np.pi)
    for mode, label in CHART_MODES:
        percent, _ = sweep.percent(mode)
        ax.plot(theta, np.append(percent, percent[0]), color=COLOURS[mode], lw=1.6, label=label)
    ax.set_rlabel_position(100)
    ax.tick_params(labelsize=8)
    dip = math.degrees(float(sweep.dip[0]))
    ax.set_title(
        f"Critical readings against the face's dip direction (azimuth, clockwise from north)\n"
        f"face dip {dip:g}°, friction {friction_deg:g}°; radius: % of poles or of intersections critical",
        fontsize=10,
    )
    ax.legend(loc="upper left", bbox_to_anchor=(-0.12, -0.04), ncol=2, fontsize=8, frameon=False)
    fig.subplots_adjust(bottom=0.16, top=0.86)
    return fig


def face_angle_chart(sweep: FaceSweep, friction_deg: float, dpi: int) -> Figure:
    """% critical of each chart mode (all readings) against the face's dip, for one wall."""
    fig = Figure(figsize=(8.0, 5.0), dpi=dpi)
    ax = fig.add_subplot()
    dips = np.degrees(sweep.dip)
    for mode, label in CHART_MODES:
        percent, error = sweep.percent(mode)
        ax.plot(dips, percent, color=COLOURS[mode], marker="o", ms=3, lw=1.5, label=label)
        if np.any(error > 0):
            ax.fill_between(dips, percent - 2 * error, percent + 2 * error, color=COLOURS[mode], alpha=0.15)
    direction = math.degrees(float(sweep.dip_direction[0]))
    ax.set_xlabel("face dip [°]")
    ax.set_ylabel("critical [% of poles or of intersections]")
    ax.set_title(
        f"Critical readings against the face angle: wall dipping towards {direction:03.0f}, "
        f"friction {friction_deg:g}°",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def _mask(face: Face, friction: float, limits: KinematicLimits, mode: str, without: str | None = None):
    """The zone of `mode` (less that of `without`) on lower-hemisphere points."""

    def mask(points: np.ndarray) -> np.ndarray:
        masks = critical_zone_masks(points, face, friction, limits)
        return masks[mode] & ~masks[without] if without else masks[mode]

    return mask


def mode_drawings(face: Face, friction: float, limits: KinematicLimits) -> dict[str, KinematicMode]:
    """Each chart mode as the stereonet draws it: its zones (masks of the classification), its
    straight lateral limits about the trend where its critical points lie (the poles of planes that
    slide trend opposite to the face's dip direction, those of planes that topple flexurally towards
    it, the lines of intersection of toppling blocks opposite to it), and whether the friction cone
    and daylight envelope belong to it."""
    towards = float(face.dip_direction)
    opposite = (towards + math.pi) % (2.0 * math.pi)

    def zone(name: str, mode: str, colour: str, without: str | None = None) -> Zone:
        return Zone(name, _mask(face, friction, limits, mode, without), colour)

    drawings = {
        "planar_sliding": KinematicMode(
            "planar sliding",
            "poles",
            (zone("critical zone", "planar_sliding", "#f4a3a3"),),
            (opposite, limits.planar),
        ),
        "wedge_sliding": KinematicMode(
            "wedge sliding",
            "lines",
            (
                zone("primary critical zone", "wedge_sliding", "#f4a3a3"),
                zone("secondary zone (sliding on one plane)", "wedge_sliding_one_plane", "#fbd38d"),
            ),
        ),
        "flexural_toppling": KinematicMode(
            "flexural toppling",
            "poles",
            (zone("critical zone", "flexural_toppling", "#9ec5f4"),),
            (towards, limits.flexural_toppling),
            friction_cone=False,
            daylight=False,
        ),
        "direct_toppling": KinematicMode(
            "direct toppling",
            "lines",
            (
                zone(
                    "zone 1: toppling (the base planes may slide)",
                    "direct_toppling",
                    "#c9a7f0",
                    without="direct_toppling_steep",
                ),
                zone(
                    "zone 2: toppling, steeper than the base planes' friction cone",
                    "direct_toppling_steep",
                    "#a77fe0",
                ),
                zone("zone 3: oblique toppling", "oblique_toppling", "#e6d8f7"),
            ),
            (opposite, limits.direct_toppling),
            daylight=False,
            cone_of="poles",
        ),
    }
    return {name: replace(drawing, curved=limits.curved) for name, drawing in drawings.items()}
