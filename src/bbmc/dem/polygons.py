"""Block geometry: convex polygons, their mass properties, and the named block generators.

Plain numpy; vertices in metres, counter-clockwise. Mass properties are per unit density and per
metre of thickness; the model multiplies them by density (the engine works per metre of thickness).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def polygon_area(vertices: np.ndarray) -> float:
    """Signed area [m^2] (shoelace): > 0 for counter-clockwise vertices."""
    x, y = vertices[:, 0], vertices[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def counter_clockwise(vertices: np.ndarray) -> np.ndarray:
    """The vertices in counter-clockwise order (reversed if they were given clockwise)."""
    return vertices if polygon_area(vertices) > 0 else vertices[::-1].copy()


def convexity_fault(vertices: np.ndarray) -> str | None:
    """Why a counter-clockwise polygon is not a usable convex block, or None if it is."""
    if len(vertices) < 3:
        return "a block needs at least 3 vertices"
    edges = np.roll(vertices, -1, axis=0) - vertices
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    scale = float(np.max(lengths))
    if scale <= 0 or np.min(lengths) <= 1e-9 * scale:
        return "two vertices coincide (an edge of zero length)"
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    if np.any(turns <= 1e-12 * scale * scale):
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


GENERATORS: dict[str, Callable[..., list[np.ndarray]]] = {"brick_wall": brick_wall}
