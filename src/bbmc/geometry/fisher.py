"""A joint set's Fisher statistics: its mean pole and K (`fisher_orientation`, the codebase's one K
estimator), the 95 % confidence cone about the mean and the spherical variance, for poles taken as
axes and weighted (Terzaghi's weights, or any case weights).

Counts. Let the N readings carry the weights w_i (all 1 when unweighted). Three counts describe them:

* N, the raw count of readings;
* sum w_i, the weighted count (for Terzaghi's weights: the number of joints the readings stand for);
* N_e = (sum w_i)^2 / sum w_i^2, the effective count (Kish 1965): the number of equally weighted
  readings whose mean would be as precise as the weighted mean. N_e = N for equal weights and
  N_e < N otherwise.

The weights are scaled to sum to N (w'_i = N w_i / sum w); the resultant of the axially aligned poles,
R = |sum w'_i n_i|, and the mean resultant length R/N are then free of the weights' scale.

* K = (N - 1) / (N - R) (Fisher 1953; Fisher, Lewis & Embleton 1987), with the raw N, as Dips uses:
  `bbmc.geometry.orientation.fisher_orientation`. R is read back from it, R = N - (N - 1) / K, so
  every statistic here comes from the one resultant.
* Spherical variance 1 - R/N (Fisher, Lewis & Embleton 1987): 0 for identical poles, 1 for a
  resultant of zero.
* The cone of confidence about the mean (Fisher 1953): the true mean lies within the angle a of the
  sample mean with the probability 1 - p, where

      cos a = 1 - (N - R) / R ((1 / p)^(1 / (N - 1)) - 1),    p = 0.05 for alpha95.

  Fisher derived it for N equally weighted readings. With unequal weights the weighted mean is less
  precise than the mean of N readings: for a concentrated set its angular variance is
  sum w_i^2 / (sum w_i)^2 / K = 1 / (N_e K) rather than 1 / (N K). So the cone is computed with the
  effective count, N_e in place of N and R_e = N_e R / N in place of R (the same mean resultant
  length); with equal weights this is Fisher's cone exactly. tests/test_fisher_statistics.py measures
  the coverage both ways on weighted samples: with N it falls short of 95 %, with N_e it holds.
  The cone of axes is meaningful below 90 deg; a value at or above it says the mean is not located.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import SetOrientation, fisher_orientation


def effective_count(weights: np.ndarray) -> float:
    """Kish's effective count (sum w)^2 / sum w^2 of readings with case weights `weights`."""
    weights = np.asarray(weights, dtype=float)
    return float(weights.sum() ** 2 / np.sum(weights**2))


def confidence_cone(count: np.ndarray, resultant: np.ndarray, probability: float = 0.95) -> np.ndarray:
    """The half-angle a [rad] of Fisher's (1953) cone of confidence `probability` about the mean of
    `count` unit vectors whose resultant has the length `resultant`:
    cos a = 1 - (N - R) / R ((1 / p)^(1 / (N - 1)) - 1), p = 1 - probability. pi where the formula
    leaves no cone (cos a < -1) and NaN for N <= 1. Vectorised over `count` and `resultant`."""
    count, resultant = np.asarray(count, dtype=float), np.asarray(resultant, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.expm1(-np.log1p(-probability) / (count - 1.0))
        cosine = 1.0 - (count - resultant) / resultant * factor
    return np.where(count > 1.0, np.arccos(np.clip(cosine, -1.0, 1.0)), np.nan)


@dataclass(frozen=True)
class FisherStatistics:
    """A set's Fisher statistics (see the module's docstring for the counts and formulas).

    `orientation` holds the mean pole (upward unit normal), the mean plane's dip and dip direction
    [rad] and K; `alpha95` is the 95 % cone about the mean pole [rad], from the effective count."""

    orientation: SetOrientation
    count: int
    weighted_count: float
    effective_count: float
    mean_resultant_length: float
    alpha95: float
    spherical_variance: float

    @property
    def fisher_k(self) -> float:
        """K = (N - 1) / (N - R), N the raw count."""
        return self.orientation.fisher_k

    @property
    def mean_pole(self) -> np.ndarray:
        """The mean pole, an upward unit normal (east, north, up)."""
        return self.orientation.normal


def fisher_statistics(normals: np.ndarray, weights: np.ndarray | None = None) -> FisherStatistics:
    """The Fisher statistics of the poles `normals` (N x 3 unit vectors, either sense: axes), weighted
    by `weights` (N,) (all 1 when None)."""
    normals = np.asarray(normals, dtype=float)
    weights = np.ones(normals.shape[0]) if weights is None else np.asarray(weights, dtype=float)
    orientation = fisher_orientation(normals, weights)
    count = normals.shape[0]
    mean_length = 1.0 - (count - 1) / (count * orientation.fisher_k)
    n_e = effective_count(weights)
    return FisherStatistics(
        orientation=orientation,
        count=count,
        weighted_count=float(weights.sum()),
        effective_count=n_e,
        mean_resultant_length=mean_length,
        alpha95=float(confidence_cone(n_e, n_e * mean_length)),
        spherical_variance=1.0 - mean_length,
    )
