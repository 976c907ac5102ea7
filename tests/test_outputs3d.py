"""A 3D run's outputs: the block and contact tables (`bbmc.dem3d.tables`), the ParaView series
(`bbmc.outputs.vtk3d`) and the mechanism figure (`bbmc.outputs.figures3d`), on a block sliding down a
held incline (30 deg towards 117 deg, phi 20 deg) and on a displacement and turn set by hand."""

import math

import numpy as np
import pytest
from matplotlib import colors
from matplotlib.backends.backend_agg import FigureCanvasAgg
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
from scipy.spatial.transform import Rotation

from bbmc.dem3d.contact_forces import AREA_CLOSED, FIRST_SUB, FN, SN, SUB_COUNT
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import QW, X
from bbmc.dem3d.model import build_model, place
from bbmc.dem3d.solver import run, time_step
from bbmc.dem3d.tables import block_table, contact_table
from bbmc.geometry.polyhedra import box, moved
from bbmc.outputs.figures3d import ARROW_COLOUR, HELD_COLOUR, mechanism_figure, view_azimuth
from bbmc.outputs.vtk import read_vtu
from bbmc.outputs.vtk3d import Series3D

G, RHO, KN = 9.81, 2500.0, 1e9  # m/s2, kg/m3, Pa/m
PSI, ALPHA = math.radians(30.0), math.radians(117.0)
NAMES = ["base", "slider"]


def incline_frame():
    """Columns: down the dip, along the strike, the plane's upward normal."""
    u = np.array([math.cos(PSI) * math.sin(ALPHA), math.cos(PSI) * math.cos(ALPHA), -math.sin(PSI)])
    n = np.array([math.sin(PSI) * math.sin(ALPHA), math.sin(PSI) * math.cos(ALPHA), math.cos(PSI)])
    return np.column_stack([u, np.cross(n, u), n])


def incline():
    """A 4 x 4 x 2 m block on a held base, sunk by its static closure (no bounce at the start)."""
    frame = incline_frame()
    sink = RHO * 2.0 * G * math.cos(PSI) / KN
    base = moved(box([-12, -6, -3], [6, 6, 0]), frame, np.zeros(3))
    block = moved(box([-2, -2, -sink], [2, 2, 2 - sink]), frame, np.zeros(3))
    law = MohrCoulomb(KN, KN / 2, math.radians(20.0))
    return build_model([base, block], RHO, [law], held=[0], refine=0), frame


@pytest.fixture(scope="module")
def slid():
    """The incline after 400 steps (0.37 s), with its start and a series of three records."""
    model, frame = incline()
    start = model.blocks.copy()
    series = Series3D(model, names=NAMES, groups=["rock"], law_names=["joint"])
    dt = time_step(model)
    series.record(model, 0.0)
    for _ in range(2):
        run(model, 200, dt)
        series.record(model, model.step * dt)
    return model, frame, start, series


def turned():
    """The incline with the block shifted by (0.1, -0.2, 0.3) m and turned 30 deg about (1, 2, 2)/3
    by hand: a displacement and rotation known exactly."""
    model, _ = incline()
    start = model.blocks.copy()
    turn = Rotation.from_rotvec(math.radians(30.0) * np.array([1.0, 2.0, 2.0]) / 3.0)
    q = Rotation.from_quat(start[1, [QW + 1, QW + 2, QW + 3, QW]])  # scipy: scalar last
    model.blocks[1, X : X + 3] += [0.1, -0.2, 0.3]
    model.blocks[1, QW : QW + 4] = np.roll((turn * q).as_quat(), 1)
    place(model.blocks, model.body_vertices, model.vertex_start, model.body_normals, model.block_face_start,
          model.vertices, model.face_normal)  # fmt: skip
    return model, start


def test_block_table_gives_a_known_displacement_and_turn():
    model, start = turned()
    table = block_table(model, start, names=NAMES, groups=["rock"])
    row = table.set_index("block").loc["slider"]
    # round-off only: the columns are the model's numbers, rescaled
    assert row[["ux_mm", "uy_mm", "uz_mm"]].to_numpy(float) == pytest.approx([100.0, -200.0, 300.0], abs=1e-9)
    assert row[["x0_m", "y0_m", "z0_m"]].to_numpy(float) == pytest.approx(start[1, X : X + 3], abs=1e-12)
    assert row["rotation_deg"] == pytest.approx(30.0, abs=1e-9)
    axis = row[["rotation_axis_x", "rotation_axis_y", "rotation_axis_z"]].to_numpy(float)
    assert axis == pytest.approx([1 / 3, 2 / 3, 2 / 3], abs=1e-9)
    base = table.set_index("block").loc["base"]
    assert base["held"] and not row["held"]
    assert base["rotation_deg"] == 0.0 and base["rotation_axis_z"] == 0.0
    assert row["group"] == "rock"
    assert list(table.columns) == [
        "block", "group", "x0_m", "y0_m", "z0_m", "x_m", "y_m", "z_m", "ux_mm", "uy_mm", "uz_mm",
        "rotation_deg", "rotation_axis_x", "rotation_axis_y", "rotation_axis_z", "vx_m_s", "vy_m_s",
        "vz_m_s", "wx_rad_s", "wy_rad_s", "wz_rad_s", "held",
    ]  # fmt: skip


def test_block_table_refuses_a_start_of_another_model():
    model, _ = incline()
    with pytest.raises(ValueError, match="start: a copy of the model's blocks"):
        block_table(model, model.blocks[:1])
    with pytest.raises(ValueError, match=r"names: one name per block \(2\), got 1"):
        block_table(model, model.blocks.copy(), names=["one"])
    with pytest.raises(ValueError, match=r"law_names: one name per joint type \(1\), got 2"):
        contact_table(model, law_names=["a", "b"])


def test_contact_table_reads_the_sub_contacts(slid):
    model, frame, _, _ = slid
    table = contact_table(model, law_names=["joint"], names=NAMES)
    (pair,) = model.contacts
    rows = model.subs[pair[FIRST_SUB] : pair[FIRST_SUB] + pair[SUB_COUNT]]
    assert len(table) == 2  # a box face at refinement 0: two triangles, both closed
    assert set(table["block_a"]) == {"slider"} and set(table["block_b"]) == {"base"}
    assert set(table["joint_type"]) == {"joint"} and set(table["contact_kind"]) == {"face-face"}
    assert table["sigma_n_MPa"].to_numpy() == pytest.approx(rows[:2, SN] / 1e6, rel=1e-12)
    assert table["area_m2"].sum() == pytest.approx(model.contact_values[0, AREA_CLOSED], rel=1e-12)
    assert (table["area_m2"] * table["sigma_n_MPa"]).sum() * 1e6 == pytest.approx(
        model.contact_values[0, FN], rel=1e-12
    )
    # A is the slider: the normal is its bottom face's outward normal now, down into the base
    normal = table[["nx", "ny", "nz"]].to_numpy()
    slider_faces = model.face_normal[model.block_face_start[1] : model.block_face_start[2]]
    bottom = slider_faces[np.argmin(slider_faces @ frame[:, 2])]
    assert np.array_equal(normal, np.tile(bottom, (2, 1)))
    assert normal == pytest.approx(np.tile(-frame[:, 2], (2, 1)), abs=1e-4)  # the slider turns 1.4e-5 rad
    tau = table[["tau_x_MPa", "tau_y_MPa", "tau_z_MPa"]].to_numpy()
    # in the plane: n is read after the last step's motion, tau on the plane before it (the slider
    # turns ~4e-6 rad a step)
    assert np.abs(np.einsum("ij,ij->i", tau, normal)).max() < 1e-5 * table["tau_MPa"].max()
    assert table["tau_MPa"].to_numpy() == pytest.approx(np.linalg.norm(tau, axis=1))
    # phi 20 deg < dip 30 deg: it slides at the limit, tau = sigma_n tan(phi)
    assert table["slipped"].all()
    assert table["tau_MPa"].to_numpy() == pytest.approx(table["sigma_n_MPa"] * math.tan(math.radians(20)))
    assert (table["slip_path_mm"] >= table["shear_displacement_mm"] - 1e-9).all()


def test_contact_table_of_pairs_apart_is_empty():
    model, _ = incline()  # no run: no pairs searched yet
    table = contact_table(model)
    assert len(table) == 0 and "sigma_n_MPa" in table.columns


def test_series_files_read_back(slid, tmp_path):
    model, _, start, series = slid
    files = series.collections()
    assert sorted(files) == sorted(
        [f"vtk/{kind}_{k:05d}.vtu" for kind in ("blocks", "contacts") for k in range(3)]
        + ["vtk/blocks.pvd", "vtk/contacts.pvd"]
    )
    assert 'timestep="0"' in files["vtk/blocks.pvd"]
    for name, data in files.items():
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_bytes(data if isinstance(data, bytes) else data.encode())
    mesh, texts = read_vtu(tmp_path / "vtk/blocks_00002.vtu")
    assert mesh.points == pytest.approx(model.vertices)
    assert sum(len(cells.data) for cells in mesh.cells) == 12  # two boxes' faces
    shift = model.blocks[1, X : X + 3] - start[1, X : X + 3]
    slider = mesh.points[8:]
    # the slider turns by ~1e-5 rad: its corners (at most 3 m from the centroid) move with it to 1e-4 m
    assert mesh.point_data["displacement_m"][8:] == pytest.approx(np.tile(shift, (8, 1)), abs=1e-4)
    assert np.abs(mesh.point_data["displacement_m"][:8]).max() == 0.0
    assert slider.shape == (8, 3)
    assert texts["block"] == ["base"] * 6 + ["slider"] * 6 and texts["group_names"] == ["rock"]
    contacts, texts = read_vtu(tmp_path / "vtk/contacts_00002.vtu")
    table = contact_table(model)
    assert contacts.point_data["sigma_n_MPa"] == pytest.approx(table["sigma_n_MPa"].to_numpy())
    assert contacts.points == pytest.approx(table[["x_m", "y_m", "z_m"]].to_numpy())
    assert texts["law"] == ["joint", "joint"]


def test_mechanism_figure(slid):
    model, _, start, _ = slid
    fig = mechanism_figure(model, start, dpi=50, names=NAMES)
    ax, bar = fig.axes
    assert ax.name == "3d" and ax.get_aspect() == "equal"
    assert ax.get_xlabel() == "x (east) [m]" and ax.get_zlabel() == "z (up) [m]"
    assert "displacement" in bar.get_ylabel()
    (faces,) = [c for c in ax.collections if isinstance(c, Poly3DCollection)]
    outlines, arrows = [c for c in ax.collections if isinstance(c, Line3DCollection)]
    assert np.allclose(arrows.get_color(), colors.to_rgba(ARROW_COLOUR))
    grey = np.all(np.isclose(faces.get_facecolor(), HELD_COLOUR), axis=1)
    assert grey.sum() == 6  # the held base's faces (in depth order: mplot3d sorts them)
    assert np.unique(faces.get_facecolor()[~grey], axis=0).shape == (1, 4)  # the slider's one colour
    FigureCanvasAgg(fig).draw()
    assert len(outlines.get_segments()) == 12  # the start's faces, projected at the draw
    assert len(arrows.get_segments()) == 3  # the slider's arrow: shaft and two strokes of its head
    assert "slider moved most" in fig._suptitle.get_text()
    # looking along the strike: the view's azimuth is the dip direction's less 90 deg
    down = 90.0 - math.degrees(ALPHA)  # the dip direction's angle from east, anticlockwise [deg]
    assert ax.azim == pytest.approx(down - 90.0, abs=0.01)  # the slider drifts off the dip by < 0.01 deg


def test_view_azimuth_without_sideways_motion():
    assert view_azimuth(np.array([[0.0, 0.0, -1.0]])) == -60.0
    assert view_azimuth(np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])) == 0.0
