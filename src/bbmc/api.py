"""bbmc from Python (a notebook, a script): load or build a scene, run it, get its tables.

    from bbmc import api
    scene = api.load_scene("configs/scenes/incline.yaml")        # or api.load_scene({...}) from a dict
    result = api.run(scene)
    result.history          # the monitors at every record step (pandas DataFrame)
    result.blocks, result.contacts, result.summary
    api.factor_of_safety(api.load_scene("configs/scenes/planar_crack.yaml")).factor_of_safety

The scene is the format of docs/scene-format.md, validated whole (`ConfigError`, one line, on any
fault); a value outside its plausible range for rock (docs/plausible-ranges.md) is a `UserWarning`,
one per value; a run that goes wrong raises `SimulationError`. Nothing is written to disk.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from bbmc.config import ConfigError, load_config, validate
from bbmc.dem.model import build_model
from bbmc.dem.solver import RunResult, SimulationError, simulate
from bbmc.fos.strength_reduction import StrengthReductionResult
from bbmc.fos.strength_reduction import factor_of_safety as _factor_of_safety
from bbmc.scene.schema import Scene

__all__ = ["ConfigError", "Scene", "SimulationError", "factor_of_safety", "load_scene", "run"]


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
