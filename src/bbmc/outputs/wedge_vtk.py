"""A wedge as a VTK file for ParaView: its faces triangulated, each triangle tagged with the face it
belongs to (written with meshio).

The faces of a wedge (`bbmc.slope.wedge.geometry`; toe O, crest points C1, C2, top T; with a tension
crack P on plane 1, Q on plane 2, R on the line of intersection):

    face_id  face           tetrahedron O C1 C2 T     with a crack O C1 C2 P Q R
    1        plane 1        O C1 T                    O C1 P R
    2        plane 2        O C2 T                    O C2 Q R
    3        slope face     O C1 C2                   O C1 C2
    4        upper surface  C1 C2 T                   C1 C2 Q P
    5        tension crack  -                         P Q R

Each face is a convex polygon, fanned into triangles from its first vertex; every triangle is turned so
that its vertices run anticlockwise seen from outside the wedge (its normal points out), so the volume
by the divergence theorem over the closed surface, V = (1/6) sum over triangles of a . (b x c), is the
wedge's volume.

wedge.vtu: points the wedge's vertices [m] (toe at the origin, x east, y north, z up); triangle cells
with cell data face_id (the table), area_m2 and normal (the outward unit normal); field data
face_names is not written (meshio writes numbers only): the table above is the key.
"""

from __future__ import annotations

import tempfile
from dataclasses import fields, replace
from pathlib import Path

import meshio
import numpy as np
from numpy.typing import NDArray

from bbmc.slope.wedge.geometry import WedgeGeometry, WedgeNotFormedError, WedgeReason

FACE_NAMES = {1: "plane 1", 2: "plane 2", 3: "slope face", 4: "upper surface", 5: "tension crack"}
_TETRAHEDRON = {1: (0, 1, 3), 2: (0, 2, 3), 3: (0, 1, 2), 4: (1, 2, 3)}
_CUT = {1: (0, 1, 3, 5), 2: (0, 2, 4, 5), 3: (0, 1, 2), 4: (1, 2, 4, 3), 5: (3, 4, 5)}
_ARRAYS = {f.name for f in fields(WedgeGeometry)} - {"has_crack", "short_solution"}


def one_wedge(geometry: WedgeGeometry, index: tuple[int, ...] = ()) -> WedgeGeometry:
    """The wedge at `index` of a batch (() for a single wedge) as a single wedge's geometry; raises
    WedgeNotFormedError with its reason where it does not form."""
    reason = np.asarray(geometry.reason)[index]
    if np.ndim(reason) != 0:
        raise ValueError(f"index: {index} picks {np.size(reason)} wedges, not one")
    if reason != WedgeReason.FORMED:
        raise WedgeNotFormedError(WedgeReason(int(reason)))
    picked = {name: np.asarray(value)[index] for name, value in vars(geometry).items() if name in _ARRAYS}
    short = geometry.short_solution
    short = type(short)(**{name: np.asarray(value)[index] for name, value in vars(short).items()})
    return replace(geometry, **picked, short_solution=short)


def wedge_faces(geometry: WedgeGeometry) -> tuple[NDArray[np.float64], dict[int, tuple[int, ...]]]:
    """The vertices (n, 3) [m] of one formed wedge and its faces by face_id (module docstring) as vertex
    indices, each polygon's vertices in order around it."""
    return np.asarray(geometry.vertices, dtype=float), (_CUT if geometry.has_crack else _TETRAHEDRON)


def wedge_triangles(
    geometry: WedgeGeometry,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """The vertices (n, 3) [m] of one formed wedge, its faces' triangles (m, 3) as vertex indices, each
    anticlockwise seen from outside, and each triangle's face_id (m,)."""
    points, faces = wedge_faces(geometry)
    centre = points.mean(axis=0)  # inside the convex wedge
    triangles, ids = [], []
    for face_id, polygon in faces.items():
        for k in range(1, len(polygon) - 1):
            a, b, c = polygon[0], polygon[k], polygon[k + 1]
            normal = np.cross(points[b] - points[a], points[c] - points[a])
            triangles.append((a, b, c) if normal @ (points[a] - centre) > 0.0 else (a, c, b))
            ids.append(face_id)
    return points, np.array(triangles, dtype=np.int64), np.array(ids, dtype=np.int64)


def enclosed_volume(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> float:
    """V = (1/6) sum a . (b x c) [m^3] over the triangles (m, 3) of a closed surface, each anticlockwise
    seen from outside (the divergence theorem with the field x / 3)."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)


def wedge_mesh(geometry: WedgeGeometry, index: tuple[int, ...] = ()) -> meshio.Mesh:
    """The wedge at `index` as a triangle mesh with cell data face_id, area_m2 and normal (module
    docstring)."""
    points, triangles, ids = wedge_triangles(one_wedge(geometry, index))
    a, b, c = (points[triangles[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)
    length = np.linalg.norm(cross, axis=1)
    return meshio.Mesh(
        points,
        [("triangle", triangles)],
        cell_data={"face_id": [ids], "area_m2": [length / 2.0], "normal": [cross / length[:, None]]},
    )


def write_wedge_vtu(path: Path | str, geometry: WedgeGeometry, index: tuple[int, ...] = ()) -> Path:
    """Write the wedge at `index` to `path` (.vtu, `wedge_mesh`); returns the path."""
    path = Path(path)
    meshio.write(path, wedge_mesh(geometry, index), binary=True)
    return path


def wedge_vtu_bytes(geometry: WedgeGeometry, index: tuple[int, ...] = ()) -> bytes:
    """The .vtu file of the wedge at `index` (`write_wedge_vtu`) as bytes, for a stage to write with its
    other files at once."""
    with tempfile.TemporaryDirectory() as folder:
        return write_wedge_vtu(Path(folder) / "wedge.vtu", geometry, index).read_bytes()
