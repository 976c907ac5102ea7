"""The blocks of a scene's entries: their shapes from each kind of entry (a polygon, a rectangle, a
brick wall, a jointed slope, a rock mass), their edges' labels, and the checks that make them a
physical start state (rigid convex blocks, finite inertia, no deep overlap), each fault one line
naming the block and the key."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bbmc import units
from bbmc.dem import detection
from bbmc.dem import layout as L
from bbmc.geometry import polygons
from bbmc.rockmass.generate import GeometryError
from bbmc.rockmass.generate import generate as generate_rock_mass
from bbmc.rockmass.generate import possible_labels as rock_mass_labels
from bbmc.scene.schema import (
    BlockEntry,
    JointedSlope,
    Scene,
    scene_error,
)

SHAPE_KEYS = ("polygon_m", "rectangle_m", "brick_wall", "jointed_slope", "rock_mass")


def _slope_blocks(slope: JointedSlope) -> tuple[list[np.ndarray], list[list[str]], list[list[str]]]:
    """The slope's blocks, the degrees of freedom held for each (all three for a block with an edge on
    a fixed boundary: a corner touching it is not enough), and their edges' labels (joint.<set> on a
    set's joint, '' elsewhere)."""
    dump = slope.model_dump()
    shapes = polygons.jointed_slope(**{k: v for k, v in dump.items() if k != "fixed_boundaries"})
    labels = [
        [slope.joint_labels[k] if k >= 0 else "" for k in edge_sets]
        for edge_sets in polygons.joint_set_of_edges(shapes, dump["joint_sets"])
    ]
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
    return shapes, held, labels


def entry_shapes(
    entry: BlockEntry, path: Path, key: str
) -> tuple[list[np.ndarray], list[list[str]], list[list[str]] | None, list[list[int]]]:
    """The entry's blocks (vertices as given, not yet turned), the degrees of freedom held for each,
    their edges' labels (a generator's; None: from `edge_labels`) and the vertices of each that may be
    straight angles (where an edge's label changes)."""
    if entry.edge_labels is not None and entry.polygon_m is None:
        raise scene_error(path, f"{key}.edge_labels", "edge labels are given with polygon_m")
    labels, straight = None, None
    if entry.jointed_slope is not None:
        shapes, held, labels = _slope_blocks(entry.jointed_slope)
    elif entry.rock_mass is not None:
        try:
            mass = generate_rock_mass(entry.rock_mass)
        except GeometryError as error:
            raise scene_error(path, f"{key}.rock_mass.{error.key}", error.reason) from None
        shapes, labels, straight = mass.polygons, mass.edge_labels, mass.split_vertices
        held = [["x", "y", "rotation"] if h else [] for h in mass.held]
    else:
        if entry.polygon_m is not None:
            shapes = [np.array(entry.polygon_m, dtype=float)]
        elif entry.rectangle_m is not None:
            r = entry.rectangle_m
            shapes = [polygons.rectangle(r.x_m, r.y_m, r.width_m, r.height_m)]
        else:
            shapes = polygons.GENERATORS["brick_wall"](**entry.brick_wall.model_dump())
        held = [[] for _ in shapes]
    fixed = [sorted(set(h) | set(entry.fix)) for h in held]
    return shapes, fixed, labels, straight or [[] for _ in shapes]


def possible_labels(entry: BlockEntry) -> list[str]:
    """The labels the edges of the entry's blocks can carry: a polygon's `edge_labels`, a jointed
    slope's joint.<set>, a rock mass's (`bbmc.rockmass.generate.possible_labels`); none otherwise."""
    if entry.jointed_slope is not None:
        return entry.jointed_slope.joint_labels
    if entry.rock_mass is not None:
        return rock_mass_labels(entry.rock_mass)
    return [label for label in entry.edge_labels or [] if label]


def edge_labels(entry: BlockEntry, n_edges: int, path: Path, key: str) -> list[str]:
    """The labels of a block's edges in the engine's (counter-clockwise) order: a polygon's
    `edge_labels` as written (edge k from vertex k to k + 1), reversed with a clockwise polygon."""
    if entry.edge_labels is None:
        return [""] * n_edges
    if len(entry.edge_labels) != n_edges:
        raise scene_error(
            path, f"{key}.edge_labels", f"give one label per edge: {n_edges}, got {len(entry.edge_labels)}"
        )
    if polygons.polygon_area(np.array(entry.polygon_m, dtype=float)) > 0.0:
        return list(entry.edge_labels)
    return [entry.edge_labels[(n_edges - 2 - i) % n_edges] for i in range(n_edges)]


def turned(shapes: list[np.ndarray], entries: list[BlockEntry]) -> list[np.ndarray]:
    """Each shape turned as its entry asks (about its own centroid unless the entry gives a point)."""
    turned = []
    for shape, entry in zip(shapes, entries, strict=True):
        if entry.rotate_deg:
            about = entry.rotate_about_m or polygons.mass_properties(shape)[1]
            shape = polygons.rotated(shape, entry.rotate_deg * units.deg, np.array(about))
        turned.append(shape)
    return turned


def start_overlap_fault(
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


def check_shapes(
    shapes: list[np.ndarray],
    vertex_start: np.ndarray,
    may_be_straight: np.ndarray,
    names: list[str],
    keys: list[str],
    path: Path,
) -> None:
    """ConfigError naming the first block whose shape cannot be a rigid convex block (a vertex marked in
    `may_be_straight` may be a straight angle)."""
    faults = polygons.shape_faults(np.concatenate(shapes), vertex_start, may_be_straight)
    if faults:
        i = min(faults)
        raise scene_error(path, keys[i], f"block '{names[i]}': {faults[i]}")


def check_inertia(blocks: np.ndarray, names: list[str], entries: list[BlockEntry], path: Path) -> None:
    """ConfigError naming the first block whose mass or moment of inertia (density x area, density x
    second moment of area) is not a positive normal floating-point number: the engine divides by both."""
    inertia = blocks[:, [L.MASS, L.INERTIA]]
    sound = np.all(np.isfinite(inertia) & (inertia >= np.finfo(float).tiny), axis=1)
    if not sound.all():
        i = int(np.argmin(sound))
        mass, moment = inertia[i]
        raise scene_error(
            path,
            f"materials.{entries[i].material}.density_kg_m3",
            f"block '{names[i]}': its mass ({mass:.3g} kg) and moment of inertia ({moment:.3g} kg m^2) "
            "are beyond floating point",
        )
