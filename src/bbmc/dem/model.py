"""From a validated `Scene` to the engine's arrays in SI, checking every cross-reference on the way.

`build_model` is the boundary where scene units (MPa, mm, kN, deg) become SI and where names become
indices; anything a scene refers to that does not exist is a `ConfigError` naming the key.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from bbmc import units
from bbmc.config import validate
from bbmc.dem import layout as L
from bbmc.dem.block_shapes import (
    SHAPE_KEYS,
    check_inertia,
    check_shapes,
    edge_labels,
    entry_shapes,
    start_overlap_fault,
    turned,
)
from bbmc.dem.contact_rules import check_rule_edges, cuts_glued_or_warned
from bbmc.dem.joint_types import joint_types
from bbmc.dem.support_elements import SupportElements, support_elements
from bbmc.geometry import polygons
from bbmc.rockmass.cut import CUT
from bbmc.rockmass.profile import crack_water_table, profile_water_table
from bbmc.scene.schema import (
    BlockEntry,
    Monitor,
    Scene,
    scene_error,
)

EDGE_DIRECTIONS = {"up": (0.0, 1.0), "down": (0.0, -1.0), "left": (-1.0, 0.0), "right": (1.0, 0.0)}


@dataclass(frozen=True)
class MonitorSpec:
    """A monitor with its names resolved to indices (-1 where not used)."""

    name: str
    quantity: str
    block: int
    point: np.ndarray | None
    groups: tuple[int, int] | None
    near: np.ndarray | None
    support: str | None = None  # bolt_force: the support element's name


@dataclass(frozen=True)
class Economy:
    """Work the engine leaves out because no scene result depends on it. Each can be switched off, to
    measure its gain side by side (`bbmc bench`) and to check that it changes no number (tests)."""

    skip_immobile_pairs: bool = True  # contact search: no pair of two blocks held still
    bound_depth_when_needed: bool = True  # contact search: separating-axis bound only for deep edge pairs
    changed_laws_only: bool = True  # law updates: not for sub-contacts whose stresses are unchanged
    skip_held_blocks: bool = True  # motion and vertices: not for blocks held still


EVERY_ECONOMY = Economy()


@dataclass
class Model:
    """Everything the engine needs, in SI; arrays are the initial state (the solver copies them)."""

    scene: Scene
    block_names: list[str]
    group_names: list[str]
    block_group: np.ndarray
    blocks: np.ndarray
    dof: np.ndarray
    vertex_start: np.ndarray
    vertex_block: np.ndarray
    vertex_next: np.ndarray
    local: np.ndarray
    law_names: list[str]
    laws: np.ndarray
    params: np.ndarray
    rule_groups: np.ndarray
    rule_dip: np.ndarray
    rule_law: np.ndarray
    rule_edges: np.ndarray  # (rules, labels) bool: the edge labels each rule matches (all without `edges`)
    default_law: int
    gravity: np.ndarray
    block_loads: np.ndarray
    load_block: np.ndarray
    edge_loads: np.ndarray
    load_edge: np.ndarray
    search_margin: float
    monitors: list[MonitorSpec]
    water_surface: np.ndarray  # the phreatic surface's points (m, 2) [m]
    water_unit_weight: float  # [N/m^3]; 0: no water
    edge_label: np.ndarray  # per edge (vertex index): its label's index in label_names ('' for none)
    label_names: list[str]
    support: SupportElements = field(default_factory=SupportElements.none)
    support_divisor: float = 1.0  # > 1: strength reduction of the support too (`bbmc.dem.support`)
    economy: Economy = field(default_factory=Economy)

    @property
    def immobile(self) -> np.ndarray:
        """Blocks with every degree of freedom held at zero velocity: they can never load each other."""
        held = (self.dof == L.PRESCRIBED) & (self.blocks[:, [L.VPX, L.VPY, L.VPW]] == 0.0)
        return np.all(held, axis=1)

    @cached_property
    def has_bridges(self) -> bool:
        """True when a joint law breaks into another (intact rock: `joint_state.break_bridges`). Kept once
        read, as `variable_laws`: the run loop asks at every kernel call, and a model's laws are not
        changed in place (a strength-reduction trial is a new model)."""
        return bool(np.any(self.laws[:, L.BREAKS_INTO] >= 0))

    @cached_property
    def variable_laws(self) -> bool:
        return bool(np.any(self.laws[:, :3] != 0))

    @property
    def laws_losing_cohesion(self) -> list[str]:
        """The joint laws in use (the default and the rules') that drop their cohesion at the first slip
        (`after_slip: zero`, Itasca's Coulomb slip) and have a cohesion to lose: a Mohr-Coulomb c > 0
        or a Barton-Bandis tangent (whose intercept is > 0 wherever sigma_n > 0)."""
        used = sorted({self.default_law, *self.rule_law.tolist()})
        return [
            self.law_names[j]
            for j in used
            if self.laws[j, L.AFTER_SLIP] == L.AFTER_SLIP_ZERO
            and (self.params[j, L.P_COH] > 0 or self.laws[j, L.STRENGTH_LAW] == L.STRENGTH_BARTON_BANDIS)
        ]

    @property
    def loads_applied_step(self) -> int:
        """The step from which every load acts in full and every prescribed velocity has started."""
        ends = [row[-2] + row[-1] for row in (*self.block_loads, *self.edge_loads)]
        return int(max([*ends, *self.blocks[:, L.VSTART]], default=0))


def _water_table(scene: Scene, path: Path) -> np.ndarray:
    """The phreatic surface [m]: as given, or from the first rock mass's profile: the filling of its
    tension crack (`bbmc.rockmass.profile.crack_water_table`) or heights at its toe and back edge
    (`bbmc.rockmass.profile.profile_water_table`); a level line at 0 without water (unit weight 0)."""
    water = scene.water
    if water is None:
        return np.array([[0.0, 0.0], [1.0, 0.0]])
    if water.phreatic_surface_m is not None:
        return np.array(water.phreatic_surface_m, dtype=float)
    profiles = [entry.rock_mass.profile for entry in scene.blocks if entry.rock_mass is not None]
    if water.tension_crack_fill_percent is None:
        if not profiles:
            raise scene_error(
                path,
                "water.height_above_toe_m",
                "no rock_mass in blocks to measure it from: give the water table as phreatic_surface_m",
            )
        profile = profiles[0]
        return profile_water_table(
            profile.surface(), profile.crest_extent_m, water.height_above_toe_m, water.depth_below_crest_m
        )
    cracked = [profile for profile in profiles if profile.tension_crack is not None]
    if not cracked:
        raise scene_error(
            path, "water.tension_crack_fill_percent", "no rock_mass with a tension_crack to fill"
        )
    profile = cracked[0]
    crack = profile.tension_crack
    fill = water.tension_crack_fill_percent / 100.0
    return crack_water_table(profile.surface(), crack.distance_behind_crest_m, crack.depth_m, fill)


def _edge_index(vertices: np.ndarray, edge: str | int, path: Path, key: str) -> int:
    n = len(vertices)
    if isinstance(edge, int):
        if edge >= n:
            raise scene_error(path, key, f"the block has {n} edges (0 to {n - 1}), got {edge}")
        return edge
    direction = np.array(EDGE_DIRECTIONS[edge])
    tangents = np.roll(vertices, -1, axis=0) - vertices
    normals = np.column_stack([tangents[:, 1], -tangents[:, 0]])
    normals /= np.hypot(normals[:, 0], normals[:, 1])[:, None]
    return int(np.argmax(normals @ direction))


def built_scene(tree: dict, name: str) -> Model:
    """A scene that code builds (a mapping in the scene format) checked and built as a scene file is: a
    fault is one `ConfigError` line naming `name` and the key. Its numbers are the program's (computed,
    or taken from inputs checked when they were read), so they are not judged as typed input
    (`bbmc.plausibility`)."""
    return build_model(validate(tree, Scene, name, strict=False, typed=False), Path(name))


def build_model(scene: Scene, path: Path) -> Model:
    """Check every reference of the scene and assemble the engine's arrays."""
    names, shape_keys, groups, shapes, entries, fixed, labels, straight = [], [], [], [], [], [], [], []
    for i, entry in enumerate(scene.blocks):
        key = f"blocks.{i}"
        if entry.material not in scene.materials:
            raise scene_error(path, f"{key}.material", f"no material '{entry.material}' in materials")
        if set(entry.fix) & set(_velocity_dofs(entry)):
            raise scene_error(path, f"{key}.velocity", "a degree of freedom is both fixed and prescribed")
        family = (
            entry.brick_wall is not None or entry.jointed_slope is not None or entry.rock_mass is not None
        )
        shape_key = next(k for k in SHAPE_KEYS if getattr(entry, k) is not None)
        try:
            shapes_of_entry, held, labels_of_entry, straight_of_entry = entry_shapes(entry, path, key)
        except ValueError as error:  # a generator asked for more blocks than it makes
            raise scene_error(path, f"{key}.{shape_key}", str(error)) from None
        if not shapes_of_entry:
            raise scene_error(path, f"{key}.{shape_key}", "it makes no block (too small to cut)")
        for k, shape in enumerate(shapes_of_entry):
            labels.append(
                labels_of_entry[k] if labels_of_entry else edge_labels(entry, len(shape), path, key)
            )
            straight.append(straight_of_entry[k])
            names.append(f"{entry.name}.{k}" if family else entry.name)
            shape_keys.append(f"{key}.{shape_key}")
            groups.append(entry.group or entry.name)
            shapes.append(shape)
            entries.append(entry)
            fixed.append(held[k])
    counts = np.array([len(s) for s in shapes])
    vertex_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    may_be_straight = np.zeros(vertex_start[-1], dtype=bool)
    for i, vertices in enumerate(straight):
        may_be_straight[vertex_start[i] + np.asarray(vertices, dtype=np.int64)] = True
    check_shapes(shapes, vertex_start, may_be_straight, names, shape_keys, path)
    shapes = [polygons.counter_clockwise(s) for s in shapes]
    if any(entry.rotate_deg for entry in scene.blocks):
        shapes = turned(shapes, entries)
        check_shapes(shapes, vertex_start, may_be_straight, names, shape_keys, path)
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            raise scene_error(path, "blocks", f"two blocks are named '{name}'")
        seen[name] = i
    group_names = sorted(set(groups))
    block_group = np.array([group_names.index(g) for g in groups], dtype=np.int64)

    n = len(shapes)
    blocks = np.zeros((n, L.BLOCK_COLUMNS))
    dof = np.zeros((n, 3), dtype=np.int64)
    vertex_block = np.repeat(np.arange(n), counts).astype(np.int64)
    vertex_next = np.empty(vertex_start[-1], dtype=np.int64)
    local = np.empty((vertex_start[-1], 2))
    for i, (shape, entry, held) in enumerate(zip(shapes, entries, fixed, strict=True)):
        area, centroid, polar = polygons.mass_properties(shape)
        density = scene.materials[entry.material].density_kg_m3
        first, last = vertex_start[i], vertex_start[i + 1]
        local[first:last] = shape - centroid
        vertex_next[first:last] = np.roll(np.arange(first, last), -1)
        row = blocks[i]
        row[[L.X, L.X0, L.XR]] = centroid[0]
        row[[L.Y, L.Y0, L.YR]] = centroid[1]
        row[[L.MASS, L.MX, L.MY]] = density * area
        row[[L.INERTIA, L.MW]] = density * polar
        row[L.RADIUS] = float(np.max(np.hypot(*(shape - centroid).T)))
        row[L.SIZE] = math.sqrt(area)
        for d, axis in enumerate(("x", "y", "rotation")):
            if axis in held:
                dof[i, d] = L.PRESCRIBED
        velocity = entry.velocity
        for d, value in enumerate(
            (velocity.x_m_s, velocity.y_m_s, velocity.rotation_rad_s) if velocity else (None,) * 3
        ):
            if value is not None:
                dof[i, d] = L.PRESCRIBED
                blocks[i, L.VPX + d] = value
                blocks[i, L.VX + d] = value if velocity.start_step == 0 else 0.0
        blocks[i, L.VSTART] = velocity.start_step if velocity else 0
    check_inertia(blocks, names, entries, path)

    overlap = start_overlap_fault(shapes, names, vertex_start, vertex_next, blocks[:, L.SIZE], scene)
    if overlap:
        raise scene_error(path, "blocks", overlap)

    law_names, law_codes, params = joint_types(scene, path)
    contacts = scene.contacts
    if contacts.default_law not in law_names:
        raise scene_error(
            path, "contacts.default_law", f"no joint law '{contacts.default_law}' in joint_laws"
        )
    rule_groups = np.full((len(contacts.rules), 2), -1, dtype=np.int64)
    rule_dip = np.tile([0.0, math.pi / 2], (len(contacts.rules), 1))
    rule_law = np.zeros(len(contacts.rules), dtype=np.int64)
    label_names = sorted({""} | {label for shape_labels in labels for label in shape_labels})
    label_index = {name: i for i, name in enumerate(label_names)}
    edge_label = np.array([label_index[x] for shape_labels in labels for x in shape_labels], dtype=np.int64)
    rule_edges = np.ones((len(contacts.rules), len(label_names)), dtype=bool)
    for r, rule in enumerate(contacts.rules):
        key = f"contacts.rules.{r}"
        if rule.law not in law_names:
            raise scene_error(path, f"{key}.law", f"no joint law '{rule.law}' in joint_laws")
        rule_law[r] = law_names.index(rule.law)
        if rule.groups:
            for k, group in enumerate(rule.groups):
                if group not in group_names:
                    raise scene_error(path, f"{key}.groups", f"no block group '{group}'")
                rule_groups[r, k] = group_names.index(group)
        if rule.dip_deg:
            rule_dip[r] = np.array(rule.dip_deg) * units.deg
        if rule.edges is not None:
            check_rule_edges(rule.edges, scene, path, f"{key}.edges")
            rule_edges[r] = [x == rule.edges or x.startswith(rule.edges + ".") for x in label_names]
    if CUT in label_names:
        law_names, law_codes, params, rule_groups, rule_dip, rule_law, rule_edges = cuts_glued_or_warned(
            contacts, law_names, law_codes, params, rule_groups, rule_dip, rule_law, rule_edges, label_names
        )

    block_loads = np.zeros((len(scene.loads.block_forces), 5))
    load_block = np.zeros(len(scene.loads.block_forces), dtype=np.int64)
    for k, load in enumerate(scene.loads.block_forces):
        load_block[k] = _block_index(seen, load.block, path, f"loads.block_forces.{k}.block")
        block_loads[k] = [
            load.force_kN[0] * 1e3 / scene.thickness_m,
            load.force_kN[1] * 1e3 / scene.thickness_m,
            load.moment_kN_m * 1e3 / scene.thickness_m,
            load.ramp_steps,
            load.start_step,
        ]
    edge_loads = np.zeros((len(scene.loads.edge_stresses), 4))
    load_edge = np.zeros(len(scene.loads.edge_stresses), dtype=np.int64)
    for k, load in enumerate(scene.loads.edge_stresses):
        key = f"loads.edge_stresses.{k}"
        b = _block_index(seen, load.block, path, f"{key}.block")
        load_edge[k] = vertex_start[b] + _edge_index(shapes[b], load.edge, path, f"{key}.edge")
        edge_loads[k] = [
            load.sigma_n_MPa * units.MPa,
            load.tau_MPa * units.MPa,
            load.ramp_steps,
            load.start_step,
        ]

    sizes = blocks[:, L.SIZE]
    margin = contacts.search_margin_m or 0.02 * float(np.median(sizes))
    monitors = _monitors(scene, seen, group_names, path)
    water = scene.water
    model = Model(
        scene=scene,
        block_names=names,
        group_names=group_names,
        block_group=block_group,
        blocks=blocks,
        dof=dof,
        vertex_start=vertex_start,
        vertex_block=vertex_block,
        vertex_next=vertex_next,
        local=local,
        law_names=law_names,
        laws=law_codes,
        params=params,
        rule_groups=rule_groups,
        rule_dip=rule_dip,
        rule_law=rule_law,
        rule_edges=rule_edges,
        edge_label=edge_label,
        label_names=label_names,
        default_law=law_names.index(contacts.default_law),
        gravity=_gravity(scene),
        block_loads=block_loads,
        load_block=load_block,
        edge_loads=edge_loads,
        load_edge=load_edge,
        search_margin=margin,
        monitors=monitors,
        water_surface=_water_table(scene, path),
        water_unit_weight=water.unit_weight_kN_m3 * 1e3 if water else 0.0,
    )
    support = support_elements(scene.support, shapes, blocks[:, [L.X, L.Y]], model.immobile, names, path)
    for k, name in enumerate(scene.design.elements if scene.design is not None else []):
        if name not in support.names:
            key = "design.support" if isinstance(scene.design.support, str) else f"design.support.{k}"
            raise scene_error(path, key, f"no support element named '{name}'")
    for k, m in enumerate(scene.monitoring.monitors):
        if m.support is not None and m.support not in support.names:
            raise scene_error(
                path, f"monitoring.monitors.{k}.support", f"no support element named '{m.support}'"
            )
    return dataclasses.replace(model, support=support)


def _gravity(scene: Scene) -> np.ndarray:
    """The acceleration on every block [m/s^2]: gravity, plus k_h |g| horizontal with a seismic load."""
    gravity = np.array(scene.gravity_m_s2, dtype=float)
    if scene.seismic is not None:
        sign = -1.0 if scene.seismic.towards == "-x" else 1.0
        gravity[0] += sign * scene.seismic.horizontal_coefficient * float(np.hypot(*gravity))
    return gravity


def _velocity_dofs(entry: BlockEntry) -> list[str]:
    v = entry.velocity
    if v is None:
        return []
    given = zip(("x", "y", "rotation"), (v.x_m_s, v.y_m_s, v.rotation_rad_s), strict=True)
    return [axis for axis, value in given if value is not None]


def _block_index(index: dict[str, int], name: str, path: Path, key: str) -> int:
    if name not in index:
        close = [n for n in index if n.startswith(name)][:3]
        hint = f" (blocks named like it: {', '.join(close)})" if close else ""
        raise scene_error(path, key, f"no block named '{name}'{hint}")
    return index[name]


def _monitors(scene: Scene, index: dict[str, int], group_names: list[str], path: Path) -> list[MonitorSpec]:
    specs, seen = [], set()
    for k, m in enumerate(scene.monitoring.monitors):
        key = f"monitoring.monitors.{k}"
        if m.name in seen:
            raise scene_error(path, f"{key}.name", f"two monitors are named '{m.name}'")
        seen.add(m.name)
        specs.append(_monitor_spec(m, index, group_names, path, key))
    return specs


def _monitor_spec(
    m: Monitor, index: dict[str, int], group_names: list[str], path: Path, key: str
) -> MonitorSpec:
    block = _block_index(index, m.block, path, f"{key}.block") if m.block is not None else -1
    groups = None
    if m.between is not None:
        for group in m.between:
            if group not in group_names:
                raise scene_error(path, f"{key}.between", f"no block group '{group}'")
        groups = (group_names.index(m.between[0]), group_names.index(m.between[1]))
    return MonitorSpec(
        name=m.name,
        quantity=m.quantity,
        block=block,
        point=np.array(m.point_m) if m.point_m is not None else None,
        groups=groups,
        near=np.array(m.near_m) if m.near_m is not None else None,
        support=m.support,
    )
