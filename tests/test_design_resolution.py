"""Designs that resolve, and support that never lowers the FS by a numerical effect (issue 31).

The engine's FS is found to `fos.tolerance` and, on a rock mass, is not monotone in the support to
better than its scatter; a design is a value the engine confirmed at or above the target, beyond
which every value tried passed too. An answer at an end of the range, or none, says why.
"""

from __future__ import annotations

import copy
import itertools
from pathlib import Path

import pandas as pd
import pytest
import yaml

from bbmc import api
from bbmc.dem.model import build_model
from bbmc.fos.design import confirmed_value, design_support, fs_scatter
from bbmc.slope import fos_cases as fc
from bbmc.support.config import Design

CONFIGS = Path(__file__).parent.parent / "configs"
BOLTED = CONFIGS / "scenes" / "bolted_planar.yaml"
BENCHED = CONFIGS / "scenes" / "benched_rock_mass.yaml"


def _design(vary: str = "capacity") -> Design:
    return Design(target_fs=1.3, support="a", vary=vary, range=[20, 5000])


def _engine(rows: list[tuple[float, float]]) -> pd.DataFrame:
    return pd.DataFrame(rows, columns=["value", "factor_of_safety"])


def test_a_value_that_passed_beside_a_safer_one_that_failed_is_no_design():
    """The trials the issue reported (1,103 kN: 1.293, 1,118: 1.379, 1,258: 1.379, 1,505: 1.316) give
    1,118 kN, all safer values passing; with 1,200 kN failing (1.28), 1,118 is no longer confirmed and
    the design is 1,258 kN; the scatter is the largest drop towards the safe end."""
    reported = [(1103.0, 1.293), (1118.0, 1.379), (1258.0, 1.379), (1505.0, 1.316)]
    assert confirmed_value(_design(), _engine(reported)) == 1118.0
    assert fs_scatter(_design(), _engine(reported)) == pytest.approx(1.379 - 1.316)
    noisy = [*reported, (1200.0, 1.28)]
    assert confirmed_value(_design(), _engine(noisy)) == 1258.0
    assert fs_scatter(_design(), _engine(noisy)) == pytest.approx(1.379 - 1.28)
    assert confirmed_value(_design(), _engine([(1000.0, 1.2), (5000.0, 1.29)])) is None
    spacing = [(4.0, 1.2), (3.0, 1.31), (2.0, 1.4)]  # the safe end of a spacing is the small one
    assert confirmed_value(_design("spacing"), _engine(spacing)) == 3.0
    assert fs_scatter(_design("spacing"), _engine(spacing)) == 0.0


def test_the_engines_fs_grows_with_the_anchors_capacity_on_the_bolted_planar_slope():
    """8 capacities from 200 to 3,000 kN: FS non-decreasing within the FS tolerance (measured: 1.145,
    1.176, 1.207, 1.238, 1.270, 1.348, 1.465, 1.715, strictly increasing)."""
    base = yaml.safe_load(BOLTED.read_text())
    base.pop("design")
    tolerance = base["fos"]["tolerance"]
    found = []
    for capacity in (200, 400, 600, 800, 1000, 1400, 2000, 3000):
        scene = copy.deepcopy(base)
        scene["support"][0].update(steel_capacity_kN=capacity, pretension_kN=capacity)
        found.append(api.factor_of_safety(scene).factor_of_safety)
    assert all(b >= a - tolerance for a, b in itertools.pairwise(found))
    assert found[-1] > found[0] + 0.5


@pytest.mark.slow  # three strength reductions of the toppling slope, 14 s
def test_a_toe_anchor_never_lowers_the_fs_of_goodman_and_brays_toppling_slope():
    """An anchor from the toe block into the fixed base, at 0 (none), 1,000 and 10,000 kN: FS
    non-decreasing within the FS tolerance (measured 0.887, 0.981, 1.637)."""
    base = fc.goodman_bray_case(35.0).scene
    found = []
    for capacity in (0, 1000, 10000):
        scene = copy.deepcopy(base)
        if capacity:
            scene["support"] = [
                {"name": "toe", "type": "anchor", "head_m": [1.0, 2.0], "end_m": [15.0, -2.0],
                 "area_mm2": 2000, "steel_capacity_kN": capacity, "pretension_kN": 0.5 * capacity}
            ]  # fmt: skip
        found.append(api.factor_of_safety(scene).factor_of_safety)
    tolerance = api.load_scene(base).fos.tolerance
    assert found[0] - tolerance <= found[1] and found[1] - tolerance <= found[2]


def _two_rows(scene: dict, design: dict) -> dict:
    """The benched rock mass's realization of seed 6 with two anchor rows, on the lower bench's crest
    block (mass.30, 2.2 m, centroid 3.7, 8.1 m) and on a block of the upper bench's face (mass.18,
    5.4 m, centroid 11.6, 14.5 m), their ends in free blocks behind (mass.9 and mass.10), varied
    together."""
    scene["blocks"][0]["rock_mass"]["seed"] = 6
    anchor = {"type": "anchor", "spacing_m": 2.0, "area_mm2": 1400, "steel_capacity_kN": 100,
              "pretension_kN": 50, "bond_strength_kN_per_m": 300, "bond_length_m": 6.0}  # fmt: skip
    scene["support"] = [
        {"name": "row1", "head_m": [3.3, 8.5], "end_m": [14.0, 5.5], **anchor},
        {"name": "row2", "head_m": [9.0, 12.9], "end_m": [20.0, 10.0], **anchor},
    ]
    scene["design"] = design
    return scene


def test_a_design_that_cannot_reach_its_target_says_which_block_fails_first():
    """On seed 6 of the benched rock mass (FS 1.129, measured on the paired generator of issue 33) the
    blocks resting on the bedding are near tan 38 / tan 35 = 1.12 and the first to fail are the upper
    bench's crest blocks mass.21 and mass.22 (x 12 to 15 m, y 18.5 to 19.6 m), which no row holds: two
    rows that hold two other blocks cannot give FS 1.3, and the design says that the block that fails
    first at the largest capacity is not one they hold (measured: 1.129 at 20 and at 1,600 kN, mass.21
    first). (Seed 3, the shipped scene's, now stands at
    1.824 on its bridges, so the premise is not its.)"""
    design = {"target_fs": 1.3, "support": ["row1", "row2"], "vary": "capacity", "range": [20, 1600]}
    scene = api.load_scene(_two_rows(yaml.safe_load(BENCHED.read_text()), design))
    result = design_support(build_model(scene, BENCHED), BENCHED)
    assert result.value is None
    assert "is not one the support holds" in result.note and "fos.judge" in result.note
    assert set(result.trials.stage) == {"engine"}


def test_a_design_whose_smallest_value_already_passes_says_it_is_at_the_end_of_its_range():
    tree = yaml.safe_load(BOLTED.read_text())
    tree["design"].update(target_fs=1.12, range=[200, 4000])  # FS 1.145 at 200 kN
    result = design_support(build_model(api.load_scene(tree), BOLTED), BOLTED)
    assert result.value == 200
    assert result.note.startswith("at the end of the range")
