"""Hoek & Bray's planar slope with a tension crack as a block scene, built to match the assumptions of
their limit equilibrium (`bbmc.slope.planar`), so that strength reduction on the engine can be checked
against it.

The scene (the `bbmc run` format, as a dict; the face looks towards -x, the toe at the origin): one
free block, the wedge toe -> crack foot -> crack top -> crest, resting on the failure plane of one
fixed block below it; nothing behind the crack (an open crack carries no force but its water). Water
fills the crack to z_w and leaves at the toe: the phreatic surface is the straight line from the toe
to the crack's water level (the pressure on the plane falls linearly from gamma_w z_w at the crack's
foot to 0 at the toe, hydrostatic in the crack, as Hoek & Bray assume). A seismic coefficient k_h
acts out of the slope (towards -x). The plane's joint law is given; with the scene's default rule its
cohesion is kept after slip (`after_slip: keep`), as the limit equilibrium counts the whole plane's
cohesion.

Only a crack in the upper surface is built (z / H <= 1 - cot psi_f tan psi_p). Where the engine
cannot match the limit equilibrium: the wedge is rigid and carries moments, so where the resultant
leaves the base, the plane opens at its heel and loses that part's cohesion, and a tall wedge may
topple; the limit equilibrium checks forces only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from bbmc.slope import planar


@dataclass(frozen=True)
class PlanarSlope:
    """The slope in the units of a scene: m, deg, kg/m^3; `water_fill` is z_w / z (0 dry, 1 full)."""

    height_m: float
    face_deg: float
    plane_deg: float
    crack_behind_crest_m: float
    water_fill: float = 0.0
    seismic_coefficient: float = 0.0
    density_kg_m3: float = 2600.0
    gravity_m_s2: float = 9.81

    @property
    def crack_depth_m(self) -> float:
        """z: the crack's foot, on the plane, below the crest's level [m]."""
        face, plane = math.radians(self.face_deg), math.radians(self.plane_deg)
        return float(planar.crack_depth_behind_crest(self.height_m, face, plane, self.crack_behind_crest_m))

    def forces(self) -> planar.PlanarForces:
        """Hoek & Bray's forces on this slope (`bbmc.slope.planar`), per metre [N]."""
        z = self.crack_depth_m
        return planar.planar_forces(
            self.height_m,
            math.radians(self.face_deg),
            math.radians(self.plane_deg),
            z,
            self.water_fill * z,
            self.density_kg_m3 * self.gravity_m_s2,
            self.seismic_coefficient,
            water_unit_weight=planar.WATER_UNIT_WEIGHT,
        )


def wedge(slope: PlanarSlope) -> list[list[float]]:
    """The sliding block's vertices, counter-clockwise: toe, crack foot, crack top, crest [m]."""
    h, z = slope.height_m, slope.crack_depth_m
    crest = h / math.tan(math.radians(slope.face_deg))
    crack = crest + slope.crack_behind_crest_m
    if slope.crack_behind_crest_m <= 0 or not 0 < z < h:
        raise ValueError("the crack must be behind the crest, its foot on the plane below the crest")
    return [[0.0, 0.0], [crack, h - z], [crack, h], [crest, h]]


def planar_scene(name: str, slope: PlanarSlope, law: dict, solver: dict, fos: dict | None = None) -> dict:
    """The scene of the slope with `law` (a scene joint-law entry) on the plane."""
    vertices = wedge(slope)
    crack_x, foot_y = vertices[1]
    reach = 1.2 * crack_x
    tan_plane = math.tan(math.radians(slope.plane_deg))
    scene = {
        "name": name,
        "description": "Hoek & Bray's planar slope with a tension crack (bbmc.slope.planar_scene).",
        "gravity_m_s2": [0.0, -slope.gravity_m_s2],
        "materials": {"rock": {"density_kg_m3": slope.density_kg_m3}},
        "blocks": [
            {
                "name": "rock_below",
                "material": "rock",
                "polygon_m": [
                    [0.0, 0.0],
                    [0.0, -0.2 * reach],
                    [reach, -0.2 * reach],
                    [reach, reach * tan_plane],
                ],
                "fix": ["x", "y", "rotation"],
            },
            {"name": "wedge", "material": "rock", "polygon_m": vertices},
        ],
        "joint_laws": {"plane": law},
        "contacts": {"default_law": "plane"},
        "solver": solver,
    }
    water_depth = slope.water_fill * slope.crack_depth_m
    if water_depth > 0:
        scene["water"] = {
            "phreatic_surface_m": [[0.0, 0.0], [crack_x, foot_y + water_depth]],
            "unit_weight_kN_m3": planar.WATER_UNIT_WEIGHT / 1e3,
        }
    if slope.seismic_coefficient > 0:
        scene["seismic"] = {"horizontal_coefficient": slope.seismic_coefficient, "towards": "-x"}
    if fos is not None:
        scene["fos"] = fos
    return scene
