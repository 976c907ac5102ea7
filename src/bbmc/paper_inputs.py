"""The paper's joint-model inputs as the mc and shear computations read them: which tables (`Inputs`,
checked by `load_inputs`), how to read them (`Coefficients`, `Errata`, `Fig2aUnits`), and the SI
parameter sets of the B-B strength and the stiffness laws they give (`parameters`).
"""

from __future__ import annotations

from typing import Literal, Protocol

import pandas as pd

from bbmc import paper_tables
from bbmc.config import InputFile, Section
from bbmc.joint import model as jm

Coefficients = Literal["printed", "fitted"]  # eq 4's coefficients: as printed, or our Table 1 fits


class Inputs(Section):
    table1: InputFile
    table3: InputFile
    equation_constants: InputFile


class Errata(Section):
    lg_e: jm.Choice
    tangent_coefficient: jm.Choice
    shear_stiffness_form: jm.Choice
    eq18_coefficient: jm.Choice


class Fig2aUnits(Section):
    stress: Literal["Pa", "kPa", "MPa"]
    displacement: Literal["m", "mm"]


class JointModelConfig(Protocol):
    """What `parameters` reads from a config (the mc and shear stages share it)."""

    joint: jm.BartonBandisJoint
    stiffness_coefficients: Coefficients
    errata: Errata


def load_inputs(data: Inputs) -> dict[str, pd.DataFrame]:
    """Table 1 (for fitted coefficients), Table 3's loads and the printed constants, checked."""
    return {
        "table1": paper_tables.read("table1_measurements", data.table1),
        "table3": paper_tables.read("table3_numerical_tests", data.table3, ["sigma_n_MPa", "tau_MPa"]),
        "constants": paper_tables.read("equation_constants", data.equation_constants),
    }


def parameters(
    config: JointModelConfig, inputs: dict[str, pd.DataFrame]
) -> tuple[jm.StrengthParameters, jm.StiffnessParameters]:
    """The SI parameter sets this config asks for."""
    printed = paper_tables.printed_constants(inputs["constants"])
    if config.stiffness_coefficients == "fitted":
        printed |= jm.fitted_coefficients(inputs["table1"])
    j, e = config.joint, config.errata
    strength = jm.strength_parameters(
        j.jrc,
        j.jcs_MPa,
        j.phi_b_deg,
        j.phi_max_deg,
        e.tangent_coefficient,
        printed["eq15.tangent_coefficient"],
    )
    stiffness = jm.stiffness_parameters(printed, e.lg_e, e.shear_stiffness_form, e.eq18_coefficient)
    return strength, stiffness
