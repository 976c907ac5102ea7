"""What the full Barton-Bandis joint (law `barton_bandis_mobilized`) costs, measured side by side.

mobilized_cost.csv, two parts:

* `update`: the time of one law update per sub-contact (`joint_state.update_joint_laws`, every sub-contact
  evaluated) for the mobilized law (Bandis K_n), the paper's peak-only law (eq 15 tangent, eq 8 K_n,
  eq 17 K_s), both again with constant stiffnesses (strength alone, like for like), and a constant
  joint, on the same arrays of sub-contacts in one process, best of N; with the ratios to the paper's.
* `trade`: the shear box of `tests/test_mobilized_engine.py` (1 MPa, sheared to 8 delta_peak) at each
  update interval and stress-change trigger of the config: the largest error of tau against the law's
  tau(delta), as a fraction of the peak strength, the steps and the wall time.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc import laws, units
from bbmc.dem import joint_state
from bbmc.dem import layout as L
from bbmc.dem.model import Model, build_model
from bbmc.dem.solver import simulate
from bbmc.scene.schema import Scene

JRC, JCS, PHI_R, LENGTH, SIGMA_N, SPEED = 10.0, 100e6, 25.0 * units.deg, 0.1, 1e6, 0.02
MOBILIZED = {
    "law": "barton_bandis_mobilized",
    "jrc0": JRC,
    "jcs0_MPa": JCS / units.MPa,
    "phi_b_deg": 30.0,
    "phi_r_deg": 25.0,
    "lab_length_m": LENGTH,
    "normal_stiffness": {"law": "bandis", "sigma_c_MPa": 150.0},
    "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 100},
}
PEAK_ONLY = {
    "law": "barton_bandis",
    "strength": {"jrc": JRC, "jcs_MPa": JCS / units.MPa, "phi_b_deg": 30.0},
    "normal_stiffness": {"law": "eq8", "q_per_mm": 7.715},
    "shear_stiffness": {"law": "simplified", "kj_MPa_per_mm": 2.0, "nj": 0.5},
}
CONSTANT = {"law": "constant", "kn_MPa_per_mm": 100, "ks_MPa_per_mm": 100, "friction_deg": 35.0}


def shear_box(law: dict, velocity: dict | None, sigma_n: float = SIGMA_N, ramp: int = 2000) -> dict:
    """A 0.1 m upper block on a fixed 0.2 m lower one (its rotation held); sigma_n [Pa] on its top edge,
    ramped on over `ramp` steps; `velocity` of the upper block (a scene `velocity` entry); the law
    updated every step, the time step automatic below 1e-4 s; monitors of the upper block's ux, uy and
    of the joint's tau, sigma_n, shear path and dilation every 100 steps. No stop: set one."""
    upper = {
        "name": "upper",
        "material": "rock",
        "rectangle_m": {"x_m": 0.0, "y_m": 0.0, "width_m": LENGTH, "height_m": 0.05},
        "fix": ["rotation"],
        **({"velocity": velocity} if velocity is not None else {}),
    }
    joint = [("tau", "tau"), ("sn", "sigma_n"), ("path", "shear_path"), ("dil", "dilation")]
    return {
        "name": "mobilized_box",
        "gravity_m_s2": [0.0, 0.0],
        "materials": {"rock": {"density_kg_m3": 2500.0}},
        "blocks": [
            {
                "name": "lower",
                "material": "rock",
                "rectangle_m": {"x_m": -0.05, "y_m": -0.05, "width_m": 0.2, "height_m": 0.05},
                "fix": ["x", "y", "rotation"],
            },
            upper,
        ],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint"},
        "loads": {
            "edge_stresses": [
                {"block": "upper", "edge": "up", "sigma_n_MPa": sigma_n / units.MPa, "ramp_steps": ramp}
            ]
        },
        "solver": {"steps": 10**7, "update_interval_steps": 1, "time_step": {"step_s": 1e-4}},
        "monitoring": {
            "every_steps": 100,
            "monitors": [
                {"name": "ux", "block": "upper", "quantity": "ux"},
                {"name": "uy", "block": "upper", "quantity": "uy"},
                *({"name": n, "between": ["upper", "lower"], "quantity": q} for n, q in joint),
            ],
        },
    }


def sheared_to(scene: dict, peaks: float, update_interval: int, stress_change: float | None) -> dict:
    """`scene` sheared to `peaks` x delta_peak, its law updated on the given schedule."""
    peak = float(laws.peak_shear_displacement(LENGTH, JRC))
    solver = {
        **scene["solver"],
        "update_interval_steps": update_interval,
        "law_update_stress_change": stress_change,
        "stop": {"displacement_m": peaks * peak},
    }
    return {**scene, "solver": solver}


def _model(scene: dict) -> Model:
    return build_model(Scene.model_validate(scene, strict=False), Path(f"<{scene['name']}>"))


def update_cost(sub_contacts: int, repeats: int) -> pd.DataFrame:
    """Seconds per sub-contact update of each law on the same random stresses and shear paths."""
    scene = shear_box(MOBILIZED, None)
    stiff = {"normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 100}}
    scene["joint_laws"] = {
        "mobilized": MOBILIZED,
        "peak_only": PEAK_ONLY,
        "mobilized_constant_stiffness": MOBILIZED | stiff,
        "peak_only_constant_stiffness": PEAK_ONLY | stiff | {"shear_stiffness": MOBILIZED["shear_stiffness"]},
        "constant": CONSTANT,
    }
    scene["contacts"] = {"default_law": "mobilized"}
    model = _model(scene)
    rng = np.random.default_rng(0)
    n_sub = 4
    subs = np.zeros((sub_contacts, L.SUB_COLUMNS))
    subs[:, L.SN] = rng.uniform(0.1e6, 5e6, sub_contacts)
    subs[:, L.TAU] = rng.uniform(0.0, 1e6, sub_contacts)
    subs[:, L.PATH] = rng.uniform(0.0, 10e-3, sub_contacts)
    rows = []
    for j, name in enumerate(model.law_names):
        contacts = np.zeros((sub_contacts // n_sub, L.CONTACT_COLUMNS), dtype=np.int64)
        contacts[:, L.JOINT_TYPE] = j
        work, law_state = subs.copy(), np.zeros((sub_contacts, L.LAW_STATE_COLUMNS))
        joint_state.update_joint_laws(contacts, work, law_state, n_sub, model.laws, model.params, False)
        best = np.inf
        for _ in range(repeats):
            work[:] = subs
            start = time.perf_counter()
            joint_state.update_joint_laws(contacts, work, law_state, n_sub, model.laws, model.params, False)
            best = min(best, time.perf_counter() - start)
        rows.append({"part": "update", "law": name, "ns_per_sub_contact_update": best / sub_contacts * 1e9})
    table = pd.DataFrame(rows)
    peak = table.loc[table["law"] == "peak_only", "ns_per_sub_contact_update"].iloc[0]
    table["over_peak_only"] = table["ns_per_sub_contact_update"] / peak
    return table


def trade(intervals: list[int], stress_changes: list[float], progress: Callable[[str], None]) -> pd.DataFrame:
    """The shear box's tau error against the law and its cost, per update schedule."""
    peak_d = float(laws.peak_shear_displacement(LENGTH, JRC))
    peak_tau = float(laws.mobilized_shear_strength(peak_d, SIGMA_N, JRC, JCS, PHI_R, peak_d, 70 * units.deg))
    schedules = [(n, None) for n in intervals] + [(max(intervals), c) for c in stress_changes]
    rows = []
    for interval, change in schedules:
        progress(f"mobilized law: update every {interval} steps, stress change {change}")
        model = _model(
            sheared_to(shear_box(MOBILIZED, {"x_m_s": SPEED, "start_step": 2000}), 8.2, interval, change)
        )
        start = time.perf_counter()
        h = simulate(model).history
        seconds = time.perf_counter() - start
        path = h["path_mm"].to_numpy() * units.mm
        keep = path > 0.05 * peak_d
        tau = np.abs(h["tau_MPa"].to_numpy()[keep]) * units.MPa
        law = laws.mobilized_shear_strength(path[keep], SIGMA_N, JRC, JCS, PHI_R, peak_d, 70 * units.deg)
        rows.append(
            {
                "part": "trade",
                "update_interval_steps": interval,
                "law_update_stress_change": change,
                "largest_tau_error_of_peak": float(np.max(np.abs(tau - law))) / peak_tau,
                "steps": int(h["step"].iloc[-1]),
                "wall_time_s": seconds,
            }
        )
    return pd.DataFrame(rows)


def mobilized_cost_table(
    sub_contacts: int, repeats: int, intervals: list[int], stress_changes: list[float], progress
) -> pd.DataFrame:
    progress("mobilized law: cost of a law update")
    return pd.concat([update_cost(sub_contacts, repeats), trade(intervals, stress_changes, progress)])
