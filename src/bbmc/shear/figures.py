"""The shear stage's figures, drawn from its tables: Fig 4, Fig 6 and the calibration.

The paper's figures are missing from the text; these follow its captions. Displacements span two
orders of magnitude between the paper's and ours, so d_h axes of Fig 4 are logarithmic.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from bbmc import plots  # noqa: F401  (selects the Agg backend before any figure is drawn)

LAW_STYLE = {
    "uncorrected": ("tab:red", "N-U ours (eq 4)"),
    "corrected": ("tab:blue", "N-C ours (eq 16)"),
    "simplified": ("tab:green", "N-S ours (eq 17, D K_si)"),
}
FULL_STYLE = ("tab:orange", "full B-B joint (mobilized, shear.yaml full_joint)")
PAPER_STYLE = {
    "d_h_test_mm": ("black", "T: test (paper)"),
    "d_h_paper_uncorrected_mm": ("salmon", "N-U paper"),
    "d_h_paper_corrected_mm": ("lightskyblue", "N-C paper"),
}


def _load_labels(table3: pd.DataFrame) -> list[str]:
    return [f"{s:g}\n{t:g}" for s, t in zip(table3["sigma_n_MPa"], table3["tau_MPa"], strict=True)]


def fig4(table3: pd.DataFrame, dpi: int) -> Figure:
    """Fig 4: (a) d_h of every load, the paper's T, N-U, N-C and our three laws; (b) sigma_n = 0.2 MPa
    against tau. A test that does not hold (it slides: tau above the eq 15 strength) has no d_h:
    marked "no d_h", not drawn. The d_h axes are logarithmic: bar lengths are not proportional."""
    fig = Figure(figsize=(13, 5.5), dpi=dpi, layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.7, 1])
    series = [
        *((column, colour, label) for column, (colour, label) in PAPER_STYLE.items()),
        *((f"d_h_{law}_mm", colour, label) for law, (colour, label) in LAW_STYLE.items()),
    ]
    x = np.arange(len(table3))
    width = 0.8 / len(series)
    for k, (column, colour, label) in enumerate(series):
        values = table3[column].to_numpy(dtype=float)
        finite = np.isfinite(values)
        offset = x + (k - (len(series) - 1) / 2) * width
        ax_a.bar(
            offset[finite], values[finite], width, color=colour, label=label, edgecolor="k", linewidth=0.3
        )
        for position in offset[~finite]:
            ax_a.text(
                position, 0.02, "slides", rotation=90, ha="center", va="bottom", fontsize=6, color=colour
            )
    ax_a.set_yscale("log")
    ax_a.set_ylim(0.01, 100)
    ax_a.set_xticks(x, _load_labels(table3), fontsize=7)
    ax_a.set(
        xlabel="load: $\\sigma_n$ (MPa) over $\\tau$ (MPa)",
        ylabel="shear displacement $d_h$ (mm, log scale)",
        title="(a) every load of Table 3",
    )
    ax_a.legend(fontsize=7, ncol=2, loc="upper left")
    ax_a.grid(alpha=0.3, axis="y", which="both")

    at = table3[np.isclose(table3["sigma_n_MPa"], 0.2)]
    for column, (colour, label) in PAPER_STYLE.items():
        ax_b.plot(at["tau_MPa"], at[column], "s--", color=colour, label=label, markeredgecolor="k")
    for law, (colour, label) in LAW_STYLE.items():
        ax_b.plot(at["tau_MPa"], at[f"d_h_{law}_mm"], "o-", color=colour, label=label)
    ax_b.set_yscale("log")
    ax_b.set(
        xlabel="shear stress $\\tau$ (MPa)",
        ylabel="shear displacement $d_h$ (mm, log scale)",
        title="(b) $\\sigma_n$ = 0.2 MPa",
    )
    ax_b.legend(fontsize=7)
    ax_b.grid(alpha=0.3, which="both")
    return fig


def fig6(
    curves: pd.DataFrame, test_curves: pd.DataFrame, peaks: pd.DataFrame, velocity_m_s: float, dpi: int
) -> Figure:
    """Fig 6: tau-d_h curves of the constant-velocity tests, one panel per normal stress, beside the
    test curves of Fig 1 (eq 1 with the Fig 2a legends and with Table 1's K_si, tau_ult). Top row:
    linear d_h; bottom row: the same on a log d_h axis, where the engine's curves can be seen."""
    stresses = sorted(curves["sigma_n_applied_MPa"].unique())
    fig = Figure(figsize=(4 * len(stresses), 7.5), dpi=dpi, layout="constrained")
    axes = fig.subplots(2, len(stresses), squeeze=False)
    test_styles = {
        "fig2a_legend": ("k", "-", "test: eq 1, Fig 2a legend"),
        "table1_K_si_tau_ult": ("0.5", ":", "eq 1, Table 1 K_si, tau_ult"),
    }
    for column, sigma in enumerate(stresses):
        for row, scale in enumerate(("linear", "log")):
            ax = axes[row, column]
            for model, (colour, style, label) in test_styles.items():
                t = test_curves[
                    np.isclose(test_curves["sigma_n_MPa"], sigma) & (test_curves["model"] == model)
                ]
                if len(t):
                    ax.plot(t["d_h_mm"], t["tau_MPa"], style, color=colour, label=label)
            for law, (colour, label) in {**LAW_STYLE, "full": FULL_STYLE}.items():
                c = curves[(curves["law"] == law) & np.isclose(curves["sigma_n_applied_MPa"], sigma)]
                c = c[c["d_h_mm"] > 0] if scale == "log" else c
                ax.plot(c["d_h_mm"], c["tau_MPa"], "-", color=colour, label=label.replace(" ours", ""))
            at = peaks.loc[np.isclose(peaks["sigma_n_MPa"], sigma)].iloc[0]
            ax.axhline(at["strength_eq15_MPa"], color="0.3", lw=0.8, ls="--", label="eq 15 strength")
            ax.axhline(
                at["tau_p_measured_MPa"],
                color="tab:purple",
                lw=0.8,
                ls="-.",
                label="measured tau_p (Table 1)",
            )
            ax.set_xscale(scale)
            ax.set(
                xlabel=f"shear displacement $d_h$ (mm{', log scale' if scale == 'log' else ''})",
                ylabel="shear stress $\\tau$ (MPa)",
                title=f"$\\sigma_n$ = {sigma:g} MPa",
            )
            ax.grid(alpha=0.3, which="both")
    axes[0, 0].legend(fontsize=7, loc="lower right")
    fig.suptitle(f"Constant-velocity shear tests ({velocity_m_s:g} m/s): engine vs the test curves of Fig 1")
    return fig


def calibration_figure(detail: pd.DataFrame, fits: pd.DataFrame, dpi: int) -> Figure:
    """f(tau/tau_p) against ln(tau/tau_p): our calibrated values, the paper's K_st solved for f, and
    the fitted lines beside the paper's eq 16."""
    fig = Figure(figsize=(7, 5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    x = np.log(detail["tau_over_tau_p"].to_numpy())
    ax.plot(
        x,
        detail["f_calibrated"],
        "o",
        color="tab:blue",
        label="ours: one K_s per test, matched to the test d_h",
    )
    ax.plot(
        x,
        detail["f_from_paper_K_st"],
        "s",
        mfc="none",
        color="k",
        label="paper's corrected K_st solved for f",
    )
    grid = np.linspace(min(x.min(), -1.5), max(x.max(), 0.1), 50)
    paper = fits.iloc[0]
    ax.plot(
        grid,
        paper["paper_a"] * grid + paper["paper_b"],
        "k--",
        label=f"eq 16: {paper['paper_a']:g} ln x + {paper['paper_b']:g}",
    )
    for row, style in zip(fits.itertuples(), ("-", "-.", ":", (0, (3, 1, 1, 1))), strict=False):
        if np.isfinite(row.a) and "secant" in row.method:
            ax.plot(
                grid,
                row.a * grid + row.b,
                style,
                color="tab:blue",
                label=f"ours ({row.fit_set}): {row.a:.3f} ln x + {row.b:.3f}, $R^2$ = {row.R2:.3f}",
            )
    ax.set(
        xlabel="ln($\\tau / \\tau_p$)", ylabel="correction f($\\tau/\\tau_p$)", title="Calibration of eq 16"
    )
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig
