"""The slope face, the lateral limits, and the two tests every kinematic criterion is built from:
a direction daylighting in a plane, and a direction within the lateral limits of an azimuth.

Axes x east, y north, z up; angles in radians. A face of dip psi_f and dip direction alpha_f has the
outward (upward) unit normal n_f = (sin psi_f sin alpha_f, sin psi_f cos alpha_f, cos psi_f) and the
horizontal unit vector of its dip direction d = (sin alpha_f, cos alpha_f, 0).

The fields of `Face` may be arrays of shape (F, 1): every criterion then broadcasts against N
points and answers (F, N), which is how the compass and face-angle sweeps evaluate many faces with
the very code that classifies one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import pole_components

# Boundaries that hold with equality (the lateral limits, the direct-toppling circles) are taken
# inclusive to within this round-off, so readings recorded in whole degrees that sit exactly on a
# limit count as inside it, whatever the rounding of the sines and cosines.
ROUND_OFF = 1e-12


@dataclass(frozen=True)
class Face:
    """A slope face: dip and dip direction [rad], floats or (F, 1) arrays."""

    dip: float | np.ndarray
    dip_direction: float | np.ndarray

    @classmethod
    def many(cls, dips: np.ndarray, dip_directions: np.ndarray) -> Face:
        """Faces of these dips and dip directions [rad] (broadcast to one length F), as (F, 1)."""
        dips, dip_directions = np.broadcast_arrays(np.asarray(dips, float), np.asarray(dip_directions, float))
        return cls(dips.reshape(-1, 1), dip_directions.reshape(-1, 1))


@dataclass(frozen=True)
class KinematicLimits:
    """Lateral limits [rad] of each mode, measured from the face's dip direction (planar sliding) or
    from its opposite (toppling), with Dips' defaults: +/-20 deg for planar sliding, +/-30 deg for
    flexural toppling (Goodman 1980's and Dips' tutorial value), +/-20 deg for direct toppling (the
    default of Dips' Kinematic Analysis dialog). Wedge sliding has none (Hudson & Harrison 1997).

    `curved` False: straight limits, lines through the centre of the net (Dips; Hudson & Harrison
    1997, ch. 18): the azimuth of the vector's horizontal part within +/-limit. True: curved limits,
    small circles about the face's strike (mplstereonet's default): the vector's angle from the
    vertical plane through the face's dip direction at most `limit`, on the face's side."""

    planar: float = np.radians(20.0)
    flexural_toppling: float = np.radians(30.0)
    direct_toppling: float = np.radians(20.0)
    curved: bool = False


def components(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The x, y and z components (N,) of unit vectors (N, 3)."""
    vectors = np.asarray(vectors, dtype=float)
    return vectors[..., 0], vectors[..., 1], vectors[..., 2]


def turned_towards(vectors: np.ndarray, azimuth: float | np.ndarray) -> tuple[np.ndarray, ...]:
    """Components of `vectors` (N, 3), those lying in the horizontal plane (an axis with no down
    sense: a vertical plane's pole, a horizontal line) turned to point towards `azimuth` [rad], the
    sense in which the criterion can be met; the others unchanged. On a lower-hemisphere net both
    senses of a horizontal axis are one point of the primitive circle."""
    x, y, z = components(vectors)
    flat = np.abs(z) < ROUND_OFF
    if not flat.any():
        return x, y, z
    sign = np.where(flat & (x * np.sin(azimuth) + y * np.cos(azimuth) < 0.0), -1.0, 1.0)
    return x * sign, y * sign, z  # z of a flat vector is below round-off: its sign is immaterial


def daylights(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    dip: float | np.ndarray,
    dip_direction: float | np.ndarray,
    inclusive: bool = False,
) -> np.ndarray:
    """True where the downward direction (x, y, z) points out of the plane (`dip`, `dip_direction`)
    into the air above it: v . n > 0, n the plane's upward normal. For a line of plunge p and trend t
    this is tan p < tan(dip) cos(t - dip direction), the line plunging less steeply than the plane's
    apparent dip along its trend (Priest 1993, eq. 2.6; Hudson & Harrison 1997, ch. 18): inside the
    great circle of the plane on a lower-hemisphere net (strict; `inclusive`: on the circle too, to
    within round-off)."""
    nx, ny, nz = pole_components(dip, dip_direction)
    product = x * nx + y * ny + z * nz
    return product >= -ROUND_OFF if inclusive else product > ROUND_OFF


def within_lateral_limits(
    x: np.ndarray, y: np.ndarray, z: np.ndarray, azimuth: float | np.ndarray, limit: float, curved: bool
) -> np.ndarray:
    """True where the vector (x, y, z) lies within +/-`limit` of `azimuth` [rad] (inclusive).

    Straight (Dips): the horizontal part h, its azimuth within the limits, h . a >= |h| cos(limit),
    a = (sin azimuth, cos azimuth); a vertical vector lies on every limit line and counts as inside.
    Curved (mplstereonet): |v . s| <= sin(limit) with s = (cos azimuth, -sin azimuth) the horizontal
    normal to the azimuth (the small circles of latitude +/-limit about the strike), and h . a >= 0."""
    along = x * np.sin(azimuth) + y * np.cos(azimuth)
    if curved:
        across = x * np.cos(azimuth) - y * np.sin(azimuth)
        return (np.abs(across) <= np.sin(limit) + ROUND_OFF) & (along >= -ROUND_OFF)
    return along >= np.hypot(x, y) * np.cos(limit) - ROUND_OFF
