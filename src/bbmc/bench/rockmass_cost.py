"""What generating a rock mass costs: a benched slope cut by three joint sets (one with bridges and a
scattered dip, one with a persistence, one 3D with Fisher scatter) into about 10,000 blocks at the
default spacings; wall time best of `repeats`, after one warm-up realization (imports, scipy)."""

from __future__ import annotations

import time

from bbmc.rockmass import RockMassConfig, generate

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
