"""The time step: a lower bound of the critical step from the assembled contact stiffness.

Gershgorin row sums of the stiffness of every share's spring bed (`stiffness_row_sums`) bound the
largest squared frequency; the step is a safety factor times 2 / sqrt((1 + damping) lambda_max), or a
fixed step with density scaling (`scale_masses`). Units: s, Pa/m, kg.
"""

import math

import numba
import numpy as np

from bbmc.dem.contact_geometry import contact_frame, share_middle
from bbmc.dem.layout import (
    BLOCK_A,
    BLOCK_B,
    DONE,
    DT,
    EDGE_A,
    EDGE_B,
    INERTIA,
    KN,
    KS,
    MASS,
    MW,
    MX,
    MY,
    NO_BOUND,
    PRESCRIBED,
    SIZE,
    STEP_ABOVE_CRITICAL,
    X,
    Y,
)


@numba.njit(cache=True)
def stiffness_row_sums(blocks, dof, world, vertex_next, contacts, subs, n_sub, symmetric, rows):
    """Gershgorin row sums of the assembled contact stiffness, per block and degree of freedom.

    Each share of an active contact (open or closed: it may close before the next evaluation) adds, for
    its normal (K_n) and shear (K_s) direction d, the rank-one stiffness k g g^T with k = K L (L the
    share's length) and g = (-d, -r_A x d | d, r_B x d) at the share's middle, and for the normal
    stress's first moment the rotational stiffness K_n L^3 / 12 with g = (0, 0, 1 | 0, 0, -1): together
    the exact stiffness of a uniform spring bed along the share. `symmetric`: rows of M^-1/2 K M^-1/2
    (their maximum bounds the largest squared frequency); else rows of |K| itself (used to choose
    scaled masses). Prescribed degrees of freedom are left out.
    """
    rows[:] = 0.0
    size = blocks[:, SIZE]
    scale_a = np.zeros(3)
    scale_b = np.zeros(3)
    ga = np.zeros(3)
    gb = np.zeros(3)
    for c in range(contacts.shape[0]):
        a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
        active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi = contact_frame(
            world, vertex_next, contacts[c, EDGE_A], contacts[c, EDGE_B], size, a, b
        )
        if not active:
            continue
        for d in range(3):
            scale_a[d] = _row_scale(blocks, dof, a, d, symmetric)
            scale_b[d] = _row_scale(blocks, dof, b, d, symmetric)
        length = (hi - lo) / n_sub
        tx, ty = -ny, nx
        for k in range(n_sub):
            s = c * n_sub + k
            f = share_middle(k, n_sub)
            along = lo + f * (hi - lo)
            middle = 0.5 * (a_lo + f * (a_hi - a_lo) + b_lo + f * (b_hi - b_lo))
            cx, cy = along * tx + middle * nx, along * ty + middle * ny
            rax, ray = cx - blocks[a, X], cy - blocks[a, Y]
            rbx, rby = cx - blocks[b, X], cy - blocks[b, Y]
            for dx, dy, k_d in ((nx, ny, subs[s, KN] * length), (tx, ty, subs[s, KS] * length)):
                ga[0], ga[1], ga[2] = -dx, -dy, -(rax * dy - ray * dx)
                gb[0], gb[1], gb[2] = dx, dy, rbx * dy - rby * dx
                _add_rank_one(rows, a, b, ga, gb, scale_a, scale_b, k_d)
            ga[0], ga[1], ga[2] = 0.0, 0.0, 1.0
            gb[0], gb[1], gb[2] = 0.0, 0.0, -1.0
            _add_rank_one(rows, a, b, ga, gb, scale_a, scale_b, subs[s, KN] * length**3 / 12.0)


@numba.njit(cache=True)
def _add_rank_one(rows, a, b, ga, gb, scale_a, scale_b, k):
    """Add the absolute row sums of the scaled rank-one stiffness k g g^T (g = (ga | gb)) to rows."""
    total = 0.0
    for d in range(3):
        total += abs(ga[d]) * scale_a[d] + abs(gb[d]) * scale_b[d]
    for d in range(3):
        rows[a, d] += k * abs(ga[d]) * scale_a[d] * total
        rows[b, d] += k * abs(gb[d]) * scale_b[d] * total


@numba.njit(cache=True)
def _row_scale(blocks, dof, i, d, symmetric):
    if dof[i, d] == PRESCRIBED:
        return 0.0
    if symmetric:
        return 1.0 / math.sqrt(blocks[i, MX + d])
    return 1.0


@numba.njit(cache=True)
def critical_time_step(blocks, dof, world, vertex_next, contacts, subs, n_sub, damping):
    """Lower bound of the critical step, 2 / sqrt((1 + damping) lambda_max) [s] (Gershgorin bound on
    lambda_max); +inf when nothing is in contact. Local damping adds damping x |F| to the force while a
    block decelerates, so it acts as a (1 + damping)-fold stiffness there: without that factor a step
    just below the undamped limit diverges (measured at damping 0.8: 0.76 of 2 / sqrt(lambda_max))."""
    rows = np.zeros((blocks.shape[0], 3))
    stiffness_row_sums(blocks, dof, world, vertex_next, contacts, subs, n_sub, True, rows)
    largest = rows.max() if rows.size else 0.0
    if largest <= 0.0:
        return math.inf
    return 2.0 / math.sqrt((1.0 + damping) * largest)


@numba.njit(cache=True)
def scale_masses(blocks, dof, world, vertex_next, contacts, subs, n_sub, dt, safety, damping):
    """Density scaling: raise each degree of freedom's inertial mass to (1 + damping) |K| row sum
    (dt / 2 safety)^2, never below the true mass, so that `dt` is `safety` times a lower bound of the
    critical step (`critical_time_step`)."""
    rows = np.zeros((blocks.shape[0], 3))
    stiffness_row_sums(blocks, dof, world, vertex_next, contacts, subs, n_sub, False, rows)
    factor = (1.0 + damping) * (dt / (2.0 * safety)) ** 2
    for i in range(blocks.shape[0]):
        blocks[i, MX] = max(blocks[i, MASS], rows[i, 0] * factor)
        blocks[i, MY] = max(blocks[i, MASS], rows[i, 1] * factor)
        blocks[i, MW] = max(blocks[i, INERTIA], rows[i, 2] * factor)


@numba.njit(cache=True)
def set_time_step(
    clock, blocks, dof, world, vertex_next, contacts, subs, n_sub, mode, safety, fixed_dt, damping
):
    """Set clock[DT] for the current stiffnesses (see `cycle` for the modes); returns a status code:
    NO_BOUND, with clock[DT] left as it was, when nothing is in contact and no step_s bounds the
    automatic step (blocks in free flight keep the last step)."""
    if mode == 2:
        scale_masses(blocks, dof, world, vertex_next, contacts, subs, n_sub, fixed_dt, safety, damping)
        clock[DT] = fixed_dt
        return DONE
    critical = critical_time_step(blocks, dof, world, vertex_next, contacts, subs, n_sub, damping)
    if mode == 1:
        clock[DT] = fixed_dt
        return STEP_ABOVE_CRITICAL if fixed_dt > critical else DONE
    step = min(safety * critical, fixed_dt)
    if step == math.inf:  # (a NaN stiffness is no free flight: it is left to the health check)
        return NO_BOUND
    clock[DT] = step
    return DONE
