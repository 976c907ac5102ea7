"""Counts and percentages of critical poles and intersections for one face: per mode, for the whole
survey, per set and per set pair, and the set pairs whose mean planes' intersection is critical.

Denominators (stated in every row):
* pole modes: the readings of the group (all readings, one set's, or the random ones), weighted;
* line modes: the pairs of readings of the group (all pairs, or the pairs with one reading in each
  of two sets) that have a line of intersection (pairs of parallel planes are left out and
  counted), each pair weighted w_i w_j; all pairs up to 5,000 readings, a random sample above
  (intersections.py), with the binomial standard error of each percentage,
  100 sqrt(p (1 - p) / m_eff), m_eff = (sum w)^2 / sum w^2 over the group's sampled pairs.
Weights are the readings' weights (Terzaghi's, or 1); a percentage is 100 sum(w critical) / sum(w).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from bbmc.geometry.orientation import trend_and_plunge
from bbmc.kinematics.criteria import set_pair_friction
from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.intersections import PairPlan, pair_chunks, pair_lines, pair_plan, set_pair_lines
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES, line_modes, pole_modes


@dataclass(frozen=True)
class ModeTally:
    """One mode in one group: critical and total weight, raw counts, the percentage and its
    standard error [percentage points] (0 when every pole or pair was taken)."""

    mode: str
    group: str
    critical: float
    total: float
    count_critical: int
    count_total: int
    percent: float
    standard_error: float
    denominator: str


@dataclass(frozen=True)
class SetPairModes:
    """The line of intersection of two sets' mean planes (trend, plunge [rad]) and the line modes
    in which it is critical."""

    set_a: str
    set_b: str
    trend: float
    plunge: float
    critical_modes: tuple[str, ...]


@dataclass(frozen=True)
class KinematicTally:
    """The rows of every mode and group, the set pairs, the pair rule and the parallel pairs."""

    rows: tuple[ModeTally, ...]
    set_pairs: tuple[SetPairModes, ...]
    plan: PairPlan
    parallel_pairs: int

    def critical_set_pairs(self, mode: str) -> list[tuple[str, str]]:
        """The set pairs whose mean planes' line of intersection is critical for `mode`."""
        return [(p.set_a, p.set_b) for p in self.set_pairs if mode in p.critical_modes]


def names_of_sets(count: int, set_names: Sequence[str] | None = None) -> list[str]:
    """The caller's names of `count` sets, else "set 1", "set 2", ..."""
    return list(set_names) if set_names is not None else [f"set {s + 1}" for s in range(count)]


def percentage(
    critical: float | np.ndarray, weight: float | np.ndarray, weight_sq: float | np.ndarray, sampled: bool
) -> tuple[np.ndarray, np.ndarray]:
    """100 p, p = critical / weight, and its binomial standard error 100 sqrt(p (1 - p) / m_eff),
    m_eff = weight^2 / weight_sq (Kish), when the items were `sampled`; 0 when all were taken."""
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(weight > 0, critical / weight, np.nan)
        error = 100.0 * np.sqrt(p * (1.0 - p) * weight_sq / weight**2) if sampled else np.zeros_like(p)
    return 100.0 * p, error


def _accumulate(sums: np.ndarray, code: np.ndarray, values: np.ndarray, size: int) -> None:
    sums += np.bincount(code, weights=values, minlength=size)


class _Groups:
    """Weighted sums per group code: sum w, sum w^2, count, and per mode sum w and count critical."""

    def __init__(self, size: int, modes: tuple[str, ...]) -> None:
        self.size, self.modes = size, modes
        self.weight, self.weight_sq, self.count = np.zeros(size), np.zeros(size), np.zeros(size)
        self.critical = {m: np.zeros(size) for m in modes}
        self.count_critical = {m: np.zeros(size) for m in modes}

    def add(self, code: np.ndarray, weight: np.ndarray, masks: dict[str, np.ndarray]) -> None:
        _accumulate(self.weight, code, weight, self.size)
        _accumulate(self.weight_sq, code, weight * weight, self.size)
        _accumulate(self.count, code, np.ones(code.size), self.size)
        for mode in self.modes:
            _accumulate(self.critical[mode], code, weight * masks[mode], self.size)
            _accumulate(self.count_critical[mode], code, masks[mode].astype(float), self.size)

    def rows(self, names: dict[int, str], sampled: bool, denominator: str) -> list[ModeTally]:
        out = []
        for mode in self.modes:
            for code, name in names.items():
                out.append(self._row(mode, name, [code], sampled, denominator))
            out.append(self._row(mode, "all", list(names), sampled, denominator))
        return [row for row in out if row.count_total > 0]

    def _row(self, mode: str, name: str, codes: list[int], sampled: bool, denominator: str) -> ModeTally:
        w, w2 = self.weight[codes].sum(), self.weight_sq[codes].sum()
        c = self.critical[mode][codes].sum()
        percent, error = percentage(c, w, w2, sampled)
        count_critical, count = int(self.count_critical[mode][codes].sum()), int(self.count[codes].sum())
        return ModeTally(
            mode, name, float(c), float(w), count_critical, count, float(percent), float(error), denominator
        )


def reading_groups(
    sets: np.ndarray | None, count: int, set_names: Sequence[str] | None = None
) -> tuple[np.ndarray, dict[int, str]]:
    """Group codes of `count` readings from their set labels (-1 random; None: all random): set s
    is group s, the random readings group k (k sets); and the groups' names ("set 1", ...)."""
    labels = np.full(count, -1) if sets is None else np.asarray(sets, dtype=int)
    k = int(labels.max()) + 1 if labels.size else 0
    return np.where(labels < 0, k, labels), dict(enumerate(names_of_sets(k, set_names))) | {k: "random"}


def pair_groups(
    code_i: np.ndarray, code_j: np.ndarray, names: dict[int, str]
) -> tuple[np.ndarray, dict[int, str]]:
    """Group codes of pairs of readings of group codes i and j (unordered), and their names."""
    size = len(names)
    a, b = np.minimum(code_i, code_j), np.maximum(code_i, code_j)
    pair_names = {x * size + y: f"{names[x]} x {names[y]}" for x in range(size) for y in range(x, size)}
    return a * size + b, pair_names


class ReadingPairs(NamedTuple):
    """One chunk of a plan's pairs of readings (i, j) that have a line of intersection: the downward
    lines (m, 3), the pairs' group codes (`pair_groups`), weights w_i w_j and friction angles
    (`set_pair_friction`) [rad]; and the number of parallel pairs the chunk left out."""

    lines: np.ndarray
    code: np.ndarray
    weight: np.ndarray
    friction: np.ndarray
    parallel: int


def reading_pairs(
    poles: np.ndarray,
    plan: PairPlan,
    code: np.ndarray,
    names: dict[int, str],
    weights: np.ndarray,
    friction: np.ndarray,
) -> Iterator[ReadingPairs]:
    """The plan's pairs of readings chunk by chunk (`pair_chunks`), for a face's tallies and for the
    sweeps alike: readings' `poles` (N, 3), group `code` and `names` (`reading_groups`), `weights` (N,)
    and `friction` (N,) [rad]."""
    for i, j in pair_chunks(plan):
        lines, defined = pair_lines(poles, i, j)
        i, j = i[defined], j[defined]
        pair_code, _ = pair_groups(code[i], code[j], names)
        pair_friction = set_pair_friction(friction[i], friction[j])
        parallel = int(np.count_nonzero(~defined))
        yield ReadingPairs(lines[defined], pair_code, weights[i] * weights[j], pair_friction, parallel)


def pole_tallies(
    poles: np.ndarray,
    face: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits,
    sets: np.ndarray | None = None,
    weights: np.ndarray | None = None,
    set_names: Sequence[str] | None = None,
) -> list[ModeTally]:
    """Per pole mode: the critical readings of the survey, of each set and of the random ones."""
    poles = np.asarray(poles, dtype=float)
    weights = np.ones(len(poles)) if weights is None else np.asarray(weights, dtype=float)
    code, names = reading_groups(sets, len(poles), set_names)
    groups = _Groups(len(names), POLE_MODES)
    groups.add(code, weights, pole_modes(poles, face, friction, limits))
    return groups.rows(names, False, "readings of the group, weighted")


def pair_tallies(
    poles: np.ndarray,
    face: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits,
    plan: PairPlan,
    sets: np.ndarray | None = None,
    weights: np.ndarray | None = None,
    set_names: Sequence[str] | None = None,
) -> tuple[list[ModeTally], int]:
    """Per line mode: the critical lines of intersection of the plan's pairs of readings, for all
    pairs and per pair of groups; and the number of parallel pairs left out."""
    poles = np.asarray(poles, dtype=float)
    weights = np.ones(len(poles)) if weights is None else np.asarray(weights, dtype=float)
    friction = np.broadcast_to(np.asarray(friction, dtype=float), (len(poles),))
    code, names = reading_groups(sets, len(poles), set_names)
    groups, parallel = _Groups(len(names) ** 2, LINE_MODES), 0
    for chunk in reading_pairs(poles, plan, code, names, weights, friction):
        parallel += chunk.parallel
        groups.add(chunk.code, chunk.weight, line_modes(chunk.lines, face, chunk.friction, limits))
    _, pair_names = pair_groups(code[:0], code[:0], names)
    denominator = f"pairs of readings with a line of intersection ({plan.rule})"
    return groups.rows(pair_names, not plan.exact, denominator), parallel


def set_pair_modes(
    set_means: np.ndarray,
    face: Face,
    set_friction: float | np.ndarray,
    limits: KinematicLimits,
    set_names: Sequence[str] | None = None,
) -> list[SetPairModes]:
    """The line of intersection of every pair of set means and the line modes it is critical for
    (friction of a pair: the smaller of the two sets')."""
    means = np.asarray(set_means, dtype=float)
    friction = np.broadcast_to(np.asarray(set_friction, dtype=float), (len(means),))
    names = names_of_sets(len(means), set_names)
    pairs = set_pair_lines(means)
    defined = ~np.isnan(pairs.lines[:, 0])
    lines = np.where(defined[:, None], pairs.lines, [0.0, 0.0, -1.0])
    modes = line_modes(lines, face, set_pair_friction(friction[pairs.set_a], friction[pairs.set_b]), limits)
    trends, plunges = trend_and_plunge(lines)
    out = []
    for n, (a, b) in enumerate(zip(pairs.set_a, pairs.set_b, strict=True)):
        if not defined[n]:
            continue
        critical = tuple(m for m in LINE_MODES if modes[m][n])
        out.append(SetPairModes(names[a], names[b], float(trends[n]), float(plunges[n]), critical))
    return out


def kinematic_tally(
    poles: np.ndarray,
    face: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits | None = None,
    sets: np.ndarray | None = None,
    weights: np.ndarray | None = None,
    set_means: np.ndarray | None = None,
    set_friction: float | np.ndarray | None = None,
    set_names: Sequence[str] | None = None,
    plan: PairPlan | None = None,
) -> KinematicTally:
    """Every mode's tallies for one face: readings (N, 3) upward unit normals with optional set
    labels (-1 random) and weights; `friction` [rad] a float or one per reading; `set_means` (k, 3)
    with `set_friction` (float or k) for the set pairs' intersections; the pairs by `plan`
    (default: `pair_plan(N)`, exact up to 5,000 readings)."""
    limits = KinematicLimits() if limits is None else limits
    plan = pair_plan(len(poles)) if plan is None else plan
    rows = pole_tallies(poles, face, friction, limits, sets, weights, set_names)
    pair_rows, parallel = pair_tallies(poles, face, friction, limits, plan, sets, weights, set_names)
    pairs = []
    if set_means is not None and len(set_means) > 1:
        if set_friction is None and np.ndim(friction) > 0:
            raise ValueError("friction per reading: give set_friction for the set pairs' intersections")
        pair_friction = friction if set_friction is None else set_friction
        pairs = set_pair_modes(set_means, face, pair_friction, limits, set_names)
    return KinematicTally(tuple(rows + pair_rows), tuple(pairs), plan, parallel)
