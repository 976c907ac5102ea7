"""Goodman & Bray's stepped toppling slope as a block scene, and its limiting friction on the engine.

The scene is written in the frame of the block bases: x along the bases, up the slope, y normal to
them; the slope's dip α enters through the direction of the weight, which is ramped on. Block n
(1 = toe) is a rectangle Δx wide and y_n tall on its own fixed step, x from (n − 1)Δx to nΔx, its
base b above the one below (`toppling.BlockSystem`). Every joint, base or side, has the same constant
Mohr–Coulomb law (no cohesion), as the limit equilibrium assumes.

A trial at one friction angle holds if the unbalanced force ratio falls below `equilibrium_ratio`
after the weight is on, or its motion decays (`bbmc.dem.verdict`, windows of `trend_window_steps`),
and fails if a block moves `failure_displacement_m`, creeps, or is projected to move that far; the
limiting friction is bisected between the two.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import pandas as pd
from scipy.optimize import bisect

from bbmc.dem.model import built_scene
from bbmc.dem.solver import RunResult, simulate
from bbmc.slope.limit_equilibrium import G
from bbmc.slope.toppling import BlockSystem


@dataclass(frozen=True)
class TrialSettings:
    """How one friction angle is tried on the engine (SI; stiffness in MPa/mm at the scene boundary)."""

    density_kg_m3: float = 2500.0
    stiffness_MPa_per_mm: float = 10.0  # K_n = K_s of every joint
    step_depth_m: float = 5.0  # the fixed steps' thickness below the bases
    ramp_steps: int = 5000
    damping: float = 0.8
    max_steps: int = 200_000
    equilibrium_ratio: float = 1e-5
    failure_displacement_m: float = 0.2
    sub_contacts_per_edge: int = 4
    trend_window_steps: int = 15_000  # the motion's trend is judged over windows of this many steps
    # (about the steps Goodman-Bray's example takes to its equilibrium at 39 deg: its response time)


def toppling_scene(blocks: BlockSystem, friction_deg: float, settings: TrialSettings) -> dict:
    """The scene (the `bbmc run` format, as a dict) of a stepped toppling slope at one friction angle."""
    dx, step = blocks.width, blocks.b
    weight = [-math.sin(blocks.base_dip), -math.cos(blocks.base_dip)]
    entries, forces = [], []
    for k, height in enumerate(blocks.heights):
        base = k * step
        entries.append(
            {
                "name": f"step{k + 1}",
                "material": "rock",
                "group": "steps",
                "rectangle_m": {
                    "x_m": k * dx,
                    "y_m": base - settings.step_depth_m,
                    "width_m": dx,
                    "height_m": settings.step_depth_m,
                },
                "fix": ["x", "y", "rotation"],
            }
        )
        entries.append(
            {
                "name": f"block{k + 1}",
                "material": "rock",
                "group": "blocks",
                "rectangle_m": {"x_m": k * dx, "y_m": base, "width_m": dx, "height_m": float(height)},
            }
        )
        kn = settings.density_kg_m3 * dx * float(height) * G / 1e3
        forces.append(
            {
                "block": f"block{k + 1}",
                "force_kN": [kn * weight[0], kn * weight[1]],
                "ramp_steps": settings.ramp_steps,
            }
        )
    k = settings.stiffness_MPa_per_mm
    return {
        "name": "toppling",
        "gravity_m_s2": [0.0, 0.0],
        "materials": {"rock": {"density_kg_m3": settings.density_kg_m3}},
        "blocks": entries,
        "joint_laws": {
            "joint": {"law": "constant", "kn_MPa_per_mm": k, "ks_MPa_per_mm": k, "friction_deg": friction_deg}
        },
        "contacts": {"default_law": "joint", "sub_contacts_per_edge": settings.sub_contacts_per_edge},
        "loads": {"block_forces": forces},
        "solver": {
            "steps": settings.max_steps,
            "damping": settings.damping,
            "stop": {
                "unbalanced_force_ratio": settings.equilibrium_ratio,
                "displacement_m": settings.failure_displacement_m,
                "trend_window_steps": settings.trend_window_steps,
            },
        },
        "monitoring": {
            "every_steps": 100,
            "monitors": [
                {"name": f"rot{k + 1}", "block": f"block{k + 1}", "quantity": "rotation"}
                for k in range(blocks.n_blocks)
            ],
        },
    }


SceneOf = Callable[[BlockSystem, float, TrialSettings], dict]


def run_trial(
    blocks: BlockSystem, friction_deg: float, settings: TrialSettings, scene_of: SceneOf = toppling_scene
) -> RunResult:
    """One friction angle on the engine; `scene_of` may add to the scene (support, say)."""
    scene = scene_of(blocks, friction_deg, settings)
    return simulate(built_scene(scene, f"<toppling slope at {friction_deg} deg>"))


def holds(result: RunResult) -> bool:
    """Whether the trial reached equilibrium or was coming to rest (`bbmc.dem.verdict`), rather than
    failing (a block's failure displacement, a creep, or a movement projected beyond it)."""
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    return bool(summary["stopped_by_equilibrium"] or summary["stopped_by_decaying"])


def limiting_friction(
    blocks: BlockSystem,
    low_deg: float,
    high_deg: float,
    tolerance_deg: float,
    settings: TrialSettings,
    scene_of: SceneOf = toppling_scene,
) -> float:
    """The friction angle [deg] between failing (low) and holding (high) to within `tolerance_deg`."""

    def held(phi: float) -> bool:
        return holds(run_trial(blocks, phi, settings, scene_of))

    if held(low_deg) or not held(high_deg):
        raise ValueError(f"the slope must fail at {low_deg} deg and hold at {high_deg} deg")
    return bisect(
        lambda phi: 1.0 if held(phi) else -1.0,
        low_deg,
        high_deg,
        xtol=tolerance_deg,
    )


def block_modes(blocks: BlockSystem, result: RunResult, still_m: float) -> pd.DataFrame:
    """Each block's mode at the end of a trial, read off its motion: its base slip s (the displacement
    along the base of its lower, downslope, corner) and the movement of its top by turning, |theta| y_n.
    'stable' if both are below `still_m` [m]; else 'topples' if the turning moved its top more than the
    base slid, 'slides' if not."""
    final = result.blocks.set_index("block")
    rows = []
    for k, height in enumerate(blocks.heights):
        row = final.loc[f"block{k + 1}"]
        turn = math.radians(row["rotation_deg"])
        slip = (
            (row["x_m"] - row["x0_m"])
            - (math.cos(turn) - 1.0) * blocks.width / 2
            + math.sin(turn) * height / 2
        )
        turning = abs(turn) * height
        mode = (
            "stable"
            if max(abs(slip), turning) < still_m
            else ("topples" if turning > abs(slip) else "slides")
        )
        rows.append(
            {
                "block": k + 1,
                "rotation_deg": row["rotation_deg"],
                "base_slip_m": slip,
                "top_by_turning_m": turning,
                "mode": mode,
            }
        )
    return pd.DataFrame(rows)
