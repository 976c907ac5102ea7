"""`bbmc audit`: every derivable number of the paper recomputed and judged (results/audit/audit.csv).

The audit reruns the fit and mc computations in memory from their own configs (named here), always in
the paper's reading (errata off), and compares with the paper's tables in `data/paper/`. The verdict
rule and the tolerances are in `bbmc.comparison`; the reasoning in docs/paper-audit.md.
"""

from __future__ import annotations

from bbmc import audit as checks
from bbmc.config import InputFile, Section, load_config
from bbmc.fitting import power_law_fit
from bbmc.io import ANY, POSITIVE, StageResult, read_table
from bbmc.joint import model as jm
from bbmc.paper_inputs import Errata, load_inputs, parameters
from bbmc.stages import fit, mc

NAME = "audit"


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


def _inputs(config: Config) -> checks.AuditInputs:
    fit_config = load_config(config.fit_config, fit.Config)
    mc_config = load_config(config.mc_config, mc.Config)
    fit_inputs, mc_inputs = fit.load_inputs(fit_config), load_inputs(mc_config.data)
    d = config.data
    paper_fits = read_table(d.table1_fits, {"a": ANY, "b": ANY, "correlation_coefficient": POSITIVE})
    table2 = read_table(d.table2, {"cohesion_MPa": POSITIVE, "compressive_strength_MPa": POSITIVE})
    constant = read_table(
        d.table4_constant, {c: POSITIVE for c in ["K_s_MPa_per_mm", "K_n_MPa_per_mm", "phi_deg", "c_kPa"]}
    )
    nonlinear = read_table(
        d.table4_nonlinear,
        {c: POSITIVE for c in ["phi_b_deg", "JRC", "JCS_MPa", "eq15_coefficient"]},
    )
    rock = read_table(d.table4_rock, {"cohesion_MPa": POSITIVE})
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
    table1 = fit_inputs["table1"]
    unrounded = power_law_fit(table1["sigma_n_MPa"], table1["K_si_GPa_per_m"], "log-log")
    return checks.AuditInputs(
        table1=table1,
        paper_fits=paper_fits,
        legends=fit_inputs["legends"],
        table2=table2,
        table3=read_table(
            mc_config.data.table3,
            {
                c: POSITIVE
                for c in [
                    "K_st_uncorrected_MPa_per_mm",
                    "K_st_corrected_MPa_per_mm",
                    "K_n_MPa_per_mm",
                    "Phi_deg",
                    "C_kPa",
                    "d_h_test_mm",
                    "d_h_numerical_uncorrected_mm",
                    "d_h_numerical_corrected_mm",
                ]
            }
            | {"sigma_n_MPa": POSITIVE, "tau_MPa": POSITIVE},
        ),
        table4_constant=constant,
        table4_nonlinear=nonlinear,
        table4_rock=rock,
        printed=jm.printed_constants(mc_inputs["constants"]),
        our_fits=fit.table1_fits(table1, fit_inputs["table3"], fit_config.fig2a_units),
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
