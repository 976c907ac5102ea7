"""The regressions of Table 1 and Fig 2: straight lines and the power law K_si = a sigma_n^b.

Straight lines are ordinary least squares (`scipy.stats.linregress`). The power law is fitted two ways,
both reported, because they weigh the data differently:

* ``log-log``: least squares of ln y on ln x (a = exp(intercept), b = slope); the usual way a power law
  is fitted in a spreadsheet, minimising relative errors.
* ``nonlinear``: least squares of y itself (`scipy.optimize.curve_fit`, started from the log-log fit),
  minimising absolute errors.

R^2 = 1 - SS_res/SS_tot is given both in the space fitted and in linear y, since software reports
either; `r` is Pearson's correlation coefficient of the fitted (transformed) variables.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats


@dataclass(frozen=True)
class Fit:
    """One regression: y = a x + b (line) or y = a x^b (power law)."""

    kind: str
    method: str
    a: float
    b: float
    r2: float
    r2_linear_y: float
    r: float
    n_points: int

    def predict(self, x: np.ndarray) -> np.ndarray:
        """y at x, in the units the fit was made in."""
        x = np.asarray(x, dtype=float)
        return self.a * x + self.b if self.kind == "line" else self.a * x**self.b


def _r2(y: np.ndarray, y_hat: np.ndarray) -> float:
    residual = float(np.sum((y - y_hat) ** 2))
    total = float(np.sum((y - np.mean(y)) ** 2))
    if total == 0.0:
        return 1.0 if residual == 0.0 else 0.0
    return 1.0 - residual / total


def _checked(x: np.ndarray, y: np.ndarray, positive: bool) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.shape != y.shape or x.size < 2:
        raise ValueError(f"need two or more (x, y) pairs of equal length, got {x.size} and {y.size}")
    if np.ptp(x) == 0.0:
        raise ValueError("all x are equal: no line can be fitted")
    if positive and (np.any(x <= 0) or np.any(y <= 0)):
        raise ValueError("a power law needs x > 0 and y > 0")
    return x, y


def linear_fit(x: np.ndarray, y: np.ndarray) -> Fit:
    """Ordinary least squares y = a x + b."""
    x, y = _checked(x, y, positive=False)
    result = stats.linregress(x, y)
    r2 = _r2(y, result.slope * x + result.intercept)
    return Fit(
        "line", "ols", float(result.slope), float(result.intercept), r2, r2, float(result.rvalue), x.size
    )


def power_law_fit(x: np.ndarray, y: np.ndarray, method: str) -> Fit:
    """y = a x^b by ``log-log`` or ``nonlinear`` least squares (see the module docstring)."""
    x, y = _checked(x, y, positive=True)
    loglog = stats.linregress(np.log(x), np.log(y))
    a, b = float(np.exp(loglog.intercept)), float(loglog.slope)
    if method == "nonlinear":
        with warnings.catch_warnings():  # its covariance (not used) cannot be estimated from two points
            warnings.simplefilter("ignore", optimize.OptimizeWarning)
            try:
                (a, b), _ = optimize.curve_fit(lambda s, a_, b_: a_ * s**b_, x, y, p0=(a, b))
            except RuntimeError as error:
                raise ValueError(f"nonlinear least squares found no power law: {error}") from None
    elif method != "log-log":
        raise ValueError(f"unknown power-law method {method!r}: use 'log-log' or 'nonlinear'")
    y_hat = a * x**b
    r2_log = _r2(np.log(y), np.log(y_hat))
    return Fit("power", method, float(a), float(b), r2_log, _r2(y, y_hat), float(loglog.rvalue), x.size)
