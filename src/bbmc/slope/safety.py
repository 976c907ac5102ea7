"""The factor of safety of the paper's slope, which the paper never gives: by strength reduction on
the engine (`bbmc.fos.strength_reduction`) for both joint models, and by Hoek & Bray's planar limit
equilibrium (`bbmc.slope.planar`) for sliding on the bedding joint through the toe.

The limit equilibrium's block is everything above that bedding joint, from the toe to where it meets
the upper surface (no tension crack: the cross joints dip at 80 deg, not vertically, and the bedding
reaches the upper surface inside the model). The constant joint is given twice: with Table 4's
cohesion on the whole plane, and without it (3DEC's Coulomb joint, which the slope runs use, loses its
cohesion where it slips, so a progressive slide ends on friction alone). The Barton-Bandis strength is
eq 9 at the plane's mean effective normal stress.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.dem import layout as L
from bbmc.dem.model import Model, built_scene
from bbmc.dem.solver import simulate
from bbmc.fos.strength_reduction import StrengthReductionResult, factor_of_safety
from bbmc.joint.derived import full_joint
from bbmc.scene.schema import name_part
from bbmc.slope import model as sm
from bbmc.slope import planar
from bbmc.slope.config import Config, Residual
from bbmc.slope.limit_equilibrium import G


def reduction_scene(config: Config, table4: sm.Table4, kind: sm.JointModel) -> dict:
    """The slope's scene with one joint model, its `fos:` section and equilibrium budget from the config."""
    law = sm.joint_law(kind, table4, config.constant, config.barton_bandis)
    scene = sm.slope_scene(f"slope_{kind}", config.slope, table4.density_kg_m3, law, config.run, [])
    return for_strength_reduction(scene, config)


def for_strength_reduction(scene: dict, config: Config) -> dict:
    """`scene` set up for `bbmc fos`: the config's `factor_of_safety` as its `fos:` section, its
    equilibrium budget as the step limit, no other stop."""
    settings = config.factor_of_safety
    solver = {**scene["solver"], "steps": settings.max_steps, "stop": None}
    return {**scene, "solver": solver, "fos": settings.model_dump(exclude={"max_steps"})}


def strength_reduction(
    config: Config, table4: sm.Table4, kind: sm.JointModel
) -> tuple[Model, StrengthReductionResult]:
    """The slope's FS with one joint model by strength reduction (its wall time: `bbmc bench`)."""
    scene = reduction_scene(config, table4, kind)
    model = built_scene(scene, f"slope_{kind}.yaml")
    return model, factor_of_safety(model)


def limit_equilibrium(config: Config, table4: sm.Table4) -> list[dict]:
    """Planar sliding on the bedding through the toe (module docstring): one row per strength."""
    s = config.slope
    forces = planar.planar_forces(
        s.height_m,
        math.radians(s.face_angle_deg),
        math.radians(s.joint_sets[0].dip_deg),
        0.0,
        0.0,
        table4.density_kg_m3 * G,
    )
    c, n = table4.constant, table4.nonlinear
    friction = math.radians(c["phi_deg"])
    rows = [
        (
            "constant",
            "Table 4's c on the whole plane",
            planar.factor_of_safety_mohr_coulomb(forces, c["c_kPa"] * units.kPa, friction),
        ),
        (
            "constant",
            "no cohesion (lost where the joint slips)",
            planar.factor_of_safety_mohr_coulomb(forces, 0.0, friction),
        ),
        (
            "barton_bandis",
            "eq 9 at the plane's mean sigma_n",
            planar.factor_of_safety_barton_bandis(
                forces,
                n["JRC"],
                n["JCS_MPa"] * units.MPa,
                math.radians(n["phi_b_deg"]),
                math.radians(config.barton_bandis.phi_max_deg),
            ),
        ),
    ]
    return [
        {"model": kind, "method": "limit_equilibrium_planar", "strength": what, "factor_of_safety": float(fs)}
        for kind, what, fs in rows
    ]


def factor_of_safety_table(
    config: Config, table4: sm.Table4
) -> tuple[pd.DataFrame, dict[str, tuple[Model, StrengthReductionResult]]]:
    """factor_of_safety.csv (both methods, both models) and each model's strength-reduction result."""
    rows, results = [], {}
    for kind in sm.JOINT_MODELS:
        model, result = strength_reduction(config, table4, kind)
        results[kind] = (model, result)
        rows.append(
            {
                "model": kind,
                "method": "strength_reduction",
                "strength": "the scene's joint law, reduced",
                "factor_of_safety": result.factor_of_safety,
                "last_stable_factor": result.bracket[0],
                "first_unstable_factor": result.bracket[1],
                "start": result.start,
                "trials": len(result.trials),
            }
        )
    table = pd.DataFrame(rows + limit_equilibrium(config, table4))
    return table.astype({"trials": "Int64"}), results


def mobilized_law(table4: sm.Table4, residual: Residual, phi_r_deg: float) -> dict:
    """Table 4's joint as the full Barton-Bandis joint (`law: barton_bandis_mobilized`): its JRC, JCS,
    phi_b at the lab length, scaled to `residual.field_length_m`, with phi_r and Table 4's constant
    stiffnesses (the mobilized law has no eq 8 K_n)."""
    n, c = table4.nonlinear, table4.constant
    return {
        "law": "barton_bandis_mobilized",
        "jrc0": n["JRC"],
        "jcs0_MPa": n["JCS_MPa"],
        "phi_b_deg": n["phi_b_deg"],
        "phi_r_deg": phi_r_deg,
        "lab_length_m": residual.lab_length_m,
        "field_length_m": residual.field_length_m,
        "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": c["K_n_MPa_per_mm"]},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": c["K_s_MPa_per_mm"]},
    }


def peak_only_law(table4: sm.Table4, residual: Residual | None = None) -> dict:
    """Table 4's peak envelope (eq 9, exact tangent) with the same constant stiffnesses; with
    `residual`, JRC and JCS scaled from its lab to its field length (as the full joint's)."""
    n, c = table4.nonlinear, table4.constant
    jrc, jcs = n["JRC"], n["JCS_MPa"]
    if residual is not None:
        scaled = full_joint(jrc, jcs * units.MPa, residual.lab_length_m, residual.field_length_m)
        jrc, jcs = scaled.jrc, scaled.jcs / units.MPa
    return {
        "law": "barton_bandis",
        "strength": {"jrc": jrc, "jcs_MPa": jcs, "phi_b_deg": n["phi_b_deg"]},
        "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": c["K_n_MPa_per_mm"]},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": c["K_s_MPa_per_mm"]},
        "after_slip": "keep",
    }


def residual_comparison(config: Config, table4: sm.Table4) -> pd.DataFrame:
    """The slope with the full joint (residual strength after slip) against the peak-only joint at lab
    scale and at the field scale the full joint uses (so that the scale effect and the residual strength
    are told apart), the same stiffnesses: each one's FS by strength reduction, and the largest
    displacement of a free block after run.duration_s from the start (the dynamic run of Figs 8-10)."""
    r = config.residual
    joints = {"peak_only": peak_only_law(table4), "peak_only_field_scale": peak_only_law(table4, r)} | {
        f"mobilized_phi_r_{name_part(phi)}": mobilized_law(table4, r, phi) for phi in r.phi_r_deg
    }
    rows = []
    for name, law in joints.items():
        scene = sm.slope_scene(f"slope_{name}", config.slope, table4.density_kg_m3, law, config.run, [])
        scene["solver"]["update_interval_steps"] = r.update_interval_steps
        model = built_scene(scene, f"{name}.yaml")
        run = simulate(model)
        free = ~model.immobile
        moved = np.hypot(*(run.state.blocks[free][:, [L.X, L.Y]] - model.blocks[free][:, [L.X, L.Y]]).T)
        fos_scene = for_strength_reduction(scene, config)
        result = factor_of_safety(built_scene(fos_scene, f"{name}.yaml"))
        rows.append(
            {
                "joint": name,
                "phi_r_deg": law.get("phi_r_deg", math.nan),
                "largest_displacement_mm": float(moved.max()) / units.mm,
                "duration_s": float(run.state.clock[L.TIME]),
                "factor_of_safety": result.factor_of_safety,
                "last_stable_factor": result.bracket[0],
                "first_unstable_factor": result.bracket[1],
                "start": result.start,
            }
        )
    return pd.DataFrame(rows)
