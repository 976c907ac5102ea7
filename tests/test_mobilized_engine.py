"""The mobilized Barton-Bandis joint law on the engine (`law: barton_bandis_mobilized`): a shear box at
constant normal load against the law's tau-delta and dilation-delta curves, a reversal, a constant
normal stiffness test against the integrated closed form, and closure under normal load against Bandis's
hyperbola. Each tolerance is stated where it is used; the measured errors are in docs/verification.md."""

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
from bbmc.dem.solver import advance, prepare, simulate
from bbmc.scene.schema import Scene

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
    """tau against the imposed shear displacement (the upper block's ux), from 0.05 delta_peak to 8
    delta_peak (peak and softening), within 1 % of the peak strength of the law's tau_mob(delta) at the
    applied sigma_n; the sub-contacts' own path is that displacement (to 0.001 delta_peak; measured:
    0.5 micrometres apart)."""
    h = constant_load
    delta = np.abs(h["ux_mm"].to_numpy()) * 1e-3
    keep = delta > 0.05 * PEAK
    tau = np.abs(h["tau_MPa"].to_numpy()[keep]) * 1e6
    expected = _strength(delta[keep])
    assert delta.max() > 7.5 * PEAK
    assert np.max(np.abs(tau - expected)) <= 0.01 * float(_strength(PEAK))
    np.testing.assert_allclose(h["path_mm"].to_numpy()[keep] * 1e-3, delta[keep], rtol=0, atol=1e-3 * PEAK)


def test_constant_normal_load_dilates_as_the_law_integrates(constant_load):
    """The upper block rises by the integral of tan(d_mob) d delta over the imposed displacement (the
    law's curve, integrated by quadrature here) to within 1 % of the final dilation, at every record."""
    h = constant_load
    delta = np.abs(h["ux_mm"].to_numpy()) * 1e-3
    start = int(np.argmax(delta > 0))
    rise = (h["uy_mm"].to_numpy() - h["uy_mm"].iloc[start]) * 1e-3
    expected = np.array([quad(lambda d: math.tan(_dilation_angle(d)), 0.0, x, limit=200)[0] for x in delta])
    assert expected[-1] > 0
    assert np.max(np.abs(rise - expected)) <= 0.01 * expected[-1]


def _reversed(at_peaks: float, back_peaks: float):
    """Sheared to `at_peaks` delta_peak, then back by `back_peaks`: (tau, dilation, path) of the first
    sub-contact just before the reversal, and their histories on the way back, every 0.1 delta_peak."""
    ramp = 2000
    model = _model(_box(LAW, 10**7, {"x_m_s": SPEED, "start_step": ramp}))
    state = prepare(model)
    steps_per_peak = int(PEAK / SPEED / state.clock[L.DT])
    advance(model, state, ramp + int(at_peaks * steps_per_peak))
    before = state.subs[0, [L.TAU, L.DILATION, L.PATH]].copy()
    state.blocks[1, L.VPX] = -SPEED
    back = []
    for _ in range(int(10 * back_peaks)):
        advance(model, state, steps_per_peak // 10)
        back.append(state.subs[0, [L.TAU, L.DILATION, L.PATH]].copy())
    return before, np.array(back)


def test_reversal_after_the_peak_finds_no_new_peak_and_closes_the_dilation():
    """Sheared to 2 delta_peak, then back 2 delta_peak: the path keeps growing (damage does not heal),
    the shear stress turns round and never exceeds the strength reached before the reversal (no new
    peak: UDEC's reduced secondary peak), and the dilation falls back as the joint returns (to within
    one recording step of 0 at the start)."""
    before, back = _reversed(2.0, 2.0)
    assert back[-1, 2] > before[2] + 1.9 * PEAK
    assert np.max(np.abs(back[:, 0])) <= abs(before[0]) * (1 + 1e-9)
    assert np.sign(back[-1, 0]) == -np.sign(before[0])
    assert np.all(np.diff(back[:, 1]) <= 1e-12)
    assert back[-1, 1] < 0.1 * before[1]


def test_reversal_before_the_peak_goes_on_along_the_path():
    """Reversed at 0.5 delta_peak: the path goes on growing, so the strength keeps rising along the law's
    curve to its peak (the documented rule: the path, not the position, mobilizes the roughness) within 1 %
    of the peak at each record after the stress has turned round."""
    before, back = _reversed(0.5, 1.0)
    turned = np.sign(back[:, 0]) == -np.sign(before[0])
    expected = _strength(back[turned, 2])
    assert np.max(np.abs(np.abs(back[turned, 0]) - expected)) <= 0.01 * float(_strength(PEAK))
    assert np.max(np.abs(back[:, 0])) > abs(before[0])


def test_constant_normal_stiffness_follows_the_integrated_closed_form():
    """Constant normal stiffness with an infinitely stiff surround: the upper block held at its height
    once 1 MPa acts, so the system's normal stiffness is the joint's own K_n and dilation raises sigma_n
    by it, d sigma_n / d delta = K_n tan(d_mob(delta, sigma_n)) (integrated here by solve_ivp);
    sigma_n within 1 % at 3 delta_peak. (A finite surround k would give k K_n / (k + K_n); the engine has
    no spring element.)"""
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


@pytest.mark.parametrize(
    "change, fragment",
    [
        ({"phi_r_deg": 35.0}, "exceeds phi_b_deg"),
        ({"normal_stiffness": {"law": "bandis", "sigma_c_MPa": 50.0}}, "below jcs0_MPa"),
        ({"phi_b_deg": 15.0, "phi_r_deg": None, "rebound_ratio": 0.1}, "phi_r"),
        ({"phi_max_deg": 25.0}, "exceed phi_b_deg"),
        ({"damage": 0.0}, "M > 0"),
    ],
)
def test_meaningless_mobilized_parameters_are_refused(change, fragment):
    """phi_r above phi_b, a rock weaker than its joint wall, an r/R that gives phi_r <= 0, a cap phi_max
    below phi_b or a damage M <= 0: the checks `bbmc joint` makes too (`bbmc.joint.inputs`)."""
    law = {k: v for k, v in {**LAW, **change}.items() if v is not None}
    with pytest.raises(ValueError, match=fragment):
        Scene.model_validate(_box(law, 10, None), strict=False)
