"""bbmc.slope.toppling with support forces on chosen blocks, against the unsupported march and a
closed form derived by hand for a two-block system."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbmc.slope import toppling as tp

DEG = math.pi / 180.0
GAMMA = 25e3
EXAMPLE = tp.regular_system(width=10.0, base_dip=30 * DEG, crest_block=10, a1=5.0, a2=5.0, b=1.0)


def test_zero_support_gives_the_unsupported_results_exactly():
    """Toe forces and the one-angle FS bit for bit; the two-angle FS's root search runs at the given
    unit weight instead of 1, which moves its root by rounding only (1e-14)."""
    none = tp.BlockSupport.on_block(EXAMPLE, 1, 0.0, 0.7, 1.0)
    friction = np.radians([36.0, 38.0, 40.0])
    plain = tp.toe_force(EXAMPLE, friction, GAMMA)
    assert np.array_equal(tp.toe_force(EXAMPLE, friction, GAMMA, support=none), plain)
    assert np.array_equal(
        tp.factor_of_safety(EXAMPLE, friction, support=none, unit_weight=GAMMA),
        tp.factor_of_safety(EXAMPLE, friction),
    )
    assert float(tp.factor_of_safety(EXAMPLE, 38 * DEG, 30 * DEG, none, GAMMA)) == pytest.approx(
        float(tp.factor_of_safety(EXAMPLE, 38 * DEG, 30 * DEG)), rel=1e-14
    )


def test_a_horizontal_support_on_the_toe_block_raises_the_factor_of_safety():
    """A horizontal force into the slope is at theta = alpha from the base's up-dip direction; FS grows
    with it, and the supported FS is a root of the supported toe force."""
    supports = [tp.BlockSupport.on_block(EXAMPLE, 1, t, 30 * DEG, 0.5) for t in (0.0, 200e3, 1000e3)]
    fs = [float(tp.factor_of_safety(EXAMPLE, 38 * DEG, support=s, unit_weight=GAMMA)) for s in supports]
    assert fs[0] < fs[1] < fs[2]
    support = tp.BlockSupport.on_block(EXAMPLE, 1, 1000e3, 30 * DEG, 0.5)
    limit = math.atan(math.tan(38 * DEG) / fs[2])
    assert abs(float(tp.toe_force(EXAMPLE, limit, GAMMA, support=support))) < 1e-6 * GAMMA


def _two_blocks() -> tp.BlockSystem:
    """Toe block y_1 = 5 m, top block y_2 = 20 m, width 10 m, bases at 30 deg; they touch at 4 m
    (M_1 = L_2 = 4 m), the toe's downhill face is whole (L_1 = 5 m)."""
    return tp.BlockSystem(np.array([5.0, 20.0]), np.array([4.0, 0.0]), np.array([5.0, 4.0]), 10.0, 30 * DEG)


def test_a_support_on_the_toe_of_two_blocks_against_the_closed_form():
    """No side friction (phi_d = 0). Top block: P_2 = 0 and it topples, so
    P_1 = (W_2/2)(y_2 sin a - dx cos a) / L_2 = gamma 200/2 (10 - 8.660) / 4 = 33.49 gamma [N/m]
    (friction-free). Toe block, toppling moment P_1 M_1 + (W_1/2)(y_1 sin a - dx cos a) - T_s h =
    gamma (133.97 - 153.98) - T_s h < 0: it cannot topple and slides, P_0 = P_1 - [W_1 (tan phi cos a -
    sin a) + T_s + T_n tan phi]. P_0 = 0 at tan phi / FS, so
        FS = tan phi (W_1 cos a + T_n) / (P_1 + W_1 sin a - T_s)
    with W_1 = 50 gamma, T_s = T cos theta, T_n = T sin theta. With T = 300 kN/m at 20 deg, h = 2.5 m,
    gamma = 25 kN/m^3, phi = 60 deg: FS = 1.732 (1082.5 + 102.6) / (837.2 + 625 - 281.9) = 1.739
    (unsupported: 1.732 x 1082.5 / 1462.2 = 1.282). Agreement to 1e-9."""
    blocks = _two_blocks()
    a, t, theta = 30 * DEG, 300e3, 20 * DEG
    support = tp.BlockSupport.on_block(blocks, 1, t, theta, 2.5)
    w1 = GAMMA * 50.0
    p1 = 0.5 * GAMMA * 200.0 * (20 * math.sin(a) - 10 * math.cos(a)) / 4.0
    tan_phi = math.tan(60 * DEG)

    def closed(ts: float, tn: float) -> float:
        return tan_phi * (w1 * math.cos(a) + tn) / (p1 + w1 * math.sin(a) - ts)

    expected = closed(t * math.cos(theta), t * math.sin(theta))
    assert expected == pytest.approx(1.739, abs=5e-4)
    assert closed(0.0, 0.0) == pytest.approx(1.282, abs=5e-4)
    fs = float(tp.factor_of_safety(blocks, 60 * DEG, 0.0, support, GAMMA))
    assert fs == pytest.approx(expected, rel=1e-9)
    unsupported = float(tp.factor_of_safety(blocks, 60 * DEG, 0.0))
    assert unsupported == pytest.approx(closed(0.0, 0.0), rel=1e-9)
    table = tp.toppling_forces(blocks, math.atan(tan_phi / fs), GAMMA, 0.0, support)
    assert list(table.mode) == ["slides", "topples"]
    assert table.force_above[0] == pytest.approx(p1, rel=1e-12)


def test_arrays_of_friction_with_a_support_equal_scalar_calls():
    support = tp.BlockSupport.on_block(EXAMPLE, 1, 500e3, 30 * DEG, 1.0)
    friction = np.radians([36.0, 38.0, 40.0])
    side = np.radians([30.0, 32.0, 34.0])
    many = tp.factor_of_safety(EXAMPLE, friction, side, support, GAMMA)
    for k in range(3):
        assert many[k] == float(tp.factor_of_safety(EXAMPLE, friction[k], side[k], support, GAMMA))


def test_meaningless_support_is_refused():
    with pytest.raises(ValueError, match="must be >= 0"):
        tp.BlockSupport.on_block(EXAMPLE, 1, -1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="not one of the system"):
        tp.BlockSupport.on_block(EXAMPLE, 99, 1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="on the block's face"):
        tp.toe_force(EXAMPLE, 0.6, GAMMA, support=tp.BlockSupport.on_block(EXAMPLE, 1, 1.0, 0.0, 99.0))
    with pytest.raises(ValueError, match="needs its unit weight"):
        tp.factor_of_safety(EXAMPLE, 0.6, support=tp.BlockSupport.on_block(EXAMPLE, 1, 1.0, 0.0, 0.0))


def _toppling_toe() -> tp.BlockSystem:
    """Two blocks 2 m wide on bases at 30°, steps b = 0.5 m: the toe y_1 = 6 m (L_1 = −b: its lower
    force would act below its pivot), the top block y_2 = 8 m; they touch at M_1 = 6 m, L_2 = 5.5 m."""
    return tp.BlockSystem(np.array([6.0, 8.0]), np.array([6.0, 0.0]), np.array([-0.5, 5.5]), 2.0, 30 * DEG)


def test_a_horizontal_support_holds_a_toppling_toe_block_by_hand():
    """φ_p = φ_d = 35°, γ = 25 kN/m³. By hand (kN/m, kN m/m):
    top block: W_2 = 25·8·2 = 400; toppling moment (W_2/2)(8 sin 30° − 2 cos 30°) = 200·2.2679 = 453.6,
      P_1,t = 453.6/5.5 = 82.47; P_1,s = −400 (tan 35° cos 30° − sin 30°)/(1 − tan² 35°) = −83.5: it
      topples and pushes the toe with P_1 = 82.47.
    toe: W_1 = 300; moment P_1 (M_1 − Δx tan 35°) + (W_1/2)(6 sin 30° − 2 cos 30°)
      = 82.47·4.5996 + 150·1.2679 = 379.3 + 190.2 = 569.5 > 0: it topples, and no force at L_1 = −0.5 m
      can hold it (the old code refused: "needs its point of application").
    A horizontal force T at h = 3 m (half the toe's height) has T_s = T cos 30° with the arm h:
      T = 569.5/(cos 30°·3) = 219.2. Sliding asks less: P_0,s = 82.47 + 300 (sin 30° − tan 35° cos 30°)/
      (1 − tan² 35°) = 19.85, T (cos 30° + tan 35° sin 30°) ≥ (1 − tan² 35°)·19.85 → T ≥ 8.32.
    The system holds with 1.001 T and fails with 0.999 T. Tolerance 0.05 kN/m (the hand rounding)."""
    blocks, phi = _toppling_toe(), 35 * DEG
    t = tp.horizontal_toe_support(blocks, phi, 25e3, height=3.0)
    assert t / 1e3 == pytest.approx(219.2, abs=0.05)
    assert float(tp.toe_force(blocks, phi, 25e3)) == math.inf  # unsupported: not held
    for factor, holds in ((1.001, True), (0.999, False)):
        support = tp.BlockSupport.on_block(blocks, 1, factor * t, 30 * DEG, 3.0)
        assert (float(tp.toe_force(blocks, phi, 25e3, support=support)) <= 0.0) == holds
    # at its top the same moment needs half the force
    assert tp.horizontal_toe_support(blocks, phi, 25e3, height=6.0) == pytest.approx(t / 2, rel=1e-12)


def test_a_support_placed_by_its_level_on_the_face():
    """Hoek & Bray's rounded system: block n's exposed face spans max(L_n, 0) to y_n above its base;
    the toe's foot is the toe. A level of 2 m is on the toe block's face, 2/cos 30° = 2.309 m up it; a
    level just above the toe's top (4 cos 30° = 3.464 m) is on its top, 0.1/sin 30° = 0.2 m in."""
    face = tp.face_support(EXAMPLE, 2.0, 1e5, 0.0)
    assert face.force[0] == 1e5 and face.height[0] == pytest.approx(2.0 / math.cos(30 * DEG), rel=1e-12)
    assert face.angle[0] == pytest.approx(30 * DEG, rel=1e-12)  # horizontal: θ = α
    top = tp.face_support(EXAMPLE, 4 * math.cos(30 * DEG) + 0.1, 1e5, 10 * DEG)
    assert top.height[0] == 4.0 and top.offset[0] == pytest.approx(0.2, rel=1e-9)
    assert top.angle[0] == pytest.approx(40 * DEG, rel=1e-12)
