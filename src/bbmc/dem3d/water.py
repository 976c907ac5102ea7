"""Joint water of the 3D engine: a phreatic plane, its pressure, and its loads on the blocks' faces.

A `WaterTable` is a plane through `point` with normal `normal` (with a vertical component), the
phreatic surface z_table(x, y). Below it the water is hydrostatic:

    p(x, y, z) = gamma_w max(z_table(x, y) - z, 0)        [Pa], gamma_w [N/m^3], x, y, z [m]

with z_table(x, y) = z0 + a x + b y, a = -n_x / n_z, b = -n_y / n_z, z0 = (n . point) / n_z.

The 2D engine's rule (`bbmc.dem.water`, UDEC's): the pressure acts on every face of every block that
can move, wherever it lies below the table, on both sides of each joint (each block gets its own face
load, equal and opposite to its neighbour's across a closed joint), and the contacts' springs carry the
effective stress sigma_n' = sigma_n - p (Terzaghi), which the strength sees. A block wholly under
water feels its buoyancy (Archimedes), a block on a wet joint the uplift, an open crack its hydrostatic
thrust. On a face (outward normal n) the load -p n is integrated exactly (`add_water_loads`): the face
is clipped to its wet part, where the head h = z_table - z, linear over the plane, is >= 0, and over
that part P

    F = -gamma_w A_P h(c_P) n at its centroid c_P, and the couple -gamma_w (S_P grad h) x n about c_P,

S_P the part's second-moment tensor in the plane. A joint type's given uniform `pressure` (the
limit-equilibrium wedge's "equal uniform pressures", its given pressure per plane) acts on the closed
parts of its contacts instead (`bbmc.dem3d.contact_forces`): p A along the normal, pushing the blocks
apart. The table is kept in every row of the joint types' parameters (`bbmc.dem3d.joint_laws`), the
same in each, so the engine's kernels carry it with the laws. Units: m, Pa, N/m^3, N, N m. Source:
Itasca, UDEC/3DEC manuals (joint water pressure, effective stresses at the contacts); Hoek & Bray, Rock
Slope Engineering (U on a sliding plane, V in a tension crack).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from bbmc.dem3d.face_contact import _in_plane, face_frame
from bbmc.dem3d.layout import DOFS, FX, PRESCRIBED, TX, X
from bbmc.dem3d.polygon_clip import clip_half_plane, polygon_moments


@dataclass(frozen=True)
class WaterTable:
    """A phreatic plane: water of `unit_weight` gamma_w [N/m^3] below the plane through `point` [m]
    with normal `normal` (any length, not horizontal)."""

    unit_weight: float
    point: Sequence[float]
    normal: Sequence[float]

    def coefficients(self) -> tuple[float, float, float, float]:
        """(gamma_w [N/m^3], z0 [m], a [1], b [1]): z_table(x, y) = z0 + a x + b y. A gamma_w < 0, or a
        normal that is not three finite numbers with a vertical component, is refused in one line."""
        n, p = np.asarray(self.normal, dtype=float), np.asarray(self.point, dtype=float)
        if n.shape != (3,) or p.shape != (3,) or not (np.all(np.isfinite(n)) and np.all(np.isfinite(p))):
            raise ValueError("water: point and normal must be three finite numbers each")
        if not self.unit_weight >= 0.0:
            raise ValueError(f"water: unit_weight must be >= 0 N/m3, got {self.unit_weight}")
        length = float(np.linalg.norm(n))
        if not length > 0.0 or abs(n[2]) < 1e-9 * length:
            raise ValueError("water: the table's normal must have a vertical component (a plane z(x, y))")
        return float(self.unit_weight), float(n @ p / n[2]), float(-n[0] / n[2]), float(-n[1] / n[2])


@numba.njit(cache=True)
def _face_load(vertices, face_vertices, face_start, face_normal, f, gamma, z0, a, b):
    """Face f's water load (module docstring): (force (3,) [N], its point c_P (3,) [m], couple (3,)
    [N m]); zeros where the face is dry."""
    o, s, t = face_frame(vertices, face_vertices, face_start, face_normal, f)
    gx, gy, gz = a, b, -1.0  # grad h
    head_o = z0 + a * o[0] + b * o[1] - o[2]
    gs, gt = gx * s[0] + gy * s[1] + gz * s[2], gx * t[0] + gy * t[1] + gz * t[2]
    wet = clip_half_plane(_in_plane(vertices, face_vertices, face_start, f, o, s, t, False), gs, gt, head_o)
    area, cs, ct, sss, sst, stt = polygon_moments(wet)
    force, point, couple = np.zeros(3), o + cs * s + ct * t, np.zeros(3)
    if area <= 0.0:
        return force, point, couple
    n = face_normal[f]
    force[:] = -gamma * area * (head_o + gs * cs + gt * ct) * n
    lever = (sss * gs + sst * gt) * s + (sst * gs + stt * gt) * t
    couple[0] = -gamma * (lever[1] * n[2] - lever[2] * n[1])
    couple[1] = -gamma * (lever[2] * n[0] - lever[0] * n[2])
    couple[2] = -gamma * (lever[0] * n[1] - lever[1] * n[0])
    return force, point, couple


@numba.njit(cache=True)
def add_water_loads(blocks, dof, vertices, vertex_start, face_vertices, face_start, block_face_start,
                    face_normal, table):  # fmt: skip
    """Add the phreatic table's load on every face of each block that can move (not all six dofs
    prescribed) to its FX.. and TX.. columns (force, and torque about the centroid); `table` (4,) is
    (gamma_w, z0, a, b) (`WaterTable.coefficients`; none where gamma_w = 0). A block whose vertices are
    all above the table is skipped."""
    gamma, z0, a, b = table[0], table[1], table[2], table[3]
    if gamma == 0.0:
        return
    for i in range(blocks.shape[0]):
        held = True
        for d in range(DOFS):
            held = held and dof[i, d] == PRESCRIBED
        deepest = -np.inf
        for v in range(vertex_start[i], vertex_start[i + 1]):
            deepest = max(deepest, z0 + a * vertices[v, 0] + b * vertices[v, 1] - vertices[v, 2])
        if held or deepest <= 0.0:
            continue
        for f in range(block_face_start[i], block_face_start[i + 1]):
            force, point, couple = _face_load(
                vertices, face_vertices, face_start, face_normal, f, gamma, z0, a, b
            )
            r = point - blocks[i, X : X + 3]
            blocks[i, FX] += force[0]
            blocks[i, FX + 1] += force[1]
            blocks[i, FX + 2] += force[2]
            blocks[i, TX] += r[1] * force[2] - r[2] * force[1] + couple[0]
            blocks[i, TX + 1] += r[2] * force[0] - r[0] * force[2] + couple[1]
            blocks[i, TX + 2] += r[0] * force[1] - r[1] * force[0] + couple[2]
