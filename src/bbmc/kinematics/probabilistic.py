"""Probabilistic kinematics: with each set's mean pole and Fisher K, the probability that each mode
is feasible for a face, by Monte Carlo over orientations.

For a set s, M poles are drawn from Fisher's distribution about its mean (`fisher_sample`, exact
inversion; Fisher 1953) and each pole mode's probability is the fraction of them that is critical:
the probability that a joint of that set, drawn at random, is. For a pair of sets (a, b) the i-th
draws of a and of b are intersected (independent planes) and each line mode's probability is the
fraction of the lines that is critical. Each estimate p has the binomial standard error
sqrt(p (1 - p) / M); when no draw (or every draw) is critical the error is 0 and the 95 % bound on
p (or 1 - p) is 3 / M (the rule of three). As K grows the draws close on the mean and p tends to 1
or 0 as the mean pole (or the means' intersection) is critical or not. Draws go in chunks of
`CHUNK_SAMPLES`, so memory stays bounded for any M.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import fisher_sample, intersection_lines, upward
from bbmc.kinematics.criteria import set_pair_friction
from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES, line_modes, pole_modes
from bbmc.kinematics.tallies import names_of_sets

CHUNK_SAMPLES = 1 << 19


@dataclass(frozen=True)
class ModeProbability:
    """The probability that `mode` is feasible for a joint of `group` (a set, or a pair of sets),
    from `samples` draws, with its binomial standard error."""

    mode: str
    group: str
    probability: float
    standard_error: float
    samples: int


def _rows(modes: tuple[str, ...], hits: dict[str, int], group: str, samples: int) -> list[ModeProbability]:
    rows = []
    for mode in modes:
        p = hits[mode] / samples
        rows.append(ModeProbability(mode, group, p, float(np.sqrt(p * (1.0 - p) / samples)), samples))
    return rows


def mode_probabilities(
    set_means: np.ndarray,
    set_kappas: np.ndarray,
    face: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits | None = None,
    samples: int = 1_000_000,
    rng: np.random.Generator | None = None,
    set_names: Sequence[str] | None = None,
) -> list[ModeProbability]:
    """Per set, the probability of each pole mode; per pair of sets, of each line mode: p = the fraction
    of `samples` Fisher draws (Fisher 1953; per set) or of their pairwise intersections (per pair of sets)
    that is critical, with the binomial standard error sqrt(p (1 - p) / samples). `set_means` (k, 3)
    mean poles, `set_kappas` (k,) Fisher K, `friction` [rad] one or per set (a pair takes the smaller,
    `set_pair_friction`)."""
    limits = KinematicLimits() if limits is None else limits
    rng = np.random.default_rng(0) if rng is None else rng
    means = np.asarray(set_means, dtype=float)
    friction = np.broadcast_to(np.asarray(friction, dtype=float), (len(means),))
    names = names_of_sets(len(means), set_names)
    pole_hits = [dict.fromkeys(POLE_MODES, 0) for _ in means]
    pairs = [(a, b) for a in range(len(means)) for b in range(a + 1, len(means))]
    line_hits = {pair: dict.fromkeys(LINE_MODES, 0) for pair in pairs}
    for start in range(0, samples, CHUNK_SAMPLES):
        size = min(CHUNK_SAMPLES, samples - start)
        draws = [
            upward(fisher_sample(m, float(k), size, rng)) for m, k in zip(means, set_kappas, strict=True)
        ]
        for s, normals in enumerate(draws):
            for mode, mask in pole_modes(normals, face, friction[s], limits).items():
                pole_hits[s][mode] += int(np.count_nonzero(mask))
        for a, b in pairs:
            lines, sine = intersection_lines(draws[a], draws[b])
            lines = np.where((sine > 1e-9)[:, None], lines, [0.0, 0.0, np.nan])
            masks = line_modes(lines, face, set_pair_friction(friction[a], friction[b]), limits)
            for mode, mask in masks.items():
                line_hits[(a, b)][mode] += int(np.count_nonzero(mask))
    rows = [row for s in range(len(means)) for row in _rows(POLE_MODES, pole_hits[s], names[s], samples)]
    for a, b in pairs:
        rows += _rows(LINE_MODES, line_hits[(a, b)], f"{names[a]} x {names[b]}", samples)
    return rows
