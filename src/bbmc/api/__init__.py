"""bbmc from Python (a notebook, a script): load or build a scene, vary it, run it, get its tables and
figures; run a study.

    from bbmc import api
    scene = api.load_scene("configs/scenes/incline.yaml")        # or api.load_scene({...}) from a dict
    result = api.run(scene, threads=2)
    result.history          # the monitors at every record step (pandas DataFrame)
    result.blocks, result.contacts, result.summary, result.bridges, result.support
    crack = api.load_scene("configs/scenes/planar_crack.yaml")
    fos = api.factor_of_safety(api.with_values(crack, {"materials.rock.density_kg_m3": 2600}))
    print(fos)              # "factor of safety 1.113 (between ...)": to the decimals its bracket supports
    fos.mechanism           # every block at the end of the last stable and the first unstable trial
    api.mechanism_figure(fos).savefig("mechanism.png")
    study = api.study("configs/sweeps/planar_block.yaml")        # a study, as `bbmc sweep` runs it
    study.samples, study.summary, study.write("results/sweep/planar_block")

The scene is the format of docs/scene-format.md, validated whole (`ConfigError`, one line, on any
fault); a value outside its plausible range for rock (docs/plausible-ranges.md) is a `UserWarning`,
one per value; a run that goes wrong raises `SimulationError`. Nothing is written to disk but what a
study result's `write` writes (and a study's finished batches, where it is told to keep them).
Progress comes as `Progress` (done, total, unit, text) to a `progress=` callback.
"""

from bbmc.api.scenes import factor_of_safety, load_scene, run
from bbmc.api.studies import StudyResult, load_study, study
from bbmc.config import ConfigError
from bbmc.dem.solver import RunResult, SimulationError
from bbmc.fos.result import StrengthReductionResult, Trial, factor_of_safety_text
from bbmc.outputs.figures import bracketing_figure, mechanism_figure
from bbmc.progress import Progress
from bbmc.scene.paths import get_path, set_path, with_values
from bbmc.scene.schema import Scene
from bbmc.sweep.runner import StudyInterrupted
from bbmc.sweep.study import NoValidSampleError

__all__ = [
    "ConfigError",
    "NoValidSampleError",
    "Progress",
    "RunResult",
    "Scene",
    "SimulationError",
    "StrengthReductionResult",
    "StudyInterrupted",
    "StudyResult",
    "Trial",
    "bracketing_figure",
    "factor_of_safety",
    "factor_of_safety_text",
    "get_path",
    "load_scene",
    "load_study",
    "mechanism_figure",
    "run",
    "set_path",
    "study",
    "with_values",
]
