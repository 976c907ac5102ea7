"""Block geometry: convex polygons, their mass properties, and the named block generators.

Plain numpy; vertices in metres, counter-clockwise. Mass properties are per unit density and per
metre of thickness; the model multiplies them by density (the engine works per metre of thickness).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def carried_points(
    start: np.ndarray, centroid_start: np.ndarray, centroid_now: np.ndarray, turn: np.ndarray
) -> np.ndarray:
    """Where points fixed in rigid blocks are now [m]: each point `start` (n, 2) of a block whose
    centroid moved from `centroid_start` to `centroid_now` (n, 2) and which turned by `turn` (n,)
    [rad] counter-clockwise: c_now + R(turn) (start - c_start)."""
    c, s = np.cos(turn), np.sin(turn)
    arm = start - centroid_start
    return centroid_now + np.column_stack([c * arm[:, 0] - s * arm[:, 1], s * arm[:, 0] + c * arm[:, 1]])


def polygon_area(vertices: np.ndarray) -> float:
    """Signed area [m^2] (shoelace, about the first vertex): > 0 for counter-clockwise vertices."""
    x, y = (vertices - vertices[0]).T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def counter_clockwise(vertices: np.ndarray) -> np.ndarray:
    """The vertices in counter-clockwise order (reversed if they were given clockwise)."""
    return vertices if polygon_area(vertices) > 0 else vertices[::-1].copy()


def shape_faults(
    vertices: np.ndarray, start: np.ndarray, straight: np.ndarray | None = None
) -> dict[int, str]:
    """The polygons that cannot be rigid convex blocks, by index, with why: fewer than 3 vertices, a
    coordinate that is not a finite number, no extent (or too little to tell its vertices apart at its
    distance from the origin, or a size beyond 1e-60 to 1e60 m), two vertices at one point, no area
    (every vertex on one line), a reflex or straight angle, or edges that cross each other (a bow tie,
    a star).

    `vertices` (m, 2) holds every polygon's vertices, in either order of turn, polygon k's at
    start[k]:start[k + 1] (the vertices named in a fault are numbered as given). Judged all at once
    (100,000 blocks in under 0.1 s), each on its polygon scaled to unit extent, so a block of any size
    is judged alike: two vertices coincide within 1e-9 of the extent, an angle is straight within a
    turn of 1e-12 (cross product of the unit-scaled edges), and the edges of a convex polygon turn
    once around in all. `straight` (m,), if given, marks the vertices that may be straight angles
    (a point where an edge's label changes: a trace's end); they may not be reflex."""
    count = np.diff(start)
    faults = {int(k): f"a block needs at least 3 vertices, got {count[k]}" for k in np.flatnonzero(count < 3)}
    if faults:
        return faults
    first = start[:-1]
    block = np.repeat(np.arange(len(count)), count)
    following_vertex = np.arange(len(vertices)) + 1
    following_vertex[start[1:] - 1] = first
    with np.errstate(all="ignore"):
        finite = np.logical_and.reduceat(np.isfinite(vertices).all(axis=1), first)
        extent = np.max(np.maximum.reduceat(vertices, first) - np.minimum.reduceat(vertices, first), axis=1)
        reach = np.maximum.reduceat(np.abs(vertices).max(axis=1), first)
        unit = (vertices - vertices[first][block]) / extent[block, None]
        edges = unit[following_vertex] - unit
        lengths = np.hypot(edges[:, 0], edges[:, 1])
        area = 0.5 * np.add.reduceat(
            unit[:, 0] * unit[following_vertex, 1] - unit[following_vertex, 0] * unit[:, 1], first
        )
        following = edges[following_vertex]
        turns = (edges[:, 0] * following[:, 1] - edges[:, 1] * following[:, 0]) * np.sign(area)[block]
        turning = np.add.reduceat(np.arctan2(turns, np.sum(edges * following, axis=1)), first)
    if straight is not None:  # turns[i] is the angle at vertex following_vertex[i]
        turns = np.where(straight[following_vertex] & (turns >= -1e-9), np.inf, turns)
    checks = [
        (~finite, lambda k: "a vertex coordinate is not a finite number"),
        (~np.isfinite(extent), lambda k: "its coordinates are too large to compute with"),
        (extent == 0.0, lambda k: "all its vertices are at one point"),
        (
            (extent < 1e-60) | (extent > 1e60),
            lambda k: (
                f"its size ({extent[k]:.3g} m across) is beyond what floating point holds in its "
                "second moment of area (size^4)"
            ),
        ),
        (
            ~(extent > 1e-9 * reach),
            lambda k: (
                f"it is too small ({extent[k]:.3g} m across) for its distance from the origin: "
                "its vertices cannot be told apart in floating point"
            ),
        ),
        (np.minimum.reduceat(lengths, first) <= 1e-9, lambda k: _short_edge(lengths, start, k)),
        (
            np.abs(area) <= 1e-12,
            lambda k: (
                _crossing_fault(unit[start[k] : start[k + 1]])
                or "it has no area (its vertices lie on one line)"
            ),
        ),
        (
            (np.minimum.reduceat(turns, first) <= 1e-12) | (turning > 3.0 * np.pi),
            lambda k: _convexity(unit[start[k] : start[k + 1]], turns[start[k] : start[k + 1]]),
        ),
    ]
    for failed, why in checks:
        for k in np.flatnonzero(failed):
            if k not in faults:
                faults[int(k)] = why(k)
    return faults


def shape_fault(vertices: np.ndarray) -> str | None:
    """Why one polygon cannot be a rigid convex block (`shape_faults`), or None."""
    return shape_faults(vertices, np.array([0, len(vertices)])).get(0)


def _short_edge(lengths: np.ndarray, start: np.ndarray, k: int) -> str:
    n, edge = start[k + 1] - start[k], int(np.argmin(lengths[start[k] : start[k + 1]]))
    return f"two vertices coincide (vertices {edge} and {(edge + 1) % n}: an edge of zero length)"


def _convexity(unit: np.ndarray, turns: np.ndarray) -> str:
    """Why a polygon (unit extent) whose edges turn the wrong way, not at all, or more than once around
    is no convex block: two vertices at one point, crossing edges, or else a reflex or straight angle."""
    vertex = (int(np.argmin(turns)) + 1) % len(unit)
    return _crossing_fault(unit) or (
        f"the polygon is not strictly convex (a reflex or straight angle at vertex {vertex})"
    )


def _crossing_fault(unit: np.ndarray) -> str | None:
    """Two vertices at one point, or two edges that cross, in a polygon (unit extent); None if neither."""
    n = len(unit)
    for i in range(n):
        for j in range(i + 1, n):
            if np.hypot(*(unit[i] - unit[j])) <= 1e-9:
                return f"two vertices coincide (vertices {i} and {j})"
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue  # neighbours: they share vertex 0
            if _segments_cross(unit[i], unit[(i + 1) % n], unit[j], unit[(j + 1) % n]):
                return f"its edges cross each other (edges {i} and {j})"
    return None


def _segments_cross(p: np.ndarray, q: np.ndarray, r: np.ndarray, s: np.ndarray) -> bool:
    """Whether segments pq and rs cross or touch (orientation tests)."""

    def side(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
        return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    sides = (side(p, q, r), side(p, q, s), side(r, s, p), side(r, s, q))
    if not any(sides):  # on one line: they cross where their extents along it overlap
        axis = q - p if np.any(q != p) else s - r
        a, b, c, d = (float(np.dot(point, axis)) for point in (p, q, r, s))
        return max(min(a, b), min(c, d)) <= min(max(a, b), max(c, d))
    return sides[0] * sides[1] <= 0.0 and sides[2] * sides[3] <= 0.0


def mass_properties(vertices: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area [m^2], centroid [m] and polar second moment of area about the centroid [m^4] of a
    counter-clockwise polygon (times density and thickness: mass and moment of inertia).

    Summed about the first vertex, not the origin: about the origin, the second moment of a block far
    from it is the difference of two large numbers (a 1 m square at x = 5e5 m, y = 5e6 m got 500.8 m^4
    instead of 1/6)."""
    origin = vertices[0]
    x, y = (vertices - origin).T
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    cx = ((x + xn) * cross).sum() / (6 * area)
    cy = ((y + yn) * cross).sum() / (6 * area)
    ixx = ((y * y + y * yn + yn * yn) * cross).sum() / 12
    iyy = ((x * x + x * xn + xn * xn) * cross).sum() / 12
    polar = ixx + iyy - area * (cx * cx + cy * cy)
    return float(area), np.array([cx, cy]) + origin, float(polar)


def rectangle(x: float, y: float, width: float, height: float) -> np.ndarray:
    """Axis-aligned rectangle from its lower-left corner [m], counter-clockwise."""
    return np.array([[x, y], [x + width, y], [x + width, y + height], [x, y + height]], dtype=float)


def rotated(vertices: np.ndarray, angle: float, about: np.ndarray) -> np.ndarray:
    """The polygon turned counter-clockwise by `angle` [rad] about the point `about` [m]."""
    c, s = np.cos(angle), np.sin(angle)
    return (vertices - about) @ np.array([[c, s], [-s, c]]) + about


ON_JOINT = 1e-6  # of a set's spacing: an edge's ends this close to one of its joints lie on it
MAX_BLOCKS = 1_000_000  # blocks a generator makes at most (the engine needs about 3.6 kB per block)


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


def _section_lines(joint_set: dict) -> tuple[np.ndarray, float, float]:
    """A set's joints in the section: the lines normal . x = offset + k spacing, as (unit normal,
    offset [m], spacing [m]) from its dip, dip direction, true spacing and offset (`jointed_slope`)."""
    trace = joint_set_trace(joint_set["dip_deg"], joint_set["dip_direction_to_face_deg"])
    return trace[:2], joint_set["offset_m"] / trace[2], joint_set["spacing_m"] / trace[2]


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
    lines = [_section_lines(s) for s in joint_sets]
    x_left, x_right, y_bottom, top = slope_bounds(
        height_m, face_angle_deg, crest_extent_m, toe_extent_m, depth_m
    )
    corners = np.array([[x_left, y_bottom], [x_right, y_bottom], [x_right, top], [x_left, top]])
    bound = 1.0
    for normal, _, spacing in lines:
        bound *= np.ptp(corners @ normal) / spacing + 2.0
    if not bound <= MAX_BLOCKS:
        raise ValueError(
            f"the joint sets would cut the slope into up to {bound:.3g} blocks, more than {MAX_BLOCKS:,} "
            "(wider spacings)"
        )
    through_toe = [normal for normal, offset, _ in lines if offset == 0]
    split = toe_split_direction(face_angle_deg, through_toe)
    pieces = slope_profile_parts(height_m, face_angle_deg, crest_extent_m, toe_extent_m, depth_m, split)
    for normal, offset, spacing in lines:
        pieces = [cell for piece in pieces for cell in _cut(piece, normal, offset, spacing)]
    areas = np.array([polygon_area(p) for p in pieces])
    smallest = min_block_fraction * np.median(areas)
    return [p for p, a in zip(pieces, areas, strict=True) if a >= smallest]


def joint_set_of_edges(shapes: list[np.ndarray], joint_sets: list[dict]) -> list[list[int]]:
    """For each edge of each of a jointed slope's blocks (edge k from vertex k to k + 1), the index of
    the first set on one of whose joints it lies, -1 for none (the model's boundary, a split at the toe
    along no set)."""
    lines = [_section_lines(s) for s in joint_sets]
    found = []
    for shape in shapes:
        ends = np.stack([shape, np.roll(shape, -1, axis=0)])  # (2, edges, 2): each edge's two ends
        sets = np.full(len(shape), -1)
        for k, (normal, offset, spacing) in reversed(list(enumerate(lines))):
            place = (ends @ normal - offset) / spacing  # in spacings from the first joint
            sets[np.all(np.abs(place - np.round(place[0])) < ON_JOINT, axis=0)] = k
        found.append(sets.tolist())
    return found


GENERATORS: dict[str, Callable[..., list[np.ndarray]]] = {"brick_wall": brick_wall}
