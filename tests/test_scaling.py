"""The scaling study (bbmc.bench.scaling): scaled slopes of the asked size, a small table measured in
fresh processes with its derived columns, the memory estimate that skips a size, and the figure."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bbmc.bench import scaling
from bbmc.dem.model import build_model
from bbmc.scene.schema import Scene
from stage_runs import CONFIGS

SLOPE = str(CONFIGS / "slope.yaml")


@pytest.mark.parametrize("blocks", [100, 1000])
def test_scaled_slope_has_about_the_blocks_asked(blocks):
    scene = Scene.model_validate(scaling.scaled_slope(blocks, SLOPE), strict=False)
    model = build_model(scene, Path("scaled.yaml"))
    assert blocks / 1.5 <= len(model.block_names) <= 1.5 * blocks
    sets = scene.blocks[0].jointed_slope.joint_sets
    assert [s.dip_deg for s in sets] == [20.0, 80.0]  # the paper slope's orientations, spacings scaled
    assert sets[1].spacing_m / sets[0].spacing_m == pytest.approx(2.0)
    assert scene.contacts.sub_contacts_per_edge == 4
    assert scene.solver.damping == 0.8
    assert scene.solver.time_step.mode == "auto"


def test_paper_scale_is_the_paper_slope():
    assert scaling.spacing_scale(34, SLOPE) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="at least 1"):
        scaling.spacing_scale(0, SLOPE)


@pytest.mark.slow  # 12 s of engine runs in fresh processes
def test_small_table_measured_in_processes_and_derived_columns():
    ballast = np.ones(60_000_000)  # 480 MB here: a process started from this one must not report it
    table = scaling.scaling_table([300, 100], 20, 1, 2**34, SLOPE, min_timed_s=0.0)
    assert list(table["blocks_asked"]) == [100, 300]
    assert (table["skipped"] == "").all()
    for column in ("seconds_per_step", "initial_search_s", "generation_and_build_s", "peak_rss_MB"):
        values = table[column].to_numpy(dtype=float)
        assert np.all(np.isfinite(values)) and np.all(values > 0), column
    assert (table["contacts"] > 0).all() and (table["sub_contacts"] == 4 * table["contacts"]).all()
    assert (table["peak_rss_MB"] >= table["peak_rss_after_build_MB"]).all()
    assert 0 < table["baseline_rss_MB"].iloc[0] < ballast.nbytes / scaling.MB
    np.testing.assert_allclose(
        table["peak_rss_above_baseline_MB"], table["peak_rss_MB"] - table["baseline_rss_MB"]
    )
    np.testing.assert_allclose(table["seconds_per_step"], table["cycles_s"] / table["steps"])

    t, n = table["seconds_per_step"].to_numpy(), table["blocks"].to_numpy(dtype=float)
    assert math.isnan(table["growth_exponent_vs_previous"].iloc[0])
    assert table["growth_exponent_vs_previous"].iloc[1] == pytest.approx(
        math.log(t[1] / t[0]) / math.log(n[1] / n[0])
    )
    relative = (t / (n * np.log(n))) / (t[0] / (n[0] * np.log(n[0])))
    np.testing.assert_allclose(table["cost_over_NlogN_relative"], relative)
    assert list(table["within_NlogN"]) == list(relative <= scaling.NLOGN_SLACK)

    fig = scaling.scaling_figure(table)
    assert len(fig.axes) == 2
    assert all(ax.get_xscale() == ax.get_yscale() == "log" for ax in fig.axes)
    assert all(ax.get_xlabel() and ax.get_ylabel() and ax.get_legend() for ax in fig.axes)


def test_a_size_estimated_above_the_memory_limit_is_skipped(monkeypatch):
    def fake(blocks, steps, repeats, slope_config, min_timed_s, threads):  # 1 kB a block above 200 MB
        return {"blocks": blocks, "seconds_per_step": 1e-6 * blocks, "peak_rss_MB": 200 + 1e-3 * blocks}

    monkeypatch.setattr(scaling, "baseline", lambda slope_config, timeout_s=None: 200.0)
    monkeypatch.setattr(scaling, "measure", fake)
    table = scaling.scaling_table([10_000, 100_000, 1_000_000], 10, 1, 1.0e9, SLOPE)
    assert list(table["skipped"] == "") == [True, True, False]
    assert "above the limit" in table["skipped"].iloc[2]
    # 10 MB above the baseline at 1e4, 100 MB at 1e5: linear; 1e6 is estimated at 200 + 1.5 x 1000 MB
    assert table["estimated_peak_rss_MB"].iloc[2] == pytest.approx(200 + 1.5 * 1000)
    assert math.isnan(table["seconds_per_step"].iloc[2]) and math.isnan(
        table["growth_exponent_vs_previous"].iloc[2]
    )
    assert table["growth_exponent_vs_previous"].iloc[1] == pytest.approx(1.0)
    assert table["memory_growth_exponent"].iloc[1] == pytest.approx(1.0)


def test_memory_estimate_grows_faster_when_memory_did():
    rows = [{"blocks": 1000, "peak_rss_MB": 110.0}, {"blocks": 10_000, "peak_rss_MB": 200.0}]  # 10 -> 100 MB
    assert scaling.estimated_peak_MB(rows, 100_000, 100.0) == pytest.approx(100 + 1.5 * 100 * 10)
    rows[1]["peak_rss_MB"] = 1100.0  # 10 -> 1000 MB over a decade: exponent 2, the cap
    assert scaling.estimated_peak_MB(rows, 100_000, 100.0) == pytest.approx(100 + 1.5 * 1000 * 100)
    rows[0]["peak_rss_MB"] = 101.0  # 1 MB is too small to tell a growth from: linear
    assert scaling.estimated_peak_MB(rows, 100_000, 100.0) == pytest.approx(100 + 1.5 * 1000 * 10)
    assert math.isnan(scaling.estimated_peak_MB([], 100, 100.0))
