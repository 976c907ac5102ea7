"""What generating a rock mass costs: a benched slope cut by three joint sets (one with bridges and a
scattered dip, one with a persistence, one 3D with Fisher scatter) into about 10,000 blocks at the
default spacings; wall time best of `repeats`, after one warm-up realization (imports, scipy)."""

from __future__ import annotations

import time
from pathlib import Path

from bbmc.dem.model import build_model
from bbmc.dem.solver import advance, prepare
from bbmc.rockmass import RockMassConfig, generate
from bbmc.scene.schema import Scene

SPACINGS_M = {"bedding": 0.8, "cross": 0.96, "steep": 3.2}  # about 10,000 blocks


def _config(spacing_scale: float) -> RockMassConfig:
    spacing = {name: value * spacing_scale for name, value in SPACINGS_M.items()}
    return RockMassConfig.model_validate(
        {
            "profile": {
                "benches": {"height_m": 15, "face_angle_deg": 65, "berm_width_m": 8, "count": 4},
                "toe_extent_m": 20,
                "crest_extent_m": 40,
                "depth_m": 20,
                "tension_crack": {"distance_behind_crest_m": 6, "depth_m": 8},
            },
            "section_azimuth_deg": 0,
            "joint_sets": [
                {
                    "name": "bedding",
                    "dip_deg": {"mean": 35, "std": 2},
                    "spacing_m": {
                        "distribution": "lognormal",
                        "mean": spacing["bedding"],
                        "std": spacing["bedding"] / 3,
                    },
                    "trace_length_m": {"distribution": "lognormal", "mean": 15, "std": 5},
                    "gap_m": {"distribution": "exponential", "mean": 2},
                },
                {
                    "name": "cross",
                    "dip_deg": 70,
                    "dip_direction_to_face_deg": 180,
                    "spacing_m": {"distribution": "exponential", "mean": spacing["cross"]},
                    "trace_length_m": 5.0,
                    "persistence": 0.7,
                },
                {
                    "name": "steep",
                    "orientation": {"dip_deg": 80, "dip_direction_deg": 20, "fisher_k": 200},
                    "spacing_m": spacing["steep"],
                    "trace_length_m": 8.0,
                    "persistence": 0.5,
                },
            ],
        }
    )


def rockmass_cost(repeats: int = 3, spacing_scale: float = 1.0, seed: int = 1) -> dict:
    """Blocks, lines, traces and cuts left out (slivers) of one realization, and the seconds it took
    to generate (best of `repeats`); `spacing_scale` multiplies every set's spacing."""
    config = _config(spacing_scale)
    generate(config, seed)
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        mass = generate(config, seed)
        seconds.append(time.perf_counter() - start)
    return {
        "blocks": len(mass.polygons),
        "lines": len(mass.lines),
        "traces": len(mass.traces),
        "skipped_cuts": len(mass.skipped),
        "seconds": min(seconds),
        "blocks_per_s": len(mass.polygons) / min(seconds),
    }


JOINT = {"law": "constant", "kn_MPa_per_mm": 10, "ks_MPa_per_mm": 5, "friction_deg": 38}
INTACT = JOINT | {
    "friction_deg": 45,
    "cohesion_MPa": 0.5,
    "tensile_strength_MPa": 0.2,
    "breaks_into": "joint",
}


def bridged_scene(spacing_scale: float, bridges: bool) -> dict:
    """The rock mass of `rockmass_cost` as a scene, its bridges intact rock (`bridges`) or the same
    geometry with the bridges the plain joint; the cuts glued in both (the rule for cuts without one of
    their own: `bbmc.dem.model`)."""
    rules = [{"law": "intact", "edges": "bridge"}] if bridges else []
    return {
        "name": "bridged" if bridges else "plain",
        "materials": {"rock": {"density_kg_m3": 2600}},
        "blocks": [{"name": "mass", "material": "rock", "rock_mass": _config(spacing_scale).model_dump()}],
        "joint_laws": {"joint": JOINT, "intact": INTACT},
        "contacts": {"default_law": "joint", "rules": rules},
        "solver": {"steps": 1},
    }


def bridge_cost(spacing_scale: float, steps: int, repeats: int) -> list[dict]:
    """Seconds per step of the same rock mass with its bridges and cuts as intact rock and with plain
    joints, alternately in this process, best of `repeats` (after one warm-up run of each)."""
    models = {
        b: build_model(Scene.model_validate(bridged_scene(spacing_scale, b)), Path("bench.yaml"))
        for b in (True, False)
    }
    best = {True: float("inf"), False: float("inf")}
    for repeat in range(repeats + 1):
        for with_bridges, model in models.items():
            state = prepare(model)
            begin = time.perf_counter()
            advance(model, state, steps)
            if repeat:
                best[with_bridges] = min(best[with_bridges], (time.perf_counter() - begin) / steps)
    blocks = len(models[True].block_names)
    return [
        {"scene": "bridges and cuts intact", "blocks": blocks, "seconds_per_step": best[True]},
        {"scene": "plain joints", "blocks": blocks, "seconds_per_step": best[False]},
    ]
