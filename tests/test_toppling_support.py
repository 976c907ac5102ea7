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
