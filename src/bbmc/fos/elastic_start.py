"""Why the elastic start of `bbmc fos` (every strength x 1e6) finds no equilibrium: the one line that
names the block at fault and what to do about it."""

from __future__ import annotations

import numpy as np

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem import monitors as mon
from bbmc.dem.model import Model
from bbmc.dem.state import State


def no_equilibrium(
    model: Model,
    state: State,
    start_world: np.ndarray,
    reason: str,
    limit: float,
    reference: float,
) -> str:
    """Why even the elastic start of `bbmc fos` (`bbmc.fos.strength_reduction`) finds no equilibrium,
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
