"""Tests of the displacement-dependent Barton-Bandis laws (`bbmc.laws.mobilized`) in SI units.

Expected numbers are computed here, independently, by hand or with plain `math` from the published
formulas (never by calling the code under test). Tolerances: rel 1e-12 where the test repeats the same
floating-point formula in another order (a few ulps of rounding), 1e-6 against numbers worked by hand
to 7 digits, 1e-6 against central finite differences (truncation ~h^2, h = 1e-6 relative). Groups:

* closed forms at chosen points and the table of Barton (1982);
* the documented edge rules;
* hypothesis properties over wide ranges; njit scalar == numpy ufunc == njit inside a kernel; broadcasting.
"""

import math

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc import laws, units
from bbmc.laws import mobilized, strength

MPa = units.MPa
mm = units.mm
deg = units.deg
PHI_MAX = 70.0 * deg

# A rough lab joint: JRC_0 = 10 on L_0 = 0.1 m, JCS_0 = 100 MPa, phi_r = 25 deg.
JRC = 10.0
JCS = 100.0 * MPa
PHI_R = 25.0 * deg
LENGTH = 0.1
SIGMA = 1.0 * MPa  # lg(JCS/sigma) = 2, so i = 20 deg

PROPERTY = settings(max_examples=200, deadline=None)

# Barton (1982): delta/delta_peak -> JRC_mob/JRC_peak (the point at 0 depends on phi_r and i).
TABLE = [(0.3, 0.0), (0.6, 0.75), (1.0, 1.0), (2.0, 0.85), (4.0, 0.70), (10.0, 0.50), (100.0, 0.0)]


def central_difference(f, x: float, h: float) -> float:
    return (f(x + h) - f(x - h)) / (2.0 * h)


# ---------------------------------------------------------------------------------------------------
# Closed forms
# ---------------------------------------------------------------------------------------------------


def test_scale_corrections():
    # 0.1 m -> 1 m is one decade: JRC_n = 10 * 10^(-0.2) = 6.309573, JCS_n = 100 * 10^(-0.3) = 50.11872
    assert strength.scaled_jrc(JRC, 0.1, 1.0) == pytest.approx(6.309573, rel=1e-6)
    assert strength.scaled_jcs(JCS, JRC, 0.1, 1.0) == pytest.approx(50.11872 * MPa, rel=1e-6)
    # the same size, or no roughness: nothing changes
    assert strength.scaled_jrc(JRC, 0.1, 0.1) == JRC
    assert strength.scaled_jcs(JCS, 0.0, 0.1, 10.0) == JCS
    # a smaller field block is rougher (the law runs both ways)
    assert strength.scaled_jrc(JRC, 1.0, 0.1) == pytest.approx(10.0 * 10.0**0.2, rel=1e-12)


def test_residual_friction_angle():
    # (30 - 20) + 20 * 0.7 = 24 deg
    assert strength.residual_friction_angle(30.0 * deg, 0.7) == pytest.approx(24.0 * deg, rel=1e-12)
    assert strength.residual_friction_angle(30.0 * deg, 1.0) == pytest.approx(30.0 * deg, rel=1e-12)
    assert strength.residual_friction_angle(30.0 * deg, 0.0) == pytest.approx(10.0 * deg, rel=1e-12)


def test_peak_shear_displacement():
    # (0.1/500) (10/0.1)^0.33 = 2e-4 * 10^0.66 = 2e-4 * 4.570882 = 0.9141764 mm
    assert mobilized.peak_shear_displacement(0.1, 10.0) == pytest.approx(0.9141764 * mm, rel=1e-6)
    # 1 m, JRC 10: (1/500) 10^0.33 = 2e-3 * 2.137962 = 4.275924 mm
    assert mobilized.peak_shear_displacement(1.0, 10.0) == pytest.approx(4.275924 * mm, rel=1e-6)


@pytest.mark.parametrize(("x", "expected"), TABLE)
def test_roughness_ratio_table_points(x, expected):
    i = 20.0 * deg
    # the table points exactly (abs 1e-15: the interpolation evaluates to them up to one rounding)
    assert mobilized.mobilized_roughness_ratio(x, PHI_R, i) == pytest.approx(expected, abs=1e-15)
    assert mobilized.mobilized_roughness_ratio(-x, PHI_R, i) == pytest.approx(expected, abs=1e-15)


def test_roughness_ratio_start_and_interpolation():
    i = 20.0 * deg
    # at 0: -phi_r/i = -25/20
    assert mobilized.mobilized_roughness_ratio(0.0, PHI_R, i) == pytest.approx(-1.25, rel=1e-15)
    # linear in x on [0, 1]: halfway between table points
    assert mobilized.mobilized_roughness_ratio(0.15, PHI_R, i) == pytest.approx(-0.625, rel=1e-12)
    assert mobilized.mobilized_roughness_ratio(0.45, PHI_R, i) == pytest.approx(0.375, rel=1e-12)
    assert mobilized.mobilized_roughness_ratio(0.8, PHI_R, i) == pytest.approx(0.875, rel=1e-12)
    # linear in lg x on [1, 100]: at the geometric means of neighbouring points
    for lo, hi, y_lo, y_hi in [(1, 2, 1.0, 0.85), (2, 4, 0.85, 0.7), (4, 10, 0.7, 0.5), (10, 100, 0.5, 0)]:
        x = math.sqrt(lo * hi)
        assert mobilized.mobilized_roughness_ratio(x, PHI_R, i) == pytest.approx(
            0.5 * (y_lo + y_hi), rel=1e-12
        )
    # and not linear in x there: at the arithmetic mean of 10 and 100 the lg rule gives
    # 0.5 (1 - lg(5.5)) = 0.1297, not 0.25
    assert mobilized.mobilized_roughness_ratio(55.0, PHI_R, i) == pytest.approx(
        0.5 * (2.0 - math.log10(55.0)), rel=1e-12
    )
    # beyond 100: 0
    assert mobilized.mobilized_roughness_ratio(150.0, PHI_R, i) == 0.0
    assert mobilized.mobilized_roughness_ratio(math.inf, PHI_R, i) == 0.0


def test_roughness_ratio_is_continuous_at_the_nodes():
    # each node approached from both sides by 1e-9 relative: the jump must be of that order (slopes <= 2.5)
    i = 20.0 * deg
    for x, _ in TABLE:
        below = mobilized.mobilized_roughness_ratio(x * (1 - 1e-9), PHI_R, i)
        above = mobilized.mobilized_roughness_ratio(x * (1 + 1e-9), PHI_R, i)
        assert abs(above - below) < 1e-8


def test_mobilized_friction_angle_along_the_path():
    dp = mobilized.peak_shear_displacement(LENGTH, JRC)
    i = 20.0 * deg  # JRC lg(JCS/sigma) = 10 * 2

    def phi(d):
        return mobilized.mobilized_friction_angle(d, SIGMA, JRC, JCS, PHI_R, dp, PHI_MAX)

    assert phi(0.0) == 0.0
    # pre-peak first segment: phi_r x / 0.3, the same as phi_r + i (-phi_r/i)(1 - x/0.3)
    assert phi(0.15 * dp) == pytest.approx(0.5 * PHI_R, rel=1e-12)
    assert phi(0.15 * dp) == pytest.approx(PHI_R + i * (-PHI_R / i) * 0.5, rel=1e-12)
    assert phi(0.3 * dp) == pytest.approx(PHI_R, rel=1e-12)
    assert phi(0.6 * dp) == pytest.approx(PHI_R + 0.75 * i, rel=1e-12)
    assert phi(dp) == pytest.approx(45.0 * deg, rel=1e-12)  # 25 + 20
    assert phi(4.0 * dp) == pytest.approx(PHI_R + 0.7 * i, rel=1e-12)
    assert phi(100.0 * dp) == pytest.approx(PHI_R, rel=1e-12)
    assert phi(1e6 * dp) == PHI_R
    assert phi(-dp) == phi(dp)


@pytest.mark.parametrize("sigma", [1.0e3, 0.1 * MPa, 1.0 * MPa, 30.0 * MPa, 99.0 * MPa])
def test_peak_of_mobilized_strength_is_barton_bandis_with_phi_r(sigma):
    dp = mobilized.peak_shear_displacement(LENGTH, JRC)
    tau = mobilized.mobilized_shear_strength(dp, sigma, JRC, JCS, PHI_R, dp, PHI_MAX)
    assert tau == pytest.approx(strength.peak_shear_strength(sigma, JRC, JCS, PHI_R, PHI_MAX), rel=1e-12)
    # and by hand, uncapped where 25 + 10 lg(JCS/sigma) < 70
    total = 25.0 + 10.0 * math.log10(JCS / sigma)
    if total < 70.0:
        assert tau == pytest.approx(sigma * math.tan(math.radians(total)), rel=1e-12)


def test_damage_and_dilation_at_the_peak():
    # M = 0.7 + 10 / (12 * 2) = 1.1166667; d = 20 deg / M = 17.910448 deg
    m = mobilized.damage_coefficient(SIGMA, JRC, JCS)
    assert m == pytest.approx(0.7 + 10.0 / 24.0, rel=1e-12)
    dp = mobilized.peak_shear_displacement(LENGTH, JRC)
    d = mobilized.mobilized_dilation_angle(dp, SIGMA, JRC, JCS, PHI_R, dp, m)
    assert math.degrees(d) == pytest.approx(17.910448, rel=1e-6)
    # the older M = 2: half the roughness angle; post-peak it follows the table (x = 10: 0.5)
    assert mobilized.mobilized_dilation_angle(dp, SIGMA, JRC, JCS, PHI_R, dp, 2.0) == pytest.approx(
        10.0 * deg, rel=1e-12
    )
    assert mobilized.mobilized_dilation_angle(10 * dp, SIGMA, JRC, JCS, PHI_R, dp, 2.0) == pytest.approx(
        5.0 * deg, rel=1e-12
    )


def test_aperture_and_closure_fits():
    # a_j = (10/5)(0.2 * 150/100 - 0.1) = 0.4 mm
    a = mobilized.initial_aperture(JRC, JCS, 150.0 * MPa)
    assert a == pytest.approx(0.4 * mm, rel=1e-12)
    # K_ni = -7.15 + 1.75 * 10 + 0.02 * 100/0.4 = 15.35 MPa/mm
    kni = mobilized.bandis_initial_normal_stiffness(JRC, JCS, a)
    assert kni == pytest.approx(15.35 * units.MPa_per_mm, rel=1e-12)
    # V_m = -0.2960 - 0.0056 * 10 + 2.2410 * 250^-0.2450 [mm] (first cycle); by hand:
    # 250^-0.245 = exp(-0.245 * 5.521461) = 0.2585263, 2.2410 * that = 0.5793574, minus 0.352 = 0.2273574
    expected_vm = -0.2960 - 0.0056 * 10.0 + 2.2410 * 250.0**-0.2450
    vm = mobilized.bandis_maximum_closure(JRC, JCS, a)
    assert vm == pytest.approx(expected_vm * mm, rel=1e-12)
    assert vm == pytest.approx(0.2273574 * mm, rel=1e-6)


@pytest.mark.parametrize("sigma", [1.0e3, 0.1 * MPa, 1.0 * MPa, 10.0 * MPa, 100.0 * MPa])
def test_closure_hyperbola_round_trip_and_tangent(sigma):
    kni, vm = 15.35 * units.MPa_per_mm, 0.2274 * mm
    dv = mobilized.bandis_closure(sigma, kni, vm)
    # by hand: dV = sigma V_m / (K_ni V_m + sigma)
    assert dv == pytest.approx(sigma * vm / (kni * vm + sigma), rel=1e-12)
    assert 0.0 < dv < vm
    # round trip: 1 - dV/V_m loses digits as sigma/(K_ni V_m) grows (at most ~30 here): rel 1e-12
    assert mobilized.bandis_closure_stress(dv, kni, vm) == pytest.approx(sigma, rel=1e-12)
    # tangent against a central difference of sigma(dV)
    fd = central_difference(lambda x: mobilized.bandis_closure_stress(x, kni, vm), dv, 1e-6 * dv)
    assert mobilized.bandis_normal_stiffness(sigma, kni, vm) == pytest.approx(fd, rel=1e-6)


# ---------------------------------------------------------------------------------------------------
# Edge rules
# ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("sigma", [0.0, -0.0, -1.0, -1e6])
def test_open_joint(sigma):
    dp = 1.0 * mm
    args = (dp, sigma, JRC, JCS, PHI_R, dp)
    assert mobilized.mobilized_friction_angle(*args, PHI_MAX) == PHI_MAX
    assert mobilized.mobilized_shear_strength(*args, PHI_MAX) == 0.0
    assert mobilized.mobilized_dilation_angle(*args, 2.0) == 0.0
    assert mobilized.damage_coefficient(sigma, JRC, JCS) == 0.7
    assert mobilized.bandis_closure(sigma, 1e10, 1e-4) == 0.0
    assert mobilized.bandis_normal_stiffness(sigma, 1e10, 1e-4) == 1e10


@pytest.mark.parametrize(("sigma", "jrc"), [(JCS, JRC), (2.0 * JCS, JRC), (SIGMA, 0.0)])
def test_no_roughness(sigma, jrc):
    # sigma_n >= JCS or JRC = 0: the friction still mobilizes from 0 to phi_r over 0.3 delta_peak, then
    # stays at phi_r; no dilation
    dp = 1.0 * mm
    for x, phi in [(0.0, 0.0), (0.15, 0.5 * PHI_R), (0.3, PHI_R), (1.0, PHI_R), (50.0, PHI_R)]:
        got = mobilized.mobilized_friction_angle(x * dp, sigma, jrc, JCS, PHI_R, dp, PHI_MAX)
        assert got == pytest.approx(phi, rel=1e-12)
        m = mobilized.damage_coefficient(sigma, jrc, JCS)
        assert mobilized.mobilized_dilation_angle(x * dp, sigma, jrc, JCS, PHI_R, dp, m) == 0.0
    assert mobilized.mobilized_roughness_ratio(0.1, PHI_R, 0.0) == 0.0
    assert mobilized.mobilized_roughness_ratio(0.6, PHI_R, 0.0) == 0.75


def test_continuity_across_jcs():
    dp = 1.0 * mm
    for x in (0.1, 0.6, 1.0, 5.0):
        below = mobilized.mobilized_friction_angle(x * dp, JCS * (1 - 1e-9), JRC, JCS, PHI_R, dp, PHI_MAX)
        above = mobilized.mobilized_friction_angle(x * dp, JCS * (1 + 1e-9), JRC, JCS, PHI_R, dp, PHI_MAX)
        assert below == pytest.approx(above, abs=1e-9)
    # M -> inf as sigma_n -> JCS-, and +inf at and above
    assert mobilized.damage_coefficient(JCS * (1 - 1e-12), JRC, JCS) > 1e10
    assert mobilized.damage_coefficient(JCS, JRC, JCS) == math.inf


def test_dilation_rules():
    dp = 1.0 * mm
    # contraction before 0.3 delta_peak is clamped to 0
    for x in (0.0, 0.1, 0.29):
        assert mobilized.mobilized_dilation_angle(x * dp, SIGMA, JRC, JCS, PHI_R, dp, 2.0) == 0.0
    # at a vanishing normal stress lg(JCS/sigma_n) grows without bound: Patton's cap pi/2 - phi_r
    for sigma in (1.0, 1e-300):
        d = mobilized.mobilized_dilation_angle(dp, sigma, JRC, JCS, PHI_R, dp, 0.7)
        assert d == math.pi / 2 - PHI_R
        assert math.isfinite(math.tan(d))


def test_friction_cap_and_overflow():
    # sigma_n = 1e-300: JCS/sigma_n overflows, the angle is capped (also where ratio is 0: phi_r)
    dp = 1.0 * mm
    assert mobilized.mobilized_friction_angle(dp, 1e-300, JRC, JCS, PHI_R, dp, PHI_MAX) == PHI_MAX
    assert mobilized.mobilized_friction_angle(200 * dp, 1e-300, JRC, JCS, PHI_R, dp, PHI_MAX) == PHI_R


def test_zero_peak_displacement():
    # delta_peak = 0 (JRC = 0 or L = 0): residual for any displacement, 0 at delta = 0
    assert mobilized.peak_shear_displacement(0.1, 0.0) == 0.0
    assert mobilized.peak_shear_displacement(0.0, 10.0) == 0.0
    assert mobilized.mobilized_friction_angle(0.0, SIGMA, JRC, JCS, PHI_R, 0.0, PHI_MAX) == 0.0
    assert mobilized.mobilized_friction_angle(1e-9, SIGMA, JRC, JCS, PHI_R, 0.0, PHI_MAX) == PHI_R


def test_scale_and_residual_rules():
    assert strength.scaled_jrc(JRC, 0.0, 1.0) == JRC
    assert strength.scaled_jcs(JCS, JRC, 0.1, -1.0) == JCS
    # r/R clamped to [0, 1], phi_r floored at 0
    assert strength.residual_friction_angle(30.0 * deg, 1.5) == pytest.approx(30.0 * deg, rel=1e-12)
    assert strength.residual_friction_angle(30.0 * deg, -1.0) == pytest.approx(10.0 * deg, rel=1e-12)
    assert strength.residual_friction_angle(15.0 * deg, 0.1) == 0.0


def test_fit_floors_and_caps():
    # aperture <= 0 by the formula (sigma_c <= JCS/2) or JRC = 0: floored at 1 micrometre
    assert mobilized.initial_aperture(JRC, JCS, 40.0 * MPa) == 1e-6
    assert mobilized.initial_aperture(0.0, JCS, 150.0 * MPa) == 1e-6
    assert mobilized.initial_aperture(JRC, 0.0, 150.0 * MPa) == 1e-6
    # K_ni fit negative (JRC 2, JCS 20 MPa, a_j 1 mm: -7.15 + 3.5 + 0.4 < 0): floored at 0.01 MPa/mm
    assert mobilized.bandis_initial_normal_stiffness(2.0, 20.0 * MPa, 1.0 * mm) == 0.01 * units.MPa_per_mm
    # V_m fit negative for large JCS/a_j (100 MPa / 0.01 mm = 1e4: -0.296 - 0.056 + 2.241e4^-0.245 < 0)
    assert -0.296 - 0.056 + 2.241 * 1e4**-0.245 < 0.0
    assert mobilized.bandis_maximum_closure(JRC, JCS, 0.01 * mm) == 1e-6
    # V_m fit larger than a_j (JCS 20 MPa, a_j 0.05 mm): capped at a_j
    assert -0.296 - 0.056 + 2.241 * 400.0**-0.245 > 0.05
    assert mobilized.bandis_maximum_closure(JRC, 20.0 * MPa, 0.05 * mm) == 0.05 * mm
    assert mobilized.bandis_maximum_closure(JRC, 0.0, 0.05 * mm) == 0.05 * mm


def test_closure_stress_at_and_beyond_maximum_closure():
    kni, vm = 1e10, 1e-4
    # clamped at dV/V_m = 1 - 2^-52: sigma = K_ni V_m (2^52 - 1), the same for every dV >= V_m
    expected = kni * vm * (2.0**52 - 1.0)
    for dv in (vm, 1.5 * vm, math.inf):
        assert mobilized.bandis_closure_stress(dv, kni, vm) == pytest.approx(expected, rel=1e-12)
    assert mobilized.bandis_closure_stress(0.0, kni, vm) == 0.0
    assert mobilized.bandis_closure_stress(-1.0, kni, vm) == 0.0
    assert mobilized.bandis_closure(math.inf, kni, vm) == vm


# ---------------------------------------------------------------------------------------------------
# Hypothesis properties
# ---------------------------------------------------------------------------------------------------

sigmas = st.floats(0.0, 8.5).map(lambda x: 10.0**x)  # 1 Pa .. 316 MPa, log-uniform (above some JCS)
jrcs = st.floats(0.0, 20.0)
jcss = st.floats(1.0, 300.0).map(lambda x: x * MPa)
phi_rs = st.floats(0.0, 40.0).map(lambda x: x * deg)
peaks = st.floats(-5.0, -1.0).map(lambda x: 10.0**x)  # 10 micrometres .. 0.1 m
ratios = st.floats(0.0, 200.0)
dampings = st.floats(0.7, 5.0)


@PROPERTY
@given(x1=ratios, x2=ratios, phi_r=phi_rs, i=st.floats(1e-3, 1.5))
def test_property_ratio_monotone_up_to_peak_then_down(x1, x2, phi_r, i):
    lo, hi = sorted((x1, x2))
    r_lo = mobilized.mobilized_roughness_ratio(lo, phi_r, i)
    r_hi = mobilized.mobilized_roughness_ratio(hi, phi_r, i)
    assert math.isfinite(r_lo)
    assert r_lo <= 1.0
    # 1e-15 absolute: rounding of the interpolation between ratios one ulp apart
    if hi <= 1.0:
        assert r_lo <= r_hi + 1e-15
    if lo >= 1.0:
        assert r_hi <= r_lo + 1e-15
    assert r_lo >= -phi_r / i * (1 + 1e-15)


@PROPERTY
@given(x1=ratios, x2=ratios, sigma=sigmas, jrc=jrcs, jcs=jcss, phi_r=phi_rs, dp=peaks, m=dampings)
def test_property_mobilized_laws(x1, x2, sigma, jrc, jcs, phi_r, dp, m):
    lo, hi = sorted((x1, x2))
    out = {}
    for name, x in (("lo", lo), ("hi", hi)):
        phi = mobilized.mobilized_friction_angle(x * dp, sigma, jrc, jcs, phi_r, dp, PHI_MAX)
        tau = mobilized.mobilized_shear_strength(x * dp, sigma, jrc, jcs, phi_r, dp, PHI_MAX)
        d = mobilized.mobilized_dilation_angle(x * dp, sigma, jrc, jcs, phi_r, dp, m)
        assert math.isfinite(phi) and math.isfinite(tau) and math.isfinite(d)
        assert 0.0 <= phi <= PHI_MAX
        assert tau >= 0.0
        assert 0.0 <= d <= math.pi / 2 - phi_r
        assert math.isfinite(math.tan(d))
        out[name] = phi
    # the friction angle rises to the peak and falls after (1e-15: rounding between near-equal x)
    if hi <= 1.0:
        assert out["lo"] <= out["hi"] * (1 + 1e-15)
    if lo >= 1.0:
        assert out["hi"] <= out["lo"] * (1 + 1e-15)
    # never below residual after 0.3 delta_peak, never above the B-B peak with phi_b -> phi_r
    peak = strength.peak_friction_angle(sigma, jrc, jcs, phi_r, PHI_MAX)
    assert out["hi"] <= peak * (1 + 1e-15)
    if hi >= 0.3:
        assert out["hi"] >= min(phi_r, PHI_MAX) * (1 - 1e-15)


@PROPERTY
@given(s1=sigmas, s2=sigmas, x=ratios, jrc=jrcs, jcs=jcss, phi_r=st.floats(10.0, 40.0), dp=peaks)
def test_property_mobilized_strength_non_decreasing_in_sigma(s1, s2, x, jrc, jcs, phi_r, dp):
    # Like the peak envelope (test_laws), tau(sigma_n) at a fixed displacement is increasing for
    # phi_r >= 10 deg, JRC <= 20: its slope is tan(theta) - k r (tan^2 theta + 1) with r <= 1.
    lo, hi = sorted((s1, s2))
    phi = phi_r * deg
    tau_lo = mobilized.mobilized_shear_strength(x * dp, lo, jrc, jcs, phi, dp, PHI_MAX)
    tau_hi = mobilized.mobilized_shear_strength(x * dp, hi, jrc, jcs, phi, dp, PHI_MAX)
    assert tau_lo <= tau_hi * (1.0 + 1e-14)


@PROPERTY
@given(sigma=sigmas, jrc=jrcs, jcs=jcss)
def test_property_damage(sigma, jrc, jcs):
    m = mobilized.damage_coefficient(sigma, jrc, jcs)
    assert m >= 0.7
    assert not math.isnan(m)
    if sigma < jcs and jrc > 0:
        assert math.isfinite(m)


kni_s = st.floats(6.0, 12.0).map(lambda x: 10.0**x)  # 1 MPa/m .. 1000 GPa/m
vm_s = st.floats(-6.0, -2.0).map(lambda x: 10.0**x)  # 1 micrometre .. 10 mm


@PROPERTY
@given(s1=sigmas, s2=sigmas, kni=kni_s, vm=vm_s)
def test_property_closure(s1, s2, kni, vm):
    lo, hi = sorted((s1, s2))
    dv_lo = mobilized.bandis_closure(lo, kni, vm)
    dv_hi = mobilized.bandis_closure(hi, kni, vm)
    assert 0.0 <= dv_lo <= dv_hi <= vm
    k_lo = mobilized.bandis_normal_stiffness(lo, kni, vm)
    k_hi = mobilized.bandis_normal_stiffness(hi, kni, vm)
    assert kni <= k_lo <= k_hi
    assert math.isfinite(k_hi)
    # round trip: the relative error of 1 - dV/V_m is ~1e-16 (1 + sigma/(K_ni V_m)), so tolerance
    # 1e-14 (1 + sigma/(K_ni V_m)); where dV rounds to V_m the clamp gives a finite, huge stress
    back = mobilized.bandis_closure_stress(dv_hi, kni, vm)
    assert math.isfinite(back)
    if dv_hi < vm:
        assert back == pytest.approx(hi, rel=1e-14 * (1.0 + hi / (kni * vm)))


@PROPERTY
@given(jrc=jrcs, jcs=jcss, sigma_c=st.floats(1.0, 400.0), a=st.floats(-6.0, -2.0))
def test_property_fits(jrc, jcs, sigma_c, a):
    aperture = 10.0**a
    assert mobilized.initial_aperture(jrc, jcs, sigma_c * MPa) >= 1e-6
    kni = mobilized.bandis_initial_normal_stiffness(jrc, jcs, aperture)
    vm = mobilized.bandis_maximum_closure(jrc, jcs, aperture)
    assert math.isfinite(kni) and kni >= 0.01 * units.MPa_per_mm
    assert 1e-6 <= vm <= max(aperture, 1e-6)


@PROPERTY
@given(jrc0=jrcs, l0=st.floats(0.01, 1.0), ln=st.floats(0.01, 100.0), phi_b=phi_rs, r=st.floats(-1, 2))
def test_property_scale_and_residual(jrc0, l0, ln, phi_b, r):
    jrc_n = strength.scaled_jrc(jrc0, l0, ln)
    jcs_n = strength.scaled_jcs(JCS, jrc0, l0, ln)
    assert math.isfinite(jrc_n) and jrc_n >= 0.0
    assert math.isfinite(jcs_n) and jcs_n > 0.0
    if ln >= l0:  # larger is smoother and weaker
        assert jrc_n <= jrc0 and jcs_n <= JCS
    dp = mobilized.peak_shear_displacement(ln, jrc_n)
    assert math.isfinite(dp) and dp >= 0.0
    phi_r = strength.residual_friction_angle(phi_b, r)
    assert 0.0 <= phi_r <= max(phi_b, 0.0)


# ---------------------------------------------------------------------------------------------------
# njit scalar == numpy ufunc == njit called from a kernel; broadcasting
# ---------------------------------------------------------------------------------------------------

_RNG = np.random.default_rng(20250101)
_N = 80
_SIG = np.concatenate([[-1.0, 0.0, 1e-300, 1.0, JCS, 2 * JCS], np.geomspace(1e3, 4e8, _N - 6)])
_JRC = _RNG.uniform(0.0, 20.0, _N)
_JRC[:3] = 0.0
_JCS = _RNG.uniform(1.0, 300.0, _N) * MPa
_JCS[4:6] = JCS
_PHI_R = _RNG.uniform(0.0, 40.0, _N) * deg
_PHI_MAX = np.full(_N, PHI_MAX)
_DP = 10.0 ** _RNG.uniform(-5.0, -1.0, _N)
_DP[0] = 0.0
_X = np.concatenate([[0.0, -0.5, 0.3, 1.0, 100.0, 1e300], _RNG.uniform(0.0, 150.0, _N - 6)])
_DELTA = _X * _DP
_I = _RNG.uniform(-0.1, 1.5, _N)
_M = _RNG.uniform(0.7, 3.0, _N)
_LN = 10.0 ** _RNG.uniform(-2.0, 2.0, _N)
_A = 10.0 ** _RNG.uniform(-6.5, -2.0, _N)
_SC = _RNG.uniform(1.0, 400.0, _N) * MPa
_KNI = 10.0 ** _RNG.uniform(6.0, 12.0, _N)
_VM = 10.0 ** _RNG.uniform(-6.0, -2.0, _N)
_DV = _RNG.uniform(-0.1, 1.2, _N) * _VM

MOBILIZED_ARGS = {
    "peak_shear_displacement": (_LN, _JRC),
    "mobilized_roughness_ratio": (_X, _PHI_R, _I),
    "mobilized_friction_angle": (_DELTA, _SIG, _JRC, _JCS, _PHI_R, _DP, _PHI_MAX),
    "mobilized_shear_strength": (_DELTA, _SIG, _JRC, _JCS, _PHI_R, _DP, _PHI_MAX),
    "damage_coefficient": (_SIG, _JRC, _JCS),
    "mobilized_dilation_angle": (_DELTA, _SIG, _JRC, _JCS, _PHI_R, _DP, _M),
    "initial_aperture": (_JRC, _JCS, _SC),
    "bandis_initial_normal_stiffness": (_JRC, _JCS, _A),
    "bandis_maximum_closure": (_JRC, _JCS, _A),
    "bandis_closure": (_SIG, _KNI, _VM),
    "bandis_closure_stress": (_DV, _KNI, _VM),
    "bandis_normal_stiffness": (_SIG, _KNI, _VM),
}


def test_every_public_mobilized_law_is_covered_and_exported():
    public = {
        name
        for name, obj in vars(mobilized).items()
        if not name.startswith("_") and isinstance(obj, numba.core.registry.CPUDispatcher)
    }
    public.discard("roughness_angle")  # imported from strength
    assert set(MOBILIZED_ARGS) == public
    assert public <= set(laws.__all__)


# sigma_n = 1e-300 makes JCS/sigma_n overflow to inf on purpose (the laws handle it); numpy reports the
# floating-point flag the ufunc loop raises there.
_OVERFLOW_OK = pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")


@_OVERFLOW_OK
@pytest.mark.parametrize("name", sorted(MOBILIZED_ARGS))
def test_ufunc_equals_njit_scalar(name):
    args = MOBILIZED_ARGS[name]
    vectorised = getattr(laws, name)(*args)
    looped = np.array([getattr(mobilized, name)(*(float(a[k]) for a in args)) for k in range(_N)])
    assert vectorised.dtype == np.float64
    assert not np.any(np.isnan(vectorised))
    np.testing.assert_array_equal(vectorised, looped)


@numba.njit
def _mobilized_kernel(delta, sig, jrc, jcs, phi_r, dp, phi_max):
    out = np.empty((sig.size, 4))
    for k in range(sig.size):
        m = mobilized.damage_coefficient(sig[k], jrc[k], jcs[k])
        out[k, 0] = mobilized.mobilized_friction_angle(
            delta[k], sig[k], jrc[k], jcs[k], phi_r[k], dp[k], phi_max[k]
        )
        out[k, 1] = mobilized.mobilized_shear_strength(
            delta[k], sig[k], jrc[k], jcs[k], phi_r[k], dp[k], phi_max[k]
        )
        out[k, 2] = m
        out[k, 3] = mobilized.mobilized_dilation_angle(delta[k], sig[k], jrc[k], jcs[k], phi_r[k], dp[k], m)
    return out


@_OVERFLOW_OK
def test_njit_laws_called_from_a_kernel_match_the_ufuncs():
    inside = _mobilized_kernel(_DELTA, _SIG, _JRC, _JCS, _PHI_R, _DP, _PHI_MAX)
    args = MOBILIZED_ARGS["mobilized_friction_angle"]
    np.testing.assert_array_equal(inside[:, 0], laws.mobilized_friction_angle(*args))
    np.testing.assert_array_equal(inside[:, 1], laws.mobilized_shear_strength(*args))
    np.testing.assert_array_equal(inside[:, 2], laws.damage_coefficient(_SIG, _JRC, _JCS))
    np.testing.assert_array_equal(inside[:, 3], laws.mobilized_dilation_angle(*args[:6], inside[:, 2]))


def test_ufuncs_broadcast():
    dp = mobilized.peak_shear_displacement(LENGTH, JRC)
    delta = np.linspace(0.0, 20.0, 7)[:, None] * dp  # (7, 1)
    sigma = np.array([0.1, 1.0, 10.0]) * MPa  # (3,)
    tau = laws.mobilized_shear_strength(delta, sigma, JRC, JCS, PHI_R, dp, PHI_MAX)
    assert tau.shape == (7, 3)
    for a in range(7):
        for b in range(3):
            expected = mobilized.mobilized_shear_strength(
                float(delta[a, 0]), float(sigma[b]), JRC, JCS, PHI_R, dp, PHI_MAX
            )
            assert tau[a, b] == expected
    x = np.array([[0.0, 0.3, 1.0, 100.0]])  # (1, 4) against two roughness angles (2, 1)
    ratio = laws.mobilized_roughness_ratio(x, PHI_R, np.array([[0.2], [0.4]]))
    assert ratio.shape == (2, 4)
    np.testing.assert_allclose(ratio[:, 1:], [[0.0, 1.0, 0.0]] * 2, atol=1e-15)
    np.testing.assert_allclose(ratio[:, 0], [-PHI_R / 0.2, -PHI_R / 0.4], rtol=1e-15)
    kn = laws.bandis_normal_stiffness(sigma[:, None], np.array([1e9, 1e10]), 1e-4)
    assert kn.shape == (3, 2)
    np.testing.assert_allclose(
        kn, np.array([1e9, 1e10]) * (1 + sigma[:, None] / (np.array([1e9, 1e10]) * 1e-4)) ** 2, rtol=1e-15
    )
    # the fits on arrays of apertures
    apertures = np.array([0.1, 0.4, 1.0]) * mm
    assert laws.bandis_maximum_closure(JRC, JCS, apertures).shape == (3,)
    assert laws.scaled_jrc(JRC, 0.1, np.array([0.1, 1.0, 10.0])).shape == (3,)
