"""The sweep's sampling design, its statistics and its figures (bbmc.sweep).

Every tolerance is stated where it is used. Designs are seeded, so each test is deterministic.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from bbmc.scene.schema import Scene
from bbmc.sweep import design, figures, ranges
from bbmc.sweep import statistics as sweep_stats
from bbmc.sweep.config import Planar
from bbmc.sweep.design import correlate, grid_table, marginal, saltelli_table, sample_table, unit_samples
from bbmc.sweep.ranges import key_range

TAN_PSI = math.tan(math.radians(35.0))  # the planar block's plane, psi = 35 deg


def _block_fs(tan_phi):
    """FS = tan(phi) / tan(psi) of a cohesionless block on a dry plane dipping at psi = 35 deg."""
    return np.asarray(tan_phi, dtype=float) / TAN_PSI


# 1. closed form ----------------------------------------------------------------------------------------


def test_monte_carlo_probability_of_failure_matches_closed_form():
    """tan(phi) ~ N(0.8, 0.15) makes FS exactly normal: mu = 0.8 / tan 35, sigma = 0.15 / tan 35,
    P_f = Phi((1 - mu) / sigma) = 0.2532. 10^4 Monte Carlo samples: |P_f - exact| <= 4 standard errors,
    and the Clopper-Pearson 95 % interval covers the exact value."""
    table = sample_table([("tan_phi", marginal("normal", mean=0.8, std=0.15))], 10_000, "monte_carlo", 11)
    fs = _block_fs(table["tan_phi"])
    result = sweep_stats.failure_statistics(fs, np.zeros(fs.size, dtype=bool))
    mu, sigma = 0.8 / TAN_PSI, 0.15 / TAN_PSI
    exact = stats.norm.cdf((1.0 - mu) / sigma)
    assert result["samples"] == 10_000 and result["failed_runs"] == 0
    assert abs(result["probability_of_failure"] - exact) <= 4.0 * result["standard_error"]
    assert result["pf_ci_low"] <= exact <= result["pf_ci_high"]
    assert result["mean_fs"] == pytest.approx(mu, abs=4.0 * sigma / 100.0)  # 4 standard errors of the mean
    assert result["reliability_index_normal"] == pytest.approx((mu - 1.0) / sigma, abs=0.03)  # ~3 SE


# 2. Latin hypercube against Monte Carlo ------------------------------------------------------------------


def test_latin_hypercube_estimates_the_mean_better_than_monte_carlo():
    """FS = tan(phi) / tan(35 deg) (1 + c'), tan(phi) ~ N(0.8, 0.15), c' ~ lognormal(mean 0.2, std
    0.08), independent: E[FS] = 0.8 / tan 35 x 1.2 exactly. Over seeds 0..19 at n = 1000 the RMS error
    of the sample mean was, as measured: Monte Carlo 6.6e-3, Latin hypercube 5.2e-4 (Sobol 2.5e-4).
    Asserted: LHS's RMS error is smaller than MC's, by at least a factor of 3."""
    variables = [
        ("tan_phi", marginal("normal", mean=0.8, std=0.15)),
        ("c", marginal("lognormal", mean=0.2, std=0.08)),
    ]
    exact = 0.8 / TAN_PSI * 1.2

    def rms(method: str) -> float:
        errors = []
        for seed in range(20):
            table = sample_table(variables, 1000, method, seed)
            errors.append(np.mean(_block_fs(table["tan_phi"]) * (1.0 + table["c"])) - exact)
        return float(np.sqrt(np.mean(np.square(errors))))

    rms_mc, rms_lhs = rms("monte_carlo"), rms("latin_hypercube")
    assert rms_lhs < rms_mc / 3.0, (rms_lhs, rms_mc)


# 3. correlation ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("rho", [0.5, -0.7])
@pytest.mark.parametrize("method", ["monte_carlo", "latin_hypercube"])
def test_correlation_between_two_normals(rho, method):
    """Gaussian copula between two normals: the Pearson correlation of the marginals is rho; at
    n = 10^4 the achieved value is within 0.03 of it (about 4 standard errors (1 - rho^2)/sqrt(n))."""
    variables = [
        ("cohesion_kpa", marginal("normal", mean=50.0, std=10.0)),
        ("friction_deg", marginal("normal", mean=35.0, std=3.0)),
    ]
    table = sample_table(variables, 10_000, method, 5, correlation=("cohesion_kpa", "friction_deg", rho))
    achieved = np.corrcoef(table["cohesion_kpa"], table["friction_deg"])[0, 1]
    assert abs(achieved - rho) <= 0.03
    # the marginals are kept: means within 0.05 std of the requested ones (~5 standard errors)
    assert table["cohesion_kpa"].mean() == pytest.approx(50.0, abs=0.5)
    assert table["friction_deg"].mean() == pytest.approx(35.0, abs=0.15)


def test_correlate_returns_a_new_array_and_keeps_column_i():
    u = unit_samples(3, 100, "monte_carlo", 0)
    before = u.copy()
    out = correlate(u, 0, 2, 0.6)
    assert np.array_equal(u, before)  # the input is untouched
    assert np.array_equal(out[:, :2], u[:, :2])
    assert not np.array_equal(out[:, 2], u[:, 2])
    assert np.all((out > 0.0) & (out < 1.0))


@pytest.mark.parametrize(("i", "j", "rho"), [(0, 0, 0.5), (0, 3, 0.5), (0, 1, 1.0), (0, 1, -1.0)])
def test_correlate_refuses_bad_arguments(i, j, rho):
    with pytest.raises(ValueError, match=r"rho|columns"):
        correlate(unit_samples(2, 10, "monte_carlo", 0), i, j, rho)


def test_sample_table_refuses_an_unknown_correlated_name():
    variables = [("a", marginal("normal", mean=0.0, std=1.0)), ("b", marginal("normal", mean=0.0, std=1.0))]
    with pytest.raises(ValueError, match="'c'"):
        sample_table(variables, 10, "monte_carlo", 0, correlation=("a", "c", 0.5))


# 4. determinism ------------------------------------------------------------------------------------------

VARIABLES = [
    ("joint_laws.joint.friction_deg", marginal("normal", mean=35.0, std=3.0)),
    ("joint_laws.joint.jcs_mpa", marginal("lognormal", mean=60.0, std=15.0)),
    ("slope.water_depth_m", marginal("uniform", min=0.0, max=5.0)),
]


@pytest.mark.parametrize("method", design.METHODS)
def test_same_seed_same_table_other_seed_other_table(method):
    n = 64  # a power of 2, so Sobol does not warn
    first, again = sample_table(VARIABLES, n, method, 3), sample_table(VARIABLES, n, method, 3)
    other = sample_table(VARIABLES, n, method, 4)
    assert np.array_equal(first.to_numpy(), again.to_numpy())
    assert not np.array_equal(first.to_numpy(), other.to_numpy())
    assert list(first.columns) == [name for name, _ in VARIABLES]
    assert first.index.name == "sample" and first.index.tolist() == list(range(n))


def test_saltelli_table_is_deterministic_and_sized():
    table, problem = saltelli_table(VARIABLES, 16, 1)
    again, _ = saltelli_table(VARIABLES, 16, 1)
    other, _ = saltelli_table(VARIABLES, 16, 2)
    assert table.shape == (16 * (len(VARIABLES) + 2), len(VARIABLES))
    assert np.array_equal(table.to_numpy(), again.to_numpy())
    assert not np.array_equal(table.to_numpy(), other.to_numpy())
    assert problem["names"] == [name for name, _ in VARIABLES] and table.index.name == "sample"
    assert np.all(np.isfinite(table.to_numpy()))


def test_unit_samples_shape_open_interval_and_sobol_warning():
    for method in design.METHODS:
        u = unit_samples(4, 256, method, 9)
        assert u.shape == (256, 4)
        assert np.all((u > 0.0) & (u < 1.0))
    with pytest.warns(UserWarning, match="power of 2"):
        assert unit_samples(2, 100, "sobol", 0).shape == (100, 2)
    with pytest.raises(ValueError, match="method"):
        unit_samples(2, 10, "halton", 0)


def test_grid_table_is_the_cartesian_product():
    table = grid_table([("a", [1.0, 2.0]), ("b", [10.0, 20.0, 30.0])])
    assert table.index.name == "sample" and table.shape == (6, 2)
    assert table.iloc[0].tolist() == [1.0, 10.0] and table.iloc[-1].tolist() == [2.0, 30.0]
    assert set(map(tuple, table.to_numpy())) == {(a, b) for a in (1.0, 2.0) for b in (10.0, 20.0, 30.0)}
    with pytest.raises(ValueError, match="'b'"):
        grid_table([("a", [1.0]), ("b", [])])


# 5. marginals ---------------------------------------------------------------------------------------------


def _truncated_normal_moments(mean, std, low, high):
    """Mean and std of N(mean, std) truncated to [low, high] (Johnson, Kotz & Balakrishnan 1994)."""
    a, b = (low - mean) / std, (high - mean) / std
    mass = stats.norm.cdf(b) - stats.norm.cdf(a)
    pa, pb = stats.norm.pdf(a), stats.norm.pdf(b)
    m = mean + std * (pa - pb) / mass
    var = std**2 * (1.0 + (a * pa - b * pb) / mass - ((pa - pb) / mass) ** 2)
    return m, math.sqrt(var)


# (kind, params, expected mean, expected std) computed by hand from the parameters
MARGINALS = [
    ("normal", {"mean": 35.0, "std": 3.0}, 35.0, 3.0),
    ("lognormal", {"mean": 60.0, "std": 15.0}, 60.0, 15.0),
    ("lognormal", {"mean": 0.5, "std": 0.4}, 0.5, 0.4),  # V = 0.8: a strongly skewed one
    ("uniform", {"min": 2.0, "max": 8.0}, 5.0, 6.0 / math.sqrt(12.0)),
    (
        "triangular",
        {"min": 20.0, "mode": 25.0, "max": 40.0},
        85.0 / 3.0,
        math.sqrt((20**2 + 25**2 + 40**2 - 20 * 25 - 20 * 40 - 25 * 40) / 18.0),
    ),
    (
        "truncated_normal",
        {"mean": 30.0, "std": 5.0, "min": 22.0, "max": 35.0},
        *_truncated_normal_moments(30.0, 5.0, 22.0, 35.0),
    ),
]


@pytest.mark.parametrize(("kind", "params", "mean", "std"), MARGINALS)
def test_marginal_moments_and_bounds(kind, params, mean, std):
    """The frozen distribution's own moments equal the hand values (rel 1e-9), and 10^5 Monte Carlo
    samples reproduce them within 1 % (relative; the sampling error is ~0.3 % of std for the mean and
    ~0.5 % for a skewed std). Bounded marginals stay within their bounds."""
    dist = marginal(kind, **params)
    assert dist.mean() == pytest.approx(mean, rel=1e-9)
    assert dist.std() == pytest.approx(std, rel=1e-9)
    x = sample_table([("x", dist)], 100_000, "monte_carlo", 2)["x"].to_numpy()
    assert x.mean() == pytest.approx(mean, rel=0.01)
    assert x.std(ddof=1) == pytest.approx(std, rel=0.01)
    if "min" in params:
        assert x.min() >= params["min"] and x.max() <= params["max"]
    if kind == "lognormal":
        assert x.min() > 0.0


@pytest.mark.parametrize(
    ("kind", "params", "named"),
    [
        ("normal", {"mean": 1.0, "std": 0.0}, "std"),
        ("normal", {"mean": 1.0, "std": -2.0}, "std"),
        ("normal", {"mean": 1.0, "std": float("nan")}, "std"),
        ("normal", {"mean": 1.0}, "std"),
        ("normal", {"mean": 1.0, "std": 1.0, "shape": 2.0}, "shape"),
        ("lognormal", {"mean": 0.0, "std": 1.0}, "mean"),
        ("lognormal", {"mean": -3.0, "std": 1.0}, "mean"),
        ("uniform", {"min": 2.0, "max": 1.0}, "min"),
        ("uniform", {"min": 1.0, "max": 1.0}, "min"),
        ("triangular", {"min": 0.0, "mode": 5.0, "max": 4.0}, "mode"),
        ("triangular", {"min": 0.0, "mode": -1.0, "max": 4.0}, "mode"),
        ("truncated_normal", {"mean": 0.0, "std": 1.0, "min": 1.0, "max": 1.0}, "min"),
        ("truncated_normal", {"mean": 0.0, "std": 0.0, "min": -1.0, "max": 1.0}, "std"),
        ("truncated_normal", {"mean": 0.0, "std": 1.0, "min": 50.0, "max": 60.0}, "min, max"),
        ("weibull", {"mean": 0.0, "std": 1.0}, "kind"),
    ],
)
def test_marginal_refuses_meaningless_parameters(kind, params, named):
    with pytest.raises(ValueError, match=named):
        marginal(kind, **params)


def test_saltelli_table_refuses_n_not_a_power_of_2():
    with pytest.raises(ValueError, match="power of 2"):
        saltelli_table(VARIABLES, 100, 0)


# 5b. truncation to the range a key accepts --------------------------------------------------------------


def test_truncated_normal_mean_ppf_and_cut_against_closed_forms():
    """N(0.8, 0.5) truncated at 0 (a tan phi), renormalised: mean mu + sigma phi(a) / (1 - Phi(a)),
    a = -mu / sigma (Johnson, Kotz & Balakrishnan 1994) = 0.85868 (rel 1e-9); the probability left out
    Phi(a) = 0.05480; the quantiles those of scipy's truncnorm (abs 1e-9 where |x| < 10). 10^4 Latin
    hypercube samples stay above 0 and their mean is the closed form within 1e-3 (LHS integrates the
    mean almost exactly)."""
    mu, sigma = 0.8, 0.5
    a = -mu / sigma
    cut = design.Truncated(stats.norm(mu, sigma), 0.0, math.inf)
    exact = mu + sigma * stats.norm.pdf(a) / stats.norm.sf(a)
    assert cut.mean() == pytest.approx(exact, rel=1e-9)
    assert cut.probability_cut == pytest.approx(stats.norm.cdf(a), rel=1e-12)
    u = np.linspace(0.001, 0.999, 999)
    assert cut.ppf(u) == pytest.approx(stats.truncnorm(a, np.inf, loc=mu, scale=sigma).ppf(u), abs=1e-9)
    x = sample_table([("tan_phi", cut)], 10_000, "latin_hypercube", 4)["tan_phi"]
    assert x.min() > 0.0 and x.mean() == pytest.approx(exact, abs=1e-3)


def test_truncation_deep_in_a_tail_keeps_its_precision():
    """N(-5, 1) truncated at 0 keeps 2.9e-7 of its probability: its quantiles equal truncnorm's to rel
    1e-9 (the upper tail is sampled through the survival function), its mean is truncnorm's."""
    cut = design.Truncated(stats.norm(-5.0, 1.0), 0.0, math.inf)
    reference = stats.truncnorm(5.0, np.inf, loc=-5.0, scale=1.0)
    u = np.array([1e-9, 0.01, 0.5, 0.99, 1.0 - 1e-9])
    assert cut.ppf(u) == pytest.approx(reference.ppf(u), rel=1e-9)
    assert cut.mean() == pytest.approx(reference.mean(), rel=1e-6)
    assert 1.0 - cut.probability_cut == pytest.approx(stats.norm.sf(5.0), rel=1e-9)


def test_truncated_uniform_is_the_uniform_on_the_overlap():
    """U(-1, 5) truncated to [0, 90) is U(0, 5): quantiles 5u, mean 2.5, a sixth of it left out."""
    cut = design.truncation(marginal("uniform", min=-1.0, max=5.0), 0.0, 90.0)
    u = np.linspace(0.01, 0.99, 50)
    assert cut.ppf(u) == pytest.approx(5.0 * u, rel=1e-12)
    assert cut.mean() == pytest.approx(2.5, rel=1e-9) and cut.probability_cut == pytest.approx(1 / 6)


def test_a_distribution_within_the_range_is_not_truncated_and_one_outside_it_is_refused():
    assert design.truncation(marginal("lognormal", mean=3.87, std=0.774), 0.0, math.inf) is None
    assert design.truncation(marginal("uniform", min=0.0, max=5.0), 0.0, math.inf) is None
    assert design.truncation(marginal("truncated_normal", mean=2, std=0.5, min=0.5, max=5), 0, 20) is None
    with pytest.raises(ValueError, match="almost none"):
        design.truncation(marginal("normal", mean=-10.0, std=0.5), 0.0, math.inf)


def test_key_ranges_come_from_the_config_models():
    """The range of a key is its own check: a scene's constant joint (cohesion >= 0, friction in
    [0, 90) deg), a Barton-Bandis strength through its law's variant (JRC in [0, 20]), a whole-number
    key, a key without bounds; the planar base (tan phi > 0, water fill in [0, 1])."""
    scene = {
        "joint_laws": {
            "plane": {"law": "constant", "kn_MPa_per_mm": 1.0, "ks_MPa_per_mm": 1.0, "cohesion_MPa": 0.1,
                      "friction_deg": 35.0},
            "bb": {"law": "barton_bandis", "strength": {"jrc": 8.0, "jcs_MPa": 50.0, "phi_b_deg": 30.0}},
        },
        "solver": {"steps": 1000},
        "blocks": [{"name": "b", "material": "rock", "rotate_deg": 5.0}],
    }  # fmt: skip
    assert str(key_range(Scene, scene, "joint_laws.plane.cohesion_MPa")) == ">= 0"
    assert key_range(Scene, scene, "joint_laws.plane.friction_deg") == ranges.Range(0.0, 90.0, False, True)
    assert str(key_range(Scene, scene, "joint_laws.bb.strength.jrc")) == ">= 0 and <= 20"
    assert key_range(Scene, scene, "solver.steps").integer
    assert str(key_range(Scene, scene, "blocks.0.rotate_deg")) == "any number"
    planar = {"strength": {"law": "mohr_coulomb", "tan_friction": 0.8}, "water_fill": 0.5}
    accepted = key_range(Planar, planar, "strength.tan_friction")
    assert str(accepted) == "> 0" and accepted.contains([-0.1, 0.0, 0.2]).tolist() == [False, False, True]
    assert str(key_range(Planar, planar, "water_fill")) == ">= 0 and <= 1"


# 6. statistics --------------------------------------------------------------------------------------------


def test_failure_statistics_against_hand_values():
    """FS = 0.8, 1.2, 1.4, 1.6, one failed run, one sample of impossible inputs and one invalid: mean
    1.25, std sqrt(0.35 / 3) (ddof 1), P_f = 1/4; the indices by hand; all to rel 1e-12. Clopper-Pearson
    for 1 of 4: low = 1 - 0.975^(1/4) (the k = 1 closed form), high the p at which P(X <= 1) = 0.025."""
    fs = np.array([0.8, 1.2, np.nan, 1.4, 1.6, np.nan, np.nan])
    errors = np.array([False, False, True, False, False, False, False])
    impossible = np.array([False, False, False, False, False, True, False])
    invalid = np.array([False, False, False, False, False, False, True])
    result = sweep_stats.failure_statistics(fs, errors, impossible, invalid)
    std = math.sqrt(0.35 / 3.0)
    v = std / 1.25
    assert result["samples"] == 7 and result["failed_runs"] == 1 and result["valid_samples"] == 4
    assert result["impossible_samples"] == 1 and result["invalid_samples"] == 1
    assert result["mean_fs"] == pytest.approx(1.25, rel=1e-12)
    assert result["std_fs"] == pytest.approx(std, rel=1e-12)
    assert result["probability_of_failure"] == 0.25
    assert result["standard_error"] == pytest.approx(math.sqrt(0.25 * 0.75 / 4.0), rel=1e-12)
    assert result["reliability_index_normal"] == pytest.approx(0.25 / std, rel=1e-12)
    expected_ln = math.log(1.25 / math.sqrt(1.0 + v * v)) / math.sqrt(math.log(1.0 + v * v))
    assert result["reliability_index_lognormal"] == pytest.approx(expected_ln, rel=1e-12)
    assert result["pf_ci_low"] == pytest.approx(1.0 - 0.975**0.25, rel=1e-9)
    assert stats.binom.cdf(1, 4, result["pf_ci_high"]) == pytest.approx(0.025, rel=1e-9)
    assert result["reliability_index_pf"] == pytest.approx(-stats.norm.ppf(0.25), rel=1e-12)
    assert result["reliability_index_pf_lower_bound"] == pytest.approx(
        -stats.norm.ppf(result["pf_ci_high"]), rel=1e-12
    )


@pytest.mark.parametrize(
    ("failures", "n", "low", "high"),
    [(81, 263, 0.2527, 0.3676), (15, 148, 0.0578, 0.1617), (0, 20, 0.0, 0.1684), (1, 29, 0.0009, 0.1776)],
)
def test_clopper_pearson_interval_against_newcombe_1998(failures, n, low, high):
    """Newcombe (1998, Stat. Med. 17:857, Table II, method 5: the exact Clopper-Pearson interval),
    printed to 4 decimals: abs 5e-5."""
    assert sweep_stats.clopper_pearson_interval(failures, n) == pytest.approx((low, high), abs=5e-5)


@pytest.mark.parametrize("n", [3, 32, 256, 100_000])
def test_clopper_pearson_interval_with_no_failure_and_with_all(n):
    """No failure in n: [0, 1 - 0.025^(1/n)] (3.69e-5 at n = 10^5, where Wilson's upper end is 3.84e-5
    and the one-sided 95 % bound 1 - 0.05^(1/n) is 3.00e-5); every sample failing: [0.025^(1/n), 1].
    rel 1e-9."""
    low, high = sweep_stats.clopper_pearson_interval(0, n)
    assert low == 0.0 and high == pytest.approx(1.0 - 0.025 ** (1.0 / n), rel=1e-9)
    low, high = sweep_stats.clopper_pearson_interval(n, n)
    assert high == 1.0 and low == pytest.approx(0.025 ** (1.0 / n), rel=1e-9)
    if n == 100_000:
        assert float(sweep_stats.clopper_pearson_interval(0, n)[1]) == pytest.approx(3.689e-5, abs=1e-8)


def test_clopper_pearson_interval_refuses_impossible_counts():
    for failures, n in ((5, 4), (-1, 4), (0, 0)):
        with pytest.raises(ValueError, match="failures"):
            sweep_stats.clopper_pearson_interval(failures, n)


def test_reliability_index_from_probability():
    """beta = -Phi^-1(P_f): 0 at 1/2, 1.6449 at 0.05 (the normal table), +inf at 0, -inf at 1."""
    beta = sweep_stats.reliability_index_from_probability([0.5, 0.05, 0.0, 1.0])
    assert beta[0] == pytest.approx(0.0, abs=1e-15) and beta[1] == pytest.approx(1.644854, abs=1e-6)
    assert beta[2] == math.inf and beta[3] == -math.inf


def test_convergence_against_hand_counts():
    """FS 0.5, 1.5, (failed), 2.0, 0.8 in design order: over the first 1, 2, 3 and 5 samples the valid
    counts are 1, 2, 2, 4, the failures 1, 1, 1, 2, the means 0.5, 1.0, 1.0, 1.2; the last row is the
    whole study's `failure_statistics` (P_f, its interval, mean FS: rel 1e-12)."""
    fs = np.array([0.5, 1.5, np.nan, 2.0, 0.8])
    excluded = np.isnan(fs)
    table = sweep_stats.convergence(fs, excluded, [1, 2, 3, 5])
    assert table["valid_samples"].tolist() == [1, 2, 2, 4]
    assert table["failures"].tolist() == [1, 1, 1, 2]
    assert table["mean_fs"].to_numpy() == pytest.approx([0.5, 1.0, 1.0, 1.2], rel=1e-12)
    assert math.isnan(table["mean_fs_ci_low"].iloc[0])  # one valid sample has no spread
    whole = sweep_stats.failure_statistics(fs, excluded)
    last = table.iloc[-1]
    for column in ("probability_of_failure", "pf_ci_low", "pf_ci_high", "mean_fs"):
        assert last[column] == pytest.approx(whole[column], rel=1e-12)
    half = stats.norm.ppf(0.975) * whole["std_fs"] / 2.0
    assert last["mean_fs_ci_high"] - last["mean_fs"] == pytest.approx(half, rel=1e-9)


def test_convergence_counts_span_the_study():
    counts = sweep_stats.convergence_counts(100_000)
    assert counts[0] == 10 and counts[-1] == 100_000 and np.all(np.diff(counts) > 0) and len(counts) <= 41
    assert sweep_stats.convergence_counts(4).tolist() == [4]
    assert sweep_stats.convergence_counts(20)[-1] == 20


def test_failure_statistics_edge_rules():
    with pytest.raises(ValueError, match="no statistics"):  # every run failed
        sweep_stats.failure_statistics(np.full(4, np.nan), np.ones(4, dtype=bool))
    with pytest.raises(ValueError, match="no statistics"):  # one valid sample has no std
        sweep_stats.failure_statistics(np.array([1.2, np.nan]), np.array([False, True]))
    with pytest.raises(ValueError, match="not marked"):  # a NaN FS must be a marked failed run
        sweep_stats.failure_statistics(np.array([1.2, np.nan, 1.3]), np.zeros(3, dtype=bool))
    ok = np.zeros(3, dtype=bool)
    stable = sweep_stats.failure_statistics(np.full(3, 1.5), ok)
    assert stable["std_fs"] == 0.0 and stable["probability_of_failure"] == 0.0
    assert stable["reliability_index_normal"] == math.inf == stable["reliability_index_lognormal"]
    assert stable["pf_ci_low"] == 0.0 and stable["pf_ci_high"] == pytest.approx(1.0 - 0.025 ** (1 / 3))
    assert stable["reliability_index_pf"] == math.inf
    failing = sweep_stats.failure_statistics(np.full(3, 0.5), ok)
    assert failing["reliability_index_normal"] == -math.inf == failing["reliability_index_lognormal"]
    limit = sweep_stats.failure_statistics(np.full(3, 1.0), ok)
    assert limit["reliability_index_normal"] == 0.0 == limit["reliability_index_lognormal"]
    assert (
        sweep_stats.failure_statistics(np.array([-0.5, 0.2]), np.zeros(2, dtype=bool))[
            "reliability_index_lognormal"
        ]
        == -math.inf
    )


def test_spearman_recovers_a_monotone_relation():
    """FS = exp(x1) (increasing in x1, independent of x2): rho(x1) = 1 exactly, |rho(x2)| < 0.1 (n = 500
    independent: 2.2 standard errors), x1 first; a constant input gets 0; failed runs are skipped."""
    rng = np.random.default_rng(0)
    inputs = pd.DataFrame({"x2": rng.random(500), "x1": rng.random(500), "fixed": np.full(500, 3.0)})
    fs = np.exp(inputs["x1"].to_numpy())
    fs[:10] = np.nan  # failed runs
    rho = sweep_stats.spearman(inputs, fs)
    assert rho.index.tolist()[0] == "x1" and rho["x1"] == pytest.approx(1.0, abs=1e-12)
    assert abs(rho["x2"]) < 0.1 and rho["fixed"] == 0.0
    assert rho.index.tolist() == ["x1", "x2", "fixed"]
    decreasing = sweep_stats.spearman(inputs, -fs)
    assert decreasing["x1"] == pytest.approx(-1.0, abs=1e-12) and decreasing.index[0] == "x1"


# 7. Sobol indices ----------------------------------------------------------------------------------------


def test_sobol_indices_of_a_linear_model():
    """y = 2 x1 + x2, x ~ U(0, 1): V = (4 + 1)/12, S1 = ST = (0.8, 0.2). Each estimate within SALib's own
    95 % bootstrap half-width of the exact value (N = 1024, 4096 runs)."""
    variables = [(name, marginal("uniform", min=0.0, max=1.0)) for name in ("x1", "x2")]
    table, problem = saltelli_table(variables, 1024, 7)
    result = sweep_stats.sobol_indices(problem, 2.0 * table["x1"] + table["x2"], 7)
    assert list(result.columns) == ["S1", "S1_conf", "ST", "ST_conf"]
    assert result.index.tolist() == ["x1", "x2"]
    exact = np.array([0.8, 0.2])
    assert np.all(np.abs(result["S1"] - exact) <= result["S1_conf"])
    assert np.all(np.abs(result["ST"] - exact) <= result["ST_conf"])


def test_sobol_indices_of_the_ishigami_function():
    """Ishigami (a = 7, b = 0.1, x ~ U(-pi, pi)), exact S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424,
    0.2437) (Sobol' & Levitan 1999): within SALib's 95 % half-width or 0.02, whichever is larger
    (N = 4096, 20480 runs)."""
    variables = [(name, marginal("uniform", min=-math.pi, max=math.pi)) for name in ("x1", "x2", "x3")]
    table, problem = saltelli_table(variables, 4096, 3)
    x1, x2, x3 = (table[name].to_numpy() for name in ("x1", "x2", "x3"))
    y = np.sin(x1) + 7.0 * np.sin(x2) ** 2 + 0.1 * x3**4 * np.sin(x1)
    result = sweep_stats.sobol_indices(problem, y, 3)
    for column, exact in (("S1", [0.3139, 0.4424, 0.0]), ("ST", [0.5576, 0.4424, 0.2437])):
        tolerance = np.maximum(result[f"{column}_conf"].to_numpy(), 0.02)
        assert np.all(np.abs(result[column].to_numpy() - exact) <= tolerance), result


def test_sobol_indices_refuses_missing_runs():
    variables = [(name, marginal("uniform", min=0.0, max=1.0)) for name in ("x1", "x2")]
    table, problem = saltelli_table(variables, 8, 0)
    y = table["x1"].to_numpy().copy()
    y[3] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        sweep_stats.sobol_indices(problem, y, 0)


# 8. figures ----------------------------------------------------------------------------------------------


def test_figures_build_and_save(tmp_path):
    variables = [
        ("joint_laws.joint.friction_deg", marginal("normal", mean=35.0, std=3.0)),
        ("joint_laws.joint.jrc", marginal("triangular", min=4.0, mode=8.0, max=12.0)),
        ("slope.water_depth_m", marginal("uniform", min=0.0, max=5.0)),
    ]
    table = sample_table(variables, 2000, "latin_hypercube", 1)
    fs = np.array(
        np.tan(np.radians(table.iloc[:, 0] + 0.4 * table.iloc[:, 1])) / TAN_PSI - 0.03 * table.iloc[:, 2]
    )
    errors = np.zeros(fs.size, dtype=bool)
    errors[:5], fs[:5] = True, np.nan
    summary = sweep_stats.failure_statistics(fs, errors)
    rho = sweep_stats.spearman(table, fs)
    convergence = sweep_stats.convergence(fs, errors, sweep_stats.convergence_counts(fs.size))
    for name, fig in (
        ("tornado", figures.tornado_figure(rho, dpi=100)),
        ("distribution", figures.distribution_figure(fs, summary, dpi=100)),
        ("convergence", figures.convergence_figure(convergence, summary, dpi=100)),
    ):
        assert fig.axes and all(ax.has_data() for ax in fig.axes)
        path = tmp_path / f"{name}.png"
        fig.savefig(path)
        assert path.stat().st_size > 10_000


def test_a_probability_of_failure_of_zero_is_printed_with_its_upper_bound():
    """10^5 samples, none failing: the title gives P_f = 0 with its 95 % interval 0-3.69e-05 (never
    0.0000-0.0000), beta from P_f as its lower bound 3.96, and the FS at the mean inputs."""
    fs = np.linspace(1.5, 2.5, 100_000)
    summary = sweep_stats.failure_statistics(fs, np.zeros(fs.size, dtype=bool)) | {"fs_at_mean_inputs": 2.0}
    title = figures.distribution_figure(fs, summary, dpi=60).get_suptitle()
    assert "$P_f$ = 0 (95 % CI 0–3.69e-05)" in title and "0.0000" not in title
    assert "$\\geq$ 3.96" in title and "FS at the mean inputs = 2.000" in title
    counts = sweep_stats.convergence_counts(fs.size)
    table = sweep_stats.convergence(fs, np.zeros(fs.size, dtype=bool), counts)
    assert "95 % CI 0–3.69e-05" in figures.convergence_figure(table, summary, dpi=60).get_suptitle()


@pytest.mark.parametrize("samples", [3, 8, 12, 64, 100_000])
def test_the_study_figures_tick_whole_samples_and_give_the_invalid_count(samples):
    """The histogram's counts and the convergence plot's sample counts are ticked at whole numbers only
    (a 12-sample study was ticked at 0.25 samples), each figure's title counts the invalid samples."""
    fs = np.linspace(0.9, 1.4, samples)
    invalid = np.zeros(samples, dtype=bool)
    invalid[-1], fs[-1] = True, np.nan
    errors = np.zeros(samples, dtype=bool)
    summary = sweep_stats.failure_statistics(fs, errors, None, invalid)
    table = sweep_stats.convergence(fs, invalid, sweep_stats.convergence_counts(samples))
    histogram = figures.distribution_figure(fs, summary, dpi=60)
    convergence = figures.convergence_figure(table, summary, dpi=60)
    for fig in (histogram, convergence):
        fig.canvas.draw()
        assert f"{samples - 1} valid of {samples} samples (1 invalid," in fig.get_suptitle()
    counts = [histogram.axes[0].yaxis] + [ax.xaxis for ax in convergence.axes]
    for axis in counts:
        low, high = sorted(axis.get_view_interval())
        shown = [t for t in axis.get_majorticklocs() if low <= t <= high]
        assert shown and all(t == round(t) for t in shown), shown


@pytest.mark.parametrize(("p", "text"), [(0.0, "0"), (1.0, "1"), (3.6888e-5, "3.69e-05"), (0.25239, "0.252")])
def test_probability_text(p, text):
    assert figures.probability_text(p) == text


@pytest.mark.parametrize("mean", [3.87, 1e-6, 3.87e-300])
def test_lognormal_parameters_give_back_the_mean_and_spread_at_any_scale(mean):
    """E[X] = exp(mu + sigma^2 / 2) and CoV^2 = exp(sigma^2) - 1, in logs so that a mean of 3.87e-300
    (whose (std/mean)^2 overflowed, a traceback) is checked too."""
    std = 0.2 * 3.87
    mu, sigma = design.lognormal_parameters(mean, std)
    assert mu + 0.5 * sigma**2 == pytest.approx(math.log(mean), rel=1e-12)
    log_cov2 = sigma**2 + math.log(-math.expm1(-(sigma**2)))  # ln(exp(sigma^2) - 1), without overflow
    assert 0.5 * log_cov2 == pytest.approx(math.log(std / mean), rel=1e-12)


def test_a_long_tail_of_fs_is_cut_off_the_distribution_figure_and_counted():
    """A wedge study's FS reaches 10^4 where a few tiny wedges are held by large bolts: the figure's axes
    stop at the 99.5 % quantile where the largest FS lies more than 3 times further off, and the
    histogram's legend counts what is left off; a distribution without such a tail is drawn whole."""
    rng = np.random.default_rng(0)
    body = rng.lognormal(0.3, 0.3, 10_000)
    tailed = np.sort(np.concatenate([body, [5e3, 1e4]]))
    top = figures.drawn_range(tailed)
    assert top == pytest.approx(np.quantile(tailed, 0.995))
    assert figures.drawn_range(np.sort(body)) == body.max()
    stats = {
        "probability_of_failure": 0.1,
        "pf_ci_low": 0.09,
        "pf_ci_high": 0.11,
        "reliability_index_pf": 1.28,
        "reliability_index_normal": 1.0,
        "reliability_index_lognormal": 1.0,
        "mean_fs": 2.0,
        "std_fs": 1.0,
        "valid_samples": tailed.size,
        "samples": tailed.size,
        "invalid_samples": 0,
        "failed_runs": 0,
        "impossible_samples": 0,
    }
    figure = figures.distribution_figure(tailed, stats, dpi=50)
    legend = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
    beyond = int(np.count_nonzero(tailed > top))
    assert any(f"not drawn: {beyond:,} samples" in text for text in legend)
    assert figure.axes[1].get_xlim()[1] < 100.0
