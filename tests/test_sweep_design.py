"""The sweep's sampling design, its statistics and its figures (bbmc.sweep).

Every tolerance is stated where it is used. Designs are seeded, so each test is deterministic.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from bbmc.sweep import design, figures
from bbmc.sweep import statistics as sweep_stats
from bbmc.sweep.design import correlate, grid_table, marginal, saltelli_table, sample_table, unit_samples

TAN_PSI = math.tan(math.radians(35.0))  # the planar block's plane, psi = 35 deg


def _block_fs(tan_phi):
    """FS = tan(phi) / tan(psi) of a cohesionless block on a dry plane dipping at psi = 35 deg."""
    return np.asarray(tan_phi, dtype=float) / TAN_PSI


# 1. closed form ----------------------------------------------------------------------------------------


def test_monte_carlo_probability_of_failure_matches_closed_form():
    """tan(phi) ~ N(0.8, 0.15) makes FS exactly normal: mu = 0.8 / tan 35, sigma = 0.15 / tan 35,
    P_f = Phi((1 - mu) / sigma) = 0.2532. 10^4 Monte Carlo samples: |P_f - exact| <= 4 standard errors,
    and the Wilson 95 % interval covers the exact value."""
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


# 6. statistics --------------------------------------------------------------------------------------------


def test_failure_statistics_against_hand_values():
    """FS = 0.8, 1.2, 1.4, 1.6 and one failed run: mean 1.25, std sqrt(0.35 / 3) (ddof 1), P_f = 1/4;
    the indices by hand; all to rel 1e-12. Wilson for 1 of 4 by hand: 0.0456, 0.6994 (abs 5e-5)."""
    fs = np.array([0.8, 1.2, np.nan, 1.4, 1.6])
    errors = np.array([False, False, True, False, False])
    result = sweep_stats.failure_statistics(fs, errors)
    std = math.sqrt(0.35 / 3.0)
    v = std / 1.25
    assert result["samples"] == 5 and result["failed_runs"] == 1 and result["valid_samples"] == 4
    assert result["mean_fs"] == pytest.approx(1.25, rel=1e-12)
    assert result["std_fs"] == pytest.approx(std, rel=1e-12)
    assert result["probability_of_failure"] == 0.25
    assert result["standard_error"] == pytest.approx(math.sqrt(0.25 * 0.75 / 4.0), rel=1e-12)
    assert result["reliability_index_normal"] == pytest.approx(0.25 / std, rel=1e-12)
    expected_ln = math.log(1.25 / math.sqrt(1.0 + v * v)) / math.sqrt(math.log(1.0 + v * v))
    assert result["reliability_index_lognormal"] == pytest.approx(expected_ln, rel=1e-12)
    assert result["pf_ci_low"] == pytest.approx(0.0456, abs=5e-5)
    assert result["pf_ci_high"] == pytest.approx(0.6994, abs=5e-5)


@pytest.mark.parametrize(
    ("failures", "n", "low", "high"),
    [(81, 263, 0.2553, 0.3662), (15, 148, 0.0624, 0.1605), (0, 20, 0.0, 0.1611), (1, 29, 0.0061, 0.1718)],
)
def test_wilson_interval_against_newcombe_1998(failures, n, low, high):
    """Newcombe (1998, Stat. Med. 17:857, Table II, method 3: Wilson score without continuity
    correction), printed to 4 decimals: abs 5e-5."""
    assert sweep_stats.wilson_interval(failures, n) == pytest.approx((low, high), abs=5e-5)


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
    assert stable["pf_ci_low"] == 0.0 and 0.0 < stable["pf_ci_high"] < 1.0  # Wilson: 0 of 3 -> [0, 0.56]
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
    for name, fig in (
        ("tornado", figures.tornado_figure(rho, dpi=100)),
        ("distribution", figures.distribution_figure(fs, summary, dpi=100)),
    ):
        assert fig.axes and all(ax.has_data() for ax in fig.axes)
        path = tmp_path / f"{name}.png"
        fig.savefig(path)
        assert path.stat().st_size > 10_000


@pytest.mark.parametrize("mean", [3.87, 1e-6, 3.87e-300])
def test_lognormal_parameters_give_back_the_mean_and_spread_at_any_scale(mean):
    """E[X] = exp(mu + sigma^2 / 2) and CoV^2 = exp(sigma^2) - 1, in logs so that a mean of 3.87e-300
    (whose (std/mean)^2 overflowed, a traceback) is checked too."""
    std = 0.2 * 3.87
    mu, sigma = design.lognormal_parameters(mean, std)
    assert mu + 0.5 * sigma**2 == pytest.approx(math.log(mean), rel=1e-12)
    log_cov2 = sigma**2 + math.log(-math.expm1(-(sigma**2)))  # ln(exp(sigma^2) - 1), without overflow
    assert 0.5 * log_cov2 == pytest.approx(math.log(std / mean), rel=1e-12)
