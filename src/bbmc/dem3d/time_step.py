"""The 3D time step: a lower bound of the critical step from each block's summed contact stiffness.

As the 2D engine (`bbmc.dem.time_step`): the step is a safety factor (the scene's, 0.5 by default) times
2 / sqrt((1 + damping) lambda_max), lambda_max bounding the largest squared frequency, or a fixed step
with density scaling (`scale_masses`). Here lambda_max is bounded block by block from two sums over the
block's contacts (`contact_stiffness`): k_t, bounding the translational stiffness's largest eigenvalue
[N/m], and k_r, bounding the rotational stiffness's about the centroid [N m/rad]. For a positive
semi-definite stiffness [[A, B], [B^T, C]], lambda_max <= lambda_max(A) + lambda_max(C) (Cauchy-Schwarz on
u^T B w), so the mass-normalised bound is k_t / M + k_r / J_min; it is doubled for the neighbour
across each contact, which moves against the block (two equal free blocks on a spring k: omega^2 = 2 k /
m; a block against a held one is then bounded with a step sqrt(2) too short). A neighbour much lighter
than the block is not covered: the safety factor is there for it.

Only the free degrees of freedom move, so M and J_min are of those (`_free_moment`): M the least
inertial mass of a free translation, J_min the least eigenvalue of the world inertia R diag(J) R^T
restricted to the free rotation axes (of the blocks as they stand; by Cauchy's interlacing it is at
least the least principal moment). A plane-strain twin, free about y alone, takes its step from its
moment about y, as the 2D engine from the block's polar moment; from the least principal moment a thin
twin's step was 2.4 x shorter. Units: s, kg, kg m^2, N/m, N m/rad.
"""

import math

import numba

from bbmc.dem3d.layout import I1, J1, MASS, MX, PRESCRIBED, QW
from bbmc.dem3d.quaternion import rotate

NEIGHBOUR = 2.0  # the neighbour across a contact moves against the block: omega^2 = 2 k / m for equals


@numba.njit(cache=True)
def contact_stiffness(kn, ks, area, polar_moment, lever, normal):
    """Bounds of one contact patch's stiffness on one block: (k_t [N/m], k_r [N m/rad]).

    The patch is a uniform spring bed, normal stiffness kn and shear stiffness ks [Pa/m], of area A
    [m^2] and polar second moment J_p about its own centroid [m^4], whose centroid is at `lever` (3,)
    from the block's centroid [m], with unit normal `normal` (3,). A translation u stores kn (n.u)^2 +
    ks |u_t|^2 per unit area, so k_t = max(kn, ks) A. A rotation theta moves the point at r by theta x r,
    whose normal part is theta . (r x n); with kn >= ks the energy density is ks |u|^2 + (kn - ks)
    (n.u)^2, and integrating |r|^2 and |r x n|^2 over the patch (its first moment about its centroid is
    zero) gives k_r = ks (A |r0|^2 + J_p) + max(kn - ks, 0) (A |r0 x n|^2 + J_p). On a block resting on a
    face (r0 along n, lever h) that is kn J_p + ks A h^2: the face's rocking stiffness kn J_a (J_a the
    second moment about the rocking axis, <= J_p <= 2 max J_a) plus the shear springs' lever.
    """
    k_translation = max(kn, ks) * area
    r2 = lever[0] ** 2 + lever[1] ** 2 + lever[2] ** 2
    c0 = lever[1] * normal[2] - lever[2] * normal[1]
    c1 = lever[2] * normal[0] - lever[0] * normal[2]
    c2 = lever[0] * normal[1] - lever[1] * normal[0]
    k_rotation = ks * (area * r2 + polar_moment) + max(kn - ks, 0.0) * (
        area * (c0 * c0 + c1 * c1 + c2 * c2) + polar_moment
    )
    return k_translation, k_rotation


@numba.njit(cache=True)
def _free_moment(blocks, dof, i):
    """The least inertial moment of block i about its free rotation axes [kg m^2]: the least eigenvalue
    of J_w = R diag(J) R^T (J the inertial principal moments J1..) restricted to the free world axes;
    +inf with none free."""
    free = [r for r in range(3) if dof[i, 3 + r] != PRESCRIBED]
    if len(free) == 3:
        return min(blocks[i, J1], blocks[i, J1 + 1], blocks[i, J1 + 2])
    if len(free) == 0:
        return math.inf
    q0, q1, q2, q3 = blocks[i, QW], blocks[i, QW + 1], blocks[i, QW + 2], blocks[i, QW + 3]
    columns = [rotate(q0, q1, q2, q3, 1.0 if k == 0 else 0.0, 1.0 if k == 1 else 0.0, 1.0 if k == 2 else 0.0)
               for k in range(3)]  # fmt: skip
    a, b, c = 0.0, 0.0, 0.0  # J_w's free block [[a, c], [c, b]] (a alone with one free axis)
    r, t = free[0], free[-1]
    for k in range(3):
        a += blocks[i, J1 + k] * columns[k][r] * columns[k][r]
        b += blocks[i, J1 + k] * columns[k][t] * columns[k][t]
        c += blocks[i, J1 + k] * columns[k][r] * columns[k][t]
    if len(free) == 1:
        return a
    return 0.5 * (a + b) - math.sqrt(0.25 * (a - b) ** 2 + c * c)


@numba.njit(cache=True)
def _squared_frequency(blocks, dof, k_translation, k_rotation, i):
    """Bound of block i's largest squared frequency [1/s^2] over its free degrees of freedom: k_t / M
    with M the least inertial mass of a free translation, k_r / J with J `_free_moment`; prescribed
    ones left out, as the 2D engine leaves out prescribed degrees of freedom."""
    mass = math.inf
    for d in range(3):
        if dof[i, d] != PRESCRIBED:
            mass = min(mass, blocks[i, MX + d])
    return NEIGHBOUR * (k_translation[i] / mass + k_rotation[i] / _free_moment(blocks, dof, i))


@numba.njit(cache=True)
def critical_time_step(blocks, dof, k_translation, k_rotation, damping):
    """Lower bound of the critical step, min over blocks of 2 / sqrt((1 + damping) lambda_i) [s], with
    the inertial masses and moments (MX.., J1..); +inf when nothing is in contact. `k_translation`,
    `k_rotation` (n,): each block's sums of `contact_stiffness` over its contacts. The (1 + damping)
    factor is the 2D engine's: local damping stiffens a decelerating block."""
    largest = 0.0
    for i in range(blocks.shape[0]):
        largest = max(largest, _squared_frequency(blocks, dof, k_translation, k_rotation, i))
    if largest <= 0.0:
        return math.inf
    return 2.0 / math.sqrt((1.0 + damping) * largest)


@numba.njit(cache=True)
def scale_masses(blocks, dof, k_translation, k_rotation, dt, safety, damping):
    """Density scaling: raise each inertial mass to 2 NEIGHBOUR (1 + damping) k_t (dt / 2 safety)^2 and
    each inertial principal moment to 2 NEIGHBOUR (1 + damping) k_r (dt / 2 safety)^2, never below the
    true ones, so that `dt` is `safety` times `critical_time_step` or less (each of the two terms of the
    bound takes half of the squared frequency that step allows)."""
    factor = 2.0 * NEIGHBOUR * (1.0 + damping) * (dt / (2.0 * safety)) ** 2
    for i in range(blocks.shape[0]):
        for d in range(3):
            blocks[i, MX + d] = max(blocks[i, MASS], k_translation[i] * factor)
            blocks[i, J1 + d] = max(blocks[i, I1 + d], k_rotation[i] * factor)
