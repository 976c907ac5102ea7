"""A wedge of the limit-equilibrium geometry as a 3D block scene (`bbmc.dem3d`): the wedge block on the
rock of its two joint planes, for the engine's strength-reduction factor of safety beside the limit
equilibrium's (issue 36's wedge verification).

The wedge is the convex hull of its vertices (O C1 C2 T, `WedgeGeometry.vertices`). The rock is two
held blocks, one for each plane: a cube of `ROCK_EXTENT` x the wedge's size centred on the wedge, cut
by the plane n_i . (x - O) = 0 (`bbmc.geometry.polyhedron_cutting.cut`), the part away from the wedge
kept (n_i points into the wedge). The two held blocks overlap each other below both planes, which a
held pair may (the engine never pairs two held blocks); each meets the wedge on its own plane only, so
the wedge can leave either plane freely (lift-off) and slides out through the face and upper surface,
where nothing holds it. Units: m, kg.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from bbmc.dem3d.joint_laws import JointLaw
from bbmc.dem3d.model import Model, build_model
from bbmc.geometry.polyhedra import Polyhedron, box, from_vertices
from bbmc.geometry.polyhedron_cutting import cut
from bbmc.slope.wedge.geometry import WedgeGeometry

ROCK_EXTENT = 3.0  # the held rock's cube edge, x the wedge's size (its bounding-box diagonal) [1]
WEDGE, ROCK_1, ROCK_2 = 0, 1, 2  # the scene's block indices


def wedge_blocks(vertices: np.ndarray, normal_1: np.ndarray, normal_2: np.ndarray) -> list[Polyhedron]:
    """[the wedge, the rock of plane 1, the rock of plane 2] (module docstring): `vertices` (k, 3) [m]
    the wedge's, the first one O on both planes; `normal_1`, `normal_2` (3,) the planes' unit normals
    pointing into the wedge. A plane that leaves the wedge on its rock's side is refused."""
    wedge = from_vertices(np.asarray(vertices, dtype=float), name="wedge")
    origin = wedge.vertices[0]
    centre = wedge.vertices.mean(axis=0)
    half = 0.5 * ROCK_EXTENT * wedge.size
    cube = box(centre - half, centre + half, name="rock")
    rock = []
    for i, normal in enumerate((normal_1, normal_2), start=1):
        normal = np.asarray(normal, dtype=float)
        depth = (wedge.vertices - origin) @ normal
        if depth.min() < -1e-9 * wedge.size:
            raise ValueError(f"normal_{i}: the wedge is not on the side plane {i}'s normal points to")
        rock.append(cut(cube, normal, float(normal @ origin))[0])
    return [wedge, *rock]


def wedge_scene(
    geometry: WedgeGeometry,
    density: float,
    law: JointLaw,
    *,
    refine: int = 1,
    gravity: Sequence[float] = (0.0, 0.0, -9.81),
) -> Model:
    """The engine's model of one wedge of `geometry` (its fields of shape (3,) or (k, 3)): the wedge
    block of `density` [kg/m3] on its two held rock blocks (`wedge_blocks`), both planes of joint type
    `law`, faces refined `refine` times. A wedge that does not form is refused by its reason."""
    if not bool(np.all(geometry.formed)):
        raise ValueError(f"wedge: {geometry.reason_texts()}")
    blocks = wedge_blocks(geometry.vertices, geometry.normal_1, geometry.normal_2)
    return build_model(blocks, density, [law], held=[ROCK_1, ROCK_2], gravity=gravity, refine=refine)
