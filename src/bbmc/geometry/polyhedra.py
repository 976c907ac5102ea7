"""Rigid convex polyhedra as data: vertices, faces as vertex loops with their planes, and edges; built
from points (faces from the convex hull), from given faces, as boxes or as extrusions of 2D blocks, and
checked at load. Their mass properties: `bbmc.geometry.polyhedron_mass`; cutting them by planes and
joint sets: `bbmc.geometry.polyhedron_cutting`.

Axes: x east, y north, z up (`bbmc.geometry.orientation`); metres. Plain numpy.

Layout of a `Polyhedron` (flat arrays, ready for numba kernels): face f's vertex loop is
``face_vertices[face_start[f]:face_start[f + 1]]``, ordered anticlockwise seen from outside (the right-hand
rule about the loop gives the outward normal); its plane is ``normals[f] . x = offsets[f]``.

Tolerances, all relative to the block's size (the diagonal of its bounding box), so a block of any size is
judged alike: distances at or below `TOLERANCE` x size are zero (a point on a plane, a face's flatness,
two vertices at one point, a point outside a face's plane), and a face's corner is straight or reflex when
the sine of its turn (between its unit edges) is at or below `TOLERANCE`. The hull's triangles are merged
into one polygonal face when they lie within the distance tolerance of one plane: for a face of the
block's size, planes within about 1e-9 rad of each other.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError, cKDTree

from bbmc.geometry.polygons import shape_fault

TOLERANCE = 1e-9  # of the block's size (distances) or a sine (angles): see the module's docstring
UNTAGGED = -1  # the tag of a face that no cut made (`Polyhedron.face_tags`)


@dataclass(frozen=True, eq=False)
class Polyhedron:
    """A rigid convex polyhedron (the module's docstring gives the layout); arrays are read-only.

    `vertices` (n, 3) float64 [m]; `face_vertices` (L,) int64 and `face_start` (f + 1,) int64: the faces'
    vertex loops; `normals` (f, 3) outward unit normals; `offsets` (f,) [m] (n . x = d on the face);
    `edges` (m, 2) int64, each edge once as (i, j) with i < j, sorted; `face_tags` (f,) int64: what made
    each face (the joint set whose cut made it, `UNTAGGED` for the block's own faces)."""

    vertices: np.ndarray
    face_vertices: np.ndarray
    face_start: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    edges: np.ndarray
    face_tags: np.ndarray

    @property
    def face_count(self) -> int:
        """The number of faces f."""
        return len(self.face_start) - 1

    @property
    def size(self) -> float:
        """The diagonal of the bounding box [m], the scale of every tolerance."""
        return float(np.linalg.norm(np.ptp(self.vertices, axis=0)))

    def face(self, f: int) -> np.ndarray:
        """Face f's vertex indices, anticlockwise seen from outside."""
        return self.face_vertices[self.face_start[f] : self.face_start[f + 1]]

    def faces(self) -> tuple[np.ndarray, ...]:
        """Every face's vertex indices (`face`)."""
        return tuple(np.split(self.face_vertices, self.face_start[1:-1]))


def from_vertices(
    points: np.ndarray, faces: Sequence[Sequence[int]] | None = None, *, name: str = "block"
) -> Polyhedron:
    """The convex polyhedron with these corners `points` (n, 3) [m].

    Without `faces`, the faces are those of the convex hull (Qhull, Barber et al. 1996, through
    scipy.spatial.ConvexHull), its triangles merged into polygonal faces where they lie on one plane
    (the module's tolerance). With `faces` (vertex-index loops, each in either sense: they are turned
    anticlockwise seen from outside), each face must be planar and strictly convex, the faces must close
    a surface, and the solid must be convex. Either way every point must be a corner (on three faces or
    more). Refused with a ValueError of one line naming the block (`name`): fewer than 4 points, a
    coordinate not finite, points at one point, on one line or one plane (no volume), a point inside
    the hull or on a face or edge, faces not planar, not closing, coplanar neighbours, non-convex."""
    vertices = np.array(points, dtype=float)
    fault = _points_fault(vertices)
    if fault is None:
        unit = (vertices - vertices.mean(axis=0)) / _size(vertices)
        loops = _hull_faces(unit) if faces is None else _given_loops(faces, len(vertices))
        fault = loops if isinstance(loops, str) else None
    if fault is None:
        fault = _solid_fault(unit, loops)
    if fault is not None:
        raise ValueError(f"{name}: {fault}")
    return assembled(vertices, *_flat(_oriented(unit, loops)), np.full(len(loops), UNTAGGED))


def box(lo: Sequence[float], hi: Sequence[float], *, name: str = "box") -> Polyhedron:
    """The axis-aligned box of corners `lo` and `hi` (3,) [m], lo < hi in every axis; faces in the
    order -x, +x, -y, +y, -z, +z."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    if lo.shape != (3,) or hi.shape != (3,) or not np.all(hi > lo):
        raise ValueError(f"{name}: a box needs lo < hi in x, y and z, got lo {lo}, hi {hi}")
    corners = np.array([[hi[i] if (k >> i) & 1 else lo[i] for i in range(3)] for k in range(8)])
    faces = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]
    return from_vertices(corners, faces, name=name)


def extrude(polygon: np.ndarray, y0: float, y1: float, *, name: str = "block") -> Polyhedron:
    """A convex 2D block extruded along the out-of-plane axis: the 2D polygon (k, 2) [m] of a bbmc 2D
    scene (x horizontal, y up), counter-clockwise or not, becomes the prism between y = `y0` and y = `y1`
    [m] in 3D with (x, y)_2D -> (x, z)_3D: x stays horizontal and the 2D up becomes z (up), so gravity
    keeps its axis. The map is a proper rotation: the 2D drawing is the prism seen from -y (looking
    north), and a 2D counter-clockwise turn is a turn about -y. Faces: the k sides (side i along the 2D
    edge from vertex i to i + 1), then the ends at y0 and y1; vertices: the polygon at y0, then at y1."""
    polygon = np.asarray(polygon, dtype=float)
    fault = shape_fault(polygon) if polygon.ndim == 2 and polygon.shape[1] == 2 else "not a (k, 2) array"
    if fault is not None:
        raise ValueError(f"{name}: the polygon to extrude: {fault}")
    if not y1 > y0:
        raise ValueError(f"{name}: an extrusion needs y1 > y0, got {y0} to {y1}")
    k = len(polygon)
    near = np.column_stack([polygon[:, 0], np.full(k, y0), polygon[:, 1]])
    far = near + np.array([0.0, y1 - y0, 0.0])
    sides = [[i, (i + 1) % k, (i + 1) % k + k, i + k] for i in range(k)]
    return from_vertices(np.vstack([near, far]), [*sides, list(range(k)), list(range(k, 2 * k))], name=name)


def moved(block: Polyhedron, rotation: np.ndarray, translation: np.ndarray) -> Polyhedron:
    """The block turned by `rotation` (3, 3) about the origin, then shifted by `translation` (3,) [m]:
    x' = R x + t, n' = R n, d' = d + n' . t; faces, edges and tags as before."""
    normals = block.normals @ rotation.T
    return Polyhedron(
        *_read_only(
            block.vertices @ rotation.T + translation,
            block.face_vertices,
            block.face_start,
            normals,
            block.offsets + normals @ translation,
            block.edges,
            block.face_tags,
        )
    )


def polyhedron_fault(block: Polyhedron) -> str | None:
    """Why `block` is no rigid convex polyhedron (`from_vertices`' checks on its vertices and loops,
    and its normals and offsets against its loops), or None."""
    fault = _points_fault(block.vertices)
    if fault is not None:
        return fault
    mean, size = block.vertices.mean(axis=0), _size(block.vertices)
    unit = (block.vertices - mean) / size
    loops = list(block.faces())
    fault = _solid_fault(unit, loops)
    if fault is not None:
        return fault
    normals, offsets = _loop_planes(unit, loops)
    if np.any(offsets <= 0):
        return f"face {int(np.argmin(offsets))}'s loop is not anticlockwise seen from outside"
    if np.any(np.sum(normals * block.normals, axis=1) < 1.0 - TOLERANCE):
        return f"face {int(np.argmin(np.sum(normals * block.normals, axis=1)))}'s normal is not its plane's"
    if np.any(np.abs(block.offsets - block.normals @ mean - size * offsets) > TOLERANCE * size):
        return "a face's offset is not its plane's"
    return None


def assembled(
    vertices: np.ndarray, face_vertices: np.ndarray, face_start: np.ndarray, tags: np.ndarray
) -> Polyhedron:
    """A `Polyhedron` from vertices (n, 3) [m], face loops already anticlockwise seen from outside (flat
    indices (L,) and starts (f + 1,), the `Polyhedron` layout) and the faces' tags (f,), without checks
    (`polyhedron_fault` makes them): the planes by Newell's method (the loop's area vector), the edges
    from the loops."""
    mean, size = vertices.mean(axis=0), _size(vertices)
    following = _successors(face_vertices, face_start)
    normals, offsets = _planes((vertices - mean) / size, face_vertices, face_start, following)
    edges = np.unique(np.sort(np.column_stack([face_vertices, following]), axis=1), axis=0)
    return Polyhedron(
        *_read_only(
            vertices, face_vertices, face_start, normals, size * offsets + normals @ mean, edges, tags
        )
    )


def _read_only(*arrays: np.ndarray) -> list[np.ndarray]:
    kinds = [np.float64, np.int64, np.int64, np.float64, np.float64, np.int64, np.int64]
    copies = [np.array(a, dtype=kind) for a, kind in zip(arrays, kinds, strict=True)]
    for array in copies:
        array.setflags(write=False)
    return copies


def _size(vertices: np.ndarray) -> float:
    return float(np.linalg.norm(np.ptp(vertices, axis=0)))


def cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of (n, 3) arrays (np.cross's axis handling costs more on small arrays)."""
    return np.column_stack(
        [
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        ]
    )


def _points_fault(vertices: np.ndarray) -> str | None:
    """Faults of the points alone: shape, count, finiteness, size, points at one point."""
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        return f"its vertices must be an (n, 3) array, got shape {vertices.shape}"
    if len(vertices) < 4:
        return f"a polyhedron needs at least 4 vertices, got {len(vertices)}"
    if not np.all(np.isfinite(vertices)):
        return "a vertex coordinate is not a finite number"
    with np.errstate(over="ignore"):
        size = _size(vertices)
    reach = float(np.abs(vertices).max())
    if size == 0.0:
        return "all its vertices are at one point"
    if not 1e-60 <= size <= 1e60:
        return f"its size ({size:.3g} m across) is beyond what floating point holds in its inertia (size^5)"
    if not size > TOLERANCE * reach:
        return (
            f"it is too small ({size:.3g} m across) for its distance from the origin: its vertices "
            "cannot be told apart in floating point"
        )
    pairs = cKDTree(vertices / size).query_pairs(TOLERANCE, output_type="ndarray")
    if len(pairs):
        i, j = sorted(pairs[0])
        return f"two vertices coincide (vertices {i} and {j})"
    return None


def _hull_faces(unit: np.ndarray) -> list[np.ndarray] | str:
    """The hull's faces of points (n, 3) at unit size: the triangles grouped by plane (a neighbour
    joins a group when its corners lie within the tolerance of the group's first triangle's plane),
    each group's boundary chained into one loop; or why there is no hull."""
    try:
        hull = ConvexHull(unit)
    except QhullError:
        return "its vertices lie on one plane or one line: it has no volume"
    triangles = hull.simplices.copy()
    normals = hull.equations[:, :3]
    corner = unit[triangles[:, 0]]
    area = cross_rows(unit[triangles[:, 1]] - corner, unit[triangles[:, 2]] - corner)
    flip = np.einsum("ij,ij->i", area, normals) < 0
    triangles[flip] = triangles[flip][:, ::-1]
    group = np.full(len(triangles), -1)
    loops = []
    for seed in range(len(triangles)):
        if group[seed] >= 0:
            continue
        group[seed] = seed
        members, pending = [seed], [seed]
        while pending:
            for other in hull.neighbors[pending.pop()]:
                distance = unit[triangles[other]] @ normals[seed] + hull.equations[seed, 3]
                if group[other] < 0 and np.all(np.abs(distance) <= TOLERANCE):
                    group[other] = seed
                    members.append(other)
                    pending.append(other)
        loops.append(_boundary(triangles[members]))
    return loops


def _boundary(triangles: np.ndarray) -> np.ndarray:
    """The boundary loop of a patch of consistently oriented triangles (t, 3) that tile a convex
    polygon: the directed edges whose reverse is not in the patch, chained."""
    directed = {(int(a), int(b)) for t in triangles for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    following = {a: b for a, b in directed if (b, a) not in directed}
    loop = [next(iter(following))]
    while following[loop[-1]] != loop[0]:
        loop.append(following[loop[-1]])
    return np.array(loop, dtype=np.int64)


def _given_loops(faces: Sequence[Sequence[int]], count: int) -> list[np.ndarray] | str:
    """The given faces as index arrays, or why they cannot be faces of `count` vertices."""
    loops = []
    for f, face in enumerate(faces):
        loop = np.asarray(face)
        if loop.ndim != 1 or len(loop) < 3 or not np.issubdtype(loop.dtype, np.integer):
            return f"face {f} must be a loop of at least 3 vertex indices, got {face!r}"
        if loop.min() < 0 or loop.max() >= count:
            return f"face {f} names a vertex outside 0 to {count - 1}"
        if len(np.unique(loop)) < len(loop):
            return f"face {f} names a vertex twice"
        loops.append(loop.astype(np.int64))
    if len(loops) < 4:
        return f"a polyhedron needs at least 4 faces, got {len(loops)}"
    return loops


def _flat(loops: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The loops as one flat index array (L,) and each loop's start (f + 1,)."""
    flat = np.concatenate(loops).astype(np.int64)
    return flat, np.concatenate([[0], np.cumsum([len(loop) for loop in loops])]).astype(np.int64)


def successor_entries(start: np.ndarray) -> np.ndarray:
    """For flat face loops starting at `start` (f + 1,): the position of each entry's successor in its
    loop (the next entry; the loop's first after its last)."""
    after = np.arange(1, start[-1] + 1)
    after[start[1:] - 1] = start[:-1]
    return after


def _successors(flat: np.ndarray, start: np.ndarray) -> np.ndarray:
    return flat[successor_entries(start)]


def _planes(
    unit: np.ndarray, flat: np.ndarray, start: np.ndarray, following: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each loop's unit normal by Newell's method (the normalised area vector, sum of p_i x p_i+1 / 2)
    and its plane's offset, the mean of n . p over the loop (flat loops, their starts, and each entry's
    successor)."""
    normals = np.add.reduceat(cross_rows(unit[flat], unit[following]), start[:-1])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    centres = np.add.reduceat(unit[flat], start[:-1]) / np.diff(start)[:, None]
    return normals, np.sum(centres * normals, axis=1)


def _loop_planes(unit: np.ndarray, loops: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    flat, start = _flat(loops)
    return _planes(unit, flat, start, _successors(flat, start))


def _oriented(unit: np.ndarray, loops: Sequence[np.ndarray]) -> list[np.ndarray]:
    """The loops turned anticlockwise seen from outside: the vertices' mean (0 at unit size) lies
    inside a convex block, so a face's plane offset must be positive."""
    _, offsets = _loop_planes(unit, loops)
    return [loop if offset > 0 else loop[::-1] for loop, offset in zip(loops, offsets, strict=True)]


def _solid_fault(unit: np.ndarray, loops: Sequence[np.ndarray]) -> str | None:
    """Why vertices (n, 3) at unit size (mean 0) and face loops make no convex solid, or None."""
    edge_faces: dict[tuple[int, int], list[int]] = {}
    for f, loop in enumerate(loops):
        for a, b in zip(loop, np.roll(loop, -1), strict=True):
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(f)
    for (a, b), faces in edge_faces.items():
        if len(faces) != 2:
            return f"its faces do not close a surface (edge {a}-{b} is on {len(faces)} faces, not 2)"
    count = np.bincount(np.concatenate(loops), minlength=len(unit))
    if np.any(count < 3):
        k = int(np.argmax(count < 3))
        return (
            f"vertex {k} is not a corner (it is on {count[k]} faces, fewer than 3: inside the solid, "
            "or on one of its faces or edges)"
        )
    loops = _oriented(unit, loops)
    normals, offsets = _loop_planes(unit, loops)
    for f, (loop, normal, offset) in enumerate(zip(loops, normals, offsets, strict=True)):
        off = np.abs(unit[loop] @ normal - offset)
        if off.max() > TOLERANCE:
            return f"face {f} is not planar (vertex {loop[off.argmax()]} is off its plane)"
        fault = _face_convexity(unit[loop], normal)
        if fault is not None:
            return f"face {f} is not strictly convex ({fault})"
    outside = unit @ normals.T - offsets
    if outside.max() > TOLERANCE:
        k, f = np.unravel_index(outside.argmax(), outside.shape)
        return f"it is not convex (vertex {k} is outside the plane of face {f})"
    for (a, b), (f, g) in edge_faces.items():
        if np.linalg.norm(np.cross(normals[f], normals[g])) <= TOLERANCE:
            return f"faces {f} and {g} lie on one plane (at edge {a}-{b}): make them one face"
    return None


def _face_convexity(corners: np.ndarray, normal: np.ndarray) -> str | None:
    """Why a face's loop of `corners` (k, 3) is no strictly convex polygon about `normal`: a corner that
    turns clockwise or not at all (the sine of the turn between unit edges at or below the tolerance),
    or edges that turn more than once around (a star); or None."""
    edges = np.roll(corners, -1, axis=0) - corners
    edges /= np.linalg.norm(edges, axis=1, keepdims=True)
    before = np.roll(edges, 1, axis=0)
    turns = np.cross(before, edges) @ normal
    if turns.min() <= TOLERANCE:
        return f"a reflex or straight angle at its corner {int(turns.argmin())}"
    if np.arctan2(turns, np.sum(before * edges, axis=1)).sum() > 3.0 * np.pi:
        return "its edges cross each other"
    return None
