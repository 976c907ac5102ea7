"""Small block scenes for the engine's tests, written as YAML into a temporary folder and run."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import yaml

from bbmc.dem.solver import RunResult, load_scene, simulate

DENSITY = 2500.0
SLIDER = (0.4, 0.2)  # width, height [m]
G = 9.81


def constant_joint(
    friction_deg: float, cohesion_MPa: float = 0.0, k_MPa_per_mm: float = 10.0, **extra
) -> dict:
    return {
        "law": "constant",
        "kn_MPa_per_mm": k_MPa_per_mm,
        "ks_MPa_per_mm": k_MPa_per_mm,
        "friction_deg": friction_deg,
        "cohesion_MPa": cohesion_MPa,
        **extra,
    }


def block_on_base(
    angle_deg: float = 0.0,
    joint: dict | None = None,
    steps: int = 5000,
    damping: float = 0.0,
    gravity: tuple[float, float] = (0.0, -G),
    slider_fix: tuple[str, ...] = (),
    every: int = 100,
    gap_m: float = 0.0,
) -> dict:
    """A 0.4 m x 0.2 m block on a long fixed base whose top face dips at `angle_deg` (down to the
    left), both turned about the origin; the block's lower left corner starts at the origin."""
    width, height = SLIDER
    turn = {"rotate_deg": angle_deg, "rotate_about_m": [0.0, 0.0]}
    return {
        "name": "block_on_base",
        "gravity_m_s2": list(gravity),
        "materials": {"rock": {"density_kg_m3": DENSITY}},
        "blocks": [
            {
                "name": "base",
                "material": "rock",
                "rectangle_m": {"x_m": -4.0, "y_m": -0.5, "width_m": 6.0, "height_m": 0.5},
                "fix": ["x", "y", "rotation"],
                **turn,
            },
            {
                "name": "slider",
                "material": "rock",
                "rectangle_m": {"x_m": 0.0, "y_m": gap_m, "width_m": width, "height_m": height},
                "fix": list(slider_fix),
                **turn,
            },
        ],
        "joint_laws": {"joint": joint or constant_joint(30.0)},
        "contacts": {"default_law": "joint"},
        "solver": {"steps": steps, "damping": damping},
        "monitoring": {
            "every_steps": every,
            "monitors": [
                {"name": "ux", "block": "slider", "quantity": "ux"},
                {"name": "uy", "block": "slider", "quantity": "uy"},
                {"name": "rot", "block": "slider", "quantity": "rotation"},
                {"name": "sn", "between": ["slider", "base"], "quantity": "sigma_n"},
                {"name": "tau", "between": ["slider", "base"], "quantity": "tau"},
                {"name": "us", "between": ["slider", "base"], "quantity": "us"},
                {"name": "un", "between": ["slider", "base"], "quantity": "un"},
                {"name": "ks", "between": ["slider", "base"], "quantity": "ks"},
                {"name": "ke", "quantity": "kinetic_energy"},
                {"name": "pe", "quantity": "potential_energy"},
                {"name": "se", "quantity": "strain_energy"},
            ],
        },
    }


def embedded_gap(angle_deg: float, k_MPa_per_mm: float, factor: float = 1.0) -> float:
    """A negative gap [m]: the block starts `factor` times its static closure into the base, so that
    its first contact stress is `factor` times its weight's normal stress (no drop onto the joint)."""
    sigma = slider_mass() * G * math.cos(math.radians(angle_deg)) / SLIDER[0]
    return -factor * sigma / (k_MPa_per_mm * 1e9)


def ramped_weight(scene: dict, angle_deg: float, ramp_steps: int) -> dict:
    """Gravity off, the block's weight applied instead as a force ramped up over `ramp_steps`
    (quasi-static loading: no dynamic overshoot)."""
    scene = copy.deepcopy(scene)
    scene["gravity_m_s2"] = [0.0, 0.0]
    weight_kN = slider_mass() * G / 1e3
    scene["loads"] = {
        "block_forces": [{"block": "slider", "force_kN": [0.0, -weight_kN], "ramp_steps": ramp_steps}]
    }
    return scene


def edited(scene: dict, **changes) -> dict:
    """A deep copy of `scene` with dotted keys replaced, e.g. edited(s, **{"solver.steps": 10})."""
    scene = copy.deepcopy(scene)
    for dotted, value in changes.items():
        node = scene
        *parents, last = dotted.split(".")
        for key in parents:
            node = node[int(key)] if isinstance(node, list) else node[key]
        node[last] = value
    return scene


def write_scene(tmp_path: Path, scene: dict, name: str = "scene.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(scene, sort_keys=False))
    return path


def run_scene(tmp_path: Path, scene: dict) -> RunResult:
    return simulate(load_scene(write_scene(tmp_path, scene)))


def slider_mass() -> float:
    return DENSITY * SLIDER[0] * SLIDER[1]
