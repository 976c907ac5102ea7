"""What a new user trips on: YAML 1.2 numbers, a key given twice, unreadable files, the Python API, and
`bbmc run SCENE.yaml`. Each failure must be one line naming the file (and the key), exit 2, nothing
written."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc import api
from bbmc.cli import main
from bbmc.config import ConfigError, read_yaml
from bbmc.dem import layout as L
from bbmc.dem import motion
from bbmc.dem.model import build_model
from bbmc.dem.solver import initial_state
from bbmc.outputs.vtk import block_mesh, read_vtu

ROOT = Path(__file__).resolve().parents[1]
INCLINE = ROOT / "configs" / "scenes" / "incline.yaml"


@pytest.mark.parametrize(
    "text, value",
    [
        ("1e4", 1e4),
        ("1E-3", 1e-3),
        ("2.5e+6", 2.5e6),
        (".5", 0.5),
        ("-1e-3", -1e-3),
        ("+.5e1", 5.0),
        ("10", 10),
    ],
)
def test_every_yaml_1_2_number_form_is_a_number(tmp_path, text, value):
    path = tmp_path / "numbers.yaml"
    path.write_text(f"x: {text}\n")
    read = read_yaml(path)["x"]
    assert read == value and isinstance(read, type(value))


def test_a_scene_written_with_exponents_runs_as_the_decimal_one(tmp_path):
    """incline.yaml with its stiffness as 1e1 and its density as 2.5e3: the same scene, the same run."""
    text = INCLINE.read_text().replace("kn_MPa_per_mm: 10", "kn_MPa_per_mm: 1e1").replace("2500", "2.5e3")
    assert "1e1" in text and "2.5e3" in text
    path = tmp_path / "incline.yaml"
    path.write_text(text)
    assert api.load_scene(path) == api.load_scene(INCLINE)


def _refused(outcome, *fragments: str) -> str:
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.output.strip().splitlines()
    assert len(lines) == 1, outcome.output
    assert "Traceback" not in outcome.output
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    return lines[0]


def test_a_key_given_twice_is_refused_naming_it_and_both_lines(tmp_path):
    text = INCLINE.read_text().replace("friction_deg: 20}", "friction_deg: 20, friction_deg: 40}")
    path = tmp_path / "twice.yaml"
    path.write_text(text)
    line = next(k for k, row in enumerate(text.splitlines(), 1) if "friction_deg: 40" in row)
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(tmp_path / "out")])
    _refused(outcome, str(path), "'friction_deg' is given twice", f"lines {line} and {line}")
    assert not (tmp_path / "out").exists()


def _unreadable(tmp_path: Path, kind: str) -> Path:
    path = tmp_path / "scene.yaml"
    if kind == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    elif kind == "latin-1":
        path.write_bytes("name: pente\ndescription: talus à 30°\n".encode("latin-1"))
    elif kind == "folder":
        path.mkdir()
    elif kind == "empty":
        path.write_text("")
    return path


@pytest.mark.parametrize(
    "kind, fragment",
    [
        ("binary", "not UTF-8 text"),
        ("latin-1", "not UTF-8 text"),
        ("folder", "is a folder"),
        ("empty", "empty"),
    ],
)
@pytest.mark.parametrize("command", ["run", "fos", "sweep", "mc"])
def test_an_unreadable_config_is_one_line(tmp_path, kind, fragment, command):
    path = _unreadable(tmp_path, kind)
    outcome = CliRunner().invoke(main, [command, "--config", str(path), "--results", str(tmp_path / "out")])
    _refused(outcome, str(path), fragment)
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file without read permission")
def test_a_config_without_read_permission_is_one_line(tmp_path):
    path = tmp_path / "scene.yaml"
    shutil.copy(INCLINE, path)
    path.chmod(0)
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(tmp_path / "out")])
    _refused(outcome, str(path), "cannot read")


def test_a_data_csv_in_another_encoding_is_one_line(tmp_path):
    """bbmc mc with its Table 1 replaced by a Latin-1 file: one line naming the CSV."""
    data = yaml.safe_load((ROOT / "configs" / "mc.yaml").read_text())
    for key, value in data["data"].items():
        data["data"][key] = str((ROOT / "configs" / value).resolve())
    bad = tmp_path / "table1.csv"
    bad.write_bytes("sigma_n_MPa,note\n0.05,d\xe9j\xe0\n".encode("latin-1"))
    first = next(iter(data["data"]))
    data["data"][first] = str(bad)
    config = tmp_path / "mc.yaml"
    config.write_text(yaml.safe_dump(data))
    outcome = CliRunner().invoke(main, ["mc", "--config", str(config), "--results", str(tmp_path / "out")])
    _refused(outcome, str(bad), "not UTF-8 text")


def test_bbmc_run_takes_the_scene_as_an_argument(tmp_path):
    outcome = CliRunner().invoke(main, ["run", str(INCLINE), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    assert (tmp_path / "run" / "incline" / "history.csv").exists()
    twice = CliRunner().invoke(
        main, ["run", str(INCLINE), "--config", str(ROOT / "configs" / "scenes" / "example.yaml")]
    )
    assert twice.exit_code == 2 and "give the scene once" in twice.output


def test_the_python_api_runs_a_scene_from_a_file_or_a_dict():
    """api.run on incline.yaml and on the same scene as a dict: the same history, as a DataFrame; bad
    input is a one-line ConfigError; api.factor_of_safety gives the cracked slope's FS."""
    from_file = api.run(INCLINE)
    from_dict = api.run(yaml.safe_load(INCLINE.read_text()))
    assert list(from_file.history.columns)[:2] == ["step", "time_s"]
    assert from_file.history.equals(from_dict.history)
    broken = yaml.safe_load(INCLINE.read_text())
    broken["solver"]["dampng"] = 0.5
    with pytest.raises(ConfigError, match="did you mean 'damping'"):
        api.load_scene(broken)
    fs = api.factor_of_safety(ROOT / "configs" / "scenes" / "planar_crack.yaml").factor_of_safety
    assert fs == pytest.approx(1.115, rel=0.01)


def test_bbmc_run_writes_a_paraview_series_that_reads_back(tmp_path):
    """`bbmc run --vtk`: one blocks and one contacts VTU per record and their PVD collections, and one
    line for the folder on stdout. Read back, every array's name carries its unit; the last record's
    block displacements and contact stresses are those of blocks.csv and contacts.csv (to 1e-9 m and
    1e-9 MPa); the vertices' displacements lead back to the start (what Warp By Vector takes); group and
    law names are text arrays, in field data and per block and sub-contact; the PVD lists every record
    at its time."""
    outcome = CliRunner().invoke(main, ["run", str(INCLINE), "--vtk", "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    folder = tmp_path / "run" / "incline"
    history = pd.read_csv(folder / "history.csv")
    blocks = sorted((folder / "vtk").glob("blocks_*.vtu"))
    assert len(blocks) == len(history) == len(sorted((folder / "vtk").glob("contacts_*.vtu")))
    assert f"  {folder / 'vtk'}/ ({2 * len(blocks) + 2} files)" in outcome.output.splitlines()
    assert ".vtu" not in outcome.output
    pvd = (folder / "vtk" / "blocks.pvd").read_text()
    assert pvd.count("<DataSet") == len(history)
    assert f'timestep="{history["time_s"].iloc[-1]:.9g}"' in pvd

    last, texts = read_vtu(blocks[-1])
    assert set(last.point_data) == {"displacement_m", "velocity_m_s"}
    assert set(last.cell_data) == {"displacement_m", "velocity_m_s", "rotation_deg", "group_id"}
    table = pd.read_csv(folder / "blocks.csv")
    moved = np.concatenate(last.cell_data["displacement_m"])[:, :2]
    np.testing.assert_allclose(moved, table[["ux_mm", "uy_mm"]].to_numpy() * 1e-3, atol=1e-9)
    first, _ = read_vtu(blocks[0])
    start = last.points - last.point_data["displacement_m"]
    np.testing.assert_allclose(start, first.points, atol=1e-9)
    assert texts["block"] == texts["group"] == table["group"].tolist() == ["base", "slider"]
    assert texts["group_names"] == ["base", "slider"] and texts["law_names"] == ["joint"]

    contacts, contact_texts = read_vtu(sorted((folder / "vtk").glob("contacts_*.vtu"))[-1])
    assert set(contacts.point_data) == {"sigma_n_MPa", "tau_MPa", "slipped", "failure", "law_id"}
    active = pd.read_csv(folder / "contacts.csv").query("length_m > 0")
    np.testing.assert_allclose(contacts.point_data["sigma_n_MPa"], active["sigma_n_MPa"], atol=1e-9)
    assert contact_texts["law"] == active["joint_law"].tolist()


def test_the_vertices_displacement_includes_the_blocks_rotation():
    """Point data for Warp By Vector: a vertex's displacement is its own (the centroid's plus what the
    rotation adds), and its velocity v + omega x r, for a column turned by 0.3 rad and moved."""
    model = build_model(api.load_scene(ROOT / "configs" / "scenes" / "toppling_column.yaml"), Path("t.yaml"))
    start = initial_state(model).world
    blocks = model.blocks.copy()
    column = model.block_names.index("column")
    blocks[column, [L.X, L.Y, L.TH, L.VX, L.VY, L.W]] += [0.2, -0.1, 0.3, 1.0, 0.0, 2.0]
    world = np.empty_like(start)
    motion.update_vertices(blocks, model.vertex_start, model.local, world, np.ones(len(blocks), dtype=bool))
    mesh, _ = block_mesh(model, blocks, world)
    np.testing.assert_allclose(mesh.point_data["displacement_m"][:, :2], world - start, atol=1e-12)
    mine = model.vertex_block == column
    arm = world[mine] - blocks[column, [L.X, L.Y]]
    expected = np.column_stack([1.0 - 2.0 * arm[:, 1], 2.0 * arm[:, 0]])
    np.testing.assert_allclose(mesh.point_data["velocity_m_s"][mine, :2], expected, atol=1e-12)
    assert np.ptp(np.hypot(*(world - start)[mine].T)) > 0.1  # the rotation moves the corners differently
