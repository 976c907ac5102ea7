"""The config of the paper's direct shear tests (`bbmc shear`, configs/shear.yaml) and the input tables
it names, read and checked (`load_inputs`)."""

from __future__ import annotations

import pandas as pd
from pydantic import Field, model_validator

from bbmc import paper_inputs as pi
from bbmc import paper_tables
from bbmc.config import InputFile, Section
from bbmc.joint import model as jm
from bbmc.shear import box


class Inputs(pi.Inputs):
    table2: InputFile
    fig2a_legends: InputFile  # for the test curves of Fig 1, drawn beside Fig 6


class FitSet(Section):
    name: str = Field(min_length=1)
    sigma_n_MPa: list[float] | None = None  # the loads at these normal stresses; none: every load


class CalibrationSettings(Section):
    fit_sets: list[FitSet] = Field(min_length=1)
    tolerance_log_k: float = Field(gt=0, le=1e-3)


class Quick(Section):
    """What `--quick` changes: a faster shear ramp, and coarser curves."""

    shear_ramp_steps: int = Field(ge=1)
    velocity_record_every_steps: int = Field(ge=1)


class Config(Section):
    data: Inputs
    joint: jm.BartonBandisJoint
    stiffness_coefficients: pi.Coefficients
    errata: pi.Errata
    specimen: box.Specimen
    joint_options: box.JointOptions
    stress_controlled: box.StressControlled
    constant_velocity: box.ConstantVelocity
    full_joint: box.FullJoint
    calibration: CalibrationSettings
    fig2a_units: pi.Fig2aUnits
    quick: Quick
    figure_dpi: int = Field(ge=50, le=600)

    @model_validator(mode="after")
    def _constant_contact_length(self) -> Config:
        extension = self.specimen.lower_extension_mm
        for key, value in (
            ("stress_controlled.slide_limit_mm", self.stress_controlled.slide_limit_mm),
            ("constant_velocity.shear_displacement_mm", self.constant_velocity.shear_displacement_mm),
        ):
            if value > extension:
                raise ValueError(
                    f"{key} ({value:g}) exceeds specimen.lower_extension_mm ({extension:g}): the joint would "
                    "lose contact length, and the nominal tau of the laws would no longer be the joint's"
                )
        return self


def load_inputs(config: Config) -> dict[str, pd.DataFrame]:
    inputs = pi.load_inputs(config.data)
    d = config.data
    inputs["table2"] = paper_tables.read("table2_rock", d.table2, ["density_kg_per_m3"])
    inputs["table3"] = paper_tables.read("table3_numerical_tests", d.table3)
    inputs["legends"] = paper_tables.read("fig2a_legends", d.fig2a_legends, paper_tables.LEGEND_CURVES)
    return inputs
