"""bbmc from Python (a notebook, a script): load or build a scene, run it, get its tables.

    from bbmc import api
    scene = api.load_scene("configs/scenes/incline.yaml")        # or api.load_scene({...}) from a dict
    result = api.run(scene)
    result.history          # the monitors at every record step (pandas DataFrame)
    result.blocks, result.contacts, result.summary
    api.factor_of_safety(api.load_scene("configs/scenes/planar_crack.yaml")).factor_of_safety
    study = api.study("configs/sweeps/planar_block.yaml")        # a study, as `bbmc sweep` runs it
    study.samples, study.summary, study.write("results/sweep/planar_block")

The scene is the format of docs/scene-format.md, validated whole (`ConfigError`, one line, on any
fault); a value outside its plausible range for rock (docs/plausible-ranges.md) is a `UserWarning`,
one per value; a run that goes wrong raises `SimulationError`. Nothing is written to disk but what a
result's `write` writes (and a study's finished batches, where it is told to keep them).
"""

from bbmc.api.scenes import factor_of_safety, load_scene, run
from bbmc.api.studies import StudyResult, load_study, study
from bbmc.config import ConfigError
from bbmc.dem.solver import SimulationError
from bbmc.scene.schema import Scene
from bbmc.sweep.runner import StudyInterrupted
from bbmc.sweep.study import NoValidSampleError

__all__ = [
    "ConfigError",
    "NoValidSampleError",
    "Scene",
    "SimulationError",
    "StudyInterrupted",
    "StudyResult",
    "factor_of_safety",
    "load_scene",
    "load_study",
    "run",
    "study",
]
