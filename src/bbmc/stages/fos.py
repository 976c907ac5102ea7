"""`bbmc fos`: the factor of safety of any block scene by shear-strength reduction
(`bbmc.fos.strength_reduction`); the scene format plus its optional `fos:` section.

Writes into <results>/fos/<scene name>/: fos.csv (every trial: F, verdict, why, steps, largest
displacement, unbalanced-force ratio, wall time), summary.csv (`quantity,value,unit`, with the row
factor_of_safety), mechanism.csv (every block's displacement, rotation and velocity at the end of the
highest stable and of the lowest unstable trial), mechanism.png (displacement at the end of the lowest
unstable trial), bracketing.png (the trials' F in order) and provenance.json. With a `support:`
section: the FS is found with the support and again without it (summary rows factor_of_safety and
factor_of_safety_without_support), and support.csv gives each element's load at the end of the
highest stable trial. With a `design:` section: design.csv, every trial of the search for the support
that reaches the target FS (`bbmc.fos.design`), and its result in summary.csv.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from bbmc.dem.model import build_model
from bbmc.dem.support_elements import SupportElements
from bbmc.dem.support_report import largest_loads, support_table
from bbmc.dem.verdict import STABLE
from bbmc.fos.design import DesignResult, design_support
from bbmc.fos.strength_reduction import StrengthReductionResult, factor_of_safety
from bbmc.io import StageResult
from bbmc.outputs.figures import bracketing_figure, mechanism_figure
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.schema import Scene

NAME = "fos"
Config = Scene


def _from_rest_rows(result: StrengthReductionResult) -> list[tuple[str, float, str]]:
    """The run from rest with the strengths as given, beside the FS: whether it stood (as `bbmc run`
    would say), and the largest displacement in it."""
    rest = result.from_rest
    if rest is None:
        return []
    return [
        ("stands_from_rest", int(rest.verdict == STABLE), "1"),
        ("from_rest_steps", rest.steps, "1"),
        ("from_rest_largest_displacement", rest.largest_displacement_m * 1e3, "mm"),
    ]


def summary_table(
    result: StrengthReductionResult,
    scene: Scene,
    seconds: float,
    unsupported: StrengthReductionResult | None = None,
    bolt_loads: dict[str, float] | None = None,
    design: DesignResult | None = None,
) -> pd.DataFrame:
    settings = scene.fos
    failing = result.failing_trial
    median = result.median_block_size_m
    rows = [
        ("factor_of_safety", result.factor_of_safety, "1"),
        ("bracketed", int(result.bracketed), "1"),
        ("last_stable_factor", result.bracket[0], "1"),
        ("first_unstable_factor", result.bracket[1], "1"),
        ("tolerance", settings.tolerance, "1"),
        ("start_from_elastic_equilibrium", int(result.start == "elastic"), "1"),
        *_from_rest_rows(result),
        ("failing_block_size", failing.block_size_m if failing else math.nan, "m"),
        ("failing_block_size_to_median", failing.block_size_m / median if failing else math.nan, "1"),
        ("equilibrium_steps", result.equilibrium_steps, "1"),
        ("equilibrium_wall_time", result.equilibrium_seconds, "s"),
        ("trials", len(result.trials), "1"),
        ("trial_steps", sum(t.steps for t in result.trials), "1"),
        ("wall_time", seconds, "s"),
        ("unbalanced_force_ratio_limit", settings.unbalanced_force_ratio, "1"),
        ("failure_displacement", result.failure_displacement_m * 1e3, "mm"),
        ("barton_bandis_reduction_phi_b_jrc", int(settings.barton_bandis_reduction == "phi_b_jrc"), "1"),
        ("laws_losing_cohesion_at_slip", len(result.laws_losing_cohesion), "1"),
    ]
    if unsupported is not None:
        rows += [
            ("factor_of_safety_without_support", unsupported.factor_of_safety, "1"),
            ("support_reduced_passive", int(settings.support_form == "passive"), "1"),
            *((f"bolt_load_{name}", load, "kN per bolt") for name, load in (bolt_loads or {}).items()),
        ]
    if design is not None:
        target = scene.design
        unit = "kN" if target.vary == "capacity" else "m"
        rows += [
            ("design_target_factor_of_safety", target.target_fs, "1"),
            (f"design_{target.vary}", math.nan if design.value is None else design.value, unit),
            ("design_reached", int(design.value is not None), "1"),
            ("design_fs_scatter", design.scatter, "1"),
            ("design_trials", len(design.trials), "1"),
            ("design_wall_time", design.seconds, "s"),
        ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def support_summary_lines(
    scene: Scene,
    summary: pd.DataFrame,
    unsupported: StrengthReductionResult | None = None,
    design_note: str = "",
) -> list[str]:
    """What the command prints of the support and the design (nothing for a scene without them)."""
    value = dict(zip(summary["quantity"], summary["value"], strict=True))
    lines = []
    if unsupported is not None:
        lines.append(f"without its support: factor of safety {unsupported.factor_of_safety_text}")
    design = scene.design
    if design is not None:
        unit = "kN" if design.vary == "capacity" else "m"
        found = value[f"design_{design.vary}"]
        elements = ", ".join(design.elements)
        lines.append(
            f"design: {elements} {design.vary} {found:.4g} {unit} gives FS {design.target_fs:g}, confirmed "
            f"by the engine ({int(value['design_trials'])} trials, {value['design_wall_time']:.1f} s; FS to "
            f"{scene.fos.tolerance:g}, scatter between trials {value['design_fs_scatter']:.3g}; design.csv)"
            if value["design_reached"]
            else f"design: no {design.vary} in {design.range} {unit} gives FS {design.target_fs:g} "
            "(design.csv)"
        )
        if design_note:
            lines.append(f"design: {design_note}")
    return lines


@dataclass
class FosRun:
    """What `bbmc fos` found: the scene's FS, the same without its support (None without support), and
    the design (None without a `design:` section)."""

    result: StrengthReductionResult
    unsupported: StrengthReductionResult | None
    design: DesignResult | None


def run(scene: Scene, config_path: Path, progress: ProgressCallback = ignore) -> tuple[StageResult, FosRun]:
    """Build the scene (checking every reference), find its factor of safety, tabulate and draw; and
    the design, where the scene has one. `progress` gets every report of the searches (in trials) and
    of the design (its text)."""
    started = time.perf_counter()
    model = build_model(scene, config_path)
    result = factor_of_safety(model, progress)
    tables = {"fos": result.trials_table, "mechanism": result.mechanism}
    unsupported, loads, design = None, None, None
    if len(model.support.names):
        progress(Progress(0, None, "trials", "the same scene without its support"))
        unsupported = factor_of_safety(dataclasses.replace(model, support=SupportElements.none()), progress)
        tables["support"] = support_table(model.support, model.block_names, result.support_state)
        loads = largest_loads(model.support, result.support_state)
    if scene.design is not None:
        design = design_support(model, config_path, progress)
        tables["design"] = design.trials
    seconds = time.perf_counter() - started
    tables["summary"] = summary_table(result, scene, seconds, unsupported, loads, design)
    figures = {"bracketing": bracketing_figure(result), "mechanism": mechanism_figure(result)}
    return StageResult(tables=tables, figures=figures), FosRun(result, unsupported, design)


def command_lines(scene: Scene, result: StageResult, found: FosRun, seconds: float) -> list[str]:
    """What `bbmc fos` prints after the search (a line starting "warning: " goes to stderr): the FS,
    the trials and the `seconds` it took, the notes, and the support's and the design's lines."""
    outcome = found.result
    bound = "" if outcome.bracketed else " (not bracketed: beyond the searched range)"
    trials = f"{len(outcome.trials)} trials, {seconds:.1f} s"
    lines = [f"factor of safety {outcome.factor_of_safety_text}{bound}, {trials}"]
    if outcome.progressive_note:
        lines.append(f"note: {outcome.progressive_note}")
    if outcome.failing_note:
        lines.append(outcome.failing_note)
    if outcome.elastic_start_note:
        lines.append(f"warning: {outcome.elastic_start_note}")
    note = found.design.note if found.design is not None else ""
    return lines + support_summary_lines(scene, result.tables["summary"], found.unsupported, note)
