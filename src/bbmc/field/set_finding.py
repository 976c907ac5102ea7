"""Joint sets found in unlabelled orientation readings: the poles clustered as axes by a mixture of
antipodally symmetric Fisher sets and a uniform background (`bbmc.field.axial_mixture`), the number of
sets chosen by BIC, or fixed by the user, or the sets given as windows; each set's Fisher statistics
from its readings (`bbmc.geometry.fisher`). docs/reference/set-finding.md has the method and sources.

Number of sets. For k = 0 (every reading random) to `max_sets`, the mixture is fitted and scored by
Schwarz's (1978) criterion BIC = -2 ln L + 4 k ln n (n readings, weights scaled to sum to n). A k is
eligible only if each of its sets holds at least `min_set_size` readings when every reading goes to
its most probable component; the eligible k of least BIC is chosen. So a survey that is one set is
not split (two halves of one Fisher set gain too little likelihood to pay for 4 parameters), and a
clump of a few random readings does not become a set.

Large surveys. Above MODEL_SAMPLE readings, the count is chosen on a random subsample of MODEL_SAMPLE
readings (drawn with the seed; the minimum set size scaled by the subsample's share), and the chosen
mixture is then refined by EM on all readings and every reading assigned in one vectorised E-step.
The BIC table is the subsample's. A set holding fewer than about 10 readings of the subsample (0.2 %
of the survey at 5,000 of them) cannot be told from noise there.

After the fit on all readings, a set that holds fewer than `min_set_size` readings is dropped (its
readings reassigned to the remaining sets or the background), repeatedly, unless the count was fixed.

Windows (as Dips' set windows): a window is a cone of half-angle `half_angle` about a mean pole;
readings inside it (angle between axes at most the half-angle) belong to its set, readings in no
window are random. A reading inside several windows goes to the window whose centre is nearest (the
smallest angle), first given on a tie. A window that catches no reading is refused by name.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc.field import axial_mixture as mix
from bbmc.geometry.fisher import FisherStatistics, fisher_statistics
from bbmc.geometry.orientation import angle_between_axes, line_vectors, poles, trend_and_plunge

MODEL_SAMPLE = 5000
REFINE_ITERATIONS = 100


@dataclass(frozen=True)
class Window:
    """A set window: readings whose poles lie within `half_angle` [rad] of the axis `pole` (a unit
    vector, either sense) belong to the set `name`."""

    name: str
    pole: np.ndarray
    half_angle: float

    @classmethod
    def about_pole(cls, name: str, trend: float, plunge: float, half_angle: float) -> Window:
        """A window about the pole of `trend` and `plunge` [rad]."""
        return cls(name, line_vectors(trend, plunge), half_angle)

    @classmethod
    def about_plane(cls, name: str, dip: float, dip_direction: float, half_angle: float) -> Window:
        """A window about the pole of the plane of `dip` and `dip_direction` [rad]."""
        return cls(name, poles(dip, dip_direction), half_angle)


@dataclass(frozen=True)
class FoundSet:
    """One set: its `label` in `FoundSets.labels`, its Fisher statistics, its share of the readings
    (the mixture's pi_j, or the weighted share of the window's readings) and its window's name."""

    label: int
    statistics: FisherStatistics
    share: float
    window: str | None = None

    @property
    def mean_pole(self) -> np.ndarray:
        """The mean pole, an upward unit normal (east, north, up)."""
        return self.statistics.mean_pole

    @property
    def pole_trend_and_plunge(self) -> tuple[float, float]:
        """The mean pole's trend and plunge [rad] (lower hemisphere)."""
        trend, plunge = trend_and_plunge(self.mean_pole)
        return float(trend), float(plunge)


@dataclass(frozen=True)
class BicRow:
    """One number of sets tried: its weighted log-likelihood, parameter count, BIC, the raw count of
    readings in its smallest set, and whether that meets the minimum set size."""

    sets: int
    log_likelihood: float
    parameters: int
    bic: float
    smallest_set: int
    eligible: bool


@dataclass(frozen=True)
class FoundSets:
    """The sets found: `labels` (n,) each reading's set (0, 1, ...; -1 random), `sets` ordered by
    label, `method` ("bic", "count" or "windows"), the BIC table (empty for windows), the background's
    share (the mixture's pi_0, or the weighted share of readings in no window) and the number of
    readings the model was chosen on (n, or MODEL_SAMPLE for large surveys)."""

    labels: np.ndarray
    sets: list[FoundSet]
    method: str
    bic: tuple[BicRow, ...]
    background_fraction: float
    sample_size: int

    @property
    def random_readings(self) -> np.ndarray:
        """Indices of the readings assigned to no set."""
        return np.flatnonzero(self.labels < 0)


def _hard_labels(poles_: np.ndarray, mixture: mix.AxialMixture) -> np.ndarray:
    """Each reading's most probable component; the background (last) as -1."""
    best = np.argmax(mix.log_densities(poles_, mixture), axis=1)
    return np.where(best == mixture.kappa.size, -1, best)


def _row(poles_: np.ndarray, mixture: mix.AxialMixture, min_size: float) -> BicRow:
    k = mixture.kappa.size
    counts = np.bincount(_hard_labels(poles_, mixture) + 1, minlength=k + 1)[1:]
    smallest = int(counts.min()) if k else 0
    bic = -2.0 * mixture.log_likelihood + mixture.parameters * np.log(poles_.shape[0])
    eligible = k == 0 or smallest >= min_size
    return BicRow(k, mixture.log_likelihood, mixture.parameters, float(bic), smallest, eligible)


def _choose(poles_, weights, max_sets, min_size, rng) -> tuple[mix.AxialMixture, tuple[BicRow, ...]]:
    """The eligible mixture of least BIC among 0 to `max_sets` sets."""
    log_kernel = mix.kernel_log_density(poles_, weights, rng)
    fits = [mix.background_only(weights)]
    for k in range(1, min(max_sets, int(poles_.shape[0] / min_size)) + 1):
        fits.append(mix.fit_axial_mixture(poles_, weights, k, rng, log_kernel, fits[-1]))
    rows = tuple(_row(poles_, fit, min_size) for fit in fits)
    best = min((r for r in rows if r.eligible), key=lambda r: r.bic)
    return fits[best.sets], rows


def _drop_small(poles_: np.ndarray, mixture: mix.AxialMixture, min_size: int) -> mix.AxialMixture:
    """Drop the smallest set while any holds fewer than `min_size` readings; its share to the
    background."""
    while mixture.kappa.size:
        counts = np.bincount(_hard_labels(poles_, mixture) + 1, minlength=mixture.kappa.size + 1)[1:]
        if counts.min() >= min_size:
            break
        keep = np.arange(mixture.kappa.size) != np.argmin(counts)
        shares = np.append(mixture.shares[:-1][keep], mixture.shares[-1] + mixture.shares[:-1][~keep])
        mixture = mix.AxialMixture(mixture.axes[keep], mixture.kappa[keep], shares, np.nan)
    return mixture


def _checked(poles_: np.ndarray, weights: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(poles_, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3 or x.shape[0] == 0:
        raise ValueError(f"poles must be an (n, 3) array of n >= 1 readings, not of shape {x.shape}")
    x = x / np.linalg.norm(x, axis=1, keepdims=True)
    w = np.ones(x.shape[0]) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (x.shape[0],) or not np.all(np.isfinite(w) & (w > 0)):
        raise ValueError("weights must be one positive finite number per reading")
    return x, w


def _sets_of(poles_, weights, labels, shares, names=None) -> list[FoundSet]:
    names = [None] * len(shares) if names is None else names
    statistics = [fisher_statistics(poles_[labels == j], weights[labels == j]) for j in range(len(shares))]
    return [
        FoundSet(j, s, float(share), name)
        for j, (s, share, name) in enumerate(zip(statistics, shares, names, strict=True))
    ]


def _by_windows(x: np.ndarray, w: np.ndarray, windows: Sequence[Window]) -> FoundSets:
    centres = np.array([win.pole / np.linalg.norm(win.pole) for win in windows])
    angles = angle_between_axes(x[:, None, :], centres[None, :, :])
    inside = angles <= np.array([win.half_angle for win in windows])
    nearest = np.argmin(np.where(inside, angles, np.inf), axis=1)
    labels = np.where(inside.any(axis=1), nearest, -1)
    for j, win in enumerate(windows):
        if not np.any(labels == j):
            trend, plunge = np.degrees(trend_and_plunge(centres[j]))
            where = "its readings all fall in nearer windows" if inside[:, j].any() else "no reading"
            raise ValueError(
                f"set window {win.name!r} (pole {float(trend):.1f}/{float(plunge):.1f} deg trend/plunge, "
                f"half-angle {np.degrees(win.half_angle):.1f} deg) catches no reading: {where}"
            )
    shares = np.array([w[labels == j].sum() for j in range(len(windows))]) / w.sum()
    sets = _sets_of(x, w, labels, shares, [win.name for win in windows])
    return FoundSets(labels, sets, "windows", (), float(1.0 - shares.sum()), x.shape[0])


def _ordered(x: np.ndarray, mixture: mix.AxialMixture) -> tuple[mix.AxialMixture, np.ndarray]:
    """The sets renumbered by their raw count of readings, largest first, and the readings' labels."""
    labels = _hard_labels(x, mixture)
    order = np.argsort(-np.bincount(labels + 1, minlength=mixture.kappa.size + 1)[1:], kind="stable")
    shares = np.append(mixture.shares[:-1][order], mixture.shares[-1])
    mixture = mix.AxialMixture(mixture.axes[order], mixture.kappa[order], shares, mixture.log_likelihood)
    return mixture, _hard_labels(x, mixture)


def find_sets(
    poles: np.ndarray,
    weights: np.ndarray | None = None,
    *,
    count: int | None = None,
    windows: Sequence[Window] | None = None,
    max_sets: int = 6,
    min_set_size: int = 10,
    seed: int = 0,
) -> FoundSets:
    """The joint sets in the readings `poles` (n, 3) (unit normals, either sense) with case `weights`
    (n,) (Terzaghi's; all 1 when None): chosen by BIC among 0 to `max_sets` sets of at least
    `min_set_size` readings each, or `count` sets exactly, or the given `windows` (one override at a
    time). Deterministic for a given `seed`."""
    x, w = _checked(poles, weights)
    if windows is not None:
        if count is not None:
            raise ValueError("give set windows or a count of sets, not both")
        if not windows:
            raise ValueError("no set window given")
        return _by_windows(x, w, windows)
    if count is not None and count < 1:
        raise ValueError(f"the count of sets must be at least 1, not {count}")
    if min_set_size < 2:
        raise ValueError(f"the minimum set size must be at least 2 readings, not {min_set_size}")
    rng = np.random.default_rng(seed)
    n = x.shape[0]
    sample = np.sort(rng.choice(n, MODEL_SAMPLE, replace=False)) if n > MODEL_SAMPLE else np.arange(n)
    xs, ws = x[sample], w[sample] * sample.size / w[sample].sum()
    if count is None:
        mixture, rows = _choose(xs, ws, max_sets, min_set_size * sample.size / n, rng)
    else:
        mixture = mix.fit_axial_mixture(xs, ws, count, rng, mix.kernel_log_density(xs, ws, rng))
        rows = (_row(xs, mixture, 0),)
    scaled = w * n / w.sum()
    if sample.size < n and mixture.kappa.size:
        mixture = mix.run_em(x, scaled, mixture, REFINE_ITERATIONS)
    if count is None:
        mixture = _drop_small(x, mixture, min_set_size)
    mixture, labels = _ordered(x, mixture)
    if count is not None and np.any(np.bincount(labels + 1, minlength=count + 1)[1:] < 2):
        raise ValueError(f"{count} sets leave a set with fewer than 2 readings: ask for fewer sets")
    sets = _sets_of(x, w, labels, mixture.shares[:-1])
    method = "bic" if count is None else "count"
    return FoundSets(labels, sets, method, rows, float(mixture.shares[-1]), sample.size)
