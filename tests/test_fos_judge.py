"""The FS of what matters (`fos.judge`): a trial's verdict read on chosen blocks, a region, or blocks
above a size, so that a sliver that slides first does not set the slope's FS; and the FS from an
elastic start said beside the run from rest.

Two blocks on two separate 30 deg planes: a 4 x 1 m block on a 40 deg joint (FS tan 40 / tan 30 =
1.453) and a 0.4 x 0.2 m chip on a 35 deg joint (1.213). Judged on every block the chip fails first;
judged on the big block, by name, by region or by size, the FS is the big block's.
"""

from __future__ import annotations

import copy
import math

import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc import api
from bbmc.cli import main
from bbmc.slope import fos_cases as fc

BIG, CHIP = (4.0, 1.0), (0.4, 0.2)
CHIP_AT = 20.0  # the chip's plane is turned about (20, 0) [m], far from the big block's


def _fs(friction_deg: float) -> float:
    return math.tan(math.radians(friction_deg)) / math.tan(math.radians(fc.DIP_DEG))


def _two_blocks(judge: dict | None = None) -> dict:
    scene = fc.block_on_plane({**fc.MOHR_COULOMB, "friction_deg": 40.0}, *BIG)
    scene["name"] = "big_and_chip"
    turn = {"rotate_deg": fc.DIP_DEG, "rotate_about_m": [CHIP_AT, 0.0]}
    width, height = CHIP
    scene["blocks"] += [
        {
            "name": "chip_base",
            "group": "chip",
            "material": "rock",
            "rectangle_m": {"x_m": CHIP_AT - 2 * width, "y_m": -0.5, "width_m": 3 * width, "height_m": 0.5},
            "fix": ["x", "y", "rotation"],
            **turn,
        },
        {
            "name": "chip",
            "group": "chip",
            "material": "rock",
            "rectangle_m": {"x_m": CHIP_AT - width, "y_m": 0.0, "width_m": width, "height_m": height},
            **turn,
        },
    ]
    scene["joint_laws"]["weak"] = {**fc.MOHR_COULOMB, "friction_deg": 35.0}
    scene["contacts"]["rules"] = [{"law": "weak", "groups": ["chip", "chip"]}]
    if judge is not None:
        scene["fos"] = {"judge": judge}
    return scene


def test_every_block_judged_the_chip_sets_the_fs_and_is_named():
    result = api.factor_of_safety(_two_blocks())
    assert result.factor_of_safety == pytest.approx(_fs(35.0), rel=0.01)
    assert result.failing_trial.block == "chip"
    assert "block 'chip' failed first" in result.failing_note  # 0.25 x the median block's size


@pytest.mark.parametrize(
    "judge",
    [
        {"blocks": ["slider"]},
        {"region_m": [[-10.0, -5.0], [5.0, 5.0]]},
        {"min_size_fraction": 0.5},  # the chip is 0.28 m, the median free block 1.14 m
    ],
    ids=["by name", "by region", "by size"],
)
def test_judged_on_the_big_block_the_fs_is_its_own(judge):
    """Within 1 % of tan 40 / tan 30 (the bisection's half-width is 0.5 %), although the chip slides
    away in every trial above 1.21."""
    result = api.factor_of_safety(_two_blocks(judge))
    assert result.factor_of_safety == pytest.approx(_fs(40.0), rel=0.01)
    assert result.failing_trial.block == "slider"


@pytest.mark.parametrize(
    "judge, key, hint",
    [
        ({"blocks": ["slidr"]}, "fos.judge.blocks.0", "did you mean 'slider'?"),
        ({"region_m": [[100.0, 100.0], [101.0, 101.0]]}, "fos.judge", "no block free to move"),
    ],
)
def test_a_judge_that_names_nothing_is_refused_in_one_line(tmp_path, judge, key, hint):
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(_two_blocks(judge)))
    results = tmp_path / "out"
    outcome = CliRunner().invoke(main, ["fos", str(path), "--results", str(results)])
    assert outcome.exit_code == 2
    error = outcome.stderr.strip().splitlines()[-1]
    assert f"key '{key}'" in error and hint in error and "Traceback" not in outcome.output
    assert not results.exists()


def test_an_fs_from_the_elastic_start_says_the_run_from_rest_fails(tmp_path):
    """A block whose FS is below 1 fails from rest (as `bbmc run` shows) and its FS is found from the
    elastic start: summary.csv says it did not stand from rest and how far it moved, and the command
    warns in one line; a block that stands says nothing of it."""
    below = copy.deepcopy(fc.cases()[0].scene)
    below["joint_laws"]["joint"]["friction_deg"] = 25.0
    below["name"] = "below"
    for scene, stands in ((below, 0), (fc.block_on_plane(fc.MOHR_COULOMB, 4.0, 1.0), 1)):
        path = tmp_path / f"{scene['name']}.yaml"
        path.write_text(yaml.safe_dump(scene))
        outcome = CliRunner().invoke(main, ["fos", str(path), "--results", str(tmp_path)])
        assert outcome.exit_code == 0, outcome.output
        table = pd.read_csv(tmp_path / "fos" / scene["name"] / "summary.csv").set_index("quantity")["value"]
        assert table["stands_from_rest"] == stands
        assert table["start_from_elastic_equilibrium"] == 1 - stands
        noted = "does not stand from rest" in outcome.stderr
        assert noted == (not stands)
        if not stands:
            assert table["from_rest_largest_displacement"] > 0.0
            assert table["factor_of_safety"] < 1.0
