"""A slope's cross-section as the engineer gives it: the ground surface (a polyline, or benches and
berms), flat ground in front of the toe and behind the crest, and a base below the toe.

Plain numpy; metres, the toe side to the left (-x), the free face looking towards -x.
"""

from __future__ import annotations

import math

import numpy as np

from bbmc.geometry.polygons import _without_repeats


def bench_surface(height_m: float, face_angle_deg: float, berm_width_m: float, count: int) -> np.ndarray:
    """The ground surface [m] of `count` benches from the toe at the origin to the crest: faces of
    `height_m` at `face_angle_deg` from the horizontal, separated by berms `berm_width_m` wide."""
    run = height_m / math.tan(math.radians(face_angle_deg))
    points = [(0.0, 0.0)]
    for bench in range(count):
        x, y = points[-1]
        points.append((x + run, y + height_m))
        if bench < count - 1 and berm_width_m > 0:
            points.append((x + run + berm_width_m, y + height_m))
    return np.array(points)


def overall_angle_deg(surface: np.ndarray) -> float:
    """The overall slope angle [deg]: of the line from the toe (first point) to the crest (last). For
    n benches of height h, face angle a and berm width b: tan = n h / (n h cot a + (n - 1) b)."""
    dx, dy = surface[-1] - surface[0]
    return math.degrees(math.atan2(dy, dx))


def body_outline(
    surface: np.ndarray, toe_extent_m: float, crest_extent_m: float, depth_m: float
) -> np.ndarray:
    """The rock's cross-section, counter-clockwise: the base `depth_m` below the toe (the surface's first
    point), vertical sides `toe_extent_m` in front of the toe and `crest_extent_m` behind the crest;
    repeated and collinear points dropped."""
    (toe_x, toe_y), (crest_x, crest_y) = surface[0], surface[-1]
    left, right, base = toe_x - toe_extent_m, crest_x + crest_extent_m, toe_y - depth_m
    ground = np.vstack([[left, toe_y], surface, [right, crest_y]])
    return _without_repeats(np.vstack([[left, base], [right, base], ground[::-1]]))


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _meet(p: np.ndarray, q: np.ndarray, r: np.ndarray, s: np.ndarray, tolerance: float) -> np.ndarray | None:
    """A point the closed segments pq and rs share, or None."""
    u, v, w = q - p, s - r, r - p
    denominator = _cross(u, v)
    if abs(denominator) > tolerance * np.hypot(*u) * np.hypot(*v):
        a, b = _cross(w, v) / denominator, _cross(w, u) / denominator
        inside = -tolerance <= a <= 1 + tolerance and -tolerance <= b <= 1 + tolerance
        return p + a * u if inside else None
    if abs(_cross(w, u)) > tolerance * np.hypot(*u) * max(np.hypot(*w), tolerance):
        return None  # parallel, on different lines
    length2 = float(u @ u)
    low, high = sorted(((r - p) @ u / length2, (s - p) @ u / length2))
    start, end = max(low, 0.0), min(high, 1.0)
    return p + 0.5 * (start + end) * u if start <= end + tolerance else None


def first_crossing(
    points: np.ndarray, closed: bool, tolerance: float = 1e-9
) -> tuple[int, int, np.ndarray] | None:
    """Where a polyline (closed: a polygon) crosses or touches itself: the indices of two segments and
    a point they share, or None if it is simple. Neighbouring segments may share their common point
    only (a fold back along the other one is a crossing); a segment of zero length is one too (i, i)."""
    n = len(points)
    segments = n if closed else n - 1
    lengths = np.hypot(*(np.roll(points, -1, axis=0) - points).T)[:segments]
    if np.any(lengths <= tolerance * max(1.0, float(np.ptp(points, axis=0).max()))):
        index = int(np.argmin(lengths))
        return index, index, points[index]
    for i in range(segments):
        p, q = points[i], points[(i + 1) % n]
        for j in range(i + 1, segments):
            r, s = points[j], points[(j + 1) % n]
            after, before = j == i + 1, closed and i == 0 and j == segments - 1
            if after or before:
                shared, far_i, far_j = (q, p, s) if after else (p, q, r)
                a, b = far_i - shared, far_j - shared
                if abs(_cross(a, b)) <= tolerance * lengths[i] * lengths[j] and a @ b > 0:
                    return i, j, shared
                continue
            point = _meet(p, q, r, s, tolerance)
            if point is not None:
                return i, j, point
    return None


def crack_water_table(
    surface: np.ndarray, behind_crest: float, crack_depth: float, fill: float
) -> np.ndarray:
    """The phreatic surface [m] of a tension crack filled to `fill` (0 to 1) of its depth: straight from
    the toe (the surface's first point) to the water in the crack, level beyond both (Hoek & Bray's
    assumption, RocPlane's percent filling): on a plane from the crack's foot to the toe the pressure is
    triangular, gamma_w z_w at the foot, 0 at the toe."""
    toe, crest = surface[0], surface[-1]
    level = crest[1] - crack_depth * (1.0 - fill)
    return np.array([[toe[0], toe[1]], [crest[0] + behind_crest, level]])


def profile_water_table(
    surface: np.ndarray, crest_extent_m: float, height_above_toe_m: float, depth_below_crest_m: float
) -> np.ndarray:
    """The phreatic surface [m] given against the profile: straight from `height_above_toe_m` above the
    toe (the surface's first point) to `depth_below_crest_m` below the crest's level at the model's back
    edge, `crest_extent_m` behind the crest (the surface's last point); level beyond both."""
    toe, crest = surface[0], surface[-1]
    back = crest[0] + crest_extent_m
    return np.array([[toe[0], toe[1] + height_above_toe_m], [back, crest[1] - depth_below_crest_m]])
