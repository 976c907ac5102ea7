"""Kinematics as a whole: mplstereonet's kinematic classes as an outside oracle, the pairs of
readings (exact and sampled), the tallies and their denominators, the compass and face-angle sweeps
against single faces, and the Monte Carlo probabilities."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.geometry.orientation import fisher_sample, line_vectors, poles, upward
from bbmc.kinematics.compass import compass_sweep, face_angle_sweep
from bbmc.kinematics.criteria import flexural_toppling, planar_sliding, wedge_sliding
from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.intersections import pair_chunks, pair_plan
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES, line_modes, pole_modes
from bbmc.kinematics.probabilistic import mode_probabilities
from bbmc.kinematics.tallies import kinematic_tally

ka = pytest.importorskip("mplstereonet.kinematic_analysis")
r = np.radians
FACES = [(60.0, 135.0, 30.0), (75.0, 20.0, 35.0), (50.0, 300.0, 25.0)]


def random_planes(count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.uniform(0.0, 90.0, count), rng.uniform(0.0, 360.0, count)


@pytest.mark.parametrize(("face_dip", "face_direction", "phi"), FACES)
def test_curved_limits_agree_exactly_with_mplstereonet(face_dip, face_direction, phi):
    """mplstereonet 0.6.3's PlanarSliding, FlexuralToppling (curved and straight lateral limits)
    and WedgeSliding on 20,000 random planes and lines: the same classification, plane for plane."""
    dip, direction = random_planes(20000, 1)
    normals, face = poles(r(dip), r(direction)), Face(r(face_dip), r(face_direction))
    for curved in (True, False):
        limits = KinematicLimits(planar=r(20.0), flexural_toppling=r(30.0), curved=curved)
        theirs, _ = ka.PlanarSliding(face_direction - 90, face_dip, phi, 20).check_failure(
            direction - 90, dip, curved_lateral_limits=curved
        )
        np.testing.assert_array_equal(planar_sliding(normals, face, r(phi), limits), theirs)
        theirs, _ = ka.FlexuralToppling(face_direction - 90, face_dip, phi, 30).check_failure(
            direction - 90, dip, curved_lateral_limits=curved
        )
        np.testing.assert_array_equal(flexural_toppling(normals, face, r(phi), limits), theirs)
    plunge, trend = random_planes(20000, 2)
    primary, secondary = ka.WedgeSliding(face_direction - 90, face_dip, phi).check_failure(trend, plunge)
    mine = wedge_sliding(line_vectors(r(trend), r(plunge)), face, r(phi))
    np.testing.assert_array_equal(mine.primary, primary)
    np.testing.assert_array_equal(mine.secondary, secondary)


def test_straight_limits_differ_from_curved_only_near_the_lateral_limits():
    """Dips' straight limits against mplstereonet's curved ones (its default): planes are classed
    alike wherever the two lateral tests agree; where they do not, the curved limits (wider for
    gently dipping planes) take more. Measured on 20,000 planes of uniform dip and dip direction,
    face 60/135, phi 30: 3.70 % critical for planar sliding with straight limits, 5.54 % with curved
    ones (1.84 % of all planes classed differently); for flexural toppling (+/-30 deg) 5.24 % and
    5.45 % (0.22 % differently)."""
    dip, direction = random_planes(20000, 1)
    normals, face = poles(r(dip), r(direction)), Face(r(60.0), r(135.0))
    straight = planar_sliding(normals, face, r(30.0), KinematicLimits())
    curved, _ = ka.PlanarSliding(45.0, 60.0, 30.0, 20).check_failure(direction - 90, dip)
    off = np.abs((direction - 135.0 + 180.0) % 360.0 - 180.0)
    latitude = np.degrees(np.arcsin(np.sin(r(dip)) * np.abs(np.sin(r(direction - 135.0)))))
    lateral_agree = (off <= 20.0) == (latitude <= 20.0)
    np.testing.assert_array_equal(straight[lateral_agree], curved[lateral_agree])
    assert not np.any(straight & ~curved)  # the curved zone holds the straight one
    assert (straight.mean(), curved.mean()) == (pytest.approx(0.03695), pytest.approx(0.05535))
    topple = flexural_toppling(normals, face, r(30.0), KinematicLimits())
    theirs, _ = ka.FlexuralToppling(45.0, 60.0, 30.0, 30).check_failure(direction - 90, dip)
    assert (topple.mean(), theirs.mean()) == (pytest.approx(0.05235), pytest.approx(0.0545))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 360.0), st.floats(20.0, 89.0), st.floats(10.0, 45.0))
def test_turning_the_survey_with_the_face_changes_nothing(turn, face_dip, phi):
    """Every criterion depends on the readings only relative to the face: rotating both about the
    vertical by any angle leaves each classification unchanged."""
    dip, direction = random_planes(400, 5)
    before = pole_modes(poles(r(dip), r(direction)), Face(r(face_dip), r(10.0)), r(phi), KinematicLimits())
    turned = Face(r(face_dip), r(10.0 + turn))
    after = pole_modes(poles(r(dip), r(direction + turn)), turned, r(phi), KinematicLimits())
    for mode in POLE_MODES:
        # away from the limits (0.01 deg), where round-off of the turn cannot move a plane across one
        assert np.mean(before[mode] != after[mode]) <= 0.005


def test_exact_pairs_are_every_pair_once():
    plan = pair_plan(57)
    pairs = np.concatenate([np.stack(c, axis=1) for c in pair_chunks(plan, chunk_pairs=100)])
    assert plan.exact and plan.evaluated == 57 * 56 // 2 == len(pairs)
    expected = np.stack(np.triu_indices(57, k=1), axis=1)
    np.testing.assert_array_equal(pairs[np.lexsort(pairs.T[::-1])], expected)


def survey(count: int, seed: int = 0):
    """Three Fisher sets (30 % each) and 10 % random readings."""
    rng = np.random.default_rng(seed)
    means = poles(r(np.array([60.0, 75.0, 20.0])), r(np.array([140.0, 320.0, 200.0])))
    each = int(0.3 * count)
    drawn = [fisher_sample(means[s], k, each, rng) for s, k in enumerate([30.0, 20.0, 50.0])]
    normals = np.vstack([*drawn, rng.normal(size=(count - 3 * each, 3))])
    normals = upward(normals / np.linalg.norm(normals, axis=1)[:, None])
    return normals, np.repeat([0, 1, 2, -1], [each, each, each, count - 3 * each]), means


def test_tally_denominators_and_set_pairs():
    """Pole modes count readings; line modes count pairs of readings with a line; the set groups
    and set-pair groups partition them; the set pairs' mean intersections are named."""
    normals, sets, means = survey(120)
    face = Face(r(60.0), r(140.0))
    tally = kinematic_tally(normals, face, r(30.0), sets=sets, set_means=means)
    rows = {(t.mode, t.group): t for t in tally.rows}
    assert rows[("planar_sliding", "all")].count_total == 120
    assert rows[("wedge_sliding", "all")].count_total == 120 * 119 // 2 - tally.parallel_pairs
    for mode in POLE_MODES:
        parts = [t for t in tally.rows if t.mode == mode and t.group != "all"]
        assert sum(t.count_critical for t in parts) == rows[(mode, "all")].count_critical
        assert sum(t.count_total for t in parts) == 120
    vertical = line_modes(np.array([[0.0, 0.0, -1.0]]), face, r(30.0), KinematicLimits())
    assert vertical["direct_toppling_steep"][0]  # a vertical line lies on every limit line: zone 2
    assert rows[("wedge_sliding", "set 1 x set 3")].count_total == 36 * 36
    named = {(p.set_a, p.set_b) for p in tally.set_pairs}
    assert named == {("set 1", "set 2"), ("set 1", "set 3"), ("set 2", "set 3")}
    assert set(tally.critical_set_pairs("wedge_sliding_one_plane")) <= named


def test_sampled_pairs_estimate_the_exact_percentage_within_their_error():
    """Above the exact limit a uniform sample of pairs: each percentage within 4 of its standard
    errors of the exact one (a false alarm once in ~16,000 draws per mode)."""
    normals, sets, _ = survey(300)
    face = Face(r(60.0), r(140.0))
    exact = kinematic_tally(normals, face, r(30.0), sets=sets)
    plan = pair_plan(300, max_exact_readings=100, sample_pairs=20000, seed=4)
    sampled = kinematic_tally(normals, face, r(30.0), sets=sets, plan=plan)
    truth = {(t.mode, t.group): t.percent for t in exact.rows}
    for row in sampled.rows:
        if row.mode in LINE_MODES and row.group == "all":
            assert row.standard_error > 0
            assert abs(row.percent - truth[(row.mode, row.group)]) <= 4 * row.standard_error + 1e-9
    assert "drawn uniformly" in sampled.rows[-1].denominator


def test_compass_sweep_at_a_face_is_the_single_face_tally():
    """The sweep around the compass (here at 30 deg steps) and the face-angle sweep give, at each
    face, the tally of that face, for every mode and group."""
    normals, sets, _ = survey(60)
    sweep = compass_sweep(normals, r(60.0), r(30.0), step=r(30.0), sets=sets)
    dips = r(np.array([40.0, 70.0, 90.0]))
    angles = face_angle_sweep(normals, r(140.0), dips, r(30.0), sets=sets)
    for f, direction in enumerate(sweep.dip_direction):
        tally = kinematic_tally(normals, Face(r(60.0), direction), r(30.0), sets=sets)
        for row in tally.rows:
            assert sweep.percent(row.mode, row.group)[0][f] == pytest.approx(row.percent, abs=1e-9)
    for f, dip in enumerate(dips):
        tally = kinematic_tally(normals, Face(dip, r(140.0)), r(30.0), sets=sets)
        for row in tally.rows:
            assert angles.percent(row.mode, row.group)[0][f] == pytest.approx(row.percent, abs=1e-9)
    assert len(sweep.rows()) > 0 and sweep.dip_direction.size == 12


def test_probability_tends_to_the_mean_classification_as_k_grows():
    """With K = 1e7 (a scatter of about 0.03 deg) every draw is classed as the mean: probabilities
    0 or 1, as the mean pole (or the means' line) is critical or not."""
    means = poles(r(np.array([45.0, 50.0, 50.0])), r(np.array([140.0, 110.0, 170.0])))
    face = Face(r(60.0), r(140.0))
    rows = mode_probabilities(means, [1e7] * 3, face, r(30.0), samples=2000)
    at_mean = pole_modes(means, face, r(30.0), KinematicLimits())
    lines = np.cross(means[1], means[2]).reshape(1, 3)
    lines = lines / np.linalg.norm(lines) * -np.sign(lines[0, 2])
    pair = line_modes(lines, face, r(30.0), KinematicLimits())
    for row in rows:
        if row.group in ("set 1", "set 2", "set 3"):
            assert row.probability == float(at_mean[row.mode][int(row.group[-1]) - 1])
        if row.group == "set 2 x set 3":
            assert row.probability == float(pair[row.mode][0])
    assert any(row.probability == 1.0 for row in rows) and any(row.probability == 0.0 for row in rows)


def test_probability_and_its_standard_error():
    """The estimate from 20,000 draws lies within 4 standard errors of the one from 400,000 draws
    (other seed), and the error is sqrt(p (1 - p) / M)."""
    means = poles(r(np.array([50.0, 75.0])), r(np.array([140.0, 320.0])))
    face = Face(r(60.0), r(140.0))
    small = mode_probabilities(
        means, [20.0, 15.0], face, r(30.0), samples=20000, rng=np.random.default_rng(1)
    )
    large = mode_probabilities(
        means, [20.0, 15.0], face, r(30.0), samples=400000, rng=np.random.default_rng(2)
    )
    for a, b in zip(small, large, strict=True):
        assert a.standard_error == pytest.approx(np.sqrt(a.probability * (1 - a.probability) / 20000))
        assert abs(a.probability - b.probability) <= 4 * np.hypot(a.standard_error, b.standard_error) + 1e-12
    planar = next(row for row in large if row.mode == "planar_sliding" and row.group == "set 1")
    assert 0.3 < planar.probability < 0.9  # a set straddling the zone: a probability, not 0 or 1
