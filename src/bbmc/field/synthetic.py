"""Synthetic orientation surveys from known sets: each set's poles drawn from Fisher's distribution
(`bbmc.geometry.orientation.fisher_sample`, exact), random readings uniform on the sphere, all turned
upward (n_z >= 0) as a reader would give them, and shuffled. The true labels come back with them, so
set finding can be scored against the truth and an example survey made by a kept script.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import fisher_sample, poles, upward


@dataclass(frozen=True)
class KnownSet:
    """A set to draw: its mean plane's `dip` and `dip_direction` [rad], Fisher's K and its count of
    readings."""

    dip: float
    dip_direction: float
    fisher_k: float
    count: int

    @property
    def mean_pole(self) -> np.ndarray:
        """The mean pole, an upward unit normal."""
        return poles(self.dip, self.dip_direction)


@dataclass(frozen=True)
class SyntheticSurvey:
    """Upward unit poles (n, 3) and their true labels (n,): the index of their set in the order given,
    -1 for a random reading."""

    poles: np.ndarray
    labels: np.ndarray


def uniform_axes(count: int, rng: np.random.Generator) -> np.ndarray:
    """`count` upward unit vectors (count, 3) uniform on the hemisphere: z = cos of the angle from the
    vertical uniform on [0, 1], the azimuth uniform (Archimedes' hat-box theorem)."""
    z, azimuth = rng.random(count), rng.random(count) * 2.0 * np.pi
    r = np.sqrt(1.0 - z**2)
    return np.column_stack([r * np.sin(azimuth), r * np.cos(azimuth), z])


def synthetic_survey(
    sets: Sequence[KnownSet], random_count: int, rng: np.random.Generator
) -> SyntheticSurvey:
    """A shuffled survey of the `sets`' readings and `random_count` random ones."""
    drawn = [fisher_sample(s.mean_pole, s.fisher_k, s.count, rng) for s in sets]
    drawn.append(uniform_axes(random_count, rng))
    labels = np.concatenate([np.full(s.count, j) for j, s in enumerate(sets)] + [np.full(random_count, -1)])
    readings = np.vstack(drawn)
    readings = upward(readings)
    order = rng.permutation(labels.size)
    return SyntheticSurvey(readings[order], labels[order].astype(int))
