"""`bbmc mc`: the equivalent Mohr-Coulomb parameters of the B-B criterion (eqs 9-15) and the stiffness
laws (eqs 2-8, 16-18), on a stress grid and at every load of Table 3.

Only the loads (sigma_n, tau) are read from Table 3; every other column is computed. Which printed
numbers the paper got wrong, and the switches that choose between the paper's and the corrected
reading, are in `bbmc.joint.model` and docs/paper-audit.md.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from pydantic import Field, field_validator, model_validator

from bbmc import plots, units
from bbmc.config import Section
from bbmc.io import StageResult
from bbmc.joint import model as jm
from bbmc.paper_inputs import Coefficients, Errata, Inputs, load_inputs, parameters

NAME = "mc"
COMMAND_HELP = """Equivalent Mohr-Coulomb phi, c (eqs 9-15) and the stiffness laws (eqs 2-8, 16-18).

    \b
    Example:
      bbmc mc configs/mc.yaml
    writes results/mc/mc_grid.csv, table3_mc.csv, tangent_lines.csv, stiffness_curves.csv,
    envelope.png, phi_c.png, stiffness_laws.png, provenance.json
    """  # `bbmc mc --help`


class Grid(Section):
    sigma_n_min_MPa: float = Field(gt=0)
    sigma_n_max_MPa: float = Field(gt=0)
    points: int = Field(ge=2, le=1_000_000)

    @model_validator(mode="after")
    def _ordered(self) -> Grid:
        if self.sigma_n_max_MPa <= self.sigma_n_min_MPa:
            raise ValueError("sigma_n_max_MPa must exceed sigma_n_min_MPa")
        return self


class Config(Section):
    data: Inputs
    joint: jm.BartonBandisJoint
    stiffness_coefficients: Coefficients
    errata: Errata
    grid: Grid
    tangent_stresses_MPa: list[float] = Field(min_length=1, max_length=12)
    figure_dpi: int = Field(ge=50, le=600)

    @field_validator("tangent_stresses_MPa")
    @classmethod
    def _positive_stresses(cls, value: list[float]) -> list[float]:
        if any(s <= 0 for s in value):
            raise ValueError("must all be > 0 (a strength is asked there)")
        return value


def _mpa_mm(values: np.ndarray) -> np.ndarray:
    return values / units.MPa_per_mm


def state_table(
    sigma_n: np.ndarray,
    tau: np.ndarray,
    strength: jm.StrengthParameters,
    stiffness: jm.StiffnessParameters,
) -> pd.DataFrame:
    """Strength and stiffness at each (sigma_n, tau) [Pa], in the paper's units."""
    s = jm.strength_state(sigma_n, strength)
    k = jm.stiffness_state(sigma_n, tau, stiffness)
    return pd.DataFrame(
        {
            "sigma_n_MPa": sigma_n / units.MPa,
            "tau_MPa": tau / units.MPa,
            "tau_p_bb_MPa": s["tau_p_bb"] / units.MPa,
            "tau_p_fit_MPa": k["tau_p_fit"] / units.MPa,
            "tau_ult_fit_MPa": k["tau_ult_fit"] / units.MPa,
            "K_si_MPa_per_mm": _mpa_mm(k["K_si"]),
            "K_st_uncorrected_MPa_per_mm": _mpa_mm(k["K_st_uncorrected"]),
            "K_st_corrected_MPa_per_mm": _mpa_mm(k["K_st_corrected"]),
            "K_st_simplified_MPa_per_mm": _mpa_mm(k["K_st_simplified"]),
            "K_n_MPa_per_mm": _mpa_mm(k["K_n"]),
            "total_friction_angle_deg": s["total_friction_angle"] / units.deg,
            "Phi_deg": s["phi"] / units.deg,
            "C_kPa": s["c"] / units.kPa,
        }
    )


def stiffness_curves(sigma_n_MPa: np.ndarray, stiffness: jm.StiffnessParameters, points: int) -> pd.DataFrame:
    """K_st against tau/tau_p (0 to 1.2) for the three shear laws at each normal stress."""
    frames = []
    ratio = np.linspace(0.0, 1.2, points)
    for s in sigma_n_MPa:
        sigma_n = np.full_like(ratio, s * units.MPa)
        tau_p, _ = jm.fitted_strengths(sigma_n, stiffness)
        k = jm.stiffness_state(sigma_n, ratio * tau_p, stiffness)
        frames.append(
            pd.DataFrame(
                {
                    "sigma_n_MPa": s,
                    "tau_over_tau_p": ratio,
                    "tau_MPa": ratio * tau_p / units.MPa,
                    "K_st_uncorrected_MPa_per_mm": _mpa_mm(k["K_st_uncorrected"]),
                    "K_st_corrected_MPa_per_mm": _mpa_mm(k["K_st_corrected"]),
                    "K_st_simplified_MPa_per_mm": _mpa_mm(k["K_st_simplified"]),
                }
            )
        )
    return pd.concat(frames, ignore_index=True)


def run(config: Config) -> StageResult:
    """Evaluate the laws on the grid, at Table 3's loads and at the tangent stresses; draw."""
    inputs = load_inputs(config.data)
    strength, stiffness = parameters(config, inputs)
    g = config.grid
    sigma_grid = np.geomspace(g.sigma_n_min_MPa, g.sigma_n_max_MPa, g.points) * units.MPa
    grid = state_table(sigma_grid, np.zeros_like(sigma_grid), strength, stiffness).drop(
        columns=["tau_MPa", "K_st_uncorrected_MPa_per_mm", "K_st_corrected_MPa_per_mm"]
    )
    exact = jm.strength_parameters(
        config.joint.jrc,
        config.joint.jcs_MPa,
        config.joint.phi_b_deg,
        config.joint.phi_max_deg,
        "corrected",
        0.0,
    )
    exact_state = jm.strength_state(sigma_grid, exact)
    grid["Phi_exact_k_deg"] = exact_state["phi"] / units.deg
    grid["C_exact_k_kPa"] = exact_state["c"] / units.kPa
    loads = inputs["table3"]
    table3 = state_table(
        loads["sigma_n_MPa"].to_numpy() * units.MPa,
        loads["tau_MPa"].to_numpy() * units.MPa,
        strength,
        stiffness,
    )
    tangents_at = np.asarray(config.tangent_stresses_MPa) * units.MPa
    tangents = state_table(tangents_at, np.zeros_like(tangents_at), strength, stiffness)[
        ["sigma_n_MPa", "tau_p_bb_MPa", "total_friction_angle_deg", "Phi_deg", "C_kPa"]
    ]
    curves = stiffness_curves(np.unique(loads["sigma_n_MPa"].to_numpy()), stiffness, 121)
    dpi = config.figure_dpi
    return StageResult(
        tables={
            "mc_grid": grid,
            "table3_mc": table3,
            "tangent_lines": tangents,
            "stiffness_curves": curves,
        },
        figures={
            "envelope": plots.envelope(grid, tangents, inputs["table1"], dpi),
            "phi_c": plots.phi_c(grid, tangents, dpi),
            "stiffness_laws": plots.stiffness_laws(curves, dpi),
        },
    )
