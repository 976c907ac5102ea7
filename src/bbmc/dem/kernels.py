"""The engine's hot loops: one explicit cycle of a 2D rigid-block DEM, in numba over flat arrays.

A cycle (one "step", as in UDEC) is: loads (gravity, edge stresses, block forces), contact forces from
the current positions and the last half-step velocities (incremental force-displacement law per
sub-contact, Mohr-Coulomb slip with a tension cut-off), then the central-difference update
of velocities (with Cundall's local damping) and positions. Every `update_interval` cycles the
stress-dependent joint laws are re-evaluated at each sub-contact from its own stresses through the
scalar laws of `bbmc.laws` (the same code the numpy ufuncs run), and the time step is recomputed.

Geometry of a contact. A contact is a pair of antiparallel edges, one of block A (the reference edge,
tangent t, outward normal n) and one of block B. The part of B's edge that projects onto A's edge is
split into `n_sub` equal sub-contacts; each sits at the middle of its part, midway between the two
edges, and carries a length L. Its overlap u_n (> 0 closed) is measured geometrically each cycle, so
closure never drifts; the normal stress is integrated incrementally, d sigma_n = K_n d u_n (which is
how a stress-dependent K_n(sigma_n) integrates eq 5). Shear is incremental: d u_s = (v_B - v_A).t dt,
d tau = K_s d u_s. The force on B is L (sigma_n n - tau t); A gets the opposite.

Rules (documented options of the scene format):

* Open: an unbonded sub-contact (tensile strength 0) with u_n <= 0 carries no force.
* Tension cut-off: a bonded sub-contact (tensile strength T > 0) may carry sigma_n down to -T; below,
  it fails: sigma_n = tau = 0, its tensile strength becomes 0 for good and so does its cohesion, except
  that a Barton-Bandis law with ``after_slip = keep`` re-derives the tangent cohesion at its next
  update (that cohesion is the envelope's intercept, not a bond).
* Slip: |tau| <= c + sigma_n tan(phi); at the limit tau stays on it and the sub-contact is marked
  slipped. With ``after_slip = zero`` (Itasca's Coulomb joint) its cohesion and tensile strength drop
  to 0 at the first slip and stay 0, also through later law updates; with ``keep`` they are kept.
"""

import math

import numba
import numpy as np

from bbmc.dem.layout import (
    AFTER_SLIP,
    AFTER_SLIP_ZERO,
    BLOCK_A,
    BLOCK_B,
    COH,
    CX,
    CY,
    DT,
    EDGE_A,
    EDGE_B,
    FM,
    FX,
    FY,
    INERTIA,
    JOINT_TYPE,
    KN,
    KS,
    LAW_SN,
    LAW_TAU,
    LENGTH,
    MASS,
    MW,
    MX,
    MY,
    NORMAL_CONSTANT,
    NORMAL_EQ8,
    NORMAL_LAW,
    P_A,
    P_B,
    P_COH,
    P_D,
    P_JCS,
    P_JRC,
    P_K_J,
    P_K_TANGENT,
    P_KN,
    P_KS,
    P_LG_E,
    P_N_J,
    P_PHI,
    P_PHI_B,
    P_PHI_MAX,
    P_Q,
    P_SHEAR_FLOOR,
    P_SIGMA_REF,
    P_STRESS_FLOOR,
    P_TAU_P_INTERCEPT,
    P_TAU_P_SLOPE,
    P_TAU_ULT_INTERCEPT,
    P_TAU_ULT_SLOPE,
    P_TEN,
    PRESCRIBED,
    PVX,
    PVY,
    PW,
    RADIUS,
    SHEAR_BANDIS,
    SHEAR_CONSTANT,
    SHEAR_CORRECTED,
    SHEAR_LAW,
    SHEAR_SIMPLIFIED,
    SINCE_UPDATE,
    SLIPPED,
    SN,
    STEP,
    STRENGTH_BARTON_BANDIS,
    STRENGTH_CONSTANT,
    STRENGTH_LAW,
    TANPHI,
    TAU,
    TEN,
    TH,
    THR,
    TIME,
    UN,
    US,
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
from bbmc.laws.stiffness import (
    bandis_shear_stiffness,
    corrected_shear_stiffness,
    hyperbolic_shear_stiffness,
    initial_shear_stiffness,
    linear_relation,
    normal_stiffness,
    simplified_shear_stiffness,
)
from bbmc.laws.strength import equivalent_cohesion, equivalent_friction_angle

# Kernel return codes.
DONE, SEARCH_NEEDED, STEP_ABOVE_CRITICAL = 0, 1, 2


@numba.njit(cache=True)
def update_vertices(blocks, vertex_start, local, world, moving):
    """World coordinates of the vertices of every `moving` block from its centroid and rotation [m]."""
    for b in range(blocks.shape[0]):
        if not moving[b]:
            continue
        c, s = math.cos(blocks[b, TH]), math.sin(blocks[b, TH])
        for v in range(vertex_start[b], vertex_start[b + 1]):
            world[v, 0] = blocks[b, X] + c * local[v, 0] - s * local[v, 1]
            world[v, 1] = blocks[b, Y] + s * local[v, 0] + c * local[v, 1]


@numba.njit(cache=True)
def edge_frame(world, vertex_next, e):
    """Start point, unit tangent and length of edge e (counter-clockwise, so the outward normal is
    (t_y, -t_x))."""
    x0, y0 = world[e, 0], world[e, 1]
    dx, dy = world[vertex_next[e], 0] - x0, world[vertex_next[e], 1] - y0
    length = math.sqrt(dx * dx + dy * dy)
    return x0, y0, dx / length, dy / length, length


@numba.njit(cache=True)
def _open(subs, s):
    subs[s, SN] = 0.0
    subs[s, TAU] = 0.0


@numba.njit(cache=True)
def _sub_contact_law(subs, s, un, dus, after_slip):
    """Incremental force-displacement law of one sub-contact (module docstring), in place."""
    bonded = subs[s, TEN] > 0.0
    if bonded:
        sn = subs[s, SN] + subs[s, KN] * (un - subs[s, UN])
        if sn < -subs[s, TEN]:
            _open(subs, s)
            subs[s, TEN] = 0.0
            subs[s, COH] = 0.0
            subs[s, SLIPPED] = 1.0
            subs[s, LAW_SN] = math.nan
            subs[s, UN] = un
            subs[s, US] += dus
            return
    else:
        if un <= 0.0:
            _open(subs, s)
            subs[s, UN] = un
            subs[s, US] += dus
            return
        sn = max(subs[s, SN] + subs[s, KN] * (un - max(subs[s, UN], 0.0)), 0.0)
    tau = subs[s, TAU] + subs[s, KS] * dus
    strength = max(subs[s, COH] + sn * subs[s, TANPHI], 0.0)
    if abs(tau) > strength:
        tau = math.copysign(strength, tau)
        if subs[s, SLIPPED] == 0.0:
            subs[s, SLIPPED] = 1.0
            subs[s, LAW_SN] = math.nan
            if after_slip == AFTER_SLIP_ZERO:
                subs[s, COH] = 0.0
                subs[s, TEN] = 0.0
    subs[s, SN] = sn
    subs[s, TAU] = tau
    subs[s, UN] = un
    subs[s, US] += dus


@numba.njit(cache=True)
def contact_forces(blocks, world, vertex_next, contacts, subs, n_sub, laws, cos_tolerance, dt):
    """Update every sub-contact's stresses and add the contact forces and moments to the blocks.

    A contact whose edges no longer face each other (angle beyond the tolerance, or no overlap of
    their projections) is inactive: zero length, zero stresses.
    """
    for c in range(contacts.shape[0]):
        a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
        ax, ay, tx, ty, la = edge_frame(world, vertex_next, contacts[c, EDGE_A])
        bx, by, ux, uy, lb = edge_frame(world, vertex_next, contacts[c, EDGE_B])
        nx, ny = ty, -tx
        nbx, nby = uy, -ux
        facing = nx * nbx + ny * nby
        s_b0 = (bx - ax) * tx + (by - ay) * ty
        s_b1 = s_b0 + (ux * tx + uy * ty) * lb
        lo, hi = max(min(s_b0, s_b1), 0.0), min(max(s_b0, s_b1), la)
        first = c * n_sub
        if facing > -cos_tolerance or hi <= lo:
            for s in range(first, first + n_sub):
                _open(subs, s)
                subs[s, LENGTH] = 0.0
            continue
        length = (hi - lo) / n_sub
        after_slip = laws[contacts[c, JOINT_TYPE], AFTER_SLIP]
        for k in range(n_sub):
            s = first + k
            along = lo + (k + 0.5) * length
            px, py = ax + along * tx, ay + along * ty
            gap = -((px - bx) * nbx + (py - by) * nby) / facing
            cx, cy = px + 0.5 * gap * nx, py + 0.5 * gap * ny
            rax, ray = cx - blocks[a, X], cy - blocks[a, Y]
            rbx, rby = cx - blocks[b, X], cy - blocks[b, Y]
            dvx = (blocks[b, VX] - blocks[b, W] * rby) - (blocks[a, VX] - blocks[a, W] * ray)
            dvy = (blocks[b, VY] + blocks[b, W] * rbx) - (blocks[a, VY] + blocks[a, W] * rax)
            _sub_contact_law(subs, s, -gap, (dvx * tx + dvy * ty) * dt, after_slip)
            subs[s, LENGTH] = length
            subs[s, CX] = cx
            subs[s, CY] = cy
            fx = length * (subs[s, SN] * nx - subs[s, TAU] * tx)
            fy = length * (subs[s, SN] * ny - subs[s, TAU] * ty)
            blocks[b, FX] += fx
            blocks[b, FY] += fy
            blocks[b, FM] += rbx * fy - rby * fx
            blocks[a, FX] -= fx
            blocks[a, FY] -= fy
            blocks[a, FM] -= rax * fy - ray * fx


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


@numba.njit(cache=True)
def move_blocks(blocks, dof, damping, dt, step, moving):
    """New velocities and positions of the `moving` blocks; returns the largest movement since the last
    contact search [m] (translation plus radius times rotation). Prescribed dofs are held until their
    start step."""
    largest = 0.0
    for i in range(blocks.shape[0]):
        if not moving[i]:
            continue
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
        moved = math.hypot(blocks[i, X] - blocks[i, XR], blocks[i, Y] - blocks[i, YR]) + blocks[
            i, RADIUS
        ] * abs(blocks[i, TH] - blocks[i, THR])
        largest = max(largest, moved)
    return largest


@numba.njit(cache=True)
def _shear_stiffness(law, sigma, tau, p):
    """K_s [Pa/m] of one shear-stiffness law at (sigma, |tau|), floored at a fraction of K_si."""
    k_si = initial_shear_stiffness(sigma, p[P_K_J], p[P_N_J], p[P_SIGMA_REF])
    if law == SHEAR_SIMPLIFIED:
        k = simplified_shear_stiffness(sigma, p[P_K_J], p[P_N_J], p[P_SIGMA_REF], p[P_D])
    else:
        tau_p = linear_relation(sigma, p[P_TAU_P_SLOPE], p[P_TAU_P_INTERCEPT])
        tau_ult = linear_relation(tau_p, p[P_TAU_ULT_SLOPE], p[P_TAU_ULT_INTERCEPT])
        if law == SHEAR_BANDIS:
            k = bandis_shear_stiffness(tau, k_si, tau_p, tau_ult)
        elif law == SHEAR_CORRECTED:
            k = corrected_shear_stiffness(tau, k_si, tau_p, tau_ult, p[P_A], p[P_B])
        else:
            k = hyperbolic_shear_stiffness(tau, k_si, tau_ult)
    return max(k, p[P_SHEAR_FLOOR] * k_si)


@numba.njit(cache=True)
def update_joint_laws(contacts, subs, n_sub, laws, params, changed_only):
    """Re-evaluate K_n, K_s, c and phi of every sub-contact of a stress-dependent joint type.

    `changed_only`: skip a sub-contact whose sigma_n and tau are those of its last evaluation (an open
    one stays at 0, 0) and that has not slipped or failed since: the laws would give the same values.

    Stiffness laws are evaluated at max(sigma_n, stress floor), so an open or barely closed joint keeps
    a usable stiffness (the laws give 0 at sigma_n = 0, and a joint with K_n = 0 could never close);
    the strength is evaluated at sigma_n itself (no strength when open). A slipped sub-contact of a
    joint type with ``after_slip = zero`` keeps c = 0.
    """
    for c in range(contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        p = params[j]
        for s in range(c * n_sub, (c + 1) * n_sub):
            sigma = subs[s, SN]
            if changed_only and sigma == subs[s, LAW_SN] and subs[s, TAU] == subs[s, LAW_TAU]:
                continue
            subs[s, LAW_SN] = sigma
            subs[s, LAW_TAU] = subs[s, TAU]
            floored = max(sigma, p[P_STRESS_FLOOR])
            if laws[j, NORMAL_LAW] == NORMAL_EQ8:
                subs[s, KN] = normal_stiffness(floored, p[P_Q], p[P_LG_E])
            if laws[j, SHEAR_LAW] != SHEAR_CONSTANT:
                subs[s, KS] = _shear_stiffness(laws[j, SHEAR_LAW], floored, abs(subs[s, TAU]), p)
            if laws[j, STRENGTH_LAW] == STRENGTH_BARTON_BANDIS:
                args = (sigma, p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PHI_MAX], p[P_K_TANGENT])
                subs[s, TANPHI] = math.tan(equivalent_friction_angle(*args))
                cohesion = equivalent_cohesion(*args)
                if subs[s, SLIPPED] != 0.0 and laws[j, AFTER_SLIP] == AFTER_SLIP_ZERO:
                    cohesion = 0.0
                subs[s, COH] = cohesion


@numba.njit(cache=True)
def stresses_moved(contacts, subs, n_sub, laws, params, change):
    """True once a sub-contact of a stress-dependent joint type has a sigma_n or tau that differs from
    the one its laws were last evaluated at by more than `change` times the larger of that value and
    the type's stress floor (so an update is due before the interval is up)."""
    for c in range(contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        if (
            laws[j, STRENGTH_LAW] == STRENGTH_CONSTANT
            and laws[j, NORMAL_LAW] == NORMAL_CONSTANT
            and (laws[j, SHEAR_LAW] == SHEAR_CONSTANT)
        ):
            continue
        floor = params[j, P_STRESS_FLOOR]
        for s in range(c * n_sub, (c + 1) * n_sub):
            if abs(subs[s, SN] - subs[s, LAW_SN]) > change * max(abs(subs[s, LAW_SN]), floor):
                return True
            if abs(subs[s, TAU] - subs[s, LAW_TAU]) > change * max(abs(subs[s, LAW_TAU]), floor):
                return True
    return False


@numba.njit(cache=True)
def initial_joint_state(contacts, subs, n_sub, laws, params, first_new, intact):
    """Parameters of new sub-contacts (contacts first_new onwards) from their joint type.

    Contacts of the initial assembly (`intact`) get the type's cohesion and tensile strength; contacts
    that form during a run carry no tensile strength, and their cohesion follows ``after_slip``.
    """
    for c in range(first_new, contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        for s in range(c * n_sub, (c + 1) * n_sub):
            subs[s, :] = 0.0
            subs[s, LAW_SN] = math.nan
            subs[s, KN] = params[j, P_KN]
            subs[s, KS] = params[j, P_KS]
            subs[s, TANPHI] = math.tan(params[j, P_PHI])
            if intact:
                subs[s, COH] = params[j, P_COH]
                subs[s, TEN] = params[j, P_TEN]
            else:
                subs[s, SLIPPED] = 1.0
                if laws[j, AFTER_SLIP] != AFTER_SLIP_ZERO:
                    subs[s, COH] = params[j, P_COH]


@numba.njit(cache=True)
def stiffness_row_sums(blocks, dof, world, vertex_next, contacts, subs, n_sub, symmetric, rows):
    """Gershgorin row sums of the assembled contact stiffness, per block and degree of freedom.

    Each sub-contact adds, for its normal (K_n) and shear (K_s) direction d, the rank-one stiffness
    k g g^T with k = K L and g = (-d, -r_A x d | d, r_B x d) over the free degrees of freedom of A and
    B. `symmetric`: rows of M^-1/2 K M^-1/2 (their maximum bounds the largest squared frequency);
    else rows of |K| itself (used to choose scaled masses). Prescribed degrees of freedom are left out.
    """
    rows[:] = 0.0
    scale_a = np.zeros(3)
    scale_b = np.zeros(3)
    ga = np.zeros(3)
    gb = np.zeros(3)
    for c in range(contacts.shape[0]):
        a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
        _, _, tx, ty, _ = edge_frame(world, vertex_next, contacts[c, EDGE_A])
        for d in range(3):
            scale_a[d] = _row_scale(blocks, dof, a, d, symmetric)
            scale_b[d] = _row_scale(blocks, dof, b, d, symmetric)
        for s in range(c * n_sub, (c + 1) * n_sub):
            length = subs[s, LENGTH]
            if length <= 0.0:
                continue
            rax, ray = subs[s, CX] - blocks[a, X], subs[s, CY] - blocks[a, Y]
            rbx, rby = subs[s, CX] - blocks[b, X], subs[s, CY] - blocks[b, Y]
            for dx, dy, k in ((ty, -tx, subs[s, KN]), (tx, ty, subs[s, KS])):
                ga[0], ga[1], ga[2] = -dx, -dy, -(rax * dy - ray * dx)
                gb[0], gb[1], gb[2] = dx, dy, rbx * dy - rby * dx
                total = 0.0
                for d in range(3):
                    total += abs(ga[d]) * scale_a[d] + abs(gb[d]) * scale_b[d]
                for d in range(3):
                    rows[a, d] += k * length * abs(ga[d]) * scale_a[d] * total
                    rows[b, d] += k * length * abs(gb[d]) * scale_b[d] * total


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
    damping,
    cos_tolerance,
    search_distance,
    time_step_mode,
    safety,
    fixed_dt,
):
    """Run up to n_steps cycles. Returns (cycles done, DONE | SEARCH_NEEDED | STEP_ABOVE_CRITICAL).

    time_step_mode: 0 automatic (safety x critical, recomputed after each law update), 1 fixed (the
    run stops with STEP_ABOVE_CRITICAL once the fixed step exceeds the critical one), 2 density
    scaling (fixed step, inertial masses rescaled after each law update). The laws are updated every
    `update_interval` cycles, and sooner once `stresses_moved` by `stress_change` (inf: never sooner).
    `changed_laws_only` and `moving`: see `update_joint_laws` and `move_blocks`.
    """
    for done in range(n_steps):
        due = clock[SINCE_UPDATE] >= update_interval
        if variable_laws and not due and stress_change < math.inf:
            due = stresses_moved(contacts, subs, n_sub, laws, params, stress_change)
        if variable_laws and due:
            update_joint_laws(contacts, subs, n_sub, laws, params, changed_laws_only)
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
            if status != DONE:
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
        contact_forces(blocks, world, vertex_next, contacts, subs, n_sub, laws, cos_tolerance, dt)
        moved = move_blocks(blocks, dof, damping, dt, clock[STEP], moving)
        update_vertices(blocks, vertex_start, local, world, moving)
        clock[STEP] += 1.0
        clock[TIME] += dt
        clock[SINCE_UPDATE] += 1.0
        if moved > 0.5 * search_distance:
            return done + 1, SEARCH_NEEDED
    return n_steps, DONE


@numba.njit(cache=True)
def set_time_step(
    clock, blocks, dof, world, vertex_next, contacts, subs, n_sub, mode, safety, fixed_dt, damping
):
    """Set clock[DT] for the current stiffnesses (see `cycle` for the modes); returns a status code."""
    if mode == 2:
        scale_masses(blocks, dof, world, vertex_next, contacts, subs, n_sub, fixed_dt, safety, damping)
        clock[DT] = fixed_dt
        return DONE
    critical = critical_time_step(blocks, dof, world, vertex_next, contacts, subs, n_sub, damping)
    if mode == 1:
        clock[DT] = fixed_dt
        return STEP_ABOVE_CRITICAL if fixed_dt > critical else DONE
    clock[DT] = min(safety * critical, fixed_dt)
    return DONE
