"""A 3D run's end state as tables: one row per block and one per sub-contact, in the units of the 2D
engine's blocks.csv and contacts.csv (`bbmc.dem.monitors`): m, mm, MPa, deg, m/s, rad/s, the unit in
every column's name (docs/reference/outputs-3d.md lists them).

A block's rotation since the start is the world-frame rotation r = q * p^-1 (p its orientation at the
start, q at the end, unit quaternions scalar first, `bbmc.dem3d.quaternion`): R(r) = R(q) R(p)^T turns
the start's placement of the block into the end's about its centroid. Its angle is 2 atan2(|r_v|, |r_w|)
in [0, 180] deg and its axis r_v / |r_v|, signed so that the turn is right-handed about it (angle 0
and axis 0 0 0 for no turn, |r_v| <= NO_TURN).

A sub-contact's row: the pair's blocks, joint type and contact kind, where its share's closed part is
(its centroid), the contact normal n (from A towards B: a face–face contact's is A's reference face's
outward normal, a degenerate contact's the last separating axis), the closed area, sigma_n, the shear
stress vector tau and the shear displacement u_s of B relative to A, the slip path and whether it has
slipped (`bbmc.dem3d.contact_forces`). Every share of every pair that touches is a row, the open ones
too with area 0 and `closed` false (as the 2D table keeps its inactive sub-contacts with length 0); a
pair apart has no row.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.dem3d.contact_forces import (
    AREA,
    AXIS_I,
    AXIS_J,
    AXIS_KIND,
    BLOCK_A,
    BLOCK_B,
    CX,
    FIRST_SUB,
    JOINT_TYPE,
    KEY,
    KIND,
    NONE,
    PATH,
    POINT,
    SLIPPED,
    SN,
    TAUX,
    USX,
)
from bbmc.dem3d.contact_geometry import separating_axis
from bbmc.dem3d.layout import QW, VX, WX, X
from bbmc.dem3d.model import Model, place
from bbmc.dem3d.monitors import free_blocks
from bbmc.dem3d.quaternion import multiply

NO_TURN = 1e-12  # sin(angle / 2) below this is round-off of equal orientations: no turn, axis 0 0 0
CONTACT_KINDS = ("face-face", "edge-face", "vertex-face", "edge-edge")  # by `contact_geometry`'s codes


def _labels(values: Sequence[str] | None, count: int, key: str, item: str) -> np.ndarray:
    """Names for `count` items (their indices if none), as an object array; a wrong count refused."""
    if values is None:
        return np.arange(count, dtype=object)
    if len(values) != count:
        raise ValueError(f"{key}: one name per {item} ({count}), got {len(values)}")
    return np.array(list(values), dtype=object)


def rotations(start: np.ndarray, blocks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each block's rotation from `start` to `blocks` (module docstring): angle (n,) [rad] in [0, pi]
    and unit axis (n, 3) in the world (0 0 0 for no turn)."""
    angle, axis = np.zeros(len(blocks)), np.zeros((len(blocks), 3))
    for i in range(len(blocks)):
        p, q = start[i, QW : QW + 4], blocks[i, QW : QW + 4]
        r = np.array(multiply(q[0], q[1], q[2], q[3], p[0], -p[1], -p[2], -p[3]))
        if r[0] < 0.0:
            r = -r  # the same rotation, the short way round
        sine = float(np.linalg.norm(r[1:]))
        if sine > NO_TURN:
            angle[i] = 2.0 * math.atan2(sine, r[0])
            axis[i] = r[1:] / sine
    return angle, axis


def placed_vertices(model: Model, blocks: np.ndarray) -> np.ndarray:
    """Every block's vertices (n_vertices, 3) [m] in the world with the blocks placed as in `blocks`
    (a block array, `bbmc.dem3d.layout`; e.g. the start's copy)."""
    vertices, normals = np.empty_like(model.vertices), np.empty_like(model.face_normal)
    place(np.ascontiguousarray(blocks), model.body_vertices, model.vertex_start, model.body_normals,
          model.block_face_start, vertices, normals)  # fmt: skip
    return vertices


def held_blocks(model: Model) -> np.ndarray:
    """A bool per block: no degree of freedom free to move (`bbmc.dem3d.monitors.free_blocks`)."""
    return ~free_blocks(model)


def block_table(
    model: Model,
    start: np.ndarray,
    names: Sequence[str] | None = None,
    groups: Sequence[str] | None = None,
) -> pd.DataFrame:
    """Every block at the end (module docstring): its name (`names`, else its index), group (`groups`
    names the model's group indices, else the index), centroid at the start (`start`, a copy of
    model.blocks taken before the run) and now [m], displacement [mm], rotation since the start [deg]
    and its axis, velocity [m/s], angular velocity [rad/s] (world frame) and whether it is held."""
    b = model.blocks
    if start.shape != b.shape:
        raise ValueError(f"start: a copy of the model's blocks {b.shape} is needed, got {start.shape}")
    group_names = _labels(groups, int(model.pair_joint.shape[0]), "groups", "group")
    angle, axis = rotations(start, b)
    moved = (b[:, X : X + 3] - start[:, X : X + 3]) / units.mm
    return pd.DataFrame(
        {
            "block": _labels(names, len(b), "names", "block"),
            "group": group_names[model.group],
            "x0_m": start[:, X],
            "y0_m": start[:, X + 1],
            "z0_m": start[:, X + 2],
            "x_m": b[:, X],
            "y_m": b[:, X + 1],
            "z_m": b[:, X + 2],
            "ux_mm": moved[:, 0],
            "uy_mm": moved[:, 1],
            "uz_mm": moved[:, 2],
            "rotation_deg": angle / units.deg,
            "rotation_axis_x": axis[:, 0],
            "rotation_axis_y": axis[:, 1],
            "rotation_axis_z": axis[:, 2],
            "vx_m_s": b[:, VX],
            "vy_m_s": b[:, VX + 1],
            "vz_m_s": b[:, VX + 2],
            "wx_rad_s": b[:, WX],
            "wy_rad_s": b[:, WX + 1],
            "wz_rad_s": b[:, WX + 2],
            "held": held_blocks(model),
        }
    )


def contact_normals(model: Model) -> np.ndarray:
    """Each pair's contact normal (n_pairs, 3), from A towards B (module docstring); 0 0 0 apart."""
    normals = np.zeros((len(model.contacts), 3))
    arrays = (model.vertices, model.vertex_start, model.face_vertices, model.face_start,
              model.block_face_start, model.face_normal)  # fmt: skip
    for c, row in enumerate(model.contacts):
        if row[KEY] >= 0:
            normals[c] = model.face_normal[row[KEY]]
        elif row[KEY] == POINT:  # the last axis, returned as it stands (margin -inf)
            a, b = row[BLOCK_A], row[BLOCK_B]
            scale = min(model.size[a], model.size[b])
            axis = separating_axis(*arrays, a, b, scale, -math.inf, row[AXIS_KIND], row[AXIS_I], row[AXIS_J])
            normals[c] = axis[4:]
    return normals


def shares_in_use(model: Model) -> np.ndarray:
    """How many of each pair's sub-contact rows its contact uses (n_pairs,): a face–face contact's
    reference face's triangles, (vertices - 2) 4^refine; a degenerate contact's one; a pair apart's 0."""
    key = model.contacts[:, KEY]
    loops = np.diff(model.face_start)[np.maximum(key, 0)] if len(key) else np.zeros(0, dtype=np.int64)
    return np.where(key >= 0, (loops - 2) * 4**model.refine, np.where(key == NONE, 0, 1))


def contact_table(
    model: Model, law_names: Sequence[str] | None = None, names: Sequence[str] | None = None
) -> pd.DataFrame:
    """Every sub-contact of every touching pair at the end (module docstring): blocks (`names`, else
    their indices), joint type (`law_names` names the joint types, else the index), contact kind,
    share index, centroid [m], normal, closed area [m²], sigma_n (compression positive), |tau| and
    tau [MPa], |u_s| and u_s [mm], slip path [mm], slipped."""
    contacts, subs = model.contacts, model.subs
    laws = _labels(law_names, len(model.law_codes), "law_names", "joint type")
    blocks = _labels(names, len(model.blocks), "names", "block")
    used = shares_in_use(model)
    pair = np.repeat(np.arange(len(contacts)), used)
    share = np.arange(int(used.sum())) - np.repeat(np.cumsum(used) - used, used)
    rows = subs[contacts[pair, FIRST_SUB] + share] if len(pair) else np.zeros((0, subs.shape[1]))
    normal = contact_normals(model)[pair]
    tau = rows[:, TAUX : TAUX + 3] / units.MPa
    slide = rows[:, USX : USX + 3] / units.mm
    return pd.DataFrame(
        {
            "block_a": blocks[contacts[pair, BLOCK_A]],
            "block_b": blocks[contacts[pair, BLOCK_B]],
            "joint_type": laws[contacts[pair, JOINT_TYPE]],
            "contact_kind": np.array(CONTACT_KINDS, dtype=object)[contacts[pair, KIND]],
            "sub_contact": share,
            "x_m": rows[:, CX],
            "y_m": rows[:, CX + 1],
            "z_m": rows[:, CX + 2],
            "nx": normal[:, 0],
            "ny": normal[:, 1],
            "nz": normal[:, 2],
            "area_m2": rows[:, AREA],
            "closed": rows[:, AREA] > 0.0,
            "sigma_n_MPa": rows[:, SN] / units.MPa,
            "tau_MPa": np.linalg.norm(tau, axis=1),
            "tau_x_MPa": tau[:, 0],
            "tau_y_MPa": tau[:, 1],
            "tau_z_MPa": tau[:, 2],
            "shear_displacement_mm": np.linalg.norm(slide, axis=1),
            "us_x_mm": slide[:, 0],
            "us_y_mm": slide[:, 1],
            "us_z_mm": slide[:, 2],
            "slip_path_mm": rows[:, PATH] / units.mm,
            "slipped": rows[:, SLIPPED] > 0.0,
        }
    )
