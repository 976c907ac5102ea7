"""Motion of rigid blocks in 3D: central differences for translation, a symplectic splitting for rotation.

The state is a leapfrog's (columns in `bbmc.dem3d.layout`): positions and orientations at the full step
t, velocities and angular velocities at the half step t - dt/2, forces and torques at t.

Translation (as the 2D engine): v(t + dt/2) = v(t - dt/2) + (F + m g) / M dt, x(t + dt) = x(t) +
v(t + dt/2) dt, with m the true mass (gravity) and M the inertial mass (density scaling may raise it).

Rotation: Euler's equations in the principal frame, J w' = T - w x (J w), with the gyroscopic term, by
the symplectic splitting of Dullweber, Leimkuhler & McLachlan (1997, J. Chem. Phys. 107, 5840) in the
quaternion form of Miller et al. (2002, J. Chem. Phys. 116, 8649, "NO_SQUISH"): a kick of the angular
momentum by the torque, L(t + dt/2) = L(t - dt/2) + T(t) dt, then the free rotor over dt, split into
exact rotations about one principal axis at a time, k = 3, 2, 1, 2, 3 for dt/2, dt/2, dt, dt/2, dt/2.
Each is the exact flow of L_k^2 / (2 J_k): the body turns by a = L_k h / J_k about its axis k, q <- q *
(cos a/2, sin a/2 e_k), and the body-frame momentum turns back by -a about e_k. The scheme is second
order, time-reversible and symplectic; it keeps the world angular momentum exactly (to round-off: each
sub-rotation leaves R(q) L_body unchanged) and the energy within O(dt^2) without drift. It is not the
spherical shortcut (w += T / J dt, q turned by w dt), which drops the gyroscopic term. q is renormalised
every step.

Blocks with a prescribed rotational degree of freedom (held about a world axis, as a plane-strain twin
is about x and z, `bbmc.dem3d.extrusion`) take the constrained kick instead: the new world angular
velocity w solves J_w(q) w = J_w(q) w_old + T dt in the free rows and w_c = the prescribed value in
the others (J_w = R diag(J) R^T), and q is turned by w dt about w. Exact for a free rotation about a
principal axis (an extruded block's y axis), first order in the gyroscopic term otherwise.

Cundall's local damping, -alpha |F| sign(v), per degree of freedom: per world axis for translation (as
in 2D); for rotation per principal axis, on the torque in the principal frame against the principal
component of w. The principal frame is the one in which J is diagonal, so each component is its own
equation J_k w_k' = T_k as a 2D dof's is, and it turns with the block, so the damping of a block does
not depend on how the world's axes are laid (world components would damp a rotation about a diagonal
axis differently from one about x). The damping torque's power, sum_k -alpha |T_k| |w_k|, is never
positive, in any frame. Units: m, s, kg, N, N m, rad.
"""

import math

import numba
import numpy as np

from bbmc.dem3d.layout import (
    BLOCK_COLUMNS,
    FX,
    I1,
    J1,
    MASS,
    MX,
    PRESCRIBED,
    PVX,
    PWX,
    QRW,
    QW,
    QX,
    QY,
    QZ,
    RADIUS,
    TX,
    VPX,
    VSTART,
    VX,
    WPX,
    WX,
    XR,
    X,
)
from bbmc.dem3d.quaternion import (
    angle_between,
    from_rotation_vector,
    multiply,
    normalised,
    quaternion_from_matrix,
    rotate,
    rotate_back,
)


@numba.njit(cache=True, inline="always")
def _damped(force, velocity, damping):
    """Force with Cundall's local damping, F - alpha |F| sign(v)."""
    if velocity > 0.0:
        return force - damping * abs(force)
    if velocity < 0.0:
        return force + damping * abs(force)
    return force


@numba.njit(cache=True, inline="always")
def _prescribed(blocks, i, column, step):
    """A prescribed dof's velocity: its prescribed value from its start step, held (0) before."""
    return blocks[i, column] if step >= blocks[i, VSTART] else 0.0


@numba.njit(cache=True, inline="always")
def _translate(blocks, dof, gravity, damping, dt, step, i):
    """Central differences for the centroid, per world axis."""
    for d in range(3):
        blocks[i, PVX + d] = blocks[i, VX + d]
        if dof[i, d] == PRESCRIBED:
            blocks[i, VX + d] = _prescribed(blocks, i, VPX + d, step)
        else:
            force = _damped(blocks[i, FX + d] + blocks[i, MASS] * gravity[d], blocks[i, VX + d], damping)
            blocks[i, VX + d] += force / blocks[i, MX + d] * dt
        blocks[i, X + d] += blocks[i, VX + d] * dt


@numba.njit(cache=True, inline="always")
def _axis_rotation(q, momentum, k, h, moments):
    """The free rotor's exact flow about principal axis k for time h: the body turns by a = L_k h / J_k
    about its axis k, the body-frame momentum by -a (Dullweber et al. 1997, eq. 3.10's sub-flows)."""
    a = momentum[k] * h / moments[k]
    c, s = math.cos(0.5 * a), math.sin(0.5 * a)
    e1, e2, e3 = (s, 0.0, 0.0) if k == 0 else ((0.0, s, 0.0) if k == 1 else (0.0, 0.0, s))
    q[0], q[1], q[2], q[3] = multiply(q[0], q[1], q[2], q[3], c, e1, e2, e3)
    m, n = (k + 1) % 3, (k + 2) % 3
    ca, sa = math.cos(a), math.sin(a)
    lm, ln = momentum[m], momentum[n]
    momentum[m] = ca * lm + sa * ln
    momentum[n] = ca * ln - sa * lm


@numba.njit(cache=True, inline="always")
def _rotate_free(blocks, damping, dt, i, q, momentum, moments):
    """Kick and free-rotor drift of a block free in rotation; leaves w(t + dt/2) in the world frame."""
    w = rotate_back(q[0], q[1], q[2], q[3], blocks[i, WX], blocks[i, WX + 1], blocks[i, WX + 2])
    torque = rotate_back(q[0], q[1], q[2], q[3], blocks[i, TX], blocks[i, TX + 1], blocks[i, TX + 2])
    for k in range(3):
        momentum[k] = moments[k] * w[k] + _damped(torque[k], w[k], damping) * dt
    _axis_rotation(q, momentum, 2, 0.5 * dt, moments)
    _axis_rotation(q, momentum, 1, 0.5 * dt, moments)
    _axis_rotation(q, momentum, 0, dt, moments)
    _axis_rotation(q, momentum, 1, 0.5 * dt, moments)
    _axis_rotation(q, momentum, 2, 0.5 * dt, moments)
    q[0], q[1], q[2], q[3] = normalised(q[0], q[1], q[2], q[3])
    w = rotate(
        q[0], q[1], q[2], q[3], momentum[0] / moments[0], momentum[1] / moments[1], momentum[2] / moments[2]
    )
    blocks[i, WX], blocks[i, WX + 1], blocks[i, WX + 2] = w


@numba.njit(cache=True, inline="always")
def _rotate_constrained(blocks, dof, damping, dt, step, i, q, moments, system):
    """Constrained kick of a block with a prescribed rotational dof, then q turned by w dt about w. The
    torque about a held world axis is the constraint's reaction, never balanced, so it is left out
    before the damping, which works in the principal frame: else, where a principal axis is oblique to
    the held ones, the damping of the free rotation would be driven by the reaction (a plane-strain
    twin's columns never settled)."""
    w = rotate_back(q[0], q[1], q[2], q[3], blocks[i, WX], blocks[i, WX + 1], blocks[i, WX + 2])
    tx = 0.0 if dof[i, 3] == PRESCRIBED else blocks[i, TX]
    ty = 0.0 if dof[i, 4] == PRESCRIBED else blocks[i, TX + 1]
    tz = 0.0 if dof[i, 5] == PRESCRIBED else blocks[i, TX + 2]
    torque = rotate_back(q[0], q[1], q[2], q[3], tx, ty, tz)
    d0 = _damped(torque[0], w[0], damping)
    d1 = _damped(torque[1], w[1], damping)
    d2 = _damped(torque[2], w[2], damping)
    momentum = rotate(q[0], q[1], q[2], q[3], moments[0] * w[0] + d0 * dt, moments[1] * w[1] + d1 * dt,
                      moments[2] * w[2] + d2 * dt)  # fmt: skip
    for c in range(3):  # column c of J_w = R diag(J) R^T: R diag(J) R^T e_c
        e = rotate_back(q[0], q[1], q[2], q[3], 1.0 if c == 0 else 0.0, 1.0 if c == 1 else 0.0,
                        1.0 if c == 2 else 0.0)  # fmt: skip
        column = rotate(q[0], q[1], q[2], q[3], moments[0] * e[0], moments[1] * e[1], moments[2] * e[2])
        for r in range(3):
            system[r, c] = column[r]
    for r in range(3):
        system[r, 3] = momentum[r]
        if dof[i, 3 + r] == PRESCRIBED:
            for c in range(3):
                system[r, c] = 1.0 if c == r else 0.0
            system[r, 3] = _prescribed(blocks, i, WPX + r, step)
    _solve3(system)
    for r in range(3):
        blocks[i, WX + r] = system[r, 3]
    p = from_rotation_vector(system[0, 3] * dt, system[1, 3] * dt, system[2, 3] * dt)
    r0, r1, r2, r3 = multiply(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])
    q[0], q[1], q[2], q[3] = normalised(r0, r1, r2, r3)


@numba.njit(cache=True, inline="always")
def _solve3(system):
    """Solve the 3 x 3 system [A | b] in place by Cramer's rule; the solution is left in column 3.
    (A is J_w with some rows replaced by unit rows: symmetric positive definite in the free rows.)"""
    a = system
    det = (
        a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
        - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
        + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0])
    )
    b0, b1, b2 = a[0, 3], a[1, 3], a[2, 3]
    x0 = (
        b0 * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
        - a[0, 1] * (b1 * a[2, 2] - a[1, 2] * b2)
        + a[0, 2] * (b1 * a[2, 1] - a[1, 1] * b2)
    )
    x1 = (
        a[0, 0] * (b1 * a[2, 2] - a[1, 2] * b2)
        - b0 * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
        + a[0, 2] * (a[1, 0] * b2 - b1 * a[2, 0])
    )
    x2 = (
        a[0, 0] * (a[1, 1] * b2 - b1 * a[2, 1])
        - a[0, 1] * (a[1, 0] * b2 - b1 * a[2, 0])
        + b0 * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0])
    )
    a[0, 3], a[1, 3], a[2, 3] = x0 / det, x1 / det, x2 / det


@numba.njit(cache=True, inline="always")
def move_block(blocks, dof, gravity, damping, dt, step, i, q, momentum, moments, system):
    """Block i's new velocities, position and orientation; returns how far it has moved since the last
    contact search [m]: |x - x_R| + RADIUS x the angle turned since [rad]. `q`, `momentum`, `moments`
    (4, 3, 3) and `system` (3, 4) are scratch arrays."""
    _translate(blocks, dof, gravity, damping, dt, step, i)
    for d in range(3):
        blocks[i, PWX + d] = blocks[i, WX + d]
        moments[d] = blocks[i, J1 + d]
    q[0], q[1], q[2], q[3] = blocks[i, QW], blocks[i, QX], blocks[i, QY], blocks[i, QZ]
    if dof[i, 3] == PRESCRIBED or dof[i, 4] == PRESCRIBED or dof[i, 5] == PRESCRIBED:
        _rotate_constrained(blocks, dof, damping, dt, step, i, q, moments, system)
    else:
        _rotate_free(blocks, damping, dt, i, q, momentum, moments)
    blocks[i, QW], blocks[i, QX], blocks[i, QY], blocks[i, QZ] = q[0], q[1], q[2], q[3]
    shift = math.sqrt(
        (blocks[i, X] - blocks[i, XR]) ** 2
        + (blocks[i, X + 1] - blocks[i, XR + 1]) ** 2
        + (blocks[i, X + 2] - blocks[i, XR + 2]) ** 2
    )
    turn = angle_between(blocks[i, QRW], blocks[i, QRW + 1], blocks[i, QRW + 2], blocks[i, QRW + 3],
                         q[0], q[1], q[2], q[3])  # fmt: skip
    return shift + blocks[i, RADIUS] * turn


CHUNK = 64  # blocks per task of a threaded `move_blocks`, each with its own scratch arrays


@numba.njit(cache=True, inline="always")
def _move_range(blocks, dof, gravity, damping, dt, step, first, last):
    """`move_block` for blocks first..last-1; returns their largest movement since the last search [m]."""
    q, momentum, moments, system = np.empty(4), np.empty(3), np.empty(3), np.empty((3, 4))
    largest = 0.0
    for i in range(first, last):
        largest = max(largest, move_block(blocks, dof, gravity, damping, dt, step, i, q, momentum, moments,
                                          system))  # fmt: skip
    return largest


@numba.njit(cache=True, parallel=True)
def move_blocks(blocks, dof, gravity, damping, dt, step, threaded=False):
    """`move_block` for every block; returns the largest movement since the last contact search [m].
    `threaded`: chunks of `CHUNK` blocks on every thread of numba's pool (each block's update reads
    and writes its own row only: the same to the bit for any number of threads)."""
    n = blocks.shape[0]
    if not threaded:
        return _move_range(blocks, dof, gravity, damping, dt, step, 0, n)
    chunks = (n + CHUNK - 1) // CHUNK
    largest = np.zeros(chunks)
    for k in numba.prange(chunks):
        largest[k] = _move_range(blocks, dof, gravity, damping, dt, step, k * CHUNK, min(n, (k + 1) * CHUNK))
    return largest.max() if chunks else 0.0


def step_motion(
    blocks: np.ndarray,
    dof: np.ndarray,
    dt: float,
    gravity=(0.0, 0.0, -9.81),
    damping: float = 0.0,
    step: int = 0,
) -> float:
    """One step of every block (`move_blocks`) from the forces and torques in its row [N, N m, world];
    `gravity` [m/s^2] is added as true mass x g, `damping` is Cundall's alpha [1], `step` decides whether
    prescribed velocities have started. Returns the largest movement since the last contact search [m]."""
    return move_blocks(
        blocks, dof, np.asarray(gravity, dtype=np.float64), float(damping), float(dt), int(step)
    )


def new_blocks(
    centroids: np.ndarray, axes: np.ndarray, masses: np.ndarray, moments: np.ndarray, radii: np.ndarray
) -> np.ndarray:
    """The block array (n, BLOCK_COLUMNS) at rest: centroids (n, 3) [m]; axes (n, 3, 3), each block's
    principal-axes matrix R0 (columns the principal axes in the world, right-handed), whose quaternion
    is the initial orientation; masses (n,) [kg]; principal moments (n, 3) [kg m^2], in the order of
    R0's columns; radii (n,) [m]. Inertial masses and moments start at the true ones; a block with a
    non-positive mass or moment is refused, naming it."""
    n = len(masses)
    blocks = np.zeros((n, BLOCK_COLUMNS))
    for i in range(n):
        if not masses[i] > 0.0 or not np.all(moments[i] > 0.0):
            raise ValueError(
                f"block {i}: mass and principal moments must be > 0, got {masses[i]}, {moments[i]}"
            )
        blocks[i, QW : QW + 4] = quaternion_from_matrix(axes[i], f"block {i}")
    blocks[:, X : X + 3] = centroids
    blocks[:, XR : XR + 3] = centroids
    blocks[:, QRW : QRW + 4] = blocks[:, QW : QW + 4]
    blocks[:, MASS] = masses
    blocks[:, MX : MX + 3] = np.asarray(masses)[:, None]
    blocks[:, I1 : I1 + 3] = moments
    blocks[:, J1 : J1 + 3] = moments
    blocks[:, RADIUS] = radii
    return blocks


def body_angular_velocity(blocks: np.ndarray) -> np.ndarray:
    """Angular velocities in each block's principal frame, R(q)^T w (n, 3) [rad/s]."""
    q = blocks[:, QW : QW + 4]
    w = blocks[:, WX : WX + 3]
    u = -q[:, 1:]
    t = 2.0 * np.cross(u, w)
    return w + q[:, :1] * t + np.cross(u, t)


def kinetic_energy(blocks: np.ndarray) -> np.ndarray:
    """Kinetic energy of each block with its true mass and moments, 1/2 m |v|^2 + 1/2 sum_k I_k w_k^2
    (w_k principal components) [J], from the velocities in the row."""
    w = body_angular_velocity(blocks)
    v = blocks[:, VX : VX + 3]
    return 0.5 * blocks[:, MASS] * np.sum(v * v, axis=1) + 0.5 * np.sum(
        blocks[:, I1 : I1 + 3] * w * w, axis=1
    )


def angular_momentum(blocks: np.ndarray) -> np.ndarray:
    """Each block's angular momentum about its centroid in the world frame, R(q) diag(I) R(q)^T w
    (n, 3) [kg m^2/s]."""
    q = blocks[:, QW : QW + 4]
    body = blocks[:, I1 : I1 + 3] * body_angular_velocity(blocks)
    u = q[:, 1:]
    t = 2.0 * np.cross(u, body)
    return body + q[:, :1] * t + np.cross(u, t)
