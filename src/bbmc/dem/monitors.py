"""What a run reports: monitored histories, the final block and sub-contact tables, and the system
energies, read off the engine's arrays (plain numpy, called only at record steps).

Units at this boundary: displacements mm, velocities m/s, rotations and angles deg, stresses MPa,
cohesion kPa, stiffness MPa/mm, energies J (for the scene's thickness).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.model import Model, MonitorSpec

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
    "kinetic_energy": ("J", 1.0),
    "strain_energy": ("J", 1.0),
    "potential_energy": ("J", 1.0),
    "unbalanced_force_ratio": ("1", 1.0),
}
SUB_COLUMN = {
    "sigma_n": L.SN,
    "tau": L.TAU,
    "kn": L.KN,
    "ks": L.KS,
    "cohesion": L.COH,
    "us": L.US,
    "un": L.UN,
}


def column_name(spec: MonitorSpec) -> str:
    return f"{spec.name}_{UNITS[spec.quantity][0]}"


def point_displacement(blocks: np.ndarray, block: int, point: np.ndarray) -> np.ndarray:
    """Displacement [m] of the material point of `block` that started at `point` [m]."""
    row = blocks[block]
    arm = point - row[[L.X0, L.Y0]]
    c, s = np.cos(row[L.TH]), np.sin(row[L.TH])
    now = row[[L.X, L.Y]] + np.array([c * arm[0] - s * arm[1], s * arm[0] + c * arm[1]])
    return now - point


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


def strain_energy(subs: np.ndarray) -> float:
    """Elastic energy stored in the joints at the last force evaluation, sum L (sigma_n^2 / 2 K_n +
    tau^2 / 2 K_s) [J per m]; exact for constant stiffness (a stress-dependent law stores a different
    amount)."""
    s = subs[subs[:, L.LENGTH] > 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        normal = np.where(s[:, L.KN] > 0, s[:, L.SN] ** 2 / (2 * s[:, L.KN]), 0.0)
        shear = np.where(s[:, L.KS] > 0, s[:, L.TAU] ** 2 / (2 * s[:, L.KS]), 0.0)
    return float(np.sum(s[:, L.LENGTH] * (normal + shear)))


def _joint_value(
    spec: MonitorSpec, model: Model, contacts: np.ndarray, subs: np.ndarray, n_sub: int
) -> float:
    active = subs[:, L.LENGTH] > 0
    if spec.groups is not None:
        ga = np.repeat(model.block_group[contacts[:, L.BLOCK_A]], n_sub)
        gb = np.repeat(model.block_group[contacts[:, L.BLOCK_B]], n_sub)
        g1, g2 = spec.groups
        chosen = active & (((ga == g1) & (gb == g2)) | ((ga == g2) & (gb == g1)))
    else:
        distance = np.hypot(subs[:, L.CX] - spec.near[0], subs[:, L.CY] - spec.near[1])
        distance[~active] = np.inf
        chosen = np.zeros(len(subs), dtype=bool)
        if active.any():
            chosen[int(np.argmin(distance))] = True
    if not chosen.any():
        return np.nan
    weights = subs[chosen, L.LENGTH]
    if spec.quantity == "friction":
        values = np.degrees(np.arctan(subs[chosen, L.TANPHI]))
    else:
        values = subs[chosen, SUB_COLUMN[spec.quantity]]
    return float(np.average(values, weights=weights))


def monitor_value(spec: MonitorSpec, model: Model, state, reference_force: float) -> float:
    """The value of one monitor now, in the units of `UNITS`."""
    b, q, scale = state.blocks, spec.quantity, UNITS[spec.quantity][1]
    thickness = model.scene.thickness_m
    if q in ("ux", "uy"):
        if spec.point is not None:
            u = point_displacement(b, spec.block, spec.point)
        else:
            u = b[spec.block, [L.X, L.Y]] - b[spec.block, [L.X0, L.Y0]]
        value = u[0] if q == "ux" else u[1]
    elif q in ("vx", "vy"):
        value = b[spec.block, L.VX if q == "vx" else L.VY]
    elif q == "rotation":
        value = b[spec.block, L.TH]
    elif q == "kinetic_energy":
        value = thickness * kinetic_energy(b)
    elif q == "potential_energy":
        value = thickness * potential_energy(b, model.gravity, state.clock[L.DT] if state.step else 0.0)
    elif q == "strain_energy":
        value = thickness * strain_energy(state.subs)
    elif q == "unbalanced_force_ratio":
        value = unbalanced_force_ratio(state, reference_force)
    else:
        value = _joint_value(spec, model, state.contacts, state.subs, state.n_sub)
    return value * scale


def reference_force(model: Model) -> float:
    """The force scale of the unbalanced-force ratio [N per m]: the largest weight of a block free to
    translate, block force or edge load."""
    free = np.any(model.dof[:, :2] == L.FREE, axis=1)
    weights = model.blocks[free, L.MASS] * float(np.hypot(*model.gravity))
    forces = np.hypot(model.block_loads[:, 0], model.block_loads[:, 1])
    edges = np.abs(model.edge_loads[:, :2]).sum(axis=1) * _edge_lengths(model)
    largest = max([0.0, *weights, *forces, *edges])
    return largest if largest > 0 else 1.0


def _edge_lengths(model: Model) -> np.ndarray:
    start = model.local[model.load_edge]
    end = model.local[model.vertex_next[model.load_edge]]
    return np.hypot(*(end - start).T)


def unbalanced_force_ratio(state, reference: float) -> float:
    """Largest out-of-balance force on a block's free translation over the reference force [1]."""
    free = state.dof[:, :2] == L.FREE
    force = np.where(free, state.blocks[:, [L.FX, L.FY]], 0.0)
    return float(np.max(np.hypot(force[:, 0], force[:, 1]), initial=0.0)) / reference


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
            "sigma_n_MPa": subs[:, L.SN] / units.MPa,
            "tau_MPa": subs[:, L.TAU] / units.MPa,
            "kn_MPa_per_mm": subs[:, L.KN] / units.MPa_per_mm,
            "ks_MPa_per_mm": subs[:, L.KS] / units.MPa_per_mm,
            "cohesion_kPa": subs[:, L.COH] / units.kPa,
            "friction_deg": np.degrees(np.arctan(subs[:, L.TANPHI])),
            "tensile_strength_MPa": subs[:, L.TEN] / units.MPa,
            "us_mm": subs[:, L.US] / units.mm,
            "un_mm": subs[:, L.UN] / units.mm,
            "slipped": subs[:, L.SLIPPED].astype(bool),
        }
    )
