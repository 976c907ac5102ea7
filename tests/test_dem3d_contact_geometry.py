"""The 3D narrow phase: separating axes, contact kinds, overlap areas and sub-contact shares."""

import math

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation
from shapely.geometry import Point, Polygon

from bbmc.dem3d import contact_geometry as cg
from bbmc.dem3d import face_contact

BOX_LOOPS = [[0, 2, 6, 4], [1, 3, 7, 5], [0, 1, 5, 4], [2, 3, 7, 6], [0, 1, 3, 2], [4, 5, 7, 6]]


def box(lo, hi, rotation=None, about=None):
    """A box [lo, hi] (vertex ix + 2 iy + 4 iz), turned by `rotation` about `about` (default its centre)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts = np.array([[(hi if (k >> d) & 1 else lo)[d] for d in range(3)] for k in range(8)])
    if rotation is not None:
        c = 0.5 * (lo + hi) if about is None else np.asarray(about, float)
        verts = c + (verts - c) @ rotation.as_matrix().T
    return verts, BOX_LOOPS


def hull(points):
    """A convex polyhedron from points: its hull's triangles as faces."""
    h = ConvexHull(points)
    return points[h.vertices], [list(np.searchsorted(h.vertices, s)) for s in h.simplices]


def scene(*blocks):
    """Flat arrays (vertices, vertex_start, face_vertices, face_start, block_face_start, face_normal)
    of blocks given as (vertices, face loops in any orientation): each loop turned counter-clockwise
    seen from outside."""
    verts, vstart, loops, fstart, bfstart, normals = [], [0], [], [0], [0], []
    for v, faces in blocks:
        base, centre = vstart[-1], v.mean(axis=0)
        for loop in faces:
            p = v[loop]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            if n @ (p.mean(axis=0) - centre) < 0.0:
                loop, n = loop[::-1], -n
            loops.extend(base + np.asarray(loop))
            fstart.append(len(loops))
            normals.append(n / np.linalg.norm(n))
        verts.extend(v)
        vstart.append(len(verts))
        bfstart.append(len(normals))
    return (
        np.array(verts, float),
        np.array(vstart, np.int64),
        np.array(loops, np.int64),
        np.array(fstart, np.int64),
        np.array(bfstart, np.int64),
        np.array(normals, float),
    )


def sat(arrays, a=0, b=1, size=1.0, margin=0.0, cache=(-1, -1, -1)):
    return cg.separating_axis(*arrays, a, b, size, margin, *cache)


def subs(arrays, ref, inc, refine, centre, rotation):
    verts, _, loops, fstart, _, normals = arrays
    return face_contact.face_sub_contacts(verts, loops, fstart, normals, ref, inc, refine, centre, rotation)


def patch(arrays, a=0, b=1, size=1.0):
    _, kind, i, j, *_ = sat(arrays, a, b, size)
    return cg.contact_patch(*arrays, a, b, size, kind, i, j)


@pytest.mark.parametrize(("a", "b"), [(0.0, 0.0), (0.3, 0.1), (0.25, -0.6), (-0.9, 0.45)])
def test_offset_cubes_overlap_on_the_offset_rectangle(a, b):
    """A unit cube on another, offset by (a, b): a face–face contact of area (1 - |a|)(1 - |b|) on the
    plane z = 1 (1e-12: a few rounding steps of numbers near 1), normal (0, 0, 1) from A to B."""
    arrays = scene(box([0, 0, 0], [1, 1, 1]), box([a, b, 0.999], [1 + a, 1 + b, 1.999]))
    s, kind, *_, nx, ny, nz = sat(arrays)
    assert kind == cg.AXIS_FACE_A and s == pytest.approx(-0.001, abs=1e-12)
    assert (nx, ny, nz) == (0.0, 0.0, 1.0)
    contact, ref, inc, area, cx, cy, cz = patch(arrays)
    assert contact == cg.FACE_FACE and (ref, inc) == (5, 10)
    assert area == pytest.approx((1 - abs(a)) * (1 - abs(b)), abs=1e-12)
    assert (cx, cy, cz) == pytest.approx((0.5 + a / 2, 0.5 + b / 2, 1.0), abs=1e-12)


def test_upper_block_first_gives_the_opposite_normal():
    """Listed the other way round the normal still runs from A (now the upper cube) to B: (0, 0, -1)."""
    arrays = scene(box([0.3, 0.1, 1.0], [1.3, 1.1, 2.0]), box([0, 0, 0], [1, 1, 1]))
    s, kind, *_, nx, ny, nz = sat(arrays)
    assert kind == cg.AXIS_FACE_A and s == 0.0 and (nx, ny, nz) == (0.0, 0.0, -1.0)
    contact, *_, area, _, _, _ = patch(arrays)
    assert contact == cg.FACE_FACE and area == pytest.approx(0.7 * 0.9, abs=1e-12)


def test_cube_turned_30_degrees_overlaps_as_shapely_says():
    """Upper cube turned 30 degrees about z: the overlap area is that of the two squares' intersection
    (shapely, 1e-12)."""
    turn = Rotation.from_euler("z", 30, degrees=True)
    upper = box([0.4, -0.2, 1.0], [1.4, 0.8, 2.0], turn)
    arrays = scene(box([0, 0, 0], [1, 1, 1]), upper)
    contact, _, _, area, cx, cy, cz = patch(arrays)
    lower_sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    upper_sq = Polygon(upper[0][4:, :2]).convex_hull
    expected = lower_sq.intersection(upper_sq)
    assert contact == cg.FACE_FACE
    assert area == pytest.approx(expected.area, abs=1e-12)
    assert (cx, cy, cz) == pytest.approx((expected.centroid.x, expected.centroid.y, 1.0), abs=1e-12)


def test_separated_blocks_report_the_gap_and_its_axis():
    """Cubes 0.5 apart in z: separation 0.5 along A's top face; 0.2 apart along -x: B's face."""
    arrays = scene(box([0, 0, 0], [1, 1, 1]), box([0.2, 0.3, 1.5], [1.2, 1.3, 2.5]))
    assert sat(arrays) == (0.5, cg.AXIS_FACE_A, 5, -1, 0.0, 0.0, 1.0)
    arrays = scene(box([0, 0, 0], [1, 1, 1]), box([-1.2, 0.3, 0.1], [-0.2, 1.3, 1.1]))
    s, kind, i, _, nx, ny, nz = sat(arrays)
    assert s == pytest.approx(0.2, abs=1e-15) and kind == cg.AXIS_FACE_A and i == 0
    assert (nx, ny, nz) == (-1.0, 0.0, 0.0)


@pytest.mark.parametrize("turn", [45, 135, -45])
def test_crossing_bars_touch_edge_to_edge(turn):
    """Two square bars turned 45 degrees (or 135, -45: another edge of each on top) about their axes (x
    and y), so that an edge of each points at the other, pushed 0.01 into each other: an edge–edge point
    contact, depth 0.01, normal z, at the middle of the closest points of the two edges that meet (each
    bar has four edges along it with the same cross product: the contact is on the ones that touch, at
    the origin, not on a parallel edge 0.2 m away)."""
    r = 0.1 * math.sqrt(2.0)
    lower = box([-2, -0.1, -0.1], [2, 0.1, 0.1], Rotation.from_euler("x", turn, degrees=True))
    c = 2 * r - 0.01
    upper = box([-0.1, -2, c - 0.1], [0.1, 2, c + 0.1], Rotation.from_euler("y", turn, degrees=True))
    arrays = scene(lower, upper)
    s, kind, *_, nx, ny, nz = sat(arrays)
    assert kind == cg.AXIS_EDGES and s == pytest.approx(-0.01, abs=1e-12)
    assert (nx, ny, nz) == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)
    contact, ref, inc, area, *centre = patch(arrays, size=0.2)
    assert (contact, ref, inc) == (cg.EDGE_EDGE, -1, -1)
    assert area == pytest.approx((cg.NOMINAL_WIDTH * 0.2) ** 2, rel=1e-12)
    assert centre == pytest.approx([0.0, 0.0, r - 0.005], abs=1e-12)


def test_tilted_cube_on_a_slab_touches_with_a_corner_or_an_edge():
    """A unit cube turned 30 degrees about x then 20 about y stands on a slab on one corner, 1 mm
    deep: vertex–face at the corner's foot, nominal area; turned about x only it stands on an edge
    of length 1: edge–face, area 1 x the nominal width, centred on the edge's foot."""
    slab = box([-5, -5, -1], [5, 5, 0])
    for turn, expected in (
        (Rotation.from_euler("xy", [30, 20], degrees=True), cg.VERTEX_FACE),
        (Rotation.from_euler("x", 30, degrees=True), cg.EDGE_FACE),
    ):
        verts, loops = box([0, 0, 0], [1, 1, 1], turn)
        verts = verts - [0, 0, verts[:, 2].min() + 0.001]
        arrays = scene(slab, (verts, loops))
        s, kind, i, *_ = sat(arrays)
        assert (kind, i) == (cg.AXIS_FACE_A, 5) and s == pytest.approx(-0.001, abs=1e-12)
        contact, ref, inc, area, *centre = patch(arrays)
        assert (contact, ref, inc) == (expected, 5, -1)
        low = verts[np.argsort(verts[:, 2])[: 1 if expected == cg.VERTEX_FACE else 2]]
        assert centre == pytest.approx([*low[:, :2].mean(axis=0), 0.0], abs=1e-12)
        width = cg.NOMINAL_WIDTH
        assert area == pytest.approx(width**2 if expected == cg.VERTEX_FACE else width, rel=1e-12)


def _turned_pair():
    turn = Rotation.from_euler("z", 30, degrees=True)
    upper = box([0.4, -0.2, 0.999], [1.4, 0.8, 1.999], turn)
    lower = box([0, 0, 0], [1, 1, 1])
    return scene(lower, upper), upper


@pytest.mark.parametrize("refine", [0, 1, 2])
def test_sub_contact_shares_tile_the_overlap(refine):
    """Shares of refinement 0, 1, 2 (2, 8, 32 sub-contacts) sum to the overlap area (1e-12: sums of
    areas of order 1) and each non-empty share's centroid lies in the overlap; points are in the body
    frame; the gap is -1 mm everywhere (parallel faces)."""
    arrays, upper = _turned_pair()
    contact, ref, inc, area, *_ = patch(arrays)
    assert contact == cg.FACE_FACE
    centre = np.array([0.5, 0.5, 0.5])
    rotation = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    points, share, gap, centroid = subs(arrays, ref, inc, refine, centre, rotation)
    pts = arrays[0]
    assert len(share) == 2 * 4**refine
    assert share.sum() == pytest.approx(area, abs=1e-12)
    assert np.all(share >= 0.0) and (refine < 2 or np.count_nonzero(share) < len(share))  # some empty
    overlap = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]).intersection(Polygon(upper[0][:4, :2]).convex_hull)
    for k in np.flatnonzero(share > 0):
        assert overlap.buffer(1e-12).contains(Point(centroid[k, :2]))
    assert gap == pytest.approx(np.full(len(gap), -0.001), abs=1e-12)
    world = centre + points @ rotation.T
    face = Polygon(pts[arrays[2][arrays[3][ref] : arrays[3][ref + 1]], :2])
    assert np.allclose(world[:, 2], 1.0, atol=1e-15)
    assert all(face.contains(Point(p[:2])) for p in world)


def test_sub_contact_shares_do_not_depend_on_refinement():
    """The area-weighted centroid of the shares is the overlap's centroid at every refinement (1e-12),
    so their resultant's position does not depend on it."""
    arrays, *_ = _turned_pair()
    contact, ref, inc, area, *centre = patch(arrays)
    assert contact == cg.FACE_FACE
    for refine in range(3):
        _, share, _, centroid = subs(arrays, ref, inc, refine, np.zeros(3), np.eye(3))
        assert share @ centroid / area == pytest.approx(centre, abs=1e-12)


def test_sub_contact_gap_of_a_slightly_tilted_face_is_linear():
    """An upper cube tilted 2 degrees about x (within the face angle) on a lower one: face–face, and each
    share's gap is the height of the tilted face above z = 1 at its centroid (1e-12)."""
    turn = Rotation.from_euler("x", 2, degrees=True)
    upper = box([0.1, 0.1, 1.0], [1.1, 1.1, 2.0], turn, about=[0.6, 0.6, 1.0])
    arrays = scene(box([0, 0, 0], [1, 1, 1]), upper)
    contact, ref, inc, *_ = patch(arrays)
    assert contact == cg.FACE_FACE
    _, share, gap, centroid = subs(arrays, ref, inc, 1, np.zeros(3), np.eye(3))
    height = np.tan(np.radians(2.0)) * (centroid[:, 1] - 0.6)
    assert gap == pytest.approx(height, abs=1e-12)
    assert share.sum() == pytest.approx(0.9 * (0.4 + 0.5 * np.cos(np.radians(2.0))), abs=1e-12)  # projected


def _random_pair(rng):
    a = box(-rng.uniform(0.2, 1.0, 3), rng.uniform(0.2, 1.0, 3), Rotation.random(random_state=rng))
    points = rng.normal(size=(12, 3)) * rng.uniform(0.3, 1.0) + rng.uniform(-1.2, 1.2, 3)
    return scene(a, hull(points))


def _interiors_meet(arrays):
    """Brute force: the largest t with n_f . x + t <= d_f for every face of both blocks (a linear
    program); the interiors meet if and only if t > 0."""
    verts, _, loops, fstart, _, normals = arrays
    d = np.array([normals[f] @ verts[loops[fstart[f]]] for f in range(len(normals))])
    a_ub = np.column_stack([normals, np.ones(len(normals))])
    res = linprog([0, 0, 0, -1], A_ub=a_ub, b_ub=d, bounds=[(None, None)] * 3 + [(None, 10.0)])
    return -res.fun


def test_verdict_agrees_with_a_linear_program_on_random_pairs():
    """300 pairs (a turned box and the hull of 12 random points): the separating-axis verdict agrees with
    the linear program's on every one (pairs whose LP margin is under 1e-9 would be ties: none occur)."""
    rng = np.random.default_rng(36)
    verdicts = []
    for _ in range(300):
        arrays = _random_pair(rng)
        t = _interiors_meet(arrays)
        assert abs(t) > 1e-9
        s = sat(arrays)[0]
        assert (s < 0.0) == (t > 0.0)
        verdicts.append(t > 0.0)
    assert 50 < sum(verdicts) < 250  # both verdicts are tested many times


def test_axis_cache_gives_the_fresh_answer():
    """Started from the axis of a previous, moved pose, the test returns exactly the fresh answer where
    the blocks are within the margin, and the same verdict (apart) otherwise."""
    rng = np.random.default_rng(7)
    margin = 0.05
    for _ in range(200):
        arrays = _random_pair(rng)
        moved = (arrays[0] + rng.normal(scale=0.05, size=3), *arrays[1:])
        cache = sat(moved, margin=margin)[1:4]
        fresh, cached = sat(arrays, margin=margin), sat(arrays, margin=margin, cache=cache)
        if fresh[0] <= margin:
            assert cached == fresh
        else:
            assert cached[0] > margin


def _edge_rows(loops, fstart, faces):
    """Every edge of the faces, once each way: (first vertex, second vertex) rows."""
    return np.array([(loops[q], loops[q + 1 if q + 1 < fstart[f + 1] else fstart[f]])
                     for f in faces for q in range(fstart[f], fstart[f + 1])])  # fmt: skip


def test_pruned_axes_find_the_depth_of_every_axis_and_the_edges_that_meet():
    """300 random pairs (`_random_pair`): where they overlap, the depth is the brute-force one over every
    face normal and every edge pair's cross product in both orientations (to FACE_PREFERENCE x size, the
    test's tie tolerance: only Gauss-map crossing pairs are tried), and an edge–edge axis names edges that
    lie on the two blocks' facing extremes along it (1e-9 m: rounding), where the contact is."""
    rng = np.random.default_rng(36)
    overlapping = edge_axes = 0
    for _ in range(300):
        arrays = _random_pair(rng)
        verts, vstart, loops, fstart, bfstart, normals = arrays
        first, second = verts[: vstart[1]], verts[vstart[1] :]
        ea = verts[_edge_rows(loops, fstart, range(bfstart[1]))]
        eb = verts[_edge_rows(loops, fstart, range(bfstart[1], bfstart[2]))]
        cross = np.cross((ea[:, 1] - ea[:, 0])[:, None], (eb[:, 1] - eb[:, 0])[None]).reshape(-1, 3)
        cross = cross[np.linalg.norm(cross, axis=1) > 1e-9]
        axes = np.vstack([normals[: bfstart[1]], -normals[bfstart[1] :], cross, -cross])
        axes /= np.linalg.norm(axes, axis=1)[:, None]
        brute = ((axes @ second.T).min(axis=1) - (axes @ first.T).max(axis=1)).max()
        s, kind, i, j, *n = sat(arrays)
        if brute >= 0.0:
            continue
        overlapping += 1
        assert brute - cg.FACE_PREFERENCE <= s <= brute + 1e-12
        if kind == cg.AXIS_EDGES:
            edge_axes += 1
            fa = cg._face_of_entry(fstart, bfstart[0], bfstart[1], i)
            fb = cg._face_of_entry(fstart, bfstart[1], bfstart[2], j)
            ends_a = verts[list(cg.edge_ends(loops, fstart, fa, i))] @ n
            ends_b = verts[list(cg.edge_ends(loops, fstart, fb, j))] @ n
            assert ends_a == pytest.approx([(first @ n).max()] * 2, abs=1e-9)
            assert ends_b == pytest.approx([(second @ n).min()] * 2, abs=1e-9)
    assert overlapping > 50 and edge_axes > 10  # both are tested many times
