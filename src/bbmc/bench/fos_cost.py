"""What a factor of safety costs, and how far it moves with the solver's settings (fos_cost.csv).

Every verification case of `bbmc.slope.fos_cases`, and the paper's slope with both joint models
(`bbmc.slope.safety`; its expected value is the planar limit equilibrium: without cohesion for the
constant joint, eq 9 for Barton-Bandis), is solved at its own settings ("default") and then once per
variant of bench.yaml's `fos.variants`, each one change to the scene (a time-step safety factor, the
sub-contacts, the damping, the verdict's limit or response time). Each row: the FS, the bracket, its
error against the expected value, the trials, the steps and the wall time of the whole search
(equilibrium included).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from bbmc.dem.model import build_model
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.scene.schema import Scene
from bbmc.slope import fos_cases, safety
from bbmc.slope import model as sm
from bbmc.slope.config import load_paper_slope


def merged(scene: dict, change: dict) -> dict:
    """`scene` with `change` laid over it, nested sections merged key by key."""
    out = dict(scene)
    for key, value in change.items():
        out[key] = merged(out.get(key) or {}, value) if isinstance(value, dict) else value
    return out


def paper_slope_cases(slope_config: Path) -> list[fos_cases.Case]:
    config, table4 = load_paper_slope(slope_config)
    expected = {
        row["model"]: (row["factor_of_safety"], f"planar limit equilibrium, {row['strength']}")
        for row in safety.limit_equilibrium(config, table4)
        if not row["strength"].startswith("Table 4's c")
    }
    return [
        fos_cases.Case(f"paper_slope_{kind}", safety.reduction_scene(config, table4, kind), *expected[kind])
        for kind in sm.JOINT_MODELS
    ]


def fos_cost_table(
    slope_config: Path, variants: dict[str, dict], progress: Callable[[str], None] = lambda _: None
) -> pd.DataFrame:
    rows = []
    for case in [*fos_cases.cases(), *paper_slope_cases(slope_config)]:
        for variant, change in {"default": {}, **variants}.items():
            progress(f"fos cost: {case.name}, {variant}")
            scene = merged(case.scene, change)
            started = time.perf_counter()
            model = build_model(Scene.model_validate(scene, strict=False), Path(f"<{case.name}>"))
            result = factor_of_safety(model)
            seconds = time.perf_counter() - started
            lo, hi = result.bracket
            rows.append(
                {
                    "case": case.name,
                    "variant": variant,
                    "expected": case.expected,
                    "expected_from": case.source,
                    "factor_of_safety": result.factor_of_safety,
                    "error_pct": 100 * (result.factor_of_safety / case.expected - 1),
                    "bracket_holds_expected": bool(lo <= case.expected <= hi) if math.isfinite(hi) else False,
                    "last_stable_factor": lo,
                    "first_unstable_factor": hi,
                    "start": result.start,
                    "trials": len(result.trials),
                    "equilibrium_steps": result.equilibrium_steps,
                    "trial_steps": sum(t.steps for t in result.trials),
                    "wall_time_s": seconds,
                }
            )
    table = pd.DataFrame(rows)
    default = table[table["variant"] == "default"].set_index("case")["factor_of_safety"]
    table["change_from_default"] = table["factor_of_safety"] - table["case"].map(default)
    return table
