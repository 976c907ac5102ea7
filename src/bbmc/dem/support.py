"""Support elements in the cycle: anchors and grouted-bolt crossings pulling on the blocks they join.

Each element joins a point of block A to a point of block B (`layout`'s support columns), in SI per
metre run:

* Anchor (end-anchored tendon): axial force P = P_0 + k (e - e_p) along the line from A's point to
  B's, where e = L - L_0 is its elongation and k = E A / L_0 per spacing; elastic-perfectly plastic
  at its capacity T (e_p grows), slack (0) below zero; it ruptures once e > rupture strain x L_0.
* Grouted-bolt crossing (UDEC's local reinforcement): the relative displacement d of B's point from
  A's (the two coincide at the start, on the joint) is split along the bolt's axis u, turned by the
  blocks' mean rotation, and across it, s: an axial force k_a (d.u - e_p) and, with a shear capacity,
  a shear force k_s (d.s - e_s), each elastic-perfectly plastic at its capacity; it ruptures once
  |d| > rupture strain x the debonded length.

The force pulls A towards B and B back (tension > 0). With `divisor` > 1 (strength reduction of the
support, RocPlane's passive form), the part of the force along the joint the element crosses (its
tangent, turning with block A) is divided by it; the part across the joint is kept.
"""

import math

import numba

from bbmc.dem import layout as L


@numba.njit(cache=True)
def _point(blocks, b, x, y):
    """World position of the point (x, y) of block b's frame [m], and its arm from the centroid."""
    c, s = math.cos(blocks[b, L.TH]), math.sin(blocks[b, L.TH])
    rx, ry = c * x - s * y, s * x + c * y
    return blocks[b, L.X] + rx, blocks[b, L.Y] + ry, rx, ry


@numba.njit(cache=True)
def _elastic_plastic(stiffness, displacement, slip, capacity):
    """(force, slip): k (d - slip) held within +-capacity, the slip taking up the excess."""
    force = stiffness * (displacement - slip)
    if force > capacity:
        return capacity, displacement - capacity / stiffness
    if force < -capacity:
        return -capacity, displacement + capacity / stiffness
    return force, slip


@numba.njit(cache=True)
def _anchor(e, support, xa, ya, xb, yb):
    """The anchor's pull on A (fx, fy) [N/m] from its ends now; updates its force and state."""
    dx, dy = xb - xa, yb - ya
    length = math.hypot(dx, dy)
    stretch = length - support[e, L.FREE_LENGTH]
    if stretch > support[e, L.RUPTURE] * support[e, L.FREE_LENGTH]:
        support[e, L.BROKEN] = 1.0
        support[e, L.AXIAL] = 0.0
        return 0.0, 0.0
    k, cap = support[e, L.K_AXIAL], support[e, L.CAP_AXIAL]
    force = support[e, L.PRETENSION] + k * (stretch - support[e, L.SLIP_AXIAL])
    if force > cap:
        support[e, L.SLIP_AXIAL] = stretch - (cap - support[e, L.PRETENSION]) / k
        support[e, L.YIELDED] = 1.0
        force = cap
    force = max(force, 0.0)
    support[e, L.AXIAL] = force
    return force * dx / length, force * dy / length


@numba.njit(cache=True)
def _crossing(blocks, e, a, b, support, xa, ya, xb, yb):
    """A grouted crossing's pull on A (fx, fy) [N/m] from the relative displacement of its sides."""
    dx, dy = xb - xa, yb - ya
    if math.hypot(dx, dy) > support[e, L.RUPTURE] * support[e, L.FREE_LENGTH]:
        support[e, L.BROKEN] = 1.0
        support[e, L.AXIAL] = 0.0
        support[e, L.SHEAR] = 0.0
        return 0.0, 0.0
    turn = 0.5 * (blocks[a, L.TH] + blocks[b, L.TH])
    c, s = math.cos(turn), math.sin(turn)
    ux = c * support[e, L.DIR_X] - s * support[e, L.DIR_Y]
    uy = s * support[e, L.DIR_X] + c * support[e, L.DIR_Y]
    axial, slip = _elastic_plastic(
        support[e, L.K_AXIAL], dx * ux + dy * uy, support[e, L.SLIP_AXIAL], support[e, L.CAP_AXIAL]
    )
    support[e, L.SLIP_AXIAL] = slip
    shear = 0.0
    if support[e, L.CAP_SHEAR] > 0.0:
        shear, slip = _elastic_plastic(
            support[e, L.K_SHEAR], -dx * uy + dy * ux, support[e, L.SLIP_SHEAR], support[e, L.CAP_SHEAR]
        )
        support[e, L.SLIP_SHEAR] = slip
        if abs(shear) >= support[e, L.CAP_SHEAR]:
            support[e, L.YIELDED] = 1.0
    if abs(axial) >= support[e, L.CAP_AXIAL]:
        support[e, L.YIELDED] = 1.0
    support[e, L.AXIAL] = axial
    support[e, L.SHEAR] = shear
    return axial * ux - shear * uy, axial * uy + shear * ux


@numba.njit(cache=True)
def support_forces(blocks, support_blocks, support, divisor):
    """Add every intact element's forces and moments to its two blocks (module docstring)."""
    for e in range(support.shape[0]):
        if support[e, L.BROKEN] > 0.0:
            continue
        a, b = support_blocks[e, 0], support_blocks[e, 1]
        xa, ya, rxa, rya = _point(blocks, a, support[e, L.AX], support[e, L.AY])
        xb, yb, rxb, ryb = _point(blocks, b, support[e, L.BX], support[e, L.BY])
        if support[e, L.KIND] == L.ANCHOR:
            fx, fy = _anchor(e, support, xa, ya, xb, yb)
        else:
            fx, fy = _crossing(blocks, e, a, b, support, xa, ya, xb, yb)
        if divisor != 1.0:
            c, s = math.cos(blocks[a, L.TH]), math.sin(blocks[a, L.TH])
            tx = c * support[e, L.PLANE_X] - s * support[e, L.PLANE_Y]
            ty = s * support[e, L.PLANE_X] + c * support[e, L.PLANE_Y]
            along = (fx * tx + fy * ty) * (1.0 / divisor - 1.0)
            fx += along * tx
            fy += along * ty
        blocks[a, L.FX] += fx
        blocks[a, L.FY] += fy
        blocks[a, L.FM] += rxa * fy - rya * fx
        blocks[b, L.FX] -= fx
        blocks[b, L.FY] -= fy
        blocks[b, L.FM] -= rxb * fy - ryb * fx
