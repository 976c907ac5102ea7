"""A joint type per joint set of a 3D rock mass (`joint_type` on a set of `rock_mass.joint_sets`): a
contact across a face the set cut takes the set's joint type (`bbmc.dem3d.model.build_model`'s
`face_joint`, decided when the pair is found, `bbmc.dem3d.solver.pair_joint_type`), the rest the
groups' rule; bad input refused in one line naming the key or block."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbmc.config import ConfigKeyError, validate
from bbmc.dem3d.contact_forces import BLOCK_A, BLOCK_B, JOINT_TYPE
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import FREE, X, Z
from bbmc.dem3d.model import build_model
from bbmc.dem3d.solver import run, search, time_step
from bbmc.geometry.polyhedra import box
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

DIP = 35.0  # deg, both sets, towards +x (east): bedding planes of two kinds, interleaved
NORMAL = np.array([math.sin(math.radians(DIP)), 0.0, math.cos(math.radians(DIP))])


def layered(weak: str | None, strong: str | None) -> dict:
    """A 6 x 2 x 3 m box held on its bottom and west side, cut by set W (planes n . x = 1.0, 4.0 m) and
    set S (1.8, 4.8 m), n the sets' upward normal: five layers, the two in the upper east corner free,
    the lower one on a W plane, the upper one on an S plane (its base on the lower one's top). Set W
    takes joint type `weak`, S `strong` (None: the set names none); weak phi 20 deg < 35 deg < strong
    phi 50 deg; contacts.default is `strong`."""

    def joint(phi):
        return {"law": "mohr_coulomb", "kn_MPa_per_mm": 1, "ks_MPa_per_mm": 0.5, "friction_deg": phi}

    sets = [
        {"name": name, "dip_deg": DIP, "dip_direction_deg": 90, "spacing_m": 3.0,
         "origin_m": (offset * NORMAL).tolist()}
        for name, offset in (("W", 4.0), ("S", 4.8))
    ]  # fmt: skip
    for s, joint_type in zip(sets, (weak, strong), strict=True):
        if joint_type is not None:
            s["joint_type"] = joint_type
    return {
        "dimension": 3,
        "materials": {"rock": {"density_kg_m3": 2500}},
        "joint_types": {"weak": joint(20), "strong": joint(50)},
        "contacts": {"default": "strong"},
        "rock_mass": {
            "material": "rock",
            "box": {"lo_m": [0, 0, 0], "hi_m": [6, 2, 3]},
            "joint_sets": sets,
            "held_sides": ["bottom", "-x"],
        },
        "solver": {"steps": 100},
    }


def moved_mm(raw: dict) -> tuple[np.ndarray, list[tuple[str, str, str]]]:
    """The free blocks' displacements [mm] (lower, upper) after 0.4 s (local damping 0.8), and the
    contacts of a free block as (block, block, joint type) at the start."""
    built = build_scene3d(validate(raw, Scene3D, "<scene>"))
    model = built.model
    free = np.flatnonzero(np.any(model.dof == FREE, axis=1))
    free = free[np.argsort(model.blocks[free, Z])]
    search(model)
    types = [
        (built.names[a], built.names[b], built.joint_type_names[j])
        for a, b, j in model.contacts[:, [BLOCK_A, BLOCK_B, JOINT_TYPE]]
        if a in free or b in free
    ]
    start = model.blocks[:, X : Z + 1].copy()
    dt = time_step(model, 0.5, 0.8)
    run(model, round(0.4 / dt), dt, 0.8)
    return np.linalg.norm(model.blocks[free, X : Z + 1] - start[free], axis=1) * 1e3, types


def test_the_blocks_slide_on_the_weak_sets_faces_only():
    """W weak, S strong: the lower free layer slides on its W base and carries the upper one on their S
    contact (both move > 10 mm in 0.4 s, measured 41.18 and 41.20 mm; apart by < 0.1 mm, 0.02). Swap
    the sets' types: the lower one holds on its now strong W base (< 0.1 mm, measured 0.03 mm: its
    settling) and the upper one slides on the weak S plane (> 10 mm, 43.1 mm). Every contact across a W
    face takes W's type, across an S face S's; none is the default's where a set names a type."""
    (lower, upper), types = moved_mm(layered("weak", "strong"))
    assert lower > 10.0 and upper > 10.0 and abs(lower - upper) < 0.1
    assert {("rock_mass.4", "rock_mass.3", "weak"), ("rock_mass.5", "rock_mass.4", "strong")} <= set(types)
    (lower, upper), types = moved_mm(layered("strong", "weak"))
    assert lower < 0.1 and upper > 10.0
    assert {("rock_mass.4", "rock_mass.3", "strong"), ("rock_mass.5", "rock_mass.4", "weak")} <= set(types)


def test_a_set_without_a_joint_type_takes_the_groups_rule():
    """No set names a type: every contact is the default's (strong), and nothing slides (< 0.1 mm;
    measured 0.04 and 0.08 mm, settling)."""
    moved, types = moved_mm(layered(None, None))
    assert {t for _, _, t in types} == {"strong"}
    assert moved.max() < 0.1


def test_an_unknown_set_joint_type_is_refused_naming_its_key():
    raw = layered("weak", "wet")
    with pytest.raises(ConfigKeyError, match=r"rock_mass\.joint_sets\.1\.joint_type.*no joint type 'wet'"):
        build_scene3d(validate(raw, Scene3D, "<scene>"))


def test_a_face_joint_row_of_the_wrong_length_or_type_is_refused_naming_its_block():
    slab, block = box([-5, -5, -1], [5, 5, 0]), box([0, 0, 0], [1, 1, 1])
    laws = [MohrCoulomb(1e9, 5e8, 0.5)]
    for rows in ([[-1] * 6, [-1] * 5], [[-1] * 6, [0, 0, 0, 0, 0, 1]]):
        with pytest.raises(ValueError, match="block 1: face_joint"):
            build_model([slab, block], 2500.0, laws, held=[0], face_joint=rows)
