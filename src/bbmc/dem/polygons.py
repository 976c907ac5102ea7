"""Block geometry: convex polygons, their mass properties, and the named block generators.

Plain numpy; vertices in metres, counter-clockwise. Mass properties are per unit density and per
metre of thickness; the model multiplies them by density (the engine works per metre of thickness).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np


def polygon_area(vertices: np.ndarray) -> float:
    """Signed area [m^2] (shoelace): > 0 for counter-clockwise vertices."""
    x, y = vertices[:, 0], vertices[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def counter_clockwise(vertices: np.ndarray) -> np.ndarray:
    """The vertices in counter-clockwise order (reversed if they were given clockwise)."""
    return vertices if polygon_area(vertices) > 0 else vertices[::-1].copy()


def convexity_fault(vertices: np.ndarray, straight: Sequence[int] = ()) -> str | None:
    """Why a counter-clockwise polygon is not a usable convex block, or None if it is; the vertices
    `straight` may be straight angles (a point where an edge's label changes: a trace's end)."""
    if len(vertices) < 3:
        return "a block needs at least 3 vertices"
    edges = np.roll(vertices, -1, axis=0) - vertices
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    scale = float(np.max(lengths))
    if scale <= 0 or np.min(lengths) <= 1e-9 * scale:
        return "two vertices coincide (an edge of zero length)"
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    at = (np.arange(len(vertices)) + 1) % len(vertices)  # turns[k] is the angle at vertex k + 1
    flat = np.isin(at, np.asarray(straight, dtype=np.int64))
    if np.any(turns[~flat] <= 1e-12 * scale * scale) or np.any(turns[flat] < -1e-9 * scale * scale):
        return "the polygon is not strictly convex (a reflex or straight angle)"
    return None


def mass_properties(vertices: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area [m^2], centroid [m] and polar second moment of area about the centroid [m^4] of a
    counter-clockwise polygon (times density and thickness: mass and moment of inertia)."""
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    cx = ((x + xn) * cross).sum() / (6 * area)
    cy = ((y + yn) * cross).sum() / (6 * area)
    ixx = ((y * y + y * yn + yn * yn) * cross).sum() / 12
    iyy = ((x * x + x * xn + xn * xn) * cross).sum() / 12
    polar = ixx + iyy - area * (cx * cx + cy * cy)
    return float(area), np.array([cx, cy]), float(polar)


def rectangle(x: float, y: float, width: float, height: float) -> np.ndarray:
    """Axis-aligned rectangle from its lower-left corner [m], counter-clockwise."""
    return np.array([[x, y], [x + width, y], [x + width, y + height], [x, y + height]], dtype=float)


def rotated(vertices: np.ndarray, angle: float, about: np.ndarray) -> np.ndarray:
    """The polygon turned counter-clockwise by `angle` [rad] about the point `about` [m]."""
    c, s = np.cos(angle), np.sin(angle)
    return (vertices - about) @ np.array([[c, s], [-s, c]]) + about


def brick_wall(
    origin_m: tuple[float, float],
    columns: int,
    rows: int,
    block_width_m: float,
    block_height_m: float,
    row_offset: float = 0.0,
) -> list[np.ndarray]:
    """Rows of equal rectangular blocks, each row shifted by `row_offset` block widths from the one
    below (0: a grid with continuous vertical joints; 0.5: running bond)."""
    x0, y0 = origin_m
    blocks = []
    for row in range(rows):
        shift = (row * row_offset % 1.0) * block_width_m
        for column in range(columns):
            blocks.append(
                rectangle(
                    x0 + shift + column * block_width_m,
                    y0 + row * block_height_m,
                    block_width_m,
                    block_height_m,
                )
            )
    return blocks


def clip_half_plane(vertices: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The part of a convex polygon where normal . x <= offset (one pass of Sutherland-Hodgman);
    an empty (0, 2) array when nothing is left."""
    distance = vertices @ normal - offset
    kept = []
    for i in range(len(vertices)):
        j = (i + 1) % len(vertices)
        if distance[i] <= 0:
            kept.append(vertices[i])
        if distance[i] * distance[j] < 0:
            kept.append(vertices[i] + (vertices[j] - vertices[i]) * distance[i] / (distance[i] - distance[j]))
    return _without_repeats(np.array(kept).reshape(-1, 2))


def _without_repeats(vertices: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
    """Drop vertices that repeat their predecessor, or lie on the line through their neighbours."""
    if len(vertices) < 3:
        return vertices
    span = max(1.0, float(np.ptp(vertices, axis=0).max()))
    step = vertices - np.roll(vertices, 1, axis=0)
    vertices = vertices[np.hypot(step[:, 0], step[:, 1]) > tolerance * span]
    if len(vertices) < 3:
        return vertices
    before, after = np.roll(vertices, 1, axis=0) - vertices, np.roll(vertices, -1, axis=0) - vertices
    turn = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
    return vertices[np.abs(turn) > tolerance * span * span]


def joint_set_trace(dip_deg: float, dip_direction_to_face_deg: float) -> np.ndarray:
    """Unit normal [1] of a joint set's traces in the slope's cross-section, and their spacing factor.

    The section is x (horizontal, away from the free face, which faces -x) and y (up). A set dips at
    `dip_deg`; its dip direction makes `dip_direction_to_face_deg` with the direction the face looks
    (0: dips out of the slope, towards the face; 180: into it). Returns [n_x, n_y, factor]: the traces
    are the lines n . x = constant, and a true spacing s puts them s / factor apart in the section.
    """
    dip, beta = np.radians(dip_deg), np.radians(dip_direction_to_face_deg)
    normal = np.array([-np.sin(dip) * np.cos(beta), np.cos(dip)])
    factor = float(np.hypot(*normal))
    if factor < 1e-9:
        raise ValueError("a joint set parallel to the cross-section has no trace in it")
    return np.append(normal / factor, factor)


def slope_bounds(
    height_m: float, face_angle_deg: float, crest_extent_m: float, toe_extent_m: float, depth_m: float
) -> tuple[float, float, float, float]:
    """The model's box (x_left, x_right, y_bottom, y_top) [m]: the toe at the origin, the crest at
    (height / tan(face angle), height), ground level in front of the toe at y = 0."""
    crest_x = height_m / np.tan(np.radians(face_angle_deg))
    return -toe_extent_m, float(crest_x + crest_extent_m), -depth_m, height_m


def slope_profile_parts(
    height_m: float,
    face_angle_deg: float,
    crest_extent_m: float,
    toe_extent_m: float,
    depth_m: float,
    toe_split: np.ndarray,
) -> list[np.ndarray]:
    """The slope's cross-section as convex polygons: the ground in front of the toe and the rock
    behind the face are split at the toe along the downward direction `toe_split` (unit vector),
    which must lie between the face's extension below the toe and the horizontal to the right."""
    x_left, x_right, y_bottom, top = slope_bounds(
        height_m, face_angle_deg, crest_extent_m, toe_extent_m, depth_m
    )
    box = rectangle(x_left, y_bottom, x_right - x_left, top - y_bottom)
    angle = np.radians(face_angle_deg)
    behind_face = clip_half_plane(box, np.array([-np.sin(angle), np.cos(angle)]), 0.0)
    if toe_extent_m == 0 or depth_m == 0:
        return [clip_half_plane(behind_face, np.array([0.0, -1.0]), 0.0) if depth_m == 0 else behind_face]
    into_slope = np.array([-toe_split[1], toe_split[0]])  # normal to the split, pointing away from the face
    return [
        clip_half_plane(behind_face, -into_slope, 0.0),
        clip_half_plane(clip_half_plane(box, into_slope, 0.0), np.array([0.0, 1.0]), 0.0),
    ]


def toe_split_direction(face_angle_deg: float, set_normals: list[np.ndarray]) -> np.ndarray:
    """The downward direction along which the profile is split at the toe: the trace of the first set
    in `set_normals` (those with a joint through the toe) that keeps both parts convex, else vertical."""
    angle = np.radians(face_angle_deg)
    face_down = -np.array([np.cos(angle), np.sin(angle)])
    for normal in set_normals:
        down = np.array([normal[1], -normal[0]])
        down = down if down[1] < 0 else -down
        if down[1] < -1e-9 and face_down[0] * down[1] - face_down[1] * down[0] >= 0:
            return down
    return np.array([0.0, -1.0])


def _cut(piece: np.ndarray, normal: np.ndarray, offset: float, spacing: float) -> list[np.ndarray]:
    """A convex piece cut by the parallel lines normal . x = offset + k spacing."""
    projection = piece @ normal
    first = int(np.floor((projection.min() - offset) / spacing))
    last = int(np.ceil((projection.max() - offset) / spacing))
    pieces = []
    for k in range(first, last):
        low, high = offset + k * spacing, offset + (k + 1) * spacing
        cell = clip_half_plane(clip_half_plane(piece, normal, high), -normal, -low)
        if len(cell) >= 3:
            pieces.append(cell)
    return pieces


def jointed_slope(
    height_m: float,
    face_angle_deg: float,
    crest_extent_m: float,
    toe_extent_m: float,
    depth_m: float,
    joint_sets: list[dict],
    min_block_fraction: float = 0.02,
) -> list[np.ndarray]:
    """A slope's cross-section cut by persistent joint sets into convex blocks.

    Each set is a dict of dip_deg, dip_direction_to_face_deg (see `joint_set_trace`), spacing_m (true,
    normal to the joints) and offset_m (of the first joint from the toe, normal to the joints). The
    profile is split into two convex parts at the toe (`toe_split_direction`): along a set that passes
    through the toe (offset 0) where one can, so the split is a joint of that set. Pieces smaller than
    `min_block_fraction` of the median piece are dropped (slivers where a joint nearly meets a corner).
    """
    traces = [joint_set_trace(s["dip_deg"], s["dip_direction_to_face_deg"]) for s in joint_sets]
    through_toe = [t[:2] for t, s in zip(traces, joint_sets, strict=True) if s["offset_m"] == 0]
    split = toe_split_direction(face_angle_deg, through_toe)
    pieces = slope_profile_parts(height_m, face_angle_deg, crest_extent_m, toe_extent_m, depth_m, split)
    for trace, joint_set in zip(traces, joint_sets, strict=True):
        normal, spacing = trace[:2], joint_set["spacing_m"] / trace[2]
        offset = joint_set["offset_m"] / trace[2]
        pieces = [cell for piece in pieces for cell in _cut(piece, normal, offset, spacing)]
    areas = np.array([polygon_area(p) for p in pieces])
    smallest = min_block_fraction * np.median(areas)
    return [p for p, a in zip(pieces, areas, strict=True) if a >= smallest]


GENERATORS: dict[str, Callable[..., list[np.ndarray]]] = {"brick_wall": brick_wall}
