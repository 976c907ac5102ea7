"""bbmc slope: the claim measures on paths with known answers, the slope generator, the limit-equilibrium
check, and the stage run (shortened) into a temporary folder."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.geometry import polygons
from bbmc.slope import limit_equilibrium as le
from bbmc.slope import measures as me
from stage_runs import config_copy, run_stage, stage_folder

SLOPE = {
    "height_m": 10.0,
    "face_angle_deg": 60.0,
    "crest_extent_m": 25.0,
    "toe_extent_m": 0.0,
    "depth_m": 0.0,
}
SETS = [
    {"dip_deg": 20.0, "dip_direction_to_face_deg": 0.0, "spacing_m": 2.5, "offset_m": 0.0},
    {"dip_deg": 80.0, "dip_direction_to_face_deg": 180.0, "spacing_m": 5.0, "offset_m": 0.0},
]


# --- measures on known answers --------------------------------------------------------------------
def test_slip_rate_of_uniform_acceleration_is_the_mean_velocity_of_the_second_half():
    t = np.linspace(0.0, 2.0, 201)
    assert me.slip_rate(t, 0.5 * 3.0 * t**2) == pytest.approx(3.0 * (1.0 + 2.0) / 2)


def test_rate_spread_and_relative_difference():
    assert me.rate_spread(np.array([1.0, 1.0, 1.0])) == 0.0
    assert me.rate_spread(np.array([1.0, 2.0, 3.0])) == pytest.approx(1.0)
    assert me.relative_difference(1.0, 3.0) == pytest.approx(1.0)


def test_separation_of_blocks_moving_together_is_zero_and_of_diverging_ones_their_drift():
    t = np.linspace(0.0, 1.0, 11)[:, None]
    a = np.hstack([t, 0 * t])
    assert me.separation(a, a + np.array([5.0, 1.0])) == pytest.approx(0.0, abs=1e-12)
    assert me.separation(a, np.hstack([3 * t + 5.0, 0 * t])) == pytest.approx(2.0)


@given(st.floats(0.1, 10.0), st.floats(-5.0, 5.0), st.floats(-1.0, 1.0))
@settings(max_examples=30, deadline=None)
def test_quadratic_fit_recovers_a_quadratic(c2, c1, c0):
    x = np.linspace(0.0, 3.0, 50)
    coefficients, r2 = me.quadratic_fit(x, c2 * x**2 + c1 * x + c0)
    np.testing.assert_allclose(coefficients, [c2, c1, c0], atol=1e-8)
    assert r2 == pytest.approx(1.0)


def test_quadratic_fit_of_noise_has_low_r2():
    rng = np.random.default_rng(1)
    assert me.quadratic_fit(np.linspace(0, 1, 200), rng.normal(size=200))[1] < 0.1


def test_onset_time_of_uniform_acceleration():
    t = np.linspace(0.0, 2.0, 2001)
    assert me.onset_time(t, 0.5 * 2.0 * t**2, 1.0) == pytest.approx(1.0, abs=1e-6)
    assert me.onset_time(t, 0 * t, 1.0) == math.inf


# --- generator ------------------------------------------------------------------------------------
def test_slope_blocks_are_convex_and_fill_the_profile():
    blocks = polygons.jointed_slope(**SLOPE, joint_sets=SETS, min_block_fraction=0.0)
    assert all(polygons.shape_fault(polygons.counter_clockwise(b)) is None for b in blocks)
    crest = SLOPE["height_m"] / math.tan(math.radians(SLOPE["face_angle_deg"]))
    x_right = crest + SLOPE["crest_extent_m"]
    profile = x_right * SLOPE["height_m"] - 0.5 * crest * SLOPE["height_m"]
    assert sum(polygons.polygon_area(b) for b in blocks) == pytest.approx(profile, rel=1e-9)


def test_slope_with_ground_in_front_fills_its_profile_and_splits_at_the_toe_along_a_joint():
    shape = dict(SLOPE, toe_extent_m=5.0, depth_m=4.0)
    blocks = polygons.jointed_slope(**shape, joint_sets=SETS, min_block_fraction=0.0)
    crest = shape["height_m"] / math.tan(math.radians(shape["face_angle_deg"]))
    width = 5.0 + crest + shape["crest_extent_m"]
    profile = width * 4.0 + (crest + shape["crest_extent_m"]) * 10.0 - 0.5 * crest * 10.0
    assert sum(polygons.polygon_area(b) for b in blocks) == pytest.approx(profile, rel=1e-9)
    assert all(polygons.shape_fault(polygons.counter_clockwise(b)) is None for b in blocks)


def test_joint_traces_lie_on_the_set_planes():
    normal = polygons.joint_set_trace(20.0, 0.0)
    np.testing.assert_allclose(normal[:2], [-math.sin(math.radians(20)), math.cos(math.radians(20))])
    assert polygons.joint_set_trace(80.0, 180.0)[0] > 0  # into the slope: the normal leans away from the face
    assert polygons.joint_set_trace(30.0, 60.0)[2] == pytest.approx(
        math.hypot(0.5 * 0.5, math.cos(math.radians(30)))
    )


# --- limit equilibrium ----------------------------------------------------------------------------
def test_factor_of_safety_is_one_at_the_critical_dip_and_follows_the_closed_forms():
    constant = {"law": "constant", "cohesion_MPa": 0.0, "friction_deg": 30.0}
    assert le.factor_of_safety(constant, 45.0, 2.0, 2500.0) == pytest.approx(math.tan(math.radians(30)))
    assert le.critical_dip(constant, 2.0, 2500.0, 1.0, 89.0) == pytest.approx(30.0)
    bb = {
        "law": "barton_bandis",
        "strength": {"jrc": 0.0, "jcs_MPa": 10.0, "phi_b_deg": 33.0, "phi_max_deg": 70.0},
    }
    assert le.critical_dip(bb, 2.0, 2500.0, 1.0, 89.0) == pytest.approx(33.0)


def test_a_block_that_holds_at_every_dip_has_no_critical_dip():
    """Cohesion against a light block: FS > 1 up to 89 deg, so no dip is critical (NaN; brentq raised)."""
    holding = {"law": "constant", "cohesion_MPa": 0.1, "friction_deg": 30.0}
    assert le.factor_of_safety(holding, 89.0, 2.0, 2.3) > 1
    assert math.isnan(le.critical_dip(holding, 2.0, 2.3, 1.0, 89.0))


def test_engine_critical_dip_bisects_a_step_function():
    assert le.engine_critical_dip(lambda d: d > 21.3, 10.0, 30.0, 0.01) == pytest.approx(21.3, abs=0.01)
    with pytest.raises(ValueError, match="hold at"):
        le.engine_critical_dip(lambda d: True, 10.0, 30.0, 0.01)


# --- the stage ------------------------------------------------------------------------------------
def _short(data):
    data["run"]["duration_s"] = 0.6
    data["limit_equilibrium"]["dips_deg"] = [15.0, 40.0]
    data["sensitivity"]["dips_deg"] = [20.0, 40.0]
    data["animation_frames"] = 3
    data["figure_dpi"] = 60
    return data


@pytest.fixture(scope="module")
def slope_run(tmp_path_factory):
    return stage_folder(tmp_path_factory, "slope", _short)


def test_stage_writes_every_file(slope_run):
    for name in ("fig7", "fig8", "fig9", "fig10", "fs_vs_dip", "dip_sensitivity"):
        assert (slope_run / f"{name}.png").stat().st_size > 0
    for name in (
        "claims",
        "fig7_blocks",
        "fig8_vectors",
        "fig9_joints",
        "fig10_displacements",
        "fig10_fits",
        "fs_vs_dip",
        "critical_dip",
        "dip_sensitivity",
    ):
        assert len(pd.read_csv(slope_run / f"{name}.csv")) > 0
    assert (slope_run / "animation.gif").read_bytes()[:3] == b"GIF"


def test_claims_table_has_one_row_per_claim_with_both_runs(slope_run):
    claims = pd.read_csv(slope_run / "claims.csv")
    assert list(claims["claim"]) == ["C1", "C2", "B1", "B2", "B3", "B4", "B5", "Q1", "S1", "S2"]
    assert claims[["constant", "barton_bandis"]].notna().all().all()


def test_monitored_blocks_sit_where_the_paper_puts_them(slope_run):
    blocks = pd.read_csv(slope_run / "fig7_blocks.csv")
    numbered = blocks[blocks["paper_number"] > 0].set_index("paper_number")
    assert not numbered["fixed"].any()
    assert numbered.loc[2, "x_m"] < numbered.loc[1, "x_m"] < numbered.loc[4, "x_m"] < numbered.loc[3, "x_m"]
    vertices = [[float(c) for c in v.split(",")] for v in numbered.loc[2, "vertices_m"].split()]
    on_face = [abs(y - math.tan(math.radians(60)) * x) < 1e-3 for x, y in vertices]
    assert sum(on_face) >= 2  # No. 2 has an edge on the free face


def test_engine_slides_where_limit_equilibrium_says(slope_run):
    critical = pd.read_csv(slope_run / "critical_dip.csv")
    assert critical["within"].all(), critical
    sweep = pd.read_csv(slope_run / "fs_vs_dip.csv")
    assert (sweep["engine_slides"] == (sweep["factor_of_safety"] < 1)).all()


def test_bedding_offset_is_refused_with_one_line(tmp_path):
    def edit(data):
        data["slope"]["joint_sets"][0]["offset_m"] = 0.5
        return data

    result = run_stage("slope", tmp_path / "results", config_copy(tmp_path, "slope", edit))
    assert result.exit_code == 2
    assert "offset_m" in result.output and len(result.output.strip().splitlines()) == 1
    assert not (tmp_path / "results").exists()


def test_joint_set_parallel_to_the_section_is_refused(tmp_path):
    def edit(data):
        data["slope"]["joint_sets"][1].update(dip_deg=90.0, dip_direction_to_face_deg=90.0)
        return data

    result = run_stage("slope", tmp_path / "results", config_copy(tmp_path, "slope", edit))
    assert result.exit_code == 2 and "joint_sets.1" in result.output


def test_a_limit_equilibrium_step_budget_too_small_to_decide_is_one_line(tmp_path):
    """The engine's block neither at rest nor slid within limit_equilibrium.max_steps: bad input naming
    the key (it was a traceback)."""

    def edit(data):
        data["run"]["duration_s"] = 0.02
        data["limit_equilibrium"]["max_steps"] = 10
        return data

    config = config_copy(tmp_path, "slope", edit)
    result = run_stage("slope", tmp_path / "results", config)
    assert result.exit_code == 2, result.output
    line = result.stderr.strip()
    assert line.startswith(f"bbmc slope: error: {config}: key 'limit_equilibrium': undecided after 10 steps")
    assert not (tmp_path / "results").exists()


def test_a_bedding_that_leaves_no_sliding_layer_is_one_line(tmp_path):
    """A near-flat bedding (2e-8 deg) leaves no block on the bedding joint through the toe: the paper's
    blocks 1-4 cannot be picked (it was a traceback)."""

    def edit(data):
        data["slope"]["joint_sets"][0]["dip_deg"] = 2e-8
        return data

    result = run_stage("slope", tmp_path / "results", config_copy(tmp_path, "slope", edit))
    assert result.exit_code == 2, result.output
    assert (
        "key 'slope': with the bedding at 2e-08 deg, 0 free blocks rest on the bedding joint" in result.stderr
    )
    assert len(result.stderr.strip().splitlines()) == 1
