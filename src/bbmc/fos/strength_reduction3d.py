"""The factor of safety of a 3D block scene (`bbmc.dem3d`) by shear-strength reduction, by the same
search as the 2D engine's (`bbmc.fos.strength_reduction`'s docstring gives the rules): the trial's
verdict and the bracketing are `bbmc.fos.search`'s, shared, and the settings `bbmc.scene.fos_settings.
StrengthReduction`'s.

The scene is brought to equilibrium with its strengths as given (N_r steps); each trial at F starts
from that state with every joint type's strength divided by F (the 3D joint laws' P_STRENGTH_DIVISOR:
c / F and tan(phi) / F; for Barton-Bandis the unreduced envelope's tangent at sigma_n, divided, as the
2D ``envelope`` reduction). A trial is *stable* once the unbalanced-force ratio of the judged blocks
(`bbmc.dem3d.monitors`) is below its limit, *unstable* once a vertex of a judged block has moved the
failure displacement (default 5 % of the median size of the blocks free to move) or when the trend or
the budget says so. The time step is fixed for the whole search: `safety` x the critical step of the
scene as built (`bbmc.dem3d.solver.time_step`).

A scene that finds no equilibrium with its own strengths (FS < 1) starts, as in 2D, from its
equilibrium with every strength multiplied by 1e6 (the elastic start, `ELASTIC_DIVISOR`), and F = 1 is
tried from there (`bbmc.fos.search.bracket_factor`). Not yet as in 2D: support and the ``phi_b_jrc``
reduction do not exist in 3D (refused); judged blocks are given as indices. Units: m, s, N.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc.dem.verdict import STABLE
from bbmc.dem3d import monitors
from bbmc.dem3d.joint_laws import P_STRENGTH_DIVISOR
from bbmc.dem3d.model import Model
from bbmc.dem3d.solver import run, time_step
from bbmc.fos import search
from bbmc.fos.result import Trial
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.fos_settings import StrengthReduction

ELASTIC_DIVISOR = 1e-6  # strengths x 1e6: the start of a scene not in equilibrium unreduced (as 2D's)
FAILURE_FRACTION = 0.05  # the default failure displacement, x the median size of the free blocks [1]


@dataclass
class _Run:
    """A 3D run as `bbmc.fos.search.settle` reads it (`search.Run`), on the judged blocks."""

    model: Model
    dt: float
    damping: float
    reference: float
    judged: np.ndarray  # bool per block
    vertices: np.ndarray  # bool per vertex
    threads: int = 1

    @property
    def step(self) -> int:
        return self.model.step

    def advance(self, steps: int) -> None:
        run(self.model, steps, self.dt, self.damping, self.threads)

    def positions(self) -> np.ndarray:
        return self.model.vertices[self.vertices].copy()

    def unbalance(self) -> float:
        return monitors.unbalanced_force_ratio(self.model, self.reference, self.judged)

    def loaded(self) -> bool:
        return True


@dataclass(frozen=True)
class StrengthReduction3DResult:
    """The search's outcome: `factor_of_safety` [1], its `bracket` [stable F, unstable F] and whether it
    was `bracketed`; the equilibrium's steps and seconds, the time step `dt` [s], the failure
    displacement [m], every trial (`bbmc.fos.result.Trial`), the equilibrium's model and the model at
    the end of the lowest unstable trial (`failed`, None if every trial held): its mechanism; `start`:
    the trials' start, ``unreduced`` or ``elastic`` (module docstring)."""

    factor_of_safety: float
    bracket: tuple[float, float]
    bracketed: bool
    equilibrium_steps: int
    equilibrium_seconds: float
    dt: float
    failure_displacement_m: float
    trials: list[Trial]
    equilibrium: Model
    failed: Model | None
    start: str


def _judged(model: Model, judged: Sequence[int] | None) -> np.ndarray:
    free = monitors.free_blocks(model)
    if judged is None:
        return free
    chosen = np.zeros(len(free), dtype=bool)
    for i in judged:
        if not 0 <= i < len(free):
            raise ValueError(f"judged: block {i} is not one of the {len(free)} blocks")
        chosen[i] = True
    if not (chosen & free).any():
        raise ValueError("judged: it leaves no block free to move to judge")
    return chosen


def _equilibrium(
    model: Model, runner, settings: StrengthReduction, steps: int, failure: float
) -> tuple[str, Model]:
    """The trials' start (module docstring): ("unreduced" or "elastic", a copy of `model` settled with
    its strengths divided by 1 or by ELASTIC_DIVISOR) within `steps`; `runner` makes the run of a
    model. ValueError if neither settles."""
    for start, divisor in (("unreduced", 1.0), ("elastic", ELASTIC_DIVISOR)):
        equilibrium = copy.deepcopy(model)
        equilibrium.law_params[:, P_STRENGTH_DIVISOR] = divisor
        verdict, reason = search.settle(runner(equilibrium), settings, steps, failure)
        if verdict == STABLE:
            return start, equilibrium
    raise ValueError(f"model: no equilibrium even elastic ({reason}, {equilibrium.step} steps)")


def factor_of_safety_3d(
    model: Model,
    settings: StrengthReduction | None = None,
    *,
    damping: float = 0.8,
    safety: float = 0.5,
    equilibrium_steps: int = 100_000,
    judged: Sequence[int] | None = None,
    progress: ProgressCallback = ignore,
    threads: int = 1,
) -> StrengthReduction3DResult:
    """The factor of safety of the 3D `model` (module docstring) with the search `settings` (default
    `StrengthReduction()`), local damping `damping` [1], the time step `safety` x critical, at most
    `equilibrium_steps` steps to the unreduced equilibrium, the verdicts read on the blocks `judged`
    (indices; default every block free to move); `progress` gets each trial's verdict; `threads`: the
    engine's (`bbmc.dem3d.solver.run`: the same answer to the bit on any count). The model is
    left as it was given. ValueError: the ``phi_b_jrc`` reduction, a judged index out of range, no
    equilibrium even with the elastic start."""
    settings = StrengthReduction() if settings is None else settings
    if settings.barton_bandis_reduction != "envelope":
        raise ValueError("fos.barton_bandis_reduction: only 'envelope' exists in 3D so far")
    chosen = _judged(model, judged)
    vertices = np.repeat(chosen, np.diff(model.vertex_start))
    free = monitors.free_blocks(model)
    failure = settings.failure_displacement_m or FAILURE_FRACTION * float(np.median(model.size[free]))
    reference = monitors.reference_force(model)
    dt = time_step(model, safety, damping)
    started = time.perf_counter()
    start, equilibrium = _equilibrium(
        model, lambda m: _Run(m, dt, damping, reference, chosen, vertices, threads), settings,
        equilibrium_steps, failure,
    )  # fmt: skip
    n_r, eq_seconds = equilibrium.step, time.perf_counter() - started
    budget = max(settings.min_trial_steps, math.ceil(settings.response_multiple * n_r))
    window = max(settings.check_every_steps, math.ceil(settings.trend_window_multiple * n_r))
    origin = equilibrium.vertices[vertices].copy()
    trials: list[Trial] = []
    failed: dict[float, Model] = {}

    def attempt(factor: float) -> bool:
        trial = copy.deepcopy(equilibrium)
        trial.law_params[:, P_STRENGTH_DIVISOR] = factor
        running = _Run(trial, dt, damping, reference, chosen, vertices, threads)
        clock, first = time.perf_counter(), trial.step
        verdict, reason = search.settle(running, settings, budget, failure, window, origin)
        trials.append(
            Trial(
                factor=factor,
                verdict=verdict,
                reason=reason,
                steps=trial.step - first,
                largest_displacement_m=search.largest_move(running.positions(), origin),
                unbalanced_force_ratio=running.unbalance(),
                seconds=time.perf_counter() - clock,
            )
        )
        if verdict != STABLE and factor < min(failed, default=math.inf):
            failed.clear()
            failed[factor] = trial
        holds = "holds" if verdict == STABLE else "fails"
        progress(Progress(len(trials), None, "trials", f"trial {len(trials)} at F = {factor:.4g}: {holds}"))
        return verdict == STABLE

    fs, bracket, bracketed = search.bracket_factor(
        attempt, settings.largest_factor, settings.tolerance, start == "elastic"
    )
    return StrengthReduction3DResult(
        fs,
        bracket,
        bracketed,
        n_r,
        eq_seconds,
        dt,
        failure,
        trials,
        equilibrium,
        next(iter(failed.values()), None),
        start,
    )
