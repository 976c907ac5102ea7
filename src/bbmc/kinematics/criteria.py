"""The kinematic tests of Markland's family for one slope face, vectorised over poles and lines.

Inputs: `poles` (N, 3), upward unit normals of planes (a downward one is turned up); `lines` (N, 3),
unit vectors of lines (an upward one is turned down); `friction` phi [rad], a float or one value
per pole / line; a `Face` (psi_f, alpha_f) whose fields may be (F, 1) arrays (the answer is then
(F, N)); `KinematicLimits`. A plane of dip delta and dip direction alpha has the lower-hemisphere
pole of trend alpha + pi and plunge pi/2 - delta; its dip vector has trend alpha and plunge delta.

Sources: the Rocscience Dips help pages "Planar Sliding", "Wedge Sliding", "Flexural Toppling" and
"Direct Toppling" (Dips' kinematic module follows Hudson & Harrison 1997, Engineering Rock
Mechanics, ch. 18); Goodman 1980 (Introduction to Rock Mechanics) for flexural toppling. Each
function states its test; docs/reference/kinematics.md states where Dips differs from the issue.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from bbmc.geometry.orientation import downward, upward
from bbmc.kinematics.face import (
    ROUND_OFF,
    Face,
    KinematicLimits,
    components,
    daylights,
    turned_towards,
    within_lateral_limits,
)


def planar_sliding(
    poles: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> np.ndarray:
    """Planar sliding (Dips "Planar Sliding"; Hudson & Harrison 1997, sec. 18.3): the pole inside the
    daylight envelope, outside the friction cone, within the lateral limits.

    * daylight: the plane's dip vector daylights in the face, tan delta < tan psi_f cos(alpha -
      alpha_f) (the dip is less than the face's apparent dip along the plane's dip direction; Dips'
      daylight envelope is the locus of poles of planes whose dip vector lies on the face's great
      circle, so the pole-envelope and dip-vector forms are one test);
    * friction: delta > phi (the pole farther than phi from the centre of the net);
    * lateral: alpha within +/-`limits.planar` of alpha_f."""
    p = upward(poles)
    px, py, pz = components(p)
    # the dip vector scaled by sin(delta): (p_h p_z, -|p_h|^2), the same sense and daylight test
    horizontal_sq = px * px + py * py
    daylight = daylights(px * pz, py * pz, -horizontal_sq, face.dip, face.dip_direction)
    steeper = pz < np.cos(friction)
    lateral = within_lateral_limits(px, py, pz, face.dip_direction, limits.planar, limits.curved)
    return daylight & steeper & lateral


class WedgeZones(NamedTuple):
    """Lines in Dips' primary critical zone (sliding on both planes, along the line) and its
    secondary zone (sliding on one plane)."""

    primary: np.ndarray
    secondary: np.ndarray


def wedge_sliding(lines: np.ndarray, face: Face, friction: float | np.ndarray) -> WedgeZones:
    """Wedge sliding (Dips "Wedge Sliding"; Hudson & Harrison 1997, sec. 18.4): lines of intersection
    of plunge p and trend t.

    * primary zone: p > phi and tan p < tan psi_f cos(t - alpha_f): the crescent between the friction
      cone (the circle of plunge phi) and the face's great circle;
    * secondary zone: p <= phi, daylighting as above, and at or below the great circle of the plane
      dipping phi towards alpha_f, tan p >= tan phi cos(t - alpha_f): the region between the friction
      cone, the face's great circle and that "friction plane", where the wedge can slide on one of
      its planes rather than along the line (as mplstereonet's WedgeSliding, after Dips).
    No lateral limits (Dips has none for wedges)."""
    x, y, z = turned_towards(downward(lines), face.dip_direction)
    daylight = daylights(x, y, z, face.dip, face.dip_direction)
    steeper = -z > np.sin(friction)
    below_friction_plane = ~daylights(x, y, z, friction, face.dip_direction)
    return WedgeZones(daylight & steeper, daylight & ~steeper & below_friction_plane)


def flexural_toppling(
    poles: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> np.ndarray:
    """Flexural toppling (Goodman 1980, sec. 8.4; Dips "Flexural Toppling"): the pole outside the
    slip-limit plane and within the lateral limits.

    The slip limit is the plane of dip psi_f - phi dipping towards alpha_f. A pole outside its great
    circle plunges less than its apparent dip along the pole's trend: with the pole's trend alpha + pi
    and plunge pi/2 - delta, tan(pi/2 - delta) < tan(psi_f - phi) cos(alpha + pi - alpha_f). In the
    face's opposite direction this is Goodman's delta > 90 deg - psi_f + phi; off it, Dips' great
    circle is stricter than the issue's form with the true dip (see the reference page). No zone
    where psi_f <= phi. Lateral: the pole's trend within +/-`limits.flexural_toppling` of alpha_f
    (the plane dipping into the face within the limits of alpha_f + pi)."""
    x, y, z = turned_towards(-upward(poles), face.dip_direction)
    slip_dip = np.asarray(face.dip) - np.asarray(friction)
    outside = daylights(x, y, z, slip_dip, face.dip_direction, inclusive=True) & (slip_dip > 0.0)
    lateral = within_lateral_limits(x, y, z, face.dip_direction, limits.flexural_toppling, limits.curved)
    return outside & lateral


class DirectTopplingZones(NamedTuple):
    """Dips' three direct-toppling zones of a set of lines (intersections) or lower-hemisphere poles
    (base planes): zones 1 and 2 form the primary critical zone, zone 3 is oblique toppling."""

    zone_1: np.ndarray
    zone_2: np.ndarray
    zone_3: np.ndarray


def direct_toppling_zones(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    face: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits,
) -> DirectTopplingZones:
    """The zones of Dips' "Direct Toppling" page (after Hudson & Harrison 1997, sec. 18.5) of
    downward unit vectors (x, y, z) of plunge p and trend t, with alpha_i = alpha_f + pi, the
    direction into the slope:

    * zones 1 and 2: t within the straight lateral limits (+/-`limits.direct_toppling`) of alpha_i,
      and p >= 90 deg - psi_f (inside the circle of cone angle psi_f about the vertical);
    * the boundary between zones 1 and 2 is the base planes' friction cone, p = 90 deg - phi:
      zone 2 inside it (p >= 90 deg - phi), zone 1 outside;
    * zone 3, oblique toppling: inside the friction cone and outside the lateral limits, on the
      into-slope side of the face's strike, |t - alpha_i| <= 90 deg (the help page's text says
      "outside the lateral limits, inside the friction cone"; the strike as its far bound is read
      from its figure, where the half of the cone towards the face is left unshaded)."""
    into = np.asarray(face.dip_direction) + np.pi
    lateral = within_lateral_limits(x, y, z, into, limits.direct_toppling, limits.curved)
    steep = -z >= np.cos(face.dip) - ROUND_OFF
    in_cone = -z >= np.cos(friction) - ROUND_OFF
    into_slope = x * np.sin(into) + y * np.cos(into) >= -ROUND_OFF
    primary = lateral & steep
    return DirectTopplingZones(primary & ~in_cone, primary & in_cone, ~lateral & in_cone & into_slope)


def direct_toppling(
    lines: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> DirectTopplingZones:
    """Direct toppling of the lines of intersection `lines` (Dips "Critical Intersections"): zones 1
    and 2 are the intersections that can cut toppling blocks, zone 3 oblique toppling."""
    into = np.asarray(face.dip_direction) + np.pi
    x, y, z = turned_towards(downward(lines), into)
    return direct_toppling_zones(x, y, z, face, friction, limits)


def base_planes(
    poles: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> DirectTopplingZones:
    """The base planes of direct toppling (Dips "Critical Base Planes"): the lower-hemisphere poles
    in the same zones. Zone 1: a base plane dipping out of the face more steeply than phi and less
    than psi_f (the blocks can slide on it as they topple); zones 2 and 3: flatter than phi (release
    without sliding; zone 3 oblique)."""
    into = np.asarray(face.dip_direction) + np.pi
    x, y, z = turned_towards(-upward(poles), into)
    return direct_toppling_zones(x, y, z, face, friction, limits)


def set_pair_friction(friction_1: float | np.ndarray, friction_2: float | np.ndarray) -> np.ndarray:
    """The friction angle of a wedge or a block edge cut by two planes: the smaller of the two
    planes' angles (the conservative choice; Dips takes one angle for all intersections)."""
    return np.minimum(friction_1, friction_2)
