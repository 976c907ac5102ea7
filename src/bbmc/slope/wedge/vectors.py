"""Vector algebra on stacks of 3-vectors (..., 3), for the wedge computed over many samples at once.

Each function works on the last axis and broadcasts over the others; written component by component
because `np.cross` and `np.linalg.det` on (N, 3) stacks are several times slower than these sums, and
components are stacked by writing them into one array (`np.stack` costs ~5 us a call, which is most of
a single wedge's time).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

Vectors = NDArray[np.float64]


def stacked(x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64]) -> Vectors:
    """The vectors (..., 3) of components x, y, z (broadcast together)."""
    shape = x.shape
    if not y.shape == z.shape == shape:
        shape = np.broadcast_shapes(shape, y.shape, z.shape)
    out = np.empty((*shape, 3))
    out[..., 0], out[..., 1], out[..., 2] = x, y, z
    return out


def spread(value: ArrayLike, shape: tuple[int, ...]) -> NDArray:
    """`value` as an array broadcast to `shape`: itself where it has that shape already (a read-only
    view from `np.broadcast_to`, ~8 us a call, only where it has not)."""
    value = np.asarray(value)
    return value if value.shape == shape else np.broadcast_to(value, shape)


def dot(a: Vectors, b: Vectors) -> NDArray[np.float64]:
    """a . b over the last axis, shape (...)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def cross(a: Vectors, b: Vectors) -> Vectors:
    """a x b over the last axis, shape (..., 3)."""
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    bx, by, bz = b[..., 0], b[..., 1], b[..., 2]
    return stacked(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)


def norm(a: Vectors) -> NDArray[np.float64]:
    """|a| over the last axis, shape (...)."""
    return np.sqrt(dot(a, a))


def unit(a: Vectors) -> Vectors:
    """a / |a| (NaN where |a| = 0)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return a / norm(a)[..., None]


def triangle_area(a: Vectors, b: Vectors, c: Vectors) -> NDArray[np.float64]:
    """Area of the triangles a b c: |(b - a) x (c - a)| / 2."""
    return 0.5 * norm(cross(b - a, c - a))


def tetrahedron_volume(a: Vectors, b: Vectors, c: Vectors, d: Vectors) -> NDArray[np.float64]:
    """Volume of the tetrahedra a b c d: |(b - a) . ((c - a) x (d - a))| / 6."""
    return np.abs(dot(b - a, cross(c - a, d - a))) / 6.0


def angle_between(a: Vectors, b: Vectors) -> NDArray[np.float64]:
    """The angle [rad] between vectors a and b (0 to pi): atan2(|a x b|, a . b), accurate at 0 and pi."""
    return np.arctan2(norm(cross(a, b)), dot(a, b))
