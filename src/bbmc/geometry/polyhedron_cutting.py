"""Convex polyhedra cut by planes, and by persistent joint sets as 3DEC's `jset` cuts them.

`cut` splits a block by one plane into the parts below and above it (each convex): every face is
clipped by the plane (Sutherland & Hodgman 1974, one pass), the plane's section of the block becomes a
new face of each part. A vertex within `TOLERANCE` x the block's size of the plane lies on it, so a
plane that only grazes the block (every vertex on it or on one side) leaves it whole.

`cut_by_joint_sets` cuts a block by every plane of every set, set after set. Slivers are handled as the
2D rock-mass generator does (`bbmc.rockmass.cut`, `bbmc.rockmass.generate`): a cut that would leave a
piece smaller than `min_block_fraction` x the median block is not made in that piece (the piece stays
whole there, as if the sliver were merged back into it), and is reported; the median is that of the same
block cut without the rule (a first pass). Blocks are never dropped, so the blocks tile the one cut.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import upward_pole
from bbmc.geometry.polygons import MAX_BLOCKS
from bbmc.geometry.polyhedra import (
    TOLERANCE,
    UNTAGGED,
    Polyhedron,
    assembled,
    successor_entries,
)
from bbmc.geometry.polyhedron_mass import volume

# A persistent joint set: dip [deg], dip direction [deg], spacing [m], origin (x, y, z) [m].
JointSet3D = tuple[float, float, float, Sequence[float]]


def cut(
    block: Polyhedron, normal: np.ndarray, offset: float, *, tag: int = UNTAGGED
) -> tuple[Polyhedron | None, Polyhedron | None]:
    """The parts of a convex `block` below (n . x < d) and above the plane n . x = d (`normal` (3,),
    any length, and `offset` [m] of the plane through the point x0: n . x0), each a convex polyhedron, or
    None where the plane leaves nothing on that side (the block is then the other part, unchanged).

    The faces of each part: the block's faces clipped by the plane (Sutherland & Hodgman 1974), each
    keeping its tag, then the section of the block by the plane, tagged `tag`. Vertices: the block's
    on that side or on the plane, then the points where edges cross the plane (x = a + (b - a) d_a /
    (d_a - d_b), d the signed distances), shared by both parts."""
    normal = np.asarray(normal, dtype=float)
    length = float(np.linalg.norm(normal))
    if not (normal.shape == (3,) and np.isfinite(length) and length > 0 and np.isfinite(offset)):
        raise ValueError(f"a cutting plane needs a finite, non-zero normal (3,) and offset, got {normal}")
    normal = normal / length
    distance = block.vertices @ normal - offset / length
    side = np.where(np.abs(distance) <= TOLERANCE * block.size, 0, np.sign(distance)).astype(np.int64)
    if side.min() >= 0:
        return None, block
    if side.max() <= 0:
        return block, None
    crossing = block.edges[side[block.edges[:, 0]] * side[block.edges[:, 1]] < 0]
    a, b = block.vertices[crossing[:, 0]], block.vertices[crossing[:, 1]]
    da, db = distance[crossing[:, 0]], distance[crossing[:, 1]]
    points = a + (b - a) * (da / (da - db))[:, None]
    vertices = np.vstack([block.vertices, points])
    sides = np.concatenate([side, np.zeros(len(points), dtype=np.int64)])
    return (
        _part(block, vertices, sides, crossing, normal, -1, tag),
        _part(block, vertices, sides, crossing, normal, 1, tag),
    )


def _part(
    block: Polyhedron,
    vertices: np.ndarray,
    sides: np.ndarray,
    crossing: np.ndarray,
    normal: np.ndarray,
    keep: int,
    tag: int,
) -> Polyhedron:
    """The part on side `keep` (-1 below, +1 above) of the plane: each face's loop clipped (its vertices
    on that side or on the plane, and where its edges cross the plane: the crossing edge's point, at
    `len(block.vertices)` + its row in `crossing`), faces left with fewer than 3 vertices dropped; then
    the section as a new face."""
    count = len(block.vertices)
    flat, start = block.face_vertices, block.face_start
    lengths = np.diff(start)
    i, j = flat, flat[successor_entries(start)]
    crossing_key = crossing[:, 0] * count + crossing[:, 1]  # ascending: the edges are sorted
    crossed = count + np.searchsorted(crossing_key, np.minimum(i, j) * count + np.maximum(i, j))
    candidate = np.column_stack([i, crossed]).ravel()
    chosen = np.column_stack([sides[i] != -keep, sides[i] * sides[j] < 0]).ravel()
    face = np.repeat(np.repeat(np.arange(len(lengths)), lengths), 2)[chosen]
    sizes = np.bincount(face, minlength=len(lengths))
    kept = sizes >= 3
    on_plane = np.flatnonzero(sides == 0)
    section = _section_loop(vertices, on_plane, -keep * normal)
    loop_flat = np.concatenate([candidate[chosen][kept[face]], section])
    tags = np.append(block.face_tags[kept], tag)
    used = np.flatnonzero(np.bincount(loop_flat, minlength=len(vertices)))
    renumber = np.full(len(vertices), -1)
    renumber[used] = np.arange(len(used))
    start = np.concatenate([[0], np.cumsum(sizes[kept]), [len(loop_flat)]])
    return assembled(vertices[used], renumber[loop_flat], start, tags)


def _section_loop(vertices: np.ndarray, on_plane: np.ndarray, outward: np.ndarray) -> np.ndarray:
    """The points on the plane (a convex polygon's corners) ordered anticlockwise about `outward`, the
    part's outward normal on the section: by their angle about their mean in the plane."""
    points = vertices[on_plane] - vertices[on_plane].mean(axis=0)
    x, y, z = outward
    u = np.array([0.0, z, -y]) if abs(x) < 0.9 else np.array([-z, 0.0, x])  # n x e_x or e_y x n
    u /= np.linalg.norm(u)
    v = np.array([y * u[2] - z * u[1], z * u[0] - x * u[2], x * u[1] - y * u[0]])  # n x u
    return on_plane[np.argsort(np.arctan2(points @ v, points @ u))]


@dataclass(frozen=True)
class JointedBlocks:
    """A block cut by joint sets: the `blocks` (faces tagged with the index of the set whose joint made
    them, `UNTAGGED` for the block's own); `cuts_per_set` (s,) int64: how many cuts each set made (0:
    the set cuts nothing, which a config should refuse); `skipped`: the cuts not made as
    (set index, plane number k, volume of the sliver [m^3]) because a piece smaller than `smallest_volume`
    [m^3] would have been left."""

    blocks: list[Polyhedron]
    cuts_per_set: np.ndarray
    skipped: list[tuple[int, int, float]]
    smallest_volume: float


def set_normal(dip_deg: float, dip_direction_deg: float) -> np.ndarray:
    """A joint set's upward unit normal (east, north, up) (3,): n = (sin psi sin alpha, sin psi cos alpha,
    cos psi) (`bbmc.geometry.orientation.upward_pole`)."""
    return upward_pole(dip_deg, dip_direction_deg)


def cut_by_joint_sets(
    block: Polyhedron, sets: Sequence[JointSet3D], *, min_block_fraction: float = 0.0
) -> JointedBlocks:
    """`block` cut by persistent joint sets, as 3DEC's `jset` cuts (Itasca, 3DEC manual, "jset"): set s
    (dip [deg], dip direction [deg], spacing [m], origin (3,) [m]) is the planes n . x = n . origin + k
    spacing for every integer k, n its upward unit normal (`set_normal`); the plane k = 0 passes through
    the origin, so a set's planes do not depend on the block they cut. Each plane cuts every piece it
    crosses (`cut`), set after set, the faces it makes tagged s. Slivers: the module's docstring.
    Refused (ValueError naming the set): a dip outside 0 to 90, a spacing not > 0, an origin not three
    finite numbers, or more than `MAX_BLOCKS` blocks possible."""
    if not 0.0 <= min_block_fraction < 1.0:
        raise ValueError(f"min_block_fraction must be in [0, 1), got {min_block_fraction}")
    planes = [_set_planes(s, joint_set) for s, joint_set in enumerate(sets)]
    bound = float(np.prod([np.ptp(block.vertices @ n) / spacing + 2.0 for n, _, spacing in planes]))
    if not bound <= MAX_BLOCKS:
        raise ValueError(
            f"the joint sets would cut the block into up to {bound:.3g} blocks, more than {MAX_BLOCKS:,} "
            "(wider spacings)"
        )
    smallest = 0.0
    if min_block_fraction > 0:
        first = _cut_all(block, planes, 0.0)
        smallest = min_block_fraction * float(np.median([volume(b) for b in first.blocks]))
    return _cut_all(block, planes, smallest)


def _set_planes(s: int, joint_set: JointSet3D) -> tuple[np.ndarray, float, float]:
    """Set s's unit normal, the offset of its plane k = 0 [m] and its spacing [m]; or a ValueError."""
    dip, direction, spacing, origin = joint_set
    origin = np.asarray(origin, dtype=float)
    if not 0.0 <= dip <= 90.0:
        raise ValueError(f"joint set {s}: dip_deg must be in [0, 90], got {dip}")
    if not np.isfinite(direction):
        raise ValueError(f"joint set {s}: dip_direction_deg must be a finite number, got {direction}")
    if not (np.isfinite(spacing) and spacing > 0):
        raise ValueError(f"joint set {s}: spacing_m must be > 0, got {spacing}")
    if origin.shape != (3,) or not np.all(np.isfinite(origin)):
        raise ValueError(f"joint set {s}: origin_m must be three finite numbers (x, y, z), got {origin}")
    normal = set_normal(dip, direction)
    return normal, float(normal @ origin), float(spacing)


def _cut_all(
    block: Polyhedron, planes: list[tuple[np.ndarray, float, float]], smallest: float
) -> JointedBlocks:
    """Every piece cut by every plane of each set in turn (ascending k): the part below a plane is
    done with that set, the part above goes on to the next plane."""
    pieces, counts, skipped = [block], np.zeros(len(planes), dtype=np.int64), []
    for s, (normal, origin_offset, spacing) in enumerate(planes):
        done = []
        for piece in pieces:
            projection = piece.vertices @ normal
            first = int(np.ceil((projection.min() - origin_offset) / spacing))
            last = int(np.floor((projection.max() - origin_offset) / spacing))
            for k in range(first, last + 1):
                below, above = cut(piece, normal, origin_offset + k * spacing, tag=s)
                if below is None or above is None:
                    continue
                sliver = min(volume(below), volume(above))
                if sliver < smallest:
                    skipped.append((s, k, sliver))
                    continue
                done.append(below)
                counts[s] += 1
                piece = above
            done.append(piece)
        pieces = done
    return JointedBlocks(pieces, counts, skipped, smallest)
