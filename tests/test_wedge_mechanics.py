"""bbmc.slope.wedge.mechanics and loads: the vector solution of a wedge against closed forms (Hoek &
Bray's wedge factor K, the planar limit), 3DEC's sliding wedge, Hoek & Bray's classic wedge dry and with
their water, the stereonet's mode rule on random wedges, and hand calculations of the loads. Each
tolerance is stated where it is used.

The classic wedge and the stereonet test take the wedge's normals, areas and volume from
`bbmc.slope.wedge.geometry` (itself checked against hand-worked wedges and scipy's convex hull in
tests/test_wedge_geometry.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from bbmc.geometry.orientation import line_vectors, poles, trend_and_plunge, wrapped_azimuth
from bbmc.slope.wedge import loads
from bbmc.slope.wedge import mechanics as wm
from bbmc.slope.wedge.geometry import wedge_geometries, wedge_geometry

DEG = math.pi / 180.0
UP = np.array([0.0, 0.0, 1.0])


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def _dry(n1, n2, phi1, phi2, c1=0.0, c2=0.0, area_1=1.0, area_2=1.0, weight=1.0, **kw):
    force = wm.active_resultant(weight, n1, n2, kw.pop("water_1", 0.0), kw.pop("water_2", 0.0))
    force = force + kw.pop("active", 0.0)
    return wm.wedge_factor_of_safety(
        n1, n2, area_1, area_2, force, wm.MohrCoulomb(c1, phi1), wm.MohrCoulomb(c2, phi2), **kw
    )


def _wedge_factor(n1: np.ndarray, n2: np.ndarray) -> tuple[float, float, float]:
    """Hoek & Bray's K = sin beta / sin(xi / 2) from angles measured in the section normal to the line
    of intersection l: xi between the planes' traces on the wedge's side, beta of the bisector from the
    section's horizontal; and the plunge psi_i of l. Also beta and xi (rad)."""
    line = np.cross(n1, n2)
    line = line / np.linalg.norm(line)
    e1, e2 = np.cross(line, n1), np.cross(line, n2)  # traces of the planes in the section
    e1, e2 = e1 * np.sign(e1 @ n2), e2 * np.sign(e2 @ n1)  # each pointing to the other plane's wedge side
    xi = math.acos(float(np.clip(e1 @ e2, -1.0, 1.0)))
    bisector = (e1 + e2) / np.linalg.norm(e1 + e2)
    horizontal = np.cross(line, UP) / np.linalg.norm(np.cross(line, UP))
    vertical = np.cross(horizontal, line)
    beta = math.atan2(abs(float(bisector @ vertical)), float(bisector @ horizontal))
    return math.sin(beta) / math.sin(xi / 2.0), beta, xi


# Hoek & Bray's classic wedge (1981, ch. 8 and appendix 2; Wyllie & Mah 2004, appendix III), in their
# units (ft, lbf): what FS needs is only that the units agree.
CLASSIC = tuple(a * DEG for a in (45.0, 105.0, 70.0, 235.0, 65.0, 185.0, 12.0, 195.0))


def _classic_geometry():
    return wedge_geometry(*CLASSIC, height_h1=100.0)


def _classic(water: bool) -> wm.WedgeSolution:
    g = _classic_geometry()
    n1, n2, a1, a2 = g.normal_1, g.normal_2, g.area_1, g.area_2
    u1, u2 = loads.hoek_bray_water(g.height_h, a1, a2, 62.5) if water else (0.0, 0.0)
    force = wm.active_resultant(160.0 * g.volume, n1, n2, u1, u2)
    return wm.wedge_factor_of_safety(
        n1, n2, a1, a2, force, wm.MohrCoulomb(500.0, 20.0 * DEG), wm.MohrCoulomb(1000.0, 30.0 * DEG)
    )


def test_classic_wedge_dry_and_with_hoek_and_brays_water():
    """FS 1.8464 dry and 1.2180 with water (the issue's values, computed independently of bbmc), each
    to 5e-4, both sliding on both planes; the total height is 130 ft (to 0.01 ft: the issue's H)."""
    height = _classic_geometry().height_h
    assert float(height) == pytest.approx(130.0, abs=0.01)
    dry, wet = _classic(False), _classic(True)
    assert float(dry.factor_of_safety) == pytest.approx(1.8464, abs=5e-4)
    assert float(wet.factor_of_safety) == pytest.approx(1.2180, abs=5e-4)
    assert int(dry.mode) == int(wet.mode) == wm.SlidingMode.BOTH


def test_classic_wedge_factor_is_1_505():
    """The classic wedge's K = sin beta / sin(xi/2) = 1.505 (the issue's value, to its 5e-4), and the
    vector solution dry with c = 0 gives K tan phi / tan psi_i (to 1e-12)."""
    g = _classic_geometry()
    n1, n2 = g.normal_1, g.normal_2
    k, *_ = _wedge_factor(n1, n2)
    assert k == pytest.approx(1.505, abs=5e-4)
    fs = float(_dry(n1, n2, 30.0 * DEG, 30.0 * DEG).factor_of_safety)
    _, plunge = trend_and_plunge(np.cross(n1, n2))
    assert fs == pytest.approx(k * math.tan(30.0 * DEG) / math.tan(float(plunge)), rel=1e-12)


angles = st.floats(min_value=2.0, max_value=88.0)
azimuths = st.floats(min_value=0.0, max_value=359.99)


@settings(max_examples=300, deadline=None)
@given(angles, azimuths, angles, azimuths, st.floats(min_value=5.0, max_value=60.0))
def test_dry_cohesionless_wedge_is_k_tan_phi_over_tan_psi(dip_1, dd_1, dip_2, dd_2, phi):
    """Wedges resting on both planes (upward poles), dry, c = 0, one phi: where xi/2 < beta < pi - xi/2
    (the bisector's section angles, measured here from the planes' traces) the wedge slides on both
    planes with FS = K tan phi / tan psi_i (to 1e-9 relative); elsewhere it slides on one plane alone."""
    n1, n2 = poles(dip_1 * DEG, dd_1 * DEG), poles(dip_2 * DEG, dd_2 * DEG)
    assume(np.linalg.norm(np.cross(n1, n2)) > 0.05)
    _, plunge = trend_and_plunge(np.cross(n1, n2))
    assume(float(plunge) > 1.0 * DEG)
    k, beta, xi = _wedge_factor(n1, n2)
    margin = min(beta - xi / 2.0, math.pi - xi / 2.0 - beta)
    assume(abs(margin) > 1e-6)
    solution = _dry(n1, n2, phi * DEG, phi * DEG)
    if margin > 0.0:
        assert int(solution.mode) == wm.SlidingMode.BOTH
        expected = k * math.tan(phi * DEG) / math.tan(float(plunge))
        assert float(solution.factor_of_safety) == pytest.approx(expected, rel=1e-9)
    else:
        assert int(solution.mode) in (wm.SlidingMode.PLANE_1, wm.SlidingMode.PLANE_2)


@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=2.0, max_value=85.0), azimuths, st.floats(min_value=5.0, max_value=60.0))
def test_vertical_frictionless_side_plane_gives_the_planar_factor_of_safety(dip, direction, phi):
    """Plane 2 vertical, frictionless and parallel to plane 1's dip direction (its normal horizontal and
    normal to that direction): FS = tan phi / tan psi_1 (to 1e-12), on plane 1 or on both (N2 = 0)."""
    n1 = poles(dip * DEG, direction * DEG)
    n2 = np.array([math.cos(direction * DEG), -math.sin(direction * DEG), 0.0])
    solution = _dry(n1, n2, phi * DEG, 0.0)
    expected = math.tan(phi * DEG) / math.tan(dip * DEG)
    assert float(solution.factor_of_safety) == pytest.approx(expected, rel=1e-12)
    assert int(solution.mode) in (wm.SlidingMode.BOTH, wm.SlidingMode.PLANE_1)


def test_3decs_sliding_wedge():
    """Planes 40/130 and 60/220, c = 0: FS 1.2746 at phi 40 deg (to 5e-5, the printed precision) and
    the limiting phi 33.36 deg (to 5e-3 deg); areas and weight do not matter."""
    n1, n2 = poles(40.0 * DEG, 130.0 * DEG), poles(60.0 * DEG, 220.0 * DEG)
    assert float(_dry(n1, n2, 40.0 * DEG, 40.0 * DEG).factor_of_safety) == pytest.approx(1.2746, abs=5e-5)

    def excess(phi_deg: float) -> float:
        return float(_dry(n1, n2, phi_deg * DEG, phi_deg * DEG, weight=7.3).factor_of_safety) - 1.0

    assert brentq(excess, 10.0, 60.0, xtol=1e-9) == pytest.approx(33.36, abs=5e-3)


def _between(start: np.ndarray, azimuth: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Whether `azimuth` lies strictly within the shorter arc from `start` to `end` [rad]."""
    arc = np.mod(end - start + np.pi, 2.0 * np.pi) - np.pi
    part = np.mod(azimuth - start + np.pi, 2.0 * np.pi) - np.pi
    return (np.sign(arc) == np.sign(part)) & (np.abs(part) < np.abs(arc))


def test_mode_follows_the_stereonet_rule_on_random_wedges():
    """Dry, gravity only, on 40 000 random plane pairs, faces and upper surfaces, of which the wedges
    that form with the toe as their lowest vertex (the rule's premise: the geometry also forms wedges
    whose crest point C2 or top T lies below the toe, about 2 % of this sample, where the wedge need not
    move towards the face): a plane whose dip direction alone lies between the trend of the line of
    intersection and the face's dip direction carries the wedge alone (Hudson & Harrison 1997); where
    both do, one plane overlies the wedge and the wedge slides on the other; where neither does, on
    both planes.
    Every wedge agrees (no tolerance: the modes are counted); the sample holds thousands of each."""
    rng = np.random.default_rng(35)
    count = 40_000
    dip_1, dip_2 = rng.uniform(5.0, 89.0, (2, count)) * DEG
    dd_1, dd_2, face_dd = rng.uniform(0.0, 2.0 * np.pi, (3, count))
    face = (rng.uniform(40.0, 89.0, count) * DEG, face_dd)
    upper = (rng.uniform(0.0, 20.0, count) * DEG, wrapped_azimuth(face_dd + rng.uniform(-0.5, 0.5, count)))
    g = wedge_geometries(dip_1, dd_1, dip_2, dd_2, *face, *upper, height_h1=1.0)
    forms = g.formed & (g.crest_2[:, 2] > 0.0) & (g.top[:, 2] > 0.0)  # the toe is the lowest vertex
    n1, n2 = g.normal_1[forms], g.normal_2[forms]
    solution = _dry(n1, n2, 30.0 * DEG, 30.0 * DEG)
    trend, _ = trend_and_plunge(np.cross(n1, n2))
    on_1 = _between(trend, dd_1[forms], face_dd[forms])
    on_2 = _between(trend, dd_2[forms], face_dd[forms])
    plane_1_overlies = n1[:, 2] < 0.0
    expected = np.where(on_1 & ~on_2, 1, np.where(on_2 & ~on_1, 2, 3))
    expected = np.where(on_1 & on_2, np.where(plane_1_overlies, 2, 1), expected)
    assert np.array_equal(solution.mode, expected)
    assert np.min(np.bincount(solution.mode, minlength=4)[1:]) > 1000
    assert np.count_nonzero(on_1 & on_2) > 100


def test_mode_follows_the_dip_vectors_from_the_normals():
    """The same rule without a face, from the normals (wedges on both planes, upward poles): plane 1
    alone exactly where plane 1's dip vector leaves plane 2 (d1 . n2 > 0), plane 2 alone where
    d2 . n1 > 0, both planes elsewhere, over 100 000 random pairs (the line plunging)."""
    rng = np.random.default_rng(7)
    dips = rng.uniform(2.0, 88.0, (2, 100_000)) * DEG
    directions = rng.uniform(0.0, 2.0 * np.pi, (2, 100_000))
    n1, n2 = poles(dips[0], directions[0]), poles(dips[1], directions[1])
    d1, d2 = line_vectors(directions[0], dips[0]), line_vectors(directions[1], dips[1])
    keep = np.abs(np.cross(n1, n2)[:, 2]) > 1e-3
    solution = _dry(n1[keep], n2[keep], 30.0 * DEG, 30.0 * DEG)
    leaves_2, leaves_1 = _dot(d1, n2)[keep] > 0.0, _dot(d2, n1)[keep] > 0.0
    expected = np.where(leaves_2, 1, np.where(leaves_1, 2, 3))
    assert np.array_equal(solution.mode, expected)


CLASSIC_NORMALS = (poles(45.0 * DEG, 105.0 * DEG), poles(70.0 * DEG, 235.0 * DEG))


def test_water_lowers_each_normal_force_by_its_uplift():
    """Contact on both planes: N_i with water = N_i dry - U_i (Hoek & Bray), to 1e-9 N."""
    n1, n2 = CLASSIC_NORMALS
    dry = _dry(n1, n2, 0.5, 0.5, weight=1e4)
    wet = _dry(n1, n2, 0.5, 0.5, weight=1e4, water_1=800.0, water_2=300.0)
    assert float(wet.normal_1) == pytest.approx(float(dry.normal_1) - 800.0, abs=1e-9)
    assert float(wet.normal_2) == pytest.approx(float(dry.normal_2) - 300.0, abs=1e-9)


def test_water_that_floats_the_wedge_loses_contact_and_gives_fs_zero():
    """Uplift larger than the weight's normal parts: contact lost on both planes, FS 0 (Hoek & Bray)."""
    n1, n2 = CLASSIC_NORMALS
    solution = _dry(n1, n2, 0.5, 0.5, c1=1e3, c2=1e3, weight=1e4, water_1=2e4, water_2=2e4)
    assert int(solution.mode) == wm.SlidingMode.LIFTED
    assert float(solution.factor_of_safety) == 0.0
    assert solution.modes()[()] == "contact lost on both planes"


def test_seismic_force_down_the_line_adds_to_the_driving_force_only():
    """k W along the line of intersection (down it): normals unchanged, D = W sin psi_i + k W, so
    FS = R / (W sin psi_i + k W) (to 1e-12)."""
    n1, n2 = CLASSIC_NORMALS
    line = np.cross(n1, n2) / np.linalg.norm(np.cross(n1, n2))
    line = -line if line[2] > 0 else line
    weight, k = 1e4, 0.15
    dry = _dry(n1, n2, 0.6, 0.5, c1=20.0, c2=30.0, weight=weight)
    shaken = _dry(
        n1, n2, 0.6, 0.5, c1=20.0, c2=30.0, weight=weight, active=loads.seismic_force(weight, k, line)
    )
    assert float(shaken.normal_1) == pytest.approx(float(dry.normal_1), rel=1e-12)
    driving = weight * -line[2] + k * weight
    assert float(shaken.factor_of_safety) == pytest.approx(float(dry.resisting) / driving, rel=1e-12)


@pytest.mark.parametrize("form", ["active", "passive"])
def test_a_force_straight_up_the_line(form):
    """A force T up the line of intersection (normal to both planes' normals): active,
    FS = R / (D - T); passive, FS = (R + T) / D (Swedge's two ways of counting support; to 1e-12)."""
    n1, n2 = CLASSIC_NORMALS
    line = np.cross(n1, n2) / np.linalg.norm(np.cross(n1, n2))
    line = -line if line[2] > 0 else line
    trend, plunge = trend_and_plunge(line)
    pull = loads.force_vector(1500.0, trend + math.pi, -plunge)  # up the line
    dry = _dry(n1, n2, 0.6, 0.5, c1=20.0, c2=30.0, weight=1e4)
    supported = _dry(n1, n2, 0.6, 0.5, c1=20.0, c2=30.0, weight=1e4, **{form: pull})
    r, d = float(dry.resisting), float(dry.driving)
    expected = r / (d - 1500.0) if form == "active" else (r + 1500.0) / d
    assert float(supported.factor_of_safety) == pytest.approx(expected, rel=1e-12)


def test_an_active_force_larger_than_the_driving_force_pushes_the_wedge_up_the_line():
    """Swedge's "sliding up the line of intersection": the FS is then the joints' resistance to the
    net push up the line, R / (T - D) (to 1e-12)."""
    n1, n2 = CLASSIC_NORMALS
    line = np.cross(n1, n2) / np.linalg.norm(np.cross(n1, n2))
    line = -line if line[2] > 0 else line
    dry = _dry(n1, n2, 0.6, 0.5, weight=1e4)
    push = -3.0 * float(dry.driving) * line
    up = _dry(n1, n2, 0.6, 0.5, weight=1e4, active=push)
    assert int(up.mode) == wm.SlidingMode.BOTH_UP
    assert float(up.factor_of_safety) == pytest.approx(
        float(dry.resisting) / (2.0 * float(dry.driving)), rel=1e-12
    )
    assert up.sliding_direction[2] > 0.0


@settings(max_examples=200, deadline=None)
@given(
    st.floats(min_value=0.0, max_value=1.0),
    st.floats(min_value=0.0, max_value=1.0),
    st.floats(min_value=0.0, max_value=1.0),
    st.floats(min_value=0.1, max_value=1.0),
)
def test_fs_never_falls_as_an_active_bolt_grows(onto_1, onto_2, up_line, phi):
    """An active bolt with no component down the line of intersection that presses the wedge onto its
    planes (its pull = -a n1 - b n2 - u l, a, b, u >= 0): over 40 capacities from 0 to the one that
    holds the wedge, the wedge keeps sliding on both planes and FS never falls (to 1e-12 relative)."""
    n1, n2 = CLASSIC_NORMALS
    line = np.cross(n1, n2) / np.linalg.norm(np.cross(n1, n2))
    line = -line if line[2] > 0 else line
    direction = -onto_1 * n1 - onto_2 * n2 - up_line * line
    assume(np.linalg.norm(direction) > 1e-3)
    direction = direction / np.linalg.norm(direction)
    dry = _dry(n1, n2, phi, phi, c1=10.0, c2=10.0, weight=1e4)
    along = -float(direction @ line)
    reach = float(dry.driving) / along if along > 1e-9 else 1e5
    capacity = np.linspace(0.0, 0.999 * reach, 40)
    bolted = _dry(n1, n2, phi, phi, c1=10.0, c2=10.0, weight=1e4, active=capacity[:, None] * direction)
    assert np.all(bolted.mode == wm.SlidingMode.BOTH)
    fs = bolted.factor_of_safety
    assert np.all(np.diff(fs) >= -1e-12 * fs[1:])


def test_hoek_bray_water_is_a_sixth_of_gamma_w_h_on_each_area():
    """U_i = gamma_w H A_i / 6 by hand: 9810 * 12 * 30 / 6 = 588 600 N (exact in floating point to 1e-9)."""
    u1, u2 = loads.hoek_bray_water(12.0, 30.0, 45.0)
    assert float(u1) == pytest.approx(588_600.0, rel=1e-12)
    assert float(u2) == pytest.approx(882_900.0, rel=1e-12)


def test_force_vector_and_horizontal_along():
    """A force of trend 90 deg, plunge 30 deg points east and down: T (cos 30, 0, -sin 30); the horizontal
    along a line of trend 90 deg is east (to 1e-12)."""
    force = loads.force_vector(2.0, 90.0 * DEG, 30.0 * DEG)
    assert np.allclose(force, [2.0 * math.cos(30 * DEG), 0.0, -1.0], atol=1e-12)
    assert np.allclose(loads.horizontal_along(force), [1.0, 0.0, 0.0], atol=1e-12)


def test_parallel_planes_give_no_factor_of_safety():
    """Planes with no line of intersection: FS NaN, never a number."""
    n = poles(40.0 * DEG, 120.0 * DEG)
    assert np.isnan(float(_dry(n, n, 0.5, 0.5).factor_of_safety))


def test_samples_broadcast():
    """The same wedge over 1000 samples of phi gives each sample's own FS (to 1e-12)."""
    n1, n2 = CLASSIC_NORMALS
    phi = np.linspace(0.2, 0.8, 1000)
    many = _dry(n1, n2, phi, phi)
    one = _dry(n1, n2, phi[123], phi[123])
    assert many.factor_of_safety.shape == (1000,)
    assert many.factor_of_safety[123] == pytest.approx(float(one.factor_of_safety), rel=1e-12)


def test_passive_support_on_a_wedge_sliding_on_plane_1_alone():
    """Plane 2 vertical, its normal 60 deg off plane 1's dip direction, so the wedge slides down plane 1's
    dip and leaves plane 2. A passive force T up the dip plus Q onto plane 1: by hand,
    FS = (c A1 + (W cos psi + Q) tan phi + T) / (W sin psi) (to 1e-12)."""
    dip, direction, weight, phi, c, area = 35.0 * DEG, 140.0 * DEG, 1e4, 0.5, 40.0, 20.0
    n1 = poles(dip, direction)
    n2 = np.array([math.sin(direction + 60 * DEG), math.cos(direction + 60 * DEG), 0.0])
    dip_vector = line_vectors(direction, dip)
    held = -900.0 * dip_vector - 300.0 * n1
    solution = _dry(n1, n2, phi, 0.3, c1=c, c2=1e3, area_1=area, weight=weight, passive=held)
    assert int(solution.mode) == wm.SlidingMode.PLANE_1
    expected = (c * area + (weight * math.cos(dip) + 300.0) * math.tan(phi) + 900.0) / (
        weight * math.sin(dip)
    )
    assert float(solution.factor_of_safety) == pytest.approx(expected, rel=1e-12)
    assert np.allclose(solution.sliding_direction, dip_vector, atol=1e-12)
