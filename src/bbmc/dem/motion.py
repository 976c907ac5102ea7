"""Loads and motion: gravity and applied loads, the central-difference update, the vertices.

Cundall's local damping, -alpha |F| sign(v), per degree of freedom; prescribed degrees of freedom move
at their prescribed velocity from their start step. SI units: m, s, kg, N, N m.
"""

import math

import numba

from bbmc.dem.contact_forces import add_contact_sums
from bbmc.dem.contact_geometry import edge_frame
from bbmc.dem.layout import (
    FM,
    FX,
    FY,
    MASS,
    MW,
    MX,
    MY,
    PRESCRIBED,
    PVX,
    PVY,
    PW,
    RADIUS,
    SIZE,
    TH,
    THR,
    VPW,
    VPX,
    VPY,
    VSTART,
    VX,
    VY,
    XR,
    YR,
    W,
    X,
    Y,
)


@numba.njit(cache=True, inline="always")
def block_vertices(blocks, vertex_start, local, world, b):
    """World coordinates of block b's vertices from its centroid and rotation [m]."""
    c, s = math.cos(blocks[b, TH]), math.sin(blocks[b, TH])
    for v in range(vertex_start[b], vertex_start[b + 1]):
        world[v, 0] = blocks[b, X] + c * local[v, 0] - s * local[v, 1]
        world[v, 1] = blocks[b, Y] + s * local[v, 0] + c * local[v, 1]


@numba.njit(cache=True)
def update_vertices(blocks, vertex_start, local, world, moving):
    """World coordinates of the vertices of every `moving` block from its centroid and rotation [m]."""
    for b in range(blocks.shape[0]):
        if moving[b]:
            block_vertices(blocks, vertex_start, local, world, b)


@numba.njit(cache=True)
def _ramp(step, ramp_steps, start_step):
    """Load factor: 0 before start_step, then linear from 1/ramp_steps to 1 over ramp_steps, then 1."""
    if step < start_step:
        return 0.0
    if ramp_steps <= 0.0:
        return 1.0
    return min(1.0, (step - start_step + 1.0) / ramp_steps)


@numba.njit(cache=True)
def apply_loads(
    blocks, world, vertex_next, vertex_block, gravity, block_loads, load_block, edge_loads, load_edge, step
):
    """Gravity (true mass), block forces [N, N m] and edge stresses [Pa] for this step.

    An edge stress (sigma, tau, ramp, start) pushes on the edge with sigma (compression > 0) and drags along
    its counter-clockwise tangent with tau; it follows the edge as the block rotates, and acts at the
    edge's middle.
    """
    for i in range(blocks.shape[0]):
        blocks[i, FX] = blocks[i, MASS] * gravity[0]
        blocks[i, FY] = blocks[i, MASS] * gravity[1]
        blocks[i, FM] = 0.0
    for k in range(load_block.shape[0]):
        i = load_block[k]
        f = _ramp(step, block_loads[k, 3], block_loads[k, 4])
        blocks[i, FX] += f * block_loads[k, 0]
        blocks[i, FY] += f * block_loads[k, 1]
        blocks[i, FM] += f * block_loads[k, 2]
    for k in range(load_edge.shape[0]):
        e = load_edge[k]
        i = vertex_block[e]
        x0, y0, tx, ty, length = edge_frame(world, vertex_next, e)
        f = _ramp(step, edge_loads[k, 2], edge_loads[k, 3]) * length
        fx = f * (-edge_loads[k, 0] * ty + edge_loads[k, 1] * tx)
        fy = f * (edge_loads[k, 0] * tx + edge_loads[k, 1] * ty)
        rx, ry = x0 + 0.5 * length * tx - blocks[i, X], y0 + 0.5 * length * ty - blocks[i, Y]
        blocks[i, FX] += fx
        blocks[i, FY] += fy
        blocks[i, FM] += rx * fy - ry * fx


@numba.njit(cache=True)
def _advance(force, velocity, mass, damping, dt):
    """Central-difference velocity update with Cundall's local damping, -alpha |F| sign(v)."""
    if velocity > 0.0:
        force -= damping * abs(force)
    elif velocity < 0.0:
        force += damping * abs(force)
    return velocity + force / mass * dt


@numba.njit(cache=True, inline="always")
def move_block(blocks, dof, damping, dt, step, i):
    """Block i's new velocities and position; returns how far it has moved since the last contact
    search [m] (translation plus radius times rotation). Prescribed dofs are held until their start
    step."""
    for d, v, f, m, vp, pv in (
        (0, VX, FX, MX, VPX, PVX),
        (1, VY, FY, MY, VPY, PVY),
        (2, W, FM, MW, VPW, PW),
    ):
        blocks[i, pv] = blocks[i, v]
        if dof[i, d] == PRESCRIBED:
            blocks[i, v] = blocks[i, vp] if step >= blocks[i, VSTART] else 0.0
        else:
            blocks[i, v] = _advance(blocks[i, f], blocks[i, v], blocks[i, m], damping, dt)
    blocks[i, X] += blocks[i, VX] * dt
    blocks[i, Y] += blocks[i, VY] * dt
    blocks[i, TH] += blocks[i, W] * dt
    return math.hypot(blocks[i, X] - blocks[i, XR], blocks[i, Y] - blocks[i, YR]) + blocks[i, RADIUS] * abs(
        blocks[i, TH] - blocks[i, THR]
    )


@numba.njit(cache=True, parallel=True)
def move_blocks(
    blocks,
    dof,
    damping,
    dt,
    step,
    moving,
    vertex_start,
    local,
    world,
    threaded,
    per_contact,
    block_start,
    block_contacts,
):
    """New velocities and positions of the `moving` blocks (`move_block`) and their vertices
    (`block_vertices`), block by block in one pass; returns the largest movement since the last contact
    search [m]. `threaded`: on every thread of numba's pool, each block first adding its contacts'
    forces that a threaded `contact_forces` left in `per_contact` (`add_contact_sums`, with
    `block_start` and `block_contacts`); the largest movement is the same whatever the order. (Compiled
    with parallel=True either way: numba's parallel pipeline also makes the one-thread loop 2.5 times
    faster, measured at 10,000 blocks.)"""
    largest = 0.0
    if threaded:
        for i in numba.prange(blocks.shape[0]):
            add_contact_sums(blocks, i, per_contact, block_start, block_contacts)
            if moving[i]:
                largest = max(largest, move_block(blocks, dof, damping, dt, step, i))
                block_vertices(blocks, vertex_start, local, world, i)
        return largest
    for i in range(blocks.shape[0]):
        if moving[i]:
            largest = max(largest, move_block(blocks, dof, damping, dt, step, i))
            block_vertices(blocks, vertex_start, local, world, i)
    return largest


@numba.njit(cache=True)
def first_runaway(blocks, dt, fraction):
    """The first block with a non-finite position or velocity, or whose travel in one step,
    (|v| + |w| R) dt / size [1] (R its radius, size its size [m]), is above `fraction`; -1 if none.
    The run loop's health check between kernel calls, in one pass (plain numpy took 18 us a call on
    the shear box, a kernel call there being 250 steps of 0.5 us)."""
    for i in range(blocks.shape[0]):
        finite = True
        for column in (X, Y, TH, VX, VY, W):
            finite = finite and math.isfinite(blocks[i, column])
        travel = (math.hypot(blocks[i, VX], blocks[i, VY]) + abs(blocks[i, W]) * blocks[i, RADIUS]) * dt
        if not finite or travel / blocks[i, SIZE] > fraction:
            return i
    return -1
