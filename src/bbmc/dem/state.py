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
    """The engine's mutable arrays (see `layout` for their columns)."""

    clock: np.ndarray
    blocks: np.ndarray
    dof: np.ndarray
    world: np.ndarray
    contacts: np.ndarray
    subs: np.ndarray
    law_state: np.ndarray  # the sub-contacts' law state (`layout.LAW_STATE_COLUMNS`), rows as `subs`
    n_sub: int
    immobile: np.ndarray  # blocks held still for the whole run (`Model.immobile`)
    moving: np.ndarray  # blocks whose motion the cycle computes (all, unless held ones are skipped)
    dry_edges: np.ndarray  # edges of intact rock that joint water does not reach (until it breaks)
    support: np.ndarray  # the support elements' rows (`layout`'s support columns), forces and state
    largest_dt: float = math.inf  # the time step's upper limit (`largest_time_step`), set once
    threads: int = 1  # numba threads of the cycle (`kernels.thread_count`)
    # each contact's force and moments, and each block's contacts (`kernels.block_contacts_of`): the
    # threaded cycle's assembly, set at each contact search when threaded
    per_contact: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    block_start: np.ndarray = field(default_factory=lambda: np.zeros(1, dtype=np.int64))
    block_contacts: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    searches: int = 0
    dt_range: list[float] = field(default_factory=lambda: [math.inf, 0.0])
    largest_overlap: float = 0.0
    # the sizes of kernel calls (shared by copies of a state: they measure the machine, not the state)
    cycle_pace: Pace = field(default_factory=Pace)
    search_pace: Pace = field(default_factory=Pace)

    @property
    def step(self) -> int:
        return int(self.clock[L.STEP])
