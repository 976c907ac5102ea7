"""A 3D scene (`bbmc.scene.schema3d.Scene3D`) made into the engine's model: its blocks as convex
polyhedra (`bbmc.geometry.polyhedra`), its rock mass cut by its joint sets
(`bbmc.geometry.polyhedron_cutting`), its joint types (`bbmc.dem3d.joint_laws`, each with its given
uniform water pressure) and the contact rules as the groups' table `pair_joint`, gravity with the
pseudo-static seismic load, the phreatic plane (`bbmc.dem3d.water.WaterTable`), held and moving blocks.

Units: the scene's (MPa, kPa, MPa/mm, kN/m3, deg) converted to SI here: Pa, Pa/m, N/m3, rad. A fault
found while building (an unknown name, a shape that is no convex polyhedron, blocks overlapping at the
start, a joint set that cuts nothing) is a `ConfigKeyError` naming the key and the block, raised before
any step.
Generated blocks (the wedge's, `bbmc.slope.scene3d`) come in as `Piece`s beside the scene's own.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bbmc import units
from bbmc.config import ConfigKeyError
from bbmc.dem3d.joint_laws import BartonBandis, JointLaw, MohrCoulomb
from bbmc.dem3d.layout import FREE, VPX
from bbmc.dem3d.model import Model, build_model
from bbmc.dem3d.seismic import seismic_gravity
from bbmc.dem3d.water import WaterTable
from bbmc.geometry.orientation import upward_pole
from bbmc.geometry.polyhedra import UNTAGGED, Polyhedron, box, extrude, from_vertices
from bbmc.geometry.polyhedron_cutting import cut_by_joint_sets
from bbmc.scene.schema3d import Block3D, Box, JointType, RockMass3D, Scene3D, Water3D

SIDE_TOLERANCE = 1e-6  # a face lies on a side of the bounding box within this x its size [1]


@dataclass(frozen=True)
class Piece:
    """A block before the model: its `name`, `group`, `material`, shape, and `key` (the scene key that
    gave it, for messages); held, or moving at `velocity` [m/s] (None: free unless held); `face_joint`:
    the joint type of a contact across each face (-1: the groups' rule), None: the rule on every face."""

    name: str
    group: str
    material: str
    shape: Polyhedron
    key: str
    held: bool = False
    velocity: tuple[float, float, float] | None = None
    face_joint: tuple[int, ...] | None = None


@dataclass
class SceneModel:
    """The model with what names its parts: each block's name and group, each joint type's name, the
    groups' names in the order of their indices (`group_names`, the model's `group`), and the blocks'
    state at the start (`start`, a copy of the block array before any step)."""

    model: Model
    names: list[str]
    groups: list[str]
    joint_type_names: list[str]
    start: np.ndarray
    group_names: list[str]

    def index(self, name: str, key: str) -> int:
        """The block called `name`; ConfigKeyError at `key` naming the closest names otherwise."""
        if name not in self.names:
            raise ConfigKeyError(key, f"no block '{name}' (blocks: {', '.join(self.names[:8])}...)")
        return self.names.index(name)


def joint_law(section: JointType) -> JointLaw:
    """The engine's law of a scene's joint type, in SI."""
    kn, ks = section.kn_MPa_per_mm * units.MPa_per_mm, section.ks_MPa_per_mm * units.MPa_per_mm
    pressure = section.pressure_kPa * units.kPa
    if section.law == "mohr_coulomb":
        friction, cohesion = section.friction_deg * units.deg, section.cohesion_MPa * units.MPa
        return MohrCoulomb(kn, ks, friction, cohesion, section.after_slip, pressure)
    k = section.tangent_coefficient
    return BartonBandis(
        kn,
        ks,
        section.jrc,
        section.jcs_MPa * units.MPa,
        section.phi_b_deg * units.deg,
        section.phi_max_deg * units.deg,
        None if k == "exact" else k,
        section.after_slip,
        pressure,
    )


def water_table(section: Water3D) -> WaterTable:
    """The scene's phreatic plane: level at `elevation_m`, or through `point_m` with the upward normal
    of a plane of `dip_deg` towards `dip_direction_deg` (`bbmc.geometry.orientation.upward_pole`);
    gamma_w from kN/m3 to N/m3."""
    gamma = section.unit_weight_kN_m3 * units.kN_per_m3
    if section.elevation_m is not None:
        return WaterTable(gamma, (0.0, 0.0, section.elevation_m), (0.0, 0.0, 1.0))
    normal = upward_pole(section.dip_deg, section.dip_direction_deg)
    return WaterTable(gamma, tuple(section.point_m), tuple(normal))


def _box(section: Box, name: str) -> Polyhedron:
    return box(section.lo_m, section.hi_m, name=name)


def _shape(block: Block3D) -> Polyhedron:
    if block.vertices_m is not None:
        return from_vertices(np.array(block.vertices_m), name=block.name)
    if block.box is not None:
        return _box(block.box, block.name)
    return extrude(np.array(block.extrusion.polygon_m), *block.extrusion.y_m, name=block.name)


def block_pieces(scene: Scene3D) -> list[Piece]:
    """The scene's `blocks:` as pieces; a shape refused names its key (blocks.i) and block."""
    pieces = []
    for i, block in enumerate(scene.blocks):
        try:
            shape = _shape(block)
        except ValueError as error:
            raise ConfigKeyError(f"blocks.{i}", str(error)) from None
        velocity = None if block.velocity_m_s is None else tuple(block.velocity_m_s)
        group = block.group or block.name
        pieces.append(Piece(block.name, group, block.material, shape, f"blocks.{i}", block.held, velocity))
    return pieces


SIDES = {
    "bottom": (2, -1.0),
    "top": (2, 1.0),
    "-x": (0, -1.0),
    "+x": (0, 1.0),
    "-y": (1, -1.0),
    "+y": (1, 1.0),
}


def _on_side(shape: Polyhedron, bounds: np.ndarray, side: str, size: float) -> bool:
    """Whether a face of `shape` lies on `side` of the bounding box `bounds` (2, 3) [m] of size `size`:
    its outward normal is the side's and its plane the side's, within SIDE_TOLERANCE."""
    axis, sense = SIDES[side]
    level = bounds[1 if sense > 0 else 0, axis]
    along = shape.normals[:, axis] * sense > 1.0 - SIDE_TOLERANCE
    return bool(np.any(along & (np.abs(shape.offsets - sense * level) <= SIDE_TOLERANCE * size)))


def rock_mass_pieces(section: RockMass3D, set_joint: Sequence[int] | None = None) -> list[Piece]:
    """The rock mass's blocks (`RockMass3D`): the shape cut by its joint sets, slivers merged by
    `min_block_fraction`, held where a face lies on one of `held_sides`; a face set s cut takes the
    joint type `set_joint[s]` (-1 or None: the groups' rule). A set that cuts nothing is refused naming
    it."""
    key = "rock_mass"
    try:
        if section.box is not None:
            shape = _box(section.box, section.name)
        else:
            shape = extrude(np.array(section.profile.polygon_m), *section.profile.y_m, name=section.name)
        sets = [(s.dip_deg, s.dip_direction_deg, s.spacing_m, s.origin_m) for s in section.joint_sets]
        jointed = cut_by_joint_sets(shape, sets, min_block_fraction=section.min_block_fraction)
    except ValueError as error:
        raise ConfigKeyError(key, str(error)) from None
    for name, cuts in zip(section.set_names, jointed.cuts_per_set, strict=True):
        if cuts == 0:
            raise ConfigKeyError(
                f"{key}.joint_sets", f"set {name} cuts nothing: no plane of it crosses the shape"
            )
    bounds = np.array([shape.vertices.min(axis=0), shape.vertices.max(axis=0)])
    by_set = np.array(set_joint or [-1] * len(section.joint_sets), dtype=np.int64)
    pieces = []
    for k, block in enumerate(jointed.blocks, start=1):
        held = any(_on_side(block, bounds, side, shape.size) for side in section.held_sides)
        tags = block.face_tags
        faces = tuple(int(t) for t in np.where(tags == UNTAGGED, -1, by_set[np.maximum(tags, 0)]))
        name = f"{section.name}.{k}"
        pieces.append(Piece(name, section.name, section.material, block, key, held, face_joint=faces))
    return pieces


def _type_of(scene: Scene3D, joint: str, key: str) -> int:
    """The index of joint type `joint`; ConfigKeyError at `key` naming the known ones otherwise."""
    names = list(scene.joint_types)
    if joint not in names:
        raise ConfigKeyError(key, f"no joint type '{joint}' (joint_types: {', '.join(names)})")
    return names.index(joint)


def _set_joints(scene: Scene3D) -> list[int]:
    """The joint type of each of the rock mass's sets (-1 where it names none)."""
    key = "rock_mass.joint_sets"
    sets = scene.rock_mass.joint_sets
    return [-1 if s.joint_type is None else _type_of(scene, s.joint_type, f"{key}.{i}.joint_type")
            for i, s in enumerate(sets)]  # fmt: skip


def _pair_joint(scene: Scene3D, groups: list[str]) -> tuple[list[str], np.ndarray, list[int]]:
    """The groups' names in order of first appearance, the (g, g) table of joint types and each block's
    group index; an unknown joint type or group names its rule."""
    known = list(dict.fromkeys(groups))
    table = np.full((len(known), len(known)), _type_of(scene, scene.contacts.default, "contacts.default"))
    for i, rule in enumerate(scene.contacts.rules):
        key = f"contacts.rules.{i}"
        j = _type_of(scene, rule.joint_type, f"{key}.joint_type")
        for group in rule.groups:
            if group not in known:
                raise ConfigKeyError(
                    f"{key}.groups", f"no block has group '{group}' (groups: {', '.join(known)})"
                )
        a, b = known.index(rule.groups[0]), known.index(rule.groups[1])
        table[a, b] = table[b, a] = j
    return known, table, [known.index(g) for g in groups]


def _named(message: str, names: Sequence[str]) -> str:
    """The engine's message ("block 3: ...", "blocks 3 and 5: ...") with the blocks' names for their
    indices."""
    head, colon, tail = message.partition(":")
    head = re.sub(r"(blocks?|and) (\d+)\b", lambda m: f"{m.group(1)} '{names[int(m.group(2))]}'", head)
    return head + colon + tail


def build_scene_model(scene: Scene3D, extra: Sequence[Piece] = ()) -> SceneModel:
    """The model of the scene's blocks and rock mass, and the `extra` pieces (the module docstring)."""
    rock_mass = rock_mass_pieces(scene.rock_mass, _set_joints(scene)) if scene.rock_mass else []
    pieces = [*block_pieces(scene), *rock_mass, *extra]
    names = [p.name for p in pieces]
    for k, p in enumerate(pieces):
        if p.name in names[:k]:
            raise ConfigKeyError(p.key, f"two blocks are called '{p.name}': names must differ")
        if p.material not in scene.materials:
            known = ", ".join(scene.materials)
            raise ConfigKeyError(f"{p.key}.material", f"no material '{p.material}' (materials: {known})")
    group_names, table, group_index = _pair_joint(scene, [p.group for p in pieces])
    laws = [joint_law(section) for section in scene.joint_types.values()]
    density = [scene.materials[p.material].density_kg_m3 for p in pieces]
    held = [i for i, p in enumerate(pieces) if p.held or p.velocity is not None]
    face_joint = [p.face_joint or [-1] * p.shape.face_count for p in pieces]
    try:
        model = build_model([p.shape for p in pieces], density, laws, held=held, gravity=_gravity(scene),
                            refine=scene.contacts.refine, group=group_index, pair_joint=table,
                            water=water_table(scene.water) if scene.water else None,
                            face_joint=face_joint)  # fmt: skip
    except ValueError as error:
        raise ConfigKeyError("blocks", _named(str(error), names)) from None
    for i, p in enumerate(pieces):
        if p.velocity is not None:
            model.blocks[i, VPX : VPX + 3] = p.velocity
    return SceneModel(
        model, names, [p.group for p in pieces], list(scene.joint_types), model.blocks.copy(), group_names
    )


def _gravity(scene: Scene3D) -> np.ndarray:
    """Gravity [m/s2] with the pseudo-static seismic acceleration k_h |g| towards its azimuth added
    (`bbmc.dem3d.seismic`)."""
    if scene.seismic is None:
        return np.array(scene.gravity_m_s2, dtype=float)
    return seismic_gravity(
        scene.gravity_m_s2, scene.seismic.horizontal_coefficient, math.radians(scene.seismic.towards_deg)
    )


def judged_blocks(scene: Scene3D, built: SceneModel) -> list[int] | None:
    """The blocks whose motion decides a `bbmc fos` trial (`fos.judge`): those named in `blocks` (block
    or group names; default every block free to move) at least `min_size_fraction` x the median size
    of the blocks free to move; None for every free block. An unknown name is refused naming it."""
    judge = scene.fos.judge
    if not judge.blocks and judge.min_size_fraction == 0:
        return None
    free = np.flatnonzero(np.any(built.model.dof == FREE, axis=1))
    chosen = set(free.tolist()) if not judge.blocks else set()
    for k, name in enumerate(judge.blocks):
        found = [i for i, (n, g) in enumerate(zip(built.names, built.groups, strict=True)) if name in (n, g)]
        if not found:
            raise ConfigKeyError(f"fos.judge.blocks.{k}", f"no block or group '{name}'")
        chosen.update(found)
    smallest = judge.min_size_fraction * float(np.median(built.model.size[free])) if len(free) else 0.0
    return sorted(i for i in chosen if built.model.size[i] >= smallest)
