"""What `bbmc run` says about how a run ended, and about the results it replaces."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import yaml
from click.testing import CliRunner

from bbmc.cli import main

FIRST_SLOPE = Path(__file__).parent.parent / "docs" / "examples" / "first-slope" / "slope.yaml"


def _run(path: Path, results: Path):
    return CliRunner().invoke(main, ["run", str(path), "--results", str(results)])


def test_a_run_that_ends_before_its_stop_says_what_still_moves(tmp_path):
    """200 steps are too few for the slope to settle: one line names the step, the unbalanced-force
    ratio, the kinetic energy's trend and the fastest block, and summary.csv says the steps ran out."""
    scene = yaml.safe_load(FIRST_SLOPE.read_text())
    scene["solver"]["steps"] = 200
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(scene))
    outcome = _run(path, tmp_path)
    assert outcome.exit_code == 0, outcome.output
    lines = [line for line in outcome.output.splitlines() if "solver.steps ran out" in line]
    assert len(lines) == 1
    assert "step 200" in lines[0] and "unbalanced-force ratio" in lines[0] and "moves at" in lines[0]
    assert "rising" in lines[0] or "falling" in lines[0]
    summary = pd.read_csv(tmp_path / "run" / "first_slope" / "summary.csv").set_index("quantity")["value"]
    assert summary["stopped_by_steps"] == 1 and summary["stopped_by_equilibrium"] == 0


def test_a_run_that_meets_its_stop_says_nothing_of_steps(tmp_path):
    outcome = _run(FIRST_SLOPE, tmp_path)
    assert outcome.exit_code == 0 and "solver.steps ran out" not in outcome.output
    summary = pd.read_csv(tmp_path / "run" / "first_slope" / "summary.csv").set_index("quantity")["value"]
    assert summary["stopped_by_steps"] == 0 and summary["stopped_by_equilibrium"] == 1


def test_results_of_another_file_with_the_same_name_are_replaced_with_a_note(tmp_path):
    """A renamed copy of a scene that keeps its `name` writes to the same folder: it says whose results
    it replaced; the same file run again replaces its own without a word."""
    copy = tmp_path / "copy.yaml"
    copy.write_text(FIRST_SLOPE.read_text())
    assert "held the results of" not in _run(FIRST_SLOPE, tmp_path).output
    assert "held the results of" not in _run(FIRST_SLOPE, tmp_path).output
    outcome = _run(copy, tmp_path)
    assert outcome.exit_code == 0
    notes = [line for line in outcome.output.splitlines() if "held the results of" in line]
    assert len(notes) == 1 and str(FIRST_SLOPE) in notes[0] and "copy.yaml" in notes[0]
