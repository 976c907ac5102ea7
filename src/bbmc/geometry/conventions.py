"""The ways orientations are recorded in the field, turned into one another: strike (right-hand rule)
and dip direction, a pole's trend and plunge and its plane, magnetic and true azimuths, and oriented
core's alpha and beta angles and the plane's pole.

Axes and angles as in `bbmc.geometry.orientation`: x east, y north, z up; radians; azimuths clockwise
from north, 0 to 2 pi; a plane's pole is its upward unit normal; a line's plunge is downward positive.

* Right-hand rule (Dips' "Strike(Right)/Dip"): looking along the strike, the plane dips to the right, so
  dip direction = strike + pi/2.
* A pole of trend t and plunge p (lower hemisphere) is the normal of the plane of dip pi/2 - p and dip
  direction t - pi (`orientation.pole_trend_and_plunge` is the other way).
* Magnetic declination D (east positive): true azimuth = magnetic azimuth + D.
* Oriented core (Rocscience Dips, "Borehole Oriented Core"; Datamine Discover, "Alpha/Beta Angles";
  Holcombe 2005, "Oriented drillcore"): alpha is the acute angle between the plane and the core axis
  (90 deg: the plane is normal to the hole; 0: it contains the hole's axis); beta is the angle from the
  core's reference line to the down-hole end of the long axis of the plane's ellipse on the core
  (the apex farthest from the collar), clockwise looking down the hole (in the drilling direction).
  The reference line is the top-of-core or the bottom-of-core line (Dips' "Orient 1" is the angle
  from the top of core to it, clockwise looking down the hole: 0 or pi).
"""

from __future__ import annotations

import numpy as np

from bbmc.geometry.orientation import line_vectors, poles, upward, wrapped_azimuth

# The angle [rad] from the top-of-core line to the core's reference line, clockwise looking down the hole.
CORE_REFERENCES = {"top": 0.0, "bottom": np.pi}


def dip_direction_of_strike(strike: np.ndarray) -> np.ndarray:
    """Dip direction [rad] of planes of right-hand-rule `strike` [rad]: strike + pi/2 (mod 2 pi)."""
    return wrapped_azimuth(np.asarray(strike, dtype=float) + np.pi / 2.0)


def strike_of_dip_direction(dip_direction: np.ndarray) -> np.ndarray:
    """Right-hand-rule strike [rad] of planes of `dip_direction` [rad]: dip direction - pi/2 (mod 2 pi)."""
    return wrapped_azimuth(np.asarray(dip_direction, dtype=float) - np.pi / 2.0)


def plane_of_pole_trend_and_plunge(trend: np.ndarray, plunge: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Dip and dip direction [rad] of planes whose lower-hemisphere pole has `trend` and `plunge` [rad]:
    dip = pi/2 - plunge, dip direction = trend - pi (mod 2 pi). A vertical pole (a horizontal plane)
    gives the dip direction trend - pi, which a horizontal plane does not need."""
    trend, plunge = np.asarray(trend, dtype=float), np.asarray(plunge, dtype=float)
    return np.pi / 2.0 - plunge, wrapped_azimuth(trend + np.pi)


def true_azimuth(magnetic: np.ndarray, declination: float) -> np.ndarray:
    """True azimuths [rad] of azimuths read on a magnetic compass, `declination` [rad] east positive:
    magnetic + declination (mod 2 pi)."""
    return wrapped_azimuth(np.asarray(magnetic, dtype=float) + declination)


def top_of_core(hole_trend: np.ndarray, hole_plunge: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) of the top-of-core line of holes of `hole_trend` and `hole_plunge` [rad]
    (plunge > 0 drilled downward, < 0 upward): the upward direction normal to the hole in its vertical
    plane, t = (sin p sin t, sin p cos t, cos p): the upward normal of the plane that holds the hole and
    dips p towards its trend (`poles(p, t)`; p < 0: away from it). A vertical hole has no top; the
    formula's value there, the horizontal line of azimuth `hole_trend`, is what an inclined hole of that
    trend tends to."""
    return poles(hole_plunge, hole_trend)


def core_poles(
    alpha: np.ndarray,
    beta: np.ndarray,
    hole_trend: np.ndarray,
    hole_plunge: np.ndarray,
    reference: float = CORE_REFERENCES["bottom"],
) -> np.ndarray:
    """Upward unit poles (..., 3) of planes read on oriented core as `alpha` and `beta` [rad], in holes
    of `hole_trend` and `hole_plunge` [rad], beta measured from the reference line `reference` [rad]
    clockwise (looking down the hole) from the top of core (`CORE_REFERENCES`).

    With h the down-hole unit vector, r the reference line (the top-of-core line t turned by
    `reference` about h: r = t cos(reference) + (h x t) sin(reference)), the apex direction (normal to
    h, towards the ellipse's down-hole apex) is a = r cos beta + (h x r) sin beta, and the pole is
    n = h sin alpha - a cos alpha, turned upward. Checks: |n . h| = sin alpha (the plane makes alpha with
    the axis), and the plane's steepest line relative to the axis, h - (h . n) n, leans towards +a."""
    h = line_vectors(hole_trend, hole_plunge)
    top = top_of_core(hole_trend, hole_plunge)
    line = np.cos(reference) * top + np.sin(reference) * np.cross(h, top)
    beta = np.asarray(beta, dtype=float)[..., None]
    apex = np.cos(beta) * line + np.sin(beta) * np.cross(h, line)
    alpha = np.asarray(alpha, dtype=float)[..., None]
    normal = np.sin(alpha) * h - np.cos(alpha) * apex
    return upward(normal)
