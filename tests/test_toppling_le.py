"""bbmc.slope.toppling: Goodman & Bray's block toppling on a stepped base against the worked example of
Hoek & Bray (1981, ch. 10) / Wyllie & Mah (2004, ch. 9), against two independent recomputations of it,
and against closed forms derived by hand.

The worked example: 16 blocks, Δx = 10 m, block bases at α = 30°, overall base ψ_b = 35.8°, face
ψ_f = 56.6°, upper slope ψ_s = 4°, H = 92.5 m, γ = 25 kN/m³, one friction angle on bases and sides;
limiting equilibrium at φ = 38.15°, blocks 1-3 slide, 4-13 topple, 14-16 stand.

Two geometries of it are used:
* EXACT: a1, a2, b from their formulas (a1 = 5.008, a2 = 4.877, b = 1.016 m; heights 3.99 ... 39.92 m);
* ROUNDED: a1 = a2 = 5 m, b = 1 m (heights 4, 8, ..., 40, 34, ..., 4 m), the "sixteen rock columns,
  10 m wide and 4 to 40 m tall" of Rocscience's RS2 joint verification problem 1 as transcribed in a
  third-party verification page ("Rocscience RS2 Joint Corpus" of the XSLOPE documentation, found by
  the code search; its repository was not shown).

Forces in the module are N/m; published values are kN/m, hence the 1e3 factors. Every tolerance is
stated where it is used.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbmc.slope import toppling as tp

DEG = math.pi / 180.0
GAMMA = 25e3  # N/m^3
DX = 10.0  # m
ALPHA = 30.0 * DEG
PSI_B = 35.8 * DEG
PSI_F = 56.6 * DEG
PSI_S = 4.0 * DEG
H = 92.5  # m
PHI_PUBLISHED = 38.15  # deg

SLIDES = list(range(1, 4))
TOPPLES = list(range(4, 14))
STABLE = list(range(14, 17))


@pytest.fixture(scope="module")
def exact() -> tp.BlockSystem:
    crest = tp.crest_block_number(H, DX, ALPHA, PSI_F)
    return tp.regular_block_heights(None, DX, ALPHA, PSI_B, PSI_F, PSI_S, crest)


@pytest.fixture(scope="module")
def rounded() -> tp.BlockSystem:
    return tp.regular_system(DX, ALPHA, 10, 5.0, 5.0, 1.0)


def single_block(height: float, width: float = DX, alpha: float = ALPHA) -> tp.BlockSystem:
    """One block whose lower neighbour is as tall as itself (M = L = y)."""
    y = np.array([height])
    return tp.BlockSystem(y, y.copy(), y.copy(), width, alpha)


# --- geometry -------------------------------------------------------------------------------------
def test_regular_constants_of_the_worked_example():
    a1, a2, b = tp.regular_constants(DX, ALPHA, PSI_B, PSI_F, PSI_S)
    # hand values: 10 tan 26.6°, 10 tan 26°, 10 tan 5.8° [m], to 1e-4 m
    assert a1 == pytest.approx(5.0076, abs=1e-4)
    assert a2 == pytest.approx(4.8773, abs=1e-4)
    assert b == pytest.approx(1.0158, abs=1e-4)
    # the example's rounded constants (5, 5, 1 m) are these to the nearest metre
    assert (round(a1), round(a2), round(b)) == (5, 5, 1)


def test_overall_base_cannot_dip_less_than_the_block_bases():
    with pytest.raises(ValueError):
        tp.regular_constants(DX, ALPHA, 29.0 * DEG, PSI_F, PSI_S)


def test_crest_block_and_number_of_blocks(exact):
    # block n's uphill top corner is at n Δx sin ψ_f / cos(ψ_f − α): 84.0 m for n = 9, 93.36 m for n = 10,
    # so the 92.5 m crest lies on block 10 (the published crest block); 93.4 m is the height Liu et al.'s
    # version of the example uses (volteoLab examples/allfunctions13bloques.m, h = 93.4)
    z10 = 10 * DX * math.sin(PSI_F) / math.cos(PSI_F - ALPHA)
    assert z10 == pytest.approx(93.4, abs=0.05)  # m, the printed precision
    assert exact.crest_block == 10
    assert tp.crest_block_number(84.0, DX, ALPHA, PSI_F) == 9
    assert exact.n_blocks == 16  # every block of positive height: 6 above the crest


def test_heights_of_the_worked_example(exact, rounded):
    a1, a2, b = exact.a1, exact.a2, exact.b
    n = np.arange(1, 11)
    expected = np.concatenate([n * (a1 - b), 10 * (a1 - b) - np.arange(1, 7) * (a2 + b)])
    np.testing.assert_allclose(exact.heights, expected, rtol=1e-14)
    # the heights an independent implementation prints for this geometry (lythoskinematic README,
    # hdaltuntas/lythoskinematic, "BLOCK TOPPLING ANALYSIS" run; blocks 1-5, 13, 14), 2 decimals
    printed = {1: 3.99, 2: 7.98, 3: 11.98, 4: 15.97, 5: 19.96, 13: 22.24, 14: 16.35}
    for k, y in printed.items():
        assert exact.heights[k - 1] == pytest.approx(y, abs=0.005)
    # the rounded geometry: 4 to 40 m below the crest, then 6 m less per block
    np.testing.assert_allclose(rounded.heights, [4, 8, 12, 16, 20, 24, 28, 32, 36, 40, 34, 28, 22, 16, 10, 4])


def test_moment_arms_are_the_top_corner_of_the_shorter_block_in_contact(exact):
    """Derived by hand: with steps of b, P_n acts at min(y_n, y_{n+1} + b) above block n's base and
    P_{n−1} at min(y_n, y_{n−1} − b), y_0 = 0; for the regular system this is the published table
    M_n = y_n, L_n = y_n − a1 below the crest; M_n = y_n − a2, L_n = y_n − a1 at it; M_n = y_n − a2,
    L_n = y_n above it. Tolerance: rounding, 1e-12 m."""
    y, b = exact.heights, exact.b
    upper = np.minimum(y[:-1], y[1:] + b)
    lower = np.minimum(y, np.concatenate([[0.0], y[:-1]]) - b)
    np.testing.assert_allclose(exact.upper_arm[:-1], upper, atol=1e-12)
    np.testing.assert_allclose(exact.lower_arm, lower, atol=1e-12)
    c = exact.crest_block - 1
    assert exact.upper_arm[c - 1] == y[c - 1] and exact.lower_arm[c - 1] == pytest.approx(y[c - 1] - exact.a1)
    assert exact.upper_arm[c] == pytest.approx(y[c] - exact.a2)
    assert exact.lower_arm[c] == pytest.approx(y[c] - exact.a1)
    assert exact.upper_arm[c + 1] == pytest.approx(y[c + 1] - exact.a2) and exact.lower_arm[c + 1] == y[c + 1]
    assert exact.lower_arm[0] == pytest.approx(-exact.b)  # the toe block: L_1 = y_1 − a1 = −b


# --- the worked example ---------------------------------------------------------------------------
@pytest.mark.parametrize("geometry", ["exact", "rounded"])
def test_limiting_friction_is_the_published_38_15_degrees(geometry, request):
    blocks = request.getfixturevalue(geometry)
    phi = tp.limiting_friction(blocks) / DEG
    # published to two decimals: 38.15°. exact geometry 38.1469°, rounded 38.1512°; tolerance ±0.005°
    assert phi == pytest.approx(PHI_PUBLISHED, abs=0.005)
    # P_0 at the root: 1e-4 N/m (Brent's 1e-13 rad times dP_0/dφ ≈ 6e7 N/m per rad is 6e-6 N/m)
    assert float(tp.toe_force(blocks, phi * DEG, GAMMA)) == pytest.approx(0.0, abs=1e-4)


def test_a_base_line_of_35_6_degrees_does_not_give_the_published_limit():
    """The brief remembered ψ_b = 35.6°; with exact constants that gives 38.24°, not 38.15° (the
    sources found use 35.8°). Two decimals, ±0.005°."""
    blocks = tp.regular_block_heights(None, DX, ALPHA, 35.6 * DEG, PSI_F, PSI_S, 10)
    assert tp.limiting_friction(blocks) / DEG == pytest.approx(38.24, abs=0.005)


@pytest.mark.parametrize("geometry", ["exact", "rounded"])
def test_modes_at_the_published_limit(geometry, request):
    """At limiting equilibrium (approached from the failing side, 1e-9 rad below the computed limit)
    blocks 1-3 slide, 4-13 topple, 14-16 stand. At the printed 38.15° itself the same holds for
    blocks 2-16 in both geometries; block 1 then slides (rounded geometry, limit 38.1512°) or just
    stands with a 3.06 kN/m surplus (exact geometry, limit 38.1469° < 38.15°)."""
    blocks = request.getfixturevalue(geometry)
    table = tp.toppling_forces(blocks, tp.limiting_friction(blocks) - 1e-9, GAMMA)
    modes = dict(zip(table.block.tolist(), table.mode.tolist(), strict=True))
    assert [n for n, m in modes.items() if m == "slides"] == SLIDES
    assert [n for n, m in modes.items() if m == "topples"] == TOPPLES
    assert [n for n, m in modes.items() if m == "stable"] == STABLE
    printed = tp.toppling_forces(blocks, PHI_PUBLISHED * DEG, GAMMA)
    assert printed.mode[1:].tolist() == table.mode[1:].tolist()
    if geometry == "rounded":
        assert printed.mode[0] == "slides" and printed.toe_force / 1e3 == pytest.approx(1.18, abs=0.005)
    else:
        assert printed.mode[0] == "stable" and printed.toe_force / 1e3 == pytest.approx(-3.06, abs=0.005)
    # blocks 5-13 are slender enough to topple on their own (y/Δx > cot 30° = 1.732); block 4
    # (y/Δx = 1.6) topples only because of the push from above
    assert table.topples_alone.tolist() == [False] * 4 + [True] * 9 + [False] * 3
    assert not table.slides_alone.any()


def test_forces_against_an_independent_implementation(exact):
    """lythoskinematic (hdaltuntas/lythoskinematic, README 'examples', exact geometry, φ = 38.15°)
    prints P(n−1) = 3970.2 kN/m for block 5 and 307.4 kN/m for block 13 and weights 998, 1996, 2994,
    3992, 4990 kN/m (blocks 1-5), 5560 (13), 4087 (14). It is a third-party program, not the book;
    its modes differ from the published ones for blocks 1-4 (it lets a block topple only if
    y/Δx > cot α), so only the blocks where both agree are compared. Tolerances: half the last printed
    digit, 0.05 kN/m and 0.5 kN/m."""
    table = tp.toppling_forces(exact, PHI_PUBLISHED * DEG, GAMMA)
    assert table.force_below[4] / 1e3 == pytest.approx(3970.2, abs=0.05)
    assert table.force_below[12] / 1e3 == pytest.approx(307.4, abs=0.05)
    weights = {1: 998, 2: 1996, 3: 2994, 4: 3992, 5: 4990, 13: 5560, 14: 4087}
    for k, w in weights.items():
        assert table.weight[k - 1] / 1e3 == pytest.approx(w, abs=0.5)


def test_toe_forces_of_the_rs2_verification_problem(rounded):
    """Rocscience RS2 joint verification problem 1 (Goodman & Bray's example, rounded geometry), as
    transcribed in the third-party corpus: at φ = 33.0239° the slope is posed with a horizontal toe
    force of 2013 kN (the manual) and the corpus' block-by-block recomputation needs 2012.86 kN/m;
    at φ = 38.15° it needs 0.36 kN/m. Tolerances: half the last printed digit."""
    h_33 = tp.horizontal_toe_support(rounded, 33.0239 * DEG, GAMMA) / 1e3
    assert h_33 == pytest.approx(2013.0, abs=0.5)
    assert h_33 == pytest.approx(2012.86, abs=0.005)
    h_38 = tp.horizontal_toe_support(rounded, PHI_PUBLISHED * DEG, GAMMA) / 1e3
    assert h_38 == pytest.approx(0.36, abs=0.005)
    # the toe block slides in both cases, held at its face: H (cos α + tan φ sin α) = (1 − tan² φ) P_0
    for phi in (33.0239, PHI_PUBLISHED):
        table = tp.toppling_forces(rounded, phi * DEG, GAMMA)
        assert table.mode[0] == "slides"


def test_the_toe_block_cannot_topple_against_a_force_below_its_pivot(rounded):
    """L_1 = −b < 0 and block 1's moment is restoring at φ = 33.0239°: not toppling (−inf). Dividing by
    L_1 would give 13 981 kN/m (±1 kN/m), which needs R_1 < 0 and would fail the base check too; the
    sliding value is what reproduces the 2012.86 kN/m above."""
    phi = 33.0239 * DEG
    table = tp.toppling_forces(rounded, phi, GAMMA)
    assert table.lower_arm[0] < 0.0
    assert table.p_topple[0] == -np.inf
    assert table.force_below[0] == pytest.approx(table.p_slide[0], rel=1e-15)
    tn, sa, ca = math.tan(phi), math.sin(ALPHA), math.cos(ALPHA)
    w, p1 = table.weight[0], table.force_above[0]
    formal = (
        p1 * (table.upper_arm[0] - DX * tn) + 0.5 * w * (table.height[0] * sa - DX * ca)
    ) / table.lower_arm[0]
    assert formal / 1e3 == pytest.approx(13981, abs=1.0)
    assert w * ca + (p1 - formal) * tn < 0.0


def test_a_toppling_block_is_held_by_its_toppling_force_whatever_its_base_check(exact):
    """Far below the limit (φ = 21°) block 2's toppling force exceeds its sliding force and would need
    R_2 < 0. The old march then took the block as sliding, with its smaller P_s, which made P_0 jump;
    now it passes P_{1,t} down (the block above may push back: docs/reference/toppling-method.md) and
    the system fails at 21° as at every angle below the limit."""
    phi = 21.0 * DEG
    t = tp.toppling_forces(exact, phi, GAMMA)
    tn, ca = math.tan(phi), math.cos(ALPHA)
    i = 1
    r_t = t.weight[i] * ca + (t.force_above[i] - t.p_topple[i]) * tn
    assert t.p_topple[i] > t.p_slide[i] > 0.0 and r_t < 0.0
    assert t.mode[i] == "topples" and t.force_below[i] == t.p_topple[i]
    assert t.toe_force > 0.0 and tp.factor_of_safety(exact, phi) < 1.0


@pytest.mark.parametrize("geometry", ["exact", "rounded"])
def test_every_block_of_the_worked_table_is_in_equilibrium(geometry, request):
    """Tolerances: 1e-9 relative (rounding only)."""
    blocks = request.getfixturevalue(geometry)
    phi = PHI_PUBLISHED * DEG
    t = tp.toppling_forces(blocks, phi, GAMMA)
    tan_phi, sa, ca = math.tan(phi), math.sin(ALPHA), math.cos(ALPHA)
    # forces are handed down: P_n of block n is P_n passed down by block n+1
    np.testing.assert_array_equal(t.force_above[:-1], t.force_below[1:])
    assert t.force_above[-1] == 0.0
    dp = t.force_above - t.force_below
    np.testing.assert_allclose(t.normal_force, t.weight * ca + dp * tan_phi, rtol=1e-12)
    np.testing.assert_allclose(t.shear_force, t.weight * sa + dp, rtol=1e-12)
    for i, mode in enumerate(t.mode):
        r, s = t.normal_force[i], t.shear_force[i]
        if mode == "slides":
            assert s == pytest.approx(r * tan_phi, rel=1e-9)
        elif mode == "topples":
            assert r > 0.0 and abs(s) < r * tan_phi
            moment = (
                t.force_above[i] * (t.upper_arm[i] - DX * tan_phi)
                + 0.5 * t.weight[i] * (t.height[i] * sa - DX * ca)
                - t.force_below[i] * t.lower_arm[i]
            )
            assert moment == pytest.approx(0.0, abs=1e-9 * t.weight[i] * DX)
        else:
            assert t.force_below[i] == 0.0 and 0.0 < s <= r * tan_phi


def test_blocks_with_nothing_from_above_reduce_to_the_single_block_equations(exact):
    """Block 13 is the first block under the stable top blocks: P_13 = 0, so
    P_12,t = (W/2)(y sin α − Δx cos α)/L and P_12,s = −W (tan φ cos α − sin α)/(1 − tan² φ). rtol 1e-12."""
    phi = PHI_PUBLISHED * DEG
    t = tp.toppling_forces(exact, phi, GAMMA)
    i = 12
    assert t.force_above[i] == 0.0
    w, y, lever = t.weight[i], t.height[i], t.lower_arm[i]
    sa, ca, tn = math.sin(ALPHA), math.cos(ALPHA), math.tan(phi)
    assert t.p_topple[i] == pytest.approx(0.5 * w * (y * sa - DX * ca) / lever, rel=1e-12)
    assert t.p_slide[i] == pytest.approx(-w * (tn * ca - sa) / (1.0 - tn**2), rel=1e-12)
    # the same numbers as the block standing alone (its own arms)
    alone = tp.toppling_forces(
        tp.BlockSystem(np.array([y]), np.array([t.upper_arm[i]]), np.array([lever]), DX, ALPHA), phi, GAMMA
    )
    assert alone.p_topple[0] == pytest.approx(t.p_topple[i], rel=1e-12)
    assert alone.p_slide[0] == pytest.approx(t.p_slide[i], rel=1e-12)


@pytest.mark.parametrize("geometry", ["exact", "rounded"])
def test_toe_force_changes_sign_at_the_limit(geometry, request):
    """Above the limit P_0 < 0 (a surplus), below it P_0 > 0 (support needed); over 25°-44.9° P_0
    falls monotonically. Checked 0.01° either side and on a 2000-point sweep."""
    blocks = request.getfixturevalue(geometry)
    phi_lim = tp.limiting_friction(blocks)
    assert float(tp.toe_force(blocks, phi_lim + 0.01 * DEG, GAMMA)) < 0.0
    assert float(tp.toe_force(blocks, phi_lim - 0.01 * DEG, GAMMA)) > 0.0
    table = tp.toppling_forces(blocks, phi_lim + 1.0 * DEG, GAMMA)
    assert table.toe_force < 0.0 and table.force_below[0] == 0.0
    sweep = np.linspace(25.0, 44.9, 2000) * DEG
    p0 = tp.toe_force(blocks, sweep, GAMMA)  # vectorised over friction
    assert np.all(np.diff(p0) < 0.0)
    assert np.all((p0 > 0.0) == (sweep < phi_lim))


def test_factor_of_safety_is_the_tangent_ratio(exact):
    """FS = tan φ / tan φ_limit (Hoek & Bray); 1 at the limit; the two-friction form agrees when the
    angles are equal. rtol 1e-9."""
    phi_lim = tp.limiting_friction(exact)
    assert tp.factor_of_safety(exact, phi_lim) == pytest.approx(1.0, rel=1e-9)
    phi = 42.0 * DEG
    fs = tp.factor_of_safety(exact, phi)
    assert fs == pytest.approx(math.tan(phi) / math.tan(phi_lim), rel=1e-12)
    assert tp.factor_of_safety(exact, phi, phi) == pytest.approx(fs, rel=1e-9)
    # dividing both tangents by FS brings P_0 to zero
    fs2 = tp.factor_of_safety(exact, 40.0 * DEG, 30.0 * DEG)
    p0 = tp.toe_force(exact, math.atan(math.tan(40 * DEG) / fs2), GAMMA, math.atan(math.tan(30 * DEG) / fs2))
    assert float(p0) == pytest.approx(0.0, abs=1e-3)  # N/m, against forces of 1e6-1e7 N/m


def test_the_table_as_a_dataframe(exact):
    frame = tp.toppling_forces(exact, PHI_PUBLISHED * DEG, GAMMA).to_frame()
    assert frame.index.tolist() == list(range(16, 0, -1))  # top block first, as printed
    assert frame.loc[13, "mode"] == "topples" and frame.loc[3, "mode"] == "slides"


# --- single blocks: closed forms derived by hand --------------------------------------------------
def test_a_single_block_topples_exactly_when_it_is_taller_than_width_cot_alpha():
    """P_n = 0, M = L = y, φ = 40° > α: P_t = (W/2)(y sin α − Δx cos α)/y > 0 iff y/Δx > cot α;
    sliding is ruled out (P_s < 0). Tested 1e-9 relative either side of y = Δx cot α."""
    phi = 40.0 * DEG
    y_crit = DX / math.tan(ALPHA)
    above = tp.toppling_forces(single_block(y_crit * (1 + 1e-9)), phi, GAMMA)
    below = tp.toppling_forces(single_block(y_crit * (1 - 1e-9)), phi, GAMMA)
    assert above.mode[0] == "topples" and above.topples_alone[0]
    assert below.mode[0] == "stable" and not below.topples_alone[0]
    tall = tp.toppling_forces(single_block(30.0), phi, GAMMA)
    w = GAMMA * 30.0 * DX
    p_t = 0.5 * w * (30.0 * math.sin(ALPHA) - DX * math.cos(ALPHA)) / 30.0
    assert tall.toe_force == pytest.approx(p_t, rel=1e-12)
    assert tall.normal_force[0] == pytest.approx(w * math.cos(ALPHA) - p_t * math.tan(phi), rel=1e-12)
    assert tall.shear_force[0] == pytest.approx(w * math.sin(ALPHA) - p_t, rel=1e-12)


def test_a_single_block_slides_exactly_when_the_base_is_steeper_than_friction():
    """A squat block (y/Δx = 0.5 < cot α): P_s = −W (tan φ cos α − sin α)/(1 − tan² φ) > 0 iff α > φ.
    Tested 1e-9 rad either side of φ = α; the toe force is that P_s (rtol 1e-12)."""
    blocks = single_block(5.0)
    assert tp.toppling_forces(blocks, ALPHA - 1e-9, GAMMA).mode[0] == "slides"
    assert tp.toppling_forces(blocks, ALPHA + 1e-9, GAMMA).mode[0] == "stable"
    phi = 25.0 * DEG
    t = tp.toppling_forces(blocks, phi, GAMMA)
    w, tn = GAMMA * 5.0 * DX, math.tan(phi)
    p_s = -w * (tn * math.cos(ALPHA) - math.sin(ALPHA)) / (1 - tn**2)
    assert t.slides_alone[0] and t.toe_force == pytest.approx(p_s, rel=1e-12)
    assert t.shear_force[0] == pytest.approx(t.normal_force[0] * tn, rel=1e-12)
    # and its limiting friction is the base dip itself (±1e-9 rad)
    assert tp.limiting_friction(blocks) == pytest.approx(ALPHA, abs=1e-9)


def test_side_friction_enters_as_in_wyllie_and_mah():
    """P_{n−1,s} = P_n − W (tan φ_p cos α − sin α)/(1 − tan φ_p tan φ_d) (Wyllie & Mah eq. 9.32, dry);
    P_{n−1,t} carries tan φ_d in the arm of P_n. Two blocks, the top one pushing; rtol 1e-12."""
    y = np.array([8.0, 30.0])
    blocks = tp.BlockSystem(y, y - 2.0, y - 3.0, DX, ALPHA)
    phi_p, phi_d = 35.0 * DEG, 20.0 * DEG
    t = tp.toppling_forces(blocks, phi_p, GAMMA, side_friction=phi_d)
    tp_, td = math.tan(phi_p), math.tan(phi_d)
    p1 = t.force_below[1]
    w0 = GAMMA * 8.0 * DX
    sa, ca = math.sin(ALPHA), math.cos(ALPHA)
    assert t.p_slide[0] == pytest.approx(p1 - w0 * (tp_ * ca - sa) / (1 - tp_ * td), rel=1e-12)
    expected_t = (p1 * (6.0 - DX * td) + 0.5 * w0 * (8.0 * sa - DX * ca)) / 5.0
    assert t.p_topple[0] == pytest.approx(expected_t, rel=1e-12)


def test_slope_blocks_from_roctopple_inputs_is_the_worked_example(exact):
    """Hoek & Bray's example as RocTopple takes it: H 92.5 m, face 56.6°, upper slope 4°, toppling
    joints dipping 60° (α = 30°) 10 m apart, overall base 35.8°: the exact geometry, φ_limit 38.15°."""
    blocks = tp.slope_blocks(H, PSI_F, PSI_S, 60.0 * DEG, DX, PSI_B)
    np.testing.assert_allclose(blocks.heights, exact.heights, rtol=1e-12)
    assert blocks.crest_block == 10 and blocks.n_blocks == 16
    assert tp.limiting_friction(blocks) / DEG == pytest.approx(PHI_PUBLISHED, abs=0.005)
    with pytest.raises(ValueError, match="dip into the slope"):
        tp.slope_blocks(H, PSI_F, PSI_S, 20.0 * DEG, DX, PSI_B)  # α = 70° > face 56.6°


def test_invalid_systems_are_refused():
    with pytest.raises(ValueError):
        tp.BlockSystem(np.array([1.0, -1.0]), np.ones(2), np.ones(2), DX, ALPHA)
    with pytest.raises(ValueError):
        tp.regular_system(DX, ALPHA, 10, 1.0, 5.0, 1.0)  # a1 − b = 0: no growth to the crest


def test_factor_of_safety_broadcasts_over_friction_arrays(rounded):
    """One call for many samples (Monte Carlo): each element equals the scalar call (to 1e-12)."""
    angles = np.radians([39.0, 42.0, 45.0])
    sides = np.radians([35.0, 38.0, 41.0])
    together = tp.factor_of_safety(rounded, angles)
    apart = [float(tp.factor_of_safety(rounded, float(a))) for a in angles]
    np.testing.assert_allclose(together, apart, rtol=1e-12)
    paired = tp.factor_of_safety(rounded, angles, sides)
    alone = [
        float(tp.factor_of_safety(rounded, float(a), float(d))) for a, d in zip(angles, sides, strict=True)
    ]
    np.testing.assert_allclose(paired, alone, rtol=1e-12)
    assert paired.shape == (3,)
