"""What a run reports: monitored histories, the final block and sub-contact tables, and the system
energies, read off the engine's arrays (plain numpy, called only at record steps).

Units at this boundary: displacements mm, velocities m/s, rotations and angles deg, stresses MPa,
cohesion kPa, stiffness MPa/mm, energies J (for the scene's thickness).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import pandas as pd

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.contact_geometry import contact_frame
from bbmc.dem.model import Model, MonitorSpec
from bbmc.dem.support_report import largest_loads
from bbmc.geometry.polygons import carried_points
from bbmc.scene.schema import JOINT_QUANTITIES

UNITS = {
    "ux": ("mm", 1 / units.mm),
    "uy": ("mm", 1 / units.mm),
    "vx": ("m_s", 1.0),
    "vy": ("m_s", 1.0),
    "rotation": ("deg", 1 / units.deg),
    "sigma_n": ("MPa", 1 / units.MPa),
    "tau": ("MPa", 1 / units.MPa),
    "kn": ("MPa_per_mm", 1 / units.MPa_per_mm),
    "ks": ("MPa_per_mm", 1 / units.MPa_per_mm),
    "cohesion": ("kPa", 1 / units.kPa),
    "friction": ("deg", 1.0),
    "us": ("mm", 1 / units.mm),
    "un": ("mm", 1 / units.mm),
    "dilation": ("mm", 1 / units.mm),
    "shear_path": ("mm", 1 / units.mm),
    "kinetic_energy": ("J", 1.0),
    "strain_energy": ("J", 1.0),
    "potential_energy": ("J", 1.0),
    "unbalanced_force_ratio": ("1", 1.0),
    "bolt_force": ("kN", 1.0),
}
SUB_COLUMN = {
    "sigma_n": L.SN,
    "tau": L.TAU,
    "kn": L.KN,
    "ks": L.KS,
    "cohesion": L.COH,
    "us": L.US,
    "un": L.UN,
    "dilation": L.DILATION,
    "shear_path": L.PATH,
}
FRICTION = -1  # joint_values' code for the friction angle, read from tan(phi)


def column_name(spec: MonitorSpec) -> str:
    return f"{spec.name}_{UNITS[spec.quantity][0]}"


def point_displacement(blocks: np.ndarray, block: int, point: np.ndarray) -> np.ndarray:
    """Displacement [m] of the material point of `block` that started at `point` [m]."""
    row = blocks[block : block + 1]
    now = carried_points(point[None], row[:, [L.X0, L.Y0]], row[:, [L.X, L.Y]], row[:, L.TH])
    return now[0] - point


def kinetic_energy(blocks: np.ndarray) -> float:
    """Sum of 1/2 (m v^2 + I w^2) with the true masses [J per m], the velocities averaged over the two
    half steps around the last force evaluation (the leapfrog's full-step velocity)."""
    b = blocks
    vx, vy, w = (
        (b[:, now] + b[:, before]) / 2 for now, before in ((L.VX, L.PVX), (L.VY, L.PVY), (L.W, L.PW))
    )
    return 0.5 * float(np.sum(b[:, L.MASS] * (vx**2 + vy**2) + b[:, L.INERTIA] * w**2))


def potential_energy(blocks: np.ndarray, gravity: np.ndarray, dt: float) -> float:
    """Gravitational energy relative to the initial positions, -sum m g.(x - x0) [J per m], at the
    positions of the last force evaluation (one step, dt, before the current ones)."""
    then = blocks[:, [L.X, L.Y]] - dt * blocks[:, [L.VX, L.VY]]
    lift = then - blocks[:, [L.X0, L.Y0]]
    return -float(np.sum(blocks[:, L.MASS] * (lift @ gravity)))


@numba.njit(cache=True)
def strain_energy(blocks, world, vertex_next, contacts, subs, n_sub):
    """Elastic energy stored in the joints [J per m]: over each share's closed part (length L_c) of
    linear normal stress, mean sigma_n and gradient g = K_n du/dxi, the integral of sigma^2 / 2 K_n is
    L_c (sigma_n^2 + g^2 L_c^2 / 12) / 2 K_n; the shear's L_c tau^2 / 2 K_s. The stresses are those of
    the last force evaluation, the gradient from the current positions (one step later). Exact for
    constant stiffness (a stress-dependent law stores a different amount)."""
    size = blocks[:, L.SIZE]
    total = 0.0
    for c in range(contacts.shape[0]):
        a, b = contacts[c, L.BLOCK_A], contacts[c, L.BLOCK_B]
        active, _, _, lo, hi, a_lo, a_hi, b_lo, b_hi = contact_frame(
            world, vertex_next, contacts[c, L.EDGE_A], contacts[c, L.EDGE_B], size, a, b
        )
        if not active:
            continue
        slope = ((a_hi - b_hi) - (a_lo - b_lo)) / (hi - lo)
        for s in range(c * n_sub, (c + 1) * n_sub):
            closed = subs[s, L.LENGTH] * subs[s, L.CLOSED]
            if closed <= 0.0:
                continue
            kn, ks = subs[s, L.KN], subs[s, L.KS]
            gradient = kn * slope
            total += closed * (subs[s, L.SN] ** 2 + (gradient * closed) ** 2 / 12.0) / (2.0 * kn)
            if ks > 0.0:
                total += closed * subs[s, L.TAU] ** 2 / (2.0 * ks)
    return total


@numba.njit(cache=True)
def _sub_value(subs, s, column):
    """Column `column` of sub-contact s; its stresses as their share's mean (open parts carry 0)."""
    if column == FRICTION:
        return math.degrees(math.atan(subs[s, L.TANPHI]))
    if column == L.SN or column == L.TAU:
        return subs[s, column] * subs[s, L.CLOSED]
    return subs[s, column]


@numba.njit(cache=True)
def joint_values(contacts, subs, n_sub, block_group, column, groups, near, out):
    """Every joint monitor in one pass over the sub-contacts: monitor m reads sub-contact column
    `column[m]` (FRICTION: the friction angle [deg]) as the length-weighted mean over the active
    sub-contacts between groups[m] (when groups[m, 0] >= 0), or at the active sub-contact nearest
    near[m] (the first of equals); nan where none is active. SI units, as the engine's arrays."""
    for m in range(column.size):
        if groups[m, 0] >= 0:
            total, weight = 0.0, 0.0
            for c in range(contacts.shape[0]):
                ga, gb = block_group[contacts[c, L.BLOCK_A]], block_group[contacts[c, L.BLOCK_B]]
                if not (
                    (ga == groups[m, 0] and gb == groups[m, 1]) or (ga == groups[m, 1] and gb == groups[m, 0])
                ):
                    continue
                for s in range(c * n_sub, (c + 1) * n_sub):
                    if subs[s, L.LENGTH] > 0.0:
                        total += subs[s, L.LENGTH] * _sub_value(subs, s, column[m])
                        weight += subs[s, L.LENGTH]
            out[m] = total / weight if weight > 0.0 else math.nan
        else:
            nearest, closest = -1, math.inf
            for s in range(subs.shape[0]):
                if subs[s, L.LENGTH] > 0.0:
                    distance = math.hypot(subs[s, L.CX] - near[m, 0], subs[s, L.CY] - near[m, 1])
                    if distance < closest:
                        nearest, closest = s, distance
            out[m] = _sub_value(subs, nearest, column[m]) if nearest >= 0 else math.nan


@dataclass(frozen=True)
class JointMonitors:
    """The joint monitors of a model as the arrays `joint_values` reads, and their places in the list
    of monitors."""

    index: list[int]
    column: np.ndarray
    groups: np.ndarray
    near: np.ndarray

    @classmethod
    def of(cls, model: Model) -> JointMonitors:
        chosen = [i for i, spec in enumerate(model.monitors) if spec.quantity in JOINT_QUANTITIES]
        specs = [model.monitors[i] for i in chosen]
        return cls(
            index=chosen,
            column=np.array([SUB_COLUMN.get(s.quantity, FRICTION) for s in specs], dtype=np.int64),
            groups=np.array([s.groups or (-1, -1) for s in specs], dtype=np.int64).reshape(-1, 2),
            near=np.array([s.near if s.near is not None else (0.0, 0.0) for s in specs]).reshape(-1, 2),
        )


def monitor_values(model: Model, state, reference_force: float, joints: JointMonitors) -> list[float]:
    """Every monitor's value now, in the units of `UNITS`, in the order of the model's monitors."""
    values = [0.0] * len(model.monitors)
    if joints.index:
        out = np.empty(len(joints.index))
        joint_values(
            state.contacts,
            state.subs,
            state.n_sub,
            model.block_group,
            joints.column,
            joints.groups,
            joints.near,
            out,
        )
        for i, value in zip(joints.index, out, strict=True):
            values[i] = float(value)
    for i, spec in enumerate(model.monitors):
        value = (
            values[i]
            if spec.quantity in JOINT_QUANTITIES
            else _block_or_system_value(spec, model, state, reference_force)
        )
        values[i] = value * UNITS[spec.quantity][1]
    return values


def _block_or_system_value(spec: MonitorSpec, model: Model, state, reference_force: float) -> float:
    b, q = state.blocks, spec.quantity
    thickness = model.scene.thickness_m
    if q in ("ux", "uy"):
        if spec.point is not None:
            u = point_displacement(b, spec.block, spec.point)
        else:
            u = b[spec.block, [L.X, L.Y]] - b[spec.block, [L.X0, L.Y0]]
        return u[0] if q == "ux" else u[1]
    if q in ("vx", "vy"):
        return b[spec.block, L.VX if q == "vx" else L.VY]
    if q == "rotation":
        return b[spec.block, L.TH]
    if q == "bolt_force":
        return largest_loads(model.support, state.support)[spec.support]
    if q == "kinetic_energy":
        return thickness * kinetic_energy(b)
    if q == "potential_energy":
        return thickness * potential_energy(b, model.gravity, state.clock[L.DT] if state.step else 0.0)
    if q == "strain_energy":
        return thickness * strain_energy(
            b, state.world, model.vertex_next, state.contacts, state.subs, state.n_sub
        )
    return unbalanced_force_ratio(state, reference_force)


def reference_force(model: Model) -> float:
    """The force scale of the unbalanced-force ratio [N per m]: the largest weight of a block free to
    move, block force or edge load."""
    free = np.any(model.dof == L.FREE, axis=1)
    weights = model.blocks[free, L.MASS] * float(np.hypot(*model.gravity))
    forces = np.hypot(model.block_loads[:, 0], model.block_loads[:, 1])
    edges = np.abs(model.edge_loads[:, :2]).sum(axis=1) * _edge_lengths(model)
    largest = max([0.0, *weights, *forces, *edges])
    return largest if largest > 0 else 1.0


def _edge_lengths(model: Model) -> np.ndarray:
    start = model.local[model.load_edge]
    end = model.local[model.vertex_next[model.load_edge]]
    return np.hypot(*(end - start).T)


def unbalanced_force_ratio(state, reference: float, judged: np.ndarray | None = None) -> float:
    """The largest out-of-balance force or moment on a block's free degrees of freedom over the
    reference force [1]: a moment M counts as the force M / R that makes it at the block's radius R
    (its farthest vertex from the centroid), so the reference moment of a block is the reference force
    times its radius. A block free only to rotate is judged by its moment alone. `judged`: only these
    blocks (a bool per block; default all)."""
    b = state.blocks
    free = state.dof == L.FREE
    if judged is not None:
        free = free & judged[:, None]
    force = np.where(free[:, :2], b[:, [L.FX, L.FY]], 0.0)
    moment = np.where(free[:, 2], np.abs(b[:, L.FM]) / b[:, L.RADIUS], 0.0)
    largest = np.maximum(np.hypot(force[:, 0], force[:, 1]), moment)
    return float(np.max(largest, initial=0.0)) / reference


def block_table(model: Model, blocks: np.ndarray) -> pd.DataFrame:
    """Final position, displacement, rotation and velocity of every block."""
    return pd.DataFrame(
        {
            "block": model.block_names,
            "group": [model.group_names[g] for g in model.block_group],
            "x0_m": blocks[:, L.X0],
            "y0_m": blocks[:, L.Y0],
            "x_m": blocks[:, L.X],
            "y_m": blocks[:, L.Y],
            "ux_mm": (blocks[:, L.X] - blocks[:, L.X0]) / units.mm,
            "uy_mm": (blocks[:, L.Y] - blocks[:, L.Y0]) / units.mm,
            "rotation_deg": blocks[:, L.TH] / units.deg,
            "vx_m_s": blocks[:, L.VX],
            "vy_m_s": blocks[:, L.VY],
        }
    )


def contact_table(model: Model, contacts: np.ndarray, subs: np.ndarray, n_sub: int) -> pd.DataFrame:
    """Every sub-contact's final state (inactive ones have length 0)."""
    names = np.array(model.block_names, dtype=object)
    return pd.DataFrame(
        {
            "block_a": np.repeat(names[contacts[:, L.BLOCK_A]], n_sub),
            "block_b": np.repeat(names[contacts[:, L.BLOCK_B]], n_sub),
            "joint_law": np.repeat(np.array(model.law_names, dtype=object)[contacts[:, L.JOINT_TYPE]], n_sub),
            "sub_contact": np.tile(np.arange(n_sub), len(contacts)),
            "x_m": subs[:, L.CX],
            "y_m": subs[:, L.CY],
            "length_m": subs[:, L.LENGTH],
            "closed_fraction": subs[:, L.CLOSED],
            "sigma_n_MPa": subs[:, L.SN] / units.MPa,
            "tau_MPa": subs[:, L.TAU] / units.MPa,
            "kn_MPa_per_mm": subs[:, L.KN] / units.MPa_per_mm,
            "ks_MPa_per_mm": subs[:, L.KS] / units.MPa_per_mm,
            "cohesion_kPa": subs[:, L.COH] / units.kPa,
            "friction_deg": np.degrees(np.arctan(subs[:, L.TANPHI])),
            "tensile_strength_MPa": subs[:, L.TEN] / units.MPa,
            "us_mm": subs[:, L.US] / units.mm,
            "un_mm": subs[:, L.UN] / units.mm,
            "shear_path_mm": subs[:, L.PATH] / units.mm,
            "dilation_mm": subs[:, L.DILATION] / units.mm,
            "slipped": subs[:, L.SLIPPED].astype(bool),
        }
    )
