"""The command line: help with examples, and one clear line + exit 2 + nothing written on bad input."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from bbmc.cli import main
from bbmc.scene.schema import Scene
from bbmc.stages import audit, fit, joint, joints, mc, shear, slope, sweep
from stage_runs import CONFIGS, PAPER, config_copy, delete_key, run_stage, set_key


@pytest.mark.parametrize("command", [[], ["fit"], ["mc"], ["audit"]])
def test_help_shows_an_example(command: list[str]) -> None:
    outcome = CliRunner().invoke(main, [*command, "--help"])
    assert outcome.exit_code == 0
    assert "Example" in outcome.output
    assert "--config" in outcome.output or not command


def _assert_refused(outcome, results: Path, *fragments: str) -> None:
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1, outcome.stderr
    assert "Traceback" not in outcome.output + outcome.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    assert not results.exists() or not any(results.iterdir()), "something was written"


BAD_VALUES = [
    ("mc", "joint.jcs_MPa", -3.31, "joint.jcs_MPa", "greater than 0"),
    ("mc", "joint.jrc", 25, "joint.jrc", "less than or equal to 20"),
    ("mc", "joint.phi_b_deg", "32", "joint.phi_b_deg", "valid number"),
    ("mc", "joint.phi_max_deg", 30.0, "joint", "phi_max_deg"),
    ("mc", "errata.lg_e", "fixed", "errata.lg_e", "'paper' or 'corrected'"),
    ("mc", "grid.points", 1, "grid.points", "greater than or equal to 2"),
    ("mc", "tangent_stresses_MPa", [0.05, 0.0], "tangent_stresses_MPa", "> 0"),
    ("fit", "power_law_method", "spline", "power_law_method", "log-log"),
    ("fit", "figure_dpi", 12.5, "figure_dpi", "valid integer"),
    ("fit", "data.table1", "/nonexistent/table1.csv", "data.table1", "file not found"),
]


@pytest.mark.parametrize(("stage", "key", "value", "named", "message"), BAD_VALUES)
def test_bad_value_is_refused(tmp_path, stage, key, value, named, message) -> None:
    config = config_copy(tmp_path, stage, set_key(key, value))
    results = tmp_path / "results"
    _assert_refused(run_stage(stage, results, config), results, str(config), f"'{named}'", message)


def test_missing_key_is_named(tmp_path) -> None:
    config = config_copy(tmp_path, "mc", delete_key("joint.jcs_MPa"))
    results = tmp_path / "results"
    _assert_refused(run_stage("mc", results, config), results, "'joint.jcs_MPa'", "missing")


COMMANDS = {  # each config command: its config file and the model it is checked against
    "fit": ("fit.yaml", fit.Config),
    "mc": ("mc.yaml", mc.Config),
    "audit": ("audit.yaml", audit.Config),
    "shear": ("shear.yaml", shear.Config),
    "slope": ("slope.yaml", slope.Config),
    "joint": ("joint.yaml", joint.Config),
    "joints": ("joints.yaml", joints.Config),
    "sweep": ("sweeps/planar_block.yaml", sweep.Config),
    "run": ("scenes/incline.yaml", Scene),
    "fos": ("scenes/incline.yaml", Scene),
}


@pytest.mark.parametrize("command", COMMANDS)
def test_every_missing_key_is_named_at_once(tmp_path, command: str) -> None:
    """A config short of two required keys names both in its one line (not one per run)."""
    name, model = COMMANDS[command]
    data = yaml.safe_load((CONFIGS / name).read_text())
    gone = [key for key, field in model.model_fields.items() if field.is_required() and key in data][:2]
    assert len(gone) == 2, gone
    for key in gone:
        del data[key]
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(data))
    results = tmp_path / "results"
    outcome = CliRunner().invoke(main, [command, str(config), "--results", str(results)])
    _assert_refused(outcome, results, str(config), f"keys '{gone[0]}', '{gone[1]}': missing")


def test_unknown_key_suggests_the_closest(tmp_path) -> None:
    def typo(data):
        data["joint"]["jcs_Mpa"] = data["joint"].pop("jcs_MPa")

    config = config_copy(tmp_path, "mc", typo)
    results = tmp_path / "results"
    _assert_refused(run_stage("mc", results, config), results, "'joint.jcs_Mpa'", "did you mean 'jcs_MPa'")


def test_missing_config_file(tmp_path) -> None:
    results = tmp_path / "results"
    _assert_refused(run_stage("fit", results, tmp_path / "nope.yaml"), results, "nope.yaml", "not found")


@pytest.mark.parametrize("text", ["data: [unclosed", "- a list\n- not a mapping\n", ""])
def test_invalid_yaml(tmp_path, text: str) -> None:
    config = tmp_path / "broken.yaml"
    config.write_text(text)
    results = tmp_path / "results"
    _assert_refused(run_stage("mc", results, config), results, "broken.yaml")


def test_bad_row_in_an_input_table_names_file_line_and_column(tmp_path) -> None:
    table = tmp_path / "table3.csv"
    shutil.copy(PAPER / "table3_numerical_tests.csv", table)
    lines = table.read_text().splitlines()
    lines[3] = "-" + lines[3]
    table.write_text("\n".join(lines) + "\n")
    config = config_copy(tmp_path, "mc", set_key("data.table3", str(table)))
    results = tmp_path / "results"
    _assert_refused(run_stage("mc", results, config), results, "table3.csv", "line 4", "'sigma_n_MPa'", "> 0")


def test_audit_refuses_a_bad_referenced_config(tmp_path) -> None:
    bad_mc = config_copy(tmp_path, "mc", set_key("joint.jcs_MPa", -1.0))
    config = config_copy(tmp_path, "audit", set_key("mc_config", str(bad_mc)))
    results = tmp_path / "results"
    _assert_refused(run_stage("audit", results, config), results, "mc.yaml", "'joint.jcs_MPa'")
