"""Contact forces of the 3D engine: for every candidate pair, the narrow phase, each sub-contact's
normal stress integrated exactly over its closed share, its shear stress as a vector in the contact
plane, Mohr-Coulomb slip, and the forces and torques summed onto the two blocks.

Per pair (a, b), each step (`contact_forces`): the separating axis (started from the last step's) and
the contact patch (`bbmc.dem3d.contact_geometry`). Apart, or touching with no area: the pair carries
nothing and forgets its shear. A face–face contact carries one sub-contact per triangle of the
reference face's triangulation (`face_shares`), a degenerate contact (edge–face, vertex–face, edge–edge)
one at the patch's centroid with its nominal area and the penetration depth as closure. Sub-contacts
are keyed by the pair, the reference face (KEY, `POINT` for a degenerate contact) and the triangle's
index, so a triangle fixed to the reference block keeps its history from step to step. A face–face
contact takes A's face as the reference even where the separating axis is B's face (the two lie within
`FACE_ANGLE` of each other): the pair's A is the sliding or falling block (`bbmc.dem3d.solver.search`),
so its sub-contacts tile its own face and travel with it; a base's face as the reference (which the
axis test picks once the block tilts by 1e-6 rad on a large base) would meet the sliding footprint with
triangles whose shares are born unloaded at its leading edge.

Normal: sigma_n = K_n u, u the closure (> 0 closed), a linear spring bed integrated exactly over the
closed part of the share: the force K_n A u(c) at the closed part's centroid c and the couple of the
stress's gradient (`face_shares`). Compression positive. n is the separating axis, from A towards B.

Shear: the stress vector tau (world, in the plane) and the shear displacement u_s, both of B relative to
A, are carried from step to step. Each step they are first rotated onto the current plane as 3DEC does:
the normal component projected out and the length kept. Then d u_s = (v_rel - (v_rel . n) n) dt, v_rel
= v_B + w_B x (c - x_B) - v_A - w_A x (c - x_A) at the share's centroid, tau += K_s d u_s (trial), and
|tau| <= c + sigma_n tan(phi) (the joint type's strength at this sigma_n, `bbmc.dem3d.joint_laws`): above
it tau is scaled back along the trial direction and the share is marked slipped. A share slips as a
whole, so its stress is taken to mobilise its local strength c + sigma(x) tan(phi) (linear over it as
sigma is) by the same fraction everywhere, stuck or slipping: its shear force acts at the strength's
centroid, the friction's part A tau tan(phi) sigma / limit at the centre of pressure c + (S_P g) /
(A u(c)), the cohesion's at the centroid c. At the centroid alone, the lean of sigma across a share
whose triangles are not symmetric about the slip direction gave a sliding block a spurious yaw torque
(2 deg of turn in 1.5 s at refinement 0, falling 4 x per refinement); at the centroid while stuck and
the centre of pressure once slipped, the yaw torque jumped each time a share crossed its limit, and a
block at the limit shook between the two without end: a resting block crept, and the wedges' factor of
safety hung on the refinement (spread 0.8 % over refinements 0-2, now 0.2 %) and, at refinement 1, on
the step and the damping. Twist: a relative spin w_n about n shears a share by w_n x r about its
centroid, whose stresses (K_s w_n dt (n x r), summed over the share) add no force but the torque
-K_s J_P w_n dt about n (J_P the closed part's polar moment), kept in TWIST from step to step and
scaled back with the stress when the share slips (by limit / trial, continuously: dropping it at once
was another such jump; a share slipping on fades it geometrically): without it a share resisted
twisting only by its centroid's lever, and a block on a few shares (a strip of a base that rocks open)
drifted round its normal. The path |d u_s| is
summed while closed; the strength is read at the path before this step's increment (as the 2D law
update reads it). The mobilized law's dilation (`bbmc.dem3d.joint_laws`) adds DILATION to the share's
closure, sigma_n = K_n (u + DILATION) over its geometrically closed part, and grows by tan(d_mob) x the
change of |u_s| in the step. Joint water: the joint type's given uniform pressure p acts on the closed
part, p A along n, pushing the blocks apart; the springs carry the effective stress sigma_n', which the
strength sees (the phreatic table loads the blocks' faces instead: `bbmc.dem3d.water`). The force on B
is A ((sigma_n' + p) n - tau) plus the couple, on A its opposite; their
torques about the centroids are r x f. A share that opens loses its shear. Where a pair's KEY changes
(a face contact tilting onto an edge, or back) the new sub-contacts start from the pair's last shear
force shared uniformly over the new closed area, so the shear force carries over.

Threads: each pair is updated on its own (`contact_forces`, a numba prange over pairs when `threaded`),
writing only its own rows: of `contacts`, `values`, `subs`, and of `loads`, each share's force and couple
on B. Each block then adds its pairs' shares in pair order and, within a pair, share order
(`add_contact_loads`, over the block's pairs listed at each search by `block_pairs`): the same additions
in the same order as one thread adding each share to both blocks as it goes, so the result is the same
to the bit for any number of threads (never an atomic or racy add).
"""

import math

import numba
import numpy as np

from bbmc.dem3d.contact_geometry import (
    AXIS_FACE_A,
    AXIS_FACE_B,
    FACE_FACE,
    contact_patch,
    separating_axis,
)
from bbmc.dem3d.face_contact import face_shares
from bbmc.dem3d.joint_laws import P_KN, P_KS, P_PRESSURE, strength
from bbmc.dem3d.layout import FX, TX, VX, WX, X
from bbmc.incidence import block_contacts

# --- contacts: int64 (n_pairs, CONTACT_COLUMNS) -----------------------------------------------------
BLOCK_A, BLOCK_B = 0, 1
JOINT_TYPE = 2
AXIS_KIND, AXIS_I, AXIS_J = 3, 4, 5  # the last separating axis (`separating_axis`'s cache); -1: none
KEY = 6  # the reference face the sub-contacts belong to; POINT: a degenerate contact; NONE: apart
KIND = 7  # contact kind (`contact_geometry`'s FACE_FACE ...), -1 when apart
FIRST_SUB, SUB_COUNT = 8, 9  # the pair's rows of `subs`
CONTACT_COLUMNS = 10
POINT, NONE = -1, -2

# --- contact_values: float64 (n_pairs, CONTACT_VALUES) ----------------------------------------------
FSX, FSY, FSZ = 0, 1, 2  # shear force on B of the last step [N], world
FN = 3  # effective normal force on B [N] (the springs'; the water's p A not counted)
AREA_CLOSED = 4  # closed area [m²]
CONTACT_VALUES = 5

# --- subs: float64 (n_subs, SUB_COLUMNS), sub-contact k of a pair at row FIRST_SUB + k ------------------
TAUX, TAUY, TAUZ = 0, 1, 2  # shear stress of B relative to A [Pa], world, in the contact plane
USX, USY, USZ = 3, 4, 5  # shear displacement of B relative to A [m], world, in the contact plane
SN = 6  # normal stress, the mean over the closed part [Pa]
AREA = 7  # the closed part's area [m²]
CX, CY, CZ = 8, 9, 10  # the closed part's centroid [m], world
POLAR = 11  # the closed part's polar second moment about its centroid [m⁴]
SLIPPED = 12  # 1 once it has slipped
PATH = 13  # shear path while closed, sum of |d u_s| [m]
TWIST = 14  # torque on B about n of the share's shear springs twisted about it [N m]
PRESSURE = 15  # the joint type's given water pressure on the closed part [Pa]
DILATION = 16  # the mobilized law's opening by dilation so far [m], added to the closure
SUB_COLUMNS = 17

# --- loads: float64 (n_subs, LOAD_COLUMNS), the force and couple a share puts on B this step ---------
LFX, LMX = 0, 3  # force on B [N] at the share's centroid (CX..), couple on B [N m]; zero: none; world
LOAD_COLUMNS = 6


@numba.njit(cache=True, inline="always")
def _onto_plane(subs, s, first, nx, ny, nz):
    """Vector subs[s, first:first + 3] rotated onto the plane of normal n: the normal component
    projected out, the length kept (3DEC's update of a shear vector)."""
    x, y, z = subs[s, first], subs[s, first + 1], subs[s, first + 2]
    length = math.sqrt(x * x + y * y + z * z)
    if length == 0.0:
        return
    d = x * nx + y * ny + z * nz
    x, y, z = x - d * nx, y - d * ny, z - d * nz
    projected = math.sqrt(x * x + y * y + z * z)
    scale = length / projected if projected > 0.0 else 0.0
    subs[s, first], subs[s, first + 1], subs[s, first + 2] = x * scale, y * scale, z * scale


@numba.njit(cache=True, inline="always")
def _length(subs, s, first):
    """|subs[s, first:first + 3]|."""
    return math.sqrt(subs[s, first] ** 2 + subs[s, first + 1] ** 2 + subs[s, first + 2] ** 2)


@numba.njit(cache=True, inline="always")
def _velocity(blocks, i, px, py, pz):
    """Velocity of block i's material point at p, v + w x (p - x) [m/s]."""
    rx, ry, rz = px - blocks[i, X], py - blocks[i, X + 1], pz - blocks[i, X + 2]
    wx, wy, wz = blocks[i, WX], blocks[i, WX + 1], blocks[i, WX + 2]
    return (
        blocks[i, VX] + wy * rz - wz * ry,
        blocks[i, VX + 1] + wz * rx - wx * rz,
        blocks[i, VX + 2] + wx * ry - wy * rx,
    )


@numba.njit(cache=True, inline="always")
def _add(blocks, i, sign, fx, fy, fz, px, py, pz, mx, my, mz):
    """Add sign x the force f at p and the couple m to block i: force and torque (p - x) x f + m."""
    rx, ry, rz = px - blocks[i, X], py - blocks[i, X + 1], pz - blocks[i, X + 2]
    blocks[i, FX] += sign * fx
    blocks[i, FX + 1] += sign * fy
    blocks[i, FX + 2] += sign * fz
    blocks[i, TX] += sign * (ry * fz - rz * fy + mx)
    blocks[i, TX + 1] += sign * (rz * fx - rx * fz + my)
    blocks[i, TX + 2] += sign * (rx * fy - ry * fx + mz)


@numba.njit(cache=True)
def _release(contacts, values, subs, c):
    """Pair c is apart: no force, no shear history."""
    contacts[c, KEY], contacts[c, KIND] = NONE, -1
    values[c, :] = 0.0
    first = contacts[c, FIRST_SUB]
    subs[first : first + contacts[c, SUB_COUNT], :] = 0.0


@numba.njit(cache=True)
def _pair(c, blocks, geometry, contacts, values, subs, loads, law_codes, law_params, refine, dt):
    """Pair c's sub-contacts updated and their forces and couples on B left in `loads` (module
    docstring); only the pair's own rows are written."""
    vertices, vertex_start, face_vertices, face_start, block_face_start, face_normal, size = geometry
    a, b = contacts[c, BLOCK_A], contacts[c, BLOCK_B]
    loads[contacts[c, FIRST_SUB] : contacts[c, FIRST_SUB] + contacts[c, SUB_COUNT], :] = 0.0
    scale = min(size[a], size[b])
    sep, axis, i, j, nx, ny, nz = separating_axis(
        vertices, vertex_start, face_vertices, face_start, block_face_start, face_normal, a, b, scale, 0.0,
        contacts[c, AXIS_KIND], contacts[c, AXIS_I], contacts[c, AXIS_J],
    )  # fmt: skip
    contacts[c, AXIS_KIND], contacts[c, AXIS_I], contacts[c, AXIS_J] = axis, i, j
    if sep > 0.0:
        _release(contacts, values, subs, c)
        return
    kind, ref, inc, patch_area, px, py, pz = contact_patch(
        vertices,
        vertex_start,
        face_vertices,
        face_start,
        block_face_start,
        face_normal,
        a,
        b,
        scale,
        axis,
        i,
        j,
    )
    if kind == FACE_FACE and axis == AXIS_FACE_B:  # A's face as the reference (module docstring)
        kind, ref, inc, patch_area, px, py, pz = contact_patch(
            vertices, vertex_start, face_vertices, face_start, block_face_start, face_normal, a, b, scale,
            AXIS_FACE_A, inc, -1,
        )  # fmt: skip
        axis, nx, ny, nz = AXIS_FACE_A, face_normal[ref, 0], face_normal[ref, 1], face_normal[ref, 2]
    if patch_area <= 0.0:
        _release(contacts, values, subs, c)
        return
    if kind == FACE_FACE:
        area, centroid, closure, couple, polar = face_shares(
            vertices, face_vertices, face_start, face_normal, ref, inc, refine
        )
        key = ref  # A's face: the couples are of B, which its normal n pushes
    else:
        area, closure, polar = np.array([patch_area]), np.array([-sep]), np.zeros(1)
        centroid, couple = np.array([[px, py, pz]]), np.zeros((1, 3))
        key = POINT
    first, count, m = contacts[c, FIRST_SUB], contacts[c, SUB_COUNT], area.size
    joint = contacts[c, JOINT_TYPE]
    kn, ks = law_params[joint, P_KN], law_params[joint, P_KS]
    renewed = key != contacts[c, KEY]
    closed_area = 0.0
    for k in range(m):
        closed_area += area[k]
    if renewed:
        subs[first : first + count, :] = 0.0
        carry = 1.0 / closed_area if closed_area > 0.0 else 0.0
        for k in range(m):
            subs[first + k, TAUX] = -values[c, FSX] * carry
            subs[first + k, TAUY] = -values[c, FSY] * carry
            subs[first + k, TAUZ] = -values[c, FSZ] * carry
    contacts[c, KEY], contacts[c, KIND] = key, kind
    fsx, fsy, fsz, fn = 0.0, 0.0, 0.0, 0.0
    for k in range(m):
        s = first + k
        subs[s, AREA], subs[s, POLAR] = area[k], polar[k]
        subs[s, CX], subs[s, CY], subs[s, CZ] = centroid[k, 0], centroid[k, 1], centroid[k, 2]
        if area[k] <= 0.0:
            for col in (TAUX, TAUY, TAUZ, USX, USY, USZ, SN, TWIST, PRESSURE, DILATION):
                subs[s, col] = 0.0
            continue
        gx, gy, gz = centroid[k, 0], centroid[k, 1], centroid[k, 2]
        sn = kn * (closure[k] + subs[s, DILATION])
        _onto_plane(subs, s, TAUX, nx, ny, nz)
        _onto_plane(subs, s, USX, nx, ny, nz)
        vb = _velocity(blocks, b, gx, gy, gz)
        va = _velocity(blocks, a, gx, gy, gz)
        rx, ry, rz = vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]
        d = rx * nx + ry * ny + rz * nz
        dx, dy, dz = (rx - d * nx) * dt, (ry - d * ny) * dt, (rz - d * nz) * dt
        path, away = subs[s, PATH], -_length(subs, s, USX)
        subs[s, USX] += dx
        subs[s, USY] += dy
        subs[s, USZ] += dz
        subs[s, PATH] += math.sqrt(dx * dx + dy * dy + dz * dz)
        away += _length(subs, s, USX)
        tx, ty, tz = subs[s, TAUX] + ks * dx, subs[s, TAUY] + ks * dy, subs[s, TAUZ] + ks * dz
        cohesion, tan_phi, tan_dilation = strength(
            law_codes, law_params, joint, sn, subs[s, SLIPPED] != 0.0, path
        )
        subs[s, DILATION] = max(subs[s, DILATION] + tan_dilation * away, 0.0)
        limit = max(cohesion + sn * tan_phi, 0.0)
        trial = math.sqrt(tx * tx + ty * ty + tz * tz)
        a_k = area[k]
        mx, my, mz = kn * couple[k, 0], kn * couple[k, 1], kn * couple[k, 2]
        spin = (
            (blocks[b, WX] - blocks[a, WX]) * nx
            + (blocks[b, WX + 1] - blocks[a, WX + 1]) * ny
            + (blocks[b, WX + 2] - blocks[a, WX + 2]) * nz
        )
        subs[s, TWIST] -= ks * polar[k] * spin * dt
        if trial > limit:
            f = limit / trial
            tx, ty, tz = tx * f, ty * f, tz * f
            subs[s, SLIPPED] = 1.0
            subs[s, TWIST] *= f
        if sn > 0.0 and limit > 0.0:  # the friction's part at the centre of pressure
            w = tan_phi / (limit * a_k)
            ox = w * (ny * mz - nz * my)
            oy = w * (nz * mx - nx * mz)
            oz = w * (nx * my - ny * mx)
            mx -= a_k * (oy * tz - oz * ty)
            my -= a_k * (oz * tx - ox * tz)
            mz -= a_k * (ox * ty - oy * tx)
        subs[s, TAUX], subs[s, TAUY], subs[s, TAUZ], subs[s, SN] = tx, ty, tz, sn
        pw = law_params[joint, P_PRESSURE]
        subs[s, PRESSURE] = pw
        mx, my, mz = mx + subs[s, TWIST] * nx, my + subs[s, TWIST] * ny, mz + subs[s, TWIST] * nz
        total = sn + pw  # the total normal stress: effective and water
        fx, fy, fz = a_k * (total * nx - tx), a_k * (total * ny - ty), a_k * (total * nz - tz)
        loads[s, LFX], loads[s, LFX + 1], loads[s, LFX + 2] = fx, fy, fz
        loads[s, LMX], loads[s, LMX + 1], loads[s, LMX + 2] = mx, my, mz
        fsx, fsy, fsz, fn = fsx - a_k * tx, fsy - a_k * ty, fsz - a_k * tz, fn + a_k * sn
    for s in range(first + m, first + count):
        subs[s, :] = 0.0
    values[c, FSX], values[c, FSY], values[c, FSZ], values[c, FN] = fsx, fsy, fsz, fn
    values[c, AREA_CLOSED] = closed_area


@numba.njit(cache=True, parallel=True)
def contact_forces(
    blocks, geometry, contacts, values, subs, loads, law_codes, law_params, refine, dt, threaded
):
    """Every pair's sub-contacts updated for a step of dt [s], each share's force and couple on B left in
    `loads` (rows as `subs`'), for `add_contact_loads`. `geometry` is the tuple (vertices, vertex_start,
    face_vertices, face_start, block_face_start, face_normal, size) in the world. `threaded`: the pairs
    on every thread of numba's pool, else in order on this one; the result is the same to the bit."""
    if threaded:
        for c in numba.prange(contacts.shape[0]):
            _pair(c, blocks, geometry, contacts, values, subs, loads, law_codes, law_params, refine, dt)
        return
    for c in range(contacts.shape[0]):
        _pair(c, blocks, geometry, contacts, values, subs, loads, law_codes, law_params, refine, dt)


@numba.njit(cache=True, inline="always")
def _add_pairs_of(blocks, i, contacts, subs, loads, block_start, block_pairs):
    """Add to block i, in pair order, its pairs' shares in share order: +f on B, -f on A (`_add`)."""
    for k in range(block_start[i], block_start[i + 1]):
        entry = block_pairs[k]
        c, sign = (entry, 1.0) if entry >= 0 else (-1 - entry, -1.0)
        if contacts[c, KEY] == NONE:
            continue
        first = contacts[c, FIRST_SUB]
        for s in range(first, first + contacts[c, SUB_COUNT]):
            _add(blocks, i, sign, loads[s, LFX], loads[s, LFX + 1], loads[s, LFX + 2], subs[s, CX],
                 subs[s, CY], subs[s, CZ], loads[s, LMX], loads[s, LMX + 1], loads[s, LMX + 2])  # fmt: skip


@numba.njit(cache=True, parallel=True)
def add_contact_loads(blocks, contacts, subs, loads, block_start, block_pairs, threaded):
    """Every block's shares (`loads`, from `contact_forces`) added to its FX.. and TX.. columns, each
    block's in pair order (`block_pairs`, CSR from `block_start`: `block_pairs`); `threaded`: the blocks
    on every thread of numba's pool. A share adds nothing where its row is zero (x + 0 is x, and a sum
    from +0 is never -0), so a block's sum is the one-thread, share-by-share sum, to the bit."""
    if threaded:
        for i in numba.prange(blocks.shape[0]):
            _add_pairs_of(blocks, i, contacts, subs, loads, block_start, block_pairs)
        return
    for i in range(blocks.shape[0]):
        _add_pairs_of(blocks, i, contacts, subs, loads, block_start, block_pairs)


def block_pairs(contacts: np.ndarray, n_blocks: int) -> tuple[np.ndarray, np.ndarray]:
    """Each block's pairs in pair order, as CSR (`bbmc.incidence.block_contacts`: c >= 0 for pair c
    with the block as B, -1 - c with it as A; the order `add_contact_loads` adds them in)."""
    return block_contacts(contacts[:, BLOCK_A], contacts[:, BLOCK_B], n_blocks)
