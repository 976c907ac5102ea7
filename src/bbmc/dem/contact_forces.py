"""Contact forces: each sub-contact's share of the overlap integrated exactly, Mohr-Coulomb slip.

Each share's closure u_n (> 0 closed) is measured geometrically each cycle (`bbmc.dem.contact_geometry`),
so closure never drifts; its normal stress is integrated exactly over the share at the sub-contact's
current K_n (`_normal_share`), its shear incrementally, d u_s = (v_B - v_A).t dt, d tau = K_s d u_s,
t = (-n_y, n_x). The force on B is L (sigma_n n - tau t); A gets the opposite. A column that starts to
topple keeps the contact it stood on: the share at the corner it turns about stays closed and keeps its
state, the others open; landing flat closes them again. K_n, K_s, c and phi come from the joint laws
(`bbmc.dem.joint_state`).

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

from bbmc.dem.contact_geometry import contact_frame
from bbmc.dem.layout import (
    AFTER_SLIP,
    AFTER_SLIP_ZERO,
    BLOCK_A,
    BLOCK_B,
    CLOSED,
    COH,
    CX,
    CY,
    DILATION,
    EDGE_A,
    EDGE_B,
    FAILED_IN_TENSION,
    FM,
    FX,
    FY,
    JOINT_TYPE,
    KN,
    KS,
    LAW_SN,
    LENGTH,
    P_STRENGTH_DIVISOR,
    PATH,
    SIZE,
    SLIPPED,
    SLIPPED_IN_SHEAR,
    SN,
    STRENGTH_LAW,
    STRENGTH_MOBILIZED,
    TAN_DILATION,
    TANPHI,
    TAU,
    TEN,
    UN,
    US,
    VX,
    VY,
    W,
    X,
    Y,
)


@numba.njit(cache=True, inline="always")
def _open(subs, s):
    subs[s, SN] = 0.0
    subs[s, TAU] = 0.0
    subs[s, CLOSED] = 0.0


@numba.njit(cache=True, inline="always")
def _break_in_tension(subs, law_state, s):
    """A share's bond has broken in tension: no tensile strength, no cohesion, from now on."""
    subs[s, TEN] = 0.0
    subs[s, COH] = 0.0
    subs[s, SLIPPED] = FAILED_IN_TENSION
    law_state[s, LAW_SN] = math.nan


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
def _shear_share(subs, law_state, s, closed, sn, dus, was_closed, after_slip, divisor, dilates):
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
            subs[s, DILATION] = max(subs[s, DILATION] + law_state[s, TAN_DILATION] * away, 0.0)
    subs[s, US] += dus
    if closed <= 0.0:
        _open(subs, s)
        if closed < 0.0:  # the bond broke in tension: a crack that has opened does not heal
            _break_in_tension(subs, law_state, s)
        return
    tau = subs[s, TAU] + subs[s, KS] * dus
    strength = max(subs[s, COH] + sn * subs[s, TANPHI], 0.0) / divisor
    if abs(tau) > strength:
        tau = math.copysign(strength, tau)
        if subs[s, SLIPPED] == 0.0:
            subs[s, SLIPPED] = SLIPPED_IN_SHEAR
            law_state[s, LAW_SN] = math.nan
            subs[s, TEN] = 0.0
            if after_slip == AFTER_SLIP_ZERO:
                subs[s, COH] = 0.0
    subs[s, SN] = sn
    subs[s, TAU] = tau
    subs[s, CLOSED] = closed


@numba.njit(cache=True, inline="always")
def _contact(c, blocks, world, vertex_next, contacts, subs, law_state, n_sub, laws, params, dt, size):
    """Contact c's shares updated in place (`contact_forces`); returns its force on block B and the
    moments of that force about B's and about A's centroid: (fx [N], fy [N], moment on B [N m],
    moment of the opposite force on A, negated [N m]), zeros for an inactive contact."""
    a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
    ea, eb = contacts[c, EDGE_A], contacts[c, EDGE_B]
    active, nx, ny, lo, hi, a_lo, a_hi, b_lo, b_hi = contact_frame(world, vertex_next, ea, eb, size, a, b)
    first = c * n_sub
    if not active:  # edges that no longer face each other: a bond still held has broken
        for s in range(first, first + n_sub):
            _open(subs, s)
            subs[s, LENGTH] = 0.0
            if subs[s, SLIPPED] == 0.0 and (subs[s, TEN] > 0.0 or subs[s, COH] > 0.0):
                _break_in_tension(subs, law_state, s)
        return 0.0, 0.0, 0.0, 0.0
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
        closed, sn, centre, couple = _normal_share(subs, s, u_mid, slope, 0.5 * length, per_length, divisor)
        f += centre * per_span  # the closed part's middle, where the share's forces act
        along, middle = lo + f * span, m_lo + f * m_rise
        dus = (slip_rate + (wb - wa) * middle) * dt
        _shear_share(subs, law_state, s, closed, sn, dus, was_closed, after_slip, divisor, dilates)
        subs[s, LENGTH] = length
        subs[s, CX] = along * tx + middle * nx
        subs[s, CY] = along * ty + middle * ny
        carried = length * subs[s, CLOSED]
        fn, fs = carried * subs[s, SN], carried * subs[s, TAU]
        fx_sum += fn * nx - fs * tx
        fy_sum += fn * ny - fs * ty
        moment -= along * fn + middle * fs + couple
    return (
        fx_sum,
        fy_sum,
        moment - (blocks[b, X] * fy_sum - blocks[b, Y] * fx_sum),
        moment - (blocks[a, X] * fy_sum - blocks[a, Y] * fx_sum),
    )


@numba.njit(cache=True, parallel=True)
def contact_forces(
    blocks, world, vertex_next, contacts, subs, law_state, n_sub, laws, params, dt, threaded, per_contact
):
    """Update every sub-contact's stresses and add the contact forces and moments to the blocks
    (`law_state`: the sub-contacts' law state, read by the mobilized law's dilation, written where a
    share slips or breaks).

    Each contact's common line comes from `contact_frame`; a contact whose edges no longer face each
    other or no longer overlap in projection is inactive: zero length, zero stresses. Its overlap is cut
    into n_sub equal shares; the closure u_n (> 0 closed), the distance along the normal between the two
    edges, is linear along each (rigid blocks). A share's normal force is its stress integrated exactly
    (`_normal_share`) and acts at the middle of its closed part, midway between the edges, with the
    couple `_normal_share` gives; its shear force acts there too. A point P = s t + m n of the line
    (s along it, m across) moves relative to A at v_B - v_A + w_B z x (P - c_B) - w_A z x (P - c_A), of
    which the part along t is (v_B - v_A).t + w_B (m - c_B.n) - w_A (m - c_A.n): the shear
    displacement varies along the line with m alone. The shares' forces are summed per contact
    (`_contact`) and added to each block in contact order, with their moments P x f = -s f_n - m f_s
    about the origin moved to the block's centroid.

    `threaded`: every thread of numba's pool takes contacts, each contact writing its sums into its own
    row of `per_contact` (float (n_contacts, 4): fx, fy [N], moment on B, negated moment on A [N m]),
    and the blocks are left for `add_contact_sums`, which adds them in the same order: the result is
    the same to the bit for any number of threads. Else one thread adds them here (`per_contact` unread).
    """
    size = blocks[:, SIZE]
    if threaded:
        for c in numba.prange(contacts.shape[0]):
            fx, fy, moment_b, moment_a = _contact(
                c, blocks, world, vertex_next, contacts, subs, law_state, n_sub, laws, params, dt, size
            )
            per_contact[c, 0] = fx
            per_contact[c, 1] = fy
            per_contact[c, 2] = moment_b
            per_contact[c, 3] = moment_a
        return
    for c in range(contacts.shape[0]):
        fx, fy, moment_b, moment_a = _contact(
            c, blocks, world, vertex_next, contacts, subs, law_state, n_sub, laws, params, dt, size
        )
        a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
        blocks[b, FX] += fx
        blocks[b, FY] += fy
        blocks[b, FM] += moment_b
        blocks[a, FX] -= fx
        blocks[a, FY] -= fy
        blocks[a, FM] -= moment_a


@numba.njit(cache=True, inline="always")
def add_contact_sums(blocks, i, per_contact, block_start, block_contacts):
    """Add to block i the sums of its contacts that a threaded `contact_forces` left in `per_contact`,
    in contact order, as one thread adds them (`block_contacts`: CSR by block from `block_start`, int64
    (n_blocks + 1,); an entry c >= 0 is contact c with the block as B, -1 - c as A;
    `kernels.block_contacts_of`)."""
    for k in range(block_start[i], block_start[i + 1]):
        entry = block_contacts[k]
        if entry >= 0:
            blocks[i, FX] += per_contact[entry, 0]
            blocks[i, FY] += per_contact[entry, 1]
            blocks[i, FM] += per_contact[entry, 2]
        else:
            c = -1 - entry
            blocks[i, FX] -= per_contact[c, 0]
            blocks[i, FY] -= per_contact[c, 1]
            blocks[i, FM] -= per_contact[c, 3]
