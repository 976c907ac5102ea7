"""`bbmc bench`'s parts: the Pareto front and the error on known answers, every economy exact on the
paper's scenes, the stage run into a temporary folder with a small config, and the sections run alone
(`--only`) or left out of the config."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc.bench.bandwidth import bandwidth_fraction, bytes_per_update, gather_bytes
from bbmc.bench.economy import economy_table
from bbmc.bench.engine_cost import engine_cost_table
from bbmc.bench.paper_scenes import Reading, ShearScene, SlopeScene, relative_error
from bbmc.bench.tradeoff import pareto_front
from bbmc.cli import main
from bbmc.stages.bench import SECTIONS
from stage_runs import CONFIGS, stage_folder


def test_pareto_front_keeps_exactly_the_undominated_runs():
    seconds = np.array([1.0, 2.0, 3.0, 2.5, 0.5, 4.0])
    error = np.array([0.1, 0.01, 0.001, 0.05, math.inf, 0.001])
    assert pareto_front(seconds, error).tolist() == [True, True, True, False, False, False]


def _reading(values, statuses=None) -> Reading:
    values = np.array(values, dtype=float)
    return Reading(values, statuses or ("holds",) * len(values), 1.0, 1)


def test_relative_error_is_scaled_by_the_largest_reference_value_and_infinite_when_an_outcome_changes():
    reference = _reading([2.0, 0.01, math.inf], ("holds", "holds", "slides"))
    assert relative_error(_reading([2.1, 0.02, math.inf], ("holds", "holds", "slides")), reference) == (
        pytest.approx(0.05)
    )
    assert relative_error(_reading([2.0, 0.01, 3.0], ("holds", "holds", "holds")), reference) == math.inf
    assert relative_error(reference, reference) == 0.0


@pytest.fixture(scope="module")
def scenes():
    return [
        ShearScene(CONFIGS / "shear.yaml"),
        SlopeScene(CONFIGS / "slope.yaml", "barton_bandis"),
        SlopeScene(CONFIGS / "slope.yaml", "constant"),
    ]


def test_every_economy_changes_no_number_on_the_paper_scenes(scenes):
    table = economy_table(scenes, 1, lambda _: None)
    assert len(table) == 3 * 4
    assert table["identical_results"].all(), table[~table["identical_results"]]


def test_slope_reading_is_the_displacement_of_blocks_1_to_4_at_the_end_of_the_run(scenes):
    slope = scenes[1]
    reading = slope.read(slope.defaults())
    assert reading.statuses == ("ran its time",) * 4
    assert np.all((reading.values > 0) & (reading.values < 0.01))  # the B-B slope creeps by millimetres


def _small(data):
    t = data["tradeoff"]
    for key in ("shear_config", "slope_config"):
        data[key] = str((CONFIGS / data[key]).resolve())
    t["scenes"] = ["shear", "slope_barton_bandis"]
    t["knobs"] = {
        "update_interval_steps": [1, 200],
        "safety_factor": [0.9],
        "sub_contacts_per_edge": [2],
        "damping": [0.5],
        "density_scaling": [5],
        "law_update_stress_change": [0.05],
    }
    t["reference"] = {"update_interval_steps": 1, "safety_factor": 0.25, "sub_contacts_per_edge": 4}
    t["reference_check"] = {"safety_factor": 0.125}
    t["repeats"] = 1
    data["economy"] = {"repeats": 1, "scenes": ["shear", "slope_barton_bandis"]}
    data["scaling"] = {"block_counts": [100, 300], "steps": 20, "repeats": 1, "memory_limit_GB": 4}
    data["laws"] = {"array_size": 2000, "python_loop_size": 200, "repeats": 1}
    data["engine_cost"] = {"commit": "deadbeef", "block_counts": [100], "steps": 20, "repeats": 1}
    data["rockmass"] = {"spacing_scale": 3.0, "steps": 20, "repeats": 1}  # about 1,100 blocks, not 10,000
    data["fos"]["variants"] = {"sub_contacts_8": data["fos"]["variants"]["sub_contacts_8"]}  # 1 of 7
    data["sweep"] = {"le_samples": 10_000, "dem_samples": 2, "repeats": 1}
    data["support"] |= {"commit": "deadbeef", "repeats": 1}
    data["support"]["design_scene"] = str((CONFIGS / data["support"]["design_scene"]).resolve())


@pytest.fixture(scope="module")
def bench_run(tmp_path_factory):
    return stage_folder(tmp_path_factory, "bench", _small)


@pytest.mark.slow  # the small bench run behind it takes about a minute
def test_bench_writes_every_file(bench_run):
    names = {p.name for p in bench_run.iterdir()}
    for stem in ("tradeoff", "scaling"):
        assert {f"{stem}.csv", f"{stem}.png"} <= names
    assert {"tradeoff_readings.csv", "recommended.csv", "economy.csv", "laws.csv", "provenance.json"} <= names
    assert {"fos_cost.csv", "sweep_cost.csv", "rockmass_cost.csv"} <= names


@pytest.mark.slow  # the small bench run behind it takes about a minute
def test_engine_cost_says_why_when_the_commit_cannot_be_checked_out(bench_run):
    table = pd.read_csv(bench_run / "engine_cost.csv")
    assert table["skipped"].iloc[0].startswith("commit deadbeef not checked out")


@pytest.mark.slow
def test_engine_cost_of_the_engine_against_itself_is_one(tmp_path):
    """HEAD against HEAD (fresh processes, one compiling the checkout's kernels): the ratio is within
    timing noise of 1 (0.8 to 1.25 on a shared machine)."""
    table = engine_cost_table("HEAD", [100], 50, 2, CONFIGS / "slope.yaml", CONFIGS / "shear.yaml")
    assert (table["skipped"] == "").all()
    assert table["now_over_then"].between(0.8, 1.25).all()


@pytest.mark.slow  # the small bench run behind it takes about a minute
def test_tradeoff_varies_one_knob_at_a_time_against_the_reference(bench_run):
    table = pd.read_csv(bench_run / "tradeoff.csv", dtype={"value": str})
    for _, rows in table.groupby("scene"):
        default = rows[rows["knob"] == "default"].iloc[0]
        safety = rows[rows["knob"] == "safety_factor"].iloc[0]
        assert safety["safety_factor"] == 0.9
        assert safety["update_interval_steps"] == default["update_interval_steps"]
        reference = rows[rows["knob"] == "reference"].iloc[0]
        assert reference["error_measured_against"] == "reference_check"
        assert np.isfinite(reference["relative_error"])
        front = rows[rows["on_pareto_front"]]
        assert not front["knob"].isin(["reference", "reference_check"]).any()
        compared = rows[~rows["knob"].isin(["reference", "reference_check"])]
        for run in front.itertuples():  # nothing compared is both faster and more accurate
            better = (compared["seconds"] <= run.seconds) & (compared["relative_error"] <= run.relative_error)
            assert not (
                better
                & ((compared["seconds"] < run.seconds) | (compared["relative_error"] < run.relative_error))
            ).any()
    slope = table[table["scene"] == "slope_barton_bandis"].set_index("knob")
    # the automatic step is proportional to the safety factor: 0.9 takes about 0.5 / 0.9 of the steps
    assert slope.loc["safety_factor", "steps"] / slope.loc["default", "steps"] == pytest.approx(
        0.5 / 0.9, rel=0.1
    )
    # the paper's 50 steps lag the B-B update: further from the reference than updating every step
    updates = table[(table["scene"] == "slope_barton_bandis") & (table["knob"] == "update_interval_steps")]
    every, rarely = updates.set_index("value")["relative_error"].loc[["1", "200"]]
    assert every < rarely


@pytest.mark.slow  # the small bench run behind it takes about a minute
def test_recommended_value_is_the_fastest_within_the_target_when_measurably_faster(bench_run):
    table = pd.read_csv(bench_run / "tradeoff.csv", dtype={"value": str})
    advice = pd.read_csv(bench_run / "recommended.csv", dtype=str, keep_default_na=False)
    assert len(advice) == 2 * 6
    for row in advice.itertuples():
        runs = table[(table["scene"] == row.scene) & (table["knob"] == row.knob)]
        within = runs[runs["relative_error"] <= float(row.target_error)]
        fastest = "" if within.empty else within.loc[within["seconds"].idxmin(), "value"]
        assert row.fastest_within_target == fastest
        if row.measurably_faster == "True":
            assert row.recommended == fastest
            assert float(row.its_time_over_default) < 1 - float(row.timing_noise)


LAWS = {"array_size": 2000, "python_loop_size": 200, "repeats": 1}


def _bench(tmp_path: Path, sections: dict, *options: str):
    """`bbmc bench` on a config of the paper's two scenes and `sections`, into tmp_path/results."""
    config = {"shear_config": str(CONFIGS / "shear.yaml"), "slope_config": str(CONFIGS / "slope.yaml")}
    path = tmp_path / "bench.yaml"
    path.write_text(yaml.safe_dump(config | sections))
    results = tmp_path / "results"
    args = ["bench", "--config", str(path), "--results", str(results), *options]
    return CliRunner().invoke(main, args), results / "bench"


def test_a_section_left_out_of_the_config_is_skipped_with_one_line_saying_so(tmp_path):
    outcome, out = _bench(tmp_path, {"laws": LAWS})
    assert outcome.exit_code == 0, outcome.output
    skipped = [line for line in outcome.stderr.splitlines() if line.endswith("skipped")]
    assert len(skipped) == len(SECTIONS) - 1
    for name in (s for s in SECTIONS if s != "laws"):
        assert sum(f"section '{name}' is not in the config" in line for line in skipped) == 1
    assert {p.name for p in out.iterdir()} == {"laws.csv", "machine.csv", "provenance.json"}
    assert len(pd.read_csv(out / "laws.csv")) == 4


def test_only_runs_the_sections_it_names(tmp_path):
    mobilized = {"sub_contacts": 1000, "repeats": 1, "update_intervals": [50]}
    outcome, out = _bench(tmp_path, {"laws": LAWS, "mobilized": mobilized}, "--only", "laws")
    assert outcome.exit_code == 0, outcome.output
    assert "skipped" not in outcome.stderr
    assert {p.name for p in out.iterdir()} == {"laws.csv", "machine.csv", "provenance.json"}
    assert json.loads((out / "provenance.json").read_text())["only"] == ["laws"]


@pytest.mark.parametrize(
    ("sections", "only", "fragments"),
    [
        ({"laws": LAWS}, "laws,scaling_law", ("--only", "'scaling_law'", ", ".join(SECTIONS))),
        ({"laws": LAWS}, "engine_cost", ("--only", "no section 'engine_cost'")),
        ({}, None, ("bench.yaml", "no section to run", ", ".join(SECTIONS))),
    ],
)
def test_a_section_that_cannot_run_is_refused_in_one_line(tmp_path, sections, only, fragments):
    outcome, out = _bench(tmp_path, sections, *(["--only", only] if only else []))
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1, outcome.stderr
    assert "Traceback" not in outcome.output + outcome.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    assert not out.exists()


def test_bytes_per_update_add_up_the_rows_a_sub_contact_update_streams():
    """16 float64 columns read and written (256 B), a quarter of a contact's 5 int64 columns (10 B),
    an eighth of a block's 28 float64 columns read and written (56 B) and of its 4 vertices' local
    and world coordinates (16 B); the gathers of 2 blocks' rows and 2 vertices each: 512 B / 4."""
    assert bytes_per_update(4, 8.0, 4.0) == 256 + 10 + 56 + 16
    assert gather_bytes(4) == 128
    assert bandwidth_fraction(50e6, 400.0, 40.0) == pytest.approx(0.5)


def test_bandwidth_section_writes_the_triad_on_one_and_every_thread_and_the_limit(tmp_path):
    bandwidth = {"array_MB": 2, "repeats": 1, "blocks": 100}
    outcome, out = _bench(tmp_path, {"bandwidth": bandwidth})
    assert outcome.exit_code == 0, outcome.output
    triad = pd.read_csv(out / "bandwidth.csv")
    assert list(triad.columns) == ["threads", "array_MB", "GB_per_s", "repeats"]
    assert triad["threads"].iloc[0] == 1 and (triad["GB_per_s"] > 0).all()
    limit = pd.read_csv(out / "bandwidth_limit.csv")
    assert (limit["bytes_per_update"] > 320).all()
    assert np.allclose(limit["updates_per_s_limit"], limit["GB_per_s"] * 1e9 / limit["bytes_per_update"])


def test_support_section_times_the_design_search_and_says_why_without_the_commit(tmp_path):
    support = {"commit": "deadbeef", "block_counts": [100], "steps": 20, "repeats": 1,
               "design_scene": str(CONFIGS / "scenes" / "bolted_planar.yaml")}  # fmt: skip
    outcome, out = _bench(tmp_path, {"support": support})
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(out / "support_cost.csv")
    assert table["skipped"].iloc[0].startswith("commit deadbeef not checked out")
    design = table[table["scene"] == "design search, bolted_planar.yaml"].iloc[0]
    assert design["design_value"] == pytest.approx(2151.0, rel=0.01)
    assert design["engine_trials"] >= 1 and design["wall_time_s"] < 60


def test_kinematics_section_writes_its_costs_with_the_issues_marks(tmp_path):
    small = {"readings": 2000, "compass_readings": 40, "samples": 2000, "repeats": 1}
    outcome, out = _bench(tmp_path, {"kinematics": small})
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(out / "kinematics_cost.csv").set_index("quantity")
    assert table.loc["sets_found", "value"] == 4
    assert table.loc["readings", "value"] == 2000
    assert (table.loc[["set_finding_time", "compass_1deg_time"], "value"] > 0).all()
    assert table.loc["compass_1deg_time", "mark"] == "under 2 s"


def test_wedge_section_writes_its_costs_with_the_issues_marks(tmp_path):
    small = {
        "wedge_config": str(CONFIGS / "wedge.yaml"),
        "study_config": str(CONFIGS / "sweeps" / "classic_wedge.yaml"),
        "calls": 3,
        "samples": 200,
        "repeats": 1,
    }
    outcome, out = _bench(tmp_path, {"wedge": small}, "--only", "wedge")
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(out / "wedge_cost.csv").set_index("quantity")
    assert list(table.columns) == ["value", "unit", "mark", "met"]
    assert table.loc["combination_pairs", "value"] == 45
    assert 0 < table.loc["combinations_formed", "value"] <= 45
    assert table.loc["samples", "value"] == 200
    timed = ["wedge_ms", "combinations_ms", "samples_per_second", "analysis_samples_per_second"]
    assert (table.loc[timed, "value"] > 0).all()
    assert table.loc["wedge_ms", "mark"] == "under 1 ms"
    assert table.loc["samples_per_second", "mark"] == "at least 1e6"
    assert set(table.loc[timed, "met"]) <= {True, False}
    assert table.loc["samples", "met"] != table.loc["samples", "met"]  # no mark, no verdict (NaN)


@pytest.mark.slow
def test_engine3d_section_writes_the_3d_rates_beside_the_2d_ones_with_the_issues_marks(tmp_path):
    """Tiny sizes (a 27-block stack, 2 steps, one process each): every row, the marks, the bitwise
    check on 1 and 2 threads, and no module of the 3D engine in a 2D run."""
    small = {"block_counts": [27], "steps": 2, "threads_blocks": 27, "repeats": 1}
    outcome, out = _bench(tmp_path, {"engine3d": small}, "--only", "engine3d")
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(out / "engine3d.csv").set_index("quantity")
    assert list(table.columns) == ["value", "unit", "mark", "met"]
    assert table.loc["blocks_3d_27", "value"] == 28  # 27 and the held base
    assert (table.loc[["rate_3d_27", "rate_2d_27", "speedup_2_threads_27", "wedge_srm_s"], "value"] > 0).all()
    assert table.loc["bitwise_1_2_threads_27", "value"] == 1
    assert table.loc["dem3d_modules_in_a_2d_run", "value"] == 0
    assert table.loc["wedge_srm_s", "mark"] == "under 30 s"
    assert table.loc["wedge_srm_fs", "value"] == pytest.approx(1.2746, rel=0.01)  # 3DEC's, issue 36
