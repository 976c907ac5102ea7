"""A rock mass in a scene: the generator's blocks and edge labels in the engine, their faults named
under the scene's key, and its geometry as a random variable of a study."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc import api
from bbmc.cli import main
from bbmc.dem.contact_rules import GLUED_CUT
from bbmc.dem.model import build_model
from bbmc.rockmass import generate
from bbmc.sweep import design
from stage_runs import refused

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "configs" / "scenes" / "benched_rock_mass.yaml"


def _scene() -> dict:
    return yaml.safe_load(SCENE.read_text())


def test_the_scene_holds_the_generators_blocks_and_labels():
    """Every block and edge label of the realization reaches the engine; the contacts on bridges get the
    intact law by their rule, those on cuts (no rule) are glued."""
    scene = api.load_scene(_scene())
    model = build_model(scene, SCENE)
    mass = generate(scene.blocks[0].rock_mass)
    assert len(model.block_names) == len(mass.polygons)
    labels = [model.label_names[i] for i in model.edge_label]
    assert labels == [label for block in mass.edge_labels for label in block]
    assert {"bridge.bedding", "joint.bedding", "joint.cross"} <= set(labels)
    result = api.run(_scene() | {"solver": {"steps": 200}})
    laws = set(result.contacts["joint_law"])
    assert laws == {"joint", "intact", GLUED_CUT}


def test_a_generators_fault_is_named_under_the_scenes_key(tmp_path):
    scene = _scene()
    scene["blocks"][0]["rock_mass"]["joint_sets"][0]["spacing_m"] = {"distribution": "constant", "value": 0.0}
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(scene))
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(tmp_path / "out")])
    assert outcome.exit_code == 2
    errors = [line for line in outcome.output.splitlines() if ": warning: " not in line]
    assert len(errors) == 1 and "blocks.0.rock_mass.joint_sets.0.spacing_m" in errors[0], outcome.output
    assert not (tmp_path / "out").exists()


def test_a_realization_variable_draws_one_seed_per_sample():
    """floor(2^31 u): whole numbers in [0, 2^31), distinct for distinct strata of the design."""
    u = np.array([1e-12, 0.25, 0.5, 1 - 1e-12])
    seeds = design.marginal("realization").ppf(u)
    assert np.array_equal(seeds, np.floor(seeds)) and seeds.min() >= 0 and seeds.max() < 2**31
    assert len(set(seeds)) == len(seeds)


def _study(tmp_path: Path, variable: dict) -> Path:
    scene = _scene()
    scene["blocks"][0]["rock_mass"]["profile"]["benches"]["count"] = 1
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene))
    study = {
        "name": "geometry",
        "base": {"kind": "scene_fos", "scene": "scene.yaml"},
        "variables": [variable],
        "sampling": {"method": "monte_carlo", "samples": 2, "seed": 4},
        "batch_size": 1,
    }
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


@pytest.mark.slow
def test_a_study_over_realizations_is_reproducible(tmp_path):
    """Two samples, each its own realization of the joint sets: the same study gives the same seeds and
    factors of safety again."""
    path = _study(tmp_path, {"path": "blocks.0.rock_mass.seed", "distribution": "realization"})
    tables = []
    for run in ("a", "b"):
        outcome = CliRunner().invoke(main, ["sweep", str(path), "--results", str(tmp_path / run)])
        assert outcome.exit_code == 0, outcome.output
        tables.append((tmp_path / run / "sweep" / "geometry" / "samples.csv").read_text())
    assert tables[0] == tables[1]
    assert "error" in tables[0].splitlines()[0]


def test_a_realization_on_a_key_that_is_no_seed_is_refused(tmp_path):
    variable = {"path": "joint_laws.joint.friction_deg", "distribution": "realization"}
    path = _study(tmp_path, variable)
    outcome = CliRunner().invoke(main, ["sweep", str(path), "--results", str(tmp_path / "out")])
    assert outcome.exit_code == 2
    assert "variables.0.distribution" in outcome.output and "no seed" in outcome.output


def test_a_tension_crack_filled_in_percent_gives_hoek_and_brays_water_table():
    """50 % of an 8 m crack 6 m behind the crest of a 20 m slope: the water table runs from the toe to
    4 m above the crack's foot, which is Hoek & Bray's (and `planar_scene`'s) line from the toe to the
    water in the crack."""
    scene = _scene()
    mass = scene["blocks"][0]["rock_mass"]
    mass["profile"]["tension_crack"] = {"distance_behind_crest_m": 6, "depth_m": 8}
    scene["water"] = {"tension_crack_fill_percent": 50}
    model = build_model(api.load_scene(scene), SCENE)
    crest = api.load_scene(scene).blocks[0].rock_mass.profile.surface()[-1]
    expected = [[0.0, 0.0], [crest[0] + 6.0, crest[1] - 4.0]]
    assert np.allclose(model.water_surface, expected, atol=1e-12)
    assert model.water_unit_weight == pytest.approx(9810.0)


def test_a_water_table_against_the_profile_runs_as_its_model_coordinates():
    """2 m above the toe, 8 m below the crest at the back edge: the water table of two 10 m benches at
    70 deg with a 4 m berm and 15 m of crest is worked out by hand, in the generator's order of sums
    (toe at the origin, the crest at 2 h cot 70 deg + 4 m, the back edge 15 m behind it). The two
    scenes have the same water surface and the same run, bit for bit."""
    relative, by_hand = _scene(), _scene()
    relative["water"] = {"height_above_toe_m": 2.0, "depth_below_crest_m": 8.0}
    run = 10.0 / math.tan(math.radians(70.0))
    by_hand["water"] = {"phreatic_surface_m": [[0.0, 0.0 + 2.0], [run + 4.0 + run + 15.0, 20.0 - 8.0]]}
    surfaces = [build_model(api.load_scene(s), SCENE).water_surface for s in (relative, by_hand)]
    assert surfaces[0].tobytes() == surfaces[1].tobytes()
    runs = [api.run(s | {"solver": {"steps": 300}}) for s in (relative, by_hand)]
    assert runs[0].state.blocks.tobytes() == runs[1].state.blocks.tobytes()
    pd.testing.assert_frame_equal(runs[0].contacts, runs[1].contacts, check_exact=True)


@pytest.mark.parametrize(
    ("water", "key", "message"),
    [
        ({"height_above_toe_m": 2.0}, "water", "give both"),
        ({"depth_below_crest_m": 8.0}, "water", "give both"),
        (
            {"height_above_toe_m": 2.0, "depth_below_crest_m": 8.0, "tension_crack_fill_percent": 50},
            "water",
            "exactly one",
        ),
    ],
)
def test_a_water_table_against_the_profile_is_given_whole(tmp_path, water, key, message):
    scene = _scene() | {"water": water}
    path = tmp_path / "wet.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "out"
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(out)])
    refused(outcome, out, str(path), f"key '{key}'", message)


def test_a_water_table_against_the_profile_needs_a_rock_mass(tmp_path):
    scene = yaml.safe_load((ROOT / "configs" / "scenes" / "incline.yaml").read_text())
    scene["water"] = {"height_above_toe_m": 2.0, "depth_below_crest_m": 8.0}
    path = tmp_path / "incline.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "out"
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(out)])
    refused(outcome, out, str(path), "key 'water.height_above_toe_m'", "no rock_mass")


def test_a_filling_without_a_crack_is_refused(tmp_path):
    scene = _scene()
    scene["water"] = {"tension_crack_fill_percent": 50}
    path = tmp_path / "dry.yaml"
    path.write_text(yaml.safe_dump(scene))
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(tmp_path / "out")])
    assert outcome.exit_code == 2 and "water.tension_crack_fill_percent" in outcome.output
