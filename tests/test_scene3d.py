"""The 3D scene format (`bbmc.scene.schema3d`) and its model (`bbmc.dem3d.scene_model`,
`bbmc.slope.scene3d`): every fault refused in one line naming the key or block, before any step; the
shapes, groups, joint types, held and moving blocks as the scene gives them."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from bbmc.config import ConfigError, ConfigKeyError, validate
from bbmc.dem3d.joint_laws import P_PHI, STRENGTH_BARTON_BANDIS
from bbmc.dem3d.layout import VPX
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

BASE = {
    "dimension": 3,
    "materials": {"rock": {"density_kg_m3": 2500}},
    "joint_types": {
        "mc": {"law": "mohr_coulomb", "kn_MPa_per_mm": 1, "ks_MPa_per_mm": 0.5, "friction_deg": 30},
        "bb": {
            "law": "barton_bandis",
            "kn_MPa_per_mm": 1,
            "ks_MPa_per_mm": 0.5,
            "jrc": 8,
            "jcs_MPa": 60,
            "phi_b_deg": 28,
        },
    },
    "contacts": {"default": "mc", "rules": [{"groups": ["base", "top"], "joint_type": "bb"}]},
    "blocks": [
        {"name": "base", "material": "rock", "held": True, "box": {"lo_m": [0, 0, -1], "hi_m": [4, 4, 0]}},
        {"name": "top", "material": "rock", "box": {"lo_m": [1, 1, 0], "hi_m": [2, 2, 1]}},
    ],
    "solver": {"steps": 100},
}


def scene(**changes) -> Scene3D:
    raw = copy.deepcopy(BASE)
    raw.update(changes)
    return validate(raw, Scene3D, "<scene>")


def block(name: str, **shape) -> dict:
    return {"name": name, "material": "rock", **shape}


def test_two_blocks_their_groups_joint_types_and_held_dofs():
    built = build_scene3d(scene())
    assert built.names == ["base", "top"] and built.groups == ["base", "top"]
    assert built.model.pair_joint.tolist() == [[0, 1], [1, 0]]  # base-top: bb; within a group: mc
    assert built.model.law_codes[1, 0] == STRENGTH_BARTON_BANDIS
    assert built.model.law_params[0, P_PHI] == pytest.approx(math.radians(30), rel=1e-15)
    assert built.model.dof[0].all() and not built.model.dof[1].any()


def test_a_moving_block_has_its_velocity_and_every_dof_prescribed():
    blocks = [*BASE["blocks"][:1], {**BASE["blocks"][1], "velocity_m_s": [0.1, 0, 0]}]
    built = build_scene3d(scene(blocks=blocks))
    assert built.model.dof[1].all() and built.model.blocks[1, VPX] == 0.1


def test_an_extrusion_maps_the_2d_section_to_x_z():
    extruded = block("top", extrusion={"polygon_m": [[1, 0], [2, 0], [2, 1], [1, 1]], "y_m": [1, 3]})
    built = build_scene3d(scene(blocks=[BASE["blocks"][0], extruded]))
    lo, hi = built.model.vertices[8:].min(axis=0), built.model.vertices[8:].max(axis=0)
    assert lo == pytest.approx([1, 1, 0], abs=1e-12) and hi == pytest.approx([2, 3, 1], abs=1e-12)


def test_a_rock_mass_is_cut_by_its_sets_and_held_on_its_sides():
    mass = {
        "material": "rock",
        "box": {"lo_m": [0, 0, 0], "hi_m": [4, 4, 4]},
        "held_sides": ["bottom"],
        "joint_sets": [
            {"dip_deg": 0, "dip_direction_deg": 0, "spacing_m": 2, "origin_m": [0, 0, 0]},
            {"dip_deg": 90, "dip_direction_deg": 90, "spacing_m": 2, "origin_m": [0, 0, 0]},
        ],
    }
    built = build_scene3d(scene(blocks=[], rock_mass=mass, contacts={"default": "mc"}))
    assert built.names == [f"rock_mass.{k}" for k in range(1, 5)]
    held = built.model.dof.all(axis=1)
    low = built.model.blocks[:, 2] < 2.0
    assert np.array_equal(held, low)  # the two lower blocks lie on the bottom; the upper two do not


def test_the_wedge_forms_its_block_and_the_held_rock_of_its_planes():
    wedge = {
        "material": "rock",
        "plane_1": {"dip_deg": 40, "dip_direction_deg": 130, "joint_type": "bb"},
        "plane_2": {"dip_deg": 60, "dip_direction_deg": 220},
        "face": {"dip_deg": 70, "dip_direction_deg": 175},
        "upper_surface": {"dip_deg": 0, "dip_direction_deg": 175},
        "height_h1_m": 10,
    }
    built = build_scene3d(scene(blocks=[], wedge=wedge, contacts={"default": "mc"}))
    assert built.names == ["wedge", "wedge.plane_1", "wedge.plane_2"]
    assert built.model.pair_joint[0].tolist() == [0, 1, 0]  # plane 1 bb (its joint_type), plane 2 mc
    assert built.model.dof[1:].all() and not built.model.dof[0].any()


@pytest.mark.parametrize(
    "changes, fragment",
    [
        ({"support": [{"bolt": 1}]}, "support.*not yet in 3D"),
        ({"water": {"phreatic": 1}}, "water.phreatic.*unknown key"),
        (
            {"blocks": [block("a", box={"lo_m": [0, 0, 0], "hi_m": [1, 1, 1]}, vertices_m=[[0, 0, 0]] * 4)]},
            "exactly one shape",
        ),
        ({"dimension": 2}, "dimension"),
        ({"blocks": [], "wedge": None}, "a scene needs blocks"),
        ({"fos": {"judge": {"region_m": [[0, 0], [1, 1]]}}}, "region_m: not yet in 3D"),
    ],
)
def test_a_bad_scene_is_refused_whole(changes, fragment):
    with pytest.raises(ConfigError, match=fragment):
        scene(**changes)


CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]]


@pytest.mark.parametrize(
    "changes, key, fragment",
    [
        (
            {
                "blocks": [
                    BASE["blocks"][0],
                    block("top", vertices_m=[*CUBE, [0.5, 0.5, 0.5]], material="rock"),
                ]
            },
            "blocks.1",
            "top",
        ),  # a point inside the hull: not a convex polyhedron's corner
        (
            {"blocks": [BASE["blocks"][0], block("top", box={"lo_m": [1, 1, -0.5], "hi_m": [2, 2, 1]})]},
            "blocks",
            "blocks 'base' and 'top': they overlap by 0.5 m",
        ),  # half a metre into the base
        (
            {"blocks": [BASE["blocks"][0], {**BASE["blocks"][1], "material": "granite"}]},
            "blocks.1.material",
            "no material 'granite'",
        ),
        (
            {"contacts": {"default": "mc", "rules": [{"groups": ["base", "lid"], "joint_type": "bb"}]}},
            "contacts.rules.0.groups",
            "no block has group 'lid'",
        ),
        ({"contacts": {"default": "wet"}}, "contacts.default", "no joint type 'wet'"),
        ({"blocks": [BASE["blocks"][0], {**BASE["blocks"][0], "name": "base"}]}, "blocks.1", "two blocks"),
    ],
)
def test_a_bad_model_is_refused_naming_its_key_and_block(changes, key, fragment):
    with pytest.raises(ConfigKeyError) as refused:
        build_scene3d(scene(**changes))
    assert refused.value.key == key and fragment in refused.value.text, refused.value


def test_a_joint_set_that_cuts_nothing_is_refused_naming_it():
    mass = {
        "material": "rock",
        "box": {"lo_m": [0, 0, 0], "hi_m": [4, 4, 4]},
        "joint_sets": [
            {"dip_deg": 0, "dip_direction_deg": 0, "spacing_m": 2, "origin_m": [0, 0, 0]},
            {"name": "far", "dip_deg": 0, "dip_direction_deg": 0, "spacing_m": 50, "origin_m": [0, 0, 25]},
        ],
    }
    with pytest.raises(ConfigKeyError, match="set far cuts nothing"):
        build_scene3d(scene(blocks=[], rock_mass=mass, contacts={"default": "mc"}))


def test_a_wedge_that_cannot_form_is_refused_with_its_reason():
    wedge = {
        "material": "rock",
        "plane_1": {"dip_deg": 80, "dip_direction_deg": 130},
        "plane_2": {"dip_deg": 80, "dip_direction_deg": 220},
        "face": {"dip_deg": 50, "dip_direction_deg": 175},
        "upper_surface": {"dip_deg": 0, "dip_direction_deg": 175},
        "height_h1_m": 10,
    }
    with pytest.raises(ConfigKeyError, match="cannot form") as refused:
        build_scene3d(scene(blocks=[], wedge=wedge, contacts={"default": "mc"}))
    assert refused.value.key == "wedge" and "daylight" in refused.value.text, refused.value
