"""`bbmc run` for a 3D scene (docs/reference/scene3d-format.md): build it (`bbmc.slope.scene3d`), run
it (`bbmc.dem3d.scene_run`), and gather its tables and figures.

Writes into <results>/run/<scene name>/: history.csv (the monitors at every record step), summary.csv
(steps, time step, physical time, why it stopped, the unbalanced-force ratio and the largest
displacement at the end), history.png and provenance.json.
"""

from __future__ import annotations

from pathlib import Path

from bbmc.config import ConfigError
from bbmc.dem3d.scene_run import RunOutcome3D, run_scene
from bbmc.io import StageResult
from bbmc.outputs.figures import history_figure
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

NAME = "run"
Config = Scene3D


def run(
    scene: Scene3D, config_path: Path, progress: ProgressCallback = ignore, vtk: bool = False
) -> tuple[StageResult, RunOutcome3D]:
    """Build the 3D scene (checking every reference and shape), run it, tabulate and draw."""
    if vtk:
        raise ConfigError(f"{config_path}: --vtk: not yet for 3D scenes")
    outcome = run_scene(build_scene3d(scene), scene, progress)
    stop = scene.solver.stop
    limit = stop.unbalanced_force_ratio if stop else None
    tables = {"history": outcome.history, "summary": outcome.summary()}
    figures = {"history": history_figure(outcome.history, scene.figure_dpi, limit)}
    return StageResult(tables=tables, figures=figures), outcome
