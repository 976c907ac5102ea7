"""bbmc.slope.toppling's factor of safety: one answer, the least factor on friction at which the block
system fails, on the quarry face of issue 33 and over random regular systems (hypothesis).

The quarry face: 30 m of slate at 70°, blocks 1.5 m wide on bases dipping α = 20° (toppling joints
dipping 70°), the overall base at ψ_b = 25°, a horizontal upper slope: 48 blocks, crest on block 14,
height/width up to 15.5. (These are the angles that give the issue's 48 blocks and its FS 0.624 at 30°
on the old code; the issue's words "foliation 75°" would give α = 15° and 62 blocks.) Unit weight
26.5 kN/m³ (2,700 kg/m³ × g). On the old code (e4ef629): P_0 +∞ at 40-42.5°, −135 kN/m at 42.76°, +∞ at
43°, −1.77e17 kN/m at 45°; FS(30°) 0.624 but FS(30°, sides 30°) 0.609; FS(32°, 30°) 0.650 though it
failed at F = 0.624 and held at 0.63.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.slope import toppling as tp

DEG = math.pi / 180.0
GAMMA = 26.5e3


@pytest.fixture(scope="module")
def quarry() -> tp.BlockSystem:
    return tp.slope_blocks(30.0, 70 * DEG, 0.0, 70 * DEG, 1.5, 25 * DEG)


def test_the_quarry_system(quarry):
    assert quarry.n_blocks == 48 and quarry.crest_block == 14
    assert quarry.heights.max() / quarry.width == pytest.approx(15.46, abs=0.01)


def test_failure_has_one_transition_in_friction(quarry):
    """fails(φ) over 20°-80° in 0.01° steps changes once: fails below φ_limit, holds above (the old
    march flipped between +∞ and finite P_0 four times between 40° and 45°)."""
    phi = np.radians(np.arange(20.0, 80.0, 0.01))
    failing = tp.fails(tp.march.Loads(quarry, 1.0), np.tan(phi), np.tan(phi))
    assert np.count_nonzero(np.diff(failing.astype(int))) == 1
    limit = tp.limiting_friction(quarry)
    assert np.all(failing == (phi < limit))


def test_one_friction_angle_once_or_twice_gives_one_fs(quarry):
    """FS(30°) and FS(30°, sides 30°) are the same number (old: 0.624 and 0.609): tan 30°/tan φ_limit."""
    once = float(tp.factor_of_safety(quarry, 30 * DEG))
    twice = float(tp.factor_of_safety(quarry, 30 * DEG, 30 * DEG))
    assert (
        once == twice == pytest.approx(math.tan(30 * DEG) / math.tan(tp.limiting_friction(quarry)), rel=1e-14)
    )


def test_fs_is_where_failure_starts(quarry):
    """Bases 32°, sides 30°: the system holds at 0.9999 FS and fails at 1.0001 FS, and at every factor
    above on a grid (old: FS 0.650 while failing at 0.624)."""
    fs = float(tp.factor_of_safety(quarry, 32 * DEG, 30 * DEG))
    loads = tp.march.Loads(quarry, 1.0)
    tb, td = math.tan(32 * DEG), math.tan(30 * DEG)
    assert not tp.fails(loads, tb / (0.9999 * fs), td / (0.9999 * fs))
    factors = fs * np.linspace(1.0001, 3.0, 500)
    assert np.all(tp.fails(loads, tb / factors, td / factors))
    # the side friction governs here: FS(32°, 30°) = FS(30°) to the bisection's 1e-13
    assert fs >= float(tp.factor_of_safety(quarry, 30 * DEG)) * (1 - 1e-12)


def test_fs_rises_with_base_friction_in_a_sweep(quarry):
    """A sweep's samples, bases ~ N(32°, 2°) and sides ~ N(30°, 2°) (seed 3, 300 samples), each
    again with 0.01° more base friction: the FS never falls (old: it fell in 3 of the 300, e.g. 0.629
    to 0.623 at 30.897°/30.278°; the issue's sweep had 31.939° → 0.675, 31.944° → 0.658)."""
    rng = np.random.default_rng(3)
    base, side = np.radians(rng.normal(32, 2, 300)), np.radians(rng.normal(30, 2, 300))
    before = tp.factor_of_safety(quarry, base, side)
    after = tp.factor_of_safety(quarry, base + 0.01 * DEG, side)
    assert np.all(after >= before * (1 - 1e-12))


def test_locked_sliding_is_minus_infinity_not_a_huge_number():
    """A squat block at φ_p = φ_d = 45°: 1 − tan² 45° is 1.1e-16 in floating point, and the sliding
    equation gave −1.77e17 kN/m on the quarry's toe; within 1e-12 of zero sliding is locked: −∞."""
    y = np.array([2.0])
    block = tp.BlockSystem(y, y.copy(), y.copy(), 10.0, 20 * DEG)
    assert tp.toppling_forces(block, 45 * DEG, GAMMA).p_slide[0] == -math.inf


def test_support_on_the_quarry_toe_moves_fs_one_way(quarry):
    """A horizontal support on the toe block, at 0, 0.5 and 1.0 of its height: FS (bases 32°, sides
    30°) non-decreasing over 0-5 MN/m and never an error (old: 0.650, 0.633, 0.650, or "P_0 does not
    change sign")."""
    for share in (0.0, 0.5, 1.0):
        fs = [
            float(
                tp.factor_of_safety(
                    quarry,
                    32 * DEG,
                    30 * DEG,
                    tp.BlockSupport.on_block(quarry, 1, force, 20 * DEG, share * quarry.heights[0]),
                    GAMMA,
                )
            )
            for force in np.linspace(0.0, 5e6, 21)
        ]
        assert np.all(np.diff(fs) >= 0.0), share


def _system(draw: st.DrawFn) -> tp.BlockSystem:
    alpha = draw(st.floats(10.0, 40.0))
    return tp.slope_blocks(
        draw(st.floats(8.0, 60.0)),
        min(alpha + draw(st.floats(20.0, 60.0)), 85.0) * DEG,
        draw(st.floats(-10.0, alpha - 1.0)) * DEG,
        (90.0 - alpha) * DEG,
        draw(st.floats(1.0, 10.0)),
        (alpha + draw(st.floats(0.0, 10.0))) * DEG,
    )


systems = st.composite(_system)()
angles = st.floats(12.0, 60.0)


@settings(max_examples=25, deadline=None)
@given(systems, angles, angles, st.floats(0.01, 5.0))
def test_fs_does_not_fall_as_base_or_side_friction_rises(blocks, base, side, step):
    fs = float(tp.factor_of_safety(blocks, base * DEG, side * DEG))
    assert float(tp.factor_of_safety(blocks, (base + step) * DEG, side * DEG)) >= fs * (1 - 1e-12)
    assert float(tp.factor_of_safety(blocks, base * DEG, (side + step) * DEG)) >= fs * (1 - 1e-12)


@settings(max_examples=20, deadline=None)
@given(systems, angles, angles, st.floats(0.0, 1.0), st.floats(0.0, 30.0))
def test_fs_does_not_fall_as_toe_support_rises(blocks, base, side, share, plunge):
    """A support on the toe block's face, plunging 0-30° into the slope; forces 0-4 × the toe's weight."""
    w = GAMMA * blocks.heights[0] * blocks.width
    fs = [
        float(
            tp.factor_of_safety(
                blocks,
                base * DEG,
                side * DEG,
                tp.BlockSupport.on_block(
                    blocks, 1, t * w, blocks.base_dip + plunge * DEG, share * blocks.heights[0]
                ),
                GAMMA,
            )
        )
        for t in np.linspace(0.0, 4.0, 9)
    ]
    fs = np.array(fs)  # +inf where the support holds the system without friction
    assert np.all(fs[1:] >= fs[:-1] * (1 - 1e-12))


@settings(max_examples=20, deadline=None)
@given(systems, st.floats(12.0, 70.0))
def test_one_angle_is_the_tangent_ratio_and_fails_at_it(blocks, phi):
    """FS = tan φ / tan φ_limit, and the two-angle search with sides = bases finds the same factor."""
    try:
        limit = tp.limiting_friction(blocks)
    except ValueError:
        return  # fails at every angle (a toe block that topples alone): FS 0 below
    fs = float(tp.factor_of_safety(blocks, phi * DEG))
    assert fs == pytest.approx(math.tan(phi * DEG) / math.tan(limit), rel=1e-12)
    nudged = float(tp.factor_of_safety(blocks, phi * DEG, phi * DEG * (1 + 1e-15)))
    assert nudged == pytest.approx(fs, rel=1e-9)


def test_fs_against_toe_support_has_no_jump(quarry):
    """The issue's case: bases 32°, sides 30°, a horizontal support at half the toe block's height.
    Old: FS 1.405 at 3.40 MN/m and 1.593 at 3.45 MN/m (a 13 % jump for 1.5 % more force), and at the
    toe's base (h = 0) 0.650, 0.633, 0.633, 0.650 for 0, 0.3, 1 and 2 MN/m. Now FS moves by less than
    1 % between 3.40 and 3.45 MN/m, and a support at the pivot's level (no arm against toppling) leaves
    the FS where it is: the toe block topples and only an arm holds it."""

    def fs(force: float, height: float) -> float:
        support = tp.BlockSupport.on_block(quarry, 1, force, 20 * DEG, height)
        return float(tp.factor_of_safety(quarry, 32 * DEG, 30 * DEG, support, GAMMA))

    half = 0.5 * quarry.heights[0]
    assert fs(3.45e6, half) / fs(3.40e6, half) == pytest.approx(1.0, abs=0.01)
    assert fs(3.45e6, half) > fs(3.40e6, half)
    at_pivot = [fs(force, 0.0) for force in (0.0, 3e5, 1e6, 2e6)]
    assert at_pivot == pytest.approx([at_pivot[0]] * 4, rel=1e-12)


def test_a_support_that_holds_the_system_without_friction_gives_fs_infinity_with_one_angle():
    """Found by the property test on a clean clone: with one friction angle, FS went through
    `limiting_friction`, which refuses a system that holds at 0.1 deg; now the general search answers,
    +inf as the module defines it (the support holds it without friction)."""
    blocks = tp.regular_system(10.0, math.radians(30.0), 10, 5.0, 5.0, 1.0)
    support = tp.face_support(blocks, 2.0, 1e12, 0.0)
    assert np.isinf(tp.factor_of_safety(blocks, math.radians(30.0), support=support, unit_weight=25e3))
