"""Joint water below a phreatic surface (`bbmc.dem.water`) against closed forms.

The integration is exact (trapezoid resultants on the pieces where the head is linear), so the closed
forms are met to rounding: relative tolerance RTOL = 1e-9 of the scale gamma_w * area (forces) or
gamma_w * area * size (moments). The comparison with adaptive quadrature allows 1e-8.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.spatial import ConvexHull, QhullError

from bbmc.dem import layout as L
from bbmc.dem.water import add_water_loads, edge_water_load, water_pressure
from bbmc.geometry.polygons import mass_properties, polygon_area, rectangle, rotated, shape_fault

GAMMA = 9810.0  # unit weight of water [N/m^3]
RTOL = 1e-9


def _close(value: float, expected: float, scale: float, rtol: float = RTOL) -> None:
    """|value - expected| <= rtol * scale."""
    error = abs(value - expected) / scale
    assert error <= rtol, (value, expected, error)


def _level(height: float) -> np.ndarray:
    return np.array([[-1.0, height], [1.0, height]])


def _loads(polygons: list[np.ndarray], surface: np.ndarray, unit_weight: float = GAMMA, moving=None):
    """(FX, FY, FM) of each block after `add_water_loads` on zeroed blocks built by hand."""
    blocks = np.zeros((len(polygons), L.BLOCK_COLUMNS))
    for b, vertices in enumerate(polygons):
        blocks[b, [L.X, L.Y]] = mass_properties(vertices)[1]
    counts = np.array([len(v) for v in polygons], dtype=np.int64)
    vertex_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    vertex_next = np.concatenate(
        [start + (np.arange(n) + 1) % n for start, n in zip(vertex_start[:-1], counts, strict=True)]
    ).astype(np.int64)
    world = np.vstack(polygons).astype(float)
    moving = np.ones(len(polygons), dtype=bool) if moving is None else np.asarray(moving, dtype=bool)
    dry = np.zeros(len(world), dtype=bool)
    add_water_loads(blocks, world, vertex_start, vertex_next, moving, surface, unit_weight, dry)
    return blocks[:, [L.FX, L.FY, L.FM]]


def _clip_below(vertices: np.ndarray, height: float) -> np.ndarray:
    """The part of a convex polygon below y = height (Sutherland-Hodgman against one half-plane)."""
    out = []
    for a, b in zip(vertices, np.roll(vertices, -1, axis=0), strict=True):
        ina, inb = a[1] <= height, b[1] <= height
        if ina:
            out.append(a)
        if ina != inb:
            out.append(a + (height - a[1]) / (b[1] - a[1]) * (b - a))
    return np.array(out)


def _check_archimedes(vertices: np.ndarray, height: float) -> None:
    """Net force (0, gamma_w A_sub) and moment about the centroid (x_sub - x_c) gamma_w A_sub."""
    area, centroid, _ = mass_properties(vertices)
    size = math.sqrt(area)
    fx, fy, fm = _loads([vertices], _level(height))[0]
    wet = _clip_below(vertices, height)
    wet_area = polygon_area(wet) if len(wet) >= 3 else 0.0
    wet_centroid = mass_properties(wet)[1] if wet_area > 0.0 else centroid
    scale = GAMMA * area
    _close(fx, 0.0, scale)
    _close(fy, GAMMA * wet_area, scale)
    _close(fm, (wet_centroid[0] - centroid[0]) * GAMMA * wet_area, scale * size)


# --- 1. buoyancy ------------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 0.3, 1.0, 2.5, -0.7])
def test_a_submerged_polygon_gets_its_buoyancy_and_no_moment(angle):
    hexagon = np.array([[0.0, 0.0], [2.0, -0.5], [3.0, 1.0], [2.5, 2.0], [0.5, 2.2], [-0.6, 1.1]])
    vertices = rotated(hexagon, angle, np.array([1.0, 1.0]))
    area = mass_properties(vertices)[0]
    fx, fy, fm = _loads([vertices], _level(10.0))[0]
    _close(fx, 0.0, GAMMA * area)
    _close(fy, GAMMA * area, GAMMA * area)
    _close(fm, 0.0, GAMMA * area * math.sqrt(area))


def test_several_blocks_each_get_their_own_buoyancy():
    squares = [rectangle(0.0, 0.0, 1.0, 1.0), rotated(rectangle(3.0, -2.0, 2.0, 0.5), 0.4, np.zeros(2))]
    loads = _loads(squares, _level(5.0))
    for vertices, (fx, fy, fm) in zip(squares, loads, strict=True):
        area = mass_properties(vertices)[0]
        _close(fx, 0.0, GAMMA * area)
        _close(fy, GAMMA * area, GAMMA * area)
        _close(fm, 0.0, GAMMA * area * math.sqrt(area))


_points = st.lists(
    st.tuples(st.floats(-5.0, 5.0), st.floats(-5.0, 5.0)), min_size=3, max_size=12, unique=True
)


def _hull(points) -> np.ndarray:
    points = np.array(points)
    try:
        hull = ConvexHull(points)
    except QhullError:  # degenerate (collinear) draws
        assume(False)
    vertices = points[hull.vertices]  # counter-clockwise in 2D
    assume(shape_fault(vertices) is None and mass_properties(vertices)[0] > 1e-2)
    return vertices


@settings(max_examples=200, deadline=None)
@given(points=_points, above=st.floats(0.0, 20.0))
def test_any_convex_polygon_below_a_level_surface_gets_archimedes_buoyancy(points, above):
    vertices = _hull(points)
    _check_archimedes(vertices, vertices[:, 1].max() + above)


@settings(max_examples=200, deadline=None)
@given(points=_points, level=st.floats(0.0, 1.0))
def test_a_convex_polygon_cut_by_a_level_surface_gets_the_buoyancy_of_its_wet_part(points, level):
    vertices = _hull(points)
    low, high = vertices[:, 1].min(), vertices[:, 1].max()
    _check_archimedes(vertices, low + level * (high - low))


# --- 2. a half-submerged rectangle ------------------------------------------------------------------


def test_a_half_submerged_rectangle():
    width, height = 3.0, 2.0
    vertices = rectangle(1.0, 0.0, width, height)
    fx, fy, fm = _loads([vertices], _level(0.5 * height))[0]
    scale = GAMMA * width * height
    _close(fx, 0.0, scale)
    _close(fy, GAMMA * width * height / 2, scale)
    _close(fm, 0.0, scale * width)  # the wet half's centroid is below the centroid


def test_a_half_submerged_tilted_rectangle_turns_about_its_centroid():
    vertices = rotated(rectangle(0.0, 0.0, 4.0, 1.0), 0.5, np.array([2.0, 0.5]))
    _check_archimedes(vertices, 0.5)  # the surface through the centroid: half of it wet
    wet = _clip_below(vertices, 0.5)
    assert mass_properties(wet)[0] == pytest.approx(2.0, rel=1e-12)


# --- 3. sloping and kinked surfaces -----------------------------------------------------------------


def test_a_surface_falling_to_the_toe_gives_a_triangular_uplift_a_third_from_the_deep_end():
    z, length = 1.5, 4.0
    surface = np.array([[0.0, z], [length, 0.0]])
    fx, fy, fm = edge_water_load(0.0, 0.0, length, 0.0, 0.0, 0.0, surface, GAMMA)
    uplift = GAMMA * z * length / 2
    _close(fx, 0.0, uplift)
    _close(fy, uplift, uplift)
    _close(fm / fy, length / 3, length)  # the resultant's x: moment about the deep end over force
    # the whole block (tall enough to stand out of the water): the uplift on its base and the
    # hydrostatic thrust gamma_w z^2 / 2 at z / 3 on its upslope face (a tension crack); the toe is dry
    vertices = rectangle(0.0, 0.0, length, 2.0)
    cx, cy = mass_properties(vertices)[1]
    thrust = GAMMA * z * z / 2
    fx, fy, fm = _loads([vertices], surface)[0]
    _close(fx, thrust, uplift)
    _close(fy, uplift, uplift)
    _close(fm, (length / 3 - cx) * uplift - (z / 3 - cy) * thrust, uplift * length)


def test_a_kink_of_the_polyline_over_an_edge_is_integrated_exactly():
    surface = np.array([[0.0, 1.0], [1.0, 2.0], [2.0, 1.0]])
    fx, fy, fm = edge_water_load(0.0, 0.0, 2.0, 0.0, 0.0, 0.0, surface, GAMMA)
    _close(fx, 0.0, GAMMA)
    _close(fy, GAMMA * 3.0, GAMMA)
    _close(fm, GAMMA * 3.0 * 1.0, GAMMA)  # symmetric load: resultant at x = 1
    # the same edge run backwards (a top edge) is pushed down
    fx, fy, fm = edge_water_load(2.0, 0.0, 0.0, 0.0, 0.0, 0.0, surface, GAMMA)
    _close(fy, -GAMMA * 3.0, GAMMA)
    _close(fm, -GAMMA * 3.0, GAMMA)
    # an asymmetric kink: h = 1 + x on [0, 1], 2 - 2 (x - 1) on [1, 2], dry beyond; the edge runs to x = 3
    surface = np.array([[0.0, 1.0], [1.0, 2.0], [3.0, -2.0]])
    fx, fy, fm = edge_water_load(0.0, 0.0, 3.0, 0.0, 0.0, 0.0, surface, GAMMA)
    force = 1.5 + 1.0  # integral of h: trapezoid on [0, 1], triangle on [1, 2]
    moment = (0.5 + 1.0 / 3.0) + 1.0 * (1.0 + 1.0 / 3.0)  # integral of x h
    _close(fy, GAMMA * force, GAMMA)
    _close(fm, GAMMA * moment, GAMMA)


def _quadrature(x0, y0, x1, y1, cx, cy, surface):
    """F and M about (cx, cy) of gamma_w max(S(x) - y, 0) on the edge, by adaptive quadrature in the
    edge's parameter s in [0, 1], with breakpoints at the polyline's kinks and where the head crosses 0
    (found by root bracketing)."""
    dx, dy = x1 - x0, y1 - y0

    def head(s):
        return float(np.interp(x0 + s * dx, surface[:, 0], surface[:, 1]) - (y0 + s * dy))

    def wet(s):
        return max(head(s), 0.0)

    def arm(s):
        return (x0 + s * dx - cx) * dx + (y0 + s * dy - cy) * dy

    kinks = sorted(
        {0.0, 1.0, *((xi - x0) / dx for xi in surface[:, 0] if dx != 0 and 0 < (xi - x0) / dx < 1)}
    )
    crossings = [
        brentq(head, a, b, xtol=1e-15) for a, b in itertools.pairwise(kinks) if head(a) * head(b) < 0
    ]
    points = sorted(set(kinks[1:-1]) | set(crossings)) or None
    options = {"points": points, "epsabs": 1e-12, "epsrel": 1e-12, "limit": 500}
    w = GAMMA * quad(wet, 0.0, 1.0, **options)[0]
    m = GAMMA * quad(lambda s: wet(s) * arm(s), 0.0, 1.0, **options)[0]
    return -w * dy, w * dx, m


_coordinate = st.floats(-3.0, 3.0)


@settings(max_examples=150, deadline=None)
@given(
    edge=st.tuples(_coordinate, _coordinate, _coordinate, _coordinate),
    xs=st.lists(st.floats(-4.0, 4.0), min_size=2, max_size=6, unique=True),
    ys=st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6),
)
def test_any_edge_under_any_polyline_matches_quadrature(edge, xs, ys):
    x0, y0, x1, y1 = edge
    assume(math.hypot(x1 - x0, y1 - y0) > 1e-2)
    xs = np.sort(xs)
    assume(np.min(np.diff(xs)) > 1e-3)
    surface = np.column_stack([xs, ys[: len(xs)]])
    fx, fy, fm = edge_water_load(x0, y0, x1, y1, 0.5, -0.5, surface, GAMMA)
    qx, qy, qm = _quadrature(x0, y0, x1, y1, 0.5, -0.5, surface)
    scale = GAMMA * 10.0 * math.hypot(x1 - x0, y1 - y0)  # heads up to 6 m, lever arms up to ~5 m
    _close(fx, qx, scale, 1e-8)
    _close(fy, qy, scale, 1e-8)
    _close(fm, qm, scale * 5.0, 1e-8)


# --- 4. no load -------------------------------------------------------------------------------------


def test_no_load_above_the_surface_on_a_still_block_or_without_water():
    above = rectangle(0.0, 1.0, 2.0, 1.0)
    under = rectangle(0.0, -3.0, 2.0, 1.0)
    surface = np.array([[0.0, 0.5], [2.0, 1.0]])
    assert np.all(_loads([above], surface)[0] == 0.0)
    loads = _loads([above, under], surface, moving=[True, False])
    assert np.all(loads == 0.0)
    assert np.all(_loads([under], surface, unit_weight=0.0) == 0.0)
    assert _loads([under], surface)[0, 1] > 0.0


def test_the_kernel_adds_to_the_forces_already_there():
    vertices = rectangle(0.0, -2.0, 1.0, 1.0)
    blocks = np.zeros((1, L.BLOCK_COLUMNS))
    blocks[0, [L.X, L.Y]] = mass_properties(vertices)[1]
    blocks[0, [L.FX, L.FY, L.FM]] = 1.0, -2.0, 3.0
    start, following = np.array([0, 4], dtype=np.int64), np.array([1, 2, 3, 0], dtype=np.int64)
    dry = np.zeros(4, dtype=bool)
    add_water_loads(blocks, vertices, start, following, np.ones(1, bool), _level(0.0), GAMMA, dry)
    _close(blocks[0, L.FX], 1.0, GAMMA)
    _close(blocks[0, L.FY], -2.0 + GAMMA, GAMMA)
    _close(blocks[0, L.FM], 3.0, GAMMA)


# --- 5. the pressure --------------------------------------------------------------------------------


def test_water_pressure_at_points_with_the_surface_level_beyond_its_ends():
    surface = np.array([[0.0, 2.0], [4.0, 0.0], [6.0, 1.0]])
    x = np.array([-10.0, 0.0, 2.0, 4.0, 5.0, 6.0, 50.0, 2.0])
    y = np.array([0.0, -1.0, 0.0, -3.0, 0.0, 1.0, -1.0, 5.0])
    expected = GAMMA * np.array([2.0, 3.0, 1.0, 3.0, 0.5, 0.0, 2.0, 0.0])
    np.testing.assert_allclose(water_pressure(x, y, surface, GAMMA), expected, rtol=1e-15, atol=0.0)
    assert water_pressure(1.0, 1.5, surface, GAMMA) == pytest.approx(0.0, abs=1e-12)
    assert float(water_pressure(1.0, 0.5, surface, 1.0)) == pytest.approx(1.0, rel=1e-15)
