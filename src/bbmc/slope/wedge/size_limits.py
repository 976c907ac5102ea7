"""Swedge's optional limits on a wedge's size (Rocscience Swedge help: "Bench Width", "Slope Length",
"Scale Wedge"), for one wedge or arrays of wedges.

By default the wedge is as large as the height makes it: the joints, the face and the upper surface
of infinite extent. Each limit caps one extent of the wedge; Swedge then *scales* the wedge ("the wedge
size has been scaled accordingly"): the same planes, the same shape, a smaller size. For the tetrahedron
O C1 C2 T of `geometry` a homothety about the toe O is a smaller height: every length is multiplied by
the scale factor s, areas by s^2, the volume by s^3. Where several limits are given, the one that
gives the smallest wedge governs (Swedge: "only the scaling parameter which gives the smallest wedge
will be applied"). The extents, each a length that grows in proportion to s:

    along the crest   max - min of the vertices' projections on the crest's direction e = f x u / |f x u|
                      (Swedge's slope length: "the maximum extent of the wedge, as measured along the
                      crest of the slope", the line where the face meets the upper surface)
    behind the crest  the horizontal distance, in plan and square to the crest's plan, of the rearmost
                      vertex on the upper surface from the crest (Swedge's bench width, "always measured
                      as the HORIZONTAL distance from the crest"; RocPlane: "to the rearmost wedge vertex
                      on the Upper Face")
    trace of plane k  max(its trace on the face, its trace on the upper surface) (Swedge's Scale Wedge
                      trace length: "for a given joint the maximum of the Slope Face or Upper Face trace
                      length is used")
    persistence of k  the largest distance between two points of the wedge's face on plane k, the
                      longest side or diagonal of that polygon (Swedge: "the maximum dimension between
                      any two points, as measured on the wedge failure surfaces")
    volume            the wedge's volume (Swedge's Scale Wedge volume), which grows as s^3

    s = min(1, min_k limit_k / extent_k, (volume limit / V)^(1/3))       extents at the given height

A limit larger than the wedge changes nothing (s = 1). The crack: Swedge places it at the distance L
from the crest, a length that does not scale with the wedge, so shrinking the cracked wedge changes its
shape, not only its size, and the crack may then miss it; bbmc refuses the two together (Swedge's bench
design likewise takes only tetrahedral wedges, and RocPlane refuses a bench width inside the crack).
Lengths in m, volumes in m^3.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, fields
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.vectors import cross, dot, norm, unit

Array = NDArray[np.float64]


class SizeLimit(IntEnum):
    """What sets a wedge's size: its height, or the limit that scaled it down."""

    HEIGHT = 0
    BENCH_WIDTH = 1
    SLOPE_LENGTH = 2
    TRACE_LENGTH_PLANE_1 = 3
    TRACE_LENGTH_PLANE_2 = 4
    PERSISTENCE_PLANE_1 = 5
    PERSISTENCE_PLANE_2 = 6
    VOLUME = 7


LIMIT_NAMES = np.array([limit.name.lower() for limit in SizeLimit])


@dataclass(frozen=True)
class SizeLimits:
    """The limits on wedges' size [m, m^3], each None (no limit) or > 0, a scalar or an array broadcast
    with the wedges: the bench width, the slope length, each plane's trace length and persistence, the
    volume (module docstring)."""

    bench_width: ArrayLike | None = None
    slope_length: ArrayLike | None = None
    trace_length_plane_1: ArrayLike | None = None
    trace_length_plane_2: ArrayLike | None = None
    persistence_plane_1: ArrayLike | None = None
    persistence_plane_2: ArrayLike | None = None
    volume: ArrayLike | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if value is not None and np.any(~(np.asarray(value, dtype=float) > 0.0)):
                raise ValueError(f"{f.name}: a size limit must be > 0")

    def any(self) -> bool:
        """True where some limit is given."""
        return any(getattr(self, f.name) is not None for f in fields(self))


@dataclass(frozen=True)
class WedgeExtents:
    """A wedge's extents [m] (module docstring), of the batch's shape: along and behind the crest, each
    plane's trace length and persistence."""

    along_crest: Array
    behind_crest: Array
    trace_length_plane_1: Array
    trace_length_plane_2: Array
    persistence_plane_1: Array
    persistence_plane_2: Array


# Vertex indices in `WedgeGeometry.vertices`: O C1 C2 T, or O C1 C2 P Q R with a crack.
_LAYOUT = {
    4: {"plane_1": (0, 1, 3), "plane_2": (0, 2, 3), "upper": (1, 2, 3), "upper_1": 3, "upper_2": 3},
    6: {"plane_1": (0, 1, 3, 5), "plane_2": (0, 2, 4, 5), "upper": (1, 2, 3, 4), "upper_1": 3, "upper_2": 4},
}


def _diameter(vertices: Array, polygon: tuple[int, ...]) -> Array:
    """The largest distance between two vertices of `polygon` (its points' largest distance: convex)."""
    pairs = itertools.combinations(polygon, 2)
    return np.max([norm(vertices[..., a, :] - vertices[..., b, :]) for a, b in pairs], axis=0)


def _behind_crest(face: Array, upper: Array) -> Array:
    """The horizontal unit vector square to the crest's plan that points from the crest into the rock:
    b, and b - (u . b / u_z) z (b taken onto the upper surface) goes behind the face, f . that < 0."""
    crest = cross(face, upper)
    square = unit(np.stack([-crest[..., 1], crest[..., 0], np.zeros_like(crest[..., 0])], axis=-1))
    ahead = dot(square, face) - dot(upper, square) * face[..., 2] / upper[..., 2]
    return np.where((ahead > 0.0)[..., None], -square, square)


def wedge_extents(vertices: Array, face: Array, upper: Array) -> WedgeExtents:
    """The extents of wedges (module docstring) from their vertices (..., 4, 3) O C1 C2 T or (..., 6, 3)
    O C1 C2 P Q R [m], the face's and the upper surface's normals out of the rock (..., 3)."""
    layout = _LAYOUT[vertices.shape[-2]]
    along = dot(vertices, unit(cross(face, upper))[..., None, :])
    crest_1 = vertices[..., 1, :]
    back = _behind_crest(face, upper)[..., None, :]
    behind = np.max(dot(vertices[..., list(layout["upper"]), :] - crest_1[..., None, :], back), axis=-1)
    upper_1 = norm(vertices[..., layout["upper_1"], :] - crest_1)
    upper_2 = norm(vertices[..., layout["upper_2"], :] - vertices[..., 2, :])
    return WedgeExtents(
        along_crest=np.max(along, axis=-1) - np.min(along, axis=-1),
        behind_crest=behind,
        trace_length_plane_1=np.maximum(norm(crest_1), upper_1),
        trace_length_plane_2=np.maximum(norm(vertices[..., 2, :]), upper_2),
        persistence_plane_1=_diameter(vertices, layout["plane_1"]),
        persistence_plane_2=_diameter(vertices, layout["plane_2"]),
    )


def size_scale(
    limits: SizeLimits, vertices: Array, volume: Array, face: Array, upper: Array
) -> tuple[Array, NDArray[np.int8]]:
    """The scale factor s (0 < s <= 1) that brings wedges of `vertices` (..., 4, 3) [m] and `volume`
    [m^3] within every one of `limits` (module docstring), and the `SizeLimit` that governs (HEIGHT
    where none scales the wedge down). NaN extents (wedges that do not form) limit nothing."""
    extents = wedge_extents(vertices, face, upper)
    caps = (
        (limits.bench_width, extents.behind_crest),
        (limits.slope_length, extents.along_crest),
        (limits.trace_length_plane_1, extents.trace_length_plane_1),
        (limits.trace_length_plane_2, extents.trace_length_plane_2),
        (limits.persistence_plane_1, extents.persistence_plane_1),
        (limits.persistence_plane_2, extents.persistence_plane_2),
        (limits.volume, volume),
    )
    ratios = [np.ones_like(volume)]
    with np.errstate(invalid="ignore", divide="ignore"):
        for code, (limit, extent) in zip(list(SizeLimit)[1:], caps, strict=True):
            ratio = np.inf if limit is None else np.asarray(limit, dtype=float) / extent
            ratios.append(np.cbrt(ratio) if code == SizeLimit.VOLUME else ratio)
    stacked = np.stack(np.broadcast_arrays(*ratios), axis=0)
    stacked = np.where(np.isnan(stacked), np.inf, stacked)
    governing = np.argmin(stacked, axis=0).astype(np.int8)
    return np.min(stacked, axis=0), governing
