"""A 3D scene's model (`bbmc.dem3d.scene_model`) with its `wedge:` made into blocks: the wedge of
`bbmc wedge`'s geometry (`bbmc.slope.wedge.geometry`) and the held rock of its two planes
(`bbmc.slope.wedge.engine_scene.wedge_blocks`). The wedge block is named and grouped by the section's
`name`; the rock of plane i by `name`.plane_i, in its own group, so each plane's contact takes the
plane's `joint_type` (a rule the section adds to `contacts.rules`). Units: deg at the file, rad here.
"""

from __future__ import annotations

import math

import numpy as np

from bbmc.config import ConfigKeyError
from bbmc.dem3d.scene_model import Piece, SceneModel, build_scene_model
from bbmc.scene.schema3d import ContactRule3D, Scene3D, Wedge3D
from bbmc.slope.wedge.engine_scene import wedge_blocks
from bbmc.slope.wedge.geometry import wedge_geometries


def wedge_pieces(section: Wedge3D) -> list[Piece]:
    """[the wedge, the rock of plane 1, the rock of plane 2] as pieces; a wedge that cannot form is
    refused in one line at key `wedge` with its reason."""
    angles = [
        math.radians(a)
        for plane in (section.plane_1, section.plane_2, section.face, section.upper_surface)
        for a in (plane.dip_deg, plane.dip_direction_deg)
    ]
    geometry = wedge_geometries(
        *angles,
        height_h1=section.height_h1_m,
        height_h=section.height_m,
        overhanging_face=section.face.overhanging,
    )
    if not bool(np.all(geometry.formed)):
        raise ConfigKeyError("wedge", f"the wedge cannot form: {geometry.reason_texts()}")
    wedge, rock_1, rock_2 = wedge_blocks(geometry.vertices, geometry.normal_1, geometry.normal_2)
    name, material = section.name, section.material
    return [
        Piece(name, name, material, wedge, "wedge"),
        Piece(f"{name}.plane_1", f"{name}.plane_1", material, rock_1, "wedge", held=True),
        Piece(f"{name}.plane_2", f"{name}.plane_2", material, rock_2, "wedge", held=True),
    ]


def _with_plane_rules(scene: Scene3D) -> Scene3D:
    """The scene with a contact rule for each wedge plane that names a joint type."""
    section = scene.wedge
    for i, plane in ((1, section.plane_1), (2, section.plane_2)):
        if plane.joint_type is not None and plane.joint_type not in scene.joint_types:
            known = ", ".join(scene.joint_types)
            raise ConfigKeyError(
                f"wedge.plane_{i}.joint_type", f"no joint type '{plane.joint_type}' ({known})"
            )
    rules = [
        ContactRule3D(groups=[section.name, f"{section.name}.plane_{i}"], joint_type=plane.joint_type)
        for i, plane in ((1, section.plane_1), (2, section.plane_2))
        if plane.joint_type is not None
    ]
    if not rules:
        return scene
    contacts = scene.contacts.model_copy(update={"rules": [*scene.contacts.rules, *rules]})
    return scene.model_copy(update={"contacts": contacts})


def build_scene3d(scene: Scene3D) -> SceneModel:
    """The 3D scene's model, its wedge's blocks after its own blocks and rock mass."""
    if scene.wedge is None:
        return build_scene_model(scene)
    return build_scene_model(_with_plane_rules(scene), wedge_pieces(scene.wedge))
