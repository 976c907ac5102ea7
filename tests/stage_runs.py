"""Run stages into a temporary folder through the real command line (shared by the test modules)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
from click.testing import CliRunner, Result

from bbmc.cli import main

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ROOT / "configs"
PAPER = ROOT / "data" / "paper"


def run_stage(stage: str, results: Path, config: Path | None = None) -> Result:
    """`bbmc <stage> --config <config> --results <results>`; the result carries exit code and output."""
    config = config or CONFIGS / f"{stage}.yaml"
    return CliRunner().invoke(main, [stage, "--config", str(config), "--results", str(results)])


def paper_table(name: str) -> pd.DataFrame:
    return pd.read_csv(PAPER / name)
