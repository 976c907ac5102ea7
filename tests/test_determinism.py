"""The same config gives bit-identical CSVs: each stage run twice into two temporary folders.

The bench's tables are left out: wall times differ from run to run by nature (their readings do not:
`test_bench` checks each economy to the bit)."""

from __future__ import annotations

from pathlib import Path

import pytest

from stage_runs import config_copy, run_stage


def _short_slope(data):
    data["run"]["duration_s"] = 0.3
    data["limit_equilibrium"]["dips_deg"] = [15.0, 40.0]
    data["limit_equilibrium"]["tolerance_deg"] = 1.0
    data["sensitivity"]["dips_deg"] = [20.0, 40.0]
    data["animation_frames"] = 0
    data["figure_dpi"] = 50


def _twice(tmp_path: Path, stage: str, config: Path | None) -> tuple[Path, Path]:
    folders = []
    for attempt in ("first", "second"):
        outcome = run_stage(stage, tmp_path / attempt, config)
        assert outcome.exit_code == 0, outcome.output
        folders.append(tmp_path / attempt / stage)
    return folders[0], folders[1]


@pytest.mark.parametrize("stage", ["fit", "mc", "audit", "slope"])
def test_same_config_gives_bit_identical_csvs(tmp_path, stage):
    config = config_copy(tmp_path, "slope", _short_slope) if stage == "slope" else None
    first, second = _twice(tmp_path, stage, config)
    tables = sorted(p.relative_to(first) for p in first.rglob("*.csv"))
    assert tables, f"{stage} wrote no CSV"
    assert tables == sorted(p.relative_to(second) for p in second.rglob("*.csv"))
    for table in tables:
        assert (first / table).read_bytes() == (second / table).read_bytes(), f"{stage}/{table} differs"
