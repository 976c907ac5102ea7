"""The mobilized Barton-Bandis joint law on the engine (`law: barton_bandis_mobilized`): a shear box at
constant normal load against the law's tau-delta and dilation-delta curves, a reversal, a constant
normal stiffness test against the integrated closed form, and closure under normal load against Bandis's
hyperbola. Each tolerance is stated where it is used; the measured errors are in the README."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from bbmc import laws
from bbmc.bench.mobilized_cost import shear_box
from bbmc.dem import layout as L
from bbmc.dem.model import build_model
from bbmc.dem.scene import Scene
from bbmc.dem.solver import advance, prepare, simulate

DEG = math.pi / 180.0
JRC, JCS, PHI_B, PHI_R, LENGTH = 10.0, 100e6, 30.0 * DEG, 25.0 * DEG, 0.1
SIGMA_N = 1e6
SPEED = 0.02  # m/s
PEAK = float(laws.peak_shear_displacement(LENGTH, JRC))
LAW = {
    "law": "barton_bandis_mobilized",
    "jrc0": JRC,
    "jcs0_MPa": JCS / 1e6,
    "phi_b_deg": 30.0,
    "phi_r_deg": 25.0,
    "lab_length_m": LENGTH,
    "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 100},
    "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 100},
}


def _box(law: dict, steps: int, velocity: dict | None, sigma_n: float = SIGMA_N, ramp: int = 2000) -> dict:
    """The bench's shear box (`bbmc.bench.mobilized_cost.shear_box`) run for `steps` steps."""
    scene = shear_box(law, velocity, sigma_n, ramp)
    return {**scene, "solver": {**scene["solver"], "steps": steps}}


def _model(scene: dict):
    return build_model(Scene.model_validate(scene, strict=False), Path("<test>"))


def _strength(delta, sigma_n=SIGMA_N):
    return laws.mobilized_shear_strength(delta, sigma_n, JRC, JCS, PHI_R, PEAK, 70 * DEG)


def _dilation_angle(delta, sigma_n=SIGMA_N):
    damage = laws.damage_coefficient(sigma_n, JRC, JCS)
    return laws.mobilized_dilation_angle(delta, sigma_n, JRC, JCS, PHI_R, PEAK, damage)


@pytest.fixture(scope="module")
def constant_load():
    """Sheared to 8 delta_peak at 0.02 m/s under 1 MPa held constant."""
    scene = _box(LAW, 10**7, {"x_m_s": SPEED, "start_step": 2000})
    scene["solver"]["stop"] = {"displacement_m": 8.2 * PEAK}
    return simulate(_model(scene)).history


def test_constant_normal_load_follows_the_laws_tau_delta_curve(constant_load):
    """tau against the sub-contacts' own shear path, from 0.05 delta_peak to 8 delta_peak (peak and
    softening), within 1 % of the peak strength of the law's tau_mob(delta) at the applied sigma_n."""
    h = constant_load
    path = h["path_mm"].to_numpy() * 1e-3
    keep = path > 0.05 * PEAK
    tau = np.abs(h["tau_MPa"].to_numpy()[keep]) * 1e6
    expected = _strength(path[keep])
    assert path.max() > 7.5 * PEAK
    assert np.max(np.abs(tau - expected)) <= 0.01 * float(_strength(PEAK))


def test_constant_normal_load_dilates_as_the_law_integrates(constant_load):
    """The upper block rises by the integral of tan(d_mob) d delta (the law's curve, integrated by
    quadrature here) to within 1 % of the final dilation, at every record."""
    h = constant_load
    path = h["path_mm"].to_numpy() * 1e-3
    rise = h["uy_mm"].to_numpy() * 1e-3 - h["uy_mm"].iloc[np.argmax(path > 0)] * 1e-3
    expected = np.array([quad(lambda d: math.tan(_dilation_angle(d)), 0.0, p, limit=200)[0] for p in path])
    assert expected[-1] > 0
    assert np.max(np.abs(rise - expected)) <= 0.01 * expected[-1]


def test_reversal_does_not_heal_the_damage():
    """Sheared to 2 delta_peak, then back: the path keeps growing, and the shear stress in the reverse
    direction never exceeds the strength reached before the reversal (no new peak: the damage does
    not heal; UDEC's reduced secondary peak)."""
    ramp = 2000
    model = _model(_box(LAW, 10**7, {"x_m_s": SPEED, "start_step": ramp}))
    state = prepare(model)
    steps_per_peak = int(PEAK / SPEED / state.clock[L.DT])
    advance(model, state, ramp + 2 * steps_per_peak)
    rows = slice(0, state.n_sub)
    before = float(np.max(np.abs(state.subs[rows, L.TAU])))
    sign_before = np.sign(np.mean(state.subs[rows, L.TAU]))
    path_before = float(state.subs[rows, L.PATH].max())
    state.blocks[1, L.VPX] = -SPEED
    taus = []
    for _ in range(20):
        advance(model, state, steps_per_peak // 10)
        taus.append(float(np.max(np.abs(state.subs[rows, L.TAU]))))
    assert state.subs[rows, L.PATH].max() > path_before + 1.5 * PEAK
    assert max(taus) <= before * (1 + 1e-9)
    assert np.sign(np.mean(state.subs[rows, L.TAU])) == -sign_before  # the shear stress has turned round


def test_constant_normal_stiffness_follows_the_integrated_closed_form():
    """The upper block held at its height once 1 MPa acts: dilation raises sigma_n by K_n per unit of
    dilation, d sigma_n / d delta = K_n tan(d_mob(delta, sigma_n)) (integrated here by solve_ivp);
    sigma_n within 1 % at 3 delta_peak."""
    ramp = 2000
    kn = 100e9
    model = _model(_box(LAW, 10**7, {"x_m_s": SPEED, "start_step": ramp + 1000}))
    state = prepare(model)
    shear_steps = int(3 * PEAK / SPEED / state.clock[L.DT])
    advance(model, state, ramp + 1000)
    state.dof[1, 1] = L.PRESCRIBED
    state.blocks[1, [L.VY, L.VPY]] = 0.0
    sigma0 = float(np.mean(state.subs[: state.n_sub, L.SN]))
    advance(model, state, shear_steps)
    path = float(np.mean(state.subs[: state.n_sub, L.PATH]))
    solution = solve_ivp(
        lambda d, s: [kn * math.tan(_dilation_angle(d, s[0]))], (0.0, path), [sigma0], rtol=1e-9, atol=1.0
    )
    expected = solution.y[0, -1]
    assert expected > 1.05 * sigma0
    assert float(np.mean(state.subs[: state.n_sub, L.SN])) == pytest.approx(expected, rel=0.01)


def test_closure_under_normal_load_follows_bandis_hyperbola():
    """A Bandis joint (JRC 10, JCS 100 MPa, sigma_c 150 MPa) loaded to 5 MPa over 20,000 steps, x
    held: the closure at each record within 1 % of dV = sigma V_m / (K_ni V_m + sigma)."""
    law = {**LAW, "normal_stiffness": {"law": "bandis", "sigma_c_MPa": 150.0}}
    scene = _box(law, 24_000, {"x_m_s": 0.0}, sigma_n=5e6, ramp=20_000)
    scene["solver"]["time_step"] = {"step_s": 1e-3}
    h = simulate(_model(scene)).history
    aperture = laws.initial_aperture(JRC, JCS, 150e6)
    kni = laws.bandis_initial_normal_stiffness(JRC, JCS, aperture)
    vm = laws.bandis_maximum_closure(JRC, JCS, aperture)
    sigma = h["sn_MPa"].to_numpy() * 1e6
    closure = -h["uy_mm"].to_numpy() * 1e-3
    loaded = sigma > 0.2e6
    expected = laws.bandis_closure(sigma[loaded], kni, vm)
    np.testing.assert_allclose(closure[loaded], expected, rtol=0.01)
