"""Convex polyhedra (bbmc.geometry.polyhedra): construction from points or faces, the checks at load,
boxes and extrusions, and exact mass properties against closed forms and an independent quadrature."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay
from scipy.spatial.transform import Rotation

from bbmc.geometry.polyhedra import UNTAGGED, box, extrude, from_vertices, moved, polyhedron_fault
from bbmc.geometry.polyhedron_mass import mass_properties, volume

# Sums of a handful of products of numbers of order 1: exact but for rounding, a few ulp each.
ROUNDING = 1e-12

CUBE = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])


def _outward_and_closed(block):
    """Each stored loop turns anticlockwise about its stored outward normal, and its vertices lie on its
    plane."""
    centroid = mass_properties(block).centroid
    for f, loop in enumerate(block.faces()):
        points = block.vertices[loop]
        area = np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0)
        assert area @ block.normals[f] > 0
        assert (points.mean(axis=0) - centroid) @ block.normals[f] > 0
        np.testing.assert_allclose(points @ block.normals[f], block.offsets[f], atol=ROUNDING * block.size)


def test_box_inertia_is_m_b2_c2_over_12():
    """A 1 x 2 x 3 m box of 2500 kg/m^3: I_xx = m (b^2 + c^2) / 12 and its cyclic twins, no products."""
    a, b, c, rho = 1.0, 2.0, 3.0, 2500.0
    props = mass_properties(box([0, 0, 0], [a, b, c]), rho)
    m = rho * a * b * c
    assert props.mass == pytest.approx(m, rel=ROUNDING)
    np.testing.assert_allclose(props.centroid, [a / 2, b / 2, c / 2], rtol=ROUNDING)
    expected = np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12
    np.testing.assert_allclose(props.inertia, expected, atol=ROUNDING * m * 14)
    np.testing.assert_allclose(props.principal_moments, np.sort(np.diag(expected)), rtol=ROUNDING)


def test_cube_from_points_has_six_square_faces_and_isotropic_inertia():
    """The hull's 12 triangles merge into 6 squares; I = m a^2 / 6 about every axis."""
    cube = from_vertices(CUBE * 2.0)
    assert cube.face_count == 6
    assert all(len(loop) == 4 for loop in cube.faces())
    assert len(cube.edges) == 12
    assert np.all(cube.face_tags == UNTAGGED)
    _outward_and_closed(cube)
    props = mass_properties(cube, 3.0)
    np.testing.assert_allclose(props.inertia, np.eye(3) * 24.0 * 4.0 / 6.0, atol=ROUNDING * 24)


def test_regular_tetrahedron_against_closed_form():
    """Edge a: V = a^3 / (6 sqrt 2), and the inertia about the centroid is isotropic, m a^2 / 20."""
    a = 2.0
    corners = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float) * a / np.sqrt(8)
    props = mass_properties(from_vertices(corners + np.array([3.0, -2.0, 7.0])), 1.0)
    assert props.volume == pytest.approx(a**3 / (6 * np.sqrt(2)), rel=ROUNDING)
    np.testing.assert_allclose(props.centroid, [3.0, -2.0, 7.0], atol=ROUNDING * 10)
    np.testing.assert_allclose(props.inertia, np.eye(3) * props.mass * a * a / 20, atol=ROUNDING)


def test_right_tetrahedron_against_closed_form():
    """Corners 0, a e1, b e2, c e3: V = abc / 6, centroid (a, b, c) / 4, and about the centroid
    I_xx = 3 m (b^2 + c^2) / 80, I_xy = m a b / 80 (the product -integral of x y dm is positive here:
    the tetrahedron's mass lies where (x - a/4)(y - b/4) < 0), cyclic."""
    a, b, c, rho = 1.0, 2.0, 3.0, 2.0
    props = mass_properties(from_vertices([[0, 0, 0], [a, 0, 0], [0, b, 0], [0, 0, c]]), rho)
    m = rho * a * b * c / 6
    assert props.volume == pytest.approx(a * b * c / 6, rel=ROUNDING)
    np.testing.assert_allclose(props.centroid, [a / 4, b / 4, c / 4], rtol=ROUNDING)
    expected = (
        m
        / 80
        * np.array(
            [
                [3 * (b * b + c * c), a * b, a * c],
                [a * b, 3 * (a * a + c * c), b * c],
                [a * c, b * c, 3 * (a * a + b * b)],
            ]
        )
    )
    np.testing.assert_allclose(props.inertia, expected, atol=ROUNDING * m * 40)


def test_moved_box_tensor_turns_as_r_i_rt():
    """A box turned by R and shifted by t: centroid R c + t, inertia R I R^T, the same principal moments,
    principal axes turned by R up to sign, and still a valid polyhedron."""
    block = box([0, 0, 0], [1, 2, 3])
    rotation = Rotation.from_euler("zyx", [0.3, -1.1, 2.0]).as_matrix()
    shift = np.array([10.0, -4.0, 2.5])
    before, after = mass_properties(block, 7.0), mass_properties(moved(block, rotation, shift), 7.0)
    np.testing.assert_allclose(after.centroid, rotation @ before.centroid + shift, atol=ROUNDING * 10)
    np.testing.assert_allclose(after.inertia, rotation @ before.inertia @ rotation.T, atol=ROUNDING * 100)
    np.testing.assert_allclose(after.principal_moments, before.principal_moments, rtol=ROUNDING)
    turned = after.principal_axes.T @ rotation @ before.principal_axes
    np.testing.assert_allclose(np.abs(turned), np.eye(3), atol=1e-12)
    assert polyhedron_fault(moved(block, rotation, shift)) is None


def _keast_mass_properties(points):
    """Volume, centroid and second moment about the origin by an independent route: the points'
    Delaunay tetrahedra, each integrated by the 4-point rule exact for quadratics (Keast 1986: the
    points a + (b - a) beta + ... with alpha = 0.5854101966249685, beta = 0.1381966011250105)."""
    alpha, beta = 0.5854101966249685, 0.1381966011250105
    volume_sum, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for simplex in Delaunay(points).simplices:
        corners = points[simplex]
        v = abs(np.linalg.det(corners[1:] - corners[0])) / 6
        for k in range(4):
            weights = np.full(4, beta)
            weights[k] = alpha
            x = weights @ corners
            volume_sum += v / 4
            first += v / 4 * x
            second += v / 4 * np.outer(x, x)
    centroid = first / volume_sum
    return volume_sum, centroid, second - volume_sum * np.outer(centroid, centroid)


@pytest.mark.parametrize("seed", range(5))
def test_random_hulls_against_qhull_and_an_independent_quadrature(seed):
    """Random convex hulls: the volume equals Qhull's to 1e-12 (relative), and centroid and inertia
    equal an independent quadrature of the Delaunay tetrahedra to 1e-10 (relative to size and I):
    both exact for polyhedra, so only rounding separates them."""
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(40, 3)) * [3.0, 1.0, 0.5] + [100.0, -50.0, 20.0]
    points = points[ConvexHull(points).vertices]
    block = from_vertices(points)
    _outward_and_closed(block)
    assert polyhedron_fault(block) is None
    props = mass_properties(block, 1.0)
    assert volume(block) == pytest.approx(ConvexHull(points).volume, rel=1e-12)
    v, centroid, second = _keast_mass_properties(points)
    assert props.volume == pytest.approx(v, rel=1e-12)
    np.testing.assert_allclose(props.centroid, centroid, atol=1e-10 * block.size)
    np.testing.assert_allclose(props.inertia, np.trace(second) * np.eye(3) - second, atol=1e-10 * v * 10)


def test_principal_axes_are_a_right_handed_rotation_that_diagonalises_inertia():
    rng = np.random.default_rng(7)
    props = mass_properties(from_vertices(_hull_points(rng)), 2600.0)
    axes = props.principal_axes
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
    assert np.all(np.diff(props.principal_moments) > 0)
    np.testing.assert_allclose(
        axes @ np.diag(props.principal_moments) @ axes.T,
        props.inertia,
        rtol=0,
        atol=1e-12 * props.inertia.max(),
    )


def _hull_points(rng):
    points = rng.normal(size=(30, 3)) * [2.0, 1.0, 0.7]
    return points[ConvexHull(points).vertices]


def test_far_from_origin_keeps_its_inertia():
    """A 1 m cube at UTM-like coordinates (5e5, 5e6, 100) m: the sums run about the vertices' mean, so its
    inertia keeps 1e-6 relative accuracy (about the origin, I would be lost in x^2 ~ 2.5e13)."""
    props = mass_properties(box([5e5, 5e6, 100.0], [5e5 + 1, 5e6 + 1, 101.0]), 1.0)
    np.testing.assert_allclose(props.inertia, np.eye(3) / 6, atol=1e-6 / 6)


def test_hexagonal_prism_from_points_merges_coplanar_triangles():
    angles = np.arange(6) * np.pi / 3
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    prism = from_vertices(
        np.vstack([np.column_stack([ring, np.zeros(6)]), np.column_stack([ring, np.ones(6)])])
    )
    assert sorted(len(loop) for loop in prism.faces()) == [4] * 6 + [6, 6]
    assert len(prism.edges) == 18
    assert volume(prism) == pytest.approx(3 * np.sqrt(3) / 2, rel=ROUNDING)


def test_given_faces_in_either_sense_are_turned_outward():
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    reversed_some = [face[::-1] if k % 2 else face for k, face in enumerate(faces)]
    for given in (faces, reversed_some):
        block = from_vertices(CUBE, given)
        _outward_and_closed(block)
        assert volume(block) == pytest.approx(1.0, rel=ROUNDING)


def test_extrusion_maps_2d_x_y_to_3d_x_z_and_extrudes_along_y():
    """A 2 x 1 rectangle of a 2D scene extruded from y = -1 to 2: the 2D point (x, y) is (x, y0, y) in 3D,
    the prism 2 x 3 x 1 m (x, y, z), side i along 2D edge i, the ends last."""
    polygon = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    prism = extrude(polygon, -1.0, 2.0, name="block 4")
    np.testing.assert_allclose(prism.vertices[:4], [[0, -1, 0], [2, -1, 0], [2, -1, 1], [0, -1, 1]])
    np.testing.assert_allclose(
        prism.normals, [[0, 0, -1], [1, 0, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 1, 0]]
    )
    props = mass_properties(prism, 1.0)
    assert props.volume == pytest.approx(6.0, rel=ROUNDING)
    np.testing.assert_allclose(props.centroid, [1.0, 0.5, 0.5], rtol=ROUNDING)
    clockwise = extrude(polygon[::-1], -1.0, 2.0)
    assert volume(clockwise) == pytest.approx(6.0, rel=ROUNDING)
    _outward_and_closed(clockwise)


@pytest.mark.parametrize(
    ("polygon", "y0", "y1", "why"),
    [
        ([[0, 0], [2, 0], [1, 0.2], [2, 1], [0, 1]], 0.0, 1.0, "block 4: the polygon to extrude: .*convex"),
        ([[0, 0], [2, 0], [2, 1], [0, 1]], 1.0, 1.0, "block 4: an extrusion needs y1 > y0"),
    ],
)
def test_extrusion_refuses_bad_input_naming_the_block(polygon, y0, y1, why):
    with pytest.raises(ValueError, match=why):
        extrude(np.array(polygon, dtype=float), y0, y1, name="block 4")


def test_wedge_tetrahedron_from_hand_coordinates():
    """The wedge of the slope issue: toe O, crests C1, C2 on the face, top T behind the crest (hand-made
    points, not a computed wedge): four triangular faces and V = |det(C1, C2, T)| / 6."""
    o, c1, c2, t = [0.0, 0.0, 0.0], [-6.0, 3.0, 10.0], [7.0, 2.5, 10.0], [0.5, 14.0, 12.0]
    wedge = from_vertices([o, c1, c2, t], name="wedge")
    assert wedge.face_count == 4
    assert all(len(loop) == 3 for loop in wedge.faces())
    assert volume(wedge) == pytest.approx(abs(np.linalg.det([c1, c2, t])) / 6, rel=ROUNDING)
    np.testing.assert_allclose(mass_properties(wedge).centroid, np.mean([o, c1, c2, t], axis=0), atol=1e-12)
    _outward_and_closed(wedge)


DENTED = [[0, 0], [2, 0], [1, 0.5], [2, 1], [0, 1]]  # a reflex corner at (1, 0.5)
DENTED_PRISM = np.array([[x, y, z] for z in (0.0, 1.0) for x, y in DENTED])
DENTED_PRISM_FACES = [
    *([i, (i + 1) % 5, (i + 1) % 5 + 5, i + 5] for i in range(5)),
    [4, 3, 2, 1, 0],
    [5, 6, 7, 8, 9],
]
CUBE_FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def _with(points, index, value):
    points = np.array(points, dtype=float)
    points[index] = value
    return points


@pytest.mark.parametrize(
    ("points", "faces", "why"),
    [
        (CUBE[:3], None, "at least 4 vertices"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], None, "one plane or one line: it has no volume"),
        ([[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]], None, "one plane or one line"),
        (np.vstack([CUBE, CUBE[3]]), None, r"two vertices coincide \(vertices 3 and 8\)"),
        (np.vstack([CUBE, [0.5, 0.5, 0.5]]), None, "vertex 8 is not a corner .* on 0 faces"),
        (np.vstack([CUBE, [0.5, 0.5, 0.0]]), None, "vertex 8 is not a corner"),
        (np.vstack([CUBE, [0.5, 0.0, 0.0]]), None, "vertex 8 is not a corner"),
        (_with(CUBE, 0, np.nan), None, "not a finite number"),
        (CUBE * 1e-4 + 1e6, None, "too small .* for its distance from the origin"),
        (CUBE * 1e-12 + 1e6, None, "all its vertices are at one point"),
        (
            _with(CUBE, 7, [1.0, 1.0, 1.001]),
            CUBE_FACES,
            "face 5 is not planar",
        ),
        (CUBE, CUBE_FACES[:5], "do not close a surface"),
        (CUBE, [[0, 1, 3], [0, 3, 2], *CUBE_FACES[1:]], "faces 0 and 1 lie on one plane"),
        (CUBE, [[0, 1, 3, 2, 9], *CUBE_FACES[1:]], "face 0 names a vertex outside 0 to 7"),
        (CUBE, [[0, 1, 1], *CUBE_FACES[1:]], "face 0 names a vertex twice"),
        (DENTED_PRISM, DENTED_PRISM_FACES, "face 5 is not strictly convex .* at its corner 2"),
    ],
)
def test_bad_blocks_refused_in_one_line_naming_the_block(points, faces, why):
    with pytest.raises(ValueError, match=f"^block 12: .*{why}") as caught:
        from_vertices(np.asarray(points, dtype=float), faces, name="block 12")
    assert "\n" not in str(caught.value)


def test_non_convex_solid_with_given_faces_refused():
    """A triangular bipyramid whose lower apex is pushed up through the base (a dent): its faces close
    and are flat, but it is no convex solid."""
    points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 1.0], [0.3, 0.3, 0.2]]
    faces = [[0, 1, 3], [1, 2, 3], [2, 0, 3], [1, 0, 4], [2, 1, 4], [0, 2, 4]]
    with pytest.raises(ValueError, match=r"^dent: it is not convex"):
        from_vertices(points, faces, name="dent")
    fine = from_vertices(_with(points, 4, [0.3, 0.3, -0.5]), faces)
    assert volume(fine) == pytest.approx(0.5 * 1.5 / 3, rel=ROUNDING)


def test_box_refuses_an_inverted_corner():
    with pytest.raises(ValueError, match=r"^wall: a box needs lo < hi"):
        box([0, 0, 0], [1, -1, 1], name="wall")


def test_arrays_are_read_only():
    block = box([0, 0, 0], [1, 1, 1])
    with pytest.raises(ValueError, match="read-only"):
        block.vertices[0, 0] = 5.0
