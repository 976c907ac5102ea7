"""Statistics of a probabilistic sweep: probability of failure, reliability indices, convergence,
sensitivities.

Definitions follow RocPlane's probabilistic analysis (Rocscience, RocPlane: Probability of failure,
Reliability index) and Hoek (2007, Practical Rock Engineering, ch. 8 "Factor of safety and probability
of failure"):

    P_f = (number of valid samples with FS < 1) / n        (n valid samples: run, with an FS; not
                                                         invalid, failed or impossible)
    beta_Pf        = -Phi^-1(P_f)                          (the normal FS that has this P_f)
    beta_normal    = (mu_FS - 1) / sigma_FS
    beta_lognormal = ln(mu_FS / sqrt(1 + V^2)) / sqrt(ln(1 + V^2)),   V = sigma_FS / mu_FS

sigma_FS is the sample standard deviation (ddof = 1). The 95 % interval of P_f is Clopper & Pearson's
(1934) exact binomial interval, whose coverage is at least 95 % for every P_f and n (Brown, Cai &
DasGupta 2001 call it conservative; it is the one that never promises more than it holds, which is
what a safety margin needs):

    low  = B^-1(0.025; k, n - k + 1)   (0 if k = 0),
    high = B^-1(0.975; k + 1, n - k)   (1 if k = n),     k failures in n valid samples,

B^-1 the beta distribution's quantile. With no failure, high = 1 - 0.025^(1/n) (3.69e-5 for n = 10^5;
Wilson's score interval gives 3.84e-5 there and the one-sided 95 % bound 1 - 0.05^(1/n) = 3.00e-5,
the "rule of three" 3/n). beta_Pf at the interval's upper end, -Phi^-1(high), is a 95 % lower bound
of beta_Pf: finite where beta_Pf is +inf (no sample failed).

The standard error sqrt(p (1 - p) / n) is the binomial one (0 when no sample, or every sample, fails:
then read the interval, whose width is not 0).

Rules at the edges (each a stated value, never a silent NaN):

* fewer than 2 valid samples (in particular every run failed): ValueError; no statistic exists.
* sigma_FS = 0 (every valid FS equal): both moment betas are +inf if mu_FS > 1, -inf if mu_FS < 1,
  and 0 if mu_FS = 1 (the limit state itself).
* mu_FS <= 0: the lognormal model does not apply (it needs FS > 0); beta_lognormal = -inf.
* P_f = 0: beta_Pf = +inf; P_f = 1: beta_Pf = -inf.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from SALib.analyze import sobol as salib_sobol
from scipy import stats

CONFIDENCE = 0.95


def clopper_pearson_interval(
    failures: ArrayLike, n: ArrayLike, confidence: float = CONFIDENCE
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Clopper & Pearson's exact two-sided interval of a binomial proportion failures / n (element by
    element for arrays; see the module docstring)."""
    k, n = np.asarray(failures, dtype=float), np.asarray(n, dtype=float)
    if np.any(n < 1) or np.any((k < 0) | (k > n)):
        raise ValueError(f"need 0 <= failures <= n and n >= 1, got failures={failures}, n={n}")
    alpha = 1.0 - confidence
    with np.errstate(invalid="ignore", divide="ignore"):  # the k = 0 and k = n ends are set below
        low = np.where(k > 0, stats.beta.ppf(alpha / 2.0, k, n - k + 1.0), 0.0)
        high = np.where(k < n, stats.beta.ppf(1.0 - alpha / 2.0, k + 1.0, n - k), 1.0)
    return low, high


def reliability_index_from_probability(p: ArrayLike) -> NDArray[np.float64]:
    """beta = -Phi^-1(p): +inf at p = 0, -inf at p = 1."""
    return -stats.norm.ppf(np.asarray(p, dtype=float))


def _beta_when_no_spread(mean: float) -> float:
    return math.inf if mean > 1.0 else (-math.inf if mean < 1.0 else 0.0)


def reliability_index_normal(mean: float, std: float) -> float:
    """beta = (mu_FS - 1) / sigma_FS [1]; the module's rule where sigma_FS = 0."""
    return _beta_when_no_spread(mean) if std == 0.0 else (mean - 1.0) / std


def reliability_index_lognormal(mean: float, std: float) -> float:
    """beta = ln(mu / sqrt(1 + V^2)) / sqrt(ln(1 + V^2)), V = sigma / mu [1]; the module's rules where
    sigma = 0 and mu <= 0."""
    if mean <= 0.0:
        return -math.inf
    if std == 0.0:
        return _beta_when_no_spread(mean)
    v2 = (std / mean) ** 2
    return math.log(mean / math.sqrt(1.0 + v2)) / math.sqrt(math.log1p(v2))


def _valid_fs(fs: ArrayLike, excluded: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    fs = np.asarray(fs, dtype=float).ravel()
    excluded = np.asarray(excluded, dtype=bool).ravel()
    if fs.shape != excluded.shape:
        raise ValueError(f"fs and the excluded samples differ in length: {fs.size} and {excluded.size}")
    unmarked = np.flatnonzero(~excluded & ~np.isfinite(fs))
    if unmarked.size:
        raise ValueError(f"FS is not finite at samples {unmarked[:10].tolist()} not marked as failed runs")
    return fs, ~excluded


def failure_statistics(
    fs: ArrayLike, errors: ArrayLike, impossible: ArrayLike | None = None, invalid: ArrayLike | None = None
) -> dict[str, float]:
    """The sweep's summary: FS per sample (NaN where the run failed or was not run), the mask of failed
    runs, that of samples not run for impossible inputs and that of invalid samples (their own scene at
    fault; `bbmc.sweep.models`), the last two none if not given.

    Returns samples (all), valid_samples, invalid_samples, failed_runs, impossible_samples, mean_fs,
    std_fs (ddof = 1),
    probability_of_failure (fraction of valid samples with FS < 1), pf_ci_low and pf_ci_high
    (Clopper-Pearson 95 %), standard_error (sqrt(p (1 - p) / n)), reliability_index_pf (-Phi^-1(P_f)),
    reliability_index_pf_lower_bound (-Phi^-1(pf_ci_high)), reliability_index_normal and
    reliability_index_lognormal; see the module docstring for the definitions and the edge rules.
    A sample not marked in either mask must have a finite FS (ValueError otherwise).
    """
    errors = np.asarray(errors, dtype=bool).ravel()
    impossible, invalid = (
        np.zeros(errors.shape, dtype=bool) if mask is None else np.asarray(mask, dtype=bool).ravel()
        for mask in (impossible, invalid)
    )
    fs, valid = _valid_fs(fs, errors | impossible | invalid)
    values = fs[valid]
    n = values.size
    if n < 2:
        raise ValueError(
            f"{n} valid sample(s) out of {fs.size} ({int(invalid.sum())} invalid, {int(errors.sum())} "
            f"failed runs, {int(impossible.sum())} impossible inputs): no statistics"
        )
    mean, std = float(values.mean()), float(values.std(ddof=1))
    failures = int(np.count_nonzero(values < 1.0))
    p = failures / n
    low, high = (float(bound) for bound in clopper_pearson_interval(failures, n))
    return {
        "samples": int(fs.size),
        "valid_samples": int(n),
        "invalid_samples": int(invalid.sum()),
        "failed_runs": int(errors.sum()),
        "impossible_samples": int(impossible.sum()),
        "mean_fs": mean,
        "std_fs": std,
        "probability_of_failure": p,
        "pf_ci_low": low,
        "pf_ci_high": high,
        "standard_error": math.sqrt(p * (1.0 - p) / n),
        "reliability_index_pf": float(reliability_index_from_probability(p)),
        "reliability_index_pf_lower_bound": float(reliability_index_from_probability(high)),
        "reliability_index_normal": reliability_index_normal(mean, std),
        "reliability_index_lognormal": reliability_index_lognormal(mean, std),
    }


def convergence_counts(samples: int, points: int = 40, first: int = 10) -> NDArray[np.int64]:
    """Sample counts spaced evenly in log from `first` (or fewer, if the study is smaller) to
    `samples`, the last always `samples`."""
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    counts = np.geomspace(min(first, samples), samples, points).round().astype(np.int64)
    return np.unique(np.append(counts, samples))


def convergence(fs: ArrayLike, excluded: ArrayLike, counts: ArrayLike) -> pd.DataFrame:
    """P_f and mean FS over the first `samples` samples of the design (in its order), for each count:
    columns samples, valid_samples, failures, probability_of_failure, pf_ci_low, pf_ci_high (Clopper-
    Pearson 95 %), mean_fs, mean_fs_ci_low, mean_fs_ci_high (mean -+ 1.96 sigma / sqrt(n), the normal
    interval of a mean) over the valid samples among them. A count with no valid sample has NaN
    statistics (1 valid sample: NaN spread)."""
    fs, valid = _valid_fs(fs, excluded)
    counts = np.asarray(counts, dtype=np.int64)
    if counts.size == 0 or counts.min() < 1 or counts.max() > fs.size:
        raise ValueError(f"counts must lie in 1..{fs.size}")
    shift = float(fs[valid].mean()) if valid.any() else 0.0  # sums of deviations: no cancellation
    deviation = np.where(valid, fs - shift, 0.0)
    n = np.cumsum(valid)[counts - 1]
    failures = np.cumsum(valid & (fs < 1.0))[counts - 1]
    total = np.cumsum(deviation)[counts - 1]
    squares = np.cumsum(deviation * deviation)[counts - 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = shift + total / n
        variance = np.maximum(squares - total * total / n, 0.0) / (n - 1)
        half = stats.norm.ppf(0.5 + CONFIDENCE / 2.0) * np.sqrt(variance / n)
        p = failures / n
    some = n > 0
    low, high = np.full(n.shape, np.nan), np.full(n.shape, np.nan)
    if some.any():
        low[some], high[some] = clopper_pearson_interval(failures[some], n[some])
    return pd.DataFrame(
        {
            "samples": counts,
            "valid_samples": n,
            "failures": failures,
            "probability_of_failure": np.where(some, p, np.nan),
            "pf_ci_low": low,
            "pf_ci_high": high,
            "mean_fs": np.where(some, mean, np.nan),
            "mean_fs_ci_low": np.where(n > 1, mean - half, np.nan),
            "mean_fs_ci_high": np.where(n > 1, mean + half, np.nan),
        }
    )


def spearman(inputs: pd.DataFrame, fs: ArrayLike) -> pd.Series:
    """Spearman's rank correlation of FS with each input (scipy.stats.spearmanr) over the valid samples
    (finite FS), sorted by |rho| descending; index "variable", name "spearman_rho".

    Rows of `inputs` pair with `fs` by position. An input (or an FS) that does not vary over the valid
    samples has no rank correlation: it gets 0 (stated, not NaN), so it sits at the bottom of a tornado.
    """
    fs = np.asarray(fs, dtype=float).ravel()
    if len(inputs) != fs.size:
        raise ValueError(f"inputs has {len(inputs)} rows and fs {fs.size} values")
    valid = np.isfinite(fs)
    if valid.sum() < 3:
        raise ValueError(f"{int(valid.sum())} valid samples: too few for a rank correlation")
    y = fs[valid]
    rho = {}
    for name in inputs.columns:
        x = inputs[name].to_numpy(dtype=float)[valid]
        if np.ptp(x) == 0.0 or np.ptp(y) == 0.0:
            rho[name] = 0.0
        else:
            rho[name] = float(stats.spearmanr(x, y).statistic)
    series = pd.Series(rho, name="spearman_rho", dtype=float)
    series.index.name = "variable"
    return series.iloc[np.argsort(-np.abs(series.to_numpy()), kind="stable")]


def sobol_indices(problem: dict, fs: ArrayLike, seed: int) -> pd.DataFrame:
    """First-order and total Sobol' indices of FS (SALib.analyze.sobol.analyze, calc_second_order =
    False: Saltelli et al. 2010's estimators, Jansen's for S_T), with 95 % bootstrap half-widths.

    `problem` and the row order are those of `design.saltelli_table`; fs has one value per row, all
    finite (the estimators pair rows across blocks; a failed run cannot be dropped: ValueError).
    Returns columns S1, S1_conf, ST, ST_conf, index "variable" (the problem's names).
    """
    fs = np.asarray(fs, dtype=float).ravel()
    d = int(problem["num_vars"])
    if fs.size % (d + 2):
        raise ValueError(f"{fs.size} FS values is not a multiple of d + 2 = {d + 2} (Saltelli's design)")
    if not np.all(np.isfinite(fs)):
        raise ValueError(f"{int((~np.isfinite(fs)).sum())} FS values are not finite: Sobol' indices need all")
    result = salib_sobol.analyze(problem, fs, calc_second_order=False, print_to_console=False, seed=seed)
    table = pd.DataFrame(
        {key: np.asarray(result[key], dtype=float) for key in ("S1", "S1_conf", "ST", "ST_conf")},
        index=pd.Index(problem["names"], name="variable"),
    )
    return table
