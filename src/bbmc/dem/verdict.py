"""Whether a run is coming to rest or failing, judged by the trend of its motion rather than by
whether it settled within a step budget.

A run near its limit creeps: it may need a million steps to reach a small unbalanced-force ratio
although it is plainly slowing down, or move at a steady rate that no budget tells from slow
settling. `Trend` watches the largest distance any vertex moved in each window of steps, d_k. The
first window is the transient of whatever started the run and is left out; over the last
`FIT_WINDOWS` windows a least-squares line through ln d_k gives the decay ratio per window, r. A
damped system coming to rest decays about geometrically, so its blocks will move at most
d_k r / (1 - r) more (the projected remainder). Then, each in `CONFIRMATIONS` successive windows:

* *decaying* (stable): r <= `STABLE_RATIO`, the projected remainder is below `SETTLED_FRACTION`
  of the failure displacement and the unbalanced-force ratio is below `UNBALANCE_MULTIPLE` times its
  limit: the run is coming to rest, well short of failing, its forces nearly balanced (a joint that
  softens after its peak can pause after a first slip, its blocks decelerating while its forces are
  far from balance, and then fail: the ratio tells that pause from rest);
* *creep* (unstable): r >= 1, the motion is not slowing (a steady creep at constant velocity is a
  failure), unless it is at rest: a window's largest movement below `RESTING_FRACTION` of the failure
  displacement (a creep that would need a million windows to fail is contact chatter: measured on a
  slope whose trial at F = 1.25 moved 3e-8 m per window, 1e-7 of its failure displacement, and was
  called creep, though a perturbation of 4e-8 of its block properties called it at rest);
* *projected* (unstable): r < 1 and the displacement so far plus the projected remainder exceeds the
  failure displacement (a run at rest with r >= 1 projects no remainder: it is chatter, not a failure;
  measured on issue 36's lift-off wedge, whose trials moving 2e-6 m of a 7 m failure displacement were
  called projected, FS -5.3 %).

A trend between (STABLE_RATIO < r < 1, coming to rest too slowly to tell) decides nothing until
`DECIDING_WINDOWS` windows after the first have been seen; then the fit over the last `FIT_WINDOWS`
decides alone: *decaying* if r <= `DECIDING_RATIO` and the projection stays short of the failure
displacement (or the motion is at rest), else *creep*. So the verdict never waits for a step
budget: a run given 1 + 8 windows or more gets the same verdict whatever its budget. Confirmations
keep a window of knocking blocks from deciding.

On a soft support (`approach`: the support's natural period, not the equilibrium's steps, sets the
windows) a block creeps towards its equilibrium on the support: the support's force grows with the
displacement u, k (u_e - u) drives the block and the damping (Cundall's, fed by the contacts'
chatter) drags it, so each window moves about a fixed fraction of what is left, d_k = (1 - r)
(u_e - u_k), with r near 0.9 per natural period (measured), and u_e = u_k + d_k r / (1 - r) is where
it comes to rest. There the decision at `DECIDING_WINDOWS` is that projection's alone: *decaying*
for any r < 1 whose projected resting place stays within the failure displacement, else *projected*
(r < 1) or *creep*. It cannot hold a failing block: one whose equilibrium lies beyond the failure
displacement projects beyond it, and one not slowing (r >= 1) projects no rest at all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

FIT_WINDOWS = 4  # windows the decay ratio is fitted over
CONFIRMATIONS = 2  # successive windows that must agree
STABLE_RATIO = 0.8  # largest decay ratio per window of a run called coming to rest
SETTLED_FRACTION = 0.01  # its projected further movement, as a fraction of the failure displacement
UNBALANCE_MULTIPLE = 100.0  # and its unbalanced-force ratio at most this times the ratio's limit
DECIDING_WINDOWS = 8  # windows after the first by which an undecided trend decides alone
DECIDING_RATIO = 0.9  # the largest decay ratio per window then called coming to rest
RESTING_FRACTION = 1e-6  # a window's largest movement below this x the failure displacement: at rest
STABLE, UNSTABLE = "stable", "unstable"


@dataclass
class Trend:
    """The verdict of a run from the largest vertex movement in each of its windows (module docstring)."""

    failure_displacement: float  # [m]
    unbalance_limit: float  # the unbalanced-force ratio that means equilibrium [1]
    approach: bool = False  # a block approaching its equilibrium on a soft support (module docstring)
    moves: list[float] = field(default_factory=list)  # largest vertex movement in each window [m]
    leaning: str = ""  # the verdict the last window leaned to
    agreeing: int = 0  # successive windows that leaned to it

    def decay_ratio(self) -> float:
        """r per window, fitted over the last FIT_WINDOWS windows [1] (0 once the motion stopped)."""
        last = np.array(self.moves[-FIT_WINDOWS:])
        if last[-1] <= 0.0:
            return 0.0
        if np.any(last <= 0.0):
            return math.inf
        return float(np.exp(np.polyfit(np.arange(FIT_WINDOWS), np.log(last), 1)[0]))

    def projected_remainder(self) -> float:
        """How much further the blocks will move if the decay goes on as fitted [m] (inf if none)."""
        r = self.decay_ratio()
        return self.moves[-1] * r / (1.0 - r) if r < 1.0 else math.inf

    def observe(
        self, moved_in_window: float, moved_so_far: float, unbalance: float
    ) -> tuple[str, str] | None:
        """Add one window's largest movement [m], the largest displacement so far [m] and the
        unbalanced-force ratio now [1]; returns (STABLE | UNSTABLE, reason) once the trend decides,
        else None."""
        self.moves.append(moved_in_window)
        if len(self.moves) <= FIT_WINDOWS:  # the first window is left out
            return None
        r, remainder = self.decay_ratio(), self.projected_remainder()
        resting = moved_in_window < RESTING_FRACTION * self.failure_displacement
        balanced = unbalance < UNBALANCE_MULTIPLE * self.unbalance_limit
        if r <= STABLE_RATIO and remainder < SETTLED_FRACTION * self.failure_displacement and balanced:
            leaning = "decaying"
        elif r >= 1.0 and not resting:
            leaning = "creep"
        elif r < 1.0 and moved_so_far + remainder > self.failure_displacement:
            leaning = "projected"
        else:
            leaning = ""
        self.agreeing = self.agreeing + 1 if leaning and leaning == self.leaning else int(bool(leaning))
        self.leaning = leaning
        if self.agreeing >= CONFIRMATIONS:
            return (STABLE if leaning == "decaying" else UNSTABLE), leaning
        if len(self.moves) > DECIDING_WINDOWS:
            deciding = 1.0 if self.approach else DECIDING_RATIO
            within = moved_so_far + remainder <= self.failure_displacement
            if resting or (r <= deciding and r < 1.0 and within):
                return STABLE, "decaying"
            return UNSTABLE, "projected" if self.approach and r < 1.0 else "creep"
        return None
