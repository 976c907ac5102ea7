"""bbmc.slope.planar: Hoek & Bray's planar failure with a tension crack against their worked example
(as recomputed by MatterCliff's documentation: H 30 m, crack 9 m behind the crest, face 60 deg, plane
30 deg, c 48 kPa, phi 30 deg, gamma 25.5 kN/m^3: z = 14.804 m, FS 1.347 drained, 0.794 with the crack
full) and against closed forms derived by hand. Each tolerance is stated where it is used."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbmc.slope import planar as pl

DEG = math.pi / 180.0
H, FACE, PLANE = 30.0, 60.0 * DEG, 30.0 * DEG
GAMMA, GAMMA_W = 25.5e3, 9.81e3
C, PHI = 48e3, 30.0 * DEG


def _example(fill: float, kh: float = 0.0) -> pl.PlanarForces:
    z = pl.crack_depth_behind_crest(H, FACE, PLANE, 9.0)
    return pl.planar_forces(H, FACE, PLANE, z, fill * z, GAMMA, kh, water_unit_weight=GAMMA_W)


def test_hoek_and_brays_example_to_its_printed_precision():
    """z = 14.804 m (to 1 mm), FS 1.347 drained and 0.794 with the crack full (to 0.0005)."""
    assert float(pl.crack_depth_behind_crest(H, FACE, PLANE, 9.0)) == pytest.approx(14.804, abs=5e-4)
    assert float(pl.factor_of_safety_mohr_coulomb(_example(0.0), C, PHI)) == pytest.approx(1.347, abs=5e-4)
    assert float(pl.factor_of_safety_mohr_coulomb(_example(1.0), C, PHI)) == pytest.approx(0.794, abs=5e-4)


@pytest.mark.parametrize("plane_deg", [10.0, 25.0, 40.0, 55.0])
def test_dry_cohesionless_plane_without_a_crack_is_tan_phi_over_tan_psi(plane_deg):
    """No crack, no water, c = 0: FS = tan phi / tan psi_p whatever the geometry (to 1e-12)."""
    forces = pl.planar_forces(20.0, 60.0 * DEG, plane_deg * DEG, 0.0, 0.0, GAMMA)
    expected = math.tan(35 * DEG) / math.tan(plane_deg * DEG)
    assert float(pl.factor_of_safety_mohr_coulomb(forces, 0.0, 35 * DEG)) == pytest.approx(
        expected, rel=1e-12
    )


@pytest.mark.parametrize("kh", [0.05, 0.1, 0.2])
def test_seismic_coefficient_tilts_gravity_by_its_angle(kh):
    """A horizontal k_h g on a cohesionless dry block is gravity tilted by arctan k_h: FS =
    tan phi / tan(psi_p + arctan k_h) (to 1e-12)."""
    forces = pl.planar_forces(20.0, 60.0 * DEG, 25.0 * DEG, 5.0, 0.0, GAMMA, kh)
    expected = math.tan(35 * DEG) / math.tan(25 * DEG + math.atan(kh))
    assert float(pl.factor_of_safety_mohr_coulomb(forces, 0.0, 35 * DEG)) == pytest.approx(
        expected, rel=1e-12
    )


def test_the_critical_crack_gives_the_least_factor_of_safety_of_a_dry_slope():
    """Over crack depths on a 0.001 H grid, the dry example's FS is least within one grid step of
    Hoek & Bray's critical depth, and the critical crack's distance puts it at that depth."""
    z = np.linspace(0.0, 0.999 * H, 1000)
    fs = pl.factor_of_safety_mohr_coulomb(pl.planar_forces(H, FACE, PLANE, z, 0.0, GAMMA), C, PHI)
    z_c, b_c = pl.critical_crack(H, FACE, PLANE)
    assert abs(z[np.argmin(fs)] - float(z_c)) <= z[1] - z[0]
    assert float(pl.crack_depth_behind_crest(H, FACE, PLANE, b_c)) == pytest.approx(float(z_c), rel=1e-12)


def test_the_weight_is_continuous_where_the_crack_moves_from_the_face_to_the_upper_surface():
    """At z / H = 1 - cot psi_f tan psi_p the two weight formulas agree (to 1e-9)."""
    boundary = H * (1.0 - math.tan(PLANE) / math.tan(FACE))
    just = pl.planar_forces(
        H, FACE, PLANE, np.array([boundary * (1 - 1e-12), boundary * (1 + 1e-12)]), 0.0, GAMMA
    )
    assert list(just.crack_in_face) == [False, True]
    assert just.weight[0] == pytest.approx(just.weight[1], rel=1e-9)


def test_barton_bandis_with_a_smooth_joint_is_mohr_coulomb_at_phi_b():
    """JRC = 0: tau_p = sigma_n tan phi_b, so the B-B FS is the M-C FS with c = 0, phi = phi_b (1e-12),
    with water and a seismic load."""
    forces = _example(0.5, 0.1)
    bb = pl.factor_of_safety_barton_bandis(forces, 0.0, 50e6, 30 * DEG, 70 * DEG)
    mc = pl.factor_of_safety_mohr_coulomb(forces, 0.0, 30 * DEG)
    assert float(bb) == pytest.approx(float(mc), rel=1e-12)


def test_barton_bandis_strength_is_taken_at_the_mean_normal_stress_on_the_plane():
    """FS = A sigma_n tan(phi_b + JRC lg(JCS / sigma_n)) / D at sigma_n = N / A, written out by hand."""
    forces = _example(0.0)
    sigma = float(forces.normal / forces.plane_length)
    angle = 30 * DEG + 10.0 * math.log10(20e6 / sigma) * DEG
    expected = float(forces.plane_length) * sigma * math.tan(angle) / float(forces.driving)
    assert float(pl.factor_of_safety_barton_bandis(forces, 10.0, 20e6, 30 * DEG, 70 * DEG)) == pytest.approx(
        expected
    )


def test_water_that_lifts_the_block_leaves_cohesion_only():
    """A light block (H 10 m, face 50 deg, plane 30 deg, a full crack 5 m deep behind the crest,
    12 kN/m^3): the water's N < 0, so FS = c A / D (the friction term is 0, never negative)."""
    forces = pl.planar_forces(10.0, 50.0 * DEG, 30.0 * DEG, 5.0, 5.0, 12e3)
    assert float(forces.normal) < 0
    expected = C * float(forces.plane_length) / float(forces.driving)
    assert float(pl.factor_of_safety_mohr_coulomb(forces, C, PHI)) == pytest.approx(expected, rel=1e-12)


def test_every_function_broadcasts_over_sample_arrays():
    """100,000 samples of friction and fill in one call give what one call per sample gives."""
    rng = np.random.default_rng(1)
    phi = rng.uniform(20, 40, 100_000) * DEG
    fill = rng.uniform(0, 1, 100_000)
    z = float(pl.crack_depth_behind_crest(H, FACE, PLANE, 9.0))
    fs = pl.factor_of_safety_mohr_coulomb(pl.planar_forces(H, FACE, PLANE, z, fill * z, GAMMA), C, phi)
    assert fs.shape == (100_000,)
    for k in (0, 777, 99_999):
        one = pl.factor_of_safety_mohr_coulomb(
            pl.planar_forces(H, FACE, PLANE, z, fill[k] * z, GAMMA), C, phi[k]
        )
        assert fs[k] == float(one)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"plane": 60.0 * DEG}, "daylight"),
        ({"plane": 0.0}, "must dip"),
        ({"crack_depth": 30.0}, "crack depth"),
        ({"water_depth": 11.0}, "water in the crack"),
        ({"crack_depth": 25.0, "water_depth": 10.5}, "water in the crack"),  # a face crack 10 m high
    ],
)
def test_geometry_that_forms_no_block_is_refused(change, message):
    args = {
        "height": H,
        "face": FACE,
        "plane": PLANE,
        "crack_depth": 10.0,
        "water_depth": 5.0,
        "unit_weight": GAMMA,
    }
    with pytest.raises(ValueError, match=message):
        pl.planar_forces(**{**args, **change})
