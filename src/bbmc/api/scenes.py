"""Scenes from Python: load or build one, run it, find its factor of safety; nothing written."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from bbmc.config import load_config, validate
from bbmc.dem.model import build_model
from bbmc.dem.solver import RunResult, simulate
from bbmc.fos.strength_reduction import StrengthReductionResult
from bbmc.fos.strength_reduction import factor_of_safety as _factor_of_safety
from bbmc.scene.schema import Scene


def load_scene(source: str | Path | Mapping) -> Scene:
    """A validated scene from a YAML file or from a dict in the same form; its implausible values are
    warned about (`bbmc.plausibility.ImplausibleValue`, a `UserWarning`)."""
    if isinstance(source, Mapping):
        return validate(dict(source), Scene, "<scene dict>")
    return load_config(source, Scene)


def run(scene: Scene | str | Path | Mapping, progress: Callable[[int], None] | None = None) -> RunResult:
    """Run a scene (as `bbmc run` does, without writing): history, blocks, contacts, summary tables."""
    scene = scene if isinstance(scene, Scene) else load_scene(scene)
    return simulate(build_model(scene, Path(f"{scene.name or 'scene'}.yaml")), progress)


def factor_of_safety(
    scene: Scene | str | Path | Mapping, progress: Callable[[str], None] = lambda _: None
) -> StrengthReductionResult:
    """The scene's factor of safety by strength reduction (as `bbmc fos` does, without writing)."""
    scene = scene if isinstance(scene, Scene) else load_scene(scene)
    return _factor_of_safety(build_model(scene, Path(f"{scene.name or 'scene'}.yaml")), progress)
