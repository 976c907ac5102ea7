"""One explicit cycle of the 2D rigid-block DEM (a "step", as in UDEC), in numba over flat arrays.

A cycle is: loads (gravity, edge stresses, block forces, water; `bbmc.dem.motion`, `bbmc.dem.water`),
contact forces from the current positions and the last half-step velocities (`bbmc.dem.contact_forces`
over the common lines of `bbmc.dem.contact_geometry`), then the central-difference update of velocities
(with Cundall's local damping) and positions (`bbmc.dem.motion`). Every `update_interval` cycles the
stress-dependent joint laws are re-evaluated at each sub-contact from its own stresses
(`bbmc.dem.joint_state`), and the time step is recomputed (`bbmc.dem.time_step`). `docs/architecture.md`
follows one step through these modules.
"""

import math

import numba
import numpy as np

from bbmc.dem.contact_forces import contact_forces
from bbmc.dem.joint_state import break_bridges, stresses_moved, update_joint_laws
from bbmc.dem.layout import (
    BLOCK_A,
    BLOCK_B,
    DONE,
    DT,
    SEARCH_NEEDED,
    SINCE_UPDATE,
    STEP,
    STEP_ABOVE_CRITICAL,
    TIME,
)
from bbmc.dem.motion import apply_loads, move_blocks
from bbmc.dem.support import support_forces
from bbmc.dem.time_step import set_time_step
from bbmc.dem.water import add_water_loads
from bbmc.incidence import block_contacts

THREADED_FROM_CONTACTS = 2000  # fewer contacts: one thread (a parallel loop's start costs more than
# the step of a small scene; the result is the same to the bit either way)
_thread_limit = numba.config.NUMBA_NUM_THREADS


def limit_threads(threads: int) -> None:
    """Run every later run of this process on at most `threads` threads (a sweep's worker processes:
    one each, the sweep itself running one per core)."""
    global _thread_limit
    _thread_limit = max(1, min(threads, numba.config.NUMBA_NUM_THREADS))


def thread_count(requested: int | None) -> int:
    """The threads a run uses: `requested` (the scene's `threads`; None: every core), at most the
    process's limit (`limit_threads`) and numba's pool."""
    return min(requested or numba.config.NUMBA_NUM_THREADS, _thread_limit)


def set_threads(threads: int) -> None:
    """Numba's parallel loops from now on run on `threads` threads (a runtime setting: one compiled
    kernel serves every count)."""
    numba.set_num_threads(threads)


def block_contacts_of(contacts: np.ndarray, n_blocks: int) -> tuple[np.ndarray, np.ndarray]:
    """Each block's contacts in contact order, as CSR (`bbmc.incidence.block_contacts`: c >= 0 for
    contact c with the block as B, -1 - c with it as A; the order `add_contact_sums` adds them in)."""
    return block_contacts(contacts[:, BLOCK_A], contacts[:, BLOCK_B], n_blocks)


@numba.njit(cache=True)
def cycle(
    n_steps,
    clock,
    blocks,
    dof,
    vertex_start,
    vertex_block,
    vertex_next,
    local,
    world,
    contacts,
    subs,
    law_state,
    n_sub,
    laws,
    params,
    variable_laws,
    update_interval,
    stress_change,
    changed_laws_only,
    moving,
    gravity,
    block_loads,
    load_block,
    edge_loads,
    load_edge,
    water_surface,
    water_unit_weight,
    dry_edges,
    bridges,
    support_blocks,
    support,
    support_divisor,
    damping,
    search_distance,
    time_step_mode,
    safety,
    fixed_dt,
    threaded,
    per_contact,
    block_start,
    block_contacts,
):
    """Run up to n_steps cycles. Returns (cycles done, DONE | SEARCH_NEEDED | STEP_ABOVE_CRITICAL).

    Water pressure (`water_surface`, `water_unit_weight`; `bbmc.dem.water`) is added to the loads, on
    every edge but the `dry_edges` of intact rock; with `bridges` (the scene has intact rock that breaks
    into a joint) each step ends with `break_bridges`. The `support` elements (anchors, grouted-bolt
    crossings; `bbmc.dem.support`) pull on their blocks before the contact forces, with the part along
    their joint divided by `support_divisor` (1 but in a strength reduction of the support).
    time_step_mode: 0 automatic (safety x critical, recomputed after each law update), 1 fixed (the
    run stops with STEP_ABOVE_CRITICAL once the fixed step exceeds the critical one), 2 density
    scaling (fixed step, inertial masses rescaled after each law update). The laws are updated every
    `update_interval` cycles, and sooner once `stresses_moved` by `stress_change` (inf: never sooner).
    `changed_laws_only` and `moving`: see `update_joint_laws` and `move_blocks`.
    `threaded`: contact forces, motion and vertices on every thread of numba's pool (`contact_forces`
    into `per_contact`, then `move_blocks` with `block_start` and `block_contacts`), else on this one;
    the result is the same to the bit.
    """
    for done in range(n_steps):
        due = clock[SINCE_UPDATE] >= update_interval
        if variable_laws and not due and stress_change < math.inf:
            due = stresses_moved(contacts, subs, law_state, n_sub, laws, params, stress_change)
        if variable_laws and due:
            update_joint_laws(contacts, subs, law_state, n_sub, laws, params, changed_laws_only)
            clock[SINCE_UPDATE] = 0.0
            status = set_time_step(
                clock,
                blocks,
                dof,
                world,
                vertex_next,
                contacts,
                subs,
                n_sub,
                time_step_mode,
                safety,
                fixed_dt,
                damping,
            )
            if status == STEP_ABOVE_CRITICAL:
                return done, status
        dt = clock[DT]
        apply_loads(
            blocks,
            world,
            vertex_next,
            vertex_block,
            gravity,
            block_loads,
            load_block,
            edge_loads,
            load_edge,
            clock[STEP],
        )
        if water_unit_weight != 0.0:  # a call passes its arrays' references: 0.1 us a step on the shear box
            add_water_loads(
                blocks, world, vertex_start, vertex_next, moving, water_surface, water_unit_weight, dry_edges
            )
        if support.shape[0]:
            support_forces(blocks, support_blocks, support, support_divisor)
        contact_forces(
            blocks,
            world,
            vertex_next,
            contacts,
            subs,
            law_state,
            n_sub,
            laws,
            params,
            dt,
            threaded,
            per_contact,
        )
        if bridges:
            break_bridges(contacts, subs, law_state, n_sub, laws, params, dry_edges)
        moved = move_blocks(
            blocks,
            dof,
            damping,
            dt,
            clock[STEP],
            moving,
            vertex_start,
            local,
            world,
            threaded,
            per_contact,
            block_start,
            block_contacts,
        )
        clock[STEP] += 1.0
        clock[TIME] += dt
        clock[SINCE_UPDATE] += 1.0
        if moved > 0.5 * search_distance:
            return done + 1, SEARCH_NEEDED
    return n_steps, DONE
