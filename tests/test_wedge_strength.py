"""bbmc.slope.wedge.strength: Barton-Bandis on a wedge's planes against its tangent Mohr-Coulomb, JRC 0
and waviness limits, the scale laws and hand-worked values. Each tolerance is stated where it is used."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.geometry.orientation import poles
from bbmc.slope.wedge import mechanics as wm
from bbmc.slope.wedge.strength import BartonBandis, normal_stresses

DEG = math.pi / 180.0


@settings(max_examples=200, deadline=None)
@given(
    jrc=st.floats(0.0, 20.0),
    jcs=st.floats(10e6, 200e6),
    phi_b=st.floats(20.0, 38.0),
    waviness=st.floats(0.0, 10.0),
    sigma_n=st.floats(1e3, 5e6),
    area=st.floats(0.5, 2000.0),
    field=st.floats(0.0, 20.0),
)
def test_barton_bandis_at_its_normal_stress_equals_its_tangent_mohr_coulomb(
    jrc, jcs, phi_b, waviness, sigma_n, area, field
):
    """A tau_p(sigma_n) = c_t A + N tan phi_t at N = sigma_n A: the tangent passes through the point
    (relative 1e-9; the two sides are computed by different laws, eq 9 and eqs 12-14)."""
    law = BartonBandis(jrc, jcs, phi_b * DEG, lab_length=0.1, field_length=field, waviness=waviness * DEG)
    normal = np.array(sigma_n * area)
    tangent = law.equivalent_mohr_coulomb(sigma_n)
    assert float(tangent.shear_force(normal, area)) == pytest.approx(
        float(law.shear_force(normal, area)), rel=1e-9
    )


def test_jrc_zero_is_mohr_coulomb_at_the_basic_friction_angle():
    """JRC 0: tau = sigma_n tan phi_b, c_t = 0, phi_t = phi_b (1e-12), at every stress."""
    law = BartonBandis(0.0, 50e6, 31.0 * DEG, lab_length=0.1, field_length=5.0)
    sigma = np.array([1e3, 1e5, 3e6, 60e6])
    area = 40.0
    assert law.shear_force(sigma * area, area) == pytest.approx(sigma * area * math.tan(31 * DEG), rel=1e-12)
    tangent = law.equivalent_mohr_coulomb(sigma)
    assert np.asarray(tangent.cohesion) == pytest.approx(0.0, abs=1e-12)
    assert np.asarray(tangent.friction) == pytest.approx(31.0 * DEG, rel=1e-12)


def test_waviness_adds_its_angle_to_the_total_friction_angle():
    """By hand: JRC 10, JCS 100 MPa, sigma_n 100 kPa: lg(JCS / sigma_n) = 3, angle 30 + 30 = 60 deg,
    with i = 5 deg 65 deg; JRC 0: phi_b + i (relative 1e-12)."""
    sigma = 100e3
    plain = BartonBandis(10.0, 100e6, 30.0 * DEG, max_friction=75.0 * DEG)
    wavy = BartonBandis(10.0, 100e6, 30.0 * DEG, max_friction=75.0 * DEG, waviness=5.0 * DEG)
    assert float(plain.shear_stress(sigma)) == pytest.approx(sigma * math.tan(60 * DEG), rel=1e-12)
    assert float(wavy.shear_stress(sigma)) == pytest.approx(sigma * math.tan(65 * DEG), rel=1e-12)
    smooth = BartonBandis(0.0, 100e6, 30.0 * DEG, waviness=8.0 * DEG)
    assert float(smooth.shear_stress(sigma)) == pytest.approx(sigma * math.tan(38 * DEG), rel=1e-12)
    assert float(np.asarray(smooth.equivalent_mohr_coulomb(sigma).friction)) == pytest.approx(38 * DEG)


def test_the_cap_acts_on_the_barton_bandis_angle_before_the_waviness():
    """sigma_n 1 Pa, JRC 20: the B-B angle is capped at phi_max 70 deg, plus i 6 deg: 76 deg (1e-12)."""
    law = BartonBandis(20.0, 100e6, 30.0 * DEG, waviness=6.0 * DEG)
    assert float(law.shear_stress(1.0)) == pytest.approx(math.tan(76 * DEG), rel=1e-12)


def test_scale_correction_by_hand():
    """JRC_0 10, JCS_0 100 MPa at L_0 0.1 m taken to L_n 1 m: JRC_n = 10 x 10^-0.2 = 6.30957,
    JCS_n = 100 x 10^-0.3 = 50.1187 MPa (1e-5); L_n = L_0 or 0 leaves them."""
    jrc_n, jcs_n = BartonBandis(10.0, 100e6, 30 * DEG, lab_length=0.1, field_length=1.0).scaled()
    assert float(jrc_n) == pytest.approx(6.30957, rel=1e-5)
    assert float(jcs_n) == pytest.approx(50.1187e6, rel=1e-5)
    for field in (0.1, 0.0):
        same = BartonBandis(10.0, 100e6, 30 * DEG, lab_length=0.1, field_length=field).scaled()
        assert (float(same[0]), float(same[1])) == (10.0, 100e6)


def test_open_plane_has_no_strength_and_bad_angles_are_refused():
    law = BartonBandis(10.0, 100e6, 30 * DEG)
    assert law.shear_force(np.array([0.0, -5.0]), np.array([10.0, 10.0])).tolist() == [0.0, 0.0]
    assert float(law.shear_force(np.array(1e5), np.array(0.0))) == 0.0
    with pytest.raises(ValueError, match="90 degrees"):
        BartonBandis(10.0, 100e6, 30 * DEG, waviness=25 * DEG)
    with pytest.raises(ValueError, match="waviness"):
        BartonBandis(10.0, 100e6, 30 * DEG, waviness=-1 * DEG)


def test_a_wedge_with_barton_bandis_planes_equals_one_with_their_tangent_mohr_coulomb():
    """3DEC's wedge planes (40/130, 60/220) under W = 2 MN, areas 120 and 90 m^2, a water push and a
    bolt: the FS with B-B on each plane equals the FS with the tangent c, phi of each plane at its own
    sigma_n from statics (relative 1e-9), so no iteration is needed; the field length scales both."""
    n1, n2 = poles(np.array([40.0, 60.0]) * DEG, np.array([130.0, 220.0]) * DEG)
    areas = np.array([120.0, 90.0])
    active = wm.active_resultant(2e6, n1, n2, 1e5, 2e5, np.array([0.0, 3e5, -1e5]))
    law_1 = BartonBandis(9.0, 60e6, 29 * DEG, lab_length=0.1, field_length=12.0, waviness=3 * DEG)
    law_2 = BartonBandis(5.0, 80e6, 32 * DEG, lab_length=0.1, field_length=12.0)
    bb = wm.wedge_factor_of_safety(n1, n2, *areas, active, law_1, law_2)
    assert bb.mode == wm.SlidingMode.BOTH
    s1, s2 = normal_stresses(bb.normal_1, bb.normal_2, *areas)
    mc = wm.wedge_factor_of_safety(
        n1, n2, *areas, active, law_1.equivalent_mohr_coulomb(s1), law_2.equivalent_mohr_coulomb(s2)
    )
    assert float(mc.factor_of_safety) == pytest.approx(float(bb.factor_of_safety), rel=1e-9)
    assert float(s1) > 0.0 and float(s2) > 0.0
