"""`bbmc run` for a 3D scene (docs/reference/scene3d-format.md): build it (`bbmc.slope.scene3d`), run
it (`bbmc.dem3d.scene_run`), and gather its tables and figures.

Writes into <results>/run/<scene name>/: history.csv (the monitors at every record step), summary.csv
(steps, time step, physical time, why it stopped, the unbalanced-force ratio and the largest
displacement at the end), blocks.csv and contacts.csv (`bbmc.dem3d.tables`), history.png,
mechanism.png (the blocks at the start and the end, `bbmc.outputs.figures3d`) and provenance.json;
with --vtk, vtk/ (`bbmc.outputs.vtk3d`: blocks and contacts of every record, for ParaView).
"""

from __future__ import annotations

from pathlib import Path

from bbmc.dem3d.scene_run import RunOutcome3D, run_scene
from bbmc.dem3d.tables import block_table, contact_table
from bbmc.io import StageResult
from bbmc.outputs.figures import history_figure
from bbmc.outputs.figures3d import mechanism_figure
from bbmc.outputs.vtk3d import Series3D
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

NAME = "run"
Config = Scene3D


def run(
    scene: Scene3D, config_path: Path, progress: ProgressCallback = ignore, vtk: bool = False
) -> tuple[StageResult, RunOutcome3D]:
    """Build the 3D scene (checking every reference and shape), run it, tabulate and draw."""
    built = build_scene3d(scene)
    model, names = built.model, built.names
    series = None
    if vtk:
        series = Series3D(model, names=names, groups=built.group_names, law_names=built.joint_type_names)
    outcome = run_scene(built, scene, progress, series.record if series else None)
    stop = scene.solver.stop
    limit = stop.unbalanced_force_ratio if stop else None
    tables = {
        "history": outcome.history,
        "summary": outcome.summary(),
        "blocks": block_table(model, built.start, names, built.group_names),
        "contacts": contact_table(model, built.joint_type_names, names),
    }
    figures = {
        "history": history_figure(outcome.history, scene.figure_dpi, limit),
        "mechanism": mechanism_figure(model, built.start, scene.figure_dpi, names),
    }
    files = series.collections() if series else {}
    return StageResult(tables=tables, figures=figures, files=files), outcome
