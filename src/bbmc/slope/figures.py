"""The slope stage's figures (Figs 7-10 of the paper, the limit-equilibrium sweep, the dip study) and
its animation, drawn from the stage's tables and runs. The paper's figures are missing from the text:
these follow its captions and section 5."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from bbmc import plots  # noqa: F401  (selects the Agg backend before any figure is drawn)
from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.geometry import polygons
from bbmc.scene.schema import JointedSlope

MODEL_STYLE = {
    "constant": ("tab:red", "constant M-C (Table 4)"),
    "barton_bandis": ("tab:blue", "B-B updated every 50 steps"),
}
NUMBER_COLOURS = {1: "tab:orange", 2: "tab:red", 3: "tab:purple", 4: "tab:green"}


def _polygons(model: Model, centroids: np.ndarray, angles: np.ndarray) -> list[np.ndarray]:
    shapes = []
    for i in range(len(model.blocks)):
        local = model.local[model.vertex_start[i] : model.vertex_start[i + 1]]
        c, s = np.cos(angles[i]), np.sin(angles[i])
        shapes.append(local @ np.array([[c, s], [-s, c]]) + centroids[i])
    return shapes


def _draw_blocks(ax, model: Model, numbering: dict[int, int], centroids=None, angles=None) -> None:
    centroids = model.blocks[:, [L.X, L.Y]] if centroids is None else centroids
    angles = np.zeros(len(model.blocks)) if angles is None else angles
    fixed = np.all(model.dof == L.PRESCRIBED, axis=1)
    paper = {b: n for n, b in numbering.items()}
    colours = [
        NUMBER_COLOURS[paper[i]] if i in paper else ("0.75" if fixed[i] else "wheat")
        for i in range(len(fixed))
    ]
    ax.add_collection(
        PolyCollection(
            _polygons(model, centroids, angles),
            facecolors=colours,
            edgecolors="k",
            linewidths=0.5,
            alpha=0.85,
        )
    )
    ax.set_aspect("equal")
    ax.autoscale_view()


def fig7(model: Model, numbering: dict[int, int], slope: JointedSlope, dpi: int) -> Figure:
    """Fig 7: the model: blocks (held ones grey), the joint sets, the monitored blocks 1-4, boundaries."""
    fig = Figure(figsize=(11, 5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    _draw_blocks(ax, model, numbering)
    for n, b in numbering.items():
        ax.annotate(
            f"No. {n}", model.blocks[b, [L.X, L.Y]], ha="center", va="center", fontsize=9, weight="bold"
        )
    x_left, x_right, y_bottom, top = polygons.slope_bounds(
        slope.height_m, slope.face_angle_deg, slope.crest_extent_m, slope.toe_extent_m, slope.depth_m
    )
    for side, xs, ys in (
        ("right", [x_right, x_right], [y_bottom, top]),
        ("bottom", [x_left, x_right], [y_bottom, y_bottom]),
    ):
        if side in slope.fixed_boundaries:
            ax.plot(xs, ys, color="k", lw=4, solid_capstyle="butt")
    ax.plot([], [], color="k", lw=4, label="fixed boundary (x, y, rotation held)")
    for patch, label in (("0.75", "held block (edge on a fixed boundary)"), ("wheat", "free block")):
        ax.fill([], [], color=patch, label=label)
    for k, joint_set in enumerate(slope.joint_sets):
        name = "bedding" if k == 0 else f"joint set {k}"
        side = "out of" if joint_set.dip_direction_to_face_deg < 90 else "into"
        ax.plot(
            [],
            [],
            color="k",
            lw=0.5,
            label=f"{name}: dip {joint_set.dip_deg:g} deg {side} the slope, "
            f"spacing {joint_set.spacing_m:g} m",
        )
    ax.set(
        xlabel="x [m] (the free face looks towards -x)",
        ylabel="y [m]",
        title=f"Fig 7: jointed slope, height {slope.height_m:g} m, face {slope.face_angle_deg:g} deg;\n"
        "monitored blocks No. 1-4 on the bedding joint through the toe",
    )
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    return fig


def fig8(runs: dict, snapshots: pd.DataFrame, dpi: int) -> Figure:
    """Fig 8: displacement vectors of the free blocks at each snapshot, one row per model (arrows of
    one row share a scale, given in the row's key), and the largest rotation of a free block."""
    fractions = sorted(snapshots["fraction"].unique())
    fig = Figure(figsize=(4 * len(fractions), 4.6), dpi=dpi, layout="constrained")  # the panels' 3:1
    axes = fig.subplots(2, len(fractions), squeeze=False, sharex=True, sharey=True)
    for row, (kind, run) in enumerate(runs.items()):
        frame = snapshots[snapshots["model"] == kind]
        largest = float(np.hypot(frame["ux_mm"], frame["uy_mm"]).max()) or 1.0
        for col, fraction in enumerate(fractions):
            ax = axes[row, col]
            shot = frame[frame["fraction"] == fraction]
            _draw_blocks(ax, run.model, {})
            q = ax.quiver(
                shot["x_m"],
                shot["y_m"],
                shot["ux_mm"],
                shot["uy_mm"],
                color=MODEL_STYLE[kind][0],
                angles="xy",
                scale_units="xy",
                scale=largest / 4.0,
                width=0.006,
            )
            ax.set_title(
                f"{MODEL_STYLE[kind][1]}\nstep {int(shot['step'].iloc[0])}, "
                f"t = {shot['time_s'].iloc[0]:.2f} s",
                fontsize=9,
            )
            turned = shot["rotation_deg"].abs().max()
            ax.text(
                0.97,
                0.04,
                f"largest rotation {turned:.2g} deg",
                transform=ax.transAxes,
                ha="right",
                fontsize=7,
            )
            if col == len(fractions) - 1:
                ax.quiverkey(q, 0.12, 0.86, largest, f"{largest:.3g} mm", labelpos="E", coordinates="axes")
            ax.set(xlabel="x [m]" if row else None, ylabel="y [m]" if col == 0 else None)
    fig.suptitle("Fig 8: displacement vectors of the free blocks (arrow length in mm, to the key's scale)")
    return fig


JOINT_QUANTITIES = (
    ("kn_MPa_per_mm", "K_n [MPa/mm]"),
    ("ks_MPa_per_mm", "K_s [MPa/mm]"),
    ("sigma_n_MPa", "sigma_n [MPa]"),
    ("cohesion_kPa", "c [kPa]"),
    ("friction_deg", "phi [deg]"),
)


def fig9(joints: pd.DataFrame, dpi: int) -> Figure:
    """Fig 9: K_n, K_s, sigma_n, c and phi of (a) the near-horizontal joint under block 2 and (b) the
    near-vertical joint behind it, against step, both models."""
    fig = Figure(figsize=(11, 12), dpi=dpi, layout="constrained")
    axes = fig.subplots(len(JOINT_QUANTITIES), 2, sharex="col")
    for col, joint in enumerate(("near_horizontal", "near_vertical")):
        for row, (quantity, label) in enumerate(JOINT_QUANTITIES):
            ax = axes[row, col]
            for kind, (colour, name) in MODEL_STYLE.items():
                frame = joints[joints["model"] == kind]
                ax.plot(frame["time_s"], frame[f"{joint}_{quantity}"], color=colour, label=name, lw=1)
            ax.set_ylabel(label)
            if row == 0:
                ax.set_title(f"({'ab'[col]}) {joint.replace('_', '-')} joint of block No. 2")
        axes[-1, col].set_xlabel("time [s] (steps in fig9_joints.csv)")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("Fig 9: joint parameters against time")
    return fig


def fig10(moves: pd.DataFrame, fits: pd.DataFrame, dpi: int) -> Figure:
    """Fig 10: (a) constant and (b) B-B: displacement of blocks 1-4 against step; (c) block 2 in both
    models against time, with quadratic fits and R^2."""
    fig = Figure(figsize=(15, 4.8), dpi=dpi, layout="constrained")
    axes = fig.subplots(1, 3)
    for ax, kind, letter in ((axes[0], "constant", "a"), (axes[1], "barton_bandis", "b")):
        frame = moves[moves["model"] == kind]
        for n, colour in NUMBER_COLOURS.items():
            ax.plot(frame["step"], frame[f"block_{n}_mm"], color=colour, label=f"No. {n}")
        ax.set(xlabel="step", ylabel="displacement [mm]", title=f"({letter}) {MODEL_STYLE[kind][1]}")
        ax.legend(fontsize=8)
    ax = axes[2]
    for kind, (colour, name) in MODEL_STYLE.items():
        frame = moves[moves["model"] == kind]
        fit = fits[(fits["model"] == kind) & (fits["against"] == "time_s")].iloc[0]
        ax.plot(frame["time_s"], frame["block_2_mm"], color=colour, label=name)
        ax.plot(
            frame["time_s"],
            np.polyval([fit["c2"], fit["c1"], fit["c0_mm"]], frame["time_s"]),
            color=colour,
            ls="--",
            lw=1,
            label=f"quadratic fit, R^2 = {fit['r2']:.4f}",
        )
    ax.set(
        xlabel="time [s]", ylabel="displacement [mm]", title="(c) block No. 2, both models", yscale="symlog"
    )
    ax.legend(fontsize=8)
    fig.suptitle(
        "Fig 10: block displacement (steps differ in length between the models: (c) is against time)"
    )
    return fig


def fs_vs_dip(sweep: pd.DataFrame, critical: pd.DataFrame, dpi: int) -> Figure:
    """Factor of safety of planar sliding against bedding dip, the engine's verdicts and critical dips."""
    fig = Figure(figsize=(8, 5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    for kind, (colour, name) in MODEL_STYLE.items():
        frame = sweep[sweep["model"] == kind]
        ax.plot(frame["dip_deg"], frame["factor_of_safety"], color=colour, label=f"limit equilibrium, {name}")
        slid = frame[frame["engine_slides"]]
        held = frame[~frame["engine_slides"]]
        ax.scatter(
            held["dip_deg"], held["factor_of_safety"], marker="o", facecolors="none", edgecolors=colour
        )
        ax.scatter(slid["dip_deg"], slid["factor_of_safety"], marker="x", color=colour)
        row = critical[critical["model"] == kind].iloc[0]
        if not np.isfinite(row["limit_equilibrium_dip_deg"]):
            continue  # FS does not cross 1 between 0.5 and 89.5 deg
        ax.axvline(
            row["engine_dip_deg"],
            color=colour,
            ls=":",
            label=f"engine starts to slide: {row['engine_dip_deg']:.2f} deg "
            f"(FS = 1 at {row['limit_equilibrium_dip_deg']:.2f} deg)",
        )
    ax.scatter([], [], marker="o", facecolors="none", edgecolors="k", label="engine: holds")
    ax.scatter([], [], marker="x", color="k", label="engine: slides")
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set(
        xlabel="bedding dip [deg]",
        ylabel="factor of safety [1]",
        yscale="log",
        title="Planar sliding of one block on the bedding plane",
    )
    ax.legend(fontsize=7)
    return fig


def dip_sensitivity(table: pd.DataFrame, dpi: int) -> Figure:
    """Block 2's displacement at the end of the run against bedding dip, both models."""
    fig = Figure(figsize=(7, 4.5), dpi=dpi, layout="constrained")
    ax = fig.subplots()
    for kind, (colour, name) in MODEL_STYLE.items():
        ax.plot(table["bedding_dip_deg"], table[f"block_2_{kind}_mm"], "o-", color=colour, label=name)
    ax.set(
        xlabel="bedding dip [deg]",
        ylabel="block No. 2 displacement at the end [mm]",
        yscale="log",
        title="Sensitivity to the bedding dip (same slope, same duration)",
    )
    ax.legend(fontsize=8)
    return fig


def animation(runs: dict, frames: int, dpi: int, path: Path) -> None:
    """A GIF of both runs side by side at equal times (blocks drawn where they are)."""
    fig = Figure(figsize=(12, 3.6), dpi=min(dpi, 80), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    end = min(r.time[-1] for r in runs.values())
    times = np.linspace(0.0, end, frames)

    def draw(k: int) -> None:
        for ax, (kind, run) in zip(axes, runs.items(), strict=True):
            ax.clear()
            j = int(np.searchsorted(run.time, times[k]).clip(0, len(run.time) - 1))
            _draw_blocks(ax, run.model, run.numbering, run.paths[j, :, :2], run.paths[j, :, 2])
            ax.set(title=f"{MODEL_STYLE[kind][1]}, t = {run.time[j]:.2f} s", xlabel="x [m]")

    FuncAnimation(fig, draw, frames=frames).save(path, writer=PillowWriter(fps=8))
