"""A 3D model: rigid convex polyhedra and a density made into the engine's flat arrays, and the
vertices and face normals placed in the world from each block's position and orientation.

Layouts: the block array and dof flags of `bbmc.dem3d.layout`; the faces as `bbmc.dem3d.contact_geometry`
describes (vertex_start, face_vertices, face_start, block_face_start, face_normal). Vertices and normals
are kept in each block's body frame (origin at its centroid, axes its principal axes: `body_vertices`,
`body_normals`) and placed in the world every step, x + R(q) b and R(q) n (`place`), so a block stays
rigid however far it turns. The contact state (`bbmc.dem3d.solver`) lives in the model too, so that a
run can be continued. Units: m, kg, s.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numba
import numpy as np

from bbmc.dem3d.broad_phase import candidate_pairs
from bbmc.dem3d.contact_forces import CONTACT_COLUMNS, CONTACT_VALUES, LOAD_COLUMNS, SUB_COLUMNS
from bbmc.dem3d.contact_geometry import separating_axis
from bbmc.dem3d.joint_laws import JointLaw, joint_tables
from bbmc.dem3d.layout import DOFS, PRESCRIBED, QW, X
from bbmc.dem3d.motion import new_blocks
from bbmc.dem3d.quaternion import rotate
from bbmc.dem3d.water import WaterTable
from bbmc.geometry.polyhedra import Polyhedron
from bbmc.geometry.polyhedron_mass import mass_properties

SEARCH_MARGIN = 0.05  # x the smallest block's size: the broad phase's margin [m]
START_OVERLAP = 0.01  # x the smaller block's size: the deepest overlap a start may have (a settled closure)


@dataclass(eq=False)
class Model:
    """Blocks, their faces, joint types and contact state (arrays as the module docstring says).

    `size` (n,): each block's size, twice its RADIUS [m], the scale of contact tolerances; `law_codes`,
    `law_params` the joint types' tables (`bbmc.dem3d.joint_laws`); `group` (n,) int64 each block's group
    and `pair_joint` (g, g) int64, symmetric, the joint type of a contact between blocks of groups i and j
    (set when the pair is found, `bbmc.dem3d.solver.search`), unless `face_joint` (n_faces,) int64 gives
    the joint type of a contact across that face (a rock mass's joint set's, -1: the groups' rule);
    `water_table` (4,) the phreatic plane's (gamma_w [N/m³], z0 [m], a, b [1])
    (`bbmc.dem3d.water.WaterTable.coefficients`; all 0: dry);
    `refine`: the face triangulation's refinement; `margin` [m]: the broad phase's. The contact state:
    `contacts` (int64, CONTACT_COLUMNS), `contact_values` (float64, CONTACT_VALUES), `subs` (float64,
    SUB_COLUMNS) as `bbmc.dem3d.contact_forces` lays them out; `vertices_at_search`; `step`. Scratch of
    the step, rebuilt at each search: `loads` (float64, LOAD_COLUMNS) and each block's pairs,
    `block_start` and `block_pairs` (`bbmc.dem3d.contact_forces.block_pairs`)."""

    blocks: np.ndarray
    dof: np.ndarray
    body_vertices: np.ndarray
    vertex_start: np.ndarray
    face_vertices: np.ndarray
    face_start: np.ndarray
    block_face_start: np.ndarray
    body_normals: np.ndarray
    vertices: np.ndarray
    face_normal: np.ndarray
    size: np.ndarray
    law_codes: np.ndarray
    law_params: np.ndarray
    gravity: np.ndarray
    refine: int
    margin: float
    group: np.ndarray
    pair_joint: np.ndarray
    water_table: np.ndarray
    face_joint: np.ndarray
    contacts: np.ndarray = field(default_factory=lambda: np.zeros((0, CONTACT_COLUMNS), dtype=np.int64))
    contact_values: np.ndarray = field(default_factory=lambda: np.zeros((0, CONTACT_VALUES)))
    subs: np.ndarray = field(default_factory=lambda: np.zeros((0, SUB_COLUMNS)))
    vertices_at_search: np.ndarray | None = None
    step: int = 0
    loads: np.ndarray = field(default_factory=lambda: np.zeros((0, LOAD_COLUMNS)))
    block_start: np.ndarray = field(default_factory=lambda: np.zeros(1, dtype=np.int64))
    block_pairs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))


def build_model(
    polyhedra: Sequence[Polyhedron],
    density: float | Sequence[float],
    laws: Sequence[JointLaw],
    *,
    held: Sequence[int] = (),
    gravity: Sequence[float] = (0.0, 0.0, -9.81),
    refine: int = 1,
    group: Sequence[int] | None = None,
    pair_joint: np.ndarray | None = None,
    water: WaterTable | None = None,
    face_joint: Sequence[Sequence[int]] | None = None,
) -> Model:
    """The model of these blocks, of `density` [kg/m³] (one for all or one each), on the joint types
    `laws`, blocks `held` fixed in all six degrees of freedom, `gravity` [m/s²] (with a seismic
    coefficient: `bbmc.dem3d.seismic.seismic_gravity`), the face triangulation refined `refine` times
    (each triangle split in four). A contact between a block of `group` i and one of group j takes joint
    type `pair_joint[i, j]` (default: every block in group 0, every contact of joint type 0), but a
    contact across a face with a `face_joint` (one row per block, one entry per face: a joint type, or
    -1 for the groups' rule) takes that face's (`bbmc.dem3d.solver.search`). `water`: a phreatic plane
    whose pressure loads the free blocks' faces below it (`bbmc.dem3d.water`; None: dry but for the
    laws' given pressures on their contacts). Refused in one line naming the block or key: a density
    <= 0, a held index out of range, a bad law, a group or joint type out of range, an asymmetric
    `pair_joint`, a block's `face_joint` not one joint type or -1 per face, a bad water table, two free
    blocks (or a free and a held one) overlapping at the start (`_refuse_overlaps`)."""
    n = len(polyhedra)
    groups = np.zeros(n, dtype=np.int64) if group is None else np.asarray(group, dtype=np.int64)
    pairs = np.zeros((1, 1), dtype=np.int64) if pair_joint is None else np.asarray(pair_joint, dtype=np.int64)
    _check_groups(groups, pairs, n, len(laws))
    densities = np.broadcast_to(np.asarray(density, dtype=float), (n,))
    if refine < 0:
        raise ValueError(f"refine: must be >= 0, got {refine}")
    for i in held:
        if not 0 <= i < n:
            raise ValueError(f"held: block {i} is not one of the {n} blocks")
    for i in range(n):
        if not densities[i] > 0.0:
            raise ValueError(f"block {i}: density must be > 0 kg/m3, got {densities[i]}")
    props = [mass_properties(p, d) for p, d in zip(polyhedra, densities, strict=True)]
    centroids = np.array([m.centroid for m in props])
    axes = np.array([m.principal_axes for m in props])
    body = [(p.vertices - m.centroid) @ m.principal_axes for p, m in zip(polyhedra, props, strict=True)]
    radii = np.array([np.sqrt((b * b).sum(axis=1)).max() for b in body])
    blocks = new_blocks(
        centroids,
        axes,
        np.array([m.mass for m in props]),
        np.array([m.principal_moments for m in props]),
        radii,
    )
    dof = np.zeros((n, DOFS), dtype=np.int64)
    dof[list(held)] = PRESCRIBED
    vertex_start = np.cumsum([0] + [len(p.vertices) for p in polyhedra])
    face_counts = [p.face_count for p in polyhedra]
    block_face_start = np.cumsum([0, *face_counts])
    face_vertices = np.concatenate([p.face_vertices + vertex_start[k] for k, p in enumerate(polyhedra)])
    loop_lengths = np.concatenate([np.diff(p.face_start) for p in polyhedra])
    face_start = np.concatenate([[0], np.cumsum(loop_lengths)])
    body_normals = np.vstack([p.normals @ m.principal_axes for p, m in zip(polyhedra, props, strict=True)])
    law_codes, law_params = joint_tables(laws)
    faces_joint = _face_joints(face_joint, face_counts, len(laws))
    size = 2.0 * radii
    model = Model(
        blocks=blocks,
        dof=dof,
        body_vertices=np.vstack(body),
        vertex_start=vertex_start.astype(np.int64),
        face_vertices=face_vertices.astype(np.int64),
        face_start=face_start.astype(np.int64),
        block_face_start=block_face_start.astype(np.int64),
        body_normals=body_normals,
        vertices=np.empty((vertex_start[-1], 3)),
        face_normal=np.empty((block_face_start[-1], 3)),
        size=size,
        law_codes=law_codes,
        law_params=law_params,
        gravity=np.asarray(gravity, dtype=float),
        refine=int(refine),
        margin=SEARCH_MARGIN * float(size.min()),
        group=groups,
        pair_joint=pairs,
        water_table=np.array(water.coefficients() if water is not None else (0.0, 0.0, 0.0, 0.0)),
        face_joint=faces_joint,
    )
    place(model.blocks, model.body_vertices, model.vertex_start, model.body_normals, model.block_face_start,
          model.vertices, model.face_normal)  # fmt: skip
    _refuse_overlaps(model, np.array([i in held for i in range(n)]))
    return model


def _check_groups(group: np.ndarray, pair_joint: np.ndarray, n: int, types: int) -> None:
    """ValueError in one line: a group per block, each a row of a square, symmetric `pair_joint` whose
    entries are joint types 0..types-1."""
    if group.shape != (n,):
        raise ValueError(f"group: one per block ({n}), got {group.shape[0] if group.ndim else 0}")
    g = pair_joint.shape[0]
    if pair_joint.ndim != 2 or pair_joint.shape != (g, g) or not np.array_equal(pair_joint, pair_joint.T):
        raise ValueError("pair_joint: must be a square, symmetric table of joint types")
    if n and not (group.min() >= 0 and group.max() < g):
        got = f"{group.min()}..{group.max()}"
        raise ValueError(f"group: must be 0..{g - 1} (the rows of pair_joint), got {got}")
    if not (pair_joint.min() >= 0 and pair_joint.max() < types):
        got = f"{pair_joint.min()}..{pair_joint.max()}"
        raise ValueError(f"pair_joint: joint types must be 0..{types - 1}, got {got}")


def _face_joints(face_joint: Sequence[Sequence[int]] | None, counts: list[int], types: int) -> np.ndarray:
    """Every face's joint type (-1: the groups' rule) as one int64 array; ValueError in one line naming
    the block whose row is not one entry per face, each -1..types-1."""
    if face_joint is None:
        return np.full(sum(counts), -1, dtype=np.int64)
    if len(face_joint) != len(counts):
        raise ValueError(f"face_joint: one row per block ({len(counts)}), got {len(face_joint)}")
    rows = [np.asarray(row, dtype=np.int64).reshape(-1) for row in face_joint]
    for i, (row, count) in enumerate(zip(rows, counts, strict=True)):
        if row.size != count or (count and not (row.min() >= -1 and row.max() < types)):
            raise ValueError(
                f"block {i}: face_joint must be one of -1..{types - 1} for each of its {count} faces"
            )
    return np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)


def _refuse_overlaps(model: Model, held: np.ndarray) -> None:
    """ValueError naming the first two blocks that overlap at the start by more than START_OVERLAP x
    the smaller one's size (the separating-axis depth; a block sunk by its settled closure passes)."""
    arrays = (model.vertices, model.vertex_start, model.face_vertices, model.face_start,
              model.block_face_start, model.face_normal)  # fmt: skip
    for a, b in candidate_pairs(model.vertices, model.vertex_start, held, 0.0):
        scale = min(model.size[a], model.size[b])
        depth = -separating_axis(*arrays, a, b, scale, 0.0, -1, -1, -1)[0]
        if depth > START_OVERLAP * scale:
            raise ValueError(f"blocks {a} and {b}: they overlap by {depth:.4g} m at the start")


@numba.njit(cache=True)
def place(blocks, body_vertices, vertex_start, body_normals, block_face_start, vertices, face_normal):
    """Every block's vertices x + R(q) b and face normals R(q) n in the world, in place."""
    for i in range(blocks.shape[0]):
        q0, q1, q2, q3 = blocks[i, QW], blocks[i, QW + 1], blocks[i, QW + 2], blocks[i, QW + 3]
        for v in range(vertex_start[i], vertex_start[i + 1]):
            r = rotate(q0, q1, q2, q3, body_vertices[v, 0], body_vertices[v, 1], body_vertices[v, 2])
            for d in range(3):
                vertices[v, d] = blocks[i, X + d] + r[d]
        for f in range(block_face_start[i], block_face_start[i + 1]):
            r = rotate(q0, q1, q2, q3, body_normals[f, 0], body_normals[f, 1], body_normals[f, 2])
            for d in range(3):
                face_normal[f, d] = r[d]
