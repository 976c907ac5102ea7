"""Convex polygons in a contact plane: Sutherland–Hodgman clipping, a segment clipped to a polygon,
and the area and centroid of a polygon, as numba functions over (n, 2) float64 arrays [m].

Polygons are counter-clockwise vertex loops in the plane's own coordinates (s, t). Clipping a convex
subject polygon by a convex clip polygon keeps, edge by edge of the clip polygon, the part of the
subject on the left of that edge (Sutherland & Hodgman 1974, "Reentrant polygon clipping", Comm. ACM
17(1)); the result is their intersection, convex, with at most n + m vertices.
"""

import numba
import numpy as np

DEGENERATE_EDGE = 1e-9  # x a clip polygon's extent: an edge this short has no reliable direction


@numba.njit(cache=True, inline="always")
def _side(c0, c1, p):
    """Twice the signed area of triangle (c0, c1, p) [m²]: > 0 with p on the left of c0 -> c1."""
    return (c1[0] - c0[0]) * (p[1] - c0[1]) - (c1[1] - c0[1]) * (p[0] - c0[0])


@numba.njit(cache=True, inline="always")
def _extent(poly):
    """The larger side of a polygon's bounding box [m]; 0 for no vertices."""
    if poly.shape[0] == 0:
        return 0.0
    lo_s, hi_s, lo_t, hi_t = poly[0, 0], poly[0, 0], poly[0, 1], poly[0, 1]
    for i in range(1, poly.shape[0]):
        lo_s, hi_s = min(lo_s, poly[i, 0]), max(hi_s, poly[i, 0])
        lo_t, hi_t = min(lo_t, poly[i, 1]), max(hi_t, poly[i, 1])
    return max(hi_s - lo_s, hi_t - lo_t)


@numba.njit(cache=True)
def clip_polygon(subject, clip):
    """The intersection of two convex counter-clockwise polygons (Sutherland–Hodgman), as an (k, 2)
    counter-clockwise polygon; k = 0 where they do not overlap. A clip edge shorter than
    `DEGENERATE_EDGE` x the clip polygon's extent is passed over: its direction is round-off (two
    near-copies of a vertex, as clipping leaves where two faces' edges coincide), so its half-plane
    could cut away any part of the subject, while its neighbours already bound the polygon there."""
    cap = subject.shape[0] + clip.shape[0] + 1
    out = np.empty((cap, 2))
    work = np.empty((cap, 2))
    n = subject.shape[0]
    out[:n] = subject
    m = clip.shape[0]
    shortest = (DEGENERATE_EDGE * _extent(clip)) ** 2
    for c in range(m):
        if n == 0:
            break
        c0, c1 = clip[c], clip[(c + 1) % m]
        if (c1[0] - c0[0]) ** 2 + (c1[1] - c0[1]) ** 2 <= shortest:
            continue
        work[:n] = out[:n]
        k = 0
        for i in range(n):
            s, e = work[i - 1 if i > 0 else n - 1], work[i]
            ds, de = _side(c0, c1, s), _side(c0, c1, e)
            if de >= 0.0:
                if ds < 0.0:
                    t = ds / (ds - de)
                    out[k, 0], out[k, 1] = s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1])
                    k += 1
                out[k] = e
                k += 1
            elif ds >= 0.0:
                t = ds / (ds - de)
                out[k, 0], out[k, 1] = s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1])
                k += 1
        n = k
    return out[:n].copy()


@numba.njit(cache=True)
def clip_segment(p0, p1, clip):
    """Segment p0 -> p1 clipped to a convex counter-clockwise polygon (Cyrus–Beck): (inside, q0, q1),
    q0 and q1 the ends of the part inside, inside False where none of it is."""
    lo, hi = 0.0, 1.0
    m = clip.shape[0]
    for c in range(m):
        c0, c1 = clip[c], clip[(c + 1) % m]
        d0, d1 = _side(c0, c1, p0), _side(c0, c1, p1)
        if d0 < 0.0 and d1 < 0.0:
            return False, p0.copy(), p1.copy()
        if d0 < 0.0:
            lo = max(lo, d0 / (d0 - d1))
        elif d1 < 0.0:
            hi = min(hi, d0 / (d0 - d1))
    if hi < lo:
        return False, p0.copy(), p1.copy()
    return True, p0 + lo * (p1 - p0), p0 + hi * (p1 - p0)


@numba.njit(cache=True)
def polygon_area_centroid(poly):
    """Area [m²] and centroid (s, t) [m] of a counter-clockwise polygon (shoelace formula, about its
    first vertex to keep round-off small); (0, first vertex) for fewer than 3 vertices or no area."""
    n = poly.shape[0]
    if n < 3:
        return (0.0, poly[0, 0], poly[0, 1]) if n > 0 else (0.0, 0.0, 0.0)
    ox, oy = poly[0, 0], poly[0, 1]
    twice, sx, sy = 0.0, 0.0, 0.0
    for i in range(1, n - 1):
        ax, ay = poly[i, 0] - ox, poly[i, 1] - oy
        bx, by = poly[i + 1, 0] - ox, poly[i + 1, 1] - oy
        cross = ax * by - ay * bx
        twice += cross
        sx += cross * (ax + bx)
        sy += cross * (ay + by)
    if twice <= 0.0:
        return 0.0, ox, oy
    return 0.5 * twice, ox + sx / (3.0 * twice), oy + sy / (3.0 * twice)


@numba.njit(cache=True)
def clip_half_plane(poly, a, b, c):
    """The part of a convex counter-clockwise polygon where a s + b t + c >= 0 (one Sutherland–Hodgman
    pass against a line), counter-clockwise; (0, 2) where none of it is."""
    n = poly.shape[0]
    out = np.empty((n + 1, 2))
    k = 0
    for i in range(n):
        s, e = poly[i - 1 if i > 0 else n - 1], poly[i]
        ds, de = a * s[0] + b * s[1] + c, a * e[0] + b * e[1] + c
        if de >= 0.0:
            if ds < 0.0:
                u = ds / (ds - de)
                out[k, 0], out[k, 1] = s[0] + u * (e[0] - s[0]), s[1] + u * (e[1] - s[1])
                k += 1
            out[k] = e
            k += 1
        elif ds >= 0.0:
            u = ds / (ds - de)
            out[k, 0], out[k, 1] = s[0] + u * (e[0] - s[0]), s[1] + u * (e[1] - s[1])
            k += 1
    return out[:k].copy()


@numba.njit(cache=True)
def polygon_moments(poly):
    """Area A [m²], centroid (s, t) [m] and second moments about the centroid, the integrals of
    (s - s_c)², (s - s_c)(t - t_c) and (t - t_c)² over the polygon [m⁴], of a counter-clockwise polygon:
    summed over its fan of triangles (o, a, b) from its first vertex o, each exact: with a, b relative
    to o and d the triangle's area, the integrals of s², s t and t² are d (a_s² + a_s b_s + b_s²) / 6,
    d (2 a_s a_t + a_s b_t + b_s a_t + 2 b_s b_t) / 12 and d (a_t² + a_t b_t + b_t²) / 6, moved to the
    centroid by the parallel-axis theorem. Zeros for fewer
    than 3 vertices or no area."""
    n = poly.shape[0]
    if n < 3:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    ox, oy = poly[0, 0], poly[0, 1]
    area, sx, sy, sxx, sxy, syy = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(1, n - 1):
        ax, ay = poly[i, 0] - ox, poly[i, 1] - oy
        bx, by = poly[i + 1, 0] - ox, poly[i + 1, 1] - oy
        d = 0.5 * (ax * by - ay * bx)  # the triangle (o, a, b)'s area
        area += d
        sx += d * (ax + bx) / 3.0
        sy += d * (ay + by) / 3.0
        sxx += d * (ax * ax + ax * bx + bx * bx) / 6.0
        sxy += d * (2.0 * ax * ay + ax * by + bx * ay + 2.0 * bx * by) / 12.0
        syy += d * (ay * ay + ay * by + by * by) / 6.0
    if area <= 0.0:
        return 0.0, ox, oy, 0.0, 0.0, 0.0
    cx, cy = sx / area, sy / area
    return area, ox + cx, oy + cy, sxx - area * cx * cx, sxy - area * cx * cy, syy - area * cy * cy
