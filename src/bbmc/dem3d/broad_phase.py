"""Broad phase: a uniform grid of block bounding boxes, searched again only when a block has moved.

Each block's axis-aligned box, grown by half the search margin on every side, is binned into the grid
cells it covers; the cell is the median box size, grown until the grid has at most about 8 cells per
block. A pair is reported once, from the cell holding the low corner of the two boxes' intersection
(as the 2D engine's `bbmc.dem.detection.candidate_pairs`). Cost linear in the number of blocks for
blocks of similar size (Cundall 1988's cell mapping). Layout as `bbmc.dem3d.contact_geometry`'s.

The search is needed again only once some point of some block has moved more than half the margin
since the last one (`needs_search`): until then no pair that was farther apart than the margin can
touch. A rigid motion moves x by t + (R - I) x, affine in x, so its length is convex and greatest at a
vertex: comparing the vertices with their positions at the last search is exact.
"""

import math

import numba
import numpy as np
from numba.typed import List


@numba.njit(cache=True)
def block_boxes(vertices, vertex_start, margin):
    """Each block's bounding box grown by margin / 2 [m]: (n_blocks, 6) as lo x, y, z, hi x, y, z."""
    n = vertex_start.size - 1
    box = np.empty((n, 6))
    for b in range(n):
        for d in range(3):
            box[b, d] = vertices[vertex_start[b] : vertex_start[b + 1], d].min() - 0.5 * margin
            box[b, 3 + d] = vertices[vertex_start[b] : vertex_start[b + 1], d].max() + 0.5 * margin
    return box


@numba.njit(cache=True)
def _cell_of(x, x0, cell, count):
    return min(int((x - x0) / cell), count - 1)


@numba.njit(cache=True)
def candidate_pairs(vertices, vertex_start, immobile, margin):
    """Block pairs (a < b) whose boxes, grown by margin / 2 each [m], overlap: int64 (n_pairs, 2).
    Pairs of two immobile blocks are skipped (they cannot load each other)."""
    box = block_boxes(vertices, vertex_start, margin)
    n = box.shape[0]
    if n < 2:
        return np.empty((0, 2), dtype=np.int64)
    sizes = np.maximum(np.maximum(box[:, 3] - box[:, 0], box[:, 4] - box[:, 1]), box[:, 5] - box[:, 2])
    cell = np.median(sizes)
    lo = np.array([box[:, 0].min(), box[:, 1].min(), box[:, 2].min()])
    span = np.array([box[:, 3].max(), box[:, 4].max(), box[:, 5].max()]) - lo
    while (span[0] / cell + 1.0) * (span[1] / cell + 1.0) * (span[2] / cell + 1.0) > 8.0 * n + 64.0:
        cell *= 1.5
    dims = np.array([int(span[d] / cell) + 1 for d in range(3)])
    cells = np.empty((n, 6), dtype=np.int64)
    count = np.zeros(dims[0] * dims[1] * dims[2] + 1, dtype=np.int64)
    for b in range(n):
        for d in range(3):
            cells[b, d] = _cell_of(box[b, d], lo[d], cell, dims[d])
            cells[b, 3 + d] = _cell_of(box[b, 3 + d], lo[d], cell, dims[d])
        for k in range(cells[b, 2], cells[b, 5] + 1):
            for j in range(cells[b, 1], cells[b, 4] + 1):
                for i in range(cells[b, 0], cells[b, 3] + 1):
                    count[(k * dims[1] + j) * dims[0] + i + 1] += 1
    start = np.cumsum(count)
    members = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for b in range(n):
        for k in range(cells[b, 2], cells[b, 5] + 1):
            for j in range(cells[b, 1], cells[b, 4] + 1):
                for i in range(cells[b, 0], cells[b, 3] + 1):
                    c = (k * dims[1] + j) * dims[0] + i
                    members[fill[c]] = b
                    fill[c] += 1
    pairs = List()
    for c in range(dims[0] * dims[1] * dims[2]):
        for p in range(start[c], start[c + 1]):
            for q in range(p + 1, start[c + 1]):
                a, b = min(members[p], members[q]), max(members[p], members[q])
                if immobile[a] and immobile[b]:
                    continue
                apart = False
                for d in range(3):
                    apart = apart or box[a, d] > box[b, 3 + d] or box[b, d] > box[a, 3 + d]
                if apart:
                    continue
                corner = 0
                for d in (2, 1, 0):
                    corner = corner * dims[d] + _cell_of(max(box[a, d], box[b, d]), lo[d], cell, dims[d])
                if corner == c:
                    pairs.append((a, b))
    out = np.empty((len(pairs), 2), dtype=np.int64)
    for k in range(len(pairs)):
        out[k, 0], out[k, 1] = pairs[k]
    return out


@numba.njit(cache=True)
def needs_search(vertices, vertices_at_search, margin):
    """Whether any vertex has moved more than margin / 2 [m] since the last search (then some pair may
    have come within reach that the last search did not list)."""
    limit = 0.25 * margin * margin
    for v in range(vertices.shape[0]):
        dx = vertices[v, 0] - vertices_at_search[v, 0]
        dy = vertices[v, 1] - vertices_at_search[v, 1]
        dz = vertices[v, 2] - vertices_at_search[v, 2]
        if dx * dx + dy * dy + dz * dz > limit or not math.isfinite(dx + dy + dz):
            return True
    return False
