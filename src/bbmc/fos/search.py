"""The engine-free parts of the strength reduction, shared by the 2D and 3D engines' searches
(`bbmc.fos.strength_reduction`, `bbmc.fos.strength_reduction3d`): a trial's verdict (`settle`) read
from a run through the small `Run` interface, and the search's bracketing and bisection
(`bracket_factor`). The rules are the 2D module's docstring's; nothing here knows a block.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

import numpy as np

from bbmc.dem.verdict import STABLE, UNSTABLE, Trend
from bbmc.scene.fos_settings import StrengthReduction


class Run(Protocol):
    """A trial's run as the verdict sees it: its step count, how to advance it, where the judged
    blocks' vertices are ((k, d) [m], any dimension d), its unbalanced-force ratio over the judged
    blocks [1], and whether its loads are all applied."""

    @property
    def step(self) -> int: ...

    def advance(self, steps: int) -> None: ...

    def positions(self) -> np.ndarray: ...

    def unbalance(self) -> float: ...

    def loaded(self) -> bool: ...


def largest_move(positions: np.ndarray, origin: np.ndarray) -> float:
    """The largest distance between rows of `positions` and `origin` (k, d) [m]; 0 for none."""
    return float(np.max(np.linalg.norm(positions - origin, axis=1), initial=0.0))


def settle(
    run: Run,
    settings: StrengthReduction,
    budget: int,
    failure_displacement: float,
    window: int | None = None,
    origin: np.ndarray | None = None,
    approach: bool = False,
) -> tuple[str, str]:
    """Advance `run` until its verdict: (verdict, reason). Every `check_every_steps`: *unstable*
    ("displacement") once a judged vertex has moved `failure_displacement` [m] from `origin` (default:
    where they are now), *stable* ("equilibrium") once the loads are applied and the unbalanced-force
    ratio is below its limit; with `window` [steps] the trend of the motion over successive windows
    decides too (`bbmc.dem.verdict.Trend`; `approach`: on a soft support); *unstable* ("not_settled")
    when `budget` steps end first."""
    start, first = (run.positions() if origin is None else origin), run.step
    trend = Trend(failure_displacement, settings.unbalanced_force_ratio, approach) if window else None
    window_start, window_positions = first, run.positions()
    while run.step - first < budget:
        run.advance(min(settings.check_every_steps, budget - (run.step - first)))
        positions = run.positions()
        moved = largest_move(positions, start)
        if moved > failure_displacement:
            return UNSTABLE, "displacement"
        loaded = run.loaded()
        unbalance = run.unbalance()
        if loaded and unbalance < settings.unbalanced_force_ratio:
            return STABLE, "equilibrium"
        if trend is not None and loaded and run.step - window_start >= window:
            verdict = trend.observe(largest_move(positions, window_positions), moved, unbalance)
            window_start, window_positions = run.step, positions
            if verdict is not None:
                return verdict
    return UNSTABLE, "not_settled"


def bracket_factor(
    attempt: Callable[[float], bool], largest: float, tolerance: float, try_one: bool
) -> tuple[float, tuple[float, float], bool]:
    """The factor of safety from trials `attempt(F)` (True: holds): (FS, bracket [stable F, unstable F],
    bracketed). F = 1 holds by the equilibrium unless `try_one` (the start was the elastic one): then it
    is tried, and if it fails F is halved until a trial holds; else F is doubled until a trial fails;
    within [1 / largest, largest]. The bracket is then bisected until narrower than `tolerance`, the FS
    its middle; a bracket not found is reported as the bound it lies beyond."""
    lo, hi = 1.0, math.inf
    if try_one and not attempt(1.0):
        lo, hi = 0.0, 1.0
    while hi == math.inf and lo < largest:
        factor = min(2.0 * lo, largest)
        lo, hi = (factor, hi) if attempt(factor) else (lo, factor)
    while lo == 0.0 and hi > 1.0 / largest:
        factor = max(0.5 * hi, 1.0 / largest)
        lo, hi = (factor, hi) if attempt(factor) else (lo, factor)
    bracketed = lo > 0.0 and hi < math.inf
    while bracketed and hi - lo > tolerance and lo < 0.5 * (lo + hi) < hi:
        factor = 0.5 * (lo + hi)  # (a tolerance finer than round-off ends at adjacent numbers)
        lo, hi = (factor, hi) if attempt(factor) else (lo, factor)
    fs = 0.5 * (lo + hi) if bracketed else (lo if hi == math.inf else hi)
    return fs, (lo, hi), bracketed
