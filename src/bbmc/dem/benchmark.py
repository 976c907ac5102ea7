"""Engine throughput on generated jointed block systems (`bbmc bench` writes results/bench/engine.csv).

Each system is a running-bond brick wall of 1 m x 0.5 m blocks on a fixed base, under gravity, with
constant Mohr-Coulomb joints; columns and rows are chosen so the wall is about twice as wide as high.
The contact search at step 0 is timed apart from the cycles; the cycles include every contact search
they trigger. Times are wall-clock on one core: compare the ratios between sizes, not the absolute
numbers across machines.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.dem import layout as L
from bbmc.dem.model import build_model
from bbmc.dem.scene import Scene
from bbmc.dem.solver import advance, prepare


def wall_scene(blocks: int, sub_contacts: int, steps: int) -> Scene:
    """A brick wall of about `blocks` blocks (rows = sqrt(blocks / 2)) on a fixed base."""
    rows = max(1, round(math.sqrt(blocks / 2)))
    columns = max(1, round(blocks / rows))
    return Scene.model_validate(
        {
            "name": f"wall_{blocks}",
            "materials": {"rock": {"density_kg_m3": 2600.0}},
            "blocks": [
                {
                    "name": "base",
                    "material": "rock",
                    "rectangle_m": {"x_m": -1.0, "y_m": -1.0, "width_m": columns + 3.0, "height_m": 1.0},
                    "fix": ["x", "y", "rotation"],
                },
                {
                    "name": "wall",
                    "material": "rock",
                    "brick_wall": {
                        "origin_m": [0.0, 0.0],
                        "columns": columns,
                        "rows": rows,
                        "block_width_m": 1.0,
                        "block_height_m": 0.5,
                        "row_offset": 0.5,
                    },
                },
            ],
            "joint_laws": {
                "joint": {
                    "law": "constant",
                    "kn_MPa_per_mm": 10.0,
                    "ks_MPa_per_mm": 10.0,
                    "friction_deg": 30.0,
                }
            },
            "contacts": {"default_law": "joint", "sub_contacts_per_edge": sub_contacts},
            "solver": {"steps": steps, "damping": 0.8},
        }
    )


def measure(blocks: int, sub_contacts: int, steps: int, repeats: int) -> dict[str, float]:
    """Best-of-`repeats` timing of `steps` cycles on a wall of about `blocks` blocks."""
    scene = wall_scene(blocks, sub_contacts, steps)
    model = build_model(scene, Path(f"<benchmark wall of {blocks} blocks>"))
    best_cycles, best_search = math.inf, math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        state = prepare(model)
        searched = time.perf_counter()
        advance(model, state, steps)
        done = time.perf_counter()
        best_search = min(best_search, searched - start)
        best_cycles = min(best_cycles, done - searched)
    subs = len(state.subs)
    return {
        "blocks": len(model.block_names),
        "contacts": len(state.contacts),
        "sub_contacts": subs,
        "active_sub_contacts": int(np.sum(state.subs[:, L.LENGTH] > 0)),
        "steps": steps,
        "contact_searches_during_cycles": state.searches - 1,
        "initial_search_s": best_search,
        "cycles_s": best_cycles,
        "steps_per_s": steps / best_cycles,
        "sub_contact_updates_per_s": subs * steps / best_cycles,
        "seconds_per_step": best_cycles / steps,
    }


def engine_table(block_counts: list[int], sub_contacts: int, steps: int, repeats: int) -> pd.DataFrame:
    """One row per size, with the growth of the cost per step against the previous size:
    exponent = log(t2/t1) / log(N2/N1) (1 is linear), and the cost per step over N log N relative to
    the smallest size (staying near 1 or below means no worse than N log N)."""
    measure(50, sub_contacts, 20, 1)
    table = pd.DataFrame([measure(n, sub_contacts, steps, repeats) for n in block_counts])
    cost, n = table["seconds_per_step"].to_numpy(), table["blocks"].to_numpy(dtype=float)
    table["growth_exponent_vs_previous"] = np.concatenate(
        [[np.nan], np.log(cost[1:] / cost[:-1]) / np.log(n[1:] / n[:-1])]
    )
    per_nlogn = cost / (n * np.log(n))
    table["cost_over_NlogN_relative"] = per_nlogn / per_nlogn[0]
    table["meets_10M_updates_per_s"] = table["sub_contact_updates_per_s"] >= 1e7
    return table
