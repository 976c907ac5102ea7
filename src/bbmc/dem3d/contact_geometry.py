"""Contact geometry of two convex polyhedra: separating axis, contact plane, overlap area and the
sub-contacts that carry it, as numba functions over flat arrays. Lengths in m, areas in m².

Array layout (world coordinates; all indices global, over every block):

* ``vertices`` float64 (n_vertices, 3); block k owns rows ``vertex_start[k]:vertex_start[k + 1]``.
* ``face_vertices`` int64: every face's vertex loop, one after another, as rows of ``vertices``,
  counter-clockwise seen from outside the block (the right-hand rule gives the outward normal);
  face f's loop is ``face_vertices[face_start[f]:face_start[f + 1]]``.
* ``block_face_start`` int64 (n_blocks + 1): block k owns faces ``block_face_start[k]:...[k + 1]``.
* ``face_normal`` float64 (n_faces, 3): each face's outward unit normal.
* An edge is named by its loop entry q (an index into ``face_vertices``): it runs from
  ``face_vertices[q]`` to the next vertex of that loop. In a closed polyhedron every edge is met
  twice, once each way; the one with the smaller first vertex is its name (`edge_ends`).

Why a separating-axis test and not Cundall's common plane. 3DEC (Cundall 1988, "Formulation of a three-
dimensional distinct element model - Part I", IJRMMS 25(3) 107-116) finds for each pair the plane that
maximises the gap between the blocks, by iterating on the plane's normal and position from the last
step's; contact type follows from counting vertices near that plane, and face contacts carry sub-contacts
at the vertices of a face triangulation, each with a share of the area. YADE's polyhedra intersect the
two blocks (CGAL) and load by the overlap VOLUME: no contact area, so neither a stress law nor a shear
history at points of a joint. LMGC90 and Bullet/Box2D-style manifolds clip one face against the other.
For convex polyhedra the separating-axis test over the face normals of both blocks and the cross products
of their edges (the pairs whose arcs cross on the Gauss map) is exact (the faces of the Minkowski
difference A - B have exactly those normals): it gives the verdict and, in overlap, the least penetration
depth and its direction without iteration or a convergence tolerance, and at a face contact its plane is
the reference face's plane, which is where a converged common plane lies as well. It is started from the
last step's axis. The area then comes from clipping (Sutherland–Hodgman), exactly, not from counting
vertices.

Contact kinds (`FACE_FACE` ...): the least-penetration axis is a face normal of one block (the
reference face; ties go to a face of A, then of B, then to edges, within `FACE_PREFERENCE` x size) and:

* the other block has a face anti-parallel to it within `FACE_ANGLE` (the incident face): face–face,
  the overlap is the incident face projected on the reference plane along the normal, clipped to the
  reference face; its area may include parts still open (the stress integration closes what is closed);
* else the other block's lowest vertex along the normal and its lowest neighbour, if that one lies within
  size x sin(`FACE_ANGLE`) above it: edge–face, the edge clipped to the reference face, with the nominal
  area length x `NOMINAL_WIDTH` x size;
* else vertex–face at the lowest vertex, nominal area (`NOMINAL_WIDTH` x size)².

The least-penetration axis is an edge–edge cross product: a point contact at the middle of the two
edges' closest points, nominal area (`NOMINAL_WIDTH` x size)². The nominal areas let a law in stresses
load a corner; they are small so that an edge or a corner is stiff only over a strip or a square of
1 % of the block's size. (A known limit: a face that tilts past `FACE_ANGLE` drops from its face's area to
the edge's nominal strip.)

Sub-contacts of a face–face contact: `bbmc.dem3d.face_contact`.
"""

import math

import numba
import numpy as np

from bbmc.dem3d.face_contact import _in_plane, face_frame, face_overlap
from bbmc.dem3d.polygon_clip import clip_segment, polygon_area_centroid

AXIS_FACE_A, AXIS_FACE_B, AXIS_EDGES = 0, 1, 2  # the separating axis: a face normal of A, of B, edge x edge
FACE_FACE, EDGE_FACE, VERTEX_FACE, EDGE_EDGE = 0, 1, 2, 3  # contact kinds
FACE_ANGLE = math.radians(5.0)  # two faces facing each other within this angle are a face–face contact
FACE_PREFERENCE = 1e-6  # x size [m]: an axis replaces an earlier one only if it separates by more
NOMINAL_WIDTH = 0.01  # x size: width of an edge's strip and side of a corner's square of contact
PARALLEL_EDGES = 1e-9  # |e_a x e_b| / (|e_a| |e_b|) below which two edges give no axis


@numba.njit(cache=True, inline="always")
def edge_ends(face_vertices, face_start, f, q):
    """The two vertex rows of the edge at loop entry q of face f."""
    nxt = q + 1 if q + 1 < face_start[f + 1] else face_start[f]
    return face_vertices[q], face_vertices[nxt]


@numba.njit(cache=True, inline="always")
def _dot(vertices, v, nx, ny, nz):
    return vertices[v, 0] * nx + vertices[v, 1] * ny + vertices[v, 2] * nz


@numba.njit(cache=True)
def _extent(vertices, first, last, nx, ny, nz):
    """Least and greatest projection of vertices first..last-1 on (nx, ny, nz) [m]."""
    lo, hi = math.inf, -math.inf
    for v in range(first, last):
        d = _dot(vertices, v, nx, ny, nz)
        lo, hi = min(lo, d), max(hi, d)
    return lo, hi


@numba.njit(cache=True)
def _face_separation(vertices, vertex_start, face_vertices, face_start, face_normal, f, other):
    """How far block `other` lies outside the plane of face f [m] (its lowest vertex's height)."""
    nx, ny, nz = face_normal[f, 0], face_normal[f, 1], face_normal[f, 2]
    lo, _ = _extent(vertices, vertex_start[other], vertex_start[other + 1], nx, ny, nz)
    return lo - _dot(vertices, face_vertices[face_start[f]], nx, ny, nz)


@numba.njit(cache=True)
def _inside(vertices, first, last):
    """A point inside the block of vertices first..last-1: their mean [m]."""
    x, y, z = 0.0, 0.0, 0.0
    for v in range(first, last):
        x, y, z = x + vertices[v, 0], y + vertices[v, 1], z + vertices[v, 2]
    return x / (last - first), y / (last - first), z / (last - first)


@numba.njit(cache=True)
def _edge_axis(vertices, vertex_start, face_vertices, face_start, a, b, fa, qa, fb, qb, inside):
    """The unit axis e_a x e_b oriented out of A at its edge (away from `inside`, a point inside A: the
    normal of the face of A - B the two edges span, along which A's edge is A's farthest part and B's
    edge B's nearest) and the separation along it [m]; separation -inf for parallel edges."""
    p0, p1 = edge_ends(face_vertices, face_start, fa, qa)
    r0, r1 = edge_ends(face_vertices, face_start, fb, qb)
    ex, ey, ez = (
        vertices[p1, 0] - vertices[p0, 0],
        vertices[p1, 1] - vertices[p0, 1],
        vertices[p1, 2] - vertices[p0, 2],
    )
    gx, gy, gz = (
        vertices[r1, 0] - vertices[r0, 0],
        vertices[r1, 1] - vertices[r0, 1],
        vertices[r1, 2] - vertices[r0, 2],
    )
    nx, ny, nz = ey * gz - ez * gy, ez * gx - ex * gz, ex * gy - ey * gx
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    if norm <= PARALLEL_EDGES * math.sqrt((ex * ex + ey * ey + ez * ez) * (gx * gx + gy * gy + gz * gz)):
        return -math.inf, 0.0, 0.0, 0.0
    out = (vertices[p0, 0] - inside[0]) * nx + (vertices[p0, 1] - inside[1]) * ny
    if out + (vertices[p0, 2] - inside[2]) * nz < 0.0:
        norm = -norm
    nx, ny, nz = nx / norm, ny / norm, nz / norm
    _, hi_a = _extent(vertices, vertex_start[a], vertex_start[a + 1], nx, ny, nz)
    lo_b, _ = _extent(vertices, vertex_start[b], vertex_start[b + 1], nx, ny, nz)
    return lo_b - hi_a, nx, ny, nz


@numba.njit(cache=True)
def _axis(vertices, vertex_start, face_vertices, face_start, face_normal, a, b, kind, i, j, fi, fj):
    """Separation [m] and unit normal (A towards B) along one candidate axis."""
    if kind == AXIS_FACE_A:
        s = _face_separation(vertices, vertex_start, face_vertices, face_start, face_normal, i, b)
        return s, face_normal[i, 0], face_normal[i, 1], face_normal[i, 2]
    if kind == AXIS_FACE_B:
        s = _face_separation(vertices, vertex_start, face_vertices, face_start, face_normal, i, a)
        return s, -face_normal[i, 0], -face_normal[i, 1], -face_normal[i, 2]
    inside = _inside(vertices, vertex_start[a], vertex_start[a + 1])
    return _edge_axis(vertices, vertex_start, face_vertices, face_start, a, b, fi, i, fj, j, inside)


@numba.njit(cache=True)
def _face_of_entry(face_start, first_face, last_face, q):
    """The face whose loop holds entry q (binary search over faces first_face..last_face-1)."""
    lo, hi = first_face, last_face - 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if face_start[mid] <= q:
            lo = mid
        else:
            hi = mid - 1
    return lo


@numba.njit(cache=True)
def _edges(face_vertices, face_start, face_normal, first_face, last_face, first_vertex, last_vertex, sign):
    """A block's edges in the order the test meets them (face by face, entry by entry, each edge at the
    entry whose first vertex is the smaller one): int64 (e, 3) rows, the entry q, its face f and the face
    g across the edge (the one whose loop runs it the other way; -1 if none does); and float64 (e, 9)
    rows, the edge's arc on the Gauss map (times `sign`, -1 for B: the arc of -B): its ends sign n_f and
    sign n_g and their cross product (sign n_g) x (sign n_f) (`_minkowski_face`)."""
    count = last_vertex - first_vertex
    across = np.full((count, count), -1, dtype=np.int64)
    e = 0
    for f in range(first_face, last_face):
        for q in range(face_start[f], face_start[f + 1]):
            p0, p1 = edge_ends(face_vertices, face_start, f, q)
            if p0 > p1:
                across[p1 - first_vertex, p0 - first_vertex] = f
            else:
                e += 1
    edges, arcs = np.empty((e, 3), dtype=np.int64), np.zeros((e, 9))
    e = 0
    for f in range(first_face, last_face):
        for q in range(face_start[f], face_start[f + 1]):
            p0, p1 = edge_ends(face_vertices, face_start, f, q)
            if p0 > p1:
                continue
            g = across[p0 - first_vertex, p1 - first_vertex]
            edges[e, 0], edges[e, 1], edges[e, 2] = q, f, g
            if g >= 0:
                ax, ay, az = sign * face_normal[f, 0], sign * face_normal[f, 1], sign * face_normal[f, 2]
                bx, by, bz = sign * face_normal[g, 0], sign * face_normal[g, 1], sign * face_normal[g, 2]
                arcs[e, 0], arcs[e, 1], arcs[e, 2] = ax, ay, az
                arcs[e, 3], arcs[e, 4], arcs[e, 5] = bx, by, bz
                arcs[e, 6], arcs[e, 7], arcs[e, 8] = by * az - bz * ay, bz * ax - bx * az, bx * ay - by * ax
            e += 1
    return edges, arcs


@numba.njit(cache=True, inline="always")
def _minkowski_face(cba, dba, adc, bdc):
    """Whether an edge of A and an edge of B span a face of the Minkowski difference A - B (so that
    their cross product is a candidate axis), from their arcs on the Gauss map, A's from a to b and that
    of -B from c to d (`_edges`): whether the arcs cross (Gregorius 2013, "The separating axis test
    between convex polyhedra", GDC), i.e. c and d lie on either side of the plane of a and b (cba = c .
    (b x a), dba = d . (b x a) of opposite signs), a and b on either side of that of c and d (adc = a .
    (d x c), bdc = b . (d x c)), and the two arcs in the same hemisphere (cba bdc > 0). Arcs that only
    touch give no axis of their own: their cross product is a face normal already tested."""
    return cba * dba < 0.0 and adc * bdc < 0.0 and cba * bdc > 0.0


@numba.njit(cache=True)
def separating_axis(
    vertices,
    vertex_start,
    face_vertices,
    face_start,
    block_face_start,
    face_normal,
    a,
    b,
    size,
    margin,
    cached_kind,
    cached_i,
    cached_j,
):
    """The separating-axis test of convex blocks a and b.

    Separation along a unit axis n (from A towards B) is min over B of n.x - max over A of n.x [m]: > 0
    apart by at least that much, <= 0 overlapping. Over the face normals of the Minkowski difference
    A - B, its greatest value is > 0 if and only if the blocks are apart, and in overlap its opposite is
    the penetration depth, the shortest move that parts them; at any other axis it is no greater. Those
    normals are the face normals of A (outward), of B (inward), and the cross products of the edges of
    A and B whose arcs cross on the Gauss map (`_minkowski_face`), oriented out of A at its edge
    (`_edge_axis`): only those pairs are tried (of two boxes' 144, about a dozen), and the edges named
    are the ones that meet, where the contact is. An axis replaces the best so far only if it separates
    by more than `FACE_PREFERENCE` x size [m], so ties go to A's faces, then B's, then edges, in index
    order.

    Started from the last step's axis (cached_kind >= 0, with cached_i and cached_j as returned): if that
    axis still parts the blocks by more than `margin` [m] it is returned at once; so is, in a full test,
    the first axis that does. Otherwise the full test runs and its answer does not depend on the cache.

    Returns (separation [m], kind, i, j, nx, ny, nz): kind `AXIS_FACE_A` or `AXIS_FACE_B` with i the face
    (j = -1), or `AXIS_EDGES` with i and j the loop entries naming the edges of A and of B; n from A
    towards B.
    """
    first_fa, last_fa = block_face_start[a], block_face_start[a + 1]
    first_fb, last_fb = block_face_start[b], block_face_start[b + 1]
    if cached_kind >= 0:
        fi = _face_of_entry(face_start, first_fa, last_fa, cached_i) if cached_kind == AXIS_EDGES else -1
        fj = _face_of_entry(face_start, first_fb, last_fb, cached_j) if cached_kind == AXIS_EDGES else -1
        s, nx, ny, nz = _axis(
            vertices,
            vertex_start,
            face_vertices,
            face_start,
            face_normal,
            a,
            b,
            cached_kind,
            cached_i,
            cached_j,
            fi,
            fj,
        )
        if s > margin:
            return s, cached_kind, cached_i, cached_j, nx, ny, nz
    tol = FACE_PREFERENCE * size
    best, kind, bi, bj, bx, by, bz = -math.inf, -1, -1, -1, 0.0, 0.0, 0.0
    for f in range(first_fa, last_fa):
        s = _face_separation(vertices, vertex_start, face_vertices, face_start, face_normal, f, b)
        if s > best + tol:
            best, kind, bi, bx, by, bz = (
                s,
                AXIS_FACE_A,
                f,
                face_normal[f, 0],
                face_normal[f, 1],
                face_normal[f, 2],
            )
            if best > margin:
                return best, kind, bi, bj, bx, by, bz
    for f in range(first_fb, last_fb):
        s = _face_separation(vertices, vertex_start, face_vertices, face_start, face_normal, f, a)
        if s > best + tol:
            best, kind, bi = s, AXIS_FACE_B, f
            bx, by, bz = -face_normal[f, 0], -face_normal[f, 1], -face_normal[f, 2]
            if best > margin:
                return best, kind, bi, bj, bx, by, bz
    edges_a, arcs_a = _edges(
        face_vertices, face_start, face_normal, first_fa, last_fa, vertex_start[a], vertex_start[a + 1], 1.0
    )
    edges_b, arcs_b = _edges(
        face_vertices, face_start, face_normal, first_fb, last_fb, vertex_start[b], vertex_start[b + 1], -1.0
    )
    inside = _inside(vertices, vertex_start[a], vertex_start[a + 1])
    for ea in range(edges_a.shape[0]):
        qa, fa, known = edges_a[ea, 0], edges_a[ea, 1], edges_a[ea, 2] >= 0
        arc = arcs_a[ea]  # a, b and b x a (`_edges`)
        for eb in range(edges_b.shape[0]):
            if known and edges_b[eb, 2] >= 0:  # both arcs known: the pair is tried only if they cross
                cba = arcs_b[eb, 0] * arc[6] + arcs_b[eb, 1] * arc[7] + arcs_b[eb, 2] * arc[8]
                dba = arcs_b[eb, 3] * arc[6] + arcs_b[eb, 4] * arc[7] + arcs_b[eb, 5] * arc[8]
                adc = arc[0] * arcs_b[eb, 6] + arc[1] * arcs_b[eb, 7] + arc[2] * arcs_b[eb, 8]
                bdc = arc[3] * arcs_b[eb, 6] + arc[4] * arcs_b[eb, 7] + arc[5] * arcs_b[eb, 8]
                if not _minkowski_face(cba, dba, adc, bdc):
                    continue
            qb, fb = edges_b[eb, 0], edges_b[eb, 1]
            s, nx, ny, nz = _edge_axis(
                vertices, vertex_start, face_vertices, face_start, a, b, fa, qa, fb, qb, inside
            )
            if s > best + tol:
                best, kind, bi, bj, bx, by, bz = s, AXIS_EDGES, qa, qb, nx, ny, nz
                if best > margin:
                    return best, kind, bi, bj, bx, by, bz
    return best, kind, bi, bj, bx, by, bz


@numba.njit(cache=True)
def _facing_face(face_normal, first, last, nx, ny, nz):
    """The face among first..last-1 most nearly opposite to n, and the cosine to n (-1: opposite)."""
    best, cosine = -1, math.inf
    for f in range(first, last):
        c = face_normal[f, 0] * nx + face_normal[f, 1] * ny + face_normal[f, 2] * nz
        if c < cosine:
            best, cosine = f, c
    return best, cosine


@numba.njit(cache=True)
def _lowest_corner(vertices, vertex_start, face_vertices, face_start, block_face_start, blk, nx, ny, nz):
    """Block blk's lowest vertex along n and its lowest neighbour along an edge: (v, w, w's height above
    v [m])."""
    v, lowest = -1, math.inf
    for k in range(vertex_start[blk], vertex_start[blk + 1]):
        d = _dot(vertices, k, nx, ny, nz)
        if d < lowest:
            v, lowest = k, d
    w, rise = -1, math.inf
    for f in range(block_face_start[blk], block_face_start[blk + 1]):
        for q in range(face_start[f], face_start[f + 1]):
            p0, p1 = edge_ends(face_vertices, face_start, f, q)
            if p0 == v and _dot(vertices, p1, nx, ny, nz) - lowest < rise:
                w, rise = p1, _dot(vertices, p1, nx, ny, nz) - lowest
    return v, w, rise


@numba.njit(cache=True)
def _closest_on_edges(p0, p1, r0, r1):
    """The middle of the closest points of segments p0-p1 and r0-r1 (not parallel)."""
    d1, d2, w = p1 - p0, r1 - r0, p0 - r0
    a, b, c = d1 @ d1, d1 @ d2, d2 @ d2
    d, e = d1 @ w, d2 @ w
    denom = a * c - b * b
    sc = min(max((b * e - c * d) / denom, 0.0), 1.0)
    tc = min(max((b * sc + e) / c, 0.0), 1.0)
    sc = min(max((b * tc - d) / a, 0.0), 1.0)
    return 0.5 * (p0 + sc * d1 + r0 + tc * d2)


@numba.njit(cache=True)
def contact_patch(
    vertices, vertex_start, face_vertices, face_start, block_face_start, face_normal, a, b, size, kind, i, j
):
    """The contact of blocks a and b on the axis `separating_axis` returned (kind, i, j).

    Returns (contact kind, reference face, incident face, area [m²], centroid x, y, z [m]): the reference
    face is the face whose normal is the axis (-1 for edge–edge), the incident face the other block's
    face facing it (-1 unless face–face); the area is the overlap's (face–face) or nominal (module
    docstring); the centroid lies on the reference plane (face–face, edge–face, vertex–face) or between
    the two edges (edge–edge). An edge or corner that projects outside the reference face gives area 0.
    """
    w = NOMINAL_WIDTH * size
    if kind == AXIS_EDGES:
        fa = _face_of_entry(face_start, block_face_start[a], block_face_start[a + 1], i)
        fb = _face_of_entry(face_start, block_face_start[b], block_face_start[b + 1], j)
        p0, p1 = edge_ends(face_vertices, face_start, fa, i)
        r0, r1 = edge_ends(face_vertices, face_start, fb, j)
        c = _closest_on_edges(vertices[p0], vertices[p1], vertices[r0], vertices[r1])
        return EDGE_EDGE, -1, -1, w * w, c[0], c[1], c[2]
    ref, other = i, b if kind == AXIS_FACE_A else a
    nx, ny, nz = face_normal[ref, 0], face_normal[ref, 1], face_normal[ref, 2]
    inc, cosine = _facing_face(face_normal, block_face_start[other], block_face_start[other + 1], nx, ny, nz)
    if cosine <= -math.cos(FACE_ANGLE):
        poly, o, s, t = face_overlap(vertices, face_vertices, face_start, face_normal, ref, inc)
        area, cs, ct = polygon_area_centroid(poly)
        c = o + cs * s + ct * t
        return FACE_FACE, ref, inc, area, c[0], c[1], c[2]
    o, s, t = face_frame(vertices, face_vertices, face_start, face_normal, ref)
    reference = _in_plane(vertices, face_vertices, face_start, ref, o, s, t, False)
    v, u, rise = _lowest_corner(
        vertices, vertex_start, face_vertices, face_start, block_face_start, other, nx, ny, nz
    )
    dv, du = vertices[v] - o, vertices[u] - o
    pv = np.array([dv @ s, dv @ t])
    if rise <= size * math.sin(FACE_ANGLE):
        inside, q0, q1 = clip_segment(pv, np.array([du @ s, du @ t]), reference)
        if not inside:
            return EDGE_FACE, ref, -1, 0.0, vertices[v, 0], vertices[v, 1], vertices[v, 2]
        m = 0.5 * (q0 + q1)
        c = o + m[0] * s + m[1] * t
        return EDGE_FACE, ref, -1, math.sqrt((q1 - q0) @ (q1 - q0)) * w, c[0], c[1], c[2]
    inside, _, _ = clip_segment(pv, pv, reference)
    c = o + pv[0] * s + pv[1] * t
    return VERTEX_FACE, ref, -1, w * w if inside else 0.0, c[0], c[1], c[2]
