"""Sampling designs of a probabilistic sweep: marginals, unit-hypercube designs, a Gaussian copula.

A sweep draws points u in the open unit hypercube (0, 1)^d, then maps each column through the inverse
CDF (ppf) of its variable's marginal distribution: x_k = F_k^-1(u_k). The designs:

* "monte_carlo": independent uniforms from numpy's default_rng(seed); the error of a mean falls as
  n^-1/2 whatever the dimension.
* "latin_hypercube": McKay, Beckman & Conover (1979), scipy.stats.qmc.LatinHypercube; each column has
  exactly one point in each of the n strata [k/n, (k+1)/n), so the additive part of a response is
  integrated almost exactly (Stein 1987) and its mean converges faster than Monte Carlo's.
* "sobol": Sobol' (1967) low-discrepancy sequence with Owen's scrambling, scipy.stats.qmc.Sobol.

Marginals follow RocPlane's input conventions (Rocscience, RocPlane: Statistical distributions):
a lognormal is given by the mean and standard deviation of the variable itself; a truncated normal by
the mean and standard deviation of the normal before truncation and the absolute bounds (RocPlane enters
"relative" bounds, distances from the mean: min = mean - relative min, max = mean + relative max).

An input whose key accepts only a range of values (a cohesion >= 0, a tan phi > 0: `bbmc.sweep.ranges`)
is sampled from its distribution truncated to that range (`Truncated`: renormalised, not clipped), as
RocPlane truncates its inputs.

Correlation between two inputs (RocPlane correlates cohesion and friction angle) is imposed with a
Gaussian copula on the normal scores (see `correlate`). Units are those of each variable; this module
never converts them.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from SALib.sample import sobol as salib_sobol
from scipy import stats
from scipy.stats import qmc

METHODS = ("monte_carlo", "latin_hypercube", "sobol")

# Points are kept this far inside (0, 1): 2^-53 maps to |z| = 8.1 standard normal deviates, finite for
# every marginal's ppf; a design point exactly 0 (possible in all three designs) would map to -inf.
UNIT_EPS = 2.0**-53

_PARAMETERS = {
    "normal": ("mean", "std"),
    "lognormal": ("mean", "std"),
    "uniform": ("min", "max"),
    "triangular": ("min", "mode", "max"),
    "truncated_normal": ("mean", "std", "min", "max"),
    "realization": (),
}

# Bounds of a truncation holding less than this of the distribution's probability are refused.
LEAST_MASS = 1e-12

Variable = tuple[str, "stats.rv_continuous | Truncated"]  # a name and anything with ppf(u)


def _check_parameters(kind: str, params: dict[str, float]) -> dict[str, float]:
    if kind not in _PARAMETERS:
        raise ValueError(f"unknown distribution kind {kind!r}; expected one of {sorted(_PARAMETERS)}")
    expected = _PARAMETERS[kind]
    missing = [name for name in expected if name not in params]
    extra = [name for name in params if name not in expected]
    if missing or extra:
        raise ValueError(f"{kind} takes parameters {expected}: missing {missing}, unexpected {extra}")
    values = {name: float(params[name]) for name in expected}
    for name, value in values.items():
        if not math.isfinite(value):
            raise ValueError(f"{kind}: parameter {name} must be finite, got {value}")
    if "std" in values and values["std"] <= 0.0:
        raise ValueError(f"{kind}: parameter std must be > 0, got {values['std']}")
    if "min" in values and values["min"] >= values["max"]:
        raise ValueError(f"{kind}: parameter min must be < max, got min={values['min']}, max={values['max']}")
    return values


def lognormal_parameters(mean: float, std: float) -> tuple[float, float]:
    """(mu, sigma) of ln X for a lognormal X of mean m and standard deviation s (both of X itself):

        sigma^2 = ln(1 + (s/m)^2),   mu = ln m - sigma^2 / 2

    (Aitchison & Brown 1957; the inverse of E[X] = exp(mu + sigma^2/2), V[X] = E[X]^2 (exp(sigma^2) - 1)).
    1 + (s/m)^2 is taken as hypot(1, s/m)^2, which does not overflow (a mean of 3.87e-300 did).
    """
    ratio = std / mean
    sigma2 = math.log1p(ratio * ratio) if abs(ratio) < 1e150 else 2.0 * math.log(math.hypot(1.0, ratio))
    return math.log(mean) - 0.5 * sigma2, math.sqrt(sigma2)


class Realizations:
    """A realization seed per sample (a rock mass's `seed`): the design's u in (0, 1) mapped to one of
    2^31 seeds, floor(2^31 u), so every sample draws its own geometry and the study integrates over it
    (Einstein et al. 1983). It has no mean: the FS at the mean inputs keeps the base's own seed."""

    SEEDS = 2**31

    def ppf(self, u: ArrayLike) -> NDArray[np.float64]:
        return np.floor(np.asarray(u, dtype=float) * self.SEEDS)


def marginal(kind: str, **params: float):
    """A frozen scipy.stats distribution for one uncertain input, from RocPlane-style parameters.

    kind and its parameters (each in the variable's own unit):

    * "normal": mean, std (> 0).
    * "lognormal": mean (> 0), std (> 0) of the variable itself, converted by `lognormal_parameters`
      to scipy's lognorm(s=sigma, scale=exp(mu)).
    * "uniform": min < max.
    * "triangular": min <= mode <= max, min < max; scipy's triang(c=(mode-min)/(max-min)).
    * "realization": no parameters; a seed per sample (`Realizations`).
    * "truncated_normal": mean, std (> 0) of the normal before truncation, absolute bounds min < max;
      scipy's truncnorm(a=(min-mean)/std, b=(max-mean)/std). Its own mean and std differ from the
      parameters unless the bounds are far out. Bounds holding less than 1e-12 of the normal's
      probability are refused (the ppf would be meaningless).

    Raises ValueError naming the parameter for a meaningless value, a missing or an unexpected one.
    """
    p = _check_parameters(kind, params)
    if kind == "realization":
        return Realizations()
    if kind == "normal":
        return stats.norm(loc=p["mean"], scale=p["std"])
    if kind == "lognormal":
        if p["mean"] <= 0.0:
            raise ValueError(f"lognormal: parameter mean must be > 0, got {p['mean']}")
        mu, sigma = lognormal_parameters(p["mean"], p["std"])
        return stats.lognorm(s=sigma, scale=math.exp(mu))
    if kind == "uniform":
        return stats.uniform(loc=p["min"], scale=p["max"] - p["min"])
    if kind == "triangular":
        if not p["min"] <= p["mode"] <= p["max"]:
            raise ValueError(f"triangular: parameter mode must lie in [min, max], got {p['mode']}")
        width = p["max"] - p["min"]
        return stats.triang(c=(p["mode"] - p["min"]) / width, loc=p["min"], scale=width)
    a, b = (p["min"] - p["mean"]) / p["std"], (p["max"] - p["mean"]) / p["std"]
    if stats.norm.cdf(b) - stats.norm.cdf(a) < LEAST_MASS:
        raise ValueError(
            f"truncated_normal: parameters min, max = [{p['min']}, {p['max']}] hold almost none of the "
            f"normal N({p['mean']}, {p['std']})"
        )
    return stats.truncnorm(a=a, b=b, loc=p["mean"], scale=p["std"])


class Truncated:
    """A distribution restricted to [low, high] and renormalised (not clipped): its CDF there is

        F_T(x) = (F(x) - F(low)) / (F(high) - F(low)),

    sampled by the inverse CDF on the truncated range, x = F^-1(F(low) + u (F(high) - F(low))), so a
    design's stratification (Latin hypercube, Sobol) carries over to x. Computed from the lower tail
    where F_T^-1 lies below the median and from the upper one (F^-1 = isf of the survival function)
    above it, so that a bound deep in a tail keeps the precision of u. For a normal this is scipy's
    truncnorm. `probability_cut` = F(low) + 1 - F(high), the part of the distribution left out.
    Raises ValueError if less than LEAST_MASS of the probability lies in [low, high].
    """

    def __init__(self, dist: stats.rv_continuous, low: float, high: float) -> None:
        self.dist, self.low, self.high = dist, float(low), float(high)
        self.below, self.above = float(dist.cdf(self.low)), float(dist.sf(self.high))
        if self.below > 0.5:  # both bounds in the upper tail: the difference of survival functions
            self.kept = float(dist.sf(self.low)) - self.above
        elif self.above > 0.5:  # both in the lower tail
            self.kept = float(dist.cdf(self.high)) - self.below
        else:
            self.kept = 1.0 - self.below - self.above
        if not self.kept >= LEAST_MASS:
            raise ValueError(
                f"[{self.low:g}, {self.high:g}] holds almost none ({self.kept:.2g}) of the "
                "distribution's probability"
            )

    @property
    def probability_cut(self) -> float:
        return self.below + self.above

    def ppf(self, u: ArrayLike) -> NDArray[np.float64]:
        u = np.asarray(u, dtype=float)
        lower = self.below + u * self.kept
        upper = self.above + (1.0 - u) * self.kept
        return np.where(
            lower <= 0.5, self.dist.ppf(np.minimum(lower, 0.5)), self.dist.isf(np.minimum(upper, 0.5))
        )

    def mean(self) -> float:
        """E[X | low <= X <= high], by quadrature (scipy's expect, conditional)."""
        return float(self.dist.expect(lb=self.low, ub=self.high, conditional=True))

    def support(self) -> tuple[float, float]:
        low, high = self.dist.support()
        return max(float(low), self.low), min(float(high), self.high)


def truncation(dist: stats.rv_continuous, low: float, high: float) -> Truncated | None:
    """`dist` truncated to [low, high] if its support reaches beyond them, else None."""
    support_low, support_high = dist.support()
    if support_low >= low and support_high <= high:
        return None
    return Truncated(dist, low, high)


def _to_open_interval(u: NDArray) -> NDArray:
    return np.clip(u, UNIT_EPS, 1.0 - UNIT_EPS)


def unit_samples(dimensions: int, n: int, method: str, seed: int) -> NDArray[np.float64]:
    """n points of the open unit hypercube (0, 1)^dimensions, shape (n, dimensions).

    method: "monte_carlo" (numpy default_rng(seed).random), "latin_hypercube" (scipy.stats.qmc.
    LatinHypercube(d, seed=seed), randomised within strata) or "sobol" (scipy.stats.qmc.Sobol(d,
    scramble=True, seed=seed)). The same seed gives the same array. Points are clipped to
    [2^-53, 1 - 2^-53] so every ppf is finite.

    Sobol with n not a power of 2: the first n points of the scrambled sequence are returned and scipy
    warns (UserWarning, "balance properties ... require n to be a power of 2"). The estimates stay
    unbiased (the scrambling randomises them) but lose the low-discrepancy convergence rate that only a
    complete 2^m block has; choose n = 2^m with Sobol.
    """
    if dimensions < 1:
        raise ValueError(f"dimensions must be >= 1, got {dimensions}")
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    if method == "monte_carlo":
        u = np.random.default_rng(seed).random((n, dimensions))
    elif method == "latin_hypercube":
        u = qmc.LatinHypercube(dimensions, seed=seed).random(n)
    elif method == "sobol":
        u = qmc.Sobol(dimensions, scramble=True, seed=seed).random(n)
    else:
        raise ValueError(f"unknown sampling method {method!r}; expected one of {METHODS}")
    return _to_open_interval(u)


def correlate(u: NDArray, i: int, j: int, rho: float) -> NDArray[np.float64]:
    """A copy of u with columns i and j correlated through a Gaussian copula (Nataf transform):

        z = Phi^-1(u),   z_j <- rho z_i + sqrt(1 - rho^2) z_j,   u = Phi(z)

    rho (-1 < rho < 1) is the correlation of the normal scores z_i, z_j. It is the Pearson correlation
    of the marginals exactly when both are normal; the Spearman (rank) correlation of any continuous
    marginals is (6/pi) arcsin(rho/2) (0.483 for rho = 0.5), and the Pearson correlation of other
    marginals is usually a little smaller in magnitude (lognormals: (exp(rho s_i s_j) - 1) /
    sqrt((exp(s_i^2) - 1)(exp(s_j^2) - 1))). Column i and the others are unchanged; column j loses
    the stratification of a Latin hypercube or Sobol design (it mixes two stratified columns), which
    is the usual price of the method (Iman & Conover 1982 keep it by rank reordering instead).
    """
    u = np.asarray(u, dtype=float)
    if u.ndim != 2:
        raise ValueError(f"u must be a 2-d array (n, d), got shape {u.shape}")
    d = u.shape[1]
    if not (0 <= i < d and 0 <= j < d) or i == j:
        raise ValueError(f"columns i={i}, j={j} must be two different columns of 0..{d - 1}")
    if not -1.0 < rho < 1.0:
        raise ValueError(f"rho must lie in (-1, 1), got {rho}")
    z = stats.norm.ppf(_to_open_interval(u))
    out = u.copy()
    out[:, j] = stats.norm.cdf(rho * z[:, i] + math.sqrt(1.0 - rho * rho) * z[:, j])
    return _to_open_interval(out)


def _names(variables: list[Variable]) -> list[str]:
    if not variables:
        raise ValueError("no variables to sample")
    names = [name for name, _ in variables]
    if len(set(names)) != len(names):
        raise ValueError(f"variable names must be unique, got {names}")
    return names


def _table(names: list[str], values: NDArray) -> pd.DataFrame:
    return pd.DataFrame(values, columns=names, index=pd.RangeIndex(len(values), name="sample"))


def _map(variables: list[Variable], u: NDArray) -> NDArray[np.float64]:
    return np.column_stack([dist.ppf(u[:, k]) for k, (_, dist) in enumerate(variables)])


def sample_table(
    variables: list[Variable],
    n: int,
    method: str,
    seed: int,
    correlation: tuple[str, str, float] | None = None,
) -> pd.DataFrame:
    """The sweep's inputs: one column per variable (its name, e.g. "joint_laws.joint.friction_deg"),
    index "sample" 0..n-1, values x = F^-1(u) with u from `unit_samples(len(variables), n, method,
    seed)`, and, if `correlation` = (name_a, name_b, rho), the copula of `correlate` between them
    (name_b's column is the one modified)."""
    names = _names(variables)
    u = unit_samples(len(variables), n, method, seed)
    if correlation is not None:
        a, b, rho = correlation
        for name in (a, b):
            if name not in names:
                raise ValueError(f"correlation names {name!r}, which is not a sampled variable")
        u = correlate(u, names.index(a), names.index(b), rho)
    return _table(names, _map(variables, u))


def crossed_table(
    geometry: list[Variable],
    others: list[Variable],
    realizations: int,
    samples: int,
    method: str,
    seed: int,
    correlation: tuple[str, str, float] | None = None,
) -> pd.DataFrame:
    """A crossed design: `realizations` n draws of the geometry variables (a rock mass's seed and what
    goes with it) and `samples` m draws of the others, each by `sample_table` from its own stream
    (numpy SeedSequence(seed).spawn(2): independent groups), every draw of the others paired with
    every realization. Row r m + s (index "sample") holds realization r and draw s, so FS reshaped to
    (n, m) is FS[r, s] (`bbmc.sweep.shares`); `correlation` between two of the others. n m rows."""
    streams = [int(child.generate_state(1)[0]) for child in np.random.SeedSequence(seed).spawn(2)]
    shapes = sample_table(geometry, realizations, method, streams[0])
    strengths = sample_table(others, samples, method, streams[1], correlation)
    rows = np.repeat(shapes.to_numpy(), samples, axis=0)
    columns = np.tile(strengths.to_numpy(), (realizations, 1))
    return _table([*shapes.columns, *strengths.columns], np.column_stack([rows, columns]))


def saltelli_table(variables: list[Variable], n: int, seed: int) -> tuple[pd.DataFrame, dict]:
    """Saltelli's design for first- and total-order Sobol' indices, and the SALib problem to analyse it.

    SALib.sample.sobol.sample(problem, n, calc_second_order=False, seed=seed) on [0, 1]^d (Saltelli
    2002; Saltelli et al. 2010): n (d + 2) rows, the blocks A, AB_1..AB_d, B; each column is then mapped
    through its marginal's ppf (clipped to [2^-53, 1 - 2^-53]). Pass the returned problem, and the FS of
    every row in order, to `statistics.sobol_indices`. n must be a power of 2 (Sobol' balance),
    otherwise ValueError.
    """
    names = _names(variables)
    if n < 2 or n & (n - 1):
        raise ValueError(f"n must be a power of 2 (>= 2) for Saltelli's Sobol' design, got {n}")
    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    u = salib_sobol.sample(problem, n, calc_second_order=False, seed=seed)
    return _table(names, _map(variables, _to_open_interval(u))), problem


def grid_table(axes: list[tuple[str, list[float]]]) -> pd.DataFrame:
    """The cartesian product of the axes' values (the first axis varies slowest), index "sample"."""
    if not axes:
        raise ValueError("no axes to combine")
    names = [name for name, _ in axes]
    if len(set(names)) != len(names):
        raise ValueError(f"axis names must be unique, got {names}")
    for name, values in axes:
        if len(values) == 0:
            raise ValueError(f"axis {name!r} has no values")
    rows = list(itertools.product(*(list(values) for _, values in axes)))
    return _table(names, np.asarray(rows, dtype=float))


def grid_realizations_table(
    axes: list[tuple[str, list[float]]],
    variables: list[Variable],
    realizations: int,
    seed: int,
    correlation: tuple[str, str, float] | None = None,
) -> pd.DataFrame:
    """A parameter study over realizations: every grid point (`grid_table`) run with the same
    `realizations` n draws of the variables (a rock mass's seed and what goes with it; a Latin hypercube
    from `seed`, `sample_table`), so that the realizations are paired across the grid (common random
    numbers: a change of FS from one grid point to the next is the parameter's, not another draw's). Row
    g n + r (index "sample") holds grid point g and realization r. n x (grid points) rows."""
    points = grid_table(axes)
    draws = sample_table(variables, realizations, "latin_hypercube", seed, correlation)
    rows = np.repeat(points.to_numpy(), realizations, axis=0)
    columns = np.tile(draws.to_numpy(), (len(points), 1))
    return _table([*points.columns, *draws.columns], np.column_stack([rows, columns]))
