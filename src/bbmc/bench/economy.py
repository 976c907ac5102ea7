"""The gain of each piece of work the engine leaves out (`bbmc.dem.model.Economy`), on the paper scenes.

For each economy: the scene run with every economy on, and with that one switched off, side by side in
one process, best of `repeats` each; the ratio of their wall times is the gain, and the two readings
must be identical to the last bit (each economy leaves out only work no result depends on).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields, replace

import numpy as np
import pandas as pd

from bbmc.bench.paper_scenes import PaperScene, Reading
from bbmc.dem.model import EVERY_ECONOMY, Economy

WHAT = {
    "skip_immobile_pairs": "contact search: no pair of two blocks held still",
    "bound_depth_when_needed": "contact search: separating-axis bound only for deep edge pairs",
    "changed_laws_only": "B-B law updates: none for sub-contacts whose stresses did not change (open ones)",
    "skip_held_blocks": "motion and vertex update: none for blocks held still",
}


def _best(scene: PaperScene, economy: Economy, repeats: int) -> Reading:
    readings = [scene.read(scene.defaults(), economy) for _ in range(repeats)]
    return min(readings, key=lambda r: r.seconds)


def economy_table(scenes: list[PaperScene], repeats: int, progress: Callable[[str], None]) -> pd.DataFrame:
    rows = []
    for scene in scenes:
        scene.read(scene.defaults())  # warm-up
        progress(f"{scene.name}: every economy on")
        on = _best(scene, EVERY_ECONOMY, repeats)
        for switch in fields(Economy):
            progress(f"{scene.name}: without {switch.name}")
            off = _best(scene, replace(EVERY_ECONOMY, **{switch.name: False}), repeats)
            rows.append(
                {
                    "scene": scene.name,
                    "economy": switch.name,
                    "what_is_left_out": WHAT[switch.name],
                    "seconds_with": on.seconds,
                    "seconds_without": off.seconds,
                    "speedup": off.seconds / on.seconds,
                    "steps": on.steps,
                    "identical_results": bool(
                        np.array_equal(on.values, off.values) and on.statuses == off.statuses
                    ),
                }
            )
    return pd.DataFrame(rows)
