"""bbmc.slope.planar with a support force: RocPlane's active and passive forms against closed forms
derived by hand and Hoek & Bray's worked example (H 30 m, crack 9 m behind the crest, face 60 deg,
plane 30 deg, c 48 kPa, phi 30 deg, gamma 25.5 kN/m^3, the crack full of water)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.slope import planar as pl

DEG = math.pi / 180.0
H, FACE, PLANE = 30.0, 60.0 * DEG, 30.0 * DEG
GAMMA, GAMMA_W = 25.5e3, 9.81e3
C, PHI = 48e3, 30.0 * DEG
FORMS = ("active", "passive")


def _example(fill: float, kh: float = 0.0) -> pl.PlanarForces:
    z = pl.crack_depth_behind_crest(H, FACE, PLANE, 9.0)
    return pl.planar_forces(H, FACE, PLANE, z, fill * z, GAMMA, kh, water_unit_weight=GAMMA_W)


def _fs(forces, support=None):
    return pl.factor_of_safety_mohr_coulomb(forces, C, PHI, support)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("fill", [0.0, 0.5, 1.0])
def test_no_force_gives_the_unsupported_factor_of_safety_exactly(form, fill):
    forces = _example(fill, 0.1)
    assert float(_fs(forces, pl.Support(0.0, 50 * DEG, form))) == float(_fs(forces))
    bb = pl.factor_of_safety_barton_bandis(forces, 8.0, 50e6, 30 * DEG, 70 * DEG, pl.Support(0.0, 1.0, form))
    assert float(bb) == float(pl.factor_of_safety_barton_bandis(forces, 8.0, 50e6, 30 * DEG, 70 * DEG))


@pytest.mark.parametrize("form", FORMS)
def test_a_support_normal_to_the_plane_adds_t_tan_phi_to_the_resistance(form):
    """theta = 90 deg: T_s = 0, T_n = T, so FS = (c A + (N + T) tan phi) / D in both forms (1e-12)."""
    forces, t = _example(0.5), 300e3
    expected = (C * forces.plane_length + (forces.normal + t) * math.tan(PHI)) / forces.driving
    assert float(_fs(forces, pl.Support(t, 90 * DEG, form))) == pytest.approx(float(expected), rel=1e-12)


def test_a_support_along_the_plane_up_dip_reduces_the_driving_force_or_adds_to_the_resistance():
    """theta = 0: active FS = R / (D - T), passive FS = (R + T) / D, R the unsupported resistance."""
    forces, t = _example(1.0), 500e3
    resisting = float(_fs(forces) * forces.driving)
    d = float(forces.driving)
    assert float(_fs(forces, pl.Support(t, 0.0, "active"))) == pytest.approx(resisting / (d - t), rel=1e-12)
    assert float(_fs(forces, pl.Support(t, 0.0, "passive"))) == pytest.approx((resisting + t) / d, rel=1e-12)


def test_hoek_and_brays_example_with_a_bolt_computed_by_hand():
    """Crack full, T = 400 kN/m plunging 20 deg below the horizontal: theta = 30 + 20 = 50 deg.
    By hand (kN/m): A = 30.392 m, W = 8410.5, U = 2206.9, V = 1074.9,
    N = W cos 30 - U - V sin 30 = 4539.3, D = W sin 30 + V cos 30 = 5136.2,
    T_n = 400 sin 50 = 306.42, T_s = 400 cos 50 = 257.12, c A = 48 x 30.392 = 1458.8,
    (N + T_n) tan 30 = 4845.8 x 0.57735 = 2797.7, so
    active  FS = (1458.8 + 2797.7) / (5136.2 - 257.12) = 4256.5 / 4879.1 = 0.8724,
    passive FS = (4256.5 + 257.12) / 5136.2 = 0.8788 (to the 4 digits worked)."""
    forces = _example(1.0)
    assert float(forces.normal) == pytest.approx(4539.3e3, abs=0.1e3)
    assert float(forces.driving) == pytest.approx(5136.2e3, abs=0.1e3)
    assert float(_fs(forces, pl.Support(400e3, 50 * DEG, "active"))) == pytest.approx(0.8724, abs=1e-4)
    assert float(_fs(forces, pl.Support(400e3, 50 * DEG, "passive"))) == pytest.approx(0.8788, abs=1e-4)


def test_an_active_support_that_holds_the_block_alone_gives_infinite_safety():
    forces = _example(0.0)
    assert float(_fs(forces, pl.Support(2.0 * float(forces.driving), 0.0, "active"))) == math.inf


@settings(max_examples=60, deadline=None)
@given(
    form=st.sampled_from(FORMS),
    theta_deg=st.floats(0.0, 90.0),
    t1=st.floats(0.0, 2000e3),
    t2=st.floats(0.0, 2000e3),
    fill=st.floats(0.0, 1.0),
)
def test_the_factor_of_safety_grows_with_the_force_of_a_resisting_bolt(form, theta_deg, t1, t2, fill):
    """For 0 <= theta <= 90 deg both components resist, so FS is non-decreasing in T."""
    forces = _example(fill)
    lo, hi = sorted((t1, t2))
    fs_lo = float(_fs(forces, pl.Support(lo, theta_deg * DEG, form)))
    fs_hi = float(_fs(forces, pl.Support(hi, theta_deg * DEG, form)))
    assert fs_hi >= fs_lo * (1.0 - 1e-12)


@pytest.mark.parametrize("form", FORMS)
def test_arrays_broadcast_as_element_wise_scalar_calls(form):
    t = np.array([0.0, 100e3, 400e3, 900e3])[:, None]
    theta = np.array([0.0, 40.0, 90.0]) * DEG
    z = pl.crack_depth_behind_crest(H, FACE, PLANE, 9.0)
    fill = np.array([0.0, 0.5, 1.0])
    forces = pl.planar_forces(H, FACE, PLANE, z, fill * z, GAMMA, water_unit_weight=GAMMA_W)
    fs = _fs(forces, pl.Support(t, theta, form))
    assert fs.shape == (4, 3)
    for i in range(4):
        for j in range(3):
            one = _example(fill[j])
            assert fs[i, j] == float(_fs(one, pl.Support(float(t[i, 0]), float(theta[j]), form)))


def test_meaningless_support_is_refused():
    with pytest.raises(ValueError, match="support force must be >= 0"):
        pl.Support(np.array([10e3, -1.0]), 0.5)
    with pytest.raises(ValueError, match="support form"):
        pl.Support(10e3, 0.5, "both")
