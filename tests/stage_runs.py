"""Run stages into a temporary folder through the real command line (shared by the test modules)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pandas as pd
import yaml
from click.testing import CliRunner, Result

from bbmc.cli import main

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ROOT / "configs"
PAPER = ROOT / "data" / "paper"


def refused(outcome: Result, out: Path, *fragments: str) -> str:
    """The one line of a refused command (exit status 2, no traceback, `out` not written), which must
    hold every one of `fragments`."""
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1, outcome.stderr
    assert "Traceback" not in outcome.output
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    assert not out.exists(), "something was written"
    return lines[0]


def run_stage(stage: str, results: Path, config: Path | None = None) -> Result:
    """`bbmc <stage> --config <config> --results <results>`; the result carries exit code and output."""
    config = config or CONFIGS / f"{stage}.yaml"
    return CliRunner().invoke(main, [stage, "--config", str(config), "--results", str(results)])


def stage_folder(tmp_path_factory, stage: str, edit) -> Path:
    """`bbmc <stage>` run with an `edit`ed copy of its config into a fresh temporary folder; the folder
    it wrote (the run must succeed)."""
    folder = tmp_path_factory.mktemp(stage)
    outcome = run_stage(stage, folder / "results", config_copy(folder, stage, edit))
    assert outcome.exit_code == 0, outcome.output
    return folder / "results" / stage


def paper_table(name: str) -> pd.DataFrame:
    return pd.read_csv(PAPER / name)


PIT_SETS_CSV = """set,dip_deg,dip_direction_deg,pole_trend_deg,pole_plunge_deg,fisher_k,alpha95_deg
S1,35.95,160.53,340.53,54.05,55.42,2.24
S2,59.80,216.50,36.50,30.20,30.30,2.82
S3,54.73,129.41,309.41,35.27,45.52,2.47
S4,77.40,13.40,193.40,12.60,84.51,2.32
random,,,,,,
"""  # the pit survey's sets as `bbmc kinematics configs/kinematics.yaml` writes them (rounded)


def _sets_table(tmp_path: Path) -> Path:
    path = tmp_path / "sets.csv"
    path.write_text(PIT_SETS_CSV)
    return path


def config_copy(tmp_path: Path, stage: str, edit) -> Path:
    """A copy of the stage's config in tmp_path with its data paths made absolute, then `edit`ed."""
    data = yaml.safe_load((CONFIGS / f"{stage}.yaml").read_text())
    for section in ("data",):
        for key, value in data.get(section, {}).items():
            data[section][key] = str((CONFIGS / value).resolve())
    for key in ("fit_config", "mc_config"):
        if key in data:
            data[key] = str((CONFIGS / data[key]).resolve())
    for sheet in data.get("surveys", []):
        sheet["file"] = str((CONFIGS / sheet["file"]).resolve())
    if "sets_file" in data.get("combinations", {}):  # a bbmc kinematics result: a copy of its form here
        data["combinations"]["sets_file"] = str(_sets_table(tmp_path))
    edit(data)
    path = tmp_path / f"{stage}.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def set_key(path: str, value):
    def edit(data):
        keys = path.split(".")
        for key in keys[:-1]:
            data = data[key]
        data[keys[-1]] = value

    return edit


def delete_key(path: str):
    def edit(data):
        keys = path.split(".")
        for key in keys[:-1]:
            data = data[key]
        del data[keys[-1]]

    return edit


def field_script(name: str):
    """The script data/field/<name>.py that draws a synthetic survey, loaded as a module."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "data" / "field" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
