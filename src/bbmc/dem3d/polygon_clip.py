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
def clip_into(subject, n, clip, out, work):
    """The intersection of the convex counter-clockwise polygon subject[:n] with a convex
    counter-clockwise polygon `clip` (Sutherland–Hodgman), left in out[:k]; returns k (0 where they do
    not overlap). out and work are scratch of at least n + len(clip) + 1 rows, neither of them subject;
    the passes go from one to the other in turn. A clip edge shorter than `DEGENERATE_EDGE` x the clip
    polygon's extent is passed over: its direction is round-off (two near-copies of a vertex, as
    clipping leaves where two faces' edges coincide), so its half-plane could cut away any part of the
    subject, while its neighbours already bound the polygon there."""
    out[:n] = subject[:n]
    src, dst, flipped = out, work, False
    m = clip.shape[0]
    shortest = (DEGENERATE_EDGE * _extent(clip)) ** 2
    for c in range(m):
        if n == 0:
            break
        d = (c + 1) % m
        c0s, c0t, ds_, dt_ = clip[c, 0], clip[c, 1], clip[d, 0] - clip[c, 0], clip[d, 1] - clip[c, 1]
        if ds_ * ds_ + dt_ * dt_ <= shortest:
            continue
        k = 0
        ss, st = src[n - 1, 0], src[n - 1, 1]
        side_s = ds_ * (st - c0t) - dt_ * (ss - c0s)
        for i in range(n):
            es, et = src[i, 0], src[i, 1]
            side_e = ds_ * (et - c0t) - dt_ * (es - c0s)
            if side_e >= 0.0:
                if side_s < 0.0:
                    t = side_s / (side_s - side_e)
                    dst[k, 0], dst[k, 1] = ss + t * (es - ss), st + t * (et - st)
                    k += 1
                dst[k, 0], dst[k, 1] = es, et
                k += 1
            elif side_s >= 0.0:
                t = side_s / (side_s - side_e)
                dst[k, 0], dst[k, 1] = ss + t * (es - ss), st + t * (et - st)
                k += 1
            ss, st, side_s = es, et, side_e
        n = k
        src, dst, flipped = dst, src, not flipped
    if flipped:
        out[:n] = work[:n]
    return n


@numba.njit(cache=True)
def clip_polygon(subject, clip):
    """The intersection of two convex counter-clockwise polygons (Sutherland–Hodgman, `clip_into`), as
    an (k, 2) counter-clockwise polygon; k = 0 where they do not overlap."""
    scratch = np.empty((2, subject.shape[0] + clip.shape[0] + 1, 2))
    return scratch[0, : clip_into(subject, subject.shape[0], clip, scratch[0], scratch[1])]


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
def half_plane_into(poly, n, a, b, c, out):
    """The part of the convex counter-clockwise polygon poly[:n] where a s + b t + c >= 0 (one
    Sutherland–Hodgman pass against a line), counter-clockwise, left in out[:k] (at least n + 1 rows,
    not poly); returns k (0 where none of it is)."""
    k = 0
    if n == 0:
        return k
    ss, st = poly[n - 1, 0], poly[n - 1, 1]
    side_s = a * ss + b * st + c
    for i in range(n):
        es, et = poly[i, 0], poly[i, 1]
        side_e = a * es + b * et + c
        if side_e >= 0.0:
            if side_s < 0.0:
                u = side_s / (side_s - side_e)
                out[k, 0], out[k, 1] = ss + u * (es - ss), st + u * (et - st)
                k += 1
            out[k, 0], out[k, 1] = es, et
            k += 1
        elif side_s >= 0.0:
            u = side_s / (side_s - side_e)
            out[k, 0], out[k, 1] = ss + u * (es - ss), st + u * (et - st)
            k += 1
        ss, st, side_s = es, et, side_e
    return k


@numba.njit(cache=True)
def clip_half_plane(poly, a, b, c):
    """The part of a convex counter-clockwise polygon where a s + b t + c >= 0 (`half_plane_into`),
    counter-clockwise; (0, 2) where none of it is."""
    out = np.empty((poly.shape[0] + 1, 2))
    return out[: half_plane_into(poly, poly.shape[0], a, b, c, out)].copy()


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
