"""Scenes from Python: load or build one, vary it by dotted paths, run it, find its factor of safety;
nothing written."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from bbmc.config import load_config, validate
from bbmc.dem.model import build_model
from bbmc.dem.solver import RunResult, simulate
from bbmc.fos.result import StrengthReductionResult
from bbmc.fos.strength_reduction import factor_of_safety as _factor_of_safety
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.paths import with_threads
from bbmc.scene.schema import Scene


def load_scene(source: str | Path | Mapping) -> Scene:
    """A validated scene from a YAML file or from a dict in the same form; its implausible values are
    warned about (`bbmc.plausibility.ImplausibleValue`, a `UserWarning`)."""
    if isinstance(source, Mapping):
        return validate(dict(source), Scene, "<scene dict>")
    return load_config(source, Scene)


def _scene(scene: Scene | str | Path | Mapping, threads: int | None) -> tuple[Scene, Path]:
    """The validated scene on `threads` threads, and the path its messages name."""
    scene = with_threads(scene if isinstance(scene, Scene) else load_scene(scene), threads)
    return scene, Path(f"{scene.name or 'scene'}.yaml")


def run(
    scene: Scene | str | Path | Mapping, threads: int | None = None, progress: ProgressCallback = ignore
) -> RunResult:
    """Run a scene as `bbmc run` does, without writing: its history, blocks, contacts, summary, bridges
    and support tables (`RunResult`). `threads`: as `bbmc run --threads` (None: the scene's
    solver.threads, else every core), the results the same to the bit for any number; `progress` gets
    a `bbmc.progress.Progress` in steps at every record step."""
    scene, path = _scene(scene, threads)
    return simulate(build_model(scene, path), progress)


def factor_of_safety(
    scene: Scene | str | Path | Mapping, threads: int | None = None, progress: ProgressCallback = ignore
) -> StrengthReductionResult:
    """The scene's factor of safety by strength reduction as `bbmc fos` finds it, without writing
    (`StrengthReductionResult`: `print(result)` shows the FS to the decimals its bracket supports).
    `threads` as for `run`; `progress` gets a `bbmc.progress.Progress` in trials."""
    scene, path = _scene(scene, threads)
    return _factor_of_safety(build_model(scene, path), progress)
