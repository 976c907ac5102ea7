"""The direct shear box of the paper's section 4 (Figs 3 and 5) as a block scene, and its two tests.

Geometry (plane strain, per metre of thickness; the paper's 60 mm x 60 mm x 120 mm specimen seen
from the side): two rigid halves of `length_mm` x `height_mm`/2, the joint between them at half height
with its middle at the origin. The lower half is fixed; the upper half is free in x and y, its rotation
held by the box's frame. Gravity is off, so the joint's normal stress is the applied one. The lower
half is `lower_extension_mm` longer at each end than the upper, so the contact keeps the upper half's
full length while it shears (the paper's tau is nominal: force over the specimen's area). The halves
are rigid: deformable limestone (Table 2, G = 1.92 GPa) under uniform tau would shear each half by
tau h / (2 G) <= 0.0041 mm, which moves the top, not the joint's relative displacement d_h.

* Stress-controlled test (Fig 3): sigma_n ramped onto the top over `normal_ramp_steps`, then tau ramped
  from `shear_start_step` over `shear_ramp_steps`, slowly enough to be quasi-static; the run ends at
  equilibrium (`equilibrium_ratio`), when the upper half has moved `slide_limit_mm`, or at `max_steps`.
* Constant-velocity test (Fig 5): sigma_n as above, then the upper half is driven along the joint at
  `velocity_m_s` until it has moved `shear_displacement_mm`.

d_h is the shear displacement of the sub-contact nearest the joint's middle point, the paper's
monitored point (0, 0, 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Annotated, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from bbmc import laws, units
from bbmc.config import Section
from bbmc.dem.layout import SLIPPED
from bbmc.dem.model import EVERY_ECONOMY, Economy, built_scene
from bbmc.dem.solver import SimulationError, simulate
from bbmc.joint import model as jm

Positive = Annotated[float, Field(gt=0)]
Steps = Annotated[int, Field(ge=1)]
ShearLaw = Literal["uncorrected", "corrected", "simplified"]
SHEAR_LAWS: tuple[ShearLaw, ...] = ("uncorrected", "corrected", "simplified")


class Specimen(Section):
    length_mm: Positive = 60.0  # along the shear direction
    height_mm: Positive = 120.0  # the joint at half height
    lower_extension_mm: Annotated[float, Field(ge=0)] = 30.0  # at each end of the lower half
    sub_contacts_per_edge: Annotated[int, Field(ge=1, le=64)] = 4


class JointOptions(Section):
    """The engine's documented rules where the laws give 0, and what slip does to eq 15's c."""

    stress_floor_MPa: Positive = 0.01
    shear_stiffness_floor: Annotated[float, Field(ge=0, le=1)] = 0.001  # K_s >= floor x K_si
    after_slip: Literal["zero", "keep"] = "keep"  # eq 15's c is the tangent's intercept, not a bond


class Schedule(Section):
    """What both tests share: sigma_n ramped on first, then shearing from `shear_start_step`."""

    normal_ramp_steps: Steps = 1000
    shear_start_step: Steps = 1500
    update_interval_steps: Steps = 50
    record_every_steps: Steps = 50

    @model_validator(mode="after")
    def _normal_first(self) -> Schedule:
        if self.shear_start_step < self.normal_ramp_steps:
            raise ValueError(
                f"shear_start_step ({self.shear_start_step}) must not come before the normal stress is fully "
                f"applied (normal_ramp_steps {self.normal_ramp_steps})"
            )
        return self


class StressControlled(Schedule):
    shear_ramp_steps: Steps = 20_000
    max_steps: Steps = 80_000
    equilibrium_ratio: Positive = 1e-6
    slide_limit_mm: Positive = 25.0

    @model_validator(mode="after")
    def _room_to_settle(self) -> StressControlled:
        if self.max_steps <= self.shear_start_step + self.shear_ramp_steps:
            raise ValueError("max_steps must exceed shear_start_step + shear_ramp_steps")
        return self


class ConstantVelocity(Schedule):
    velocity_m_s: Positive = 0.005
    shear_displacement_mm: Positive = 20.0


@dataclass(frozen=True)
class Outcome:
    """A stress-controlled test: d_h [m] (inf unless it holds), how it ended, and the joint's K_s at
    the end [Pa/m] (the tangent stiffness at the load; nan unless it holds)."""

    d_h: float
    status: str
    steps: int
    final_ks: float


def shear_stiffness_law(
    kind: ShearLaw, sigma_n: float, p: jm.StiffnessParameters, correction: tuple[float, float] | None = None
) -> dict:
    """The scene's shear_stiffness entry of one law, in the scene's units.

    uncorrected: eq 3/4 (or eq 2 where `p.form` is corrected); corrected: eq 16 with (a, b) =
    `correction`, else the paper's; simplified: eq 17, D K_j sigma_n^n_j, with eq 18's printed 0.1164
    or D from eq 16 at tau = tau_p at this sigma_n (`p.simplified`).
    """
    fits = {
        "kj_MPa_per_mm": p.k_j / units.MPa_per_mm,
        "nj": p.n_j,
        "peak_strength": {"slope": p.tau_p_slope, "intercept_MPa": p.tau_p_intercept / units.MPa},
        "ultimate_strength": {"slope": p.tau_ult_slope, "intercept_MPa": p.tau_ult_intercept / units.MPa},
    }
    if kind == "uncorrected":
        return {"law": "bandis" if p.form == "paper" else "hyperbolic", **fits}
    if kind == "corrected":
        a, b = correction if correction is not None else (p.correction_a, p.correction_b)
        return {"law": "corrected", **fits, "a": float(a), "b": float(b)}
    if p.simplified == "paper":
        return {
            "law": "simplified",
            "kj_MPa_per_mm": p.eq18_k_j / units.MPa_per_mm,
            "nj": p.eq18_n_j,
            "d": 1.0,
        }
    tau_p, tau_ult = jm.fitted_strengths(np.array(sigma_n), p)
    d = float(laws.peak_reduction_factor(tau_p, tau_ult, p.correction_b))
    return {"law": "simplified", "kj_MPa_per_mm": fits["kj_MPa_per_mm"], "nj": p.n_j, "d": d}


def joint_law(
    shear: dict, strength: jm.StrengthParameters, p: jm.StiffnessParameters, options: JointOptions
) -> dict:
    """A barton_bandis joint-law entry: eq 15 strength, eq 8 K_n, the given shear law."""
    return {
        "law": "barton_bandis",
        "strength": {
            "jrc": strength.jrc,
            "jcs_MPa": strength.jcs / units.MPa,
            "phi_b_deg": strength.phi_b / units.deg,
            "phi_max_deg": strength.phi_max / units.deg,
            "tangent_coefficient": strength.k,
        },
        "normal_stiffness": {"law": "eq8", "q_per_mm": p.q / units.per_mm, "lg_e": p.log10_e},
        "shear_stiffness": shear,
        "stress_floor_MPa": options.stress_floor_MPa,
        "shear_stiffness_floor": options.shear_stiffness_floor,
        "after_slip": options.after_slip,
    }


class FullJoint(Section):
    """The full Barton-Bandis joint (`law: barton_bandis_mobilized`) beside the paper's in the
    constant-velocity tests: the paper's JRC, JCS and phi_b at the specimen's length; phi_r (the paper
    gives no r/R); K_n and K_s constant at each test's sigma_n, from eq 8 and K_si (eq 2's initial
    stiffness)."""

    phi_r_deg: Annotated[float, Field(gt=0, lt=90)]
    damage: Literal["barton_1985"] | Positive = "barton_1985"
    update_interval_steps: Annotated[int, Field(ge=1)] = 5


def mobilized_joint_law(
    joint: jm.StrengthParameters,
    full: FullJoint,
    p: jm.StiffnessParameters,
    specimen: Specimen,
    sigma_n: float,
) -> dict:
    """A barton_bandis_mobilized joint-law entry for one test at sigma_n [Pa], in the scene's units."""
    k_n = float(laws.normal_stiffness(sigma_n, p.q, p.log10_e))
    k_s = float(laws.initial_shear_stiffness(sigma_n, p.k_j, p.n_j, jm.SIGMA_REF))
    return {
        "law": "barton_bandis_mobilized",
        "jrc0": joint.jrc,
        "jcs0_MPa": joint.jcs / units.MPa,
        "phi_b_deg": joint.phi_b / units.deg,
        "phi_r_deg": full.phi_r_deg,
        "lab_length_m": specimen.length_mm * units.mm,
        "phi_max_deg": joint.phi_max / units.deg,
        "damage": full.damage,
        "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": k_n / units.MPa_per_mm},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": k_s / units.MPa_per_mm},
    }


def _scene(
    name: str,
    specimen: Specimen,
    density: float,
    law: dict,
    sigma_n: float,
    normal_ramp_steps: int,
    every: int,
    upper_velocity: dict | None = None,
) -> dict:
    """The box with sigma_n [Pa] ramped onto the upper half's top; loads after it and the solver are
    added by the two tests."""
    length, half = specimen.length_mm * 1e-3, specimen.height_mm * 0.5e-3
    extension = specimen.lower_extension_mm * 1e-3
    upper = {
        "name": "upper",
        "material": "limestone",
        "rectangle_m": {"x_m": -length / 2, "y_m": 0.0, "width_m": length, "height_m": half},
        "fix": ["rotation"],
        **({"velocity": upper_velocity} if upper_velocity else {}),
    }
    lower = {
        "name": "lower",
        "material": "limestone",
        "rectangle_m": {
            "x_m": -length / 2 - extension,
            "y_m": -half,
            "width_m": length + 2 * extension,
            "height_m": half,
        },
        "fix": ["x", "y", "rotation"],
    }
    joint_monitors = [
        {"name": name, "near_m": [0.0, 0.0], "quantity": quantity}
        for name, quantity in (("d_h", "us"), ("tau", "tau"), ("sigma_n", "sigma_n"), ("ks", "ks"))
    ]
    normal = {"block": "upper", "edge": "up", "sigma_n_MPa": float(sigma_n / units.MPa)}
    return {
        "name": name,
        "gravity_m_s2": [0.0, 0.0],
        "materials": {"limestone": {"density_kg_m3": density}},
        "blocks": [lower, upper],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint", "sub_contacts_per_edge": specimen.sub_contacts_per_edge},
        "loads": {"edge_stresses": [{**normal, "ramp_steps": normal_ramp_steps}]},
        "monitoring": {
            "every_steps": every,
            "monitors": [*joint_monitors, {"name": "uy", "block": "upper", "quantity": "uy"}],
        },
    }


def stress_controlled_scene(
    name: str,
    specimen: Specimen,
    run: StressControlled,
    density: float,
    law: dict,
    sigma_n: float,
    tau: float,
) -> dict:
    """The scene of one stress-controlled test (stresses in Pa); tau drags the upper half towards +x."""
    scene = _scene(name, specimen, density, law, sigma_n, run.normal_ramp_steps, run.record_every_steps)
    scene["loads"]["edge_stresses"].append(
        {
            "block": "upper",
            "edge": "up",
            "tau_MPa": float(-tau / units.MPa),  # the top edge's counter-clockwise tangent is -x
            "ramp_steps": run.shear_ramp_steps,
            "start_step": run.shear_start_step,
        }
    )
    scene["solver"] = {
        "steps": run.max_steps,
        "update_interval_steps": run.update_interval_steps,
        "stop": {
            "unbalanced_force_ratio": run.equilibrium_ratio,
            "displacement_m": run.slide_limit_mm * 1e-3,
        },
    }
    return scene


def constant_velocity_scene(
    name: str, specimen: Specimen, run: ConstantVelocity, density: float, law: dict, sigma_n: float
) -> dict:
    """The scene of one constant-velocity test (sigma_n in Pa): the upper half driven towards +x."""
    velocity = {"x_m_s": run.velocity_m_s, "start_step": run.shear_start_step}
    scene = _scene(
        name, specimen, density, law, sigma_n, run.normal_ramp_steps, run.record_every_steps, velocity
    )
    scene["solver"] = {
        "steps": 10**9,  # the displacement stop ends it: the velocity is prescribed
        "update_interval_steps": run.update_interval_steps,
        "stop": {"displacement_m": run.shear_displacement_mm * 1e-3},
    }
    return scene


def _simulate(scene: dict, economy: Economy):
    model = built_scene(scene, f"<{scene['name']}>")
    return simulate(replace(model, economy=economy))


def run_stress_controlled(scene: dict, economy: Economy = EVERY_ECONOMY) -> Outcome:
    """Run a stress-controlled test and classify how it ended: "holds" (equilibrium), "slides" (moved
    slide_limit_mm and slipped), "runs off" (moved that far without slip: K_s at its floor) or "not
    settled" (max_steps reached)."""
    result = _simulate(scene, economy)
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    h = result.history
    slipped = bool(np.any(result.state.subs[:, SLIPPED] > 0))
    if summary["stopped_by_equilibrium"]:
        status = "holds"
    elif summary["stopped_by_displacement"]:
        status = "slides" if slipped else "runs off"
    else:
        status = "not settled"
    holds = status == "holds"
    d_h = abs(float(h["d_h_mm"].iloc[-1])) * units.mm if holds else math.inf
    final_ks = float(h["ks_MPa_per_mm"].iloc[-1]) * units.MPa_per_mm if holds else math.nan
    return Outcome(d_h=d_h, status=status, steps=int(summary["steps"]), final_ks=final_ks)


def run_constant_velocity(scene: dict) -> pd.DataFrame:
    """The tau-d_h curve of a constant-velocity test from the start of shearing: d_h [mm], tau, sigma_n
    [MPa], time [s] since shearing began."""
    result = _simulate(scene, EVERY_ECONOMY)
    start = next(b for b in scene["blocks"] if b["name"] == "upper")["velocity"]["start_step"]
    steps = int(dict(zip(result.summary["quantity"], result.summary["value"], strict=True))["steps"])
    if steps < start:
        raise SimulationError(
            f"key 'constant_velocity.shear_displacement_mm': the test stopped at step {steps}, before "
            f"shearing began at step {start}: the block moved that far under the normal load alone (a joint "
            "far too soft for it)",
            bad_input=True,
        )
    h = result.history[result.history["step"] >= start]  # the last step is always recorded
    return pd.DataFrame(
        {
            "time_s": h["time_s"].to_numpy() - h["time_s"].iloc[0],
            "d_h_mm": np.abs(h["d_h_mm"].to_numpy()),
            "tau_MPa": np.abs(h["tau_MPa"].to_numpy()),
            "sigma_n_MPa": h["sigma_n_MPa"].to_numpy(),
        }
    )
