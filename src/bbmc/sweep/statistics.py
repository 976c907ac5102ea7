"""Statistics of a probabilistic sweep: probability of failure, reliability indices, sensitivities.

Definitions follow RocPlane's probabilistic analysis (Rocscience, RocPlane: Probability of failure,
Reliability index) and Hoek (2007, Practical Rock Engineering, ch. 8 "Factor of safety and probability
of failure"):

    P_f = (number of valid samples with FS < 1) / n        (n valid samples: runs that did not fail)
    beta_normal    = (mu_FS - 1) / sigma_FS
    beta_lognormal = ln(mu_FS / sqrt(1 + V^2)) / sqrt(ln(1 + V^2)),   V = sigma_FS / mu_FS

sigma_FS is the sample standard deviation (ddof = 1). The 95 % interval of P_f is Wilson's score
interval (Wilson 1927; recommended over the normal "Wald" interval by Newcombe 1998 and Brown, Cai &
DasGupta 2001: it stays inside [0, 1] and covers well when P_f is near 0, as it is for a good design):

    low, high = (p + z^2/2n) / (1 + z^2/n)  -+  z / (1 + z^2/n) sqrt(p (1 - p)/n + z^2/4n^2),
    p = failures / n,  z = Phi^-1(0.975) = 1.95996

The standard error sqrt(p (1 - p) / n) is the binomial one (0 when no sample, or every sample, fails:
then read the Wilson interval, whose width is not 0).

Rules at the edges (each a stated value, never a silent NaN):

* fewer than 2 valid samples (in particular every run failed): ValueError; no statistic exists.
* sigma_FS = 0 (every valid FS equal): both betas are +inf if mu_FS > 1, -inf if mu_FS < 1, and 0 if
  mu_FS = 1 (the limit state itself).
* mu_FS <= 0: the lognormal model does not apply (it needs FS > 0); beta_lognormal = -inf.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from SALib.analyze import sobol as salib_sobol
from scipy import stats

Z_95 = float(stats.norm.ppf(0.975))


def wilson_interval(failures: int, n: int, z: float = Z_95) -> tuple[float, float]:
    """Wilson's score interval of a binomial proportion failures / n (95 % for z = 1.95996)."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    p = failures / n
    z2 = z * z
    centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n)
    half = z / (1.0 + z2 / n) * math.sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n))
    return max(centre - half, 0.0), min(centre + half, 1.0)


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


def failure_statistics(fs: ArrayLike, errors: ArrayLike) -> dict[str, float]:
    """The sweep's summary: FS per sample (NaN where the run failed) and the mask of failed runs.

    Returns samples (all, failed included), failed_runs, valid_samples, mean_fs, std_fs (ddof = 1),
    probability_of_failure (fraction of valid samples with FS < 1), pf_ci_low and pf_ci_high (Wilson
    95 %), standard_error (sqrt(p (1 - p) / n)), reliability_index_normal and
    reliability_index_lognormal; see the module docstring for the definitions and the edge rules.
    A run not marked failed must have a finite FS (ValueError otherwise: mark it in `errors`).
    """
    fs = np.asarray(fs, dtype=float).ravel()
    errors = np.asarray(errors, dtype=bool).ravel()
    if fs.shape != errors.shape:
        raise ValueError(f"fs and errors differ in length: {fs.size} and {errors.size}")
    valid = ~errors
    unmarked = np.flatnonzero(valid & ~np.isfinite(fs))
    if unmarked.size:
        raise ValueError(f"FS is not finite at samples {unmarked[:10].tolist()} not marked as failed runs")
    values = fs[valid]
    n = values.size
    if n < 2:
        raise ValueError(
            f"{n} valid sample(s) out of {fs.size} ({int(errors.sum())} failed runs): no statistics"
        )
    mean, std = float(values.mean()), float(values.std(ddof=1))
    failures = int(np.count_nonzero(values < 1.0))
    p = failures / n
    low, high = wilson_interval(failures, n)
    return {
        "samples": int(fs.size),
        "failed_runs": int(errors.sum()),
        "valid_samples": int(n),
        "mean_fs": mean,
        "std_fs": std,
        "probability_of_failure": p,
        "pf_ci_low": low,
        "pf_ci_high": high,
        "standard_error": math.sqrt(p * (1.0 - p) / n),
        "reliability_index_normal": reliability_index_normal(mean, std),
        "reliability_index_lognormal": reliability_index_lognormal(mean, std),
    }


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
