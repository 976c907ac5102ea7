"""bbmc.slope.toppling with water in the joints (Wyllie & Mah 2004, eqs. 9.31-9.33) against a
two-block case worked by hand, and water from a phreatic line."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbmc.slope import toppling as tp

DEG = math.pi / 180.0


def test_two_blocks_with_water_by_hand():
    """Toe y_1 = 5 m, top y_2 = 20 m, Δx = 10 m, α = 30°; M_1 = 4, L_1 = 5, L_2 = 4 m; γ = 25 kN/m³,
    γ_w = 10 kN/m³, φ_p = φ_d = 35°. Water fills the joint between them: 4 m on the toe's uphill side,
    3 m on the top block's downhill side (its base is 1 m higher); the slope face and the top block's
    uphill side are dry. k = ½ γ_w cos 30° = 4.3301 kN/m³. By hand (kN/m, kN m/m):
    top block: V_3 = 9k = 38.97, V_2 = 3k·10 = 129.90, water moment −38.97·1 + k·100·3/3 = 394.04;
      weight moment 2500 (10 − 8.6603) = 3349.4; P_1,t = (3349.4 + 394.0)/4 = 935.9;
      P_1,s = [2500 − 38.97 − tan 35° (4330.1 − 129.9)]/(1 − tan² 35°) = −941.7: it topples.
    toe: W = 1250; V_1 = 16k = 69.28, V_2 = 4k·10 = 173.21; its toppling force is negative; sliding:
      P_0 = 935.9 + [625 + 69.28 − tan 35° (1082.5 − 173.21)]/(1 − tan² 35°) = 935.9 + 113.0 = 1048.9.
    Dry the same system needs 837.4 − 261.0 = 576.4. Tolerance 0.2 kN/m (the hand rounding)."""
    blocks = tp.BlockSystem(np.array([5.0, 20.0]), np.array([4.0, 0.0]), np.array([5.0, 4.0]), 10.0, 30 * DEG)
    water = tp.BlockWater(upper=[4.0, 0.0], lower=[0.0, 3.0], unit_weight=10e3)
    wet = tp.toppling_forces(blocks, 35 * DEG, 25e3, water=water)
    assert list(wet.mode) == ["slides", "topples"]
    assert wet.force_above[0] / 1e3 == pytest.approx(935.9, abs=0.2)
    assert wet.toe_force / 1e3 == pytest.approx(1048.9, abs=0.2)
    dry = tp.toppling_forces(blocks, 35 * DEG, 25e3)
    assert dry.toe_force / 1e3 == pytest.approx(576.4, abs=0.2)
    # water lowers the factor of safety
    fs_wet = float(tp.factor_of_safety(blocks, 35 * DEG, 30 * DEG, unit_weight=25e3, water=water))
    assert fs_wet < float(tp.factor_of_safety(blocks, 35 * DEG, 30 * DEG))


def test_water_from_a_phreatic_line():
    """Hoek & Bray's rounded system under a horizontal water table 20 m above the toe. The joint above
    block n rises from (nΔx cos α − (n−1)b sin α, nΔx sin α + (n−1)b cos α) normal to the bases, so the
    water stands (20 − its foot's height)/cos α up it, capped at the joint's top M_n; block n+1 sees it
    b lower; the toe's face and the top block's uphill side are dry."""
    blocks = tp.regular_system(10.0, 30 * DEG, 10, 5.0, 5.0, 1.0)
    water = tp.phreatic_water(blocks, [-100.0, 500.0], [20.0, 20.0])
    n = np.arange(1, 17)
    foot = n * 10 * math.sin(30 * DEG) + (n - 1) * 1.0 * math.cos(30 * DEG)
    expected = np.clip((20.0 - foot) / math.cos(30 * DEG), 0.0, np.maximum(blocks.upper_arm, 0.0))
    expected[-1] = 0.0
    np.testing.assert_allclose(water.upper, expected, atol=1e-9)
    assert water.lower[0] == 0.0
    np.testing.assert_allclose(water.lower[1:], np.clip(expected[:-1] - 1.0, 0.0, None), atol=1e-9)
    dry = tp.limiting_friction(blocks)
    wet = tp.limiting_friction(blocks, unit_weight=25e3, water=water)
    assert wet > dry  # water needs more friction to hold the slope
