"""A mixture of antipodally symmetric Fisher distributions and a uniform background on the sphere,
fitted to poles (axes) by EM with case weights.

Model. A pole x (a unit vector whose sense carries no information) is drawn from one of k sets or from
the background. Set j has the density (Fisher 1953, made antipodally symmetric; Fisher, Lewis &
Embleton 1987)

    g_j(x) = 1/2 [f(x; mu_j, kappa_j) + f(-x; mu_j, kappa_j)] = kappa_j cosh(kappa_j mu_j . x)
             / (4 pi sinh kappa_j)                                                    [1/sr]

with f Fisher's density kappa exp(kappa mu . x) / (4 pi sinh kappa); g_j(x) = g_j(-x), so the
upward pole and its antipode are the same reading and a set whose poles straddle the horizontal (a
subvertical set) is one component. The background, random readings, has the density 1 / (4 pi). The
mixture is

    p(x) = sum_j pi_j g_j(x) + pi_0 / (4 pi),    pi_0 + sum_j pi_j = 1,

with 3 k + k free parameters (a mean axis, a concentration and a share per set). Peel, Whiten &
McLachlan (2001) fit mixtures of Kent distributions to joint orientations the same way; the Fisher
component is its rotationally symmetric case, the one whose concentration is the K that bbmc reports
and samples (`bbmc.geometry.orientation`).

EM (Dempster, Laird & Rubin 1977). With case weights w_i (Terzaghi's, scaled to sum to the count n)
the weighted log-likelihood sum_i w_i ln p(x_i) is raised at every iteration:

* E-step: the responsibilities r_ij = pi_j g_j(x_i) / p(x_i), and within set j the chance that x_i is
  the sense drawn (the latent sign of the antipodal pair), whose expected signed vector is
  tanh(kappa_j mu_j . x_i) x_i;
* M-step: S_j = sum_i w_i r_ij tanh(kappa_j mu_j . x_i) x_i, mu_j = S_j / |S_j|, the mean resultant
  length Rbar_j = |S_j| / sum_i w_i r_ij, kappa_j = A^-1(Rbar_j) with A(kappa) = coth kappa - 1/kappa
  (Banerjee et al. 2005's start kappa = Rbar (3 - Rbar^2) / (1 - Rbar^2), then two Newton steps), and
  pi_j = sum_i w_i r_ij / n.

kappa is kept within [KAPPA_MIN, KAPPA_MAX]: below it a set is indistinguishable from the background,
and above it a component could collapse onto repeated readings (field readings are often rounded to
whole degrees) and its likelihood grow without bound.

Starts. Several starts from axial k-means++ (Arthur & Vassilvitskii 2007, with the distance
1 - (x . c)^2 = sin^2 of the angle between axes, and the chance of a reading weighted by a kernel
estimate of the density there, so starts fall in clusters rather than on random readings); and from
the fit with one set fewer, grown by a set where the readings are densest against that fit, or with
each of its sets split in two along its largest spread. Each start runs a few iterations ("short EM",
Biernacki, Celeux & Govaert 2003); the best is run to convergence. The random generator is the
caller's, so a seed fixes the result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

KAPPA_MIN = 1e-3
KAPPA_MAX = 5e3
LOG_UNIFORM = -np.log(4.0 * np.pi)  # the background's density, ln(1 / (4 pi)) [1/sr]
STARTS = 4  # k-means++ starts per number of sets, beside the one grown from the previous fit
SHORT_ITERATIONS = 20
MAX_ITERATIONS = 500
TOLERANCE = 1e-6  # convergence: gain in the log-likelihood per unit weight
KERNEL_KAPPA = 20.0  # the kernel density's concentration (81 deg / sqrt(20) = 18 deg)
KERNEL_READINGS = 1500


@dataclass(frozen=True)
class AxialMixture:
    """A fitted mixture: `axes` (k, 3) the sets' mean axes, `kappa` (k,) their concentrations,
    `shares` (k + 1,) the sets' shares and, last, the background's, and the weighted log-likelihood."""

    axes: np.ndarray
    kappa: np.ndarray
    shares: np.ndarray
    log_likelihood: float

    @property
    def parameters(self) -> int:
        """Free parameters: an axis (2), a concentration and a share per set."""
        return 4 * self.kappa.size


def log_axial_fisher(cosines: np.ndarray, kappa: np.ndarray) -> np.ndarray:
    """ln g = ln kappa - ln 4 pi - ln sinh kappa + ln cosh(kappa c) [ln(1/sr)] at the cosines c between
    the poles and the mean axis, written to stay finite from kappa -> 0 (ln 1/(4 pi)) to large kappa."""
    c = np.abs(cosines)
    return (np.log(kappa) + LOG_UNIFORM - kappa - np.log(-np.expm1(-2.0 * kappa))
            + kappa * c + np.log1p(np.exp(-2.0 * kappa * c)))  # fmt: skip


def inverse_mean_length(mean_length: np.ndarray) -> np.ndarray:
    """kappa with A(kappa) = coth kappa - 1/kappa = Rbar, clipped to [KAPPA_MIN, KAPPA_MAX]."""
    r = np.clip(mean_length, 1e-9, 1.0 - 1e-12)
    kappa = r * (3.0 - r**2) / (1.0 - r**2)
    for _ in range(2):
        e = np.exp(-2.0 * kappa)
        value = (1.0 + e) / (1.0 - e) - 1.0 / kappa
        slope = 1.0 / kappa**2 - 4.0 * e / (1.0 - e) ** 2
        kappa = np.where(slope > 0, kappa - (value - r) / np.maximum(slope, 1e-300), kappa)
    return np.clip(kappa, KAPPA_MIN, KAPPA_MAX)


def log_densities(poles: np.ndarray, mixture: AxialMixture) -> np.ndarray:
    """ln(pi_j g_j(x_i)) (n, k + 1), the background last."""
    with np.errstate(divide="ignore"):
        log_shares = np.log(mixture.shares)
    sets = log_axial_fisher(poles @ mixture.axes.T, mixture.kappa) + log_shares[:-1]
    return np.column_stack([sets, np.full(poles.shape[0], LOG_UNIFORM + log_shares[-1])])


def responsibilities(poles: np.ndarray, mixture: AxialMixture) -> tuple[np.ndarray, np.ndarray]:
    """Each pole's log-density ln p(x_i) (n,) and responsibilities r_ij (n, k + 1)."""
    log_p = log_densities(poles, mixture)
    top = log_p.max(axis=1, keepdims=True)
    density = np.exp(log_p - top)
    total = density.sum(axis=1, keepdims=True)
    return (top + np.log(total)).ravel(), density / total


def _m_step(poles: np.ndarray, weights: np.ndarray, mixture: AxialMixture, resp: np.ndarray) -> tuple:
    set_weight = weights[:, None] * resp[:, :-1]
    signs = np.tanh(mixture.kappa * (poles @ mixture.axes.T))
    resultant = (set_weight * signs).T @ poles
    length = np.linalg.norm(resultant, axis=1)
    alive = length > 1e-12
    axes = np.where(alive[:, None], resultant / np.where(alive, length, 1.0)[:, None], mixture.axes)
    total = set_weight.sum(axis=0)
    kappa = inverse_mean_length(np.where(alive, length / np.maximum(total, 1e-300), 0.0))
    shares = (weights[:, None] * resp).sum(axis=0) / weights.sum()
    return axes, kappa, shares


def run_em(poles: np.ndarray, weights: np.ndarray, start: AxialMixture, iterations: int) -> AxialMixture:
    """EM from `start` for at most `iterations` steps, or until the log-likelihood gains less than
    TOLERANCE per unit weight."""
    mixture = start
    log_p, resp = responsibilities(poles, mixture)
    mixture = AxialMixture(mixture.axes, mixture.kappa, mixture.shares, float(weights @ log_p))
    for _ in range(iterations):
        axes, kappa, shares = _m_step(poles, weights, mixture, resp)
        trial = AxialMixture(axes, kappa, shares, 0.0)
        log_p, resp = responsibilities(poles, trial)
        gain = float(weights @ log_p) - mixture.log_likelihood
        mixture = AxialMixture(axes, kappa, shares, float(weights @ log_p))
        if gain < TOLERANCE * weights.sum():
            break
    return mixture


def _from_centres(poles: np.ndarray, weights: np.ndarray, centres: np.ndarray) -> AxialMixture:
    """A start from centre axes: readings to their nearest centre, a few rounds of axial k-means, each
    set's kappa from its readings' mean resultant length, 10 % of the weight to the background."""
    for _ in range(5):
        cosines = poles @ centres.T
        nearest = np.argmax(np.abs(cosines), axis=1)
        member = weights[:, None] * (nearest[:, None] == np.arange(centres.shape[0]))
        resultant = (member * np.sign(cosines)).T @ poles
        length = np.linalg.norm(resultant, axis=1)
        centres = np.where(length[:, None] > 0, resultant / np.maximum(length, 1e-300)[:, None], centres)
    total = member.sum(axis=0)
    kappa = inverse_mean_length(length / np.maximum(total, 1e-300))
    shares = np.append(0.9 * np.maximum(total, 1e-3) / total.sum(), 0.1)
    return AxialMixture(centres, kappa, shares / shares.sum(), -np.inf)


def kernel_log_density(poles: np.ndarray, weights: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """ln of a kernel estimate of the poles' density at each pole [ln(1/sr)]: the mean of axial Fisher
    kernels of concentration KERNEL_KAPPA about (at most KERNEL_READINGS of) the readings."""
    n = poles.shape[0]
    chosen = rng.choice(n, KERNEL_READINGS, replace=False) if n > KERNEL_READINGS else np.arange(n)
    kernels = log_axial_fisher(poles @ poles[chosen].T, np.array(KERNEL_KAPPA)) + np.log(weights[chosen])
    return logsumexp(kernels, axis=1) - np.log(weights[chosen].sum())


def _seed(poles: np.ndarray, chance: np.ndarray, centres: list, count: int, rng) -> np.ndarray:
    """Axial k-means++ (each new centre drawn with the chance `chance` sin^2(angle to the nearest
    centre)), `centres` kept."""
    distance = np.ones(poles.shape[0])
    for centre in centres:
        distance = np.minimum(distance, 1.0 - (poles @ centre) ** 2)
    while len(centres) < count:
        odds = chance * np.maximum(distance, 0.0)
        pick = rng.choice(poles.shape[0], p=odds / odds.sum()) if odds.sum() > 0 else 0
        centres.append(poles[pick])
        distance = np.minimum(distance, 1.0 - (poles @ poles[pick]) ** 2)
    return np.array(centres)


def _grown(poles: np.ndarray, log_kernel: np.ndarray, previous: AxialMixture) -> np.ndarray:
    """The previous fit's axes and a new one where the readings are densest against what the previous
    fit predicts: at the largest ln(kernel density) - ln p(x)."""
    log_p, _ = responsibilities(poles, previous)
    return np.vstack([previous.axes, poles[np.argmax(log_kernel - log_p)]])


def _splits(poles: np.ndarray, weights: np.ndarray, previous: AxialMixture) -> list[np.ndarray]:
    """The previous fit with one of its sets split in two, for each set: its axis mu replaced by
    mu cos d +/- e sin d, e the direction of the set's largest spread about mu (the second eigenvector
    of sum r w x x^T over its readings) and d the angular spread along it (two sets merged into one
    are found again this way)."""
    _, resp = responsibilities(poles, previous)
    starts = []
    for j, axis in enumerate(previous.axes):
        scatter = (poles * (weights * resp[:, j])[:, None]).T @ poles
        values, vectors = np.linalg.eigh(scatter / max(scatter.trace(), 1e-300))
        spread = np.arcsin(np.sqrt(np.clip(values[1], 0.0, 1.0)))
        pair = [axis * np.cos(spread) + sign * vectors[:, 1] * np.sin(spread) for sign in (1.0, -1.0)]
        starts.append(np.vstack([np.delete(previous.axes, j, axis=0), *pair]))
    return starts


def fit_axial_mixture(
    poles: np.ndarray,
    weights: np.ndarray,
    count: int,
    rng: np.random.Generator,
    log_kernel: np.ndarray,
    previous: AxialMixture | None = None,
) -> AxialMixture:
    """The best of several EM starts of a mixture of `count` sets and the background fitted to unit
    `poles` (n, 3) with case `weights` (n,) scaled to sum to n. `log_kernel` is `kernel_log_density`
    at the poles: the k-means++ chances are w times the kernel density, so starts fall where the
    readings gather rather than on scattered random ones; `previous`, a fit with one set fewer, gives
    more starts (`_grown`, `_splits`)."""
    chance = weights * np.exp(log_kernel - log_kernel.max())
    seeds = [_seed(poles, chance, [], count, rng) for _ in range(STARTS)]
    if previous is not None and previous.kappa.size:
        seeds += [_grown(poles, log_kernel, previous), *_splits(poles, weights, previous)]
    shorts = [run_em(poles, weights, _from_centres(poles, weights, s), SHORT_ITERATIONS) for s in seeds]
    best = max(shorts, key=lambda m: m.log_likelihood)
    return run_em(poles, weights, best, MAX_ITERATIONS)


def background_only(weights: np.ndarray) -> AxialMixture:
    """No set: every reading random, ln L = sum w ln(1 / (4 pi))."""
    return AxialMixture(np.zeros((0, 3)), np.zeros(0), np.ones(1), float(weights.sum() * LOG_UNIFORM))
