"""What a strength reduction returns (`bbmc.fos.strength_reduction.factor_of_safety`): its trials, its
bracket, the start and end states of the blocks, and the tables `bbmc fos` writes of them (fos.csv,
mechanism.csv); and the one way bbmc shows a factor of safety (`factor_of_safety_text`)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.dem.verdict import UNSTABLE

LARGEST_DECIMALS = 12  # a bracket bisected down to adjacent floating-point numbers shows this many


def factor_of_safety_text(factor_of_safety: float, bracket: tuple[float, float], bracketed: bool) -> str:
    """A factor of safety as bbmc shows it everywhere (the command's line, the figures' titles, a
    result's repr): to the decimals its bracket supports. The FS lies in the bracket [last stable,
    first unstable factor], whose width w is at most the search's tolerance; it is shown with d
    decimals, the first place w reaches (10^-d <= w < 10^(1-d), d >= 0): "0.840" for the midpoint
    0.83984375 of [0.8359375, 0.84375] (w = 0.0078). Beyond the searched range, the bound it lies
    beyond: "> 8", "< 0.125". The full number stays in `factor_of_safety` and summary.csv."""
    if not bracketed:
        return f"> {factor_of_safety:g}" if math.isinf(bracket[1]) else f"< {factor_of_safety:g}"
    return f"{factor_of_safety:.{bracket_decimals(bracket)}f}"


def bracket_decimals(bracket: tuple[float, float]) -> int:
    """The decimals d a bracket [low, high] supports: the first place its width w reaches,
    10^-d <= w < 10^(1-d), at least 0 and at most LARGEST_DECIMALS (a bracket bisected to adjacent
    floating-point numbers)."""
    width = bracket[1] - bracket[0]
    decimals = -math.floor(math.log10(width)) if width > 0 else LARGEST_DECIMALS
    return min(max(decimals, 0), LARGEST_DECIMALS)


@dataclass(frozen=True)
class Trial:
    """One trial of the search: the scene with every joint's strength divided by `factor`, run from
    the start state until its verdict.

    Attributes:
        factor: the strength reduction factor F of the trial [1].
        verdict: "stable" (holds) or "unstable" (fails).
        reason: why: "equilibrium" (the unbalanced-force ratio fell below its limit), "displacement" (a
            judged block moved `failure_displacement_m`), "not_settled" (the budget ended first), or the
            trend's verdict (`bbmc.dem.verdict`).
        steps: time steps the trial ran [1].
        largest_displacement_m: the largest displacement of a vertex of a judged block from the start
            state at the trial's end [m].
        unbalanced_force_ratio: the unbalanced-force ratio of the judged blocks at its end [1].
        seconds: its wall time [s].
        block: the judged block that moved most.
        block_size_m: that block's size, the square root of its area [m].
    """

    factor: float
    verdict: str
    reason: str
    steps: int
    largest_displacement_m: float
    unbalanced_force_ratio: float
    seconds: float
    block: str = ""
    block_size_m: float = math.nan


def trials_table(trials: Sequence[Trial]) -> pd.DataFrame:
    """fos.csv: one row per trial, in the order run: `trial` (1, 2, ...), `factor` (F), `verdict`,
    `reason`, `steps`, `largest_displacement_mm`, `unbalanced_force_ratio`, `wall_time_s`,
    `moved_most_block` (of the judged blocks) and `moved_most_block_size_m`."""
    return pd.DataFrame(
        {
            "trial": range(1, len(trials) + 1),
            "factor": [t.factor for t in trials],
            "verdict": [t.verdict for t in trials],
            "reason": [t.reason for t in trials],
            "steps": [t.steps for t in trials],
            "largest_displacement_mm": [t.largest_displacement_m * 1e3 for t in trials],
            "unbalanced_force_ratio": [t.unbalanced_force_ratio for t in trials],
            "wall_time_s": [t.seconds for t in trials],
            "moved_most_block": [t.block for t in trials],
            "moved_most_block_size_m": [t.block_size_m for t in trials],
        }
    )


@dataclass(frozen=True)
class FromRest:
    """The scene's run from rest with its strengths as given (the unreduced equilibrium, as `bbmc run`
    runs it).

    Attributes:
        verdict: "stable" or "unstable".
        reason: why (as `Trial.reason`).
        steps: time steps it ran [1].
        block: the judged block that moved most.
        largest_displacement_m: how far a vertex of it moved [m].
    """

    verdict: str
    reason: str
    steps: int
    block: str
    largest_displacement_m: float


@dataclass(repr=False)
class StrengthReductionResult:
    """A scene's factor of safety by strength reduction, with every trial of the search. `str()` and
    `repr()` show the FS to the decimals its bracket supports (`factor_of_safety_text`, also
    `.factor_of_safety_text`); `mechanism` and `trials_table` are the tables `bbmc fos` writes as
    mechanism.csv and fos.csv; `bbmc.api.mechanism_figure` and `bbmc.api.bracketing_figure` draw them.

    Attributes:
        factor_of_safety: the FS [1], the bracket's middle at full precision (the bound it lies beyond
            where `bracketed` is False).
        bracket: the highest stable and the lowest unstable factor found (last stable, first unstable)
            [1]; 0 or inf for a side the search did not find.
        bracketed: False where the FS lies beyond the searched range ([1 / largest_factor,
            largest_factor]): `factor_of_safety` is then that bound.
        start: where every trial starts: "unreduced" (the equilibrium with the strengths as given) or
            "elastic" (every strength x 1e6 to equilibrium, for a scene that does not stand from rest).
        equilibrium_steps: the steps N_r of that equilibrium [1], the search's response time.
        equilibrium_seconds: its wall time [s].
        trials: every trial in the order run (`Trial`).
        start_world: every vertex where the trials start, (vertices, 2) [m], in the scene's block order
            (`model.vertex_start` gives each block's first vertex).
        mechanism_world: every vertex at the end of the lowest unstable trial, (vertices, 2) [m]; None
            where no trial failed.
        start_blocks: the blocks' engine rows (`bbmc.dem.layout`: x, y [m], rotation [rad], velocities
            [m/s, rad/s], size [m] ...) at the start of every trial.
        stable_blocks: their rows at the end of the highest stable trial (the start state where none
            ran: F = 1 holds by the equilibrium).
        mechanism_blocks: their rows at the end of the lowest unstable trial; None where none failed.
        failure_displacement_m: the displacement of a vertex that makes a trial unstable [m].
        laws_losing_cohesion: joint laws in use with `after_slip: zero` (their FS includes
            progressive failure).
        support_state: the support elements' engine rows at the end of the highest stable trial (no
            rows without support).
        from_rest: the run from rest with the strengths as given (`FromRest`).
        median_block_size_m: the median size of the blocks free to move [m].
        model: the assembled scene the trials ran on (`bbmc.dem.model.Model`: block names, vertices,
            degrees of freedom), for the tables and figures.
    """

    factor_of_safety: float
    bracket: tuple[float, float]
    bracketed: bool
    start: str
    equilibrium_steps: int
    equilibrium_seconds: float
    trials: list[Trial]
    start_world: np.ndarray
    mechanism_world: np.ndarray | None
    start_blocks: np.ndarray
    stable_blocks: np.ndarray
    mechanism_blocks: np.ndarray | None
    failure_displacement_m: float
    laws_losing_cohesion: list[str]
    model: Model = dataclasses.field(compare=False)
    support_state: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, L.SUPPORT_COLUMNS)))
    from_rest: FromRest | None = None
    median_block_size_m: float = math.nan

    @property
    def factor_of_safety_text(self) -> str:
        """The FS as bbmc shows it: to the decimals its bracket supports (`factor_of_safety_text`)."""
        return factor_of_safety_text(self.factor_of_safety, self.bracket, self.bracketed)

    def __str__(self) -> str:
        low, high = self.bracket
        where = (
            f"between {low:.6g} (holds) and {high:.6g} (fails)"
            if self.bracketed
            else "beyond the searched range"
        )
        return (
            f"factor of safety {self.factor_of_safety_text} ({where}; {len(self.trials)} trials from the "
            f"{self.start} equilibrium)"
        )

    def __repr__(self) -> str:
        return (
            f"StrengthReductionResult(factor_of_safety={self.factor_of_safety!r} (FS "
            f"{self.factor_of_safety_text}), bracket={self.bracket!r}, bracketed={self.bracketed}, "
            f"start={self.start!r}, trials={len(self.trials)})"
        )

    @property
    def failing_trial(self) -> Trial | None:
        """The lowest unstable trial (None if none failed): its block that moved most failed first."""
        failed = [t for t in self.trials if t.verdict == UNSTABLE]
        return min(failed, key=lambda t: t.factor) if failed else None

    @property
    def failing_note(self) -> str:
        """One line naming the block that failed in the lowest unstable trial, where it is smaller than
        half the median block (a sliver may set the FS: `fos.judge`); "" otherwise."""
        trial = self.failing_trial
        if trial is None or not trial.block or not trial.block_size_m < 0.5 * self.median_block_size_m:
            return ""
        moved_mm, relative = trial.largest_displacement_m * 1e3, trial.block_size_m / self.median_block_size_m
        return (
            f"at F = {trial.factor:.4g} block '{trial.block}' failed first ({moved_mm:.3g} mm), "
            f"{relative:.2g} x the median block's size: fos.judge asks for the FS of the blocks that matter"
        )

    @property
    def elastic_start_note(self) -> str:
        """One line for an FS taken from the elastic start, beside the run from rest ("" otherwise)."""
        rest = self.from_rest
        if self.start != "elastic" or rest is None:
            return ""
        held = "holds" if self.factor_of_safety >= 1.0 else "fails too"
        why = rest.reason.replace("_", " ")
        return (
            f"the scene does not stand from rest with its strengths as given ({why} "
            f"in {rest.steps} steps, block '{rest.block}' moved {rest.largest_displacement_m * 1e3:.3g} mm: "
            "what bbmc run shows); this FS is from the elastic start (every strength x 1e6 to equilibrium, "
            f"then as given), where F = 1 {held}: a slope loaded gradually, not all at once"
        )

    def moved(self, end: np.ndarray) -> np.ndarray:
        """Each block's centroid displacement x, y [m] and rotation [rad] from the start of the trials to
        `end` (the blocks' rows at the end of one: `stable_blocks`, `mechanism_blocks`)."""
        columns = [L.X, L.Y, L.TH]
        return end[:, columns] - self.start_blocks[:, columns]

    @property
    def progressive_note(self) -> str:
        """One line for a scene whose joints lose their cohesion at the first slip ("" otherwise)."""
        if not self.laws_losing_cohesion:
            return ""
        names = ", ".join(f"'{name}'" for name in self.laws_losing_cohesion)
        return (
            f"joint law {names} loses its cohesion at the first slip (after_slip: zero, UDEC's Coulomb "
            "slip): this FS includes progressive failure and lies below limit equilibrium's"
        )

    @property
    def trials_table(self) -> pd.DataFrame:
        """fos.csv: one row per trial, in the order run: `trial` (1, 2, ...), `factor` (F), `verdict`,
        `reason`, `steps`, `largest_displacement_mm`, `unbalanced_force_ratio`, `wall_time_s`,
        `moved_most_block` (of the judged blocks) and `moved_most_block_size_m` (the module's
        `trials_table`, which the 3D search's table shares)."""
        return trials_table(self.trials)

    @property
    def mechanism(self) -> pd.DataFrame:
        """mechanism.csv, by block: every block at the end of the highest stable trial and of the
        lowest unstable one, with `trial` (last_stable or first_unstable), `factor` (its F), `block_id`
        (the block's index in the scene's block order, as in the VTK files), `block`, `group`, `free`
        (False: every degree of freedom held), `size_m` (square root of its area), `x_m`, `y_m` (its
        centroid where the trials start), `ux_mm`, `uy_mm`, `displacement_mm`, `rotation_deg` (since
        then), `vx_m_s`, `vy_m_s`, `angular_velocity_deg_s` (at the trial's last step). Where no stable
        trial ran, the last stable rows are the start state at F = 1; a trial the search did not find
        (none failed, or none held) has no rows; one of the two always is."""
        low, high = self.bracket
        ends = []
        if low > 0.0:
            ends.append(self._trial_end("last_stable", low, self.stable_blocks))
        if self.mechanism_blocks is not None:
            ends.append(self._trial_end("first_unstable", high, self.mechanism_blocks))
        return pd.concat(ends, ignore_index=True)

    def _trial_end(self, kind: str, factor: float, blocks: np.ndarray) -> pd.DataFrame:
        model, start, moved = self.model, self.start_blocks, self.moved(blocks)
        return pd.DataFrame(
            {
                "trial": kind,
                "factor": factor,
                "block_id": np.arange(len(model.block_names)),
                "block": model.block_names,
                "group": [model.group_names[g] for g in model.block_group],
                "free": ~np.all(model.dof == L.PRESCRIBED, axis=1),
                "size_m": start[:, L.SIZE],
                "x_m": start[:, L.X],
                "y_m": start[:, L.Y],
                "ux_mm": moved[:, 0] / units.mm,
                "uy_mm": moved[:, 1] / units.mm,
                "displacement_mm": np.hypot(moved[:, 0], moved[:, 1]) / units.mm,
                "rotation_deg": moved[:, 2] / units.deg,
                "vx_m_s": blocks[:, L.VX],
                "vy_m_s": blocks[:, L.VY],
                "angular_velocity_deg_s": blocks[:, L.W] / units.deg,
            }
        )
