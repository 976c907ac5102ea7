"""A 3D run as a time series that ParaView opens: one VTU file of the blocks and one of the sub-contacts
per record, and a PVD collection of each with the records' times; the 3D twin of `bbmc.outputs.vtk`,
written by its helpers (`vtu_bytes`, `collection`: meshio, with VTK string arrays for the names).

Every array's name carries its unit, as the CSV columns do (`_m`, `_m_s`, `_deg`, `_MPa`, `_mm`, `_m2`);
ids and flags have none. The columns' meanings are those of `bbmc.dem3d.tables`.

* blocks_<k>.vtu: every face of every block a polygon at its place then (a block's own vertices, so
  each block is a closed surface of its own). Point data (every vertex; what Warp By Vector and Glyph
  take): displacement_m (from the start, rotation included) and velocity_m_s (v + omega x r), 3-vectors.
  Cell data (every face, its block's values): block_id, group_id, held (0 or 1), displacement_m and
  velocity_m_s of the centroid, rotation_deg; text: block and group (the names).
* contacts_<k>.vtu: every closed sub-contact (area > 0) a vertex at its closed part's centroid, with
  point data sigma_n_MPa, tau_MPa (|tau|), tau_vector_MPa, normal (n, from block A towards B),
  shear_displacement_mm (|u_s|), slip_path_mm, area_m2, slipped (0 or 1), law_id; text: law.
* Both carry field data group_names and law_names: every name, in the order of the ids.
* blocks.pvd, contacts.pvd: the collections.

Read a file back with `bbmc.outputs.vtk.read_vtu` (meshio refuses the text arrays) or with ParaView.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import meshio
import numpy as np

from bbmc.dem3d.layout import VX, WX, X
from bbmc.dem3d.model import Model
from bbmc.dem3d.tables import contact_table, held_blocks, placed_vertices, rotations
from bbmc.outputs.vtk import collections, vtu_bytes


def _names(values: Sequence[str] | None, count: int) -> list[str]:
    return [str(k) for k in range(count)] if values is None else [str(v) for v in values]


def block_mesh(
    model: Model, start: np.ndarray, names: list[str], groups: list[str]
) -> tuple[meshio.Mesh, dict[str, list[str]]]:
    """The blocks' faces as polygons, grouped by vertex count (VTK cells of one kind per group), and
    the text arrays of their cells (block and group names, in the cells' order)."""
    blocks = model.blocks
    owner = np.repeat(np.arange(len(blocks)), np.diff(model.vertex_start))
    world = model.vertices
    arm = world - blocks[owner, X : X + 3]
    velocity = blocks[owner, VX : VX + 3] + np.cross(blocks[owner, WX : WX + 3], arm)
    moved = blocks[:, X : X + 3] - start[:, X : X + 3]
    turn = np.degrees(rotations(start, blocks)[0])
    face_owner = np.repeat(np.arange(len(blocks)), np.diff(model.block_face_start))
    counts = np.diff(model.face_start)
    held = held_blocks(model).astype(np.int64)
    cells, order = [], []
    data = {
        key: [] for key in ("block_id", "group_id", "held", "displacement_m", "velocity_m_s", "rotation_deg")
    }
    for count in np.unique(counts):
        faces = np.flatnonzero(counts == count)
        order.extend(faces.tolist())
        loops = model.face_start[faces][:, None] + np.arange(count)
        cells.append(("polygon", model.face_vertices[loops]))
        who = face_owner[faces]
        data["block_id"].append(who.astype(np.int64))
        data["group_id"].append(model.group[who].astype(np.int64))
        data["held"].append(held[who])
        data["displacement_m"].append(moved[who])
        data["velocity_m_s"].append(blocks[who, VX : VX + 3])
        data["rotation_deg"].append(turn[who])
    mesh = meshio.Mesh(
        world,
        cells,
        point_data={
            "displacement_m": world - placed_vertices(model, start),
            "velocity_m_s": velocity,
        },
        cell_data=data,
    )
    who = face_owner[order]
    return mesh, {"block": [names[b] for b in who], "group": [groups[model.group[b]] for b in who]}


def contact_mesh(model: Model, law_names: list[str]) -> tuple[meshio.Mesh, dict[str, list[str]]]:
    """The closed sub-contacts as vertices with their stresses, slip and joint type, and the text
    array of their joint types' names."""
    table = contact_table(model)
    closed = table[table["closed"]]
    points = closed[["x_m", "y_m", "z_m"]].to_numpy()
    law = closed["joint_type"].to_numpy().astype(np.int64)
    mesh = meshio.Mesh(
        points.reshape(-1, 3),
        [("vertex", np.arange(len(points)).reshape(-1, 1))],
        point_data={
            "sigma_n_MPa": closed["sigma_n_MPa"].to_numpy(),
            "tau_MPa": closed["tau_MPa"].to_numpy(),
            "tau_vector_MPa": closed[["tau_x_MPa", "tau_y_MPa", "tau_z_MPa"]].to_numpy().reshape(-1, 3),
            "normal": closed[["nx", "ny", "nz"]].to_numpy().reshape(-1, 3),
            "shear_displacement_mm": closed["shear_displacement_mm"].to_numpy(),
            "slip_path_mm": closed["slip_path_mm"].to_numpy(),
            "area_m2": closed["area_m2"].to_numpy(),
            "slipped": closed["slipped"].to_numpy().astype(np.int64),
            "law_id": law,
        },
    )
    return mesh, {"law": [law_names[j] for j in law]}


@dataclass
class Series3D:
    """Collects one record per `record` call as files by relative path; the start is the model's
    blocks when the series is made. `names`, `groups`, `law_names` name the blocks, the group indices
    and the joint types (their indices if not given)."""

    model: Model
    folder: str = "vtk"
    every: int = 1  # keep every `every`-th record (the first always)
    names: Sequence[str] | None = None
    groups: Sequence[str] | None = None
    law_names: Sequence[str] | None = None
    files: dict[str, bytes | str] = field(default_factory=dict)
    times: list[float] = field(default_factory=list)
    seen: int = 0
    start: np.ndarray = field(init=False)  # the blocks when the series was made

    def __post_init__(self) -> None:
        self.start = self.model.blocks.copy()

    def record(self, model: Model, time_s: float) -> None:
        """The model as it stands at `time_s` [s], if this record is one kept."""
        self.seen += 1
        if (self.seen - 1) % self.every:
            return
        k = len(self.times)
        self.times.append(float(time_s))
        groups = _names(self.groups, int(model.pair_joint.shape[0]))
        laws = _names(self.law_names, len(model.law_codes))
        fields = {"group_names": groups, "law_names": laws}
        blocks, block_text = block_mesh(model, self.start, _names(self.names, len(model.blocks)), groups)
        contacts, contact_text = contact_mesh(model, laws)
        self.files[f"{self.folder}/blocks_{k:05d}.vtu"] = vtu_bytes(blocks, block_text, "CellData", fields)
        self.files[f"{self.folder}/contacts_{k:05d}.vtu"] = vtu_bytes(
            contacts, contact_text, "PointData", fields
        )

    def collections(self) -> dict[str, bytes | str]:
        """The files of every record and the two PVD collections."""
        return {**self.files, **collections(self.folder, ["blocks", "contacts"], self.times)}
