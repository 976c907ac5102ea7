"""The fast path of the wedge's geometry: only what the vector solution needs (the normals of planes 1
and 2 into the wedge, the line of intersection, the areas A1 and A2, the volume V and the total height
H) and the wedge's `WedgeReason`, for many wedges without a tension crack, in one compiled pass.

`geometry.wedge_geometries` is the full path (every vertex, area, trace length and angle, NaN-masked,
with a crack); it costs ~46 stacked (N, 3) temporaries and runs at ~0.5 M wedges/s on one core. The
kernel here follows the same construction scalar by scalar (geometry's module docstring: the points
x = d (n_p x n_q) / (u . (n_p x n_q)), the same conditions in the same order, the same tolerance), so
its outputs equal the full path's to rounding: `tests/test_wedge_analysis.py` checks them to 1e-12 on
random wedges, formed or not. Angles rad, lengths m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.geometry import TOLERANCE, WedgeReason

Array = NDArray[np.float64]


@dataclass(frozen=True)
class WedgeEssentials:
    """What the mechanics needs of wedges (fields as `geometry.WedgeGeometry`'s of the same name; NaN
    where the wedge does not form): `normal_1`, `normal_2` (n, 3) into the wedge, `line` (n, 3) the
    downward line of intersection, `area_1`, `area_2` [m^2], `volume` [m^3], `height_h` [m], `reason`."""

    normal_1: Array
    normal_2: Array
    line: Array
    area_1: Array
    area_2: Array
    volume: Array
    height_h: Array
    reason: NDArray[np.int8]

    @property
    def formed(self) -> NDArray[np.bool_]:
        """True where the wedge forms."""
        return self.reason == WedgeReason.FORMED


@numba.njit(cache=True, inline="always")
def _cross(a: tuple, b: tuple) -> tuple:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@numba.njit(cache=True, inline="always")
def _dot(a: tuple, b: tuple) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(cache=True, inline="always")
def _pole(dip: float, direction: float) -> tuple:
    return (math.sin(dip) * math.sin(direction), math.sin(dip) * math.cos(direction), math.cos(dip))


@numba.njit(cache=True, inline="always")
def _on_upper(p: tuple, q: tuple, u: tuple) -> tuple:
    """The point on planes p, q and on u . x = 1, and |u . e| for e the unit direction of p x q."""
    d = _cross(p, q)
    along = _dot(u, d)
    length = math.sqrt(_dot(d, d))
    if along == 0.0:
        return (math.nan, math.nan, math.nan), 0.0 if length > 0.0 else math.nan
    return (d[0] / along, d[1] / along, d[2] / along), abs(along) / length


@numba.njit(cache=True)
def _wedge_kernel(angles, overhanging, height, height_is_h1, normals, lines, scalars, reasons):
    """Per wedge i: `angles[:, i]` the 8 dips and dip directions (planes 1, 2, face, upper), then
    normals[0|1, i], lines[i], scalars[:, i] = A1, A2, V, H and the reason code (NaN if not formed)."""
    tol = TOLERANCE
    for i in range(angles.shape[1]):
        p1 = _pole(angles[0, i], angles[1, i])
        p2 = _pole(angles[2, i], angles[3, i])
        f = _pole(angles[4, i], angles[5, i])
        if overhanging[i]:
            f = (f[0], f[1], -f[2])
        u = _pole(angles[6, i], angles[7, i])
        c1, along_1 = _on_upper(p1, f, u)
        c2, along_2 = _on_upper(p2, f, u)
        top, along_line = _on_upper(p1, p2, u)
        up = (-f[2] * f[0], -f[2] * f[1], 1.0 - f[2] * f[2])
        up_length = math.sqrt(_dot(up, up))
        fu = _cross(f, u)
        convex = math.sqrt(_dot(fu, fu)) > tol and _dot(u, up) / up_length > tol
        d = _cross(p1, p2)
        sine = math.sqrt(_dot(d, d))
        line = (d[0] / sine, d[1] / sine, d[2] / sine) if sine > 0.0 else (math.nan, math.nan, math.nan)
        if line[2] > 0.0:
            line = (-line[0], -line[1], -line[2])
        behind = _dot(f, top) < -tol * math.sqrt(_dot(top, top))
        point = c1 if height_is_h1 else top
        below = not point[2] > tol * math.sqrt(_dot(point, point))
        if not convex:
            reason = 1
        elif not sine > tol:
            reason = 2
        elif not (along_1 > tol and along_2 > tol):
            reason = 3
        elif not behind and not _dot(f, line) > tol:
            reason = 4
        elif not behind or not along_line > tol:
            reason = 5
        elif below:
            reason = 6
        else:
            reason = 0
        reasons[i] = reason
        if reason != 0:
            for k in range(3):
                normals[0, i, k] = normals[1, i, k] = lines[i, k] = math.nan
            for k in range(4):
                scalars[k, i] = math.nan
            continue
        scale = height[i] / point[2]
        c1 = (scale * c1[0], scale * c1[1], scale * c1[2])
        c2 = (scale * c2[0], scale * c2[1], scale * c2[2])
        top = (scale * top[0], scale * top[1], scale * top[2])
        s1 = -1.0 if _dot(p1, c2) < 0.0 else 1.0
        s2 = -1.0 if _dot(p2, c1) < 0.0 else 1.0
        for k in range(3):
            normals[0, i, k] = s1 * p1[k]
            normals[1, i, k] = s2 * p2[k]
            lines[i, k] = line[k]
        a1, a2 = _cross(c1, top), _cross(c2, top)
        scalars[0, i] = 0.5 * math.sqrt(_dot(a1, a1))
        scalars[1, i] = 0.5 * math.sqrt(_dot(a2, a2))
        scalars[2, i] = abs(_dot(c1, _cross(c2, top))) / 6.0
        scalars[3, i] = top[2]


def wedge_essentials(
    dip_1: ArrayLike,
    dip_direction_1: ArrayLike,
    dip_2: ArrayLike,
    dip_direction_2: ArrayLike,
    face_dip: ArrayLike,
    face_dip_direction: ArrayLike,
    upper_dip: ArrayLike,
    upper_dip_direction: ArrayLike,
    *,
    height_h1: ArrayLike | None = None,
    height_h: ArrayLike | None = None,
    overhanging_face: ArrayLike = False,
) -> WedgeEssentials:
    """The mechanics' part of `geometry.wedge_geometries` (same arguments but the crack, same checks and
    ValueErrors) for a batch of wedges: every argument broadcast to one 1-D shape (n,) or scalars."""
    dips = {"dip_1": dip_1, "dip_2": dip_2, "face_dip": face_dip, "upper_dip": upper_dip}
    for key, value in dips.items():
        value = np.asarray(value, dtype=float)
        if np.any(~((value >= 0.0) & (value <= np.pi / 2.0))):
            raise ValueError(f"{key}: a dip must be 0 to 90 degrees")
    if np.any(~(np.asarray(face_dip, dtype=float) > 0.0)):
        raise ValueError("face_dip: the face must dip (> 0)")
    if (height_h1 is None) == (height_h is None):
        raise ValueError("height_h1, height_h: give exactly one")
    key, height = ("height_h1", height_h1) if height_h1 is not None else ("height_h", height_h)
    if np.any(~(np.asarray(height, dtype=float) > 0.0)):
        raise ValueError(f"{key}: a height must be > 0")
    inputs = (dip_1, dip_direction_1, dip_2, dip_direction_2, face_dip, face_dip_direction)
    arrays = np.broadcast_arrays(
        *(np.asarray(a, dtype=float) for a in (*inputs, upper_dip, upper_dip_direction, height)),
        np.asarray(overhanging_face, dtype=bool),
    )
    shape = arrays[0].shape
    count = int(np.prod(shape))
    angles = np.stack([np.ravel(a) for a in arrays[:8]])
    normals, lines = np.empty((2, count, 3)), np.empty((count, 3))
    scalars, reasons = np.empty((4, count)), np.empty(count, dtype=np.int8)
    _wedge_kernel(
        angles,
        np.ravel(arrays[9]),
        np.ravel(arrays[8]),
        height_h1 is not None,
        normals,
        lines,
        scalars,
        reasons,
    )
    vector = (*shape, 3)
    return WedgeEssentials(
        normals[0].reshape(vector),
        normals[1].reshape(vector),
        lines.reshape(vector),
        *(s.reshape(shape) for s in scalars),
        reasons.reshape(shape),
    )
