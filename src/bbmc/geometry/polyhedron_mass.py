"""The mass properties of a rigid convex polyhedron (`bbmc.geometry.polyhedra`), exact: volume,
centroid, the inertia tensor about the centroid, principal moments and axes, from its decomposition
into tetrahedra (Tonon 2004)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.geometry.polyhedra import Polyhedron, cross_rows


@dataclass(frozen=True)
class MassProperties:
    """`volume` [m^3], `mass` [kg], `centroid` (3,) [m], `inertia` (3, 3) [kg m^2] about the centroid in
    the world axes, `principal_moments` (3,) [kg m^2] ascending and `principal_axes` (3, 3) whose columns
    are the matching unit axes: a rotation (det +1), inertia = axes @ diag(moments) @ axes.T."""

    volume: float
    mass: float
    centroid: np.ndarray
    inertia: np.ndarray
    principal_moments: np.ndarray
    principal_axes: np.ndarray


def mass_properties(block: Polyhedron, density: float = 1.0) -> MassProperties:
    """Volume, mass, centroid and inertia tensor of a uniform solid of `density` [kg/m^3], exact for a
    polyhedron: the sum over tetrahedra (m, a, b, c) from the vertices' mean m to each face's fan
    triangles (a, b, c), with relative corners p, q, r:

    * volume V = (p x q) . r / 6 (signed: each > 0 for a convex block, m inside);
    * first moment V (p + q + r) / 4;
    * second moment S = integral of x x^T dV = V / 20 (p p^T + q q^T + r r^T + s s^T), s = p + q + r
      (the tetrahedron's canonical covariance; Tonon 2004, "Explicit exact formulas for the 3-D
      tetrahedron inertia tensor in terms of its vertex coordinates", J. Math. Stat. 1(1), eqs. 2-8);
    * about the centroid c: S_c = S - V c c^T, and the inertia I = rho (tr(S_c) 1 - S_c).

    Summed about m, not the origin, so a block far from the origin is not the difference of large
    numbers (the 2D `mass_properties`' lesson). Principal axes: the eigenvectors of I, moments
    ascending; each axis turned so its largest component is positive, then the last one flipped if
    needed to make a right-handed frame."""
    mean, (p, q, r), volumes = _tetrahedra(block)
    s = p + q + r
    volume = float(volumes.sum())
    centre = (volumes @ s) / (4.0 * volume)
    second = np.einsum("i,ij,ik->jk", volumes / 20.0, p, p)
    for corner in (q, r, s):
        second += np.einsum("i,ij,ik->jk", volumes / 20.0, corner, corner)
    second -= volume * np.outer(centre, centre)
    inertia = density * (np.trace(second) * np.eye(3) - second)
    inertia = 0.5 * (inertia + inertia.T)
    moments, axes = np.linalg.eigh(inertia)
    biggest = np.abs(axes).argmax(axis=0)
    axes = axes * np.sign(axes[biggest, np.arange(3)])
    axes[:, 2] *= np.sign(np.linalg.det(axes))
    return MassProperties(volume, density * volume, centre + mean, inertia, moments, axes)


def volume(block: Polyhedron) -> float:
    """The block's volume [m^3]: the sum of the signed volumes (p x q) . r / 6 of the tetrahedra from
    the vertices' mean to each face's fan triangles (`mass_properties`)."""
    return float(_tetrahedra(block)[2].sum())


def _tetrahedra(block: Polyhedron) -> tuple[np.ndarray, tuple[np.ndarray, ...], np.ndarray]:
    """The vertices' mean m, the corners p, q, r (t, 3) of each face's fan triangles relative to m, and
    each tetrahedron's signed volume (p x q) . r / 6 (t,)."""
    mean = block.vertices.mean(axis=0)
    p, q, r = (block.vertices[corner] - mean for corner in _fan_triangles(block))
    return mean, (p, q, r), np.einsum("ij,ij->i", cross_rows(p, q), r) / 6.0


def _fan_triangles(block: Polyhedron) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each face split into the triangles (v_0, v_i, v_i+1), 0 < i < k - 1, of its loop of k vertices:
    three index arrays."""
    lengths = np.diff(block.face_start)
    first = np.repeat(block.face_start[:-1], lengths)
    position = np.arange(len(block.face_vertices)) - first
    middle = np.flatnonzero((position >= 1) & (position <= np.repeat(lengths, lengths) - 2))
    flat = block.face_vertices
    return flat[first[middle]], flat[middle], flat[middle + 1]
