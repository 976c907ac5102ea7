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

Sub-contacts of a face–face contact (`face_sub_contacts`): the reference face is cut into triangles, a
fan from its first vertex, each split into four at its mid-sides `refine` times; a sub-contact sits at
each triangle's centroid, fixed to the reference block, so it keeps its shear history as the blocks
slide. Its share of the overlap is the triangle clipped to the overlap polygon, integrated exactly (area
and centroid): shares never overlap, they tile the overlap, and they sum to its area whatever the
refinement. 3DEC puts sub-contacts at the triangulation's vertices with a third of each neighbouring
triangle's area, all or nothing as the vertex is inside the other face or not, which makes the area
depend on the refinement; 2D bbmc's lesson (`bbmc.dem.contact_geometry`) was to integrate each share.
"""

import math

import numba
import numpy as np

from bbmc.dem3d.polygon_clip import (
    clip_into,
    clip_polygon,
    clip_segment,
    half_plane_into,
    polygon_area_centroid,
    polygon_moments,
)

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
