"""Fitting a joint set's spacings and trace lengths by maximum likelihood, and choosing the
distribution by Akaike's information criterion, AIC = 2 k - 2 ln L (k parameters).

Candidates: exponential, lognormal and gamma, all with their lower end at 0 (scipy.stats `expon`,
`lognorm`, `gamma` with loc = 0).

Spacings (`fit_spacings`). The spacings between consecutive joints of a set along the scanline are a
sample of the spacing distribution; the stretch from the last joint to the scanline's end is a spacing
known only to be longer (right-censored), and enters the likelihood through the survival function
S = 1 - F; two joints read at the same position are a spacing known only to be shorter than the
reading (left-censored, through F). scipy's `fit` takes these as scipy.stats.CensoredData. The stretch
before the first joint is left out: for any but the exponential distribution it is not a spacing but
the remainder of one.

Trace lengths (`fit_trace_lengths`). A scanline does not sample traces evenly, and their ends may be
hidden. Let f be the density of the set's trace lengths, S its survival function and mu its mean:

* Size bias: a line meets a trace with a chance proportional to its length, at a uniform point along
  it, so the traces it meets have the density l f(l) / mu (Priest & Hudson 1981; Priest 1993). Fitting f
  to their lengths as if they were a plain sample overestimates the mean; for exponential traces by a
  factor of 2.
* Censoring: if the line meets a trace at distances u and v from its ends, the pair (u, v) has the
  density f(u + v) / mu. An end hidden beyond the exposure's edge (at the distance c from the line)
  leaves only v > c known, and integrating over it gives, for the visible length l:

      both ends seen:     f(l) / mu                (times l for the density of l itself)
      one end hidden:     S(l) / mu
      both ends hidden:   I(l) / mu,   I(l) = integral from l to infinity of S(t) dt = E[(L - l)+]

  So a trace with a hidden end is not simply "longer than seen" under f (a right-censored value of f),
  nor under the size-biased density: its weight is S(l) / mu, the density of a semi-trace (Priest &
  Hudson 1981). The log-likelihood of a set is the sum of the logarithms above (with the factor l,
  which no parameter changes), maximised over each candidate's parameters (scipy.optimize, in the
  logarithms of the positive parameters). Its only assumption on the exposure is that the distance to
  its edges does not depend on the trace's length. For the exponential candidate it has the closed
  form mu = sum(l) / (2 n_0 + n_1), with n_0 traces seen whole and n_1 with one end hidden.

  I(l) in closed form: exponential mu exp(-l / mu); lognormal (log-mean m, sigma)
  mu Phi(d1) - l Phi(d2), d1 = (m + sigma^2 - ln l) / sigma, d2 = d1 - sigma (evaluated through the
  scaled complementary error function where the two terms nearly cancel); gamma (shape a, scale theta)
  theta [(a - x) Q(a, x) + x^a e^(-x) / Gamma(a)], x = l / theta, Q the regularized upper incomplete
  gamma function; numerical quadrature of S where a closed form loses its precision.

Goodness of fit: the Kolmogorov-Smirnov p-value (scipy.stats.kstest) of the uncensored values against
the fitted distribution (for trace lengths: the size-biased density, and only for a set with no hidden
end, since the seen lengths of censored traces follow no distribution the survey alone determines).
The parameters are fitted to the same data, so the p-value is too high (Lilliefors); it flags a poor
fit, it does not prove a good one.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize, special, stats

FAMILIES = ("exponential", "lognormal", "gamma")


@dataclass(frozen=True)
class Candidate:
    """One fitted distribution: its scipy form, log-likelihood, AIC and KS p-value (NaN where none)."""

    family: str
    distribution: stats.rv_continuous
    log_likelihood: float
    parameters: int
    ks_p_value: float

    @property
    def aic(self) -> float:
        return 2.0 * self.parameters - 2.0 * self.log_likelihood

    @property
    def mean(self) -> float:
        return float(self.distribution.mean())

    @property
    def std(self) -> float:
        return float(self.distribution.std())

    @property
    def scipy(self) -> str:
        """The distribution as scipy.stats writes it, e.g. lognorm(s=0.5, scale=3.2)."""
        shapes = self.distribution.dist.shapes
        names = shapes.split(", ") if shapes else []
        values = [*self.distribution.args, self.distribution.kwds.get("scale", 1.0)]
        text = ", ".join(f"{n}={v:.6g}" for n, v in zip([*names, "scale"], values, strict=True))
        return f"{self.distribution.dist.name}({text})"


def frozen(family: str, values: np.ndarray) -> stats.rv_continuous:
    """The scipy distribution of `family` from its parameters in log form: exponential (ln mean),
    lognormal (log-mean m, ln sigma), gamma (ln shape, ln scale)."""
    if family == "exponential":
        return stats.expon(scale=np.exp(values[0]))
    if family == "lognormal":
        return stats.lognorm(np.exp(values[1]), scale=np.exp(values[0]))
    return stats.gamma(np.exp(values[0]), scale=np.exp(values[1]))


def _ks(values: np.ndarray, cdf: Callable[[np.ndarray], np.ndarray]) -> float:
    return float(stats.kstest(values, cdf).pvalue) if values.size else np.nan


def _precise(func: Callable, start: np.ndarray, args: tuple = (), disp: int = 0) -> np.ndarray:
    """scipy's default optimizer for `fit` (Nelder-Mead) run to round-off rather than to 1e-4."""
    return optimize.fmin(
        func, start, args=args, disp=disp, xtol=1e-10, ftol=1e-10, maxiter=20_000, maxfun=40_000
    )


def fit_spacings(spacings: np.ndarray, resolution: float, censored_tail: float | None) -> list[Candidate]:
    """Every candidate fitted to the `spacings` [m], by scipy's `fit` on CensoredData: a spacing of 0
    (two joints read at one position) is known only to be below the `resolution` of the readings
    (left-censored), the stretch after the last joint `censored_tail` only to be exceeded
    (right-censored; None if the last joint ends the line)."""
    measured = spacings[spacings > 0]
    left = np.full(spacings.size - measured.size, resolution)
    right = np.array([censored_tail] if censored_tail else [])
    data = stats.CensoredData(uncensored=measured, left=left, right=right)
    scipy_families = {"exponential": stats.expon, "lognormal": stats.lognorm, "gamma": stats.gamma}
    fitted = []
    for family in FAMILIES:
        dist = scipy_families[family]
        *shapes, loc, scale = dist.fit(data, floc=0, optimizer=_precise)
        law = dist(*shapes, loc=loc, scale=scale)
        log_l = np.sum(law.logpdf(measured)) + np.sum(law.logcdf(left)) + np.sum(law.logsf(right))
        fitted.append(Candidate(family, law, float(log_l), len(shapes) + 1, _ks(measured, law.cdf)))
    return fitted


def _log_partial_mean_quadrature(law: stats.rv_continuous, lengths: np.ndarray) -> np.ndarray:
    values = [integrate.quad(law.sf, length, np.inf, limit=200)[0] for length in lengths]
    with np.errstate(divide="ignore"):
        return np.log(np.asarray(values))


def log_partial_mean(family: str, law: stats.rv_continuous, lengths: np.ndarray) -> np.ndarray:
    """ln I(l), I(l) = integral from l to infinity of S(t) dt = E[(L - l)+], for each of `lengths`."""
    lengths = np.asarray(lengths, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        if family == "exponential":
            mean = law.mean()
            return np.log(mean) - lengths / mean
        if family == "lognormal":
            sigma, m = law.args[0], np.log(law.kwds["scale"])
            mean = np.exp(m + sigma**2 / 2.0)
            x1 = (np.log(lengths) - m - sigma**2) / sigma  # -d1
            direct = np.log(mean * special.ndtr(-x1) - lengths * special.ndtr(-x1 - sigma))
            # where -d1 >= 0: mu phi(x1) [R(x1) - R(x1 + sigma)], R(x) = sqrt(pi/2) erfcx(x / sqrt 2)
            mills = np.sqrt(np.pi / 2.0) * (
                special.erfcx(x1 / np.sqrt(2.0)) - special.erfcx((x1 + sigma) / np.sqrt(2.0))
            )
            scaled = np.log(mean) - x1**2 / 2.0 - 0.5 * np.log(2.0 * np.pi) + np.log(mills)
            result = np.where(x1 < 0, direct, scaled)
        else:
            shape, scale = law.args[0], law.kwds["scale"]
            x = lengths / scale
            tail = np.exp(shape * np.log(x) - x - special.gammaln(shape))
            total = (shape - x) * special.gammaincc(shape, x) + tail
            result = np.log(scale * total)
            result = np.where(total > 1e-6 * tail, result, np.nan)
    poor = ~np.isfinite(result)
    if np.any(poor):
        result = result.copy()
        result[poor] = _log_partial_mean_quadrature(law, lengths[poor])
    return result


def trace_log_likelihood(
    family: str, law: stats.rv_continuous, lengths: np.ndarray, ends: np.ndarray
) -> float:
    """The scanline log-likelihood of a set's visible trace `lengths` [m] with `ends` hidden (0, 1, 2):
    sum of ln(l f(l)), ln S(l), ln I(l) by the number of hidden ends, minus N ln mu."""
    whole, one, both = lengths[ends == 0], lengths[ends == 1], lengths[ends == 2]
    total = (
        np.sum(np.log(whole) + law.logpdf(whole))
        + np.sum(law.logsf(one))
        + (np.sum(log_partial_mean(family, law, both)) if both.size else 0.0)
        - lengths.size * np.log(law.mean())
    )
    return float(total) if np.isfinite(total) else -np.inf


def _start(family: str, lengths: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Starting parameters: the exponential's closed-form mean; for the others the size-biased sample's
    log-moments shifted back (a lognormal's size bias raises its log-mean by sigma^2)."""
    mean = lengths.sum() / (2 * np.sum(ends == 0) + np.sum(ends == 1))
    if family == "exponential":
        return np.array([np.log(mean)])
    spread = max(float(np.std(np.log(lengths))), 0.1)
    if family == "lognormal":
        return np.array([np.log(mean) - spread**2 / 2.0, np.log(spread)])
    shape = 1.0 / spread**2
    return np.array([np.log(shape), np.log(mean / shape)])


def size_biased_cdf(law: stats.rv_continuous) -> Callable[[np.ndarray], np.ndarray]:
    """CDF of l f(l) / mu: (integral from 0 to l of t f(t) dt) / mu = 1 - (l S(l) + I(l)) / mu."""
    family = {"expon": "exponential", "lognorm": "lognormal", "gamma": "gamma"}[law.dist.name]

    def cdf(lengths: np.ndarray) -> np.ndarray:
        lengths = np.asarray(lengths, dtype=float)
        partial = np.exp(log_partial_mean(family, law, lengths))
        return 1.0 - (lengths * law.sf(lengths) + partial) / law.mean()

    return cdf


def fit_trace_lengths(lengths: np.ndarray, ends: np.ndarray) -> list[Candidate]:
    """Every candidate fitted to a set's visible trace `lengths` [m] with `ends` hidden (0, 1 or 2),
    by maximising `trace_log_likelihood` (Nelder-Mead in the log-parameters)."""
    lengths, ends = np.asarray(lengths, dtype=float), np.asarray(ends)
    fitted = []
    for family in FAMILIES:

        def cost(values: np.ndarray, family: str = family) -> float:
            return -trace_log_likelihood(family, frozen(family, values), lengths, ends)

        start = _start(family, lengths, ends)
        best = optimize.minimize(
            cost, start, method="Nelder-Mead", options={"xatol": 1e-8, "fatol": 1e-10, "maxiter": 4000}
        )
        law = frozen(family, best.x)
        ks = _ks(lengths, size_biased_cdf(law)) if np.all(ends == 0) else np.nan
        fitted.append(Candidate(family, law, -float(best.fun), start.size, ks))
    return fitted


def best(candidates: list[Candidate], families: tuple[str, ...] = FAMILIES) -> Candidate:
    """The candidate of least AIC among `families`."""
    return min((c for c in candidates if c.family in families), key=lambda c: c.aic)
