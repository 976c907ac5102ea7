"""When a run stops (a scene's `solver.stop`): equilibrium once every load acts in full, a displacement
beyond the stop's, a physical time, or the trend of the motion over windows (`bbmc.dem.verdict`).
Read at record steps by `bbmc.dem.solver.simulate`; plain numpy."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem import monitors as mon
from bbmc.dem.model import Model
from bbmc.dem.verdict import Trend

if TYPE_CHECKING:
    from bbmc.dem.solver import State

STOP_REASONS = ("equilibrium", "displacement", "time", "decaying", "creep", "projected")
DEFAULT_UNBALANCE_LIMIT = 1e-5  # the trend's balance limit when the stop gives no unbalanced_force_ratio


@dataclass
class Watch:
    """The trend of a run's motion (`bbmc.dem.verdict.Trend`) over windows of `solver.stop`'s
    trend_window_steps, counted from the step every load acts in full."""

    trend: Trend
    window: int
    start: int
    world: np.ndarray

    @classmethod
    def of(cls, model: Model, state: State) -> Watch | None:
        stop = model.scene.solver.stop
        if stop is None or stop.trend_window_steps is None:
            return None
        limit = stop.unbalanced_force_ratio or DEFAULT_UNBALANCE_LIMIT
        return cls(Trend(stop.displacement_m, limit), stop.trend_window_steps, -1, state.world.copy())

    def verdict(self, model: Model, state: State, reference: float) -> str:
        """The trend's reason once it decides ("" until then), read at a record step."""
        if state.step < model.loads_applied_step:
            return ""
        if self.start < 0 or state.step - self.start >= self.window:
            moved = float(np.max(np.hypot(*(state.world - self.world).T), initial=0.0))
            decided = (
                self.trend.observe(
                    moved,
                    largest_centroid_displacement(model, state),
                    mon.unbalanced_force_ratio(state, reference),
                )
                if self.start >= 0
                else None
            )
            self.start, self.world = state.step, state.world.copy()
            if decided is not None:
                return decided[1]
        return ""


def moved_beyond_stop(model: Model, state: State) -> bool:
    """True once a block that can move (free, or driven at a velocity) has moved further than the
    stop's displacement_m from its start (its centroid's displacement)."""
    stop = model.scene.solver.stop
    if stop is None or stop.displacement_m is None:
        return False
    return largest_centroid_displacement(model, state) > stop.displacement_m


def largest_centroid_displacement(model: Model, state: State) -> float:
    """How far the centroid of a block that can move has moved from its start, at most [m]."""
    b = state.blocks[~state.immobile]
    return float(np.max(np.hypot(b[:, L.X] - b[:, L.X0], b[:, L.Y] - b[:, L.Y0]), initial=0.0))


def stop_reason(model: Model, state: State, reference: float) -> str:
    """Which stop condition holds now ("" for none); equilibrium counts only once the loads act in
    full, since a slowly ramped load is in near balance all along its ramp."""
    stop = model.scene.solver.stop
    if stop is None:
        return ""
    if moved_beyond_stop(model, state):
        return "displacement"
    if stop.time_s is not None and state.clock[L.TIME] >= stop.time_s:
        return "time"
    if (
        stop.unbalanced_force_ratio is not None
        and state.step >= model.loads_applied_step
        and mon.unbalanced_force_ratio(state, reference) < stop.unbalanced_force_ratio
    ):
        return "equilibrium"
    return ""


UNSETTLED_MULTIPLE = 10.0  # a run that ends above this x its stop's unbalanced-force ratio is unsettled
ROUND_OFF_MOTION = 1e-12  # kinetic energy below the reference force over this x the median block size:
# motion at round-off (a closure of 1e-13 m under a 100 m block leaves a ratio of 5e-3 and 2e-16 J)


def far_from_balance(model: Model, state: State, reference: float) -> bool:
    """Whether a run that used all its steps ended far from its stop's equilibrium: its unbalanced-force
    ratio above UNSETTLED_MULTIPLE x the stop's, and its blocks moving above round-off."""
    stop = model.scene.solver.stop
    if stop is None or stop.unbalanced_force_ratio is None:
        return False
    ratio = mon.unbalanced_force_ratio(state, reference)
    unbalanced = ratio > UNSETTLED_MULTIPLE * stop.unbalanced_force_ratio
    size = float(np.median(state.blocks[:, L.SIZE]))
    return unbalanced and mon.kinetic_energy(state.blocks) > ROUND_OFF_MOTION * reference * size


def unsettled(model: Model, state: State, reference: float, energy_before: float) -> str:
    """The one line for a run that used all its steps without meeting its stop: what still moves, and
    whether its kinetic energy rose over the last record interval."""
    speed = np.hypot(state.blocks[:, L.VX], state.blocks[:, L.VY])
    fastest = int(np.argmax(np.where(state.immobile, -1.0, speed)))
    energy = mon.kinetic_energy(state.blocks)
    return (
        f"step {state.step}: solver.steps ran out before the stop was met: unbalanced-force ratio "
        f"{mon.unbalanced_force_ratio(state, reference):.3g}, kinetic energy {energy:.3g} J per m, "
        f"{'rising' if energy > energy_before else 'falling'}; block '{model.block_names[fastest]}' moves "
        f"at {speed[fastest]:.3g} m/s. Blocks that keep moving are failing (bbmc fos gives the factor of "
        "safety); a slope still settling needs more steps"
    )


def no_equilibrium(
    model: Model,
    state: State,
    start_world: np.ndarray,
    reason: str,
    limit: float,
    reference: float,
) -> str:
    """Why even the elastic start of `bbmc fos` (`bbmc.dem.strength_reduction`) finds no equilibrium,
    naming the block whose vertex moved most (how far, how fast): a block that moved the failure
    displacement has nothing holding it (its geometry is at fault, however many steps); one still moving
    when solver.steps ran out may only need more; `limit` is the fos's unbalanced-force ratio [1]."""
    moved = np.hypot(*(state.world - start_world).T)
    block = int(model.vertex_block[np.argmax(moved)])
    name, distance = model.block_names[block], float(moved.max()) / units.mm
    speed = float(np.hypot(state.blocks[block, L.VX], state.blocks[block, L.VY]))
    where = f"block '{name}' moved {distance:.3g} mm and moves at {speed:.3g} m/s after {state.step} steps"
    if reason == "displacement":
        return (
            f"key 'blocks': no equilibrium even with every strength x 1e6 (elastic): {where}: nothing holds "
            "it (more solver.steps will not help): give it a block or a held side to rest on, or fix it"
        )
    return (
        f"key 'solver.steps': no equilibrium even with every strength x 1e6 (elastic) in {state.step} steps: "
        f"the unbalanced-force ratio is {mon.unbalanced_force_ratio(state, reference):.3g} (limit "
        f"{limit:g}); {where}: raise solver.steps if it is still settling, else "
        "give it support or fix it"
    )
