"""`bbmc audit`: every derivable number of the paper recomputed and judged (results/audit/audit.csv).

The audit reruns the fit and mc computations in memory from their own configs (named here), always in
the paper's reading (errata off), and compares with the paper's tables in `data/paper/`. The verdict
rule and the tolerances are in `bbmc.comparison`; the reasoning in docs/paper-audit.md.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from bbmc import audit as checks
from bbmc import paper_tables
from bbmc.config import ConfigError, InputFile, Section, load_config
from bbmc.fitting import power_law_fit
from bbmc.io import StageResult, require_distinct
from bbmc.paper_inputs import Errata, load_inputs, parameters
from bbmc.stages import fit, mc

NAME = "audit"
COMMAND_HELP = """Recompute and judge every derivable number of the paper (docs/paper-audit.md).

    \b
    Example:
      bbmc audit configs/audit.yaml
    writes results/audit/audit.csv (one row per number: paper, ours, difference, verdict,
    reasoning), summary.csv, provenance.json
    """  # `bbmc audit --help`


class PaperTables(Section):
    table1_fits: InputFile
    table2: InputFile
    table4_constant: InputFile
    table4_nonlinear: InputFile
    table4_rock: InputFile


class Config(Section):
    fit_config: InputFile
    mc_config: InputFile
    data: PaperTables


def _rows_at(table: pd.DataFrame, column: str, sigma_n_MPa: float, scale: float = 1.0) -> int:
    return int(np.isclose(table[column] * scale, sigma_n_MPa).sum())


def _check_alignment(
    fit_inputs: dict[str, pd.DataFrame], fit_data: fit.Inputs, table3: pd.DataFrame, table3_path: Path
) -> None:
    """What the audit compares across tables: each Fig 2a legend at one Table 1 normal stress, each Table
    3 test at one legend's; Phi and C printed together, at one row or more; and two or more loads at
    Table 3's highest normal stress (eq 16's a, b are recovered from them)."""
    table1, legends = fit_inputs["table1"], fit_inputs["legends"]
    for line, sigma_kPa in legends["sigma_n_kPa"].items():
        if _rows_at(table1, "sigma_n_MPa", sigma_kPa * 1e-3) != 1:
            raise ConfigError(
                f"{fit_data.fig2a_legends}: line {line}: sigma_n_kPa {sigma_kPa:g} is at no normal stress "
                f"(or at several) of {fit_data.table1}"
            )
    for line, sigma_n in table3["sigma_n_MPa"].items():
        if _rows_at(legends, "sigma_n_kPa", sigma_n, 1e-3) != 1:
            raise ConfigError(
                f"{table3_path}: line {line}: sigma_n_MPa {sigma_n:g} has no legend (or several) in "
                f"{fit_data.fig2a_legends}"
            )
    printed = table3["Phi_deg"].notna()
    if not printed.any() or (printed != table3["C_kPa"].notna()).any():
        raise ConfigError(
            f"{table3_path}: columns 'Phi_deg' and 'C_kPa' are printed together, on one row or more"
        )
    top = table3[np.isclose(table3["sigma_n_MPa"], table3["sigma_n_MPa"].max())]
    require_distinct(
        top, table3_path, "tau_MPa", "eq 16's a and b are recovered from them", " at the highest sigma_n_MPa"
    )


def _inputs(config: Config) -> checks.AuditInputs:
    fit_config = load_config(config.fit_config, fit.Config)
    mc_config = load_config(config.mc_config, mc.Config)
    fit_inputs, mc_inputs = fit.load_inputs(fit_config), load_inputs(mc_config.data)
    d = config.data
    paper_fits = paper_tables.read("table1_fits", d.table1_fits)
    table2 = paper_tables.read("table2_rock", d.table2, ["cohesion_MPa", "compressive_strength_MPa"])
    constant = paper_tables.read("table4_joints_constant", d.table4_constant)
    nonlinear = paper_tables.read(
        "table4_joints_nonlinear", d.table4_nonlinear, ["phi_b_deg", "JRC", "JCS_MPa", "eq15_coefficient"]
    )
    rock = paper_tables.read("table4_rock_mass", d.table4_rock, ["cohesion_MPa"])
    paper_reading = mc_config.model_copy(
        update={
            "stiffness_coefficients": "printed",
            "errata": Errata(
                lg_e="paper",
                tangent_coefficient="paper",
                shear_stiffness_form="paper",
                eq18_coefficient="paper",
            ),
        }
    )
    strength, stiffness = parameters(paper_reading, mc_inputs)
    table3 = paper_tables.read("table3_numerical_tests", mc_config.data.table3)
    _check_alignment(fit_inputs, fit_config.data, table3, mc_config.data.table3)
    table1 = fit_inputs["table1"]
    unrounded = power_law_fit(table1["sigma_n_MPa"], table1["K_si_GPa_per_m"], "log-log")
    return checks.AuditInputs(
        table1=table1,
        paper_fits=paper_fits,
        legends=fit_inputs["legends"],
        table2=table2,
        table3=table3,
        table4_constant=constant,
        table4_nonlinear=nonlinear,
        table4_rock=rock,
        printed=paper_tables.printed_constants(mc_inputs["constants"]),
        our_fits=fit.checked_fits(fit_config, fit_inputs),
        strength=strength,
        stiffness=stiffness,
        k_j_unrounded=unrounded.a,
        n_j_unrounded=unrounded.b,
    )


def run(config: Config) -> StageResult:
    """Check every derivable number; tabulate the verdicts."""
    table = checks.audit(_inputs(config))
    summary = table.groupby(["source", "verdict"]).size().rename("checks").reset_index()
    return StageResult(tables={"audit": table, "summary": summary})
