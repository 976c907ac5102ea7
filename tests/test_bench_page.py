"""docs/benchmarks.md is written from one bench run's folder (`bbmc.bench.page`): its numbers are the
run's CSVs' as rounded, the machine and date are the run's, a replaced run goes to the history page,
and a folder that is not a bench run is one line, exit 2, nothing written."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc.bench.machine import machine_table
from bbmc.bench.page import HISTORY, HISTORY_MARK, main, number
from bbmc.cli import main as bbmc
from bbmc.stages.bench import SECTIONS
from stage_runs import CONFIGS


@pytest.mark.parametrize(
    ("value", "shown"),
    [
        (123456789.4, "123,000,000"),
        (52.345, "52.3"),
        (0.012345, "0.0123"),
        (0.0001234, "1.23e-04"),
        (102054.0, "102,054"),
        (7, "7"),
        (True, "yes"),
        (math.nan, "—"),
        (math.inf, "∞"),
        ("as the reference", "as the reference"),
    ],
)
def test_numbers_are_whole_in_full_and_otherwise_to_three_significant_figures(value, shown):
    assert number(value) == shown


def _run_folder(folder: Path, started: str, rate: float) -> Path:
    """A bench folder of the laws section only, written by hand: laws.csv, machine.csv, provenance."""
    folder.mkdir(parents=True)
    laws = {
        "law": ["peak_shear_strength (eq 9)"],
        "njit_kernel_evals_per_s": [rate],
        "ufunc_evals_per_s": [2.5],
    }
    pd.DataFrame(laws).to_csv(folder / "laws.csv", index=False)
    machine_table(started, started, {"laws": 12.5}).to_csv(folder / "machine.csv", index=False)
    config = {"laws": {"array_size": 2000, "python_loop_size": 200, "repeats": 3}}
    record = {"stage": "bench", "git_commit": "0123456789abcdef", "config": config}
    (folder / "provenance.json").write_text(json.dumps(record))
    return folder


def test_the_page_shows_the_runs_numbers_machine_date_and_settings(tmp_path):
    folder = _run_folder(tmp_path / "bench", "2026-11-26T21:00:00+00:00", 123456789.4)
    target = tmp_path / "docs" / "benchmarks.md"
    assert main([str(folder), str(target)]) == 0
    text = target.read_text()
    machine = dict(pd.read_csv(folder / "machine.csv", dtype=str).values)
    assert "| peak_shear_strength (eq 9) | 2.50 | 123,000,000 |" in text
    assert f"| processor | {machine['cpu_model']} |" in text
    assert "| started (UTC) | 2026-11-26T21:00:00+00:00 |" in text
    assert "`0123456789abcdef`" in text
    assert "| laws | 12.5 s |" in text
    assert "best of 3" in text  # the run's own setting, in the prose
    assert text.count("Not measured in this run") == len(SECTIONS) - 1  # every other section
    assert "—." not in text  # no prose of a section the run left out, with its settings missing


def test_a_rerun_moves_the_page_it_replaces_into_the_history(tmp_path):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / HISTORY).write_text(f"# History\n\n{HISTORY_MARK}\n\n## An older run\n")
    target = docs / "benchmarks.md"
    first = _run_folder(tmp_path / "first", "2026-11-26T21:00:00+00:00", 111.0)
    second = _run_folder(tmp_path / "second", "2026-11-27T09:00:00+00:00", 222.0)
    assert main([str(first), str(target)]) == 0
    assert main([str(first), str(target)]) == 0  # the same run again: nothing to keep
    assert "111" not in (docs / HISTORY).read_text()
    assert main([str(second), str(target)]) == 0
    history = (docs / HISTORY).read_text()
    assert "| 222 |" in target.read_text() and "| 111 |" not in target.read_text()
    assert "## The run started 2026-11-26T21:00:00+00:00 (commit 0123456)" in history
    assert "| peak_shear_strength (eq 9) | 2.50 | 111 |" in history
    assert "### The joint laws' throughput" in history
    assert history.index("2026-11-26T21:00") < history.index("## An older run")


@pytest.mark.parametrize("missing", ["provenance.json", "machine.csv"])
def test_a_folder_without_its_record_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, missing):
    folder = _run_folder(tmp_path / "bench", "2026-11-26T21:00:00+00:00", 1.0)
    (folder / missing).unlink()
    target = tmp_path / "benchmarks.md"
    assert main([str(folder), str(target)]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1 and missing in error
    assert not target.exists()


def test_the_page_of_a_real_bench_run_shows_its_csv(tmp_path):
    config = {"shear_config": str(CONFIGS / "shear.yaml"), "slope_config": str(CONFIGS / "slope.yaml")}
    config["laws"] = {"array_size": 2000, "python_loop_size": 200, "repeats": 1}
    path = tmp_path / "bench.yaml"
    path.write_text(yaml.safe_dump(config))
    args = ["bench", "--config", str(path), "--results", str(tmp_path / "results")]
    outcome = CliRunner().invoke(bbmc, args)
    assert outcome.exit_code == 0, outcome.output
    folder, target = tmp_path / "results" / "bench", tmp_path / "benchmarks.md"
    assert main([str(folder), str(target)]) == 0
    laws, text = pd.read_csv(folder / "laws.csv"), target.read_text()
    for row in laws.itertuples():
        assert (
            f"| {row.law} | {number(row.ufunc_evals_per_s)} | {number(row.njit_kernel_evals_per_s)} |" in text
        )
    started = pd.read_csv(folder / "machine.csv").set_index("key")["value"]["started_utc"]
    assert f"| started (UTC) | {started} |" in text
