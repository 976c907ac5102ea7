"""`bbmc sweep`: the probability of failure against a closed form, the same answer for any number of
workers and on a dask cluster, resuming after an interruption, a worker killed mid-study, failed
samples recorded, bad input refused. Each tolerance is stated where it is used."""

from __future__ import annotations

import copy
import math
import os
import signal
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner
from scipy.stats import norm

from bbmc.cli import main
from bbmc.command_outcome import reported
from bbmc.config import load_config
from bbmc.progress import Progress
from bbmc.slope import fos_cases as fc
from bbmc.slope import toppling as tp
from bbmc.stages import sweep as stage
from bbmc.sweep import design, report
from bbmc.sweep.outcomes import Outcomes
from bbmc.sweep.runner import run_batches

ROOT = Path(__file__).resolve().parents[1]
PLANAR = ROOT / "configs" / "sweeps" / "planar_block.yaml"


def _sweep(config: Path, results: Path, *options: str):
    outcome = CliRunner().invoke(
        main, ["sweep", "--config", str(config), "--results", str(results), *options]
    )
    assert outcome.exit_code == 0, outcome.output
    return outcome, results / "sweep"


def _config(tmp_path: Path, data: dict, name: str = "study.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data))
    return path


def _planar(samples: int, batch: int, **changes) -> dict:
    data = yaml.safe_load(PLANAR.read_text())
    data["sampling"]["samples"] = samples
    data["batch_size"] = batch
    data.update(changes)
    return data


def test_probability_of_failure_matches_the_closed_form(tmp_path):
    """configs/sweeps/planar_block.yaml: a dry cohesionless block on a 35 deg plane with tan phi normal
    (0.8, 0.15), so FS = tan phi / tan 35 is exactly normal and P_f = Phi(-beta), beta = (mu_FS - 1) /
    sigma_FS = 0.665, P_f = 0.2529. At 10^4 Monte Carlo samples ours lies within 4 standard errors
    (measured 0.2524, 0.1 standard error) and its 95 % interval covers it."""
    _, out = _sweep(PLANAR, tmp_path)
    summary = pd.read_csv(out / "planar_block" / "summary.csv").set_index("quantity")["value"]
    tan_psi = math.tan(math.radians(35.0))
    beta = (0.8 / tan_psi - 1.0) / (0.15 / tan_psi)
    exact = norm.cdf(-beta)
    assert summary["samples"] == 10_000
    assert abs(summary["probability_of_failure"] - exact) <= 4 * summary["standard_error"]
    assert summary["pf_ci_low"] <= exact <= summary["pf_ci_high"]
    assert summary["reliability_index_normal"] == pytest.approx(beta, abs=4 * 0.15 / tan_psi / 100 / 0.2)


def test_results_are_byte_identical_for_one_and_two_workers(tmp_path):
    """The same study on 1 and on 2 local processes, batches finishing in any order: samples.csv and
    summary.csv byte for byte equal."""
    config = _config(tmp_path, _planar(3000, 250))
    _, one = _sweep(config, tmp_path / "one", "--workers", "1")
    _, two = _sweep(config, tmp_path / "two", "--workers", "2")
    for name in ("samples.csv", "summary.csv", "sensitivity.csv"):
        assert (one / "planar_block" / name).read_bytes() == (two / "planar_block" / name).read_bytes(), name


def test_an_interrupted_study_runs_only_its_missing_samples(tmp_path):
    """Two finished batches removed (as if the run had been stopped before writing them): the same
    command runs those two only, and the result is the same as the uninterrupted one."""
    config = _config(tmp_path, _planar(2000, 250))
    _, out = _sweep(config, tmp_path, "--workers", "2")
    whole = (out / "planar_block" / "samples.csv").read_bytes()
    store = next((out / "planar_block.progress").iterdir())
    batches = sorted(store.glob("batch_*.csv"))
    assert len(batches) == 8
    for path in batches[3:5]:
        path.unlink()
    again, out = _sweep(config, tmp_path, "--workers", "2")
    assert "2 batches of up to 250 samples to run (1500 samples done before)" in again.output
    assert (out / "planar_block" / "samples.csv").read_bytes() == whole


def test_a_changed_study_does_not_reuse_another_studys_batches(tmp_path):
    """A different seed is a different study: its batches go to a folder of their own."""
    _sweep(_config(tmp_path, _planar(500, 250)), tmp_path)
    data = _planar(500, 250)
    data["sampling"]["seed"] = 2
    again, out = _sweep(_config(tmp_path, data), tmp_path)
    assert "2 batches of up to 250 samples to run (0 samples done before)" in again.output
    assert len(list((out / "planar_block.progress").iterdir())) == 2


def test_a_sample_that_cannot_run_is_recorded_with_its_error(tmp_path):
    """A crack depth drawn up to 25 m on a 20 m slope: the samples whose crack reaches below the toe
    form no block; each is kept with its error and no FS, the others are evaluated, the summary counts
    them."""
    data = _planar(400, 100)
    data["base"]["crack_depth_m"] = 5.0
    data["variables"] = [{"path": "crack_depth_m", "distribution": "uniform", "min": 0.0, "max": 25.0}]
    _, out = _sweep(_config(tmp_path, data), tmp_path, "--workers", "1")
    samples = pd.read_csv(out / "planar_block" / "samples.csv", keep_default_na=False, na_values=["nan", ""])
    bad = samples["crack_depth_m"] >= 20.0
    assert bad.sum() > 0 and (~bad).sum() > 0
    assert samples.loc[bad, "error"].str.contains("crack depth").all()
    assert samples.loc[bad, "factor_of_safety"].isna().all()
    assert samples.loc[~bad, "factor_of_safety"].notna().all()
    summary = pd.read_csv(out / "planar_block" / "summary.csv").set_index("quantity")["value"]
    assert summary["failed_runs"] == bad.sum()


def test_a_path_not_in_the_base_is_refused_naming_the_entry(tmp_path):
    data = _planar(100, 50)
    data["variables"][0]["path"] = "strength.friction_angle"
    outcome = CliRunner().invoke(
        main, ["sweep", "--config", str(_config(tmp_path, data)), "--results", str(tmp_path / "out")]
    )
    assert outcome.exit_code == 2
    assert "variables.0.path" in outcome.output and len(outcome.output.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def _scene_study(tmp_path: Path, samples: int) -> Path:
    """DEM factor of safety of the block on a 30 deg plane (`bbmc.slope.fos_cases`) with its friction
    uncertain: one sample per batch, so that a cluster has many tasks to lose."""
    scene = _config(tmp_path, fc.block_on_plane(fc.MOHR_COULOMB, 0.8, 0.2), "scene.yaml")
    return _config(
        tmp_path,
        {
            "name": "block_fos",
            "base": {"kind": "scene_fos", "scene": str(scene)},
            "variables": [
                {"path": "joint_laws.joint.friction_deg", "distribution": "normal", "mean": 33.0, "std": 3.0}
            ],
            "sampling": {"method": "latin_hypercube", "samples": samples, "seed": 3},
            "batch_size": 1,
        },
    )


@pytest.mark.slow  # 8-11 s: a local dask cluster; make test-slow runs it
def test_a_dask_cluster_gives_the_same_answer_and_survives_a_killed_worker(tmp_path):
    """The DEM study on a 2-worker LocalCluster, one worker process killed (SIGKILL) after the first
    batch has come back: the study completes, every sample once, byte for byte what 1 local process
    gives."""
    distributed = pytest.importorskip("distributed")
    config = _scene_study(tmp_path, 16)
    _, local = _sweep(config, tmp_path / "local", "--workers", "1")
    settings = load_config(config, stage.Config)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster:
        with distributed.Client(cluster) as client:
            pids = list(client.run(os.getpid).values())
        killed = []

        def say(news: Progress) -> None:
            if "1/16 samples" in news.text and not killed:
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])

        result = stage.run(
            settings, config, tmp_path / "cluster" / "sweep", cluster.scheduler_address, None, say
        )
    assert killed
    samples = result.tables["samples"]
    assert list(samples["sample"]) == list(range(16))
    expected = pd.read_csv(local / "block_fos" / "samples.csv")
    numbers = ["sample", "joint_laws.joint.friction_deg", "factor_of_safety"]
    pd.testing.assert_frame_equal(
        samples[numbers].reset_index(drop=True), expected[numbers], check_exact=True
    )
    assert (samples["error"].fillna("") == "").all() and expected["error"].isna().all()


def test_toppling_probability_of_failure_is_that_of_phi_below_its_limit(tmp_path):
    """configs/sweeps/toppling.yaml: Goodman & Bray's example with phi ~ N(40, 3) deg; FS < 1 exactly
    where phi is below the limiting friction (38.15 deg), so P_f = Phi((38.15 - 40) / 3) = 0.2689; at
    10^4 samples within 4 standard errors (measured 0.2713, 0.5 standard error)."""
    _, out = _sweep(ROOT / "configs" / "sweeps" / "toppling.yaml", tmp_path)
    summary = pd.read_csv(out / "toppling" / "summary.csv").set_index("quantity")["value"]
    limit = math.degrees(tp.limiting_friction(tp.regular_system(10.0, math.radians(30.0), 10, 5.0, 5.0, 1.0)))
    exact = norm.cdf((limit - 40.0) / 3.0)
    assert abs(summary["probability_of_failure"] - exact) <= 4 * summary["standard_error"]


# Checks before any work, impossible inputs, truncation, a study that gives nothing ----------------------


def _refused(config: Path, results: Path, *fragments: str) -> None:
    """Exit 2 with one error line naming each fragment (after any plausibility warnings of the values
    it refuses), nothing written."""
    outcome = CliRunner().invoke(main, ["sweep", "--config", str(config), "--results", str(results)])
    assert outcome.exit_code == 2, outcome.output
    errors = [line for line in outcome.output.strip().splitlines() if ": warning: " not in line]
    assert len(errors) == 1, outcome.output
    for fragment in fragments:
        assert fragment in errors[0], outcome.output
    assert not results.exists()


def _wide_friction(samples: int, **variable) -> dict:
    """The planar block with tan phi ~ N(0.8, 0.5): 5.5 % of the normal lies below 0."""
    data = _planar(samples, samples)
    data["variables"] = [
        {"path": "strength.tan_friction", "distribution": "normal", "mean": 0.8, "std": 0.5, **variable}
    ]
    return data


def test_a_scene_run_monitor_that_does_not_exist_is_refused_before_any_run(tmp_path):
    """`monitor: slider_x` where the history's column is slider_x_mm: exit 2 naming base.monitor and the
    closest column, before any sample runs (before, every sample failed with a KeyError and the study
    ended with status 0)."""
    study = {
        "name": "incline_run",
        "base": {"kind": "scene_run", "scene": str(ROOT / "configs" / "scenes" / "incline.yaml"),
                 "monitor": "slider_x"},
        "variables": [{"path": "joint_laws.joint.friction_deg", "distribution": "normal", "mean": 20.0,
                       "std": 2.0}],
        "sampling": {"method": "monte_carlo", "samples": 4, "seed": 1},
    }  # fmt: skip
    _refused(_config(tmp_path, study), tmp_path / "out", "'base.monitor'", "did you mean 'slider_x_mm'")


def test_a_base_scene_that_fails_its_checks_is_refused_naming_the_scene(tmp_path):
    """A misspelt key in the base scene: the scene's own one-line error, before any sample runs."""
    scene = copy.deepcopy(fc.block_on_plane(fc.MOHR_COULOMB, 0.8, 0.2))  # it shares its solver section
    scene["solver"]["stepz"] = scene["solver"].pop("steps")
    _scene_study(tmp_path, 4)  # writes scene.yaml and study.yaml
    _config(tmp_path, scene, "scene.yaml")
    _refused(tmp_path / "study.yaml", tmp_path / "out", "scene.yaml", "solver.stepz")


def test_inputs_that_cannot_be_sampled_within_their_range_are_refused(tmp_path):
    """A distribution with almost none of its probability where its key is defined, a grid value
    outside the range, a whole-number key given a distribution: exit 2 naming the entry."""
    data = _planar(100, 50)
    data["variables"][0].update(mean=-5.0, std=0.1)
    _refused(_config(tmp_path, data), tmp_path / "out", "'variables.0'", "accepts > 0")
    grid = _planar(100, 50)
    grid.pop("variables")
    grid["sampling"] = {"method": "grid"}
    grid["grid"] = [{"path": "strength.tan_friction", "values": [0.5, -0.1]}]
    _refused(_config(tmp_path, grid), tmp_path / "out", "'grid.0.values'", "-0.1")
    scene = _scene_study(tmp_path, 4)
    data = yaml.safe_load(scene.read_text())
    data["variables"][0]["path"] = "solver.steps"
    _refused(_config(tmp_path, data), tmp_path / "out", "'variables.0.path'", "whole numbers")


def test_a_study_in_which_no_sample_gives_a_result_exits_4_with_its_first_errors(tmp_path):
    """Every crack drawn below the toe: exit 4, the counts and the first error on stderr, the finished
    batches kept (each sample's error) and no results folder."""
    data = _planar(100, 50)
    data["base"]["crack_depth_m"] = 5.0
    data["variables"] = [{"path": "crack_depth_m", "distribution": "uniform", "min": 21.0, "max": 25.0}]
    outcome = CliRunner().invoke(
        main, ["sweep", "--config", str(_config(tmp_path, data)), "--results", str(tmp_path / "out")]
    )
    assert outcome.exit_code == 4, outcome.output
    assert "no sample gave a result of 100: 0 invalid, 100 failed runs, 0 impossible inputs" in outcome.output
    assert "sample 0 (and 99 more): no planar block: the crack depth" in outcome.output
    assert not (tmp_path / "out" / "sweep" / "planar_block").exists()
    assert len(list((tmp_path / "out" / "sweep" / "planar_block.progress").glob("*/batch_*.csv"))) == 2


def test_impossible_samples_drawn_without_truncation_are_counted_and_not_run(tmp_path):
    """tan phi ~ N(0.8, 0.5) with `truncate: false`: the samples drawn at or below 0 are not run,
    carry their error, are counted in summary.csv and in one line on stderr; P_f is that of the others.
    (Before, they ran and gave a negative FS counted as a failure.)"""
    outcome, out = _sweep(_config(tmp_path, _wide_friction(2000, truncate=False)), tmp_path, "--workers", "1")
    samples = pd.read_csv(out / "planar_block" / "samples.csv", keep_default_na=False, na_values=["nan", ""])
    summary = pd.read_csv(out / "planar_block" / "summary.csv").set_index("quantity")["value"]
    bad = samples["strength.tan_friction"] <= 0.0
    assert 60 < bad.sum() < 160  # 5.5 % of 2000 = 110
    assert samples.loc[bad, "error"].str.startswith("impossible input: strength.tan_friction = -").all()
    assert samples.loc[bad, "factor_of_safety"].isna().all() and samples.loc[~bad, "error"].isna().all()
    assert summary["impossible_samples"] == bad.sum() and summary["failed_runs"] == 0
    assert summary["valid_samples"] == 2000 - bad.sum()
    fs = samples.loc[~bad, "factor_of_safety"]
    assert summary["probability_of_failure"] == pytest.approx((fs < 1.0).mean(), rel=1e-12)
    line = (
        f"{bad.sum()} of 2000 samples have impossible inputs (strength.tan_friction outside > 0: {bad.sum()})"
    )
    assert line in outcome.output


def test_inputs_are_truncated_to_their_range_by_default_and_the_truncation_recorded(tmp_path):
    """tan phi ~ N(0.8, 0.5) truncated at 0 (the default): no impossible sample; summary.csv records
    the bound and the probability left out, Phi(-1.6) = 0.0548; P_f is the truncated normal's closed
    form P(tan phi < tan 35 | tan phi > 0) = 0.3873 within 4 standard errors (measured 0.3834 at 10^4
    Monte Carlo samples, 0.8 SE); the FS at the mean inputs is the truncated mean's, 0.85868 / tan 35
    (rel 1e-9); beta from P_f is -Phi^-1(P_f); convergence.csv ends on the whole study's values."""
    outcome, out = _sweep(_config(tmp_path, _wide_friction(10_000)), tmp_path, "--workers", "1")
    summary = pd.read_csv(out / "planar_block" / "summary.csv").set_index("quantity")
    value = summary["value"]
    tan_psi = math.tan(math.radians(35.0))
    cut = norm.cdf(-1.6)
    assert value["impossible_samples"] == 0 and value["valid_samples"] == 10_000
    assert value["truncation.strength.tan_friction.min"] == 0.0
    assert value["truncation.strength.tan_friction.probability_cut"] == pytest.approx(cut, rel=1e-12)
    assert "truncation.strength.tan_friction.max" not in value  # no upper bound
    exact = (norm.cdf((tan_psi - 0.8) / 0.5) - cut) / (1.0 - cut)
    assert abs(value["probability_of_failure"] - exact) <= 4 * value["standard_error"]
    assert value["pf_ci_low"] <= exact <= value["pf_ci_high"]
    truncated_mean = 0.8 + 0.5 * norm.pdf(-1.6) / norm.sf(-1.6)
    assert value["fs_at_mean_inputs"] == pytest.approx(truncated_mean / tan_psi, rel=1e-9)
    assert value["reliability_index_pf"] == pytest.approx(-norm.ppf(value["probability_of_failure"]))
    assert "truncated to > 0, which leaves out 0.0548 of its probability" in outcome.output
    convergence = pd.read_csv(out / "planar_block" / "convergence.csv")
    assert convergence["samples"].iloc[-1] == 10_000
    assert convergence["probability_of_failure"].iloc[-1] == value["probability_of_failure"]
    assert convergence["mean_fs"].iloc[-1] == pytest.approx(value["mean_fs"], rel=1e-12)
    assert (out / "planar_block" / "convergence.png").stat().st_size > 10_000


def test_no_failure_in_a_large_study_gives_the_exact_upper_bound(tmp_path):
    """configs/sweeps/paper_slope_le.yaml: 10^5 samples, none below FS 1: P_f = 0, its 95 % interval
    [0, 1 - 0.025^(1/n)] = [0, 3.69e-5] (Clopper-Pearson, two-sided), beta from P_f infinite and at
    least 3.96 at 95 %; the moment betas 6.47 and 9.07."""
    outcome, out = _sweep(ROOT / "configs" / "sweeps" / "paper_slope_le.yaml", tmp_path, "--workers", "1")
    value = pd.read_csv(out / "paper_slope_le" / "summary.csv").set_index("quantity")["value"]
    assert value["probability_of_failure"] == 0.0 and value["pf_ci_low"] == 0.0
    assert value["pf_ci_high"] == pytest.approx(1.0 - 0.025 ** (1.0 / 100_000), rel=1e-9)
    assert value["reliability_index_pf"] == math.inf
    assert value["reliability_index_pf_lower_bound"] == pytest.approx(-norm.ppf(3.6888e-5), abs=1e-3)
    assert "P_f = 0 (95 % CI 0 to 3.69e-05)" in outcome.output


@pytest.mark.parametrize("form", ["active", "passive"])
def test_a_planar_study_with_an_uncertain_bolt_capacity(tmp_path, form):
    """The planar block with tan phi = 0.8 and a bolt along the plane (angle 0) whose capacity is a grid
    axis: W = 1/2 gamma H^2 (cot psi_p - cot psi_f), N = W cos psi_p, D = W sin psi_p, and per sample
    FS = N tan phi / (D - T) (active) or (N tan phi + T) / D (passive) (1e-12); T = 0 is unsupported."""
    data = _planar(3, 3)
    data.pop("variables")
    data["base"]["support"] = {"force_kN_per_m": 0.0, "angle_deg": 0.0, "form": form}
    data["sampling"] = {"method": "grid"}
    forces_kn = [0.0, 500.0, 1500.0]
    data["grid"] = [{"path": "support.force_kN_per_m", "values": forces_kn}]
    _, out = _sweep(_config(tmp_path, data), tmp_path)
    samples = pd.read_csv(out / "planar_block" / "samples.csv").sort_values("support.force_kN_per_m")
    psi, face = math.radians(35.0), math.radians(60.0)
    weight = 0.5 * 26e3 * 20.0**2 * (1 / math.tan(psi) - 1 / math.tan(face))
    n, d = weight * math.cos(psi), weight * math.sin(psi)
    t = np.array(forces_kn) * 1e3
    expected = n * 0.8 / (d - t) if form == "active" else (n * 0.8 + t) / d
    assert samples["factor_of_safety"].to_numpy() == pytest.approx(expected, rel=1e-12)
    assert expected[0] == pytest.approx(0.8 / math.tan(psi), rel=1e-12)


def test_a_scene_that_cannot_stand_fails_and_one_with_an_unsupported_block_is_invalid(tmp_path):
    """The block on its 30 deg plane, on a grid of friction (20 deg: it cannot stand under its own
    strength; 40 deg: it stands) and of where it lies (on the plane, or beyond the plane's end: nothing
    holds it). The block that slides gets its FS < 1 (tan 20 / tan 30 = 0.630, from the elastic start)
    and counts as below one at its grid point; the one beyond the plane falls even with every strength
    x 1e6, so both samples there are invalid, each with its reason in samples.csv and summary.csv; 2 of
    4 samples without an FS is more than 10 %: one line on stderr says so."""
    scene = _config(tmp_path, fc.block_on_plane(fc.MOHR_COULOMB, 0.8, 0.2), "scene.yaml")
    study = {
        "name": "unsupported",
        "base": {"kind": "scene_fos", "scene": str(scene)},
        "grid": [
            {"path": "joint_laws.joint.friction_deg", "values": [20.0, 40.0]},
            {"path": "blocks.1.rectangle_m.x_m", "values": [-0.8, 2.0]},
        ],
        "sampling": {"method": "grid"},
        "batch_size": 4,
    }
    outcome, out = _sweep(_config(tmp_path, study), tmp_path, "--workers", "1")
    samples = pd.read_csv(out / "unsupported" / "samples.csv", keep_default_na=False, na_values=["nan", ""])
    beyond = samples["blocks.1.rectangle_m.x_m"] == 2.0
    assert (samples.loc[beyond, "outcome"] == "invalid").all()
    assert samples.loc[beyond, "error"].str.contains("key 'blocks': no equilibrium even with every").all()
    assert samples.loc[beyond, "error"].str.contains("block 'slider' moved").all()
    on_plane = samples[~beyond].set_index("joint_laws.joint.friction_deg")
    assert (on_plane["outcome"] == "valid").all()
    tan30 = math.tan(math.radians(30.0))
    assert on_plane.loc[20.0, "factor_of_safety"] == pytest.approx(
        math.tan(math.radians(20.0)) / tan30, rel=0.02
    )
    assert on_plane.loc[40.0, "factor_of_safety"] > 1.0
    summary = pd.read_csv(out / "unsupported" / "summary.csv").set_index("quantity")["value"]
    assert summary["valid_samples"] == 2 and summary["invalid_samples"] == 2 and summary["failed_runs"] == 0
    assert "probability_of_failure" not in summary.index  # a grid is no sample of a distribution
    chart = pd.read_csv(out / "unsupported" / "fs_against_parameter.csv")
    assert list(chart["runs"]) == [1, 1, 1, 1] and list(chart["excluded"]) == [0, 1, 0, 1]
    assert list(chart["below_one"]) == [1, 0, 0, 0]
    rows = [f"invalid_sample.{k}.blocks" for k in samples.index[beyond]]
    assert all(row in summary.index and math.isnan(summary[row]) for row in rows)  # no realization: no seed
    warning = [line for line in outcome.output.splitlines() if "warning: 2 of 4 samples (50 %" in line]
    assert len(warning) == 1 and "more than 10 %" in warning[0] and "2 invalid" in warning[0]


def test_an_invalid_realization_is_listed_with_its_seed():
    """A study with a realization variable: each invalid sample's row in summary.csv holds its seed and
    the key its error names; a valid sample and a failed run have none."""
    samples = pd.DataFrame(
        {
            "blocks.0.rock_mass.seed": [11.0, 22.0, 33.0],
            "factor_of_safety": [1.2, math.nan, math.nan],
            "error": ["", "SimulationError: key 'blocks': no equilibrium ...", "ValueError: engine"],
            "outcome": ["valid", "invalid", "failed_run"],
        },
        index=pd.RangeIndex(3, name="sample"),
    )
    inputs = report.Inputs([("blocks.0.rock_mass.seed", design.marginal("realization"))], {}, {})
    rows = report.invalid_rows(samples, Outcomes.of(samples), inputs)
    assert rows.values.tolist() == [["invalid_sample.1.blocks", 22.0, "seed"]]


def _warning_model(inputs: pd.DataFrame) -> pd.DataFrame:
    """A model (at module level: a worker process unpickles it) that warns on every sample."""
    for sample in inputs.index:
        warnings.warn(f"sample {sample % 2} overflowed", RuntimeWarning, stacklevel=1)
    return pd.DataFrame({"fs": np.ones(len(inputs))}, index=inputs.index)


def test_warnings_raised_in_worker_processes_reach_the_command_one_line_each(tmp_path, capfd):
    """Two workers, two batches, four warnings of two messages: the command shows each message once,
    one line, as it shows its own; no worker writes to stderr itself."""
    design = pd.DataFrame({"x": np.arange(4.0)}, index=pd.Index(range(4), name="sample"))
    with reported("sweep"):
        run_batches(_warning_model, design, tmp_path / "store", 2, workers=2)
    assert sorted(capfd.readouterr().err.splitlines()) == [
        "bbmc sweep: warning: RuntimeWarning: sample 0 overflowed",
        "bbmc sweep: warning: RuntimeWarning: sample 1 overflowed",
    ]
