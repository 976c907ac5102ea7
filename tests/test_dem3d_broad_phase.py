"""The 3D broad phase: grid candidate pairs against all pairs, and when to search again."""

import numpy as np

from bbmc.dem3d.broad_phase import block_boxes, candidate_pairs, needs_search


def _blocks(rng, n):
    """n random tetrahedra-like point clouds of size 0.2-1.5 m scattered in a 10 m cube (flat layout)."""
    verts = [rng.uniform(0, 10, 3) + rng.uniform(0.2, 1.5) * rng.uniform(-0.5, 0.5, (6, 3)) for _ in range(n)]
    return np.concatenate(verts), np.arange(0, 6 * n + 1, 6, dtype=np.int64)


def test_grid_pairs_are_all_pairs_whose_grown_boxes_overlap():
    """500 scattered blocks: the grid lists exactly the pairs whose boxes (grown by half the margin)
    overlap, each once, as brute force over all pairs finds them; immobile pairs are dropped."""
    rng = np.random.default_rng(3)
    verts, start = _blocks(rng, 500)
    margin = 0.1
    immobile = rng.random(500) < 0.2
    box = block_boxes(verts, start, margin)
    meet = np.all((box[:, None, :3] <= box[None, :, 3:]) & (box[None, :, :3] <= box[:, None, 3:]), axis=2)
    a, b = np.nonzero(np.triu(meet, 1) & ~(immobile[:, None] & immobile[None, :]))
    expected = set(zip(a.tolist(), b.tolist(), strict=True))
    pairs = candidate_pairs(verts, start, immobile, margin)
    found = [tuple(p) for p in pairs.tolist()]
    assert len(found) == len(set(found)) and set(found) == expected
    assert len(expected) > 100  # the scatter is dense enough for the test to mean something


def test_search_again_once_a_vertex_moved_half_the_margin():
    """A block turned about a far point moves its vertices by different amounts: no search while the
    farthest one moved less than margin / 2, a search once it moved more."""
    rng = np.random.default_rng(4)
    verts, _ = _blocks(rng, 3)
    margin = 0.02
    for angle, expected in ((0.009 / 20.0, False), (0.011 / 20.0, True)):
        moved = verts.copy()
        c, s = np.cos(angle), np.sin(angle)
        turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        pivot = np.array([verts[6:12, 0].min() - 20.0, verts[6:12, 1].mean(), 0.0])
        moved[6:12] = pivot + (verts[6:12] - pivot) @ turn.T
        reach = np.linalg.norm(moved - verts, axis=1).max()
        assert (reach > 0.5 * margin) == expected
        assert needs_search(moved, verts, margin) == expected
