"""Joint water below a phreatic surface, applied as pressure loads on the block edges.

Convention (UDEC's): the stresses the engine carries at its contacts are effective stresses. Water
fills the joints below the phreatic surface and its pressure p acts on every block edge below that
surface, on both faces of each joint (each block gets its own edge load, equal and opposite to its
neighbour's across a closed joint), so a joint's total normal stress is sigma_n' + p, sigma_n' the
contact's effective stress. A block wholly under water therefore feels its buoyancy (Archimedes), and
a block resting on a wet joint feels the uplift that lowers the joint's effective stress.

The phreatic surface is a polyline S(x) through points (x_i, y_i), x strictly increasing, extended
level beyond its first and last points (as `numpy.interp`). At a point (x, y):

    h = S(x) - y        pressure head [m]
    p = gamma_w max(h, 0)        water pressure [Pa], gamma_w the water's unit weight [N/m^3]

The pressure pushes inward on an edge: the force on an element ds is dF = -p n_out ds, n_out the
outward normal (t_y, -t_x) of a counter-clockwise edge with unit tangent t. The resultant and its
moment about the block's centroid are integrated exactly: along an edge h is piecewise linear in the
arc length, with kinks where the edge crosses the x of a polyline point (a vertical edge has none)
and where h changes sign (p = gamma_w max(h, 0)). Each edge is split at those points; on a piece of
length L with heads h_a, h_b >= 0 at its ends the load is a trapezoid whose resultant is

    F = gamma_w L (h_a + h_b) / 2   at fraction (h_a + 2 h_b) / (3 (h_a + h_b)) of the piece from a,

and a piece where h changes sign is first cut where h = 0 (its wet part is a triangle, resultant at a
third of its length from the deep end). Units are SI: m, Pa, N/m^3; forces per metre of thickness
[N/m] and moments [N m/m] (plane strain).

Source: UDEC's joint water pressure below a phreatic surface (Itasca, UDEC manual: effective stresses
at the contacts, hydrostatic pressure on the block edges), as in Hoek & Bray's plane and toppling
failure analyses (Rock Slope Engineering; Wyllie & Mah 2004): with the phreatic surface falling to the
toe the pressure on a sliding plane is triangular, U = gamma_w z_w A / 2, and hydrostatic in a tension
crack, V = gamma_w z_w^2 / 2.
"""

import numba
import numpy as np
from numpy.typing import ArrayLike

from bbmc.dem.layout import FM, FX, FY, X, Y


def water_pressure(x: ArrayLike, y: ArrayLike, surface: np.ndarray, unit_weight: float) -> np.ndarray:
    """Water pressure p = gamma_w max(S(x) - y, 0) [Pa] at points (x, y) [m] (broadcast together).

    `surface` is the phreatic polyline, float (m, 2) with x strictly increasing, level beyond its ends;
    `unit_weight` is gamma_w [N/m^3].
    """
    surface = np.asarray(surface, dtype=float)
    head = np.interp(x, surface[:, 0], surface[:, 1]) - np.asarray(y, dtype=float)
    return unit_weight * np.maximum(head, 0.0)


@numba.njit(cache=True)
def _first_above(surface, x):
    """Index of the first polyline point with x_i > x (m if none): binary search."""
    lo, hi = 0, surface.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if surface[mid, 0] > x:
            hi = mid
        else:
            lo = mid + 1
    return lo


@numba.njit(cache=True)
def surface_height(surface: np.ndarray, x: float) -> float:
    """S(x) [m]: the phreatic polyline at x, level beyond its first and last points."""
    m = surface.shape[0]
    if x <= surface[0, 0]:
        return surface[0, 1]
    if x >= surface[m - 1, 0]:
        return surface[m - 1, 1]
    j = _first_above(surface, x)
    x0, y0, x1, y1 = surface[j - 1, 0], surface[j - 1, 1], surface[j, 0], surface[j, 1]
    return y0 + (x - x0) / (x1 - x0) * (y1 - y0)


@numba.njit(cache=True)
def _piece_load(x0, y0, dx, dy, cx, cy, sa, ha, sb, hb, unit_weight):
    """Force [N/m] and moment about (cx, cy) [N m/m] on the piece [sa, sb] of the edge (x0, y0) +
    s (dx, dy), s in [0, 1], along which the head runs linearly from ha to hb [m].

    The wet part is cut where h = 0; its trapezoidal load gamma_w L (h_a + h_b) / 2 acts along the inward
    normal at fraction (h_a + 2 h_b) / (3 (h_a + h_b)) of the part from a.
    """
    if ha <= 0.0 and hb <= 0.0:
        return 0.0, 0.0, 0.0
    if ha < 0.0:
        sa = sa + (sb - sa) * ha / (ha - hb)
        ha = 0.0
    elif hb < 0.0:
        sb = sa + (sb - sa) * ha / (ha - hb)
        hb = 0.0
    w = 0.5 * unit_weight * (sb - sa) * (ha + hb)  # mean pressure times the piece's share of the edge [Pa]
    s = sa + (sb - sa) * (ha + 2.0 * hb) / (3.0 * (ha + hb))
    fx, fy = -w * dy, w * dx  # -p n_out, n_out = (dy, -dx) / length
    return fx, fy, (x0 + s * dx - cx) * fy - (y0 + s * dy - cy) * fx


@numba.njit(cache=True)
def edge_water_load(
    x0: float, y0: float, x1: float, y1: float, cx: float, cy: float, surface: np.ndarray, unit_weight: float
) -> tuple[float, float, float]:
    """Resultant (fx, fy) [N/m] and its moment about (cx, cy) [N m/m] of the water pressure on the edge
    from (x0, y0) to (x1, y1) [m], the block lying on its left (counter-clockwise edge).

    F = -integral of p n_out ds, exact: the edge is split where it crosses the x of a polyline point
    and each piece's trapezoidal load (cut where h = 0) is replaced by its resultant.
    """
    dx, dy = x1 - x0, y1 - y0
    fx = fy = moment = 0.0
    sa, ha = 0.0, surface_height(surface, x0) - y0
    if dx != 0.0:
        # interior polyline points, in the order the edge meets them
        lo = _first_above(surface, min(x0, x1))
        hi = _first_above(surface, max(x0, x1))
        if hi > lo and surface[hi - 1, 0] == max(x0, x1):
            hi -= 1
        for k in range(hi - lo):
            j = lo + k if dx > 0.0 else hi - 1 - k
            sb = (surface[j, 0] - x0) / dx
            hb = surface[j, 1] - (y0 + sb * dy)
            gx, gy, gm = _piece_load(x0, y0, dx, dy, cx, cy, sa, ha, sb, hb, unit_weight)
            fx, fy, moment = fx + gx, fy + gy, moment + gm
            sa, ha = sb, hb
    hb = surface_height(surface, x1) - y1
    gx, gy, gm = _piece_load(x0, y0, dx, dy, cx, cy, sa, ha, 1.0, hb, unit_weight)
    return fx + gx, fy + gy, moment + gm


@numba.njit(cache=True)
def add_water_loads(
    blocks: np.ndarray,
    world: np.ndarray,
    vertex_start: np.ndarray,
    vertex_next: np.ndarray,
    moving: np.ndarray,
    surface: np.ndarray,
    unit_weight: float,
    dry: np.ndarray,
) -> None:
    """Add the water pressure's resultant force [N/m] and moment about the centroid [N m/m] on every
    edge of each `moving` block to blocks[b, FX], blocks[b, FY], blocks[b, FM].

    `world`: vertex coordinates [m], float (n_vertices, 2), block b's counter-clockwise vertices being
    rows vertex_start[b] .. vertex_start[b + 1] - 1; edge e runs from world[e] to world[vertex_next[e]].
    `surface`: phreatic polyline [m], float (m, 2), x strictly increasing; `unit_weight`: gamma_w
    [N/m^3]. Edges wholly above the polyline's highest point are skipped, and so are `dry` ones (per
    edge: intact rock, which carries no joint water pressure until it breaks). No allocation.
    """
    if unit_weight == 0.0:
        return
    top = surface[0, 1]
    for i in range(1, surface.shape[0]):
        top = max(top, surface[i, 1])
    for b in range(blocks.shape[0]):
        if not moving[b]:
            continue
        cx, cy = blocks[b, X], blocks[b, Y]
        for e in range(vertex_start[b], vertex_start[b + 1]):
            n = vertex_next[e]
            if dry[e] or (world[e, 1] >= top and world[n, 1] >= top):
                continue
            fx, fy, moment = edge_water_load(
                world[e, 0], world[e, 1], world[n, 0], world[n, 1], cx, cy, surface, unit_weight
            )
            blocks[b, FX] += fx
            blocks[b, FY] += fy
            blocks[b, FM] += moment
