"""`bbmc fit`: the regressions of Table 1 / Fig 2 and the tau-d_h curves of Fig 1.

Inputs are the paper's measurements (Table 1), the test displacements of Table 3 and the Fig 2a
legends. Fig 1's raw curves are not published, so panel (a)'s regressions are refitted from the test
points of Table 3 (two per normal stress, four at 0.2 MPa), and Fig 1 is reconstructed from the
hyperbolic model of eq 1 with the Fig 2a legend parameters (read in `fig2a_units`), beside the same
model with Table 1's K_si and tau_ult.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import pandas as pd
from pydantic import Field

from bbmc import laws, paper_tables, plots, units
from bbmc.config import ConfigError, InputFile, Section
from bbmc.fitting import Fit, linear_fit, power_law_fit
from bbmc.io import StageResult, require_distinct
from bbmc.paper_inputs import Fig2aUnits

NAME = "fit"
COMMAND_HELP = """Table 1 / Fig 2 regressions and the Fig 1 curves.

    \b
    Example:
      bbmc fit configs/fit.yaml
    writes results/fit/table1_fits.csv, fig1_curves.csv, fig1.png, fig2.png, provenance.json
    """  # `bbmc fit --help`

STRESS_UNITS = {"Pa": units.Pa, "kPa": units.kPa, "MPa": units.MPa}
LENGTH_UNITS = {"m": units.m, "mm": units.mm}


class Inputs(Section):
    table1: InputFile
    table3: InputFile
    fig2a_legends: InputFile


class Fig1(Section):
    points_per_curve: int = Field(ge=10, le=100_000)


class Config(Section):
    data: Inputs
    power_law_method: Literal["log-log", "nonlinear"]
    fig2a_units: Fig2aUnits
    fig1: Fig1
    figure_dpi: int = Field(ge=50, le=600)


def load_inputs(config: Config) -> dict[str, pd.DataFrame]:
    """The three input tables, checked row by row; Table 3 with two or more test points per normal
    stress (a line is fitted through them for Fig 2a)."""
    d = config.data
    table3 = paper_tables.read("table3_numerical_tests", d.table3, ["sigma_n_MPa", "tau_MPa", "d_h_test_mm"])
    for sigma_n, tests in table3.groupby("sigma_n_MPa"):
        where = f" at sigma_n_MPa = {sigma_n:g}"
        require_distinct(tests, d.table3, "d_h_test_mm", "Fig 2a's line is fitted through them", where)
    return {
        "table1": paper_tables.read("table1_measurements", d.table1),
        "table3": table3,
        "legends": paper_tables.read("fig2a_legends", d.fig2a_legends, paper_tables.LEGEND_CURVES),
    }


def _row(relation: str, panel: str, fit: Fit, sigma_n_MPa: float, unit: dict[str, str]) -> dict:
    return {
        "relation": relation,
        "fig2_panel": panel,
        "method": fit.method,
        "sigma_n_MPa": sigma_n_MPa,
        "a": fit.a,
        "b": fit.b,
        "R2": fit.r2,
        "R2_linear_y": fit.r2_linear_y,
        "r": fit.r,
        "n_points": fit.n_points,
        **unit,
    }


def table1_fits(table1: pd.DataFrame, table3: pd.DataFrame, fig2a_units: Fig2aUnits) -> pd.DataFrame:
    """Every regression of Table 1 and Fig 2, ours, one row each (both power-law methods)."""
    s, tp = table1["sigma_n_MPa"].to_numpy(), table1["tau_p_MPa"].to_numpy()
    ksi, tu = table1["K_si_GPa_per_m"].to_numpy(), table1["tau_ult_MPa"].to_numpy()
    power = {"x_unit": "MPa", "y_unit": "GPa/m", "a_unit": "GPa/m at 1 MPa", "b_unit": "1"}
    line = {"x_unit": "MPa", "y_unit": "MPa", "a_unit": "1", "b_unit": "MPa"}
    rows = [
        _row("K_si_vs_sigma_n", "b", power_law_fit(s, ksi, method), np.nan, power)
        for method in ("log-log", "nonlinear")
    ]
    rows.append(_row("tau_ult_vs_tau_p", "c", linear_fit(tp, tu), np.nan, line))
    rows.append(_row("tau_p_vs_sigma_n", "d", linear_fit(s, tp), np.nan, line))
    stress_u, disp_u = fig2a_units.stress, fig2a_units.displacement
    inverse = {
        "x_unit": f"1/{disp_u}",
        "y_unit": f"1/{stress_u}",
        "a_unit": f"{disp_u}/{stress_u}",
        "b_unit": f"1/{stress_u}",
    }
    to_stress = units.MPa / STRESS_UNITS[stress_u]
    to_disp = units.mm / LENGTH_UNITS[disp_u]
    for sigma_n, group in table3.groupby("sigma_n_MPa", sort=True):
        inv_d = 1.0 / (group["d_h_test_mm"].to_numpy() * to_disp)
        inv_t = 1.0 / (group["tau_MPa"].to_numpy() * to_stress)
        fit = linear_fit(inv_d, inv_t)
        rows.append(_row("inverse_tau_vs_inverse_dh", "a", fit, float(sigma_n), inverse))
    return pd.DataFrame(rows)


def fig1_curves(
    table1: pd.DataFrame, legends: pd.DataFrame, fig2a_units: Fig2aUnits, points: int
) -> pd.DataFrame:
    """tau-d_h curves of eq 1 up to each measured peak: Fig 2a legends and Table 1's K_si, tau_ult."""
    stress_u = STRESS_UNITS[fig2a_units.stress]
    disp_u = LENGTH_UNITS[fig2a_units.displacement]
    frames = []
    for row in table1.itertuples():
        tau = np.linspace(0.0, row.tau_p_MPa, points) * units.MPa
        legend = legends.loc[np.isclose(legends["sigma_n_kPa"] * units.kPa, row.sigma_n_MPa * units.MPa)]
        models = {
            "table1_K_si_tau_ult": (
                1.0 / (row.K_si_GPa_per_m * units.GPa_per_m),
                1.0 / (row.tau_ult_MPa * units.MPa),
            )
        }
        if not legend.empty:
            models["fig2a_legend"] = (
                float(legend["slope_a"].iloc[0]) * disp_u / stress_u,
                float(legend["intercept_b"].iloc[0]) / stress_u,
            )
        for model, (m, n) in models.items():
            d_h = laws.hyperbolic_shear_displacement(tau, m, n)
            frames.append(
                pd.DataFrame(
                    {
                        "sigma_n_MPa": row.sigma_n_MPa,
                        "model": model,
                        "tau_MPa": tau / units.MPa,
                        "d_h_mm": d_h / units.mm,
                    }
                )
            )
    return pd.concat(frames, ignore_index=True)


def checked_fits(config: Config, data: dict[str, pd.DataFrame]) -> pd.DataFrame:
    """`table1_fits` of the loaded inputs; a power law that cannot be fitted to Table 1 (nonlinear least
    squares that do not converge) is a ConfigError naming it."""
    try:
        return table1_fits(data["table1"], data["table3"], config.fig2a_units)
    except ValueError as error:
        raise ConfigError(f"{config.data.table1}: K_si = a sigma_n^b: {error}") from None


def run(config: Config) -> StageResult:
    """Fit, tabulate and draw; nothing is written here."""
    data = load_inputs(config)
    fits = checked_fits(config, data)
    curves = fig1_curves(data["table1"], data["legends"], config.fig2a_units, config.fig1.points_per_curve)
    chosen = fits[(fits["relation"] != "K_si_vs_sigma_n") | (fits["method"] == config.power_law_method)]
    return StageResult(
        tables={"table1_fits": fits, "fig1_curves": curves},
        figures={
            "fig2": plots.fig2(data["table1"], data["table3"], data["legends"], chosen, config.figure_dpi),
            "fig1": plots.fig1(curves, data["table3"], config.figure_dpi),
        },
    )
