"""Convex polyhedra cut by planes and by persistent joint sets (bbmc.geometry.polyhedron_cutting)."""

import numpy as np
import pytest

from bbmc.geometry.polyhedra import UNTAGGED, box, from_vertices, polyhedron_fault
from bbmc.geometry.polyhedron_cutting import cut, cut_by_joint_sets, set_normal
from bbmc.geometry.polyhedron_mass import mass_properties, volume

# Volumes and centroids are sums of a few dozen products of numbers of order 1-10: rounding only.
ROUNDING = 1e-12


def test_box_cut_by_one_plane_keeps_volume_and_centroid():
    """Two convex pieces whose volumes sum to the box's and whose volume-weighted centroids give the
    box's; each piece a valid polyhedron with the section tagged as asked."""
    block = box([0, 0, 0], [4, 3, 2])
    below, above = cut(block, np.array([1.0, 2.0, 3.0]), 7.0, tag=5)
    parts = [mass_properties(below), mass_properties(above)]
    assert parts[0].volume + parts[1].volume == pytest.approx(24.0, rel=ROUNDING)
    combined = (parts[0].volume * parts[0].centroid + parts[1].volume * parts[1].centroid) / 24.0
    np.testing.assert_allclose(combined, [2.0, 1.5, 1.0], atol=ROUNDING * 10)
    for piece, sense in ((below, 1.0), (above, -1.0)):
        assert polyhedron_fault(piece) is None
        section = np.flatnonzero(piece.face_tags == 5)
        assert len(section) == 1
        np.testing.assert_allclose(piece.normals[section[0]], sense * np.array([1, 2, 3]) / np.sqrt(14))
        assert np.sum(piece.face_tags == UNTAGGED) == piece.face_count - 1
    assert np.all(below.vertices @ [1, 2, 3] <= 7.0 + 1e-12)
    assert np.all(above.vertices @ [1, 2, 3] >= 7.0 - 1e-12)


def test_cut_of_a_random_hull_keeps_inertia_about_the_origin():
    """The second moments about a common point add up: sum over pieces of (I_c + m (|c|^2 1 - c c^T))
    is the whole block's, to rounding."""
    rng = np.random.default_rng(3)
    block = from_vertices(_hull_points(rng))
    whole = _about_origin(mass_properties(block, 2.0))
    below, above = cut(block, rng.normal(size=3), 0.1)
    total = _about_origin(mass_properties(below, 2.0)) + _about_origin(mass_properties(above, 2.0))
    np.testing.assert_allclose(total, whole, atol=1e-12 * np.abs(whole).max())


def _about_origin(props):
    c = props.centroid
    return props.inertia + props.mass * (c @ c * np.eye(3) - np.outer(c, c))


def _hull_points(rng):
    from scipy.spatial import ConvexHull

    points = rng.normal(size=(30, 3))
    return points[ConvexHull(points).vertices]


@pytest.mark.parametrize(
    ("offset", "expected"),
    [(5.0, "below"), (-1.0, "above"), (1.0, "below"), (0.0, "above")],
)
def test_a_plane_that_misses_or_grazes_leaves_the_block_whole(offset, expected):
    """Planes beyond the unit cube (x = 5, x = -1) or on its faces (x = 1, x = 0) cut nothing: the
    block comes back unchanged on its side, None on the other."""
    block = box([0, 0, 0], [1, 1, 1])
    below, above = cut(block, np.array([1.0, 0.0, 0.0]), offset)
    assert (below if expected == "below" else above) is block
    assert (above if expected == "below" else below) is None


def test_a_plane_through_an_edge_and_a_corner_cuts_cleanly():
    """The diagonal plane x = y through the cube's edge (0, 0, z) and corner edge (1, 1, z): two
    triangular prisms of half the volume, no vertex doubled."""
    below, above = cut(box([0, 0, 0], [1, 1, 1]), np.array([1.0, -1.0, 0.0]), 0.0)
    for piece in (below, above):
        assert polyhedron_fault(piece) is None
        assert len(piece.vertices) == 6
        assert piece.face_count == 5
        assert volume(piece) == pytest.approx(0.5, rel=ROUNDING)


def test_cut_refuses_a_zero_normal():
    with pytest.raises(ValueError, match="non-zero normal"):
        cut(box([0, 0, 0], [1, 1, 1]), np.zeros(3), 0.0)


def test_set_normal_is_bbmc_orientation_convention():
    """x east, y north, z up: a vertical set dipping east has normal +x, one dipping north +y, a
    horizontal one +z; 45/135 is (1/2, -1/2, 1/sqrt 2)."""
    np.testing.assert_allclose(set_normal(90, 90), [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(set_normal(90, 0), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(set_normal(0, 0), [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(set_normal(45, 135), [0.5, -0.5, np.sqrt(0.5)], atol=1e-15)


ORTHOGONAL = [(90.0, 90.0, 1.0, [0, 0, 0]), (90.0, 0.0, 1.0, [0, 0, 0]), (0.0, 0.0, 1.0, [0, 0, 0])]


def test_cube_cut_by_three_orthogonal_sets_gives_n_cubed_unit_cubes():
    """A 3 m cube by three orthogonal sets of spacing 1 through the origin: 27 unit cubes (the planes on
    the cube's faces cut nothing), 2 + 6 + 18 cuts, each cube's faces tagged by the sets that made
    them."""
    result = cut_by_joint_sets(box([0, 0, 0], [3, 3, 3]), ORTHOGONAL)
    assert len(result.blocks) == 27
    assert result.cuts_per_set.tolist() == [2, 6, 18]
    assert result.skipped == []
    corners = set()
    for block in result.blocks:
        assert polyhedron_fault(block) is None
        assert volume(block) == pytest.approx(1.0, rel=ROUNDING)
        lo = block.vertices.min(axis=0)
        np.testing.assert_allclose(block.vertices.max(axis=0) - lo, 1.0, rtol=ROUNDING)
        corners.add(tuple(np.round(lo).astype(int)))
        for f in range(block.face_count):
            axis = int(np.argmax(np.abs(block.normals[f])))
            on_box = abs(block.offsets[f]) < 1e-12 or abs(abs(block.offsets[f]) - 3.0) < 1e-12
            assert block.face_tags[f] == (UNTAGGED if on_box else axis)
    assert len(corners) == 27


def test_oblique_sets_tile_the_block():
    """Three oblique sets cut a 10 m box into valid convex blocks whose volumes sum to the box's
    (rounding over some 190 blocks: 1e-12 relative), each joint face on a plane n . x = n . o + k s."""
    sets = [(60.0, 30.0, 1.1, [0.3, 0.0, 0.0]), (70.0, 200.0, 1.7, [0, 0, 0]), (15.0, 100.0, 2.3, [0, 0, 1])]
    result = cut_by_joint_sets(box([0, 0, 0], [10, 10, 10]), sets)
    assert len(result.blocks) == 1 + result.cuts_per_set.sum()  # each cut adds one block
    assert sum(volume(b) for b in result.blocks) == pytest.approx(1000.0, rel=1e-12)
    for block in result.blocks:
        assert polyhedron_fault(block) is None
        for f in np.flatnonzero(block.face_tags >= 0):
            dip, direction, spacing, origin = sets[block.face_tags[f]]
            normal = set_normal(dip, direction)
            sense = np.sign(block.normals[f] @ normal)
            np.testing.assert_allclose(block.normals[f], sense * normal, atol=1e-12)
            k = (sense * block.offsets[f] - normal @ origin) / spacing
            assert k == pytest.approx(round(k), abs=1e-9)


def test_a_set_that_cuts_nothing_is_counted_and_leaves_the_block():
    """A set whose planes all miss the block (planes x = 0.5 + 10 k; the box spans x = 1 to 1.6) makes
    no cut: the block comes back unchanged and the set's count is 0, which is how a config layer knows
    to refuse it."""
    block = box([1, 0, 0], [1.6, 1, 1])
    result = cut_by_joint_sets(block, [(90.0, 90.0, 10.0, [0.5, 0, 0]), (0.0, 0.0, 0.5, [0, 0, 0])])
    assert result.cuts_per_set.tolist() == [0, 1]
    alone = cut_by_joint_sets(block, [(90.0, 90.0, 10.0, [0.5, 0, 0])])
    assert alone.blocks == [block]
    assert alone.cuts_per_set.tolist() == [0]


def test_slivers_are_not_cut_off_as_in_the_2d_generator():
    """Planes x = 0.01 + k on a 3 m cube: without the rule 4 blocks, one a 0.09 m^3 sliver; with
    min_block_fraction 0.1 (of the first pass's median, 8.955 m^3) the cut at k = 0 is not made and is
    reported, the sliver left on its neighbour: 3 blocks that still tile the cube."""
    block = box([0, 0, 0], [3, 3, 3])
    sets = [(90.0, 90.0, 1.0, [0.01, 0, 0])]
    assert len(cut_by_joint_sets(block, sets).blocks) == 4
    result = cut_by_joint_sets(block, sets, min_block_fraction=0.1)
    assert len(result.blocks) == 3
    assert result.smallest_volume == pytest.approx(0.8955, rel=ROUNDING)
    assert [(s, k) for s, k, _ in result.skipped] == [(0, 0)]
    assert result.skipped[0][2] == pytest.approx(0.09, rel=1e-9)
    assert result.cuts_per_set.tolist() == [2]
    assert sorted(volume(b) for b in result.blocks) == pytest.approx([8.91, 9.0, 9.09], rel=1e-9)


@pytest.mark.parametrize(
    ("sets", "why"),
    [
        ([(90.0, 90.0, 0.0, [0, 0, 0])], "^joint set 0: spacing_m must be > 0"),
        ([ORTHOGONAL[0], (95.0, 0.0, 1.0, [0, 0, 0])], r"^joint set 1: dip_deg must be in \[0, 90\]"),
        ([(45.0, 0.0, 1.0, [0, 0])], "^joint set 0: origin_m must be three finite numbers"),
        ([(45.0, np.nan, 1.0, [0, 0, 0])], "^joint set 0: dip_direction_deg"),
        ([(90.0, 90.0, 1e-3, [0, 0, 0])] * 3, "more than 1,000,000"),
    ],
)
def test_bad_sets_refused_naming_the_set(sets, why):
    with pytest.raises(ValueError, match=why):
        cut_by_joint_sets(box([0, 0, 0], [3, 3, 3]), sets)
