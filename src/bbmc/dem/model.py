"""From a validated `Scene` to the engine's arrays in SI, checking every cross-reference on the way.

`build_model` is the boundary where scene units (MPa, mm, kN, deg) become SI and where names become
indices; anything a scene refers to that does not exist is a `ConfigError` naming the key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bbmc import laws, units
from bbmc.config import ConfigError, validate
from bbmc.dem import detection, polygons
from bbmc.dem import layout as L
from bbmc.dem.scene import (
    BartonBandisLaw,
    BlockEntry,
    ConstantLaw,
    JointedSlope,
    MobilizedLaw,
    Monitor,
    Scene,
)
from bbmc.joint_model import SIGMA_REF

EDGE_DIRECTIONS = {"up": (0.0, 1.0), "down": (0.0, -1.0), "left": (-1.0, 0.0), "right": (1.0, 0.0)}
SHEAR_CODES = {
    "constant": L.SHEAR_CONSTANT,
    "bandis": L.SHEAR_BANDIS,
    "corrected": L.SHEAR_CORRECTED,
    "simplified": L.SHEAR_SIMPLIFIED,
    "hyperbolic": L.SHEAR_HYPERBOLIC,
}


@dataclass(frozen=True)
class MonitorSpec:
    """A monitor with its names resolved to indices (-1 where not used)."""

    name: str
    quantity: str
    block: int
    point: np.ndarray | None
    groups: tuple[int, int] | None
    near: np.ndarray | None


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
    economy: Economy = field(default_factory=Economy)

    @property
    def immobile(self) -> np.ndarray:
        """Blocks with every degree of freedom held at zero velocity: they can never load each other."""
        held = (self.dof == L.PRESCRIBED) & (self.blocks[:, [L.VPX, L.VPY, L.VPW]] == 0.0)
        return np.all(held, axis=1)

    @property
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


SHAPE_KEYS = ("polygon_m", "rectangle_m", "brick_wall", "jointed_slope")


def _error(path: Path, key: str, message: str) -> ConfigError:
    return ConfigError(f"{path}: key '{key}': {message}")


def _slope_blocks(slope: JointedSlope) -> tuple[list[np.ndarray], list[list[str]]]:
    """The slope's blocks, and the degrees of freedom held for each: all three for a block with an
    edge on a fixed boundary (a corner touching it is not enough)."""
    dump = slope.model_dump()
    shapes = polygons.jointed_slope(**{k: v for k, v in dump.items() if k != "fixed_boundaries"})
    x_left, x_right, y_bottom, _ = polygons.slope_bounds(
        slope.height_m, slope.face_angle_deg, slope.crest_extent_m, slope.toe_extent_m, slope.depth_m
    )
    tolerance = 1e-6 * (x_right - x_left)
    sides = {
        "left": lambda v: v[:, 0] <= x_left + tolerance,
        "right": lambda v: v[:, 0] >= x_right - tolerance,
        "bottom": lambda v: v[:, 1] <= y_bottom + tolerance,
    }
    held = [
        ["x", "y", "rotation"] if any(sides[side](s).sum() >= 2 for side in slope.fixed_boundaries) else []
        for s in shapes
    ]
    return shapes, held


def _shapes(entry: BlockEntry) -> tuple[list[np.ndarray], list[list[str]]]:
    """The entry's blocks (vertices as given, not yet turned) and the degrees of freedom held for each."""
    if entry.jointed_slope is not None:
        shapes, held = _slope_blocks(entry.jointed_slope)
    else:
        if entry.polygon_m is not None:
            shapes = [np.array(entry.polygon_m, dtype=float)]
        elif entry.rectangle_m is not None:
            r = entry.rectangle_m
            shapes = [polygons.rectangle(r.x_m, r.y_m, r.width_m, r.height_m)]
        else:
            shapes = polygons.GENERATORS["brick_wall"](**entry.brick_wall.model_dump())
        held = [[] for _ in shapes]
    return shapes, [sorted(set(h) | set(entry.fix)) for h in held]


def _turned(shapes: list[np.ndarray], entries: list[BlockEntry]) -> list[np.ndarray]:
    """Each shape turned as its entry asks (about its own centroid unless the entry gives a point)."""
    turned = []
    for shape, entry in zip(shapes, entries, strict=True):
        if entry.rotate_deg:
            about = entry.rotate_about_m or polygons.mass_properties(shape)[1]
            shape = polygons.rotated(shape, entry.rotate_deg * units.deg, np.array(about))
        turned.append(shape)
    return turned


def _mobilized_law_row(law: MobilizedLaw, p: np.ndarray) -> tuple[list[int], np.ndarray]:
    """The mobilized law's parameters: JRC_n, JCS_n at the field length, phi_r, delta_peak, M, and the
    Bandis closure's K_ni, V_m (from the lab-scale JRC_0, JCS_0, where the fits were made)."""
    lab, field = law.lab_length_m, law.field_length_m or law.lab_length_m
    jcs0 = law.jcs0_MPa * units.MPa
    jrc_n = float(laws.scaled_jrc(law.jrc0, lab, field))
    p[L.P_JRC], p[L.P_JCS] = jrc_n, float(laws.scaled_jcs(jcs0, law.jrc0, lab, field))
    phi_b = law.phi_b_deg * units.deg
    p[L.P_PHI_B] = (
        law.phi_r_deg * units.deg
        if law.phi_r_deg is not None
        else float(laws.residual_friction_angle(phi_b, law.rebound_ratio))
    )
    p[L.P_PHI_MAX] = law.phi_max_deg * units.deg
    p[L.P_PEAK_DISPLACEMENT] = float(laws.peak_shear_displacement(field, jrc_n))
    p[L.P_DAMAGE] = 0.0 if law.damage == "barton_1985" else law.damage
    p[L.P_STRESS_FLOOR] = law.stress_floor_MPa * units.MPa
    p[L.P_KS] = law.shear_stiffness.ks_MPa_per_mm * units.MPa_per_mm
    normal = law.normal_stiffness
    if normal.law == "constant":
        p[L.P_KN] = normal.kn_MPa_per_mm * units.MPa_per_mm
        normal_code = L.NORMAL_CONSTANT
    else:
        aperture = (
            normal.aperture_mm * units.mm
            if normal.aperture_mm is not None
            else float(laws.initial_aperture(law.jrc0, jcs0, normal.sigma_c_MPa * units.MPa))
        )
        p[L.P_K_NI] = float(laws.bandis_initial_normal_stiffness(law.jrc0, jcs0, aperture))
        p[L.P_V_M] = float(laws.bandis_maximum_closure(law.jrc0, jcs0, aperture))
        p[L.P_KN] = p[L.P_K_NI]
        normal_code = L.NORMAL_BANDIS
    return [L.STRENGTH_MOBILIZED, normal_code, L.SHEAR_CONSTANT, L.AFTER_SLIP_KEEP], p


def _joint_law_row(law: ConstantLaw | BartonBandisLaw | MobilizedLaw) -> tuple[list[int], np.ndarray]:
    p = np.zeros(L.PARAMETERS)
    p[L.P_STRENGTH_DIVISOR] = 1.0
    if isinstance(law, MobilizedLaw):
        return _mobilized_law_row(law, p)
    after = L.AFTER_SLIP_ZERO if law.after_slip == "zero" else L.AFTER_SLIP_KEEP
    p[L.P_TEN] = law.tensile_strength_MPa * units.MPa
    if isinstance(law, ConstantLaw):
        p[L.P_KN] = law.kn_MPa_per_mm * units.MPa_per_mm
        p[L.P_KS] = law.ks_MPa_per_mm * units.MPa_per_mm
        p[L.P_COH] = law.cohesion_MPa * units.MPa
        p[L.P_PHI] = law.friction_deg * units.deg
        return [L.STRENGTH_CONSTANT, L.NORMAL_CONSTANT, L.SHEAR_CONSTANT, after], p
    s = law.strength
    p[L.P_JRC], p[L.P_JCS] = s.jrc, s.jcs_MPa * units.MPa
    p[L.P_PHI_B], p[L.P_PHI_MAX] = s.phi_b_deg * units.deg, s.phi_max_deg * units.deg
    exact = float(laws.exact_tangent_coefficient(s.jrc))
    p[L.P_K_TANGENT] = exact if s.tangent_coefficient == "exact" else s.tangent_coefficient
    p[L.P_STRESS_FLOOR] = law.stress_floor_MPa * units.MPa
    p[L.P_SHEAR_FLOOR] = law.shear_stiffness_floor
    p[L.P_SIGMA_REF] = SIGMA_REF
    normal, shear = law.normal_stiffness, law.shear_stiffness
    if normal.law == "constant":
        p[L.P_KN] = normal.kn_MPa_per_mm * units.MPa_per_mm
    else:
        p[L.P_Q], p[L.P_LG_E] = normal.q_per_mm * units.per_mm, normal.lg_e
    if shear.law == "constant":
        p[L.P_KS] = shear.ks_MPa_per_mm * units.MPa_per_mm
    else:
        p[L.P_K_J], p[L.P_N_J] = shear.kj_MPa_per_mm * units.MPa_per_mm, shear.nj
    if shear.law == "simplified":
        p[L.P_D] = shear.d
    elif shear.law != "constant":
        p[L.P_TAU_P_SLOPE] = shear.peak_strength.slope
        p[L.P_TAU_P_INTERCEPT] = shear.peak_strength.intercept_MPa * units.MPa
        p[L.P_TAU_ULT_SLOPE] = shear.ultimate_strength.slope
        p[L.P_TAU_ULT_INTERCEPT] = shear.ultimate_strength.intercept_MPa * units.MPa
        p[L.P_A], p[L.P_B] = shear.a, shear.b
    normal_code = L.NORMAL_CONSTANT if normal.law == "constant" else L.NORMAL_EQ8
    return [L.STRENGTH_BARTON_BANDIS, normal_code, SHEAR_CODES[shear.law], after], p


def _edge_index(vertices: np.ndarray, edge: str | int, path: Path, key: str) -> int:
    n = len(vertices)
    if isinstance(edge, int):
        if edge >= n:
            raise _error(path, key, f"the block has {n} edges (0 to {n - 1}), got {edge}")
        return edge
    direction = np.array(EDGE_DIRECTIONS[edge])
    tangents = np.roll(vertices, -1, axis=0) - vertices
    normals = np.column_stack([tangents[:, 1], -tangents[:, 0]])
    normals /= np.hypot(normals[:, 0], normals[:, 1])[:, None]
    return int(np.argmax(normals @ direction))


def _start_overlap_fault(
    shapes: list[np.ndarray],
    names: list[str],
    vertex_start: np.ndarray,
    vertex_next: np.ndarray,
    sizes: np.ndarray,
    scene: Scene,
) -> str | None:
    """Why the blocks cannot start where they are, or None: they span more than floating point holds,
    or two of them overlap deeper than `contacts.interpenetration_limit` x the smaller one's size (the
    depth at which a run warns). Every pair whose boxes meet is measured (the contact search's broad
    phase, then separating axes), held blocks included."""
    world = np.concatenate(shapes)
    span = float(np.max(np.ptp(world, axis=0)))
    if not np.isfinite(span):
        return "the blocks lie too far apart for floating point (their span is not a finite number)"
    pairs = detection.candidate_pairs(world, vertex_start, np.zeros(len(shapes), dtype=np.bool_), 0.0)
    if not len(pairs):
        return None
    depth = detection.overlap_depth(pairs, world, vertex_start, vertex_next)
    relative = depth / np.minimum(sizes[pairs[:, 0]], sizes[pairs[:, 1]])
    limit = scene.contacts.interpenetration_limit
    deep = np.flatnonzero(relative > limit)
    if not len(deep):
        return None
    k = deep[np.argmax(relative[deep])]
    a, b = pairs[k]
    others = f"; {len(deep) - 1} other pairs overlap too" if len(deep) > 1 else ""
    return (
        f"blocks '{names[a]}' and '{names[b]}' overlap by {depth[k]:.3g} m at the start, "
        f"{100 * relative[k]:.3g} % of the smaller one's size (contacts.interpenetration_limit: "
        f"{100 * limit:.3g} %){others}"
    )


def _check_shapes(
    shapes: list[np.ndarray], vertex_start: np.ndarray, names: list[str], keys: list[str], path: Path
) -> None:
    """ConfigError naming the first block whose shape cannot be a rigid convex block."""
    faults = polygons.shape_faults(np.concatenate(shapes), vertex_start)
    if faults:
        i = min(faults)
        raise _error(path, keys[i], f"block '{names[i]}': {faults[i]}")


def _check_inertia(blocks: np.ndarray, names: list[str], entries: list[BlockEntry], path: Path) -> None:
    """ConfigError naming the first block whose mass or moment of inertia (density x area, density x
    second moment of area) is not a positive normal floating-point number: the engine divides by both."""
    inertia = blocks[:, [L.MASS, L.INERTIA]]
    sound = np.all(np.isfinite(inertia) & (inertia >= np.finfo(float).tiny), axis=1)
    if not sound.all():
        i = int(np.argmin(sound))
        mass, moment = inertia[i]
        raise _error(
            path,
            f"materials.{entries[i].material}.density_kg_m3",
            f"block '{names[i]}': its mass ({mass:.3g} kg) and moment of inertia ({moment:.3g} kg m^2) "
            "are beyond floating point",
        )


def built_scene(tree: dict, name: str) -> Model:
    """A scene that code builds (a mapping in the scene format) checked and built as a scene file is: a
    fault is one `ConfigError` line naming `name` and the key."""
    return build_model(validate(tree, Scene, name, strict=False), Path(name))


def build_model(scene: Scene, path: Path) -> Model:
    """Check every reference of the scene and assemble the engine's arrays."""
    names, shape_keys, groups, shapes, entries, fixed = [], [], [], [], [], []
    for i, entry in enumerate(scene.blocks):
        key = f"blocks.{i}"
        if entry.material not in scene.materials:
            raise _error(path, f"{key}.material", f"no material '{entry.material}' in materials")
        if set(entry.fix) & set(_velocity_dofs(entry)):
            raise _error(path, f"{key}.velocity", "a degree of freedom is both fixed and prescribed")
        family = entry.brick_wall is not None or entry.jointed_slope is not None
        shape_key = next(k for k in SHAPE_KEYS if getattr(entry, k) is not None)
        try:
            shapes_of_entry, held = _shapes(entry)
        except ValueError as error:  # a generator asked for more blocks than it makes
            raise _error(path, f"{key}.{shape_key}", str(error)) from None
        if not shapes_of_entry:
            raise _error(path, f"{key}.{shape_key}", "it makes no block (too small to cut)")
        for k, shape in enumerate(shapes_of_entry):
            names.append(f"{entry.name}.{k}" if family else entry.name)
            shape_keys.append(f"{key}.{shape_key}")
            groups.append(entry.group or entry.name)
            shapes.append(shape)
            entries.append(entry)
            fixed.append(held[k])
    counts = np.array([len(s) for s in shapes])
    vertex_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    _check_shapes(shapes, vertex_start, names, shape_keys, path)
    shapes = [polygons.counter_clockwise(s) for s in shapes]
    if any(entry.rotate_deg for entry in scene.blocks):
        shapes = _turned(shapes, entries)
        _check_shapes(shapes, vertex_start, names, shape_keys, path)
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            raise _error(path, "blocks", f"two blocks are named '{name}'")
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
    _check_inertia(blocks, names, entries, path)

    overlap = _start_overlap_fault(shapes, names, vertex_start, vertex_next, blocks[:, L.SIZE], scene)
    if overlap:
        raise _error(path, "blocks", overlap)

    law_names = list(scene.joint_laws)
    rows = [_joint_law_row(law) for law in scene.joint_laws.values()]
    law_codes = np.array([r[0] for r in rows], dtype=np.int64)
    params = np.array([r[1] for r in rows])
    contacts = scene.contacts
    if contacts.default_law not in law_names:
        raise _error(path, "contacts.default_law", f"no joint law '{contacts.default_law}' in joint_laws")
    rule_groups = np.full((len(contacts.rules), 2), -1, dtype=np.int64)
    rule_dip = np.tile([0.0, math.pi / 2], (len(contacts.rules), 1))
    rule_law = np.zeros(len(contacts.rules), dtype=np.int64)
    for r, rule in enumerate(contacts.rules):
        key = f"contacts.rules.{r}"
        if rule.law not in law_names:
            raise _error(path, f"{key}.law", f"no joint law '{rule.law}' in joint_laws")
        rule_law[r] = law_names.index(rule.law)
        if rule.groups:
            for k, group in enumerate(rule.groups):
                if group not in group_names:
                    raise _error(path, f"{key}.groups", f"no block group '{group}'")
                rule_groups[r, k] = group_names.index(group)
        if rule.dip_deg:
            rule_dip[r] = np.array(rule.dip_deg) * units.deg

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
    return Model(
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
        default_law=law_names.index(contacts.default_law),
        gravity=_gravity(scene),
        block_loads=block_loads,
        load_block=load_block,
        edge_loads=edge_loads,
        load_edge=load_edge,
        search_margin=margin,
        monitors=monitors,
        water_surface=np.array(water.phreatic_surface_m if water else [[0.0, 0.0], [1.0, 0.0]], dtype=float),
        water_unit_weight=water.unit_weight_kN_m3 * 1e3 if water else 0.0,
    )


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
        raise _error(path, key, f"no block named '{name}'{hint}")
    return index[name]


def _monitors(scene: Scene, index: dict[str, int], group_names: list[str], path: Path) -> list[MonitorSpec]:
    specs, seen = [], set()
    for k, m in enumerate(scene.monitoring.monitors):
        key = f"monitoring.monitors.{k}"
        if m.name in seen:
            raise _error(path, f"{key}.name", f"two monitors are named '{m.name}'")
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
                raise _error(path, f"{key}.between", f"no block group '{group}'")
        groups = (group_names.index(m.between[0]), group_names.index(m.between[1]))
    return MonitorSpec(
        name=m.name,
        quantity=m.quantity,
        block=block,
        point=np.array(m.point_m) if m.point_m is not None else None,
        groups=groups,
        near=np.array(m.near_m) if m.near_m is not None else None,
    )
