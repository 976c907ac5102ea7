"""The block engine against closed forms, before any paper figure depends on it.

Each test states its tolerance. Scenes are built in `dem_scenes` and run into a temporary folder.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from bbmc import laws, units
from bbmc.joint.model import SIGMA_REF
from dem_scenes import (
    SLIDER,
    G,
    block_on_base,
    constant_joint,
    edited,
    embedded_gap,
    ramped_weight,
    run_scene,
    slider_mass,
)

MPA_PER_MM = units.MPa_per_mm


def _sliding_distance(history):
    return np.hypot(history["ux_mm"], history["uy_mm"]).to_numpy() * units.mm


def _closed_form_distance(time, angle_deg, friction_deg, cohesion_pa=0.0):
    """s = 1/2 a t^2, a = g (sin b - cos b tan phi) - c L / m (block from rest on an incline)."""
    b, phi = math.radians(angle_deg), math.radians(friction_deg)
    a = G * (math.sin(b) - math.cos(b) * math.tan(phi)) - cohesion_pa * SLIDER[0] / slider_mass()
    return 0.5 * a * time**2


@pytest.mark.parametrize(("angle", "friction"), [(30.0, 20.0), (45.0, 30.0), (20.0, 0.0)])
def test_block_slides_from_rest_as_the_closed_form(tmp_path, angle, friction):
    """Undamped sliding: s(t) = 1/2 g (sin b - cos b tan phi) t^2 within 1 % from t = 0.25 s on.

    Before the joint's shear stress reaches its strength the block accelerates at g sin b for about a
    quarter period of its shear vibration; the velocity this adds is what the closed form (a rigid
    joint) leaves out, and its share of s falls as 1/t.

    The block starts pressed into the joint by its static closure, so it does not bounce.
    The block does not tip: friction at its base excites an undamped rocking of the contact springs,
    which stays below 0.1 degree over the 1.4 m slide."""
    scene = block_on_base(
        angle, constant_joint(friction), steps=6000, every=500, gap_m=embedded_gap(angle, 10.0)
    )
    result = run_scene(tmp_path, scene)
    h = result.history
    later = h["time_s"] > 0.25
    expected = _closed_form_distance(h["time_s"][later].to_numpy(), angle, friction)
    np.testing.assert_allclose(_sliding_distance(h)[later], expected, rtol=0.01)
    assert abs(h["rot_deg"]).max() < 0.1


def test_block_sliding_past_a_collinear_joint_end_slides_as_the_closed_form(tmp_path):
    """The base is two fixed blocks meeting at a joint normal to the slope, in line with the slider's
    up-slope edge: as the slider slides down past the joint's end, its edge and the lower base block's
    overlap in projection by as much as it has slid. That is no contact (the blocks touch only on the
    slope). Before the separating-axis check of the contact search, the next search made it one, as
    deep as the slide, and threw the slider back up the slope (68 % off the closed form).

    Still short of the 1 % of the single-base test: the two edges touch end to end at step 0, so they
    are a contact until the next search drops it; over that half-margin of slide it holds the slider
    back, which ends 3.5 % behind the closed form. The slide must never reverse."""
    angle, friction = 30.0, 20.0
    scene = block_on_base(
        angle, constant_joint(friction), steps=6000, every=250, gap_m=embedded_gap(angle, 10.0)
    )
    base = scene["blocks"][0]
    scene["blocks"][0:1] = [
        edited(base, name="base_lower", group="base", **{"rectangle_m.width_m": 4.0}),
        edited(base, name="base_upper", group="base", **{"rectangle_m.x_m": 0.0, "rectangle_m.width_m": 2.0}),
    ]
    h = run_scene(tmp_path, scene).history
    later = h["time_s"] > 0.25
    expected = _closed_form_distance(h["time_s"][later].to_numpy(), angle, friction)
    np.testing.assert_allclose(_sliding_distance(h)[later], expected, rtol=0.04)
    assert np.all(np.diff(_sliding_distance(h)) > 0)
    assert _sliding_distance(h)[-1] > 0.4  # far past the joint's end, after many contact searches


def test_block_at_rest_moves_only_elastically_when_friction_exceeds_the_dip(tmp_path):
    """phi > b, the weight ramped up over 3000 steps and damped: shear displacement = tau / K_s and
    closure = sigma_n / K_n (1 %). The block's rotation is held, so the joint stresses are uniform and
    the closed form holds at every sub-contact (free, the block's weight and base friction tilt the
    normal stress and the uphill end, nearly unloaded, slips locally)."""
    angle, k = 30.0, 10.0
    scene = block_on_base(
        angle, constant_joint(40.0, k_MPa_per_mm=k), steps=6000, damping=0.8, slider_fix=("rotation",)
    )
    result = run_scene(tmp_path, ramped_weight(scene, angle, 3000))
    last = result.history.iloc[-1]
    weight = slider_mass() * G
    tau = weight * math.sin(math.radians(angle)) / SLIDER[0]
    sigma = weight * math.cos(math.radians(angle)) / SLIDER[0]
    assert last["us_mm"] * units.mm == pytest.approx(tau / (k * MPA_PER_MM), rel=0.01)
    assert last["un_mm"] * units.mm == pytest.approx(sigma / (k * MPA_PER_MM), rel=0.01)
    assert last["sn_MPa"] * units.MPa == pytest.approx(sigma, rel=0.01)
    assert abs(last["tau_MPa"] * units.MPa) == pytest.approx(tau, rel=0.01)


def test_cohesion_holds_a_block_the_friction_alone_cannot(tmp_path):
    """phi < b but c L > W (sin b - cos b tan phi), the weight ramped up: the block stays (it moves
    less than 1.01 times its elastic displacement tau / K_s; rotation held, as above)."""
    angle, friction = 30.0, 20.0
    weight = slider_mass() * G
    b, phi = math.radians(angle), math.radians(friction)
    needed = weight * (math.sin(b) - math.cos(b) * math.tan(phi)) / SLIDER[0]
    joint = constant_joint(friction, cohesion_MPa=2 * needed / units.MPa)
    scene = block_on_base(angle, joint, steps=6000, damping=0.8, slider_fix=("rotation",))
    h = run_scene(tmp_path, ramped_weight(scene, angle, 3000)).history
    elastic = weight * math.sin(b) / SLIDER[0] / (10.0 * MPA_PER_MM)
    assert abs(h["us_mm"].iloc[-1]) * units.mm < 1.01 * elastic


@pytest.mark.parametrize(("after_slip", "keeps_cohesion"), [("keep", True), ("zero", False)])
def test_sliding_with_cohesion_follows_the_after_slip_rule(tmp_path, after_slip, keeps_cohesion):
    """c L < W (sin b - cos b tan phi): with `keep` the block slides at a = g(...) - c L / m, with
    `zero` (Itasca) the cohesion is gone after the first slip and a = g(...) (1 %). Rotation held: the
    closed form assumes the whole base in contact, while a free block tilts and opens its uphill end,
    which then carries no cohesion."""
    angle, friction = 30.0, 20.0
    weight = slider_mass() * G
    b, phi = math.radians(angle), math.radians(friction)
    cohesion = 0.5 * weight * (math.sin(b) - math.cos(b) * math.tan(phi)) / SLIDER[0]
    joint = constant_joint(friction, cohesion_MPa=cohesion / units.MPa, after_slip=after_slip)
    scene = block_on_base(
        angle, joint, steps=6000, every=500, gap_m=embedded_gap(angle, 10.0), slider_fix=("rotation",)
    )
    h = run_scene(tmp_path, scene).history
    later = h["time_s"] > 0.25
    expected = _closed_form_distance(
        h["time_s"][later].to_numpy(), angle, friction, cohesion if keeps_cohesion else 0.0
    )
    np.testing.assert_allclose(_sliding_distance(h)[later], expected, rtol=0.01)


def test_the_default_joint_keeps_its_cohesion_after_slip(tmp_path):
    """A joint written without `after_slip` is ductile (limit equilibrium's rule): the block slides at
    a = g(sin b - cos b tan phi) - c L / m, as with `keep` (1 %)."""
    angle, friction = 30.0, 20.0
    weight = slider_mass() * G
    b, phi = math.radians(angle), math.radians(friction)
    cohesion = 0.5 * weight * (math.sin(b) - math.cos(b) * math.tan(phi)) / SLIDER[0]
    joint = constant_joint(friction, cohesion_MPa=cohesion / units.MPa)
    scene = block_on_base(
        angle, joint, steps=6000, every=500, gap_m=embedded_gap(angle, 10.0), slider_fix=("rotation",)
    )
    h = run_scene(tmp_path, scene).history
    later = h["time_s"] > 0.25
    expected = _closed_form_distance(h["time_s"][later].to_numpy(), angle, friction, cohesion)
    np.testing.assert_allclose(_sliding_distance(h)[later], expected, rtol=0.01)


@pytest.mark.parametrize("after_slip", ["keep", "zero"])
def test_a_joint_that_has_slipped_carries_no_tension(tmp_path, after_slip):
    """A bonded joint (T = 0.1 MPa, c = 0.05 MPa) pulled at 0.02 MPa holds the block (sigma_n =
    -0.02 MPa to 0.1 %); sheared past c + sigma_n tan phi it slips, loses its tensile strength under
    either rule (limit equilibrium counts no tension) and opens: the block leaves the base."""
    joint = constant_joint(30.0, cohesion_MPa=0.05, tensile_strength_MPa=0.1, after_slip=after_slip)
    scene = block_on_base(0.0, joint, steps=6000, every=100, gravity=(0.0, 0.0), slider_fix=("rotation",))
    scene["loads"] = {
        "edge_stresses": [
            {"block": "slider", "edge": "up", "sigma_n_MPa": -0.02, "ramp_steps": 500},
            {"block": "slider", "edge": "up", "tau_MPa": 0.06, "ramp_steps": 1000, "start_step": 2000},
        ]
    }
    scene["solver"]["damping"] = 0.8
    h = run_scene(tmp_path, scene).history.set_index("step")
    assert h.loc[1900, "sn_MPa"] == pytest.approx(-0.02, rel=1e-3)
    assert h.loc[1900, "uy_mm"] < 0.01
    assert h["uy_mm"].iloc[-1] > 1.0
    opened = h.loc[h["uy_mm"] > 1.0]
    assert (opened["sn_MPa"].fillna(0.0) == 0.0).all()


def _loaded_block(sigma_MPa: float, tau_MPa: float, joint: dict, steps: int, ramp: int = 0) -> dict:
    scene = block_on_base(0.0, joint, steps=steps, damping=0.8, gravity=(0.0, 0.0), slider_fix=("rotation",))
    scene["loads"] = {
        "edge_stresses": [
            {"block": "slider", "edge": "up", "sigma_n_MPa": sigma_MPa},
            {"block": "slider", "edge": "up", "tau_MPa": tau_MPa, "ramp_steps": ramp},
        ]
    }
    return scene


def test_normal_closure_equals_sigma_over_kn(tmp_path):
    """Closure of a loaded joint = sigma_n / K_n (0.1 %); the joint's sigma_n equals the load."""
    k = 25.0
    h = run_scene(tmp_path, _loaded_block(1.0, 0.0, constant_joint(30.0, k_MPa_per_mm=k), 3000)).history
    last = h.iloc[-1]
    assert last["un_mm"] == pytest.approx(1.0 / k, rel=1e-3)
    assert last["sn_MPa"] == pytest.approx(1.0, rel=1e-3)
    assert -last["uy_mm"] == pytest.approx(1.0 / k, rel=1e-3)


def test_elastic_shear_displacement_equals_tau_over_ks(tmp_path):
    """Below the strength, shear displacement = tau / K_s (0.1 %)."""
    k = 10.0
    h = run_scene(tmp_path, _loaded_block(1.0, 0.3, constant_joint(30.0, k_MPa_per_mm=k), 4000)).history
    last = h.iloc[-1]
    assert abs(last["us_mm"]) == pytest.approx(0.3 / k, rel=1e-3)
    assert abs(last["tau_MPa"]) == pytest.approx(0.3, rel=1e-3)


def test_energy_is_conserved_without_damping(tmp_path):
    """A block released 1.3 times its static closure into a 10-degree incline (friction high enough
    that no sub-contact slips, and none opens) vibrates in shear, closure and rocking for 20,000
    steps without damping: kinetic + potential + strain energy stays within 1 % of the largest kinetic
    energy, with no trend (first and last tenth of the run agree within 0.2 %).

    The time step is 0.1 of the critical one: the leapfrog's full-step energy oscillates by
    O((omega dt)^2) (25 % of the kinetic swing at the default 0.5), though it does not drift."""
    scene = block_on_base(
        10.0, constant_joint(85.0), steps=20_000, every=20, gap_m=embedded_gap(10.0, 10.0, 1.3)
    )
    scene["solver"]["time_step"] = {"safety_factor": 0.1}
    result = run_scene(tmp_path, scene)
    h = result.history
    assert not result.contacts["slipped"].any()
    assert h["rot_deg"].abs().max() > 0
    total = (h["ke_J"] + h["pe_J"] + h["se_J"]).to_numpy()
    swing = h["ke_J"].max()
    assert swing > 0
    assert np.max(np.abs(total - total[0])) < 0.01 * swing
    tenth = len(total) // 10
    assert abs(total[-tenth:].mean() - total[:tenth].mean()) < 0.002 * swing


def _bandis_joint(update_every: int) -> dict:
    """Eq 4 with the paper's printed coefficients (data/paper/equation_constants.csv), constant K_n."""
    return {
        "law": "barton_bandis",
        "strength": {"jrc": 2.13, "jcs_MPa": 3.31, "phi_b_deg": 32.0},
        "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 20.0},
        "shear_stiffness": {
            "law": "bandis",
            "kj_MPa_per_mm": 2.0547,
            "nj": 0.4881,
            "peak_strength": {"slope": 0.417, "intercept_MPa": 0.0458},
            "ultimate_strength": {"slope": 1.0812, "intercept_MPa": 0.0014},
        },
    }


@pytest.mark.parametrize("law", ["bandis", "corrected"])
def test_stress_dependent_joint_follows_the_tangent_stiffness_integral(tmp_path, law):
    """Slow shear loading at sigma_n = 0.2 MPa to 80 % of tau_p, the law updated every step:
    d_h = integral_0^tau d tau / K_st(tau) within 1 %."""
    sigma, steps = 0.2 * units.MPa, 30_000
    joint = _bandis_joint(1)
    joint["shear_stiffness"]["law"] = law
    if law == "corrected":
        joint["shear_stiffness"].update(a=0.312, b=0.7188)
    tau_p = (0.417 * sigma / units.MPa + 0.0458) * units.MPa
    tau_ult = (1.0812 * tau_p / units.MPa + 0.0014) * units.MPa
    target = 0.8 * tau_p
    scene = _loaded_block(sigma / units.MPa, target / units.MPa, joint, steps + 5000, ramp=steps)
    scene = edited(scene, **{"solver.update_interval_steps": 1})
    h = run_scene(tmp_path, scene).history
    k_si = float(laws.initial_shear_stiffness(sigma, 2.0547 * MPA_PER_MM, 0.4881, SIGMA_REF))
    if law == "bandis":
        stiffness = lambda t: float(laws.bandis_shear_stiffness(t, k_si, tau_p, tau_ult))  # noqa: E731
    else:
        stiffness = lambda t: float(laws.corrected_shear_stiffness(t, k_si, tau_p, tau_ult, 0.312, 0.7188))  # noqa: E731
    expected, _ = quad(lambda t: 1.0 / stiffness(t), 0.0, target)
    assert abs(h["us_mm"].iloc[-1]) * units.mm == pytest.approx(expected, rel=0.01)
