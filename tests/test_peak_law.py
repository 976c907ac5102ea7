"""The peak Barton-Bandis law (`law: barton_bandis`) with the keys it shares with the full joint
(`bbmc.joint.inputs.ResidualAndScale`): JRC and JCS scaled from the lab to the field length (Barton &
Bandis 1982), phi_r in place of phi_b (Barton & Choubey 1977), and bad values refused in one line."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc import laws
from bbmc.bench.mobilized_cost import shear_box
from bbmc.cli import main
from bbmc.dem import layout as L
from bbmc.dem.model import built_scene
from stage_runs import refused

DEG = math.pi / 180.0
STRENGTH = {"jrc": 10.0, "jcs_MPa": 100.0, "phi_b_deg": 30.0}
STRESSES = np.geomspace(1e3, 2e8, 60)  # [Pa] past the cap (low) and past JCS (high)


def _law(**strength) -> dict:
    return {
        "law": "barton_bandis",
        "strength": {k: v for k, v in {**STRENGTH, **strength}.items() if v is not None},
        "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 100},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 100},
    }


def _row(law: dict) -> np.ndarray:
    """The engine's parameters of the law (the shear box's one joint type), in SI."""
    return built_scene(shear_box(law, None), "<test>").params[0]


def _envelope(p: np.ndarray, sigma: np.ndarray = STRESSES) -> dict[str, np.ndarray]:
    """What the engine evaluates from a row at the stresses `sigma` [Pa]: tau_p, the tangent's phi, c."""
    args = (p[L.P_JRC], p[L.P_JCS], p[L.P_PHI_B], p[L.P_PHI_MAX])
    return {
        "tau_p": laws.peak_shear_strength(sigma, *args),
        "phi": laws.equivalent_friction_angle(sigma, *args, p[L.P_K_TANGENT]),
        "c": laws.equivalent_cohesion(sigma, *args, p[L.P_K_TANGENT]),
    }


def test_without_the_new_keys_the_row_is_as_given():
    p = _row(_law())
    assert (p[L.P_JRC], p[L.P_JCS], p[L.P_PHI_B]) == (10.0, 100e6, 30.0 * DEG)
    same = _row(_law(lab_length_m=0.3))  # a lab length alone: no field length, no scale effect
    assert p.tobytes() == same.tobytes()


@pytest.mark.filterwarnings("ignore::bbmc.plausibility.ImplausibleValue")  # wide ranges on purpose
@settings(max_examples=60, deadline=None)
@given(
    jrc=st.floats(0.0, 20.0),
    jcs=st.floats(1.0, 300.0),
    lab=st.floats(0.01, 1.0),
    ratio=st.floats(1.0, 1e4),
    exact=st.booleans(),
)
def test_lab_and_field_lengths_give_the_strength_of_the_hand_scaled_joint(jrc, jcs, lab, ratio, exact):
    """JRC_n = JRC_0 (L_n/L_0)^(-0.02 JRC_0), JCS_n = JCS_0 (L_n/L_0)^(-0.03 JRC_0), worked by hand
    and given as the law's jrc and jcs_MPa, give the envelope and its tangent that the lab values with
    lab_length_m and field_length_m give (field joints longer than the lab's: JRC_n stays <= 20)."""
    field = lab * ratio
    k = "exact" if exact else 0.016
    scaled = _row(_law(jrc=jrc, jcs_MPa=jcs, lab_length_m=lab, field_length_m=field, tangent_coefficient=k))
    jrc_n = jrc * (field / lab) ** (-0.02 * jrc)
    jcs_n = jcs * (field / lab) ** (-0.03 * jrc)
    by_hand = _row(_law(jrc=jrc_n, jcs_MPa=jcs_n, tangent_coefficient=k))
    for name, value in _envelope(scaled).items():
        np.testing.assert_allclose(value, _envelope(by_hand)[name], rtol=1e-12, atol=0, err_msg=name)


@pytest.mark.parametrize(("residual", "phi_r"), [({"phi_r_deg": 25.0}, 25.0), ({"rebound_ratio": 0.7}, 24.0)])
def test_phi_r_is_the_friction_term_of_the_envelope(residual, phi_r):
    """Barton & Choubey (1977): tau = sigma_n tan(JRC lg(JCS/sigma_n) + phi_r), phi_r given or
    (phi_b - 20 deg) + 20 deg r/R (30 - 20 x 0.3 = 24 deg): the law with phi_r is the law with phi_b
    set to phi_r, and matches the formula worked by hand below the cap and JCS."""
    p = _row(_law(**residual))
    np.testing.assert_allclose(p, _row(_law(phi_b_deg=phi_r)), rtol=1e-15, atol=0)
    sigma = np.array([0.1e6, 1e6, 10e6])
    by_hand = sigma * np.tan(np.radians(10.0 * np.log10(100e6 / sigma) + phi_r))
    np.testing.assert_allclose(_envelope(p, sigma)["tau_p"], by_hand, rtol=1e-12)


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("field_length_m", -1.0, "greater than 0"),
        ("lab_length_m", 0.0, "greater than 0"),
        ("rebound_ratio", 1.2, "less than or equal to 1"),
        ("phi_r_deg", 35.0, "exceeds phi_b_deg"),
    ],
)
def test_bad_values_are_refused_in_one_line(tmp_path, key, value, message):
    """A field length below zero, a rebound r above R (r/R > 1), phi_r above phi_b: one line naming the
    file and the key, exit status 2, nothing written."""
    scene = {**shear_box(_law(**{key: value}), None), "solver": {"steps": 10}}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "results"
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(out)])
    refused(outcome, out, str(path), f"key 'joint_laws.joint.strength.{key}'", message)


def test_phi_r_and_rebound_ratio_are_not_both_given(tmp_path):
    scene = {**shear_box(_law(phi_r_deg=25.0, rebound_ratio=0.7), None), "solver": {"steps": 10}}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "results"
    outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(out)])
    refused(outcome, out, "'joint_laws.joint.strength.rebound_ratio'", "at most one", "both are given")
