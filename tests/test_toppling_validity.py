"""The study of where Goodman & Bray's limit equilibrium holds against the block engine
(`bbmc.slope.toppling_validity`, docs/reference/toppling-validity.md): the cases it builds, one cheap
comparison, and (slow) a subset of the page's table measured again."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from bbmc.slope import fos_cases
from bbmc.slope import toppling_scene as ts
from bbmc.slope import toppling_validity as tv

PAGE = Path(__file__).resolve().parents[1] / "docs" / "reference" / "toppling-validity.md"


@pytest.mark.parametrize("slenderness", tv.SLENDERNESS)
@pytest.mark.parametrize("base_dip", tv.BASE_DIPS_DEG)
def test_a_grid_case_has_the_slenderness_it_is_built_for(slenderness, base_dip):
    """The tallest column is the crest block, exactly `slenderness` widths tall; the heights grow by
    a1 − b up to it and fall by a2 + b beyond, with a1 from the face angle, a2 from a horizontal top and
    b from the base line 5 deg steeper than the bases; the next block up would have no height; the face
    lies within 15 deg of 70 deg."""
    case = tv.grid_case(slenderness, base_dip)
    blocks, width = case.blocks, tv.WIDTH_M
    alpha = math.radians(base_dip)
    rise = width * (math.tan(math.radians(case.face_deg) - alpha) - math.tan(math.radians(5.0)))
    fall = width * (math.tan(alpha) + math.tan(math.radians(5.0)))
    crest = blocks.crest_block
    assert blocks.width == width and blocks.base_dip == pytest.approx(alpha)
    assert case.slenderness == pytest.approx(slenderness, rel=1e-12)
    assert np.argmax(blocks.heights) + 1 == crest
    assert np.diff(blocks.heights[:crest]) == pytest.approx(np.full(crest - 1, rise))
    assert np.diff(blocks.heights[crest - 1 :]) == pytest.approx(np.full(blocks.n_blocks - crest, -fall))
    assert blocks.heights[-1] - fall <= 0.0 < blocks.heights[-1]
    assert abs(case.face_deg - tv.FACE_DEG) < 15.0
    assert case.base_line_deg == base_dip + tv.STEP_DEG


def test_the_guides_examples_are_hoek_brays_and_the_issues_quarry():
    """Hoek & Bray's example is the verification's (16 blocks, 4-40 m); the quarry (H 30 m, face 70 deg,
    bases 20 deg, base line 25 deg, Δx 1.5 m) has 48 blocks, its crest in block 14, 15.46 widths tall."""
    hoek_bray, quarry = tv.study_cases()[:2]
    assert hoek_bray.blocks is fos_cases.GOODMAN_BRAY
    assert hoek_bray.slenderness == pytest.approx(4.0)
    assert (quarry.blocks.n_blocks, quarry.blocks.crest_block) == (48, 14)
    first = 1.5 * (math.tan(math.radians(50.0)) - math.tan(math.radians(5.0)))
    assert quarry.blocks.heights[0] == pytest.approx(first)
    assert quarry.slenderness == pytest.approx(14 * first / 1.5)
    assert quarry.slenderness == pytest.approx(15.46, abs=0.005)
    assert len(tv.study_cases()) == 2 + len(tv.SLENDERNESS) * len(tv.BASE_DIPS_DEG)


def test_mode_runs_name_the_blocks_toe_first():
    modes = ["slides"] * 3 + ["topples"] * 10 + ["stable"] * 3
    assert tv.mode_runs(modes) == "S1-3 T4-13 -14-16"
    assert tv.mode_runs(["topples", "slides"]) == "T1 S2"


def test_the_limit_equilibriums_limit_is_the_toppling_packages():
    """The study's limit equilibrium is `toppling.limiting_friction` (one search, not a second copy):
    38.15 deg on Hoek & Bray's example; 47.62 deg on the quarry, where the old root of P_0, 42.76 deg,
    held only because a block that topples was passed no force (docs/reference/toppling-method.md)."""
    hoek_bray, quarry = tv.study_cases()[:2]
    assert tv.le_limit(hoek_bray) == pytest.approx(38.1512, abs=1e-4)
    assert tv.le_limit(quarry) == pytest.approx(47.617, abs=1e-3)


def test_a_squat_sliding_slope_gives_the_same_limit_on_both():
    """Columns twice as tall as wide on bases at 20 deg: every block slides, at φ = α by limit
    equilibrium; the engine's bisection finds the same within its tolerance, and the same modes. The
    study reports each case done in the one progress protocol."""
    reports = []
    row = tv.study([tv.grid_case(2.0, 20.0)], reports.append).iloc[0]
    assert [(r.done, r.total, r.unit) for r in reports] == [(1, 1, "cases")]
    assert row["le_limit_deg"] == pytest.approx(20.0, abs=0.01)
    assert row["engine_limit_deg"] == pytest.approx(20.0, abs=tv.TOLERANCE_DEG)
    assert row["le_modes"] == row["engine_modes"] == "S1-6"


def page_rows() -> dict[str, list[str]]:
    """The page's table of measured numbers (its 13 columns), by case name (in backticks)."""
    rows = {}
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        match = re.match(r"\| `(\w+)` \|", line)
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if match and len(cells) == 13:
            rows[match.group(1)] = cells
    return rows


@pytest.mark.slow
@pytest.mark.parametrize("name", ["hoek_bray", "quarry", "s2_a30", "s4_a20", "s8_a20"])
def test_the_pages_numbers_are_what_the_study_measures(name):
    """A subset of the page's table measured again: both limits and the modes as printed."""
    case = {case.name: case for case in tv.study_cases()}[name]
    row = tv.compare(case)
    page = page_rows()[name]
    assert float(page[5]) == pytest.approx(row["le_limit_deg"], abs=0.005)
    assert float(page[6]) == pytest.approx(row["engine_limit_deg"], abs=0.005)
    assert float(page[7].replace("−", "-")) == pytest.approx(row["difference_deg"], abs=0.005)
    assert page[9:11] == [f"`{row['le_modes']}`", f"`{row['engine_modes']}`"]


def test_the_page_shows_every_case_of_the_study():
    assert sorted(page_rows()) == sorted(case.name for case in tv.study_cases())


def test_stiffer_joints_keep_the_trials_span_of_time():
    """The critical time step goes as sqrt(m / K): at 100 times the stiffness, ten times the steps."""
    default, stiff = ts.TrialSettings(), tv.stiff_settings(1000.0)
    assert stiff.stiffness_MPa_per_mm == 1000.0
    assert (stiff.ramp_steps, stiff.trend_window_steps, stiff.max_steps) == (
        10 * default.ramp_steps,
        10 * default.trend_window_steps,
        10 * default.max_steps,
    )
