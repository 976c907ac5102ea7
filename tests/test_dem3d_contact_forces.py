"""The 3D engine's sub-contact law and the geometry it integrates: shear as a vector in the plane,
Mohr-Coulomb capped along the trial direction, the same in any orientation; polygon moments; a model's
refusals."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bbmc.dem3d.contact_forces import FN, FSX
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import VPX
from bbmc.dem3d.model import build_model
from bbmc.dem3d.polygon_clip import clip_half_plane, clip_polygon, polygon_moments
from bbmc.dem3d.solver import run
from bbmc.geometry.polyhedra import box, moved

KN, KS, PHI, COHESION = 1e9, 5e8, math.atan(0.5), 1e5  # Pa/m, Pa/m, rad, Pa


def shear_history(rotation, steps=200, dt=0.01, speed=1e-3):
    """A 10 x 6 m block sunk 1 mm into a slab, both held, the block pushed along its long side at
    `speed` [m/s] (a prescribed velocity), all of it turned by `rotation`: each step's shear and normal
    force on the slab [N], and the pushing direction."""
    slab = moved(box([-20, -20, -5], [20, 20, 0]), rotation, np.zeros(3))
    block = moved(box([-5, -3, -0.001], [5, 3, 2]), rotation, np.zeros(3))
    law = MohrCoulomb(KN, KS, PHI, COHESION)
    model = build_model([slab, block], 2500.0, [law], held=[0, 1], refine=1)
    push = rotation @ np.array([speed, 0.0, 0.0])
    model.blocks[1, VPX : VPX + 3] = push
    shear, normal = [], []
    for _ in range(steps):
        run(model, 1, dt)
        shear.append(model.contact_values[0, FSX : FSX + 3].copy())
        normal.append(model.contact_values[0, FN])
    return np.array(shear), np.array(normal), push / speed


@pytest.mark.parametrize("turn", [None, (33.0, -71.0, 117.0)])
def test_shear_in_one_direction_follows_the_mohr_coulomb_law_exactly(turn):
    """Pushed in one direction, the shear force is K_s A u until it reaches c A + N tan(phi), then stays
    there, along the push (on the slab, which the block drags), to 1e-9; N = K_n A 1 mm. The same to
    1e-9 with the whole scene turned by Euler angles (33, -71, 117) deg: no axis is favoured. The limit
    is reached at u = 1.2 mm, in step 120."""
    rotation = np.eye(3) if turn is None else Rotation.from_euler("zxz", turn, degrees=True).as_matrix()
    shear, normal, direction = shear_history(rotation)
    area = 60.0
    n_expected = KN * area * 1e-3
    assert normal == pytest.approx(n_expected, rel=1e-9)
    u = 1e-5 * np.arange(len(shear))  # the push's first half step has v = 0
    expected = np.minimum(KS * area * u, COHESION * area + n_expected * math.tan(PHI))
    magnitude = np.linalg.norm(shear, axis=1)
    assert magnitude == pytest.approx(expected, rel=1e-9)
    assert np.allclose(shear[1:] / magnitude[1:, None], direction, atol=1e-9)
    assert magnitude[119] < magnitude[-1] == pytest.approx(magnitude[121], rel=1e-12)


def test_polygon_moments_of_a_rectangle_and_a_triangle():
    """A 4 x 2 rectangle at (1, 1): A 8, centroid (3, 2), second moments b^3 h / 12 = 32/3 and
    b h^3 / 12 = 8/3, product 0. The right triangle (0,0), (3,0), (0,6): A 9, centroid (1, 2), about
    it b^3 h / 36 = 4.5, b h^3 / 36 = 18 and the product -b^2 h^2 / 72 = -4.5. Exact to 1e-12."""
    rect = np.array([[1.0, 1.0], [5.0, 1.0], [5.0, 3.0], [1.0, 3.0]])
    assert polygon_moments(rect) == pytest.approx((8.0, 3.0, 2.0, 32.0 / 3.0, 0.0, 8.0 / 3.0), abs=1e-12)
    tri = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 6.0]])
    assert polygon_moments(tri) == pytest.approx((9.0, 1.0, 2.0, 4.5, -4.5, 18.0), abs=1e-12)


def test_half_plane_clipping_keeps_the_side_asked_for():
    """The unit square cut by s + t - 1 >= 0 keeps the triangle above the diagonal (area 1/2); a
    plane that misses it keeps all or nothing."""
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    assert polygon_moments(clip_half_plane(square, 1.0, 1.0, -1.0))[0] == pytest.approx(0.5)
    assert polygon_moments(clip_half_plane(square, 1.0, 0.0, 2.0))[0] == pytest.approx(1.0)
    assert clip_half_plane(square, 1.0, 0.0, -2.0).shape[0] == 0


def test_clipping_by_a_polygon_with_two_near_copies_of_a_vertex_keeps_the_overlap():
    """A clip square whose corner (1, 1) comes twice, 1e-15 m apart along (1, -1), as clipping two
    faces whose edges coincide leaves it (a plane-strain twin's prisms, all from y = 0 to the depth):
    the subject square half over it keeps the overlap, area 1/2 (exact to 1e-12). The 1e-15 edge's
    own half-plane would cut the whole subject away (its direction is round-off), which opened a twin's
    column-to-column contact for a step and dropped its shear."""
    d = 1e-15
    clip = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0 + d, 1.0 - d], [0.0, 1.0]])
    subject = np.array([[0.5, 0.0], [1.5, 0.0], [1.5, 1.0], [0.5, 1.0]])
    assert polygon_moments(clip_polygon(subject, clip))[:3] == pytest.approx((0.5, 0.75, 0.5), abs=1e-12)


def test_a_model_refuses_bad_input_in_one_line():
    """A non-positive density names its block, a held index out of range names it, a bad law names
    its joint type, a negative refinement is refused, and so are two blocks that overlap at the start
    (here by 0.2 m; a block sunk by its settled closure, a few mm, is let through)."""
    blocks = [box([0, 0, 0], [1, 1, 1]), box([0, 0, 1], [1, 1, 2])]
    law = MohrCoulomb(KN, KS, PHI)
    with pytest.raises(ValueError, match=r"^block 1: density"):
        build_model(blocks, [2500.0, 0.0], [law])
    with pytest.raises(ValueError, match=r"^held: block 5"):
        build_model(blocks, 2500.0, [law], held=[5])
    with pytest.raises(ValueError, match=r"^joint type 0: after_slip"):
        build_model(blocks, 2500.0, [MohrCoulomb(KN, KS, PHI, after_slip="drop")])
    with pytest.raises(ValueError, match=r"^refine"):
        build_model(blocks, 2500.0, [law], refine=-1)
    overlapping = [blocks[0], box([0.5, 0.5, 0.8], [1.5, 1.5, 1.8])]
    with pytest.raises(ValueError, match=r"^blocks 0 and 1: they overlap by 0.2 m at the start$"):
        build_model(overlapping, 2500.0, [law])
