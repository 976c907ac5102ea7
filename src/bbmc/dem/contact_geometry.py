"""Contact geometry: where two blocks' edges meet, as numba functions over the flat arrays.

A contact is a pair of edges, one of block A (the lower index) and one of block B, whose outward
normals face each other at any angle below 90 degrees and whose projections on their common line
overlap (`contact_frame`): two faces, a corner against a face, or a corner against a corner. The common
line's normal n is the face's where a corner presses on a face, turns gradually around corners that
meet (rounded over `CORNER_ROUNDING` of the smaller block's size), and is the faces' own for parallel
faces. The overlap is cut into `n_sub` equal shares (`share_middle`), each integrated exactly by
`bbmc.dem.contact_forces`. Lengths in m.
"""

import math

import numba

from bbmc.dem.layout import (
    CORNER_ROUNDING,
)

PARALLEL = -1.0 + 1e-12  # cosine between two edges' normals below which they are parallel faces


@numba.njit(cache=True, inline="always")
def edge_frame(world, vertex_next, e):
    """Start point, unit tangent and length of edge e (counter-clockwise, so the outward normal is
    (t_y, -t_x))."""
    x0, y0 = world[e, 0], world[e, 1]
    dx, dy = world[vertex_next[e], 0] - x0, world[vertex_next[e], 1] - y0
    length = math.sqrt(dx * dx + dy * dy)
    return x0, y0, dx / length, dy / length, length


@numba.njit(cache=True)
def _overlap(world, vertex_next, ea, eb, nx, ny):
    """Edges ea and eb projected on the line of unit normal n (tangent t = (-n_y, n_x)): the overlap
    [lo, hi] of their projections on t, and each edge's height along n at lo and at hi [m]:
    (lo, hi, A's height at lo, A's at hi, B's at lo, B's at hi)."""
    tx, ty = -ny, nx
    pa, qa, pb, qb = ea, vertex_next[ea], eb, vertex_next[eb]
    sa0, sa1 = world[pa, 0] * tx + world[pa, 1] * ty, world[qa, 0] * tx + world[qa, 1] * ty
    sb0, sb1 = world[pb, 0] * tx + world[pb, 1] * ty, world[qb, 0] * tx + world[qb, 1] * ty
    ha0, ha1 = world[pa, 0] * nx + world[pa, 1] * ny, world[qa, 0] * nx + world[qa, 1] * ny
    hb0, hb1 = world[pb, 0] * nx + world[pb, 1] * ny, world[qb, 0] * nx + world[qb, 1] * ny
    lo, hi = max(min(sa0, sa1), min(sb0, sb1)), min(max(sa0, sa1), max(sb0, sb1))
    ka = (ha1 - ha0) / (sa1 - sa0) if sa1 != sa0 else 0.0
    kb = (hb1 - hb0) / (sb1 - sb0) if sb1 != sb0 else 0.0
    return (
        lo,
        hi,
        ha0 + (lo - sa0) * ka,
        ha0 + (hi - sa0) * ka,
        hb0 + (lo - sb0) * kb,
        hb0 + (hi - sb0) * kb,
    )


@numba.njit(cache=True, inline="always")
def contact_frame(world, vertex_next, ea, eb, size, a, b):
    """The common line of edge ea (block A) and edge eb (block B), at any angle between them.

    Returns (active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi): the unit normal n (from A towards B; the
    tangent is t = (-n_y, n_x)), the overlap [lo, hi] of the two edges projected on t [m], and the
    heights along n of A's and of B's edge at lo and at hi [m] (the gap, > 0 open, is B's minus A's).
    Inactive when the edges do not face each other (their outward normals make 90 degrees or more)
    or do not overlap in projection.

    The normal is that of the face a corner presses on (UDEC's corner-edge contact): at the closed end
    of the overlap (the end with the smaller gap, first measured along A's normal) sits a vertex of B,
    inside A's edge (n = n_A), or a vertex of A, inside B's edge (n = -n_B). Where the two vertices at
    that end are less than the rounding length apart along the line (corner against corner: the
    rounding length is `CORNER_ROUNDING` times the smaller of the sizes `size[a]`, `size[b]` of the
    blocks a and b) the normal turns linearly from one to the other, as around a corner rounded over
    that length, so it never jumps as a corner slides past another corner. Two parallel edges give
    n = n_A = -n_B whatever the end (and the sizes are not read: a face contact costs no more).
    """
    ax, ay, tax, tay, la = edge_frame(world, vertex_next, ea)
    bx, by, tbx, tby, lb = edge_frame(world, vertex_next, eb)
    facing = tax * tbx + tay * tby  # n_A . n_B
    if facing >= -1e-9:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # first on A's own line: t = t_A, n = n_A = (t_Ay, -t_Ax); B's edge runs against t (facing < 0)
    sa0 = ax * tax + ay * tay
    sb0 = bx * tax + by * tay
    sb1 = sb0 + lb * facing
    height_a = ax * tay - ay * tax
    hb0 = bx * tay - by * tax
    slope_b = (tbx * tay - tby * tax) / facing  # B's height change per unit along t
    lo, hi = max(sa0, sb1), min(sa0 + la, sb0)
    if hi - lo <= 1e-9 * max(la, lb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    b_lo, b_hi = hb0 + (lo - sb0) * slope_b, hb0 + (hi - sb0) * slope_b
    if facing < PARALLEL:  # n_A and -n_B differ by less than 1.5e-6 rad: either is the normal
        return True, tay, -tax, lo, hi, height_a, height_a, b_lo, b_hi
    # > 0: A's vertex lies inside B's edge at the closed end (the end with the smaller gap)
    inside = sa0 - sb1 if b_lo <= b_hi else sb0 - (sa0 + la)
    rounding = CORNER_ROUNDING * min(size[a], size[b])
    w = min(max(0.5 - inside / (2.0 * rounding), 0.0), 1.0)
    if w == 1.0:
        return True, tay, -tax, lo, hi, height_a, height_a, b_lo, b_hi
    nx, ny = w * tay - (1.0 - w) * tby, -w * tax + (1.0 - w) * tbx
    norm = math.sqrt(nx * nx + ny * ny)
    nx, ny = nx / norm, ny / norm
    lo, hi, a_lo, a_hi, b_lo, b_hi = _overlap(world, vertex_next, ea, eb, nx, ny)
    if hi - lo <= 1e-9 * max(la, lb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi


@numba.njit(cache=True)
def share_middle(k, n_sub):
    """The middle of sub-contact k's share of a contact's overlap, as a fraction of the overlap [1]: the
    overlap is cut into n_sub equal shares, each integrated exactly (`contact_forces._normal_share`)."""
    return (k + 0.5) / n_sub
