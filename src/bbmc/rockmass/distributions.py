"""The distributions of a joint set's lengths and dips, as frozen scipy.stats distributions.

Every sample is drawn with `.rvs(size=..., random_state=rng)` from a numpy Generator, so a realization
is reproducible from its seed. A constant is a distribution too (`Fixed`), with the same interface.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from scipy import stats

from bbmc.rockmass import config as c


class Sampler(Protocol):
    """What the generator needs of a distribution (a scipy frozen distribution has all of it)."""

    def rvs(self, size: int, random_state: np.random.Generator) -> np.ndarray: ...

    def mean(self) -> float: ...

    def var(self) -> float: ...

    def cdf(self, x: np.ndarray) -> np.ndarray: ...


class Fixed:
    """A constant, as a distribution: every draw is `value` (drawing it leaves the generator as it was)."""

    def __init__(self, value: float) -> None:
        self.value = value

    def rvs(self, size: int, random_state: np.random.Generator) -> np.ndarray:
        return np.full(size, self.value)

    def mean(self) -> float:
        return self.value

    def var(self) -> float:
        return 0.0

    def cdf(self, x: np.ndarray) -> np.ndarray:
        return (np.asarray(x) >= self.value).astype(float)


def length(spec: float | c.Constant | c.Exponential | c.Lognormal | c.TruncatedNormal) -> Sampler:
    """A length's distribution [m] from its config (a number is a constant).

    lognormal: of the length's own mean m and standard deviation s, ln L ~ N(mu, sigma) with
    sigma^2 = ln(1 + s^2/m^2) and mu = ln m - sigma^2 / 2. truncated_normal: N(mean, std) kept in
    [min, max]."""
    if isinstance(spec, float | int):
        return Fixed(float(spec))
    if isinstance(spec, c.Constant):
        return Fixed(spec.value)
    if isinstance(spec, c.Exponential):
        return stats.expon(scale=spec.mean)
    if isinstance(spec, c.Lognormal):
        spread = 1.0 + (spec.std / spec.mean) ** 2
        return stats.lognorm(s=math.sqrt(math.log(spread)), scale=spec.mean / math.sqrt(spread))
    upper = math.inf if spec.max is None else (spec.max - spec.mean) / spec.std
    return stats.truncnorm((spec.min - spec.mean) / spec.std, upper, loc=spec.mean, scale=spec.std)


def dip(spec: float | c.DipScatter) -> Sampler:
    """A dip's distribution [deg]: normal of the given mean and standard deviation, or a constant."""
    if isinstance(spec, c.DipScatter):
        return stats.norm(spec.mean, spec.std) if spec.std > 0 else Fixed(spec.mean)
    return Fixed(float(spec))
