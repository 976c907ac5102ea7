"""`bbmc slope`: the jointed limestone slope of the paper's section 5 (Table 4, Figs 7-10), both joint
models, the claims of section 5.2 measured, a limit-equilibrium check, a dip sensitivity study, and
the slope's factor of safety by strength reduction and by planar limit equilibrium, and the full
Barton-Bandis joint with residual strength against the peak-only joint (`slope.safety`).

Read from data/paper as inputs: Table 4 (density, the constant and the nonlinear joint parameters) and
eq 6's printed lg e (behind Table 4's K_n coefficient). Nothing the paper reports as a result of its
slope runs is read: its claims are words, quoted in `CLAIMS` and measured here.

What a step is: one explicit time step of the engine, real masses (no density scaling), the automatic
time step (`run.safety_factor` x critical). The two joint models have different stiffnesses, so their
steps differ in length; the runs last the same physical time (`run.duration_s`), every curve is also
given against time, and the claims are measured against time.
"""

from __future__ import annotations

import itertools
import math
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.config import ConfigError
from bbmc.dem import layout as L
from bbmc.dem.model import Model, built_scene
from bbmc.dem.solver import SimulationError, simulate
from bbmc.io import StageResult
from bbmc.outputs.figures import mechanism_figure
from bbmc.outputs.vtk import Series
from bbmc.progress import ProgressCallback, ignore
from bbmc.scene.schema import JointedSlope
from bbmc.slope import figures, safety
from bbmc.slope import limit_equilibrium as le
from bbmc.slope import measures as me
from bbmc.slope import model as sm
from bbmc.slope.config import Claims, Config, load_table4

NAME = "slope"


class SlopeRun:
    """One run of the slope: every block's centroid and rotation at every record, and the monitors."""

    def __init__(
        self,
        model: Model,
        numbering: dict[int, int],
        progress: ProgressCallback,
        series: Series | None = None,
    ) -> None:
        self.model, self.numbering, self.paths, self.series = model, numbering, [], series

        def record(state) -> None:
            self.paths.append(state.blocks[:, [L.X, L.Y, L.TH]].copy())
            if series is not None:
                series(state)

        self.result = simulate(model, progress, record)
        self.paths = np.array(self.paths)
        self.steps = self.result.history["step"].to_numpy()
        self.time = self.result.history["time_s"].to_numpy()

    def displacement(self, block: int) -> np.ndarray:
        """Centroid displacement magnitude of one block at every record [m]."""
        return np.hypot(*(self.paths[:, block, :2] - self.paths[0, block, :2]).T)


def _model(
    config: Config,
    table4: sm.Table4,
    kind: sm.JointModel,
    slope: JointedSlope,
    monitors: list[dict],
) -> Model:
    law = sm.joint_law(kind, table4, config.constant, config.barton_bandis)
    scene = sm.slope_scene(f"slope_{kind}", slope, table4.density_kg_m3, law, config.run, monitors)
    try:
        return built_scene(scene, f"slope_{kind}.yaml")
    except ConfigError as error:  # the scene is the config's slope and Table 4's parameters
        raise SimulationError(
            f"key 'slope': the {kind} slope it makes is refused: {error}", bad_input=True
        ) from None


def run_slope(
    config: Config,
    table4: sm.Table4,
    kind: sm.JointModel,
    slope: JointedSlope,
    monitor_joints: bool,
    progress: ProgressCallback = ignore,
    vtk_every: int | None = None,
) -> SlopeRun:
    """Run one joint model on one slope for run.duration_s of physical time (with `vtk_every`, its
    ParaView series of every vtk_every-th record too)."""
    probe = _model(config, table4, kind, slope, [])
    layer = sm.sliding_layer(probe, slope)
    needed = 4 if monitor_joints else 1
    if len(layer) < needed:
        raise SimulationError(
            f"key 'slope': with the bedding at {slope.joint_sets[0].dip_deg:g} deg, {len(layer)} free blocks "
            f"rest on the bedding joint through the toe; the paper's measures need {needed}",
            bad_input=True,
        )
    numbering = sm.paper_numbering(layer) if monitor_joints else {2: layer[0]}
    monitors = []
    if monitor_joints:
        points = sm.monitored_joints(probe, numbering[2])
        monitors = [
            {"name": f"{joint}_{q}", "near_m": point, "quantity": q}
            for joint, point in points.items()
            for q in ("sigma_n", "tau", "kn", "ks", "cohesion", "friction")
        ]
    model = _model(config, table4, kind, slope, monitors)
    series = Series(model, f"vtk/{kind}", vtk_every) if vtk_every else None
    return SlopeRun(model, numbering, progress, series)


CLAIMS = (
    (
        "C1",
        "constant",
        "no separation occurred between blocks in the process of slippage",
        "largest drawing apart of neighbouring monitored blocks [mm]",
        "together",
    ),
    (
        "C2",
        "constant",
        "the slip velocity of the block was consistent",
        "(fastest - slowest) / mean slip rate of blocks 1-4",
        "alike_rates",
    ),
    (
        "B1",
        "barton_bandis",
        "the slip rate of the blocks was different",
        "(fastest - slowest) / mean slip rate of blocks 1-4",
        "different_rates",
    ),
    (
        "B2",
        "barton_bandis",
        "No. 2 block ... its slip rate was the fastest",
        "fastest block (paper number)",
        "fastest_is_2",
    ),
    (
        "B3",
        "barton_bandis",
        "No. 3 block ... its slip rate was the slowest",
        "slowest block (paper number)",
        "slowest_is_3",
    ),
    (
        "B4",
        "barton_bandis",
        "No. 1 block and No. 4 block ... the sliding speed remained basically the same",
        "|rate 1 - rate 4| / their mean",
        "one_and_four_alike",
    ),
    (
        "B5",
        "barton_bandis",
        "the tendency for disintegration and destruction between blocks was evident",
        "largest drawing apart of neighbouring monitored blocks [mm]",
        "separate",
    ),
    (
        "Q1",
        "both",
        "both curves could be fitted to quadratic polynomials",
        "R^2 of a quadratic fit of block 2's displacement against time",
        "quadratic",
    ),
    (
        "S1",
        "both",
        "the start of the slide process was slower [constant model]",
        "time for block 2 to move onset_displacement_mm [s]",
        "constant_starts_later",
    ),
    (
        "S2",
        "both",
        "the displacement volume was relatively smaller [constant model]",
        "block 2's displacement at the end of the common duration [mm]",
        "constant_moves_less",
    ),
)


def _on_common_time(runs: dict[str, SlopeRun]) -> float:
    return min(r.time[-1] for r in runs.values())


def _rates(run: SlopeRun, end: float) -> dict[int, float]:
    keep = run.time <= end
    return {n: me.slip_rate(run.time[keep], run.displacement(b)[keep]) for n, b in run.numbering.items()}


def _separation_mm(run: SlopeRun, end: float) -> float:
    """The most any two neighbouring monitored blocks have drawn apart [mm]."""
    keep = run.time <= end
    order = [2, 1, 4, 3]  # up-dip along the layer
    paths = {n: run.paths[keep, run.numbering[n], :2] for n in order}
    return max(me.separation(paths[a], paths[b]) for a, b in itertools.pairwise(order)) * 1e3


def claims_table(runs: dict[str, SlopeRun], settings: Claims) -> pd.DataFrame:
    """One row per claim: the measure in both runs, the paper's statement, ours, and whether they agree."""
    end = _on_common_time(runs)
    values: dict[str, dict[str, float]] = {}
    for kind, run in runs.items():
        keep = run.time <= end
        rates = _rates(run, end)
        d2 = run.displacement(run.numbering[2])[keep]
        _, r2 = me.quadratic_fit(run.time[keep], d2)
        values[kind] = {
            "spread": me.rate_spread(np.array(list(rates.values()))),
            "fastest": max(rates, key=rates.get),
            "slowest": min(rates, key=rates.get),
            "one_four": me.relative_difference(rates[1], rates[4]),
            "separation": _separation_mm(run, end),
            "r2": r2,
            "onset": me.onset_time(run.time[keep], d2, settings.onset_displacement_mm * 1e-3),
            "final_mm": d2[-1] * 1e3,
        }
    c, b = values["constant"], values["barton_bandis"]
    alike, together = settings.alike_fraction, settings.separation_mm
    tests = {
        "together": ("separation", lambda v: v["separation"] <= together, f"<= {together}"),
        "alike_rates": ("spread", lambda v: v["spread"] <= alike, f"<= {alike}"),
        "different_rates": ("spread", lambda v: v["spread"] > alike, f"> {alike}"),
        "fastest_is_2": ("fastest", lambda v: v["fastest"] == 2, "== 2"),
        "slowest_is_3": ("slowest", lambda v: v["slowest"] == 3, "== 3"),
        "one_and_four_alike": ("one_four", lambda v: v["one_four"] <= alike, f"<= {alike}"),
        "separate": ("separation", lambda v: v["separation"] > together, f"> {together}"),
        "quadratic": ("r2", lambda v: v["r2"] >= settings.quadratic_r2, f">= {settings.quadratic_r2}"),
    }
    rows = []
    for claim_id, model, quote, measure, test in CLAIMS:
        if test == "constant_starts_later":
            key, holds, criterion = "onset", c["onset"] > b["onset"], "constant > barton_bandis"
        elif test == "constant_moves_less":
            key, holds, criterion = "final_mm", c["final_mm"] < b["final_mm"], "constant < barton_bandis"
        else:
            key, check, criterion = tests[test]
            holds = all(check(values[m]) for m in (sm.JOINT_MODELS if model == "both" else (model,)))
        rows.append(
            {
                "claim": claim_id,
                "model": model,
                "paper_says": quote,
                "measure": measure,
                "constant": c[key],
                "barton_bandis": b[key],
                "criterion": criterion,
                "agrees_with_paper": bool(holds),
                "compared_over_s": end,
            }
        )
    return pd.DataFrame(rows)


def block_table(model: Model, numbering: dict[int, int]) -> pd.DataFrame:
    """Fig 7's blocks: index, paper number, held or free, centroid, area, and the vertices."""
    paper = {b: n for n, b in numbering.items()}
    rows = []
    for i in range(len(model.blocks)):
        shape = sm.block_shape(model, i)
        rows.append(
            {
                "block": i,
                "paper_number": paper.get(i, 0),
                "fixed": bool(np.all(model.dof[i] == L.PRESCRIBED)),
                "x_m": model.blocks[i, L.X],
                "y_m": model.blocks[i, L.Y],
                "area_m2": model.blocks[i, L.MASS] / model.scene.materials["limestone"].density_kg_m3,
                "vertices_m": " ".join(f"{x:.4f},{y:.4f}" for x, y in shape),
            }
        )
    return pd.DataFrame(rows)


def snapshot_table(runs: dict[str, SlopeRun], fractions: list[float]) -> pd.DataFrame:
    """Fig 8: every free block's displacement vector and rotation (counter-clockwise) at each snapshot
    (nearest record to the fraction of the run's own duration)."""
    rows = []
    for kind, run in runs.items():
        free = ~np.all(run.model.dof == L.PRESCRIBED, axis=1)
        for fraction in fractions:
            k = int(np.argmin(np.abs(run.time - fraction * run.time[-1])))
            moved = run.paths[k, :, :2] - run.paths[0, :, :2]
            for i in np.flatnonzero(free):
                rows.append(
                    {
                        "model": kind,
                        "fraction": fraction,
                        "step": int(run.steps[k]),
                        "time_s": run.time[k],
                        "block": int(i),
                        "x_m": run.paths[0, i, 0],
                        "y_m": run.paths[0, i, 1],
                        "ux_mm": moved[i, 0] * 1e3,
                        "uy_mm": moved[i, 1] * 1e3,
                        "rotation_deg": np.degrees(run.paths[k, i, 2] - run.paths[0, i, 2]),
                    }
                )
    return pd.DataFrame(rows)


def joint_histories(runs: dict[str, SlopeRun]) -> pd.DataFrame:
    """Fig 9: K_n, K_s, sigma_n, tau, c and phi of the two monitored joints against step and time."""
    return pd.concat([r.result.history.assign(model=kind) for kind, r in runs.items()], ignore_index=True)


def displacement_histories(runs: dict[str, SlopeRun]) -> pd.DataFrame:
    """Fig 10: displacement of blocks 1-4 against step and time."""
    frames = []
    for kind, run in runs.items():
        frame = pd.DataFrame({"model": kind, "step": run.steps, "time_s": run.time})
        for n in sorted(run.numbering):
            frame[f"block_{n}_mm"] = run.displacement(run.numbering[n]) * 1e3
        frames.append(frame)
    return pd.concat(frames, ignore_index=True)


def quadratic_fits(runs: dict[str, SlopeRun]) -> pd.DataFrame:
    """Fig 10(c): block 2's displacement fitted by quadratics in time and in step."""
    end = _on_common_time(runs)
    rows = []
    for kind, run in runs.items():
        keep = run.time <= end
        d2 = run.displacement(run.numbering[2])[keep] * 1e3
        for axis, x in (("time_s", run.time[keep]), ("step", run.steps[keep].astype(float))):
            (c2, c1, c0), r2 = me.quadratic_fit(x, d2)
            rows.append({"model": kind, "against": axis, "c2": c2, "c1": c1, "c0_mm": c0, "r2": r2})
    return pd.DataFrame(rows)


def limit_equilibrium(config: Config, table4: sm.Table4) -> tuple[pd.DataFrame, pd.DataFrame]:
    """FS against dip for both models beside the engine's verdict, and each model's critical dip."""
    s = config.limit_equilibrium
    settings = {
        "max_steps": s.max_steps,
        "damping": config.run.damping,
        "update_interval_steps": config.run.update_interval_steps,
        "equilibrium_ratio": s.equilibrium_ratio,
        "slide_m": s.slide_mm * 1e-3,
        "ramp_steps": s.ramp_steps,
    }
    sweep, critical = [], []
    rho, h = table4.density_kg_m3, s.block_thickness_m
    for kind in sm.JOINT_MODELS:
        law = sm.joint_law(kind, table4, config.constant, config.barton_bandis)

        def slides(dip: float, law: dict = law) -> bool:
            return le.engine_slides(le.block_scene(law, dip, s.block_length_m, h, rho, settings))

        for dip in s.dips_deg:
            sweep.append(
                {
                    "model": kind,
                    "dip_deg": dip,
                    "factor_of_safety": le.factor_of_safety(law, dip, h, rho),
                    "engine_slides": slides(dip),
                }
            )
        analytic = le.critical_dip(law, h, rho, 0.5, 89.5)
        engine = (  # none where FS does not cross 1
            le.engine_critical_dip(slides, max(analytic - 5, 0.5), min(analytic + 5, 89.5), s.tolerance_deg)
            if math.isfinite(analytic)
            else math.nan
        )
        critical.append(
            {
                "model": kind,
                "limit_equilibrium_dip_deg": analytic,
                "engine_dip_deg": engine,
                "difference_deg": engine - analytic,
                "stated_agreement_deg": s.agreement_deg[kind],
                "within": abs(engine - analytic) <= s.agreement_deg[kind],
                "bisection_tolerance_deg": s.tolerance_deg,
            }
        )
    return pd.DataFrame(sweep), pd.DataFrame(critical)


def sensitivity(config: Config, table4: sm.Table4, progress: Callable[[str], None]) -> pd.DataFrame:
    """Block 2's displacement after run.duration_s for each bedding dip, both models."""
    rows = []
    for dip in config.sensitivity.dips_deg:
        sets = [config.slope.joint_sets[0].model_copy(update={"dip_deg": dip}), *config.slope.joint_sets[1:]]
        slope = config.slope.model_copy(update={"joint_sets": sets})
        for kind in sm.JOINT_MODELS:
            progress(f"sensitivity: bedding dip {dip:g} deg, {kind}")
            run = run_slope(config, table4, kind, slope, monitor_joints=False)
            rows.append(
                {
                    "bedding_dip_deg": dip,
                    "model": kind,
                    "time_s": run.time[-1],
                    "steps": int(run.steps[-1]),
                    "block_2_mm": run.displacement(run.numbering[2])[-1] * 1e3,
                }
            )
    frame = pd.DataFrame(rows).pivot(index="bedding_dip_deg", columns="model", values="block_2_mm")
    frame.columns = [f"block_2_{c}_mm" for c in frame.columns]
    frame["barton_bandis_over_constant"] = frame["block_2_barton_bandis_mm"] / frame["block_2_constant_mm"]
    return frame.reset_index()


def _gif(runs: dict[str, SlopeRun], frames: int, dpi: int) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "slope.gif"
        figures.animation(runs, frames, dpi, path)
        return path.read_bytes()


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """Run both joint models, the limit-equilibrium check and the dip study; tabulate and draw."""
    table4 = load_table4(config.data)
    phi_b = table4.nonlinear["phi_b_deg"]
    for phi_r in config.residual.phi_r_deg:
        if phi_r > phi_b:
            raise SimulationError(
                f"key 'residual.phi_r_deg': {phi_r:g} exceeds Table 4's phi_b_deg {phi_b:g} "
                f"({config.data.table4_joints_nonlinear}): a residual angle is at most the basic one",
                bad_input=True,
            )
    runs = {}
    for kind in sm.JOINT_MODELS:
        progress(f"slope run, {kind} joints")
        runs[kind] = run_slope(
            config, table4, kind, config.slope, monitor_joints=True, vtk_every=config.vtk_every_records
        )
    end = _on_common_time(runs)
    records = min(int(np.sum(r.time <= end)) for r in runs.values())
    if records < 3:
        raise SimulationError(
            f"key 'run.duration_s': the runs hold {records} record(s) in their common {end:.3g} s; Fig 10's "
            "quadratic fits need 3 or more: lengthen duration_s, or record more often (record_every_steps)",
            bad_input=True,
        )
    progress("limit equilibrium")
    try:
        sweep, critical = limit_equilibrium(config, table4)
    except le.UndecidedError as error:
        raise SimulationError(
            f"key 'limit_equilibrium': {error}; raise max_steps, or check equilibrium_ratio and slide_mm",
            bad_input=True,
        ) from None
    dips = sensitivity(config, table4, progress)
    progress("factor of safety by strength reduction, both models")
    safety_table, reductions = safety.factor_of_safety_table(config, table4)
    progress("the full Barton-Bandis joint (residual strength) against the peak-only joint")
    residual = safety.residual_comparison(config, table4)
    snapshots = snapshot_table(runs, config.snapshots)
    joints = joint_histories(runs)
    moves = displacement_histories(runs)
    fits = quadratic_fits(runs)
    blocks = block_table(runs["constant"].model, runs["constant"].numbering)
    dpi = config.figure_dpi
    files = {"animation.gif": _gif(runs, config.animation_frames, dpi)} if config.animation_frames else {}
    for run_of_kind in runs.values():
        if run_of_kind.series is not None:
            files |= run_of_kind.series.collections()
    return StageResult(
        tables={
            "fig7_blocks": blocks,
            "fig8_vectors": snapshots,
            "fig9_joints": joints,
            "fig10_displacements": moves,
            "fig10_fits": fits,
            "claims": claims_table(runs, config.claims),
            "fs_vs_dip": sweep,
            "critical_dip": critical,
            "dip_sensitivity": dips,
            "factor_of_safety": safety_table,
            "residual_strength": residual,
        },
        figures={
            "fig7": figures.fig7(runs["constant"].model, runs["constant"].numbering, config.slope, dpi),
            "fig8": figures.fig8(runs, snapshots, dpi),
            "fig9": figures.fig9(joints, dpi),
            "fig10": figures.fig10(moves, fits, dpi),
            "fs_vs_dip": figures.fs_vs_dip(sweep, critical, dpi),
            "dip_sensitivity": figures.dip_sensitivity(dips, dpi),
            **{f"fos_{kind}": mechanism_figure(reductions[kind][1], dpi) for kind in sm.JOINT_MODELS},
        },
        files=files,
    )
