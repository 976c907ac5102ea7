"""Tests of the Table 1 / Fig 2 regressions: straight lines and the power law y = a x^b."""

import numpy as np
import pytest

from bbmc.fitting import Fit, linear_fit, power_law_fit

# Synthetic x: the paper's four normal stresses (MPa) and a wider, denser set.
X_FOUR = np.array([0.05, 0.10, 0.15, 0.20])
X_WIDE = np.geomspace(0.01, 10.0, 25)


@pytest.mark.parametrize("x", [X_FOUR, X_WIDE])
@pytest.mark.parametrize(("slope", "intercept"), [(0.417, 0.0458), (-3.0, 12.5), (2.0, 0.0)])
def test_linear_fit_recovers_exact_line(x, slope, intercept):
    y = slope * x + intercept
    fit = linear_fit(x, y)
    assert isinstance(fit, Fit)
    assert (fit.kind, fit.method, fit.n_points) == ("line", "ols", x.size)
    assert fit.a == pytest.approx(slope, rel=1e-12)
    assert fit.b == pytest.approx(intercept, rel=1e-12, abs=1e-12)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)
    assert fit.r2_linear_y == fit.r2
    assert fit.r == pytest.approx(np.sign(slope), abs=1e-12)
    np.testing.assert_allclose(fit.predict(x), y, rtol=1e-12, atol=1e-12)


def test_linear_fit_accepts_lists_and_negative_values():
    fit = linear_fit([-2.0, -1.0, 0.0, 1.0], [5.0, 3.0, 1.0, -1.0])  # y = -2 x + 1
    assert fit.a == pytest.approx(-2.0)
    assert fit.b == pytest.approx(1.0)


@pytest.mark.parametrize("method", ["log-log", "nonlinear"])
@pytest.mark.parametrize("x", [X_FOUR, X_WIDE])
@pytest.mark.parametrize(("a", "b"), [(2.0547, 0.4881), (0.3, -1.2), (5.0, 2.0)])
def test_power_law_fit_recovers_exact_power_law(method, x, a, b):
    y = a * x**b
    fit = power_law_fit(x, y, method)
    assert (fit.kind, fit.method, fit.n_points) == ("power", method, x.size)
    assert fit.a == pytest.approx(a, rel=1e-8)
    assert fit.b == pytest.approx(b, rel=1e-8)
    assert fit.r2 == pytest.approx(1.0, abs=1e-10)
    assert fit.r2_linear_y == pytest.approx(1.0, abs=1e-10)
    # r is Pearson's r of ln y on ln x: +-1 for exact data
    assert fit.r == pytest.approx(np.sign(b), abs=1e-12)
    np.testing.assert_allclose(fit.predict(x), y, rtol=1e-8)


def _noisy_power_law(seed: int):
    rng = np.random.default_rng(seed)
    x = np.geomspace(0.05, 5.0, 30)
    y = 2.0547 * x**0.4881 * np.exp(rng.normal(0.0, 0.2, x.size))
    return x, y


def _r2_by_hand(y, y_hat):
    ss_res = sum((yi - fi) ** 2 for yi, fi in zip(y, y_hat, strict=True))
    mean = sum(y) / len(y)
    ss_tot = sum((yi - mean) ** 2 for yi in y)
    return 1.0 - ss_res / ss_tot


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_power_law_log_log_on_noisy_data(seed):
    x, y = _noisy_power_law(seed)
    fit = power_law_fit(x, y, "log-log")
    lx, ly = np.log(x), np.log(y)
    # ordinary least squares of ln y on ln x, by the normal equations
    n = lx.size
    slope = (n * np.sum(lx * ly) - lx.sum() * ly.sum()) / (n * np.sum(lx**2) - lx.sum() ** 2)
    intercept = (ly.sum() - slope * lx.sum()) / n
    assert fit.b == pytest.approx(slope, rel=1e-10)
    assert fit.a == pytest.approx(np.exp(intercept), rel=1e-10)
    # R^2 in log space = 1 - SS_res/SS_tot of ln y, and in linear y likewise, computed by hand
    ly_hat = [intercept + slope * v for v in lx]
    assert fit.r2 == pytest.approx(_r2_by_hand(list(ly), ly_hat), rel=1e-10)
    y_hat = [np.exp(intercept) * v**slope for v in x]
    assert fit.r2_linear_y == pytest.approx(_r2_by_hand(list(y), y_hat), rel=1e-10)
    assert 0.0 < fit.r2 < 1.0
    # for a straight-line fit R^2 is Pearson's r squared
    assert fit.r == pytest.approx(np.corrcoef(lx, ly)[0, 1], rel=1e-10)
    assert fit.r2 == pytest.approx(fit.r**2, rel=1e-10)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_power_law_methods_minimise_their_own_errors(seed):
    x, y = _noisy_power_law(seed)
    loglog = power_law_fit(x, y, "log-log")
    nonlinear = power_law_fit(x, y, "nonlinear")

    def sse_linear(f):
        return float(np.sum((y - f.predict(x)) ** 2))

    def sse_log(f):
        return float(np.sum((np.log(y) - np.log(f.predict(x))) ** 2))

    # each method is least squares in its own space, so it wins there (up to the optimiser's tolerance)
    assert sse_linear(nonlinear) <= sse_linear(loglog) * (1 + 1e-9)
    assert sse_log(loglog) <= sse_log(nonlinear) * (1 + 1e-12)
    assert nonlinear.r2_linear_y >= loglog.r2_linear_y - 1e-9
    assert loglog.r2 >= nonlinear.r2 - 1e-12
    # r is reported from the log-log regression either way
    assert nonlinear.r == loglog.r


@pytest.mark.parametrize(
    ("x", "y"),
    [
        ([1.0, 2.0, 3.0], [1.0, 2.0]),  # unequal lengths
        ([1.0], [1.0]),  # one point
        ([], []),  # no points
        ([2.0, 2.0, 2.0], [1.0, 2.0, 3.0]),  # all x equal
        (np.ones((2, 2)), np.ones(4)),  # same size, different shape
    ],
)
def test_bad_inputs_raise(x, y):
    with pytest.raises(ValueError):
        linear_fit(x, y)
    for method in ("log-log", "nonlinear"):
        with pytest.raises(ValueError):
            power_law_fit(x, y, method)


@pytest.mark.parametrize(
    ("x", "y"),
    [
        ([0.0, 1.0, 2.0], [1.0, 2.0, 3.0]),
        ([-1.0, 1.0, 2.0], [1.0, 2.0, 3.0]),
        ([1.0, 2.0, 3.0], [0.0, 2.0, 3.0]),
        ([1.0, 2.0, 3.0], [1.0, -2.0, 3.0]),
    ],
)
@pytest.mark.parametrize("method", ["log-log", "nonlinear"])
def test_power_law_rejects_non_positive(x, y, method):
    with pytest.raises(ValueError, match="x > 0 and y > 0"):
        power_law_fit(x, y, method)
    # a straight line does not care about the sign
    assert np.isfinite(linear_fit(x, y).a)


@pytest.mark.parametrize("method", ["loglog", "linear", "", "LOG-LOG"])
def test_power_law_unknown_method(method):
    with pytest.raises(ValueError, match="unknown power-law method"):
        power_law_fit(X_FOUR, 2.0 * X_FOUR**0.5, method)
