"""Stereonets: the lower hemisphere on an equal-area (Schmidt) or equal-angle (Wulff) net, drawn on the
axes of mplstereonet (Kington, MIT licence) from bbmc's unit vectors. North is up, east to the right.

A line of plunge p lies at the angle theta = 90 deg - p from the centre of the net and, on a net of
radius 1, at r = sqrt(2) sin(theta / 2) (equal area, Lambert's projection) or r = tan(theta / 2)
(equal angle, the stereographic projection), in the direction of its trend (Priest 1985, ch. 2). A plane
is drawn by its lower-hemisphere pole, trend = dip direction + 180 deg, plunge = 90 deg - dip, so the
pole of a plane dipping east plots west of the centre, at the angle of the dip from it.

Every drawing passes through `net_coordinates`: bbmc's vectors (x east, y north, z up; either sense,
turned to the lower hemisphere) to trend and plunge, and mplstereonet's `line` from there to its own
longitude and latitude, which its axes project. `net_vectors` is the way back, for fields evaluated on
a grid over the net (density, kinematic zones).

Density (`plot_density`): the Schmidt count, the share of the readings inside a counting cone of 1 % of
the hemisphere's area (half-angle acos(0.99) = 8.1 deg) centred on each grid point, as Dips counts with
its default count circle; axial, so a pole near the primitive also counts on the opposite side. With
weights w_i (Terzaghi's), each reading counts w_i / mean(w), so the levels read "% of the weighted
readings per 1 % area".
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib import ticker
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap
from matplotlib.contour import QuadContourSet
from matplotlib.figure import Figure, SubFigure
from matplotlib.lines import Line2D

with warnings.catch_warnings():  # its axes override Axes.cla, pending deprecation since matplotlib 3.6
    warnings.filterwarnings("ignore", "Overriding `Axes.cla`", PendingDeprecationWarning)
    import mplstereonet  # registers the projections  # noqa: F401
from mplstereonet import contouring, stereonet_math

from bbmc.geometry.orientation import apparent_dip, line_vectors, poles, trend_and_plunge

PROJECTIONS = {"equal_area": "equal_area_stereonet", "equal_angle": "equal_angle_stereonet"}
PROJECTION_NAMES = {"equal_area": "equal-area (Schmidt) net", "equal_angle": "equal-angle (Wulff) net"}
DENSITY_UNITS = {
    "schmidt": "% of readings per 1 % area",
    "exponential_kamb": "standard deviations above uniform (exponential Kamb, Vollmer 1995)",
}
COUNT_CONE = float(np.arccos(0.99))  # half-angle [rad] of the Schmidt counting cone: 1 % of the hemisphere
DENSITY_COLOURS = ListedColormap(matplotlib.colormaps["Greys"](np.linspace(0.12, 0.8, 256)), "bbmc_density")
ZONE_STEP = np.radians(0.5)  # grid step of the zone fill [rad]: the fill's edge is within it of the mask's


Mask = Callable[[np.ndarray], np.ndarray]


def net_axes(
    fig: Figure | SubFigure, rect: tuple[float, float, float, float], projection: str = "equal_area"
) -> Axes:
    """A lower-hemisphere net (`projection` "equal_area" or "equal_angle") at `rect` (left, bottom, width,
    height, figure fraction): azimuths every 30 deg with N, E, S and W, the centre marked, no grid. Its
    azimuth labels live on a hidden polar axes placed once, so the figure must not use a layout engine
    that moves axes (constrained layout moved the net and left the labels behind)."""
    if projection not in PROJECTIONS:
        raise ValueError(f"projection must be one of {sorted(PROJECTIONS)}, not {projection!r}")
    ax = fig.add_axes(rect, projection=PROJECTIONS[projection])
    azimuths = np.arange(0, 360, 30)
    names = {0: "N", 90: "E", 180: "S", 270: "W"}
    ax.set_azimuth_ticks(azimuths, labels=[names.get(int(a), f"{a:03d}") for a in azimuths], fontsize=8)
    ax.grid(False)
    ax.plot([0.0], [0.0], "+", color="0.2", markersize=8, zorder=4)
    return ax


def projection_of(ax: Axes) -> str:
    """The projection ("equal_area" or "equal_angle") of a net made by `net_axes`."""
    return next(key for key, name in PROJECTIONS.items() if ax.name == name)


def net_coordinates(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """mplstereonet's longitude and latitude [rad] of the lines along `vectors` (..., 3), either sense,
    on the lower hemisphere: an upward pole plots where its downward sense meets the hemisphere."""
    trend, plunge = trend_and_plunge(np.asarray(vectors, dtype=float))
    lon, lat = stereonet_math.line(np.degrees(plunge).ravel(), np.degrees(trend).ravel())
    return lon.reshape(plunge.shape), lat.reshape(plunge.shape)


def net_vectors(lon: np.ndarray, lat: np.ndarray) -> np.ndarray:
    """Downward unit vectors (..., 3) of the points of the net at mplstereonet's `lon`, `lat` [rad]."""
    lon, lat = np.asarray(lon, dtype=float), np.asarray(lat, dtype=float)
    plunge, bearing = stereonet_math.geographic2plunge_bearing(lon.ravel(), lat.ravel())
    return line_vectors(np.radians(bearing), np.radians(plunge)).reshape(*lon.shape, 3)


def plot_points(ax: Axes, vectors: np.ndarray, **style: Any) -> Line2D:
    """Points of the lines (or poles) along `vectors` (n, 3); `style`: `Axes.plot` keywords."""
    lon, lat = net_coordinates(vectors)
    return ax.plot(lon, lat, **{"linestyle": "none", "marker": "o", "markersize": 4, **style})[0]


def plot_planes(ax: Axes, dip: np.ndarray, dip_direction: np.ndarray, **style: Any) -> list[Line2D]:
    """Great circles of planes of `dip` and `dip_direction` [rad]; `style`: `Axes.plot` keywords."""
    strike = np.degrees(np.atleast_1d(dip_direction)) - 90.0  # right-hand rule: dips to the strike's right
    return ax.plane(strike, np.degrees(np.atleast_1d(dip)), **style)


def plot_cones(ax: Axes, axes: np.ndarray, angles: np.ndarray, **style: Any) -> list:
    """Small circles of half-angle `angles` [rad] about the lines along `axes` (k, 3), either sense; a
    circle crossing the primitive comes back on the opposite side. `style`: collection keywords."""
    trend, plunge = trend_and_plunge(np.atleast_2d(axes))
    style = {"facecolor": "none", **style}
    return [
        ax.cone(np.degrees(p), np.degrees(t), np.degrees(a), segments=181, bidirectional=bool(a > p), **style)
        for t, p, a in zip(trend, plunge, np.broadcast_to(angles, trend.shape), strict=True)
    ]


def friction_cone_angle(friction_angle: float, vectors: str) -> float:
    """The half-angle [rad] about the vertical of the friction cone as Dips draws it: on a pole plot
    (`vectors` "poles") the poles of planes dipping at the friction angle phi lie phi from the centre,
    and poles outside the cone are of planes steeper than phi; on a plot of lines ("lines": dip vectors,
    intersections) the lines plunging at phi lie 90 deg - phi from the centre, and lines inside the cone
    plunge more steeply than phi."""
    if vectors not in ("poles", "lines"):
        raise ValueError(f"vectors must be 'poles' or 'lines', not {vectors!r}")
    return friction_angle if vectors == "poles" else np.pi / 2.0 - friction_angle


def plot_friction_cone(ax: Axes, friction_angle: float, vectors: str, **style: Any) -> list:
    """The friction cone (`friction_cone_angle`) of `friction_angle` [rad] about the vertical."""
    angle = friction_cone_angle(friction_angle, vectors)
    return plot_cones(ax, np.array([[0.0, 0.0, -1.0]]), np.array([angle]), **style)


def daylight_envelope(face_dip: float, face_dip_direction: float, count: int = 361) -> np.ndarray:
    """Poles (count, 3) on the daylight envelope of a face: the poles of the planes whose dip vectors lie
    in the face, i.e. whose dip equals the face's apparent dip along their dip direction,
    tan(dip) = tan(psi_f) cos(alpha - alpha_f) for |alpha - alpha_f| <= 90 deg (Priest 1993, eq. 2.6;
    Dips' daylight envelope). Poles inside the envelope are of planes that daylight in the face."""
    direction = face_dip_direction + np.linspace(-np.pi / 2.0, np.pi / 2.0, count)
    dip = np.clip(apparent_dip(face_dip, face_dip_direction, direction), 0.0, None)
    return poles(dip, direction)


def plot_lateral_limits(ax: Axes, trend: float, half_width: float, **style: Any) -> list[Line2D]:
    """Straight lateral limits: the two radii of the net at `trend` +- `half_width` [rad] (Dips' straight
    limits; a pole plot centres them on the face's dip direction + 180 deg, a plot of lines on the
    sliding direction)."""
    plunge = np.linspace(0.0, 90.0, 46)
    lines = []
    for limit in (trend - half_width, trend + half_width):
        lon, lat = stereonet_math.line(plunge, np.full_like(plunge, np.degrees(limit) % 360.0))
        lines += ax.plot(lon, lat, **{"color": "0.25", "linestyle": "--", "linewidth": 0.9, **style})
    return lines


def zone_grid(step: float = ZONE_STEP) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A regular grid over the lower hemisphere in mplstereonet's longitude and latitude (spacing `step`
    [rad], so no two neighbours are more than `step` apart on the sphere) and its downward unit vectors."""
    side = np.linspace(-np.pi / 2.0, np.pi / 2.0, round(np.pi / step) + 1)
    lon, lat = np.meshgrid(side, side)
    return lon, lat, net_vectors(lon, lat)


def fill_zone(
    ax: Axes, zone: Mask, colour: str, step: float = ZONE_STEP, alpha: float = 0.35
) -> QuadContourSet:
    """Fill the region of the net where `zone` (lower-hemisphere unit vectors (m, 3) -> bool (m,)) is
    True: the mask on `zone_grid(step)`, filled at its 0.5 level, so the fill and the classification
    cannot disagree farther than one grid step from the zone's edge; the edge drawn in `colour`."""
    lon, lat, vectors = zone_grid(step)
    inside = np.asarray(zone(vectors.reshape(-1, 3)), dtype=bool).reshape(lon.shape).astype(float)
    filled = ax.contourf(lon, lat, inside, levels=[0.5, 1.5], colors=[colour], alpha=alpha, zorder=1)
    ax.contour(lon, lat, inside, levels=[0.5], colors=[colour], linewidths=1.2, zorder=1)
    return filled


def density_grid(
    vectors: np.ndarray, weights: np.ndarray | None = None, method: str = "schmidt", gridsize: int = 121
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """mplstereonet's density of the lines along `vectors` (n, 3) on a `gridsize`^2 longitude-latitude
    grid: (lon, lat, density) in `DENSITY_UNITS[method]`. `weights` (n,) count each reading w_i / mean(w)
    times (mplstereonet divides a copy, never the caller's array)."""
    if method not in DENSITY_UNITS:  # its linear and square Kamb kernels fail with weights (0.6.3)
        raise ValueError(f"method must be one of {sorted(DENSITY_UNITS)}, not {method!r}")
    lon, lat = net_coordinates(vectors)
    weights = None if weights is None else np.array(weights, dtype=float, copy=True)
    return contouring.density_grid(
        lon, lat, measurement="radians", method=method, weights=weights, gridsize=gridsize
    )


def density_levels(peak: float, count: int = 8) -> np.ndarray:
    """Round contour levels from the first above zero to above `peak` (about `count` of them)."""
    levels = ticker.MaxNLocator(count, steps=[1, 2, 2.5, 5, 10]).tick_values(0.0, peak)
    return levels[levels > 0]


def plot_density(
    ax: Axes,
    vectors: np.ndarray,
    weights: np.ndarray | None = None,
    method: str = "schmidt",
    levels: np.ndarray | None = None,
    cmap: str | ListedColormap = DENSITY_COLOURS,
) -> QuadContourSet:
    """Filled density contours of the poles or lines along `vectors` (`density_grid`), nothing below the
    first level, with thin contour lines; `levels` default to `density_levels` of the peak."""
    lon, lat, density = density_grid(vectors, weights, method)
    if levels is None:
        levels = density_levels(float(density.max()))
    filled = ax.contourf(lon, lat, density, levels=levels, cmap=cmap, extend="max", alpha=0.75, zorder=0)
    ax.contour(lon, lat, density, levels=levels, colors="0.35", linewidths=0.4, zorder=0)
    return filled
