"""Contact search: a uniform-grid broad phase over block bounding boxes, then edge pairs.

The search runs at the start and again only when some block has moved (translation plus radius times
rotation) more than half the search margin since the last one (see `kernels.cycle`): until then no
pair farther apart than the margin can have come into contact. Its cost is linear in the number of
blocks for blocks of similar size (each block is binned into the grid cells its box covers; a pair is
reported once, from the cell holding the lower-left corner of the two boxes' intersection). Pairs of
two immobile blocks (every degree of freedom fixed) are skipped: they can never load each other.
"""

import math

import numba
import numpy as np
from numba.typed import List

from bbmc.dem.contact_geometry import contact_frame, edge_frame
from bbmc.dem.layout import CORNER_ROUNDING

SQUARER = 1e-12  # a neighbouring edge faces more squarely only by more than this (in the cosine):
# collinear neighbours (a boundary split where a trace ends on it) tie, up to round-off, and a tie
# broken by round-off dropped a whole face contact for its neighbour's
CONTACT, CORNER_REPLACED = 0, 1  # a found edge pair: a contact, or one the corner rule drops (`facing_edges`)


@numba.njit(cache=True)
def _boxes(world, vertex_start, margin):
    n = vertex_start.size - 1
    box = np.empty((n, 4))
    for b in range(n):
        first, last = vertex_start[b], vertex_start[b + 1]
        box[b, 0] = world[first:last, 0].min() - 0.5 * margin
        box[b, 1] = world[first:last, 1].min() - 0.5 * margin
        box[b, 2] = world[first:last, 0].max() + 0.5 * margin
        box[b, 3] = world[first:last, 1].max() + 0.5 * margin
    return box


@numba.njit(cache=True)
def candidate_pairs(world, vertex_start, immobile, margin):
    """Block pairs (a < b) whose boxes, grown by the margin, overlap: int64 (n_pairs, 2)."""
    box = _boxes(world, vertex_start, margin)
    n = box.shape[0]
    sizes = np.maximum(box[:, 2] - box[:, 0], box[:, 3] - box[:, 1])
    cell = np.median(sizes)
    x0, y0 = box[:, 0].min(), box[:, 1].min()
    width, height = box[:, 2].max() - x0, box[:, 3].max() - y0
    while (width / cell + 1.0) * (height / cell + 1.0) > 4.0 * n + 16.0:
        cell *= 1.5
    nx, ny = int(width / cell) + 1, int(height / cell) + 1
    span = np.empty((n, 4), dtype=np.int64)
    count = np.zeros(nx * ny + 1, dtype=np.int64)
    for b in range(n):
        span[b, 0] = min(int((box[b, 0] - x0) / cell), nx - 1)
        span[b, 1] = min(int((box[b, 1] - y0) / cell), ny - 1)
        span[b, 2] = min(int((box[b, 2] - x0) / cell), nx - 1)
        span[b, 3] = min(int((box[b, 3] - y0) / cell), ny - 1)
        for j in range(span[b, 1], span[b, 3] + 1):
            for i in range(span[b, 0], span[b, 2] + 1):
                count[j * nx + i + 1] += 1
    start = np.cumsum(count)
    members = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for b in range(n):
        for j in range(span[b, 1], span[b, 3] + 1):
            for i in range(span[b, 0], span[b, 2] + 1):
                members[fill[j * nx + i]] = b
                fill[j * nx + i] += 1
    pairs = List()
    for c in range(nx * ny):
        for p in range(start[c], start[c + 1]):
            for q in range(p + 1, start[c + 1]):
                a, b = min(members[p], members[q]), max(members[p], members[q])
                if immobile[a] and immobile[b]:
                    continue
                if box[a, 0] > box[b, 2] or box[b, 0] > box[a, 2]:
                    continue
                if box[a, 1] > box[b, 3] or box[b, 1] > box[a, 3]:
                    continue
                corner_i = min(int((max(box[a, 0], box[b, 0]) - x0) / cell), nx - 1)
                corner_j = min(int((max(box[a, 1], box[b, 1]) - y0) / cell), ny - 1)
                if corner_j * nx + corner_i == c:
                    pairs.append((a, b))
    out = np.empty((len(pairs), 2), dtype=np.int64)
    for k in range(len(pairs)):
        out[k, 0], out[k, 1] = pairs[k]
    return out


@numba.njit(cache=True)
def _least_overlap(world, vertex_start, vertex_next, a, b):
    """The least overlap of blocks a and b projected on the normal of any of their edges [m]
    (separating axes: <= 0 if they are apart). Two convex blocks in contact are pushed into each other
    along that axis only."""
    least = math.inf
    for block in (a, b):
        for e in range(vertex_start[block], vertex_start[block + 1]):
            x0, y0, tx, ty, _ = edge_frame(world, vertex_next, e)
            lo_a, hi_a, lo_b, hi_b = math.inf, -math.inf, math.inf, -math.inf
            for v in range(vertex_start[a], vertex_start[a + 1]):
                d = (world[v, 0] - x0) * ty - (world[v, 1] - y0) * tx
                lo_a, hi_a = min(lo_a, d), max(hi_a, d)
            for v in range(vertex_start[b], vertex_start[b + 1]):
                d = (world[v, 0] - x0) * ty - (world[v, 1] - y0) * tx
                lo_b, hi_b = min(lo_b, d), max(hi_b, d)
            least = min(least, min(hi_a, hi_b) - max(lo_a, lo_b))
    return least


@numba.njit(cache=True)
def overlap_depth(pairs, world, vertex_start, vertex_next):
    """For each block pair, how deep the two convex blocks overlap [m]: the least overlap of their
    projections on the normals of their edges, which is the shortest move that parts them (separating
    axes); <= 0 where they touch or are apart."""
    depth = np.empty(pairs.shape[0])
    for k in range(pairs.shape[0]):
        depth[k] = _least_overlap(world, vertex_start, vertex_next, pairs[k, 0], pairs[k, 1])
    return depth


@numba.njit(cache=True)
def _depth_bound(world, vertex_start, vertex_next, size, margin, a, b):
    """How deep two edges of blocks a and b may be inside each other and still be a contact [m]."""
    depth = min(0.25 * min(size[a], size[b]), _least_overlap(world, vertex_start, vertex_next, a, b))
    return max(depth, 0.0) + 0.01 * margin


@numba.njit(cache=True)
def _squarer_neighbour(world, vertex_next, e, first, last, s_closed, tx, ty, reach, other_nx, other_ny):
    """The neighbouring edge of e (its block has edges first..last-1) at an end vertex of e that lies at
    the overlap's closed end (within `reach` of s_closed along the tangent), if that edge faces the
    other block's edge (normal other_n) more squarely than e does; else -1."""
    facing = _facing(world, vertex_next, e, other_nx, other_ny)
    for end, neighbour in ((e, e - 1 if e > first else last - 1), (vertex_next[e], vertex_next[e])):
        at_corner = abs(world[end, 0] * tx + world[end, 1] * ty - s_closed) <= reach
        if at_corner and _facing(world, vertex_next, neighbour, other_nx, other_ny) < facing - SQUARER:
            return neighbour
    return -1


@numba.njit(cache=True)
def _facing(world, vertex_next, e, other_nx, other_ny):
    """Cosine between edge e's outward normal and another normal (-1: they face each other squarely)."""
    _, _, tx, ty, _ = edge_frame(world, vertex_next, e)
    return ty * other_nx - tx * other_ny


@numba.njit(cache=True)
def _candidate(world, vertex_start, vertex_next, size, margin, depth, a, b, ea, eb, bound_when_needed):
    """Whether edges ea and eb are in contact or about to be (see `facing_edges`), the separating-axis
    depth bound (computed once per block pair, -1 until then), and the pair's normal and closed end."""
    active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi = contact_frame(world, vertex_next, ea, eb, size, a, b)
    if not active:
        return False, depth, 0.0, 0.0, 0.0
    gap = min(b_lo - a_lo, b_hi - a_hi)
    if gap > margin or not math.isfinite(gap):
        return False, depth, 0.0, 0.0, 0.0
    if gap < -0.01 * margin or not bound_when_needed:
        if depth < 0.0:
            depth = _depth_bound(world, vertex_start, vertex_next, size, margin, a, b)
        if gap < -depth:
            return False, depth, 0.0, 0.0, 0.0
    return True, depth, nx, ny, lo if b_lo - a_lo <= b_hi - a_hi else hi


@numba.njit(cache=True)
def facing_edges(pairs, world, vertex_start, vertex_next, size, margin, bound_when_needed):
    """Edge pairs (edge of a, edge of b) of each block pair that are in contact or about to be: their
    outward normals face each other at any angle below 90 degrees (a face, a corner against a face, a
    corner against a corner; `contact_geometry.contact_frame`), they overlap on their common line, and
    at the closer end of that overlap they are no farther apart than the margin and
    no deeper inside each other than the blocks overlap along their separating axis (plus 1 % of the
    margin) nor than a quarter of the smaller block's size. The separating-axis bound rejects edges of
    two blocks that meet corner to corner along a persistent joint: once one has slid past the other's
    end, their edges overlap in projection by as much as it slid, although the blocks touch only on the
    joint they slide along.

    A corner makes one contact with a face: of two such pairs that share a corner, the one whose edge
    at that corner faces the other edge less squarely is dropped, if the one that replaces it (the
    neighbouring edge with the same other edge) is itself a contact. A column toppling about its corner
    thus keeps the contact of its base until it has turned 45 degrees, and two blocks that meet at a
    corner beside their common face make no second contact there; a corner on a face is never left with
    none. Two corners that meet exactly, each with its other edge facing the other block more squarely
    (diagonal neighbours at the junction of four blocks), make no contact: they touch at a point, and a
    contact forms once one corner moves onto the other's face.
    `bound_when_needed`: compute the separating-axis bound only for a pair with an edge pair deeper
    than 1 % of the margin (no shallower one can fail it), else for every pair.
    Returns int64 (n, 5): edge a, edge b, block a, block b, and CONTACT, or CORNER_REPLACED for a pair
    the corner rule above drops (listed so that the search can keep one that is already a contact and
    loaded); and float64 (n, 2): each pair's normal
    (`contact_geometry.contact_frame`)."""
    found, normals = List(), List()
    for k in range(pairs.shape[0]):
        a, b = pairs[k, 0], pairs[k, 1]
        reach = CORNER_ROUNDING * min(size[a], size[b])
        first_a, last_a = vertex_start[a], vertex_start[a + 1]
        first_b, last_b = vertex_start[b], vertex_start[b + 1]
        depth = -1.0
        for ea in range(first_a, last_a):
            for eb in range(first_b, last_b):
                ok, depth, nx, ny, closed = _candidate(
                    world, vertex_start, vertex_next, size, margin, depth, a, b, ea, eb, bound_when_needed
                )
                if not ok:
                    continue
                tx, ty = -ny, nx
                _, _, tax, tay, _ = edge_frame(world, vertex_next, ea)
                _, _, tbx, tby, _ = edge_frame(world, vertex_next, eb)
                turn_a = _squarer_neighbour(
                    world, vertex_next, ea, first_a, last_a, closed, tx, ty, reach, tby, -tbx
                )
                turn_b = _squarer_neighbour(
                    world, vertex_next, eb, first_b, last_b, closed, tx, ty, reach, tay, -tax
                )
                if turn_a >= 0 and turn_b >= 0:  # two corners that meet, each turned from the other's edge
                    found.append((ea, eb, a, b, CORNER_REPLACED))
                    normals.append((nx, ny))
                    continue
                if turn_a >= 0 or turn_b >= 0:
                    other_a, other_b = (turn_a, eb) if turn_a >= 0 else (ea, turn_b)
                    replaced, depth, _, _, _ = _candidate(
                        world,
                        vertex_start,
                        vertex_next,
                        size,
                        margin,
                        depth,
                        a,
                        b,
                        other_a,
                        other_b,
                        bound_when_needed,
                    )
                    if replaced:
                        found.append((ea, eb, a, b, CORNER_REPLACED))
                        normals.append((nx, ny))
                        continue
                found.append((ea, eb, a, b, CONTACT))
                normals.append((nx, ny))
    out = np.empty((len(found), 5), dtype=np.int64)
    normal = np.empty((len(found), 2))
    for k in range(len(found)):
        out[k, 0], out[k, 1], out[k, 2], out[k, 3], out[k, 4] = found[k]
        normal[k, 0], normal[k, 1] = normals[k]
    return out, normal


@numba.njit(cache=True)
def _deepest_vertex(world, vertex_start, vertex_next, a, b):
    """How far the deepest vertex of block a lies inside convex block b [m] (0 if none is inside)."""
    deepest = 0.0
    for v in range(vertex_start[a], vertex_start[a + 1]):
        inside = math.inf
        for e in range(vertex_start[b], vertex_start[b + 1]):
            x0, y0, tx, ty, _ = edge_frame(world, vertex_next, e)
            outward = (world[v, 0] - x0) * ty - (world[v, 1] - y0) * tx
            if outward >= 0.0:
                inside = 0.0
                break
            inside = min(inside, -outward)
        deepest = max(deepest, inside)
    return deepest


@numba.njit(cache=True)
def vertex_penetration(pairs, world, vertex_start, vertex_next):
    """For each block pair, the depth of the deepest vertex of either block inside the other [m].

    Independent of the contacts: the safety net that sees blocks pushed into each other whatever
    the contacts did."""
    depth = np.zeros(pairs.shape[0])
    for k in range(pairs.shape[0]):
        a, b = pairs[k, 0], pairs[k, 1]
        depth[k] = max(
            _deepest_vertex(world, vertex_start, vertex_next, a, b),
            _deepest_vertex(world, vertex_start, vertex_next, b, a),
        )
    return depth
