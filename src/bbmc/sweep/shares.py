"""The geometry's share of the variance of FS, from a crossed design (`design.crossed_table`).

A realization's seed has no order: its rank correlation with FS is noise, and it is left out of the
tornado and of the Sobol' indices (`sensitivity_inputs`). What the geometry does is measured instead
by the law of total variance on a crossed design: n realizations r of the geometry variables, each
run with the same m draws s of the others (the strength), FS[r, s]. Over the two independent groups
FS decomposes (functional ANOVA, Hoeffding 1948; Sobol' 1993) into uncorrelated terms

    FS[r, s] = mu + a_r + b_s + e_rs,    a_r = E[FS | r] - mu,   b_s = E[FS | s] - mu,

e_rs the interaction, of variances s_a^2, s_b^2, s_e^2 (FS^2, dimensionless). The geometry's share is

    S_geo = Var(E[FS | r]) / Var(FS) = s_a^2 / (s_a^2 + s_b^2 + s_e^2)

(its first-order Sobol' index), the others' s_b^2 / Var(FS), their interaction s_e^2 / Var(FS).

Estimator: the ANOVA (method of moments) estimators of the two-way crossed random-effects model with
one run per cell (Searle, Casella & McCulloch 1992, Variance Components, ch. 4, balanced data),
unbiased for each variance:

    MS_r = m sum_r (ybar_r. - ybar..)^2 / (n - 1),                  E[MS_r] = s_e^2 + m s_a^2
    MS_s = n sum_s (ybar_.s - ybar..)^2 / (m - 1),                  E[MS_s] = s_e^2 + n s_b^2
    MS_e = sum (y_rs - ybar_r. - ybar_.s + ybar..)^2 / ((n-1)(m-1)),  E[MS_e] = s_e^2
    s_a^2 = (MS_r - MS_e) / m,   s_b^2 = (MS_s - MS_e) / n,   s_e^2 = MS_e

A negative estimate (a mean square below MS_e: no detectable effect) is set to 0, so each share lies in
[0, 1] and the three add up to 1. Not the plain Var_r(ybar_r.) / Var(FS): a realization's mean over m
draws keeps e's mean, s_e^2 / m too much; b's mean is the same in every row (the same m draws) and
cancels, so the nested design's correction Var_within / m would take s_b^2 / m too much; and the
pooled variance of the n m runs holds only m (n - 1) / (nm - 1) of s_a^2 (a row shares its a_r).

Interval: the pigeonhole bootstrap (McCullagh 2000, Bernoulli 6, 285; Owen 2007, Ann. Appl. Stat. 1,
386): realizations and draws resampled with replacement, independently, `REPLICATES` times from
numpy's default_rng(seed); the 2.5 % and 97.5 % percentiles of the replicates' estimates. It is known
to overstate the spread of a crossed array's mean somewhat (conservative).

A realization any of whose runs has no FS (invalid, a failed run, impossible inputs) is left out
whole: the share is over the complete realizations, and their count is reported.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from bbmc.sweep.config import Sampling

REPLICATES = 2000
CONFIDENCE = 0.95
CHUNK = 4_000_000  # bootstrap cells evaluated at once (32 MB of float64)
COMPONENTS = ("geometry", "other_inputs", "interaction")


def components(fs: NDArray) -> NDArray[np.float64]:
    """The ANOVA estimates (s_a^2, s_b^2, s_e^2), each >= 0, of arrays FS[..., r, s] (n, m >= 2): the
    module docstring's formulas over the last two axes; shape (..., 3)."""
    n, m = fs.shape[-2:]
    rows, cols = fs.mean(axis=-1), fs.mean(axis=-2)
    grand = rows.mean(axis=-1)
    ms_r = m * ((rows - grand[..., None]) ** 2).sum(axis=-1) / (n - 1)
    ms_s = n * ((cols - grand[..., None]) ** 2).sum(axis=-1) / (m - 1)
    residual = fs - rows[..., :, None] - cols[..., None, :] + grand[..., None, None]
    ms_e = (residual**2).sum(axis=(-2, -1)) / ((n - 1) * (m - 1))
    return np.stack([np.maximum((ms_r - ms_e) / m, 0.0), np.maximum((ms_s - ms_e) / n, 0.0), ms_e], axis=-1)


def _shares(variances: NDArray) -> NDArray[np.float64]:
    total = variances.sum(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return variances / total


@dataclass(frozen=True)
class Share:
    """Variances (FS^2) and shares of the geometry, the other inputs and their interaction, each with
    its bootstrap interval; the realizations used and left out, the draws per realization."""

    variances: NDArray[np.float64]  # (3,)
    shares: NDArray[np.float64]  # (3,)
    variance_interval: NDArray[np.float64]  # (2, 3): low, high
    share_interval: NDArray[np.float64]  # (2, 3)
    realizations: int
    left_out: int
    samples: int

    def table(self) -> pd.DataFrame:
        """geometry_share.csv: quantity, value, ci_low, ci_high, unit; the three shares, their
        variances, Var(FS), then the counts (no interval)."""
        total = self.variances.sum()
        rows = [
            (f"{name}_share", self.shares[k], *self.share_interval[:, k], "1")
            for k, name in enumerate(COMPONENTS)
        ] + [
            (f"variance_{name}", self.variances[k], *self.variance_interval[:, k], "1")
            for k, name in enumerate(COMPONENTS)
        ]
        rows.append(("variance_fs", total, np.nan, np.nan, "1"))
        for name, count in (
            ("realizations", self.realizations),
            ("realizations_left_out", self.left_out),
            ("samples_per_realization", self.samples),
            ("runs", (self.realizations + self.left_out) * self.samples),
            ("bootstrap_replicates", REPLICATES),
        ):
            rows.append((name, float(count), np.nan, np.nan, "1"))
        return pd.DataFrame(rows, columns=["quantity", "value", "ci_low", "ci_high", "unit"])

    def text(self) -> str:
        """The command's line: the geometry's share with its interval, over how many runs."""
        low, high = self.share_interval[:, 0]
        dropped = f" ({self.left_out} left out: a run without an FS)" if self.left_out else ""
        return (
            f"the geometry holds {self.shares[0]:.2f} of the variance of FS (95 % bootstrap interval "
            f"{low:.2f} to {high:.2f}), the other inputs {self.shares[1]:.2f}, their interaction "
            f"{self.shares[2]:.2f}; over {self.realizations} realizations{dropped} x {self.samples} draws"
        )


def geometry_share(fs: ArrayLike, excluded: ArrayLike, realizations: int, seed: int) -> Share:
    """The geometry's share of Var(FS) from a crossed design's FS in sample order (row r m + s:
    realization r, draw s; `design.crossed_table`), the samples without an FS marked in `excluded`.
    ValueError if fewer than 2 realizations are complete or FS does not vary over them."""
    fs = np.asarray(fs, dtype=float).reshape(realizations, -1)
    complete = ~np.asarray(excluded, dtype=bool).reshape(fs.shape).any(axis=1)
    kept = fs[complete]
    n, m = kept.shape
    if n < 2:
        raise ValueError(f"{n} of {realizations} realizations have an FS in every run: no geometry share")
    if np.ptp(kept) == 0.0:
        raise ValueError("FS is the same in every run: no variance to share")
    variances = components(kept)
    rng = np.random.default_rng(seed)
    per = max(1, CHUNK // (n * m))
    replicates = []
    for first in range(0, REPLICATES, per):
        count = min(per, REPLICATES - first)
        r = rng.integers(0, n, size=(count, n))
        s = rng.integers(0, m, size=(count, m))
        replicates.append(components(kept[r[:, :, None], s[:, None, :]]))
    boot = np.concatenate(replicates)
    tails = [100 * (1 - CONFIDENCE) / 2, 100 * (1 + CONFIDENCE) / 2]
    return Share(
        variances=variances,
        shares=_shares(variances),
        variance_interval=np.percentile(boot, tails, axis=0),
        share_interval=np.nanpercentile(_shares(boot), tails, axis=0),
        realizations=n,
        left_out=realizations - n,
        samples=m,
    )


def tables(
    fs: ArrayLike, excluded: ArrayLike, sampling: Sampling, summary: pd.DataFrame, say: Callable[[str], None]
) -> dict[str, pd.DataFrame]:
    """A crossed study's geometry_share.csv and its summary.csv with the share and its interval
    (geometry_share, geometry_share_ci_low, _ci_high) appended; the share's line said. None of it,
    with a line, if there is no share (`geometry_share`'s ValueError)."""
    try:
        share = geometry_share(fs, excluded, sampling.realizations, sampling.seed)
    except ValueError as error:
        say(f"no geometry share: {error}")
        return {}
    say(share.text())
    low, high = share.share_interval[:, 0]
    values = {"geometry_share": share.shares[0], "geometry_share_ci_low": low, "geometry_share_ci_high": high}
    rows = pd.DataFrame([(k, v, "1") for k, v in values.items()], columns=["quantity", "value", "unit"])
    return {"geometry_share": share.table(), "summary": pd.concat([summary, rows], ignore_index=True)}
