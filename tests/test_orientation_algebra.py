"""The orientation algebra (bbmc.geometry.orientation, bbmc.geometry.conventions): every conversion
round-trips over the whole sphere (property tests, with vertical and horizontal planes and lines as
explicit cases); the intersection of two planes and apparent dips against hand-worked and published
values; Fisher's sampler against Fisher's law, its K and mean recovered; oriented core's alpha and beta
against a hand-worked example, its special cases and its inverse.

Tolerances: the round trips hold to 1e-9 rad except where an angle comes back through arccos or arcsin
near 1 (a dip near 0, a plunge near 90 deg), where double precision gives about sqrt(2.2e-16) = 1.5e-8
rad: those compare 1e-7. Hand-worked values are given to 4 decimals of a degree and compared to 1e-4 deg.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy import stats

from bbmc.geometry.conventions import (
    CORE_REFERENCES,
    core_poles,
    dip_direction_of_strike,
    plane_of_pole_trend_and_plunge,
    strike_of_dip_direction,
    top_of_core,
    true_azimuth,
)
from bbmc.geometry.orientation import (
    apparent_dip,
    dip_and_direction,
    fisher_deviation_cdf,
    fisher_sample,
    intersection_lines,
    line_vectors,
    plane_of_pole,
    pole_trend_and_plunge,
    poles,
    trend_and_plunge,
    wrapped_azimuth,
)

HALF_PI, TWO_PI = np.pi / 2.0, 2.0 * np.pi
DIPS = st.floats(0.0, HALF_PI)
AZIMUTHS = st.floats(0.0, TWO_PI, exclude_max=True)
PLUNGES = st.floats(0.0, HALF_PI)
SPHERE = settings(max_examples=300, deadline=None)


def _same_azimuth(a, b, tol=1e-9):
    """Azimuths equal modulo 2 pi."""
    return abs((a - b + np.pi) % TWO_PI - np.pi) <= tol


def _deg(*values):
    return np.radians(values)


# ---------------------------------------------------------------------------------------------------
# planes: dip / dip direction <-> pole vector <-> pole trend and plunge <-> strike (right-hand rule)


@SPHERE
@given(DIPS, AZIMUTHS)
@example(0.0, 1.0)  # horizontal plane
@example(HALF_PI, 0.0)  # vertical planes, both senses of the strike
@example(HALF_PI, np.pi)
@example(HALF_PI, 3.0 * HALF_PI)
def test_dip_and_direction_round_trip_through_the_upward_pole(dip, direction):
    pole = poles(dip, direction)
    assert np.linalg.norm(pole) == pytest.approx(1.0, abs=1e-12)
    assert pole[2] >= 0.0  # upward
    back_dip, back_direction = np.radians(plane_of_pole(pole[None]))
    assert back_dip[0] == pytest.approx(dip, abs=1e-7)
    if dip > 1e-6:  # a horizontal plane has no dip direction
        assert _same_azimuth(back_direction[0], direction, 1e-7)


@SPHERE
@given(DIPS, AZIMUTHS)
@example(0.0, 0.0)
@example(HALF_PI, 0.5)
def test_the_pole_trend_and_plunge_is_the_downward_normal_and_gives_the_plane_back(dip, direction):
    trend, plunge = pole_trend_and_plunge(dip, direction)
    assert 0.0 <= plunge <= HALF_PI
    np.testing.assert_allclose(line_vectors(trend, plunge), -poles(dip, direction), atol=1e-12)
    back_dip, back_direction = plane_of_pole_trend_and_plunge(trend, plunge)
    assert back_dip == pytest.approx(dip, abs=1e-12)
    assert _same_azimuth(back_direction, direction)
    # and from the vector alone, through trend_and_plunge (lower hemisphere)
    vector_trend, vector_plunge = trend_and_plunge(-poles(dip, direction))
    assert vector_plunge == pytest.approx(plunge, abs=1e-7)
    if dip > 1e-6:
        assert _same_azimuth(vector_trend, trend, 1e-7)


@SPHERE
@given(DIPS, AZIMUTHS)
@example(HALF_PI, 0.0)
@example(0.3, TWO_PI - 1e-12)
def test_strike_by_the_right_hand_rule_round_trips_and_the_plane_dips_to_its_right(dip, direction):
    strike = strike_of_dip_direction(direction)
    assert 0.0 <= strike < TWO_PI
    assert _same_azimuth(dip_direction_of_strike(strike), direction)
    pole = poles(dip, direction)
    along = np.array([np.sin(strike), np.cos(strike), 0.0])  # the strike line
    right = np.array([np.cos(strike), -np.sin(strike), 0.0])  # 90 deg clockwise of it, looking down
    assert pole @ along == pytest.approx(0.0, abs=1e-12)  # the strike line lies in the plane
    assert pole @ right == pytest.approx(np.sin(dip), abs=1e-12)  # it dips to the right


def test_strike_and_dip_direction_by_hand():
    """Strike 030 (RHR) dips to 120; strike 300 to 030; dip direction 045 has strike 315."""
    assert np.degrees(dip_direction_of_strike(np.radians(30.0))) == pytest.approx(120.0)
    assert np.degrees(dip_direction_of_strike(np.radians(300.0))) == pytest.approx(30.0)
    assert np.degrees(strike_of_dip_direction(np.radians(45.0))) == pytest.approx(315.0)


# ---------------------------------------------------------------------------------------------------
# lines: trend and plunge <-> unit vectors, both hemispheres


@SPHERE
@given(AZIMUTHS, PLUNGES)
@example(1.0, HALF_PI)  # vertical line
@example(0.0, 0.0)  # horizontal lines
@example(np.pi, 0.0)
def test_line_vectors_round_trip_and_either_sense_gives_the_same_lower_hemisphere_line(trend, plunge):
    vector = line_vectors(trend, plunge)
    assert np.linalg.norm(vector) == pytest.approx(1.0, abs=1e-12)
    assert vector[2] <= 0.0
    for sense in (vector, -vector):
        back_trend, back_plunge = trend_and_plunge(sense)
        assert back_plunge == pytest.approx(plunge, abs=1e-7)
        if plunge < HALF_PI - 1e-6 and not (sense is not vector and plunge == 0.0):
            assert _same_azimuth(back_trend, trend, 1e-7)
    if plunge == 0.0:  # a horizontal line keeps the sense it was given in
        assert _same_azimuth(trend_and_plunge(-vector)[0], trend + np.pi, 1e-9)


def test_vertical_and_horizontal_cases_by_hand():
    np.testing.assert_allclose(line_vectors(0.7, HALF_PI), [0.0, 0.0, -1.0], atol=1e-15)
    np.testing.assert_allclose(line_vectors(HALF_PI, 0.0), [1.0, 0.0, 0.0], atol=1e-15)  # east
    np.testing.assert_allclose(poles(0.0, 2.0), [0.0, 0.0, 1.0], atol=1e-15)  # horizontal plane
    np.testing.assert_allclose(poles(HALF_PI, np.pi), [0.0, -1.0, 0.0], atol=1e-15)  # vertical, E-W
    assert np.degrees(trend_and_plunge(np.array([0.0, 0.0, 1.0]))[1]) == pytest.approx(90.0)


@SPHERE
@given(st.floats(-1e-12, 0.0, exclude_max=True), st.floats(0.1, 1.0), st.floats(0.0, 1.0))
@example(-1e-20, 1.0, 0.5)  # atan2 = -1e-20: -1e-20 mod 2 pi rounds to exactly 2 pi
@example(-5e-324, 1.0, 0.0)  # the smallest negative float, a horizontal line
def test_azimuths_just_west_of_north_lie_in_the_half_open_turn(west, north, height):
    """A vector a hair west of north has atan2(x, y) a tiny negative angle, whose modulo 2 pi (or 360
    deg) rounds up to exactly 2 pi (360 deg): trend_and_plunge, plane_of_pole, dip_and_direction and
    pole_trend_and_plunge all give 0 there, and every azimuth lies in [0, 2 pi) or [0, 360)."""
    trend, _ = trend_and_plunge(np.array([west, north, -height]))
    assert 0.0 <= trend < TWO_PI
    _, direction = plane_of_pole(np.array([[west, north, height]]))
    assert 0.0 <= direction[0] < 360.0
    assert 0.0 <= dip_and_direction(np.array([west, north, height]))[1] < TWO_PI
    assert 0.0 <= pole_trend_and_plunge(0.5, west - np.pi)[0] < TWO_PI


def test_wrapped_azimuth_by_hand():
    """Exact values: a tiny negative angle is 0, not the full turn; a turn and a bit is the bit."""
    assert wrapped_azimuth(-1e-20) == 0.0
    assert wrapped_azimuth(-1e-20, 360.0) == 0.0
    assert wrapped_azimuth(TWO_PI) == 0.0
    assert wrapped_azimuth(-HALF_PI) == pytest.approx(3.0 * HALF_PI, abs=1e-15)
    np.testing.assert_array_equal(
        wrapped_azimuth(np.array([370.0, -10.0, -1e-14]), 360.0), [10.0, 350.0, 0.0]
    )


def test_declination_is_added_east_positive_modulo_360():
    assert np.degrees(true_azimuth(np.radians(350.0), np.radians(15.0))) == pytest.approx(5.0)
    assert np.degrees(true_azimuth(np.radians(5.0), np.radians(-12.5))) == pytest.approx(352.5)


# ---------------------------------------------------------------------------------------------------
# intersections and apparent dips


def test_intersection_of_two_symmetric_planes_by_hand():
    """Planes 60/090 and 60/180: poles n1 = (sin 60, 0, cos 60) = (0.8660, 0, 0.5) and n2 = (0, -0.8660,
    0.5); n1 x n2 = (0.4330, -0.4330, -0.75), of length sqrt(0.9375) = 0.9682, so the line points down
    at trend atan2(0.4330, -0.4330) = 135 deg and plunge asin(0.75 / 0.9682) = 50.7685 deg, which is
    also each plane's apparent dip along 135: atan(tan 60 cos 45) = atan(1.2247) = 50.7685 deg."""
    line, sine = intersection_lines(poles(*_deg(60, 90)), poles(*_deg(60, 180)))
    trend, plunge = np.degrees(trend_and_plunge(line))
    assert trend == pytest.approx(135.0, abs=1e-4)
    assert plunge == pytest.approx(50.7685, abs=1e-4)
    assert sine == pytest.approx(np.sqrt(0.9375), abs=1e-12)
    assert np.degrees(apparent_dip(*_deg(60, 90, 135))) == pytest.approx(50.7685, abs=1e-4)


def test_intersection_against_a_published_example():
    """CREALP's MatterCliff help ("Wedges" tool): planes of dip direction / dip 195/20 and 045/35 meet
    along the line 124.8 / 7 (trend / plunge) at an angle of 53.13 deg. Trend and plunge are compared to
    half a unit of their last printed digit. The angle between the poles is exactly acos(sin 20 sin 35
    cos 150 + cos 20 cos 35) = acos(0.59986) = 53.140 deg, 0.01 deg off the printed 53.13 (rounding
    inside the tool, it seems): compared to 0.02 deg."""
    line, sine = intersection_lines(poles(*_deg(20, 195)), poles(*_deg(35, 45)))
    trend, plunge = np.degrees(trend_and_plunge(line))
    assert trend == pytest.approx(124.8, abs=0.05)
    assert plunge == pytest.approx(7.0, abs=0.5)
    assert np.degrees(np.arcsin(sine)) == pytest.approx(53.13, abs=0.02)


@SPHERE
@given(DIPS, AZIMUTHS, DIPS, AZIMUTHS)
def test_the_intersection_lies_in_both_planes_and_points_down(dip_1, direction_1, dip_2, direction_2):
    n1, n2 = poles(dip_1, direction_1), poles(dip_2, direction_2)
    line, sine = intersection_lines(n1, n2)
    if sine <= 1e-9:
        assert np.isnan(line).all()
        return
    assert line[2] <= 0.0
    assert abs(line @ n1) < 1e-9 and abs(line @ n2) < 1e-9


def test_apparent_dips_by_hand():
    """tan(apparent dip) = tan(dip) cos(trend - dip direction): the plane 60/090 along 090 dips 60, along
    180 (its strike) 0, along 270 -60 (it rises); the plane 40/120 along 150: tan 40 cos 30 = 0.83910 x
    0.86603 = 0.72668, atan = 36.0052 deg."""
    for trend, expected in ((90, 60.0), (180, 0.0), (270, -60.0)):
        assert np.degrees(apparent_dip(*_deg(60, 90, trend))) == pytest.approx(expected, abs=1e-9)
    assert np.degrees(apparent_dip(*_deg(40, 120, 150))) == pytest.approx(36.0052, abs=1e-4)


@SPHERE
@given(st.floats(0.0, HALF_PI - 1e-6), AZIMUTHS, AZIMUTHS)
def test_an_apparent_dip_never_exceeds_the_true_dip(dip, direction, trend):
    seen = apparent_dip(dip, direction, trend)
    assert abs(seen) <= dip + 1e-12
    assert apparent_dip(dip, direction, direction) == pytest.approx(dip, abs=1e-12)


# ---------------------------------------------------------------------------------------------------
# Fisher's sampler


MEAN = np.array([0.3, -0.5, 0.81]) / np.linalg.norm([0.3, -0.5, 0.81])


@pytest.mark.parametrize("kappa", [2.0, 10.0, 100.0])
def test_fisher_sample_angles_follow_fishers_law(kappa):
    """The angles from the mean of 2,000 draws against Fisher's distribution of them (KS test, p > 1e-3);
    the test has the power to see a K off by 20 % either way (p < 1e-6 then)."""
    sample = fisher_sample(MEAN, kappa, 2000, np.random.default_rng(1))
    assert np.linalg.norm(sample, axis=1) == pytest.approx(np.ones(2000), abs=1e-12)
    theta = np.arccos(np.clip(sample @ MEAN, -1.0, 1.0))
    assert stats.kstest(theta, lambda t: fisher_deviation_cdf(t, kappa)).pvalue > 1e-3
    for wrong in (0.8 * kappa, 1.2 * kappa):
        assert stats.kstest(theta, lambda t, k=wrong: fisher_deviation_cdf(t, k)).pvalue < 1e-6


@pytest.mark.parametrize("kappa", [5.0, 20.0, 100.0])
@pytest.mark.parametrize("count", [30, 200])
def test_fisher_sample_k_is_recovered(kappa, count):
    """K estimated as (N - 1) / (N - R) from 400 samples of N: for K >= 3, 2K(N - R) is chi-square with
    2(N - 1) degrees of freedom (Fisher 1953), so the estimate's mean is K (N - 1) / (N - 2) and its
    standard deviation about K / sqrt(N - 1); the mean of the 400 must lie within 4 standard errors
    (K / sqrt((N - 1) 400)) of it."""
    rng = np.random.default_rng(int(kappa) * 1000 + count)
    estimates = []
    for _ in range(400):
        sample = fisher_sample(MEAN, kappa, count, rng)
        estimates.append((count - 1) / (count - np.linalg.norm(sample.sum(axis=0))))
    expected = kappa * (count - 1) / (count - 2)
    assert np.mean(estimates) == pytest.approx(expected, abs=4.0 * kappa / np.sqrt((count - 1) * 400))


@pytest.mark.parametrize(("kappa", "count"), [(5.0, 30), (20.0, 100), (100.0, 30)])
def test_fisher_sample_mean_is_recovered(kappa, count):
    """Over 1,000 samples, the true mean lies inside the sample's 95 % cone (Fisher 1953: cos a95 = 1 -
    (N - R) / R (20^(1/(N-1)) - 1)) in 95 % of them: 95 +- 2.5 % (3.6 binomial standard deviations)."""
    rng = np.random.default_rng(int(kappa) + count)
    inside = 0
    for _ in range(1000):
        resultant = fisher_sample(MEAN, kappa, count, rng).sum(axis=0)
        length = np.linalg.norm(resultant)
        cos_a95 = 1.0 - (count - length) / length * (20.0 ** (1.0 / (count - 1)) - 1.0)
        inside += resultant @ MEAN / length >= cos_a95
    assert inside / 1000 == pytest.approx(0.95, abs=0.025)


# ---------------------------------------------------------------------------------------------------
# oriented core: alpha and beta


def test_core_against_a_hand_worked_example():
    """No published alpha/beta example with its numbers was found (Dips' help, Datamine Discover's and
    Micromine's pages, Holcombe's and Marjoribanks' notes define the angles with figures only), so this
    one is worked by hand.

    Hole trend 180, plunge 60 (drilled south, down); bottom-of-core reference; alpha 60, beta 90.
      down-hole h = (cos 60 sin 180, cos 60 cos 180, -sin 60) = (0, -0.5, -0.8660)
      top of core t = (sin 60 sin 180, sin 60 cos 180, cos 60) = (0, -0.8660, 0.5); bottom b = -t
        = (0, 0.8660, -0.5)
      beta 90 clockwise looking down the hole (facing south, 6 o'clock to 9 o'clock, the viewer's
        left = east): a = h x b = (0.25 + 0.75, 0, 0) = (1, 0, 0)
      pole n = h sin 60 - a cos 60 = (-0.5, -0.4330, -0.75), upward (0.5, 0.4330, 0.75)
      dip = acos 0.75 = 41.4096 deg, dip direction = atan2(0.5, 0.4330) = 49.1066 deg.
    Check: |n . h| = 0.2165 + 0.6495 = 0.8660 = sin 60 (alpha)."""
    pole = core_poles(*_deg(60, 90, 180, 60), CORE_REFERENCES["bottom"])
    np.testing.assert_allclose(pole, [0.5, np.sqrt(3) / 4, 0.75], atol=1e-12)
    dip, direction = plane_of_pole(pole[None])
    assert dip[0] == pytest.approx(41.4096, abs=1e-4)
    assert direction[0] == pytest.approx(49.1066, abs=1e-4)
    # from the top-of-core line the same apex is 180 deg further round
    np.testing.assert_allclose(core_poles(*_deg(60, 270, 180, 60), CORE_REFERENCES["top"]), pole, atol=1e-12)


@SPHERE
@given(st.floats(0.0, HALF_PI), AZIMUTHS, AZIMUTHS)
@example(0.0, 0.0, 0.0)
@example(HALF_PI, 1.0, 2.0)
def test_core_in_a_vertical_hole_dips_90_minus_alpha_towards_the_reference_plus_beta(alpha, beta, trend):
    """A vertical hole: the plane dips 90 - alpha; the apex lies down-dip, so the dip direction is the
    reference line's azimuth plus beta (clockwise looking down = clockwise on a map). The top-of-core
    line of a vertical hole is taken at the azimuth `hole_trend` (the limit of an inclined hole of that
    trend); the bottom line opposite it."""
    for reference, azimuth in (("top", trend), ("bottom", trend + np.pi)):
        pole = core_poles(alpha, beta, trend, HALF_PI, CORE_REFERENCES[reference])
        dip, direction = np.radians(plane_of_pole(pole[None]))
        assert dip[0] == pytest.approx(HALF_PI - alpha, abs=1e-7)
        if 1e-6 < alpha < HALF_PI - 1e-6:
            assert _same_azimuth(direction[0], azimuth + beta, 1e-7)


def test_core_special_cases():
    """alpha 90: the plane is normal to the hole whatever beta (hole 180/60: plane 30/000); alpha 0: the
    plane holds the hole's axis (beta 0 from the bottom line: the plane 60/180 whose dip line is the
    hole; beta 90: the vertical N-S plane)."""
    for beta in (0.0, 1.0, 4.0):
        pole = core_poles(HALF_PI, beta, np.pi, np.radians(60.0))
        np.testing.assert_allclose(pole, -line_vectors(np.pi, np.radians(60.0)), atol=1e-12)
        dip, direction = plane_of_pole(pole[None])
        assert dip[0] == pytest.approx(30.0, abs=1e-9)
        assert _same_azimuth(np.radians(direction[0]), 0.0)
    np.testing.assert_allclose(plane_of_pole(core_poles(0.0, 0.0, np.pi, np.radians(60.0))[None]),
                               [[60.0], [180.0]], atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(
        core_poles(0.0, HALF_PI, np.pi, np.radians(60.0)), [-1.0, 0.0, 0.0], atol=1e-12
    )


def _core_angles(pole, trend, plunge, reference):
    """alpha and beta of a pole, computed back from the definitions: alpha = asin |n . h|; beta the
    clockwise angle (about h) from the reference line to the apex direction -(h . n) n_perp."""
    h = line_vectors(trend, plunge)
    top = top_of_core(trend, plunge)
    line = np.cos(reference) * top + np.sin(reference) * np.cross(h, top)
    along = pole @ h
    apex = -along * (pole - along * h)
    return np.arcsin(abs(along)), np.arctan2(np.cross(h, line) @ apex, line @ apex) % TWO_PI


@SPHERE
@given(
    st.floats(np.radians(0.5), np.radians(89.5)),
    AZIMUTHS,
    AZIMUTHS,
    st.floats(-HALF_PI, HALF_PI),
    st.sampled_from(sorted(CORE_REFERENCES)),
)
@example(np.radians(30.0), 0.0, 0.0, np.radians(-45.0), "bottom")  # a hole drilled upward
def test_core_poles_give_their_alpha_and_beta_back(alpha, beta, trend, plunge, reference):
    pole = core_poles(alpha, beta, trend, plunge, CORE_REFERENCES[reference])
    assert np.linalg.norm(pole) == pytest.approx(1.0, abs=1e-12)
    assert pole[2] >= 0.0
    back_alpha, back_beta = _core_angles(pole, trend, plunge, CORE_REFERENCES[reference])
    assert back_alpha == pytest.approx(alpha, abs=1e-7)
    assert _same_azimuth(back_beta, beta, 1e-7)


def test_core_poles_are_vectorised():
    alpha, beta = np.radians([10.0, 45.0, 80.0]), np.radians([0.0, 120.0, 300.0])
    together = core_poles(alpha, beta, np.radians(90.0), np.radians(70.0))
    one_by_one = [
        core_poles(a, b, np.radians(90.0), np.radians(70.0)) for a, b in zip(alpha, beta, strict=True)
    ]
    np.testing.assert_allclose(together, one_by_one, atol=1e-15)
