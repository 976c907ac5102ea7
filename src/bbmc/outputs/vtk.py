"""A run as a time series that ParaView opens: one VTU file of the blocks and one of the sub-contacts per
record step, and a PVD collection of each with the records' times (written with meshio).

Every array's name carries its unit, as the CSV columns do (`_m`, `_m_s`, `_deg`, `_MPa`); ids and
flags have none.

* blocks_<k>.vtu: every block a polygon (z = 0) at its position then.
  Point data (at every vertex; what Warp By Vector and Glyph take): displacement_m (from its start,
  rotation included, 3-vector) and velocity_m_s (v + omega x r).
  Cell data (per block): displacement_m and velocity_m_s of the centroid, rotation_deg, group_id (its
  index in the scene's sorted group names), and the names themselves as text arrays: block and group.
* contacts_<k>.vtu: every active sub-contact a vertex at its position, with point data sigma_n_MPa,
  tau_MPa, slipped (0 or 1), failure (0 intact, 1 slipped in shear, 2 failed in tension: a rock bridge
  that broke, a bond that opened), law_id (the joint law's index) and law (its name).
* Both carry field data group_names and law_names: every name, in the order of the ids.
* blocks.pvd, contacts.pvd: the collections; open either in ParaView and play the series.

meshio writes numbers only; the text arrays are added as VTK's own writer writes a vtkStringArray in
ASCII (`<Array type="String">`, each string's character codes then 0), which ParaView (VTK's XML reader)
shows in its spreadsheet and information panels. meshio's own reader (5.3) refuses text arrays: read
these files with VTK (ParaView, pyvista) or with `read_vtu`.
"""

from __future__ import annotations

import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import meshio
import numpy as np

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.bridges import failure_mode
from bbmc.dem.model import Model
from bbmc.dem.support_report import per_bolt_kN, support_lines


def _vector(xy: np.ndarray) -> np.ndarray:
    return np.column_stack([xy, np.zeros(len(xy))])


def block_mesh(model: Model, blocks: np.ndarray, world: np.ndarray) -> tuple[meshio.Mesh, dict]:
    """The blocks as polygons, grouped by vertex count (VTK cells of one kind per block of cells), and
    the text arrays of their cells (block and group names, in the cells' order)."""
    owner = model.vertex_block
    centroid = blocks[owner][:, [L.X, L.Y]]
    start = blocks[owner][:, [L.X0, L.Y0]] + model.local  # rotation is measured from the start
    arm = world - centroid
    spin = blocks[owner, L.W]
    vertex_velocity = blocks[owner][:, [L.VX, L.VY]] + np.column_stack([-spin * arm[:, 1], spin * arm[:, 0]])
    counts = np.diff(model.vertex_start)
    order = np.argsort(counts, kind="stable")
    cells, data = [], {"displacement_m": [], "velocity_m_s": [], "rotation_deg": [], "group_id": []}
    members_in_order = []
    for count in np.unique(counts):
        members = order[counts[order] == count]
        members_in_order.extend(members.tolist())
        cells.append(
            (
                "polygon",
                np.array([np.arange(model.vertex_start[b], model.vertex_start[b + 1]) for b in members]),
            )
        )
        moved = blocks[members][:, [L.X, L.Y]] - blocks[members][:, [L.X0, L.Y0]]
        data["displacement_m"].append(_vector(moved))
        data["velocity_m_s"].append(_vector(blocks[members][:, [L.VX, L.VY]]))
        data["rotation_deg"].append(np.degrees(blocks[members, L.TH]))
        data["group_id"].append(model.block_group[members].astype(np.int64))
    mesh = meshio.Mesh(
        _vector(world),
        cells,
        point_data={"displacement_m": _vector(world - start), "velocity_m_s": _vector(vertex_velocity)},
        cell_data=data,
    )
    text = {
        "block": [model.block_names[b] for b in members_in_order],
        "group": [model.group_names[model.block_group[b]] for b in members_in_order],
    }
    return mesh, text


def contact_mesh(
    model: Model, contacts: np.ndarray, subs: np.ndarray, n_sub: int
) -> tuple[meshio.Mesh, dict]:
    """The active sub-contacts as vertices with their stresses, slip state and joint law, and the text
    array of their joint laws' names."""
    active = subs[:, L.LENGTH] > 0
    points = _vector(subs[active][:, [L.CX, L.CY]])
    law = (
        np.repeat(contacts[:, L.JOINT_TYPE], n_sub)[active] if len(contacts) else np.zeros(0, dtype=np.int64)
    ).astype(np.int64)
    mesh = meshio.Mesh(
        points,
        [("vertex", np.arange(len(points)).reshape(-1, 1))],
        point_data={
            "sigma_n_MPa": subs[active, L.SN] / units.MPa,
            "tau_MPa": subs[active, L.TAU] / units.MPa,
            "slipped": (subs[active, L.SLIPPED] > 0).astype(np.int64),
            "failure": failure_mode(subs[active, L.SLIPPED]),
            "law_id": law,
        },
    )
    return mesh, {"law": [model.law_names[j] for j in law]}


def support_mesh(model: Model, blocks: np.ndarray, support: np.ndarray) -> meshio.Mesh:
    """The support elements as lines at the blocks' positions (`bbmc.dem.support_report.support_lines`),
    with their axial and shear force [kN per bolt] and state (0 elastic, 1 yielded, 2 ruptured)."""
    lines, axial = support_lines(model.support, blocks, support)
    state = np.where(support[:, L.BROKEN] > 0, 2, np.where(support[:, L.YIELDED] > 0, 1, 0))
    return meshio.Mesh(
        _vector(lines.reshape(-1, 2)),
        [("line", np.arange(2 * len(lines)).reshape(-1, 2))],
        cell_data={
            "axial_kN": [axial],
            "shear_kN": [per_bolt_kN(model.support, support[:, L.SHEAR])],
            "state": [state.astype(np.int64)],
        },
    )


def _text_array(parent: ET.Element, name: str, values: list[str], with_count: bool) -> None:
    """Append a vtkStringArray in VTK's ASCII form: each string's character codes (UTF-8), then 0."""
    array = ET.SubElement(parent, "Array", type="String", Name=name, format="ascii")
    if with_count:
        array.set("NumberOfTuples", str(len(values)))
    array.text = " ".join(" ".join([*map(str, value.encode()), "0"]) for value in values)


def vtu_bytes(
    mesh: meshio.Mesh, texts: dict[str, list[str]], where: str, names: dict[str, list[str]]
) -> bytes:
    """The mesh as VTU (meshio), with the text arrays `texts` added to its `where` ("CellData" or
    "PointData") and the name lists `names` as field data."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.vtu"
        meshio.write(path, mesh, binary=True)
        tree = ET.parse(path)
    grid = tree.getroot().find("UnstructuredGrid")
    piece = grid.find("Piece")
    fields = ET.Element("FieldData")
    for name, values in names.items():
        _text_array(fields, name, values, with_count=True)
    grid.insert(0, fields)
    data = piece.find(where)
    if data is None:
        data = ET.SubElement(piece, where)
    for name, values in texts.items():
        _text_array(data, name, values, with_count=False)
    return ET.tostring(tree.getroot(), xml_declaration=True, encoding="utf-8")


def _decoded(text: str | None) -> list[str]:
    codes = bytes(int(code) for code in (text or "").split())
    return [value.decode() for value in codes.split(b"\0")[:-1]]


def read_vtu(path: Path) -> tuple[meshio.Mesh, dict[str, list[str]]]:
    """A VTU file of a series read back: its numbers (meshio) and its text arrays by name (field,
    cell and point data alike)."""
    tree = ET.parse(path)
    texts = {}
    for parent in tree.getroot().iter():
        for array in [child for child in parent if child.tag == "Array" and child.get("type") == "String"]:
            texts[array.get("Name")] = _decoded(array.text)
            parent.remove(array)
    with tempfile.TemporaryDirectory() as folder:
        numbers = Path(folder) / "numbers.vtu"
        tree.write(numbers)
        return meshio.read(numbers), texts


def collection(names: list[str], times: list[float]) -> str:
    """A PVD collection (ParaView's time series) of the files `names` at the record times `times` [s]."""
    rows = "\n".join(
        f'    <DataSet timestep="{t:.9g}" group="" part="0" file="{name}"/>'
        for name, t in zip(names, times, strict=True)
    )
    return (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
        f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n"
    )


def collections(folder: str, kinds: list[str], times: list[float]) -> dict[str, str]:
    """A PVD collection `<folder>/<kind>.pvd` of `<kind>_<k>.vtu` for each kind, one file per time [s]."""
    return {
        f"{folder}/{kind}.pvd": collection([f"{kind}_{k:05d}.vtu" for k in range(len(times))], times)
        for kind in kinds
    }


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
        names = {"group_names": self.model.group_names, "law_names": self.model.law_names}
        blocks, block_text = block_mesh(self.model, state.blocks, state.world)
        contacts, contact_text = contact_mesh(self.model, state.contacts, state.subs, state.n_sub)
        self.files[f"{self.folder}/blocks_{k:05d}.vtu"] = vtu_bytes(blocks, block_text, "CellData", names)
        self.files[f"{self.folder}/contacts_{k:05d}.vtu"] = vtu_bytes(
            contacts, contact_text, "PointData", names
        )
        if len(self.model.support.names):
            mesh = support_mesh(self.model, state.blocks, state.support)
            self.files[f"{self.folder}/support_{k:05d}.vtu"] = vtu_bytes(mesh, {}, "CellData", names)

    def collections(self) -> dict[str, bytes | str]:
        """The files of every record and the PVD collections."""
        kinds = ["blocks", "contacts"] + (["support"] if len(self.model.support.names) else [])
        return {**self.files, **collections(self.folder, kinds, self.times)}
