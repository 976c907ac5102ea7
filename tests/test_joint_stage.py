"""`bbmc joint`: run through the command line into a temporary folder, its tables checked against numbers
computed here by hand from the published formulas (Barton & Choubey 1977, Barton & Bandis 1982,
Barton 1982, Barton, Bandis & Bakhtar 1985, Bandis, Lumsden & Barton 1983), never from bbmc's laws.

Tolerances: rel 1e-12 where the same closed form is evaluated in another order; rel 1e-5 against an
adaptive quadrature of the dilation (the stage sums trapezoids on its grid: 6e-6 at most, measured).
"""

from __future__ import annotations

import math
from itertools import pairwise
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from scipy.integrate import quad

from bbmc.cli import main
from bbmc.config import load_config
from bbmc.stages import joint as joint_stage
from stage_runs import CONFIGS, config_copy, run_stage, set_key

# The joint the tests pin (the example of configs/joint.yaml, set explicitly so the hand numbers hold).
JOINT = {
    "jrc0": 10.0,
    "jcs0_MPa": 100.0,
    "phi_b_deg": 30.0,
    "rebound_ratio": 0.7,
    "lab_length_m": 0.1,
    "field_length_m": 1.0,
    "sigma_c_MPa": 150.0,
    "phi_max_deg": 70.0,
    "damage": "barton_1985",
    "normal_stresses_MPa": [0.1, 0.5, 1.0, 2.0],
    "envelope_range_MPa": [0.01, 5.0],
    "max_displacement_ratio": 20.0,
}
PHI_R = 30.0 - 20.0 * (1.0 - 0.7)  # deg, Barton & Choubey (1977)
# Barton & Bandis (1982), one decade from 0.1 m to 1 m
JRC_N = 10.0 * 10.0 ** (-0.02 * 10.0)
JCS_N = 100.0 * 10.0 ** (-0.03 * 10.0)
SCALES = {
    "lab": {"L": 0.1, "JRC": 10.0, "JCS": 100.0},
    "field": {"L": 1.0, "JRC": JRC_N, "JCS": JCS_N},
}
TABLE = [(0.3, 0.0), (0.6, 0.75), (1.0, 1.0), (2.0, 0.85), (4.0, 0.70), (10.0, 0.50), (100.0, 0.0)]
OUTPUTS = [
    "scale.csv",
    "envelopes.csv",
    "shear_curves.csv",
    "closure.csv",
    "envelopes.png",
    "shear_curves.png",
    "mobilization.png",
    "closure.png",
    "provenance.json",
]


def _pinned(**changes):
    def edit(data):
        data.clear()
        data.update(JOINT | {"figure_dpi": 60} | changes)

    return edit


def _run(tmp_path_factory, **changes) -> Path:
    folder = tmp_path_factory.mktemp("joint")
    outcome = run_stage("joint", folder / "results", config_copy(folder, "joint", _pinned(**changes)))
    assert outcome.exit_code == 0, outcome.output
    return folder / "results" / "joint"


@pytest.fixture(scope="module")
def out(tmp_path_factory) -> Path:
    return _run(tmp_path_factory)


def delta_peak_mm(length: float, jrc: float) -> float:
    return length / 500.0 * (jrc / length) ** 0.33 * 1000.0


def roughness_deg(sigma: float, jrc: float, jcs: float) -> float:
    return jrc * math.log10(jcs / sigma)


def table_ratio(x: float) -> float:
    """JRC_mob/JRC_peak of Barton (1982) for x >= 0.3: linear in x to 1, linear in lg x after."""
    for (x0, y0), (x1, y1) in pairwise(TABLE):
        if x <= x1:
            if x1 <= 1.0:
                return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            return y0 + (y1 - y0) * math.log10(x / x0) / math.log10(x1 / x0)
    return 0.0


def test_the_shipped_config_is_valid() -> None:
    config = load_config(CONFIGS / "joint.yaml", joint_stage.Config)
    assert (config.phi_r_deg is None) != (config.rebound_ratio is None)


def test_every_output_is_written(out: Path) -> None:
    assert sorted(p.name for p in out.iterdir()) == sorted(OUTPUTS)


def test_scale_effects(out: Path) -> None:
    scale = pd.read_csv(out / "scale.csv").set_index("scale")
    assert list(scale.index) == ["lab", "field"]
    assert pytest.approx(6.309573, rel=1e-6) == JRC_N
    for name, s in SCALES.items():
        row = scale.loc[name]
        assert row["length_m"] == s["L"]
        assert row["JRC"] == pytest.approx(s["JRC"], rel=1e-12)
        assert row["JCS_MPa"] == pytest.approx(s["JCS"], rel=1e-12)
        assert row["delta_peak_mm"] == pytest.approx(delta_peak_mm(s["L"], s["JRC"]), rel=1e-12)
        assert row["phi_r_deg"] == pytest.approx(PHI_R, rel=1e-12)
    assert scale.loc["lab", "delta_peak_mm"] == pytest.approx(0.9141764, rel=1e-6)


def test_envelopes(out: Path) -> None:
    env = pd.read_csv(out / "envelopes.csv")
    sigma = env["sigma_n_MPa"].to_numpy()
    assert sigma[0] == pytest.approx(0.01) and sigma[-1] == pytest.approx(5.0)
    residual = sigma * math.tan(math.radians(PHI_R))
    np.testing.assert_allclose(env["tau_residual_MPa"], residual, rtol=1e-12)
    for name, s in SCALES.items():
        for column, friction in ((f"tau_peak_{name}_MPa", 30.0), (f"tau_peak_phi_r_{name}_MPa", PHI_R)):
            total = [min(friction + roughness_deg(v, s["JRC"], s["JCS"]), 70.0) for v in sigma]
            np.testing.assert_allclose(env[column], sigma * np.tan(np.radians(total)), rtol=1e-12)
        # the tangent where the cap does not act: d tau/d sigma = tan t - k (tan^2 t + 1)
        k = math.pi * s["JRC"] / (180.0 * math.log(10.0))
        for v, phi, c in zip(
            sigma, env[f"phi_tangent_{name}_deg"], env[f"c_tangent_{name}_kPa"], strict=True
        ):
            t = math.radians(30.0 + roughness_deg(v, s["JRC"], s["JCS"]))
            if t >= math.radians(70.0):
                assert (phi, c) == (pytest.approx(70.0), 0.0)
                continue
            slope = math.tan(t) - k * (math.tan(t) ** 2 + 1.0)
            assert phi == pytest.approx(math.degrees(math.atan(slope)), rel=1e-12)
            assert c == pytest.approx((v * math.tan(t) - v * slope) * 1e3, rel=1e-9)


def test_each_shear_curve_peaks_at_delta_peak_with_phi_r(out: Path) -> None:
    curves = pd.read_csv(out / "shear_curves.csv")
    assert sorted(curves["sigma_n_MPa"].unique()) == JOINT["normal_stresses_MPa"]
    for (name, sigma), curve in curves.groupby(["scale", "sigma_n_MPa"]):
        s = SCALES[name]
        i = roughness_deg(sigma, s["JRC"], s["JCS"])
        top = curve.loc[curve["tau_MPa"].idxmax()]
        assert top["delta_over_delta_peak"] == 1.0
        assert top["delta_mm"] == pytest.approx(delta_peak_mm(s["L"], s["JRC"]), rel=1e-12)
        assert top["tau_MPa"] == pytest.approx(sigma * math.tan(math.radians(PHI_R + i)), rel=1e-12)
        at = curve.set_index("delta_over_delta_peak")
        assert at.loc[0.0, "tau_MPa"] == 0.0
        assert at.loc[0.3, "phi_mob_deg"] == pytest.approx(PHI_R, rel=1e-12)
        assert at.loc[10.0, "tau_MPa"] == pytest.approx(
            sigma * math.tan(math.radians(PHI_R + 0.5 * i)), rel=1e-12
        )
        assert curve["delta_over_delta_peak"].max() == 20.0


def test_dilation_is_the_integral_of_tan_d_mob(out: Path) -> None:
    curves = pd.read_csv(out / "shear_curves.csv")
    for (name, sigma), curve in curves.groupby(["scale", "sigma_n_MPa"]):
        s = SCALES[name]
        i = roughness_deg(sigma, s["JRC"], s["JCS"])
        m = 0.7 + s["JRC"] / (12.0 * math.log10(s["JCS"] / sigma))  # Barton, Bandis & Bakhtar (1985)
        peak = delta_peak_mm(s["L"], s["JRC"])
        at = curve.set_index("delta_over_delta_peak")
        assert at.loc[1.0, "d_mob_deg"] == pytest.approx(i / m, rel=1e-12)
        assert (at.loc[at.index <= 0.3, "dilation_mm"] == 0.0).all()
        assert (np.diff(curve["dilation_mm"]) >= 0.0).all()

        def slope(x: float, i=i, m=m) -> float:
            return math.tan(math.radians(table_ratio(x) * i / m))

        edges = [0.3, 0.6, 1.0, 2.0, 4.0, 10.0, 20.0]
        expected = peak * sum(quad(slope, a, b, epsabs=0, epsrel=1e-10)[0] for a, b in pairwise(edges))
        assert curve["dilation_mm"].iloc[-1] == pytest.approx(expected, rel=1e-5)


def test_mobilized_roughness_passes_through_bartons_table(out: Path) -> None:
    curves = pd.read_csv(out / "shear_curves.csv")
    for (name, sigma), curve in curves.groupby(["scale", "sigma_n_MPa"]):
        s = SCALES[name]
        at = curve.set_index("delta_over_delta_peak")["JRC_mob_over_JRC_peak"]
        for x, ratio in TABLE[:-1]:
            assert at.loc[x] == pytest.approx(ratio, abs=1e-12)
        assert at.loc[0.0] == pytest.approx(-PHI_R / roughness_deg(sigma, s["JRC"], s["JCS"]), rel=1e-12)


def test_closure_is_the_bandis_hyperbola(out: Path) -> None:
    closure = pd.read_csv(out / "closure.csv")
    a_j = 10.0 / 5.0 * (0.2 * 150.0 / 100.0 - 0.1)  # mm, Barton, Bandis & Bakhtar (1985)
    k_ni = -7.15 + 1.75 * 10.0 + 0.02 * 100.0 / a_j  # MPa/mm, Bandis et al. (1983)
    v_m = -0.2960 - 0.0056 * 10.0 + 2.2410 * (100.0 / a_j) ** -0.2450  # mm, first loading cycle
    assert (a_j, k_ni) == (pytest.approx(0.4), pytest.approx(15.35))
    assert closure["a_j_mm"].iloc[0] == pytest.approx(a_j, rel=1e-12)
    assert closure["K_ni_MPa_per_mm"].iloc[0] == pytest.approx(k_ni, rel=1e-12)
    assert closure["V_m_mm"].iloc[0] == pytest.approx(v_m, rel=1e-12)
    half = closure[np.isclose(closure["sigma_n_MPa"], k_ni * v_m, rtol=1e-12, atol=0)]
    assert len(half) == 1
    assert half["closure_mm"].iloc[0] == pytest.approx(v_m / 2.0, rel=1e-12)
    assert half["K_n_MPa_per_mm"].iloc[0] == pytest.approx(4.0 * k_ni, rel=1e-12)
    dv = closure["closure_mm"].to_numpy()
    np.testing.assert_allclose(closure["sigma_n_MPa"], k_ni * dv / (1.0 - dv / v_m), rtol=1e-9, atol=1e-15)
    assert closure["sigma_n_MPa"].max() == pytest.approx(4.0 * k_ni * v_m, rel=1e-12)


def test_a_given_damage_and_residual_angle(tmp_path_factory) -> None:
    changes = {"damage": 2.5, "phi_r_deg": 26.0, "rebound_ratio": None}
    out = _run(tmp_path_factory, **changes)
    assert pd.read_csv(out / "scale.csv")["phi_r_deg"].tolist() == [26.0, 26.0]
    curves = pd.read_csv(out / "shear_curves.csv")
    peaks = curves[curves["delta_over_delta_peak"] == 1.0]
    for row in peaks.itertuples():
        s = SCALES[row.scale]
        i = roughness_deg(row.sigma_n_MPa, s["JRC"], s["JCS"])
        assert row.d_mob_deg == pytest.approx(i / 2.5, rel=1e-12)
        assert row.tau_MPa == pytest.approx(row.sigma_n_MPa * math.tan(math.radians(26.0 + i)), rel=1e-12)


def test_help_shows_an_example() -> None:
    outcome = CliRunner().invoke(main, ["joint", "--help"])
    assert outcome.exit_code == 0
    assert "Example" in outcome.output and "configs/joint.yaml" in outcome.output


BAD = [
    ("jrc0", 25, "jrc0", "less than or equal to 20"),
    ("jcs0_MPa", "100", "jcs0_MPa", "valid number"),
    ("phi_r_deg", 20.0, "rebound_ratio", "exactly one"),
    ("rebound_ratio", None, "rebound_ratio", "neither"),
    ("phi_max_deg", 25.0, "phi_max_deg", "exceed phi_b_deg"),
    ("sigma_c_MPa", 50.0, "sigma_c_MPa", "jcs0_MPa"),
    ("damage", "barton", "damage", "'barton_1985' or a number"),
    ("damage", 0.0, "damage", "M > 0"),
    ("normal_stresses_MPa", [0.5, -1.0], "normal_stresses_MPa", "> 0"),
    ("normal_stresses_MPa", [0.5, 0.5], "normal_stresses_MPa", "distinct"),
    ("envelope_range_MPa", [5.0, 0.01], "envelope_range_MPa", "low < high"),
    ("max_displacement_ratio", 1.0, "max_displacement_ratio", "greater than 1"),
    ("lab_length_m", 0.0, "lab_length_m", "greater than 0"),
    ("figure_dpi", 10, "figure_dpi", "greater than or equal to 50"),
]


@pytest.mark.parametrize(("key", "value", "named", "message"), BAD)
def test_bad_value_is_refused(tmp_path, key: str, value, named: str, message: str) -> None:
    config = config_copy(tmp_path, "joint", _pinned(**{key: value}))
    results = tmp_path / "results"
    outcome = run_stage("joint", results, config)
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1, outcome.stderr
    assert "Traceback" not in outcome.output + outcome.stderr
    assert f"key '{named}'" in lines[0] and message in lines[0], lines[0]
    assert not results.exists() or not any(results.iterdir()), "something was written"


def test_an_unknown_key_is_refused(tmp_path) -> None:
    config = config_copy(tmp_path, "joint", set_key("jrc", 10.0))
    results = tmp_path / "results"
    outcome = run_stage("joint", results, config)
    assert outcome.exit_code == 2
    assert "key 'jrc'" in outcome.stderr and "did you mean 'jrc0'" in outcome.stderr
    assert not results.exists() or not any(results.iterdir())
