"""A run as a time series that ParaView opens: one VTU file of the blocks and one of the sub-contacts per
record step, and a PVD collection of each with the records' times (written with meshio).

* blocks_<k>.vtu: every block a polygon (z = 0) at its position then, with cell data displacement
  (of the centroid, [m], 3-vector), velocity [m/s], rotation [deg] and group (its index in the
  scene's sorted group names; the names are in the PVD's comment).
* contacts_<k>.vtu: every active sub-contact a vertex at its position, with point data sigma_n and
  tau [MPa], slipped (0 or 1) and law (the joint law's index; the names in the PVD's comment).
* blocks.pvd, contacts.pvd: the collections; open either in ParaView and play the series.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import escape

import meshio
import numpy as np

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.model import Model


def block_mesh(model: Model, blocks: np.ndarray, world: np.ndarray) -> meshio.Mesh:
    """The blocks as polygons, grouped by vertex count (VTK cells of one kind per block of cells)."""
    points = np.column_stack([world, np.zeros(len(world))])
    counts = np.diff(model.vertex_start)
    order = np.argsort(counts, kind="stable")
    cells, data = [], {"displacement": [], "velocity": [], "rotation_deg": [], "group": []}
    for count in np.unique(counts):
        members = order[counts[order] == count]
        cells.append(
            (
                "polygon",
                np.array([np.arange(model.vertex_start[b], model.vertex_start[b + 1]) for b in members]),
            )
        )
        moved = blocks[members][:, [L.X, L.Y]] - blocks[members][:, [L.X0, L.Y0]]
        data["displacement"].append(np.column_stack([moved, np.zeros(len(members))]))
        data["velocity"].append(np.column_stack([blocks[members][:, [L.VX, L.VY]], np.zeros(len(members))]))
        data["rotation_deg"].append(np.degrees(blocks[members, L.TH]))
        data["group"].append(model.block_group[members].astype(np.int64))
    return meshio.Mesh(points, cells, cell_data=data)


def contact_mesh(contacts: np.ndarray, subs: np.ndarray, n_sub: int) -> meshio.Mesh:
    """The active sub-contacts as vertices with their stresses, slip state and joint law."""
    active = subs[:, L.LENGTH] > 0
    points = np.column_stack([subs[active][:, [L.CX, L.CY]], np.zeros(int(active.sum()))])
    law = (
        np.repeat(contacts[:, L.JOINT_TYPE], n_sub)[active] if len(contacts) else np.zeros(0, dtype=np.int64)
    )
    return meshio.Mesh(
        points,
        [("vertex", np.arange(len(points)).reshape(-1, 1))],
        point_data={
            "sigma_n_MPa": subs[active, L.SN] / units.MPa,
            "tau_MPa": subs[active, L.TAU] / units.MPa,
            "slipped": (subs[active, L.SLIPPED] > 0).astype(np.int64),
            "law": law.astype(np.int64),
        },
    )


def _collection(names: list[str], times: list[float], legend: str) -> str:
    rows = "\n".join(
        f'    <DataSet timestep="{t:.9g}" group="" part="0" file="{name}"/>'
        for name, t in zip(names, times, strict=True)
    )
    return (
        '<?xml version="1.0"?>\n'
        f"<!-- {escape(legend)} -->\n"
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
        f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n"
    )


def _vtu_bytes(mesh: meshio.Mesh) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.vtu"
        meshio.write(path, mesh, binary=True)
        return path.read_bytes()


@dataclass
class Series:
    """Collects one record per call (a `simulate` on_record callback) as files by relative path."""

    model: Model
    folder: str = "vtk"
    every: int = 1  # keep every `every`-th record (the first always)
    files: dict[str, bytes | str] = field(default_factory=dict)
    times: list[float] = field(default_factory=list)
    seen: int = 0

    def __call__(self, state) -> None:
        self.seen += 1
        if (self.seen - 1) % self.every:
            return
        k = len(self.times)
        self.times.append(float(state.clock[L.TIME]))
        blocks = block_mesh(self.model, state.blocks, state.world)
        contacts = contact_mesh(state.contacts, state.subs, state.n_sub)
        self.files[f"{self.folder}/blocks_{k:05d}.vtu"] = _vtu_bytes(blocks)
        self.files[f"{self.folder}/contacts_{k:05d}.vtu"] = _vtu_bytes(contacts)

    def collections(self) -> dict[str, bytes | str]:
        """The files of every record and the two PVD collections."""
        n = len(self.times)
        groups = "group: " + ", ".join(f"{i} {g}" for i, g in enumerate(self.model.group_names))
        laws = "law: " + ", ".join(f"{i} {name}" for i, name in enumerate(self.model.law_names))
        return {
            **self.files,
            f"{self.folder}/blocks.pvd": _collection(
                [f"blocks_{k:05d}.vtu" for k in range(n)], self.times, groups
            ),
            f"{self.folder}/contacts.pvd": _collection(
                [f"contacts_{k:05d}.vtu" for k in range(n)], self.times, laws
            ),
        }
