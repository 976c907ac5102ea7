"""`bbmc shear`: the paper's direct shear tests (section 4, Table 3, Figs 3-6) on the block engine.

Three parts, all on the shear box of `bbmc.shear.box`:

* Stress-controlled tests at every load of Table 3 with the uncorrected (eq 4), corrected (eq 16) and
  simplified (eq 17) shear stiffness; strength from eq 15, K_n from eq 8. Beside each engine d_h is
  the closed form the engine must match, the integral of d tau / K_st(tau) from 0 to the load.
* Constant-velocity tests (Fig 5) at the four normal stresses with each law: the tau-d_h curves of
  Fig 6, beside the test curves that `bbmc fit` reconstructs for Fig 1; and with the full
  displacement-dependent Barton-Bandis joint (`full_joint`: peak, softening, residual, dilation).
* The calibration of eq 16 (`bbmc.shear.calibration`) on the laboratory d_h of Table 3.

Read from data/paper as inputs: the loads and test d_h of Table 3 (the calibration's targets), the
printed coefficients (equation_constants.csv), Table 2's density, Table 1 (fitted coefficients if
asked; its measured tau_p is drawn in Fig 6) and the Fig 2a legends (the test curves of Fig 1). The
printed numerical d_h and stiffnesses of Table 3 are read only to compare with.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
import pandas as pd

from bbmc import paper_tables, units
from bbmc.comparison import TOLERANCES, judge
from bbmc.io import StageResult
from bbmc.joint import model as jm
from bbmc.scene.schema import name_part
from bbmc.shear import box
from bbmc.shear import calibration as cal
from bbmc.shear.bench import Bench
from bbmc.shear.config import Config, load_inputs
from bbmc.shear.figures import calibration_figure, fig4, fig6
from bbmc.stages import fit as fit_stage

NAME = "shear"
PAPER_COLUMNS = {"uncorrected": "d_h_numerical_uncorrected_mm", "corrected": "d_h_numerical_corrected_mm"}
SECANT_METHOD = (
    "one constant K_s per test (a secant, as a 3DEC M-C joint) matched on the engine to the test d_h"
)
PEAK_FRACTION = 0.999  # a curve's peak is where tau first reaches this fraction of its largest value
LAW_KEYS = {"uncorrected": "K_st_uncorrected", "corrected": "K_st_corrected", "simplified": "K_st_simplified"}


def quick_config(config: Config) -> Config:
    """The config `--quick` runs: the shear ramp and the curve records from `quick`, validated again
    (ValueError if the quick settings break a rule of the config)."""
    data = config.model_dump()
    data["stress_controlled"]["shear_ramp_steps"] = config.quick.shear_ramp_steps
    data["constant_velocity"]["record_every_steps"] = config.quick.velocity_record_every_steps
    return Config.model_validate(data, strict=False)


def _label(sigma_n: float, tau: float | None, law: str) -> str:
    load = f"{name_part(sigma_n / units.MPa)}MPa" + (
        f"_{name_part(tau / units.MPa)}MPa" if tau is not None else ""
    )
    return f"{law}_{load}"


def stress_tests(bench: Bench, loads: pd.DataFrame, progress: Callable[[str], None]) -> pd.DataFrame:
    """Every load of Table 3 with every law: the engine's outcome beside the closed form."""
    rows = []
    floor_fraction = bench.config.joint_options.shear_stiffness_floor
    for load in loads.itertuples():
        sigma_n, tau = load.sigma_n_MPa * units.MPa, load.tau_MPa * units.MPa
        state = jm.stiffness_state(np.array([sigma_n]), np.array([tau]), bench.stiffness)
        strength = jm.strength_state(np.array([sigma_n]), bench.strength)
        for kind in box.SHEAR_LAWS:
            progress(f"stress-controlled {kind} sigma_n {load.sigma_n_MPa:g} MPa, tau {load.tau_MPa:g} MPa")
            outcome = bench.stress_test(
                _label(sigma_n, tau, kind), bench.paper_law(kind, sigma_n), sigma_n, tau
            )
            closed = jm.tangent_displacement(sigma_n, tau, bench.stiffness, LAW_KEYS[kind], floor_fraction)
            law_k = float(state[LAW_KEYS[kind]][0])
            floor = floor_fraction * float(state["K_si"][0])
            rows.append(
                {
                    "sigma_n_MPa": load.sigma_n_MPa,
                    "tau_MPa": load.tau_MPa,
                    "law": kind,
                    "status": outcome.status,
                    "d_h_mm": outcome.d_h / units.mm,
                    "d_h_closed_form_mm": closed / units.mm,
                    "engine_minus_closed_form_pct": 100 * (outcome.d_h / closed - 1)
                    if outcome.status == "holds"
                    else math.nan,
                    "strength_eq15_MPa": float(strength["tau_p_bb"][0]) / units.MPa,
                    "tau_over_strength": tau / float(strength["tau_p_bb"][0]),
                    "K_st_at_load_MPa_per_mm": max(law_k, floor) / units.MPa_per_mm,
                    "K_st_engine_end_MPa_per_mm": outcome.final_ks / units.MPa_per_mm,
                    "stiffness_floor_acts": law_k < floor,
                    "steps": outcome.steps,
                }
            )
    return pd.DataFrame(rows)


def _reasoning(row: pd.Series, paper: float) -> str:
    if row["status"] != "holds" and row["tau_over_strength"] <= 1.0:
        return f"the engine's test ended '{row['status']}' (no d_h); the paper prints {paper:g} mm"
    if row["status"] != "holds":
        return (
            f"tau = {row['tau_MPa']:g} MPa exceeds the eq 15 strength {row['strength_eq15_MPa']:.4f} MPa "
            f"({row['tau_over_strength']:.2f} x): a stress-controlled test has no equilibrium and the joint "
            "slides without limit; the paper's finite d_h cannot come from this model (audit F16)"
        )
    return (
        "engine d_h equals the closed form integral of d tau / K_st "
        f"({row['engine_minus_closed_form_pct']:+.2f} %); "
        f"the paper's is {paper / row['d_h_mm']:.0f} x larger: its stiffnesses cannot give its displacements "
        "(audit F5)"
    )


def table3_comparison(loads: pd.DataFrame, tests: pd.DataFrame) -> pd.DataFrame:
    """Table 3 beside ours, cell by cell: the paper's T, N-U and N-C; our three laws; differences and
    the verdict on each printed numerical d_h (bbmc.comparison.judge, d_h tolerance)."""
    tol = TOLERANCES["d_h_mm"].value
    wide = tests.pivot_table(index=["sigma_n_MPa", "tau_MPa"], columns="law", values="d_h_mm", sort=False)
    rows = []
    for load in loads.itertuples():
        key = (load.sigma_n_MPa, load.tau_MPa)
        row = {
            "sigma_n_MPa": load.sigma_n_MPa,
            "tau_MPa": load.tau_MPa,
            "d_h_test_mm": load.d_h_test_mm,
            "d_h_paper_uncorrected_mm": load.d_h_numerical_uncorrected_mm,
            "d_h_paper_corrected_mm": load.d_h_numerical_corrected_mm,
        }
        for kind in box.SHEAR_LAWS:
            row[f"d_h_{kind}_mm"] = wide.loc[key, kind]
        for kind, column in PAPER_COLUMNS.items():
            paper, ours = getattr(load, column), row[f"d_h_{kind}_mm"]
            test_row = tests[
                (tests["sigma_n_MPa"] == load.sigma_n_MPa)
                & (tests["tau_MPa"] == load.tau_MPa)
                & (tests["law"] == kind)
            ].iloc[0]
            verdict = judge(paper, ours, tol)
            row[f"{kind}_minus_paper_mm"] = ours - paper
            row[f"{kind}_relative_difference"] = (ours - paper) / paper
            row[f"{kind}_verdict"] = verdict.verdict
            row[f"{kind}_reasoning"] = _reasoning(test_row, paper)
        row["corrected_minus_test_mm"] = row["d_h_corrected_mm"] - load.d_h_test_mm
        rows.append(row)
    return pd.DataFrame(rows)


def velocity_curves(bench: Bench, stresses: np.ndarray, progress: Callable[[str], None]) -> pd.DataFrame:
    frames = []
    for sigma_n in stresses:
        for kind in box.SHEAR_LAWS:
            progress(f"constant-velocity {kind} sigma_n {sigma_n / units.MPa:g} MPa")
            curve = bench.velocity_test(
                f"velocity_{_label(sigma_n, None, kind)}", bench.paper_law(kind, sigma_n), sigma_n
            )
            frames.append(curve.assign(law=kind, sigma_n_applied_MPa=sigma_n / units.MPa))
        progress(f"constant-velocity full Barton-Bandis joint sigma_n {sigma_n / units.MPa:g} MPa")
        curve = bench.velocity_test(
            f"velocity_{_label(sigma_n, None, 'full')}",
            bench.full_law(sigma_n),
            sigma_n,
            bench.config.full_joint.update_interval_steps,
        )
        frames.append(curve.assign(law="full", sigma_n_applied_MPa=sigma_n / units.MPa))
    table = pd.concat(frames, ignore_index=True)
    return table[["law", "sigma_n_applied_MPa", "time_s", "d_h_mm", "tau_MPa", "sigma_n_MPa"]]


def velocity_peaks(curves: pd.DataFrame, bench: Bench, table1: pd.DataFrame) -> pd.DataFrame:
    """Peak of each curve beside the eq 15 strength and the measured tau_p of Table 1."""
    rows = []
    for (kind, sigma), curve in curves.groupby(["law", "sigma_n_applied_MPa"], sort=False):
        peak = curve.index[np.argmax(curve["tau_MPa"].to_numpy() >= PEAK_FRACTION * curve["tau_MPa"].max())]
        strength = jm.strength_state(np.array([sigma * units.MPa]), bench.strength)["tau_p_bb"][0] / units.MPa
        measured = table1.loc[np.isclose(table1["sigma_n_MPa"], sigma), "tau_p_MPa"]
        rows.append(
            {
                "law": kind,
                "sigma_n_MPa": sigma,
                "peak_tau_MPa": curve.loc[peak, "tau_MPa"],
                "d_h_at_peak_mm": curve.loc[peak, "d_h_mm"],
                "strength_eq15_MPa": float(strength),
                "tau_p_measured_MPa": float(measured.iloc[0]) if len(measured) else math.nan,
            }
        )
    return pd.DataFrame(rows)


def _calibration_tests(bench: Bench, loads: pd.DataFrame) -> list[cal.Test]:
    tests = []
    for load in loads.itertuples():
        sigma_n, tau = load.sigma_n_MPa * units.MPa, load.tau_MPa * units.MPa
        state = jm.stiffness_state(np.array([sigma_n]), np.array([tau]), bench.stiffness)
        tests.append(
            cal.Test(
                sigma_n=sigma_n,
                tau=tau,
                tau_p=float(state["tau_p_fit"][0]),
                tau_ult=float(state["tau_ult_fit"][0]),
                k_si=float(state["K_si"][0]),
                target=load.d_h_test_mm * units.mm,
            )
        )
    return tests


def constant_stiffness_forward(bench: Bench, tests: list[cal.Test]) -> cal.Forward:
    """The simulation the calibration root-finds around: one test with one constant K_s."""

    def forward(index: int, k_s: float) -> float:
        t = tests[index]
        shear = {"law": "constant", "ks_MPa_per_mm": k_s / units.MPa_per_mm}
        name = f"calibration_{_label(t.sigma_n, t.tau, 'constant')}"
        return bench.stress_test(name, bench.law(shear), t.sigma_n, t.tau, keep=False).d_h

    return forward


def _as_tangent_law(bench: Bench, fit, tests: list[cal.Test]) -> list[float]:
    """d_h / target at each test of eq 16 with the fitted a, b used as the tangent law it is written
    as (the integral of d tau / K_st, the engine's floor): does the fitted law give back the targets?"""
    if fit is None:
        return []
    law = dataclasses.replace(bench.stiffness, correction_a=fit.a, correction_b=fit.b)
    floor = bench.config.joint_options.shear_stiffness_floor
    return [jm.tangent_displacement(t.sigma_n, t.tau, law, "K_st_corrected", floor) / t.target for t in tests]


def calibration(
    bench: Bench, loads: pd.DataFrame, constants: dict[str, float], progress: Callable[[str], None]
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Eq 16's a and b from the test d_h, per fit set, beside the paper's; and the per-test detail."""
    paper_a, paper_b = constants["eq16.correction_a"], constants["eq16.correction_b"]
    progress("calibration: one K_s per test")
    tests = _calibration_tests(bench, loads)
    forward = constant_stiffness_forward(bench, tests)
    results = cal.calibrate(tests, forward, bench.config.calibration.tolerance_log_k)
    detail = pd.DataFrame(
        {
            "sigma_n_MPa": loads["sigma_n_MPa"].to_numpy(),
            "tau_MPa": loads["tau_MPa"].to_numpy(),
            "tau_over_tau_p": [t.ratio for t in tests],
            "d_h_target_mm": [t.target / units.mm for t in tests],
            "status": [r.status for r in results],
            "d_h_reached_mm": [r.d_h / units.mm for r in results],
            "K_s_calibrated_MPa_per_mm": [r.k_s / units.MPa_per_mm for r in results],
            "K_si_MPa_per_mm": [t.k_si / units.MPa_per_mm for t in tests],
            "K_st_uncorrected_MPa_per_mm": [
                float(
                    jm.stiffness_state(np.array([t.sigma_n]), np.array([t.tau]), bench.stiffness)[
                        "K_st_uncorrected"
                    ][0]
                )
                / units.MPa_per_mm
                for t in tests
            ],
            "f_calibrated": [
                t.correction(r.k_s) if r.status == "matched" else math.nan
                for t, r in zip(tests, results, strict=True)
            ],
            "K_st_corrected_paper_MPa_per_mm": loads["K_st_corrected_MPa_per_mm"].to_numpy(),
            "f_from_paper_K_st": [
                t.correction(k * units.MPa_per_mm)
                for t, k in zip(tests, loads["K_st_corrected_MPa_per_mm"], strict=True)
            ],
            "simulations": [r.evaluations for r in results],
        }
    )
    detail["calibrated_over_uncorrected"] = (
        detail["K_s_calibrated_MPa_per_mm"] / detail["K_st_uncorrected_MPa_per_mm"]
    )
    rows = []
    for fit_set in bench.config.calibration.fit_sets:
        chosen = [
            fit_set.sigma_n_MPa is None or float(s) in fit_set.sigma_n_MPa for s in detail["sigma_n_MPa"]
        ]
        subset = [t for t, keep in zip(tests, chosen, strict=True) if keep]
        for method, column in (
            (SECANT_METHOD, "f_calibrated"),
            ("no simulation: the paper's corrected K_st solved for f", "f_from_paper_K_st"),
        ):
            f = detail.loc[chosen, column].tolist()
            fit = cal.fit_correction(subset, f)
            replay = _as_tangent_law(
                bench, fit, [t for t, v in zip(subset, f, strict=True) if math.isfinite(v)]
            )
            rows.append(
                {
                    "fit_set": fit_set.name,
                    "method": method,
                    "tests_used": int(np.isfinite(f).sum()),
                    "tests_in_set": len(subset),
                    "a": fit.a if fit else math.nan,
                    "b": fit.b if fit else math.nan,
                    "R2": fit.r2 if fit else math.nan,
                    "paper_a": paper_a,
                    "paper_b": paper_b,
                    "a_minus_paper": (fit.a - paper_a) if fit else math.nan,
                    "b_minus_paper": (fit.b - paper_b) if fit else math.nan,
                    "tangent_law_d_h_over_target_min": min(replay, default=math.nan),
                    "tangent_law_d_h_over_target_max": max(replay, default=math.nan),
                }
            )
    return pd.DataFrame(rows), detail


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """Run every test and the calibration; tabulate and draw. Nothing is written here."""
    inputs = load_inputs(config)
    bench = Bench(config, inputs)
    loads = inputs["table3"]
    tests = stress_tests(bench, loads, progress)
    table3 = table3_comparison(loads, tests)
    stresses = np.unique(loads["sigma_n_MPa"].to_numpy()) * units.MPa
    curves = velocity_curves(bench, stresses, progress)
    peaks = velocity_peaks(curves, bench, inputs["table1"])
    test_curves = fit_stage.fig1_curves(inputs["table1"], inputs["legends"], config.fig2a_units, 200)
    constants = paper_tables.printed_constants(inputs["constants"])
    fits, detail = calibration(bench, loads, constants, progress)
    dpi = config.figure_dpi
    return StageResult(
        tables={
            "table3_shear": table3,
            "stress_tests": tests,
            "velocity_curves": curves,
            "velocity_peaks": peaks,
            "test_curves": test_curves,
            "calibration": fits,
            "calibration_tests": detail,
        },
        figures={
            "fig4": fig4(table3, dpi),
            "fig6": fig6(curves, test_curves, peaks, config.constant_velocity.velocity_m_s, dpi),
            "calibration": calibration_figure(detail, fits, dpi),
        },
        files=bench.scenes,
    )
