"""`bbmc joint`: one joint's behaviour from its Barton-Bandis parameters, at lab and field scale, in the
style of Barton's figures: scale effects, peak and residual envelopes with their tangent phi and c, the
mobilized tau-delta and dilation curves, and the Bandis closure.

The config gives the joint in the units of its key names; they are converted to SI here, and the
computing is in `bbmc.joint.curves`, the drawing in `bbmc.joint.figures`.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, ValidationInfo, field_validator

from bbmc import units
from bbmc.io import StageResult
from bbmc.joint import curves as jc
from bbmc.joint import figures as joint_figures
from bbmc.joint.derived import full_joint
from bbmc.joint.inputs import FullJointInputs, wall_not_stronger_than_rock
from bbmc.laws.mobilized import MOBILIZATION_TABLE

NAME = "joint"
COMMAND_HELP = """A joint's behaviour from its Barton-Bandis parameters, at lab and field scale: scale
    effects, peak and residual envelopes with tangent phi and c, tau-delta and dilation curves, closure.

    \b
    Example:
      bbmc joint configs/joint.yaml
    writes results/joint/scale.csv, envelopes.csv, shear_curves.csv, closure.csv, envelopes.png,
    shear_curves.png, mobilization.png, closure.png, provenance.json
    """  # `bbmc joint --help`


class Config(FullJointInputs):
    """The joint (`bbmc.joint.inputs`, the scene's checks; here also JRC_0 > 0, the field length and the
    rock's sigma_c required) and what to draw."""

    jrc0: float = Field(gt=0, le=20)  # a smooth joint has no scale effect or mobilization to draw
    field_length_m: float = Field(gt=0)  # L_n
    sigma_c_MPa: float = Field(gt=0)  # for the initial aperture a_j
    normal_stresses_MPa: list[float] = Field(min_length=1, max_length=6)
    envelope_range_MPa: list[float] = Field(min_length=2, max_length=2)
    max_displacement_ratio: float = Field(gt=1, le=1000)  # delta/delta_peak at the curves' end
    figure_dpi: int = Field(ge=50, le=600)

    @field_validator("sigma_c_MPa")
    @classmethod
    def _rock_not_weaker_than_wall(cls, value: float, info: ValidationInfo) -> float:
        jcs0 = info.data.get("jcs0_MPa")
        if jcs0 is not None:
            wall_not_stronger_than_rock(value, jcs0)
        return value

    @field_validator("normal_stresses_MPa")
    @classmethod
    def _stresses(cls, value: list[float], info: ValidationInfo) -> list[float]:
        jcs0 = info.data.get("jcs0_MPa")
        if any(s <= 0 for s in value) or (jcs0 is not None and any(s >= jcs0 for s in value)):
            raise ValueError(f"each must be > 0 and < jcs0_MPa ({jcs0})")
        if len(set(value)) != len(value):
            raise ValueError("must be distinct")
        return value

    @field_validator("envelope_range_MPa")
    @classmethod
    def _range(cls, value: list[float], info: ValidationInfo) -> list[float]:
        low, high = value
        jcs0 = info.data.get("jcs0_MPa")
        if not 0 < low < high or (jcs0 is not None and high > jcs0):
            raise ValueError(f"must be [low, high] with 0 < low < high <= jcs0_MPa ({jcs0})")
        return value


def joint_parameters(config: Config) -> jc.Joint:
    """The config's joint in SI, phi_r and the closure derived once (`bbmc.joint.derived`)."""
    phi_b = config.phi_b_deg * units.deg
    lab, field = config.lab_length_m * units.m, config.field_length_m * units.m
    derived = full_joint(
        config.jrc0,
        config.jcs0_MPa * units.MPa,
        lab,
        field,
        phi_b=phi_b,
        phi_r=None if config.phi_r_deg is None else config.phi_r_deg * units.deg,
        rebound_ratio=config.rebound_ratio,
        sigma_c=config.sigma_c_MPa * units.MPa,
    )
    return jc.Joint(
        jrc0=config.jrc0,
        jcs0=config.jcs0_MPa * units.MPa,
        phi_b=phi_b,
        phi_r=derived.phi_r,
        lab_length=lab,
        field_length=field,
        closure=derived.closure,
        phi_max=config.phi_max_deg * units.deg,
        damage=None if config.damage == "barton_1985" else float(config.damage),
    )


def run(config: Config) -> StageResult:
    """Tabulate the joint's scale effects, envelopes, shear curves and closure; draw them."""
    joint = joint_parameters(config)
    low, high = (s * units.MPa for s in config.envelope_range_MPa)
    stresses = np.sort(np.asarray(config.normal_stresses_MPa)) * units.MPa
    scale = jc.scale_table(joint)
    envelopes = jc.envelope_table(joint, jc.envelope_stresses(low, high))
    curves = jc.shear_curves_table(joint, stresses, config.max_displacement_ratio)
    closing = jc.closure_table(joint.closure, jc.closure_stresses(joint.closure, high))
    dpi = config.figure_dpi
    return StageResult(
        tables={
            "scale": scale,
            "envelopes": envelopes,
            "shear_curves": curves,
            "closure": closing,
        },
        figures={
            "envelopes": joint_figures.envelopes(envelopes, curves, dpi),
            "shear_curves": joint_figures.shear_curves(curves, scale, dpi),
            "mobilization": joint_figures.mobilization(curves, MOBILIZATION_TABLE, dpi),
            "closure": joint_figures.closure(closing, dpi),
        },
    )
