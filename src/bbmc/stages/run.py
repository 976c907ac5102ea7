"""`bbmc run`: run any block scene written in the scene format (docs/scene-format.md).

Writes into <results>/run/<scene name>/: history.csv (the monitors at every record step),
blocks.csv (final state of every block), contacts.csv (final state of every sub-contact),
summary.csv (steps, time, time-step range, contact searches, interpenetration, warnings),
scene.png (bolts coloured by their load), history.png and provenance.json; for a scene with support,
support.csv (each anchor and each grouted bolt's crossing of a joint: its force, capacity and state;
`bbmc.dem.support_report`); for a scene with rock bridges, bridges.csv and bridges.png
(`bbmc.dem.bridges`); with --vtk, vtk/ (blocks and sub-contacts of every record
as VTU files and their PVD collections, for ParaView).
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from bbmc.dem.model import Model, build_model
from bbmc.dem.solver import RunResult, initial_state, simulate
from bbmc.io import StageResult
from bbmc.outputs.figures import bridges_figure, history_figure, scene_figure
from bbmc.outputs.vtk import Series
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.schema import Scene

NAME = "run"
Config = Scene


def output_name(scene: Scene, config_path: Path) -> str:
    """The scene's results folder name: its `name`, else the config file's stem."""
    return scene.name or config_path.stem


def run(
    scene: Scene, config_path: Path, progress: ProgressCallback = ignore, vtk: bool = False
) -> tuple[StageResult, RunResult]:
    """Build the scene (checking every reference), run it, and gather its tables and figures; with
    `vtk`, also the ParaView series of every record (`bbmc.outputs.vtk`)."""
    model: Model = build_model(scene, config_path)
    initial = initial_state(model).world.copy()
    series = Series(model) if vtk else None
    result = simulate(model, progress, series)
    warnings = pd.DataFrame({"warning": result.warnings}, dtype=object)
    stop = scene.solver.stop
    tables = {
        "history": result.history,
        "blocks": result.blocks,
        "contacts": result.contacts,
        "summary": result.summary,
        "warnings": warnings,
    }
    figures = {
        "scene": scene_figure(
            model,
            initial,
            result.state.world,
            result.state.dof,
            scene.figure_dpi,
            (result.state.blocks, result.state.support),
        ),
        "history": history_figure(
            result.history, scene.figure_dpi, stop.unbalanced_force_ratio if stop else None
        ),
    }
    if len(model.support.names):
        tables["support"] = result.support
    if model.has_bridges:
        tables["bridges"] = result.bridges
        figures["bridges"] = bridges_figure(model, result.state.world, result.bridges, scene.figure_dpi)
    files = series.collections() if series else {}
    return StageResult(tables=tables, figures=figures, files=files), result
