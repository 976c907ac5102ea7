"""A plane-strain 3D twin of a 2D section: every 2D block extruded into a prism, with the out-of-plane
constraints that make the 3D engine reproduce the 2D engine.

Axes: the 2D section is x horizontal, y up (`bbmc.dem`); the 3D engine's z is up (`bbmc.geometry.
orientation`). The twin maps 2D (x, y) -> 3D (x, z) and extrudes along 3D y from 0 to the `depth`
(`bbmc.geometry.polyhedra.extrude`), so gravity keeps its axis: a 2D acceleration (g_x, g_y) becomes
(g_x, 0, g_y). The map is a proper rotation seen from -y, so a 2D counter-clockwise turn theta is a turn
-theta about the world y axis, and the 2D degrees of freedom (x, y, rotation) are the 3D ones (x, z,
rotation about y) = dof columns (0, 2, 4) of `bbmc.dem3d.layout` (`IN_PLANE`).

Plane strain, two ways (`constraint`):

* ``held`` (default): every block's out-of-plane translation (y) and its rotations about the two
  in-plane axes (x and z) are prescribed at zero velocity (`OUT_OF_PLANE`: dof columns 1, 3, 5); the
  motion kernel's constrained kick then turns the block about y alone (`bbmc.dem3d.motion`). A prism is
  symmetric about its mid-depth plane, so y is one of its principal axes and the kick is exact.
* ``walls``: two held, frictionless side walls (boxes `WALL_THICKNESS` x the depth thick, one against
  each end of the prisms, reaching `WALL_MARGIN` x the section's extent beyond it) on a joint type of
  their own: the stiffest joint type's K_n and K_s, no friction, no cohesion. The blocks' own dofs stay
  free, as in 3DEC's plane-strain models; the walls' normal springs hold y and the two in-plane-axis
  rotations elastically, and carry no shear, so they take nothing from the in-plane mechanism.

Per unit depth the twin has the 2D block's mass and moment (the 2D engine works per metre of
thickness): a prism of area A and depth d has mass rho A d, centroid (x_c, d / 2, y_c) and moment about
its axis rho d J_p (J_p the section's polar moment), so every force, and so every factor of safety,
is d x the 2D one and their ratios are the 2D engine's. Units: m, kg, s, Pa/m.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from bbmc.dem3d.joint_laws import JointLaw, MohrCoulomb
from bbmc.dem3d.layout import PRESCRIBED
from bbmc.dem3d.model import Model, build_model
from bbmc.geometry.polyhedra import box, extrude

IN_PLANE = (0, 2, 4)  # the 3D dofs of 2D (x, y, rotation): x, z, rotation about y
OUT_OF_PLANE = (1, 3, 5)  # y, rotation about x, rotation about z
WALL_THICKNESS = 0.5  # x the depth [1]
WALL_MARGIN = 0.5  # x the section's extent, how far the walls reach beyond it [1]
CONSTRAINTS = ("held", "walls")


def gravity_3d(gravity_2d: Sequence[float]) -> np.ndarray:
    """The 3D acceleration (g_x, 0, g_y) [m/s^2] of the 2D (g_x, g_y)."""
    return np.array([gravity_2d[0], 0.0, gravity_2d[1]], dtype=float)


def extruded_model(
    polygons: Sequence[np.ndarray],
    depth: float,
    density: float | Sequence[float],
    laws: Sequence[JointLaw],
    *,
    dof_2d: np.ndarray | None = None,
    gravity_2d: Sequence[float] = (0.0, -9.81),
    group: Sequence[int] | None = None,
    pair_joint: np.ndarray | None = None,
    refine: int = 1,
    constraint: str = "held",
) -> Model:
    """The plane-strain twin (module docstring) of the 2D blocks `polygons` ((k, 2) each [m], x right, y
    up), extruded `depth` [m], of `density` [kg/m^3] (one or one each), on the joint types `laws` chosen
    by `group` and `pair_joint` as `bbmc.dem3d.model.build_model` chooses them; `dof_2d` (n, 3) int64
    the 2D dof codes (x, y, rotation; FREE or PRESCRIBED at zero velocity, default all free): a block
    prescribed in all three is held in all six; `gravity_2d` [m/s^2]; `refine` the faces' triangulation;
    `constraint` ``held`` or ``walls``. With walls, blocks n and n + 1 are the walls, of a group and a
    joint type after the given ones. Refused in one line naming the key: a depth <= 0, an unknown
    constraint, a dof_2d of the wrong shape (and whatever `build_model` refuses, naming the block)."""
    n = len(polygons)
    if not depth > 0.0:
        raise ValueError(f"depth: must be > 0 m, got {depth}")
    if constraint not in CONSTRAINTS:
        raise ValueError(f"constraint: must be one of {', '.join(CONSTRAINTS)}, got {constraint!r}")
    codes = np.zeros((n, 3), dtype=np.int64) if dof_2d is None else np.asarray(dof_2d, dtype=np.int64)
    if codes.shape != (n, 3):
        raise ValueError(f"dof_2d: one row (x, y, rotation) per block, shape ({n}, 3), got {codes.shape}")
    prisms = [extrude(p, 0.0, depth, name=f"block {i}") for i, p in enumerate(polygons)]
    held = [i for i in range(n) if np.all(codes[i] == PRESCRIBED)]
    groups = np.zeros(n, dtype=np.int64) if group is None else np.asarray(group, dtype=np.int64)
    pairs = np.zeros((1, 1), dtype=np.int64) if pair_joint is None else np.asarray(pair_joint, dtype=np.int64)
    densities = np.broadcast_to(np.asarray(density, dtype=float), (n,))
    laws = list(laws)
    if constraint == "walls":
        prisms += _walls(polygons, depth)
        held += [n, n + 1]
        densities = np.concatenate([densities, densities[:1].repeat(2) if n else [1.0, 1.0]])
        groups, pairs = _wall_pairs(groups, pairs, len(laws))
        laws.append(_frictionless(laws))
    model = build_model(
        prisms,
        densities,
        laws,
        held=held,
        gravity=gravity_3d(gravity_2d),
        refine=refine,
        group=groups,
        pair_joint=pairs,
    )
    for i in range(n):
        if i not in held:
            model.dof[i, list(IN_PLANE)] = codes[i]
            if constraint == "held":
                model.dof[i, list(OUT_OF_PLANE)] = PRESCRIBED
    return model


def _walls(polygons: Sequence[np.ndarray], depth: float) -> list:
    """The two side walls (module docstring): boxes against y = 0 and y = depth."""
    points = np.vstack([np.asarray(p, dtype=float) for p in polygons])
    lo, hi = points.min(axis=0), points.max(axis=0)
    reach = WALL_MARGIN * float(np.max(hi - lo))
    (x0, z0), (x1, z1) = lo - reach, hi + reach
    t = WALL_THICKNESS * depth
    return [
        box((x0, -t, z0), (x1, 0.0, z1), name="wall at y = 0"),
        box((x0, depth, z0), (x1, depth + t, z1), name="wall at y = depth"),
    ]


def _wall_pairs(group: np.ndarray, pair_joint: np.ndarray, types: int) -> tuple[np.ndarray, np.ndarray]:
    """The groups with the walls' group appended, and `pair_joint` grown by its row: joint type `types`
    (the frictionless one) between the walls and any block."""
    g = pair_joint.shape[0]
    grown = np.full((g + 1, g + 1), types, dtype=np.int64)
    grown[:g, :g] = pair_joint
    return np.concatenate([group, [g, g]]).astype(np.int64), grown


def _frictionless(laws: Sequence[JointLaw]) -> MohrCoulomb:
    """The walls' joint type: the stiffest given K_n and K_s [Pa/m], no friction, no cohesion."""
    return MohrCoulomb(max(law.kn for law in laws), max(law.ks for law in laws), 0.0, 0.0)
