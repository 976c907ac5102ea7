"""Sets found in unlabelled readings (bbmc.field.set_finding), scored on synthetic surveys from known
sets (bbmc.field.synthetic): 3 to 5 Fisher sets of K 10 to 100 (log-uniform), 40 to 150 readings
each, whose means lie at least 3 x 81 deg / sqrt(K) apart (K the smaller of a pair's), and 10 % of the
readings random.

Scoring. The adjusted Rand index (Hubert & Arabie 1985), with the random readings a class of their
own, compares the labels found with the true ones. It cannot reach 0.9 on every such survey, whatever
the method: a random reading that falls inside a set's cluster is more probable under the set than
under the background, so even the true mixture (true means, K and shares) puts it in the set. Measured
while writing, over the 100 surveys of the slow test (seeds 0-99): the true mixture's labels score
ARI >= 0.9 in 30 of them (mean 0.887), the fitted ones in 30 too (mean 0.882). So the tests ask what
can be asked:

* the count of sets is the true one (measured: 100 of 100);
* the fitted labels score within 0.05 of the true mixture's labels (the fit does as well as knowing
  the truth, less its sampling error: measured worst 0.043 below);
* over the readings drawn from sets (the random ones left out), ARI >= 0.9 (measured: 99 of 100
  surveys, the true mixture 100; the worst 0.869, where the true mixture scores 0.923);
* each true mean inside its fitted set's alpha95 at the measured rate (the slow test's docstring).
"""

from __future__ import annotations

import numpy as np
import pytest

from bbmc.field import axial_mixture as mix
from bbmc.field.set_finding import MODEL_SAMPLE, Window, find_sets
from bbmc.field.synthetic import KnownSet, SyntheticSurvey, synthetic_survey, uniform_axes
from bbmc.geometry.orientation import angle_between_axes, dip_and_direction, fisher_sample, poles

SPREAD = np.radians(81.0)  # 81 deg / sqrt(K): the angular standard deviation of a Fisher set


def adjusted_rand_index(truth: np.ndarray, found: np.ndarray) -> float:
    """Hubert & Arabie's (1985) ARI from the contingency table of two labellings."""
    _, a = np.unique(truth, return_inverse=True)
    _, b = np.unique(found, return_inverse=True)
    table = np.zeros((a.max() + 1, b.max() + 1))
    np.add.at(table, (a, b), 1)

    def pairs(v):
        return float(np.sum(v * (v - 1) / 2))

    index, rows, columns = pairs(table), pairs(table.sum(axis=1)), pairs(table.sum(axis=0))
    expected = rows * columns / pairs(np.array([truth.size]))
    return (index - expected) / ((rows + columns) / 2 - expected)


def test_the_adjusted_rand_index_against_hand_worked_values():
    """Identical partitions: 1. Truth {0,0,1,1}, found {0,0,0,1}: pairs 1 agreeing + ... worked: index
    sum C(n_ij, 2) = C(2,2) = 1; rows C(2,2) + C(2,2) = 2; columns C(3,2) = 3; expected 2 * 3 / 6 = 1;
    ARI = (1 - 1) / (2.5 - 1) = 0."""
    assert adjusted_rand_index(np.array([0, 0, 1, 1]), np.array([5, 5, 7, 7])) == pytest.approx(1.0)
    assert adjusted_rand_index(np.array([0, 0, 1, 1]), np.array([0, 0, 0, 1])) == pytest.approx(0.0)


def known_survey(rng: np.random.Generator, set_count: int) -> tuple[list[KnownSet], SyntheticSurvey]:
    """A survey as the module's docstring says: means drawn uniformly, kept if far enough apart."""
    while True:
        kappa = np.exp(rng.uniform(np.log(10.0), np.log(100.0), set_count))
        means: list[np.ndarray] = []
        for j in range(set_count):
            for _ in range(2000):
                m = uniform_axes(1, rng)[0]
                apart = [angle_between_axes(m, means[i]) >= 3 * SPREAD / np.sqrt(min(kappa[i], kappa[j]))
                         for i in range(len(means))]  # fmt: skip
                if all(apart):
                    means.append(m)
                    break
        if len(means) == set_count:
            break
    counts = rng.integers(40, 151, set_count)
    sets = [KnownSet(*dip_and_direction(m), k, int(c)) for m, k, c in zip(means, kappa, counts, strict=True)]
    return sets, synthetic_survey(sets, round(counts.sum() / 9), rng)


def true_mixture_labels(sets: list[KnownSet], survey: SyntheticSurvey) -> np.ndarray:
    """Each reading's most probable component under the true mixture."""
    shares = np.array([s.count for s in sets] + [np.sum(survey.labels < 0)]) / survey.labels.size
    truth = mix.AxialMixture(np.array([s.mean_pole for s in sets]), np.array([s.fisher_k for s in sets]),
                             shares, 0.0)  # fmt: skip
    best = np.argmax(mix.log_densities(survey.poles, truth), axis=1)
    return np.where(best == len(sets), -1, best)


def score(seed: int) -> dict:
    """One survey found and scored: counts, the three ARIs, and per true set whether its mean lies in
    the alpha95 of the nearest fitted set."""
    rng = np.random.default_rng(seed)
    sets, survey = known_survey(rng, int(rng.integers(3, 6)))
    found = find_sets(survey.poles, seed=seed)
    from_sets = survey.labels >= 0
    inside = []
    for s in sets:
        nearest = min(found.sets, key=lambda f, s=s: angle_between_axes(s.mean_pole, f.mean_pole))
        inside.append(angle_between_axes(s.mean_pole, nearest.mean_pole) <= nearest.statistics.alpha95)
    return {
        "sets": (len(sets), len(found.sets)),
        "ari": adjusted_rand_index(survey.labels, found.labels),
        "ari_truth": adjusted_rand_index(survey.labels, true_mixture_labels(sets, survey)),
        "ari_sets": adjusted_rand_index(survey.labels[from_sets], found.labels[from_sets]),
        "inside": inside,
    }


@pytest.mark.parametrize("seed", [101, 102, 103, 104, 105, 106])
def test_sets_of_surveys_from_known_sets_are_recovered(seed):
    result = score(seed)
    assert result["sets"][1] == result["sets"][0]
    assert result["ari"] >= result["ari_truth"] - 0.05
    assert result["ari_sets"] >= 0.9


@pytest.mark.slow
def test_over_100_surveys_the_sets_and_their_cones():
    """100 surveys (about 40 s): the count always right; ARI within 0.05 of the true mixture's in
    every survey; ARI over the set readings >= 0.9 in at least 95 of them; the true mean inside its
    fitted alpha95 for at least 82 % of the sets. Measured while writing (seeds 0-99): count right in
    100, worst ARI gap 0.043, set-reading ARI >= 0.9 in 99, the cone rate 85.9 % of 417 sets (its
    standard error 1.7 %). Below 95 % because a set's readings, as found, are not a pure Fisher
    sample: the random readings that fall inside its cluster are in it (about 5-10 % of it) and its
    tails that fall nearer the background or another set are not, and its mean and K are read from
    those readings. With the true labels the rate is 94.2 % on the same surveys; with the mixture's
    responsibilities as weights it was 89.6 % on 60 of them."""
    results = [score(seed) for seed in range(100)]
    assert all(r["sets"][0] == r["sets"][1] for r in results)
    assert all(r["ari"] >= r["ari_truth"] - 0.05 for r in results)
    assert sum(r["ari_sets"] >= 0.9 for r in results) >= 95
    assert np.mean([i for r in results for i in r["inside"]]) >= 0.82


@pytest.mark.parametrize(("kappa", "count"), [(5.0, 30), (10.0, 200), (50.0, 100), (200.0, 400)])
def test_a_survey_that_is_one_set_is_not_split(kappa, count):
    rng = np.random.default_rng(count)
    known = KnownSet(np.radians(40.0), np.radians(130.0), kappa, count)
    found = find_sets(synthetic_survey([known], count // 10, rng).poles, seed=1)
    assert len(found.sets) == 1
    assert np.degrees(angle_between_axes(found.sets[0].mean_pole, known.mean_pole)) < 81.0 / np.sqrt(kappa)


@pytest.mark.parametrize("kappa", [15.0, 40.0, 120.0])
def test_a_subvertical_set_straddling_the_primitive_is_one_set(kappa):
    """Planes dipping 88 deg: about half the poles drawn point below the horizontal and are turned up,
    to the opposite side of the net. One set, its mean the true one within 81 / sqrt(K) deg, holding
    all but a few of the set's readings (at least 90 %)."""
    rng = np.random.default_rng(int(kappa))
    known = KnownSet(np.radians(88.0), np.radians(75.0), kappa, 150)
    survey = synthetic_survey([known], 15, rng)
    from_set = survey.poles[survey.labels == 0]
    sides = np.sign(from_set @ np.array([np.sin(np.radians(75.0)), np.cos(np.radians(75.0)), 0.0]))
    assert 0.25 < np.mean(sides < 0) < 0.75
    found = find_sets(survey.poles, seed=2)
    assert len(found.sets) == 1
    assert np.degrees(angle_between_axes(found.sets[0].mean_pole, known.mean_pole)) < 81.0 / np.sqrt(kappa)
    assert np.sum((found.labels == 0) & (survey.labels == 0)) >= 0.9 * 150


def test_random_readings_are_no_set():
    found = find_sets(uniform_axes(300, np.random.default_rng(5)))
    assert found.sets == [] and np.all(found.labels == -1)
    assert found.background_fraction == pytest.approx(1.0)


def two_sets(seed: int = 9, random: int = 20) -> tuple[list[KnownSet], SyntheticSurvey]:
    sets = [
        KnownSet(np.radians(30.0), np.radians(100.0), 40.0, 120),
        KnownSet(np.radians(80.0), np.radians(220.0), 30.0, 90),
    ]
    return sets, synthetic_survey(sets, random, np.random.default_rng(seed))


def test_a_cluster_below_the_minimum_size_is_no_set():
    """Six readings of K = 300 beside two sets: with min_set_size 10 they are random; with 5, a set."""
    _, survey = two_sets()
    tight = fisher_sample(poles(np.radians(60.0), np.radians(330.0)), 300.0, 6, np.random.default_rng(1))
    readings = np.vstack([survey.poles, tight * np.sign(tight[:, 2:3])])
    assert len(find_sets(readings).sets) == 2
    small = find_sets(readings, min_set_size=5)
    assert len(small.sets) == 3 and small.sets[2].statistics.count == 6


def test_the_same_seed_gives_the_same_sets_and_the_weights_enter():
    _, survey = two_sets()
    weights = np.random.default_rng(3).uniform(1.0, 3.86, survey.labels.size)
    first, second = find_sets(survey.poles, weights, seed=4), find_sets(survey.poles, weights, seed=4)
    assert np.array_equal(first.labels, second.labels)
    for found in first.sets:
        mine = first.labels == found.label
        assert found.statistics.count == mine.sum()
        assert found.statistics.weighted_count == pytest.approx(weights[mine].sum())
        assert found.statistics.effective_count < found.statistics.count


@pytest.mark.parametrize("count", [1, 2, 3])
def test_a_fixed_count_gives_that_many_sets(count):
    _, survey = two_sets()
    found = find_sets(survey.poles, count=count)
    assert len(found.sets) == count and found.method == "count"
    assert set(np.unique(found.labels)) <= {-1, *range(count)}


def test_windows_take_the_readings_inside_them_and_the_nearest_window_on_an_overlap():
    """Two windows of 25 deg about the true poles, and a third of 40 deg about the first pole's
    neighbourhood overlapping it: a reading in both goes to the nearer centre."""
    sets, survey = two_sets()
    wide_centre = poles(np.radians(45.0), np.radians(100.0))
    windows = [
        Window.about_plane("J1", sets[0].dip, sets[0].dip_direction, np.radians(25.0)),
        Window.about_plane("J2", sets[1].dip, sets[1].dip_direction, np.radians(25.0)),
        Window("wide", wide_centre, np.radians(40.0)),
    ]
    found = find_sets(survey.poles, windows=windows)
    assert [s.window for s in found.sets] == ["J1", "J2", "wide"] and found.method == "windows"
    angles = angle_between_axes(survey.poles[:, None, :], np.array([w.pole for w in windows])[None])
    inside = angles <= np.array([w.half_angle for w in windows])
    expected = np.where(inside.any(axis=1), np.argmin(np.where(inside, angles, np.inf), axis=1), -1)
    assert np.array_equal(found.labels, expected)
    both = inside[:, 0] & inside[:, 2]
    assert both.any() and np.all(found.labels[both] == np.where(angles[both, 0] <= angles[both, 2], 0, 2))
    assert found.background_fraction == pytest.approx(np.mean(expected == -1))


def test_a_window_about_a_pole_trend_and_plunge():
    """The pole of a plane dipping 30 deg towards 100 deg trends 280 deg and plunges 60 deg."""
    _, survey = two_sets()
    by_pole = Window.about_pole("J1", np.radians(280.0), np.radians(60.0), np.radians(20.0))
    by_plane = Window.about_plane("J1", np.radians(30.0), np.radians(100.0), np.radians(20.0))
    a, b = find_sets(survey.poles, windows=[by_pole]), find_sets(survey.poles, windows=[by_plane])
    assert np.array_equal(a.labels, b.labels) and a.sets[0].statistics.count > 100
    trend, plunge = np.degrees(a.sets[0].pole_trend_and_plunge)
    assert abs(trend - 280.0) < 5.0 and abs(plunge - 60.0) < 3.0


def test_a_count_that_leaves_a_set_without_readings_is_refused():
    """Six sets asked of eight readings of one set."""
    survey = synthetic_survey([KnownSet(0.5, 1.0, 50.0, 8)], 0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="6 sets leave a set with fewer than 2 readings"):
        find_sets(survey.poles, count=6)


def test_a_window_that_catches_nothing_is_refused_by_name():
    _, survey = two_sets(random=0)
    empty = Window.about_plane("J9", np.radians(50.0), np.radians(10.0), np.radians(5.0))
    with pytest.raises(ValueError, match=r"set window 'J9'.*catches no reading"):
        find_sets(survey.poles, windows=[empty])
    sets, _ = two_sets()
    outer = Window.about_plane("J1", sets[0].dip, sets[0].dip_direction, np.radians(30.0))
    shadowed = Window("J1b", outer.pole * -1.0, np.radians(20.0))
    with pytest.raises(ValueError, match=r"'J1b'.*nearer windows"):
        find_sets(survey.poles, windows=[outer, shadowed])


def test_a_large_survey_is_chosen_on_a_subsample_and_every_reading_assigned():
    """12,000 readings: the count chosen on MODEL_SAMPLE of them, all readings labelled."""
    sets = [KnownSet(np.radians(30.0), np.radians(100.0), 40.0, 6000),
            KnownSet(np.radians(80.0), np.radians(220.0), 30.0, 5000)]  # fmt: skip
    survey = synthetic_survey(sets, 1000, np.random.default_rng(2))
    found = find_sets(survey.poles)
    assert found.sample_size == MODEL_SAMPLE and found.labels.size == 12_000
    assert len(found.sets) == 2
    assert adjusted_rand_index(survey.labels[survey.labels >= 0], found.labels[survey.labels >= 0]) > 0.98


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"count": 2, "windows": [Window("a", np.array([0.0, 0.0, 1.0]), 0.3)]}, "not both"),
        ({"count": 0}, "at least 1"),
        ({"min_set_size": 1}, "at least 2"),
        ({"weights": -np.ones(230)}, "positive"),
        ({"windows": []}, "no set window"),
    ],
)
def test_bad_arguments_are_refused(kwargs, message):
    _, survey = two_sets()
    with pytest.raises(ValueError, match=message):
        find_sets(survey.poles, **kwargs)
