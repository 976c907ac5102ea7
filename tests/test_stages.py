"""Stages as files: what they write, byte-identical reruns, all-or-nothing writes, the errata switch."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from bbmc import io as bbmc_io
from stage_runs import config_copy, run_stage, set_key

EXPECTED = {
    "fit": {"table1_fits.csv", "fig1_curves.csv", "fig1.png", "fig2.png", "provenance.json"},
    "mc": {
        "mc_grid.csv",
        "table3_mc.csv",
        "tangent_lines.csv",
        "stiffness_curves.csv",
        "envelope.png",
        "phi_c.png",
        "stiffness_laws.png",
        "provenance.json",
    },
    "audit": {"audit.csv", "summary.csv", "provenance.json"},
}


@pytest.mark.parametrize("stage", ["fit", "mc", "audit"])
def test_stage_writes_its_files_and_provenance(tmp_path, stage: str) -> None:
    outcome = run_stage(stage, tmp_path)
    assert outcome.exit_code == 0, outcome.output
    assert {p.name for p in (tmp_path / stage).iterdir()} == EXPECTED[stage]
    record = json.loads((tmp_path / stage / "provenance.json").read_text())
    assert record["stage"] == stage
    assert record["versions"]["numba"] != "not installed"
    assert len(record["config_sha256"]) == 64
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")], "staging folders left behind"


@pytest.mark.parametrize("stage", ["fit", "mc", "audit"])
def test_same_config_gives_identical_csvs(tmp_path, stage: str) -> None:
    for run in ("a", "b"):
        assert run_stage(stage, tmp_path / run).exit_code == 0
    for csv in sorted((tmp_path / "a" / stage).glob("*.csv")):
        assert csv.read_bytes() == (tmp_path / "b" / stage / csv.name).read_bytes(), csv.name


def test_failed_write_leaves_previous_results_untouched(tmp_path, monkeypatch) -> None:
    assert run_stage("fit", tmp_path).exit_code == 0
    before = {p.name: p.read_bytes() for p in (tmp_path / "fit").iterdir() if p.suffix == ".csv"}

    def broken(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(bbmc_io.Figure, "savefig", broken)
    outcome = run_stage("fit", tmp_path)
    assert outcome.exit_code == 1
    assert outcome.stderr.strip() == "bbmc fit: error: cannot write results: disk full"
    after = {p.name: p.read_bytes() for p in (tmp_path / "fit").iterdir() if p.suffix == ".csv"}
    assert after == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_errata_switch_gives_the_corrected_values(tmp_path) -> None:
    """`corrected` changes exactly the quantities each erratum names, by the audit's factors."""

    def all_corrected(data):
        for key in data["errata"]:
            data["errata"][key] = "corrected"

    paper_run = run_stage("mc", tmp_path / "paper")
    fixed_run = run_stage("mc", tmp_path / "fixed", config_copy(tmp_path, "mc", all_corrected))
    assert paper_run.exit_code == 0 and fixed_run.exit_code == 0
    paper = pd.read_csv(tmp_path / "paper" / "mc" / "table3_mc.csv")
    fixed = pd.read_csv(tmp_path / "fixed" / "mc" / "table3_mc.csv")
    lg_e = np.log10(np.e)
    assert np.allclose(fixed["K_n_MPa_per_mm"] / paper["K_n_MPa_per_mm"], 0.3434 / lg_e)
    assert np.allclose(fixed["K_st_corrected_MPa_per_mm"], paper["K_st_corrected_MPa_per_mm"])
    hyperbola = fixed["K_si_MPa_per_mm"] * np.clip(1 - fixed["tau_MPa"] / fixed["tau_ult_fit_MPa"], 0, 1) ** 2
    assert np.allclose(fixed["K_st_uncorrected_MPa_per_mm"], hyperbola)
    assert (fixed["K_st_simplified_MPa_per_mm"] > 2 * paper["K_st_simplified_MPa_per_mm"]).all()
    assert not np.allclose(fixed["Phi_deg"], paper["Phi_deg"])


def test_fitted_coefficients_reproduce_the_printed_K_si(tmp_path) -> None:
    """`stiffness_coefficients: fitted` uses our regressions; K_si matches the printed fit to 4 digits."""
    config = config_copy(tmp_path, "mc", set_key("stiffness_coefficients", "fitted"))
    assert run_stage("mc", tmp_path / "fitted", config).exit_code == 0
    assert run_stage("mc", tmp_path / "printed").exit_code == 0
    fitted = pd.read_csv(tmp_path / "fitted" / "mc" / "table3_mc.csv")
    printed = pd.read_csv(tmp_path / "printed" / "mc" / "table3_mc.csv")
    assert np.allclose(fitted["K_si_MPa_per_mm"], printed["K_si_MPa_per_mm"], rtol=1e-4)
