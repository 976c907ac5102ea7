"""The figures of `bbmc joint`, in the style of Barton's, drawn from its tables only (`bbmc.joint.curves`).

Axes carry units; lab scale is drawn solid and field scale dashed, one colour per normal stress.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from bbmc.plots import COLOURS

SCALE_STYLE = {"lab": "-", "field": "--"}
SCALE_MARKER = {"lab": "o", "field": "s"}


def _stress_colours(curves: pd.DataFrame) -> dict[float, str]:
    """One colour per normal stress of the shear curves, in increasing order."""
    stresses = sorted(curves["sigma_n_MPa"].unique())
    return {s: COLOURS[i % len(COLOURS)] for i, s in enumerate(stresses)}


def _scale_handles() -> list[Line2D]:
    return [Line2D([], [], color="k", ls=SCALE_STYLE[name], label=f"{name} scale") for name in SCALE_STYLE]


def envelopes(envelopes: pd.DataFrame, curves: pd.DataFrame, dpi: int) -> Figure:
    """(a) Peak envelopes at lab and field scale (phi_b and phi_r forms), residual line and the peaks of
    the tau-delta curves; (b), (c) the peak's tangent friction angle and cohesion against sigma_n."""
    fig = Figure(figsize=(10, 9), dpi=dpi, layout="constrained")
    axes = fig.subplot_mosaic([["env", "env"], ["phi", "c"]], height_ratios=[1.4, 1])
    ax = axes["env"]
    s = envelopes["sigma_n_MPa"]
    colour = {"lab": "tab:blue", "field": "tab:orange"}
    for name in ("lab", "field"):
        ax.plot(
            s,
            envelopes[f"tau_peak_{name}_MPa"],
            SCALE_STYLE[name],
            color=colour[name],
            lw=2,
            label=f"peak, {name}: $\\sigma_n \\tan(\\varphi_b + JRC\\,\\lg(JCS/\\sigma_n))$",
        )
        ax.plot(
            s,
            envelopes[f"tau_peak_phi_r_{name}_MPa"],
            ":",
            color=colour[name],
            lw=1.5,
            label=f"peak, {name}, with $\\varphi_r$ for $\\varphi_b$ (Barton & Choubey 1977)",
        )
        peaks = curves[curves["scale"] == name].groupby("sigma_n_MPa")["tau_MPa"].max()
        ax.plot(
            peaks.index,
            peaks.to_numpy(),
            SCALE_MARKER[name],
            color=colour[name],
            mfc="white",
            label=f"peak of the $\\tau$-$\\delta$ curves, {name}",
        )
    ax.plot(
        s,
        envelopes["tau_residual_MPa"],
        "-.",
        color="grey",
        lw=1.5,
        label="residual: $\\sigma_n \\tan\\,\\varphi_r$",
    )
    ax.set(
        xlabel="normal stress $\\sigma_n$ [MPa]",
        ylabel="shear strength $\\tau$ [MPa]",
        title="(a) peak and residual strength envelopes",
        xlim=(0, float(s.max())),
        ylim=(0, None),
    )
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    for key, column, ylabel, title in (
        (
            "phi",
            "phi_tangent_{}_deg",
            "tangent friction angle $\\varphi$ [°]",
            "(b) tangent friction angle of the peak envelope",
        ),
        (
            "c",
            "c_tangent_{}_kPa",
            "tangent cohesion $c$ [kPa]",
            "(c) tangent cohesion (intercept) of the peak envelope",
        ),
    ):
        for name in ("lab", "field"):
            axes[key].semilogx(
                s,
                envelopes[column.format(name)],
                SCALE_STYLE[name],
                color=colour[name],
                label=f"{name} scale",
            )
        axes[key].set(xlabel="normal stress $\\sigma_n$ [MPa]", ylabel=ylabel, title=title)
        axes[key].legend(fontsize=8)
        axes[key].grid(alpha=0.3, which="both")
    fig.suptitle(
        "Barton-Bandis envelopes; (b), (c): tangents to the $\\varphi_b$ peak envelope, "
        "exact $k = \\pi\\,JRC / (180 \\ln 10)$",
        fontsize=10,
    )
    return fig


def shear_curves(curves: pd.DataFrame, scale: pd.DataFrame, dpi: int) -> Figure:
    """Barton's pair: tau against delta above, the dilation (normal displacement) against delta below,
    sharing the delta axis; lab scale on the left, field scale on the right."""
    fig = Figure(figsize=(12, 8), dpi=dpi, layout="constrained")
    axes = fig.subplots(2, 2, sharex="col", height_ratios=[1.4, 1])
    colours = _stress_colours(curves)
    for column, row in enumerate(scale.itertuples()):
        top, bottom = axes[0, column], axes[1, column]
        mine = curves[curves["scale"] == row.scale]
        for sigma_n, curve in mine.groupby("sigma_n_MPa"):
            colour = colours[sigma_n]
            label = f"$\\sigma_n$ = {sigma_n:g} MPa"
            top.plot(curve["delta_mm"], curve["tau_MPa"], SCALE_STYLE[row.scale], color=colour, label=label)
            bottom.plot(
                curve["delta_mm"], curve["dilation_mm"], SCALE_STYLE[row.scale], color=colour, label=label
            )
        for ax in (top, bottom):
            ax.axvline(row.delta_peak_mm, color="grey", lw=0.8, ls=":")
            ax.grid(alpha=0.3)
            ax.set_xlim(0, float(mine["delta_mm"].max()))
            ax.set_ylim(0, None)
        bottom.annotate(
            f"$\\delta_{{peak}}$ = {row.delta_peak_mm:.3g} mm",
            xy=(row.delta_peak_mm, 0.93),
            xycoords=("data", "axes fraction"),
            xytext=(4, 0),
            textcoords="offset points",
            fontsize=8,
            color="grey",
        )
        top.set(
            ylabel="shear stress $\\tau$ [MPa]",
            title=(
                f"{row.scale} scale: L = {row.length_m:g} m, JRC = {row.JRC:.3g}, "
                f"JCS = {row.JCS_MPa:.3g} MPa, $\\varphi_r$ = {row.phi_r_deg:.3g}°"
            ),
        )
        bottom.set(xlabel="shear displacement $\\delta$ [mm]", ylabel="dilation (normal displacement) [mm]")
        top.legend(fontsize=8, loc="upper right")
        bottom.legend(fontsize=8, loc="lower right")
    fig.suptitle("Mobilized shear strength and dilation at constant normal stress (Barton 1982)", fontsize=11)
    return fig


def mobilization(curves: pd.DataFrame, table: tuple[tuple[float, float], ...], dpi: int) -> Figure:
    """JRC_mob/JRC_peak against delta/delta_peak (log axis) at each normal stress and scale, with Barton
    (1982)'s table points; below 0.3 the ratio is -phi_r/i (1 - x/0.3) and depends on the stress."""
    fig = Figure(figsize=(9, 6), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    colours = _stress_colours(curves)
    shown = curves[curves["delta_over_delta_peak"] > 0]
    for (name, sigma_n), curve in shown.groupby(["scale", "sigma_n_MPa"], sort=False):
        ax.semilogx(
            curve["delta_over_delta_peak"],
            curve["JRC_mob_over_JRC_peak"],
            SCALE_STYLE[name],
            color=colours[sigma_n],
            lw=1.2,
        )
    top = float(shown["delta_over_delta_peak"].max())
    points = np.array([p for p in table if p[0] <= top])
    ax.plot(points[:, 0], points[:, 1], "D", color="k", ms=7, mfc="yellow", zorder=5)
    ax.axhline(0.0, color="grey", lw=0.8)
    ax.axvline(1.0, color="grey", lw=0.8, ls=":")
    handles = [Line2D([], [], color=c, label=f"$\\sigma_n$ = {s:g} MPa") for s, c in colours.items()] + [
        *_scale_handles(),
        Line2D([], [], ls="", marker="D", color="k", mfc="yellow", label="Barton (1982) table"),
    ]
    ax.legend(handles=handles, fontsize=8, loc="lower right")
    ax.set(
        xlabel="$\\delta / \\delta_{peak}$ [-]",
        ylabel="$JRC_{mob} / JRC_{peak}$ [-]",
        title=(
            "Mobilized roughness (Barton 1982): one curve for every stress from 0.3 on;\n"
            "below 0.3 it starts at $-\\varphi_r / i$, so that the friction angle starts at 0"
        ),
        xlim=(float(shown["delta_over_delta_peak"].min()), top),
    )
    ax.grid(alpha=0.3, which="both")
    return fig


def closure(table: pd.DataFrame, dpi: int) -> Figure:
    """(a) sigma_n against closure: the Bandis hyperbola, its initial tangent K_ni, the asymptote V_m and
    the half-closure point (K_ni V_m, V_m/2); (b) the tangent K_n against sigma_n."""
    fig = Figure(figsize=(12, 5.5), dpi=dpi, layout="constrained")
    left, right = fig.subplots(1, 2)
    kni, vm, aj = (float(table[c].iloc[0]) for c in ("K_ni_MPa_per_mm", "V_m_mm", "a_j_mm"))
    top = float(table["sigma_n_MPa"].max())
    left.plot(
        table["closure_mm"],
        table["sigma_n_MPa"],
        "k-",
        lw=2,
        label="$\\sigma_n = K_{ni}\\,\\Delta V / (1 - \\Delta V / V_m)$",
    )
    tangent = np.array([0.0, top / kni])
    left.plot(
        tangent, kni * tangent, ":", color="tab:blue", label=f"initial tangent $K_{{ni}}$ = {kni:.4g} MPa/mm"
    )
    left.axvline(vm, color="tab:red", ls="--", label=f"asymptote $V_m$ = {vm:.4g} mm")
    left.plot(
        vm / 2.0,
        kni * vm,
        "o",
        color="tab:red",
        label=f"half closure at $K_{{ni}}\\,V_m$ = {kni * vm:.4g} MPa",
    )
    left.set(
        xlabel="closure $\\Delta V$ [mm]",
        ylabel="normal stress $\\sigma_n$ [MPa]",
        title=f"(a) normal closure (Bandis et al. 1983; $a_j$ = {aj:.3g} mm)",
        xlim=(0, 1.08 * vm),
        ylim=(0, top),
    )
    left.legend(fontsize=8, loc="upper left")
    right.plot(
        table["sigma_n_MPa"],
        table["K_n_MPa_per_mm"],
        "k-",
        lw=2,
        label="tangent $K_n = K_{ni} (1 + \\sigma_n / (K_{ni}\\,V_m))^2$",
    )
    right.set(
        xlabel="normal stress $\\sigma_n$ [MPa]",
        ylabel="normal stiffness $K_n$ [MPa/mm]",
        title="(b) tangent normal stiffness",
        xlim=(0, top),
        ylim=(0, None),
    )
    right.legend(fontsize=8, loc="upper left")
    for ax in (left, right):
        ax.grid(alpha=0.3)
    return fig
