"""Figures, drawn from the stages' tables (never from anything the tables do not hold).

Axes carry units; every curve has a legend entry. Matplotlib's non-interactive Agg backend is used,
so figures render on machines without a screen.
"""

from __future__ import annotations

import itertools

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]


def _equation(row: pd.Series, x: str, y: str) -> str:
    if row["relation"] == "K_si_vs_sigma_n":
        return f"${y} = {row['a']:.4f}\\,{x}^{{{row['b']:.4f}}}$,  $R^2 = {row['R2']:.4f}$"
    sign = "+" if row["b"] >= 0 else "-"
    return f"${y} = {row['a']:.4f}\\,{x} {sign} {abs(row['b']):.4f}$,  $R^2 = {row['R2']:.4f}$"


def _panel(ax, x, y, row, xlabel, ylabel, xs, ys, title) -> None:
    ax.plot(x, y, "o", color="k", label="Table 1 (measured)")
    grid = np.linspace(0.0, float(np.max(x)) * 1.1, 200)
    if row["relation"] == "K_si_vs_sigma_n":
        grid = grid[1:]
        fitted = row["a"] * grid ** row["b"]
    else:
        fitted = row["a"] * grid + row["b"]
    ax.plot(
        grid,
        fitted,
        "-",
        color="tab:blue",
        label=f"ours ({row['method']}): " + _equation(row, xs, ys),
    )
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)


def fig2(
    table1: pd.DataFrame,
    table3: pd.DataFrame,
    legends: pd.DataFrame,
    fits: pd.DataFrame,
    dpi: int,
) -> Figure:
    """Fig 2 (a)-(d): data, our fitted curve, equation and R^2 in the legend."""
    fig = Figure(figsize=(12, 9), dpi=dpi, layout="constrained")
    axes = fig.subplots(2, 2)
    inverse = fits[fits["relation"] == "inverse_tau_vs_inverse_dh"]
    ax = axes[0, 0]
    for colour, row in zip(itertools.cycle(COLOURS), inverse.itertuples(), strict=False):
        points = table3[np.isclose(table3["sigma_n_MPa"], row.sigma_n_MPa)]
        x_unit, y_unit = row.x_unit, row.y_unit
        scale_d = 1.0 if x_unit == "1/mm" else 1e-3
        scale_t = {"1/kPa": 1e-3, "1/MPa": 1.0, "1/Pa": 1e-6}[y_unit]
        inv_d = 1.0 / (points["d_h_test_mm"].to_numpy() * scale_d)
        inv_t = 1.0 / (points["tau_MPa"].to_numpy() / scale_t)
        grid = np.linspace(0.0, inv_d.max() * 1.15, 50)
        kpa = row.sigma_n_MPa * 1e3
        ax.plot(inv_d, inv_t, "o", color=colour, label=f"{kpa:.0f} kPa: Table 3 test points")
        ax.plot(
            grid,
            row.a * grid + row.b,
            "-",
            color=colour,
            label=f"  ours: $\\tau^{{-1}} = {row.a:.4f}\\,d_h^{{-1}} {row.b:+.4f}$ (n = {row.n_points})",
        )
        at = np.isclose(legends["sigma_n_kPa"], kpa)  # the paper's legend at this normal stress, if any
        for legend in legends[at].itertuples():
            a, b = legend.slope_a, legend.intercept_b
            label = f"  paper legend: $\\tau^{{-1}} = {a}\\,d_h^{{-1}} {b:+}$"
            ax.plot(grid, a * grid + b, ":", color=colour, label=label)
    ax.set(
        xlabel=f"$1/d_h$ [{x_unit}]",
        ylabel=f"$1/\\tau$ [{y_unit}]",
        title="(a) $1/\\tau$ - $1/d_h$ (Fig 1 data unpublished: Table 3 test points)",
    )
    ax.legend(fontsize=6, loc="upper left")
    ax.grid(alpha=0.3)
    by_relation = {r["relation"]: r for _, r in fits.iterrows()}
    _panel(
        axes[0, 1],
        table1["sigma_n_MPa"],
        table1["K_si_GPa_per_m"],
        by_relation["K_si_vs_sigma_n"],
        "$\\sigma_n$ [MPa]",
        "$K_{si}$ [GPa/m]",
        "\\sigma_n",
        "K_{si}",
        "(b) $K_{si}$ - $\\sigma_n$",
    )
    _panel(
        axes[1, 0],
        table1["tau_p_MPa"],
        table1["tau_ult_MPa"],
        by_relation["tau_ult_vs_tau_p"],
        "$\\tau_p$ [MPa]",
        "$\\tau_{ult}$ [MPa]",
        "\\tau_p",
        "\\tau_{ult}",
        "(c) $\\tau_{ult}$ - $\\tau_p$",
    )
    _panel(
        axes[1, 1],
        table1["sigma_n_MPa"],
        table1["tau_p_MPa"],
        by_relation["tau_p_vs_sigma_n"],
        "$\\sigma_n$ [MPa]",
        "$\\tau_p$ [MPa]",
        "\\sigma_n",
        "\\tau_p",
        "(d) $\\tau_p$ - $\\sigma_n$",
    )
    fig.suptitle("Fig 2: fitting curves of the shear strength parameters (bbmc fit)")
    return fig


def fig1(curves: pd.DataFrame, table3: pd.DataFrame, dpi: int) -> Figure:
    """Fig 1 reconstructed: tau-d_h of eq 1 at the four normal stresses, with the Table 3 test points."""
    fig = Figure(figsize=(8, 5.5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    styles = {
        "fig2a_legend": ("-", "eq 1, Fig 2a legend"),
        "table1_K_si_tau_ult": ("--", "eq 1, Table 1 $K_{si}$, $\\tau_{ult}$"),
    }
    for colour, (sigma_n, group) in zip(COLOURS, curves.groupby("sigma_n_MPa"), strict=False):
        kpa = sigma_n * 1e3
        for model, (style, text) in styles.items():
            curve = group[group["model"] == model]
            if not curve.empty:
                ax.plot(
                    curve["d_h_mm"],
                    curve["tau_MPa"],
                    style,
                    color=colour,
                    label=f"{kpa:.0f} kPa: {text}",
                )
        points = table3[np.isclose(table3["sigma_n_MPa"], sigma_n)]
        ax.plot(
            points["d_h_test_mm"],
            points["tau_MPa"],
            "o",
            color=colour,
            label=f"{kpa:.0f} kPa: Table 3 test",
        )
    ax.set(
        xlabel="shear displacement $d_h$ [mm]",
        ylabel="shear stress $\\tau$ [MPa]",
        title="Fig 1 reconstructed: $\\tau$ - $d_h$ up to the measured peak $\\tau_p$",
    )
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    return fig


def envelope(grid: pd.DataFrame, tangents: pd.DataFrame, table1: pd.DataFrame, dpi: int) -> Figure:
    """B-B envelope (eq 9) with the tangent M-C lines (eqs 14-15) at the chosen normal stresses."""
    fig = Figure(figsize=(8, 5.5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    top = 2.5 * float(tangents["sigma_n_MPa"].max())
    shown = grid[grid["sigma_n_MPa"] <= top]
    ax.plot(
        shown["sigma_n_MPa"],
        shown["tau_p_bb_MPa"],
        "k-",
        lw=2,
        label="Barton-Bandis envelope (eq 9)",
    )
    s = np.linspace(0.0, top, 50)
    for colour, row in zip(COLOURS, tangents.itertuples(), strict=False):
        line = row.C_kPa / 1e3 + s * np.tan(np.radians(row.Phi_deg))
        ax.plot(
            s,
            line,
            "--",
            color=colour,
            label=(
                f"M-C tangent at {row.sigma_n_MPa:g} MPa: "
                f"$\\varphi$ = {row.Phi_deg:.2f}°, c = {row.C_kPa:.2f} kPa"
            ),
        )
        ax.plot(row.sigma_n_MPa, row.tau_p_bb_MPa, "o", color=colour)
    ax.plot(
        table1["sigma_n_MPa"],
        table1["tau_p_MPa"],
        "s",
        color="grey",
        label="measured $\\tau_p$ (Table 1)",
    )
    ax.set(
        xlabel="normal stress $\\sigma_n$ [MPa]",
        ylabel="peak shear strength $\\tau_p$ [MPa]",
        title="B-B envelope and its equivalent Mohr-Coulomb tangents",
        xlim=(0, top),
        ylim=(0, None),
    )
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def phi_c(grid: pd.DataFrame, tangents: pd.DataFrame, dpi: int) -> Figure:
    """Equivalent friction angle and cohesion against normal stress (eq 15 and exact eq 14)."""
    fig = Figure(figsize=(9, 4.5), dpi=dpi, layout="constrained")
    left, right = fig.subplots(1, 2)
    left.semilogx(grid["sigma_n_MPa"], grid["Phi_deg"], "k-", label="equivalent $\\varphi$ (pipeline's k)")
    left.semilogx(
        grid["sigma_n_MPa"],
        grid["Phi_exact_k_deg"],
        "b:",
        label="equivalent $\\varphi$, exact k (eq 14)",
    )
    left.semilogx(
        grid["sigma_n_MPa"],
        grid["total_friction_angle_deg"],
        "g--",
        label="total angle $\\varphi_b + i$",
    )
    right.loglog(grid["sigma_n_MPa"], grid["C_kPa"], "k-", label="equivalent c (pipeline's k)")
    right.loglog(grid["sigma_n_MPa"], grid["C_exact_k_kPa"], "b:", label="equivalent c, exact k (eq 14)")
    left.plot(tangents["sigma_n_MPa"], tangents["Phi_deg"], "o", color="tab:red", label="test stresses")
    right.plot(tangents["sigma_n_MPa"], tangents["C_kPa"], "o", color="tab:red", label="test stresses")
    left.set(xlabel="$\\sigma_n$ [MPa]", ylabel="friction angle [°]", title="equivalent friction angle")
    right.set(xlabel="$\\sigma_n$ [MPa]", ylabel="cohesion c [kPa]", title="equivalent cohesion")
    for ax in (left, right):
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, which="both")
    return fig


def stiffness_laws(curves: pd.DataFrame, dpi: int) -> Figure:
    """K_st against tau/tau_p: uncorrected (eq 4), corrected (eq 16), simplified (eqs 17-18)."""
    fig = Figure(figsize=(8, 5.5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    laws_ = [
        ("K_st_uncorrected_MPa_per_mm", "-", "uncorrected (eq 4)"),
        ("K_st_corrected_MPa_per_mm", "--", "corrected (eq 16)"),
        ("K_st_simplified_MPa_per_mm", ":", "simplified (eqs 17-18)"),
    ]
    for colour, (sigma_n, group) in zip(COLOURS, curves.groupby("sigma_n_MPa"), strict=False):
        for column, style, text in laws_:
            ax.plot(
                group["tau_over_tau_p"],
                group[column],
                style,
                color=colour,
                label=f"{sigma_n:g} MPa: {text}",
            )
    ax.axvline(1.0, color="grey", lw=0.8)
    ax.set(
        xlabel="$\\tau / \\tau_p$ [-] ($\\tau_p$ from the Table 1 fit)",
        ylabel="shear stiffness $K_{st}$ [MPa/mm]",
        title="Shear stiffness laws",
    )
    ax.legend(fontsize=6, ncol=2)
    ax.grid(alpha=0.3)
    return fig
