"""A strength-reduction trial on a soft support, its strength reduced gradually rather than at once.

A block of mass m whose support (stiffness k) must take up a load step at once, with Cundall's local
damping alpha (the force cut by alpha |F| while the block speeds up, raised by alpha |F| while it
slows), gains (1 - alpha) k u_e^2 / 2 of kinetic energy on its way to its equilibrium u_e and loses it
at (1 + alpha) k x^2 / 2 beyond it: it overshoots by x = u_e sqrt((1 - alpha) / (1 + alpha)), u_e / 3
at the default alpha 0.8, and sticks there (friction holds it on the far side). A trial whose
equilibrium on the support lies at 3/4 of the failure displacement is then carried past it by the
sudden reduction alone (measured on the soft bolt of docs/verification.md: F = 0.97, u_e 182 mm, the
block stops at 230 mm), though the rule (the support's force at the failure displacement holds the
block) calls it stable; a stiff support takes its load within a fraction of a millimetre, where no
overshoot counts.

Reduced instead linearly from the factor at which the start state's first joint slips (`hold_factor`)
to the trial's factor over `RAMP_PERIODS` natural periods T of the block on its support, the load on
the support grows at a constant rate over t_r = RAMP_PERIODS T, and an undamped spring so loaded ends
the ramp oscillating about its equilibrium with an amplitude u_e (T / (pi t_r)) |sin(pi t_r / T)|
(the ramp response, e.g. Clough & Penzien, Dynamics of Structures, ch. 4): none for a whole number of
periods, and at most u_e / (2 pi) for any t_r >= 2 T; damping only lowers it. Measured: every trial of
that bolt between F 0.93 and 0.99 comes to rest within 0.1 mm of its equilibrium. Only the
`envelope` reduction is spread (`phi_b_jrc` re-evaluates the joints' laws at a trial's start, so it
is applied at once there).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.dem.solver import advance
from bbmc.dem.state import State

RAMP_PERIODS = 2  # whole natural periods of the block on its support the reduction is spread over


def hold_factor(subs: np.ndarray, n_sub: int) -> float:
    """The largest factor F at which every contact still holds its shear force [1]: min over the contacts
    of sum(max(c + sigma_n tan phi, 0) l) / |sum(tau l)| over its closed shares (l their closed length;
    `contact_forces._shear_share`'s strength before its divisor); inf where none carries shear. A contact,
    not a share: the stresses along a joint vary with the moment it carries, and the shares redistribute
    their shear as the first slip (measured: the block's top share slips at 0.19, the joint at 0.82)."""
    closed = np.where(subs[:, L.SN] > 0.0, subs[:, L.LENGTH] * subs[:, L.CLOSED], 0.0)
    strength = np.maximum(subs[:, L.COH] + subs[:, L.SN] * subs[:, L.TANPHI], 0.0) * closed
    shear = np.abs((subs[:, L.TAU] * closed).reshape(-1, n_sub).sum(axis=1))
    held = strength.reshape(-1, n_sub).sum(axis=1)
    carrying = shear > 0.0
    return float(np.min(held[carrying] / shear[carrying], initial=np.inf))


def ramp(
    model_at: Callable[[float], Model],
    state: State,
    factor: float,
    steps: int,
    every: int,
    beyond: Callable[[State], bool],
) -> bool:
    """Advance `state` through a reduction from `hold_factor` to `factor` spread over `steps` steps, the
    factor raised every `every` steps (`model_at` gives the scene reduced by a factor); True as soon as
    `beyond` holds (the block has moved its failure displacement), else False at the ramp's end (at
    once where the start state holds at `factor`)."""
    start = hold_factor(state.subs, state.n_sub)
    if start >= factor:  # it holds at the trial's factor already: nothing to spread
        return False
    increments = max(1, steps // every)
    for j in range(1, increments + 1):
        advance(model_at(start + (factor - start) * j / increments), state, every)
        if beyond(state):
            return True
    return False
