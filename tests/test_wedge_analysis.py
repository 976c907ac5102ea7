"""bbmc.slope.wedge.analysis, water, essentials and the short solution's FS: Hoek & Bray's classic wedge
by the short and the vector solutions (dry, with their water, with a tension crack and the comprehensive
solution's water), the two solutions on random wedges, the fast geometry against the full one, and the
water models and seismic directions by hand. Each tolerance is stated where it is used."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from bbmc.geometry.orientation import poles
from bbmc.slope.wedge.analysis import Seismic, WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.essentials import wedge_essentials
from bbmc.slope.wedge.geometry import TensionCrack, wedge_geometries
from bbmc.slope.wedge.mechanics import MohrCoulomb, SlidingMode
from bbmc.slope.wedge.short_solution import short_solution_factor_of_safety
from bbmc.slope.wedge.water import Dry, HoekBrayWater, PlanePressures, crack_foot_depth

R = np.radians
# Hoek & Bray's classic wedge (1981, ch. 8 and appendix 2; issue 35), in their units (ft, lbf, psf, pcf).
CLASSIC = WedgeOrientations(R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))
STRENGTH_A, STRENGTH_B = MohrCoulomb(500.0, R(20)), MohrCoulomb(1000.0, R(30))
GAMMA, GAMMA_W = 160.0, 62.5
CRACK = TensionCrack(R(70), R(165), 40.0)  # Hoek & Bray's crack, L = 40 ft from C1 along plane 1's trace


def _classic(**kwargs):
    return analyse_wedges(
        CLASSIC,
        STRENGTH_A,
        STRENGTH_B,
        unit_weight=GAMMA,
        water_unit_weight=GAMMA_W,
        height_h1=100.0,
        **kwargs,
    )


def _short(analysis, water_unit_weight):
    g = analysis.geometry
    return short_solution_factor_of_safety(
        g.short_solution, g.height_h, GAMMA, 500.0, 1000.0, R(20), R(30), water_unit_weight
    )


@pytest.mark.parametrize(
    ("water", "published"), [(Dry(), 1.8464), (HoekBrayWater(), 1.2180)], ids=["dry", "wet"]
)
def test_classic_wedge_short_and_vector_solutions_agree(water, published):
    """The issue's check: the short solution (Hoek & Bray 1981) and the vector solution agree to 1e-9,
    dry and with Hoek & Bray's water, each within 5e-4 of the issue's 1.8464 and 1.2180 (measured:
    1.846367 and 1.217995); the fast geometry gives the same FS to 1e-12."""
    analysis = _classic(water=water)
    vector = float(analysis.factor_of_safety)
    short = float(_short(analysis, 0.0 if isinstance(water, Dry) else GAMMA_W))
    assert int(analysis.solution.mode) == SlidingMode.BOTH
    assert short == pytest.approx(vector, abs=1e-9)
    assert vector == pytest.approx(published, abs=5e-4)
    assert short == pytest.approx(published, abs=5e-4)
    fast = float(_classic(water=water, essentials_only=True).factor_of_safety)
    assert fast == pytest.approx(vector, rel=1e-12)


def _independent_crack_wedge(water: bool) -> float:
    """The classic wedge with the crack, built here without the geometry module: vertices by 3x3 solves,
    the piece T P Q R cut off, h_5 from the upper surface's equation, u = gamma_w h_5 / 3 on planes 1, 2
    and the crack, and the normal reactions and the force along the line by one 3x3 solve of
    N1 n1 + N2 n2 + S l = -F. Returns FS = (sum c A + N tan phi) / |S|."""
    n1, n2, face, upper = (poles(*pair) for pair in np.reshape(CLASSIC.angles(), (4, 2)))

    def meet(a, b, c, rhs):
        return np.linalg.solve(np.stack([a, b, c]), rhs)

    c1 = meet(n1, face, upper, [0.0, 0.0, 1.0])
    offset = 100.0 / c1[2]
    c1 = c1 * offset
    c2, top = meet(n2, face, upper, [0.0, 0.0, offset]), meet(n1, n2, upper, [0.0, 0.0, offset])
    n5 = poles(CRACK.dip, CRACK.dip_direction)
    start = c1 + CRACK.distance * (top - c1) / np.linalg.norm(top - c1)

    def cut(a, b):  # the crack's point on the segment a b
        t = n5 @ (start - a) / (n5 @ (b - a))
        return a + t * (b - a)

    p, q, r = cut(c1, top), cut(c2, top), cut(np.zeros(3), top)

    def area(a, b, c):
        return 0.5 * np.linalg.norm(np.cross(b - a, c - a))

    def volume(a, b, c, d):
        return abs(np.dot(b - a, np.cross(c - a, d - a))) / 6.0

    origin = np.zeros(3)
    area_1, area_2 = area(origin, c1, top) - area(top, p, r), area(origin, c2, top) - area(top, q, r)
    area_5, weight = area(p, q, r), GAMMA * (volume(origin, c1, c2, top) - volume(top, p, q, r))
    into_1, into_2 = n1 * np.sign(n1 @ c2), n2 * np.sign(n2 @ c1)
    into_5 = n5 * np.sign(n5 @ (origin - r))
    depth = (upper @ c1 - upper @ r) / upper[2]
    u = GAMMA_W * depth / 3.0 if water else 0.0
    force = np.array([0.0, 0.0, -weight]) + u * (area_1 * into_1 + area_2 * into_2 + area_5 * into_5)
    line = np.cross(n1, n2) / np.linalg.norm(np.cross(n1, n2))
    normal_1, normal_2, shear = np.linalg.solve(np.column_stack([into_1, into_2, line]), -force)
    assert normal_1 > 0 and normal_2 > 0
    resisting = 500.0 * area_1 + normal_1 * np.tan(R(20)) + 1000.0 * area_2 + normal_2 * np.tan(R(30))
    return resisting / abs(shear)


@pytest.mark.parametrize("water", [False, True], ids=["dry", "crack water"])
def test_classic_wedge_with_hoek_and_brays_tension_crack(water):
    """The issue's check with Hoek & Bray's tension crack 70/165 at L = 40 ft from C1 along plane 1's
    trace on the upper surface: the vector solution with the comprehensive solution's water
    (u = gamma_w h_5 / 3 on planes 1, 2 and the crack) against the independent build above, to 1e-9
    relative. Measured: FS 1.73558 dry, 1.13782 with the crack full (h_5 = 52.045 ft)."""
    analysis = _classic(crack=CRACK, water=HoekBrayWater() if water else Dry())
    assert int(analysis.solution.mode) == SlidingMode.BOTH
    assert float(analysis.factor_of_safety) == pytest.approx(_independent_crack_wedge(water), rel=1e-9)
    assert float(crack_foot_depth(analysis.geometry)) == pytest.approx(52.045, abs=1e-3)


@settings(max_examples=200, deadline=None)
@given(
    st.floats(25.0, 75.0),
    st.floats(10.0, 80.0),
    st.floats(25.0, 75.0),
    st.floats(10.0, 80.0),
    st.floats(60.0, 89.0),
    st.floats(0.0, 359.99),
    st.floats(0.0, 15.0),
    st.floats(-30.0, 30.0),
    st.floats(10.0, 40.0),
    st.floats(10.0, 40.0),
)
def test_short_and_vector_solutions_agree_on_random_wedges(
    dip_1, left, dip_2, right, face_dip, face_dd, upper_dip, upper_turn, phi_a, phi_b
):
    """Random wedges (planes dipping `left` and `right` degrees either side of the face's dip direction)
    that form and slide on both planes with neither overlying the wedge, dry and with Hoek & Bray's
    water: the short solution's FS equals the vector solution's to 1e-9 relative."""
    orientations = WedgeOrientations(
        R(dip_1),
        R(face_dd - left),
        R(dip_2),
        R(face_dd + right),
        R(face_dip),
        R(face_dd),
        R(upper_dip),
        R(face_dd + upper_turn),
    )
    strengths = MohrCoulomb(2e4, R(phi_a)), MohrCoulomb(1e4, R(phi_b))
    for water, gamma_w in ((Dry(), 0.0), (HoekBrayWater(), 9810.0)):
        analysis = analyse_wedges(
            orientations, *strengths, unit_weight=26e3, height_h=20.0, water=water, water_unit_weight=9810.0
        )
        g = analysis.geometry
        assume(bool(g.formed) and g.normal_1[2] > 0.0 and g.normal_2[2] > 0.0)
        assume(int(analysis.solution.mode) == SlidingMode.BOTH)
        short = short_solution_factor_of_safety(
            g.short_solution, g.height_h, 26e3, 2e4, 1e4, R(phi_a), R(phi_b), gamma_w
        )
        assert float(short) == pytest.approx(float(analysis.factor_of_safety), rel=1e-9)


def _random_inputs(count: int, seed: int) -> tuple[list[np.ndarray], np.ndarray]:
    """Eight random angles [rad] per wedge (planes 1 and 2 anywhere, the face 20 to 90 deg, the upper
    surface's dip direction within 60 deg of the face's) and a fifth of the faces overhanging."""
    rng = np.random.default_rng(seed)
    dips = R(rng.uniform(0.0, 90.0, (4, count)))
    directions = R(rng.uniform(0.0, 360.0, (4, count)))
    dips[2] = R(rng.uniform(20.0, 90.0, count))
    directions[3] = directions[2] + R(rng.uniform(-60.0, 60.0, count))
    angles = [a for pair in zip(dips, directions, strict=True) for a in pair]
    return angles, rng.random(count) < 0.2


@pytest.mark.parametrize("key", ["height_h1", "height_h"])
def test_fast_geometry_equals_the_full_geometry(key):
    """On 20 000 random wedges (a fifth with overhanging faces; about a quarter form): the compiled fast
    path gives the same reason per wedge as the full geometry, NaN in the same places, and the same
    normals, line, areas, volume and total height to 1e-12 relative."""
    angles, overhanging = _random_inputs(20_000, 35)
    heights = np.random.default_rng(1).uniform(1.0, 50.0, 20_000)
    full = wedge_geometries(*angles, overhanging_face=overhanging, **{key: heights})
    fast = wedge_essentials(*angles, overhanging_face=overhanging, **{key: heights})
    assert np.array_equal(fast.reason, full.reason)
    assert 0.1 < np.mean(full.formed) < 0.9 and len(np.unique(full.reason)) >= 5
    for name in ("normal_1", "normal_2", "line", "area_1", "area_2", "volume", "height_h"):
        a, b = getattr(fast, name), getattr(full, name)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        assert np.allclose(a, b, rtol=1e-12, atol=0.0, equal_nan=True), name


def test_fast_geometry_refuses_what_the_full_one_refuses():
    with pytest.raises(ValueError, match="dip_2"):
        wedge_essentials(*(R(a) for a in (45, 105, 95, 235, 65, 185, 12, 195)), height_h1=1.0)
    with pytest.raises(ValueError, match="height_h1"):
        wedge_essentials(*CLASSIC.angles(), height_h1=-1.0)


def test_a_wedge_that_cannot_form_has_no_factor_of_safety():
    """Planes steeper than the face: the reason, NaN weight and FS, never a number."""
    steep = WedgeOrientations(R(75), R(160), R(80), R(210), R(65), R(185), R(12), R(195))
    for fast in (False, True):
        analysis = analyse_wedges(
            steep, STRENGTH_A, STRENGTH_B, unit_weight=GAMMA, height_h1=100.0, essentials_only=fast
        )
        assert not analysis.geometry.formed
        assert np.isnan(analysis.loads.weight) and np.isnan(analysis.factor_of_safety)


def test_water_models_by_hand():
    """U_i = p_i A_i and V = p_5 A_5 for given pressures; half filled halves Hoek & Bray's forces;
    filled = 0 is the dry wedge; the crack's water u A_5 = gamma_w h_5 A_5 / 3 (all to 1e-12)."""
    wet = _classic(water=HoekBrayWater())
    g = wet.geometry
    half = _classic(water=HoekBrayWater(0.5))
    assert float(half.loads.water_1) == pytest.approx(0.5 * float(wet.loads.water_1), rel=1e-12)
    assert float(wet.loads.water_1) == pytest.approx(
        GAMMA_W * float(g.height_h) * float(g.area_1) / 6, rel=1e-12
    )
    empty, dry = _classic(water=HoekBrayWater(0.0)), _classic()
    assert float(empty.factor_of_safety) == pytest.approx(float(dry.factor_of_safety), rel=1e-12)
    given_ = _classic(crack=CRACK, water=PlanePressures(1000.0, 2000.0, 500.0))
    gc = given_.geometry
    expected = (1000.0 * gc.area_1, 2000.0 * gc.area_2, 500.0 * gc.area_crack)
    measured = (given_.loads.water_1, given_.loads.water_2, given_.loads.water_crack)
    assert np.allclose(measured, expected, rtol=1e-12)
    crack = _classic(crack=CRACK, water=HoekBrayWater())
    u = GAMMA_W * crack_foot_depth(crack.geometry) / 3.0
    assert float(crack.loads.water_crack) == pytest.approx(float(u * crack.geometry.area_crack), rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"water": HoekBrayWater(1.5)}, "filled"),
        ({"water": "wet"}, "water"),
        ({"water": PlanePressures(1.0, 1.0, 1.0)}, "water.crack"),
        ({"crack": CRACK, "essentials_only": True}, "essentials_only"),
        ({"seismic": Seismic(0.1, "sideways")}, "seismic.direction"),
    ],
)
def test_bad_loads_name_their_key(kwargs, key):
    with pytest.raises(ValueError, match=key):
        _classic(**kwargs)


def test_seismic_directions():
    """k W horizontal along the line's trend, down the line, and along a given vector (to 1e-12)."""
    g = _classic().geometry
    weight = GAMMA * float(g.volume)
    flat = g.line * np.array([1.0, 1.0, 0.0])
    flat = flat / np.linalg.norm(flat)
    for direction, expected in (
        ("horizontal", flat),
        ("line", g.line),
        ([0.0, 1.0, 0.0], np.array([0, 1.0, 0])),
    ):
        shaken = _classic(seismic=Seismic(0.2, direction))
        assert np.allclose(shaken.loads.seismic, 0.2 * weight * expected, rtol=1e-12, atol=1e-6)
    assert float(_classic(seismic=Seismic(0.2, "line")).factor_of_safety) < float(_classic().factor_of_safety)


def test_batches_of_strength_and_water():
    """One geometry, 1000 friction angles and fill fractions: each sample equals its own analysis
    (to 1e-12)."""
    phi = np.linspace(R(15), R(40), 1000)
    filled = np.linspace(0.0, 1.0, 1000)
    many = analyse_wedges(
        CLASSIC,
        MohrCoulomb(500.0, phi),
        MohrCoulomb(1000.0, phi),
        unit_weight=GAMMA,
        water_unit_weight=GAMMA_W,
        height_h1=100.0,
        water=HoekBrayWater(filled),
    )
    one = analyse_wedges(
        CLASSIC,
        MohrCoulomb(500.0, phi[321]),
        MohrCoulomb(1000.0, phi[321]),
        unit_weight=GAMMA,
        water_unit_weight=GAMMA_W,
        height_h1=100.0,
        water=HoekBrayWater(filled[321]),
    )
    assert many.factor_of_safety.shape == (1000,)
    assert many.factor_of_safety[321] == pytest.approx(float(one.factor_of_safety), rel=1e-12)
