"""bbmc.slope.wedge.support and design: bolts and shotcrete against hand calculations and the planar
model's forms, the optimum bolt in closed form against numerical maximisation, the bisection design
against the closed form, and how FS moves as an active bolt grows. Tolerances are stated where used."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize

from bbmc.geometry.orientation import line_vectors, poles
from bbmc.slope import planar as pl
from bbmc.slope.wedge import design as wd
from bbmc.slope.wedge import mechanics as wm
from bbmc.slope.wedge.strength import BartonBandis
from bbmc.slope.wedge.support import Bolt, shotcrete_force, support_resultants

DEG = math.pi / 180.0
W = 20e6  # N
AREAS = (120.0, 90.0)  # m^2
C1, C2, PHI = 20e3, 10e3, 35.0 * DEG


def _planes(dip_1=40.0, dir_1=130.0, dip_2=60.0, dir_2=220.0):
    n1, n2 = poles(np.array([dip_1, dip_2]) * DEG, np.array([dir_1, dir_2]) * DEG)
    return n1, n2


def _solve(n1, n2, active_bolt=0.0, passive=0.0, c1=C1, c2=C2, phi1=PHI, phi2=PHI):
    active = wm.active_resultant(W, n1, n2) + active_bolt
    return wm.wedge_factor_of_safety(
        n1, n2, *AREAS, active, wm.MohrCoulomb(c1, phi1), wm.MohrCoulomb(c2, phi2), passive
    )


def test_a_bolt_vector_by_hand():
    """3 bolts of 100 kN drilled trend 0, plunge 30 deg: (0, 300 cos 30, -300 sin 30) kN (1e-9 N)."""
    bolt = Bolt(100e3, 0.0, 30 * DEG, count=3)
    assert bolt.vector == pytest.approx([0.0, 300e3 * math.cos(30 * DEG), -150e3], abs=1e-9)


def test_swedges_shotcrete_example():
    """Swedge: traces 10 m and 12 m, t 0.1 m, tau_s 100 t/m^2 gives 220 t, normal to the face into
    the slope (face 65/185: the force is minus its outward pole; 1e-9 relative)."""
    tonne = 9.80665e3  # N
    face = poles(np.array(65 * DEG), np.array(185 * DEG))
    force = shotcrete_force(0.1, 100 * tonne, 10.0 + 12.0, face)
    assert np.linalg.norm(force) == pytest.approx(220 * tonne, rel=1e-9)
    assert force / np.linalg.norm(force) == pytest.approx(-face, abs=1e-12)
    with pytest.raises(ValueError, match="shotcrete"):
        shotcrete_force(-0.1, 1e6, 10.0, face)


def test_support_resultants_sum_each_form():
    a, b = Bolt(1e5, 0.3, 0.2), Bolt(2e5, 1.0, -0.1, count=2, form="passive")
    shot = np.array([1.0, 2.0, 3.0])
    active, passive = support_resultants([a, b], shot)
    assert active == pytest.approx(a.vector, abs=1e-9)
    assert passive == pytest.approx(b.vector + shot, abs=1e-9)


def test_bad_bolts_are_refused():
    with pytest.raises(ValueError, match="form"):
        Bolt(1e5, 0.0, 0.0, form="pretensioned")
    with pytest.raises(ValueError, match="pulls"):
        Bolt(-1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="count"):
        Bolt(1.0, 0.0, 0.0, count=-1)


def _planar_wedge(psi_p=35.0):
    """Plane 1 dipping psi_p to 180, plane 2 vertical through its dip direction, frictionless and
    without cohesion: the wedge is plane 1's planar block (the issue's planar limit)."""
    n1, n2 = _planes(psi_p, 180.0, 90.0, 90.0)
    return n1, n2 * np.sign(n2 @ np.array([-1.0, 0.0, 0.0]))


@pytest.mark.parametrize("form", ["active", "passive"])
def test_a_bolt_on_the_planar_limit_gives_the_planar_models_factor_of_safety(form):
    """A bolt drilled into the slope (trend 0) plunging 20 deg on plane 1 dipping 35 deg: the planar
    model's theta = psi_p + psi_T = 55 deg and its active or passive form (`bbmc.slope.planar`) give the
    same FS as the wedge's vector solution (relative 1e-12)."""
    n1, n2 = _planar_wedge()
    bolt = Bolt(500e3, 0.0, 20 * DEG, form=form)
    active, passive = support_resultants([bolt])
    wedge = _solve(n1, n2, active, passive, C1, 0.0, PHI, 0.0)
    psi = 35 * DEG
    forces = pl.PlanarForces(
        np.array(AREAS[0]),
        np.array(W),
        0.0,
        0.0,
        np.array(W * math.cos(psi)),
        np.array(W * math.sin(psi)),
        False,
    )
    planar = pl.factor_of_safety_mohr_coulomb(forces, C1, PHI, pl.Support(500e3, 55 * DEG, form))
    assert float(wedge.factor_of_safety) == pytest.approx(float(planar), rel=1e-12)


def test_active_and_passive_bolts_up_the_line_by_hand():
    """A bolt along -l (up the line of intersection) of T = 300 kN: active FS = R_0 / (D_0 - T),
    passive (R_0 + T) / D_0, R_0 and D_0 the unbolted wedge's (relative 1e-12)."""
    n1, n2 = _planes()
    bare = _solve(n1, n2)
    up = -bare.sliding_direction * 300e3
    r0, d0 = float(bare.resisting), float(bare.driving)
    assert float(_solve(n1, n2, up).factor_of_safety) == pytest.approx(r0 / (d0 - 300e3), rel=1e-12)
    assert float(_solve(n1, n2, passive=up).factor_of_safety) == pytest.approx((r0 + 300e3) / d0, rel=1e-12)


def _best_numerically(n1, n2, force, form):
    """max FS over the bolt's direction (trend, plunge) by Nelder-Mead from the best of a 5-degree
    grid, on the full vector solution."""

    def minus_fs(angles):
        d = line_vectors(angles[0], angles[1]) * force
        kw = {"active_bolt": d} if form == "active" else {"passive": d}
        return -float(_solve(n1, n2, **kw).factor_of_safety)

    grid = [(t, p) for t in np.arange(0, 360, 5) * DEG for p in np.arange(-85, 90, 5) * DEG]
    start = min(grid, key=minus_fs)
    best = minimize(minus_fs, start, method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-14})
    return -best.fun, line_vectors(*best.x)


@pytest.mark.parametrize("form", ["active", "passive"])
def test_the_optimum_bolt_in_closed_form_is_the_numerical_maximum(form):
    """3DEC's wedge with c, a 4 MN bolt: the closed-form optimum (tan theta = G / F active,
    tan theta = G passive, in the plane of s and g) matches the maximum of FS over all directions
    found numerically: FS to 1e-9 relative, the direction to 1e-4 rad (the optimum is flat)."""
    n1, n2 = _planes()
    bare = _solve(n1, n2)
    tan = math.tan(PHI)
    best = wd.optimum_bolt(bare, n1, n2, tan, tan, form, force=4e6)
    fs, direction = _best_numerically(n1, n2, 4e6, form)
    assert float(best.factor_of_safety) == pytest.approx(fs, rel=1e-9)
    assert math.acos(min(float(direction @ best.direction), 1.0)) < 1e-4
    kw = {"active_bolt": best.direction * 4e6} if form == "active" else {"passive": best.direction * 4e6}
    assert float(_solve(n1, n2, **kw).factor_of_safety) == pytest.approx(
        float(best.factor_of_safety), rel=1e-12
    )


@pytest.mark.parametrize("form", ["active", "passive"])
def test_the_planar_limit_gives_the_issues_optimum_angles(form):
    """On the planar limit G = tan phi: active tan theta = tan phi / F, passive theta = phi, measured
    from the up-dip direction (1e-12)."""
    n1, n2 = _planar_wedge()
    bare = _solve(n1, n2, c2=0.0, phi2=0.0)
    best = wd.optimum_bolt(bare, n1, n2, math.tan(PHI), 0.0, form, target=1.5)
    expected = math.atan(math.tan(PHI) / 1.5) if form == "active" else PHI
    assert float(best.angle) == pytest.approx(expected, rel=1e-12)
    g = wd.friction_gradient(bare.mode, n1, n2, math.tan(PHI), 0.0)
    assert float(np.linalg.norm(g)) == pytest.approx(math.tan(PHI), rel=1e-12)


def test_a_symmetric_wedges_friction_gradient_is_tan_phi_over_sin_half_its_angle():
    """Planes 50/140 and 50/220 with one phi: G = tan phi / sin(xi / 2), xi = pi - the angle between
    the normals into the wedge (1e-12)."""
    n1, n2 = _planes(50.0, 140.0, 50.0, 220.0)
    g = wd.friction_gradient(wm.SlidingMode.BOTH, n1, n2, math.tan(PHI), math.tan(PHI))
    xi = math.pi - math.acos(float(n1 @ n2))
    assert float(np.linalg.norm(g)) == pytest.approx(math.tan(PHI) / math.sin(xi / 2), rel=1e-12)


@pytest.mark.parametrize("form", ["active", "passive"])
def test_the_least_force_for_a_target_matches_the_bisection_design(form):
    """FS 1.5: the closed form's least force along its optimum direction, and `required_bolt_force`
    bisecting the vector solution along that direction, agree to 1e-8 relative; the FS there is 1.5."""
    n1, n2 = _planes()
    bare = _solve(n1, n2)
    tan = math.tan(PHI)
    best = wd.optimum_bolt(bare, n1, n2, tan, tan, form, target=1.5)
    assert float(bare.factor_of_safety) < 1.5
    active = wm.active_resultant(W, n1, n2)
    strengths = (wm.MohrCoulomb(C1, PHI), wm.MohrCoulomb(C2, PHI))
    force = wd.required_bolt_force(1.5, best.direction, form, n1, n2, *AREAS, active, *strengths, 1e8)
    assert float(force) == pytest.approx(float(best.force), rel=1e-8)
    kw = (
        {"active_bolt": best.direction * best.force}
        if form == "active"
        else {"passive": best.direction * best.force}
    )
    assert float(_solve(n1, n2, **kw).factor_of_safety) == pytest.approx(1.5, rel=1e-12)


def test_the_bisection_design_with_barton_bandis_and_a_bolt_count():
    """B-B planes, passive bolts drilled trend 310 deg plunging 15 deg: the force found gives FS 1.5
    (to the bisection's 1e-10 of the bracket), a force a little lower does not, and the count of 250 kN
    bolts is its ceiling; an unreachable target (bracket 1 kN) is NaN, a reached one 0."""
    n1, n2 = _planes()
    active = wm.active_resultant(W, n1, n2)
    law = BartonBandis(8.0, 60e6, 30 * DEG, lab_length=0.1, field_length=10.0)
    d = line_vectors(310 * DEG, 15 * DEG)
    force = float(wd.required_bolt_force(1.5, d, "passive", n1, n2, *AREAS, active, law, law, 1e8))
    fs = wm.wedge_factor_of_safety(n1, n2, *AREAS, active, law, law, force * d).factor_of_safety
    below = wm.wedge_factor_of_safety(n1, n2, *AREAS, active, law, law, (force - 0.1) * d).factor_of_safety
    assert float(fs) >= 1.5 > float(below)
    assert float(fs) == pytest.approx(1.5, rel=1e-6)
    assert math.ceil(force / 250e3) == pytest.approx(force / 250e3, abs=1.0)
    unreachable = wd.required_bolt_force(1.5, d, "passive", n1, n2, *AREAS, active, law, law, 1e3)
    assert np.isnan(unreachable)
    assert float(wd.required_bolt_force(0.1, d, "passive", n1, n2, *AREAS, active, law, law, 1e8)) == 0.0


def _fs_along(n1, n2, d, forces):
    active = wm.active_resultant(W, n1, n2)[None, :] + forces[:, None] * d
    strengths = (wm.MohrCoulomb(C1, PHI), wm.MohrCoulomb(C2, PHI))
    return wm.wedge_factor_of_safety(n1, n2, *AREAS, active, *strengths)


@settings(max_examples=80, deadline=None)
@given(
    dip_1=st.floats(25.0, 75.0),
    dip_2=st.floats(25.0, 75.0),
    spread=st.floats(40.0, 140.0),
    weights=st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
)
def test_an_active_bolt_that_presses_on_the_planes_and_not_down_the_line_only_raises_fs(
    dip_1, dip_2, spread, weights
):
    """d = -(alpha n1 + beta n2 + gamma l) (alpha, beta, gamma >= 0: q_1 = alpha, q_2 = beta >= 0, no
    component down the line): FS never falls (to 1e-12 relative) for T in [0, T_0), T_0 = D_0 / gamma;
    beyond T_0 the wedge is pushed up the line and FS falls from there (module docstring's range)."""
    assume(sum(weights) > 0.05)
    n1, n2 = _planes(dip_1, 180.0 - spread / 2, dip_2, 180.0 + spread / 2)
    bare = _solve(n1, n2)
    assume(int(bare.mode) == wm.SlidingMode.BOTH and float(bare.driving) > 1e-6 * W)
    alpha, beta, gamma = weights
    d = -(alpha * n1 + beta * n2 + gamma * bare.sliding_direction)
    d = d / np.linalg.norm(d)
    up_line = -float(d @ bare.sliding_direction)
    stop = float(bare.driving) / up_line if up_line > 1e-6 else 10 * W
    forces = np.linspace(0.0, 0.999 * stop, 60)
    fs = _fs_along(n1, n2, d, forces).factor_of_safety
    assert np.all(np.diff(fs) >= -1e-12 * fs[1:])
    if up_line > 1e-3:
        past = _fs_along(n1, n2, d, np.linspace(1.001, 5.0, 30) * stop)
        assert np.all(past.mode == wm.SlidingMode.BOTH_UP)
        assert np.all(np.diff(past.factor_of_safety) < 0.0)


def test_a_force_with_no_down_line_component_that_lifts_a_plane_lowers_fs():
    """The issue's property needs the bolt not to unload the planes: a force T n1 (normal to l, so no
    component down the line, pointing up and out of plane 1) lowers FS from the first newton. Measured
    on 3DEC's wedge: FS 1.0 MN along n1 vs none."""
    n1, n2 = _planes()
    fs = _fs_along(n1, n2, n1, np.array([0.0, 1e5, 1e6])).factor_of_safety
    assert abs(float(n1 @ _solve(n1, n2).sliding_direction)) < 1e-12
    assert fs[0] > fs[1] > fs[2]


@settings(max_examples=60, deadline=None)
@given(trend=st.floats(0.0, 360.0), plunge=st.floats(-89.0, 89.0))
def test_fs_moves_with_an_active_bolt_as_the_sign_of_a_d0_minus_b_r0(trend, plunge):
    """In the mode of both planes FS = (R_0 + a T) / (D_0 + b T): its change over a small force has the
    sign of a D_0 - b R_0 (a = d . g, b = d . s), for every direction that keeps the mode."""
    n1, n2 = _planes()
    bare = _solve(n1, n2)
    d = line_vectors(trend * DEG, plunge * DEG)
    g = wd.friction_gradient(bare.mode, n1, n2, math.tan(PHI), math.tan(PHI))
    a, b = float(d @ g), float(d @ bare.sliding_direction)
    criterion = a * float(bare.driving) - b * float(bare.resisting)
    assume(abs(criterion) > 1e-3 * float(bare.resisting))
    moved = _fs_along(n1, n2, d, np.array([0.0, 1e3]))
    assume(int(moved.mode[1]) == wm.SlidingMode.BOTH)
    assert np.sign(moved.factor_of_safety[1] - moved.factor_of_safety[0]) == np.sign(criterion)
