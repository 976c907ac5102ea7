"""Stereonets (bbmc.outputs.stereonet, stereonet_figures): positions on the net against the closed-form
projections and bbmc's handedness, the friction cone, daylight envelope and great circles against their
definitions, the weighted density against hand-counted values, the zone fill against its mask, and the
figures of a synthetic survey."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure
from matplotlib.text import Text

from bbmc.geometry.orientation import downward, fisher_sample, line_vectors, poles, upward, upward_pole
from bbmc.outputs.stereonet import (
    COUNT_CONE,
    daylight_envelope,
    density_grid,
    fill_zone,
    friction_cone_angle,
    net_axes,
    net_coordinates,
    net_vectors,
    plot_cones,
    plot_friction_cone,
    plot_lateral_limits,
    plot_planes,
    plot_points,
)
from bbmc.outputs.stereonet_figures import (
    Face,
    KinematicMode,
    PoleSurvey,
    SetMeans,
    Zone,
    kinematic_figure,
    pole_figure,
)

CLOSED_FORM = {
    "equal_area": lambda theta: np.sqrt(2.0) * np.sin(theta / 2.0),  # Lambert, radius 1 at the primitive
    "equal_angle": lambda theta: np.tan(theta / 2.0),  # stereographic
}


@pytest.fixture(scope="module", params=sorted(CLOSED_FORM))
def net(request):
    fig = Figure(figsize=(5.0, 5.0), dpi=100)
    ax = net_axes(fig, (0.1, 0.1, 0.8, 0.8), projection=request.param)
    fig.draw_without_rendering()
    centre = ax.transData.transform(np.column_stack(net_coordinates(np.array([[0.0, 0.0, -1.0]]))))[0]
    north = ax.transData.transform(np.column_stack(net_coordinates(np.array([[0.0, 1.0, 0.0]]))))[0]
    return ax, request.param, centre, float(np.hypot(*(north - centre)))


def _on_net(ax, centre, radius, vectors):
    """Positions (n, 2) on a net of radius 1 (x right, y up) of the points drawn for `vectors`."""
    line = plot_points(ax, vectors)
    return (ax.transData.transform(np.column_stack(line.get_data())) - centre) / radius


def test_north_is_up_and_east_right(net):
    """The north end of the primitive is straight above the centre, the east end straight to its right
    (tolerance 1e-9 of the net's radius: the transform is exact up to rounding)."""
    ax, _, centre, radius = net
    xy = _on_net(ax, centre, radius, np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]))
    np.testing.assert_allclose(xy, [[0.0, 1.0], [1.0, 0.0], [-1.0, 0.0]], atol=1e-9)


def test_pole_of_a_plane_dipping_east_plots_west(net):
    """A plane dipping 60 deg towards 090: its pole plunges 30 deg towards 270, so it lies west of the
    centre, 60 deg from it: r = sqrt(2) sin 30 deg (equal area) or tan 30 deg (equal angle)."""
    ax, projection, centre, radius = net
    xy = _on_net(ax, centre, radius, poles(np.radians([60.0]), np.radians([90.0])))[0]
    np.testing.assert_allclose(xy, [-CLOSED_FORM[projection](np.radians(60.0)), 0.0], atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(trend=st.floats(0.0, 2.0 * np.pi), plunge=st.floats(0.0, np.pi / 2.0))
def test_projection_is_the_closed_form(net, trend, plunge):
    """A line of trend t and plunge p lies at r(90 deg - p) in the direction t clockwise from north:
    (r sin t, r cos t), r the closed form of the net's projection (tolerance 1e-7 of the radius:
    mplstereonet's latitude is an arcsine, which near its poles, the north and south points of the
    primitive, keeps about half the digits, sqrt(eps) = 1.5e-8 rad)."""
    ax, projection, centre, radius = net
    xy = _on_net(ax, centre, radius, line_vectors(np.array([trend]), np.array([plunge])))[0]
    r = CLOSED_FORM[projection](np.pi / 2.0 - plunge)
    np.testing.assert_allclose(xy, [r * np.sin(trend), r * np.cos(trend)], atol=1e-7)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 1e-3))
def test_net_coordinates_round_trip(vector):
    """Any vector comes back from the net as its lower-hemisphere sense (tolerance 1e-7, as for the
    projection; a horizontal vector may come back as its opposite, the same axis on the primitive)."""
    v = np.array(vector) / np.linalg.norm(vector)
    back = net_vectors(*net_coordinates(v[None]))[0]
    lower = -v if v[2] > 0 else v
    horizontal = abs(v[2]) < 1e-7
    assert min(np.linalg.norm(back - lower), np.linalg.norm(back + lower) if horizontal else 1.0) < 1e-7


def _drawn_vectors(artist) -> np.ndarray:
    """The downward unit vectors of the vertices of a drawn line or cone (in mplstereonet's lon, lat)."""
    if hasattr(artist, "get_data"):
        return net_vectors(*np.asarray(artist.get_data()))
    vertices = np.vstack([path.vertices for path in artist.get_paths()])
    return net_vectors(vertices[:, 0], vertices[:, 1])


@pytest.mark.parametrize("vectors, from_centre", [("poles", 30.0), ("lines", 60.0)])
def test_friction_cone_as_dips_draws_it(net, vectors, from_centre):
    """phi = 30 deg: on a pole plot the poles of planes dipping 30 deg, 30 deg from the centre; on a plot
    of lines the lines plunging 30 deg, 60 deg from it (Dips: pole and plane friction cones). Every
    vertex of the drawn circle is at that angle from the vertical (tolerance 1e-9 rad)."""
    ax = net[0]
    assert np.degrees(friction_cone_angle(np.radians(30.0), vectors)) == pytest.approx(from_centre)
    (cone,) = plot_friction_cone(ax, np.radians(30.0), vectors)
    angle = np.arccos(np.clip(-_drawn_vectors(cone)[:, 2], -1.0, 1.0))
    np.testing.assert_allclose(angle, np.radians(from_centre), atol=1e-9)


def test_cone_about_any_axis(net):
    """A 12 deg cone about a line plunging 5 deg (it crosses the primitive): every vertex of both drawn
    halves is 12 deg from the axis taken as an axis (tolerance 1e-9 rad)."""
    axis = line_vectors(np.radians(75.0), np.radians(5.0))
    (cone,) = plot_cones(net[0], axis[None], np.array([np.radians(12.0)]))
    angle = np.arccos(np.clip(np.abs(_drawn_vectors(cone) @ axis), 0.0, 1.0))
    np.testing.assert_allclose(angle, np.radians(12.0), atol=1e-9)


def test_great_circle_is_the_plane(net):
    """Every vertex of the great circle of the plane 35/250 lies in it: normal to its pole (1e-9)."""
    (circle,) = plot_planes(net[0], np.radians(35.0), np.radians(250.0))
    np.testing.assert_allclose(_drawn_vectors(circle) @ upward_pole(35.0, 250.0), 0.0, atol=1e-9)


def test_lateral_limits_are_radii_at_their_trends(net):
    """Limits +-20 deg about 350 deg: the two radii at trends 330 and 010 deg (tolerance 1e-9 rad)."""
    lines = plot_lateral_limits(net[0], np.radians(350.0), np.radians(20.0))
    for line, trend in zip(lines, (330.0, 10.0), strict=True):
        v = _drawn_vectors(line)[:-1]  # the last vertex is the centre, of no trend
        np.testing.assert_allclose(np.degrees(np.arctan2(v[:, 0], v[:, 1])) % 360.0, trend, atol=1e-7)


def test_daylight_envelope_poles_have_dip_vectors_in_the_face():
    """The envelope of the face 60/180: each plane's dip vector lies in the face (tolerance 1e-12)."""
    envelope = daylight_envelope(np.radians(60.0), np.radians(180.0))
    dip = np.arccos(envelope[:, 2])
    direction = np.arctan2(envelope[:, 0], envelope[:, 1])
    dip_vectors = line_vectors(direction, dip)
    np.testing.assert_allclose(dip_vectors @ upward_pole(60.0, 180.0), 0.0, atol=1e-12)


def test_schmidt_density_counts_weighted_readings():
    """Three readings at A (weight 3 each) and one at B, 90 deg apart: the Schmidt count reads at its
    peaks 100 % x 9 / 10 = 90 and 10 % per 1 % area, and 75 and 25 unweighted (grid nodes lie within
    the 8.1 deg counting cone of each point; tolerance 1e-9). The caller's weights are left untouched."""
    a, b = line_vectors(np.radians(20.0), np.radians(50.0)), line_vectors(np.radians(200.0), np.radians(40.0))
    vectors = np.array([a, a, a, b])
    weights = np.array([3.0, 3.0, 3.0, 1.0])
    for w, expected in ((None, (75.0, 25.0)), (weights, (90.0, 10.0))):
        lon, lat, density = density_grid(vectors, w)
        nodes = net_vectors(lon, lat)
        near = [np.arccos(np.clip(nodes @ v, -1, 1)) < COUNT_CONE for v in (a, b)]
        assert [density[m].max() for m in near] == pytest.approx(expected, abs=1e-9)
    np.testing.assert_array_equal(weights, [3.0, 3.0, 3.0, 1.0])


def test_weight_on_a_cluster_raises_its_density():
    """Two Fisher clusters of 60 (K = 40); weight 3 on the first raises its peak density and lowers
    the second's (peaks within 15 deg of each mean)."""
    rng = np.random.default_rng(2)
    means = [line_vectors(np.radians(t), np.radians(p)) for t, p in ((45.0, 40.0), (250.0, 60.0))]
    vectors = np.vstack([fisher_sample(m, 40.0, 60, rng) for m in means])
    peaks = []
    for weights in (np.ones(120), np.r_[np.full(60, 3.0), np.ones(60)]):
        lon, lat, density = density_grid(vectors, weights)
        nodes = net_vectors(lon, lat)
        peaks.append([density[np.arccos(np.clip(nodes @ m, -1, 1)) < np.radians(15.0)].max() for m in means])
    assert peaks[1][0] > 1.3 * peaks[0][0]
    assert peaks[1][1] < 0.8 * peaks[0][1]


def _cone_zone(axis: np.ndarray, half_angle: float):
    return lambda points: np.abs(points @ axis) > np.cos(half_angle)


@pytest.mark.parametrize("trend, plunge", [(200.0, 30.0), (80.0, 4.0)])
def test_zone_fill_agrees_with_its_mask(net, trend, plunge):
    """The filled region of a 35 deg cone (one crossing the primitive too) contains, on the drawn net, the
    sample points the mask calls True and no other, except within 1 deg of the cone's edge (the fill's
    grid step is 0.5 deg) and within 0.1 deg of the primitive (where the fill's edge is a polygon of
    chords, clipped by the primitive anyway)."""
    ax, _, _, _ = net
    axis, half = line_vectors(np.radians(trend), np.radians(plunge)), np.radians(35.0)
    filled = fill_zone(ax, _cone_zone(axis, half), "tab:red")
    rng = np.random.default_rng(5)
    points = rng.normal(size=(4000, 3))
    points /= np.linalg.norm(points, axis=1, keepdims=True)
    points = downward(points)
    display = ax.transData.transform(np.column_stack(net_coordinates(points)))
    inside = np.zeros(len(points), dtype=bool)
    for path in filled.get_paths():
        inside |= ax.transData.transform_path(path).contains_points(display)
    angle = np.arccos(np.clip(np.abs(points @ axis), 0.0, 1.0))
    clear = (np.abs(angle - half) > np.radians(1.0)) & (-points[:, 2] > np.sin(np.radians(0.1)))
    np.testing.assert_array_equal(inside[clear], _cone_zone(axis, half)(points)[clear])
    assert inside[clear].sum() > 300


def test_unknown_projection_and_density_method_are_refused():
    with pytest.raises(ValueError, match="projection"):
        net_axes(Figure(), (0, 0, 1, 1), projection="polar")
    with pytest.raises(ValueError, match="method"):
        density_grid(np.array([[0.0, 0.0, -1.0]]), method="linear_kamb")


@pytest.fixture(scope="module")
def survey():
    rng = np.random.default_rng(34)
    sets = [(60.0, 170.0, 40.0, 50), (75.0, 270.0, 30.0, 40), (20.0, 30.0, 60.0, 30)]
    normals = [fisher_sample(upward_pole(d, dd), k, n, rng) for d, dd, k, n in sets]
    normals.append(rng.normal(size=(20, 3)))
    normals = np.vstack(normals)
    normals = upward(normals / np.linalg.norm(normals, axis=1, keepdims=True))
    labels = np.repeat([0, 1, 2, -1], [50, 40, 30, 20])
    weights = np.minimum(1.0 / np.abs(normals @ upward_pole(60.0, 180.0)), 3.86)
    return PoleSurvey(normals, labels, weights, 3.86)


def _texts(fig: Figure) -> str:
    """All the figure's text, its lines joined by single spaces (the legend wraps long entries)."""
    return " ".join(" ".join(t.get_text() for t in fig.findobj(Text)).split())


def test_pole_figure_is_written_and_names_what_it_shows(survey, tmp_path):
    means = SetMeans(
        np.arange(3),
        np.array([upward_pole(60, 170), upward_pole(75, 270), upward_pole(20, 30)]),
        np.radians([3.0, 4.0, 5.0]),
    )
    fig = pole_figure(survey, means, Face(np.radians(60.0), np.radians(180.0)))
    fig.savefig(tmp_path / "poles.png")
    text = _texts(fig)
    for expected in (
        "set 1 (n = 50)",
        "set 2 (n = 40)",
        "set 3 (n = 30)",
        "random (n = 20)",
        "equal-area",
        "lower hemisphere",
        "140 readings",
        "capped at 3.86",
        "slope face 60/180",
        "% of weighted readings per 1 % area",
        "set 1 mean 60/170, α95 = 3.0°",
    ):
        assert expected in text
    assert f"Terzaghi-weighted total {survey.weights.sum():.1f}" in text
    assert (tmp_path / "poles.png").stat().st_size > 10_000


def test_kinematic_figure_counts_points_by_the_mask(survey, tmp_path):
    """The zone's count in the legend is the mask's count over the lower-hemisphere poles."""
    face, phi = Face(np.radians(60.0), np.radians(180.0)), np.radians(30.0)
    zone = _cone_zone(line_vectors(0.0, np.radians(30.0)), np.radians(20.0))
    mode = KinematicMode(
        "planar sliding",
        "poles",
        (Zone("critical zone", zone, "tab:red"),),
        (face.dip_direction + np.pi, np.radians(20.0)),
    )
    fig = kinematic_figure(mode, face, phi, survey=survey, projection="equal_angle")
    fig.savefig(tmp_path / "planar.png")
    count = int(zone(-survey.poles).sum())
    text = _texts(fig)
    assert f"critical zone: {count} of 140 poles" in text
    for expected in (
        "equal-angle",
        "lower hemisphere",
        "friction cone, φ = 30° (30° from the centre)",
        "daylight envelope",
        "lateral limits ±20°",
        "face 60/180",
    ):
        assert expected in text


def test_kinematic_references_follow_the_mode(tmp_path):
    """A mode of lines draws the plane friction cone (60 deg from the centre for phi = 30 deg) and no
    daylight envelope; a mode that uses neither cone nor envelope (flexural toppling) draws neither."""
    face, phi = Face(np.radians(60.0), np.radians(180.0)), np.radians(30.0)
    zone = Zone("zone", lambda points: points[:, 1] < 0.0, "tab:red")
    lines = line_vectors(np.radians([170.0, 10.0]), np.radians([45.0, 20.0]))
    wedge = kinematic_figure(KinematicMode("wedge sliding", "lines", (zone,)), face, phi, lines=lines)
    text = _texts(wedge)
    assert "(60° from the centre)" in text and "daylight envelope" not in text
    assert "zone: 1 of 2 lines (50.0 %)" in text
    toppling = KinematicMode("flexural toppling", "poles", (zone,), friction_cone=False, daylight=False)
    text = _texts(kinematic_figure(toppling, face, phi))
    assert "friction cone" not in text and "daylight envelope" not in text
