"""The same config gives bit-identical CSVs: each stage run twice into two temporary folders.

The bench's tables are left out: wall times differ from run to run by nature (their readings do not:
`test_bench` checks each economy to the bit)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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


@pytest.mark.parametrize("stage", ["fit", "mc", "audit", pytest.param("slope", marks=pytest.mark.slow)])
def test_same_config_gives_bit_identical_csvs(tmp_path, stage):
    config = config_copy(tmp_path, "slope", _short_slope) if stage == "slope" else None
    first, second = _twice(tmp_path, stage, config)
    tables = sorted(p.relative_to(first) for p in first.rglob("*.csv"))
    assert tables, f"{stage} wrote no CSV"
    assert tables == sorted(p.relative_to(second) for p in second.rglob("*.csv"))
    for table in tables:
        assert (first / table).read_bytes() == (second / table).read_bytes(), f"{stage}/{table} differs"


def _run_on(scene: dict, threads: int):
    """The scene run to its end on `threads` threads (the threaded cycle even on a small scene)."""
    from bbmc.dem.model import build_model
    from bbmc.dem.solver import simulate
    from bbmc.scene.schema import Scene

    scene = {**scene, "solver": {**scene["solver"], "threads": threads}}
    return simulate(build_model(Scene.model_validate(scene, strict=False), Path(f"<{scene['name']}>"))).state


@pytest.mark.parametrize("paper_scene", ["shear", "slope"])
def test_one_and_two_threads_give_bit_identical_results(monkeypatch, paper_scene):
    """Each contact's force is computed alone and each block adds its contacts' forces in contact order,
    so the paper's shear box (its first Table 3 test) and B-B slope end with the same block positions
    and contact stresses to the bit on one thread and on two (the threaded path taken on these small
    scenes too)."""
    from bbmc.bench.paper_scenes import ShearScene, SlopeScene
    from bbmc.dem import kernels
    from bbmc.dem import layout as L

    monkeypatch.setattr(kernels, "THREADED_FROM_CONTACTS", 0)
    configs = Path(__file__).resolve().parents[1] / "configs"
    if paper_scene == "shear":
        bench = ShearScene(configs / "shear.yaml")
        scene = bench._scene(bench.defaults(), *bench.loads[0])
    else:
        bench = SlopeScene(configs / "slope.yaml", "barton_bandis")
        scene = bench._scene(bench.defaults())
    one, two = _run_on(scene, 1), _run_on(scene, 2)
    assert two.threads == min(2, kernels.thread_count(None))
    assert one.step == two.step > 0
    assert np.array_equal(one.blocks, two.blocks)
    assert np.array_equal(one.subs[:, [L.SN, L.TAU]], two.subs[:, [L.SN, L.TAU]])
    assert np.array_equal(one.subs, two.subs, equal_nan=True)


def test_threads_option_sets_the_scene_threads_and_changes_no_result(tmp_path, monkeypatch):
    """`bbmc run --threads N` runs the scene on N threads (the scene's solver.threads, kept in
    provenance.json) and writes the same tables for 1 and 2, the threaded path taken on this small
    scene too."""
    from click.testing import CliRunner

    from bbmc.cli import main
    from bbmc.dem import kernels

    monkeypatch.setattr(kernels, "THREADED_FROM_CONTACTS", 0)
    scene = Path(__file__).resolve().parents[1] / "configs" / "scenes" / "toppling_column.yaml"
    written = {}
    for threads in (1, 2):
        out = tmp_path / str(threads)
        outcome = CliRunner().invoke(
            main, ["run", str(scene), "--results", str(out), "--threads", str(threads)]
        )
        assert outcome.exit_code == 0, outcome.output
        (written[threads],) = (out / "run").iterdir()
        provenance = json.loads((written[threads] / "provenance.json").read_text())
        assert provenance["config"]["solver"]["threads"] == threads
    for table in ("blocks.csv", "contacts.csv", "history.csv"):
        assert (written[1] / table).read_bytes() == (written[2] / table).read_bytes(), table


def test_a_process_limited_to_one_thread_runs_every_scene_on_one(monkeypatch):
    """A sweep's worker process calls `limit_threads(1)`: whatever a scene asks, its runs use one thread."""
    from bbmc.dem import kernels

    monkeypatch.setattr(kernels, "_thread_limit", kernels._thread_limit)
    assert kernels.thread_count(1) == 1
    kernels.limit_threads(1)
    assert kernels.thread_count(None) == kernels.thread_count(8) == 1
