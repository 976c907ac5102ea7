"""A face–face contact's overlap and its sub-contacts' shares, as numba functions over the flat arrays
of `bbmc.dem3d.contact_geometry` (its module docstring gives the layout). Lengths in m, areas in m².

The overlap of a reference face and the other block's face facing it (the incident face): the incident
face projected on the reference plane along its normal and clipped to the reference face
(Sutherland–Hodgman, `bbmc.dem3d.polygon_clip`), in the reference face's own (s, t) coordinates.

Sub-contacts of a face–face contact (`face_sub_contacts`): the reference face is cut into triangles, a
fan from its first vertex, each split into four at its mid-sides `refine` times; a sub-contact sits at
each triangle's centroid, fixed to the reference block, so it keeps its shear history as the blocks
slide. Its share of the overlap is the triangle clipped to the overlap polygon, integrated exactly (area
and centroid): shares never overlap, they tile the overlap, and they sum to its area whatever the
refinement. 3DEC puts sub-contacts at the triangulation's vertices with a third of each neighbouring
triangle's area, all or nothing as the vertex is inside the other face or not, which makes the area
depend on the refinement; 2D bbmc's lesson (`bbmc.dem.contact_geometry`) was to integrate each share.

Scratch: a contact's shares are clipped into three rows of one array allocated once per contact, not
per share (`face_shares`).
"""

import math

import numba
import numpy as np

from bbmc.dem3d.polygon_clip import (
    clip_into,
    clip_polygon,
    half_plane_into,
    polygon_area_centroid,
    polygon_moments,
)


@numba.njit(cache=True)
def face_frame(vertices, face_vertices, face_start, face_normal, f):
    """Origin (the face's first vertex) and in-plane unit axes s, t of face f, s x t = its normal (the
    rows of one (3, 3) array)."""
    frame = np.empty((3, 3))
    o, s, t = frame[0], frame[1], frame[2]
    first, second = face_vertices[face_start[f]], face_vertices[face_start[f] + 1]
    for d in range(3):
        o[d] = vertices[first, d]
        s[d] = vertices[second, d] - o[d]
    length = math.sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2])
    for d in range(3):
        s[d] /= length
    n = face_normal[f]
    t[0], t[1], t[2] = n[1] * s[2] - n[2] * s[1], n[2] * s[0] - n[0] * s[2], n[0] * s[1] - n[1] * s[0]
    return o, s, t


@numba.njit(cache=True)
def _in_plane(vertices, face_vertices, face_start, f, o, s, t, reverse):
    """Face f's loop in a plane's coordinates (projected along its normal), reversed if asked."""
    first, n = face_start[f], face_start[f + 1] - face_start[f]
    out = np.empty((n, 2))
    for k in range(n):
        v = face_vertices[first + (n - 1 - k if reverse else k)]
        dx, dy, dz = vertices[v, 0] - o[0], vertices[v, 1] - o[1], vertices[v, 2] - o[2]
        out[k, 0] = dx * s[0] + dy * s[1] + dz * s[2]
        out[k, 1] = dx * t[0] + dy * t[1] + dz * t[2]
    return out


@numba.njit(cache=True)
def _overlap(vertices, face_vertices, face_start, face_normal, ref, inc):
    """`face_overlap`, and the reference face in its own (s, t) coordinates."""
    o, s, t = face_frame(vertices, face_vertices, face_start, face_normal, ref)
    reference = _in_plane(vertices, face_vertices, face_start, ref, o, s, t, False)
    incident = _in_plane(vertices, face_vertices, face_start, inc, o, s, t, True)
    return clip_polygon(incident, reference), reference, o, s, t


@numba.njit(cache=True)
def face_overlap(vertices, face_vertices, face_start, face_normal, ref, inc):
    """The overlap of reference face `ref` and incident face `inc` (of the other block, facing it): the
    incident face projected on the reference plane along its normal and clipped to the reference face
    (Sutherland–Hodgman). Returns (polygon (k, 2) counter-clockwise in the reference face's (s, t)
    coordinates [m], o, s, t: `face_frame` of the reference face)."""
    poly, _, o, s, t = _overlap(vertices, face_vertices, face_start, face_normal, ref, inc)
    return poly, o, s, t


@numba.njit(cache=True)
def _fan(poly, refine):
    """Triangles (m, 3, 2) of a convex counter-clockwise polygon: a fan from its first vertex, each
    triangle split into four at its mid-sides `refine` times, in a fixed order (triangle k's four at
    4k..4k + 3, written in place from the last triangle down)."""
    n = poly.shape[0] - 2
    tri = np.empty((n * 4**refine, 3, 2))
    for k in range(n):
        for d in range(2):
            tri[k, 0, d], tri[k, 1, d], tri[k, 2, d] = poly[0, d], poly[k + 1, d], poly[k + 2, d]
    for _ in range(refine):
        for k in range(n - 1, -1, -1):
            for d in range(2):
                p, q, r = tri[k, 0, d], tri[k, 1, d], tri[k, 2, d]
                pq, qr, rp = 0.5 * (p + q), 0.5 * (q + r), 0.5 * (r + p)
                tri[4 * k, 0, d], tri[4 * k, 1, d], tri[4 * k, 2, d] = p, pq, rp
                tri[4 * k + 1, 0, d], tri[4 * k + 1, 1, d], tri[4 * k + 1, 2, d] = pq, q, qr
                tri[4 * k + 2, 0, d], tri[4 * k + 2, 1, d], tri[4 * k + 2, 2, d] = rp, qr, r
                tri[4 * k + 3, 0, d], tri[4 * k + 3, 1, d], tri[4 * k + 3, 2, d] = qr, rp, pq
        n *= 4
    return tri


@numba.njit(cache=True)
def face_sub_contacts(vertices, face_vertices, face_start, face_normal, ref, inc, refine, centre, rotation):
    """The sub-contacts of a face–face contact between reference face `ref` and incident face `inc`.

    The reference face is cut into (n - 2) 4^refine triangles (`_fan`, n its vertex count); sub-contact
    k sits at triangle k's centroid. Its share is triangle k clipped to the overlap polygon
    (`face_overlap`), its area and centroid integrated exactly; the shares tile the overlap.

    centre (3,) and rotation (3, 3) place the reference block: x_world = centre + rotation @ x_body.

    Returns (points (m, 3): the sub-contacts in the reference block's body frame [m]; area (m,): each
    share's area [m²]; gap (m,): the gap at each share's centroid [m], the signed distance along the
    reference normal from the reference plane to the incident face's plane (> 0 open; for rigid faces
    it is linear over the plane, so it is also the share's mean gap); centroid (m, 3): each share's
    centroid in world coordinates [m], the triangle's centroid where its share is empty).
    """
    poly, reference, o, s, t = _overlap(vertices, face_vertices, face_start, face_normal, ref, inc)
    tri = _fan(reference, refine)
    m = tri.shape[0]
    n, ni = face_normal[ref], face_normal[inc]
    d_inc = vertices[face_vertices[face_start[inc]]] @ ni
    facing = ni @ n
    points, area, gap, centroid = np.empty((m, 3)), np.empty(m), np.empty(m), np.empty((m, 3))
    for k in range(m):
        mid = (tri[k, 0] + tri[k, 1] + tri[k, 2]) / 3.0
        world = o + mid[0] * s + mid[1] * t
        points[k] = rotation.T @ (world - centre)
        share = clip_polygon(tri[k], poly) if poly.shape[0] >= 3 else poly
        area[k], cs, ct = polygon_area_centroid(share)
        if area[k] == 0.0:
            cs, ct = mid[0], mid[1]
        centroid[k] = o + cs * s + ct * t
        gap[k] = (d_inc - ni @ centroid[k]) / facing
    return points, area, gap, centroid


@numba.njit(cache=True)
def face_shares(vertices, face_vertices, face_start, face_normal, ref, inc, refine):
    """The closed part of each sub-contact's share of a face–face contact, with the moments a linear
    normal stress over it needs: the stress integrated exactly, not sampled at a point.

    Shares as `face_sub_contacts` (the reference face's triangle k clipped to the overlap). The closure
    u(x) = -gap(x) (> 0 closed) is linear over the reference plane, u = u_0 + g . (x - x_0), so a linear
    normal law sigma = K_n u has, over the closed part P of a share (the share clipped to u >= 0), the
    force K_n A_P u(c_P) along the reference normal n, acting at P's centroid c_P, and about c_P the
    couple K_n (S_P g) x n on the block the normal pushes (S_P P's second-moment tensor about c_P in the
    plane): the integral of (x - c_P) x n sigma(x). With it a face's rocking stiffness is whole at any
    refinement (a point force per share would have none about the line through two shares).

    Returns (area (m,) [m²], centroid (m, 3) world [m], closure (m,) at the centroid [m], couple (m, 3)
    world: (S_P g) x n [m³], polar (m,): P's polar second moment about c_P [m⁴]) for the m triangles,
    zero area (and the triangle's centroid) where a share is empty or open.
    """
    poly, reference, o, s, t = _overlap(vertices, face_vertices, face_start, face_normal, ref, inc)
    tri = _fan(reference, refine)
    m = tri.shape[0]
    n, ni = face_normal[ref], face_normal[inc]
    facing = ni @ n
    u0 = (ni @ o - vertices[face_vertices[face_start[inc]]] @ ni) / facing
    gs, gt = (ni @ s) / facing, (ni @ t) / facing
    area, centroid, closure = np.zeros(m), np.empty((m, 3)), np.zeros(m)
    couple, polar = np.zeros((m, 3)), np.zeros(m)
    scratch = np.empty((3, poly.shape[0] + 5, 2))  # the share, the clipping's other pass, its closed part
    for k in range(m):
        ms = (tri[k, 0, 0] + tri[k, 1, 0] + tri[k, 2, 0]) / 3.0
        mt = (tri[k, 0, 1] + tri[k, 1, 1] + tri[k, 2, 1]) / 3.0
        for d in range(3):
            centroid[k, d] = o[d] + ms * s[d] + mt * t[d]
        if poly.shape[0] < 3:
            continue
        share = clip_into(tri[k], 3, poly, scratch[0], scratch[1])
        closed = half_plane_into(scratch[0], share, gs, gt, u0, scratch[2])
        a, cs, ct, sss, sst, stt = polygon_moments(scratch[2, :closed])
        if a <= 0.0:
            continue
        area[k], polar[k] = a, sss + stt
        for d in range(3):
            centroid[k, d] = o[d] + cs * s[d] + ct * t[d]
        closure[k] = u0 + gs * cs + gt * ct
        ls, lt = sss * gs + sst * gt, sst * gs + stt * gt
        lx, ly, lz = ls * s[0] + lt * t[0], ls * s[1] + lt * t[1], ls * s[2] + lt * t[2]
        couple[k, 0] = ly * n[2] - lz * n[1]
        couple[k, 1] = lz * n[0] - lx * n[2]
        couple[k, 2] = lx * n[1] - ly * n[0]
    return area, centroid, closure, couple, polar
