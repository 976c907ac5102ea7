"""Lines of intersection for kinematic analysis: of every pair of readings (exactly, up to a number
of readings; from a random sample of pairs above it) and of every pair of set means.

N readings have N (N - 1) / 2 pairs: 12.5 million at 5,000 readings, 5 billion at 100,000. Up to
`MAX_EXACT_READINGS` every pair is taken, in chunks of `CHUNK_PAIRS` so that memory stays bounded;
above it, `SAMPLE_PAIRS` pairs are drawn uniformly with replacement (i uniform on the N readings,
j uniform on the other N - 1; a pair drawn twice counts twice), from a seeded generator. A
percentage p estimated from m sampled pairs then has the binomial standard error
sqrt(p (1 - p) / m) (with weights, m is Kish's effective number (sum w)^2 / sum w^2): at most
0.5 / sqrt(m), 0.05 percentage points for the default million pairs (tallies.py reports it).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import intersection_lines

MAX_EXACT_READINGS = 5000
SAMPLE_PAIRS = 1_000_000
CHUNK_PAIRS = 1 << 20


@dataclass(frozen=True)
class PairPlan:
    """Which pairs of `readings` readings are intersected: all `pairs` (`exact`), or `evaluated`
    pairs drawn uniformly with replacement by a generator seeded with `seed`."""

    readings: int
    pairs: int
    exact: bool
    evaluated: int
    seed: int

    @property
    def rule(self) -> str:
        """The rule in one sentence, for the outputs."""
        if self.exact:
            return f"all {self.pairs:,} pairs of the {self.readings:,} readings"
        return (
            f"{self.evaluated:,} of the {self.pairs:,} pairs of the {self.readings:,} readings, drawn "
            f"uniformly with replacement (seed {self.seed}); more than {MAX_EXACT_READINGS:,} readings"
        )


def pair_plan(
    readings: int,
    max_exact_readings: int = MAX_EXACT_READINGS,
    sample_pairs: int = SAMPLE_PAIRS,
    seed: int = 0,
) -> PairPlan:
    """Every pair when `readings` <= `max_exact_readings`, else a sample of `sample_pairs`."""
    pairs = readings * (readings - 1) // 2
    exact = readings <= max_exact_readings
    return PairPlan(readings, pairs, exact, pairs if exact else sample_pairs, seed)


def _exact_chunks(readings: int, chunk_pairs: int) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """All pairs i < j, row by row, in blocks of whole rows of about `chunk_pairs` pairs."""
    per_row = np.arange(readings - 1, -1, -1, dtype=np.int64)  # row i pairs with j = i+1 .. N-1
    ends = np.cumsum(per_row)
    start_row = 0
    while start_row < readings - 1:
        target = (ends[start_row - 1] if start_row else 0) + chunk_pairs
        stop_row = max(int(np.searchsorted(ends, target, side="right")), start_row + 1)
        rows = np.arange(start_row, stop_row)
        counts = per_row[rows]
        i = np.repeat(rows, counts)
        offsets = np.arange(i.size) - np.repeat(np.cumsum(counts) - counts, counts)
        yield i, i + 1 + offsets
        start_row = stop_row


def _sampled_chunks(plan: PairPlan, chunk_pairs: int) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(plan.seed)
    left = plan.evaluated
    while left > 0:
        size = min(left, chunk_pairs)
        i = rng.integers(0, plan.readings, size)
        j = rng.integers(0, plan.readings - 1, size)
        j = j + (j >= i)
        yield np.minimum(i, j), np.maximum(i, j)
        left -= size


def pair_chunks(plan: PairPlan, chunk_pairs: int = CHUNK_PAIRS) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Index arrays (i, j), i < j, of the plan's pairs, chunk by chunk."""
    if plan.readings < 2:
        return iter(())
    if plan.exact:
        return _exact_chunks(plan.readings, chunk_pairs)
    return _sampled_chunks(plan, chunk_pairs)


def pair_lines(poles: np.ndarray, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The downward lines of intersection (m, 3) of the planes of poles i and j, and a mask of the
    pairs that have one (planes closer to parallel than 1e-9 rad have none and are left out)."""
    lines, sine = intersection_lines(poles[i], poles[j])
    return lines, sine > 1e-9


@dataclass(frozen=True)
class SetPairLines:
    """The lines of intersection of the mean planes of every pair of sets a < b (NaN where the two
    means are parallel)."""

    set_a: np.ndarray
    set_b: np.ndarray
    lines: np.ndarray


def set_pair_lines(set_means: np.ndarray) -> SetPairLines:
    """The line of intersection of each pair of set mean poles `set_means` (k, 3)."""
    a, b = np.triu_indices(len(set_means), k=1)
    lines, _ = intersection_lines(np.asarray(set_means, float)[a], np.asarray(set_means, float)[b])
    return SetPairLines(a, b, lines)
