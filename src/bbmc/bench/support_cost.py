"""What support costs (support_cost.csv): where a scene has none, this engine's time per step against
the last commit before support elements (`bbmc.bench.engine_cost`, alternating fresh processes, on
the scaling slope and the shear box); and the design search of a scene's `design:` section
(`bbmc.fos.design`: limit equilibrium, then the engine's confirmation), its wall time and trials.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from bbmc.bench.engine_cost import engine_cost_table
from bbmc.dem.solver import load_scene
from bbmc.fos.design import design_support


def design_search_row(scene: Path, repeats: int) -> dict[str, object]:
    """The design search of `scene` (its `design:` section), best wall time of `repeats` (the scene
    built each time, as `bbmc fos` builds it), with its result and trial counts."""
    best, result = float("inf"), None
    for _ in range(repeats):
        started = time.perf_counter()
        result = design_support(load_scene(scene), scene)
        best = min(best, time.perf_counter() - started)
    stages = result.trials["stage"]
    return {
        "scene": f"design search, {scene.name}",
        "design_value": result.value,
        "limit_equilibrium_trials": int((stages == "limit_equilibrium").sum()),
        "engine_trials": int((stages == "engine").sum()),
        "engine_fs": float(result.trials["factor_of_safety"].iloc[-1]),
        "wall_time_s": best,
    }


def support_cost_table(
    commit: str,
    block_counts: list[int],
    steps: int,
    repeats: int,
    slope_config: str,
    shear_config: str,
    design_scene: Path,
    progress: Callable[[str], None] = lambda _: None,
) -> pd.DataFrame:
    """The engine-cost rows against `commit` (scenes without support), then the design search's row."""
    engine = engine_cost_table(commit, block_counts, steps, repeats, slope_config, shear_config, progress)
    progress(f"support cost: the design search of {design_scene.name}")
    return pd.concat([engine, pd.DataFrame([design_search_row(design_scene, repeats)])], ignore_index=True)
