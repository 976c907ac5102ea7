"""Where Goodman & Bray's limit equilibrium holds: its limiting friction against the block engine's on
the same stepped slopes, over the slenderness of the columns and the dip of their bases.

Each case is a regular system (`toppling.regular_block_heights`) with a horizontal upper slope, the
overall base ψ_b = α + 5° (the issue's quarry: bases 20°, base line 25°) and its tallest column, the
crest block, `slenderness` times as tall as it is wide: with the crest in block n_c,
    y_max = n_c (a1 − b) = n_c Δx (tan(ψ_f − α) − tan(ψ_b − α))
so n_c is the whole number that puts the face nearest `FACE_DEG`, and the face angle
    ψ_f = α + atan(s / n_c + tan(ψ_b − α))
makes y_max / Δx = s exactly. Beside the grid, the guide's two examples: Hoek & Bray's (16 blocks,
Δx 10 m, α 30°, `fos_cases.GOODMAN_BRAY`) and the issue's slate quarry (H 30 m, face 70°, bases 20°,
base line 25°, horizontal top, Δx 1.5 m: 48 blocks, the tallest 15.5 Δx).

Both methods give the friction angle φ at which the slope just stands, bases and sides alike: the
limit equilibrium's (`toppling.limiting_friction`: below it the system fails, `le_limit`) and the
engine's, bisected on trials from rest (`toppling_scene.limiting_friction`). With one φ on every
joint the factor of safety is
FS = tan φ / tan φ_limit for either (Hoek & Bray 1981, ch. 10), so where the engine's slope just
stands (its FS = 1) the limit equilibrium claims FS = tan φ_engine / tan φ_LE.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.ticker import NullLocator

from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.slope import fos_cases, toppling
from bbmc.slope import toppling_scene as ts

FACE_DEG = 70.0  # the face angle each grid case is built nearest to [deg]
STEP_DEG = 5.0  # ψ_b − α: the overall base lies this much steeper than the block bases [deg]
WIDTH_M = 2.0  # Δx of the grid's blocks [m]
SLENDERNESS = (2.0, 4.0, 8.0, 15.0)
BASE_DIPS_DEG = (10.0, 20.0, 30.0)
TOLERANCE_DEG = 0.05  # the engine's bisection
MODE_MARGIN_DEG = 1.5  # the modes are compared this far below the lower of the two limits
EXAMPLES = {"hoek_bray": "Hoek & Bray's example", "quarry": "the slate quarry"}
STILL_M = 0.01  # a block that moved less than this is 'stable' (`toppling_scene.block_modes`)


@dataclass(frozen=True)
class Case:
    """One slope of the study: its blocks and the angles it was built from [deg]."""

    name: str
    blocks: toppling.BlockSystem
    face_deg: float
    base_line_deg: float
    upper_slope_deg: float

    @property
    def slenderness(self) -> float:
        """y_max / Δx of the tallest column."""
        return float(self.blocks.heights.max() / self.blocks.width)


def grid_case(slenderness: float, base_dip_deg: float, width: float = WIDTH_M) -> Case:
    """The grid's slope with its tallest column `slenderness` × `width` [m] tall on bases at
    `base_dip_deg` (module docstring: n_c nearest the face FACE_DEG, ψ_f to make it exact)."""
    alpha, step = math.radians(base_dip_deg), math.radians(STEP_DEG)
    per_block = math.tan(math.radians(FACE_DEG) - alpha) - math.tan(step)
    crest = max(1, round(slenderness / per_block))
    face = alpha + math.atan(slenderness / crest + math.tan(step))
    blocks = toppling.regular_block_heights(None, width, alpha, alpha + step, face, 0.0, crest)
    return Case(
        f"s{slenderness:g}_a{base_dip_deg:g}", blocks, math.degrees(face), base_dip_deg + STEP_DEG, 0.0
    )


def hoek_bray_case() -> Case:
    """Hoek & Bray's worked example (a1 = a2 = 5 m, b = 1 m, Δx 10 m, α 30°, crest block 10)."""
    return Case("hoek_bray", fos_cases.GOODMAN_BRAY, 56.6, 35.8, 4.2)


def quarry_case() -> Case:
    """The issue's slate quarry: H 30 m, face 70°, bases 20°, base line 25°, horizontal top, Δx 1.5 m."""
    alpha, face = math.radians(20.0), math.radians(70.0)
    crest = toppling.crest_block_number(30.0, 1.5, alpha, face)
    blocks = toppling.regular_block_heights(None, 1.5, alpha, math.radians(25.0), face, 0.0, crest)
    return Case("quarry", blocks, 70.0, 25.0, 0.0)


def study_cases(
    slenderness: Iterable[float] = SLENDERNESS, base_dips_deg: Iterable[float] = BASE_DIPS_DEG
) -> list[Case]:
    """The guide's two examples, then the grid, base angle by base angle."""
    grid = [grid_case(s, a) for a in base_dips_deg for s in slenderness]
    return [hoek_bray_case(), quarry_case(), *grid]


def mode_runs(modes: Iterable[str]) -> str:
    """Block modes, toe first, as runs: 'S1-3 T4-13 -14-16' (S slides, T topples, - stable)."""
    letters = {"slides": "S", "topples": "T", "stable": "-"}
    runs: list[list] = []
    for n, mode in enumerate(modes, start=1):
        if runs and runs[-1][0] == mode:
            runs[-1][2] = n
        else:
            runs.append([mode, n, n])
    return " ".join(f"{letters[m]}{a}" + (f"-{b}" if b > a else "") for m, a, b in runs)


def engine_limit(case: Case, settings: ts.TrialSettings, guess_deg: float) -> float:
    """The engine's limiting friction [deg], bisected to TOLERANCE_DEG in a bracket around `guess_deg`
    that is widened (5° down, 10° up at a time) until the slope fails at its bottom and holds at its top."""
    low, high = max(guess_deg - 5.0, 1.0), min(guess_deg + 10.0, 85.0)
    while True:
        try:
            return ts.limiting_friction(case.blocks, low, high, TOLERANCE_DEG, settings)
        except ValueError:
            if low <= 1.0 and high >= 85.0:
                raise
            if ts.holds(ts.run_trial(case.blocks, low, settings)):
                low = max(low - 5.0, 1.0)
            else:
                high = min(high + 10.0, 85.0)


def le_limit(case: Case) -> float:
    """The limit equilibrium's limiting friction [deg], bases and sides alike: `toppling.limiting_friction`,
    the friction below which the system fails (the least factor of safety at which it fails, FS = 1;
    docs/reference/toppling-method.md)."""
    return math.degrees(toppling.limiting_friction(case.blocks))


def le_toe_topples(case: Case, limit_deg: float) -> bool:
    """Whether the limit equilibrium's limit is its toe block toppling: P_0 = +inf at `limit_deg`, the
    toe's lower force acting at L_1 = −b, below its pivot, where no force can hold it."""
    return bool(np.isinf(toppling.toe_force(case.blocks, math.radians(limit_deg), 1.0)))


def compare(case: Case, settings: ts.TrialSettings | None = None) -> dict:
    """One row of the study: both limits, their difference, the FS the limit equilibrium claims where the
    engine's slope just stands, and the modes of both just below the lower limit (module docstring)."""
    settings = settings or ts.TrialSettings()
    start = time.perf_counter()
    le = le_limit(case)
    engine = engine_limit(case, settings, le)
    modes_at = min(le, engine) - MODE_MARGIN_DEG
    trial = ts.run_trial(case.blocks, modes_at, settings)
    engine_modes = ts.block_modes(case.blocks, trial, STILL_M)["mode"]
    le_modes = toppling.toppling_forces(case.blocks, math.radians(modes_at), 1.0).mode
    return {
        "case": case.name,
        "slenderness": case.slenderness,
        "base_dip_deg": math.degrees(case.blocks.base_dip),
        "face_deg": case.face_deg,
        "n_blocks": case.blocks.n_blocks,
        "crest_block": case.blocks.crest_block,
        "le_limit_deg": le,
        "le_toe_topples": le_toe_topples(case, le),
        "engine_limit_deg": engine,
        "difference_deg": engine - le,
        "le_fs_where_engine_fs_1": math.tan(math.radians(engine)) / math.tan(math.radians(le)),
        "modes_at_deg": modes_at,
        "le_modes": mode_runs(le_modes),
        "engine_modes": mode_runs(engine_modes),
        "modes_agree": int(np.sum(np.asarray(le_modes) == engine_modes.to_numpy())),
        "seconds": time.perf_counter() - start,
    }


def study(cases: Iterable[Case], progress: ProgressCallback = ignore) -> pd.DataFrame:
    """`compare` on every case, one row each; `progress` hears of each case done (`bbmc.progress`)."""
    cases = list(cases)
    rows = []
    for case in cases:
        rows.append(compare(case))
        text = f"{case.name}: {rows[-1]['engine_limit_deg']:.2f} deg ({rows[-1]['seconds']:.0f} s)"
        progress(Progress(len(rows), len(cases), "cases", text))
    return pd.DataFrame(rows)


#: The joint stiffness study: the runs (case, K_n = K_s [MPa/mm]) the page shows.
STIFFNESS_RUNS = (
    *(("s2_a30", k) for k in (1.0, 10.0, 100.0)),
    *(("s4_a20", k) for k in (1.0, 10.0, 100.0, 1000.0)),
    *(("s8_a20", k) for k in (10.0, 100.0)),
    *(("quarry", k) for k in (1.0, 10.0, 100.0)),
)

#: The computational settings varied on one case: name → the change to `TrialSettings`.
SETTINGS_VARIANTS = {
    "default": {},
    "2 sub-contacts": {"sub_contacts_per_edge": 2},
    "8 sub-contacts": {"sub_contacts_per_edge": 8},
    "damping 0.5": {"damping": 0.5},
    "1,000,000 steps": {"max_steps": 1_000_000},
    "trend window 30,000": {"trend_window_steps": 30_000},
    "ramp 20,000 steps": {"ramp_steps": 20_000},
}


def settings_spread(case: Case, variants: dict[str, dict] = SETTINGS_VARIANTS) -> pd.DataFrame:
    """The engine's limiting friction of `case` [deg] under each variant of its computational settings."""
    guess = le_limit(case)
    rows = []
    for name, change in variants.items():
        start = time.perf_counter()
        limit = engine_limit(case, replace(ts.TrialSettings(), **change), guess)
        rows.append({"settings": name, "engine_limit_deg": limit, "seconds": time.perf_counter() - start})
    return pd.DataFrame(rows)


def stiff_settings(stiffness_MPa_per_mm: float) -> ts.TrialSettings:
    """The default trial with every joint's K_n = K_s changed, its step counts (ramp, trend window,
    budget) scaled by sqrt(K / K_default) so that they span the same time: the critical time step
    goes as sqrt(m / K)."""
    default = ts.TrialSettings()
    scale = math.sqrt(stiffness_MPa_per_mm / default.stiffness_MPa_per_mm)
    return replace(
        default,
        stiffness_MPa_per_mm=stiffness_MPa_per_mm,
        ramp_steps=round(default.ramp_steps * scale),
        trend_window_steps=round(default.trend_window_steps * scale),
        max_steps=round(default.max_steps * scale),
    )


def stiffness_spread(runs: Iterable[tuple[Case, float]]) -> pd.DataFrame:
    """The engine's limiting friction [deg] of each case at its joint stiffness [MPa/mm], beside the
    limit equilibrium's (rigid blocks)."""
    rows = []
    for case, k in runs:
        le = le_limit(case)
        start = time.perf_counter()
        limit = engine_limit(case, stiff_settings(k), le)
        rows.append(
            {
                "case": case.name,
                "stiffness_MPa_per_mm": k,
                "le_limit_deg": le,
                "engine_limit_deg": limit,
                "difference_deg": limit - le,
                "seconds": time.perf_counter() - start,
            }
        )
    return pd.DataFrame(rows)


def figure(table: pd.DataFrame) -> Figure:
    """Left, both limits against the slenderness, one colour per base angle (limit equilibrium dashed
    and open, engine solid and filled), the guide's examples as their own markers; right, the engine's
    limit minus the limit equilibrium's, ringed where the limit equilibrium's limit is its toe block
    toppling (`le_toe_topples`)."""
    fig = Figure(figsize=(12.0, 5.0), dpi=120)
    ax, diff = fig.subplots(1, 2)
    examples = table["case"].isin(EXAMPLES)
    for colour, (alpha, rows) in zip(
        ("C0", "C1", "C2"), table[~examples].groupby("base_dip_deg"), strict=False
    ):
        label = f"α {alpha:g}°"
        s, le, dem = rows["slenderness"], rows["le_limit_deg"], rows["engine_limit_deg"]
        ax.plot(s, le, "--o", color=colour, mfc="none", label=f"{label}, limit equilibrium")
        ax.plot(s, dem, "-o", color=colour, label=f"{label}, engine")
        diff.plot(s, rows["difference_deg"], "-o", color=colour, label=label)
    for marker, (_, row) in zip(("*", "D"), table[examples].iterrows(), strict=True):
        name = f"{EXAMPLES[row['case']]} (α {row['base_dip_deg']:g}°)"
        ax.plot(
            row["slenderness"], row["le_limit_deg"], marker, color="k", mfc="none", ms=10, label=f"{name}, LE"
        )
        ax.plot(row["slenderness"], row["engine_limit_deg"], marker, color="k", ms=8, label=f"{name}, engine")
        diff.plot(row["slenderness"], row["difference_deg"], marker, color="k", ms=9, label=name)
    toe = table[table["le_toe_topples"].astype(bool)]
    diff.plot(
        toe["slenderness"],
        toe["difference_deg"],
        "o",
        mfc="none",
        mec="r",
        ms=16,
        mew=1.5,
        label="limit equilibrium's toe block topples",
    )
    for axis in (ax, diff):
        axis.set_xscale("log")
        axis.xaxis.set_minor_locator(NullLocator())
        axis.set_xticks([2, 4, 8, 15], ["2", "4", "8", "15"])
        axis.set_xlabel("slenderness of the tallest column, y_max / Δx [-]")
        axis.grid(True, alpha=0.3)
    ax.set_ylabel("limiting friction angle φ [deg]")
    ax.legend(fontsize=7, loc="lower right")
    diff.axhline(0.0, color="grey", lw=0.8)
    diff.set_ylabel("engine − limit equilibrium [deg]")
    diff.set_ylim(top=table["difference_deg"].max() + 1.5)  # room for the legend
    diff.legend(fontsize=8, loc="upper left")
    fig.suptitle("Goodman & Bray's limit equilibrium against the block engine (one φ on bases and sides)")
    fig.tight_layout()
    return fig


def write_study(folder: Path, progress: ProgressCallback = ignore) -> pd.DataFrame:
    """Run the study; write its table (toppling-validity.csv) and figure (toppling-validity.png) into
    `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    table = study(study_cases(), progress)
    table.to_csv(folder / "toppling-validity.csv", index=False, float_format="%.4f")
    figure(table).savefig(folder / "toppling-validity.png")
    return table


def write_checks(folder: Path) -> None:
    """The engine's limit against its computational settings on the quarry
    (toppling-validity-settings.csv) and against the joint stiffness (toppling-validity-stiffness.csv)."""
    folder.mkdir(parents=True, exist_ok=True)
    settings_spread(quarry_case()).to_csv(
        folder / "toppling-validity-settings.csv", index=False, float_format="%.4f"
    )
    cases = {case.name: case for case in study_cases()}
    stiff = stiffness_spread((cases[name], k) for name, k in STIFFNESS_RUNS)
    stiff.to_csv(folder / "toppling-validity-stiffness.csv", index=False, float_format="%.4f")
