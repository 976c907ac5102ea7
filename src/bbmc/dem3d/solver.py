"""The 3D engine's cycle: place the blocks' vertices, search for pairs when some block has moved far
enough (`bbmc.dem3d.broad_phase`), contact forces (`bbmc.dem3d.contact_forces`), the phreatic table's
loads on the faces (`bbmc.dem3d.water`), motion (`bbmc.dem3d.motion`); and the time step from the
contacts' stiffness (`bbmc.dem3d.time_step`).

The steps run in one numba loop (`_cycle`) until a search is due; the search itself (rare) is Python:
the broad phase's pairs, each ordered so that its first block A is the one whose face should carry the
sub-contacts (a free block before a held one, then the smaller before the larger: the separating axis
prefers A's faces on ties, so the sub-contacts sit on the sliding or falling block's face and their
triangles tile its own footprint, not a large base's), and the state of every pair found before carried
over. A new pair's joint type is its blocks' groups' (`pair_joint`), or, where it is a face–face
contact across a face with a joint type of its own (`face_joint`: a rock mass's joint set's), that
face's: A's face (the reference face of `bbmc.dem3d.contact_forces`), else B's (`pair_joint_type`). It
is decided once, when the pair is found, from the geometry then (the separating axis and the contact
patch, as the kernel finds them each step), and kept while the pair stays within the search margin, so
the contact kernels never read it. Units: m, kg, s, N.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from bbmc.dem3d.broad_phase import candidate_pairs, needs_search
from bbmc.dem3d.contact_forces import (
    AXIS_KIND,
    BLOCK_A,
    BLOCK_B,
    CONTACT_COLUMNS,
    CONTACT_VALUES,
    FIRST_SUB,
    JOINT_TYPE,
    KEY,
    LOAD_COLUMNS,
    NONE,
    SUB_COLUMNS,
    SUB_COUNT,
    add_contact_loads,
    block_pairs,
    contact_forces,
)
from bbmc.dem3d.contact_geometry import AXIS_FACE_A, FACE_FACE, contact_patch, separating_axis
from bbmc.dem3d.face_contact import face_overlap
from bbmc.dem3d.joint_laws import P_KN, P_KS
from bbmc.dem3d.layout import FX, PRESCRIBED, TX, VPX, WPX, X
from bbmc.dem3d.model import Model, place
from bbmc.dem3d.motion import move_blocks
from bbmc.dem3d.polygon_clip import polygon_moments
from bbmc.dem3d.time_step import contact_stiffness, critical_time_step
from bbmc.dem3d.water import add_water_loads


def _geometry(model: Model) -> tuple:
    return (model.vertices, model.vertex_start, model.face_vertices, model.face_start,
            model.block_face_start, model.face_normal, model.size)  # fmt: skip


def _held(model: Model) -> np.ndarray:
    """Blocks that cannot move: all six dofs prescribed, at zero velocity."""
    still = np.all(model.blocks[:, VPX : VPX + 3] == 0.0, axis=1) & np.all(
        model.blocks[:, WPX : WPX + 3] == 0.0, axis=1
    )
    return np.all(model.dof == PRESCRIBED, axis=1) & still


def _slots(model: Model, block: int) -> int:
    """Sub-contacts a pair needs for a reference face of this block: its largest face's triangles."""
    first, last = model.block_face_start[block], model.block_face_start[block + 1]
    return int(np.diff(model.face_start[first : last + 1]).max() - 2) * 4**model.refine


def pair_joint_type(model: Model, a: int, b: int, tagged: np.ndarray) -> int:
    """The joint type of the new pair (a, b) (module docstring): the groups' rule, unless a block of it
    has a face with a joint type (`tagged`, per block) and the pair is a face–face contact whose face of
    A, else of B, has one."""
    rule = int(model.pair_joint[model.group[a], model.group[b]])
    if not (tagged[a] or tagged[b]):
        return rule
    arrays = _geometry(model)[:6]
    scale = min(model.size[a], model.size[b])
    _, axis, i, j, *_ = separating_axis(*arrays, a, b, scale, 0.0, -1, -1, -1)
    kind, ref, inc, area, *_ = contact_patch(*arrays, a, b, scale, axis, i, j)
    if kind != FACE_FACE or not area > 0.0:
        return rule
    face_a, face_b = (ref, inc) if axis == AXIS_FACE_A else (inc, ref)
    for face in (face_a, face_b):
        if model.face_joint[face] >= 0:
            return int(model.face_joint[face])
    return rule


def search(model: Model) -> None:
    """New candidate pairs from the broad phase, ordered (module docstring), each pair's contact state
    carried over from the last search where it was a pair then, new pairs apart until they touch."""
    held = _held(model)
    pairs = candidate_pairs(model.vertices, model.vertex_start, held, model.margin)
    ordered = [
        (a, b) if (held[a], model.size[a], a) <= (held[b], model.size[b], b) else (b, a) for a, b in pairs
    ]
    old = {(int(r[BLOCK_A]), int(r[BLOCK_B])): k for k, r in enumerate(model.contacts)}
    tagged = np.zeros(len(model.blocks), dtype=bool)
    np.logical_or.at(tagged, np.repeat(np.arange(len(tagged)), np.diff(model.block_face_start)),
                     model.face_joint >= 0)  # fmt: skip
    counts = [max(_slots(model, a), _slots(model, b), 1) for a, b in ordered]
    contacts = np.zeros((len(ordered), CONTACT_COLUMNS), dtype=np.int64)
    values = np.zeros((len(ordered), CONTACT_VALUES))
    subs = np.zeros((int(sum(counts)), SUB_COLUMNS))
    first = 0
    for c, ((a, b), count) in enumerate(zip(ordered, counts, strict=True)):
        k = old.get((a, b))
        if k is None:
            contacts[c, BLOCK_A], contacts[c, BLOCK_B] = a, b
            contacts[c, JOINT_TYPE] = pair_joint_type(model, a, b, tagged)
            contacts[c, AXIS_KIND : AXIS_KIND + 3] = -1
            contacts[c, KEY] = NONE
        else:
            contacts[c] = model.contacts[k]
            values[c] = model.contact_values[k]
            start = model.contacts[k, FIRST_SUB]
            subs[first : first + count] = model.subs[start : start + count]
        contacts[c, FIRST_SUB], contacts[c, SUB_COUNT] = first, count
        first += count
    model.contacts, model.contact_values, model.subs = contacts, values, subs
    model.loads = np.zeros((len(subs), LOAD_COLUMNS))
    model.block_start, model.block_pairs = block_pairs(contacts, len(model.blocks))
    model.vertices_at_search = model.vertices.copy()


@numba.njit(cache=True)
def _cycle(blocks, dof, gravity, damping, dt, step, steps, geometry, placing, at_search, margin, pairs,
           forces, law_codes, law_params, refine, water_table, threaded):  # fmt: skip
    """Up to `steps` steps from `step`; returns how many ran before a search fell due. `pairs` is
    (contacts, values, subs, loads), `forces` (block_start, block_pairs); `threaded`: contact forces
    and motion on every thread of numba's pool (the same to the bit); `water_table` the phreatic plane's
    (gamma_w, z0, a, b) (`bbmc.dem3d.water`; gamma_w 0: dry)."""
    vertices, face_normal = geometry[0], geometry[5]
    body_vertices, vertex_start, body_normals, block_face_start = placing
    contacts, values, subs, loads = pairs
    for k in range(steps):
        place(blocks, body_vertices, vertex_start, body_normals, block_face_start, vertices, face_normal)
        if needs_search(vertices, at_search, margin):
            return k
        blocks[:, FX : FX + 3] = 0.0
        blocks[:, TX : TX + 3] = 0.0
        contact_forces(blocks, geometry, contacts, values, subs, loads, law_codes, law_params, refine, dt,
                       threaded)  # fmt: skip
        add_contact_loads(blocks, contacts, subs, loads, forces[0], forces[1], threaded)
        add_water_loads(blocks, dof, vertices, vertex_start, geometry[2], geometry[3], block_face_start,
                        face_normal, water_table)  # fmt: skip
        move_blocks(blocks, dof, gravity, damping, dt, step + k, threaded)
    place(blocks, body_vertices, vertex_start, body_normals, block_face_start, vertices, face_normal)
    return steps


def forces(model: Model, dt: float) -> None:
    """The contact forces and torques on every block [N, N m] for a step of dt [s] from the model as it
    stands (searched), in its FX.. and TX.. columns, which start from zero."""
    model.blocks[:, FX : FX + 3] = 0.0
    model.blocks[:, TX : TX + 3] = 0.0
    contact_forces(model.blocks, _geometry(model), model.contacts, model.contact_values, model.subs,
                   model.loads, model.law_codes, model.law_params, model.refine, float(dt),
                   False)  # fmt: skip
    add_contact_loads(model.blocks, model.contacts, model.subs, model.loads, model.block_start,
                      model.block_pairs, False)  # fmt: skip


def thread_count(requested: int | None) -> int:
    """The threads a run takes: `requested`, or numba's whole pool (every core) when None."""
    return requested or numba.config.NUMBA_NUM_THREADS


def run(model: Model, steps: int, dt: float, damping: float = 0.0, threads: int = 1) -> None:
    """`steps` steps of dt [s] with Cundall's local damping `damping` [1], continuing the model, on
    `threads` threads (at most numba's pool; above 1 the pairs and blocks are shared among them, with
    the same result to the bit as on one)."""
    placing = (model.body_vertices, model.vertex_start, model.body_normals, model.block_face_start)
    threaded = threads > 1
    if threaded:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    done = 0
    while done < steps:
        if model.vertices_at_search is None:
            search(model)
        pairs = (model.contacts, model.contact_values, model.subs, model.loads)
        ran = _cycle(model.blocks, model.dof, model.gravity, float(damping), float(dt), model.step,
                     steps - done, _geometry(model), placing, model.vertices_at_search, model.margin, pairs,
                     (model.block_start, model.block_pairs), model.law_codes, model.law_params,
                     model.refine, model.water_table, threaded)  # fmt: skip
        done += ran
        model.step += ran
        if done < steps:
            model.vertices_at_search = None


def time_step(model: Model, safety: float = 0.5, damping: float = 0.0) -> float:
    """`safety` x the critical step [s] (`critical_time_step`) of the model as it stands: every pair
    within the search margin counted as a spring bed over its whole contact patch (face–face: the
    overlap polygon, its polar moment; degenerate contacts: their nominal area) of the stiffest joint
    type's K_n and K_s; +inf with no such pair."""
    n = model.blocks.shape[0]
    k_t, k_r = np.zeros(n), np.zeros(n)
    kn, ks = model.law_params[:, P_KN].max(), model.law_params[:, P_KS].max()
    arrays = _geometry(model)[:6]
    for a, b in candidate_pairs(model.vertices, model.vertex_start, _held(model), model.margin):
        scale = min(model.size[a], model.size[b])
        sep, axis, i, j, *normal = separating_axis(*arrays, a, b, scale, 0.0, -1, -1, -1)
        if sep > model.margin:
            continue
        _, ref, inc, area, *centre = contact_patch(*arrays, a, b, scale, axis, i, j)
        polar = 0.0
        if inc >= 0:
            poly, *_ = face_overlap(model.vertices, model.face_vertices, model.face_start,
                                    model.face_normal, ref, inc)  # fmt: skip
            _, _, _, sss, _, stt = polygon_moments(poly)
            polar = sss + stt
        for blk in (a, b):
            lever = np.asarray(centre) - model.blocks[blk, X : X + 3]
            kt, kr = contact_stiffness(kn, ks, area, polar, lever, np.asarray(normal))
            k_t[blk] += kt
            k_r[blk] += kr
    step = critical_time_step(model.blocks, model.dof, k_t, k_r, float(damping))
    return safety * step if math.isfinite(step) else math.inf
