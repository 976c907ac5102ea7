"""Tests of the joint laws (paper eqs 1-18) in SI units.

Expected numbers are computed here, independently, with plain `math` from the formulas as the paper
writes them (never copied from the paper's tables). Three groups:

* closed forms and derivatives at chosen points;
* the documented rules at the extremes (open joint, the phi_max cap, sigma_n >= JCS, past the peak);
* hypothesis properties over the physical parameter range, and agreement of the three ways a law is
  called (njit scalar, numpy ufunc, njit called from inside another njit kernel).
"""

import math

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc import laws, units
from bbmc.laws import stiffness, strength

MPa = units.MPa
kPa = units.kPa
deg = units.deg

# The paper's limestone joint (text under eq 14): phi_b = 32 deg, JCS = 3.31 MPa, JRC = 2.13.
JRC_P = 2.13
JCS_P = 3.31 * MPa
PHI_B_P = 32.0 * deg
PHI_MAX = 70.0 * deg
K_P = 0.016  # eq 15's rounded tangent coefficient

# A rough joint whose total angle reaches the 70 deg cap at a normal stress inside the test range.
JRC_R = 15.0
JCS_R = 100.0 * MPa
PHI_B_R = 30.0 * deg
K_R = math.pi * JRC_R / (180.0 * math.log(10.0))
# phi_b + JRC lg(JCS/sigma) = phi_max  <=>  sigma = JCS 10^(-(70 - 30)/15)  (about 215 kPa)
SIGMA_CAP_R = JCS_R * 10.0 ** (-(70.0 - 30.0) / JRC_R)

# The paper's eq 16 correction.
A_P = 0.312
B_P = 0.7188

PROPERTY = settings(max_examples=200, deadline=None)


def tau_p_by_hand(sigma: float, jrc: float, jcs: float, phi_b: float) -> float:
    """Eq 9 written out, uncapped: sigma tan(phi_b + JRC lg(JCS/sigma)), JRC lg(.) in degrees."""
    return sigma * math.tan(phi_b + math.radians(jrc * math.log10(jcs / sigma)))


def central_difference(f, x: float, h: float) -> float:
    return (f(x + h) - f(x - h)) / (2.0 * h)


# ---------------------------------------------------------------------------------------------------
# Closed forms
# ---------------------------------------------------------------------------------------------------


def test_eq9_peak_strength_at_a_point():
    # sigma_n = 1 MPa on the paper's joint: lg(3.31/1) = 0.519828, 2.13 * 0.519828 = 1.107234 deg,
    # total angle 33.107234 deg, tan = 0.652072, so tau_p = 0.652072 MPa (computed by hand).
    sigma = 1.0 * MPa
    tau = strength.peak_shear_strength(sigma, JRC_P, JCS_P, PHI_B_P, PHI_MAX)
    assert tau == pytest.approx(tau_p_by_hand(sigma, JRC_P, JCS_P, PHI_B_P), rel=1e-14)
    assert tau == pytest.approx(0.652072 * MPa, rel=1e-5)
    total = strength.peak_friction_angle(sigma, JRC_P, JCS_P, PHI_B_P, PHI_MAX)
    assert math.degrees(total) == pytest.approx(33.107234, rel=1e-7)
    roughness = strength.roughness_angle(sigma, JRC_P, JCS_P)
    assert math.degrees(roughness) == pytest.approx(2.13 * math.log10(3.31), rel=1e-14)


@pytest.mark.parametrize(
    ("sigma", "jrc", "jcs", "phi_b"),
    [
        # the paper's joint: uncapped everywhere below JCS
        (10.0 * kPa, JRC_P, JCS_P, PHI_B_P),
        (0.1 * MPa, JRC_P, JCS_P, PHI_B_P),
        (0.5 * MPa, JRC_P, JCS_P, PHI_B_P),
        (1.0 * MPa, JRC_P, JCS_P, PHI_B_P),
        (3.0 * MPa, JRC_P, JCS_P, PHI_B_P),
        # the rough joint, above its cap stress (~215 kPa) and below JCS
        (0.5 * MPa, JRC_R, JCS_R, PHI_B_R),
        (1.0 * MPa, JRC_R, JCS_R, PHI_B_R),
        (10.0 * MPa, JRC_R, JCS_R, PHI_B_R),
        (60.0 * MPa, JRC_R, JCS_R, PHI_B_R),
    ],
)
def test_eq13_slope_is_the_derivative_of_eq9(sigma, jrc, jcs, phi_b):
    # Eq 13 with the exact k must be d tau_p / d sigma_n: compare with a central difference.
    k = strength.exact_tangent_coefficient(jrc)
    slope = strength.envelope_slope(sigma, jrc, jcs, phi_b, PHI_MAX, k)
    fd = central_difference(
        lambda s: strength.peak_shear_strength(s, jrc, jcs, phi_b, PHI_MAX), sigma, 1e-5 * sigma
    )
    assert slope == pytest.approx(fd, rel=1e-6)
    # and eq 11: the equivalent angle is the arctan of that slope
    phi = strength.equivalent_friction_angle(sigma, jrc, jcs, phi_b, PHI_MAX, k)
    assert phi == pytest.approx(math.atan(fd), rel=1e-6)


@pytest.mark.parametrize(
    ("sigma", "jrc", "jcs", "phi_b"),
    [
        (0.05 * MPa, JRC_P, JCS_P, PHI_B_P),
        (0.2 * MPa, JRC_P, JCS_P, PHI_B_P),
        (1.0 * MPa, JRC_P, JCS_P, PHI_B_P),
        (0.3 * MPa, JRC_R, JCS_R, PHI_B_R),
        (5.0 * MPa, JRC_R, JCS_R, PHI_B_R),
        (40.0 * MPa, JRC_R, JCS_R, PHI_B_R),
    ],
)
def test_equivalent_mohr_coulomb_line_is_the_tangent(sigma, jrc, jcs, phi_b):
    k = strength.exact_tangent_coefficient(jrc)
    tau_p = strength.peak_shear_strength(sigma, jrc, jcs, phi_b, PHI_MAX)
    phi = strength.equivalent_friction_angle(sigma, jrc, jcs, phi_b, PHI_MAX, k)
    c = strength.equivalent_cohesion(sigma, jrc, jcs, phi_b, PHI_MAX, k)
    assert c > 0.0

    def line(s: float) -> float:
        return c + s * math.tan(phi)

    # Eq 10 / 12: the line touches the envelope at sigma_n.
    assert line(sigma) == pytest.approx(tau_p, rel=1e-12)
    # Below JCS the envelope is concave (its second derivative is sec^2 theta theta' (1 - 2k tan theta)
    # with theta' < 0 and 2k tan theta < 1 for JRC <= 20, theta <= 70 deg; the cap kink is concave
    # too), so the tangent lies on or above it at neighbouring stresses that stay below JCS.
    for factor in (0.1, 0.5, 0.9, 0.99, 0.999, 1.001, 1.01, 1.1, 2.0):
        s = sigma * factor
        assert s < jcs
        envelope = strength.peak_shear_strength(s, jrc, jcs, phi_b, PHI_MAX)
        assert line(s) >= envelope * (1.0 - 1e-12)


@pytest.mark.parametrize("sigma_mpa", [0.01, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 3.0])
def test_eq15_with_rounded_k_is_the_papers_formula(sigma_mpa):
    # Eq 15 written out literally, in the paper's units (MPa, degrees):
    #   f = tan(32 deg + 2.13 lg(3.31/sigma)), phi = arctan(f - 0.016 (f^2 + 1)), c = 0.016 sigma (f^2+1)
    f = math.tan(math.radians(32.0 + 2.13 * math.log10(3.31 / sigma_mpa)))
    phi_paper = math.atan(f - 0.016 * (f**2 + 1.0))
    c_paper_mpa = 0.016 * sigma_mpa * (f**2 + 1.0)

    sigma = sigma_mpa * MPa
    phi = strength.equivalent_friction_angle(sigma, JRC_P, JCS_P, PHI_B_P, PHI_MAX, K_P)
    c = strength.equivalent_cohesion(sigma, JRC_P, JCS_P, PHI_B_P, PHI_MAX, K_P)
    assert phi == pytest.approx(phi_paper, rel=1e-12)
    assert c / MPa == pytest.approx(c_paper_mpa, rel=1e-12)
    # eq 14's second line, c = sigma f - sigma tan(phi), holds with the same f
    assert c / MPa == pytest.approx(sigma_mpa * f - sigma_mpa * math.tan(phi_paper), rel=1e-9)


def test_exact_tangent_coefficient():
    # d/dsigma of JRC lg(JCS/sigma) degrees is -pi JRC / (180 ln10 sigma) radians.
    expected = math.pi * 2.13 / (180.0 * math.log(10.0))
    assert strength.exact_tangent_coefficient(2.13) == expected
    # eq 15's 0.016 is this number rounded (0.016145...)
    assert expected == pytest.approx(0.016, abs=5e-4)
    assert strength.exact_tangent_coefficient(0.0) == 0.0


# Table 1, 50 kPa row, as round SI inputs for the hyperbola (any positive values would do).
K_SI = 0.5 * units.GPa_per_m
TAU_ULT = 0.073 * MPa


def hyperbola_tau(d: float, k_si: float, tau_ult: float) -> float:
    """Eq 1 solved for tau: 1/tau = m/d + n  =>  tau = d/(m + n d), m = 1/K_si, n = 1/tau_ult."""
    return d / (1.0 / k_si + d / tau_ult)


@pytest.mark.parametrize("fraction", [0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99])
def test_eq2_is_the_derivative_of_the_hyperbola(fraction):
    tau = fraction * TAU_ULT
    m, n = 1.0 / K_SI, 1.0 / TAU_ULT
    d = stiffness.hyperbolic_shear_displacement(tau, m, n)
    # d tau / d d at the displacement where the hyperbola carries tau
    fd = central_difference(lambda x: hyperbola_tau(x, K_SI, TAU_ULT), d, 1e-5 * d)
    assert stiffness.hyperbolic_shear_stiffness(tau, K_SI, TAU_ULT) == pytest.approx(fd, rel=1e-6)
    # the analytic derivative m/(m + n d)^2 as well
    exact = m / (m + n * d) ** 2
    assert stiffness.hyperbolic_shear_stiffness(tau, K_SI, TAU_ULT) == pytest.approx(exact, rel=1e-12)


@pytest.mark.parametrize("fraction", [1e-6, 0.01, 0.25, 0.5, 0.75, 0.999])
def test_hyperbolic_displacement_inverts_eq1(fraction):
    m, n = 1.0 / K_SI, 1.0 / TAU_ULT
    tau = fraction * TAU_ULT
    d = stiffness.hyperbolic_shear_displacement(tau, m, n)
    assert d > 0.0
    assert 1.0 / tau == pytest.approx(m / d + n, rel=1e-12)
    assert hyperbola_tau(d, K_SI, TAU_ULT) == pytest.approx(tau, rel=1e-12)


def test_hyperbolic_displacement_edges():
    m, n = 1.0 / K_SI, 1.0 / TAU_ULT
    assert stiffness.hyperbolic_shear_displacement(0.0, m, n) == 0.0
    assert stiffness.hyperbolic_shear_displacement(-1.0 * kPa, m, n) == 0.0
    # the asymptote tau_ult = 1/n is never reached
    assert stiffness.hyperbolic_shear_displacement(TAU_ULT, m, n) == math.inf
    assert stiffness.hyperbolic_shear_displacement(2.0 * TAU_ULT, m, n) == math.inf


@pytest.mark.parametrize("sigma", [10.0 * kPa, 0.1 * MPa, 1.0 * MPa, 20.0 * MPa])
def test_normal_stiffness_is_the_derivative_of_eq5(sigma):
    # eq 5: lg sigma = p + q dV  =>  sigma(dV) = 10^(p + q dV); eq 7's slope, 7.715 per mm, in SI.
    q = 7.715 / units.mm
    p = 0.0
    dv = (math.log10(sigma) - p) / q  # the closure at which the joint carries sigma

    def sigma_of(x: float) -> float:
        return 10.0 ** (p + q * x)

    kn = stiffness.normal_stiffness(sigma, q, math.log10(math.e))
    h = 1e-6 / q
    assert kn == pytest.approx(central_difference(sigma_of, dv, h), rel=1e-6)
    # analytically d/dV 10^(p + q V) = ln(10) q sigma
    assert kn == pytest.approx(math.log(10.0) * q * sigma, rel=1e-12)
    # eq 6 with the printed 0.3434 divides by that number instead
    assert stiffness.normal_stiffness(sigma, q, 0.3434) == pytest.approx(q * sigma / 0.3434, rel=1e-15)


@pytest.mark.parametrize("fraction", [0.0, 0.1, 0.4, 0.7, 0.95, 0.999])
def test_eq3_bandis_stiffness(fraction):
    tau_p, tau_ult = 0.07 * MPa, 0.073 * MPa
    tau = fraction * math.sqrt(tau_p * tau_ult)  # the law's range: bracket in [0, 1]
    expected = K_SI * (1.0 - tau**2 / (tau_p * tau_ult)) ** 2
    got = stiffness.bandis_shear_stiffness(tau, K_SI, tau_p, tau_ult)
    assert got == pytest.approx(expected, rel=1e-12, abs=1e-12 * K_SI)


def test_eq16_at_the_peak_and_eq17_reduction_factor():
    tau_p, tau_ult = 0.11 * MPa, 0.113 * MPa
    # at tau = tau_p, ln(1) = 0 so f = b, and eq 16 is K_si (1 - b tau_p/tau_ult)^2
    expected_d = (1.0 - B_P * tau_p / tau_ult) ** 2
    got = stiffness.corrected_shear_stiffness(tau_p, K_SI, tau_p, tau_ult, A_P, B_P)
    assert got == pytest.approx(K_SI * expected_d, rel=1e-14)
    d = stiffness.peak_reduction_factor(tau_p, tau_ult, B_P)
    assert d == pytest.approx(expected_d, rel=1e-14)
    assert got == pytest.approx(d * K_SI, rel=1e-14)
    # the correction function itself at tau = tau_p and at tau = tau_p / e
    assert stiffness.correction_function(tau_p, tau_p, A_P, B_P) == B_P
    assert stiffness.correction_function(tau_p / math.e, tau_p, A_P, B_P) == pytest.approx(
        B_P - A_P, rel=1e-14
    )


@pytest.mark.parametrize("sigma", [50.0 * kPa, 0.2 * MPa, 1.0 * MPa])
def test_eq17_simplified_stiffness(sigma):
    k_j, n_j, sigma_ref = 2.0547 * units.GPa_per_m, 0.4881, 1.0 * MPa
    d = 0.35
    k_si = stiffness.initial_shear_stiffness(sigma, k_j, n_j, sigma_ref)
    # K_si = K_j (sigma/sigma_ref)^n_j
    assert k_si == pytest.approx(k_j * (sigma / sigma_ref) ** n_j, rel=1e-14)
    got = stiffness.simplified_shear_stiffness(sigma, k_j, n_j, sigma_ref, d)
    assert got == d * k_si


def test_linear_relation():
    assert stiffness.linear_relation(2.0, 0.5, 0.25) == 1.25


# ---------------------------------------------------------------------------------------------------
# Extremes
# ---------------------------------------------------------------------------------------------------


def _strength_outputs(sigma, jrc, jcs, phi_b, k):
    return {
        "total": strength.peak_friction_angle(sigma, jrc, jcs, phi_b, PHI_MAX),
        "tau_p": strength.peak_shear_strength(sigma, jrc, jcs, phi_b, PHI_MAX),
        "slope": strength.envelope_slope(sigma, jrc, jcs, phi_b, PHI_MAX, k),
        "phi": strength.equivalent_friction_angle(sigma, jrc, jcs, phi_b, PHI_MAX, k),
        "c": strength.equivalent_cohesion(sigma, jrc, jcs, phi_b, PHI_MAX, k),
    }


@pytest.mark.parametrize("sigma", [1.0, 1e-300])
def test_low_stress_limit_rough_joint_is_capped(sigma):
    # 30 + 15 lg(1e8/1) = 150 deg > 70: capped; the envelope is tau = sigma tan(phi_max), c = 0
    out = _strength_outputs(sigma, JRC_R, JCS_R, PHI_B_R, K_R)
    assert all(math.isfinite(v) for v in out.values())
    assert out["total"] == PHI_MAX
    assert out["phi"] == pytest.approx(PHI_MAX, rel=1e-15)
    assert out["tau_p"] == sigma * math.tan(PHI_MAX)
    assert out["c"] == 0.0


@pytest.mark.parametrize("sigma", [1.0, 1e-300])
def test_low_stress_limit_papers_joint(sigma):
    # at 1 Pa the paper's joint is not capped (32 + 2.13 lg(3.31e6) = 45.9 deg), at 1e-300 it is;
    # either way everything is finite, the angle is <= phi_max and c <= k sigma (tan^2 phi_max + 1) -> 0
    out = _strength_outputs(sigma, JRC_P, JCS_P, PHI_B_P, K_P)
    assert all(math.isfinite(v) for v in out.values())
    assert out["total"] <= PHI_MAX
    assert 0.0 < out["phi"] <= PHI_MAX
    assert 0.0 <= out["c"] <= K_P * sigma * (math.tan(PHI_MAX) ** 2 + 1.0)
    if sigma == 1e-300:
        assert out["total"] == PHI_MAX
        assert out["c"] == 0.0


@pytest.mark.parametrize(("sigma", "jcs"), [(1e-300, 300.0 * MPa), (5e-324, 1.0 * MPa)])
def test_low_stress_limit_smooth_joint_no_nan(sigma, jcs):
    # A smooth joint (JRC = 0) has no roughness at any stress: the documented rule is 'never a NaN'
    out = _strength_outputs(sigma, 0.0, jcs, PHI_B_P, 0.0)
    assert all(math.isfinite(v) for v in out.values())
    assert out["total"] == PHI_B_P


@pytest.mark.parametrize("sigma", [0.0, -0.0, -1.0, -1e6])
def test_open_joint(sigma):
    for jrc, jcs, phi_b, k in [(JRC_P, JCS_P, PHI_B_P, K_P), (JRC_R, JCS_R, PHI_B_R, K_R)]:
        out = _strength_outputs(sigma, jrc, jcs, phi_b, k)
        assert out["tau_p"] == 0.0
        assert out["c"] == 0.0
        assert out["total"] == PHI_MAX
        assert out["phi"] == pytest.approx(PHI_MAX, rel=1e-15)
    assert stiffness.initial_shear_stiffness(sigma, 2.0e9, 0.4881, 1.0 * MPa) == 0.0
    assert stiffness.simplified_shear_stiffness(sigma, 2.0e9, 0.4881, 1.0 * MPa, 0.5) == 0.0
    assert stiffness.normal_stiffness(sigma, 7715.0, math.log10(math.e)) == 0.0


@pytest.mark.parametrize("factor", [1.0, 1.0 + 1e-12, 1.5, 10.0, 1e6])
def test_at_and_above_jcs(factor):
    for jrc, jcs, phi_b, k in [(JRC_P, JCS_P, PHI_B_P, K_P), (JRC_R, JCS_R, PHI_B_R, K_R)]:
        sigma = factor * jcs
        out = _strength_outputs(sigma, jrc, jcs, phi_b, k)
        assert strength.roughness_angle(sigma, jrc, jcs) == 0.0
        assert out["total"] == phi_b
        assert out["phi"] == pytest.approx(phi_b, rel=1e-15)
        assert out["slope"] == math.tan(phi_b)
        assert out["c"] == 0.0
        assert out["tau_p"] == sigma * math.tan(phi_b)


def test_peak_strength_continuous_across_cap():
    below = strength.peak_shear_strength(SIGMA_CAP_R * (1 - 1e-9), JRC_R, JCS_R, PHI_B_R, PHI_MAX)
    above = strength.peak_shear_strength(SIGMA_CAP_R * (1 + 1e-9), JRC_R, JCS_R, PHI_B_R, PHI_MAX)
    at = SIGMA_CAP_R * math.tan(PHI_MAX)
    assert below == pytest.approx(at, rel=1e-8)
    assert above == pytest.approx(at, rel=1e-8)
    # the cap really switches there
    assert strength.peak_friction_angle(SIGMA_CAP_R * 0.99, JRC_R, JCS_R, PHI_B_R, PHI_MAX) == pytest.approx(
        PHI_MAX, rel=1e-15
    )
    assert strength.peak_friction_angle(SIGMA_CAP_R * 1.01, JRC_R, JCS_R, PHI_B_R, PHI_MAX) < PHI_MAX
    # The cohesion jumps there, by design: the envelope has a kink at the cap, so the tangent is not
    # unique. On the capped side the line is tau = sigma tan(phi_max) (c = 0); just above, the tangent
    # of the uncapped branch has c = k sigma (tan^2 phi_max + 1).
    c_below = strength.equivalent_cohesion(SIGMA_CAP_R * (1 - 1e-9), JRC_R, JCS_R, PHI_B_R, PHI_MAX, K_R)
    c_above = strength.equivalent_cohesion(SIGMA_CAP_R * (1 + 1e-9), JRC_R, JCS_R, PHI_B_R, PHI_MAX, K_R)
    assert c_below == 0.0
    assert c_above == pytest.approx(K_R * SIGMA_CAP_R * (math.tan(PHI_MAX) ** 2 + 1.0), rel=1e-7)


@pytest.mark.parametrize(("jrc", "jcs", "phi_b"), [(JRC_P, JCS_P, PHI_B_P), (JRC_R, JCS_R, PHI_B_R)])
def test_peak_strength_continuous_across_jcs(jrc, jcs, phi_b):
    at = jcs * math.tan(phi_b)
    for factor in (1 - 1e-9, 1.0, 1 + 1e-9):
        tau = strength.peak_shear_strength(jcs * factor, jrc, jcs, phi_b, PHI_MAX)
        assert tau == pytest.approx(at, rel=1e-8)


def _stiffness_grid(k_si, tau_p, tau_ult, a, b, tau):
    return {
        "eq2": laws.hyperbolic_shear_stiffness(tau, k_si, tau_ult),
        "eq3": laws.bandis_shear_stiffness(tau, k_si, tau_p, tau_ult),
        "eq16": laws.corrected_shear_stiffness(tau, k_si, tau_p, tau_ult, a, b),
    }


@pytest.mark.parametrize(
    ("tau_p", "tau_ult", "a", "b"),
    [
        (0.07 * MPa, 0.073 * MPa, A_P, B_P),
        (0.13 * MPa, 0.146 * MPa, A_P, B_P),
        (1.0 * MPa, 3.0 * MPa, 0.0, 0.2),
        (1.0 * MPa, 1.0001 * MPa, 1.0, 1.0),
    ],
)
def test_stiffness_past_peak_and_ultimate(tau_p, tau_ult, a, b):
    # a dense grid from 0 through tau_p and tau_ult up to 10 tau_ult
    tau = np.linspace(0.0, 10.0 * tau_ult, 20001)
    tau = np.sort(np.concatenate([tau, [tau_p, tau_ult, math.sqrt(tau_p * tau_ult)]]))
    for name, k in _stiffness_grid(K_SI, tau_p, tau_ult, a, b, tau).items():
        assert np.all(np.isfinite(k)), name
        assert np.all(k >= 0.0), name
        assert np.all(k <= K_SI), name
        assert np.all(np.diff(k) <= 0.0), name
        past = tau >= tau_p
        assert np.all(k[past] <= k[tau == tau_p][0]), name
    ks = _stiffness_grid(K_SI, tau_p, tau_ult, a, b, tau)
    # eq 2 is zero from tau_ult on, eq 3 from sqrt(tau_p tau_ult) on
    assert np.all(ks["eq2"][tau >= tau_ult] == 0.0)
    # (at tau = sqrt(tau_p tau_ult) itself the rounded bracket is ~1e-16, its square ~1e-32)
    assert np.all(ks["eq3"][tau > math.sqrt(tau_p * tau_ult) * (1 + 1e-12)] == 0.0)
    assert ks["eq3"][tau == math.sqrt(tau_p * tau_ult)][0] <= 1e-30 * K_SI
    # eq 16 at 10 tau_ult: f R_f >= (a ln(10 tau_ult/tau_p) + b) * 10 > 1 for these a, b
    assert ks["eq16"][-1] == 0.0


def test_eq16_at_zero_stress():
    tau_p, tau_ult = 0.11 * MPa, 0.113 * MPa
    assert stiffness.corrected_shear_stiffness(0.0, K_SI, tau_p, tau_ult, A_P, B_P) == K_SI
    assert stiffness.corrected_shear_stiffness(-1.0, K_SI, tau_p, tau_ult, A_P, B_P) == K_SI
    for tiny in (1e-300, 1e-310):
        k = stiffness.corrected_shear_stiffness(tiny, K_SI, tau_p, tau_ult, A_P, B_P)
        assert math.isfinite(k)
        assert 0.0 <= k <= K_SI
    # below 0.1 tau_p the paper's f is negative; the bracket clamp keeps K_st at K_si
    assert stiffness.correction_function(0.05 * tau_p, tau_p, A_P, B_P) < 0.0
    assert stiffness.corrected_shear_stiffness(0.05 * tau_p, K_SI, tau_p, tau_ult, A_P, B_P) == K_SI


def test_eq16_at_smallest_positive_stress():
    # 5e-324 / 1.1e5 rounds to 0: ln -> -inf, R_f -> 0, f R_f = -inf * 0 = NaN; the limit is K_si
    tau_p, tau_ult = 0.11 * MPa, 0.113 * MPa
    k = stiffness.corrected_shear_stiffness(5e-324, K_SI, tau_p, tau_ult, A_P, B_P)
    assert k == K_SI


# ---------------------------------------------------------------------------------------------------
# Hypothesis properties
# ---------------------------------------------------------------------------------------------------

sigmas = st.floats(0.0, 8.0).map(lambda x: 10.0**x)  # 1 Pa .. 100 MPa, log-uniform
jrcs = st.floats(0.0, 20.0)
jcss = st.floats(1.0, 300.0).map(lambda x: x * MPa)
phi_bs = st.floats(10.0, 45.0).map(lambda x: x * deg)


@PROPERTY
@given(sigma=sigmas, jrc=jrcs, jcs=jcss, phi_b=phi_bs)
def test_property_strength_outputs(sigma, jrc, jcs, phi_b):
    k = strength.exact_tangent_coefficient(jrc)
    out = _strength_outputs(sigma, jrc, jcs, phi_b, k)
    out["roughness"] = strength.roughness_angle(sigma, jrc, jcs)
    assert all(math.isfinite(v) for v in out.values()), out
    assert out["roughness"] >= 0.0
    assert phi_b <= out["total"] <= PHI_MAX
    # the tangent is never steeper than the secant from the origin, and never flat
    assert 0.0 < out["phi"] < math.pi / 2
    assert out["phi"] <= out["total"] * (1 + 1e-15)
    assert out["c"] >= 0.0
    assert out["tau_p"] > 0.0
    # eq 12: the tangent line passes through (sigma, tau_p)
    assert out["c"] + sigma * math.tan(out["phi"]) == pytest.approx(out["tau_p"], rel=1e-12)


@PROPERTY
@given(s1=sigmas, s2=sigmas, jrc=jrcs, jcs=jcss, phi_b=phi_bs)
def test_property_peak_strength_non_decreasing(s1, s2, jrc, jcs, phi_b):
    lo, hi = min(s1, s2), max(s1, s2)
    tau_lo = strength.peak_shear_strength(lo, jrc, jcs, phi_b, PHI_MAX)
    tau_hi = strength.peak_shear_strength(hi, jrc, jcs, phi_b, PHI_MAX)
    # Mathematically tau_p is strictly increasing (eq 13's slope is >= tan(10 deg) - k(20) (tan^2 10
    # deg + 1) ~ 0.02 > 0). Evaluated in floating point, stresses one ulp apart can come out ~1e-15 out
    # of order (tan, log10 rounding), so allow that; stresses resolvably apart must be strictly ordered.
    assert tau_lo <= tau_hi * (1.0 + 1e-14)
    if hi > lo * (1.0 + 1e-9):
        assert tau_lo < tau_hi


k_sis = st.floats(6.0, 12.0).map(lambda x: 10.0**x)  # 1 MPa/m .. 1000 GPa/m
tau_ps = st.floats(3.0, 7.0).map(lambda x: 10.0**x)  # 1 kPa .. 10 MPa
ult_ratios = st.floats(1.0001, 3.0)
unit = st.floats(0.0, 1.0)


@PROPERTY
@given(k_si=k_sis, tau_p=tau_ps, ratio=ult_ratios, a=unit, b=unit, u1=unit, u2=unit)
def test_property_stiffness_laws(k_si, tau_p, ratio, a, b, u1, u2):
    tau_ult = tau_p * ratio
    t_lo, t_hi = sorted((u1 * 10.0 * tau_ult, u2 * 10.0 * tau_ult))

    def all_laws(t):
        return (
            stiffness.hyperbolic_shear_stiffness(t, k_si, tau_ult),
            stiffness.bandis_shear_stiffness(t, k_si, tau_p, tau_ult),
            stiffness.corrected_shear_stiffness(t, k_si, tau_p, tau_ult, a, b),
        )

    for k_lo, k_hi in zip(all_laws(t_lo), all_laws(t_hi), strict=True):
        for k in (k_lo, k_hi):
            assert math.isfinite(k)
            assert 0.0 <= k <= k_si
        assert k_hi <= k_lo
    d = stiffness.peak_reduction_factor(tau_p, tau_ult, b)
    assert 0.0 <= d <= 1.0
    assert 0.0 <= stiffness.simplified_shear_stiffness(1.0 * MPa, k_si, 0.5, 1.0 * MPa, d) <= k_si


# ---------------------------------------------------------------------------------------------------
# njit scalar == numpy ufunc == njit called from a kernel
# ---------------------------------------------------------------------------------------------------

_SIG = np.concatenate(
    [
        [-1e6, -0.0, 0.0, 1e-300, 1.0],
        np.geomspace(1.0 * kPa, 400.0 * MPa, 60),
        [JCS_P, JCS_R, SIGMA_CAP_R],
    ]
)
_N = _SIG.size
_RNG = np.random.default_rng(20240601)
_JRC = _RNG.uniform(0.0, 20.0, _N)
_JCS = _RNG.uniform(1.0, 300.0, _N) * MPa
_PHI_B = _RNG.uniform(10.0, 45.0, _N) * deg
_PHI_MAX = np.full(_N, PHI_MAX)
_K = _JRC * math.pi / (180.0 * math.log(10.0))
_TAU_P = _RNG.uniform(1.0 * kPa, 10.0 * MPa, _N)
_TAU_ULT = _TAU_P * _RNG.uniform(1.0001, 3.0, _N)
_TAU = np.concatenate([[-1.0, 0.0, 1e-300], _RNG.uniform(0.0, 1.0, _N - 3)]) * 10 * _TAU_ULT
_K_SI = 10.0 ** _RNG.uniform(6.0, 12.0, _N)
_A = _RNG.uniform(0.0, 1.0, _N)
_B = _RNG.uniform(0.0, 1.0, _N)
_N_J = _RNG.uniform(0.0, 1.0, _N)
_REF = np.full(_N, 1.0 * MPa)
_Q = _RNG.uniform(1.0, 1e4, _N)
_LOG10_E = np.full(_N, math.log10(math.e))
_L0 = np.full(_N, 0.1)
_LN = 10.0 ** _RNG.uniform(-2.0, 2.0, _N)
_REBOUND = _RNG.uniform(-0.5, 1.5, _N)

LAW_ARGS = {
    "roughness_angle": (strength, (np.abs(_SIG) + 1.0, _JRC, _JCS)),
    "peak_friction_angle": (strength, (_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX)),
    "peak_shear_strength": (strength, (_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX)),
    "exact_tangent_coefficient": (strength, (_JRC,)),
    "envelope_slope": (strength, (_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX, _K)),
    "equivalent_friction_angle": (strength, (_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX, _K)),
    "equivalent_cohesion": (strength, (_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX, _K)),
    "scaled_jrc": (strength, (_JRC, _L0, _LN)),
    "scaled_jcs": (strength, (_JCS, _JRC, _L0, _LN)),
    "residual_friction_angle": (strength, (_PHI_B, _REBOUND)),
    "linear_relation": (stiffness, (_SIG, _A, _B)),
    "initial_shear_stiffness": (stiffness, (_SIG, _K_SI, _N_J, _REF)),
    "hyperbolic_shear_stiffness": (stiffness, (_TAU, _K_SI, _TAU_ULT)),
    "bandis_shear_stiffness": (stiffness, (_TAU, _K_SI, _TAU_P, _TAU_ULT)),
    "correction_function": (stiffness, (np.abs(_TAU) + 1.0, _TAU_P, _A, _B)),
    "corrected_shear_stiffness": (stiffness, (_TAU, _K_SI, _TAU_P, _TAU_ULT, _A, _B)),
    "peak_reduction_factor": (stiffness, (_TAU_P, _TAU_ULT, _B)),
    "simplified_shear_stiffness": (stiffness, (_SIG, _K_SI, _N_J, _REF, _B)),
    "hyperbolic_shear_displacement": (stiffness, (_TAU, 1.0 / _K_SI, 1.0 / _TAU_ULT)),
    "normal_stiffness": (stiffness, (_SIG, _Q, _LOG10_E)),
}


# the peak laws; the displacement-dependent ones (bbmc.laws.mobilized) are covered by tests/test_mobilized.py
PEAK_LAWS = {name for name in laws.__all__ if hasattr(strength, name) or hasattr(stiffness, name)}


def test_every_public_law_is_covered():
    assert set(LAW_ARGS) == PEAK_LAWS


# sigma_n = 1e-300 makes JCS/sigma_n overflow to inf on purpose (the law handles it); numpy reports the
# floating-point overflow flag the ufunc loop raises there.
_OVERFLOW_OK = pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")


@_OVERFLOW_OK
@pytest.mark.parametrize("name", sorted(LAW_ARGS))
def test_ufunc_equals_njit_scalar(name):
    module, args = LAW_ARGS[name]
    scalar = getattr(module, name)
    ufunc = getattr(laws, name)
    vectorised = ufunc(*args)
    looped = np.array([scalar(*(float(x[i]) for x in args)) for i in range(_N)])
    assert vectorised.dtype == np.float64
    np.testing.assert_array_equal(vectorised, looped)


@numba.njit
def _strength_kernel(sig, jrc, jcs, phi_b, phi_max, k):
    out = np.empty((sig.size, 7))
    for i in range(sig.size):
        s = sig[i]
        out[i, 0] = strength.roughness_angle(abs(s) + 1.0, jrc[i], jcs[i])
        out[i, 1] = strength.peak_friction_angle(s, jrc[i], jcs[i], phi_b[i], phi_max[i])
        out[i, 2] = strength.peak_shear_strength(s, jrc[i], jcs[i], phi_b[i], phi_max[i])
        out[i, 3] = strength.exact_tangent_coefficient(jrc[i])
        out[i, 4] = strength.envelope_slope(s, jrc[i], jcs[i], phi_b[i], phi_max[i], k[i])
        out[i, 5] = strength.equivalent_friction_angle(s, jrc[i], jcs[i], phi_b[i], phi_max[i], k[i])
        out[i, 6] = strength.equivalent_cohesion(s, jrc[i], jcs[i], phi_b[i], phi_max[i], k[i])
    return out


@numba.njit
def _stiffness_kernel(sig, tau, k_si, tau_p, tau_ult, a, b, n_j, ref, q, log10_e):
    out = np.empty((sig.size, 10))
    for i in range(sig.size):
        t = tau[i]
        out[i, 0] = stiffness.linear_relation(sig[i], a[i], b[i])
        out[i, 1] = stiffness.initial_shear_stiffness(sig[i], k_si[i], n_j[i], ref[i])
        out[i, 2] = stiffness.hyperbolic_shear_stiffness(t, k_si[i], tau_ult[i])
        out[i, 3] = stiffness.bandis_shear_stiffness(t, k_si[i], tau_p[i], tau_ult[i])
        out[i, 4] = stiffness.correction_function(abs(t) + 1.0, tau_p[i], a[i], b[i])
        out[i, 5] = stiffness.corrected_shear_stiffness(t, k_si[i], tau_p[i], tau_ult[i], a[i], b[i])
        out[i, 6] = stiffness.peak_reduction_factor(tau_p[i], tau_ult[i], b[i])
        out[i, 7] = stiffness.simplified_shear_stiffness(sig[i], k_si[i], n_j[i], ref[i], b[i])
        out[i, 8] = stiffness.hyperbolic_shear_displacement(t, 1.0 / k_si[i], 1.0 / tau_ult[i])
        out[i, 9] = stiffness.normal_stiffness(sig[i], q[i], log10_e[i])
    return out


@numba.njit
def _field_scale_kernel(jrc, jcs, lab, field, phi_b, rebound):
    out = np.empty((jrc.size, 3))
    for i in range(jrc.size):
        out[i, 0] = strength.scaled_jrc(jrc[i], lab[i], field[i])
        out[i, 1] = strength.scaled_jcs(jcs[i], jrc[i], lab[i], field[i])
        out[i, 2] = strength.residual_friction_angle(phi_b[i], rebound[i])
    return out


_FIELD_SCALE_ORDER = ["scaled_jrc", "scaled_jcs", "residual_friction_angle"]
_STRENGTH_ORDER = [
    "roughness_angle",
    "peak_friction_angle",
    "peak_shear_strength",
    "exact_tangent_coefficient",
    "envelope_slope",
    "equivalent_friction_angle",
    "equivalent_cohesion",
]
_STIFFNESS_ORDER = [
    "linear_relation",
    "initial_shear_stiffness",
    "hyperbolic_shear_stiffness",
    "bandis_shear_stiffness",
    "correction_function",
    "corrected_shear_stiffness",
    "peak_reduction_factor",
    "simplified_shear_stiffness",
    "hyperbolic_shear_displacement",
    "normal_stiffness",
]


@_OVERFLOW_OK
def test_njit_law_called_from_a_kernel_matches_the_ufunc():
    inside = _strength_kernel(_SIG, _JRC, _JCS, _PHI_B, _PHI_MAX, _K)
    for column, name in enumerate(_STRENGTH_ORDER):
        _, args = LAW_ARGS[name]
        np.testing.assert_array_equal(inside[:, column], getattr(laws, name)(*args), err_msg=name)
    inside = _stiffness_kernel(_SIG, _TAU, _K_SI, _TAU_P, _TAU_ULT, _A, _B, _N_J, _REF, _Q, _LOG10_E)
    for column, name in enumerate(_STIFFNESS_ORDER):
        _, args = LAW_ARGS[name]
        np.testing.assert_array_equal(inside[:, column], getattr(laws, name)(*args), err_msg=name)
    inside = _field_scale_kernel(_JRC, _JCS, _L0, _LN, _PHI_B, _REBOUND)
    for column, name in enumerate(_FIELD_SCALE_ORDER):
        _, args = LAW_ARGS[name]
        np.testing.assert_array_equal(inside[:, column], getattr(laws, name)(*args), err_msg=name)
    assert set(_STRENGTH_ORDER) | set(_STIFFNESS_ORDER) | set(_FIELD_SCALE_ORDER) == PEAK_LAWS
