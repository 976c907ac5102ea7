"""The engine's hot loops: one explicit cycle of a 2D rigid-block DEM, in numba over flat arrays.

A cycle (one "step", as in UDEC) is: loads (gravity, edge stresses, block forces), contact forces from
the current positions and the last half-step velocities (incremental force-displacement law per
sub-contact, Mohr-Coulomb slip with a tension cut-off), then the central-difference update
of velocities (with Cundall's local damping) and positions. Every `update_interval` cycles the
stress-dependent joint laws are re-evaluated at each sub-contact from its own stresses through the
scalar laws of `bbmc.laws` (the same code the numpy ufuncs run), and the time step is recomputed.

Geometry of a contact. A contact is a pair of edges, one of block A (the lower index) and one of
block B, whose outward normals face each other at any angle below 90 degrees and whose projections
on their common line overlap (`contact_frame`): two faces, a corner against a face, or a corner
against a corner. The common line's normal n is the face's where a corner presses on a face, turns
gradually around corners that meet (rounded over `CORNER_ROUNDING` of the smaller block's size), and is
the faces' own for parallel faces. The overlap is split into `n_sub` sub-contacts by the trapezoidal
rule (`sub_contact_place`): the two end ones at its ends (corners), the others evenly between. Each
sub-contact's overlap u_n (> 0 closed) is measured geometrically each cycle, so closure never
drifts; the normal stress is integrated incrementally, d sigma_n = K_n d u_n (which is how a
stress-dependent K_n(sigma_n) integrates eq 5). Shear is incremental: d u_s = (v_B - v_A).t dt,
d tau = K_s d u_s, t = (-n_y, n_x). The force on B is L (sigma_n n - tau t); A gets the opposite.
A column that starts to topple keeps the contact it stood on: the sub-contact at the corner it turns
about stays closed and keeps its state, the others open; landing flat closes them again.

Rules (documented options of the scene format):

* Open: an unbonded sub-contact (tensile strength 0) with u_n <= 0 carries no force.
* Tension cut-off: a bonded sub-contact (tensile strength T > 0) may carry sigma_n down to -T; below,
  it fails: sigma_n = tau = 0, its tensile strength becomes 0 for good and so does its cohesion (a
  crack that has opened does not heal), except that a Barton-Bandis law with ``after_slip = keep``
  re-derives the tangent cohesion at its next update (that cohesion is the envelope's intercept, not
  a bond).
* Slip: |tau| <= c + sigma_n tan(phi); at the limit tau stays on it and the sub-contact is marked
  slipped. Its tensile strength drops to 0 at the first slip (a slipped joint is a fracture: limit
  equilibrium counts no tension). With ``after_slip = keep`` (the default: ductile, as limit
  equilibrium counts the cohesion of the whole plane) the cohesion is kept; with ``zero`` (Itasca's
  Coulomb slip) it drops to 0 at the first slip and stays 0, also through later law updates.
"""

import math

import numba
import numpy as np

from bbmc.dem.layout import (
    AFTER_SLIP,
    AFTER_SLIP_ZERO,
    BLOCK_A,
    BLOCK_B,
    CLOSED,
    COH,
    CORNER_ROUNDING,
    CX,
    CY,
    DILATION,
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
    LAW_PATH,
    LAW_SN,
    LAW_TAU,
    LENGTH,
    MASS,
    MW,
    MX,
    MY,
    NORMAL_BANDIS,
    NORMAL_CONSTANT,
    NORMAL_EQ8,
    NORMAL_LAW,
    P_A,
    P_B,
    P_COH,
    P_D,
    P_DAMAGE,
    P_JCS,
    P_JRC,
    P_K_J,
    P_K_NI,
    P_K_TANGENT,
    P_KN,
    P_KS,
    P_LG_E,
    P_N_J,
    P_PEAK_DISPLACEMENT,
    P_PHI,
    P_PHI_B,
    P_PHI_MAX,
    P_Q,
    P_SHEAR_FLOOR,
    P_SIGMA_REF,
    P_STRENGTH_DIVISOR,
    P_STRESS_FLOOR,
    P_TAU_P_INTERCEPT,
    P_TAU_P_SLOPE,
    P_TAU_ULT_INTERCEPT,
    P_TAU_ULT_SLOPE,
    P_TEN,
    P_V_M,
    PATH,
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
    SIZE,
    SLIPPED,
    SN,
    STEP,
    STRENGTH_BARTON_BANDIS,
    STRENGTH_CONSTANT,
    STRENGTH_LAW,
    STRENGTH_MOBILIZED,
    TAN_DILATION,
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
from bbmc.dem.water import add_water_loads
from bbmc.laws.mobilized import (
    bandis_normal_stiffness,
    damage_coefficient,
    mobilized_dilation_angle,
    mobilized_friction_angle,
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

PARALLEL = -1.0 + 1e-12  # cosine between two edges' normals below which they are parallel faces

# Kernel return codes.
DONE, SEARCH_NEEDED, STEP_ABOVE_CRITICAL, NO_BOUND = 0, 1, 2, 3


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


@numba.njit(cache=True, inline="always")
def _open(subs, s):
    subs[s, SN] = 0.0
    subs[s, TAU] = 0.0
    subs[s, CLOSED] = 0.0


@numba.njit(cache=True, inline="always")
def _normal_share(subs, s, u_mid, slope, half, inv_length, divisor):
    """The normal stress over one sub-contact's share of the overlap, integrated exactly, in place.

    The share runs xi in [-half, half] about its middle; for rigid blocks its closure is linear, u(xi) =
    u_mid + slope xi [m], and so is the stress of the sub-contact's linear law at its current K_n,
    sigma(xi) = K_n (u(xi) - u_0), u_0 its stress-free closure: u_0 = UN - SN / K_n from the last step
    (SN the mean stress over the closed part, UN the closure there), so that a K_n changed by a law
    update keeps that mean (incremental integration at the closed part's centroid, eq 5's way), or
    max(UN, 0) for an unbonded share that was open (closing starts from contact). An unbonded share
    carries no tension: sigma = max(sigma(xi), 0), closed over [lo, hi] (part of it where one end is
    open); a bonded one (T > 0) carries the whole linear stress and fails in tension once its mean is
    below -T / divisor.

    Returns (closed fraction, mean sigma_n over the closed part [Pa], the closed part's middle xi_c
    [m], couple [N m per m]), the fraction -1 when the bond broke in this step. The normal force acts at
    xi_c with that couple on block A and its opposite on B: the stress's first moment about xi_c,
    (hi - lo)^2 (sigma_hi - sigma_lo) / 12, less slope x the share's strain energy, integral of
    sigma^2 / 2 K_n. The energy term is the work of the common line turning with a block whose edge is
    tilted on it (a corner on a face): with it the contact's forces are the gradient of its strain
    energy (checked by finite differences in the tests), so a corner that strikes a face neither gains
    nor loses energy by it."""
    kn = subs[s, KN]
    flexibility = 1.0 / kn
    bonded = subs[s, TEN] > 0.0
    u0 = subs[s, UN] - subs[s, SN] * flexibility if bonded or subs[s, SN] > 0.0 else max(subs[s, UN], 0.0)
    middle = kn * (u_mid - u0)
    grad = kn * slope
    lo, hi = -half, half
    s_lo, s_hi = middle - grad * half, middle + grad * half
    if bonded:
        if middle < -subs[s, TEN] / divisor:
            subs[s, UN] = u_mid + abs(slope) * half
            return -1.0, 0.0, 0.0, 0.0
    elif s_lo <= 0.0 and s_hi <= 0.0:
        subs[s, UN] = u_mid + abs(slope) * half  # the share's largest closure (smallest gap)
        return 0.0, 0.0, 0.0, 0.0
    elif s_lo < 0.0:
        lo, s_lo = -middle / grad, 0.0
    elif s_hi < 0.0:
        hi, s_hi = -middle / grad, 0.0
    mean = 0.5 * (s_lo + s_hi)
    subs[s, UN] = u0 + mean * flexibility
    closed = hi - lo
    energy = closed * (s_lo * s_lo + s_lo * s_hi + s_hi * s_hi) * flexibility * (1.0 / 6.0)
    couple = closed * closed * (s_hi - s_lo) * (1.0 / 12.0) - slope * energy
    return closed * inv_length, mean, 0.5 * (lo + hi), couple


@numba.njit(cache=True, inline="always")
def _shear_share(subs, s, closed, sn, dus, was_closed, after_slip, divisor, dilates):
    """The shear of one sub-contact's share (module docstring), in place, after its normal stress
    (`_normal_share`: closed fraction `closed`, mean sigma_n `sn` over the closed part); its shear and
    tensile strengths divided by `divisor` (strength reduction; 1 otherwise).

    TAU is the mean shear stress over the closed part, d tau = K_s d u_s, d u_s the relative shear
    displacement at the closed part's middle (the mean over it); |tau| <= c + sigma_n tan(phi) (exact
    for the share's resultant, Mohr-Coulomb being linear in sigma_n). Slip state, cohesion loss, shear
    displacement and path are stored once per share: a part that closes takes on the share's tau.

    While it carried normal stress (`was_closed`) it accumulates its shear path |d u_s|, and its
    dilation tan(d_mob) d|u_s|: the asperities ride up as the joint moves away from where it started
    and down as it moves back (never below 0); the law sees the geometric closure plus the dilation so
    far, from the next step (`dilates`: the law has any; the others skip its work)."""
    if was_closed:
        subs[s, PATH] += abs(dus)
        if dilates:
            away = abs(subs[s, US] + dus) - abs(subs[s, US])
            subs[s, DILATION] = max(subs[s, DILATION] + subs[s, TAN_DILATION] * away, 0.0)
    subs[s, US] += dus
    if closed <= 0.0:
        _open(subs, s)
        if closed < 0.0:  # the bond broke in tension: a crack that has opened does not heal
            subs[s, TEN] = 0.0
            subs[s, COH] = 0.0
            subs[s, SLIPPED] = 1.0
            subs[s, LAW_SN] = math.nan
        return
    tau = subs[s, TAU] + subs[s, KS] * dus
    strength = max(subs[s, COH] + sn * subs[s, TANPHI], 0.0) / divisor
    if abs(tau) > strength:
        tau = math.copysign(strength, tau)
        if subs[s, SLIPPED] == 0.0:
            subs[s, SLIPPED] = 1.0
            subs[s, LAW_SN] = math.nan
            subs[s, TEN] = 0.0
            if after_slip == AFTER_SLIP_ZERO:
                subs[s, COH] = 0.0
    subs[s, SN] = sn
    subs[s, TAU] = tau
    subs[s, CLOSED] = closed


@numba.njit(cache=True)
def _overlap(world, vertex_next, ea, eb, nx, ny):
    """Edges ea and eb projected on the line of unit normal n (tangent t = (-n_y, n_x)): the overlap
    [lo, hi] of their projections on t, and each edge's height along n at lo and at hi [m]:
    (lo, hi, A's height at lo, A's at hi, B's at lo, B's at hi)."""
    tx, ty = -ny, nx
    pa, qa, pb, qb = ea, vertex_next[ea], eb, vertex_next[eb]
    sa0, sa1 = world[pa, 0] * tx + world[pa, 1] * ty, world[qa, 0] * tx + world[qa, 1] * ty
    sb0, sb1 = world[pb, 0] * tx + world[pb, 1] * ty, world[qb, 0] * tx + world[qb, 1] * ty
    ha0, ha1 = world[pa, 0] * nx + world[pa, 1] * ny, world[qa, 0] * nx + world[qa, 1] * ny
    hb0, hb1 = world[pb, 0] * nx + world[pb, 1] * ny, world[qb, 0] * nx + world[qb, 1] * ny
    lo, hi = max(min(sa0, sa1), min(sb0, sb1)), min(max(sa0, sa1), max(sb0, sb1))
    ka = (ha1 - ha0) / (sa1 - sa0) if sa1 != sa0 else 0.0
    kb = (hb1 - hb0) / (sb1 - sb0) if sb1 != sb0 else 0.0
    return (
        lo,
        hi,
        ha0 + (lo - sa0) * ka,
        ha0 + (hi - sa0) * ka,
        hb0 + (lo - sb0) * kb,
        hb0 + (hi - sb0) * kb,
    )


@numba.njit(cache=True)
def contact_frame(world, vertex_next, ea, eb, size, a, b):
    """The common line of edge ea (block A) and edge eb (block B), at any angle between them.

    Returns (active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi): the unit normal n (from A towards B; the
    tangent is t = (-n_y, n_x)), the overlap [lo, hi] of the two edges projected on t [m], and the
    heights along n of A's and of B's edge at lo and at hi [m] (the gap, > 0 open, is B's minus A's).
    Inactive when the edges do not face each other (their outward normals make 90 degrees or more)
    or do not overlap in projection.

    The normal is that of the face a corner presses on (UDEC's corner-edge contact): at the closed end
    of the overlap (the end with the smaller gap, first measured along A's normal) sits a vertex of B,
    inside A's edge (n = n_A), or a vertex of A, inside B's edge (n = -n_B). Where the two vertices at
    that end are less than the rounding length apart along the line (corner against corner: the
    rounding length is `CORNER_ROUNDING` times the smaller of the sizes `size[a]`, `size[b]` of the
    blocks a and b) the normal turns linearly from one to the other, as around a corner rounded over
    that length, so it never jumps as a corner slides past another corner. Two parallel edges give
    n = n_A = -n_B whatever the end (and the sizes are not read: a face contact costs no more).
    """
    ax, ay, tax, tay, la = edge_frame(world, vertex_next, ea)
    bx, by, tbx, tby, lb = edge_frame(world, vertex_next, eb)
    facing = tax * tbx + tay * tby  # n_A . n_B
    if facing >= -1e-9:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # first on A's own line: t = t_A, n = n_A = (t_Ay, -t_Ax); B's edge runs against t (facing < 0)
    sa0 = ax * tax + ay * tay
    sb0 = bx * tax + by * tay
    sb1 = sb0 + lb * facing
    height_a = ax * tay - ay * tax
    hb0 = bx * tay - by * tax
    slope_b = (tbx * tay - tby * tax) / facing  # B's height change per unit along t
    lo, hi = max(sa0, sb1), min(sa0 + la, sb0)
    if hi - lo <= 1e-9 * max(la, lb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    b_lo, b_hi = hb0 + (lo - sb0) * slope_b, hb0 + (hi - sb0) * slope_b
    if facing < PARALLEL:  # n_A and -n_B differ by less than 1.5e-6 rad: either is the normal
        return True, tay, -tax, lo, hi, height_a, height_a, b_lo, b_hi
    # > 0: A's vertex lies inside B's edge at the closed end (the end with the smaller gap)
    inside = sa0 - sb1 if b_lo <= b_hi else sb0 - (sa0 + la)
    rounding = CORNER_ROUNDING * min(size[a], size[b])
    w = min(max(0.5 - inside / (2.0 * rounding), 0.0), 1.0)
    if w == 1.0:
        return True, tay, -tax, lo, hi, height_a, height_a, b_lo, b_hi
    nx, ny = w * tay - (1.0 - w) * tby, -w * tax + (1.0 - w) * tbx
    norm = math.sqrt(nx * nx + ny * ny)
    nx, ny = nx / norm, ny / norm
    lo, hi, a_lo, a_hi, b_lo, b_hi = _overlap(world, vertex_next, ea, eb, nx, ny)
    if hi - lo <= 1e-9 * max(la, lb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi


@numba.njit(cache=True)
def share_middle(k, n_sub):
    """The middle of sub-contact k's share of a contact's overlap, as a fraction of the overlap [1]: the
    overlap is cut into n_sub equal shares, each integrated exactly (`_normal_share`)."""
    return (k + 0.5) / n_sub


@numba.njit(cache=True)
def contact_forces(blocks, world, vertex_next, contacts, subs, n_sub, laws, params, dt):
    """Update every sub-contact's stresses and add the contact forces and moments to the blocks.

    Each contact's common line comes from `contact_frame`; a contact whose edges no longer face each
    other or no longer overlap in projection is inactive: zero length, zero stresses. Its overlap is cut
    into n_sub equal shares; the closure u_n (> 0 closed), the distance along the normal between the two
    edges, is linear along each (rigid blocks). A share's normal force is its stress integrated exactly
    (`_normal_share`) and acts at the middle of its closed part, midway between the edges, with the
    couple `_normal_share` gives; its shear force acts there too. A point P = s t + m n of the line
    (s along it, m across) moves relative to A at v_B - v_A + w_B z x (P - c_B) - w_A z x (P - c_A), of
    which the part along t is (v_B - v_A).t + w_B (m - c_B.n) - w_A (m - c_A.n): the shear
    displacement varies along the line with m alone. The shares' forces are summed per contact and
    added to each block once, with their moments P x f = -s f_n - m f_s about the origin moved to the
    block's centroid.
    """
    size = blocks[:, SIZE]
    for c in range(contacts.shape[0]):
        a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
        ea, eb = contacts[c, EDGE_A], contacts[c, EDGE_B]
        active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi = contact_frame(world, vertex_next, ea, eb, size, a, b)
        first = c * n_sub
        if not active:
            for s in range(first, first + n_sub):
                _open(subs, s)
                subs[s, LENGTH] = 0.0
            continue
        tx, ty = -ny, nx
        joint = contacts[c, JOINT_TYPE]
        after_slip = laws[joint, AFTER_SLIP]
        divisor = params[joint, P_STRENGTH_DIVISOR]
        dilates = laws[joint, STRENGTH_LAW] == STRENGTH_MOBILIZED
        span = hi - lo
        per_span = 1.0 / span
        length = span / n_sub
        per_length = n_sub * per_span
        per_share = 1.0 / n_sub
        u_lo, u_rise = a_lo - b_lo, (a_hi - b_hi) - (a_lo - b_lo)
        slope = u_rise * per_span
        m_lo, m_rise = 0.5 * (a_lo + b_lo), 0.5 * ((a_hi - a_lo) + (b_hi - b_lo))
        wa, wb = blocks[a, W], blocks[b, W]
        slip_rate = (
            (blocks[b, VX] - blocks[a, VX]) * tx
            + (blocks[b, VY] - blocks[a, VY]) * ty
            - wb * (blocks[b, X] * nx + blocks[b, Y] * ny)
            + wa * (blocks[a, X] * nx + blocks[a, Y] * ny)
        )
        fx_sum, fy_sum, moment = 0.0, 0.0, 0.0
        for k in range(n_sub):
            s = first + k
            f = (k + 0.5) * per_share
            u_mid = u_lo + f * u_rise
            if dilates:
                u_mid += subs[s, DILATION]
            was_closed = subs[s, SN] > 0.0
            closed, sn, centre, couple = _normal_share(
                subs, s, u_mid, slope, 0.5 * length, per_length, divisor
            )
            f += centre * per_span  # the closed part's middle, where the share's forces act
            along, middle = lo + f * span, m_lo + f * m_rise
            dus = (slip_rate + (wb - wa) * middle) * dt
            _shear_share(subs, s, closed, sn, dus, was_closed, after_slip, divisor, dilates)
            subs[s, LENGTH] = length
            subs[s, CX] = along * tx + middle * nx
            subs[s, CY] = along * ty + middle * ny
            carried = length * subs[s, CLOSED]
            fn, fs = carried * subs[s, SN], carried * subs[s, TAU]
            fx_sum += fn * nx - fs * tx
            fy_sum += fn * ny - fs * ty
            moment -= along * fn + middle * fs + couple
        blocks[b, FX] += fx_sum
        blocks[b, FY] += fy_sum
        blocks[b, FM] += moment - (blocks[b, X] * fy_sum - blocks[b, Y] * fx_sum)
        blocks[a, FX] -= fx_sum
        blocks[a, FY] -= fy_sum
        blocks[a, FM] -= moment - (blocks[a, X] * fy_sum - blocks[a, Y] * fx_sum)


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
def _mobilize(subs, s, floored, p):
    """The mobilized Barton-Bandis law at the sub-contact's sigma_n and shear path (Barton 1982): the
    secant tan(phi_mob) (c = 0: the strength sigma_n tan(phi_mob) is exact at this sigma_n and path) and
    the dilation angle's tangent, both at max(sigma_n, stress floor) (an open joint carries no strength
    whatever its angle; it is the angle it will close with, and lg(JCS/sigma_n) has no limit at 0)."""
    path, jrc, jcs, phi_r, peak = subs[s, PATH], p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PEAK_DISPLACEMENT]
    subs[s, TANPHI] = math.tan(mobilized_friction_angle(path, floored, jrc, jcs, phi_r, peak, p[P_PHI_MAX]))
    subs[s, COH] = 0.0
    damage = p[P_DAMAGE] if p[P_DAMAGE] > 0.0 else damage_coefficient(floored, jrc, jcs)
    subs[s, TAN_DILATION] = math.tan(mobilized_dilation_angle(path, floored, jrc, jcs, phi_r, peak, damage))


@numba.njit(cache=True)
def update_joint_laws(contacts, subs, n_sub, laws, params, changed_only):
    """Re-evaluate K_n, K_s, c and phi of every sub-contact of a stress-dependent joint type.

    `changed_only`: skip a sub-contact whose sigma_n, tau and (mobilized law) shear path are those of
    its last evaluation (an open one stays at 0, 0) and that has not slipped or failed since: the laws
    would give the same values.

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
            if (
                changed_only
                and sigma == subs[s, LAW_SN]
                and subs[s, TAU] == subs[s, LAW_TAU]
                and (subs[s, PATH] == subs[s, LAW_PATH] or laws[j, STRENGTH_LAW] != STRENGTH_MOBILIZED)
            ):
                continue
            subs[s, LAW_SN] = sigma
            subs[s, LAW_TAU] = subs[s, TAU]
            subs[s, LAW_PATH] = subs[s, PATH]
            floored = max(sigma, p[P_STRESS_FLOOR])
            if laws[j, NORMAL_LAW] == NORMAL_EQ8:
                subs[s, KN] = normal_stiffness(floored, p[P_Q], p[P_LG_E])
            elif laws[j, NORMAL_LAW] == NORMAL_BANDIS:
                subs[s, KN] = bandis_normal_stiffness(floored, p[P_K_NI], p[P_V_M])
            if laws[j, SHEAR_LAW] != SHEAR_CONSTANT:
                subs[s, KS] = _shear_stiffness(laws[j, SHEAR_LAW], floored, abs(subs[s, TAU]), p)
            if laws[j, STRENGTH_LAW] == STRENGTH_MOBILIZED:
                _mobilize(subs, s, floored, p)
            elif laws[j, STRENGTH_LAW] == STRENGTH_BARTON_BANDIS:
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
    the type's stress floor, or (mobilized law) a shear path longer by `change` x delta_peak (so an
    update is due before the interval is up)."""
    for c in range(contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        if (
            laws[j, STRENGTH_LAW] == STRENGTH_CONSTANT
            and laws[j, NORMAL_LAW] == NORMAL_CONSTANT
            and (laws[j, SHEAR_LAW] == SHEAR_CONSTANT)
        ):
            continue
        floor = params[j, P_STRESS_FLOOR]
        peak = params[j, P_PEAK_DISPLACEMENT]
        for s in range(c * n_sub, (c + 1) * n_sub):
            if peak > 0.0 and subs[s, PATH] - subs[s, LAW_PATH] > change * peak:
                return True
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
    water_surface,
    water_unit_weight,
    damping,
    search_distance,
    time_step_mode,
    safety,
    fixed_dt,
):
    """Run up to n_steps cycles. Returns (cycles done, DONE | SEARCH_NEEDED | STEP_ABOVE_CRITICAL).

    Water pressure (`water_surface`, `water_unit_weight`; `bbmc.dem.water`) is added to the loads.
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
        add_water_loads(blocks, world, vertex_start, vertex_next, moving, water_surface, water_unit_weight)
        contact_forces(blocks, world, vertex_next, contacts, subs, n_sub, laws, params, dt)
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
