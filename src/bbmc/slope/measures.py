"""The quantities that test the paper's claims about the slope (section 5.2), on displacement paths.

Each takes plain arrays: times t [s], displacement magnitudes d [m] along a path, or centroid paths
p [m] of shape (n_records, 2). They know nothing of the engine, so tests give them paths with a known
answer.
"""

from __future__ import annotations

import numpy as np


def slip_rate(t: np.ndarray, d: np.ndarray) -> float:
    """Mean slip rate over the second half of the run, (d_end - d_mid) / (t_end - t_mid) [m/s]."""
    mid = len(t) // 2
    return float((d[-1] - d[mid]) / (t[-1] - t[mid]))


def rate_spread(rates: np.ndarray) -> float:
    """(fastest - slowest) / mean of the blocks' slip rates [1]; 0 when they all move alike."""
    mean = float(np.mean(rates))
    return float((np.max(rates) - np.min(rates)) / mean) if mean > 0 else 0.0


def relative_difference(a: float, b: float) -> float:
    """|a - b| / mean(a, b) [1] (0 for two zeros)."""
    mean = 0.5 * (abs(a) + abs(b))
    return abs(a - b) / mean if mean > 0 else 0.0


def separation(path_a: np.ndarray, path_b: np.ndarray) -> float:
    """How far two blocks' centroids have drawn apart at most, from their starting distance [m]."""
    distance = np.hypot(*(path_a - path_b).T)
    return float(np.max(distance - distance[0]))


def quadratic_fit(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares y = c2 x^2 + c1 x + c0: the coefficients (c2, c1, c0) and R^2 [1]."""
    coefficients = np.polyfit(x, y, 2)
    residual = y - np.polyval(coefficients, x)
    total = np.sum((y - np.mean(y)) ** 2)
    return coefficients, float(1.0 - np.sum(residual**2) / total) if total > 0 else 1.0


def onset_time(t: np.ndarray, d: np.ndarray, threshold: float) -> float:
    """The time the displacement first reaches `threshold` [s] (linear between records; inf if never)."""
    above = np.flatnonzero(d >= threshold)
    if not len(above):
        return float("inf")
    k = int(above[0])
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (threshold - d[k - 1]) * (t[k] - t[k - 1]) / (d[k] - d[k - 1]))
