"""The engine's mutable state during a run: the arrays the kernels advance and the run's bookkeeping.

Its own module, below the run loop (`solver`) and the parts it calls (`contact_search`, `stopping`), so
each of them can take the type without importing the others.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from bbmc.dem import layout as L
from bbmc.dem.pace import Pace


@dataclass
class State:
    """The engine's mutable arrays, SI throughout (`bbmc.dem.layout` names their columns); a run's
    last state is `RunResult.state`.

    Attributes:
        clock: the step count, time [s], time step [s] and the time-step bookkeeping (`layout`'s clock
            entries: `step` reads the step).
        blocks: one row per block: centroid x, y [m], rotation [rad], velocities [m/s, rad/s], size
            [m], out-of-balance force [N] and moment [N m], mass [kg] and moment of inertia [kg m²],
            start position [m] ... (forces and masses per metre of thickness: plane strain).
        dof: per block and degree of freedom (x, y, rotation), free or prescribed.
        world: every vertex now, (vertices, 2) [m], in the scene's block order.
        contacts: one row per contact: its two blocks, edges, joint type (law).
        subs: one row per sub-contact (n_sub per contact): place [m], length [m], stresses [Pa],
            stiffnesses [Pa/m], strength, displacements [m], slip state.
        law_state: the sub-contacts' joint-law state (`layout.LAW_STATE_COLUMNS`), rows as `subs`.
        n_sub: sub-contacts per contact.
        immobile: per block, held still for the whole run (`Model.immobile`).
        moving: per block, whether the cycle computes its motion (all, unless held ones are skipped).
        dry_edges: per edge, intact rock that joint water does not reach (until it breaks).
        support: the support elements' rows (`layout`'s support columns): forces [N], state.
        largest_dt: the time step's upper limit [s] (`largest_time_step`), set once.
        threads: numba threads of the cycle (`kernels.thread_count`).
        per_contact: each contact's force and moments, the threaded cycle's assembly (set at each
            contact search when threaded).
        block_start: where each block's contacts start in `block_contacts`.
        block_contacts: each block's contacts (`kernels.block_contacts_of`).
        searches: contact searches so far.
        dt_range: the smallest and largest time step used [s].
        largest_overlap: the deepest interpenetration seen, a fraction of the smaller block's size.
        cycle_pace: the sizes of kernel calls (shared by copies of a state: they measure the
            machine, not the state).
        search_pace: the same for the contact search.
    """

    clock: np.ndarray
    blocks: np.ndarray
    dof: np.ndarray
    world: np.ndarray
    contacts: np.ndarray
    subs: np.ndarray
    law_state: np.ndarray
    n_sub: int
    immobile: np.ndarray
    moving: np.ndarray
    dry_edges: np.ndarray
    support: np.ndarray
    largest_dt: float = math.inf
    threads: int = 1
    per_contact: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    block_start: np.ndarray = field(default_factory=lambda: np.zeros(1, dtype=np.int64))
    block_contacts: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    searches: int = 0
    dt_range: list[float] = field(default_factory=lambda: [math.inf, 0.0])
    largest_overlap: float = 0.0
    cycle_pace: Pace = field(default_factory=Pace)
    search_pace: Pace = field(default_factory=Pace)

    @property
    def step(self) -> int:
        """The step count [1]."""
        return int(self.clock[L.STEP])
