"""Strength reduction (`bbmc.dem.strength_reduction`, `bbmc fos`) against closed forms and limit
equilibrium. Each tolerance is stated where it is used; the measured errors are in the README
("Factor of safety")."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest
import yaml
from click.testing import CliRunner
from scipy.optimize import brentq

from bbmc import laws
from bbmc.cli import main
from bbmc.dem.model import build_model
from bbmc.dem.scene import Scene
from bbmc.dem.solver import simulate
from bbmc.dem.strength_reduction import StrengthReductionResult, factor_of_safety
from bbmc.slope import planar as pl
from bbmc.slope import planar_scene as ps
from bbmc.slope import toppling as tp
from bbmc.slope import toppling_scene as ts

DEG = math.pi / 180.0
G = 9.81
RHO = 2500.0
DIP = 30.0
SOLVER = {"steps": 100_000, "time_step": {"step_s": 1e-3}}


def _fos(scene: dict) -> StrengthReductionResult:
    return factor_of_safety(build_model(Scene.model_validate(scene, strict=False), Path("<test>")))


def _incline(law: dict, width: float, height: float, **changes) -> dict:
    """A block `width` x `height` on a fixed base, both turned DIP degrees about the origin."""
    turn = {"rotate_deg": DIP, "rotate_about_m": [0.0, 0.0]}
    scene = {
        "name": "incline",
        "materials": {"rock": {"density_kg_m3": RHO}},
        "blocks": [
            {
                "name": "base",
                "material": "rock",
                "rectangle_m": {"x_m": -2 * width, "y_m": -1.0, "width_m": 3 * width, "height_m": 1.0},
                "fix": ["x", "y", "rotation"],
                **turn,
            },
            {
                "name": "slider",
                "material": "rock",
                "rectangle_m": {"x_m": -width, "y_m": 0.0, "width_m": width, "height_m": height},
                **turn,
            },
        ],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint"},
        "solver": SOLVER,
    }
    for key, value in changes.items():
        scene[key] = value
    return scene


def _within_bracket(result: StrengthReductionResult, expected: float) -> float:
    """The relative error of the FS found; the bracket must straddle the expected value."""
    lo, hi = result.bracket
    assert result.bracketed
    assert lo - 1e-9 <= expected <= hi + 1e-9, (lo, expected, hi)
    return abs(result.factor_of_safety - expected) / expected


MC = {"law": "constant", "kn_MPa_per_mm": 10, "ks_MPa_per_mm": 10, "friction_deg": 40.0}


def test_planar_block_mohr_coulomb_is_tan_phi_over_tan_psi():
    """Dry, cohesionless: FS = tan phi / tan psi; within 1 % (the bisection's half-width is 0.5 %)."""
    result = _fos(_incline(MC, 0.8, 0.2))
    assert result.start == "unreduced"
    assert _within_bracket(result, math.tan(40 * DEG) / math.tan(DIP * DEG)) < 0.01


def test_planar_block_with_cohesion_is_the_closed_form():
    """FS = (c L + W cos psi tan phi) / (W sin psi), c kept after slip; within 1 %."""
    law = {**MC, "friction_deg": 25.0, "cohesion_MPa": 0.002, "after_slip": "keep"}
    width, height = 2.0, 0.5
    weight = RHO * G * width * height
    expected = (2e3 * width + weight * math.cos(DIP * DEG) * math.tan(25 * DEG)) / (
        weight * math.sin(DIP * DEG)
    )
    assert _within_bracket(_fos(_incline(law, width, height)), expected) < 0.01


def test_a_block_that_slides_unreduced_has_fs_below_one():
    """phi 25 deg on 30 deg: FS = tan 25 / tan 30 = 0.81, found from the elastic equilibrium; within 1 %."""
    result = _fos(_incline({**MC, "friction_deg": 25.0}, 0.8, 0.2))
    assert result.start == "elastic"
    assert _within_bracket(result, math.tan(25 * DEG) / math.tan(DIP * DEG)) < 0.01


BB = {
    "law": "barton_bandis",
    "strength": {"jrc": 5.0, "jcs_MPa": 20.0, "phi_b_deg": 30.0, "phi_max_deg": 70.0},
    "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 10},
    "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 10},
    "after_slip": "keep",  # the tangent's intercept is the envelope's, not a bond lost at slip
}
BB_WIDTH, BB_HEIGHT = 10.0, 1.0  # wide and flat: sigma_n near uniform along the base


def _bb_stresses() -> tuple[float, float]:
    weight = RHO * G * BB_HEIGHT
    return weight * math.cos(DIP * DEG), weight * math.sin(DIP * DEG)


def _peak(sigma_n: float, jrc: float, phi_b: float) -> float:
    return float(laws.peak_shear_strength(sigma_n, jrc, 20e6, phi_b, 70 * DEG))


def test_planar_block_barton_bandis_envelope_reduction_is_tau_p_over_tau():
    """FS = tau_p(sigma_n) / tau with sigma_n, tau the block's mean stresses; within 1 %."""
    sigma_n, tau = _bb_stresses()
    expected = _peak(sigma_n, 5.0, 30 * DEG) / tau
    assert _within_bracket(_fos(_incline(BB, BB_WIDTH, BB_HEIGHT)), expected) < 0.01


def test_planar_block_barton_bandis_phi_b_jrc_reduction_is_its_own_closed_form():
    """Reducing tan phi_b and JRC by F: FS solves tau_p(sigma_n; JRC / F, atan(tan phi_b / F)) = tau;
    within 1 %; and it lies 10-20 % below the envelope's FS on this block."""
    sigma_n, tau = _bb_stresses()
    expected = brentq(lambda f: _peak(sigma_n, 5.0 / f, math.atan(math.tan(30 * DEG) / f)) - tau, 0.5, 5.0)
    scene = _incline(BB, BB_WIDTH, BB_HEIGHT, fos={"barton_bandis_reduction": "phi_b_jrc"})
    assert _within_bracket(_fos(scene), expected) < 0.01
    envelope = _peak(sigma_n, 5.0, 30 * DEG) / tau
    assert 0.10 <= 1 - expected / envelope <= 0.20


HB_LAW = {
    "law": "constant",
    "kn_MPa_per_mm": 10,
    "ks_MPa_per_mm": 10,
    "friction_deg": 30.0,
    "cohesion_MPa": 0.048,
}
HB_SOLVER = {"steps": 200_000, "time_step": {"step_s": 1e-2}}


@pytest.mark.parametrize("fill", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("kh", [0.0, 0.1])
def test_hoek_and_brays_planar_slope_with_a_crack_matches_limit_equilibrium(fill, kh):
    """Hoek & Bray's example (H 30 m, face 60 deg, plane 30 deg, crack 9 m behind the crest, c 48 kPa,
    phi 30 deg, gamma 25.5 kN/m^3), the crack dry, half full or full, k_h 0 or 0.1: the engine's FS by
    strength reduction within 1 % of the limit equilibrium's (measured: within 0.3 %)."""
    slope = ps.PlanarSlope(30.0, 60.0, 30.0, 9.0, fill, kh, 25.5e3 / G, G)
    expected = float(pl.factor_of_safety_mohr_coulomb(slope.forces(), 48e3, 30 * DEG))
    result = _fos(ps.planar_scene("hoek_bray", slope, HB_LAW, HB_SOLVER))
    assert _within_bracket(result, expected) < 0.01


@pytest.mark.parametrize("friction", [40.0, 45.0])
def test_goodman_bray_toppling_fs_is_near_tan_phi_over_tan_38_15(friction):
    """Hoek & Bray's toppling example on the engine (4 sub-contacts per edge): FS by strength reduction
    within 3 % of tan phi / tan 38.15 deg (measured +2.0 % and +2.2 %: the engine's own limiting
    friction is 37.45 deg, README "Goodman-Bray on the engine"), and above it."""
    blocks = tp.regular_system(10.0, 30 * DEG, 10, 5.0, 5.0, 1.0)
    expected = math.tan(friction * DEG) / math.tan(tp.limiting_friction(blocks))
    result = _fos(ts.toppling_scene(blocks, friction, ts.TrialSettings()))
    assert result.bracketed
    assert 0.0 < result.factor_of_safety / expected - 1 < 0.03


@pytest.mark.parametrize(
    "name, scene",
    [
        ("planar block", _incline(MC, 0.8, 0.2)),
        (
            "Hoek-Bray crack full",
            ps.planar_scene(
                "hb", ps.PlanarSlope(30.0, 60.0, 30.0, 9.0, 1.0, 0.0, 25.5e3 / G, G), HB_LAW, HB_SOLVER
            ),
        ),
    ],
)
def test_fs_is_stable_to_the_solver_settings(name, scene):
    """Halving the time step's safety factor, or doubling the sub-contacts, moves the FS by less than
    the bisection's tolerance (0.01; measured: README, "Factor of safety")."""
    reference = _fos(scene).factor_of_safety
    halved = {
        **scene,
        "solver": {**scene["solver"], "time_step": {**scene["solver"]["time_step"], "safety_factor": 0.25}},
    }
    doubled = {**scene, "contacts": {**scene["contacts"], "sub_contacts_per_edge": 8}}
    for changed in (halved, doubled):
        assert abs(_fos(changed).factor_of_safety - reference) < 0.01, name


def test_submerged_block_rests_on_its_effective_weight(tmp_path):
    """A block under a level water table on a level base: the contact's sigma_n is the effective stress
    (rho - rho_w) g h (to 1e-6): the water pushes on every edge, the joint's face included."""
    height, width = 1.0, 2.0
    scene = _incline(MC, width, height)
    for block in scene["blocks"]:
        del block["rotate_deg"], block["rotate_about_m"]
    scene["water"] = {"phreatic_surface_m": [[-10.0, 5.0], [10.0, 5.0]], "unit_weight_kN_m3": 9.81}
    scene["solver"] = {
        "steps": 20_000,
        "time_step": {"step_s": 1e-3},
        "stop": {"unbalanced_force_ratio": 1e-8},
    }
    scene["monitoring"] = {"monitors": [{"name": "sn", "between": ["slider", "base"], "quantity": "sigma_n"}]}
    result = simulate(build_model(Scene.model_validate(scene, strict=False), Path("<test>")))
    expected = (RHO - 1000.0) * G * height
    assert result.history["sn_MPa"].iloc[-1] * 1e6 == pytest.approx(expected, rel=1e-6)


ROOT = Path(__file__).resolve().parents[1]
HAND_WRITTEN = ROOT / "configs" / "scenes" / "planar_crack.yaml"


def test_bbmc_fos_runs_the_hand_written_scene(tmp_path):
    """configs/scenes/planar_crack.yaml, written by hand from docs/scene-format.md: its FS within 1 % of
    Hoek & Bray's for the crack half full (1.115), and every file of the stage written."""
    outcome = CliRunner().invoke(main, ["fos", "--config", str(HAND_WRITTEN), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    folder = tmp_path / "fos" / "planar_crack"
    names = {"fos.csv", "summary.csv", "mechanism.png", "bracketing.png", "provenance.json"}
    assert names <= {p.name for p in folder.iterdir()}
    summary = pd.read_csv(folder / "summary.csv").set_index("quantity")["value"]
    expected = float(
        pl.factor_of_safety_mohr_coulomb(
            ps.PlanarSlope(30.0, 60.0, 30.0, 9.0, 0.5, 0.0, 25.5e3 / G, G).forces(), 48e3, 30 * DEG
        )
    )
    assert summary["factor_of_safety"] == pytest.approx(expected, rel=0.01)
    trials = pd.read_csv(folder / "fos.csv")
    assert len(trials) == summary["trials"]
    assert set(trials["verdict"]) == {"stable", "unstable"}


@pytest.mark.parametrize(
    "change, key",
    [
        ({"fos": {"tolerance": 0.0}}, "fos.tolerance"),
        ({"fos": {"barton_bandis_reduction": "jrc"}}, "fos.barton_bandis_reduction"),
        ({"water": {"phreatic_surface_m": [[5.0, 0.0], [0.0, 1.0]]}}, "water"),
        ({"seismic": {"horizontal_coefficient": -0.1}}, "seismic.horizontal_coefficient"),
    ],
)
def test_bad_fos_water_or_seismic_input_gives_one_line_naming_the_key(tmp_path, change, key):
    scene = yaml.safe_load(HAND_WRITTEN.read_text())
    scene.update(change)
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    outcome = CliRunner().invoke(main, ["fos", "--config", str(path), "--results", str(tmp_path / "out")])
    assert outcome.exit_code == 2, outcome.output
    assert len(outcome.output.strip().splitlines()) == 1
    assert key in outcome.output
    assert not (tmp_path / "out").exists()
