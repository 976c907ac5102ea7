"""`bbmc fos` for a 3D scene: its factor of safety by shear-strength reduction
(`bbmc.fos.strength_reduction3d`, the search shared with 2D) with the scene's `fos:` section.

Writes into <results>/fos/<scene name>/: fos.csv (every trial: F, verdict, why, steps, largest
displacement, unbalanced-force ratio, wall time), summary.csv (`quantity,value,unit`, with the row
factor_of_safety), bracketing.png (the trials' F in order), mechanism.png (the blocks at the end of the
lowest unstable trial against the equilibrium, `bbmc.outputs.figures3d`) and provenance.json.
"""

from __future__ import annotations

import time
from pathlib import Path

import pandas as pd

from bbmc.config import ConfigKeyError
from bbmc.dem3d.scene_model import SceneModel, judged_blocks
from bbmc.dem3d.solver import thread_count
from bbmc.fos.result import factor_of_safety_text, trials_table
from bbmc.fos.strength_reduction3d import StrengthReduction3DResult, factor_of_safety_3d
from bbmc.io import StageResult
from bbmc.outputs.figures import trials_figure
from bbmc.outputs.figures3d import mechanism_figure
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

NAME = "fos"
Config = Scene3D


def summary_table(result: StrengthReduction3DResult, scene: Scene3D, seconds: float) -> pd.DataFrame:
    """summary.csv: the factor of safety, its bracket and the search's cost."""
    rows = [
        ("factor_of_safety", result.factor_of_safety, "1"),
        ("bracketed", int(result.bracketed), "1"),
        ("last_stable_factor", result.bracket[0], "1"),
        ("first_unstable_factor", result.bracket[1], "1"),
        ("tolerance", scene.fos.tolerance, "1"),
        ("elastic_start", int(result.start == "elastic"), "1"),
        ("equilibrium_steps", result.equilibrium_steps, "1"),
        ("equilibrium_wall_time", result.equilibrium_seconds, "s"),
        ("time_step", result.dt, "s"),
        ("trials", len(result.trials), "1"),
        ("trial_steps", sum(t.steps for t in result.trials), "1"),
        ("wall_time", seconds, "s"),
        ("unbalanced_force_ratio_limit", scene.fos.unbalanced_force_ratio, "1"),
        ("failure_displacement", result.failure_displacement_m * 1e3, "mm"),
    ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def command_lines(
    scene: Scene3D, result: StageResult, found: StrengthReduction3DResult, seconds: float
) -> list[str]:
    """What `bbmc fos` prints after the search, as for a 2D scene: the FS (to the decimals its bracket
    supports, `bbmc.fos.result.factor_of_safety_text`), the trials and the `seconds` it took."""
    text = factor_of_safety_text(found.factor_of_safety, found.bracket, found.bracketed)
    bound = "" if found.bracketed else " (not bracketed: beyond the searched range)"
    return [f"factor of safety {text}{bound}, {len(found.trials)} trials, {seconds:.1f} s"]


def run(
    scene: Scene3D, config_path: Path, progress: ProgressCallback = ignore
) -> tuple[StageResult, StrengthReduction3DResult]:
    """Build the 3D scene (checking every reference and shape), find its factor of safety, tabulate."""
    started = time.perf_counter()
    built: SceneModel = build_scene3d(scene)
    solver = scene.solver
    judged = judged_blocks(scene, built)
    try:
        result = factor_of_safety_3d(
            built.model,
            scene.fos,
            damping=solver.damping,
            safety=solver.safety_factor,
            equilibrium_steps=solver.steps,
            judged=judged,
            progress=progress,
            threads=thread_count(solver.threads),
        )
    except ValueError as error:
        raise ConfigKeyError("solver.steps", str(error)) from None
    tables = {
        "fos": trials_table(result.trials),
        "summary": summary_table(result, scene, time.perf_counter() - started),
    }
    text = factor_of_safety_text(result.factor_of_safety, result.bracket, result.bracketed)
    title = f"bracketing and bisection; trials start from the {result.start} equilibrium"
    figures = {"bracketing": trials_figure(result.trials, result.factor_of_safety, text, result.bracketed,
                                           title, scene.figure_dpi)}  # fmt: skip
    if result.failed is not None:
        figures["mechanism"] = mechanism_figure(
            result.failed, result.equilibrium.blocks, scene.figure_dpi, built.names,
            title=f"the lowest unstable trial, F = {result.bracket[1]:.4g}: displacement from equilibrium",
        )  # fmt: skip
    return StageResult(tables=tables, figures=figures), result
