"""The wedge's geometry: Hoek & Bray's classic wedge, hand-worked and independent checks, invariance,
batches, and the wedges that cannot form."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from bbmc.slope.wedge.geometry import (
    TensionCrack,
    WedgeNotFormedError,
    WedgeReason,
    wedge_geometries,
    wedge_geometry,
)

R = np.radians
# Hoek & Bray's classic wedge (Rock Slope Engineering 1981, ch. 8; issue 35): planes 45/105 and 70/235,
# face 65/185, upper surface 12/195; H1 = 100 ft.
CLASSIC = (R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))


def _classic(**kwargs):
    kwargs.setdefault("height_h1", 100.0)
    return wedge_geometry(*CLASSIC, **kwargs)


def test_classic_wedge_total_height_is_130_ft():
    """The issue: H1 100 ft, so H 130 ft. Measured H = 129.998 ft: Hoek & Bray's 130 is this rounded to
    3 figures; tolerance 0.01 ft (1e-4 of H), and back from H = 130 ft to H1 within the same."""
    geometry = _classic()
    assert geometry.height_h1 == pytest.approx(100.0, abs=1e-9)
    assert geometry.height_h == pytest.approx(130.0, abs=0.01)
    assert wedge_geometry(*CLASSIC, height_h=130.0).height_h1 == pytest.approx(100.0, abs=0.01)


def test_classic_wedge_factor_is_1_505():
    """K = sin beta / sin(xi / 2) = 1.505 for the classic wedge (issue 35), to its 4 figures."""
    assert _classic().short_solution.wedge_factor == pytest.approx(1.505, abs=5e-4)


def test_classic_wedge_line_of_intersection_by_hoek_and_brays_formulas():
    """The trend and plunge of the line of intersection by Hoek & Bray's closed forms (1981, ch. 8):
    tan alpha_i = (tan psi_A cos alpha_A - tan psi_B cos alpha_B) / (tan psi_B sin alpha_B -
    tan psi_A sin alpha_A), tan psi_i = tan psi_A cos(alpha_A - alpha_i); to 1e-9 rad."""
    geometry = _classic()
    dir_a, dir_b, ta, tb = CLASSIC[1], CLASSIC[3], np.tan(CLASSIC[0]), np.tan(CLASSIC[2])
    trend = np.arctan((ta * np.cos(dir_a) - tb * np.cos(dir_b)) / (tb * np.sin(dir_b) - ta * np.sin(dir_a)))
    trend = np.mod(trend + np.pi * (ta * np.cos(dir_a - trend) < 0), 2 * np.pi)  # the downward sense
    plunge = np.arctan(ta * np.cos(dir_a - trend))
    assert geometry.trend == pytest.approx(trend, abs=1e-9)
    assert geometry.plunge == pytest.approx(plunge, abs=1e-9)
    assert np.degrees(geometry.plunge) == pytest.approx(31.2, abs=0.05)  # Hoek & Bray's psi_i = 31.2 deg


def test_classic_wedge_stereonet_angles():
    """Hoek & Bray's (1981) short-solution example reads these angles off the stereonet, to about 1 deg:
    theta_na.nb 101, theta_24 65, theta_45 25, theta_2.na 50, theta_13 62, theta_35 31, theta_1.nb 60
    (deg). Source: the worked example as remembered by this test's author; the book's page was not
    in the searchable corpus, so this is a check of conventions (tolerance 1 deg), not a citation."""
    s = _classic().short_solution
    measured = np.degrees(
        [s.theta_na_nb, s.theta_24, s.theta_45, s.theta_2_na, s.theta_13, s.theta_35, s.theta_1_nb]
    )
    assert measured == pytest.approx([101, 65, 25, 50, 62, 31, 60], abs=1.0)


def test_short_solution_factors_give_the_issue_factors_of_safety():
    """Hoek & Bray's short solution with this geometry's X, Y, A, B and H, and the issue's strengths
    (c_A 500 psf, c_B 1000 psf, phi_A 20, phi_B 30 deg, gamma 160 pcf, gamma_w 62.5 pcf), gives the FS
    the issue computed independently by the vector solution: 1.8464 dry and 1.2180 with Hoek & Bray's
    water, each within 5e-4 (the issue's tolerance)."""
    g = _classic()
    s, ratio = g.short_solution, 62.5 / (2 * 160.0)
    cohesion = 3.0 / (160.0 * g.height_h) * (500.0 * s.x + 1000.0 * s.y)
    dry = cohesion + s.a * np.tan(R(20)) + s.b * np.tan(R(30))
    wet = cohesion + (s.a - ratio * s.x) * np.tan(R(20)) + (s.b - ratio * s.y) * np.tan(R(30))
    assert dry == pytest.approx(1.8464, abs=5e-4)
    assert wet == pytest.approx(1.2180, abs=5e-4)


def test_x_and_y_agree_with_areas_and_volume():
    """Two paths to the short solution's X and Y: the sine rule on the stereonet angles, and
    X = A_1 H / (3 V sin psi_i), Y = A_2 H / (3 V sin psi_i) from the areas and volume; to 1e-12."""
    g = _classic()
    s, denominator = g.short_solution, 3.0 * g.volume * np.sin(g.plunge)
    assert s.x == pytest.approx(g.area_1 * g.height_h / denominator, rel=1e-12)
    assert s.y == pytest.approx(g.area_2 * g.height_h / denominator, rel=1e-12)


def _statics_reactions(g):
    """Normal reactions (per unit weight) on planes 1 and 2 under gravity alone, solved from
    N1 n1 + N2 n2 = z - (z . l) l."""
    z = np.array([0.0, 0.0, 1.0])
    load = z - (z @ g.line) * g.line
    matrix = np.column_stack([g.normal_1, g.normal_2])
    return np.linalg.lstsq(matrix, load, rcond=None)[0]


def test_wedge_factor_and_a_b_against_statics():
    """K = (N1 + N2) / (W cos psi_i) and A, B = N1, N2 / (W sin psi_i) with N1, N2 from a direct 3D
    solve of the normal reactions; to 1e-12."""
    g = _classic()
    n1, n2 = _statics_reactions(g)
    assert g.short_solution.wedge_factor == pytest.approx((n1 + n2) / np.cos(g.plunge), rel=1e-12)
    assert g.short_solution.a == pytest.approx(n1 / np.sin(g.plunge), rel=1e-12)
    assert g.short_solution.b == pytest.approx(n2 / np.sin(g.plunge), rel=1e-12)


def test_symmetric_wedge_by_hand():
    """Planes 45/135 and 45/225, vertical face 90/180, horizontal upper surface, H = h: the toe at O,
    C1 = (-sqrt2 h, 0, h), C2 = (sqrt2 h, 0, h), T = (0, sqrt2 h, h); V = 2 h^3 / 3, A_1 = A_2 =
    A_face = sqrt2 h^2, A_upper = 2 h^2; xi = 120 deg, beta = 90 deg, K = 1 / sin 60 deg. To 1e-12."""
    h = 7.0
    g = wedge_geometry(R(45), R(135), R(45), R(225), R(90), R(180), 0.0, 0.0, height_h=h)
    r2 = np.sqrt(2.0)
    assert g.crest_1 == pytest.approx([-r2 * h, 0, h], abs=1e-12)
    assert g.crest_2 == pytest.approx([r2 * h, 0, h], abs=1e-12)
    assert g.top == pytest.approx([0, r2 * h, h], abs=1e-12)
    assert g.height_h1 == pytest.approx(h, rel=1e-12)
    assert g.volume == pytest.approx(2 * h**3 / 3, rel=1e-12)
    areas = [g.area_1, g.area_2, g.area_face, g.area_upper]
    assert areas == pytest.approx([r2 * h**2, r2 * h**2, r2 * h**2, 2 * h**2], rel=1e-12)
    s = g.short_solution
    assert np.degrees([s.included_angle, s.bisector_angle]) == pytest.approx([120, 90], abs=1e-9)
    assert s.wedge_factor == pytest.approx(1 / np.sin(R(60)), rel=1e-12)


def _closure(g):
    """sum over faces of area x outward normal (0 for a closed polyhedron)."""
    return (
        g.area_face[..., None] * g.normal_face
        + g.area_upper[..., None] * g.normal_upper
        - g.area_1[..., None] * g.normal_1
        - g.area_2[..., None] * g.normal_2
        - np.nan_to_num(g.area_crack[..., None] * g.normal_crack)
    )


@pytest.mark.parametrize("crack", [None, TensionCrack(R(70), R(165), 40.0)], ids=["no crack", "crack"])
def test_volume_against_convex_hull_and_areas_close(crack):
    """The volume against scipy's convex hull of the vertices (rel 1e-10) and the centroid against the
    hull's facets (1e-9 of the wedge's length); the faces' areas times their
    outward normals sum to 0 (a closed surface, to 1e-9 of the largest area); the areas sum to the
    hull's surface area (rel 1e-10). The crack is Hoek & Bray's 70/165 at L = 40 ft."""
    g = _classic(crack=crack)
    hull = ConvexHull(g.vertices)
    assert g.volume == pytest.approx(hull.volume, rel=1e-10)
    inside = g.vertices.mean(axis=0)  # the centroid by tetrahedra from an inner point to each facet
    corners = g.vertices[hull.simplices]
    parts = np.abs(
        np.einsum(
            "ij,ij->i", corners[:, 0] - inside, np.cross(corners[:, 1] - inside, corners[:, 2] - inside)
        )
    )
    centres = (corners.sum(axis=1) + inside) / 4.0
    assert g.centroid == pytest.approx(parts @ centres / parts.sum(), abs=1e-9 * g.intersection_length)
    total = g.area_1 + g.area_2 + g.area_face + g.area_upper + g.area_crack
    assert total == pytest.approx(hull.area, rel=1e-10)
    assert np.abs(_closure(g)).max() < 1e-9 * g.area_2
    if crack is not None:
        centre = g.vertices.mean(axis=0)
        assert g.normal_crack @ (centre - g.crack_foot) > 0  # the crack's normal points into the wedge


def test_crack_truncates_the_tetrahedron():
    """The crack's wedge is the tetrahedron less the piece T P Q R; P lies L = 40 ft from C1 along
    plane 1's trace on the upper surface; faces on the face are unchanged (to 1e-9)."""
    whole, cut = _classic(), _classic(crack=TensionCrack(R(70), R(165), 40.0))
    assert np.linalg.norm(cut.crack_1 - cut.crest_1) == pytest.approx(40.0, rel=1e-12)
    assert cut.trace_upper_1 == pytest.approx(40.0, rel=1e-12)
    assert cut.area_face == pytest.approx(whole.area_face, rel=1e-12)
    assert 0 < cut.volume < whole.volume
    assert cut.height_h == pytest.approx(whole.height_h, rel=1e-12)


def test_scaling_with_height():
    """Doubling H1 doubles lengths, quadruples areas and multiplies the volume by 8 (rel 1e-12)."""
    a, b = _classic(), _classic(height_h1=200.0)
    assert b.trace_face_2 == pytest.approx(2 * a.trace_face_2, rel=1e-12)
    assert b.area_upper == pytest.approx(4 * a.area_upper, rel=1e-12)
    assert b.volume == pytest.approx(8 * a.volume, rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(turn=st.floats(-360.0, 360.0), crack=st.booleans())
def test_rotation_about_the_vertical_changes_no_measure(turn, crack):
    """Turning every dip direction by the same angle turns the wedge about the vertical: areas, volume,
    heights and angles stay (rel 1e-9), the points turn with it."""
    shift = R(turn)
    turned = tuple(v + shift if i % 2 else v for i, v in enumerate(CLASSIC))
    tension = TensionCrack(R(70), R(165) + shift, 40.0) if crack else None
    base = _classic(crack=TensionCrack(R(70), R(165), 40.0) if crack else None)
    other = wedge_geometry(*turned, height_h1=100.0, crack=tension)
    for name in ("area_1", "area_2", "area_face", "area_upper", "area_crack", "volume", "height_h"):
        assert getattr(other, name) == pytest.approx(getattr(base, name), rel=1e-9, abs=1e-9)
    assert other.short_solution.wedge_factor == pytest.approx(base.short_solution.wedge_factor, rel=1e-9)
    c, s = np.cos(shift), np.sin(shift)
    rotation = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])  # clockwise from north by `shift`
    assert other.top == pytest.approx(rotation @ base.top, abs=1e-9 * base.intersection_length)


def test_a_batch_equals_one_wedge_at_a_time():
    """Random wedges in one call equal the same wedges one by one (to 1e-12), formed or not, and the
    formed ones close (sum of area x normal = 0)."""
    rng = np.random.default_rng(35)
    n = 200
    dips = R(rng.uniform(10, 85, (n, 2)))
    directions = R(rng.uniform(100, 280, (n, 2)))
    args = (dips[:, 0], directions[:, 0], dips[:, 1], directions[:, 1], R(70), R(180), R(10), R(190))
    batch = wedge_geometries(*args, height_h1=20.0)
    assert 20 < batch.formed.sum() < n  # both kinds are in the sample
    for i in range(n):
        one = wedge_geometries(*(np.asarray(a)[i] if np.ndim(a) else a for a in args), height_h1=20.0)
        assert one.reason == batch.reason[i]
        assert np.array_equal(np.isnan(one.volume), np.isnan(batch.volume[i]))
        if one.reason == 0:
            assert one.volume == pytest.approx(batch.volume[i], rel=1e-12)
            assert one.short_solution.wedge_factor == pytest.approx(batch.short_solution.wedge_factor[i])
    formed = batch.formed
    closure = np.linalg.norm(_closure(batch)[formed], axis=-1)
    assert np.all(closure < 1e-9 * batch.area_1[formed] + 1e-9 * batch.area_2[formed])


def test_overhanging_face_by_its_key():
    """An overhanging face (80 deg, leaning out over the toe) by the explicit key: the face's outward
    normal points down and out, the wedge closes and its volume is the convex hull's (rel 1e-10); the
    same plane entered without the key is a face leaning the other way, a different wedge."""
    args = (R(45), R(120), R(50), R(240), R(80), R(180), R(5), R(180))
    g = wedge_geometry(*args, height_h1=10.0, overhanging_face=True)
    assert g.normal_face[2] < 0 and g.normal_face[1] < 0
    assert g.volume == pytest.approx(ConvexHull(g.vertices).volume, rel=1e-10)
    assert np.abs(_closure(g)).max() < 1e-9 * g.area_1
    assert wedge_geometry(*args, height_h1=10.0).volume != pytest.approx(g.volume, rel=1e-3)


@pytest.mark.parametrize(
    ("args", "kwargs", "reason"),
    [
        ((45, 105, 45, 105, 65, 185, 12, 195), {}, WedgeReason.PARALLEL_PLANES),
        ((75, 160, 80, 210, 65, 185, 12, 195), {}, WedgeReason.NOT_DAYLIGHTING),  # steeper than the face
        ((40, 20, 50, 340, 65, 185, 12, 195), {}, WedgeReason.NOT_DAYLIGHTING),  # into the slope
        ((20, 150, 25, 215, 65, 185, 20, 185), {}, WedgeReason.NOT_OUTCROPPING),  # flatter than the upper
        ((45, 105, 70, 235, 20, 185, 30, 185), {}, WedgeReason.SLOPE_NOT_CONVEX),
        ((45, 105, 70, 235, 65, 185, 12, 195), {"crack": (70, 165, 400.0)}, WedgeReason.CRACK_OUTSIDE),
        ((45, 105, 70, 235, 65, 185, 12, 195), {"crack": (90, 90, 40.0)}, WedgeReason.CRACK_OUTSIDE),
    ],
    ids=[
        "parallel",
        "too steep",
        "into slope",
        "too flat",
        "face flatter",
        "crack beyond",
        "crack cuts face",
    ],
)
def test_wedges_that_cannot_form(args, kwargs, reason):
    """Each cannot-form case gives its reason: NaN in a batch, WedgeNotFormedError for one wedge."""
    if "crack" in kwargs:
        dip, direction, distance = kwargs["crack"]
        kwargs = {"crack": TensionCrack(R(dip), R(direction), distance)}
    radians = tuple(R(a) for a in args)
    batch = wedge_geometries(*radians, height_h1=100.0, **kwargs)
    assert batch.reason == reason
    assert np.isnan(batch.volume) and np.all(np.isnan(batch.top))
    with pytest.raises(WedgeNotFormedError, match="no wedge"):
        wedge_geometry(*radians, height_h1=100.0, **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [({"height_h1": 0.0}, "height_h1"), ({"height_h1": 1.0, "height_h": 1.0}, "height_h1, height_h")],
)
def test_bad_heights_name_their_key(kwargs, key):
    with pytest.raises(ValueError, match=key):
        wedge_geometries(*CLASSIC, **kwargs)


def test_bad_dip_names_its_key():
    with pytest.raises(ValueError, match="dip_2"):
        wedge_geometries(R(45), R(105), R(95), R(235), R(65), R(185), R(12), R(195), height_h1=1.0)
